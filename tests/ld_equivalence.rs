//! Ladder diagrams and their IL twins give the same optimised IR.
//!
//! Every ladder program `tests/programs/ld/NAME.xml` (PLCopen XML) has an IL twin
//! `NAME.il` beside it, written by hand: the Instruction List a person writes for the
//! same rungs, in the conventions of plcc's conversion (docs/plcopen.md: the seed's
//! method of series as AND, parallel branches as OR and `AND(`, hidden variables named
//! after the localId of the element they stand for). Both share the scenario
//! `NAME.expect`, which `tests/e2e.rs` runs on every target; this test checks that the
//! two lower to the same program: their optimised IR, printed, must be identical.
//!
//! The one difference allowed is the table of source files at the top of the printed
//! IR: a ladder build has the XML file and its IL view (a source file of its own), an
//! IL build the `.il` file only. Those `file` lines are left out of the comparison;
//! nothing else in the printed IR depends on file names. A build must give no
//! diagnostics at all, not even warnings.
//!
//! The test never skips: fewer than [`MIN_PROGRAMS`] ladder programs, a program
//! without its twin or scenario, or a namespace of PLCopen XML that no program uses is
//! a failure.

use plcc::driver::{build_sources, BuildOptions};
use plcc_ir::text::{print_module, PrintOptions};
use std::path::{Path, PathBuf};

/// Fewer ladder programs than this is a failure.
const MIN_PROGRAMS: usize = 20;

/// The namespaces the programs must use between them: TC6 2.01 and TC6 1.0.
const NAMESPACES: [&str; 2] = [
    "http://www.plcopen.org/xml/tc6_0201",
    "http://www.plcopen.org/xml/tc6.xsd",
];

fn ld_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/programs/ld")
}

/// The stems of the ladder programs, sorted.
fn programs() -> Vec<String> {
    let mut out: Vec<String> = std::fs::read_dir(ld_dir())
        .expect("tests/programs/ld")
        .filter_map(|e| {
            let p = e.expect("directory entry").path();
            (p.extension()? == "xml").then(|| p.file_stem()?.to_str().map(str::to_string))?
        })
        .collect();
    out.sort();
    out
}

/// The optimised IR of one file, without the table of source files, or why there is
/// none.
fn ir(path: &Path) -> Result<String, String> {
    let bytes = std::fs::read(path).map_err(|e| format!("cannot read it: {e}"))?;
    let name = format!(
        "tests/programs/ld/{}",
        path.file_name().unwrap().to_string_lossy()
    );
    let b = build_sources(vec![(name, bytes)], &BuildOptions::default()).map_err(|e| e.0)?;
    if !b.diagnostics.is_empty() {
        let d: Vec<String> = b.diagnostics.iter().map(|d| d.to_string()).collect();
        return Err(format!("diagnostics:\n      {}", d.join("\n      ")));
    }
    let m = b.module.ok_or("no module and no diagnostics")?;
    let text = print_module(&m, &PrintOptions::default());
    Ok(text
        .lines()
        .filter(|l| !l.starts_with("file "))
        .map(|l| format!("{l}\n"))
        .collect())
}

/// The first line where two IR texts differ, for messages.
fn first_difference(a: &str, b: &str) -> String {
    for (n, (x, y)) in a.lines().zip(b.lines()).enumerate() {
        if x != y {
            return format!("line {}:\n      xml: {x}\n      il:  {y}", n + 1);
        }
    }
    format!(
        "the ladder IR has {} lines, the IL IR {}",
        a.lines().count(),
        b.lines().count()
    )
}

#[test]
fn every_ladder_program_gives_the_ir_of_its_il_twin() {
    let programs = programs();
    let mut problems = Vec::new();
    for stem in &programs {
        let xml = ld_dir().join(format!("{stem}.xml"));
        let il = ld_dir().join(format!("{stem}.il"));
        if !il.exists() {
            problems.push(format!("{stem}: no IL twin {stem}.il"));
            continue;
        }
        match (ir(&xml), ir(&il)) {
            (Ok(a), Ok(b)) => {
                if !a.contains("func ") {
                    problems.push(format!("{stem}: no function in the IR"));
                } else if a != b {
                    problems.push(format!(
                        "{stem}: the IR of the ladder and of its IL twin differ, first at {}",
                        first_difference(&a, &b)
                    ));
                }
            }
            (a, b) => {
                if let Err(e) = a {
                    problems.push(format!("{stem}.xml: {e}"));
                }
                if let Err(e) = b {
                    problems.push(format!("{stem}.il: {e}"));
                }
            }
        }
    }
    println!(
        "{} ladder programs compared with their IL twins",
        programs.len()
    );
    assert!(
        problems.is_empty(),
        "{} problem(s):\n  {}",
        problems.len(),
        problems.join("\n  ")
    );
}

#[test]
fn ladder_programs_are_complete() {
    let programs = programs();
    let mut problems = Vec::new();
    if programs.len() < MIN_PROGRAMS {
        problems.push(format!(
            "only {} ladder programs (at least {MIN_PROGRAMS} expected)",
            programs.len()
        ));
    }
    let mut used = [false; NAMESPACES.len()];
    for stem in &programs {
        for ext in ["il", "expect"] {
            if !ld_dir().join(format!("{stem}.{ext}")).exists() {
                problems.push(format!("{stem}: no {stem}.{ext}"));
            }
        }
        let text = std::fs::read_to_string(ld_dir().join(format!("{stem}.xml"))).unwrap();
        for (i, ns) in NAMESPACES.iter().enumerate() {
            if text.contains(&format!("xmlns=\"{ns}\"")) {
                used[i] = true;
            }
        }
    }
    for (ns, u) in NAMESPACES.iter().zip(used) {
        if !u {
            problems.push(format!("no ladder program in the namespace {ns}"));
        }
    }
    // Nothing else in the directory: every file is a program, a twin or a scenario.
    for e in std::fs::read_dir(ld_dir()).unwrap() {
        let p = e.unwrap().path();
        let ok = p.extension().and_then(|x| x.to_str()).is_some_and(|x| {
            matches!(x, "xml" | "il" | "expect")
                && programs
                    .iter()
                    .any(|s| p.file_stem().unwrap() == s.as_str())
        });
        if !ok {
            problems.push(format!(
                "{}: not a ladder program, twin or scenario",
                p.display()
            ));
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}
