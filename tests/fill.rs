//! The IR's `fill` (which the JIT's `passes::fill` makes) on the machines that lower
//! it, against the interpreter: the JIT (`memset` or a loop of stores) and the C
//! machine (a loop). The VM and the PIC16 refuse it (only the JIT's pipeline makes
//! fills): they are not asked.

#[path = "common/ir_machines.rs"]
mod ir_machines;

use plcc_ir::text::parse_module;
use plcc_ir::verify::verify_module;

#[test]
fn fills_agree_with_the_interpreter() {
    let path = format!("{}/ir/tests/fill/fill.ir", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).unwrap();
    let m = parse_module(&text).unwrap_or_else(|e| panic!("{path}: {e}"));
    verify_module(&m).unwrap();
    let machines: Vec<String> = plcc::targets::checked_machines()
        .into_iter()
        .filter(|t| t == "host" || t.starts_with("c"))
        .collect();
    // Counts of 0 and below write nothing; 7 reaches the arrays' last elements.
    let script: Vec<Vec<(&str, f64)>> = [
        (3, 1, 5),
        (0, 0, -2),
        (7, 1, 300),
        (-4, 1, 9),
        (1, 0, -1),
        (5, 1, 0),
    ]
    .iter()
    .map(|&(n, flag, v)| {
        vec![
            ("main.n", n as f64),
            ("main.flag", flag as f64),
            ("main.v", v as f64),
        ]
    })
    .collect();
    let a = ir_machines::agree_with_interp(&m, &machines, &script).unwrap();
    assert!(a.faulted.is_empty(), "{:?}", a.faulted);
    assert!(
        a.machines.iter().any(|m| m == "host"),
        "the JIT did not run: {:?}",
        a.machines
    );
    eprintln!("fill.ir agrees on interp and {:?}", a.machines);
}
