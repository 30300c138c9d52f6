//! Literals: their emission at the type the context wants, and IEC 61131-3's
//! boolean literals `0` and `1` wherever a BOOL is expected.
//!
//! An untyped integer literal is [`Ty::AnyInt`] until its context types it. Where a
//! BOOL is wanted (an assignment, an input, a condition) a plain 0 or 1 is that BOOL;
//! beside a BOOL operand of `AND`, `OR`, `XOR`, `AND_THEN`, `OR_ELSE` or a comparison,
//! and among the arguments of a standard function whose other arguments are BOOLs, it
//! is taken for a BOOL too ([`bool_digit_operands`], [`is_bool_digit`]). Any other
//! integer stays an integer: 2 is never a BOOL.

use super::body::BodyCx;
use super::consts::ConstVal;
use super::expr::Val;
use super::typing::concretize;
use super::usertypes::TypeState;
use crate::ast::{BinaryOp as Op, Expr, ExprKind, Literal, LiteralKind, UnaryOp};
use crate::codes;
use crate::types::Ty;
use plcc_ir::diag::Span;
use plcc_ir::{ElemType, Type};

/// True if `e` is one of IEC 61131-3's boolean literals 0 and 1 (an integer literal
/// of value 0 or 1 written without a type prefix), in parentheses or not, or `NOT`,
/// `AND`, `OR` or `XOR` of such: an expression that is a BOOL where a BOOL is wanted.
pub(super) fn is_bool_digit(e: &Expr) -> bool {
    match &e.kind {
        ExprKind::Paren(x) | ExprKind::UsedBy { value: x, .. } => is_bool_digit(x),
        ExprKind::Literal(l) => matches!(
            **l,
            Literal {
                kind: LiteralKind::Int(0 | 1),
                type_prefix: None,
            }
        ),
        ExprKind::Unary(UnaryOp::Not, x) => is_bool_digit(x),
        ExprKind::Binary(Op::And | Op::Or | Op::Xor, a, b) => is_bool_digit(a) && is_bool_digit(b),
        _ => false,
    }
}

/// The operand types `(lt, rt)` of `a op b`, with a 0 or 1 beside a BOOL taken for a
/// BOOL when `op` is one that BOOLs take (logic and comparison); two of them joined
/// by `AND`, `OR` or `XOR` are BOOLs where the context `want`s a BOOL.
pub(super) fn bool_digit_operands(
    op: Op,
    lt: Ty,
    rt: Ty,
    (a, b): (&Expr, &Expr),
    want: Option<Ty>,
) -> (Ty, Ty) {
    use Op::*;
    let logic = matches!(op, And | Or | Xor | AndThen | OrElse);
    if !logic && !matches!(op, Eq | Ne | Lt | Le | Gt | Ge) {
        return (lt, rt);
    }
    match (lt, rt) {
        (Ty::BOOL, Ty::AnyInt) if is_bool_digit(b) => (lt, Ty::BOOL),
        (Ty::AnyInt, Ty::BOOL) if is_bool_digit(a) => (Ty::BOOL, rt),
        (Ty::AnyInt, Ty::AnyInt)
            if logic && want == Some(Ty::BOOL) && is_bool_digit(a) && is_bool_digit(b) =>
        {
            (Ty::BOOL, Ty::BOOL)
        }
        _ => (lt, rt),
    }
}

/// True if the arguments `xs` of a standard function, of the types `tys`, are BOOLs
/// with their integer literals all 0 or 1: some argument is a BOOL, or the context
/// wants a BOOL, and every untyped integer literal among them is 0 or 1.
pub(super) fn bool_digit_args(xs: &[&Expr], tys: &[Ty], want: Option<Ty>) -> bool {
    let literals = || xs.iter().zip(tys).filter(|(_, t)| **t == Ty::AnyInt);
    (want == Some(Ty::BOOL) || tys.contains(&Ty::BOOL))
        && literals().next().is_some()
        && literals().all(|(x, _)| is_bool_digit(x))
        && tys.iter().all(|t| matches!(*t, Ty::AnyInt | Ty::BOOL))
}

impl<'s> BodyCx<'_, 's> {
    /// The type a typed literal's prefix names: an elementary type, or a TYPE that
    /// is one (`Celsius#20.5`).
    pub(super) fn prefix_type(&self, sym: crate::intern::Symbol) -> Option<Ty> {
        if let Some(t) = ElemType::from_name(self.l.sym_name(sym)) {
            return Some(Ty::Elem(t));
        }
        let &i = self.l.user.by_name.get(&sym)?;
        match self.l.user.named[i as usize].state {
            TypeState::Done(t @ Ty::Elem(_), _) => Some(t),
            _ => None,
        }
    }

    /// Emits a literal; `negate` folds a unary minus in (so `-128` is a SINT).
    pub(super) fn literal(&mut self, e: &'s Expr, want: Option<Ty>, negate: bool) -> Val {
        let ExprKind::Literal(lit) = &e.kind else {
            unreachable!()
        };
        if let LiteralKind::String { .. } = lit.kind {
            return self.string_literal(e, want);
        }
        let prefix = match lit.type_prefix {
            Some(p) => match self.prefix_type(p.sym) {
                Some(t) => Some(t),
                None => {
                    let n = self.l.text(p.span).to_string();
                    self.l.error(
                        codes::E_UNKNOWN_TYPE,
                        format!("unknown type `{n}` in a typed literal"),
                        p.span,
                    );
                    return self.error_val();
                }
            },
            None => None,
        };
        let (value, lit_ty) = match &lit.kind {
            LiteralKind::Int(v) => (ConstVal::Int(if negate { -v } else { *v }), Ty::AnyInt),
            LiteralKind::Real(text) => {
                // Keep the text so REAL literals round once, straight to binary32.
                let ty = concretize(prefix.unwrap_or(Ty::AnyReal), want);
                let ty = if prefix.is_some() {
                    prefix.unwrap_or(ty)
                } else {
                    ty
                };
                return match ty {
                    Ty::Elem(ElemType::Real) => {
                        let f: f32 = text.parse().unwrap_or(0.0);
                        let v = self.b.f32const(if negate { -f } else { f });
                        Val { v, ty }
                    }
                    Ty::Elem(ElemType::LReal) => {
                        let f: f64 = text.parse().unwrap_or(0.0);
                        let v = self.b.f64const(if negate { -f } else { f });
                        Val { v, ty }
                    }
                    _ => {
                        let t = self.l.ty_name(ty);
                        self.l.error(
                            codes::E_TYPE_MISMATCH,
                            format!("a real literal cannot be a {t}"),
                            e.span,
                        );
                        self.error_val()
                    }
                };
            }
            LiteralKind::Bool(b) => (ConstVal::Bool(*b), Ty::BOOL),
            LiteralKind::Duration { ns, long } => {
                let ns = if negate { -ns } else { *ns };
                if *long {
                    (ConstVal::Int(ns), Ty::Elem(ElemType::LTime))
                } else {
                    (ConstVal::Int(ns / 1_000_000), Ty::TIME)
                }
            }
            kind => match self.date_literal(kind, e.span) {
                Some(x) => x,
                None => return self.error_val(),
            },
        };
        let ty = match prefix {
            Some(p) => {
                if let (Ty::Elem(ElemType::Bool), ConstVal::Int(v)) = (p, value) {
                    if v == 0 || v == 1 {
                        let v = self.b.iconst(Type::I1, v as i64);
                        return Val { v, ty: p };
                    }
                }
                p
            }
            // IEC 61131-3's boolean literals include plain 0 and 1.
            None if lit_ty == Ty::AnyInt
                && want == Some(Ty::BOOL)
                && matches!(value, ConstVal::Int(0 | 1)) =>
            {
                Ty::BOOL
            }
            None => concretize(lit_ty, want),
        };
        self.constant(value, ty, None, e.span)
    }

    /// Emits a constant of type `ty` (a literal type is made concrete with `want`).
    pub(super) fn constant(&mut self, c: ConstVal, ty: Ty, want: Option<Ty>, span: Span) -> Val {
        if let (Ty::Enum(_, base), ConstVal::Int(i)) = (ty, c) {
            let v = self.b.iconst(base.ir_type(), i as i64);
            return Val { v, ty };
        }
        let ty = concretize(ty, want);
        let c = match c.coerce(ty) {
            Ok(c) => c,
            Err(msg) => {
                self.l.error(codes::E_LITERAL_RANGE, msg, span);
                return self.error_val();
            }
        };
        let v = match (c, ty.ir()) {
            (ConstVal::Bool(b), _) => self.b.iconst(Type::I1, b as i64),
            (ConstVal::Real(r), Some(t)) => self.b.fconst(t, r),
            (ConstVal::Int(i), Some(t)) => self.b.iconst(t, i as i64),
            _ => return self.error_val(),
        };
        Val { v, ty }
    }
}
