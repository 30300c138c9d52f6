//! Ladder diagrams and their IL twins compute the same thing, scan by scan.
//!
//! Every ladder program `tests/programs/ld/NAME.xml` (PLCopen XML) has an IL twin
//! `NAME.il` beside it, written by hand: the Instruction List a person writes for the
//! same rungs (series as AND, parallel branches as OR and `AND(`, an edge contact as
//! an R_TRIG called on its variable). Both share the scenario `NAME.expect`, which
//! `tests/e2e.rs` runs on every target; this test checks far more states than a
//! scenario: the two run side by side on the interpreter for [`SCANS`] scans, with the
//! same random values written to the programs' variables before every scan, and every
//! variable they share must be equal after every scan (`common/lockstep.rs`). A build
//! must give no diagnostics at all, not even warnings.
//!
//! The test never skips: fewer than [`MIN_PROGRAMS`] ladder programs, a program
//! without its twin or scenario, or a namespace of PLCopen XML that no program uses is
//! a failure.

#[path = "common/lockstep.rs"]
mod lockstep;
#[path = "common/rng.rs"]
#[allow(dead_code)]
mod rng;

use plcc::driver::{build_sources, BuildOptions};
use plcc_ir::Module;
use std::path::{Path, PathBuf};

/// Scans per program.
const SCANS: u32 = 500;

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

/// The module of one file, or why there is none.
fn module(path: &Path) -> Result<Module, String> {
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
    b.module
        .ok_or_else(|| "no module and no diagnostics".into())
}

/// A variable written at random: one of a program instance (`inst.x`), not a member
/// of a block instance.
fn writable(path: &str) -> bool {
    path.split('.').count() == 2
}

#[test]
fn every_ladder_program_computes_what_its_il_twin_computes() {
    let programs = programs();
    let mut problems = Vec::new();
    for stem in &programs {
        let xml = ld_dir().join(format!("{stem}.xml"));
        let il = ld_dir().join(format!("{stem}.il"));
        if !il.exists() {
            problems.push(format!("{stem}: no IL twin {stem}.il"));
            continue;
        }
        match (module(&xml), module(&il)) {
            (Ok(a), Ok(b)) => {
                let cycle = a.task_tick_us().map_or(10, |us| us.div_ceil(1000) as u32);
                let seed = 0xD1B5_4A32_D192_ED03 ^ stem.len() as u64;
                match lockstep::run(&a, &b, "interp", SCANS, cycle, seed, &writable, &|_| true) {
                    Ok(Some(o)) if o.compared == 0 || o.inputs == 0 => problems.push(format!(
                        "{stem}: {} variables compared, {} written: nothing to test",
                        o.compared, o.inputs
                    )),
                    Ok(Some(_)) => {}
                    Ok(None) => problems.push(format!("{stem}: the interpreter cannot run it")),
                    Err(e) => {
                        problems.push(format!("{stem}: the ladder and its IL twin differ {e}"))
                    }
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
