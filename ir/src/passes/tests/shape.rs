//! Before/after tests of the passes a backend chooses for its target's sake: loop
//! rotation, if-conversion and fills.

use super::{check, check_in_module};
use crate::passes::{fill, if_convert, rotate};

// ---- rotate ----

#[test]
fn rotate_a_counting_loop() {
    check(
        r#"
func @f(i32) -> i32 function {
block0(v0: i32):
    v1 = iconst.i32 0
    jump block1(v1, v1)
block1(v2: i32, v3: i32):
    v4 = icmp slt v2, v0
    brif v4, block2, block3
block2:
    v5 = iadd v3, v2
    v6 = iconst.i32 1
    v7 = iadd v2, v6
    jump block1(v7, v5)
block3:
    return v3
}
"#,
        rotate::run,
        r#"
func @f(i32) -> i32 function {
block0(v0: i32):
    v1 = iconst.i32 0
    jump block1(v1, v1)

block1(v2: i32, v3: i32):
    v4 = icmp slt v2, v0
    brif v4, block2(v3, v2), block3(v3)

block2(v8: i32, v9: i32):
    v5 = iadd v8, v9
    v6 = iconst.i32 1
    v7 = iadd v9, v6
    v11 = icmp slt v7, v0
    brif v11, block2(v5, v7), block3(v5)

block3(v10: i32):
    return v10
}
"#,
    );
}

/// The first loop's exit is the second loop's header, which its own latch reaches
/// too: the first loop's value used in the second gets a block of its own on the
/// edge from the first header. Both loops rotate.
#[test]
fn rotate_splits_the_edge_into_a_following_loop() {
    check(
        r#"
func @f(i32) -> i32 function {
block0(v0: i32):
    v1 = iconst.i32 0
    jump block1(v1)
block1(v2: i32):
    v3 = icmp slt v2, v0
    brif v3, block2, block3(v1)
block2:
    v4 = iconst.i32 1
    v5 = iadd v2, v4
    jump block1(v5)
block3(v6: i32):
    v7 = icmp slt v6, v2
    brif v7, block4, block5
block4:
    v8 = iconst.i32 2
    v9 = iadd v6, v8
    jump block3(v9)
block5:
    return v6
}
"#,
        rotate::run,
        r#"
func @f(i32) -> i32 function {
block0(v0: i32):
    v1 = iconst.i32 0
    jump block1(v1)

block1(v2: i32):
    v3 = icmp slt v2, v0
    brif v3, block2(v2), block6(v1, v2)

block2(v10: i32):
    v4 = iconst.i32 1
    v5 = iadd v10, v4
    v13 = icmp slt v5, v0
    brif v13, block2(v5), block6(v1, v5)

block6(v11: i32, v12: i32):
    jump block3(v11)

block3(v6: i32):
    v7 = icmp slt v6, v12
    brif v7, block4(v6), block5(v6)

block4(v14: i32):
    v8 = iconst.i32 2
    v9 = iadd v14, v8
    v16 = icmp slt v9, v12
    brif v16, block4(v9), block5(v9)

block5(v15: i32):
    return v15
}
"#,
    );
}

/// The back edge leaves a `brif` (a watchdog check): the copy goes into a new block
/// on that edge.
#[test]
fn rotate_through_a_check_on_the_back_edge() {
    check(
        r#"
func @f(i32) -> i32 function {
block0(v0: i32):
    v1 = iconst.i32 0
    jump block1(v1)
block1(v2: i32):
    v3 = icmp slt v2, v0
    brif v3, block2, block4
block2:
    v4 = iconst.i32 1
    v5 = iadd v2, v4
    v6 = stop_requested
    brif v6, block3, block1(v5)
block3:
    return v1
block4:
    return v2
}
"#,
        rotate::run,
        r#"
func @f(i32) -> i32 function {
block0(v0: i32):
    v1 = iconst.i32 0
    jump block1(v1)

block1(v2: i32):
    v3 = icmp slt v2, v0
    brif v3, block2(v2), block4(v2)

block2(v7: i32):
    v4 = iconst.i32 1
    v5 = iadd v7, v4
    v6 = stop_requested
    brif v6, block3, block5

block5:
    v9 = icmp slt v5, v0
    brif v9, block2(v5), block4(v5)

block3:
    return v1

block4(v8: i32):
    return v8
}
"#,
    );
}

/// An `EXIT` joins the loop's exit: the header's value used there is reached from
/// two places, so the loop stays as it is.
#[test]
fn rotate_leaves_a_loop_with_an_exit_that_uses_the_header() {
    let text = r#"
func @f(i32) -> i32 function {
block0(v0: i32):
    v1 = iconst.i32 0
    jump block1(v1)

block1(v2: i32):
    v3 = icmp slt v2, v0
    brif v3, block2, block4

block2:
    v4 = iconst.i32 7
    v5 = icmp eq v2, v4
    brif v5, block4, block3

block3:
    v6 = iconst.i32 1
    v7 = iadd v2, v6
    jump block1(v7)

block4:
    return v2
}
"#;
    check(text, rotate::run, text);
}

/// A use the header's successors do not dominate (after a join of the exit and a
/// path from the body that does not pass the exit's edge) leaves the loop as it is.
#[test]
fn rotate_leaves_a_loop_whose_value_escapes_a_join() {
    let text = r#"
func @f(i32) -> i32 function {
block0(v0: i32):
    v1 = iconst.i32 0
    jump block1(v1)

block1(v2: i32):
    v3 = icmp slt v2, v0
    brif v3, block2, block4(v1)

block2:
    v4 = iconst.i32 7
    v5 = icmp eq v2, v4
    brif v5, block4(v4), block3

block3:
    v6 = iconst.i32 1
    v7 = iadd v2, v6
    jump block1(v7)

block4(v8: i32):
    v9 = iadd v8, v2
    return v9
}
"#;
    check(text, rotate::run, text);
}

/// A header with an effect (a store) is not copied.
#[test]
fn rotate_leaves_a_test_with_an_effect() {
    let text = r#"
func @f(ptr, i32) function {
block0(v0: ptr, v1: i32):
    v2 = iconst.i32 0
    jump block1(v2)

block1(v3: i32):
    store v3, v0
    v4 = icmp slt v3, v1
    brif v4, block2, block3

block2:
    v5 = iconst.i32 1
    v6 = iadd v3, v5
    jump block1(v6)

block3:
    return
}
"#;
    check(text, rotate::run, text);
}

// ---- if_convert ----

#[test]
fn if_convert_a_triangle() {
    check(
        r#"
func @f(i32, i32, i32) -> i32 function {
block0(v0: i32, v1: i32, v2: i32):
    v3 = icmp sgt v0, v1
    brif v3, block1, block2(v1, v2)
block1:
    v4 = iconst.i32 1
    v5 = iadd v1, v4
    jump block2(v5, v2)
block2(v6: i32, v7: i32):
    v8 = iadd v6, v7
    return v8
}
"#,
        if_convert::run,
        r#"
func @f(i32, i32, i32) -> i32 function {
block0(v0: i32, v1: i32, v2: i32):
    v3 = icmp sgt v0, v1
    v4 = iconst.i32 1
    v5 = iadd v1, v4
    v9 = select v3, v5, v1
    jump block2(v9, v2)

block2(v6: i32, v7: i32):
    v8 = iadd v6, v7
    return v8
}
"#,
    );
}

#[test]
fn if_convert_a_diamond_with_parameters() {
    check(
        r#"
func @f(f32, f32) -> f32 function {
block0(v0: f32, v1: f32):
    v2 = fcmp lt v0, v1
    brif v2, block1(v0), block2(v1)
block1(v3: f32):
    v4 = fneg v3
    jump block3(v4)
block2(v5: f32):
    v6 = fmul v5, v5
    jump block3(v6)
block3(v7: f32):
    return v7
}
"#,
        if_convert::run,
        r#"
func @f(f32, f32) -> f32 function {
block0(v0: f32, v1: f32):
    v2 = fcmp lt v0, v1
    v4 = fneg v0
    v6 = fmul v1, v1
    v8 = select v2, v4, v6
    jump block3(v8)

block3(v7: f32):
    return v7
}
"#,
    );
}

/// A division may fault and a load may read what the test guards: neither moves.
#[test]
fn if_convert_leaves_what_may_fault() {
    let text = r#"
func @f(i32, i32, ptr) -> i32 function {
block0(v0: i32, v1: i32, v2: ptr):
    v3 = iconst.i32 0
    v4 = icmp ne v1, v3
    brif v4, block1, block2(v3)

block1:
    v5 = sdiv v0, v1
    jump block2(v5)

block2(v6: i32):
    brif v4, block3, block4(v6)

block3:
    v7 = load.i32 v2
    jump block4(v7)

block4(v8: i32):
    return v8
}
"#;
    check(text, if_convert::run, text);
}

// ---- fill ----

/// The JIT's view of `FOR i := 0 TO 9999 DO flags[i] := TRUE; END_FOR;` under the
/// runner (the watchdog's check merged into the body): one fill, and the counter
/// stored after the loop holds 10000.
#[test]
fn fill_a_loop_that_sets_every_flag() {
    check_in_module(
        r#"
struct %s program {
    var flags: %arr
    var i: i32 DINT
}
array %arr = [10000 x i1 BOOL] lower 0

func @f(ptr) program {
block0(v0: ptr):
    v1 = iconst.i32 0
    v2 = iconst.i32 9999
    v3 = iconst.i32 1
    jump block1(v1)
block1(v4: i32):
    v5 = icmp sgt v4, v2
    brif v5, block3, block2
block2:
    v6 = field_addr v0, %s.flags
    v7 = elem_addr v6, %arr, v4
    v8 = iconst.i1 1
    store v8, v7
    v9 = iadd v4, v3
    v10 = stop_requested
    brif v10, block4, block1(v9)
block3:
    v11 = field_addr v0, %s.i
    store v4, v11
    return
block4:
    return
}
"#,
        fill::run,
        r#"
func @f(ptr) program {
block0(v0: ptr):
    v1 = iconst.i32 0
    v6 = field_addr v0, %s.flags
    v8 = iconst.i1 1
    v16 = iconst.i64 10000
    v22 = elem_addr v6, %arr, v1
    fill v22, v8, v16
    v24 = iconst.i32 10000
    v11 = field_addr v0, %s.i
    store v24, v11
    return
}
"#,
    );
}

/// An INT counter, sign-extended and offset for an array from 1, between bounds
/// read from variables: the number of elements and the counter after the loop are
/// worked out at run time (none when `lo > hi`: element 0 is addressed, nothing
/// written, and the counter keeps `lo`).
#[test]
fn fill_between_variable_bounds() {
    check_in_module(
        r#"
array %a = [8 x i16 INT] lower 1

func @f(ptr, i16, i16, i16) -> i16 function {
block0(v0: ptr, v1: i16, v2: i16, v3: i16):
    jump block1(v1)
block1(v4: i16):
    v5 = icmp sle v4, v2
    brif v5, block2, block3
block2:
    v6 = sext.i32 v4
    v7 = iconst.i32 1
    v8 = isub v6, v7
    v9 = elem_addr v0, %a, v8
    store v3, v9
    v10 = iconst.i16 1
    v11 = iadd v4, v10
    jump block1(v11)
block3:
    return v4
}
"#,
        fill::run,
        r#"
func @f(ptr, i16, i16, i16) -> i16 function {
block0(v0: ptr, v1: i16, v2: i16, v3: i16):
    v6 = sext.i32 v1
    v7 = iconst.i32 1
    v8 = isub v6, v7
    v12 = sext.i64 v1
    v13 = sext.i64 v2
    v14 = isub v13, v12
    v15 = iconst.i64 1
    v16 = iadd v14, v15
    v17 = iconst.i64 0
    v18 = icmp sgt v16, v17
    v19 = select v18, v16, v17
    v20 = iconst.i32 0
    v21 = select v18, v8, v20
    v22 = elem_addr v0, %a, v21
    fill v22, v3, v19
    v23 = iconst.i16 1
    v24 = iadd v2, v23
    v25 = select v18, v24, v1
    return v25
}
"#,
    );
}

/// Loops that do more than set elements to one value stay loops: the value depends
/// on the counter, the body reads memory, the counter steps by 2, or the counter is
/// INT over an array as long as INT's range.
#[test]
fn fill_leaves_other_loops() {
    let shape = |value: &str, read: &str, step: i64, len: u32| {
        format!(
            r#"
array %a = [{len} x i32 DINT] lower 0

func @f(ptr, i32) function {{
block0(v0: ptr, v1: i32):
    v2 = iconst.i32 0
    v3 = iconst.i32 9
    jump block1(v2)
block1(v4: i32):
    v5 = icmp sle v4, v3
    brif v5, block2, block3
block2:
    v6 = elem_addr v0, %a, v4
    {read}
    store {value}, v6
    v10 = iconst.i32 {step}
    v11 = iadd v4, v10
    jump block1(v11)
block3:
    return
}}
"#
        )
    };
    let nothing = "v7 = iconst.i32 0";
    for text in [
        shape("v4", nothing, 1, 10),
        shape("v7", "v7 = load.i32 v0", 1, 10),
        shape("v1", nothing, 2, 10),
    ] {
        let mut m = super::parse(&text);
        let types = m.clone();
        let changed = super::apply(&mut m, "fill", |f| fill::run(f, &types));
        assert!(!changed, "{}", super::print_funcs(&m));
    }
    // The same loop with a stored value from outside is one.
    let mut m = super::parse(&shape("v1", nothing, 1, 10));
    let types = m.clone();
    assert!(super::apply(&mut m, "fill", |f| fill::run(f, &types)));
}
