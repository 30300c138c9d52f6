//! Every instruction of docs/ir.md on the edge cases of every width, checked against an
//! oracle written here from the contract and, differentially, against the interpreter.

mod common;

use common::{ld, st, val, Pair, Prog};
use plcc_ir::{BinaryOp, ConvOp, FloatCC, FuncBuilder, IntCC, Module, Type, UnaryOp, Value};

const INTS: [Type; 4] = [Type::I8, Type::I16, Type::I32, Type::I64];

fn width(ty: Type) -> u32 {
    ty.bits()
}

fn mask(ty: Type, v: u64) -> u64 {
    match width(ty) {
        64 => v,
        w => v & ((1u64 << w) - 1),
    }
}

/// The signed reading (an `i1` 1 is -1).
fn sx(ty: Type, v: u64) -> i64 {
    let w = width(ty);
    ((v << (64 - w)) as i64) >> (64 - w)
}

fn interesting(ty: Type) -> Vec<u64> {
    let w = width(ty) as i64;
    let min = if w == 64 {
        i64::MIN
    } else {
        -(1i64 << (w - 1))
    };
    let max = if w == 64 {
        i64::MAX
    } else {
        (1i64 << (w - 1)) - 1
    };
    let mut v: Vec<u64> = [
        0,
        1,
        2,
        3,
        5,
        7,
        8,
        w - 1,
        w,
        w + 1,
        63,
        64,
        65,
        100,
        1000,
        -1,
        -2,
        -3,
        -7,
        -100,
        min,
        min + 1,
        max,
        max - 1,
        0x5555_5555_5555_5555,
        0xAAAA_AAAA_AAAA_AAAAu64 as i64,
    ]
    .iter()
    .map(|&x| mask(ty, x as u64))
    .collect();
    v.sort();
    v.dedup();
    v
}

/// The contract's result of an integer binary operation and whether it faults.
fn oracle(op: BinaryOp, ty: Type, a: u64, b: u64) -> (u64, bool) {
    let w = width(ty) as u64;
    let (sa, sb) = (sx(ty, a), sx(ty, b));
    let r = match op {
        BinaryOp::Iadd => a.wrapping_add(b),
        BinaryOp::Isub => a.wrapping_sub(b),
        BinaryOp::Imul => a.wrapping_mul(b),
        BinaryOp::Sdiv | BinaryOp::Srem | BinaryOp::Udiv | BinaryOp::Urem if b == 0 => {
            return (0, true)
        }
        BinaryOp::Sdiv => {
            if sb == -1 {
                sa.wrapping_neg() as u64
            } else {
                (sa / sb) as u64
            }
        }
        BinaryOp::Srem => {
            if sb == -1 {
                0
            } else {
                (sa % sb) as u64
            }
        }
        BinaryOp::Udiv => a / b,
        BinaryOp::Urem => a % b,
        BinaryOp::Band => a & b,
        BinaryOp::Bor => a | b,
        BinaryOp::Bxor => a ^ b,
        BinaryOp::Ishl => {
            if b >= w {
                0
            } else {
                a << b
            }
        }
        BinaryOp::Ushr => {
            if b >= w {
                0
            } else {
                a >> b
            }
        }
        BinaryOp::Sshr => (sa >> b.min(w - 1)) as u64,
        BinaryOp::Rotl | BinaryOp::Rotr => {
            let mut c = b % w;
            if op == BinaryOp::Rotr {
                c = (w - c) % w;
            }
            if c == 0 {
                a
            } else {
                (a << c) | (a >> (w - c))
            }
        }
        _ => unreachable!(),
    };
    (mask(ty, r), false)
}

/// A program `r := f(a, b)` where `f` applies `op` (so calls with narrow arguments and
/// results are exercised too).
fn binary_module(
    tin: Type,
    tout: Type,
    op: impl FnOnce(&mut FuncBuilder, Value, Value) -> Value,
) -> Module {
    let mut p = Prog::new(vec![
        common::field("a", tin),
        common::field("b", tin),
        common::field("r", tout),
    ]);
    let f = p.func("f", vec![tin, tin], Some(tout), |b, ps| {
        let r = op(b, ps[0], ps[1]);
        b.ret(Some(r));
    });
    let (fa, fb, fr) = (p.f("a"), p.f("b"), p.f("r"));
    p.finish(|b, inst, agg| {
        let a = ld(b, inst, agg, fa, tin);
        let bv = ld(b, inst, agg, fb, tin);
        let r = b.call(f, Some(tout), vec![a, bv]).unwrap();
        st(b, r, inst, agg, fr);
    })
}

fn unary_module(
    tin: Type,
    tout: Type,
    op: impl FnOnce(&mut FuncBuilder, Value) -> Value,
) -> Module {
    binary_module(tin, tout, |b, a, _| op(b, a))
}

/// Runs `r := a op b` on both machines; returns (r bits, fault).
fn run2(p: &mut Pair, tin: Type, tout: Type, a: u64, b: u64) -> (u64, bool) {
    p.clear_fault();
    p.write("main.a", val(tin, a));
    p.write("main.b", val(tin, b));
    p.scan();
    let r = p.read("main.r").bits;
    let _ = tout;
    (r, p.fault())
}

#[test]
fn integer_binary_ops_at_every_width() {
    use BinaryOp::*;
    for op in [
        Iadd, Isub, Imul, Sdiv, Udiv, Srem, Urem, Band, Bor, Bxor, Ishl, Ushr, Sshr, Rotl, Rotr,
    ] {
        for ty in INTS {
            let mut p = Pair::new(binary_module(ty, ty, |b, x, y| b.binary(op, x, y)));
            let vals = interesting(ty);
            for &a in &vals {
                for &b in &vals {
                    let got = run2(&mut p, ty, ty, a, b);
                    let want = oracle(op, ty, a, b);
                    assert_eq!(got, want, "{} {ty} {} {}", op.name(), sx(ty, a), sx(ty, b));
                }
            }
        }
    }
}

#[test]
fn division_by_zero_faults_without_a_signal() {
    for op in [
        BinaryOp::Sdiv,
        BinaryOp::Udiv,
        BinaryOp::Srem,
        BinaryOp::Urem,
    ] {
        for ty in INTS {
            let mut p = Pair::new(binary_module(ty, ty, |b, x, y| b.binary(op, x, y)));
            assert!(!p.fault());
            assert_eq!(run2(&mut p, ty, ty, 7, 0), (0, true), "{} {ty}", op.name());
            // The flag stays raised until cleared.
            p.write("main.b", val(ty, 1));
            p.scan();
            assert!(p.fault());
            p.clear_fault();
            p.scan();
            assert!(!p.fault());
            // MIN / -1 and MIN % -1.
            let min = mask(ty, 1u64 << (width(ty) - 1));
            let m1 = mask(ty, u64::MAX);
            let got = run2(&mut p, ty, ty, min, m1);
            assert_eq!(got, oracle(op, ty, min, m1), "{} {ty} MIN, -1", op.name());
        }
    }
}

#[test]
fn bool_operations() {
    use BinaryOp::*;
    let t = Type::I1;
    // The verifier allows only the logical operations on i1.
    for op in [Band, Bor, Bxor] {
        let mut p = Pair::new(binary_module(t, t, |b, x, y| b.binary(op, x, y)));
        for a in 0..2 {
            for b in 0..2 {
                let got = run2(&mut p, t, t, a, b);
                if matches!(op, Band | Bor | Bxor) {
                    let want = match op {
                        Band => a & b,
                        Bor => a | b,
                        _ => a ^ b,
                    };
                    assert_eq!(got, (want, false), "{} {a} {b}", op.name());
                }
            }
        }
    }
    for op in [UnaryOp::Bnot] {
        let mut p = Pair::new(unary_module(t, t, |b, x| b.unary(op, x)));
        for a in 0..2 {
            let (r, _) = run2(&mut p, t, t, a, 0);
            if op == UnaryOp::Bnot {
                assert_eq!(r, 1 - a);
            }
        }
    }
    for cc in IntCC::ALL {
        let mut p = Pair::new(binary_module(t, t, |b, x, y| b.icmp(cc, x, y)));
        for a in 0..2 {
            for b in 0..2 {
                run2(&mut p, t, t, a, b);
            }
        }
    }
}

#[test]
fn integer_unary_ops_and_comparisons() {
    for ty in INTS {
        for op in [UnaryOp::Ineg, UnaryOp::Bnot, UnaryOp::Iabs] {
            let mut p = Pair::new(unary_module(ty, ty, |b, x| b.unary(op, x)));
            for a in interesting(ty) {
                let want = match op {
                    UnaryOp::Ineg => mask(ty, a.wrapping_neg()),
                    UnaryOp::Bnot => mask(ty, !a),
                    _ => mask(ty, sx(ty, a).wrapping_abs() as u64),
                };
                assert_eq!(run2(&mut p, ty, ty, a, 0).0, want, "{} {ty} {a}", op.name());
            }
        }
        for cc in IntCC::ALL {
            let mut p = Pair::new(binary_module(ty, Type::I1, |b, x, y| b.icmp(cc, x, y)));
            let vals = interesting(ty);
            for &a in &vals {
                for &b in &vals {
                    let (sa, sb) = (sx(ty, a), sx(ty, b));
                    let want = match cc {
                        IntCC::Eq => a == b,
                        IntCC::Ne => a != b,
                        IntCC::Slt => sa < sb,
                        IntCC::Sle => sa <= sb,
                        IntCC::Sgt => sa > sb,
                        IntCC::Sge => sa >= sb,
                        IntCC::Ult => a < b,
                        IntCC::Ule => a <= b,
                        IntCC::Ugt => a > b,
                        IntCC::Uge => a >= b,
                    };
                    assert_eq!(run2(&mut p, ty, Type::I1, a, b).0, want as u64);
                }
            }
        }
    }
}

#[test]
fn select_of_every_type() {
    for ty in [
        Type::I1,
        Type::I8,
        Type::I16,
        Type::I32,
        Type::I64,
        Type::F32,
        Type::F64,
    ] {
        let mut p = Pair::new(binary_module(ty, ty, |b, x, y| {
            let z = common::zero(b, ty);
            let c = if ty.is_float() {
                b.fcmp(FloatCC::Ne, x, z)
            } else {
                b.icmp(IntCC::Ne, x, z)
            };
            b.select(c, x, y)
        }));
        let one = if ty == Type::F32 {
            1f32.to_bits() as u64
        } else if ty == Type::F64 {
            1f64.to_bits()
        } else {
            1
        };
        assert_eq!(run2(&mut p, ty, ty, one, 0).0, one);
        assert_eq!(run2(&mut p, ty, ty, 0, one).0, one);
        assert_eq!(run2(&mut p, ty, ty, 0, 0).0, 0);
    }
}

fn floats32() -> Vec<f32> {
    vec![
        0.0,
        -0.0,
        0.5,
        -0.5,
        1.5,
        2.5,
        -2.5,
        3.5,
        1.0,
        -1.0,
        0.1,
        100.25,
        1e10,
        -1e10,
        127.9,
        128.0,
        -128.9,
        -129.0,
        255.9,
        256.0,
        32767.5,
        32768.0,
        -32768.9,
        65535.9,
        65536.0,
        2147483520.0,
        2147483648.0,
        -2147483648.0,
        4294967040.0,
        4294967296.0,
        9.223372e18,
        -9.223372e18,
        1.8446743e19,
        2e19,
        f32::MAX,
        f32::MIN,
        f32::MIN_POSITIVE,
        1e-45,
        f32::INFINITY,
        f32::NEG_INFINITY,
        f32::NAN,
        -f32::NAN,
        0.49999997,
        8388609.0,
    ]
}

fn floats64() -> Vec<f64> {
    let mut v: Vec<f64> = floats32().into_iter().map(|x| x as f64).collect();
    v.extend([
        0.49999999999999994,
        4503599627370497.0,
        2147483647.5,
        2147483648.5,
        -2147483648.5,
        -2147483649.0,
        4294967295.5,
        9223372036854775807.0,
        -9223372036854775808.0,
        18446744073709551615.0,
        f64::MAX,
        f64::MIN_POSITIVE,
        5e-324,
    ]);
    v
}

fn fbits(ty: Type, x: f64) -> u64 {
    if ty == Type::F32 {
        (x as f32).to_bits() as u64
    } else {
        x.to_bits()
    }
}

/// The inputs for a float type, as bits.
fn float_inputs(ty: Type) -> Vec<u64> {
    if ty == Type::F32 {
        floats32().into_iter().map(|x| x.to_bits() as u64).collect()
    } else {
        floats64().into_iter().map(|x| x.to_bits()).collect()
    }
}

#[test]
fn float_to_integer_saturates_at_every_width() {
    for from in [Type::F32, Type::F64] {
        for to in INTS {
            for op in [ConvOp::FToSi, ConvOp::FToUi] {
                let mut p = Pair::new(unary_module(from, to, |b, x| b.convert(op, to, x)));
                for a in float_inputs(from) {
                    let x = if from == Type::F32 {
                        f32::from_bits(a as u32) as f64
                    } else {
                        f64::from_bits(a)
                    };
                    // Rust's `as` truncates toward zero, saturates and maps NaN to 0.
                    let want = match (op, to) {
                        (ConvOp::FToSi, Type::I8) => x as i8 as u8 as u64,
                        (ConvOp::FToSi, Type::I16) => x as i16 as u16 as u64,
                        (ConvOp::FToSi, Type::I32) => x as i32 as u32 as u64,
                        (ConvOp::FToSi, Type::I64) => x as i64 as u64,
                        (ConvOp::FToUi, Type::I8) => x as u8 as u64,
                        (ConvOp::FToUi, Type::I16) => x as u16 as u64,
                        (ConvOp::FToUi, Type::I32) => x as u32 as u64,
                        (ConvOp::FToUi, Type::I64) => x as u64,
                        // i1: signed range -1..0, unsigned 0..1.
                        (ConvOp::FToSi, _) => ((x as i64).clamp(-1, 0) & 1) as u64,
                        (_, _) => (x as u64).min(1),
                    };
                    let got = run2(&mut p, from, to, a, 0);
                    assert_eq!(got, (want, false), "{}.{to} of {from} {x}", op.name());
                }
            }
        }
    }
}

#[test]
fn integer_to_float_rounds_to_nearest_even() {
    for from in INTS {
        for to in [Type::F32, Type::F64] {
            for op in [ConvOp::SiToF, ConvOp::UiToF] {
                let mut p = Pair::new(unary_module(from, to, |b, x| b.convert(op, to, x)));
                let mut inputs = if from == Type::I1 {
                    vec![0, 1]
                } else {
                    interesting(from)
                };
                inputs.extend([
                    mask(from, 16777217),
                    mask(from, (1u64 << 53) + 1),
                    mask(from, u64::MAX - 1023),
                ]);
                if from == Type::I1 {
                    inputs.truncate(2);
                }
                for a in inputs {
                    let v = if op == ConvOp::SiToF {
                        let s = if from == Type::I1 {
                            -(a as i64)
                        } else {
                            sx(from, a)
                        };
                        if to == Type::F32 {
                            (s as f32).to_bits() as u64
                        } else {
                            (s as f64).to_bits()
                        }
                    } else if to == Type::F32 {
                        (a as f32).to_bits() as u64
                    } else {
                        (a as f64).to_bits()
                    };
                    assert_eq!(
                        run2(&mut p, from, to, a, 0),
                        (v, false),
                        "{}.{to} {from} {a}",
                        op.name()
                    );
                }
            }
        }
    }
}

#[test]
fn integer_width_conversions() {
    let all = [Type::I1, Type::I8, Type::I16, Type::I32, Type::I64];
    for from in all {
        for to in all {
            let inputs = if from == Type::I1 {
                vec![0, 1]
            } else {
                interesting(from)
            };
            if to.bits() > from.bits() {
                // sext takes i8..i64 only; uext also takes i1.
                let ops: &[ConvOp] = if from == Type::I1 {
                    &[ConvOp::Uext]
                } else {
                    &[ConvOp::Sext, ConvOp::Uext]
                };
                for &op in ops {
                    let mut p = Pair::new(unary_module(from, to, |b, x| b.convert(op, to, x)));
                    for &a in &inputs {
                        let want = if op == ConvOp::Uext {
                            a
                        } else if from == Type::I1 {
                            mask(to, (a as i64).wrapping_neg() as u64)
                        } else {
                            mask(to, sx(from, a) as u64)
                        };
                        assert_eq!(
                            run2(&mut p, from, to, a, 0).0,
                            want,
                            "{}.{to} {from} {a}",
                            op.name()
                        );
                    }
                }
            }
            if to.bits() < from.bits() && from != Type::I1 {
                let mut p = Pair::new(unary_module(from, to, |b, x| {
                    b.convert(ConvOp::Itrunc, to, x)
                }));
                for &a in &inputs {
                    assert_eq!(run2(&mut p, from, to, a, 0).0, mask(to, a));
                }
            }
        }
    }
}

#[test]
fn float_conversions_and_bitcasts() {
    let mut p = Pair::new(unary_module(Type::F32, Type::F64, |b, x| {
        b.convert(ConvOp::Fpromote, Type::F64, x)
    }));
    for a in float_inputs(Type::F32) {
        let want = (f32::from_bits(a as u32) as f64).to_bits();
        let (got, _) = run2(&mut p, Type::F32, Type::F64, a, 0);
        // NaN payloads may differ in quietening; everything else is exact.
        if !f64::from_bits(want).is_nan() {
            assert_eq!(got, want);
        } else {
            assert!(f64::from_bits(got).is_nan());
        }
    }
    let mut p = Pair::new(unary_module(Type::F64, Type::F32, |b, x| {
        b.convert(ConvOp::Fdemote, Type::F32, x)
    }));
    for a in float_inputs(Type::F64).into_iter().chain([
        1.0000000596046448f64.to_bits(),
        1.0000001788139343f64.to_bits(),
    ]) {
        let want = (f64::from_bits(a) as f32).to_bits() as u64;
        let (got, _) = run2(&mut p, Type::F64, Type::F32, a, 0);
        if !f32::from_bits(want as u32).is_nan() {
            assert_eq!(got, want, "fdemote {}", f64::from_bits(a));
        }
    }
    for (i, f) in [(Type::I32, Type::F32), (Type::I64, Type::F64)] {
        let mut p = Pair::new(unary_module(i, f, |b, x| b.convert(ConvOp::Bitcast, f, x)));
        for a in interesting(i) {
            assert_eq!(run2(&mut p, i, f, a, 0).0, a);
        }
        let mut p = Pair::new(unary_module(f, i, |b, x| b.convert(ConvOp::Bitcast, i, x)));
        for a in float_inputs(f) {
            assert_eq!(run2(&mut p, f, i, a, 0).0, a);
        }
    }
}

fn float_unary_want(op: UnaryOp, ty: Type, a: u64) -> u64 {
    macro_rules! go {
        ($x:expr) => {{
            let x = $x;
            let r = match op {
                UnaryOp::Fneg => -x,
                UnaryOp::Fabs => x.abs(),
                UnaryOp::Fsqrt => x.sqrt(),
                UnaryOp::Fnearest => x.round_ties_even(),
                UnaryOp::Ftrunc => x.trunc(),
                UnaryOp::Ffloor => x.floor(),
                UnaryOp::Fceil => x.ceil(),
                UnaryOp::Sin => x.sin(),
                UnaryOp::Cos => x.cos(),
                UnaryOp::Tan => x.tan(),
                UnaryOp::Asin => x.asin(),
                UnaryOp::Acos => x.acos(),
                UnaryOp::Atan => x.atan(),
                UnaryOp::Ln => x.ln(),
                UnaryOp::Log10 => x.log10(),
                UnaryOp::Exp => x.exp(),
                _ => unreachable!(),
            };
            r
        }};
    }
    if ty == Type::F32 {
        go!(f32::from_bits(a as u32)).to_bits() as u64
    } else {
        go!(f64::from_bits(a)).to_bits()
    }
}

fn same_float(ty: Type, a: u64, b: u64) -> bool {
    if ty == Type::F32 {
        let (x, y) = (f32::from_bits(a as u32), f32::from_bits(b as u32));
        a == b || x.is_nan() && y.is_nan()
    } else {
        let (x, y) = (f64::from_bits(a), f64::from_bits(b));
        a == b || x.is_nan() && y.is_nan()
    }
}

#[test]
fn float_unary_ops_match_the_rust_library_bit_for_bit() {
    for ty in [Type::F32, Type::F64] {
        for op in UnaryOp::ALL.into_iter().filter(|o| !o.is_int_op()) {
            let mut p = Pair::new(unary_module(ty, ty, |b, x| b.unary(op, x)));
            let mut inputs = float_inputs(ty);
            inputs.extend(
                [
                    0.3,
                    0.7,
                    1.2345,
                    -0.75,
                    2.0,
                    10.0,
                    1e-3,
                    88.7,
                    710.0,
                    std::f64::consts::PI,
                ]
                .map(|x| fbits(ty, x)),
            );
            for a in inputs {
                let (got, fault) = run2(&mut p, ty, ty, a, 0);
                let want = float_unary_want(op, ty, a);
                assert!(!fault);
                assert!(
                    same_float(ty, got, want),
                    "{} {ty} of {a:#x}: {got:#x} vs {want:#x}",
                    op.name()
                );
            }
        }
    }
}

#[test]
fn nearest_ties_to_even() {
    for ty in [Type::F32, Type::F64] {
        let mut p = Pair::new(unary_module(ty, ty, |b, x| b.unary(UnaryOp::Fnearest, x)));
        for (x, r) in [
            (0.5, 0.0),
            (1.5, 2.0),
            (2.5, 2.0),
            (-0.5, -0.0),
            (-1.5, -2.0),
            (-2.5, -2.0),
            (3.5, 4.0),
            (0.49999997, 0.0),
        ] {
            let got = run2(&mut p, ty, ty, fbits(ty, x), 0).0;
            assert_eq!(got, fbits(ty, r), "fnearest {x}");
        }
    }
}

#[test]
fn float_binary_ops_and_comparisons() {
    for ty in [Type::F32, Type::F64] {
        for op in BinaryOp::ALL.into_iter().filter(|o| !o.is_int_op()) {
            let mut p = Pair::new(binary_module(ty, ty, |b, x, y| b.binary(op, x, y)));
            let inputs: Vec<u64> = [
                0.0,
                -0.0,
                1.0,
                -1.0,
                0.5,
                2.0,
                3.0,
                -2.5,
                10.0,
                1e30,
                f64::INFINITY,
                f64::NAN,
                1e-40,
            ]
            .map(|x| fbits(ty, x))
            .to_vec();
            for &a in &inputs {
                for &b in &inputs {
                    let (got, fault) = run2(&mut p, ty, ty, a, b);
                    assert!(!fault, "float ops never fault");
                    macro_rules! go {
                        ($x:expr, $y:expr) => {{
                            let (x, y) = ($x, $y);
                            match op {
                                BinaryOp::Fadd => x + y,
                                BinaryOp::Fsub => x - y,
                                BinaryOp::Fmul => x * y,
                                BinaryOp::Fdiv => x / y,
                                BinaryOp::Fpow => x.powf(y),
                                _ => x.atan2(y),
                            }
                        }};
                    }
                    let want = if ty == Type::F32 {
                        go!(f32::from_bits(a as u32), f32::from_bits(b as u32)).to_bits() as u64
                    } else {
                        go!(f64::from_bits(a), f64::from_bits(b)).to_bits()
                    };
                    assert!(
                        same_float(ty, got, want),
                        "{} {ty} {a:#x} {b:#x}",
                        op.name()
                    );
                }
            }
        }
        for cc in FloatCC::ALL {
            let mut p = Pair::new(binary_module(ty, Type::I1, |b, x, y| b.fcmp(cc, x, y)));
            let inputs: Vec<u64> = [0.0, -0.0, 1.0, -1.0, f64::INFINITY, f64::NAN]
                .map(|x| fbits(ty, x))
                .to_vec();
            for &a in &inputs {
                for &b in &inputs {
                    let (x, y) = (
                        f64::from_bits(fbits(
                            Type::F64,
                            if ty == Type::F32 {
                                f32::from_bits(a as u32) as f64
                            } else {
                                f64::from_bits(a)
                            },
                        )),
                        if ty == Type::F32 {
                            f32::from_bits(b as u32) as f64
                        } else {
                            f64::from_bits(b)
                        },
                    );
                    let want = match cc {
                        FloatCC::Eq => x == y,
                        FloatCC::Ne => x != y,
                        FloatCC::Lt => x < y,
                        FloatCC::Le => x <= y,
                        FloatCC::Gt => x > y,
                        FloatCC::Ge => x >= y,
                    };
                    assert_eq!(
                        run2(&mut p, ty, Type::I1, a, b).0,
                        want as u64,
                        "fcmp {} {x} {y}",
                        cc.name()
                    );
                }
            }
        }
    }
}

#[test]
fn f32_math_stays_in_f32() {
    // sin computed in f64 and rounded would differ from sinf for some inputs; the JIT
    // must agree with f32::sin bit for bit.
    let ty = Type::F32;
    let mut p = Pair::new(unary_module(ty, ty, |b, x| b.unary(UnaryOp::Sin, x)));
    let mut x = 0.001f32;
    while x < 100.0 {
        let got = run2(&mut p, ty, ty, x.to_bits() as u64, 0).0;
        assert_eq!(got, x.sin().to_bits() as u64, "sinf({x})");
        x *= 1.37;
    }
}

#[test]
fn other_settings_keep_the_semantics() {
    use plcc_ir::backend::{Backend, Options};
    use BinaryOp::*;
    for (opt, ra) in [("none", "single_pass"), ("speed_and_size", "backtracking")] {
        let opts = Options {
            emit: None,
            settings: vec![
                ("opt_level".into(), opt.into()),
                ("regalloc".into(), ra.into()),
            ],
            sources: Vec::new(),
            output_stem: None,
        };
        for op in [Sdiv, Srem, Udiv, Urem, Ishl, Ushr, Sshr, Rotl] {
            for ty in INTS {
                let m = binary_module(ty, ty, |b, x, y| b.binary(op, x, y));
                let mut j = plcc_native::NativeBackend
                    .machine(&m, &opts)
                    .unwrap()
                    .unwrap();
                j.cold_start().unwrap();
                let vals = interesting(ty);
                for &a in &vals {
                    for &b in &vals {
                        j.clear_fault();
                        j.write("main.a", val(ty, a)).unwrap();
                        j.write("main.b", val(ty, b)).unwrap();
                        j.scan().unwrap();
                        let got = (j.read("main.r").unwrap().bits, j.fault());
                        assert_eq!(
                            got,
                            oracle(op, ty, a, b),
                            "{opt} {} {ty} {a} {b}",
                            op.name()
                        );
                    }
                }
            }
        }
    }
}

/// `r_k := a op c_k` for every interesting constant `c_k` (constant divisors take
/// another path through the backend than variable ones).
#[test]
fn division_by_constants() {
    use BinaryOp::*;
    for op in [Sdiv, Udiv, Srem, Urem] {
        for ty in INTS {
            let consts: Vec<u64> = interesting(ty).into_iter().filter(|&c| c != 0).collect();
            let mut fields = vec![common::field("a", ty)];
            for k in 0..consts.len() {
                fields.push(common::field(&format!("r{k}"), ty));
            }
            let p = Prog::new(fields);
            let fa = p.f("a");
            let cs = consts.clone();
            let m = p.finish(|b, inst, agg| {
                let a = ld(b, inst, agg, fa, ty);
                for (k, &c) in cs.iter().enumerate() {
                    let cv = b.iconst(ty, c as i64);
                    let r = b.binary(op, a, cv);
                    st(b, r, inst, agg, k as u32 + 1);
                }
            });
            let mut p = Pair::new(m);
            for a in interesting(ty) {
                p.write("main.a", val(ty, a));
                p.scan();
                for (k, &c) in consts.iter().enumerate() {
                    let got = p.read(&format!("main.r{k}")).bits;
                    assert_eq!(got, oracle(op, ty, a, c).0, "{} {ty} {a} by {c}", op.name());
                }
                assert!(!p.fault());
            }
            // By a constant 0: 0 and the fault.
            let p = Prog::new(vec![common::field("a", ty), common::field("r", ty)]);
            let (fa, fr) = (p.f("a"), p.f("r"));
            let m = p.finish(|b, inst, agg| {
                let a = ld(b, inst, agg, fa, ty);
                let z = b.iconst(ty, 0);
                let r = b.binary(op, a, z);
                st(b, r, inst, agg, fr);
            });
            let mut p = Pair::new(m);
            p.write("main.a", val(ty, 5));
            p.write("main.r", val(ty, 9));
            p.scan();
            assert_eq!(p.read("main.r").bits, 0);
            assert!(p.fault());
        }
    }
}
