//! The printed forms of builds (docs/editors.md), on every program of
//! `tests/programs` and `../shared/corpus` that compiles:
//!
//! - `--emit st`: in any language (ST, IL, STL, PLCopen XML with ladder, FBD, SFC and
//!   IL bodies), printed as Structured Text, it compiles as ST to the same optimised
//!   IR, or, where the printed form makes other IR (IL's compiler temporaries become
//!   variables), computes the same values over 1,000 scans with random inputs on the
//!   interpreter;
//! - `--emit plcopen`: an ST, IL or STL file written as a PLCopen XML project reads
//!   back to the same optimised IR or the same values (the file built with the
//!   configuration the project got, when it had none), or is refused with E0601 for
//!   what PLCopen XML has no form for.

use plcc::driver::{build_sources, BuildOptions};
use plcc_frontend::{Lang, PrintAs};
use plcc_ir::text::{print_module, PrintOptions};
use plcc_ir::Module;
use std::path::Path;

#[path = "common/skip.rs"]
mod skip;

#[path = "common/sources.rs"]
mod sources;
use sources::{corpus_files, is_codesys, lang_of, read_text};

#[path = "common/cli.rs"]
#[allow(dead_code)]
mod cli;
use cli::{plcc, stderr};

#[path = "common/rng.rs"]
#[allow(dead_code)]
mod rng;

#[path = "common/lockstep.rs"]
mod lockstep;

const SCANS: u32 = 1000;

/// The build of the files `(name, text, lang)`: its module, the printed form asked
/// for, and whether it was built in the CODESYS dialect; or its first errors.
fn build(
    files: &[(&str, &str, Lang)],
    codesys: bool,
    print: PrintAs,
) -> Result<(Module, Option<String>, bool), String> {
    let opts = BuildOptions {
        codesys,
        lang: (files.len() == 1).then_some(files[0].2),
        print,
        ..Default::default()
    };
    let texts = files
        .iter()
        .map(|(n, t, _)| (n.to_string(), t.as_bytes().to_vec()))
        .collect();
    let build = build_sources(texts, &opts).map_err(|e| e.0)?;
    // A PLCopen file from a CODESYS-based editor is built in CODESYS's dialect.
    let codesys = codesys
        || build
            .ladder
            .iter()
            .any(|v| v.dialect == plcc_frontend::plcopen::Dialect::Codesys);
    match build.module {
        Some(m) => Ok((m, build.printed, codesys)),
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
    refused: Vec<String>,
    failures: Vec<String>,
}

/// Compares `original` with `printed`, built from what `name` was printed as:
/// the same IR, else the same values over [`SCANS`] random scans.
fn compare(name: &str, original: &Module, printed: &Module, t: &mut Tally) {
    if canonical(original) == canonical(printed) {
        t.same_ir += 1;
        return;
    }
    let cycle = original
        .task_tick_us()
        .or(printed.task_tick_us())
        .map_or(10, |us| us.div_ceil(1000) as u32);
    let seed = 0x9E37_79B9_7F4A_7C15 ^ name.len() as u64;
    match lockstep::run(
        original,
        printed,
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

/// A file's name, text and language.
fn source(path: &Path) -> (String, String, Lang) {
    let lang = lang_of(path).expect("a source file");
    (path.display().to_string(), read_text(path), lang)
}

/// `--emit st` of one file, compiled as ST and compared.
fn check_st(path: &Path, t: &mut Tally) {
    let (name, text, lang) = source(path);
    let file = [(name.as_str(), text.as_str(), lang)];
    let Ok((original, Some(st), codesys)) = build(&file, is_codesys(path), PrintAs::St) else {
        t.not_compiling += 1;
        return;
    };
    match build(&[("printed.st", &st, Lang::St)], codesys, PrintAs::Nothing) {
        Ok((printed, ..)) => compare(&name, &original, &printed, t),
        Err(e) => t
            .failures
            .push(format!("{name}: the printed ST does not compile: {e}")),
    }
}

/// `--emit plcopen` of one ST, IL or STL file, read back and compared.
fn check_plcopen(path: &Path, t: &mut Tally) {
    let (name, text, lang) = source(path);
    let codesys = is_codesys(path);
    let file = [(name.as_str(), text.as_str(), lang)];
    let xml = match build(&file, codesys, PrintAs::Plcopen) {
        Ok((_, Some(xml), _)) => xml,
        Ok((_, None, _)) => {
            t.refused.push(name);
            return;
        }
        Err(_) => {
            t.not_compiling += 1;
            return;
        }
    };
    let printed = match build(
        &[("printed.xml", &xml, Lang::Ld)],
        codesys,
        PrintAs::Nothing,
    ) {
        Ok((m, ..)) => m,
        Err(e) => {
            t.failures
                .push(format!("{name}: the PLCopen project does not compile: {e}"));
            return;
        }
    };
    // A file without a configuration got the one OpenPLC Editor starts with: the
    // original is built with the same one.
    let config = (!text.to_ascii_uppercase().contains("CONFIGURATION"))
        .then(|| {
            let mut c = String::from(
                "CONFIGURATION config RESOURCE resource1 ON PLC\n\
             TASK task0(INTERVAL := T#20ms, PRIORITY := 0);\n",
            );
            for inst in xml.split("<pouInstance ").skip(1) {
                let attr = |k: &str| inst.split(&format!("{k}=\"")).nth(1)?.split('"').next();
                if let (Some(n), Some(ty)) = (attr("name"), attr("typeName")) {
                    // CODESYS's tasks call a PROGRAM by its name: no instance of another.
                    if n == ty {
                        return None;
                    }
                    c.push_str(&format!("PROGRAM {n} WITH task0 : {ty};\n"));
                }
            }
            Some(c + "END_RESOURCE END_CONFIGURATION\n")
        })
        .flatten();
    let mut files = file.to_vec();
    if let Some(c) = &config {
        files.push(("config.st", c, Lang::St));
    }
    match build(&files, codesys, PrintAs::Nothing) {
        Ok((original, ..)) => compare(&name, &original, &printed, t),
        Err(e) => t.failures.push(format!(
            "{name}: does not compile with the configuration: {e}"
        )),
    }
}

/// Runs `check` on the project's and the corpus's files (with `xml`, the PLCopen
/// files too): the tally, how many files, and how many are the project's. Fails on
/// any failure, or when too few files compiled.
fn over_corpus(xml: bool, check: fn(&Path, &mut Tally)) -> (Tally, usize, usize) {
    let (files, ours) = corpus_files(xml, "printing");
    let mut t = Tally::default();
    for f in &files {
        check(f, &mut t);
    }
    for r in &t.refused {
        println!("  refused: {r}");
    }
    assert!(
        t.failures.is_empty(),
        "{} failures:\n{}",
        t.failures.len(),
        t.failures.join("\n")
    );
    assert!(t.same_ir >= ours / 2, "too few files compiled");
    (t, files.len(), ours)
}

#[test]
fn every_program_printed_as_st_means_the_same() {
    let (t, files, ours) = over_corpus(true, check_st);
    println!(
        "{files} files ({ours} of tests/programs): {} printed as ST to the same IR, {} to other IR \
         with the same values over {SCANS} random scans, {} do not compile",
        t.same_ir, t.same_values, t.not_compiling,
    );
}

#[test]
fn every_st_il_and_stl_program_written_as_plcopen_means_the_same() {
    let (t, files, ours) = over_corpus(false, check_plcopen);
    println!(
        "{files} files ({ours} of tests/programs): {} written as PLCopen XML to the same IR, {} to \
         other IR with the same values over {SCANS} random scans, {} refused (E0601), {} do \
         not compile",
        t.same_ir,
        t.same_values,
        t.refused.len(),
        t.not_compiling,
    );
}

/// The command line: `--emit st` and `--emit plcopen` on standard output or into a
/// file that builds again; what cannot be written is an error with its code and
/// place; a PLCopen file is not written as one again.
#[test]
fn the_command_line_prints_and_refuses() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("emit");
    std::fs::create_dir_all(&dir).unwrap();
    let o = plcc(&["--emit", "st", "tests/programs/il/bake_timer.il"]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let st = String::from_utf8(o.stdout).unwrap();
    assert!(st.contains("JMP in_limit;"), "{st}");
    let xml = dir.join("bake_timer.xml");
    let o = plcc(&[
        "--emit",
        "plcopen",
        "tests/programs/il/bake_timer.il",
        "-o",
        xml.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let text = std::fs::read_to_string(&xml).unwrap();
    assert!(text.starts_with("<?xml version='1.0' encoding='utf-8'?>\n<project "));
    assert!(text.contains("<IL>\n"), "{text}");
    let o = plcc(&["check", xml.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    // A FUNCTION_BLOCK with a METHOD: E0601 at the METHOD, nothing written.
    let oo = dir.join("oo.st");
    std::fs::write(
        &oo,
        "FUNCTION_BLOCK fb\nMETHOD m : INT\nm := 1;\nEND_METHOD\nEND_FUNCTION_BLOCK\n\
         PROGRAM p\nVAR f : fb; x : INT; END_VAR\nx := f.m();\nEND_PROGRAM\n",
    )
    .unwrap();
    let o = plcc(&["--emit", "plcopen", oo.to_str().unwrap()]);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(
        err.contains("error[E0601]: a METHOD cannot be written as PLCopen XML")
            && err.contains(":2:1"),
        "{err}"
    );
    assert!(o.stdout.is_empty());
    // A PLCopen file: a usage error.
    let o = plcc(&["--emit", "plcopen", "tests/programs/ld/counter_reset.xml"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("are one already"));
}
