//! The interpreter on modules written in the text form, and on the shared kitchen sink.

mod common;

use plcc_ir::interp::Interp;
use plcc_ir::machine::Machine;
use plcc_ir::text::parse_module;
use plcc_ir::verify::verify_module;
use plcc_ir::{ElemType, PlcValue};

/// Everything the verifier accepts decodes without a malformed instruction.
#[test]
fn kitchen_sink_decodes_cleanly() {
    let m = common::kitchen_sink();
    verify_module(&m).unwrap();
    let it = Interp::new(&m).unwrap();
    assert_eq!(it.problems(), Vec::<String>::new());
}

/// A program with a timer, an array filled and summed through a function, and a REAL
/// accumulator: each scan `count += 1; arr[(count-1) mod 5 + 1] := count;
/// total := sum(arr); r := r + 0.1; q := start AND clock_ms - t0 >= 1000`.
const PROGRAM: &str = r#"
array %a = [5 x i16 INT] lower 1
struct %main program {
    in start: i1 BOOL
    var count: i32 DINT
    var total: i32 DINT
    var arr: %a
    var r: f32 REAL
    out q: i1 BOOL
    hidden t0: i32 TIME
}

data @main: %main program

func @sum(ptr) -> i32 function {
block0(v0: ptr):
    v1 = iconst.i32 0
    jump block1(v1, v1)
block1(v2: i32, v3: i32):
    v4 = iconst.i32 5
    v5 = icmp slt v2, v4
    brif v5, block2, block3
block2:
    v6 = elem_addr v0, %a, v2
    v7 = load.i16 v6
    v8 = sext.i32 v7
    v9 = iadd v3, v8
    v10 = iconst.i32 1
    v11 = iadd v2, v10
    jump block1(v11, v9)
block3:
    return v3
}

func @main$init(ptr) init {
block0(v0: ptr):
    v1 = iconst.i1 0
    v2 = field_addr v0, %main.start
    store v1, v2
    v3 = field_addr v0, %main.q
    store v1, v3
    v4 = iconst.i32 0
    v5 = field_addr v0, %main.count
    store v4, v5
    v6 = field_addr v0, %main.total
    store v4, v6
    v7 = field_addr v0, %main.t0
    store v4, v7
    v8 = fconst.f32 0.0
    v9 = field_addr v0, %main.r
    store v8, v9
    v10 = field_addr v0, %main.arr
    v11 = iconst.i16 0
    v12 = iconst.i32 0
    jump block1(v12)
block1(v13: i32):
    v14 = iconst.i32 5
    v15 = icmp slt v13, v14
    brif v15, block2, block3
block2:
    v16 = elem_addr v10, %a, v13
    store v11, v16
    v17 = iconst.i32 1
    v18 = iadd v13, v17
    jump block1(v18)
block3:
    return
}

func @main(ptr) program {
block0(v0: ptr):
    v1 = field_addr v0, %main.count
    v2 = load.i32 v1
    v3 = iconst.i32 1
    v4 = iadd v2, v3
    store v4, v1
    v5 = iconst.i32 5
    v6 = srem v2, v5
    v7 = field_addr v0, %main.arr
    v8 = elem_addr v7, %a, v6
    v9 = itrunc.i16 v4
    store v9, v8
    v10 = call @sum(v7)
    v11 = field_addr v0, %main.total
    store v10, v11
    v12 = field_addr v0, %main.r
    v13 = load.f32 v12
    v14 = fconst.f32 0.1
    v15 = fadd v13, v14
    store v15, v12
    v16 = clock_ms
    v17 = field_addr v0, %main.start
    v18 = load.i1 v17
    v19 = field_addr v0, %main.t0
    brif v18, block1, block2
block1:
    v20 = load.i32 v19
    v21 = isub v16, v20
    v22 = iconst.i32 1000
    v23 = icmp sge v21, v22
    jump block3(v23)
block2:
    store v16, v19
    v24 = iconst.i1 0
    jump block3(v24)
block3(v25: i1):
    v26 = field_addr v0, %main.q
    store v25, v26
    return
}

program "main" data @main body @main init @main$init
"#;

#[test]
fn text_program_runs_scan_by_scan() {
    let m = parse_module(PROGRAM).unwrap();
    verify_module(&m).unwrap();
    let mut it = Interp::new(&m).unwrap();
    assert!(it.problems().is_empty());
    it.set_step_limit(Some(100_000));
    it.cold_start().unwrap();
    let mut r = 0.0f32;
    for scan in 1..=1000i64 {
        it.set_clock_us(scan * 10_000); // 10 ms per scan
        if scan == 300 {
            it.write("main.start", PlcValue::from_bool(true)).unwrap();
        }
        it.scan().unwrap();
        r += 0.1;
        // The last five counts are in the array.
        let want: i64 = (scan.saturating_sub(4).max(1)..=scan).sum();
        assert_eq!(it.read("main.total").unwrap().as_i64(), want, "scan {scan}");
        // `start` rose at scan 300 (t0 = 2990 ms): q after 1000 ms more.
        let q = scan >= 300 && scan * 10 - 2990 >= 1000;
        assert_eq!(
            it.read("main.q").unwrap(),
            PlcValue::from_bool(q),
            "scan {scan}"
        );
    }
    assert_eq!(it.read("main.count").unwrap().as_i64(), 1000);
    assert_eq!(
        it.read("main.arr[5]").unwrap(),
        PlcValue::from_i64(ElemType::Int, 1000)
    );
    // Accumulated in binary32, exactly like the loop above.
    assert_eq!(it.read("main.r").unwrap(), PlcValue::from_f32(r));
    assert!(!it.fault());
}
