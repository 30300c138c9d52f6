//! IR modules (hand-written in the text form) run on every machine of the target
//! registry beside the interpreter, with scripted inputs, compared variable by
//! variable and on the fault flag after cold start and after every scan. The fault
//! flag is cleared before every scan, so each scan's own faults are compared.

use plcc_ir::machine::Machine;
use plcc_ir::value::PlcValue;
use plcc_ir::vars::variables;
use plcc_ir::{ElemType, Module};

/// Two values are the same: bit for bit, except that any two NaNs are equal.
fn same(a: PlcValue, b: PlcValue) -> bool {
    match a.ty {
        ElemType::Real | ElemType::LReal if a.as_f64().is_nan() => b.as_f64().is_nan(),
        _ => a.ty == b.ty && a.bits == b.bits,
    }
}

/// What one run showed.
#[derive(Debug)]
pub struct Agreement {
    /// The machines that ran the module besides the interpreter.
    pub machines: Vec<String>,
    /// Scans after which the fault flag was raised (on every machine alike).
    pub faulted: Vec<usize>,
}

/// Runs `module` on the interpreter and on `machines` (names with their settings, as
/// `plcc::targets::checked_machines()` gives them). Before scan `s`, the writes of `script[s]`
/// (a path and a value as an integer, or a float for REAL/LREAL variables) go to every
/// machine. A machine that cannot build the module is an error: these modules are
/// written to fit them all.
pub fn agree_with_interp(
    module: &Module,
    machines: &[String],
    script: &[Vec<(&str, f64)>],
) -> Result<Agreement, String> {
    let vars: Vec<(String, ElemType)> = module
        .programs
        .iter()
        .flat_map(|e| variables(module, e.data))
        .map(|v| (v.path, v.elem))
        .collect();
    let mut ms: Vec<(String, Box<dyn Machine>)> = Vec::new();
    let names = std::iter::once("interp".to_string())
        .chain(machines.iter().filter(|m| *m != "interp").cloned());
    for name in names {
        let m = plcc::targets::machine_spec(&name, module).map_err(|d| {
            format!(
                "{name} cannot build it: {}",
                d.iter()
                    .map(|x| x.to_string())
                    .collect::<Vec<_>>()
                    .join("; ")
            )
        })?;
        ms.push((name, m));
    }
    let compare = |ms: &[(String, Box<dyn Machine>)], when: &str| -> Result<bool, String> {
        let (_, r) = &ms[0];
        for (name, m) in &ms[1..] {
            for (v, _) in &vars {
                let a = r.read(v).map_err(|e| format!("interp: {e}"))?;
                let b = m.read(v).map_err(|e| format!("{name}: {e}"))?;
                if !same(a, b) {
                    return Err(format!("{when}: {v} is {a} on interp, {b} on {name}"));
                }
            }
            if r.fault() != m.fault() {
                return Err(format!(
                    "{when}: the fault flag is {} on interp, {} on {name}",
                    r.fault(),
                    m.fault()
                ));
            }
        }
        Ok(r.fault())
    };
    for (name, m) in ms.iter_mut() {
        m.cold_start()
            .map_err(|e| format!("{name}: cold start: {e}"))?;
    }
    compare(&ms, "after cold start")?;
    let mut faulted = Vec::new();
    for (s, writes) in script.iter().enumerate() {
        for (path, x) in writes {
            let ty = vars
                .iter()
                .find(|(p, _)| p.eq_ignore_ascii_case(path))
                .map(|(_, t)| *t)
                .ok_or_else(|| format!("no variable {path}"))?;
            let v = match ty {
                ElemType::Real => PlcValue::from_f32(*x as f32),
                ElemType::LReal => PlcValue::from_f64(*x),
                _ => PlcValue::from_i64(ty, *x as i64),
            };
            for (name, m) in ms.iter_mut() {
                m.write(path, v)
                    .map_err(|e| format!("{name}: write {path}: {e}"))?;
            }
        }
        for (name, m) in ms.iter_mut() {
            m.clear_fault();
            m.set_clock_us(s as i64 * 10_000);
            m.scan()
                .map_err(|e| format!("scan {s}: {name} failed: {e}"))?;
        }
        if compare(&ms, &format!("after scan {s}"))? {
            faulted.push(s);
        }
    }
    Ok(Agreement {
        machines: ms.into_iter().skip(1).map(|(n, _)| n).collect(),
        faulted,
    })
}
