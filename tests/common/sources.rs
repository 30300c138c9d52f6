//! The source files the whole-corpus suites walk (`tests/programs`, `../shared/corpus`):
//! finding them, their language, their dialect, and their text.

use plcc_frontend::Lang;
use std::path::{Path, PathBuf};

/// The `.st`, `.il` and `.stl` files under `dir`, sorted (with `xml`, the PLCopen
/// `.xml` files too).
pub fn source_files(dir: &Path, xml: bool, out: &mut Vec<PathBuf>) {
    let Ok(rd) = std::fs::read_dir(dir) else {
        return;
    };
    let mut entries: Vec<PathBuf> = rd.filter_map(|e| e.ok().map(|e| e.path())).collect();
    entries.sort();
    for p in entries {
        if p.is_dir() {
            source_files(&p, xml, out);
        } else if lang_of(&p).is_some_and(|l| xml || l != Lang::Ld) {
            out.push(p);
        }
    }
}

/// The source files of `tests/programs`, then those of `../shared/corpus` (with a
/// skip notice, which the including test's `skip` module shows, when it is absent):
/// the files, and how many of them are the project's. `doing` says what the test
/// does with them, for the notice.
pub fn corpus_files(xml: bool, doing: &str) -> (Vec<PathBuf>, usize) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files = Vec::new();
    source_files(&root.join("tests/programs"), xml, &mut files);
    let ours = files.len();
    let shared = root.join("../shared/corpus");
    if shared.is_dir() {
        source_files(&shared, xml, &mut files);
    } else {
        crate::skip::notice(&format!(
            "../shared/corpus not found; {doing} tests/programs only"
        ));
    }
    (files, ours)
}

/// ST, IL, STL or PLCopen XML, by the file's extension; `None` for other files.
pub fn lang_of(p: &Path) -> Option<Lang> {
    match p
        .extension()?
        .to_string_lossy()
        .to_ascii_lowercase()
        .as_str()
    {
        "st" => Some(Lang::St),
        "il" => Some(Lang::Il),
        "stl" => Some(Lang::Stl),
        "xml" => Some(Lang::Ld),
        _ => None,
    }
}

/// Files under a `codesys` directory and the OSCAT library are in the CODESYS
/// dialect.
pub fn is_codesys(p: &Path) -> bool {
    p.components().any(|c| {
        let c = c.as_os_str().to_string_lossy().to_ascii_lowercase();
        c == "codesys" || c.starts_with("oscat")
    })
}

/// A file's text: UTF-8 without its byte-order mark, else Latin-1.
pub fn read_text(path: &Path) -> String {
    let bytes = std::fs::read(path).expect("readable");
    let bytes = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(&bytes);
    match std::str::from_utf8(bytes) {
        Ok(s) => s.to_string(),
        Err(_) => bytes.iter().map(|&b| b as char).collect(),
    }
}
