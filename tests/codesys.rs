//! The CODESYS dialect's pointer arithmetic (`tests/codesys/*.st`, each with its
//! scenario): it runs on the IR interpreter, which checks every access; the host JIT
//! refuses it (E8007: a wrong address would corrupt plcc's own process), so does the
//! C machine (E9205, for the same reason: it runs in plcc's process), and the
//! vmasm and PIC16 targets reject it at compile time. The dialect's other features
//! run on every target as e2e programs (`tests/programs/st/codesys`).

use std::path::{Path, PathBuf};
use std::process::Command;

fn programs() -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/codesys");
    let mut out: Vec<PathBuf> = std::fs::read_dir(&dir)
        .expect("tests/codesys")
        .map(|e| e.expect("entry").path())
        .filter(|p| p.extension().is_some_and(|x| x == "st"))
        .collect();
    out.sort();
    assert!(!out.is_empty(), "no programs in {}", dir.display());
    out
}

/// Runs `plcc test --dialect codesys` on one target: exit status and stderr.
fn test_on(src: &Path, target: &str) -> (i32, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_plcc"))
        .args(["test", "--dialect", "codesys", "--target", target])
        .arg(src)
        .arg("--scenario")
        .arg(src.with_extension("expect"))
        .output()
        .expect("plcc runs");
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    (out.status.code().unwrap_or(-1), text)
}

#[test]
fn pointer_arithmetic_runs_on_the_interpreter() {
    for src in programs() {
        let (code, text) = test_on(&src, "interp");
        assert_eq!(code, 0, "{}:\n{text}", src.display());
        assert!(text.contains("0 failed"), "{}:\n{text}", src.display());
    }
}

#[test]
fn the_host_refuses_unchecked_pointers() {
    for src in programs() {
        let (code, text) = test_on(&src, "host");
        assert_eq!(code, 1, "{}:\n{text}", src.display());
        assert!(text.contains("E8007"), "{}:\n{text}", src.display());
    }
}

#[test]
fn the_c_machine_refuses_unchecked_pointers() {
    for src in programs() {
        let (code, text) = test_on(&src, "c");
        assert_eq!(code, 1, "{}:\n{text}", src.display());
        assert!(text.contains("E9205"), "{}:\n{text}", src.display());
    }
}

#[test]
fn vmasm_and_pic16_reject_pointer_arithmetic() {
    for src in programs() {
        let (code, text) = test_on(&src, "vmasm");
        assert_eq!(code, 1, "{}:\n{text}", src.display());
        assert!(text.contains("E9101"), "{}:\n{text}", src.display());
        // The PIC16 may run out of RAM first; either way it is a backend error.
        let (code, text) = test_on(&src, "pic16f876a");
        assert_eq!(code, 1, "{}:\n{text}", src.display());
        assert!(text.contains("error[E90"), "{}:\n{text}", src.display());
    }
}

#[test]
fn pointers_need_the_dialect() {
    let src = programs().remove(0);
    let out = Command::new(env!("CARGO_BIN_EXE_plcc"))
        .args(["check"])
        .arg(&src)
        .output()
        .expect("plcc runs");
    let text = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{text}");
    assert!(text.contains("--dialect codesys"), "{text}");
}
