//! `call_table`, calls bound at run time, on every machine of the target registry:
//! the IR programs of `ir/tests/call_table/` with scripted inputs, compared with the
//! interpreter variable by variable and on the fault flag after every scan.

#[path = "common/c_driver.rs"]
#[allow(dead_code)]
mod c_driver;
#[path = "common/ir_machines.rs"]
mod ir_machines;

use plcc_ir::text::parse_module;
use plcc_ir::verify::verify_module;
use plcc_ir::Module;

/// The machines that run calls bound at run time so far.
fn machines() -> Vec<String> {
    plcc::targets::checked_machines()
        .into_iter()
        .filter(|m| m == "host" || m.starts_with("c:") || m == "c")
        .collect()
}

fn load(name: &str) -> Module {
    let path = format!("{}/ir/tests/call_table/{name}", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).unwrap();
    let m = parse_module(&text).unwrap_or_else(|e| panic!("{path}: {e}"));
    verify_module(&m).unwrap();
    m
}

/// Four tables (integer, REAL, BOOL results and none; indexes of 8 to 64 bits), empty
/// entries, indexes out of range, a call_table in a loop: only `sel = 1` does not
/// fault.
#[test]
fn tables_agree_on_every_machine() {
    let m = load("tables.ir");
    let sels = [1, 3, 0, 2, -1, 1, 100, 4, 1, -32768, 32767, 256, 257, 1];
    let script: Vec<Vec<(&str, f64)>> = sels
        .iter()
        .enumerate()
        .map(|(k, &sel)| {
            vec![
                ("main.sel", sel as f64),
                ("main.x", (k as f64 - 5.0) * 13.0),
                ("main.y", 0.5 + k as f64),
            ]
        })
        .collect();
    let a = ir_machines::agree_with_interp(&m, &machines(), &script).unwrap();
    let want: Vec<usize> = (0..sels.len()).filter(|&k| sels[k] != 1).collect();
    assert_eq!(a.faulted, want, "on {:?}", a.machines);
    eprintln!("tables.ir agrees on interp and {:?}", a.machines);
}

/// Methods of two FB types through one table on their instances, a nested dispatch,
/// a table of empty entries.
#[test]
fn methods_agree_on_every_machine() {
    let m = load("methods.ir");
    let steps = [
        (0, 1),
        (1, 1),
        (1, 0),
        (0, 2),
        (2, 1),
        (1, 45),
        (0, 0),
        (-1, 1),
        (1, -7),
        (1, 1),
        (0, 1),
        (1, 0),
        (0, 1),
    ];
    let script: Vec<Vec<(&str, f64)>> = steps
        .iter()
        .map(|&(w, s)| vec![("main.which", w as f64), ("main.step", s as f64)])
        .collect();
    let a = ir_machines::agree_with_interp(&m, &machines(), &script).unwrap();
    assert!(
        !a.faulted.is_empty() && a.faulted.len() < steps.len(),
        "{:?}",
        a.faulted
    );
    eprintln!(
        "methods.ir agrees on interp and {:?} (faults after scans {:?})",
        a.machines, a.faulted
    );
}

/// The `c` target's files of both programs compile without a warning as C++ under
/// g++ and clang++ and as C99 under clang, and run under ASan and UBSan in an
/// executable of their own, agreeing with the interpreter.
#[test]
fn the_c_of_call_tables_is_clean_under_every_compiler_and_the_sanitizers() {
    if !plcc_c::can_run() {
        eprintln!("notice: no C compiler here; the C of call tables is not checked");
        return;
    }
    let modules = [load("tables.ir"), load("methods.ir")];
    let dir = plcc_c::cc::TempDir::new().expect("a temporary directory");
    let refs: Vec<&Module> = modules.iter().collect();
    let dirs = c_driver::write_programs(&refs, &dir.path().join("programs")).unwrap();
    for (k, c) in c_driver::COMPILERS.iter().enumerate() {
        let failed =
            c_driver::compile_programs(c, &dir.path().join(format!("pch{k}")), &dirs).unwrap();
        assert!(failed.is_empty(), "under {}: {failed:?}", c.name);
    }
    for m in &modules {
        let n = c_driver::agrees_under_asan(m, 5, 10_000).unwrap();
        assert!(n > 0);
    }
}
