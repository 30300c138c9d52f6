//! An endless loop in a scan ends in an error from the machine, not a hang, on every
//! target that runs programs.

use plcc::driver::{build_sources, BuildOptions};
use plcc::targets;
use plcc_ir::machine::Machine;
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

/// Every machine that runs programs, cold-started with a watchdog of 100 ms, on
/// the program `src`.
fn machines(src: &str) -> Vec<(&'static str, Box<dyn Machine>)> {
    let b = build_sources(
        vec![("watchdog.st".into(), src.as_bytes().to_vec())],
        &BuildOptions::default(),
    )
    .unwrap();
    let module = b.module.expect("compiles");
    ["host", "interp", "vmasm", "c"]
        .into_iter()
        .map(|target| {
            let mut m = targets::machine(target, &module).unwrap();
            m.set_watchdog(Some(Duration::from_millis(100)));
            m.cold_start().unwrap();
            (target, m)
        })
        .collect()
}

/// The scan ends in the watchdog's error (or the interpreter's step limit).
fn assert_stopped(target: &str, m: &mut dyn Machine) {
    let err = m.scan().expect_err("the scan must be stopped");
    assert!(
        err.0.contains("watchdog") || err.0.contains("step limit"),
        "{target}: {err}"
    );
}

#[test]
fn endless_loops_are_stopped() {
    for (target, mut m) in machines(ENDLESS) {
        // Two ordinary scans, then the one that calls the endless function.
        m.scan().unwrap();
        m.scan().unwrap();
        assert_stopped(target, m.as_mut());
    }
}

/// A loop that counts up to a bound by a step it reads: the watchdog pass cannot
/// show that it ends (the step may be 0), so it keeps its check, and runs a copy
/// without it only when the step is at least 1; with a step of 0 the scan is
/// stopped. The FOR loop before it has constant bounds and no check.
const COUNTING: &str = "
PROGRAM main
VAR a : ARRAY[0..99] OF DINT; j : DINT; s : DINT := 1; n : DINT; k : DINT; END_VAR
    FOR k := 0 TO 99 DO a[k] := a[k] + k; END_FOR;
    j := 0;
    WHILE j <= 100 DO n := n + 1; j := j + s; END_WHILE;
    s := s - 1;
END_PROGRAM
";

#[test]
fn a_loop_stepping_by_zero_is_stopped() {
    for (target, mut m) in machines(COUNTING) {
        // The first scan steps by 1; the second by 0.
        m.scan().unwrap();
        assert_eq!(m.read("main.n").unwrap().as_i64(), 101, "{target}");
        assert_eq!(m.read("main.a[99]").unwrap().as_i64(), 99, "{target}");
        assert_stopped(target, m.as_mut());
    }
}

/// The same kind of loop from a start it reads: from 0 it runs 101 times (in the copy
/// without checks); from -2,000,000,000 it would run for seconds, so the test before
/// the loop picks the loop with its checks, and the scan is stopped in the loop:
/// `n`, kept in a register through the loop, is not stored (a copy without checks
/// would finish the loop, late, and store it).
const FROM_LOW: &str = "
PROGRAM main
VAR j : DINT; s : DINT := 1; n : DINT; lo : DINT := 0; END_VAR
    j := lo;
    WHILE j <= 100 DO n := n + 1; j := j + s; END_WHILE;
    lo := -2000000000;
END_PROGRAM
";

#[test]
fn a_loop_from_a_start_too_low_is_stopped() {
    for (target, mut m) in machines(FROM_LOW) {
        m.scan().unwrap();
        assert_eq!(m.read("main.n").unwrap().as_i64(), 101, "{target}");
        assert_stopped(target, m.as_mut());
        assert_eq!(m.read("main.n").unwrap().as_i64(), 101, "{target}");
    }
}
