//! EXPT on the CPDev VM, whose own EXPT is `exp(log(x) * y)`, against the
//! interpreter's C `pow` on the operands where the two are easiest to get apart:
//! signed zeros, infinities, NaN, ±1, negative bases with integral and fractional
//! exponents, 0.5, and powers whose result is exact. Both machines run the same
//! program; the values must be the same bits where pow is exact (and NaN where it is
//! NaN), else within a few units in the last place.

use plcc::driver::{build_sources, BuildOptions};
use plcc::targets;
use plcc_ir::value::PlcValue;

const SRC: &str = "PROGRAM main
VAR x, y, r : REAL; lx, ly, lr : LREAL; END_VAR
    r := x ** y;
    lr := lx ** ly;
END_PROGRAM
";

fn operands() -> Vec<f64> {
    let mut v = vec![
        0.0,
        -0.0,
        1.0,
        -1.0,
        0.5,
        -0.5,
        2.0,
        -2.0,
        3.0,
        -3.0,
        10.0,
        -10.0,
        0.25,
        1.5,
        -1.5,
        7.0,
        100.0,
        1e-3,
        1e10,
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::NAN,
    ];
    v.extend([-4.0, 4.0, 5.0, -5.0, 20.0, 0.75, -0.75, 1.0 / 3.0]);
    v
}

/// Units in the last place between two floats of `bits` width (0 for the same bits,
/// and for two NaNs).
fn ulps(a: f64, b: f64, single: bool) -> u64 {
    if a.is_nan() && b.is_nan() {
        return 0;
    }
    if a.is_nan() || b.is_nan() {
        return u64::MAX;
    }
    let key = |x: f64| -> i64 {
        if single {
            let i = (x as f32).to_bits() as i32 as i64;
            if i < 0 {
                i64::from(i32::MIN) - i
            } else {
                i
            }
        } else {
            let i = x.to_bits() as i64;
            if i < 0 {
                i64::MIN - i
            } else {
                i
            }
        }
    };
    key(a).abs_diff(key(b))
}

#[test]
fn vm_expt_follows_c_pow() {
    let module = build_sources(
        vec![("expt.st".to_string(), SRC.as_bytes().to_vec())],
        &BuildOptions::default(),
    )
    .unwrap()
    .module
    .unwrap();
    let mut vm = targets::machine_with("vmasm", &module, &[]).unwrap();
    let mut interp = targets::machine_with("interp", &module, &[]).unwrap();
    vm.cold_start().unwrap();
    interp.cold_start().unwrap();
    let mut bad = Vec::new();
    let mut n = 0;
    for &x in &operands() {
        for &y in &operands() {
            for m in [&mut vm, &mut interp] {
                m.write("main.x", PlcValue::from_f32(x as f32)).unwrap();
                m.write("main.y", PlcValue::from_f32(y as f32)).unwrap();
                m.write("main.lx", PlcValue::from_f64(x)).unwrap();
                m.write("main.ly", PlcValue::from_f64(y)).unwrap();
                m.scan().unwrap();
            }
            for (var, single) in [("main.r", true), ("main.lr", false)] {
                let a = vm.read(var).unwrap().as_f64();
                let b = interp.read(var).unwrap().as_f64();
                n += 1;
                // Exact: where pow's result is exact, or an edge case of its definition.
                let integral = y.fract() == 0.0 || y.is_infinite();
                let exact = y == 0.0
                    || x.abs() == 1.0
                    || y == 0.5
                    || x.is_nan()
                    || y.is_nan()
                    || x.is_infinite()
                    || x == 0.0
                    || (integral
                        && (b.fract() == 0.0 || b == 0.0 || b.is_infinite())
                        && b.abs() < 1e15)
                    || (x < 0.0 && !integral);
                let tol = if exact {
                    0
                } else if single {
                    1
                } else {
                    64
                };
                if ulps(a, b, single) > tol {
                    bad.push(format!("{var}: {x:e} ** {y:e}: vm {a:e}, interp {b:e}"));
                }
            }
        }
    }
    assert!(n > 1500, "{n}");
    assert!(bad.is_empty(), "{} of {n}:\n{}", bad.len(), bad.join("\n"));
}
