//! Expressions: type inference, type checking and emission.
//!
//! `infer` computes an expression's type without emitting anything (literals stay
//! [`Ty::AnyInt`]/[`Ty::AnyReal`]); `emit` then emits it, giving untyped literals the
//! type the context wants. Operators follow IEC 61131-3: both operands get one common
//! type by implicit widening, integer literals adapt to the other operand.

use super::body::{BodyCx, Named, Place};
use super::consts::ConstVal;
use super::literals::bool_digit_operands;
use super::typing::{binary_typing, concretize, is_duration};
use crate::ast::{BinaryOp as Op, Expr, ExprKind, LiteralKind, UnaryOp as UOp};
use crate::codes;
use crate::types::{implicit, Ty};
use plcc_ir::diag::Span;
use plcc_ir::{BinaryOp, ConvOp, ElemType, FloatCC, IntCC, Type, UnaryOp, Value};

/// An emitted value and its (concrete) type.
#[derive(Copy, Clone, Debug)]
pub(super) struct Val {
    pub v: Value,
    pub ty: Ty,
}

impl<'s> BodyCx<'_, 's> {
    /// Emits an expression and converts it (implicitly, with checks) to `target`.
    pub(super) fn emit_as(&mut self, e: &'s Expr, target: Ty) -> Value {
        // An instance where an interface is expected: its address.
        if let Some(v) = self.instance_as_iface(e, target) {
            return v;
        }
        let v = self.emit(e, Some(target));
        if v.ty == target && target.is_aggregate() {
            // A whole STRUCT or array is copied through its address (`agg_source`),
            // never carried as one value.
            let t = self.l.ty_name(target);
            self.l.error(
                codes::E_TYPE_MISMATCH,
                format!("a whole {t} cannot be used as a value here"),
                e.span,
            );
            return self.zero(target);
        }
        if let (Ty::Enum(en, _), ExprKind::Name(id)) = (target, &e.kind) {
            if v.ty != target && v.ty != Ty::Error && self.l.enum_value_of(en, id.sym).is_some() {
                // A variable hides the enumeration value of the same name.
                let n = self.l.text(id.span).to_string();
                let (t, found) = (self.l.ty_name(target), self.l.ty_name(v.ty));
                self.l.diags.push(
                    plcc_ir::diag::Diagnostic::error(
                        codes::E_TYPE_MISMATCH,
                        format!("expected {t}, found {found}"),
                        e.span,
                    )
                    .with_label(format!("this `{n}` is a variable, not the value of {t}"))
                    .with_note(format!("write `{t}#{n}` for the value")),
                );
                return self.zero(target);
            }
        }
        let fits = match (v.ty, target) {
            (a, b) if a == b => true,
            (a, b) if self.ref_fits(a, b) => true,
            (a, b) if self.codesys_implicit(a, b) => true,
            (Ty::Error, _) | (_, Ty::Error) => true,
            (Ty::Elem(a), Ty::Elem(b)) => implicit(a, b),
            _ => false,
        };
        if let (false, Ty::Elem(from), Ty::Elem(to)) = (fits, v.ty, target) {
            // A constant integer expression (`7 MOD 2`, `16#F0 OR 1`) computed as an
            // integer is a number like a literal: it converts to a real.
            if from.is_integer() && to.is_real() && self.infer(e) == Ty::AnyInt {
                return self.convert(v.v, from, to);
            }
        }
        if !fits {
            // A literal that cannot take the wanted type: say so in source terms, not
            // in terms of the type plcc picked for it.
            let lit = self.infer(e);
            if lit.is_literal() {
                let what = if lit == Ty::AnyInt {
                    "an integer literal"
                } else {
                    "a real literal"
                };
                let want = self.l.ty_name(target);
                let mut d = plcc_ir::diag::Diagnostic::error(
                    codes::E_TYPE_MISMATCH,
                    format!("expected {want}, found {what}"),
                    e.span,
                );
                d = match target {
                    Ty::Elem(t) if t.is_duration() => d.with_note("write a duration literal, e.g. `T#5s`"),
                    Ty::Elem(ElemType::Bool) => d.with_note("write TRUE or FALSE, or 1 or 0"),
                    Ty::Elem(t) if t.is_integer() || t.is_bit_string() => {
                        d.with_note(format!("{want} holds whole numbers; convert explicitly, e.g. `LREAL_TO_{want}(...)`"))
                    }
                    Ty::Enum(en, _) => d.with_note(self.enum_note(en)),
                    _ => d,
                };
                self.l.diags.push(d);
                return self.zero(target);
            }
        }
        self.coerce(v, target, e.span)
    }

    /// Converts a value to `target` if IEC allows it implicitly; reports otherwise.
    pub(super) fn coerce(&mut self, v: Val, target: Ty, span: Span) -> Value {
        if v.ty == target {
            return v.v;
        }
        if v.ty == Ty::Error || target == Ty::Error {
            return self.zero(target);
        }
        if self.ref_fits(v.ty, target) {
            self.note_pointer_cast(v.ty, target);
            return v.v;
        }
        if self.codesys_implicit(v.ty, target) {
            return self.codesys_convert(v.v, v.ty, target);
        }
        match (v.ty, target) {
            (Ty::Elem(from), Ty::Elem(to)) if implicit(from, to) => self.convert(v.v, from, to),
            (Ty::Elem(from), Ty::Elem(to)) => {
                let d = plcc_ir::diag::Diagnostic::error(
                    codes::E_TYPE_MISMATCH,
                    format!("expected {}, found {}", to.name(), from.name()),
                    span,
                )
                .with_label(format!("this is {}", from.name()))
                .with_note(format!(
                    "convert explicitly, e.g. `{}_TO_{}(...)`",
                    from.name(),
                    to.name()
                ));
                self.l.diags.push(d);
                self.zero(target)
            }
            _ => {
                let (a, b) = (self.l.ty_name(target), self.l.ty_name(v.ty));
                let mut d = plcc_ir::diag::Diagnostic::error(
                    codes::E_TYPE_MISMATCH,
                    format!("expected {a}, found {b}"),
                    span,
                );
                match (target, v.ty) {
                    (Ty::Enum(en, _), _) => d = d.with_note(self.enum_note(en)),
                    (_, Ty::Enum(..)) => {
                        d = d.with_note("an enumeration value is not a number: compare it with the values of its type, or use CASE")
                    }
                    _ => {}
                }
                self.l.diags.push(d);
                self.zero(target)
            }
        }
    }

    /// What an enumeration accepts, for a mismatch diagnostic.
    fn enum_note(&self, en: crate::types::EnumId) -> String {
        let e = &self.l.user.enums[en.0 as usize];
        let first = e.values.first().map_or("", |v| v.display.as_str());
        format!(
            "a variable of the enumeration {} takes only its values, e.g. `{}#{first}`",
            e.display, e.display
        )
    }

    /// The value of what a name stands for.
    fn named_val(&mut self, named: Named, want: Option<Ty>, span: Span) -> Val {
        match named {
            Named::Place(p) if matches!(p.ty, Ty::Str(_)) => {
                let v = self.readable_addr(&p);
                Val { v, ty: p.ty }
            }
            Named::Place(p) => {
                let p = self.auto_deref(p);
                if let Ty::Str(_) = p.ty {
                    let v = self.readable_addr(&p);
                    return Val { v, ty: p.ty };
                }
                let v = self.load_place(&p);
                Val { v, ty: p.ty }
            }
            Named::Const(c, ty) => self.constant(c, ty, want, span),
            Named::Error => self.error_val(),
        }
    }

    /// The value of a member, element, bit or dereference at `p`: a string's
    /// address, or a scalar.
    fn member_val(&mut self, p: Place, span: Span) -> Val {
        if matches!(p.ty, Ty::Str(_)) {
            let v = self.readable_addr(&p);
            return Val { v, ty: p.ty };
        }
        if !matches!(p.ty, Ty::Elem(_) | Ty::Enum(..) | Ty::Ref(_) | Ty::Error) {
            let t = self.l.ty_name(p.ty);
            self.l.error(
                codes::E_TYPE_MISMATCH,
                format!("a whole {t} cannot be used as a value here"),
                span,
            );
            return self.error_val();
        }
        let v = self.load_place(&p);
        Val { v, ty: p.ty }
    }

    /// Emits an expression. `want` is the type the context would like (it decides the
    /// type of untyped literals); the result may still have another type.
    pub(super) fn emit(&mut self, e: &'s Expr, want: Option<Ty>) -> Val {
        match &e.kind {
            ExprKind::Paren(x) | ExprKind::UsedBy { value: x, .. } => self.emit(x, want),
            ExprKind::Literal(_) => self.literal(e, want, false),
            ExprKind::Name(_) if self.is_null_name(e) => self.null_val(),
            ExprKind::Name(_) | ExprKind::Member(..) if self.property_of(e).is_some() => {
                let p = self.property_of(e).expect("checked");
                self.property_read(p, e.span)
            }
            ExprKind::Name(id) => {
                let named = self.resolve_name(*id, true, want);
                self.named_val(named, want, e.span)
            }
            // `GVL.x`, `Prog.x` (see `qualified`).
            ExprKind::Member(base, name) if self.qualifier(base).is_some() => {
                let q = self.qualifier(base).expect("checked");
                match self.qualified(q, base, *name) {
                    Named::Place(p) => {
                        let p = self.auto_deref(p);
                        self.member_val(p, e.span)
                    }
                    named => self.named_val(named, want, e.span),
                }
            }
            ExprKind::Member(..) | ExprKind::Index(..) | ExprKind::Bit(..) | ExprKind::Deref(_) => {
                match self.place(e) {
                    Some(p) => self.member_val(p, e.span),
                    None => self.error_val(),
                }
            }
            ExprKind::Unary(op, x) => self.unary(*op, x, want, e.span),
            ExprKind::Binary(op, a, b) => self.binary(*op, a, b, want, e.span),
            ExprKind::Call { callee, args } => match self.call_expr(callee, args, want, e.span) {
                Some(v) => v,
                None => self.error_val(),
            },
            ExprKind::EnumValue { ty, value } => match self.l.qualified_enum(**ty, *value, true) {
                Some((en, base, v)) => {
                    self.constant(ConstVal::Int(v), Ty::Enum(en, base), None, e.span)
                }
                None => self.error_val(),
            },
            ExprKind::DirectAddress(_) => {
                self.unsupported("direct addresses in expressions", e.span)
            }
            ExprKind::Partial(base, size, n) => self.partial_read(e, base, *size, *n),
        }
    }

    pub(super) fn unsupported(&mut self, what: &str, span: Span) -> Val {
        self.l.error(
            codes::E_UNSUPPORTED,
            format!("not supported yet: {what}"),
            span,
        );
        self.error_val()
    }

    /// A placeholder for an expression that had an error.
    pub(super) fn error_val(&mut self) -> Val {
        let v = self.b.iconst(Type::I32, 0);
        Val { v, ty: Ty::Error }
    }

    fn unary(&mut self, op: UOp, x: &'s Expr, want: Option<Ty>, span: Span) -> Val {
        match op {
            UOp::Plus => self.emit(x, want),
            UOp::Neg => {
                let mut inner = x;
                while let ExprKind::Paren(i) = &inner.kind {
                    inner = i;
                }
                if let ExprKind::Literal(lit) = &inner.kind {
                    if !matches!(lit.kind, LiteralKind::Bool(_) | LiteralKind::String { .. }) {
                        return self.literal(inner, want, true);
                    }
                }
                let v = self.emit(x, want);
                match v.ty {
                    Ty::Error => v,
                    t if t.is_real() => Val {
                        v: self.b.unary(UnaryOp::Fneg, v.v),
                        ty: t,
                    },
                    t if t.is_signed() => Val {
                        v: self.b.unary(UnaryOp::Ineg, v.v),
                        ty: t,
                    },
                    // CODESYS negates unsigned values too (two's complement).
                    t if self.l.codesys && t.is_int_like() => Val {
                        v: self.b.unary(UnaryOp::Ineg, v.v),
                        ty: t,
                    },
                    t => {
                        let n = self.l.ty_name(t);
                        self.l.error(
                            codes::E_TYPE_MISMATCH,
                            format!("cannot negate a value of type {n} (it has no sign)"),
                            span,
                        );
                        self.error_val()
                    }
                }
            }
            UOp::Not => {
                let v = self.emit(x, want);
                match v.ty {
                    Ty::Error => v,
                    t if t == Ty::BOOL || t.is_int_like() => Val {
                        v: self.b.unary(UnaryOp::Bnot, v.v),
                        ty: t,
                    },
                    t => {
                        let n = self.l.ty_name(t);
                        self.l.error(
                            codes::E_TYPE_MISMATCH,
                            format!("NOT needs a BOOL or a bit string, not {n}"),
                            span,
                        );
                        self.error_val()
                    }
                }
            }
        }
    }

    pub(super) fn binary(
        &mut self,
        op: Op,
        a: &'s Expr,
        b: &'s Expr,
        want: Option<Ty>,
        span: Span,
    ) -> Val {
        let (mut lt, mut rt) = (self.infer(a), self.infer(b));
        // `c = Red` with `Red` a value of several enumerations: `c` says which.
        if matches!(lt, Ty::Enum(..)) && rt == Ty::Error && self.is_value_of(b, lt) {
            rt = lt;
        } else if matches!(rt, Ty::Enum(..)) && lt == Ty::Error && self.is_value_of(a, rt) {
            lt = rt;
        }
        if matches!(op, Op::Eq | Op::Ne) {
            if let Some(v) = self.iface_compare(op == Op::Eq, a, b, lt, rt) {
                return v;
            }
        }
        let (lt, rt) = bool_digit_operands(op, lt, rt, (a, b), want);
        let typing = {
            let l = &*self.l;
            binary_typing(op, lt, rt, &|t| l.ty_name(t))
        };
        let typing = match typing.or_else(|e| self.codesys_binary_type(op, lt, rt).ok_or(e)) {
            Ok(t) => t,
            Err(msg) => {
                // Emit both sides for their own errors, then report the mismatch.
                let _ = self.emit(a, None);
                let _ = self.emit(b, None);
                self.l.error(codes::E_TYPE_MISMATCH, msg, span);
                return self.error_val();
            }
        };
        if matches!(op, Op::AndThen | Op::OrElse) {
            return self.short_circuit(op, a, b);
        }
        let is_cmp = matches!(op, Op::Eq | Op::Ne | Op::Lt | Op::Le | Op::Gt | Op::Ge);
        if let Ty::Str(_) = typing.operand {
            return self.compare_strings(op, a, b, span);
        }
        if self.l.codesys
            && [lt, rt]
                .iter()
                .any(|t| matches!(t, Ty::Ref(id) if self.l.types.get_ref(*id).pointer))
        {
            return self.pointer_binary(op, a, b, typing.result);
        }
        if let Ty::Ref(_) | Ty::Null = typing.operand {
            return self.compare_refs(op == Op::Eq, a, b);
        }
        let operand = if is_cmp {
            concretize(typing.operand, None)
        } else if matches!(op, Op::And | Op::Or | Op::Xor | Op::Mod) {
            // Bit and integer operations: a REAL context does not make literals REAL.
            concretize(
                typing.operand,
                want.filter(|w| w.is_int_like() || *w == Ty::BOOL),
            )
        } else {
            concretize(typing.operand, want)
        };
        if operand == Ty::Error {
            let _ = self.emit(a, None);
            let _ = self.emit(b, None);
            return Val {
                v: self.zero(typing.result),
                ty: if is_cmp { Ty::BOOL } else { Ty::Error },
            };
        }
        let operand = self.codesys_widen_for_literal(operand, a, b);
        let result = if is_cmp { Ty::BOOL } else { operand };
        if let (true, Ty::Elem(le), Some(Ty::Elem(re))) = (
            super::dates::is_date(typing.operand),
            typing.operand,
            typing.right,
        ) {
            return self.date_arith(op, a, b, le, re);
        }
        // TIME * n, n * TIME, TIME / n, x ** n: the right operand keeps its own type.
        if let Some(rt) = typing.right {
            return self.mixed_binary(op, a, b, operand, rt, span);
        }
        let x = self.emit_as(a, operand);
        let y = self.emit_as(b, operand);
        let e = match operand {
            // Only `=` and `<>` get here (`binary_typing`).
            Ty::Enum(_, base) => base,
            t => match t.elem() {
                Some(e) => e,
                None => return self.error_val(),
            },
        };
        let v = self.arith(op, x, y, e);
        Val { v, ty: result }
    }

    /// The IR for `x op y` on operands of type `e` (both already of that type).
    pub(super) fn arith(&mut self, op: Op, x: Value, y: Value, e: ElemType) -> Value {
        let float = e.is_real();
        let signed = e.is_signed();
        let b = &mut self.b;
        match op {
            Op::Add => b.binary(
                if float {
                    BinaryOp::Fadd
                } else {
                    BinaryOp::Iadd
                },
                x,
                y,
            ),
            Op::Sub => b.binary(
                if float {
                    BinaryOp::Fsub
                } else {
                    BinaryOp::Isub
                },
                x,
                y,
            ),
            Op::Mul => b.binary(
                if float {
                    BinaryOp::Fmul
                } else {
                    BinaryOp::Imul
                },
                x,
                y,
            ),
            Op::Div => b.binary(
                if float {
                    BinaryOp::Fdiv
                } else if signed {
                    BinaryOp::Sdiv
                } else {
                    BinaryOp::Udiv
                },
                x,
                y,
            ),
            Op::Mod => b.binary(
                if signed {
                    BinaryOp::Srem
                } else {
                    BinaryOp::Urem
                },
                x,
                y,
            ),
            Op::And | Op::AndThen => b.binary(BinaryOp::Band, x, y),
            Op::Or | Op::OrElse => b.binary(BinaryOp::Bor, x, y),
            Op::Xor => b.binary(BinaryOp::Bxor, x, y),
            Op::Eq | Op::Ne | Op::Lt | Op::Le | Op::Gt | Op::Ge => {
                if float {
                    let cc = match op {
                        Op::Eq => FloatCC::Eq,
                        Op::Ne => FloatCC::Ne,
                        Op::Lt => FloatCC::Lt,
                        Op::Le => FloatCC::Le,
                        Op::Gt => FloatCC::Gt,
                        _ => FloatCC::Ge,
                    };
                    b.fcmp(cc, x, y)
                } else {
                    let cc = match (op, signed) {
                        (Op::Eq, _) => IntCC::Eq,
                        (Op::Ne, _) => IntCC::Ne,
                        (Op::Lt, true) => IntCC::Slt,
                        (Op::Le, true) => IntCC::Sle,
                        (Op::Gt, true) => IntCC::Sgt,
                        (Op::Ge, true) => IntCC::Sge,
                        (Op::Lt, false) => IntCC::Ult,
                        (Op::Le, false) => IntCC::Ule,
                        (Op::Gt, false) => IntCC::Ugt,
                        _ => IntCC::Uge,
                    };
                    b.icmp(cc, x, y)
                }
            }
            Op::Pow => unreachable!("** is lowered by mixed_binary"),
        }
    }

    /// Operators whose right operand keeps its own type: TIME * n, TIME / n, and `**`.
    fn mixed_binary(
        &mut self,
        op: Op,
        a: &'s Expr,
        b: &'s Expr,
        operand: Ty,
        right: Ty,
        span: Span,
    ) -> Val {
        let (left_e, right_e, right_ty) =
            if op == Op::Mul && is_duration(self.infer(b)) && !is_duration(self.infer(a)) {
                (b, a, self.infer(a))
            } else {
                (a, b, right)
            };
        let x = self.emit_as(left_e, operand);
        let n = self.emit(right_e, Some(concretize(right_ty, None)));
        let Some(e) = operand.elem() else {
            return self.error_val();
        };
        if op == Op::Pow {
            let v = self.power(x, e, n, span);
            return Val { v, ty: operand };
        }
        let v = self.scale_duration(op, x, e, n);
        Val { v, ty: operand }
    }

    /// `x * n` or `x / n` (`op`) for a duration `x` of type `e` (TIME, LTIME) and a
    /// number `n`: integers multiply or divide the count (ms, ns), reals go through
    /// LREAL and truncate toward zero. Also the function forms (MUL, MUL_TIME, ...).
    pub(super) fn scale_duration(&mut self, op: Op, x: Value, e: ElemType, n: Val) -> Value {
        let t = e.ir_type();
        match n.ty {
            Ty::Error => x,
            nt if nt.is_real() => {
                let nf = self.as_lreal(n);
                let xf = self.b.convert(ConvOp::SiToF, Type::F64, x);
                let r = self.b.binary(
                    if op == Op::Mul {
                        BinaryOp::Fmul
                    } else {
                        BinaryOp::Fdiv
                    },
                    xf,
                    nf,
                );
                self.b.convert(ConvOp::FToSi, t, r)
            }
            Ty::Elem(ne) => {
                let nv = self.convert(n.v, ne, e);
                self.b.binary(
                    if op == Op::Mul {
                        BinaryOp::Imul
                    } else {
                        BinaryOp::Sdiv
                    },
                    x,
                    nv,
                )
            }
            _ => x,
        }
    }

    /// A REAL or LREAL value as LREAL.
    pub(super) fn as_lreal(&mut self, v: Val) -> Value {
        match v.ty {
            Ty::Elem(ElemType::Real) => self.b.convert(ConvOp::Fpromote, Type::F64, v.v),
            _ => v.v,
        }
    }

    /// `x ** n` with `x` of type `e`.
    fn power(&mut self, x: Value, e: ElemType, n: Val, span: Span) -> Value {
        if e.is_real() {
            let t = e.ir_type();
            let nv = match n.ty {
                Ty::Elem(ne) if ne.is_real() => {
                    if ne == e {
                        n.v
                    } else {
                        self.convert(n.v, ne, e)
                    }
                }
                Ty::Elem(ne) if ne.is_integer() => self.convert(n.v, ne, e),
                Ty::Error => self.b.fconst(t, 1.0),
                other => {
                    let name = self.l.ty_name(other);
                    self.l.error(
                        codes::E_TYPE_MISMATCH,
                        format!("an exponent cannot be {name}"),
                        span,
                    );
                    self.b.fconst(t, 1.0)
                }
            };
            return self.b.binary(BinaryOp::Fpow, x, nv);
        }
        // Integer power by repeated squaring (a helper function).
        let exp = match n.ty {
            Ty::Elem(ne) if ne.is_integer() || ne.is_bit_string() => {
                self.convert(n.v, ne, ElemType::LInt)
            }
            Ty::Error => self.b.iconst(Type::I64, 1),
            other => {
                let name = self.l.ty_name(other);
                self.l.error(
                    codes::E_TYPE_MISMATCH,
                    format!("an integer power needs an integer exponent, not {name}"),
                    span,
                );
                self.b.iconst(Type::I64, 1)
            }
        };
        let f = self.l.ipow_helper(e.ir_type());
        self.b
            .call(f, Some(e.ir_type()), vec![x, exp])
            .expect("ipow returns a value")
    }

    /// `a AND_THEN b` / `a OR_ELSE b`: the right side runs only when needed.
    fn short_circuit(&mut self, op: Op, a: &'s Expr, b: &'s Expr) -> Val {
        let x = self.emit_as(a, Ty::BOOL);
        let rhs = self.b.create_block();
        let join = self.b.create_block();
        let r = self.b.block_param(join, Type::I1);
        if op == Op::AndThen {
            self.b.brif(x, rhs, vec![], join, vec![x]);
        } else {
            self.b.brif(x, join, vec![x], rhs, vec![]);
        }
        self.b.switch_to(rhs);
        let y = self.emit_as(b, Ty::BOOL);
        self.b.jump(join, vec![y]);
        self.b.switch_to(join);
        Val { v: r, ty: Ty::BOOL }
    }

    /// Explicit conversion between elementary types (`*_TO_*`), with the semantics of
    /// DESIGN.md: narrowing wraps, reals round to nearest (ties to even) and
    /// saturate, NaN gives 0, TIME counts milliseconds and LTIME nanoseconds.
    pub(super) fn convert(&mut self, v: Value, from: ElemType, to: ElemType) -> Value {
        use ElemType::*;
        if from == to {
            return v;
        }
        let (ft, tt) = (from.ir_type(), to.ir_type());
        match (from, to) {
            (Time, LTime) => {
                let w = self.b.convert(ConvOp::Sext, Type::I64, v);
                let k = self.b.iconst(Type::I64, 1_000_000);
                return self.b.binary(BinaryOp::Imul, w, k);
            }
            (LTime, Time) => {
                let k = self.b.iconst(Type::I64, 1_000_000);
                let d = self.b.binary(BinaryOp::Sdiv, v, k);
                return self.b.convert(ConvOp::Itrunc, Type::I32, d);
            }
            // The 32-bit dates count seconds (TOD milliseconds), the 64-bit ones
            // nanoseconds; a long date past 2106 wraps in the short one.
            (Date, LDate) | (Dt, LDt) | (Tod, LTod) => {
                let w = self.b.convert(ConvOp::Uext, Type::I64, v);
                let unit = if from == Tod {
                    1_000_000
                } else {
                    1_000_000_000
                };
                let k = self.b.iconst(Type::I64, unit);
                return self.b.binary(BinaryOp::Imul, w, k);
            }
            (LDate, Date) | (LDt, Dt) | (LTod, Tod) => {
                let unit = if from == LTod {
                    1_000_000
                } else {
                    1_000_000_000
                };
                let k = self.b.iconst(Type::I64, unit);
                let d = self.b.binary(BinaryOp::Udiv, v, k);
                return self.b.convert(ConvOp::Itrunc, Type::I32, d);
            }
            _ => {}
        }
        if to == Bool {
            return if ft.is_float() {
                let z = self.b.fconst(ft, 0.0);
                self.b.fcmp(FloatCC::Ne, v, z)
            } else {
                let z = self.b.iconst(ft, 0);
                self.b.icmp(IntCC::Ne, v, z)
            };
        }
        if from == Bool {
            let one_or_zero = if tt.is_float() {
                let w = self.b.convert(ConvOp::Uext, Type::I32, v);
                return self.b.convert(ConvOp::SiToF, tt, w);
            } else {
                self.b.convert(ConvOp::Uext, tt, v)
            };
            return one_or_zero;
        }
        match (ft.is_float(), tt.is_float()) {
            (true, true) => {
                if ft == tt {
                    v
                } else if tt == Type::F64 {
                    self.b.convert(ConvOp::Fpromote, Type::F64, v)
                } else {
                    self.b.convert(ConvOp::Fdemote, Type::F32, v)
                }
            }
            (false, true) => {
                let op = if from.is_signed() {
                    ConvOp::SiToF
                } else {
                    ConvOp::UiToF
                };
                self.b.convert(op, tt, v)
            }
            (true, false) => {
                // IEC 61131-3 rounds; the CPDev compiler truncates (its REAL_TO_DINT is
                // the VM's TRUNC), so a `.cst` file gets CPDev's meaning.
                let file = self.l.pou_ast(self.pou).span.file;
                let r = if self.l.cpdev_files.contains(&file) {
                    v
                } else {
                    self.b.unary(UnaryOp::Fnearest, v)
                };
                let op = if to.is_signed() {
                    ConvOp::FToSi
                } else {
                    ConvOp::FToUi
                };
                self.b.convert(op, tt, r)
            }
            (false, false) => {
                let (fb, tb) = (ft.bits(), tt.bits());
                if fb == tb {
                    v
                } else if fb > tb {
                    self.b.convert(ConvOp::Itrunc, tt, v)
                } else if from.is_signed() {
                    self.b.convert(ConvOp::Sext, tt, v)
                } else {
                    self.b.convert(ConvOp::Uext, tt, v)
                }
            }
        }
    }
}
