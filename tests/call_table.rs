//! `call_table`, calls bound at run time, on every machine of the target registry:
//! the IR programs of `ir/tests/call_table/` with scripted inputs, compared with the
//! interpreter variable by variable and on the fault flag after every scan.

#[path = "common/c_driver.rs"]
#[allow(dead_code)]
mod c_driver;
#[path = "common/cpdev_opcodes.rs"]
mod cpdev_opcodes;
#[path = "common/gpsim.rs"]
mod gpsim;
#[path = "common/ir_machines.rs"]
mod ir_machines;

use plcc_ir::backend::Backend;
use plcc_ir::text::parse_module;
use plcc_ir::verify::verify_module;
use plcc_ir::Module;

#[path = "common/skip.rs"]
mod skip;

/// Every machine of the registry, and the VM's 32-bit modes.
fn machines() -> Vec<String> {
    let mut ms = plcc::targets::checked_machines();
    ms.extend(["vmasm:mode=32".to_string(), "vmasm:mode=32a".to_string()]);
    ms
}

fn parse(name: &str) -> Module {
    let path = format!("{}/ir/tests/call_table/{name}", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).unwrap();
    parse_module(&text).unwrap_or_else(|e| panic!("{path}: {e}"))
}

fn load(name: &str) -> Module {
    let m = parse(name);
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

/// FB bodies of two types as the entries, each on its own instance.
#[test]
fn fb_bodies_through_a_table_agree_on_every_machine() {
    let m = load("fbs.ir");
    let runs = [
        (0, 1),
        (1, 5),
        (1, -3),
        (0, 2),
        (2, 7),
        (0, 3),
        (-1, 1),
        (1, 100),
        (0, 1),
    ];
    let script: Vec<Vec<(&str, f64)>> = runs
        .iter()
        .map(|&(w, x)| vec![("main.which", w as f64), ("main.x", x as f64)])
        .collect();
    let a = ir_machines::agree_with_interp(&m, &machines(), &script).unwrap();
    assert_eq!(a.faulted, [4, 6], "on {:?}", a.machines);
}

/// The program's own counter drives the index: every entry, the empty one and an index
/// out of range each come in turn.
#[test]
fn a_counter_driven_dispatch_agrees_on_every_machine() {
    let m = load("cycle.ir");
    let script = vec![Vec::new(); 12];
    let a = ir_machines::agree_with_interp(&m, &machines(), &script).unwrap();
    // Scan s calls entry (s + 1) mod 5: 2 is empty, 4 out of range.
    assert_eq!(a.faulted, [1, 3, 6, 8, 11], "on {:?}", a.machines);
}

/// gpasm assembles the PIC16 code of the three programs to plcc's words, and gpsim
/// ends 5 scans at the same cycles and with the same variables as plcc's simulator
/// (`tests/common/gpsim.rs`, as `tests/pic16_gpsim.rs` checks the test programs).
#[test]
fn gpsim_agrees_with_the_simulator_on_call_tables() {
    let tools = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/tools");
    if !tools.join("pic16-run").exists() || !gpsim::have("gpasm") || !gpsim::have("gpsim") {
        skip::notice("gpasm, gpsim or ../shared/tools/pic16-run is missing; skipping");
        return;
    }
    let dir = plcc_c::cc::TempDir::new().expect("a temporary directory");
    for name in ["tables.ir", "methods.ir", "cycle.ir", "fbs.ir"] {
        let stem = name.trim_end_matches(".ir");
        let fits = gpsim::check_module(&load(name), stem, &tools, dir.path())
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        assert!(fits, "{name} does not fit the chip");
    }
}

/// The `c` target's files of the programs compile without a warning as C++ under
/// g++ and clang++ and as C99 under clang, and run under ASan and UBSan in an
/// executable of their own, agreeing with the interpreter.
#[test]
fn the_c_of_call_tables_is_clean_under_every_compiler_and_the_sanitizers() {
    if !plcc_c::can_run() {
        skip::notice("no C compiler here; the C of call tables is not checked");
        return;
    }
    let modules = [
        load("tables.ir"),
        load("methods.ir"),
        load("cycle.ir"),
        load("fbs.ir"),
    ];
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

/// The VM has no call to a computed address: the compare chains and direct calls of
/// both programs use only instructions the reference's C VMs execute, in every mode
/// (the reference's table, `tests/common/cpdev_opcodes.rs`).
#[test]
fn the_vm_images_use_only_what_the_c_vms_execute() {
    for name in ["tables.ir", "methods.ir", "cycle.ir", "fbs.ir"] {
        let m = load(name);
        for mode in ["16", "32", "32a"] {
            let options = plcc_ir::backend::Options {
                settings: vec![("mode".into(), mode.into())],
                ..Default::default()
            };
            let arts = plcc_vmasm::VmasmBackend::new()
                .compile(&m, &options)
                .unwrap_or_else(|d| panic!("{name} (mode {mode}): {}", d[0]));
            let list = cpdev_opcodes::walk(&arts.files[0].bytes, mode)
                .unwrap_or_else(|e| panic!("{name} (mode {mode}): {e}"));
            assert!(!list.is_empty());
        }
    }
}

/// Recursion through a table: the verifier rejects it (the driver runs it before any
/// backend), and every backend given the module anyway refuses it with a diagnostic,
/// never a panic, a hang or code with static frames that would overwrite each other.
#[test]
fn recursion_through_a_table_is_refused() {
    let m = parse("recursion.ir");
    let errs = verify_module(&m).unwrap_err();
    assert!(
        errs.iter()
            .any(|e| e.message.contains("recursion: @again -> @step -> @again")),
        "{errs:?}"
    );
    for t in plcc::targets::TARGETS {
        let Some(make) = t.backend else { continue };
        let d = make()
            .compile(&m, &plcc_ir::backend::Options::default())
            .err()
            .unwrap_or_else(|| panic!("{} compiled a recursive module", t.name));
        eprintln!("{}: {}", t.name, d[0]);
    }
}

/// A chain of `n` functions below the program body, entered by a direct call or
/// through a table whose other entry calls nothing.
fn nested(n: usize, through_table: bool) -> Module {
    let mut t = String::from("struct %main program {\n    var x: i16 INT\n}\n\n");
    t.push_str("data @main: %main program\n\n");
    t.push_str("table t0 \"I_Deep.Go\" (i16) -> i16 = [@leaf, @f1]\n\n");
    t.push_str("func @leaf(i16) -> i16 function {\nblock0(v0: i16):\n    return v0\n}\n\n");
    for k in 1..=n {
        t.push_str(&format!(
            "func @f{k}(i16) -> i16 function {{\nblock0(v0: i16):\n"
        ));
        t.push_str("    v1 = iconst.i16 1\n    v2 = iadd v0, v1\n");
        if k < n {
            t.push_str(&format!(
                "    v3 = call @f{}(v2)\n    return v3\n}}\n\n",
                k + 1
            ));
        } else {
            t.push_str("    return v2\n}\n\n");
        }
    }
    t.push_str("func @main(ptr) program {\nblock0(v0: ptr):\n");
    t.push_str("    v1 = field_addr v0, %main.x\n    v2 = load.i16 v1\n");
    if through_table {
        t.push_str("    v3 = iconst.i16 1\n    v4 = band v2, v3\n");
        t.push_str("    v5 = call_table t0, v4(v2)\n");
    } else {
        t.push_str("    v5 = call @f1(v2)\n");
    }
    t.push_str("    store v5, v1\n    return\n}\n\n");
    t.push_str("func @main$init(ptr) init {\nblock0(v0: ptr):\n");
    t.push_str("    v1 = iconst.i16 1\n    v2 = field_addr v0, %main.x\n");
    t.push_str("    store v1, v2\n    return\n}\n\n");
    t.push_str("program \"main\" data @main body @main init @main$init\n");
    let m = parse_module(&t).unwrap_or_else(|e| panic!("{e}\n{t}"));
    verify_module(&m).unwrap();
    m
}

/// The PIC16's 8-level stack: a call through a table costs what a direct call of its
/// deepest entry costs (the compare chain itself uses no level), so the deepest chain
/// that fits is the same both ways, one more is E9004 both ways, and what fits runs
/// as the interpreter does.
#[test]
fn the_pic16_counts_the_deepest_entry_in_its_stack_depth() {
    let fits = |m: &Module| match plcc_pic16::build(m, &plcc_ir::backend::Options::default()) {
        Ok(_) => true,
        Err(d) if d.iter().all(|x| x.code == "E9004") => false,
        Err(d) => panic!("{}", d[0]),
    };
    let deepest = (1..12)
        .take_while(|&n| fits(&nested(n, false)))
        .last()
        .unwrap();
    assert!(deepest >= 3, "only {deepest} nested calls fit");
    eprintln!("{deepest} nested calls below the body fit the PIC16's stack");
    assert!(fits(&nested(deepest, true)));
    assert!(!fits(&nested(deepest + 1, true)));
    let pic = vec!["pic16f876a".to_string()];
    let a =
        ir_machines::agree_with_interp(&nested(deepest, true), &pic, &vec![Vec::new(); 4]).unwrap();
    assert!(a.faulted.is_empty());
}
