//! Speed of plcc's CPDev VM on the CPDev samples: test2 (primes) and cpyMem (BYTE,
//! WORD, DWORD, LWORD), 16-bit addressing.
//!
//! `cargo run --release -p plcc-vmasm --example vm_speed`
//!
//! With arguments, `vm_speed FILE.xcp…` times those images instead (16-bit, each with
//! the data size of its `.dcp`), on the VM with the `full` port's checks as plcc's
//! `Machine` runs it: `plcc --target vmasm prog.st -o prog.xcp` writes them.

use std::path::Path;
use std::time::{Duration, Instant};

use plcc_vmasm::isa::Mode;
use plcc_vmasm::port::Port;
use plcc_vmasm::vm::Vm;

const SAMPLES: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../../shared/reference/cpdev-samples"
);

/// Wall-clock time one measurement should take.
const TARGET: Duration = Duration::from_millis(300);

/// Measurements per program (the median is reported).
const RUNS: usize = 5;

/// The data size of a `.dcp` (`<MEMORY_MAP Type="data"><file Size="…">`).
fn data_size(dcp: &str) -> usize {
    let doc = roxmltree::Document::parse(dcp.trim_start_matches('\u{feff}')).expect("dcp parses");
    doc.descendants()
        .find(|n| n.has_tag_name("MEMORY_MAP") && n.attribute("Type") == Some("data"))
        .and_then(|n| n.children().find(|c| c.has_tag_name("file")))
        .and_then(|f| f.attribute("Size"))
        .and_then(|s| s.parse().ok())
        .expect("data MEMORY_MAP")
}

/// A VM after its first scan (the initialisers), its data filled with garbage first;
/// with the `full` port's checks if `checked`.
fn load(xcp: &Path, checked: bool) -> Vm {
    let code = std::fs::read(xcp).unwrap();
    let dcp = std::fs::read_to_string(xcp.with_extension("dcp")).unwrap();
    let mut vm = if checked {
        Vm::for_port(&code, data_size(&dcp), Mode::M16, Port::Full).unwrap()
    } else {
        Vm::new(&code, data_size(&dcp), Mode::M16).unwrap()
    };
    for (i, b) in vm.data_mut().iter_mut().enumerate() {
        *b = (i as u8).wrapping_mul(0x9D) | 1;
    }
    vm.run_cycle(u64::MAX).unwrap();
    vm
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let checked = !args.is_empty();
    let dir = Path::new(SAMPLES).join("16bit");
    if !checked && !dir.is_dir() {
        println!("skipping: ../shared not found");
        return;
    }
    let programs: Vec<(String, std::path::PathBuf)> = if checked {
        args.iter()
            .map(|a| {
                (
                    Path::new(a).file_stem().unwrap().to_string_lossy().into(),
                    a.into(),
                )
            })
            .collect()
    } else {
        [
            ("test2 (primes)", dir.join("test2.xcp")),
            ("cpyMem BYTE", dir.join("cpyMem_8b/cpyMem.xcp")),
            ("cpyMem WORD", dir.join("cpyMem_16b/cpyMem.xcp")),
            ("cpyMem DWORD", dir.join("cpyMem_32b/cpyMem.xcp")),
            ("cpyMem LWORD", dir.join("cpyMem_64b/cpyMem.xcp")),
        ]
        .into_iter()
        .map(|(n, p)| (n.to_string(), p))
        .collect()
    };
    println!(
        "Method: 16-bit images; after the first scan (initialisers), the wall clock over N \
         scans (N sized for ~{} ms); median of {RUNS} runs; ns/instruction = ns/scan / \
         instructions per scan.",
        TARGET.as_millis()
    );
    println!();
    println!(
        "{:<16} {:>12} {:>8} {:>14} {:>10}",
        "program", "instr/scan", "N", "ns/scan", "ns/instr"
    );
    for (name, xcp) in programs {
        let mut vm = load(&xcp, checked);
        let per_scan = vm.run_cycle(u64::MAX).unwrap();
        // Calibrate N.
        let t = Instant::now();
        let mut k = 0u64;
        while t.elapsed() < TARGET / 10 {
            vm.run_cycle(u64::MAX).unwrap();
            k += 1;
        }
        let n = (k * 10).max(1);
        let mut ns: Vec<f64> = (0..RUNS)
            .map(|_| {
                let before = vm.executed();
                let t = Instant::now();
                for _ in 0..n {
                    vm.run_cycle(u64::MAX).unwrap();
                }
                let e = t.elapsed();
                // The given images' scans may differ in length (timers); the samples'
                // do not.
                assert!(
                    checked || vm.executed() - before == n * per_scan,
                    "scans differ in length"
                );
                e.as_nanos() as f64 / n as f64
            })
            .collect();
        ns.sort_by(f64::total_cmp);
        let med = ns[RUNS / 2];
        println!(
            "{:<16} {:>12} {:>8} {:>14.0} {:>10.2}",
            name,
            per_scan,
            n,
            med,
            med / per_scan as f64
        );
    }
}
