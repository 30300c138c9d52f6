//! Golden tests against the CPDev compiler's own output: the sample programs in
//! `../shared/reference/cpdev-samples` (relative to the workspace root), their code
//! images (`.xcp`) and listings (`.dcp` `MNEMONIC_MAP`). When `../shared` is absent the
//! tests print a notice and pass.

use plcc_vmasm::asm::{self, Scope, Symbols};
use plcc_vmasm::dcp_read::{self, Dcp};
use plcc_vmasm::disasm;
use plcc_vmasm::isa::Mode;
use std::collections::{HashMap, HashSet};
use std::path::{Path, PathBuf};

fn samples() -> Option<PathBuf> {
    let shared = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared");
    if !shared.is_dir() {
        eprintln!("skipping: ../shared not found");
        return None;
    }
    Some(shared.join("reference/cpdev-samples"))
}

const MODE_DIRS: [(Mode, &str); 3] = [
    (Mode::M16, "16bit"),
    (Mode::M32, "32bit"),
    (Mode::M32A, "32bitAlign"),
];

fn mode_dir(mode: Mode) -> &'static str {
    MODE_DIRS
        .iter()
        .find(|(m, _)| *m == mode)
        .map(|p| p.1)
        .unwrap()
}

/// Every sample: its `.dcp`, its `.xcp`, its mode.
fn sample_files(root: &Path) -> Vec<(PathBuf, PathBuf, Mode)> {
    fn walk(dir: &Path, mode: Mode, out: &mut Vec<(PathBuf, PathBuf, Mode)>) {
        let mut entries: Vec<PathBuf> = std::fs::read_dir(dir)
            .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
            .map(|e| e.unwrap().path())
            .collect();
        entries.sort();
        for p in entries {
            if p.is_dir() {
                walk(&p, mode, out);
            } else if p.extension().is_some_and(|x| x == "dcp") {
                let xcp = p.with_extension("xcp");
                assert!(xcp.is_file(), "{} has no .xcp beside it", p.display());
                out.push((p, xcp, mode));
            }
        }
    }
    let mut out = Vec::new();
    for (mode, d) in MODE_DIRS {
        walk(&root.join(d), mode, &mut out);
    }
    assert!(
        out.len() >= 24,
        "expected the 24 sample programs, found {}",
        out.len()
    );
    out
}

struct Loaded {
    dcp: Dcp,
    syms: Symbols,
}

fn load(path: &Path) -> Loaded {
    let dcp = Dcp::read(path).unwrap_or_else(|e| panic!("{e}"));
    let syms = Symbols::from_dcp(&dcp);
    Loaded { dcp, syms }
}

/// The local sample for a path of the CPDev repository named in golden-examples.tsv.
fn local_dcp(root: &Path, mode: Mode, orig: &str) -> PathBuf {
    let parts: Vec<&str> = orig.split('/').collect();
    let file = parts.last().unwrap();
    let dir = root.join(mode_dir(mode));
    // …/2021/mach16b/16b/cpyMem.dcp → 16bit/cpyMem_16b/cpyMem.dcp
    if let Some(i) = parts.iter().position(|p| p.starts_with("mach")) {
        let stem = file.trim_end_matches(".dcp");
        return dir.join(format!("{stem}_{}", parts[i + 1])).join(file);
    }
    let p = dir.join(file);
    if p.is_file() {
        return p;
    }
    dir.join(format!("{}@32ARM.dcp", file.trim_end_matches(".dcp")))
}

fn hex_bytes(s: &str) -> Vec<u8> {
    let d: Vec<u8> = s.bytes().filter(|b| !b.is_ascii_whitespace()).collect();
    d.chunks(2)
        .map(|c| u8::from_str_radix(std::str::from_utf8(c).unwrap(), 16).unwrap())
        .collect()
}

fn hex(b: &[u8]) -> String {
    b.iter().map(|x| format!("{x:02X}")).collect()
}

#[test]
fn golden_rows_assemble_to_their_bytes() {
    let Some(root) = samples() else { return };
    let tsv = std::fs::read_to_string(root.join("golden-examples.tsv")).unwrap();
    let mut cache: HashMap<PathBuf, (Loaded, Vec<u8>)> = HashMap::new();
    let (mut checked, mut failures) = (0, Vec::new());
    for line in tsv
        .lines()
        .filter(|l| !l.starts_with('#') && !l.trim().is_empty())
    {
        let cols: Vec<&str> = line.split('\t').collect();
        assert_eq!(cols.len(), 5, "bad row `{line}`");
        let mode = Mode::parse(cols[0]).unwrap_or_else(|| panic!("bad mode in `{line}`"));
        let path = local_dcp(&root, mode, cols[1]);
        let (l, xcp) = cache.entry(path.clone()).or_insert_with(|| {
            let x = std::fs::read(path.with_extension("xcp")).unwrap();
            (load(&path), x)
        });
        let addr = u32::from_str_radix(cols[2], 16).unwrap();
        let want = hex_bytes(cols[3]);
        // The tsv itself must agree with the image.
        assert_eq!(
            xcp.get(addr as usize..addr as usize + want.len()),
            Some(&want[..]),
            "row `{line}`"
        );
        let scope = l.syms.scope_at(addr);
        checked += 1;
        match asm::assemble_bytes(cols[4], mode, &l.syms.resolver(&scope)) {
            Ok(got) if got == want => {}
            Ok(got) => failures.push(format!("{line}\n    got {} in {scope:?}", hex(&got))),
            Err(e) => failures.push(format!("{line}\n    error: {e}")),
        }
    }
    println!(
        "golden-examples.tsv: {checked} rows checked, {} failed",
        failures.len()
    );
    assert!(checked >= 73, "only {checked} rows");
    assert!(
        failures.is_empty(),
        "failing rows:\n{}",
        failures.join("\n")
    );
}

#[test]
fn listings_reassemble_to_the_images() {
    let Some(root) = samples() else { return };
    let (mut lines, mut images, mut failures) = (0, 0, Vec::new());
    for (dcp_path, xcp_path, mode) in sample_files(&root) {
        let name = dcp_path.strip_prefix(&root).unwrap().display().to_string();
        let l = load(&dcp_path);
        let xcp = std::fs::read(&xcp_path).unwrap();
        assert_eq!(
            l.dcp.code_size,
            Some(xcp.len() as u32),
            "{name}: MEMORY_MAP code size"
        );
        assert_eq!(
            l.dcp.listing_end,
            Some(xcp.len() as u32),
            "{name}: listing end"
        );
        // The reader: every listed instruction's hex is the image's bytes there.
        for ll in l.dcp.listing.iter().filter(|ll| ll.label().is_none()) {
            let at = ll.addr as usize;
            assert_eq!(
                xcp.get(at..at + ll.bytes.len()),
                Some(&ll.bytes[..]),
                "{name}: hex of {:04x}",
                ll.addr
            );
        }
        let got = match asm::assemble_listing(&l.dcp.listing, mode, &l.syms) {
            Ok(g) => g,
            Err(e) => {
                failures.push(format!("{name}: {e}"));
                continue;
            }
        };
        images += 1;
        lines += l.dcp.listing.len();
        for (ll, &a) in l.dcp.listing.iter().zip(&got.addrs) {
            if ll.addr != a {
                failures.push(format!(
                    "{name}: `{}` listed at {:04x}, assembled at {a:04x}",
                    ll.text, ll.addr
                ));
            }
        }
        if got.code != xcp {
            let at = got
                .code
                .iter()
                .zip(&xcp)
                .position(|(a, b)| a != b)
                .unwrap_or(got.code.len().min(xcp.len()));
            let line = l
                .dcp
                .listing
                .iter()
                .rev()
                .find(|ll| ll.addr as usize <= at && ll.label().is_none());
            failures.push(format!(
                "{name}: the image differs from byte {at:04x} (line `{}`), lengths {} / {}",
                line.map_or("", |l| &l.text),
                got.code.len(),
                xcp.len()
            ));
        }
        let want_labels: Vec<(String, u32)> = l.syms.labels.clone();
        if got.labels != want_labels {
            failures.push(format!("{name}: label addresses differ"));
        }
    }
    println!(
        "listings: {lines} lines of {images} images re-assembled, {} failures",
        failures.len()
    );
    assert!(images >= 24);
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// The non-comment lines of the raw `MNEMONIC_MAP`, trailing blanks trimmed.
fn raw_listing(dcp_path: &Path) -> Vec<String> {
    let t = std::fs::read_to_string(dcp_path).unwrap();
    let a = t.find("<MNEMONIC_MAP").unwrap();
    let a = a + t[a..].find('>').unwrap() + 1;
    let b = t.find("</MNEMONIC_MAP>").unwrap();
    t[a..b]
        .lines()
        .map(|l| {
            l.trim_end()
                .replace("&lt;", "<")
                .replace("&gt;", ">")
                .replace("&amp;", "&")
        })
        .filter(|l| !l.is_empty() && !l.starts_with(';'))
        .collect()
}

/// The value an operand text stands for in a scope: a data address, a label's
/// address, or the text itself.
fn operand_value(syms: &Symbols, scope: &Scope, op: &str) -> String {
    if let Some(l) = op.strip_prefix(':') {
        return match syms.label(l) {
            Some(a) => format!("code {a:x}"),
            None => op.to_string(),
        };
    }
    match syms.data(scope, op) {
        Some(e) => format!("data {:x}", e.sym.addr),
        None => op.to_string(),
    }
}

#[test]
fn disassembler_matches_the_listings() {
    let Some(root) = samples() else { return };
    let (mut images, mut foreign, mut insts, mut ambiguous, mut failures) =
        (0, 0, 0, 0, Vec::new());
    for (dcp_path, xcp_path, mode) in sample_files(&root) {
        let name = dcp_path.strip_prefix(&root).unwrap().display().to_string();
        let xcp = std::fs::read(&xcp_path).unwrap();
        // Without names: decodes all of it, and re-encodes to the same bytes.
        let plain = match disasm::disassemble_lines(&xcp, mode, None) {
            Ok(p) => p,
            Err(e) => {
                failures.push(format!("{name}: {e}"));
                continue;
            }
        };
        let mut again = Vec::new();
        for p in &plain {
            p.inst.encode(mode, &mut again);
        }
        if again != xcp {
            failures.push(format!(
                "{name}: re-encoding the decoded instructions changes the image"
            ));
        }
        disasm::disassemble(&xcp, mode, None).unwrap();
        images += 1;
        // In the other modes the image need not decode, but must not panic.
        for other in Mode::ALL.into_iter().filter(|&m| m != mode) {
            let _ = disasm::disassemble(&xcp, other, None);
            foreign += 1;
        }

        // With the names of the .dcp: the listing's text.
        let l = load(&dcp_path);
        let named = disasm::disassemble_lines(&xcp, mode, Some(&l.syms)).unwrap();
        let mut ambiguous_at = HashSet::new();
        let listed: Vec<_> = l
            .dcp
            .listing
            .iter()
            .filter(|ll| ll.label().is_none())
            .collect();
        if listed.len() != named.len() {
            failures.push(format!(
                "{name}: {} instructions listed, {} decoded",
                listed.len(),
                named.len()
            ));
        }
        for (ours, theirs) in named.iter().zip(&listed) {
            insts += 1;
            let at = ours.addr;
            if ours.addr != theirs.addr || ours.hex != theirs.hex {
                failures.push(format!(
                    "{name} {at:04x}: `{}` vs listed {:04x} `{}`",
                    ours.hex, theirs.addr, theirs.hex
                ));
            }
            if ours.text == theirs.text {
                continue;
            }
            let (m1, o1) = asm::split_text(&ours.text).unwrap();
            let (m2, o2) = asm::split_text(&theirs.text).unwrap();
            let same = m1 == m2
                && o1.len() == o2.len()
                && o1.iter().zip(&o2).all(|(a, b)| {
                    a == b
                        || operand_value(&l.syms, &ours.scope, a)
                            == operand_value(&l.syms, &ours.scope, b)
                });
            if same {
                ambiguous_at.insert(at);
                println!(
                    "names of one address: {name} {at:04x}: `{}` vs `{}`",
                    ours.text, theirs.text
                );
                ambiguous += 1;
            } else {
                failures.push(format!(
                    "{name} {at:04x}: `{}` vs listed `{}`",
                    ours.text, theirs.text
                ));
            }
        }
        // The whole text: line for line the MNEMONIC_MAP, but for names of one address.
        let text = disasm::disassemble(&xcp, mode, Some(&l.syms)).unwrap();
        let ours: Vec<&str> = text.lines().map(str::trim_end).collect();
        let theirs = raw_listing(&dcp_path);
        if ours.len() != theirs.len() {
            failures.push(format!(
                "{name}: {} listing lines, {} disassembled",
                theirs.len(),
                ours.len()
            ));
        }
        for (a, b) in ours.iter().zip(&theirs) {
            if a != b {
                // Allowed only where the mnemonic differs by names of one address.
                let addr = u32::from_str_radix(&a[1..a.find('|').unwrap_or(1)], 16).ok();
                let known = addr.is_some_and(|x| ambiguous_at.contains(&x));
                let pa = a.split('|').take(2).collect::<Vec<_>>();
                let pb = b.split('|').take(2).collect::<Vec<_>>();
                if !(known && pa == pb) {
                    failures.push(format!("{name}: line\n  `{a}`\nvs\n  `{b}`"));
                }
            }
        }
    }
    println!(
        "disassembler: {images} images decoded and re-encoded ({foreign} tries in a foreign mode), {insts} instructions compared with their listings \
         ({ambiguous} equal only up to names of one address), {} failures",
        failures.len()
    );
    assert!(images >= 24);
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn find_var_reads_sample_variables() {
    let Some(root) = samples() else { return };
    let d = dcp_read::Dcp::read(&root.join("16bit/test1.dcp")).unwrap();
    let i = d.find_var("benchmark1.TASK.PERFECT_NUMBERS_01.I").unwrap();
    assert_eq!((i.addr, i.size, i.ty.as_str()), (4, 4, "DWORD"));
    assert_eq!(
        d.find_var("perfect_numbers_01.indx").map(|v| v.addr),
        Some(0x30)
    );
    let e = d.find_var("PERFECT_NUMBERS_01.P_NUMBERS[2]").unwrap();
    assert_eq!((e.addr, e.size, e.ty.as_str()), (0x18, 4, "DWORD"));
    let b = dcp_read::Dcp::read(&root.join("16bit/blink.dcp")).unwrap();
    assert_eq!(b.find_var("Blinking_light.LIGHT").map(|v| v.addr), Some(1));
    assert_eq!(b.find_var("TON2.PT").map(|v| v.addr), Some(0x24));
    assert_eq!(b.find_var("Q"), None, "ambiguous tails are not guessed");
    println!("find_var: 6 lookups checked");
}
