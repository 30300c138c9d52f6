//! Compile-time constants: array bounds, CASE labels, VAR CONSTANT values.

use crate::ast::{BinaryOp, Expr, ExprKind, LiteralKind, UnaryOp};
use crate::intern::{Interner, Symbol};
use crate::types::{int_range, Ty};
use plcc_ir::ElemType;

/// A constant value.
#[derive(Copy, Clone, Debug, PartialEq)]
pub enum ConstVal {
    /// Integers, bit strings, and durations in their unit (ms for TIME, ns for LTIME,
    /// or ns for an untyped duration literal: see `eval`).
    Int(i128),
    /// Reals.
    Real(f64),
    /// BOOL.
    Bool(bool),
}

impl ConstVal {
    /// The zero value of a type.
    pub fn zero_of(ty: Ty) -> ConstVal {
        match ty {
            Ty::Elem(ElemType::Bool) => ConstVal::Bool(false),
            t if t.is_real() => ConstVal::Real(0.0),
            _ => ConstVal::Int(0),
        }
    }

    /// Converts the value to a variable of type `ty` as an assignment would, or says
    /// why it cannot.
    pub fn coerce(self, ty: Ty) -> Result<ConstVal, String> {
        let Some(e) = ty.elem() else {
            return Err("expected a value of an elementary type".into());
        };
        match (self, e) {
            (ConstVal::Bool(b), ElemType::Bool) => Ok(ConstVal::Bool(b)),
            // IEC 61131-3's boolean literals include plain 0 and 1.
            (ConstVal::Int(v @ (0 | 1)), ElemType::Bool) => Ok(ConstVal::Bool(v == 1)),
            // Round once, straight to the target's precision.
            (ConstVal::Int(v), ElemType::Real) => Ok(ConstVal::Real(v as f32 as f64)),
            (ConstVal::Int(v), ElemType::LReal) => Ok(ConstVal::Real(v as f64)),
            (ConstVal::Real(r), ElemType::Real | ElemType::LReal) => Ok(ConstVal::Real(r)),
            (ConstVal::Int(v), e) => match int_range(e) {
                Some((lo, hi)) if e != ElemType::Bool => {
                    if v < lo || v > hi {
                        Err(format!(
                            "{v} is out of the range of {} ({lo}..{hi})",
                            e.name()
                        ))
                    } else {
                        Ok(ConstVal::Int(v))
                    }
                }
                _ => Err(format!("an integer cannot be a {}", e.name())),
            },
            (ConstVal::Real(_), e) => Err(format!("a real number cannot be a {}", e.name())),
            (ConstVal::Bool(_), e) => Err(format!("TRUE/FALSE cannot be a {}", e.name())),
        }
    }
}

/// How deep constant definitions may refer to each other (stops cycles).
const MAX_DEPTH: u32 = 32;

/// Resolves the name of a constant, qualified by a global variable list's name
/// (`GVL.c`) or not; it gets the evaluator back (expression, depth, wanted type) to
/// evaluate the constant's initialiser.
type Lookup<'a> = dyn Fn(
        Option<Symbol>,
        Symbol,
        u32,
        &dyn Fn(&Expr, u32, Option<Ty>) -> Option<(ConstVal, Ty)>,
    ) -> Option<(ConstVal, Ty)>
    + 'a;

/// Evaluates a constant expression. `lookup` resolves names of constants (it gets the
/// evaluator back to evaluate their initialisers). TIME literals evaluate to
/// milliseconds, LTIME literals to nanoseconds. `None` if the expression is not
/// constant or overflows.
///
/// `want` is the type the value is for (a constant's declared type), if known: `NOT`
/// of an untyped integer literal needs a width (`NOT 16#00FF` is 16#FF00 as a WORD).
pub fn eval(
    e: &Expr,
    interner: &Interner,
    lookup: &Lookup<'_>,
    want: Option<Ty>,
) -> Option<(ConstVal, Ty)> {
    eval_depth(e, interner, lookup, 0, want)
}

/// The bitwise complement of `v` at the width of the integer or bit-string type `e`.
fn not_at_width(v: i128, e: ElemType) -> Option<i128> {
    let (lo, hi) = int_range(e)?;
    if e == ElemType::Bool || v < lo || v > hi {
        return None;
    }
    let bits = e.ir_type().bits();
    let modulus = 1i128 << bits;
    let u = !v & (modulus - 1);
    Some(if lo < 0 && u > hi { u - modulus } else { u })
}

fn eval_depth(
    e: &Expr,
    interner: &Interner,
    lookup: &Lookup<'_>,
    depth: u32,
    want: Option<Ty>,
) -> Option<(ConstVal, Ty)> {
    if depth > MAX_DEPTH {
        return None;
    }
    let rec = |x: &Expr, d: u32| eval_depth(x, interner, lookup, d, want);
    match &e.kind {
        ExprKind::Paren(inner) | ExprKind::UsedBy { value: inner, .. } => rec(inner, depth),
        ExprKind::Literal(lit) => {
            let prefix = lit
                .type_prefix
                .and_then(|p| ElemType::from_name(interner.name(p.sym)));
            let (v, t) = match &lit.kind {
                LiteralKind::Int(v) => (ConstVal::Int(*v), Ty::AnyInt),
                LiteralKind::Real(text) => {
                    // A REAL literal rounds once, from its decimal text straight to
                    // binary32 (through binary64 it could round twice).
                    let single = match prefix {
                        Some(p) => p == ElemType::Real,
                        None => want == Some(Ty::Elem(ElemType::Real)),
                    };
                    let v = if single {
                        text.parse::<f32>().ok()? as f64
                    } else {
                        text.parse::<f64>().ok()?
                    };
                    (ConstVal::Real(v), Ty::AnyReal)
                }
                LiteralKind::Bool(b) => (ConstVal::Bool(*b), Ty::BOOL),
                LiteralKind::Duration { ns, long: false } => {
                    (ConstVal::Int(ns / 1_000_000), Ty::TIME)
                }
                LiteralKind::Duration { ns, long: true } => {
                    (ConstVal::Int(*ns), Ty::Elem(ElemType::LTime))
                }
                _ => return None,
            };
            match prefix {
                Some(p) => Some((v.coerce(Ty::Elem(p)).ok()?, Ty::Elem(p))),
                None => Some((v, t)),
            }
        }
        ExprKind::Name(id) => lookup(None, id.sym, depth, &|x, d, w| {
            eval_depth(x, interner, lookup, d, w)
        }),
        ExprKind::Member(base, name) => match &base.kind {
            ExprKind::Name(list) => lookup(Some(list.sym), name.sym, depth, &|x, d, w| {
                eval_depth(x, interner, lookup, d, w)
            }),
            _ => None,
        },
        ExprKind::Unary(op, inner) => {
            let (v, t) = rec(inner, depth + 1)?;
            let r = match (op, v) {
                (UnaryOp::Plus, v) => v,
                (UnaryOp::Neg, ConstVal::Int(i)) => ConstVal::Int(-i),
                (UnaryOp::Neg, ConstVal::Real(r)) => ConstVal::Real(-r),
                (UnaryOp::Not, ConstVal::Bool(b)) => ConstVal::Bool(!b),
                (UnaryOp::Not, ConstVal::Int(i)) => {
                    let ty = if t.is_literal() { want.unwrap_or(t) } else { t };
                    ConstVal::Int(not_at_width(i, ty.elem()?)?)
                }
                _ => return None,
            };
            Some((r, t))
        }
        ExprKind::Binary(op, l, r) => {
            let (a, ta) = rec(l, depth + 1)?;
            let (b, tb) = rec(r, depth + 1)?;
            // A 0 or 1 beside a BOOL is a BOOL literal (`TRUE AND 1`).
            let digit = |v: ConstVal, e: &Expr| match v {
                ConstVal::Int(i) if super::literals::is_bool_digit(e) => ConstVal::Bool(i == 1),
                v => v,
            };
            let (a, b) = match (a, b) {
                (ConstVal::Bool(_), _) => (a, digit(b, r)),
                (_, ConstVal::Bool(_)) => (digit(a, l), b),
                _ => (a, b),
            };
            let ty = if ta.is_literal() { tb } else { ta };
            use BinaryOp::*;
            let v = match (a, b) {
                (ConstVal::Int(x), ConstVal::Int(y)) => match op {
                    Add => ConstVal::Int(x.checked_add(y)?),
                    Sub => ConstVal::Int(x.checked_sub(y)?),
                    Mul => ConstVal::Int(x.checked_mul(y)?),
                    Div => ConstVal::Int(if y == 0 { return None } else { x / y }),
                    Mod => ConstVal::Int(if y == 0 { return None } else { x % y }),
                    Pow => ConstVal::Int(x.checked_pow(u32::try_from(y).ok()?)?),
                    Eq => ConstVal::Bool(x == y),
                    Ne => ConstVal::Bool(x != y),
                    Lt => ConstVal::Bool(x < y),
                    Le => ConstVal::Bool(x <= y),
                    Gt => ConstVal::Bool(x > y),
                    Ge => ConstVal::Bool(x >= y),
                    And | AndThen => ConstVal::Int(x & y),
                    Or | OrElse => ConstVal::Int(x | y),
                    Xor => ConstVal::Int(x ^ y),
                },
                (ConstVal::Real(x), ConstVal::Real(y)) => match op {
                    Add => ConstVal::Real(x + y),
                    Sub => ConstVal::Real(x - y),
                    Mul => ConstVal::Real(x * y),
                    Div => ConstVal::Real(x / y),
                    Pow => ConstVal::Real(x.powf(y)),
                    Eq => ConstVal::Bool(x == y),
                    Ne => ConstVal::Bool(x != y),
                    Lt => ConstVal::Bool(x < y),
                    Le => ConstVal::Bool(x <= y),
                    Gt => ConstVal::Bool(x > y),
                    Ge => ConstVal::Bool(x >= y),
                    _ => return None,
                },
                (ConstVal::Bool(x), ConstVal::Bool(y)) => match op {
                    And | AndThen => ConstVal::Bool(x && y),
                    Or | OrElse => ConstVal::Bool(x || y),
                    Xor => ConstVal::Bool(x ^ y),
                    Eq => ConstVal::Bool(x == y),
                    Ne => ConstVal::Bool(x != y),
                    _ => return None,
                },
                _ => return None,
            };
            let ty = if matches!(v, ConstVal::Bool(_)) {
                Ty::BOOL
            } else {
                ty
            };
            // Typed integer arithmetic wraps at run time; a result outside the type is
            // not the value the program computes, so it is no constant to rely on
            // (an index known "in range" this way would skip its bounds check).
            if let (ConstVal::Int(i), Some(e)) = (&v, ty.elem()) {
                if let Some((lo, hi)) = int_range(e) {
                    if !ty.is_literal() && (*i < lo || *i > hi) {
                        return None;
                    }
                }
            }
            // REAL arithmetic rounds every result to binary32, as at run time (binary64
            // arithmetic on binary32 operands, then one rounding, gives the same
            // result for + - * /).
            let single = ty == Ty::Elem(ElemType::Real)
                || (ty.is_literal() && want == Some(Ty::Elem(ElemType::Real)));
            let v = match v {
                ConstVal::Real(r) if single => ConstVal::Real(r as f32 as f64),
                v => v,
            };
            Some((v, ty))
        }
        _ => None,
    }
}
