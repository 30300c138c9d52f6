//! Constant folding checked against the reference interpreter: every operation on
//! interesting constants (and with one operand variable, for the identities) gives the
//! same result and fault flag before and after `const_fold` (+ `dce`).

use super::verify;
use crate::builder::FuncBuilder;
use crate::entities::{FuncId, Value};
use crate::function::{FuncKind, Function};
use crate::inst::{BinaryOp, ConvOp, FloatCC, IntCC, UnaryOp};
use crate::interp::Interp;
use crate::machine::Machine;
use crate::module::Module;
use crate::passes::{const_fold, dce};
use crate::types::Type;

const INTS: [Type; 5] = [Type::I1, Type::I8, Type::I16, Type::I32, Type::I64];

/// The types an operation takes (the verifier allows `i1` only in logic).
fn types_for(int_op: bool, logic: bool) -> &'static [Type] {
    match (int_op, logic) {
        (true, true) => &INTS,
        (true, false) => &INTS[1..],
        (false, _) => &FLOATS,
    }
}
const FLOATS: [Type; 2] = [Type::F32, Type::F64];

fn int_values(ty: Type) -> Vec<i64> {
    let w = ty.bits() as i64;
    let mut v = vec![
        0,
        1,
        -1,
        2,
        3,
        -7,
        w - 1,
        w,
        w + 1,
        0x5555_5555_5555_5555,
        i64::MIN,
        i64::MAX,
        1 << (w - 1).max(0),
        (1i64 << (w - 1).max(0)).wrapping_sub(1),
        16,
        100,
    ];
    for x in v.iter_mut() {
        *x = ty.canon_int(*x);
    }
    v.sort();
    v.dedup();
    v
}

fn float_values(ty: Type) -> Vec<u64> {
    let xs: [f64; 16] = [
        0.0,
        -0.0,
        1.0,
        -1.0,
        0.1,
        2.5,
        3.5,
        -2.5,
        1e30,
        -1e30,
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::NAN,
        4e9,
        -3e9,
        1e-310,
    ];
    xs.iter()
        .map(|&x| {
            if ty == Type::F32 {
                (x as f32).to_bits() as u64
            } else {
                x.to_bits()
            }
        })
        .collect()
}

/// Builds a function of no parameters whose body is `make` and that returns its value.
fn func_of(m: &mut Module, ret: Type, make: impl FnOnce(&mut FuncBuilder) -> Value) -> FuncId {
    let mut f = Function::new(
        format!("f{}", m.funcs.len()),
        FuncKind::Function,
        vec![],
        Some(ret),
    );
    {
        let mut b = FuncBuilder::new(&mut f);
        let v = make(&mut b);
        b.ret(Some(v));
    }
    m.add_func(f)
}

fn konst(b: &mut FuncBuilder, ty: Type, bits: u64) -> Value {
    if ty.is_float() {
        if ty == Type::F32 {
            b.f32const(f32::from_bits(bits as u32))
        } else {
            b.f64const(f64::from_bits(bits))
        }
    } else {
        b.iconst(ty, bits as i64)
    }
}

fn values_of(ty: Type) -> Vec<u64> {
    if ty.is_float() {
        float_values(ty)
    } else {
        int_values(ty).into_iter().map(|x| x as u64).collect()
    }
}

/// Optimises a copy of `m` with `const_fold` + `dce` and runs every function (with
/// `args`) on both, comparing results and fault flags.
fn compare(m: &Module, args: &[Vec<u64>]) {
    let mut opt = m.clone();
    for k in 0..opt.funcs.len() {
        verify(m, &m.funcs[k], "before const_fold");
        const_fold::run(&mut opt.funcs[k]);
        dce::run(&mut opt.funcs[k]);
        verify(&opt, &opt.funcs[k], "after const_fold");
    }
    let mut a = Interp::new(m).expect("module runs");
    let mut b = Interp::new(&opt).expect("optimised module runs");
    for k in 0..m.funcs.len() {
        let f = FuncId::new(k);
        for args in args.iter().filter(|a| a.len() == m.funcs[k].params.len()) {
            a.clear_fault();
            b.clear_fault();
            let ra = a.call(f, args);
            let rb = b.call(f, args);
            if ra != rb || a.fault() != b.fault() {
                panic!(
                    "{}({args:?}): {ra:?} fault {} before, {rb:?} fault {} after\n{}\n{}",
                    m.funcs[k].name,
                    a.fault(),
                    b.fault(),
                    crate::text::print_function(m, &m.funcs[k], &Default::default()),
                    crate::text::print_function(&opt, &opt.funcs[k], &Default::default()),
                );
            }
        }
    }
}

#[test]
fn binary_operations_fold_like_the_interpreter() {
    let mut m = Module::new();
    for op in BinaryOp::ALL {
        let logic = matches!(op, BinaryOp::Band | BinaryOp::Bor | BinaryOp::Bxor);
        let types = types_for(op.is_int_op(), logic);
        for &ty in types {
            let vals = values_of(ty);
            for &x in &vals {
                for &y in &vals {
                    func_of(&mut m, ty, |b| {
                        let (x, y) = (konst(b, ty, x), konst(b, ty, y));
                        b.binary(op, x, y)
                    });
                }
            }
        }
    }
    compare(&m, &[vec![]]);
}

#[test]
fn unary_operations_and_comparisons_fold_like_the_interpreter() {
    let mut m = Module::new();
    for op in UnaryOp::ALL {
        let types = types_for(op.is_int_op(), op == UnaryOp::Bnot);
        for &ty in types {
            for x in values_of(ty) {
                func_of(&mut m, ty, |b| {
                    let x = konst(b, ty, x);
                    b.unary(op, x)
                });
            }
        }
    }
    for cc in IntCC::ALL {
        for ty in INTS {
            let vals = values_of(ty);
            for &x in &vals {
                for &y in &vals {
                    func_of(&mut m, Type::I1, |b| {
                        let (x, y) = (konst(b, ty, x), konst(b, ty, y));
                        b.icmp(cc, x, y)
                    });
                }
            }
        }
    }
    for cc in FloatCC::ALL {
        for ty in FLOATS {
            let vals = values_of(ty);
            for &x in &vals {
                for &y in &vals {
                    func_of(&mut m, Type::I1, |b| {
                        let (x, y) = (konst(b, ty, x), konst(b, ty, y));
                        b.fcmp(cc, x, y)
                    });
                }
            }
        }
    }
    for ty in [Type::I8, Type::F32] {
        for c in [0, 1] {
            func_of(&mut m, ty, |b| {
                let c = b.iconst(Type::I1, c);
                let x = konst(b, ty, 5);
                let y = konst(b, ty, 9);
                b.select(c, x, y)
            });
        }
    }
    compare(&m, &[vec![]]);
}

#[test]
fn conversions_fold_like_the_interpreter() {
    let all = [
        Type::I1,
        Type::I8,
        Type::I16,
        Type::I32,
        Type::I64,
        Type::F32,
        Type::F64,
    ];
    let mut m = Module::new();
    for op in ConvOp::ALL {
        for from in all {
            for to in all {
                let arith = |t: Type| t.is_int() && t != Type::I1;
                let ok = match op {
                    ConvOp::Sext => arith(from) && arith(to) && to.bits() > from.bits(),
                    ConvOp::Uext => from.is_int() && arith(to) && to.bits() > from.bits(),
                    ConvOp::Itrunc => arith(from) && to.is_int() && to.bits() < from.bits(),
                    ConvOp::Fpromote => from == Type::F32 && to == Type::F64,
                    ConvOp::Fdemote => from == Type::F64 && to == Type::F32,
                    ConvOp::SiToF | ConvOp::UiToF => arith(from) && to.is_float(),
                    ConvOp::FToSi | ConvOp::FToUi => from.is_float() && arith(to),
                    ConvOp::Bitcast => {
                        from.bits() == to.bits() && from.is_int() != to.is_int() && from != Type::I1
                    }
                    // Pointers have no constants to fold (but null).
                    ConvOp::PtrToInt | ConvOp::IntToPtr => false,
                };
                if !ok {
                    continue;
                }
                for x in values_of(from) {
                    func_of(&mut m, to, |b| {
                        let x = konst(b, from, x);
                        b.convert(op, to, x)
                    });
                }
            }
        }
    }
    compare(&m, &[vec![]]);
}

#[test]
fn identities_hold_for_every_operand() {
    // op(x, k) and op(k, x) for a variable x and constant k.
    let mut m = Module::new();
    for op in BinaryOp::ALL.into_iter().filter(|o| o.is_int_op()) {
        let logic = matches!(op, BinaryOp::Band | BinaryOp::Bor | BinaryOp::Bxor);
        for &ty in types_for(true, logic) {
            for k in int_values(ty) {
                for swap in [false, true] {
                    let mut f = Function::new(
                        format!("f{}", m.funcs.len()),
                        FuncKind::Function,
                        vec![ty],
                        Some(ty),
                    );
                    {
                        let mut b = FuncBuilder::new(&mut f);
                        let x = b.params()[0];
                        let c = b.iconst(ty, k);
                        let r = if swap {
                            b.binary(op, c, x)
                        } else {
                            b.binary(op, x, c)
                        };
                        b.ret(Some(r));
                    }
                    m.add_func(f);
                }
            }
            // x op x
            let mut f = Function::new(
                format!("f{}", m.funcs.len()),
                FuncKind::Function,
                vec![ty],
                Some(ty),
            );
            {
                let mut b = FuncBuilder::new(&mut f);
                let x = b.params()[0];
                let r = b.binary(op, x, x);
                b.ret(Some(r));
            }
            m.add_func(f);
        }
    }
    for cc in IntCC::ALL {
        for ty in INTS {
            for k in [0, 1, -1] {
                let mut f = Function::new(
                    format!("f{}", m.funcs.len()),
                    FuncKind::Function,
                    vec![ty],
                    Some(Type::I1),
                );
                {
                    let mut b = FuncBuilder::new(&mut f);
                    let x = b.params()[0];
                    let c = b.iconst(ty, k);
                    let r = b.icmp(cc, x, c);
                    let r2 = b.icmp(cc, c, x);
                    let r3 = b.icmp(cc, x, x);
                    let n = b.unary(UnaryOp::Bnot, r);
                    let s = b.select(n, r2, r3);
                    b.ret(Some(s));
                }
                m.add_func(f);
            }
        }
    }
    let mut args: Vec<Vec<u64>> = Vec::new();
    for x in int_values(Type::I64) {
        args.push(vec![x as u64]);
    }
    for x in [5i64, -100, 0x1234_5678, 40000, -129] {
        args.push(vec![x as u64]);
    }
    compare(&m, &args);
}
