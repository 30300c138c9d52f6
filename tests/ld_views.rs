//! The views of PLCopen files the binary prints: `--emit ld-text` (the rungs drawn in
//! ASCII) and `--emit st` (the project as IEC text, its diagrams lowered to ST; `il`
//! is the same), with their exit statuses.
//!
//! The drawings of every program of `tests/programs/ld/` are one insta snapshot, so a
//! change of the drawing (or of how a program is read) shows as a diff to review; the
//! ST view of one program is another. Review with `cargo insta review`.

use std::path::Path;

#[path = "common/cli.rs"]
#[allow(dead_code)]
mod cli;
use cli::{plcc, stderr, stdout};

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// The ladder programs, sorted.
fn programs() -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(root().join("tests/programs/ld"))
        .unwrap()
        .filter_map(|e| {
            let p = e.unwrap().path();
            let name = p.file_name()?.to_str()?.to_string();
            (p.extension()? == "xml").then(|| format!("tests/programs/ld/{name}"))
        })
        .collect();
    v.sort();
    v
}

#[test]
fn ld_text_of_every_program() {
    let mut all = String::new();
    for p in programs() {
        let o = plcc(&["--emit", "ld-text", &p]);
        assert_eq!(o.status.code(), Some(0), "{p}: {}", stderr(&o));
        assert!(stderr(&o).is_empty(), "{p}: {}", stderr(&o));
        all.push_str(&format!("==== {p}\n{}", stdout(&o)));
    }
    insta::assert_snapshot!(all);
}

#[test]
fn st_view_of_a_program() {
    let o = plcc(&["--emit", "st", "tests/programs/ld/counter_reset.xml"]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    insta::assert_snapshot!(stdout(&o));
}

/// The view is text that plcc compiles to the program the diagram is (saved as `.il`,
/// the Instruction List front end reads it, ST bodies and all).
#[test]
fn the_view_compiles_to_the_same_ir() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("ld_views");
    std::fs::create_dir_all(&dir).unwrap();
    for p in programs() {
        let stem = Path::new(&p)
            .file_stem()
            .unwrap()
            .to_string_lossy()
            .into_owned();
        let il = dir.join(format!("{stem}.il"));
        let o = plcc(&["--emit", "il", &p, "-o", il.to_str().unwrap()]);
        assert_eq!(o.status.code(), Some(0), "{p}: {}", stderr(&o));
        let ir = |f: &str| {
            let o = plcc(&["--emit", "ir", f]);
            assert_eq!(o.status.code(), Some(0), "{f}: {}", stderr(&o));
            stdout(&o)
                .lines()
                .filter(|l| !l.starts_with("file "))
                .collect::<Vec<_>>()
                .join("\n")
        };
        assert_eq!(ir(&p), ir(il.to_str().unwrap()), "{p}");
    }
}

#[test]
fn views_of_files_that_are_not_ladder_or_not_valid() {
    // Not a ladder file: a usage error, exit 2 (`--emit st` prints any build).
    for view in ["il", "ld-text"] {
        let o = plcc(&["--emit", view, "examples/traffic_light.st"]);
        assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
        assert!(
            stderr(&o).contains("give a PLCopen XML file"),
            "{}",
            stderr(&o)
        );
        assert!(o.stdout.is_empty());
    }
    // A ladder with errors: exit 1, the diagnostics, nothing printed.
    let o = plcc(&[
        "--emit",
        "st",
        "--strict-rungs",
        "tests/bad/ld_short_circuit.xml",
    ]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(stderr(&o).contains("error[E0745]"), "{}", stderr(&o));
    assert!(o.stdout.is_empty());
}
