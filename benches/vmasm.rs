//! VM time per scan on the CPDev samples test2 (primes) and cpyMem, for the CPDev
//! compiler's images and plcc's, in ns per VM instruction and as a ratio to the JIT.
//!
//! `cargo bench --bench vmasm` prints the table (the method is printed with it).
//! Needs `../shared/reference/cpdev-samples`.

use plcc::driver::{build_sources, BuildOptions};
use plcc::targets;
use plcc_ir::backend::Options;
use plcc_ir::Module;
use plcc_vmasm::isa::Mode;
use plcc_vmasm::vm::{End, Vm};
use std::path::Path;
use std::time::Instant;

const RUNS: usize = 5;

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(|a, b| a.partial_cmp(b).unwrap());
    v[v.len() / 2]
}

fn compile(cst: &Path, program: &str) -> Module {
    let texts = vec![(cst.display().to_string(), std::fs::read(cst).unwrap())];
    let opts = BuildOptions {
        programs: vec![program.to_string()],
        ..Default::default()
    };
    build_sources(texts, &opts)
        .unwrap()
        .module
        .unwrap_or_else(|| panic!("{} does not compile", cst.display()))
}

/// ns per scan and instructions per scan of an image on plcc's VM, from the scan
/// loop's top (`start` runs first: cold start, or the first cycle).
fn time_vm(code: &[u8], data: usize, start: Option<u32>, scans: u32) -> (f64, u64) {
    let mut times = Vec::new();
    let mut per_scan = 0;
    for _ in 0..RUNS {
        let mut vm = Vm::new(code, data, Mode::M16).unwrap();
        vm.data_mut().fill(0);
        let first = vm.run(start, u64::MAX).unwrap();
        assert!(matches!(first.end, End::StopAt | End::Trml));
        let t = Instant::now();
        let mut n = 0;
        for k in 0..scans {
            vm.set_clock_ms(k * 10);
            let o = vm.run(None, u64::MAX).unwrap();
            assert_eq!(o.end, End::Trml);
            n += o.executed;
        }
        times.push(t.elapsed().as_nanos() as f64 / scans as f64);
        per_scan = n / scans as u64;
    }
    (median(times), per_scan)
}

fn time_jit(module: &Module, scans: u32) -> f64 {
    let mut times = Vec::new();
    for _ in 0..RUNS {
        let mut m = targets::machine("host", module).unwrap();
        m.cold_start().unwrap();
        let t = Instant::now();
        for k in 0..scans {
            m.set_clock_us(k as i64 * 10_000);
            m.scan().unwrap();
        }
        times.push(t.elapsed().as_nanos() as f64 / scans as f64);
    }
    median(times)
}

fn main() {
    let root =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/reference/cpdev-samples/16bit");
    if !root.is_dir() {
        eprintln!("notice: ../shared/reference/cpdev-samples not found; nothing to measure");
        return;
    }
    println!(
        "VM and JIT time per scan (release build; median of {RUNS} runs of N scans, wall clock;"
    );
    println!("16-bit images; the VM counts the instructions it executes)\n");
    println!(
        "{:<14} {:>5} | {:>9} {:>11} {:>8} | {:>9} {:>11} {:>8} | {:>11} {:>9} {:>9}",
        "program",
        "N",
        "CPDev ins",
        "ns/scan",
        "ns/ins",
        "plcc ins",
        "ns/scan",
        "ns/ins",
        "JIT ns/scan",
        "CPDev/JIT",
        "plcc/JIT"
    );
    let cases = [
        (
            "test2 primes",
            "test2.cst",
            "test2.xcp",
            "PRIME_NUMBERS",
            20,
        ),
        (
            "cpyMem 8b",
            "cpyMem_8b/cpyMem.cst",
            "cpyMem_8b/cpyMem.xcp",
            "CPYMEM_BYTE",
            20000,
        ),
        (
            "cpyMem 16b",
            "cpyMem_16b/cpyMem.cst",
            "cpyMem_16b/cpyMem.xcp",
            "CPYMEM_WORD",
            20000,
        ),
        (
            "cpyMem 32b",
            "cpyMem_32b/cpyMem.cst",
            "cpyMem_32b/cpyMem.xcp",
            "CPYMEM_DWORD",
            20000,
        ),
        (
            "cpyMem 64b",
            "cpyMem_64b/cpyMem.cst",
            "cpyMem_64b/cpyMem.xcp",
            "CPYMEM_LWORD",
            20000,
        ),
    ];
    for (name, cst, xcp, program, scans) in cases {
        let dcp = plcc_vmasm::dcp_read::Dcp::read(&root.join(xcp).with_extension("dcp")).unwrap();
        let theirs = std::fs::read(root.join(xcp)).unwrap();
        let (c_ns, c_ins) = time_vm(&theirs, dcp.data_size.unwrap() as usize, None, scans);
        let module = compile(&root.join(cst), program);
        let build = plcc_vmasm::build::build(&module, &Options::default()).unwrap();
        let (p_ns, p_ins) = time_vm(
            &build.image.code,
            build.data_size as usize,
            Some(build.loop_addr),
            scans,
        );
        let jit = time_jit(&module, scans);
        println!(
            "{:<14} {:>5} | {:>9} {:>11.0} {:>8.2} | {:>9} {:>11.0} {:>8.2} | {:>11.0} {:>8.1}x {:>8.1}x",
            name,
            scans,
            c_ins,
            c_ns,
            c_ns / c_ins as f64,
            p_ins,
            p_ns,
            p_ns / p_ins as f64,
            jit,
            c_ns / jit,
            p_ns / jit
        );
    }
}
