//! The IR's `fill` (which `passes::fill` makes for the JIT and the VM) on the machines
//! that lower it, against the interpreter: the JIT (`memset` or a loop of stores), the
//! C machine (a loop) and the VM (FPAT and MEMCPs for constant counts, else a loop
//! through a pointer). The PIC16 refuses it (its pipeline makes no fills): it is not
//! asked.

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
    // The VM in its three modes: FPAT counts a byte, FPAT4A (aligned mode) a word.
    let machines: Vec<String> = plcc::targets::checked_machines()
        .into_iter()
        .filter(|t| t == "host" || t.starts_with("c") || t.starts_with("vmasm"))
        .chain(["vmasm:mode=32".to_string(), "vmasm:mode=32a".to_string()])
        .collect();
    // Counts of 0 and below write nothing; 7 reaches the arrays' last elements.
    // `s` (-2..=3) is where the run-time-start fills begin.
    let script: Vec<Vec<(&str, f64)>> = [
        (3, 1, 5, 0),
        (0, 0, -2, -2),
        (7, 1, 300, 3),
        (-4, 1, 9, 1),
        (1, 0, -1, -1),
        (5, 1, 0, 2),
    ]
    .iter()
    .map(|&(n, flag, v, s)| {
        vec![
            ("main.n", n as f64),
            ("main.flag", flag as f64),
            ("main.v", v as f64),
            ("main.s", s as f64),
        ]
    })
    .collect();
    let a = ir_machines::agree_with_interp(&m, &machines, &script).unwrap();
    assert!(a.faulted.is_empty(), "{:?}", a.faulted);
    for want in ["host", "vmasm"] {
        assert!(
            a.machines.iter().any(|m| m.starts_with(want)),
            "{want} did not run: {:?}",
            a.machines
        );
    }
    eprintln!("fill.ir agrees on interp and {:?}", a.machines);
}
