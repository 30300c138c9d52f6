//! Mutated programs never make plcc panic: every ST file of the project (and of the
//! corpus, when present) is mutated with a fixed seed (bytes deleted, duplicated,
//! replaced by tokens), then built end to end and, if it compiles, run for a few scans
//! on the interpreter. The ladder files (PLCopen XML) are mutated too, by lines and
//! attribute values as well as bytes, so that the reader, the rung checks and the IL
//! made from the rungs see broken XML, dangling and crossed connections, loops and
//! missing elements. A panic anywhere, or an internal compiler error (E9001: the front
//! end made invalid IR), fails the test and prints the input.

use plcc::driver::{build_sources, BuildOptions};
use plcc::targets;
use std::path::{Path, PathBuf};

#[allow(dead_code)]
#[path = "common/rng.rs"]
mod rng;
use rng::Rng;

const TOKENS: &[&str] = &[
    ";",
    ":=",
    "(",
    ")",
    "[",
    "]",
    ",",
    ".",
    "..",
    "#",
    "^",
    "END_IF",
    "IF",
    "THEN",
    "ELSE",
    "FOR",
    "TO",
    "BY",
    "DO",
    "END_FOR",
    "WHILE",
    "END_WHILE",
    "CASE",
    "OF",
    "END_CASE",
    "VAR",
    "END_VAR",
    "VAR_INPUT",
    "VAR_IN_OUT",
    "FUNCTION",
    "END_FUNCTION",
    "TON",
    "INT",
    "DINT",
    "REAL",
    "BOOL",
    "TIME",
    "ARRAY[1..3] OF INT",
    "T#5s",
    "16#FF",
    "1.5E3",
    "-",
    "*",
    "/",
    "MOD",
    "**",
    "AND",
    "NOT",
    "TRUE",
    "x",
    "i",
    "0",
    "1",
    "-2147483648",
    "32767",
    "RETURN",
    "EXIT",
    "(*",
    "*)",
    "'",
    "\"",
    "%IX0.0",
    "LREAL#1.0",
    "SINT#200",
];

/// Byte ranges of the words (identifiers, keywords, numbers) of a source.
fn words(v: &[u8]) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut i = 0;
    while i < v.len() {
        if v[i].is_ascii_alphanumeric() || v[i] == b'_' {
            let s = i;
            while i < v.len() && (v[i].is_ascii_alphanumeric() || v[i] == b'_' || v[i] == b'#') {
                i += 1;
            }
            out.push((s, i));
        } else {
            i += 1;
        }
    }
    out
}

fn mutate(src: &[u8], rng: &mut Rng) -> Vec<u8> {
    let mut v = src.to_vec();
    for _ in 0..1 + rng.index(4) {
        if v.is_empty() {
            break;
        }
        let at = rng.index(v.len());
        if rng.index(2) == 0 {
            // Swap one word for another word of the file: the syntax usually stays
            // valid, so the checks and the lowering get exercised.
            let ws = words(&v);
            if ws.len() >= 2 {
                let (a0, a1) = ws[rng.index(ws.len())];
                let (b0, b1) = ws[rng.index(ws.len())];
                let word: Vec<u8> = v[b0..b1].to_vec();
                v.splice(a0..a1, word);
                continue;
            }
        }
        match rng.index(4) {
            0 => {
                let n = rng.index(16).min(v.len() - at);
                v.drain(at..at + n);
            }
            1 => {
                let n = rng.index(24).min(v.len() - at);
                let chunk: Vec<u8> = v[at..at + n].to_vec();
                let to = rng.index(v.len());
                v.splice(to..to, chunk);
            }
            2 => {
                let t = TOKENS[rng.index(TOKENS.len())];
                let bytes = format!(" {t} ");
                v.splice(at..at, bytes.bytes());
            }
            _ => v[at] = (rng.next_u64() & 0xFF) as u8,
        }
    }
    v
}

fn sources() -> Vec<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut out = Vec::new();
    let mut stack = vec![root.join("tests/programs"), root.join("examples")];
    let corpus = root.join("../shared/corpus/st");
    if corpus.is_dir() {
        stack.push(corpus);
    }
    while let Some(d) = stack.pop() {
        let Ok(rd) = std::fs::read_dir(&d) else {
            continue;
        };
        for e in rd {
            let p = e.unwrap().path();
            if p.is_dir() {
                stack.push(p);
            } else if p.extension().is_some_and(|e| e == "st") {
                out.push(p);
            }
        }
    }
    out.sort();
    out
}

fn try_one(name: &str, bytes: Vec<u8>) {
    let b = match build_sources(vec![(name.to_string(), bytes)], &BuildOptions::default()) {
        Ok(b) => b,
        Err(_) => return,
    };
    let rendered = plcc::render::render(&b.sources, &b.diagnostics);
    assert!(
        !b.diagnostics
            .iter()
            .any(|d| d.code == plcc::driver::E_INTERNAL),
        "internal error:\n{rendered}"
    );
    let Some(module) = b.module else { return };
    if let Ok(mut m) = targets::machine("interp", &module) {
        m.set_watchdog(Some(std::time::Duration::from_millis(200)));
        if m.cold_start().is_ok() {
            for k in 0..3 {
                m.set_clock_us(k * 10_000);
                if m.scan().is_err() {
                    break;
                }
            }
        }
    }
}

#[test]
fn mutated_programs_never_panic() {
    let files = sources();
    let per_file: usize = std::env::var("PLCC_FUZZ_PER_FILE")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(4);
    let mut rng = Rng(0x9E37_79B9_7F4A_7C15);
    let mut failures = Vec::new();
    let mut n = 0;
    for f in &files {
        let src = std::fs::read(f).unwrap();
        for _ in 0..per_file {
            let m = mutate(&src, &mut rng);
            n += 1;
            let name = f.file_name().unwrap().to_string_lossy().into_owned();
            let input = m.clone();
            if std::panic::catch_unwind(|| try_one(&name, input)).is_err() {
                failures.push((name, String::from_utf8_lossy(&m).into_owned()));
            }
        }
    }
    println!("{n} mutated programs from {} files", files.len());
    for (name, text) in failures.iter().take(3) {
        println!("--- panic on a mutation of {name}:\n{text}\n");
    }
    assert!(
        failures.is_empty(),
        "{} mutated programs made plcc panic",
        failures.len()
    );
}

/// The ladder files of the project: the programs and the malformed ones.
fn ladder_sources() -> Vec<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut out = Vec::new();
    for dir in ["tests/programs/ld", "tests/bad"] {
        for e in std::fs::read_dir(root.join(dir)).unwrap() {
            let p = e.unwrap().path();
            if p.extension().is_some_and(|e| e == "xml") {
                out.push(p);
            }
        }
    }
    out.sort();
    out
}

/// A mutation of a PLCopen file: lines deleted, moved or swapped, numbers in
/// attribute values changed (localIds, connections, positions), or bytes as for ST.
fn mutate_xml(src: &[u8], rng: &mut Rng) -> Vec<u8> {
    let text = String::from_utf8_lossy(src).into_owned();
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    for _ in 0..1 + rng.index(3) {
        if lines.len() < 2 {
            break;
        }
        let i = rng.index(lines.len());
        match rng.index(5) {
            0 => {
                lines.remove(i);
            }
            1 => {
                let l = lines[i].clone();
                let j = rng.index(lines.len());
                lines.insert(j, l);
            }
            2 => {
                let j = rng.index(lines.len());
                lines.swap(i, j);
            }
            3 => {
                // A number inside quotes becomes another small number.
                let l = &lines[i];
                let quoted: Vec<usize> = l
                    .char_indices()
                    .filter(|&(k, c)| {
                        c == '"' && l[k + 1..].starts_with(|d: char| d.is_ascii_digit())
                    })
                    .map(|(k, _)| k + 1)
                    .collect();
                if !quoted.is_empty() {
                    let at = quoted[rng.index(quoted.len())];
                    let end = l[at..].find('"').map_or(l.len(), |e| at + e);
                    let n = rng.index(24).to_string();
                    lines[i] = format!("{}{n}{}", &l[..at], &l[end..]);
                }
            }
            _ => {
                let joined = lines.join("\n");
                let m = mutate(joined.as_bytes(), rng);
                lines = String::from_utf8_lossy(&m)
                    .lines()
                    .map(str::to_string)
                    .collect();
            }
        }
    }
    lines.join("\n").into_bytes()
}

#[test]
fn mutated_ladders_never_panic() {
    let files = ladder_sources();
    assert!(files.len() >= 30, "only {} ladder files", files.len());
    let per_file: usize = std::env::var("PLCC_FUZZ_PER_FILE")
        .ok()
        .and_then(|s| s.parse().ok())
        .map_or(40, |n: usize| n * 10);
    let mut rng = Rng(0x2545_F491_4F6C_DD1D);
    let mut failures = Vec::new();
    let mut n = 0;
    for f in &files {
        let src = std::fs::read(f).unwrap();
        for _ in 0..per_file {
            let m = mutate_xml(&src, &mut rng);
            n += 1;
            let name = f.file_name().unwrap().to_string_lossy().into_owned();
            let input = m.clone();
            if std::panic::catch_unwind(|| try_one(&name, input)).is_err() {
                failures.push((name, String::from_utf8_lossy(&m).into_owned()));
            }
        }
    }
    println!("{n} mutated ladders from {} files", files.len());
    for (name, text) in failures.iter().take(2) {
        println!("--- panic on a mutation of {name}:\n{text}\n");
    }
    assert!(
        failures.is_empty(),
        "{} mutated ladders made plcc panic",
        failures.len()
    );
}
