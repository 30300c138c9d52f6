//! `plcc fmt` (docs/editors.md): every ST file of `tests/programs` and
//! `../shared/corpus` (OSCAT included) formats idempotently, and a file that compiles
//! compiles after formatting to the same optimised IR; snapshots of small layouts;
//! the command's exit statuses and file handling.

use plcc::driver::{build_sources, BuildOptions};
use plcc_frontend::fmt::{format_st, FmtError};
use plcc_ir::text::{print_module, PrintOptions};
use std::path::{Path, PathBuf};

fn st_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(rd) = std::fs::read_dir(dir) else {
        return;
    };
    let mut entries: Vec<PathBuf> = rd.filter_map(|e| e.ok().map(|e| e.path())).collect();
    entries.sort();
    for p in entries {
        if p.is_dir() {
            st_files(&p, out);
        } else if p.extension().is_some_and(|e| e.eq_ignore_ascii_case("st")) {
            out.push(p);
        }
    }
}

/// The optimised IR of one file as text, or its errors' codes.
fn ir_of(name: &str, text: &str, codesys: bool) -> Result<String, Vec<String>> {
    let opts = BuildOptions {
        codesys,
        lang: Some(plcc_frontend::Lang::St),
        ..Default::default()
    };
    let build = build_sources(vec![(name.to_string(), text.as_bytes().to_vec())], &opts)
        .map_err(|e| vec![e.0])?;
    match build.module {
        Some(m) => Ok(print_module(&m, &PrintOptions::default())),
        None => Err(build
            .diagnostics
            .iter()
            .filter(|d| d.is_error())
            .map(|d| d.code.to_string())
            .collect()),
    }
}

/// How one file fared.
#[derive(Default)]
struct Tally {
    same_ir: usize,
    not_compiling: usize,
    not_parsing: usize,
    failures: Vec<String>,
}

fn check_file(path: &Path, codesys: bool, t: &mut Tally) {
    let bytes = std::fs::read(path).expect("readable");
    let bytes = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(&bytes);
    let text = match std::str::from_utf8(bytes) {
        Ok(s) => s.to_string(),
        Err(_) => bytes.iter().map(|&b| b as char).collect(),
    };
    let name = path.display().to_string();
    let once = match format_st(&text) {
        Ok(s) => s,
        Err(FmtError::Syntax(_)) => {
            t.not_parsing += 1;
            return;
        }
        Err(e) => {
            t.failures.push(format!("{name}: {e}"));
            return;
        }
    };
    match format_st(&once) {
        Ok(twice) if twice == once => {}
        Ok(twice) => {
            let line = once
                .lines()
                .zip(twice.lines())
                .position(|(a, b)| a != b)
                .unwrap_or(0);
            t.failures.push(format!(
                "{name}: not idempotent at line {}:\n  {:?}\n  {:?}",
                line + 1,
                once.lines().nth(line).unwrap_or(""),
                twice.lines().nth(line).unwrap_or("")
            ));
            return;
        }
        Err(e) => {
            t.failures
                .push(format!("{name}: the formatted text fails: {e}"));
            return;
        }
    }
    match (ir_of(&name, &text, codesys), ir_of(&name, &once, codesys)) {
        (Ok(a), Ok(b)) if a == b => t.same_ir += 1,
        (Ok(_), Ok(_)) => t.failures.push(format!("{name}: the IR differs")),
        (Err(a), Err(b)) if a == b => t.not_compiling += 1,
        (a, b) => t.failures.push(format!(
            "{name}: compiles {} before, {} after formatting",
            if a.is_ok() { "ok" } else { "with errors" },
            if b.is_ok() { "ok" } else { "with errors" },
        )),
    }
}

/// Files under a `codesys` directory and the OSCAT library are in the CODESYS
/// dialect.
fn is_codesys(p: &Path) -> bool {
    p.components().any(|c| {
        let c = c.as_os_str().to_string_lossy().to_ascii_lowercase();
        c == "codesys" || c.starts_with("oscat")
    })
}

#[test]
fn corpus_formats_idempotently_to_the_same_ir() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files = Vec::new();
    st_files(&root.join("tests/programs"), &mut files);
    let ours = files.len();
    let shared = root.join("../shared/corpus");
    if shared.is_dir() {
        st_files(&shared, &mut files);
    } else {
        eprintln!("notice: ../shared/corpus not found; formatting tests/programs only");
    }
    let mut t = Tally::default();
    for f in &files {
        check_file(f, is_codesys(f), &mut t);
    }
    println!(
        "{} files ({} of tests/programs): {} formatted idempotently to the same IR, \
         {} formatted idempotently with the same errors (they do not compile today), \
         {} refused (they do not parse)",
        files.len(),
        ours,
        t.same_ir,
        t.not_compiling,
        t.not_parsing
    );
    assert!(t.failures.is_empty(), "{}", t.failures.join("\n"));
    assert!(t.same_ir >= ours / 2, "too few files compiled");
}
