//! `--lib FILE`: a library of declarations added to the build (`tests/lib/`): a
//! program calling blocks no IEC library defines compiles and runs on a user's
//! stubs of them, with `run`, `test`, `check` and a plain build; a library may be in
//! any language plcc reads, and its PROGRAMs run only when named.

use std::path::{Path, PathBuf};

#[path = "common/cli.rs"]
#[allow(dead_code)]
mod cli;
use cli::{plcc, stderr, stdout};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// A fresh directory for one test's files.
fn scratch(test: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("lib-option-{test}"));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("cannot create a scratch directory");
    dir
}

const PROGRAM: &str = "tests/lib/vendor_blocks.st";
const STUBS: &str = "tests/lib/vendor_stubs.st";

/// After three scans: `row` is 3; `first` is triggered from row 2 on (acks 2);
/// `second` echoes its code at every scan (echoes 3); the stub's cells are
/// row * 10 + column: 31 (the reader's), 32, 33.
const AFTER_3_SCANS: [&str; 6] = [
    "row = 3",
    "acks = 2",
    "echoes = 3",
    "reader.cell = 31",
    "a = 32",
    "b = 33",
];

fn has_lines(out: &str, lines: &[&str], what: &str) {
    for line in lines {
        assert!(
            out.lines().any(|l| l == *line),
            "{what}: no line `{line}` in:\n{out}"
        );
    }
}

#[test]
fn the_program_does_not_compile_without_its_library() {
    // One error per unknown block, however often it is used, suggesting `--lib`.
    let o = plcc(&["check", PROGRAM]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    let err = stderr(&o);
    for block in ["python_eval", "csv_read_by_int"] {
        let head = format!("error[E0203]: unknown type `{block}`");
        assert_eq!(err.matches(&head).count(), 1, "{err}");
        assert!(
            err.contains(&format!("`{block}` is used in 3 places")),
            "{err}"
        );
    }
    assert_eq!(err.matches("also used here").count(), 4, "{err}");
    assert_eq!(err.matches("`--lib FILE`").count(), 2, "{err}");
    assert!(err.contains("could not compile: 2 error(s)"), "{err}");
    let o = plcc(&["check", PROGRAM, "--lib", STUBS]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(!stderr(&o).contains("error"), "{}", stderr(&o));
}

/// The strings of the stubs (81 bytes each) do not fit the PIC16's RAM, so the
/// machines with room for them run it.
#[test]
fn run_with_a_library_of_stubs_on_every_machine_with_room() {
    for target in ["host", "interp", "vmasm"] {
        let o = plcc(&[
            "run", PROGRAM, "--lib", STUBS, "--target", target, "--scans", "3",
        ]);
        assert!(o.status.success(), "{target}: {}", stderr(&o));
        let out = stdout(&o);
        has_lines(&out, &AFTER_3_SCANS, target);
        // Only `main` ran: its variables are printed without its name, and the
        // library's PROGRAM is not there.
        assert!(!out.contains("runs"), "{target}: {out}");
    }
}

#[test]
fn a_librarys_program_runs_only_when_named() {
    let o = plcc(&[
        "run",
        PROGRAM,
        "--lib",
        STUBS,
        "--target",
        "interp",
        "--scans",
        "3",
        "--program",
        "stub_selftest",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(stdout(&o), "runs = 3\n");
    // Given as an input file, the same file's PROGRAM runs with main's.
    let o = plcc(&["run", PROGRAM, STUBS, "--target", "interp", "--scans", "3"]);
    assert!(o.status.success(), "{}", stderr(&o));
    has_lines(
        &stdout(&o),
        &["main.row = 3", "stub_selftest.runs = 3"],
        "both as inputs",
    );
}

#[test]
fn test_with_a_library() {
    let dir = scratch("test_with_a_library");
    let scenario = dir.join("vendor.expect");
    std::fs::write(
        &scenario,
        "# corpus-expect v1\nrun 3\nexpect a = 32\nexpect reader.cell = 31\nexpect acks = 2\n",
    )
    .unwrap();
    let scenario = scenario.to_str().unwrap();
    let o = plcc(&["test", PROGRAM, "--lib", STUBS, "--scenario", scenario]);
    assert!(o.status.success(), "{}\n{}", stdout(&o), stderr(&o));
    assert!(
        stdout(&o).contains("passed: 3 check(s), 0 failed"),
        "{}",
        stdout(&o)
    );
    // A check that does not hold fails: the test can fail.
    std::fs::write(dir.join("wrong.expect"), "run 3\nexpect a = 31\n").unwrap();
    let wrong = dir.join("wrong.expect");
    let o = plcc(&[
        "test",
        PROGRAM,
        "--lib",
        STUBS,
        "--scenario",
        wrong.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(1), "{}", stdout(&o));
}

/// A plain build names its output after the first input, never after a library.
#[test]
fn a_build_is_named_after_its_input() {
    let dir = scratch("a_build_is_named_after_its_input");
    let prog = dir.join("vendor_blocks.st");
    std::fs::copy(root().join(PROGRAM), &prog).unwrap();
    let o = plcc(&["--target", "vmasm", "--lib", STUBS, prog.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(dir.join("vendor_blocks.xcp").exists());
    assert!(dir.join("vendor_blocks.dcp").exists());
    assert!(!root().join("tests/lib/vendor_stubs.xcp").exists());
}

/// A library in Instruction List; several `--lib`s.
#[test]
fn libraries_in_other_languages() {
    let dir = scratch("libraries_in_other_languages");
    let prog = dir.join("main.st");
    std::fs::write(
        &prog,
        "PROGRAM main\nVAR n : INT; d : INT; END_VAR\nn := TRIPLE(n + 1);\nd := DOUBLE(n);\nEND_PROGRAM\n",
    )
    .unwrap();
    let il = dir.join("triple.il");
    std::fs::write(
        &il,
        "FUNCTION TRIPLE : INT\nVAR_INPUT x : INT; END_VAR\n    LD x\n    MUL 3\n    ST TRIPLE\nEND_FUNCTION\n",
    )
    .unwrap();
    let st = dir.join("double.st");
    std::fs::write(
        &st,
        "FUNCTION DOUBLE : INT\nVAR_INPUT x : INT; END_VAR\nDOUBLE := 2 * x;\nEND_FUNCTION\n",
    )
    .unwrap();
    let o = plcc(&[
        "run",
        prog.to_str().unwrap(),
        "--lib",
        il.to_str().unwrap(),
        "--lib",
        st.to_str().unwrap(),
        "--target",
        "interp",
        "--scans",
        "2",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    // n: (0 + 1) * 3 = 3, then (3 + 1) * 3 = 12; d = 24.
    assert_eq!(stdout(&o), "n = 12\nd = 24\n");
}

/// A ladder library (PLCopen XML): fb_ld.xml without its configuration declares the
/// function block `debounce` (in ladder) and the PROGRAM `fb_ld`, which does not run.
#[test]
fn a_ladder_library() {
    let dir = scratch("a_ladder_library");
    let xml = std::fs::read_to_string(root().join("tests/programs/ld/fb_ld.xml")).unwrap();
    let (start, end) = (
        xml.find("<instances>").expect("instances"),
        xml.find("</instances>").expect("instances") + "</instances>".len(),
    );
    let lib = dir.join("debounce.xml");
    std::fs::write(&lib, format!("{}{}", &xml[..start], &xml[end..])).unwrap();
    let prog = dir.join("main.st");
    std::fs::write(
        &prog,
        "PROGRAM main\nVAR d : debounce; q : BOOL; END_VAR\nd(raw := TRUE, delay := T#30ms);\nq := d.clean;\nEND_PROGRAM\n",
    )
    .unwrap();
    // Scans at 0, 10, 20 and 30 ms: the TON inside starts at 0 and is done at 30.
    for (scans, q) in [("3", "q = FALSE"), ("4", "q = TRUE")] {
        let o = plcc(&[
            "run",
            prog.to_str().unwrap(),
            "--lib",
            lib.to_str().unwrap(),
            "--target",
            "interp",
            "--scans",
            scans,
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
        let out = stdout(&o);
        has_lines(&out, &[q, "d.delay = T#30ms"], "ladder library");
        assert!(!out.contains("out1"), "the library's PROGRAM ran:\n{out}");
    }
}

#[test]
fn a_missing_library_is_a_usage_error() {
    let o = plcc(&["check", PROGRAM, "--lib", "tests/lib/no_such_file.st"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("cannot read tests/lib/no_such_file.st"),
        "{}",
        stderr(&o)
    );
}
