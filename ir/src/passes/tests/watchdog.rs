//! Which loops the watchdog pass leaves without a check: those that cannot run long
//! (`passes::watchdog`'s module doc).

use super::{apply, parse, print_funcs};
use crate::inst::{InstData, Intrinsic};
use crate::passes::watchdog;

/// The checks in the module after the pass.
fn checks(text: &str) -> usize {
    let mut m = parse(text);
    apply(&mut m, "watchdog", watchdog::run_function);
    let n = m
        .funcs
        .iter()
        .flat_map(|f| f.inst_iter().map(move |(_, i)| f.inst(i)))
        .filter(|d| {
            matches!(
                d,
                InstData::Intrinsic {
                    op: Intrinsic::StopRequested,
                    ..
                }
            )
        })
        .count();
    println!("{}", print_funcs(&m));
    n
}

/// `for i := start to end (step)` over an INT or DINT counter, with a body that adds
/// to the result (and `extra` inside).
fn counting(ty: &str, start: i64, end: i64, step: &str, extra: &str) -> String {
    format!(
        r#"
func @g() -> i32 function {{
block0:
    v0 = iconst.i32 7
    return v0
}}

func @f(i32) -> i32 function {{
block0(v0: i32):
    v1 = iconst.{ty} {start}
    v2 = iconst.{ty} {end}
    v3 = iconst.{ty} 1
    jump block1(v1, v0)
block1(v4: {ty}, v5: i32):
    v6 = icmp sgt v4, v2
    brif v6, block3, block2
block2:
    v7 = iadd v5, v0
    {extra}
    v8 = iadd v4, {step}
    jump block1(v8, v7)
block3:
    return v5
}}
"#
    )
}

#[test]
fn a_short_counted_loop_needs_no_check() {
    assert_eq!(checks(&counting("i32", 0, 9999, "v3", "")), 0);
    assert_eq!(checks(&counting("i16", -100, 100, "v3", "")), 0);
    // The step is the function's parameter: it may be 0 or negative.
    assert_eq!(checks(&counting("i32", 0, 9999, "v0", "")), 1);
}

#[test]
fn a_loop_that_may_not_end_keeps_its_check() {
    // INT counting to 32767 wraps to -32768 and goes on.
    assert_eq!(checks(&counting("i16", 0, 32767, "v3", "")), 1);
    // Too long: 2^26 iterations of five instructions.
    assert_eq!(checks(&counting("i32", 0, 1 << 26, "v3", "")), 1);
    // A call inside.
    assert_eq!(checks(&counting("i32", 0, 10, "v3", "v9 = call @g()")), 1);
}

#[test]
fn an_enclosing_loop_keeps_its_check() {
    let text = r#"
func @f(i32) -> i32 function {
block0(v0: i32):
    v1 = iconst.i32 0
    v2 = iconst.i32 99
    v3 = iconst.i32 1
    jump block1(v1, v0)
block1(v4: i32, v5: i32):
    v6 = icmp sgt v4, v2
    brif v6, block5, block2(v1, v5)
block2(v7: i32, v8: i32):
    v9 = icmp sgt v7, v2
    brif v9, block4, block3
block3:
    v10 = iadd v8, v7
    v11 = iadd v7, v3
    jump block2(v11, v10)
block4:
    v12 = iadd v4, v3
    jump block1(v12, v8)
block5:
    return v5
}
"#;
    // The inner loop is short; the outer loop, around it, keeps its check.
    assert_eq!(checks(text), 1);
}
