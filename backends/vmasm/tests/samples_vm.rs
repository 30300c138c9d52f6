//! Runs the CPDev sample programs (`shared/reference/cpdev-samples`, compiled by the
//! CPDev compiler) on plcc's VM and checks the results the samples' README gives.
//! Without `../shared` the tests print "skipping: ../shared not found" and pass.

use std::path::{Path, PathBuf};

use plcc_vmasm::isa::Mode;
use plcc_vmasm::vm::{status, End, Vm};

const SHARED: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../../shared");

/// Instructions one scan may take (test1 needs about 10 million).
const BUDGET: u64 = 200_000_000;

/// The samples directory, or None (with the skip message) when `../shared` is absent.
fn samples_dir() -> Option<PathBuf> {
    let p = Path::new(SHARED).join("reference/cpdev-samples");
    if p.is_dir() {
        Some(p)
    } else {
        println!("skipping: ../shared not found");
        None
    }
}

/// A compiled sample: code image, mode and description.
struct Sample {
    /// `16bit/test1`, `32bitAlign/cpyMem_8b/cpyMem`, … (for messages).
    name: String,
    /// The program: `test1`, `cpyMem`, `blink`, … (the file stem up to `@`).
    program: String,
    mode: Mode,
    code: Vec<u8>,
    dcp: String,
}

/// Every sample `.xcp` with its `.dcp` under the three mode folders.
fn samples(dir: &Path) -> Vec<Sample> {
    fn walk(d: &Path, out: &mut Vec<PathBuf>) {
        let mut es: Vec<_> = std::fs::read_dir(d)
            .unwrap()
            .map(|e| e.unwrap().path())
            .collect();
        es.sort();
        for p in es {
            if p.is_dir() {
                walk(&p, out);
            } else if p.extension().is_some_and(|x| x == "xcp") {
                out.push(p);
            }
        }
    }
    let mut out = Vec::new();
    for (folder, mode) in [
        ("16bit", Mode::M16),
        ("32bit", Mode::M32),
        ("32bitAlign", Mode::M32A),
    ] {
        let mut files = Vec::new();
        walk(&dir.join(folder), &mut files);
        for xcp in files {
            let stem = xcp.file_stem().unwrap().to_string_lossy().into_owned();
            let rel = xcp.strip_prefix(dir).unwrap().with_extension("");
            out.push(Sample {
                name: rel.to_string_lossy().into_owned(),
                program: stem.split('@').next().unwrap().to_string(),
                mode,
                code: std::fs::read(&xcp).unwrap(),
                dcp: std::fs::read_to_string(xcp.with_extension("dcp")).unwrap(),
            });
        }
    }
    out
}

/// A variable of the description.
#[derive(Debug)]
struct Var {
    addr: usize,
    size: usize,
    /// Element size for arrays, else `size`.
    elem: usize,
}

/// What the tests need of a `.dcp`.
struct Desc {
    data_size: usize,
    cycle_ms: u32,
    doc: String,
}

impl Desc {
    fn new(dcp: &str) -> Desc {
        let doc = dcp.trim_start_matches('\u{feff}').to_string();
        let x = roxmltree::Document::parse(&doc).expect("dcp parses");
        let data_size = x
            .descendants()
            .find(|n| n.has_tag_name("MEMORY_MAP") && n.attribute("Type") == Some("data"))
            .and_then(|n| n.children().find(|c| c.has_tag_name("file")))
            .and_then(|f| f.attribute("Size"))
            .expect("data MEMORY_MAP")
            .parse()
            .unwrap();
        let task = x
            .descendants()
            .find(|n| n.has_tag_name("TASK"))
            .expect("a TASK");
        let cycle: u32 = task.attribute("Cycle").unwrap().parse().unwrap();
        let cycle_ms = match task.attribute("CycleUnit") {
            Some("s") => cycle * 1000,
            _ => cycle,
        };
        Desc {
            data_size,
            cycle_ms,
            doc,
        }
    }

    /// The variable with local name `name` (a `<GLOBAL><VAR>` or a `<DATA_MAP>` object
    /// with an absolute address; the shortest qualified name wins).
    fn var(&self, name: &str) -> Var {
        let x = roxmltree::Document::parse(&self.doc).unwrap();
        let hex = |s: &str| usize::from_str_radix(s, 16).ok();
        let mut best: Option<(usize, Var)> = None;
        for n in x.descendants() {
            if !n
                .attribute("LName")
                .is_some_and(|l| l.eq_ignore_ascii_case(name))
            {
                continue;
            }
            let addr = match (
                n.tag_name().name(),
                n.attribute("CAddr"),
                n.attribute("Addr"),
            ) {
                ("OBJ", Some(a), _) => hex(a),
                ("VAR", _, Some(a)) if n.parent().is_some_and(|p| p.has_tag_name("GLOBAL")) => {
                    hex(a)
                }
                _ => None,
            };
            let Some(addr) = addr else { continue };
            let size: usize = n.attribute("Size").unwrap().parse().unwrap();
            let count: usize = n
                .descendants()
                .filter(|l| l.has_tag_name("LEVEL"))
                .map(|l| {
                    let b = |a| l.attribute(a).unwrap().parse::<i64>().unwrap();
                    (b("UpBound") - b("LoBound") + 1) as usize
                })
                .product();
            let len = n.attribute("PName").map_or(0, str::len);
            if best.as_ref().is_none_or(|(l, _)| len < *l) {
                best = Some((
                    len,
                    Var {
                        addr,
                        size,
                        elem: size / count.max(1),
                    },
                ));
            }
        }
        best.unwrap_or_else(|| panic!("no variable {name}")).1
    }
}

/// Garbage that is never zero, so that programs must initialise what they read.
fn garbage(m: &mut [u8]) {
    for (i, b) in m.iter_mut().enumerate() {
        *b = (i as u8).wrapping_mul(0x9D).wrapping_add(0x5B) | 0x01;
    }
}

/// A VM for a sample, its data filled with garbage and its task cycle set.
fn load(s: &Sample) -> (Vm, Desc) {
    let d = Desc::new(&s.dcp);
    let mut vm =
        Vm::new(&s.code, d.data_size, s.mode).unwrap_or_else(|e| panic!("{}: {e}", s.name));
    garbage(vm.data_mut());
    vm.set_task_cycle_ms(d.cycle_ms);
    (vm, d)
}

/// Element `i` of `v` as an unsigned little-endian integer.
fn elem(vm: &Vm, v: &Var, i: usize) -> u64 {
    assert!(i * v.elem < v.size, "index {i} out of {v:?}");
    let a = v.addr + i * v.elem;
    vm.data()[a..a + v.elem]
        .iter()
        .rev()
        .fold(0, |acc, &b| acc << 8 | b as u64)
}

fn value(vm: &Vm, d: &Desc, name: &str) -> u64 {
    elem(vm, &d.var(name), 0)
}

/// Runs the first scan (clock 0) of every sample of `program` and calls `check`;
/// returns how many ran. Fails on a VM error or when no sample of `program` exists.
fn first_scan(program: &str, check: impl Fn(&Sample, &Vm, &Desc)) -> usize {
    let Some(dir) = samples_dir() else { return 0 };
    let mut n = 0;
    for s in samples(&dir).iter().filter(|s| s.program == program) {
        let (mut vm, d) = load(s);
        vm.set_clock_ms(0);
        let o = vm
            .run(None, BUDGET)
            .unwrap_or_else(|e| panic!("{}: {e}", s.name));
        assert_eq!(o.end, End::Trml, "{}: the first scan did not end", s.name);
        assert_eq!(
            vm.status() & status::ARRAYBOUND,
            0,
            "{}: ARRAYBOUND",
            s.name
        );
        check(s, &vm, &d);
        n += 1;
    }
    assert!(n > 0, "no sample {program}");
    n
}

#[test]
fn test1_perfect_numbers() {
    first_scan("test1", |s, vm, d| {
        let p = d.var("P_NUMBERS");
        let got: Vec<u64> = (0..3).map(|i| elem(vm, &p, i)).collect();
        assert_eq!(got, [6, 28, 496], "{}: P_NUMBERS", s.name);
        assert_eq!(value(vm, d, "INDX"), 3, "{}: INDX", s.name);
        assert_eq!(value(vm, d, "I"), 1001, "{}: I", s.name);
        assert_eq!(value(vm, d, "S"), 1340, "{}: S", s.name);
    });
}

#[test]
fn test2_primes() {
    first_scan("test2", |s, vm, d| {
        let p = d.var("PRIME_NUMBERS");
        let got: Vec<u64> = (0..5).map(|i| elem(vm, &p, i)).collect();
        assert_eq!(got, [997, 991, 983, 977, 971], "{}: PRIME_NUMBERS", s.name);
        assert_eq!(value(vm, d, "I"), 1001, "{}: I", s.name);
    });
}

#[test]
fn test3_binary_operations() {
    first_scan("test3", |s, vm, d| {
        assert_eq!(value(vm, d, "ERR"), 0, "{}: ERR", s.name);
        assert_eq!(value(vm, d, "I"), 1001, "{}: I", s.name);
        assert_eq!(value(vm, d, "S"), 1000, "{}: S", s.name);
        assert_eq!(value(vm, d, "F"), 1000, "{}: F", s.name);
        assert_eq!(value(vm, d, "J"), 1, "{}: J", s.name);
    });
}

#[test]
fn cpymem_every_width_and_mode() {
    let n = first_scan("cpyMem", |s, vm, d| {
        let (b1, b2) = (d.var("BUF1"), d.var("BUF2"));
        assert_eq!(b1.size / b1.elem, 20, "{}", s.name);
        for i in 0..20 {
            assert_eq!(elem(vm, &b1, i), 3, "{}: BUF1[{i}]", s.name);
            assert_eq!(elem(vm, &b2, i), 0, "{}: BUF2[{i}]", s.name);
        }
    });
    if samples_dir().is_some() {
        assert_eq!(n, 12, "cpyMem samples: 4 widths × 3 modes");
    }
}

#[test]
fn blink_period() {
    let Some(dir) = samples_dir() else { return };
    let all = samples(&dir);
    let s = all
        .iter()
        .find(|s| s.program == "blink")
        .expect("blink sample");
    let (mut vm, d) = load(s);
    let light = d.var("LIGHT");
    assert_eq!(d.cycle_ms, 50);
    let (mut on, mut off) = (Vec::new(), Vec::new());
    let mut prev = false;
    for k in 0..200u32 {
        let t = k * d.cycle_ms;
        vm.set_clock_ms(t);
        vm.run_cycle(1_000_000)
            .unwrap_or_else(|e| panic!("scan {k}: {e}"));
        let l = elem(&vm, &light, 0);
        assert!(l <= 1, "LIGHT = {l}");
        let l = l == 1;
        if l && !prev {
            on.push(t);
        }
        if !l && prev {
            off.push(t);
        }
        prev = l;
    }
    // TRUE at 1 s, FALSE at 3 s, with a 3 s period (10 s simulated).
    assert_eq!(on, [1000, 4000, 7000]);
    assert_eq!(off, [3000, 6000, 9000]);
}

/// Runs `program`'s samples for `cycles` scans, the clock advancing by the task cycle.
fn run_cycles(program: &str, cycles: u32) {
    let Some(dir) = samples_dir() else { return };
    let all = samples(&dir);
    let mut n = 0;
    for s in all.iter().filter(|s| s.program == program) {
        let (mut vm, d) = load(s);
        for k in 0..cycles {
            vm.set_clock_ms(k * d.cycle_ms);
            vm.run_cycle(BUDGET)
                .unwrap_or_else(|e| panic!("{}, scan {k}: {e}", s.name));
        }
        assert!(vm.executed() > cycles as u64, "{}", s.name);
        n += 1;
    }
    assert!(n > 0, "no sample {program}");
}

#[test]
fn shipsim_runs() {
    run_cycles("ShipSim", 150);
}

#[test]
fn wejestst_runs() {
    run_cycles("WeJeStSt", 150);
}

/// Every instruction of the listings is reachable from address 0, so the VM decoded it.
#[test]
fn listings_are_decoded() {
    let Some(dir) = samples_dir() else { return };
    let all = samples(&dir);
    assert!(all.len() >= 20, "only {} samples", all.len());
    for s in &all {
        let (vm, d) = load(s);
        let x = roxmltree::Document::parse(&d.doc).unwrap();
        let listing = x
            .descendants()
            .find(|n| n.has_tag_name("MNEMONIC_MAP"))
            .and_then(|n| n.text())
            .unwrap_or("");
        let mut count = 0;
        for line in listing.lines() {
            // `:0010| 1C15 0000 02 0500 | $VMSYS.MCD …`: an instruction has bytes.
            let f: Vec<&str> = line.split('|').collect();
            if f.len() < 3 || !f[0].starts_with(':') || !f[2].trim_start().starts_with('$') {
                continue;
            }
            let pc = u32::from_str_radix(f[0][1..].trim(), 16).unwrap();
            assert!(vm.is_instruction(pc), "{}: {pc:04x} not decoded", s.name);
            count += 1;
        }
        assert!(count > 10, "{}: {count} listing instructions", s.name);
    }
}

/// Runs in small budgets (which end superinstruction sequences early and step through
/// the last instructions one by one) give the same states as whole scans.
#[test]
fn budgeted_runs_match_whole_scans() {
    let Some(dir) = samples_dir() else { return };
    let all = samples(&dir);
    let mut n = 0;
    for s in all
        .iter()
        .filter(|s| matches!(s.program.as_str(), "cpyMem" | "ShipSim" | "blink"))
    {
        let (mut whole, d) = load(s);
        let (mut parts, _) = load(s);
        let budgets = [1u64, 2, 3, 5, 8, 13];
        let mut b = 0;
        for k in 0..3u32 {
            whole.set_clock_ms(k * d.cycle_ms);
            parts.set_clock_ms(k * d.cycle_ms);
            let want = whole.run_cycle(BUDGET).unwrap();
            let mut got = 0;
            loop {
                let o = parts.run(None, budgets[b % budgets.len()]).unwrap();
                b += 1;
                got += o.executed;
                if o.end == End::Trml {
                    break;
                }
                assert_eq!(o.executed, budgets[(b - 1) % budgets.len()], "{}", s.name);
            }
            assert_eq!(got, want, "{}: scan {k} instruction count", s.name);
            assert_eq!(parts.pc(), whole.pc(), "{}: scan {k}", s.name);
            assert!(
                parts.data() == whole.data(),
                "{}: scan {k} data differs",
                s.name
            );
        }
        n += 1;
    }
    assert!(n >= 14, "{n} samples");
}
