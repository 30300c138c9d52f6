//! Before/after tests of each pass, in the text form.

use super::check;
use crate::passes::{const_fold, copy_prop, dce, load_store, mem2reg, simplify_cfg};

// ---- mem2reg ----

#[test]
fn mem2reg_straight_line() {
    check(
        r#"
func @f(i32) -> i32 function {
    ss0 = slot i32 "x"
block0(v0: i32):
    v1 = slot_addr ss0
    store v0, v1
    v2 = slot_addr ss0
    v3 = load.i32 v2
    v4 = iadd v3, v3
    store v4, v1
    v5 = load.i32 v2
    return v5
}
"#,
        mem2reg::run,
        r#"
func @f(i32) -> i32 function {
block0(v0: i32):
    v4 = iadd v0, v0
    return v4
}
"#,
    );
}

#[test]
fn mem2reg_diamond_gets_a_block_param() {
    check(
        r#"
func @f(i1) -> i32 function {
    ss0 = slot i32 "x"
block0(v0: i1):
    v1 = slot_addr ss0
    brif v0, block1, block2
block1:
    v2 = iconst.i32 1
    store v2, v1
    jump block3
block2:
    v3 = iconst.i32 2
    store v3, v1
    jump block3
block3:
    v4 = load.i32 v1
    return v4
}
"#,
        mem2reg::run,
        r#"
func @f(i1) -> i32 function {
block0(v0: i1):
    brif v0, block1, block2

block1:
    v2 = iconst.i32 1
    jump block3(v2)

block2:
    v3 = iconst.i32 2
    jump block3(v3)

block3(v5: i32):
    return v5
}
"#,
    );
}

#[test]
fn mem2reg_loop() {
    // i := 0; WHILE i < n DO i := i + 1; END_WHILE; RETURN i
    check(
        r#"
func @f(i32) -> i32 function {
    ss0 = slot i32 "i"
    ss1 = slot i32 "n"
block0(v0: i32):
    v1 = slot_addr ss1
    store v0, v1
    v2 = slot_addr ss0
    v3 = iconst.i32 0
    store v3, v2
    jump block1
block1:
    v4 = slot_addr ss0
    v5 = load.i32 v4
    v6 = slot_addr ss1
    v7 = load.i32 v6
    v8 = icmp slt v5, v7
    brif v8, block2, block3
block2:
    v9 = slot_addr ss0
    v10 = load.i32 v9
    v11 = iconst.i32 1
    v12 = iadd v10, v11
    v13 = slot_addr ss0
    store v12, v13
    jump block1
block3:
    v14 = slot_addr ss0
    v15 = load.i32 v14
    return v15
}
"#,
        mem2reg::run,
        r#"
func @f(i32) -> i32 function {
block0(v0: i32):
    v3 = iconst.i32 0
    jump block1(v3)

block1(v16: i32):
    v8 = icmp slt v16, v0
    brif v8, block2, block3

block2:
    v11 = iconst.i32 1
    v12 = iadd v16, v11
    jump block1(v12)

block3:
    return v16
}
"#,
    );
}

#[test]
fn mem2reg_keeps_escaping_and_mistyped_slots() {
    // ss0 escapes into a call, ss1 is read with another type, ss2 is an aggregate,
    // ss4 is stored a value of another type, ss6 has its address stored; ss3 (a
    // pointer) is promotable and ss5 unused: both go, and the others are renumbered.
    check(
        r#"
array %A = [2 x i32 DINT] lower 0
func @g(ptr) function {
block0(v0: ptr):
    return
}
func @f(i32) -> i32 function {
    ss0 = slot i32 "a"
    ss1 = slot i32 "b"
    ss2 = slot %A "c"
    ss3 = slot ptr "d"
    ss4 = slot i32 "e"
    ss5 = slot i16 "unused"
    ss6 = slot i32 "f"
block0(v0: i32):
    v1 = slot_addr ss0
    call @g(v1)
    v2 = slot_addr ss1
    store v0, v2
    v3 = load.i16 v2
    v4 = slot_addr ss2
    v5 = slot_addr ss4
    store v4, v5
    v6 = slot_addr ss6
    v7 = slot_addr ss3
    store v6, v7
    v8 = load.i32 v6
    return v8
}
"#,
        mem2reg::run,
        r#"
func @g(ptr) function {
block0(v0: ptr):
    return
}

func @f(i32) -> i32 function {
    ss0 = slot i32 "a"
    ss1 = slot i32 "b"
    ss2 = slot %A "c"
    ss3 = slot i32 "e"
    ss4 = slot i32 "f"
block0(v0: i32):
    v1 = slot_addr ss0
    call @g(v1)
    v2 = slot_addr ss1
    store v0, v2
    v3 = load.i16 v2
    v4 = slot_addr ss2
    v5 = slot_addr ss3
    store v4, v5
    v6 = slot_addr ss4
    v8 = load.i32 v6
    return v8
}
"#,
    );
}

#[test]
fn mem2reg_read_before_write_is_zero() {
    check(
        r#"
func @f(i1) -> f32 function {
    ss0 = slot f32 "x"
    ss1 = slot i8 "y"
block0(v0: i1):
    v1 = slot_addr ss0
    v9 = slot_addr ss1
    brif v0, block1, block2
block1:
    v2 = fconst.f32 1.5
    store v2, v1
    jump block2
block2:
    v3 = load.f32 v1
    v4 = load.i8 v9
    return v3
}
"#,
        mem2reg::run,
        r#"
func @f(i1) -> f32 function {
block0(v0: i1):
    v11 = fconst.f32 0.0
    v12 = iconst.i8 0
    brif v0, block1, block2(v11)

block1:
    v2 = fconst.f32 1.5
    jump block2(v2)

block2(v10: f32):
    return v10
}
"#,
    );
}

#[test]
fn mem2reg_loop_to_entry_splits_the_entry() {
    check(
        r#"
func @f(i32) -> i32 function {
    ss0 = slot i32 "x"
block0(v0: i32):
    v1 = slot_addr ss0
    v2 = load.i32 v1
    v3 = iadd v2, v0
    store v3, v1
    v4 = icmp slt v3, v0
    brif v4, block0(v3), block1
block1:
    return v3
}
"#,
        mem2reg::run,
        r#"
func @f(i32) -> i32 function {
block2(v5: i32):
    v7 = iconst.i32 0
    jump block0(v5, v7)

block0(v0: i32, v6: i32):
    v3 = iadd v6, v0
    v4 = icmp slt v3, v0
    brif v4, block0(v3, v3), block1

block1:
    return v3
}
"#,
    );
}

// ---- const_fold ----

#[test]
fn const_fold_integers_wrap_at_width() {
    check(
        r#"
func @f() -> i8 function {
block0:
    v0 = iconst.i8 100
    v1 = iconst.i8 100
    v2 = iadd v0, v1
    v3 = iconst.i8 -128
    v4 = iconst.i8 -1
    v5 = sdiv v3, v4
    v6 = srem v3, v4
    v7 = iabs v3
    v8 = iconst.i8 9
    v9 = ishl v0, v8
    v10 = sshr v3, v8
    v11 = iconst.i8 3
    v12 = rotl v3, v11
    v13 = rotr v3, v11
    v14 = udiv v3, v11
    v15 = isub v2, v5
    return v15
}
"#,
        const_fold::run,
        r#"
func @f() -> i8 function {
block0:
    v0 = iconst.i8 100
    v1 = iconst.i8 100
    v2 = iconst.i8 -56
    v3 = iconst.i8 -128
    v4 = iconst.i8 -1
    v5 = iconst.i8 -128
    v6 = iconst.i8 0
    v7 = iconst.i8 -128
    v8 = iconst.i8 9
    v9 = iconst.i8 0
    v10 = iconst.i8 -1
    v11 = iconst.i8 3
    v12 = iconst.i8 4
    v13 = iconst.i8 16
    v14 = iconst.i8 42
    v15 = iconst.i8 72
    return v15
}
"#,
    );
}

#[test]
fn const_fold_keeps_division_by_zero() {
    check(
        r#"
func @f(i32) -> i32 function {
block0(v0: i32):
    v1 = iconst.i32 0
    v2 = iconst.i32 7
    v3 = sdiv v2, v1
    v4 = urem v0, v1
    v5 = sdiv v0, v2
    v6 = iadd v3, v4
    v7 = iadd v6, v5
    return v7
}
"#,
        const_fold::run,
        r#"
func @f(i32) -> i32 function {
block0(v0: i32):
    v1 = iconst.i32 0
    v2 = iconst.i32 7
    v3 = sdiv v2, v1
    v4 = urem v0, v1
    v5 = sdiv v0, v2
    v6 = iadd v3, v4
    v7 = iadd v6, v5
    return v7
}
"#,
    );
}

#[test]
fn const_fold_identities() {
    check(
        r#"
func @f(i32, i32, i1) -> i32 function {
block0(v0: i32, v1: i32, v2: i1):
    v3 = iconst.i32 0
    v4 = iconst.i32 1
    v5 = iconst.i32 -1
    v6 = iadd v0, v3
    v7 = imul v6, v4
    v8 = bor v7, v3
    v9 = band v8, v5
    v10 = bxor v9, v3
    v11 = ishl v10, v3
    v12 = imul v11, v3
    v13 = iadd v12, v1
    v14 = select v2, v13, v13
    v15 = bnot v14
    v16 = bnot v15
    v17 = icmp sle v16, v16
    v18 = select v17, v16, v0
    v19 = isub v18, v18
    v20 = iadd v18, v19
    return v20
}
"#,
        const_fold::run,
        r#"
func @f(i32, i32, i1) -> i32 function {
block0(v0: i32, v1: i32, v2: i1):
    v3 = iconst.i32 0
    v4 = iconst.i32 1
    v5 = iconst.i32 -1
    v12 = iconst.i32 0
    v15 = bnot v1
    v17 = iconst.i1 1
    v19 = iconst.i32 0
    return v1
}
"#,
    );
}

#[test]
fn const_fold_floats_and_conversions() {
    check(
        r#"
func @f() -> i32 function {
block0:
    v0 = fconst.f32 2.5
    v1 = fnearest v0
    v2 = fconst.f32 0.1
    v3 = fconst.f32 0.2
    v4 = fadd v2, v3
    v5 = fconst.f64 1e300
    v6 = ftosi.i16 v5
    v7 = fconst.f32 -0.0
    v8 = fsqrt v7
    v9 = fconst.f32 -1.0
    v10 = fsqrt v9
    v11 = ftoui.i8 v9
    v12 = fcmp ne v10, v10
    v13 = fcmp eq v10, v10
    v14 = sin v0
    v15 = iconst.i16 -1
    v16 = uext.i32 v15
    v17 = sext.i32 v15
    v18 = sitof.f32 v16
    v19 = bitcast.i32 v0
    v20 = ftosi.i32 v10
    return v16
}
"#,
        const_fold::run,
        r#"
func @f() -> i32 function {
block0:
    v0 = fconst.f32 2.5
    v1 = fconst.f32 2.0
    v2 = fconst.f32 0.1
    v3 = fconst.f32 0.2
    v4 = fconst.f32 0.3
    v5 = fconst.f64 1e300
    v6 = iconst.i16 32767
    v7 = fconst.f32 -0.0
    v8 = fconst.f32 -0.0
    v9 = fconst.f32 -1.0
    v10 = fsqrt v9
    v11 = iconst.i8 0
    v12 = fcmp ne v10, v10
    v13 = fcmp eq v10, v10
    v14 = sin v0
    v15 = iconst.i16 -1
    v16 = iconst.i32 65535
    v17 = iconst.i32 -1
    v18 = fconst.f32 65535.0
    v19 = iconst.i32 1075838976
    v20 = ftosi.i32 v10
    return v16
}
"#,
    );
}

#[test]
fn const_fold_branches_and_strength_reduction() {
    check(
        r#"
func @f(i32, i1) -> i32 function {
block0(v0: i32, v1: i1):
    v2 = iconst.i32 8
    v3 = imul v0, v2
    v4 = udiv v3, v2
    v5 = urem v4, v2
    v6 = iconst.i1 1
    brif v6, block1(v5), block2
block1(v7: i32):
    v8 = bnot v1
    brif v8, block2, block3
block2:
    return v0
block3:
    v9 = icmp slt v7, v0
    v10 = bnot v9
    v11 = uext.i32 v10
    v12 = iconst.i32 0
    v13 = icmp ne v11, v12
    v14 = select v13, v0, v7
    return v14
}
"#,
        const_fold::run,
        r#"
func @f(i32, i1) -> i32 function {
block0(v0: i32, v1: i1):
    v2 = iconst.i32 8
    v15 = iconst.i32 3
    v3 = ishl v0, v15
    v16 = iconst.i32 3
    v4 = ushr v3, v16
    v17 = iconst.i32 7
    v5 = band v4, v17
    v6 = iconst.i1 1
    jump block1(v5)

block1(v7: i32):
    v8 = bnot v1
    brif v1, block3, block2

block2:
    return v0

block3:
    v9 = icmp slt v7, v0
    v10 = icmp sge v7, v0
    v11 = uext.i32 v10
    v12 = iconst.i32 0
    v14 = select v10, v0, v7
    return v14
}
"#,
    );
}

// ---- copy_prop ----

#[test]
fn copy_prop_removes_trivial_params() {
    check(
        r#"
func @f(i32, i1) -> i32 function {
block0(v0: i32, v1: i1):
    jump block1(v0, v0)
block1(v2: i32, v3: i32):
    v4 = iconst.i32 1
    v5 = iadd v3, v4
    brif v1, block1(v2, v5), block2(v2)
block2(v6: i32):
    v7 = select v1, v6, v2
    v8 = iadd v7, v3
    return v8
}
"#,
        copy_prop::run,
        r#"
func @f(i32, i1) -> i32 function {
block0(v0: i32, v1: i1):
    jump block1(v0)

block1(v3: i32):
    v4 = iconst.i32 1
    v5 = iadd v3, v4
    brif v1, block1(v5), block2

block2:
    v8 = iadd v0, v3
    return v8
}
"#,
    );
}

// ---- load_store ----

const STRUCTS: &str = r#"
struct %S struct {
    var a: i32 DINT
    var b: i32 DINT
    var arr: %A
}
array %A = [4 x i16 INT] lower 0
data @g: %S global
data @h: %S global
"#;

#[test]
fn load_store_forwards_within_a_block() {
    check(
        &format!(
            "{STRUCTS}{}",
            r#"
func @f(ptr, i32) -> i32 function {
block0(v0: ptr, v1: i32):
    v2 = field_addr v0, %S.a
    store v1, v2
    v3 = field_addr v0, %S.b
    v4 = load.i32 v3
    v5 = field_addr v0, %S.a
    v6 = load.i32 v5
    v7 = field_addr v0, %S.b
    v8 = load.i32 v7
    v9 = iadd v6, v8
    v10 = global_addr @g
    v11 = field_addr v10, %S.a
    store v9, v11
    v12 = load.i32 v5
    v13 = global_addr @h
    v14 = field_addr v13, %S.a
    v15 = load.i32 v14
    v16 = global_addr @g
    v17 = field_addr v16, %S.a
    v18 = load.i32 v17
    v19 = load.i16 v17
    v20 = iadd v12, v15
    v21 = iadd v20, v18
    return v21
}
"#
        ),
        load_store::run,
        r#"
func @f(ptr, i32) -> i32 function {
block0(v0: ptr, v1: i32):
    v2 = field_addr v0, %S.a
    store v1, v2
    v3 = field_addr v0, %S.b
    v4 = load.i32 v3
    v5 = field_addr v0, %S.a
    v7 = field_addr v0, %S.b
    v9 = iadd v1, v4
    v10 = global_addr @g
    v11 = field_addr v10, %S.a
    store v9, v11
    v12 = load.i32 v5
    v13 = global_addr @h
    v14 = field_addr v13, %S.a
    v15 = load.i32 v14
    v16 = global_addr @g
    v17 = field_addr v16, %S.a
    v19 = load.i16 v17
    v20 = iadd v12, v15
    v21 = iadd v20, v9
    return v21
}
"#,
    );
}

#[test]
fn load_store_calls_and_unknown_indices_clobber() {
    check(
        &format!(
            "{STRUCTS}{}",
            r#"
func @g() function {
block0:
    return
}
func @f(ptr, i32) -> i16 function {
block0(v0: ptr, v1: i32):
    v2 = field_addr v0, %S.arr
    v3 = iconst.i32 1
    v4 = elem_addr v2, %A, v3
    v5 = load.i16 v4
    v6 = iconst.i32 2
    v7 = elem_addr v2, %A, v6
    store v5, v7
    v8 = load.i16 v4
    v9 = elem_addr v2, %A, v1
    store v8, v9
    v10 = load.i16 v4
    v11 = field_addr v0, %S.a
    v12 = load.i32 v11
    call @g()
    v13 = load.i32 v11
    v14 = itrunc.i16 v13
    v15 = iadd v10, v14
    return v15
}
"#
        ),
        load_store::run,
        r#"
func @g() function {
block0:
    return
}

func @f(ptr, i32) -> i16 function {
block0(v0: ptr, v1: i32):
    v2 = field_addr v0, %S.arr
    v3 = iconst.i32 1
    v4 = elem_addr v2, %A, v3
    v5 = load.i16 v4
    v6 = iconst.i32 2
    v7 = elem_addr v2, %A, v6
    store v5, v7
    v9 = elem_addr v2, %A, v1
    store v5, v9
    v10 = load.i16 v4
    v11 = field_addr v0, %S.a
    v12 = load.i32 v11
    call @g()
    v13 = load.i32 v11
    v14 = itrunc.i16 v13
    v15 = iadd v10, v14
    return v15
}
"#,
    );
}

#[test]
fn load_store_dead_and_redundant_stores() {
    check(
        &format!(
            "{STRUCTS}{}",
            r#"
func @f(ptr, ptr, i32) function {
block0(v0: ptr, v1: ptr, v2: i32):
    v3 = field_addr v0, %S.a
    v4 = field_addr v0, %S.b
    store v2, v3
    store v2, v4
    v5 = iconst.i32 1
    store v5, v3
    v6 = load.i32 v4
    store v6, v4
    v7 = field_addr v1, %S.a
    store v5, v7
    v8 = load.i32 v7
    store v2, v7
    v9 = sdiv v2, v6
    store v5, v7
    return
}
"#
        ),
        load_store::run,
        r#"
func @f(ptr, ptr, i32) function {
block0(v0: ptr, v1: ptr, v2: i32):
    v3 = field_addr v0, %S.a
    v4 = field_addr v0, %S.b
    store v2, v4
    v5 = iconst.i32 1
    store v5, v3
    v7 = field_addr v1, %S.a
    store v2, v7
    v9 = sdiv v2, v2
    store v5, v7
    return
}
"#,
    );
}

// ---- dce ----

#[test]
fn dce_removes_dead_code_and_params() {
    check(
        r#"
func @f(i32, i1) -> i32 function {
block0(v0: i32, v1: i1):
    v2 = iconst.i32 0
    v3 = iconst.i32 3
    v4 = sdiv v0, v3
    v5 = sdiv v0, v2
    v6 = udiv v0, v0
    v7 = iadd v0, v0
    v8 = clock_ms
    jump block1(v0, v7)
block1(v9: i32, v10: i32):
    v11 = iadd v10, v10
    brif v1, block1(v9, v11), block2
block2:
    return v9
}
"#,
        dce::run,
        r#"
func @f(i32, i1) -> i32 function {
block0(v0: i32, v1: i1):
    v2 = iconst.i32 0
    v5 = sdiv v0, v2
    v6 = udiv v0, v0
    jump block1(v0)

block1(v9: i32):
    brif v1, block1(v9), block2

block2:
    return v9
}
"#,
    );
}

// ---- simplify_cfg ----

#[test]
fn simplify_cfg_threads_merges_and_prunes() {
    check(
        r#"
func @f(i32, i1) -> i32 function {
block0(v0: i32, v1: i1):
    brif v1, block1(v0), block2
block1(v2: i32):
    jump block3(v2, v0)
block2:
    v3 = iconst.i32 5
    jump block1(v3)
block3(v4: i32, v5: i32):
    v6 = iadd v4, v5
    jump block4
block4:
    brif v1, block5, block5
block5:
    return v6
block6:
    v7 = iconst.i32 1
    jump block5
}
"#,
        simplify_cfg::run,
        r#"
func @f(i32, i1) -> i32 function {
block0(v0: i32, v1: i1):
    brif v1, block3(v0, v0), block2

block2:
    v3 = iconst.i32 5
    jump block3(v3, v0)

block3(v4: i32, v5: i32):
    v6 = iadd v4, v5
    return v6
}
"#,
    );
}

// ---- the driver ----

#[test]
fn driver_optimises_naive_lowering() {
    // FUNCTION f : INT  VAR_INPUT x : INT; END_VAR  VAR t : INT; END_VAR
    //   t := x * 2; IF t > 10 THEN f := t - 10; RETURN; END_IF; f := t + 3 * 4;
    // lowered naively, dead block after RETURN included.
    let mut m = super::parse(
        r#"
func @f(i16) -> i16 function {
    ss0 = slot i16 "x"
    ss1 = slot i16 "t"
    ss2 = slot i16 "f"
block0(v0: i16):
    v1 = slot_addr ss0
    store v0, v1
    v2 = slot_addr ss0
    v3 = load.i16 v2
    v4 = iconst.i16 2
    v5 = imul v3, v4
    v6 = slot_addr ss1
    store v5, v6
    v7 = slot_addr ss1
    v8 = load.i16 v7
    v9 = iconst.i16 10
    v10 = icmp sgt v8, v9
    brif v10, block1, block2
block1:
    v11 = slot_addr ss1
    v12 = load.i16 v11
    v13 = iconst.i16 10
    v14 = isub v12, v13
    v15 = slot_addr ss2
    store v14, v15
    v16 = slot_addr ss2
    v17 = load.i16 v16
    return v17
block3:
    jump block2
block2:
    v18 = slot_addr ss1
    v19 = load.i16 v18
    v20 = iconst.i16 3
    v21 = iconst.i16 4
    v22 = imul v20, v21
    v23 = iadd v19, v22
    v24 = slot_addr ss2
    store v23, v24
    v25 = slot_addr ss2
    v26 = load.i16 v25
    return v26
}
"#,
    );
    super::apply(
        &mut m,
        "optimize_function",
        crate::passes::optimize_function,
    );
    let got = super::print_funcs(&m);
    let expected = r#"func @f(i16) -> i16 function {
block0(v0: i16):
    v27 = iconst.i16 1
    v5 = ishl v0, v27
    v9 = iconst.i16 10
    v10 = icmp sgt v5, v9
    brif v10, block1, block2

block1:
    v14 = isub v5, v9
    return v14

block2:
    v22 = iconst.i16 12
    v23 = iadd v5, v22
    return v23
}
"#;
    assert_eq!(got, expected);
}

// ---- regressions ----

#[test]
fn simplify_cfg_keeps_a_forwarder_whose_params_are_used_later() {
    // block1 only jumps, but block2 (which it dominates) reads its parameter: edges
    // into block1 must not bypass it.
    check(
        r#"
func @f(i32, i1) -> i32 function {
block0(v0: i32, v1: i1):
    brif v1, block1(v0), block3
block3:
    v5 = iconst.i32 7
    jump block1(v5)
block1(v2: i32):
    jump block2
block2:
    v3 = iadd v2, v2
    brif v1, block4, block2
block4:
    return v3
}
"#,
        simplify_cfg::run,
        r#"
func @f(i32, i1) -> i32 function {
block0(v0: i32, v1: i1):
    brif v1, block1(v0), block3

block3:
    v5 = iconst.i32 7
    jump block1(v5)

block1(v2: i32):
    jump block2

block2:
    v3 = iadd v2, v2
    brif v1, block4, block2

block4:
    return v3
}
"#,
    );
}

#[test]
fn load_store_same_field_of_possibly_equal_elements_aliases() {
    // a[i].x := v1; r := a[j].x  -- i and j may be equal: no forwarding, and the store
    // to a[j].y does not touch a[i].x.
    check(
        r#"
struct %R struct {
    var x: i32 DINT
    var y: i32 DINT
}
array %RA = [4 x %R] lower 0
func @f(ptr, i32, i32, i32) -> i32 function {
block0(v0: ptr, v1: i32, v2: i32, v3: i32):
    v4 = elem_addr v0, %RA, v2
    v5 = field_addr v4, %R.x
    store v1, v5
    v6 = elem_addr v0, %RA, v3
    v7 = field_addr v6, %R.y
    store v2, v7
    v8 = load.i32 v5
    v9 = field_addr v6, %R.x
    v10 = load.i32 v9
    v11 = iadd v8, v10
    return v11
}
"#,
        load_store::run,
        r#"
func @f(ptr, i32, i32, i32) -> i32 function {
block0(v0: ptr, v1: i32, v2: i32, v3: i32):
    v4 = elem_addr v0, %RA, v2
    v5 = field_addr v4, %R.x
    store v1, v5
    v6 = elem_addr v0, %RA, v3
    v7 = field_addr v6, %R.y
    store v2, v7
    v9 = field_addr v6, %R.x
    v10 = load.i32 v9
    v11 = iadd v1, v10
    return v11
}
"#,
    );
}

#[test]
fn mem2reg_undefined_pointer_uses_the_slot_address() {
    // A pointer variable read before any write (a front-end bug) reads some valid
    // address: its own slot's, which stays declared.
    check(
        r#"
func @f(i1, ptr) -> ptr function {
    ss0 = slot i32 "unused"
    ss1 = slot ptr "p"
block0(v0: i1, v1: ptr):
    v2 = slot_addr ss1
    brif v0, block1, block2
block1:
    store v1, v2
    jump block2
block2:
    v3 = load.ptr v2
    return v3
}
"#,
        mem2reg::run,
        r#"
func @f(i1, ptr) -> ptr function {
    ss0 = slot ptr "p"
block0(v0: i1, v1: ptr):
    v5 = slot_addr ss0
    brif v0, block1, block2(v5)

block1:
    jump block2(v1)

block2(v4: ptr):
    return v4
}
"#,
    );
}

/// A fill writes elements from its address on: the value stored into another element
/// before it is not forwarded to a load after it, and the store before it stays.
#[test]
fn load_store_fills_clobber() {
    let func = r#"
func @f(ptr, i16) -> i16 function {
block0(v0: ptr, v1: i16):
    v2 = field_addr v0, %S.arr
    v3 = iconst.i32 1
    v4 = elem_addr v2, %A, v3
    store v1, v4
    v5 = iconst.i32 0
    v6 = elem_addr v2, %A, v5
    v7 = iconst.i16 7
    v8 = iconst.i64 4
    fill v6, v7, v8
    v9 = load.i16 v4
    return v9
}
"#;
    check(&format!("{STRUCTS}{func}"), load_store::run, func);
}

/// The constants a backend can fill byte by byte, and those it cannot.
#[test]
fn fill_repeated_bytes() {
    let m = super::parse(
        r#"
func @f(i32) function {
block0(v0: i32):
    v1 = iconst.i32 -1
    v2 = iconst.i16 258
    v3 = fconst.f64 0.0
    v4 = fconst.f64 2.5
    v5 = iconst.i1 1
    return
}
"#,
    );
    let f = &m.funcs[0];
    let byte =
        |v: u32, size| crate::passes::fill::repeated_byte(f, crate::entities::Value(v), size);
    assert_eq!(byte(1, 4), Some(0xFF));
    assert_eq!(byte(2, 2), None);
    assert_eq!(byte(3, 8), Some(0));
    assert_eq!(byte(4, 8), None);
    assert_eq!(byte(5, 1), Some(1));
    assert_eq!(byte(0, 4), None);
}
