//! Runs every ST and IL program of `../shared/corpus` (bulk/, st/, il/) that has a
//! scenario, on every machine of the target registry, and prints a table per category: passed, failed, unsupported
//! (with the diagnostic code that says why). Fails if a program that plcc accepts
//! fails its scenario, if a program is rejected for a reason other than a
//! not-supported-yet diagnostic, or if anything panics. matiec's IL syntax file must
//! check with only not-supported diagnostics (and its one known error).
//!
//! Skips with a notice when `../shared` is absent (a user's fresh clone).

#[path = "common/c_driver.rs"]
#[allow(dead_code)]
mod c_driver;

use plcc::driver::{build_sources, BuildOptions};
use plcc::{scenario, targets};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

#[path = "common/skip.rs"]
mod skip;

fn corpus_dir() -> Option<PathBuf> {
    let d = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/corpus");
    d.is_dir().then_some(d)
}

#[derive(Default)]
struct Row {
    passed: u32,
    failed: Vec<String>,
    unsupported: BTreeMap<String, u32>,
    excluded: u32,
}

/// Programs excluded because their expectations follow another dialect:
/// name -> reason.
fn exclusions() -> BTreeMap<String, String> {
    let text = include_str!("corpus_exclusions.txt");
    text.lines()
        .filter(|l| !l.trim().is_empty() && !l.starts_with('#'))
        .filter_map(|l| l.split_once('\t'))
        .map(|(n, r)| (n.trim().to_string(), r.trim().to_string()))
        .collect()
}

/// Codes that mean "valid, but not compiled by plcc yet".
fn is_unsupported_code(code: &str) -> bool {
    code.starts_with("E06") || code == "E0107"
}

/// Backend codes that mean "does not fit this target" (see `plcc explain`), as
/// `common/lockstep.rs`'s `UNFIT` (too big, a type the target lacks, an address the `c`
/// target's located-variable ABI cannot hold: zplc's `INT AT %Q0`).
fn is_unfit_code(code: &str) -> bool {
    matches!(
        code,
        "E9001" | "E9002" | "E9003" | "E9004" | "E9101" | "E9102" | "E9207" | "E9208"
    )
}

enum Verdict {
    Pass,
    Fail(String),
    Unsupported(String),
}

fn category(name: &str) -> String {
    let stem = name.trim_end_matches(".st").trim_end_matches(".il");
    let base = stem.split("__").next().unwrap_or(stem);
    base.to_string()
}

fn judge(st: &Path, expect: &Path, target: &str) -> Verdict {
    let text = std::fs::read_to_string(expect).unwrap();
    let scn = match scenario::parse(&text) {
        Ok(s) => s,
        Err(e) => return Verdict::Fail(format!("scenario: {e}")),
    };
    if let Some(why) = scn.unsupported {
        return Verdict::Unsupported(format!("scenario: {why}"));
    }
    let bytes = std::fs::read(st).unwrap();
    let opts = BuildOptions {
        programs: scn.program.iter().cloned().collect(),
        ..Default::default()
    };
    let build = match build_sources(vec![(st.display().to_string(), bytes)], &opts) {
        Ok(b) => b,
        Err(e) => return Verdict::Fail(e.0),
    };
    let Some(module) = build.module else {
        let errors: Vec<_> = build.diagnostics.iter().filter(|d| d.is_error()).collect();
        // Errors after a construct plcc does not support yet are usually its
        // consequences; the unsupported construct is the reason.
        if errors.iter().any(|d| is_unsupported_code(d.code)) {
            let mut codes: Vec<&str> = errors
                .iter()
                .map(|d| d.code)
                .filter(|c| is_unsupported_code(c))
                .collect();
            codes.sort();
            codes.dedup();
            let first = errors
                .iter()
                .find(|d| is_unsupported_code(d.code))
                .map(|d| d.message.clone())
                .unwrap_or_default();
            return Verdict::Unsupported(format!("{} ({first})", codes.join(",")));
        }
        let shown: Vec<String> = errors.iter().take(3).map(|d| d.to_string()).collect();
        return Verdict::Fail(format!("does not compile: {}", shown.join("; ")));
    };
    let program = match scn.program.clone() {
        Some(p) => p,
        None => match module.programs.as_slice() {
            [one] => one.name.clone(),
            _ => return Verdict::Fail("no single PROGRAM to run".into()),
        },
    };
    let mut m = match targets::machine_spec(target, &module) {
        Ok(m) => m,
        Err(d) => {
            // The chip cannot hold it (REAL arithmetic, too much RAM...): not a failure,
            // but reported in the table with the backend's code.
            if let Some(x) = d.iter().find(|x| is_unfit_code(x.code)) {
                return Verdict::Unsupported(format!("{} ({})", x.code, x.message));
            }
            return Verdict::Fail(format!("machine: {:?}", d));
        }
    };
    // The cycle `plcc test` uses: the tasks' common tick, else 10 ms.
    let cycle = scenario::Cycle::of(&module, None);
    let out = scenario::run(&scn, m.as_mut(), &program, cycle.us);
    if out.passed() {
        Verdict::Pass
    } else {
        let why: Vec<String> = out
            .checks
            .iter()
            .filter(|c| !c.ok)
            .take(3)
            .map(|c| format!("line {}: {}: {}", c.line, c.text, c.detail))
            .chain(out.error.clone())
            .collect();
        Verdict::Fail(why.join("; "))
    }
}

/// Runs every scenario of the corpus in `dir` on `target`; the table and the
/// failures as text, and the number of failures.
fn run_corpus(dir: &Path, target: &str) -> (String, usize) {
    use std::fmt::Write;
    let mut out = String::new();
    let mut table: BTreeMap<String, Row> = BTreeMap::new();
    let mut failures = Vec::new();
    let excluded = exclusions();
    let mut excluded_seen = Vec::new();
    for sub in ["bulk/ironplc_e2e", "st", "il"] {
        let mut entries: Vec<PathBuf> = std::fs::read_dir(dir.join(sub))
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|e| e == "st" || e == "il"))
            .collect();
        entries.sort();
        for st in entries {
            let expect = st.with_extension("expect");
            if !expect.exists() {
                continue;
            }
            let name = st.file_name().unwrap().to_string_lossy().into_owned();
            let cat = format!("{}/{}", sub.split('/').next().unwrap(), category(&name));
            let row = table.entry(cat).or_default();
            if let Some(reason) = excluded.get(name.trim_end_matches(".st")) {
                row.excluded += 1;
                excluded_seen.push(format!("{name}: {reason}"));
                continue;
            }
            let verdict = std::panic::catch_unwind(|| judge(&st, &expect, target))
                .unwrap_or_else(|_| Verdict::Fail("PANIC".into()));
            match verdict {
                Verdict::Pass => row.passed += 1,
                Verdict::Unsupported(code) => {
                    let key = code.split(' ').next().unwrap_or("").to_string();
                    *row.unsupported.entry(key).or_default() += 1;
                    if std::env::var_os("PLCC_CORPUS_VERBOSE").is_some() {
                        let _ = writeln!(out, "unsupported {name}: {code}");
                    }
                }
                Verdict::Fail(why) => {
                    row.failed.push(name.clone());
                    failures.push(format!("{name}: {why}"));
                }
            }
        }
    }
    let _ = writeln!(out, "\ncorpus on {target}:");
    let _ = writeln!(
        out,
        "{:<40} {:>6} {:>6} {:>6} {:>6}  unsupported by",
        "category", "passed", "failed", "unsup", "excl"
    );
    let (mut tp, mut tf, mut tu, mut te) = (0, 0, 0, 0);
    for (cat, row) in &table {
        let u: u32 = row.unsupported.values().sum();
        let why: Vec<String> = row
            .unsupported
            .iter()
            .map(|(k, v)| format!("{k}×{v}"))
            .collect();
        let _ = writeln!(
            out,
            "{:<40} {:>6} {:>6} {:>6} {:>6}  {}",
            cat,
            row.passed,
            row.failed.len(),
            u,
            row.excluded,
            why.join(" ")
        );
        tp += row.passed;
        tf += row.failed.len();
        tu += u;
        te += row.excluded;
    }
    let _ = writeln!(
        out,
        "{:<40} {:>6} {:>6} {:>6} {:>6}",
        "total", tp, tf, tu, te
    );
    if !excluded_seen.is_empty() {
        let _ = writeln!(out, "\nexcluded (dialect-specific expectations):");
        for e in &excluded_seen {
            let _ = writeln!(out, "  {e}");
        }
    }
    if !failures.is_empty() {
        let _ = writeln!(out, "\nfailures:");
        for f in &failures {
            let _ = writeln!(out, "  {f}");
        }
    }
    (out, failures.len())
}

/// Every corpus scenario passes on every machine of the target registry that runs
/// here (`targets::checked_machines`: the C machine under the undefined-behaviour
/// sanitizer), the machines side by side. A scenario a machine cannot hold (the
/// PIC16's RAM, REAL arithmetic...) counts as unsupported there, by code, in its
/// table (`PLCC_CORPUS_VERBOSE=1` lists them).
#[test]
fn corpus_on_every_machine() {
    let Some(dir) = corpus_dir() else {
        skip::notice("../shared/corpus not found; skipping the corpus test");
        return;
    };
    for t in targets::not_running() {
        skip::notice(&format!(
            "target `{t}` cannot run programs here; the corpus skips it"
        ));
    }
    let machines = targets::checked_machines();
    let results: Vec<(String, usize)> = std::thread::scope(|s| {
        let jobs: Vec<_> = machines
            .iter()
            .map(|m| {
                let dir = &dir;
                s.spawn(move || run_corpus(dir, m))
            })
            .collect();
        jobs.into_iter()
            .map(|j| j.join().expect("a machine's run"))
            .collect()
    });
    let mut failed = Vec::new();
    for (m, (table, n)) in machines.iter().zip(results) {
        println!("{table}");
        if n > 0 {
            failed.push(format!("{n} on {m}"));
        }
    }
    assert!(
        failed.is_empty(),
        "corpus programs failed: {}",
        failed.join(", ")
    );
}

/// Every corpus scenario's program that plcc builds, its C in an executable of its
/// own under the address and undefined-behaviour sanitizers (which cannot be loaded
/// into the running test), cold start and 10 scans with no inputs: every variable and
/// the fault flag as the interpreter has them (`tests/common/c_driver.rs`).
#[test]
fn corpus_c_under_address_sanitizer() {
    let Some(dir) = corpus_dir() else {
        skip::notice("../shared/corpus not found; skipping the corpus test");
        return;
    };
    if !targets::find("c").is_some_and(|t| t.runs()) {
        skip::notice("no C compiler; skipping the corpus under the address sanitizer");
        return;
    }
    let mut modules = Vec::new();
    for sub in ["bulk/ironplc_e2e", "st", "il"] {
        let mut entries: Vec<PathBuf> = std::fs::read_dir(dir.join(sub))
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|e| e == "st" || e == "il"))
            .filter(|p| p.with_extension("expect").exists())
            .collect();
        entries.sort();
        for st in entries {
            let text = std::fs::read_to_string(st.with_extension("expect")).unwrap();
            let Ok(scn) = scenario::parse(&text) else {
                continue;
            };
            let opts = BuildOptions {
                programs: scn.program.iter().cloned().collect(),
                ..Default::default()
            };
            let bytes = std::fs::read(&st).unwrap();
            // What does not build is judged by `corpus_on_every_machine`.
            if let Ok(b) = build_sources(vec![(st.display().to_string(), bytes)], &opts) {
                if let Some(m) = b.module {
                    // What the C target cannot hold (zplc's `INT AT %Q0`) is counted
                    // unsupported by `corpus_on_every_machine`.
                    let unfit = plcc_c::files::generate(&m)
                        .is_err_and(|d| d.iter().any(|d| is_unfit_code(d.code)));
                    if !unfit {
                        modules.push((st.display().to_string(), m));
                    }
                }
            }
        }
    }
    let half = modules.len().div_ceil(2).max(1);
    let results: Vec<(usize, Vec<String>)> = std::thread::scope(|s| {
        let jobs: Vec<_> = modules
            .chunks(half)
            .map(|chunk| {
                s.spawn(move || {
                    let (mut compared, mut failures) = (0, Vec::new());
                    for (name, m) in chunk {
                        let cycle = scenario::Cycle::of(m, None).us;
                        match c_driver::agrees_under_asan(m, 10, cycle) {
                            Ok(n) => compared += n,
                            Err(e) => failures.push(format!("{name}: {e}")),
                        }
                    }
                    (compared, failures)
                })
            })
            .collect();
        jobs.into_iter().map(|j| j.join().expect("a job")).collect()
    });
    let compared: usize = results.iter().map(|r| r.0).sum();
    let failures: Vec<String> = results.into_iter().flat_map(|r| r.1).collect();
    println!(
        "{} corpus programs under ASan and UBSan, {compared} values compared",
        modules.len()
    );
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    assert!(modules.len() > 300, "only {} programs built", modules.len());
}

/// Every ST source in the corpus (programs without scenarios, parser fixtures, the
/// OSCAT and matiec libraries) goes through `check` without a panic; prints how many
/// are accepted.
#[test]
fn corpus_never_panics() {
    let Some(dir) = corpus_dir() else {
        skip::notice("../shared/corpus not found; skipping the corpus test");
        return;
    };
    let mut files = Vec::new();
    let mut stack = vec![dir];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                stack.push(p);
            } else if p
                .extension()
                .is_some_and(|e| e == "st" || e == "txt" || e == "il")
            {
                files.push(p);
            }
        }
    }
    files.sort();
    let (mut accepted, mut rejected, mut panicked) = (0, 0, Vec::new());
    for f in &files {
        let bytes = std::fs::read(f).unwrap();
        let name = f.display().to_string();
        let lang = if f.extension().is_some_and(|e| e == "il") {
            plcc_frontend::Lang::Il
        } else {
            plcc_frontend::Lang::St
        };
        let opts = BuildOptions {
            lang: Some(lang),
            check_only: true,
            ..Default::default()
        };
        match std::panic::catch_unwind(|| build_sources(vec![(name.clone(), bytes)], &opts)) {
            Ok(Ok(b)) if !b.failed() => accepted += 1,
            Ok(_) => rejected += 1,
            Err(_) => panicked.push(name),
        }
    }
    println!(
        "corpus sources checked: {} ({accepted} accepted, {rejected} with diagnostics)",
        files.len()
    );
    assert!(panicked.is_empty(), "plcc panicked on: {panicked:?}");
}

/// matiec's IL syntax test (`il/matiec_syntax_basic_code.il`, one POU per IL construct)
/// parses and type-checks: every error is about a construct plcc does not support yet
/// (E06xx), except one genuine error of that file, which only tests syntax:
/// `R1 tt` on an SR instance (SR's inputs are S1 and R; R1 is RS's).
#[test]
fn matiec_il_syntax_file_checks() {
    let Some(dir) = corpus_dir() else {
        skip::notice("../shared/corpus not found; skipping the corpus test");
        return;
    };
    let path = dir.join("il/matiec_syntax_basic_code.il");
    let bytes = std::fs::read(&path).unwrap();
    let text = String::from_utf8_lossy(&bytes).into_owned();
    let opts = BuildOptions {
        check_only: true,
        ..Default::default()
    };
    let b = build_sources(vec![(path.display().to_string(), bytes)], &opts).unwrap();
    let line_of = |d: &plcc_ir::diag::Diagnostic| {
        let start = d.span.map_or(0, |s| s.start as usize);
        text[..start.min(text.len())].lines().count()
    };
    let mut unexpected = Vec::new();
    for d in b.diagnostics.iter().filter(|d| d.is_error()) {
        let known = d.code == "E0207" && d.message.contains("R1") && {
            let line = text.lines().nth(line_of(d) - 1).unwrap_or("");
            line.trim_start().starts_with("R1 tt")
        };
        if !is_unsupported_code(d.code) && !known {
            unexpected.push(format!("line {}: {d}", line_of(d)));
        }
    }
    assert!(unexpected.is_empty(), "unexpected errors: {unexpected:#?}");
}
