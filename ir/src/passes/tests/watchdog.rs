//! Which loops the watchdog pass leaves without a check: those that cannot run long
//! (`passes::watchdog`'s module doc).

use super::{apply, back_edges, parse, print_funcs};
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

/// Back edges in the module.
fn loops(m: &crate::module::Module) -> usize {
    m.funcs.iter().map(back_edges).sum()
}

/// Runs `@f` on each of `inputs` in the interpreter before and after the pass, asks
/// for the same results, and gives the module after it.
fn same_results(text: &str, inputs: &[[u64; 2]]) -> crate::module::Module {
    use crate::interp::Interp;
    let m = parse(text);
    let mut after = m.clone();
    apply(&mut after, "watchdog", watchdog::run_function);
    let f = m.func_by_name("f").expect("@f");
    let mut a = Interp::new(&m).expect("runs");
    let mut b = Interp::new(&after).expect("runs");
    for it in [&mut a, &mut b] {
        it.set_step_limit(Some(2_000_000));
    }
    for args in inputs {
        match (a.call(f, args), b.call(f, args)) {
            // Endless: out of steps in both, each somewhere in its loop.
            (Err(_), Err(_)) => {}
            (x, y) => assert_eq!(x, y, "@f{args:?}"),
        }
    }
    after
}

/// `j := start; WHILE j <= bound (or the compare given) DO acc := acc + j; j := j +
/// step; END_WHILE; RETURN acc - j` over `ty`, with `start` and `step` the
/// function's parameters.
fn stepping(ty: &str, cc: &str, bound: i64) -> String {
    format!(
        r#"
func @f({ty}, {ty}) -> {ty} function {{
block0(v0: {ty}, v1: {ty}):
    v2 = iconst.{ty} {bound}
    v3 = iconst.{ty} 0
    jump block1(v0, v3)
block1(v4: {ty}, v5: {ty}):
    v6 = icmp {cc} v4, v2
    brif v6, block2, block3
block2:
    v8 = iadd v5, v4
    v9 = iadd v4, v1
    jump block1(v9, v8)
block3:
    v10 = isub v5, v4
    return v10
}}
"#
    )
}

#[test]
fn a_loop_of_steps_known_at_run_time_gets_a_copy_without_checks() {
    let text = stepping("i32", "sle", 9999);
    let m = same_results(
        &text,
        &[
            [0, 1],
            [5, 3],
            [(-100i32) as u32 as u64, 7],
            [9999, 1],
            [10000, 1],
            [0, 10000],
            // Steps that could wrap, and a start too low: the loop with its checks.
            [0, 0x7fff_ffff],
            [0, 0x7fff_d8f1],
            [(-2_000_000_000i32) as u32 as u64, 1_000_000],
            // Steps of 0 and -1: endless, in both.
            [0, 0],
            [0, 0xffff_ffff],
        ],
    );
    // The copy is a second loop; only the first has a check.
    assert_eq!(loops(&m), 2);
    assert_eq!(checks(&text), 1);
    let printed = print_funcs(&m);
    // The test: the step at least 1 and at most 2^31 - 1 - 9999, the start at
    // least 10000 - 2^24 / 5.
    for test in [
        "iconst.i32 1\n",
        "iconst.i32 2147473648\n",
        "iconst.i32 -3345443\n",
    ] {
        assert!(printed.contains(test), "no `{test}` in\n{printed}");
    }
}

#[test]
fn unsigned_and_narrow_counters_get_copies_too() {
    // USINT-like: `j < 200` unsigned (-56 in the canonical form), steps up to 56
    // cannot wrap.
    let text = stepping("i8", "ult", -56);
    let m = same_results(
        &text,
        &[[0, 1], [3, 56], [3, 57], [199, 1], [250, 1], [0, 0]],
    );
    assert_eq!(loops(&m), 2);
    let text = stepping("i16", "slt", -5);
    let m = same_results(
        &text,
        &[
            [(-300i16) as u16 as u64, 7],
            [0, 1],
            [(-32768i16) as u16 as u64, 1],
        ],
    );
    assert_eq!(loops(&m), 2);
}

#[test]
fn a_loop_whose_values_cannot_be_merged_gets_no_copy() {
    // The sum leaves by two exits, each using it.
    let text = r#"
func @f(i32, i32) -> i32 function {
block0(v0: i32, v1: i32):
    v2 = iconst.i32 9999
    v3 = iconst.i32 0
    v10 = iconst.i32 500
    jump block1(v0, v3)
block1(v4: i32, v5: i32):
    v6 = icmp sle v4, v2
    brif v6, block2, block3
block2:
    v8 = iadd v5, v4
    v11 = icmp sgt v8, v10
    brif v11, block4, block5
block5:
    v9 = iadd v4, v1
    jump block1(v9, v8)
block3:
    return v5
block4:
    return v8
}
"#;
    let m = same_results(text, &[[0, 1], [0, 100], [600, 1]]);
    assert_eq!(loops(&m), 1);
    // The same through one exit block: merged.
    let text = text
        .replace("brif v11, block4, block5", "brif v11, block3, block5")
        .replace("block4:\n    return v8\n", "");
    let m = same_results(
        &text,
        &[[0, 1], [0, 100], [600, 1], [-5i32 as u32 as u64, 0]],
    );
    assert_eq!(loops(&m), 2);
}

#[test]
fn a_header_whose_compare_does_not_leave_gets_no_copy() {
    // Both ways of the header's compare stay in the loop; it ends (or not) elsewhere,
    // so the compare bounds nothing.
    let text = r#"
func @f(i32, i32) -> i32 function {
block0(v0: i32, v1: i32):
    v2 = iconst.i32 9999
    v3 = iconst.i32 0
    jump block1(v0, v3)
block1(v4: i32, v5: i32):
    v6 = icmp sle v4, v2
    brif v6, block2, block3
block2:
    v7 = iadd v4, v1
    jump block1(v7, v5)
block3:
    v8 = iadd v5, v1
    v9 = icmp sgt v8, v2
    v10 = iadd v4, v1
    brif v9, block4, block1(v10, v8)
block4:
    return v8
}
"#;
    let m = same_results(text, &[[0, 1], [10000, 1], [10000, 5000]]);
    assert_eq!(loops(&m), 2);
}
