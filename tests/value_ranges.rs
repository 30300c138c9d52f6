//! `passes::ranges` (which the compiling targets run before their code), followed by
//! `passes::fill` (which the JIT runs after it), against the program it started from, on the reference interpreter: the random programs of the three
//! difftest generators (ST, PLCopen, charts) run side by side with and without the
//! pass, with the same random values written to *every* variable before every scan
//! (indexes and loop state included, so that removed checks meet indexes out of
//! range if they could), and must agree on every variable and the fault flag after
//! every scan. The interpreter stops on an index out of range at `elem_addr`, so a
//! check the pass removed wrongly is an error even where the value read would not
//! show.

#[path = "common/rng.rs"]
#[allow(dead_code)]
mod rng;

use plcc::difftest::{self, plcopen, sfc};
use plcc_ir::interp::Interp;
use plcc_ir::machine::Machine;
use plcc_ir::value::PlcValue;
use plcc_ir::{ElemType, Module};
use rng::Rng;

fn random_bits(rng: &mut Rng, ty: ElemType) -> u64 {
    match ty {
        ElemType::Bool => rng.below(2),
        ElemType::Real => (rng.below(20_000) as f32 / 8.0 - 1000.0).to_bits() as u64,
        ElemType::LReal => (rng.below(2_000_000) as f64 / 16.0 - 50_000.0).to_bits(),
        _ => match rng.below(5) {
            0 => rng.below(3),
            1 => rng.below(40),
            2 => (rng.below(40)).wrapping_neg(),
            3 => rng.next_u64(),
            _ => rng.below(20_000),
        },
    }
}

/// The module with the passes run on every function, and how many fills they made.
fn ranged(m: &Module) -> (Module, usize) {
    let mut r = m.clone();
    let mut fills = 0;
    for f in &mut r.funcs {
        plcc_ir::passes::ranges::run(f);
        plcc_ir::passes::fill::run(f, m);
        fills += f
            .inst_iter()
            .filter(|&(_, i)| {
                matches!(
                    f.inst(i),
                    plcc_ir::InstData::Intrinsic {
                        op: plcc_ir::Intrinsic::Fill,
                        ..
                    }
                )
            })
            .count();
    }
    plcc_ir::verify::verify_module(&r).unwrap_or_else(|e| panic!("{e:?}"));
    (r, fills)
}

/// Runs the module and its ranged copy side by side; the scans compared, and the
/// fills in the copy.
fn agree(m: &Module, scans: u32, seed: u64) -> Result<(u32, usize), String> {
    let (r, fills) = ranged(m);
    let mut a = Interp::new(m).map_err(|e| e.to_string())?;
    let mut b = Interp::new(&r).map_err(|e| e.to_string())?;
    let vars = plcc::scenario::all_variables(m);
    let mut rng = Rng::new(seed);
    a.cold_start().map_err(|e| format!("cold start: {e}"))?;
    b.cold_start()
        .map_err(|e| format!("cold start (ranged): {e}"))?;
    for s in 0..scans {
        for v in &vars {
            if rng.below(3) == 0 {
                let x = PlcValue::from_bits(v.elem, random_bits(&mut rng, v.elem));
                a.write(&v.path, x).map_err(|e| e.to_string())?;
                b.write(&v.path, x).map_err(|e| e.to_string())?;
            }
        }
        let t = s as i64 * 10_000;
        a.set_clock_us(t);
        b.set_clock_us(t);
        let ra = a.scan();
        let rb = b.scan();
        match (ra, rb) {
            (Ok(()), Ok(())) => {}
            // The program itself goes wrong with these values (a call too deep,
            // the step limit): both must.
            (Err(_), Err(_)) => return Ok((s, fills)),
            (x, y) => return Err(format!("scan {s}: original {x:?}, ranged {y:?}")),
        }
        for v in &vars {
            let (x, y) = (a.read(&v.path), b.read(&v.path));
            let (x, y) = (x.map_err(|e| e.to_string())?, y.map_err(|e| e.to_string())?);
            if !x.same(y) {
                return Err(format!("after scan {s}: {} is {x}, ranged {y}", v.path));
            }
        }
        if a.fault() != b.fault() {
            return Err(format!("after scan {s}: the fault flag"));
        }
    }
    Ok((scans, fills))
}

#[test]
fn value_ranges_keep_the_meaning_of_random_programs() {
    let mut failures = Vec::new();
    let mut scans = 0;
    let mut fills = 0;
    let mut check = |what: String, m: Result<Module, String>, seed: u64| {
        let Ok(m) = m else { return };
        match agree(&m, 8, seed) {
            Ok((n, f)) => {
                scans += n;
                fills += f;
            }
            Err(e) => failures.push(format!("{what}: {e}")),
        }
    };
    for seed in 1..=300 {
        let p = difftest::program(seed);
        let m = plcc::driver::build_sources(
            vec![("difftest.st".into(), p.to_st().into_bytes())],
            &Default::default(),
        )
        .map_err(|e| e.0)
        .and_then(|b| b.into_module());
        check(format!("ST seed {seed}"), m, seed);
    }
    for seed in 1..=150 {
        let p = plcopen::program(seed);
        let m = plcopen::compile(&p, plcc_frontend::plcopen::Profile::Iec);
        check(format!("PLCopen seed {seed}"), m, seed);
    }
    for seed in 1..=90 {
        let p = sfc::program(seed);
        let (profile, name) = sfc::PROFILES[seed as usize % 3];
        check(
            format!("chart seed {seed} --sfc {name}"),
            sfc::compile(&p, profile),
            seed,
        );
    }
    println!("{scans} scans compared, {fills} fills made");
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    assert!(scans > 4000, "only {scans} scans compared");
    // The generators' `Stmt::Fill` loops and the init functions' zeroing loops.
    assert!(fills > 200, "only {fills} fills made");
}
