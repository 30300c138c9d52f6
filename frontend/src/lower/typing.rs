//! Typing of expressions: the common type of two operands, literal types made
//! concrete, the typing of binary operators, and the type of an expression inferred
//! without emitting anything (`infer`). `expr` emits what these type.

use super::body::BodyCx;
use super::literals::bool_digit_operands;
use super::places::index_chain;
use super::usertypes::EnumLookup;
use crate::ast::{BinaryOp as Op, Expr, ExprKind, LiteralKind, UnaryOp as UOp};
use crate::types::{implicit, Ty};
use plcc_ir::ElemType;

/// How a binary operator's operands and result are typed.
#[derive(Copy, Clone, Debug)]
pub(super) struct BinTyping {
    /// The type both operands are emitted at (may be a literal type).
    pub operand: Ty,
    /// For TIME * n and TIME / n: the type of the right operand.
    pub right: Option<Ty>,
    /// The result type.
    pub result: Ty,
}

/// The common type of two operands, or `None` if they do not combine.
pub(super) fn unify(a: Ty, b: Ty) -> Option<Ty> {
    use Ty::*;
    Some(match (a, b) {
        (Error, _) | (_, Error) => Error,
        (x, y) if x == y => x,
        (AnyInt, AnyReal) | (AnyReal, AnyInt) => AnyReal,
        (AnyInt, t) | (t, AnyInt) if t.is_numeric() => t,
        (AnyInt, _) | (_, AnyInt) => return None,
        (AnyReal, t) | (t, AnyReal) if t.is_real() => t,
        (AnyReal, _) | (_, AnyReal) => return None,
        (Elem(x), Elem(y)) => {
            if implicit(x, y) {
                Elem(y)
            } else if implicit(y, x) {
                Elem(x)
            } else {
                return None;
            }
        }
        _ => return None,
    })
}

/// The concrete type a literal type takes in a context that wants `want`: the wanted
/// type if it is of the same kind, else the default (DINT, LREAL).
pub(super) fn concretize(t: Ty, want: Option<Ty>) -> Ty {
    match t {
        Ty::AnyInt => match want {
            Some(w @ Ty::Elem(e)) if w.is_int_like() || e.is_real() => w,
            _ => Ty::DINT,
        },
        Ty::AnyReal => match want {
            Some(w) if w.is_real() && !w.is_literal() => w,
            _ => Ty::Elem(ElemType::LReal),
        },
        t => t,
    }
}

pub(super) fn is_duration(t: Ty) -> bool {
    t.elem().is_some_and(|e| e.is_duration())
}

/// Types a binary operator. The error text says what is wrong.
pub(super) fn binary_typing(
    op: Op,
    l: Ty,
    r: Ty,
    names: &dyn Fn(Ty) -> String,
) -> Result<BinTyping, String> {
    let mismatch = || {
        format!(
            "`{}` cannot combine {} and {}",
            op.symbol(),
            names(l),
            names(r)
        )
    };
    if l == Ty::Error || r == Ty::Error {
        return Ok(BinTyping {
            operand: Ty::Error,
            right: None,
            result: if matches!(op, Op::Eq | Op::Ne | Op::Lt | Op::Le | Op::Gt | Op::Ge) {
                Ty::BOOL
            } else {
                Ty::Error
            },
        });
    }
    let same = |t: Ty| BinTyping {
        operand: t,
        right: None,
        result: t,
    };
    match op {
        Op::And | Op::Or | Op::Xor => {
            let t = unify(l, r).ok_or_else(mismatch)?;
            if t == Ty::BOOL || t.is_int_like() {
                Ok(same(t))
            } else {
                Err(format!(
                    "`{}` needs BOOL or bit-string operands, not {}",
                    op.symbol(),
                    names(t)
                ))
            }
        }
        Op::AndThen | Op::OrElse => {
            if unify(l, r) == Some(Ty::BOOL) {
                Ok(same(Ty::BOOL))
            } else {
                Err(format!("`{}` needs BOOL operands", op.symbol()))
            }
        }
        Op::Eq | Op::Ne | Op::Lt | Op::Le | Op::Gt | Op::Ge
            if matches!(l, Ty::Ref(_) | Ty::Null) || matches!(r, Ty::Ref(_) | Ty::Null) =>
        {
            let fits = match (l, r) {
                (Ty::Null, Ty::Ref(_) | Ty::Null) | (Ty::Ref(_), Ty::Null) => true,
                (Ty::Ref(a), Ty::Ref(b)) => a == b,
                _ => false,
            };
            if !fits {
                return Err(mismatch());
            }
            if !matches!(op, Op::Eq | Op::Ne) {
                return Err(format!(
                    "`{}` cannot compare references: only `=` and `<>` can",
                    op.symbol()
                ));
            }
            Ok(BinTyping {
                operand: l,
                right: None,
                result: Ty::BOOL,
            })
        }
        Op::Eq | Op::Ne | Op::Lt | Op::Le | Op::Gt | Op::Ge => {
            if let (Ty::Str(x), Ty::Str(y)) = (l, r) {
                if x.wide != y.wide {
                    return Err(format!(
                        "`{}` cannot compare a STRING with a WSTRING: convert one with STRING_TO_WSTRING or WSTRING_TO_STRING",
                        op.symbol()
                    ));
                }
                return Ok(BinTyping {
                    operand: l,
                    right: None,
                    result: Ty::BOOL,
                });
            }
            if l.is_aggregate() || r.is_aggregate() {
                let t = if l.is_aggregate() { l } else { r };
                return Err(format!(
                    "`{}` cannot compare {} as a whole: compare STRUCTs field by field and arrays element by element",
                    op.symbol(),
                    names(t)
                ));
            }
            let t = unify(l, r).ok_or_else(mismatch)?;
            if let Ty::Enum(..) = t {
                return if matches!(op, Op::Eq | Op::Ne) {
                    Ok(BinTyping {
                        operand: t,
                        right: None,
                        result: Ty::BOOL,
                    })
                } else {
                    Err(format!(
                        "`{}` cannot compare values of the enumeration {}: only `=` and `<>` can",
                        op.symbol(),
                        names(t)
                    ))
                };
            }
            if t.elem().is_some() || t.is_literal() {
                Ok(BinTyping {
                    operand: t,
                    right: None,
                    result: Ty::BOOL,
                })
            } else {
                Err(format!(
                    "`{}` cannot compare values of type {}",
                    op.symbol(),
                    names(t)
                ))
            }
        }
        Op::Add | Op::Sub if super::dates::is_date(l) || super::dates::is_date(r) => {
            match super::dates::date_arith_type(op, l, r) {
                Some(t) => Ok(BinTyping {
                    operand: l,
                    right: Some(r),
                    result: t,
                }),
                None => Err(format!(
                    "{}: dates combine as TOD ± TIME, DT ± TIME, and DATE, TOD or DT minus one of its own type",
                    mismatch()
                )),
            }
        }
        Op::Add | Op::Sub => {
            if is_duration(l) || is_duration(r) {
                let t = unify(l, r)
                    .filter(|t| is_duration(*t))
                    .ok_or_else(mismatch)?;
                return Ok(same(t));
            }
            let t = unify(l, r).ok_or_else(mismatch)?;
            if t.is_numeric() {
                Ok(same(t))
            } else {
                Err(mismatch())
            }
        }
        Op::Mul | Op::Div => {
            if is_duration(l) && r.is_numeric() {
                return Ok(BinTyping {
                    operand: l,
                    right: Some(r),
                    result: l,
                });
            }
            if op == Op::Mul && is_duration(r) && l.is_numeric() {
                return Ok(BinTyping {
                    operand: r,
                    right: Some(l),
                    result: r,
                });
            }
            let t = unify(l, r).ok_or_else(mismatch)?;
            if t.is_numeric() {
                Ok(same(t))
            } else {
                Err(mismatch())
            }
        }
        Op::Mod => {
            let t = unify(l, r).ok_or_else(mismatch)?;
            if t.is_int_like() {
                Ok(same(t))
            } else {
                Err(format!("MOD needs integer operands, not {}", names(t)))
            }
        }
        Op::Pow => {
            if !(l.is_numeric() && r.is_numeric()) {
                return Err(mismatch());
            }
            if l.is_real() {
                Ok(BinTyping {
                    operand: l,
                    right: Some(r),
                    result: l,
                })
            } else if r.is_real() {
                // An integer base with a real exponent computes in the exponent's type.
                let t = if r == Ty::AnyReal {
                    Ty::Elem(ElemType::LReal)
                } else {
                    r
                };
                Ok(BinTyping {
                    operand: t,
                    right: Some(r),
                    result: t,
                })
            } else {
                Ok(BinTyping {
                    operand: l,
                    right: Some(r),
                    result: l,
                })
            }
        }
    }
}

impl<'s> BodyCx<'_, 's> {
    /// The type of an expression, without emitting anything or reporting errors.
    pub(super) fn infer(&mut self, e: &Expr) -> Ty {
        let t = self.infer_raw(e);
        self.auto_deref_ty(t)
    }

    /// The type of an expression, a REFERENCE TO variable as itself.
    pub(super) fn infer_raw(&mut self, e: &Expr) -> Ty {
        match &e.kind {
            ExprKind::Paren(x) | ExprKind::UsedBy { value: x, .. } => self.infer(x),
            ExprKind::Literal(lit) => {
                if let Some(p) = lit.type_prefix {
                    if !matches!(lit.kind, LiteralKind::String { .. }) {
                        return self.prefix_type(p.sym).unwrap_or(Ty::Error);
                    }
                }
                match &lit.kind {
                    LiteralKind::Int(_) => Ty::AnyInt,
                    LiteralKind::Real(_) => Ty::AnyReal,
                    LiteralKind::Bool(_) => Ty::BOOL,
                    LiteralKind::Duration { long: false, .. } => Ty::TIME,
                    LiteralKind::Duration { long: true, .. } => Ty::Elem(ElemType::LTime),
                    LiteralKind::String { wide, units } => Self::literal_string_ty(*wide, units),
                    LiteralKind::Date { long: false, .. } => Ty::Elem(ElemType::Date),
                    LiteralKind::TimeOfDay { long: false, .. } => Ty::Elem(ElemType::Tod),
                    LiteralKind::DateTime { long: false, .. } => Ty::Elem(ElemType::Dt),
                    LiteralKind::Date { long: true, .. } => Ty::Elem(ElemType::LDate),
                    LiteralKind::TimeOfDay { long: true, .. } => Ty::Elem(ElemType::LTod),
                    LiteralKind::DateTime { long: true, .. } => Ty::Elem(ElemType::LDt),
                }
            }
            ExprKind::Name(_) | ExprKind::Member(..) if self.property_of(e).is_some() => {
                self.property_ty(e).unwrap_or(Ty::Error)
            }
            ExprKind::Name(id) => self.name_type(id.sym),
            ExprKind::Member(base, name) if self.qualifier(base).is_some() => {
                let q = self.qualifier(base).expect("checked");
                self.qualified_type(q, *name)
            }
            ExprKind::Deref(_) if self.self_ref(e).is_some() => match self.self_ref(e) {
                Some(super::methods::SelfRef::This(c) | super::methods::SelfRef::Super(c)) => {
                    Ty::Fb(c)
                }
                None => Ty::Error,
            },
            ExprKind::Member(base, name) => match self.infer(base) {
                Ty::Fb(p) => match self.l.class_var(p, name.sym) {
                    Some((c, vi)) => self.l.pou(c).vars[vi].ty,
                    None => self.property_type(p, name.sym),
                },
                Ty::Struct(s) => self
                    .l
                    .struct_field(s, name.sym)
                    .map(|f| self.l.user.structs[s.0 as usize].fields[f].ty)
                    .unwrap_or(Ty::Error),
                _ => Ty::Error,
            },
            ExprKind::EnumValue { ty, value } => match self.l.qualified_enum(**ty, *value, false) {
                Some((e, base, _)) => Ty::Enum(e, base),
                None => Ty::Error,
            },
            ExprKind::Bit(..) => Ty::BOOL,
            ExprKind::Partial(_, size, _) => match size {
                8 => Ty::Elem(ElemType::Byte),
                16 => Ty::Elem(ElemType::Word),
                32 => Ty::Elem(ElemType::DWord),
                _ => Ty::Elem(ElemType::LWord),
            },
            ExprKind::Deref(x) => {
                let r = self.infer_raw(x);
                self.deref_type(r)
            }
            ExprKind::Index(..) => {
                let (base, idx) = index_chain(e);
                match self.infer(base) {
                    Ty::Array(a) if self.l.types.get(a).dims.len() == idx.len() => {
                        self.l.types.get(a).elem
                    }
                    _ => Ty::Error,
                }
            }
            ExprKind::Unary(UOp::Not, x)
            | ExprKind::Unary(UOp::Neg, x)
            | ExprKind::Unary(UOp::Plus, x) => self.infer(x),
            ExprKind::Binary(op, a, b) => {
                let (l, r) = (self.infer(a), self.infer(b));
                if matches!(op, Op::Eq | Op::Ne) && self.is_iface_zero(l, r) {
                    return Ty::BOOL;
                }
                let (l, r) = bool_digit_operands(*op, l, r, (a, b), None);
                binary_typing(*op, l, r, &|_| String::new())
                    .ok()
                    .or_else(|| self.codesys_binary_type(*op, l, r))
                    .map(|t| t.result)
                    .unwrap_or(Ty::Error)
            }
            ExprKind::Call { callee, args } => self.infer_call(callee, args),
            _ => Ty::Error,
        }
    }

    /// The type of a plain name (without emitting code).
    fn name_type(&self, sym: crate::intern::Symbol) -> Ty {
        if self.void_temps.contains_key(&sym) {
            return Ty::Error;
        }
        if let Some(&(_, ty)) = self.temps.get(&sym) {
            return ty;
        }
        let pou = self.l.pou(self.pou);
        if let Some(vi) = pou.var(sym) {
            return pou.vars[vi as usize].ty;
        }
        if let Some(t) = self.class_name_type(sym) {
            return t;
        }
        if pou.kind == crate::ast::PouKind::Function && pou.name.sym == sym {
            return pou.ret;
        }
        if let Some(g) = self.l.globals_pou.filter(|_| !pou.std) {
            let gp = self.l.pou(g);
            if let Some(vi) = gp.var(sym) {
                return gp.vars[vi as usize].ty;
            }
        }
        match self.l.enum_named(sym, None) {
            EnumLookup::One(e, base, _) => Ty::Enum(e, base),
            _ if self.l.sym_name(sym).eq_ignore_ascii_case("NULL") => Ty::Null,
            _ => Ty::Error,
        }
    }

    /// True if `e` is a bare name that reads as a value of the enumeration `ty` (and
    /// names nothing else): an operand whose enumeration the other operand tells.
    pub(super) fn is_value_of(&self, e: &Expr, ty: Ty) -> bool {
        let mut e = e;
        while let ExprKind::Paren(x) = &e.kind {
            e = x;
        }
        match (&e.kind, ty) {
            (ExprKind::Name(id), Ty::Enum(en, _)) => {
                self.name_type(id.sym) == Ty::Error && self.l.enum_value_of(en, id.sym).is_some()
            }
            _ => false,
        }
    }
}
