//! Equivalence groups: the same logic written in Structured Text, Instruction List and
//! PLC-UD STL must give the same optimised IR.
//!
//! A group is a stem under `tests/programs/equiv/`: `NAME.st`, `NAME.il` and, where
//! STL can express the logic (no DINT, no function blocks, no TIME, no function
//! outputs), `NAME.stl`, with one shared scenario `NAME.expect` that `tests/e2e.rs` runs
//! on every file of the group on both machines. This test checks the other half of the
//! claim: that the three front ends lower the group to the same program. IL is
//! translated into the syntax tree ST gives (the CPDev method) and STL is mapped onto
//! it too, so any difference in the printed IR is a front end that does not mean what
//! the others mean, or one that leaves the optimiser a different program to work on.
//!
//! Every file of a group is built alone, with its language forced and under the same
//! file name, so that even the table of source files in the IR agrees; the printed
//! modules must then be identical, byte for byte. The one exception is IL with
//! labels: a label gets its block before the code around it is lowered, so values and
//! blocks are numbered differently from ST. The groups where that happens are listed
//! in [`RENUMBERED_IL`] (and say so in their source comments); their IL is compared
//! after renaming values and blocks in order of appearance (the printer's canonical
//! numbering), nothing
//! else. A group on that list whose IL is identical anyway is an error, so the list
//! stays exact. A build must give no diagnostics at all, not even warnings.
//!
//! The test never skips: these are the project's own files, and a missing directory,
//! a group without ST or IL, or fewer than [`MIN_FULL_GROUPS`] groups in all three
//! languages is a failure. Failures are collected and reported together.

use plcc::driver::{build_sources, BuildOptions};
use plcc_frontend::Lang;
use plcc_ir::text::{print_module, PrintOptions};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// The languages of a group, by file extension, in the order they are compared (the
/// first is the reference).
const LANGS: [(&str, Lang); 3] = [("st", Lang::St), ("il", Lang::Il), ("stl", Lang::Stl)];

/// Fewer groups than this with all three languages is a failure.
const MIN_FULL_GROUPS: usize = 15;

/// Groups whose IL uses labels and gives the IR of ST only up to the numbering of
/// values and blocks.
const RENUMBERED_IL: [&str; 6] = [
    "counter",
    "for_loop",
    "if_else",
    "latch",
    "repeat_loop",
    "state_machine",
];

/// The directory of the groups.
fn equiv_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/programs/equiv")
}

/// Every group under `dir`: its stem and the source file of each language present
/// (indexed like [`LANGS`]). Also the names of files that belong to no language.
fn groups(dir: &Path) -> (BTreeMap<String, [Option<PathBuf>; 3]>, Vec<String>) {
    let mut out: BTreeMap<String, [Option<PathBuf>; 3]> = BTreeMap::new();
    let mut strays = Vec::new();
    let entries =
        std::fs::read_dir(dir).unwrap_or_else(|e| panic!("cannot read {}: {e}", dir.display()));
    for entry in entries {
        let path = entry.expect("directory entry").path();
        let (Some(stem), Some(ext)) = (
            path.file_stem()
                .and_then(|s| s.to_str())
                .map(str::to_string),
            path.extension()
                .and_then(|s| s.to_str())
                .map(str::to_string),
        ) else {
            strays.push(path.display().to_string());
            continue;
        };
        if ext == "expect" {
            continue;
        }
        match LANGS.iter().position(|(e, _)| *e == ext) {
            Some(i) => out.entry(stem).or_default()[i] = Some(path),
            None => strays.push(path.display().to_string()),
        }
    }
    (out, strays)
}

/// The optimised IR of the file at `path` read as `lang` and built under the name
/// `name`, printed as built and with canonical numbering, or why it could not be had
/// (it does not compile, or gives diagnostics).
fn optimised_ir(path: &Path, lang: Lang, name: &str) -> Result<(String, String), String> {
    let text = std::fs::read(path).map_err(|e| format!("cannot read it: {e}"))?;
    let opts = BuildOptions {
        lang: Some(lang),
        ..BuildOptions::default()
    };
    let build = build_sources(vec![(name.to_string(), text)], &opts).map_err(|e| e.0)?;
    if !build.diagnostics.is_empty() {
        let diags: Vec<String> = build.diagnostics.iter().map(|d| d.to_string()).collect();
        return Err(format!("diagnostics:\n      {}", diags.join("\n      ")));
    }
    let module = build
        .module
        .ok_or_else(|| "no module and no diagnostics".to_string())?;
    let canonical = PrintOptions {
        canonical: true,
        ..PrintOptions::default()
    };
    Ok((
        print_module(&module, &PrintOptions::default()),
        print_module(&module, &canonical),
    ))
}

/// The first line where `st` and `other` (from the file with extension `ext`)
/// differ, shown from both sides, for messages.
fn first_difference(st: &str, other: &str, ext: &str) -> String {
    let (mut la, mut lb) = (st.lines(), other.lines());
    let mut n = 1;
    loop {
        match (la.next(), lb.next()) {
            (None, None) => return "no difference".into(),
            (x, y) if x == y => n += 1,
            (x, y) => {
                return format!(
                    "line {n}:\n      {:<5} {}\n      {:<5} {}",
                    "st:",
                    x.unwrap_or("(end)"),
                    format!("{ext}:"),
                    y.unwrap_or("(end)")
                )
            }
        }
    }
}

/// Compares the IR of every language of one group with its ST; the problems found.
fn check_group(stem: &str, files: &[Option<PathBuf>; 3]) -> Vec<String> {
    let mut problems = Vec::new();
    // The same name for every language: the file table of the IR must agree too.
    let name = format!("tests/programs/equiv/{stem}");
    let mut irs: Vec<Option<(String, String)>> = Vec::new();
    for ((ext, lang), file) in LANGS.iter().zip(files) {
        let ir = file
            .as_ref()
            .and_then(|path| match optimised_ir(path, *lang, &name) {
                Ok(ir) => Some(ir),
                Err(e) => {
                    problems.push(format!("{stem}.{ext}: {e}"));
                    None
                }
            });
        irs.push(ir);
    }
    let Some((st, st_canonical)) = &irs[0] else {
        return problems;
    };
    if !st.contains("func ") {
        problems.push(format!("{stem}.st: no function in the IR"));
    }
    let renumbered = RENUMBERED_IL.contains(&stem);
    for ((ext, lang), ir) in LANGS.iter().zip(&irs).skip(1) {
        let Some((ir, ir_canonical)) = ir else {
            continue;
        };
        let may_renumber = renumbered && *lang == Lang::Il;
        if ir == st {
            if may_renumber {
                problems.push(format!(
                    "{stem}.{ext}: the IR is identical to ST's; take `{stem}` off \
                     RENUMBERED_IL (and its source comments)"
                ));
            }
            continue;
        }
        let (a, b) = if may_renumber {
            (st_canonical, ir_canonical)
        } else {
            (st, ir)
        };
        if a != b {
            let how = if may_renumber {
                " (even up to numbering)"
            } else {
                ""
            };
            problems.push(format!(
                "{stem}.{ext}: the IR differs from ST's{how}, first at {}",
                first_difference(a, b, ext)
            ));
        }
    }
    problems
}

/// The IR of every IL and STL file is the IR of its group's ST file (IL of the groups
/// in [`RENUMBERED_IL`] up to numbering), and no build gives a diagnostic.
#[test]
fn every_group_gives_the_same_ir_in_every_language() {
    let (groups, _) = groups(&equiv_dir());
    assert!(!groups.is_empty(), "no groups in {}", equiv_dir().display());
    let mut problems = Vec::new();
    for (stem, files) in &groups {
        problems.extend(check_group(stem, files));
    }
    let full = groups
        .values()
        .filter(|f| f.iter().all(Option::is_some))
        .count();
    println!("{} groups, {full} in all three languages", groups.len());
    assert!(
        problems.is_empty(),
        "{} problem(s):\n  {}",
        problems.len(),
        problems.join("\n  ")
    );
}

/// Every group has ST, IL and a scenario; enough groups have STL too; the directory
/// holds nothing else; [`RENUMBERED_IL`] names only groups with IL.
#[test]
fn groups_are_complete() {
    let dir = equiv_dir();
    let (groups, strays) = groups(&dir);
    let mut problems: Vec<String> = strays
        .iter()
        .map(|s| format!("{s}: not a source of any language nor a scenario"))
        .collect();
    for (stem, files) in &groups {
        for (i, (ext, _)) in LANGS.iter().enumerate().take(2) {
            if files[i].is_none() {
                problems.push(format!("{stem}: no {stem}.{ext}"));
            }
        }
        if !dir.join(format!("{stem}.expect")).exists() {
            problems.push(format!("{stem}: no scenario {stem}.expect"));
        }
    }
    let full = groups
        .values()
        .filter(|f| f.iter().all(Option::is_some))
        .count();
    if full < MIN_FULL_GROUPS {
        problems.push(format!(
            "only {full} groups in all three languages (at least {MIN_FULL_GROUPS} expected)"
        ));
    }
    for stem in RENUMBERED_IL {
        if groups.get(stem).is_none_or(|f| f[1].is_none()) {
            problems.push(format!(
                "RENUMBERED_IL names `{stem}`, which has no IL file"
            ));
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}
