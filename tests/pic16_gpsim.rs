//! plcc's PIC16F876A output checked with tools nobody here wrote (gputils and gpsim,
//! through `../shared/tools/pic16-run`), for every test program that fits the chip
//! (`tests/pic16/`, `tests/programs/`, `examples/`):
//!
//! - gpasm assembles plcc's `.asm` without an error, and its HEX holds the same
//!   words (configuration word included) as plcc's own assembler;
//! - gpsim, running the program for 5 scans (to the 5th `plc_scan_end`), ends with
//!   the same bytes in every program variable as plcc's simulator, and reaches each
//!   scan end at the same cycle.
//!
//! RAM is filled with 0xA5 before reset in both, so a variable the program forgets to
//! initialise would show. The test skips with a notice when gpasm, gpsim or
//! `../shared` is missing (CI installs the Debian packages).

#[path = "common/gpsim.rs"]
mod gpsim;

use plcc::driver::{build_sources, BuildOptions};
use std::path::{Path, PathBuf};

#[path = "common/skip.rs"]
mod skip;

/// Fewer programs than this means the discovery or the backend is broken.
const MIN_PROGRAMS: usize = 40;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn sources(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(rd) = std::fs::read_dir(dir) else {
        return;
    };
    for e in rd.flatten() {
        let p = e.path();
        if p.is_dir() {
            sources(&p, out);
        } else if p
            .extension()
            .is_some_and(|x| x == "st" || x == "il" || x == "stl")
        {
            out.push(p);
        }
    }
}

/// Files a scenario builds with its program (`# with:` lines), so a case compiles.
fn with_files(src: &Path) -> Vec<PathBuf> {
    let text = std::fs::read_to_string(src.with_extension("expect")).unwrap_or_default();
    let dir = src.parent().unwrap().to_path_buf();
    text.lines()
        .filter_map(|l| l.trim().strip_prefix("# with:"))
        .flat_map(|r| {
            r.split_whitespace()
                .map(|f| dir.join(f))
                .collect::<Vec<_>>()
        })
        .collect()
}

/// Checks one program; `Ok(false)` if it does not fit the chip.
fn check(src: &Path, tools: &Path, dir: &Path) -> Result<bool, String> {
    let mut files = vec![src.to_path_buf()];
    files.extend(with_files(src));
    let texts = files
        .iter()
        .map(|f| {
            Ok((
                f.display().to_string(),
                std::fs::read(f).map_err(|e| e.to_string())?,
            ))
        })
        .collect::<Result<Vec<_>, String>>()?;
    // Programs under a `codesys` directory are in the CODESYS dialect.
    let opts = BuildOptions {
        codesys: src.components().any(|c| c.as_os_str() == "codesys"),
        ..Default::default()
    };
    let b = build_sources(texts, &opts).map_err(|e| e.0)?;
    let Some(module) = b.module else {
        return Err("does not compile".into());
    };
    let stem = src.file_stem().unwrap().to_string_lossy().into_owned();
    gpsim::check_module(&module, &stem, tools, dir)
}

#[test]
fn gpasm_and_gpsim_agree_with_plcc() {
    let tools = root().join("../shared/tools");
    if !tools.join("pic16-run").exists() {
        skip::notice("../shared/tools/pic16-run is not there");
        return;
    }
    if !gpsim::have("gpasm") || !gpsim::have("gpsim") {
        skip::notice("gpasm or gpsim is not installed (apt-get install gputils gpsim)");
        return;
    }
    let mut progs = Vec::new();
    for d in ["tests/pic16", "tests/programs", "examples"] {
        sources(&root().join(d), &mut progs);
    }
    progs.sort();
    // Files built only as part of another program's case.
    let helpers: Vec<PathBuf> = progs.iter().flat_map(|p| with_files(p)).collect();
    progs.retain(|p| {
        !helpers.contains(p) && p.with_extension("expect").exists()
            || p.starts_with(root().join("tests/pic16"))
    });
    let dir = std::env::temp_dir().join(format!("plcc-gpsim-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let results: Vec<(PathBuf, Result<bool, String>)> = std::thread::scope(|s| {
        let chunks: Vec<&[PathBuf]> = progs.chunks(progs.len().div_ceil(2).max(1)).collect();
        let handles: Vec<_> = chunks
            .into_iter()
            .enumerate()
            .map(|(n, chunk)| {
                let (tools, dir) = (&tools, dir.join(n.to_string()));
                s.spawn(move || {
                    std::fs::create_dir_all(&dir).unwrap();
                    chunk
                        .iter()
                        .map(|p| (p.clone(), check(p, tools, &dir)))
                        .collect::<Vec<_>>()
                })
            })
            .collect();
        handles
            .into_iter()
            .flat_map(|h| h.join().unwrap())
            .collect()
    });
    let _ = std::fs::remove_dir_all(&dir);
    let checked = results
        .iter()
        .filter(|(_, r)| matches!(r, Ok(true)))
        .count();
    let failures: Vec<String> = results
        .iter()
        .filter_map(|(p, r)| r.as_ref().err().map(|e| format!("{}: {e}", p.display())))
        .collect();
    println!(
        "{checked} programs checked against gpasm and gpsim ({} do not fit the chip)",
        results
            .iter()
            .filter(|(_, r)| matches!(r, Ok(false)))
            .count()
    );
    assert!(
        failures.is_empty(),
        "{} programs disagree:\n{}",
        failures.len(),
        failures.join("\n")
    );
    assert!(checked >= MIN_PROGRAMS, "only {checked} programs checked");
}
