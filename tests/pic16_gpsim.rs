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

use plcc::driver::{build_sources, BuildOptions};
use plcc_ir::backend::Options;
use plcc_pic16::asm::parse_hex;
use plcc_pic16::machine::PicMachine;
use std::path::{Path, PathBuf};
use std::process::Command;

const SCANS: u32 = 5;
/// Fewer programs than this means the discovery or the backend is broken.
const MIN_PROGRAMS: usize = 40;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn have(tool: &str) -> bool {
    Command::new(tool)
        .arg("--version")
        .output()
        .map(|o| o.status.success() || !o.stdout.is_empty())
        .unwrap_or(false)
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

/// The RAM bytes gpsim reports (`"0x0ab": 12` lines of pic16-run's JSON).
fn json_ram(json: &str) -> Vec<(u16, u8)> {
    json.lines()
        .filter_map(|l| {
            let l = l.trim().trim_end_matches(',');
            let (k, v) = l.split_once(':')?;
            let k = k.trim().trim_matches('"').strip_prefix("0x")?;
            Some((u16::from_str_radix(k, 16).ok()?, v.trim().parse().ok()?))
        })
        .collect()
}

fn json_cycles(json: &str) -> Vec<u64> {
    let Some(start) = json.find("\"break_cycles\"") else {
        return Vec::new();
    };
    let rest = &json[start..];
    let open = rest.find('[').unwrap();
    let close = rest.find(']').unwrap();
    rest[open + 1..close]
        .split(',')
        .filter_map(|x| x.trim().parse().ok())
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
    let build = match plcc_pic16::build(&module, &Options::default()) {
        Ok(b) => b,
        Err(d)
            if d.iter()
                .any(|x| x.code.starts_with("E900") && x.code != "E9006") =>
        {
            return Ok(false)
        }
        Err(d) => return Err(format!("{d:?}")),
    };
    let stem = src.file_stem().unwrap().to_string_lossy().into_owned();
    let asm = dir.join(format!("{stem}.asm"));
    std::fs::write(&asm, build.program.mpasm()).map_err(|e| e.to_string())?;
    // gpasm and the HEX.
    let out = Command::new("gpasm")
        .arg(&asm)
        .current_dir(dir)
        .output()
        .map_err(|e| e.to_string())?;
    if !out.status.success() {
        return Err(format!(
            "gpasm failed: {}",
            String::from_utf8_lossy(&out.stdout)
                .lines()
                .filter(|l| l.contains("Error"))
                .take(3)
                .collect::<Vec<_>>()
                .join("; ")
        ));
    }
    let hex = std::fs::read_to_string(asm.with_extension("hex")).map_err(|e| e.to_string())?;
    let (words, config) = parse_hex(&hex)?;
    let mut mine = build.image.words.clone();
    while mine.last() == Some(&0x3FFF) {
        mine.pop();
    }
    let mut theirs = words;
    while theirs.last() == Some(&0x3FFF) {
        theirs.pop();
    }
    if mine != theirs {
        let at = mine
            .iter()
            .zip(&theirs)
            .position(|(a, b)| a != b)
            .unwrap_or(0);
        return Err(format!(
            "gpasm's words differ from plcc's at 0x{at:04X} ({} vs {} words)",
            theirs.len(),
            mine.len()
        ));
    }
    if config != Some(build.image.config) {
        return Err(format!(
            "configuration word: gpasm {config:?}, plcc {:04X}",
            build.image.config
        ));
    }
    // gpsim against plcc's simulator.
    let json = Command::new(tools.join("pic16-run"))
        .arg(&asm)
        .args(["--break", "plc_scan_end", "--hits", &SCANS.to_string()])
        .args([
            "--ram-fill",
            "0xA5",
            "--dump",
            "0x20-0x7f,0xa0-0xef,0x110-0x16f,0x190-0x1ef",
        ])
        .args(["--json", "-q", "--cycles", "200M"])
        .output()
        .map_err(|e| e.to_string())?;
    let json = String::from_utf8_lossy(&json.stdout).into_owned();
    if !json.contains("\"status\": \"break\"") {
        return Err(format!(
            "gpsim did not reach plc_scan_end {SCANS} times: {}",
            &json[..json.len().min(200)]
        ));
    }
    let ram = json_ram(&json);
    let mut m = PicMachine::new(&module, build.clone());
    let cycles = m.run_free(SCANS).map_err(|e| e.to_string())?;
    let gp_cycles = json_cycles(&json);
    if cycles != gp_cycles {
        return Err(format!(
            "cycles at the scan ends: gpsim {gp_cycles:?}, plcc {cycles:?}"
        ));
    }
    let mut diffs = Vec::new();
    for (i, sym) in build.symbols.iter().enumerate() {
        for k in 0..sym.size as u16 {
            let a = sym.address as u16 + k;
            let Some(&(_, theirs)) = ram.iter().find(|(x, _)| *x == a) else {
                return Err(format!("gpsim gave no byte at 0x{a:03X}"));
            };
            let mine = m.sim().read(a);
            let (mine, theirs) = match build.bits[i] {
                Some(b) => (mine >> b & 1, theirs >> b & 1),
                None => (mine, theirs),
            };
            if mine != theirs {
                diffs.push(format!(
                    "{} byte {k}: gpsim {theirs:#04x} plcc {mine:#04x}",
                    sym.path
                ));
            }
        }
    }
    if diffs.is_empty() {
        Ok(true)
    } else {
        diffs.truncate(4);
        Err(diffs.join(", "))
    }
}

#[test]
fn gpasm_and_gpsim_agree_with_plcc() {
    let tools = root().join("../shared/tools");
    if !tools.join("pic16-run").exists() {
        println!("skipping: ../shared/tools/pic16-run is not there");
        return;
    }
    if !have("gpasm") || !have("gpsim") {
        println!("skipping: gpasm or gpsim is not installed (apt-get install gputils gpsim)");
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
