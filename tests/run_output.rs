//! What `plcc run` prints: every variable in IEC literal form, the same on every
//! target; unsigned 64-bit values of 2^63 and above are not negative numbers.

use std::path::Path;
use std::process::Command;

#[test]
fn run_prints_unsigned_64_bit_values_unsigned_on_every_target() {
    let prog =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/programs/st/regress/ulint_printing.st");
    for target in ["host", "interp", "vmasm", "pic16f876a", "c"] {
        let out = Command::new(env!("CARGO_BIN_EXE_plcc"))
            .args([
                "run",
                prog.to_str().unwrap(),
                "--target",
                target,
                "--scans",
                "1",
            ])
            .output()
            .expect("plcc runs");
        let text = String::from_utf8_lossy(&out.stdout);
        assert!(
            out.status.success(),
            "{target}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        for line in [
            "u = 18446744073709551615",
            "w = 16#8000000000000001",
            "h = 9223372036854775808",
            "ud = 4294967295",
        ] {
            assert!(
                text.lines().any(|l| l == line),
                "{target}: no line `{line}` in:\n{text}"
            );
        }
    }
}

/// Without `--cycle-ms`, `run` scans at the common tick of the configuration's tasks
/// (10 and 15 ms: 5 ms) and says so on stderr; `--cycle-ms` overrides it. After 31
/// scans at 5 ms, the 10 ms task ran at the 16 even ticks of 0..30, the 15 ms one at
/// the 11 multiples of 3, and the clock reads 150 ms; at 10 ms the 10 ms task runs
/// every scan and the clock reads 300 ms.
#[test]
fn run_scans_at_the_tasks_common_tick_unless_told() {
    let prog =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/programs/st/config/common_tick.st");
    let cases: [(&[&str], &str, [&str; 3]); 2] = [
        (
            &[],
            "cycle: 5 ms (the common tick of the tasks: the GCD of their intervals)",
            ["a.runs = 16", "b.runs = 11", "clk.et = T#150ms"],
        ),
        (
            &["--cycle-ms", "10"],
            "cycle: 10 ms (--cycle-ms)",
            ["a.runs = 31", "b.runs = 21", "clk.et = T#300ms"],
        ),
    ];
    for target in ["host", "interp", "vmasm", "pic16f876a", "c"] {
        for (extra, cycle, lines) in &cases {
            let out = Command::new(env!("CARGO_BIN_EXE_plcc"))
                .args(["run", prog.to_str().unwrap(), "--target", target])
                .args(["--scans", "31"])
                .args(*extra)
                .output()
                .expect("plcc runs");
            let text = String::from_utf8_lossy(&out.stdout);
            let err = String::from_utf8_lossy(&out.stderr);
            assert!(out.status.success(), "{target}: {err}");
            assert!(
                err.lines().any(|l| l == *cycle),
                "{target} {extra:?}: no line `{cycle}` in stderr:\n{err}"
            );
            for line in lines {
                assert!(
                    text.lines().any(|l| l == *line),
                    "{target} {extra:?}: no line `{line}` in:\n{text}"
                );
            }
        }
    }
}

/// A build without tasks runs at 10 ms unless told otherwise.
#[test]
fn run_without_tasks_scans_every_10_ms() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("run-output-no-tasks");
    std::fs::create_dir_all(&dir).unwrap();
    let src = dir.join("clock.st");
    std::fs::write(
        &src,
        "PROGRAM main\nVAR t : TON; et : TIME; END_VAR\nt(IN := TRUE, PT := T#1h);\net := t.ET;\nEND_PROGRAM\n",
    )
    .unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_plcc"))
        .args(["run", src.to_str().unwrap(), "--target", "interp"])
        .args(["--scans", "4"])
        .output()
        .expect("plcc runs");
    let text = String::from_utf8_lossy(&out.stdout);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert!(
        err.lines()
            .any(|l| l == "cycle: 10 ms (the default: no task has an interval)"),
        "{err}"
    );
    assert!(text.lines().any(|l| l == "et = T#30ms"), "{text}");
}

/// STRING and WSTRING variables print whole, as literals with `$` escapes, the same on
/// every target.
#[test]
fn run_prints_strings_as_literals_on_every_target() {
    let prog =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/programs/st/regress/string_printing.st");
    for target in ["host", "interp", "vmasm", "pic16f876a", "c"] {
        let out = Command::new(env!("CARGO_BIN_EXE_plcc"))
            .args(["run", prog.to_str().unwrap(), "--target", target])
            .output()
            .expect("plcc runs");
        assert!(
            out.status.success(),
            "{target}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        assert_eq!(
            String::from_utf8_lossy(&out.stdout),
            "s = 'it$'s'\ne = ''\nw = \"Grüße\"\nt = 'a$Nb'\nn = 1\n",
            "{target}"
        );
    }
}

/// Output that cannot be written is an I/O error (exit status 2) with a message,
/// not a panic: the variables go through one buffer, flushed and checked.
#[cfg(target_os = "linux")]
#[test]
fn run_reports_output_it_cannot_write() {
    let prog =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/programs/st/regress/ulint_printing.st");
    let full = std::fs::OpenOptions::new()
        .write(true)
        .open("/dev/full")
        .expect("/dev/full");
    let out = Command::new(env!("CARGO_BIN_EXE_plcc"))
        .args(["run", prog.to_str().unwrap()])
        .stdout(full)
        .output()
        .expect("plcc runs");
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(err.contains("error: cannot write the variables"), "{err}");
    assert!(!err.contains("panicked"), "{err}");
}
