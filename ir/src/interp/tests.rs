//! Tests of the interpreter: every operation with its edge cases, control flow,
//! memory, programs and the `Machine` interface, on modules built with the builder.

use super::*;
use crate::builder::FuncBuilder;
use crate::entities::Value;
use crate::function::{FuncKind, Function};
use crate::inst::{BinaryOp, ConvOp, FloatCC, IntCC, Intrinsic, UnaryOp};
use crate::module::{
    ArrayDef, DataDef, DataKind, Field, FieldRole, ProgramEntry, StructDef, StructKind,
};
use crate::types::ElemType;

const INTS: [Type; 4] = [Type::I8, Type::I16, Type::I32, Type::I64];

fn func(
    m: &mut Module,
    name: &str,
    params: &[Type],
    ret: Option<Type>,
    body: impl FnOnce(&mut FuncBuilder, Vec<Value>),
) -> FuncId {
    let mut f = Function::new(name, FuncKind::Function, params.to_vec(), ret);
    let mut b = FuncBuilder::new(&mut f);
    let p = b.params();
    body(&mut b, p);
    m.add_func(f)
}

/// Runs a one-function module: `f(params) -> ret`.
fn run1(
    params: &[Type],
    ret: Option<Type>,
    args: &[u64],
    body: impl FnOnce(&mut FuncBuilder, Vec<Value>),
) -> (Result<Option<u64>, MachineError>, bool) {
    let mut m = Module::new();
    let f = func(&mut m, "f", params, ret, body);
    let mut it = Interp::new(&m).unwrap();
    let r = it.call(f, args);
    (r, it.fault())
}

fn bin(op: BinaryOp, ty: Type, a: i64, b: i64) -> (i64, bool) {
    let (r, fault) = run1(&[ty, ty], Some(ty), &[a as u64, b as u64], |b, p| {
        let v = b.binary(op, p[0], p[1]);
        b.ret(Some(v));
    });
    (r.unwrap().unwrap() as i64, fault)
}

fn un(op: UnaryOp, ty: Type, a: u64) -> u64 {
    let (r, _) = run1(&[ty], Some(ty), &[a], |b, p| {
        let v = b.unary(op, p[0]);
        b.ret(Some(v));
    });
    r.unwrap().unwrap()
}

fn conv(op: ConvOp, from: Type, to: Type, a: u64) -> u64 {
    let (r, _) = run1(&[from], Some(to), &[a], |b, p| {
        let v = b.convert(op, to, p[0]);
        b.ret(Some(v));
    });
    r.unwrap().unwrap()
}

fn icmp(cc: IntCC, ty: Type, a: i64, b: i64) -> bool {
    let (r, _) = run1(&[ty, ty], Some(Type::I1), &[a as u64, b as u64], |b, p| {
        let v = b.icmp(cc, p[0], p[1]);
        b.ret(Some(v));
    });
    r.unwrap().unwrap() == 1
}

fn f32b(x: f32) -> u64 {
    x.to_bits() as u64
}

fn f64b(x: f64) -> u64 {
    x.to_bits()
}

fn f32_bin(op: BinaryOp, a: f32, b: f32) -> f32 {
    let (r, fault) = run1(
        &[Type::F32, Type::F32],
        Some(Type::F32),
        &[f32b(a), f32b(b)],
        |b, p| {
            let v = b.binary(op, p[0], p[1]);
            b.ret(Some(v));
        },
    );
    assert!(!fault);
    f32::from_bits(r.unwrap().unwrap() as u32)
}

fn f64_bin(op: BinaryOp, a: f64, b: f64) -> f64 {
    let (r, _) = run1(
        &[Type::F64, Type::F64],
        Some(Type::F64),
        &[f64b(a), f64b(b)],
        |b, p| {
            let v = b.binary(op, p[0], p[1]);
            b.ret(Some(v));
        },
    );
    f64::from_bits(r.unwrap().unwrap())
}

fn min(ty: Type) -> i64 {
    ty.canon_int(1i64 << (ty.bits() - 1))
}

fn max(ty: Type) -> i64 {
    !min(ty)
}

#[test]
fn integer_arithmetic_wraps() {
    assert_eq!(bin(BinaryOp::Iadd, Type::I8, 127, 1), (-128, false));
    assert_eq!(bin(BinaryOp::Isub, Type::I16, -32768, 1), (32767, false));
    assert_eq!(bin(BinaryOp::Imul, Type::I32, 0x10000, 0x10000), (0, false));
    assert_eq!(bin(BinaryOp::Imul, Type::I64, i64::MAX, 2), (-2, false));
    assert_eq!(bin(BinaryOp::Iadd, Type::I1, 1, 1), (0, false));
    assert_eq!(bin(BinaryOp::Band, Type::I8, -1, 0x0F), (0x0F, false));
    assert_eq!(bin(BinaryOp::Bor, Type::I1, 0, 1), (1, false));
    assert_eq!(bin(BinaryOp::Bxor, Type::I16, -1, 1), (-2, false));
    for ty in INTS {
        assert_eq!(
            un(UnaryOp::Ineg, ty, min(ty) as u64) as i64,
            min(ty),
            "{ty}"
        );
        assert_eq!(
            un(UnaryOp::Iabs, ty, min(ty) as u64) as i64,
            min(ty),
            "{ty}"
        );
        assert_eq!(un(UnaryOp::Iabs, ty, -5i64 as u64) as i64, 5);
        assert_eq!(un(UnaryOp::Ineg, ty, 5) as i64, -5);
        assert_eq!(un(UnaryOp::Bnot, ty, 0) as i64, -1);
    }
    assert_eq!(un(UnaryOp::Bnot, Type::I1, 0), 1);
    assert_eq!(un(UnaryOp::Bnot, Type::I1, 1), 0);
}

#[test]
fn division_by_zero_gives_zero_and_faults() {
    for ty in INTS.into_iter().chain([Type::I1]) {
        for op in [
            BinaryOp::Sdiv,
            BinaryOp::Udiv,
            BinaryOp::Srem,
            BinaryOp::Urem,
        ] {
            assert_eq!(bin(op, ty, 7 & max(ty).max(1), 0), (0, true), "{ty} {op:?}");
        }
    }
    assert_eq!(bin(BinaryOp::Sdiv, Type::I32, 7, 2), (3, false));
}

#[test]
fn signed_division_edge_cases() {
    for ty in INTS {
        assert_eq!(
            bin(BinaryOp::Sdiv, ty, min(ty), -1),
            (min(ty), false),
            "{ty}"
        );
        assert_eq!(bin(BinaryOp::Srem, ty, min(ty), -1), (0, false), "{ty}");
        assert_eq!(bin(BinaryOp::Srem, ty, 5, -1), (0, false));
        assert_eq!(bin(BinaryOp::Sdiv, ty, -7, 2), (-3, false));
        assert_eq!(bin(BinaryOp::Srem, ty, -7, 2), (-1, false));
        assert_eq!(bin(BinaryOp::Srem, ty, 7, -2), (1, false));
        // Unsigned readings of negative registers.
        assert_eq!(bin(BinaryOp::Udiv, ty, -1, 2), (max(ty), false));
        assert_eq!(bin(BinaryOp::Urem, ty, -1, 16), (15, false));
    }
    assert_eq!(bin(BinaryOp::Udiv, Type::I8, -2, 3), (84, false)); // 254 / 3
}

#[test]
fn shifts_by_width_and_more() {
    for ty in INTS {
        let w = ty.bits() as i64;
        assert_eq!(bin(BinaryOp::Ishl, ty, 1, w - 1).0, min(ty), "{ty}");
        for c in [w, w + 1, 200, -1] {
            assert_eq!(bin(BinaryOp::Ishl, ty, 1, c).0, 0, "{ty} ishl {c}");
            assert_eq!(bin(BinaryOp::Ushr, ty, -1, c).0, 0, "{ty} ushr {c}");
            assert_eq!(bin(BinaryOp::Sshr, ty, -8, c).0, -1, "{ty} sshr {c}");
            assert_eq!(bin(BinaryOp::Sshr, ty, 8, c).0, 0, "{ty} sshr {c}");
        }
        assert_eq!(bin(BinaryOp::Ushr, ty, -1, 1).0, max(ty), "{ty}");
        assert_eq!(bin(BinaryOp::Sshr, ty, -8, 1).0, -4);
        assert_eq!(bin(BinaryOp::Ishl, ty, 3, 0).0, 3);
    }
    // 8, 16, 32 and 64 are each "the width" of one type and a normal count of wider ones.
    assert_eq!(bin(BinaryOp::Ishl, Type::I16, 1, 8).0, 256);
    assert_eq!(bin(BinaryOp::Ishl, Type::I32, 1, 16).0, 65536);
    assert_eq!(bin(BinaryOp::Ishl, Type::I64, 1, 32).0, 1 << 32);
    assert_eq!(bin(BinaryOp::Ushr, Type::I64, i64::MIN, 63).0, 1);
}

#[test]
fn rotates_modulo_width() {
    assert_eq!(
        bin(BinaryOp::Rotl, Type::I8, 0x81u8 as i8 as i64, 1).0,
        0x03
    );
    assert_eq!(
        bin(BinaryOp::Rotl, Type::I8, 0x81u8 as i8 as i64, 9).0,
        0x03
    );
    assert_eq!(
        bin(BinaryOp::Rotr, Type::I8, 0x81u8 as i8 as i64, 9).0,
        0xC0u8 as i8 as i64
    );
    for ty in INTS {
        let w = ty.bits() as i64;
        let x = min(ty) | 1; // 100…001
        let once_l = bin(BinaryOp::Rotl, ty, x, 1).0;
        assert_eq!(once_l, 3, "{ty}");
        assert_eq!(bin(BinaryOp::Rotl, ty, x, w + 1).0, once_l, "{ty}");
        assert_eq!(bin(BinaryOp::Rotl, ty, x, w).0, x, "{ty}");
        assert_eq!(bin(BinaryOp::Rotl, ty, x, 0).0, x, "{ty}");
        let once_r = bin(BinaryOp::Rotr, ty, x, 1).0;
        assert_eq!(once_r, ty.canon_int(3i64 << (w - 2)), "{ty}");
        assert_eq!(bin(BinaryOp::Rotr, ty, x, w + 1).0, once_r, "{ty}");
        // A negative count is a large unsigned one: -1 mod w = w - 1.
        assert_eq!(bin(BinaryOp::Rotl, ty, x, -1).0, once_r, "{ty}");
    }
}

#[test]
fn integer_comparisons_at_width() {
    assert!(icmp(IntCC::Slt, Type::I8, -1, 1));
    assert!(!icmp(IntCC::Ult, Type::I8, -1, 1));
    assert!(icmp(IntCC::Ugt, Type::I16, -1, 32767));
    assert!(icmp(IntCC::Uge, Type::I32, -1, -1));
    assert!(icmp(IntCC::Sle, Type::I64, i64::MIN, 0));
    assert!(!icmp(IntCC::Ule, Type::I64, i64::MIN, 0));
    assert!(icmp(IntCC::Eq, Type::I32, -5, -5));
    assert!(icmp(IntCC::Ne, Type::I32, -5, 5));
    assert!(icmp(IntCC::Sgt, Type::I8, 127, -128));
    assert!(icmp(IntCC::Sge, Type::I8, 0, 0));
    assert!(icmp(IntCC::Ult, Type::Ptr, 16, 24));
    assert!(icmp(IntCC::Ult, Type::I1, 0, 1));
}

#[test]
fn f32_rounds_as_binary32() {
    assert_eq!(f32_bin(BinaryOp::Fadd, 16777216.0, 1.0), 16777216.0);
    assert_eq!(
        f32_bin(BinaryOp::Fadd, 0.1, 0.2).to_bits(),
        (0.1f32 + 0.2f32).to_bits()
    );
    assert_eq!(
        f32_bin(BinaryOp::Fdiv, 1.0, 3.0).to_bits(),
        (1.0f32 / 3.0).to_bits()
    );
    assert_eq!(f32_bin(BinaryOp::Fmul, 1e20, 1e20), f32::INFINITY);
    assert_eq!(f32_bin(BinaryOp::Fsub, 1.0, 1e-8), 1.0);
    assert_eq!(f64_bin(BinaryOp::Fadd, 16777216.0, 1.0), 16777217.0);
    assert_eq!(f64_bin(BinaryOp::Fmul, 1e20, 1e20), 1e40);
    // Division by zero is IEEE, and not a fault.
    assert_eq!(f32_bin(BinaryOp::Fdiv, 1.0, 0.0), f32::INFINITY);
    assert_eq!(f32_bin(BinaryOp::Fdiv, -1.0, 0.0), f32::NEG_INFINITY);
    assert!(f64_bin(BinaryOp::Fdiv, 0.0, 0.0).is_nan());
    assert_eq!(f32_bin(BinaryOp::Fpow, 2.0, 10.0), 1024.0);
    assert_eq!(
        f32_bin(BinaryOp::Fpow, 1.1, 2.5).to_bits(),
        1.1f32.powf(2.5).to_bits()
    );
    assert_eq!(f64_bin(BinaryOp::Fpow, 1.1, 2.5), 1.1f64.powf(2.5));
    assert_eq!(
        f32_bin(BinaryOp::Fatan2, 1.0, -1.0).to_bits(),
        1.0f32.atan2(-1.0).to_bits()
    );
    assert_eq!(f64_bin(BinaryOp::Fatan2, -1.0, -1.0), (-1.0f64).atan2(-1.0));
}

type F32Fn = fn(f32) -> f32;
type F64Fn = fn(f64) -> f64;

#[test]
fn float_unary_operations() {
    let u32f = |op, x: f32| f32::from_bits(un(op, Type::F32, f32b(x)) as u32);
    let u64f = |op, x: f64| f64::from_bits(un(op, Type::F64, f64b(x)));
    for (x, want) in [
        (0.5f32, 0.0f64),
        (1.5, 2.0),
        (2.5, 2.0),
        (-2.5, -2.0),
        (3.5, 4.0),
        (-0.4, -0.0),
    ] {
        assert_eq!(
            u32f(UnaryOp::Fnearest, x).to_bits(),
            (want as f32).to_bits(),
            "{x}"
        );
        assert_eq!(
            u64f(UnaryOp::Fnearest, x as f64).to_bits(),
            want.to_bits(),
            "{x}"
        );
    }
    assert_eq!(u32f(UnaryOp::Fnearest, 8388609.0), 8388609.0);
    assert_eq!(u32f(UnaryOp::Ftrunc, -1.5), -1.0);
    assert_eq!(u32f(UnaryOp::Ffloor, -1.5), -2.0);
    assert_eq!(u32f(UnaryOp::Fceil, -1.5), -1.0);
    assert_eq!(u64f(UnaryOp::Fceil, 1.2), 2.0);
    assert_eq!(u32f(UnaryOp::Fneg, 0.0).to_bits(), (-0.0f32).to_bits());
    assert_eq!(u64f(UnaryOp::Fabs, -3.0), 3.0);
    assert!(u32f(UnaryOp::Fsqrt, -1.0).is_nan());
    assert_eq!(u32f(UnaryOp::Fsqrt, 2.0).to_bits(), 2.0f32.sqrt().to_bits());
    let cases32: [(UnaryOp, F32Fn); 9] = [
        (UnaryOp::Sin, f32::sin),
        (UnaryOp::Cos, f32::cos),
        (UnaryOp::Tan, f32::tan),
        (UnaryOp::Asin, f32::asin),
        (UnaryOp::Acos, f32::acos),
        (UnaryOp::Atan, f32::atan),
        (UnaryOp::Ln, f32::ln),
        (UnaryOp::Log10, f32::log10),
        (UnaryOp::Exp, f32::exp),
    ];
    for (op, f) in cases32 {
        assert_eq!(u32f(op, 0.3).to_bits(), f(0.3).to_bits(), "{op:?}");
    }
    let cases64: [(UnaryOp, F64Fn); 9] = [
        (UnaryOp::Sin, f64::sin),
        (UnaryOp::Cos, f64::cos),
        (UnaryOp::Tan, f64::tan),
        (UnaryOp::Asin, f64::asin),
        (UnaryOp::Acos, f64::acos),
        (UnaryOp::Atan, f64::atan),
        (UnaryOp::Ln, f64::ln),
        (UnaryOp::Log10, f64::log10),
        (UnaryOp::Exp, f64::exp),
    ];
    for (op, f) in cases64 {
        assert_eq!(u64f(op, 0.3).to_bits(), f(0.3).to_bits(), "{op:?}");
    }
    assert!(u64f(UnaryOp::Ln, -1.0).is_nan());
}

#[test]
fn float_comparisons_and_nan() {
    let cmp = |cc, ty: Type, a: f64, b: f64| {
        let bits = |x: f64| {
            if ty == Type::F32 {
                f32b(x as f32)
            } else {
                f64b(x)
            }
        };
        let (r, _) = run1(&[ty, ty], Some(Type::I1), &[bits(a), bits(b)], |b, p| {
            let v = b.fcmp(cc, p[0], p[1]);
            b.ret(Some(v));
        });
        r.unwrap().unwrap() == 1
    };
    for ty in [Type::F32, Type::F64] {
        for (a, b) in [(f64::NAN, 1.0), (1.0, f64::NAN), (f64::NAN, f64::NAN)] {
            assert!(cmp(FloatCC::Ne, ty, a, b));
            for cc in [
                FloatCC::Eq,
                FloatCC::Lt,
                FloatCC::Le,
                FloatCC::Gt,
                FloatCC::Ge,
            ] {
                assert!(!cmp(cc, ty, a, b), "{ty} {cc:?}");
            }
        }
        assert!(cmp(FloatCC::Eq, ty, 0.0, -0.0));
        assert!(cmp(FloatCC::Lt, ty, -1.0, 1.0));
        assert!(cmp(FloatCC::Le, ty, 1.0, 1.0));
        assert!(cmp(FloatCC::Gt, ty, f64::INFINITY, 1e30));
        assert!(cmp(FloatCC::Ge, ty, 2.0, 1.0));
        assert!(!cmp(FloatCC::Ne, ty, 2.0, 2.0));
    }
}

#[test]
fn float_to_int_saturates_truncates_and_nan_is_zero() {
    for from in [Type::F32, Type::F64] {
        let bits = |x: f64| {
            if from == Type::F32 {
                f32b(x as f32)
            } else {
                f64b(x)
            }
        };
        for to in INTS {
            let si = |x: f64| conv(ConvOp::FToSi, from, to, bits(x)) as i64;
            let ui = |x: f64| to.zext_bits(conv(ConvOp::FToUi, from, to, bits(x)) as i64);
            let umax = to.zext_bits(-1);
            assert_eq!(si(1e30), max(to), "{from}->{to}");
            assert_eq!(si(-1e30), min(to), "{from}->{to}");
            assert_eq!(si(f64::INFINITY), max(to));
            assert_eq!(si(f64::NEG_INFINITY), min(to));
            assert_eq!(si(f64::NAN), 0);
            assert_eq!(si(2.9), 2);
            assert_eq!(si(-2.9), -2);
            assert_eq!(si(-0.5), 0);
            assert_eq!(ui(1e30), umax, "{from}->{to}");
            assert_eq!(ui(f64::INFINITY), umax);
            assert_eq!(ui(f64::NAN), 0);
            assert_eq!(ui(-1.0), 0);
            assert_eq!(ui(-0.9), 0);
            assert_eq!(ui(f64::NEG_INFINITY), 0);
            assert_eq!(ui(3.99), 3);
        }
        // Just outside and inside the narrow ranges.
        let si8 = |x: f64| conv(ConvOp::FToSi, from, Type::I8, bits(x)) as i64;
        assert_eq!(si8(127.9), 127);
        assert_eq!(si8(128.0), 127);
        assert_eq!(si8(-128.9), -128);
        assert_eq!(si8(-129.0), -128);
        let ui8 = |x: f64| conv(ConvOp::FToUi, from, Type::I8, bits(x)) as u8;
        assert_eq!(ui8(255.5), 255);
        assert_eq!(ui8(256.0), 255);
        let si16 = |x: f64| conv(ConvOp::FToSi, from, Type::I16, bits(x)) as i64;
        assert_eq!(si16(40000.0), 32767);
        assert_eq!(si16(-40000.0), -32768);
    }
    let si32 = |x: f64| conv(ConvOp::FToSi, Type::F64, Type::I32, f64b(x)) as i64;
    assert_eq!(si32(2147483647.9), 2147483647);
    assert_eq!(si32(-2147483648.9), -2147483648);
    let ui32 = |x: f64| conv(ConvOp::FToUi, Type::F64, Type::I32, f64b(x)) as u32;
    assert_eq!(ui32(4294967295.5), u32::MAX);
    let si64 = |x: f64| conv(ConvOp::FToSi, Type::F64, Type::I64, f64b(x)) as i64;
    assert_eq!(si64(9.3e18), i64::MAX);
    assert_eq!(si64(-9.3e18), i64::MIN);
    assert_eq!(si64(-9223372036854775808.0), i64::MIN);
}

#[test]
fn int_to_float_rounds_to_nearest_even() {
    let c = |op, from, to, a: i64| conv(op, from, to, a as u64);
    // 2^53 + 1 is a tie between 2^53 and 2^53 + 2: even wins.
    assert_eq!(
        c(ConvOp::SiToF, Type::I64, Type::F64, (1 << 53) + 1),
        f64b(9007199254740992.0)
    );
    assert_eq!(
        c(ConvOp::SiToF, Type::I64, Type::F64, (1 << 53) + 3),
        f64b(9007199254740996.0)
    );
    assert_eq!(
        c(ConvOp::SiToF, Type::I32, Type::F32, 16777217),
        f32b(16777216.0)
    );
    assert_eq!(
        c(ConvOp::SiToF, Type::I32, Type::F32, 16777219),
        f32b(16777220.0)
    );
    assert_eq!(c(ConvOp::SiToF, Type::I8, Type::F32, -1), f32b(-1.0));
    assert_eq!(c(ConvOp::UiToF, Type::I8, Type::F32, -1), f32b(255.0));
    assert_eq!(
        c(ConvOp::UiToF, Type::I32, Type::F64, -1),
        f64b(4294967295.0)
    );
    assert_eq!(
        c(ConvOp::UiToF, Type::I64, Type::F64, -1),
        f64b(18446744073709551615.0)
    );
    assert_eq!(
        c(ConvOp::UiToF, Type::I64, Type::F32, -1),
        f32b(18446744073709551615.0)
    );
    assert_eq!(c(ConvOp::UiToF, Type::I1, Type::F64, 1), f64b(1.0));
    assert_eq!(
        c(ConvOp::SiToF, Type::I64, Type::F32, i64::MIN),
        f32b(-9.223372e18)
    );
}

#[test]
fn integer_and_float_width_conversions() {
    let c = |op, from, to, a: i64| conv(op, from, to, a as u64) as i64;
    assert_eq!(c(ConvOp::Sext, Type::I8, Type::I32, -1), -1);
    assert_eq!(c(ConvOp::Uext, Type::I8, Type::I32, -1), 255);
    assert_eq!(c(ConvOp::Uext, Type::I16, Type::I64, -2), 65534);
    assert_eq!(c(ConvOp::Uext, Type::I32, Type::I64, -1), 0xFFFF_FFFF);
    assert_eq!(
        c(ConvOp::Sext, Type::I32, Type::I64, i32::MIN as i64),
        i32::MIN as i64
    );
    assert_eq!(c(ConvOp::Uext, Type::I1, Type::I32, 1), 1);
    // i1 read signed is a one-bit two's complement number.
    assert_eq!(c(ConvOp::Sext, Type::I1, Type::I8, 1), -1);
    assert_eq!(c(ConvOp::Itrunc, Type::I32, Type::I8, 0x1FF), -1);
    assert_eq!(c(ConvOp::Itrunc, Type::I64, Type::I16, 0x1_8000), -32768);
    assert_eq!(c(ConvOp::Itrunc, Type::I32, Type::I1, 2), 0);
    assert_eq!(c(ConvOp::Itrunc, Type::I32, Type::I1, 3), 1);
    assert_eq!(
        conv(ConvOp::Fdemote, Type::F64, Type::F32, f64b(0.1)),
        f32b(0.1)
    );
    assert_eq!(
        conv(ConvOp::Fdemote, Type::F64, Type::F32, f64b(1e300)),
        f32b(f32::INFINITY)
    );
    // 1 + 2^-24 is a tie between 1 and 1 + 2^-23: even (1) wins.
    assert_eq!(
        conv(
            ConvOp::Fdemote,
            Type::F64,
            Type::F32,
            f64b(1.0 + 2f64.powi(-24))
        ),
        f32b(1.0)
    );
    assert_eq!(
        conv(ConvOp::Fpromote, Type::F32, Type::F64, f32b(0.1)),
        f64b(0.1f32 as f64)
    );
    assert_eq!(
        conv(ConvOp::Bitcast, Type::F32, Type::I32, f32b(1.0)),
        0x3F80_0000
    );
    assert_eq!(
        conv(ConvOp::Bitcast, Type::F32, Type::I32, f32b(-0.0)) as i64,
        i32::MIN as i64
    );
    assert_eq!(
        conv(ConvOp::Bitcast, Type::I32, Type::F32, -1i64 as u64),
        0xFFFF_FFFF
    );
    assert_eq!(
        conv(ConvOp::Bitcast, Type::F64, Type::I64, f64b(-2.0)),
        f64b(-2.0)
    );
    assert_eq!(
        conv(ConvOp::Bitcast, Type::I64, Type::F64, f64b(3.5)),
        f64b(3.5)
    );
}

#[test]
fn select_picks_by_condition() {
    for (c, want) in [(1u64, 10u64), (0, 20)] {
        let (r, _) = run1(&[Type::I1], Some(Type::I64), &[c], |b, p| {
            let x = b.iconst(Type::I64, 10);
            let y = b.iconst(Type::I64, 20);
            let v = b.select(p[0], x, y);
            b.ret(Some(v));
        });
        assert_eq!(r.unwrap(), Some(want));
    }
}

#[test]
fn constants_are_canonical() {
    let (r, _) = run1(&[], Some(Type::I8), &[], |b, _| {
        let v = b.iconst(Type::I8, 0xFF);
        b.ret(Some(v));
    });
    assert_eq!(r.unwrap(), Some(-1i64 as u64));
    let (r, _) = run1(&[], Some(Type::F32), &[], |b, _| {
        let v = b.f32const(-1.5);
        b.ret(Some(v));
    });
    assert_eq!(r.unwrap(), Some(f32b(-1.5)));
}

/// `swap(n, a, b)`: n times `(a, b) = (b, a)` through block parameters, then `a*10+b`.
#[test]
fn block_arguments_are_parallel_copies() {
    for (n, want) in [(0u64, 12u64), (1, 21), (2, 12), (5, 21)] {
        let (r, _) = run1(&[Type::I32], Some(Type::I32), &[n], |b, p| {
            let head = b.create_block();
            let i = b.block_param(head, Type::I32);
            let x = b.block_param(head, Type::I32);
            let y = b.block_param(head, Type::I32);
            let body = b.create_block();
            let exit = b.create_block();
            let one = b.iconst(Type::I32, 1);
            let two = b.iconst(Type::I32, 2);
            b.jump(head, vec![p[0], one, two]);
            b.switch_to(head);
            let zero = b.iconst(Type::I32, 0);
            let done = b.icmp(IntCC::Eq, i, zero);
            b.brif(done, exit, vec![], body, vec![]);
            b.switch_to(body);
            let one = b.iconst(Type::I32, 1);
            let i2 = b.binary(BinaryOp::Isub, i, one);
            b.jump(head, vec![i2, y, x]);
            b.switch_to(exit);
            let ten = b.iconst(Type::I32, 10);
            let t = b.binary(BinaryOp::Imul, x, ten);
            let s = b.binary(BinaryOp::Iadd, t, y);
            b.ret(Some(s));
        });
        assert_eq!(r.unwrap(), Some(want), "n = {n}");
    }
}

#[test]
fn calls_pass_arguments_and_results() {
    let mut m = Module::new();
    let add3 = func(&mut m, "add3", &[Type::I32; 3], Some(Type::I32), |b, p| {
        let s = b.binary(BinaryOp::Iadd, p[0], p[1]);
        let s = b.binary(BinaryOp::Iadd, s, p[2]);
        b.ret(Some(s));
    });
    let nothing = func(&mut m, "nothing", &[], None, |b, _| b.ret(None));
    let top = func(&mut m, "top", &[Type::I32], Some(Type::I32), |b, p| {
        let one = b.iconst(Type::I32, 1);
        let a = b.call(add3, Some(Type::I32), vec![p[0], one, one]).unwrap();
        b.call(nothing, None, vec![]);
        b.call(add3, Some(Type::I32), vec![one, one, one]); // result unused
        let r = b.call(add3, Some(Type::I32), vec![a, a, p[0]]).unwrap();
        b.ret(Some(r));
    });
    let mut it = Interp::new(&m).unwrap();
    assert_eq!(it.call(top, &[5]).unwrap(), Some(7 + 7 + 5));
    assert_eq!(it.call(add3, &[1, 2, 3]).unwrap(), Some(6));
    assert!(it.call(add3, &[1]).is_err());
}

#[test]
fn slots_are_per_call_and_start_as_garbage() {
    let mut m = Module::new();
    // inner(x) stores x in its own slot, returns what it loads back.
    let inner = func(&mut m, "inner", &[Type::I32], Some(Type::I32), |b, p| {
        let s = b.slot("t", MemType::Scalar(Type::I32));
        let a = b.slot_addr(s);
        b.store(p[0], a);
        let v = b.load(Type::I32, a);
        b.ret(Some(v));
    });
    // outer: its slot keeps 7 across a call to inner(9).
    let outer = func(&mut m, "outer", &[], Some(Type::I32), |b, _| {
        let s = b.slot("t", MemType::Scalar(Type::I32));
        let a = b.slot_addr(s);
        let seven = b.iconst(Type::I32, 7);
        b.store(seven, a);
        let nine = b.iconst(Type::I32, 9);
        let r = b.call(inner, Some(Type::I32), vec![nine]).unwrap();
        let v = b.load(Type::I32, a);
        let s = b.binary(BinaryOp::Iadd, r, v);
        b.ret(Some(s));
    });
    let fresh = func(&mut m, "fresh", &[], Some(Type::I32), |b, _| {
        let s = b.slot("t", MemType::Scalar(Type::I32));
        let a = b.slot_addr(s);
        let v = b.load(Type::I32, a);
        b.ret(Some(v));
    });
    let fresh_bool = func(&mut m, "fresh_bool", &[], Some(Type::I1), |b, _| {
        let s = b.slot("t", MemType::Scalar(Type::I1));
        let a = b.slot_addr(s);
        let v = b.load(Type::I1, a);
        b.ret(Some(v));
    });
    let mut it = Interp::new(&m).unwrap();
    assert_eq!(it.call(outer, &[]).unwrap(), Some(16));
    assert_eq!(
        it.call(fresh, &[]).unwrap(),
        Some(0xA5A5_A5A5u32 as i32 as i64 as u64)
    );
    let e = it.call(fresh_bool, &[]).unwrap_err();
    assert!(
        e.0.contains("not 0 or 1") && e.0.contains("@fresh_bool"),
        "{e}"
    );
}

#[test]
fn memory_errors_are_errors_not_panics() {
    let mut m = Module::new();
    let g = m.add_data(DataDef {
        name: "g".into(),
        ty: MemType::Scalar(Type::I64),
        elem: Some(ElemType::LInt),
        kind: DataKind::Global,
        location: None,
    });
    let load_at = func(&mut m, "load_at", &[Type::Ptr], Some(Type::I32), |b, p| {
        let v = b.load(Type::I32, p[0]);
        b.ret(Some(v));
    });
    let store_at = func(&mut m, "store_at", &[Type::Ptr], None, |b, p| {
        let v = b.iconst(Type::I64, 1);
        b.store(v, p[0]);
        b.ret(None);
    });
    // Returns the address of its slot, which is dead once it returns.
    let leak = func(&mut m, "leak", &[], Some(Type::Ptr), |b, _| {
        let s = b.slot("t", MemType::Scalar(Type::I32));
        let a = b.slot_addr(s);
        let v = b.iconst(Type::I32, 1);
        b.store(v, a);
        b.ret(Some(a));
    });
    let dangling = func(&mut m, "dangling", &[], Some(Type::I32), |b, _| {
        let a = b.call(leak, Some(Type::Ptr), vec![]).unwrap();
        let v = b.load(Type::I32, a);
        b.ret(Some(v));
    });
    let mut it = Interp::new(&m).unwrap();
    let ga = it.data_addr(g).unwrap();
    assert_eq!(it.call(store_at, &[ga]).unwrap(), None);
    assert_eq!(it.call(load_at, &[ga]).unwrap(), Some(1));
    for addr in [0, 4, ga + 2, u64::MAX - 1, u64::MAX - 3, 1 << 40] {
        let e = it.call(load_at, &[addr]).unwrap_err();
        assert!(e.0.contains("load.i32") && e.0.contains("@load_at"), "{e}");
    }
    let e = it.call(store_at, &[ga + 4]).unwrap_err();
    assert!(e.0.contains("misaligned") && e.0.contains("store"), "{e}");
    let e = it.call(dangling, &[]).unwrap_err();
    assert!(
        e.0.contains("outside memory") && e.0.contains("@dangling"),
        "{e}"
    );
}

#[test]
fn recursion_hits_the_call_depth_limit() {
    let mut m = Module::new();
    let mut f = Function::new("forever", FuncKind::Function, vec![], None);
    {
        let mut b = FuncBuilder::new(&mut f);
        b.call(FuncId::new(0), None, vec![]);
        b.ret(None);
    }
    let id = m.add_func(f);
    let mut it = Interp::new(&m).unwrap();
    let e = it.call(id, &[]).unwrap_err();
    assert!(e.0.contains("call depth"), "{e}");
}

#[test]
fn step_limit_stops_infinite_loops() {
    let mut m = Module::new();
    let f = func(&mut m, "spin", &[], None, |b, _| {
        let l = b.create_block();
        b.jump(l, vec![]);
        b.switch_to(l);
        b.jump(l, vec![]);
    });
    let mut it = Interp::new(&m).unwrap();
    it.set_step_limit(Some(1000));
    let e = it.call(f, &[]).unwrap_err();
    assert!(
        e.0.contains("step limit exceeded") && e.0.contains("@spin"),
        "{e}"
    );
    assert_eq!(it.steps(), 1001);
}

#[test]
fn malformed_code_fails_only_when_run() {
    let mut m = Module::new();
    let f = func(&mut m, "f", &[Type::I1], Some(Type::I32), |b, p| {
        let good = b.create_block();
        let bad = b.create_block();
        b.brif(p[0], good, vec![], bad, vec![]);
        b.switch_to(good);
        let v = b.iconst(Type::I32, 1);
        b.ret(Some(v));
        b.switch_to(bad);
        let x = b.iconst(Type::I32, 1);
        let y = b.f32const(1.0);
        b.binary(BinaryOp::Iadd, x, y); // mismatched operand types
        b.ret(Some(x));
    });
    let g = func(&mut m, "g", &[], None, |b, _| {
        b.iconst(Type::I32, 1); // no terminator
    });
    let mut it = Interp::new(&m).unwrap();
    assert_eq!(it.call(f, &[1]).unwrap(), Some(1));
    let e = it.call(f, &[0]).unwrap_err();
    assert!(e.0.contains("one type") && e.0.contains("iadd"), "{e}");
    let e = it.call(g, &[]).unwrap_err();
    assert!(e.0.contains("without a terminator"), "{e}");
}

/// `%T = { x: INT, y: LREAL }`, `%ta = [3 x %T] lower 1`, `%grid = [2 x [3 x DINT]]`,
/// `%P = { flag: BOOL, count: DINT, ts: %ta, grid: %grid, t: TIME, ns: LTIME }`.
struct Fixture {
    m: Module,
    t: AggId,
    ta: AggId,
    row: AggId,
    grid: AggId,
    p: AggId,
    main: DataId,
}

fn field(name: &str, ty: MemType, elem: Option<ElemType>) -> Field {
    Field {
        name: name.into(),
        ty,
        elem,
        role: FieldRole::Var,
        location: None,
    }
}

fn fixture() -> Fixture {
    let mut m = Module::new();
    let t = m.add_agg(AggDef::Struct(StructDef {
        name: "T".into(),
        kind: StructKind::Struct,
        fields: vec![
            field("x", MemType::Scalar(Type::I16), Some(ElemType::Int)),
            field("y", MemType::Scalar(Type::F64), Some(ElemType::LReal)),
        ],
    }));
    let ta = m.add_agg(AggDef::Array(ArrayDef {
        name: "ta".into(),
        elem: MemType::Agg(t),
        elem_type: None,
        len: 3,
        lower: 1,
    }));
    let row = m.add_agg(AggDef::Array(ArrayDef {
        name: "row".into(),
        elem: MemType::Scalar(Type::I32),
        elem_type: Some(ElemType::DInt),
        len: 3,
        lower: 0,
    }));
    let grid = m.add_agg(AggDef::Array(ArrayDef {
        name: "grid".into(),
        elem: MemType::Agg(row),
        elem_type: None,
        len: 2,
        lower: 0,
    }));
    let p = m.add_agg(AggDef::Struct(StructDef {
        name: "P".into(),
        kind: StructKind::Program,
        fields: vec![
            field("flag", MemType::Scalar(Type::I1), Some(ElemType::Bool)),
            field("count", MemType::Scalar(Type::I32), Some(ElemType::DInt)),
            field("ts", MemType::Agg(ta), None),
            field("grid", MemType::Agg(grid), None),
            field("t", MemType::Scalar(Type::I32), Some(ElemType::Time)),
            field("ns", MemType::Scalar(Type::I64), Some(ElemType::LTime)),
        ],
    }));
    let main = m.add_data(DataDef {
        name: "main".into(),
        ty: MemType::Agg(p),
        elem: None,
        kind: DataKind::Program,
        location: None,
    });
    Fixture {
        m,
        t,
        ta,
        row,
        grid,
        p,
        main,
    }
}

impl Fixture {
    /// Adds `main` as a program with the given body and an init that zeroes `flag` and
    /// `count` (and leaves the rest to the body).
    fn program(&mut self, body: impl FnOnce(&mut FuncBuilder, Value, &Fixture)) {
        let mut f = Function::new("main$body", FuncKind::ProgramBody, vec![Type::Ptr], None);
        {
            let mut b = FuncBuilder::new(&mut f);
            let inst = b.params()[0];
            body(&mut b, inst, self);
            b.ret(None);
        }
        let body = self.m.add_func(f);
        let p = self.p;
        let init = func(&mut self.m, "main$init", &[Type::Ptr], None, |b, a| {
            let flag = b.field_addr(a[0], p, 0);
            let f = b.iconst(Type::I1, 0);
            b.store(f, flag);
            let count = b.field_addr(a[0], p, 1);
            let z = b.iconst(Type::I32, 0);
            b.store(z, count);
            b.ret(None);
        });
        self.m.programs.push(ProgramEntry {
            name: "main".into(),
            data: self.main,
            body,
            init,
            interval_us: None,
            priority: None,
        });
    }
}

#[test]
fn cold_start_and_scans_keep_state() {
    let mut fx = fixture();
    fx.program(|b, inst, fx| {
        let c = b.field_addr(inst, fx.p, 1);
        let v = b.load(Type::I32, c);
        let one = b.iconst(Type::I32, 1);
        let v = b.binary(BinaryOp::Iadd, v, one);
        b.store(v, c);
        let flag = b.field_addr(inst, fx.p, 0);
        let f = b.load(Type::I1, flag);
        let nf = b.unary(UnaryOp::Bnot, f);
        b.store(nf, flag);
    });
    let mut it = Interp::new(&fx.m).unwrap();
    assert_eq!(it.target(), "interp");
    it.cold_start().unwrap();
    assert_eq!(
        it.read("main.count").unwrap(),
        PlcValue::from_i64(ElemType::DInt, 0)
    );
    // Not initialised by init: still the garbage pattern.
    assert_eq!(it.read("MAIN.T").unwrap().bits, 0xA5A5_A5A5);
    for _ in 0..1000 {
        it.scan().unwrap();
    }
    assert_eq!(it.read("main.count").unwrap().as_i64(), 1000);
    assert_eq!(it.read("main.flag").unwrap(), PlcValue::from_bool(false));
    it.scan().unwrap();
    assert_eq!(it.read("main.flag").unwrap(), PlcValue::from_bool(true));
    it.cold_start().unwrap();
    assert_eq!(it.read("main.count").unwrap().as_i64(), 0);
}

#[test]
fn nested_aggregates_and_paths() {
    let mut fx = fixture();
    // main.ts[3].y := 2.5 (zero-based 2); main.grid[1][2] := -7; main.ts[1].x := count.
    fx.program(|b, inst, fx| {
        let ts = b.field_addr(inst, fx.p, 2);
        let two = b.iconst(Type::I32, 2);
        let e = b.elem_addr(ts, fx.ta, two);
        let y = b.field_addr(e, fx.t, 1);
        let v = b.f64const(2.5);
        b.store(v, y);
        let grid = b.field_addr(inst, fx.p, 3);
        let one = b.iconst(Type::I64, 1);
        let r = b.elem_addr(grid, fx.grid, one);
        let two = b.iconst(Type::I8, 2);
        let c = b.elem_addr(r, fx.row, two);
        let v = b.iconst(Type::I32, -7);
        b.store(v, c);
        let cnt = b.field_addr(inst, fx.p, 1);
        let n = b.load(Type::I32, cnt);
        let n = b.convert(ConvOp::Itrunc, Type::I16, n);
        let zero = b.iconst(Type::I16, 0);
        let e0 = b.elem_addr(ts, fx.ta, zero);
        let x = b.field_addr(e0, fx.t, 0);
        b.store(n, x);
    });
    let mut it = Interp::new(&fx.m).unwrap();
    // Natural layout: flag@0, count@4, ts@8 (3 x 16), grid@56 (2 x 12), t@80, ns@88.
    assert_eq!(it.layout().field_offset(fx.p, 2), 8);
    assert_eq!(it.layout().field_offset(fx.p, 3), 56);
    assert_eq!(it.layout().stride(fx.ta), 16);
    let base = it.data_addr(fx.main).unwrap();
    assert_eq!(base % 8, 0);
    assert!(base >= DATA_BASE);
    assert_eq!(it.field_addr(base, fx.p, 5), base + 88);
    it.cold_start().unwrap();
    it.write("main.count", PlcValue::from_i64(ElemType::DInt, 300))
        .unwrap();
    it.scan().unwrap();
    assert_eq!(it.read("main.ts[3].y").unwrap(), PlcValue::from_f64(2.5));
    assert_eq!(it.read("main.grid[1][2]").unwrap().as_i64(), -7);
    assert_eq!(it.read("main.grid[1,2]").unwrap().as_i64(), -7);
    assert_eq!(it.read("main.ts[1].x").unwrap().as_i64(), 300);
    // Writes through paths land where the code reads.
    it.write("main.grid[0,1]", PlcValue::from_i64(ElemType::DInt, 42))
        .unwrap();
    assert_eq!(it.read("main.grid[0][1]").unwrap().as_i64(), 42);
    it.write("main.ts[2].y", PlcValue::from_f64(-0.0)).unwrap();
    assert_eq!(it.read("main.ts[2].y").unwrap().bits, (-0.0f64).to_bits());
    it.write("main.flag", PlcValue::from_bool(true)).unwrap();
    assert_eq!(it.read("main.flag").unwrap(), PlcValue::from_bool(true));
    it.write("main.t", PlcValue::from_i64(ElemType::Time, -5))
        .unwrap();
    assert_eq!(it.read("main.t").unwrap().as_i64(), -5);
    // Type mismatches and bad paths are errors.
    assert!(it
        .write("main.count", PlcValue::from_i64(ElemType::Int, 1))
        .is_err());
    assert!(it
        .write("main.count", PlcValue::from_i64(ElemType::UDInt, 1))
        .is_err());
    assert!(it.read("main.nope").is_err());
    assert!(it.read("main.ts[4].y").is_err());
    assert!(it.read("main.ts[1]").is_err());
    assert!(it.read("other.x").is_err());
}

#[test]
fn elem_addr_index_out_of_range_is_an_error() {
    for idx in [-1i64, 3, 1 << 40] {
        let mut fx = fixture();
        fx.program(|b, inst, fx| {
            let ts = b.field_addr(inst, fx.p, 2);
            let i = b.iconst(Type::I64, idx);
            b.elem_addr(ts, fx.ta, i);
        });
        let mut it = Interp::new(&fx.m).unwrap();
        it.cold_start().unwrap();
        let e = it.scan().unwrap_err();
        assert!(
            e.0.contains("out of range") && e.0.contains("elem_addr"),
            "{e}"
        );
    }
}

#[test]
fn clock_and_fault_intrinsics() {
    let mut fx = fixture();
    fx.program(|b, inst, fx| {
        let ms = b.intrinsic(Intrinsic::ClockMs, vec![]).unwrap();
        let t = b.field_addr(inst, fx.p, 4);
        b.store(ms, t);
        let ns = b.intrinsic(Intrinsic::ClockNs, vec![]).unwrap();
        let n = b.field_addr(inst, fx.p, 5);
        b.store(ns, n);
        // Fault when the clock passed 10 s.
        let lim = b.iconst(Type::I32, 10_000);
        let late = b.icmp(IntCC::Sgt, ms, lim);
        let yes = b.create_block();
        let done = b.create_block();
        b.brif(late, yes, vec![], done, vec![]);
        b.switch_to(yes);
        b.intrinsic(Intrinsic::RaiseFault, vec![]);
        b.jump(done, vec![]);
        b.switch_to(done);
    });
    let mut it = Interp::new(&fx.m).unwrap();
    it.cold_start().unwrap();
    it.scan().unwrap();
    assert_eq!(it.read("main.t").unwrap().as_i64(), 0);
    it.set_clock_us(1_500_499);
    it.scan().unwrap();
    assert_eq!(it.read("main.t").unwrap().as_i64(), 1500);
    assert_eq!(it.read("main.ns").unwrap().as_i64(), 1_500_499_000);
    assert!(!it.fault());
    it.set_clock_us(-1);
    it.scan().unwrap();
    assert_eq!(it.read("main.t").unwrap().as_i64(), -1);
    assert_eq!(it.read("main.ns").unwrap().as_i64(), -1000);
    it.set_clock_us((1i64 << 31) * 1000);
    it.scan().unwrap();
    assert_eq!(it.read("main.t").unwrap().as_i64(), i32::MIN as i64);
    it.set_clock_us(10_001_000);
    it.scan().unwrap();
    assert!(it.fault());
    it.clear_fault();
    assert!(!it.fault());
    it.scan().unwrap();
    assert!(it.fault());
    it.cold_start().unwrap();
    assert!(!it.fault());
    it.scan().unwrap();
    assert_eq!(
        it.read("main.t").unwrap().as_i64(),
        0,
        "cold start resets the clock"
    );
}

#[test]
fn division_by_zero_in_a_scan_sets_the_fault_flag() {
    let mut fx = fixture();
    fx.program(|b, inst, fx| {
        let c = b.field_addr(inst, fx.p, 1);
        let v = b.load(Type::I32, c);
        let q = b.binary(BinaryOp::Sdiv, v, v);
        b.store(q, c);
    });
    let mut it = Interp::new(&fx.m).unwrap();
    it.cold_start().unwrap();
    it.scan().unwrap();
    assert!(it.fault());
    assert_eq!(it.read("main.count").unwrap().as_i64(), 0);
}

#[test]
fn init_globals_runs_before_program_inits() {
    let mut fx = fixture();
    let g = fx.m.add_data(DataDef {
        name: "g".into(),
        ty: MemType::Scalar(Type::I16),
        elem: Some(ElemType::Int),
        kind: DataKind::Global,
        location: None,
    });
    let gi = func(&mut fx.m, "globals$init", &[], None, |b, _| {
        let a = b.global_addr(g);
        let v = b.iconst(Type::I16, 41);
        b.store(v, a);
        b.ret(None);
    });
    fx.m.init_globals = Some(gi);
    // Every scan: count := g; g := g + 1.
    fx.program(|b, inst, fx| {
        let a = b.global_addr(g);
        let v = b.load(Type::I16, a);
        let w = b.convert(ConvOp::Sext, Type::I32, v);
        let c = b.field_addr(inst, fx.p, 1);
        b.store(w, c);
        let one = b.iconst(Type::I16, 1);
        let v = b.binary(BinaryOp::Iadd, v, one);
        b.store(v, a);
    });
    let mut it = Interp::new(&fx.m).unwrap();
    it.cold_start().unwrap();
    assert_eq!(it.read("g").unwrap().as_i64(), 41);
    it.scan().unwrap();
    it.scan().unwrap();
    assert_eq!(it.read("main.count").unwrap().as_i64(), 42);
    assert_eq!(it.read("G").unwrap().as_i64(), 43);
}

#[test]
fn broken_modules_fail_to_load() {
    let mut m = Module::new();
    let a = m.add_agg(AggDef::Struct(StructDef {
        name: "A".into(),
        kind: StructKind::Struct,
        fields: vec![field("me", MemType::Agg(AggId::new(0)), None)],
    }));
    let _ = a;
    let e = Interp::new(&m).unwrap_err();
    assert!(e.to_string().contains("contains itself"), "{e}");
    let mut m = Module::new();
    m.add_agg(AggDef::Array(ArrayDef {
        name: "B".into(),
        elem: MemType::Agg(AggId::new(7)),
        elem_type: None,
        len: 2,
        lower: 0,
    }));
    assert!(Interp::new(&m).is_err());
}

/// A loop of a few million operations, to keep the interpreter honest about speed
/// (run with `--release` and `--nocapture` to see the rate).
#[test]
fn loops_run_fast_enough() {
    let n = 200_000u64;
    let mut m = Module::new();
    let sum = func(&mut m, "sum", &[Type::I64], Some(Type::I64), |b, p| {
        let head = b.create_block();
        let i = b.block_param(head, Type::I64);
        let acc = b.block_param(head, Type::I64);
        let exit = b.create_block();
        let body = b.create_block();
        let zero = b.iconst(Type::I64, 0);
        b.jump(head, vec![zero, zero]);
        b.switch_to(head);
        let more = b.icmp(IntCC::Slt, i, p[0]);
        b.brif(more, body, vec![], exit, vec![]);
        b.switch_to(body);
        let acc2 = b.binary(BinaryOp::Iadd, acc, i);
        let one = b.iconst(Type::I64, 1);
        let i2 = b.binary(BinaryOp::Iadd, i, one);
        b.jump(head, vec![i2, acc2]);
        b.switch_to(exit);
        b.ret(Some(acc));
    });
    let mut it = Interp::new(&m).unwrap();
    let t = std::time::Instant::now();
    assert_eq!(it.call(sum, &[n]).unwrap(), Some(n * (n - 1) / 2));
    let rate = it.steps() as f64 / t.elapsed().as_secs_f64();
    eprintln!("{} operations, {:.1} M/s", it.steps(), rate / 1e6);
}

#[test]
fn eval_functions_match_the_machine() {
    let vals = [
        0i64,
        1,
        -1,
        2,
        7,
        -7,
        127,
        -128,
        255,
        1 << 31,
        i64::MIN,
        i64::MAX,
    ];
    for ty in INTS {
        for op in BinaryOp::ALL.into_iter().filter(|o| o.is_int_op()) {
            for &a in &vals {
                for &b in &vals {
                    let (r, fault) = bin(op, ty, a, b);
                    let (e, efault) = eval_binary(op, ty, a as u64, b as u64);
                    assert_eq!((e as i64, efault), (r, fault), "{ty} {op:?} {a} {b}");
                }
            }
        }
    }
    assert_eq!(
        eval_binary(BinaryOp::Fadd, Type::F32, f32b(16777216.0), f32b(1.0)).0,
        f32b(16777216.0)
    );
    assert_eq!(
        eval_unary(UnaryOp::Fnearest, Type::F64, f64b(2.5)),
        f64b(2.0)
    );
    assert_eq!(
        eval_unary(UnaryOp::Ineg, Type::I8, 0x80),
        0xFFFF_FFFF_FFFF_FF80
    );
    assert!(eval_icmp(IntCC::Ugt, Type::I8, -1i64 as u64, 1));
    assert!(eval_fcmp(
        FloatCC::Ne,
        Type::F32,
        f32b(f32::NAN),
        f32b(f32::NAN)
    ));
    assert_eq!(
        eval_convert(ConvOp::FToUi, Type::F32, Type::I8, f32b(-3.0)),
        0
    );
    assert_eq!(canonical(Type::I16, 0xFFFF), u64::MAX);
}

/// A callee without slots sees exactly its caller's memory: reading past the caller's
/// last slot is an error, not a read of unallocated arena.
#[test]
fn reads_past_the_stack_top_are_errors() {
    let mut m = Module::new();
    let inner = func(&mut m, "inner", &[Type::Ptr], Some(Type::I64), |b, p| {
        let v = b.load(Type::I64, p[0]);
        b.ret(Some(v));
    });
    let outer = func(&mut m, "outer", &[Type::I64], Some(Type::I64), |b, p| {
        let s = b.slot("t", MemType::Scalar(Type::I32));
        let a = b.slot_addr(s);
        let v = b.iconst(Type::I32, 0);
        b.store(v, a);
        let a = b.convert(ConvOp::Bitcast, Type::I64, a);
        let a = b.binary(BinaryOp::Iadd, a, p[0]);
        let a = b.convert(ConvOp::Bitcast, Type::Ptr, a);
        let r = b.call(inner, Some(Type::I64), vec![a]).unwrap();
        b.ret(Some(r));
    });
    let mut it = Interp::new(&m).unwrap();
    for off in [8u64, 16, 64, 4096] {
        let e = it.call(outer, &[off]).unwrap_err();
        assert!(
            e.0.contains("outside memory") && e.0.contains("@inner"),
            "{e}"
        );
    }
}
