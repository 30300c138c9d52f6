//! plcc's PIC16F876A output against gputils and gpsim (through
//! `../shared/tools/pic16-run`): gpasm assembles plcc's `.asm` to the same words as
//! plcc's own assembler, and gpsim, running the program for [`SCANS`] scans (to the
//! last `plc_scan_end`), reaches each scan end at the same cycle as plcc's simulator
//! and ends with the same bytes in every program variable. RAM is filled with 0xA5
//! before reset in both, so a variable the program forgets to initialise would show.

use plcc_ir::backend::Options;
use plcc_ir::Module;
use plcc_pic16::asm::parse_hex;
use plcc_pic16::machine::PicMachine;
use std::path::Path;
use std::process::Command;

/// Scans both simulators run.
pub const SCANS: u32 = 5;

/// True if `tool` runs here.
pub fn have(tool: &str) -> bool {
    Command::new(tool)
        .arg("--version")
        .output()
        .map(|o| o.status.success() || !o.stdout.is_empty())
        .unwrap_or(false)
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

/// Checks one module (`stem` names its files in `dir`; `tools` holds `pic16-run`);
/// `Ok(false)` if it does not fit the chip.
pub fn check_module(module: &Module, stem: &str, tools: &Path, dir: &Path) -> Result<bool, String> {
    let build = match plcc_pic16::build(module, &Options::default()) {
        Ok(b) => b,
        Err(d)
            if d.iter()
                .any(|x| x.code.starts_with("E900") && x.code != "E9006") =>
        {
            return Ok(false)
        }
        Err(d) => return Err(format!("{d:?}")),
    };
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
    let mut m = PicMachine::new(module, build.clone());
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
