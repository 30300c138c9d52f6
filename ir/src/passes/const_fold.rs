//! Constant folding and exact algebraic simplification.
//!
//! Folding follows `docs/ir.md` bit for bit. It deliberately leaves alone what could
//! make the folded program differ from what a target computes at run time:
//! - division and remainder by a constant zero (they raise the fault flag);
//! - float operations whose result is NaN (NaN payloads and signs differ between
//!   targets, and `bitcast` can observe them);
//! - transcendental functions (`sin`, `exp`, `fpow`, …): C libraries are not correctly
//!   rounded, so the compiler's host and the target may disagree in the last bit;
//! - operations that read an `i1` as a signed number (`sdiv`, `sshr`, signed compares,
//!   `sext`, `sitof`, `ftosi.i1`, …): the contract does not say whether a true `i1` is
//!   1 or -1 when read signed.
//!
//! Simplifications are exact identities on integers (never on floats: `x + 0.0` is not
//! `x` for `x = -0.0`). Multiplication, unsigned division and unsigned remainder by a
//! power of two become shifts and masks, which matters on 8-bit targets.
//!
//! Blocks are visited in reverse postorder, so an operand is simplified before its
//! uses and one run reaches every chain in the dominator tree.

use crate::dominators::reverse_postorder;
use crate::entities::{Inst, Value};
use crate::function::Function;
use crate::inst::{BinaryOp, ConvOp, FloatCC, InstData, IntCC, UnaryOp};
use crate::passes::util::{def_inst, ValueMap};
use crate::types::Type;

/// What to do with an instruction.
enum Fold {
    /// Nothing.
    Keep,
    /// Replace by an integer constant of the result type.
    Int(i64),
    /// Replace by a float constant (raw bits) of the result type.
    Float(u64),
    /// The result equals an existing value: substitute it and drop the instruction.
    Alias(Value),
    /// Replace the instruction by another one with the same result.
    Rewrite(InstData),
    /// `op x, k` where `k` is a new integer constant of `x`'s type (strength reduction).
    WithConst(BinaryOp, Value, i64),
}

/// Folds constants and simplifies instructions throughout `func`. Returns true if the
/// function changed.
pub fn run(func: &mut Function) -> bool {
    let mut order = reverse_postorder(func);
    let reachable = order.len();
    if order.len() != func.layout.len() {
        // Unreachable blocks are still valid code: fold them too, after the rest.
        let mut seen = vec![false; func.blocks.len()];
        for &b in &order {
            seen[b.index()] = true;
        }
        order.extend(func.layout.iter().filter(|b| !seen[b.index()]));
    }
    let mut vmap = ValueMap::new(func);
    let mut changed = false;
    // Uses are rewritten as they are visited: in reverse postorder every use comes
    // after its definition, so only substitutions found in unreachable blocks (which
    // have no such order) need a final sweep.
    let mut late_alias = false;
    // Instruction lists are rebuilt through one spare vector, so that no block
    // allocates.
    let mut spare: Vec<Inst> = Vec::new();
    for (k, b) in order.into_iter().enumerate() {
        let old = std::mem::take(&mut func.blocks[b.index()].insts);
        spare.clear();
        for &i in &old {
            if !vmap.is_empty() {
                func.insts[i.index()].map_args(|a| vmap.resolve(a));
            }
            // A rewritten instruction may simplify further (`icmp eq x, 0` on a truth
            // value becomes `bnot x`, which may invert a comparison): fold again.
            let mut fold_result = fold(func, i);
            for _ in 0..4 {
                let Fold::Rewrite(data) = fold_result else {
                    break;
                };
                func.insts[i.index()] = data;
                changed = true;
                fold_result = fold(func, i);
            }
            match fold_result {
                Fold::Keep | Fold::Rewrite(_) => spare.push(i),
                Fold::Int(imm) => {
                    let ty = result_type(func, i);
                    func.insts[i.index()] = InstData::Iconst {
                        ty,
                        imm: ty.canon_int(imm),
                    };
                    spare.push(i);
                    changed = true;
                }
                Fold::Float(bits) => {
                    let ty = result_type(func, i);
                    func.insts[i.index()] = InstData::Fconst { ty, bits };
                    spare.push(i);
                    changed = true;
                }
                Fold::Alias(v) => {
                    let r = func.result(i).expect("aliased instructions have results");
                    vmap.set(r, v);
                    late_alias |= k >= reachable;
                    changed = true;
                }
                Fold::WithConst(op, x, k) => {
                    let ty = func.value_type(x);
                    let span = func.spans[i.index()];
                    let c = func.create_inst(
                        InstData::Iconst {
                            ty,
                            imm: ty.canon_int(k),
                        },
                        Some(ty),
                        span,
                    );
                    let cv = func.result(c).expect("a constant has a result");
                    spare.push(c);
                    func.insts[i.index()] = InstData::Binary { op, args: [x, cv] };
                    spare.push(i);
                    changed = true;
                }
            }
        }
        func.blocks[b.index()].insts = std::mem::replace(&mut spare, old);
    }
    if late_alias {
        vmap.apply(func);
    }
    changed
}

fn result_type(func: &Function, i: Inst) -> Type {
    func.value_type(func.result(i).expect("folded instructions have results"))
}

/// A constant operand: a canonical integer or the raw bits of a float.
#[derive(Copy, Clone, PartialEq, Eq, Debug)]
enum K {
    Int(i64),
    Float(u64),
}

fn konst(func: &Function, v: Value) -> Option<K> {
    match def_inst(func, v)? {
        InstData::Iconst { imm, .. } => Some(K::Int(*imm)),
        InstData::Fconst { bits, .. } => Some(K::Float(*bits)),
        _ => None,
    }
}

fn iconst(func: &Function, v: Value) -> Option<i64> {
    match konst(func, v)? {
        K::Int(x) => Some(x),
        K::Float(_) => None,
    }
}

fn fold(func: &Function, i: Inst) -> Fold {
    let data = func.inst(i);
    match *data {
        InstData::Unary { op, arg } => fold_unary(func, op, arg),
        InstData::Binary { op, args: [a, b] } => fold_binary(func, op, a, b),
        InstData::Icmp { cond, args: [a, b] } => fold_icmp(func, cond, a, b),
        InstData::Fcmp { cond, args: [a, b] } => match (konst(func, a), konst(func, b)) {
            (Some(K::Float(x)), Some(K::Float(y))) => {
                Fold::Int(eval_fcmp(cond, func.value_type(a), x, y) as i64)
            }
            _ => Fold::Keep,
        },
        InstData::Convert { op, ty, arg } => fold_convert(func, op, ty, arg),
        InstData::Select {
            cond,
            if_true,
            if_false,
        } => fold_select(func, cond, if_true, if_false),
        InstData::Brif {
            cond,
            ref then_dest,
            ref else_dest,
        } => {
            if let Some(c) = iconst(func, cond) {
                let dest = if c & 1 != 0 { then_dest } else { else_dest };
                return Fold::Rewrite(InstData::Jump {
                    dest: (**dest).clone(),
                });
            }
            if let Some(InstData::Unary {
                op: UnaryOp::Bnot,
                arg,
            }) = def_inst(func, cond)
            {
                // `brif !c, a, b` is `brif c, b, a`.
                return Fold::Rewrite(InstData::Brif {
                    cond: *arg,
                    then_dest: else_dest.clone(),
                    else_dest: then_dest.clone(),
                });
            }
            Fold::Keep
        }
        InstData::BrTable {
            arg,
            ref default,
            ref table,
        } => match iconst(func, arg) {
            // The index read unsigned picks the entry; past the table, the default.
            Some(c) => {
                let u = func.value_type(arg).zext_bits(c);
                let dest = usize::try_from(u)
                    .ok()
                    .and_then(|k| table.get(k))
                    .unwrap_or(default);
                Fold::Rewrite(InstData::Jump { dest: dest.clone() })
            }
            None => Fold::Keep,
        },
        _ => Fold::Keep,
    }
}

/// The value of an integer type with every bit set, canonical.
fn all_ones(ty: Type) -> i64 {
    ty.canon_int(-1)
}

/// `log2(x)` if `x` read unsigned at `ty`'s width is a power of two greater than 1.
fn log2_of(ty: Type, x: i64) -> Option<u32> {
    let u = ty.zext_bits(x);
    (u > 1 && u.is_power_of_two()).then(|| u.trailing_zeros())
}

fn fold_unary(func: &Function, op: UnaryOp, arg: Value) -> Fold {
    let ty = func.value_type(arg);
    match konst(func, arg) {
        Some(K::Int(a)) if op.is_int_op() && ty.is_int() => {
            return match eval_iunary(op, ty, a) {
                Some(r) => Fold::Int(r),
                None => Fold::Keep,
            }
        }
        Some(K::Float(a)) if !op.is_int_op() && ty.is_float() => {
            return match eval_funary(op, ty, a) {
                Some(r) => Fold::Float(r),
                None => Fold::Keep,
            }
        }
        _ => {}
    }
    match (op, def_inst(func, arg)) {
        // Involutions: exact on every bit pattern.
        (
            UnaryOp::Bnot,
            Some(InstData::Unary {
                op: UnaryOp::Bnot,
                arg: x,
            }),
        )
        | (
            UnaryOp::Ineg,
            Some(InstData::Unary {
                op: UnaryOp::Ineg,
                arg: x,
            }),
        )
        | (
            UnaryOp::Fneg,
            Some(InstData::Unary {
                op: UnaryOp::Fneg,
                arg: x,
            }),
        ) => Fold::Alias(*x),
        (UnaryOp::Bnot, Some(InstData::Icmp { cond, args })) => Fold::Rewrite(InstData::Icmp {
            cond: cond.inverted(),
            args: *args,
        }),
        // `ne` is exactly "not `eq`" for floats, NaN included; the ordered conditions
        // have no inverse among the IR's conditions.
        (UnaryOp::Bnot, Some(InstData::Fcmp { cond, args })) => match cond {
            FloatCC::Eq => Fold::Rewrite(InstData::Fcmp {
                cond: FloatCC::Ne,
                args: *args,
            }),
            FloatCC::Ne => Fold::Rewrite(InstData::Fcmp {
                cond: FloatCC::Eq,
                args: *args,
            }),
            _ => Fold::Keep,
        },
        _ => Fold::Keep,
    }
}

fn fold_binary(func: &Function, op: BinaryOp, a: Value, b: Value) -> Fold {
    let ty = func.value_type(a);
    let (ka, kb) = (konst(func, a), konst(func, b));
    if !op.is_int_op() {
        if let (Some(K::Float(x)), Some(K::Float(y))) = (ka, kb) {
            if let Some(r) = eval_fbinary(op, ty, x, y) {
                return Fold::Float(r);
            }
        }
        return Fold::Keep;
    }
    if !ty.is_int() {
        return Fold::Keep;
    }
    let (ka, kb) = match (ka, kb) {
        (Some(K::Int(x)), Some(K::Int(y))) => {
            return match eval_ibinary(op, ty, x, y) {
                Some(r) => Fold::Int(r),
                None => Fold::Keep,
            }
        }
        (x, y) => (
            x.and_then(|k| if let K::Int(v) = k { Some(v) } else { None }),
            y.and_then(|k| if let K::Int(v) = k { Some(v) } else { None }),
        ),
    };
    let ones = all_ones(ty);
    let signed_ok = ty != Type::I1;
    let w = ty.bits() as u64;
    use BinaryOp::*;
    match op {
        Iadd => match (ka, kb) {
            (_, Some(0)) => Fold::Alias(a),
            (Some(0), _) => Fold::Alias(b),
            _ => Fold::Keep,
        },
        Isub => match kb {
            Some(0) => Fold::Alias(a),
            _ if a == b => Fold::Int(0),
            _ => Fold::Keep,
        },
        Imul => match (ka, kb) {
            (_, Some(0)) | (Some(0), _) => Fold::Int(0),
            (_, Some(1)) => Fold::Alias(a),
            (Some(1), _) => Fold::Alias(b),
            (_, Some(k)) if log2_of(ty, k).is_some() => Fold::WithConst(
                Ishl,
                a,
                log2_of(ty, k).expect("checked by the guard") as i64,
            ),
            (Some(k), _) if log2_of(ty, k).is_some() => Fold::WithConst(
                Ishl,
                b,
                log2_of(ty, k).expect("checked by the guard") as i64,
            ),
            _ => Fold::Keep,
        },
        // A nonzero constant divisor cannot fault, so these are exact.
        Udiv => match kb {
            Some(1) => Fold::Alias(a),
            Some(k) if log2_of(ty, k).is_some() => Fold::WithConst(
                Ushr,
                a,
                log2_of(ty, k).expect("checked by the guard") as i64,
            ),
            _ => Fold::Keep,
        },
        Urem => match kb {
            Some(1) => Fold::Int(0),
            Some(k) if log2_of(ty, k).is_some() => {
                Fold::WithConst(Band, a, (ty.zext_bits(k) - 1) as i64)
            }
            _ => Fold::Keep,
        },
        Sdiv if signed_ok => match kb {
            Some(1) => Fold::Alias(a),
            // `MIN / -1 = MIN` is exactly the wrapping negation.
            Some(-1) => Fold::Rewrite(InstData::Unary {
                op: UnaryOp::Ineg,
                arg: a,
            }),
            _ => Fold::Keep,
        },
        Srem if signed_ok => match kb {
            Some(1) | Some(-1) => Fold::Int(0),
            _ => Fold::Keep,
        },
        Band => match (ka, kb) {
            (_, Some(0)) | (Some(0), _) => Fold::Int(0),
            (_, Some(k)) if k == ones => Fold::Alias(a),
            (Some(k), _) if k == ones => Fold::Alias(b),
            _ if a == b => Fold::Alias(a),
            _ => Fold::Keep,
        },
        Bor => match (ka, kb) {
            (_, Some(0)) => Fold::Alias(a),
            (Some(0), _) => Fold::Alias(b),
            (_, Some(k)) | (Some(k), _) if k == ones => Fold::Int(ones),
            _ if a == b => Fold::Alias(a),
            _ => Fold::Keep,
        },
        Bxor => match (ka, kb) {
            (_, Some(0)) => Fold::Alias(a),
            (Some(0), _) => Fold::Alias(b),
            (_, Some(k)) if k == ones => Fold::Rewrite(InstData::Unary {
                op: UnaryOp::Bnot,
                arg: a,
            }),
            (Some(k), _) if k == ones => Fold::Rewrite(InstData::Unary {
                op: UnaryOp::Bnot,
                arg: b,
            }),
            _ if a == b => Fold::Int(0),
            _ => Fold::Keep,
        },
        Ishl | Ushr | Sshr | Rotl | Rotr => match (ka, kb) {
            (_, Some(0)) => Fold::Alias(a),
            (Some(0), _) => Fold::Int(0),
            (Some(k), _) if k == ones && matches!(op, Rotl | Rotr) => Fold::Int(ones),
            (Some(k), _) if k == ones && op == Sshr && signed_ok => Fold::Int(ones),
            (_, Some(k)) if matches!(op, Ishl | Ushr) && ty.zext_bits(k) >= w => Fold::Int(0),
            _ => Fold::Keep,
        },
        _ => Fold::Keep,
    }
}

fn fold_icmp(func: &Function, cond: IntCC, a: Value, b: Value) -> Fold {
    let ty = func.value_type(a);
    let (ka, kb) = (iconst(func, a), iconst(func, b));
    if let (Some(x), Some(y)) = (ka, kb) {
        return match eval_icmp(cond, ty, x, y) {
            Some(r) => Fold::Int(r as i64),
            None => Fold::Keep,
        };
    }
    if a == b {
        // Integers and pointers equal themselves (no NaN here).
        use IntCC::*;
        return Fold::Int(matches!(cond, Eq | Sle | Sge | Ule | Uge) as i64);
    }
    // Put a lone constant on the right.
    let (cond, x, k) = match (ka, kb) {
        (_, Some(k)) => (cond, a, k),
        (Some(k), _) => (cond.swapped(), b, k),
        _ => return Fold::Keep,
    };
    if ty.is_int() {
        match (cond, ty.zext_bits(k)) {
            (IntCC::Ult, 0) => return Fold::Int(0),
            (IntCC::Uge, 0) => return Fold::Int(1),
            _ => {}
        }
    }
    // Truth values compared with 0 or 1, and `uext` of one compared with 0.
    let (x, k) = match def_inst(func, x) {
        Some(InstData::Convert {
            op: ConvOp::Uext,
            arg,
            ..
        }) if func.value_type(*arg) == Type::I1 && k == 0 => (*arg, 0),
        _ if ty == Type::I1 => (x, k),
        _ => return Fold::Keep,
    };
    let is_x = match (cond, k) {
        (IntCC::Ne, 0) | (IntCC::Eq, 1) => true,
        (IntCC::Eq, 0) | (IntCC::Ne, 1) => false,
        _ => return Fold::Keep,
    };
    if is_x {
        Fold::Alias(x)
    } else {
        Fold::Rewrite(InstData::Unary {
            op: UnaryOp::Bnot,
            arg: x,
        })
    }
}

fn fold_convert(func: &Function, op: ConvOp, to: Type, arg: Value) -> Fold {
    let from = func.value_type(arg);
    if let Some(k) = konst(func, arg) {
        return match eval_convert(op, from, to, k) {
            Some(K::Int(r)) => Fold::Int(r),
            Some(K::Float(r)) => Fold::Float(r),
            None => Fold::Keep,
        };
    }
    match (op, def_inst(func, arg)) {
        // Truncating an extension back to the original width gives the original.
        (
            ConvOp::Itrunc,
            Some(InstData::Convert {
                op: ConvOp::Uext | ConvOp::Sext,
                arg: x,
                ..
            }),
        ) if func.value_type(*x) == to => Fold::Alias(*x),
        // Truncation and zero extension compose.
        (
            ConvOp::Itrunc,
            Some(InstData::Convert {
                op: ConvOp::Itrunc,
                arg: x,
                ..
            }),
        )
        | (
            ConvOp::Uext,
            Some(InstData::Convert {
                op: ConvOp::Uext,
                arg: x,
                ..
            }),
        ) => Fold::Rewrite(InstData::Convert {
            op,
            ty: to,
            arg: *x,
        }),
        _ => Fold::Keep,
    }
}

fn fold_select(func: &Function, cond: Value, t: Value, f: Value) -> Fold {
    if t == f {
        return Fold::Alias(t);
    }
    if let Some(c) = iconst(func, cond) {
        return Fold::Alias(if c & 1 != 0 { t } else { f });
    }
    if let Some(InstData::Unary {
        op: UnaryOp::Bnot,
        arg,
    }) = def_inst(func, cond)
    {
        return Fold::Rewrite(InstData::Select {
            cond: *arg,
            if_true: f,
            if_false: t,
        });
    }
    if func.value_type(t) == Type::I1 {
        match (iconst(func, t), iconst(func, f)) {
            (Some(1), Some(0)) => return Fold::Alias(cond),
            (Some(0), Some(1)) => {
                return Fold::Rewrite(InstData::Unary {
                    op: UnaryOp::Bnot,
                    arg: cond,
                })
            }
            _ => {}
        }
    }
    Fold::Keep
}

// ---- Evaluation of constant operations (the semantics of docs/ir.md). ----

/// Evaluates an integer unary operation on a canonical constant; `None` when folding
/// is not allowed (see the module documentation).
pub(crate) fn eval_iunary(op: UnaryOp, ty: Type, a: i64) -> Option<i64> {
    let r = match op {
        UnaryOp::Ineg => a.wrapping_neg(),
        UnaryOp::Bnot => !a,
        UnaryOp::Iabs if ty != Type::I1 => a.wrapping_abs(),
        _ => return None,
    };
    Some(ty.canon_int(r))
}

/// Evaluates an integer binary operation on canonical constants.
pub(crate) fn eval_ibinary(op: BinaryOp, ty: Type, a: i64, b: i64) -> Option<i64> {
    let w = ty.bits() as u64;
    let (ua, ub) = (ty.zext_bits(a), ty.zext_bits(b));
    let signed_ok = ty != Type::I1;
    use BinaryOp::*;
    let r = match op {
        Iadd => a.wrapping_add(b),
        Isub => a.wrapping_sub(b),
        Imul => a.wrapping_mul(b),
        // Canonical values are sign-extended, so i64 arithmetic then truncation is
        // exact; `MIN / -1` wraps to MIN (and `MIN % -1` is 0) at every width.
        Sdiv if signed_ok && b != 0 => a.wrapping_div(b),
        Srem if signed_ok && b != 0 => a.wrapping_rem(b),
        Udiv if ub != 0 => (ua / ub) as i64,
        Urem if ub != 0 => (ua % ub) as i64,
        Band => a & b,
        Bor => a | b,
        Bxor => a ^ b,
        Ishl => {
            if ub >= w {
                0
            } else {
                (ua << ub) as i64
            }
        }
        Ushr => {
            if ub >= w {
                0
            } else {
                (ua >> ub) as i64
            }
        }
        Sshr if signed_ok => a >> ub.min(63),
        Rotl | Rotr => {
            let c = ub % w;
            let c = if op == Rotr { (w - c) % w } else { c };
            if c == 0 {
                a
            } else {
                ((ua << c) | (ua >> (w - c))) as i64
            }
        }
        _ => return None,
    };
    Some(ty.canon_int(r))
}

/// Evaluates an integer comparison of canonical constants.
pub(crate) fn eval_icmp(cond: IntCC, ty: Type, a: i64, b: i64) -> Option<bool> {
    let (ua, ub) = (ty.zext_bits(a), ty.zext_bits(b));
    let signed_ok = ty != Type::I1;
    use IntCC::*;
    Some(match cond {
        Eq => a == b,
        Ne => a != b,
        Slt if signed_ok => a < b,
        Sle if signed_ok => a <= b,
        Sgt if signed_ok => a > b,
        Sge if signed_ok => a >= b,
        Ult => ua < ub,
        Ule => ua <= ub,
        Ugt => ua > ub,
        Uge => ua >= ub,
        _ => return None,
    })
}

/// A float constant as `f64` (exact for `f32`), and back.
fn fval(ty: Type, bits: u64) -> f64 {
    if ty == Type::F32 {
        f32::from_bits(bits as u32) as f64
    } else {
        f64::from_bits(bits)
    }
}

fn fbits_checked(ty: Type, x: f64) -> Option<u64> {
    if x.is_nan() {
        return None;
    }
    Some(if ty == Type::F32 {
        (x as f32).to_bits() as u64
    } else {
        x.to_bits()
    })
}

/// Evaluates a float unary operation; `None` for NaN results and library functions.
pub(crate) fn eval_funary(op: UnaryOp, ty: Type, bits: u64) -> Option<u64> {
    let sign = if ty == Type::F32 {
        1u64 << 31
    } else {
        1u64 << 63
    };
    match op {
        // Sign-bit operations: exact on every encoding, NaN included.
        UnaryOp::Fneg => return Some(bits ^ sign),
        UnaryOp::Fabs => return Some(bits & !sign),
        _ => {}
    }
    if ty == Type::F32 {
        let x = f32::from_bits(bits as u32);
        let r = match op {
            UnaryOp::Fsqrt => x.sqrt(),
            UnaryOp::Fnearest => x.round_ties_even(),
            UnaryOp::Ftrunc => x.trunc(),
            UnaryOp::Ffloor => x.floor(),
            UnaryOp::Fceil => x.ceil(),
            _ => return None,
        };
        fbits_checked(ty, r as f64)
    } else {
        let x = f64::from_bits(bits);
        let r = match op {
            UnaryOp::Fsqrt => x.sqrt(),
            UnaryOp::Fnearest => x.round_ties_even(),
            UnaryOp::Ftrunc => x.trunc(),
            UnaryOp::Ffloor => x.floor(),
            UnaryOp::Fceil => x.ceil(),
            _ => return None,
        };
        fbits_checked(ty, r)
    }
}

/// Evaluates a float binary operation in the operands' precision.
pub(crate) fn eval_fbinary(op: BinaryOp, ty: Type, a: u64, b: u64) -> Option<u64> {
    if ty == Type::F32 {
        let (x, y) = (f32::from_bits(a as u32), f32::from_bits(b as u32));
        let r = match op {
            BinaryOp::Fadd => x + y,
            BinaryOp::Fsub => x - y,
            BinaryOp::Fmul => x * y,
            BinaryOp::Fdiv => x / y,
            _ => return None,
        };
        fbits_checked(ty, r as f64)
    } else {
        let (x, y) = (f64::from_bits(a), f64::from_bits(b));
        let r = match op {
            BinaryOp::Fadd => x + y,
            BinaryOp::Fsub => x - y,
            BinaryOp::Fmul => x * y,
            BinaryOp::Fdiv => x / y,
            _ => return None,
        };
        fbits_checked(ty, r)
    }
}

/// Evaluates a float comparison (false when unordered, except `ne`).
pub(crate) fn eval_fcmp(cond: FloatCC, ty: Type, a: u64, b: u64) -> bool {
    let (x, y) = (fval(ty, a), fval(ty, b));
    match cond {
        FloatCC::Eq => x == y,
        FloatCC::Ne => x != y,
        FloatCC::Lt => x < y,
        FloatCC::Le => x <= y,
        FloatCC::Gt => x > y,
        FloatCC::Ge => x >= y,
    }
}

/// The signed range of an integer type.
fn signed_range(ty: Type) -> (i64, i64) {
    let w = ty.bits();
    if w >= 64 {
        (i64::MIN, i64::MAX)
    } else {
        (-(1i64 << (w - 1)), (1i64 << (w - 1)) - 1)
    }
}

/// Evaluates a conversion of a constant.
fn eval_convert(op: ConvOp, from: Type, to: Type, k: K) -> Option<K> {
    use ConvOp::*;
    Some(match (op, k) {
        (Sext, K::Int(a)) if from != Type::I1 && to.is_int() => K::Int(to.canon_int(a)),
        (Uext, K::Int(a)) if to.is_int() => K::Int(to.canon_int(from.zext_bits(a) as i64)),
        (Itrunc, K::Int(a)) if to.is_int() => K::Int(to.canon_int(a)),
        (Fpromote, K::Float(x)) if from == Type::F32 && to == Type::F64 => {
            K::Float(fbits_checked(to, fval(from, x))?)
        }
        (Fdemote, K::Float(x)) if from == Type::F64 && to == Type::F32 => {
            // `as f32` rounds to nearest even.
            let r = f64::from_bits(x) as f32;
            if r.is_nan() {
                return None;
            }
            K::Float(r.to_bits() as u64)
        }
        (SiToF, K::Int(a)) if from != Type::I1 && from.is_int() => K::Float(match to {
            Type::F32 => (a as f32).to_bits() as u64,
            Type::F64 => (a as f64).to_bits(),
            _ => return None,
        }),
        (UiToF, K::Int(a)) if from.is_int() => {
            let u = from.zext_bits(a);
            K::Float(match to {
                Type::F32 => (u as f32).to_bits() as u64,
                Type::F64 => (u as f64).to_bits(),
                _ => return None,
            })
        }
        (FToSi, K::Float(x)) if from.is_float() && to.is_int() && to != Type::I1 => {
            // `as` truncates toward zero, saturates and maps NaN to 0.
            let (lo, hi) = signed_range(to);
            K::Int((fval(from, x) as i64).clamp(lo, hi))
        }
        (FToUi, K::Float(x)) if from.is_float() && to.is_int() && to != Type::I1 => {
            let hi = to.zext_bits(-1);
            K::Int(to.canon_int((fval(from, x) as u64).min(hi) as i64))
        }
        (Bitcast, K::Int(a)) => match (from, to) {
            (Type::I32, Type::F32) => K::Float(from.zext_bits(a)),
            (Type::I64, Type::F64) => K::Float(a as u64),
            _ => return None,
        },
        (Bitcast, K::Float(x)) => match (from, to) {
            (Type::F32, Type::I32) => K::Int(to.canon_int(x as i64)),
            (Type::F64, Type::I64) => K::Int(x as i64),
            _ => return None,
        },
        _ => return None,
    })
}
