//! The CPDev samples on the vmasm target: plcc compiles the ST sources the CPDev
//! compiler consumed (`.cst`) and runs them on its VM in every addressing mode, side by
//! side with the CPDev compiler's own code image of the same program on the same VM;
//! the values the samples' README gives must come out, and both images must agree on
//! every checked variable after every scan.
//!
//! Reads `../shared/reference/cpdev-samples`; skipped with a notice when it is absent.

use plcc::driver::{build_sources, BuildOptions};
use plcc_ir::backend::{Backend, Options};
use plcc_ir::machine::Machine;
use plcc_ir::Module;
use plcc_vmasm::dcp_read::{self, Dcp};
use plcc_vmasm::isa::Mode;
use plcc_vmasm::vm::{End, Vm};
use std::path::{Path, PathBuf};

#[path = "common/skip.rs"]
mod skip;

fn samples_dir() -> Option<PathBuf> {
    let d = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/reference/cpdev-samples");
    if d.is_dir() {
        Some(d)
    } else {
        skip::notice("../shared/reference/cpdev-samples not found; skipping");
        None
    }
}

/// The programs of the `.cst`'s task (its `(*$TASKS … *)` pragma) and the cycle.
fn task_of(cst: &str) -> (Vec<String>, u32) {
    let start = cst.find("(*$TASKS").expect("the .cst has a $TASKS pragma");
    let body = &cst[start..];
    let mut progs = Vec::new();
    let mut cycle = 0;
    for line in body.lines().skip(1) {
        let l = line.trim();
        if l.starts_with(".END_TASK") {
            break;
        }
        if let Some(p) = l.strip_prefix(".LOOPPARAM") {
            cycle = p
                .split_whitespace()
                .nth(1)
                .and_then(|c| c.parse().ok())
                .unwrap_or(0);
        } else if !l.is_empty() && !l.starts_with('.') {
            progs.push(l.to_string());
        }
    }
    (progs, cycle)
}

fn compile(files: &[PathBuf], programs: &[String]) -> Module {
    let texts = files
        .iter()
        .map(|f| {
            (
                f.display().to_string(),
                std::fs::read(f).expect("readable source"),
            )
        })
        .collect();
    let opts = BuildOptions {
        programs: programs.to_vec(),
        ..Default::default()
    };
    let b = build_sources(texts, &opts).expect("the sources build");
    let errors: Vec<String> = b
        .diagnostics
        .iter()
        .filter(|d| d.is_error())
        .map(|d| d.to_string())
        .collect();
    b.module
        .unwrap_or_else(|| panic!("{:?} does not compile: {}", files, errors.join("; ")))
}

/// The CPDev compiler's image of a sample, on plcc's VM.
struct Reference {
    vm: Vm,
    dcp: Dcp,
    started: bool,
}

impl Reference {
    fn new(xcp: &Path, mode: Mode) -> Reference {
        Reference::with_fill(xcp, mode, 0x5A)
    }

    /// The image with data memory first filled with `fill` (the VM does not zero it).
    fn with_fill(xcp: &Path, mode: Mode, fill: u8) -> Reference {
        let dcp = dcp_read::Dcp::read(&xcp.with_extension("dcp")).expect("the sample's dcp");
        let code = std::fs::read(xcp).expect("the sample's xcp");
        let size = dcp.data_size.expect("the dcp gives the data size") as usize;
        let mut vm = Vm::new(&code, size, mode).expect("the sample image loads");
        vm.data_mut().fill(fill);
        Reference {
            vm,
            dcp,
            started: false,
        }
    }

    /// One cycle; the first runs the initialisers too, from address 0.
    fn scan(&mut self, clock_ms: u32) {
        self.vm.set_clock_ms(clock_ms);
        let o = self.vm.run(None, 1 << 32).expect("the sample runs");
        assert_eq!(o.end, End::Trml);
        self.started = true;
    }

    fn read(&self, name: &str) -> u64 {
        let v = self
            .dcp
            .find_var(name)
            .unwrap_or_else(|| panic!("the sample's dcp has no `{name}`"));
        let a = v.addr as usize;
        self.vm.data()[a..a + v.size as usize]
            .iter()
            .rev()
            .fold(0u64, |acc, &b| acc << 8 | b as u64)
    }
}

/// plcc's image of the same sources.
fn plcc_machine(module: &Module, mode: Mode) -> Box<dyn Machine> {
    let opts = Options {
        settings: vec![("mode".into(), mode.name().into())],
        ..Default::default()
    };
    let mut m = plcc_vmasm::VmasmBackend::new()
        .machine(module, &opts)
        .expect("vmasm runs programs")
        .unwrap_or_else(|d| panic!("vmasm build: {d:?}"));
    m.cold_start().expect("cold start");
    m
}

/// Runs both images for `scans` cycles of `cycle_ms`, comparing `vars` (CPDev name,
/// plcc path) after every scan; returns plcc's machine and the values after each scan.
fn lockstep(
    reference: &mut Reference,
    ours: &mut dyn Machine,
    vars: &[(String, String)],
    scans: u32,
    cycle_ms: u32,
) -> Vec<Vec<u64>> {
    let mut history = Vec::new();
    for k in 0..scans {
        let t = k * cycle_ms;
        reference.scan(t);
        ours.set_clock_us(t as i64 * 1000);
        ours.scan().expect("plcc's image runs");
        let mut row = Vec::new();
        for (cp, path) in vars {
            let theirs = reference.read(cp);
            let mine = ours.read(path).expect("variable").bits;
            assert_eq!(
                mine, theirs,
                "scan {k} (t = {t} ms): `{path}` is {mine} in plcc's image, {theirs} in CPDev's"
            );
            row.push(mine);
        }
        history.push(row);
    }
    history
}

struct Case {
    /// Folder under the samples, and the image's file name there.
    dir: &'static str,
    xcp: &'static str,
    /// The `.cst`, relative to the samples.
    cst: &'static str,
    /// Instance name in CPDev's data map.
    instance: &'static str,
    /// Variables and the values the README gives after one scan.
    expect: Vec<(String, u64)>,
}

fn numbered(name: &str, values: &[u64]) -> Vec<(String, u64)> {
    values
        .iter()
        .enumerate()
        .map(|(i, v)| (format!("{name}[{i}]"), *v))
        .collect()
}

fn cases() -> Vec<Case> {
    let mut v = Vec::new();
    let test1 = || {
        let mut e = numbered("P_NUMBERS", &[6, 28, 496]);
        e.extend([("INDX".into(), 3), ("I".into(), 1001), ("S".into(), 1340)]);
        e
    };
    let test2 = || {
        let mut e = numbered("PRIME_NUMBERS", &[997, 991, 983, 977, 971]);
        e.push(("I".into(), 1001));
        e
    };
    let test3 = || {
        vec![
            ("ERR".into(), 0),
            ("I".into(), 1001),
            ("S".into(), 1000),
            ("F".into(), 1000),
            ("J".into(), 1),
        ]
    };
    let cpy = || {
        let mut e = numbered("BUF1", &[3; 20]);
        e.extend(numbered("BUF2", &[0; 20]));
        e
    };
    for (dir, suffix) in [("16bit", ""), ("32bit", ""), ("32bitAlign", "@32ARM")] {
        let t1: &'static str = Box::leak(format!("test1{suffix}.xcp").into_boxed_str());
        let t2: &'static str = Box::leak(format!("test2{suffix}.xcp").into_boxed_str());
        let t3: &'static str = Box::leak(format!("test3{suffix}.xcp").into_boxed_str());
        v.push(Case {
            dir,
            xcp: t1,
            cst: "16bit/test1.cst",
            instance: "PERFECT_NUMBERS",
            expect: test1(),
        });
        if dir != "32bit" {
            v.push(Case {
                dir,
                xcp: t2,
                cst: "16bit/test2.cst",
                instance: "PRIME_NUMBERS",
                expect: test2(),
            });
        }
        v.push(Case {
            dir,
            xcp: t3,
            cst: "16bit/test3.cst",
            instance: "BINARY_OP_TEST",
            expect: test3(),
        });
        for w in ["8b", "16b", "32b", "64b"] {
            let sub: &'static str = Box::leak(format!("{dir}/cpyMem_{w}").into_boxed_str());
            let cst: &'static str =
                Box::leak(format!("16bit/cpyMem_{w}/cpyMem.cst").into_boxed_str());
            v.push(Case {
                dir: sub,
                xcp: "cpyMem.xcp",
                cst,
                instance: "",
                expect: cpy(),
            });
        }
    }
    v
}

fn mode_of(dir: &str) -> Mode {
    if dir.starts_with("32bitAlign") {
        Mode::M32A
    } else if dir.starts_with("32bit") {
        Mode::M32
    } else {
        Mode::M16
    }
}

#[test]
fn cst_sources_give_the_readme_results_and_agree_with_cpdev_images() {
    let Some(root) = samples_dir() else { return };
    let mut checked = 0;
    for case in cases() {
        let cst_path = root.join(case.cst);
        let cst = std::fs::read_to_string(&cst_path).unwrap_or_else(|_| {
            String::from_utf8_lossy(&std::fs::read(&cst_path).expect("the .cst")).into_owned()
        });
        let (programs, cycle) = task_of(&cst);
        assert_eq!(programs.len(), 1, "{}: one program per task", case.cst);
        let prog = &programs[0];
        let instance = if case.instance.is_empty() {
            prog.as_str()
        } else {
            case.instance
        };
        let mode = mode_of(case.dir);
        let module = compile(std::slice::from_ref(&cst_path), &programs);
        let mut ours = plcc_machine(&module, mode);
        let mut reference = Reference::new(&root.join(case.dir).join(case.xcp), mode);
        let vars: Vec<(String, String)> = case
            .expect
            .iter()
            .map(|(n, _)| (format!("{instance}_01.{n}"), format!("{prog}.{n}")))
            .collect();
        let history = lockstep(&mut reference, ours.as_mut(), &vars, 2, cycle.max(1));
        for ((name, want), got) in case.expect.iter().zip(&history[0]) {
            assert_eq!(
                got,
                want,
                "{} in mode {}: {prog}.{name} after one scan",
                case.cst,
                mode.name()
            );
            checked += 1;
        }
    }
    println!("{checked} README values checked, every one also against CPDev's image");
    assert!(checked > 100);
}

#[test]
fn blink_turns_the_light_on_at_1_s_and_off_at_3_s_every_3_s() {
    let Some(root) = samples_dir() else { return };
    let cst = root.join("16bit/blink.cst");
    let tff = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/vmasm/cpdev_libs.st");
    let text = String::from_utf8_lossy(&std::fs::read(&cst).expect("blink.cst")).into_owned();
    let (programs, cycle) = task_of(&text);
    let module = compile(&[cst, tff], &programs);
    let mut ours = plcc_machine(&module, Mode::M16);
    let mut reference = Reference::new(&root.join("16bit/blink.xcp"), Mode::M16);
    let vars = vec![("LIGHT".to_string(), "$globals.LIGHT".to_string())];
    let scans = 10_000 / cycle;
    let history = lockstep(&mut reference, ours.as_mut(), &vars, scans, cycle);
    let mut edges = Vec::new();
    for k in 1..history.len() {
        if history[k][0] != history[k - 1][0] {
            edges.push((k as u32 * cycle, history[k][0] != 0));
        }
    }
    assert_eq!(edges[0], (1000, true), "edges: {edges:?}");
    assert_eq!(edges[1], (3000, false), "edges: {edges:?}");
    for w in edges.windows(3) {
        assert_eq!(w[2].0 - w[0].0, 3000, "a 3 s period: {edges:?}");
    }
    assert!(edges.len() >= 6, "{edges:?}");
}

/// ShipSim (a ship simulator: FBs, FUNCTIONs, REAL arithmetic and the math functions)
/// has no results in the README: plcc's image must agree with CPDev's on every
/// variable both describe, after every scan.
#[test]
fn shipsim_agrees_with_the_cpdev_image() {
    let Some(root) = samples_dir() else { return };
    for (image, mode) in [
        ("16bit/ShipSim.xcp", Mode::M16),
        ("32bitAlign/ShipSim@32ARM.xcp", Mode::M32A),
    ] {
        shipsim_in(&root, &root.join(image), mode);
    }
}

fn shipsim_in(root: &Path, image: &Path, mode: Mode) {
    let cst = root.join("16bit/ShipSim.cst");
    let text = String::from_utf8_lossy(&std::fs::read(&cst).expect("ShipSim.cst")).into_owned();
    let (programs, cycle) = task_of(&text);
    let module = compile(&[cst], &programs);
    let prog = &programs[0];
    let entry = module.program(prog).expect("the task's program");
    let mut ours = plcc_machine(&module, mode);
    let mut reference = Reference::new(image, mode);
    let vars: Vec<(String, String)> = plcc_ir::vars::variables(&module, entry.data)
        .into_iter()
        .filter_map(|v| {
            let tail = v.path.split_once('.')?.1.to_string();
            let cp = format!("{prog}_01.{tail}");
            reference.dcp.find_var(&cp).map(|_| (cp, v.path.clone()))
        })
        .collect();
    assert!(vars.len() > 50, "{} variables in common", vars.len());
    // CPDev's image leaves some variables to whatever memory held: a second run of it
    // from other garbage shows which; those are not compared.
    let mut other = Reference::with_fill(image, mode, 0xC3);
    let mut garbage = vec![false; vars.len()];
    let mut compared = 0;
    for k in 0..50u32 {
        let t = k * cycle;
        reference.scan(t);
        other.scan(t);
        ours.set_clock_us(t as i64 * 1000);
        ours.scan().expect("plcc's image runs");
        for (j, (cp, path)) in vars.iter().enumerate() {
            let theirs = reference.read(cp);
            garbage[j] |= theirs != other.read(cp);
            if garbage[j] {
                continue;
            }
            let mine = ours.read(path).expect("variable").bits;
            assert_eq!(mine, theirs, "scan {k} (t = {t} ms): `{path}` differs");
            compared += 1;
        }
    }
    let unset = garbage.iter().filter(|&&g| g).count();
    println!(
        "mode {}: {} variables, {compared} comparisons over 50 scans; {unset} left uninitialised by CPDev's image",
        mode.name(),
        vars.len()
    );
    assert!(
        unset < vars.len() / 2,
        "{unset} of {} uninitialised",
        vars.len()
    );
}
