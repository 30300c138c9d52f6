//! Two builds of one program run side by side on the same machine, with the same
//! random writes before every scan, compared variable by variable after every scan.
//!
//! Used where a program exists in two forms that must mean the same: a PLCopen XML
//! file and the ST its editor made of it, a ladder and its IL twin.

use plcc_ir::value::PlcValue;
use plcc_ir::{ElemType, Module};

use crate::rng::Rng;

/// Diagnostic codes of a target that cannot hold a program (too big, a type it does
/// not have): the machine is left out, not failed.
pub const UNFIT: [&str; 8] = [
    "E9001", "E9002", "E9003", "E9004", "E9101", "E9102", "E9207", "E9208",
];

fn random_bits(rng: &mut Rng, ty: ElemType) -> u64 {
    match ty {
        ElemType::Bool => rng.below(2),
        ElemType::Real => (rng.below(20_000) as f32 / 8.0 - 1000.0).to_bits() as u64,
        ElemType::LReal => (rng.below(2_000_000) as f64 / 16.0 - 50_000.0).to_bits(),
        _ => match rng.below(4) {
            0 => rng.below(3),
            1 => rng.below(200),
            2 => rng.next_u64(),
            _ => rng.below(20_000),
        },
    }
}

/// What a comparison found.
pub struct Outcome {
    /// Variables compared after every scan.
    pub compared: usize,
    /// Variables written at random.
    pub inputs: usize,
}

/// Runs `a` and `b` on `target` for `scans` scans of `cycle_ms`. Before every scan,
/// each variable that `writable` accepts and both builds have is written, with
/// probability 1/4, with the same random value on both; after every scan every
/// variable both have (and `compare` accepts) must be equal. `Err` says where they
/// first differ; `Ok(None)` if the target cannot hold one of them.
#[allow(clippy::too_many_arguments)]
pub fn run(
    a: &Module,
    b: &Module,
    target: &str,
    scans: u32,
    cycle_ms: u32,
    seed: u64,
    writable: &dyn Fn(&str) -> bool,
    compare: &dyn Fn(&str) -> bool,
) -> Result<Option<Outcome>, String> {
    let machine = |m: &Module, which: &str| match plcc::targets::machine_spec(target, m) {
        Ok(x) => Ok(Some(x)),
        Err(d) if d.iter().any(|x| UNFIT.contains(&x.code)) => Ok(None),
        Err(d) => Err(format!(
            "{target} cannot build {which}: {}",
            d.iter()
                .map(|x| x.to_string())
                .collect::<Vec<_>>()
                .join("; ")
        )),
    };
    let (Some(mut ma), Some(mut mb)) = (machine(a, "the first")?, machine(b, "the second")?) else {
        return Ok(None);
    };
    let va = plcc::scenario::all_variables(a);
    let vb = plcc::scenario::all_variables(b);
    let shared: Vec<(String, ElemType)> = va
        .iter()
        .filter(|x| {
            vb.iter()
                .any(|y| y.path.eq_ignore_ascii_case(&x.path) && y.elem == x.elem)
        })
        .map(|x| (x.path.clone(), x.elem))
        .collect();
    let path_b = |p: &str| {
        vb.iter()
            .find(|y| y.path.eq_ignore_ascii_case(p))
            .map(|y| y.path.clone())
            .expect("shared")
    };
    let inputs: Vec<&(String, ElemType)> = shared.iter().filter(|(p, _)| writable(p)).collect();
    let checked: Vec<&(String, ElemType)> = shared.iter().filter(|(p, _)| compare(p)).collect();
    ma.cold_start().map_err(|e| format!("cold start: {e}"))?;
    mb.cold_start().map_err(|e| format!("cold start: {e}"))?;
    let mut rng = Rng(seed | 1);
    for s in 0..scans {
        for (p, ty) in &inputs {
            if rng.below(4) != 0 {
                continue;
            }
            let v = PlcValue::from_bits(*ty, random_bits(&mut rng, *ty));
            ma.write(p, v).map_err(|e| format!("write {p}: {e}"))?;
            mb.write(&path_b(p), v)
                .map_err(|e| format!("write {p}: {e}"))?;
        }
        let t = s as i64 * cycle_ms as i64 * 1000;
        ma.set_clock_us(t);
        mb.set_clock_us(t);
        ma.scan().map_err(|e| format!("scan {s}: {e}"))?;
        mb.scan().map_err(|e| format!("scan {s}: {e}"))?;
        for (p, _) in &checked {
            let x = ma.read(p).map_err(|e| format!("read {p}: {e}"))?;
            let y = mb.read(&path_b(p)).map_err(|e| format!("read {p}: {e}"))?;
            if !x.same(y) {
                return Err(format!(
                    "after scan {s}: {p} is {x} in the first, {y} in the second"
                ));
            }
        }
    }
    Ok(Some(Outcome {
        compared: checked.len(),
        inputs: inputs.len(),
    }))
}
