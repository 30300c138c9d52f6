//! `plcc fmt`: Structured Text, Instruction List and STL files formatted by the front end's formatter
//! (`plcc_frontend::fmt`), printed, checked (`--check`) or rewritten in place
//! (`--write`, atomically). See docs/editors.md.

use crate::commands::{EXIT_FAIL, EXIT_USAGE};
use crate::{output, render};
use plcc_frontend::fmt::{format_il, format_st, format_stl, FmtError};
use plcc_frontend::source::{SourceFile, SourceMap};
use std::io::{Read, Write};
use std::path::{Path, PathBuf};

/// What `plcc fmt` does with the formatted text.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum FmtMode {
    /// Print it on standard output.
    Print,
    /// Change nothing; name every file that would change (exit status 1 if any).
    Check,
    /// Rewrite each file that changes, atomically.
    Write,
}

/// A file's bytes as text, and how to write the text back the same way.
struct Decoded {
    text: String,
    bom: bool,
    latin1: bool,
}

fn decode(bytes: &[u8]) -> Decoded {
    let (bom, bytes) = match bytes.strip_prefix(b"\xEF\xBB\xBF") {
        Some(rest) => (true, rest),
        None => (false, bytes),
    };
    match std::str::from_utf8(bytes) {
        Ok(s) => Decoded {
            text: s.to_string(),
            bom,
            latin1: false,
        },
        Err(_) => Decoded {
            text: bytes.iter().map(|&b| b as char).collect(),
            bom,
            latin1: true,
        },
    }
}

fn encode(d: &Decoded, text: &str) -> Vec<u8> {
    let mut out = Vec::with_capacity(text.len() + 3);
    if d.bom {
        out.extend_from_slice(b"\xEF\xBB\xBF");
    }
    if d.latin1 {
        // Every character came from the Latin-1 text or is ASCII.
        out.extend(
            text.chars()
                .map(|c| u8::try_from(u32::from(c)).unwrap_or(b'?')),
        );
    } else {
        out.extend_from_slice(text.as_bytes());
    }
    out
}

/// Runs `plcc fmt` on `files` (none, or `-`: standard input), in `lang` (`st`, `il`
/// or `stl`; `None`: from each file's extension). Exit status: 0, 1 when a file does not
/// parse or (`--check`) would change, 2 for usage and I/O errors.
pub fn fmt(files: &[PathBuf], lang: Option<&str>, mode: FmtMode) -> u8 {
    let stdin = PathBuf::from("-");
    let files: Vec<&Path> = if files.is_empty() {
        vec![stdin.as_path()]
    } else {
        files.iter().map(PathBuf::as_path).collect()
    };
    let mut status = 0u8;
    for path in files {
        let s = fmt_one(path, lang, mode);
        status = status.max(s);
    }
    status
}

fn fmt_one(path: &Path, lang: Option<&str>, mode: FmtMode) -> u8 {
    let is_stdin = path.as_os_str() == "-";
    let name = if is_stdin {
        "<stdin>".to_string()
    } else {
        path.display().to_string()
    };
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase());
    let lang = match (lang, ext.as_deref()) {
        (Some(l), _) => l,
        (None, Some("xml")) if !is_stdin => {
            eprintln!("error: {name}: plcc fmt formats Structured Text, Instruction List and STL (not PLCopen XML)");
            return EXIT_USAGE;
        }
        (None, Some(e @ ("il" | "stl"))) if !is_stdin => e,
        (None, _) => "st",
    };
    if is_stdin && mode == FmtMode::Write {
        eprintln!("error: --write needs files (standard input is printed)");
        return EXIT_USAGE;
    }
    let bytes = if is_stdin {
        let mut b = Vec::new();
        if let Err(e) = std::io::stdin().read_to_end(&mut b) {
            eprintln!("error: cannot read standard input: {e}");
            return EXIT_USAGE;
        }
        b
    } else {
        match std::fs::read(path) {
            Ok(b) => b,
            Err(e) => {
                eprintln!("error: cannot read {name}: {e}");
                return EXIT_USAGE;
            }
        }
    };
    let decoded = decode(&bytes);
    let format = match lang {
        "il" => format_il,
        "stl" => format_stl,
        _ => format_st,
    };
    let formatted = match format(&decoded.text) {
        Ok(t) => t,
        Err(FmtError::Syntax(diags)) => {
            let mut map = SourceMap::new();
            map.add(SourceFile::new(name.clone(), decoded.text.clone()));
            render::to_stderr(&map, &diags);
            eprintln!("error: {name} does not parse; it is left as it is");
            return EXIT_FAIL;
        }
        Err(e @ FmtError::Internal(_)) => {
            eprintln!("error: {name}: {e}; it is left as it is");
            return EXIT_FAIL;
        }
    };
    let changed = formatted != decoded.text;
    match mode {
        FmtMode::Print => {
            let mut out = std::io::stdout().lock();
            if out.write_all(&encode(&decoded, &formatted)).is_err() {
                return EXIT_USAGE;
            }
            0
        }
        FmtMode::Check => {
            if changed {
                println!("{name}");
                EXIT_FAIL
            } else {
                0
            }
        }
        FmtMode::Write => {
            if !changed {
                return 0;
            }
            match output::write_atomic(path, &encode(&decoded, &formatted)) {
                Ok(()) => 0,
                Err(e) => {
                    eprintln!("error: cannot write {name}: {e}");
                    EXIT_USAGE
                }
            }
        }
    }
}
