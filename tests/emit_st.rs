//! `--emit st` (docs/editors.md): every program of `tests/programs` and
//! `../shared/corpus` that compiles, in any language (ST, IL, STL, PLCopen XML with
//! ladder, FBD, SFC and IL bodies), printed as Structured Text, compiles as ST to
//! the same optimised IR, or, where the printed form makes other IR (IL's compiler
//! temporaries become variables), computes the same values over 1,000 scans with
//! random inputs on the interpreter.

use plcc::driver::{build_sources, BuildOptions};
use plcc_frontend::Lang;
use plcc_ir::text::{print_module, PrintOptions};
use plcc_ir::Module;
use std::path::Path;

#[path = "common/skip.rs"]
mod skip;

#[path = "common/sources.rs"]
mod sources;
use sources::{is_codesys, lang_of, read_text, source_files};

#[path = "common/rng.rs"]
#[allow(dead_code)]
mod rng;

#[path = "common/lockstep.rs"]
mod lockstep;

const SCANS: u32 = 1000;

/// The build of one file: its module, with `print` its ST, and whether it was built
/// in the CODESYS dialect; or its first errors.
fn build(
    name: &str,
    text: &str,
    lang: Lang,
    codesys: bool,
    print: bool,
) -> Result<(Module, Option<String>, bool), String> {
    let opts = BuildOptions {
        codesys,
        lang: Some(lang),
        print_st: print,
        ..Default::default()
    };
    let build = build_sources(vec![(name.to_string(), text.as_bytes().to_vec())], &opts)
        .map_err(|e| e.0)?;
    // A PLCopen file from a CODESYS-based editor is built in CODESYS's dialect.
    let codesys = codesys
        || build
            .ladder
            .iter()
            .any(|v| v.dialect == plcc_frontend::plcopen::Dialect::Codesys);
    match build.module {
        Some(m) => Ok((m, build.st, codesys)),
        None => Err(build
            .diagnostics
            .iter()
            .filter(|d| d.is_error())
            .take(3)
            .map(|d| d.to_string())
            .collect::<Vec<_>>()
            .join("; ")),
    }
}

/// The module as text with values numbered in order, without the file table.
fn canonical(m: &Module) -> String {
    let opts = PrintOptions {
        canonical: true,
        ..PrintOptions::default()
    };
    print_module(m, &opts)
        .lines()
        .filter(|l| !l.starts_with("file "))
        .collect::<Vec<_>>()
        .join("\n")
}

/// A variable written at random: one of a program instance (`inst.x`) or a global,
/// not a member of a block instance.
fn writable(path: &str) -> bool {
    path.split('.').count() == 2
}

#[derive(Default)]
struct Tally {
    same_ir: usize,
    same_values: usize,
    not_compiling: usize,
    failures: Vec<String>,
}

fn check_file(path: &Path, t: &mut Tally) {
    let lang = lang_of(path).expect("a source file");
    let codesys = is_codesys(path);
    let name = path.display().to_string();
    let text = read_text(path);
    let Ok((original, Some(st), codesys)) = build(&name, &text, lang, codesys, true) else {
        t.not_compiling += 1;
        return;
    };
    let printed = match build("printed.st", &st, Lang::St, codesys, false) {
        Ok((m, ..)) => m,
        Err(e) => {
            t.failures
                .push(format!("{name}: the printed ST does not compile: {e}"));
            return;
        }
    };
    if canonical(&original) == canonical(&printed) {
        t.same_ir += 1;
        return;
    }
    let cycle = original
        .task_tick_us()
        .map_or(10, |us| us.div_ceil(1000) as u32);
    let seed = 0x9E37_79B9_7F4A_7C15 ^ name.len() as u64;
    match lockstep::run(
        &original,
        &printed,
        "interp",
        SCANS,
        cycle,
        seed,
        &writable,
        &|_| true,
    ) {
        Ok(Some(o)) if o.compared == 0 => t.failures.push(format!(
            "{name}: other IR, and no variable to compare ({} written)",
            o.inputs
        )),
        Ok(Some(_)) => t.same_values += 1,
        Ok(None) => t
            .failures
            .push(format!("{name}: the interpreter cannot run it")),
        Err(e) => t
            .failures
            .push(format!("{name}: other IR, and the values differ {e}")),
    }
}

#[test]
fn every_program_printed_as_st_means_the_same() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files = Vec::new();
    source_files(&root.join("tests/programs"), true, &mut files);
    let ours = files.len();
    let shared = root.join("../shared/corpus");
    if shared.is_dir() {
        source_files(&shared, true, &mut files);
    } else {
        skip::notice("../shared/corpus not found; printing tests/programs only");
    }
    let mut t = Tally::default();
    for f in &files {
        check_file(f, &mut t);
    }
    println!(
        "{} files ({ours} of tests/programs): {} printed as ST to the same IR, {} to other IR \
         with the same values over {SCANS} random scans, {} do not compile",
        files.len(),
        t.same_ir,
        t.same_values,
        t.not_compiling,
    );
    assert!(
        t.failures.is_empty(),
        "{} failures:\n{}",
        t.failures.len(),
        t.failures.join("\n")
    );
    assert!(t.same_ir >= ours / 2, "too few files compiled");
}
