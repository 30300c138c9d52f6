//! Test helper: the source files of the repository and of `../shared`, which tests
//! that compare two ways of doing one thing run over.

use std::path::{Path, PathBuf};

/// The repository's root.
pub(crate) fn repo_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// `../shared`, if it is there.
pub(crate) fn shared() -> Option<PathBuf> {
    let shared = repo_root().join("../shared");
    shared.is_dir().then_some(shared)
}

/// The files under `dirs` whose path `keep` accepts, with their text (those that
/// are not UTF-8 left out), sorted by path.
pub(crate) fn files_under(
    mut dirs: Vec<PathBuf>,
    keep: impl Fn(&Path) -> bool,
) -> Vec<(String, String)> {
    let mut out = Vec::new();
    while let Some(d) = dirs.pop() {
        let Ok(entries) = std::fs::read_dir(&d) else {
            continue;
        };
        for e in entries.flatten() {
            let p = e.path();
            if p.is_dir() {
                dirs.push(p);
            } else if keep(&p) {
                if let Ok(text) = std::fs::read_to_string(&p) {
                    out.push((p.display().to_string(), text));
                }
            }
        }
    }
    out.sort();
    out
}

/// The Structured Text files under `dirs` (as [`files_under`]).
fn st_files(dirs: Vec<PathBuf>) -> Vec<(String, String)> {
    files_under(dirs, |p| p.extension().is_some_and(|x| x == "st"))
}

/// Runs `compare` (which does a job two ways on the given files and returns how many
/// cases it compared and how many it refused) over the repository's ST files
/// (`examples`, `tests`), then over those of `../shared` (a notice if it is absent),
/// and asserts that each compared more than its minimum (`min.0`, `min.1`).
pub(crate) fn compare_over_st_files(
    what: &str,
    min: (usize, usize),
    compare: impl Fn(&[(String, String)]) -> (usize, usize),
) {
    let root = repo_root();
    let files = st_files(vec![root.join("examples"), root.join("tests")]);
    assert!(files.len() > 50, "{} ST files found", files.len());
    let (compared, refused) = compare(&files);
    eprintln!("repository: {compared} {what} compared, {refused} refused");
    assert!(
        compared > min.0,
        "{compared} {what} compared, {refused} refused"
    );
    let Some(shared) = shared() else {
        eprintln!("NOTICE: ../shared is absent: its ST corpus was not compared ({what})");
        return;
    };
    let files = st_files(vec![shared]);
    let (compared, refused) = compare(&files);
    eprintln!(
        "../shared: {} files, {compared} {what} compared, {refused} refused",
        files.len()
    );
    assert!(
        compared > min.1,
        "{compared} {what} compared, {refused} refused"
    );
}
