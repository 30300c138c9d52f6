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
