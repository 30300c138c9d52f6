//! An endless loop in a scan ends in an error from the machine, not a hang, on every
//! target that runs programs.

use plcc::driver::{build_sources, BuildOptions};
use plcc::targets;
use std::time::Duration;

const ENDLESS: &str = "
FUNCTION spin : INT
VAR_INPUT n : INT; END_VAR
    REPEAT n := n + 1; UNTIL FALSE END_REPEAT;
    spin := n;
END_FUNCTION
PROGRAM main
VAR i : DINT; k : INT; END_VAR
    i := i + 1;
    IF i > 2 THEN
        k := spin(1);
    END_IF;
END_PROGRAM
";

#[test]
fn endless_loops_are_stopped() {
    let b = build_sources(
        vec![("spin.st".into(), ENDLESS.as_bytes().to_vec())],
        &BuildOptions::default(),
    )
    .unwrap();
    let module = b.module.expect("compiles");
    for target in ["host", "interp", "vmasm", "c"] {
        let mut m = targets::machine(target, &module).unwrap();
        m.set_watchdog(Some(Duration::from_millis(100)));
        m.cold_start().unwrap();
        // Two ordinary scans, then the one that calls the endless function.
        m.scan().unwrap();
        m.scan().unwrap();
        let err = m.scan().expect_err("the third scan must be stopped");
        assert!(
            err.0.contains("watchdog") || err.0.contains("step limit"),
            "{target}: {err}"
        );
    }
}
