//! The VM loads the constant pool of a task's PROGRAM body once, at cold start, from a
//! unit of its own (`?CONST`, called in `TSKSTR`), instead of on every scan; bodies
//! something else calls keep theirs in their prologue. The machines agree with the
//! interpreter over several scans, with data memory full of garbage at cold start.

#[path = "common/cli.rs"]
mod cli;
#[path = "common/ir_machines.rs"]
#[allow(dead_code)]
mod ir_machines;

use plcc::driver::{build_sources, BuildOptions};
use plcc_ir::Module;

fn module(src: &str) -> Module {
    build_sources(
        vec![("p.st".to_string(), src.as_bytes().to_vec())],
        &BuildOptions::default(),
    )
    .unwrap()
    .module
    .unwrap()
}

/// The listing's lines from `label`'s line to the next unit's label (a line whose
/// text column is a `:?plcc.` label).
fn unit<'a>(listing: &'a str, label: &str) -> Vec<&'a str> {
    let text = |l: &'a str| l.split('|').nth(2).unwrap_or("").trim();
    let is_unit = |l: &'a str| text(l).starts_with(":?plcc.");
    let mut lines = listing.lines().skip_while(|l| text(l) != label);
    let first = lines.next().into_iter();
    first.chain(lines.take_while(|l| !is_unit(l))).collect()
}

fn listing(name: &str, src: &str) -> String {
    let dir = std::env::temp_dir().join(format!("plcc-vmasm-const-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let st = dir.join(format!("{name}.st"));
    std::fs::write(&st, src).unwrap();
    let out = cli::plcc(&[
        "--target",
        "vmasm",
        "--emit",
        "asm",
        "-o",
        "-",
        st.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", cli::stderr(&out));
    cli::stdout(&out)
}

const ALONE: &str = "
PROGRAM main
VAR total : DINT := 5; x : DINT; r : REAL := 1.5; END_VAR
  total := total + 7000;
  x := total MOD 13;
  r := r * 1.25 + 0.5;
END_PROGRAM
";

const CONFIGURED: &str = "
PROGRAM counter
VAR total : DINT := 5; x : DINT; END_VAR
  total := total + 7000;
  x := total MOD 13;
END_PROGRAM

PROGRAM other
VAR n : DINT; END_VAR
  n := n + 3000;
END_PROGRAM

CONFIGURATION cfg
  RESOURCE r ON PLC
    TASK t(INTERVAL := T#10ms, PRIORITY := 1);
    PROGRAM a WITH t : counter;
    PROGRAM b WITH t : counter;
    PROGRAM c WITH t : other;
  END_RESOURCE
END_CONFIGURATION
";

#[test]
fn a_program_body_loads_its_constants_at_cold_start() {
    let asm = listing("alone", ALONE);
    let start = unit(&asm, ":?plcc.TASK?TSKSTR");
    assert!(
        start
            .iter()
            .any(|l| l.ends_with("CALB main, :?plcc.main?CONST")),
        "{start:#?}"
    );
    let pool = unit(&asm, ":?plcc.main?CONST");
    assert!(
        pool.iter().filter(|l| l.contains("MCD")).count() >= 3,
        "{pool:#?}"
    );
    assert!(pool.last().unwrap().contains("RETURN"), "{pool:#?}");
    let body = unit(&asm, ":?plcc.main?CODE");
    assert!(!body.iter().any(|l| l.contains("MCD")), "{body:#?}");
}

#[test]
fn each_instance_loads_the_pool_and_called_bodies_keep_theirs() {
    let asm = listing("configured", CONFIGURED);
    let start = unit(&asm, ":?plcc.TASK?TSKSTR");
    for p in ["a", "b", "c"] {
        let call = format!("CALB {p}, :?plcc.{p}$scan?CONST");
        assert!(
            start.iter().any(|l| l.ends_with(&call)),
            "{call}: {start:#?}"
        );
    }
    // `counter`'s body is called by the task's wrappers of `a` and `b`: its pool
    // stays in its prologue.
    let body = unit(&asm, ":?plcc.counter?CODE");
    assert!(body.iter().any(|l| l.contains("MCD")), "{body:#?}");
}

#[test]
fn the_vm_agrees_with_the_interpreter() {
    let machines: Vec<String> = ["vmasm", "vmasm:mode=32", "vmasm:mode=32a"]
        .iter()
        .map(|s| s.to_string())
        .collect();
    let script: Vec<Vec<(&str, f64)>> = vec![vec![]; 5];
    for src in [ALONE, CONFIGURED] {
        let a = ir_machines::agree_with_interp(&module(src), &machines, &script).unwrap();
        assert_eq!(a.machines.len(), 3, "{:?}", a.machines);
    }
}
