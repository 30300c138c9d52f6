//! DATE, TIME_OF_DAY and DATE_AND_TIME, and their 64-bit forms LDATE, LTIME_OF_DAY
//! and LDATE_AND_TIME: their literals, arithmetic (IEC 61131-3 table 30, as operators
//! and as functions, named (`ADD_DT_TIME`, `ADD_LDT_LTIME`) or overloaded (`ADD`, also
//! on TIME and LTIME)) and conversions.
//!
//! The three short ones are unsigned 32-bit counts: DATE and DATE_AND_TIME in seconds
//! since 1970-01-01 (a DATE at midnight), TIME_OF_DAY in milliseconds since midnight,
//! as on CODESYS. TIME is signed milliseconds, so `DT - DT` is a TIME in milliseconds
//! and `DT + TIME` adds whole seconds (the milliseconds of the TIME are dropped, as a
//! DATE_AND_TIME holds none). The long ones are 64-bit counts of nanoseconds (since
//! 1970, or since midnight), as LTIME is: `LDT - LDT` is an LTIME, exact.

use super::body::BodyCx;
use super::consts::ConstVal;
use super::expr::Val;
use crate::ast::{BinaryOp as Op, Expr, LiteralKind};
use crate::codes;
use crate::types::Ty;
use plcc_ir::diag::Span;
use plcc_ir::{BinaryOp, ElemType, Type, Value};

const SECS_PER_DAY: i64 = 86_400;
const MS_PER_DAY: i64 = 86_400_000;
const NS_PER_DAY: i64 = 86_400_000_000_000;

/// True for DATE, TIME_OF_DAY and DATE_AND_TIME, and LDATE, LTOD and LDT.
pub(super) fn is_date(t: Ty) -> bool {
    use ElemType::*;
    matches!(t, Ty::Elem(Date | Tod | Dt | LDate | LTod | LDt))
}

/// The result of `l op r` when one side is a date type (table 30), or `None` if the
/// standard does not define it.
pub(super) fn date_arith_type(op: Op, l: Ty, r: Ty) -> Option<Ty> {
    use ElemType::*;
    let (Ty::Elem(a), Ty::Elem(b)) = (l, r) else {
        return None;
    };
    Some(Ty::Elem(match (op, a, b) {
        (Op::Add, Tod, Time) => Tod,
        (Op::Add, Dt, Time) => Dt,
        (Op::Sub, Tod, Time) => Tod,
        (Op::Sub, Dt, Time) => Dt,
        (Op::Sub, Date, Date) | (Op::Sub, Tod, Tod) | (Op::Sub, Dt, Dt) => Time,
        (Op::Add | Op::Sub, LTod, LTime) => LTod,
        (Op::Add | Op::Sub, LDt, LTime) => LDt,
        (Op::Sub, LDate, LDate) | (Op::Sub, LTod, LTod) | (Op::Sub, LDt, LDt) => LTime,
        _ => return None,
    }))
}

/// True for the types of table 30's arithmetic: TIME, LTIME, DATE, TOD and DT.
pub(super) fn is_time_or_date(t: Ty) -> bool {
    super::typing::is_duration(t) || is_date(t)
}

/// The result of the overloaded function `ADD`, `SUB`, `MUL` or `DIV` (`op`) on `l`
/// and `r` when one of them is a duration or a date, or `None` if IEC 61131-3 does not
/// define it (edition 3, table 36; edition 2, table 30): TIME + TIME, TOD + TIME,
/// DT + TIME; TIME - TIME, DATE - DATE, TOD - TIME, TOD - TOD, DT - TIME, DT - DT;
/// TIME * ANY_NUM and TIME / ANY_NUM, the TIME first; the same for LTIME.
pub(super) fn time_fn_type(op: Op, l: Ty, r: Ty) -> Option<Ty> {
    use super::typing::{is_duration, unify};
    match op {
        Op::Add | Op::Sub if is_date(l) || is_date(r) => date_arith_type(op, l, r),
        Op::Add | Op::Sub => unify(l, r).filter(|t| is_duration(*t)),
        Op::Mul | Op::Div if is_duration(l) && (r.is_integer() || r.is_real()) => Some(l),
        _ => None,
    }
}

/// What the function `name` (`ADD`, ...) accepts on durations and dates, for a
/// diagnostic.
fn time_fn_forms(op: Op) -> &'static str {
    match op {
        Op::Add => "TIME + TIME, TOD + TIME and DT + TIME (and the same with LTIME, LTOD, LDT)",
        Op::Sub => {
            "TIME - TIME, DATE - DATE, TOD - TIME, TOD - TOD, DT - TIME and DT - DT (and the same with LTIME, LDATE, LTOD, LDT)"
        }
        Op::Mul => "a TIME or LTIME (IN1) times a number (IN2)",
        _ => "a TIME or LTIME (IN1) divided by a number (IN2)",
    }
}

/// A function of table 30 by name: the operator it is, or CONCAT_DATE_TOD.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub(super) enum DateFn {
    /// `ADD_TOD_TIME`, `SUB_DT_DT`, ...: the operator on the two arguments.
    Op(Op, ElemType, ElemType),
    /// `CONCAT_DATE_TOD(D, TOD)`: the DATE_AND_TIME of that day at that time.
    ConcatDateTod,
    /// `CONCAT_LDATE_LTOD(LD, LTOD)`: the same in nanoseconds.
    ConcatLDateLTod,
}

impl DateFn {
    /// The date function with this (upper-case) name.
    pub(super) fn lookup(name: &str) -> Option<DateFn> {
        use ElemType::*;
        Some(match name {
            "ADD_TOD_TIME" => DateFn::Op(Op::Add, Tod, Time),
            "ADD_DT_TIME" => DateFn::Op(Op::Add, Dt, Time),
            "SUB_DATE_DATE" => DateFn::Op(Op::Sub, Date, Date),
            "SUB_TOD_TIME" => DateFn::Op(Op::Sub, Tod, Time),
            "SUB_TOD_TOD" => DateFn::Op(Op::Sub, Tod, Tod),
            "SUB_DT_TIME" => DateFn::Op(Op::Sub, Dt, Time),
            "SUB_DT_DT" => DateFn::Op(Op::Sub, Dt, Dt),
            "CONCAT_DATE_TOD" => DateFn::ConcatDateTod,
            "ADD_LTOD_LTIME" => DateFn::Op(Op::Add, LTod, LTime),
            "ADD_LDT_LTIME" => DateFn::Op(Op::Add, LDt, LTime),
            "SUB_LDATE_LDATE" => DateFn::Op(Op::Sub, LDate, LDate),
            "SUB_LTOD_LTIME" => DateFn::Op(Op::Sub, LTod, LTime),
            "SUB_LTOD_LTOD" => DateFn::Op(Op::Sub, LTod, LTod),
            "SUB_LDT_LTIME" => DateFn::Op(Op::Sub, LDt, LTime),
            "SUB_LDT_LDT" => DateFn::Op(Op::Sub, LDt, LDt),
            "CONCAT_LDATE_LTOD" => DateFn::ConcatLDateLTod,
            _ => return None,
        })
    }

    /// The result type.
    pub(super) fn result(self) -> Ty {
        match self {
            DateFn::Op(op, a, b) => {
                date_arith_type(op, Ty::Elem(a), Ty::Elem(b)).unwrap_or(Ty::Error)
            }
            DateFn::ConcatDateTod => Ty::Elem(ElemType::Dt),
            DateFn::ConcatLDateLTod => Ty::Elem(ElemType::LDt),
        }
    }
}

impl<'s> BodyCx<'_, 's> {
    /// The value and type of a date literal (`D#`, `TOD#`, `DT#`, and the long forms
    /// `LDATE#`, `LTOD#`, `LDT#` in nanoseconds).
    pub(super) fn date_literal(
        &mut self,
        kind: &LiteralKind,
        span: Span,
    ) -> Option<(ConstVal, Ty)> {
        let (v, t, long) = match *kind {
            LiteralKind::Date { days, long } => {
                (days as i128 * SECS_PER_DAY as i128, ElemType::Date, long)
            }
            LiteralKind::TimeOfDay { ns, long } => (ns as i128 / 1_000_000, ElemType::Tod, long),
            LiteralKind::DateTime { ns, long } => (ns / 1_000_000_000, ElemType::Dt, long),
            _ => return None,
        };
        if long {
            let (ns, t) = match *kind {
                LiteralKind::Date { days, .. } => {
                    (days as i128 * NS_PER_DAY as i128, ElemType::LDate)
                }
                LiteralKind::TimeOfDay { ns, .. } => (ns as i128, ElemType::LTod),
                LiteralKind::DateTime { ns, .. } => (ns, ElemType::LDt),
                _ => return None,
            };
            if !(0..=i64::MAX as i128).contains(&ns) {
                self.l.error(
                    codes::E_LITERAL_RANGE,
                    format!(
                        "{} holds dates from 1970 to 2262; this one is outside",
                        t.name()
                    ),
                    span,
                );
                return None;
            }
            return Some((ConstVal::Int(ns), Ty::Elem(t)));
        }
        if !(0..=u32::MAX as i128).contains(&v) {
            self.l.error(
                codes::E_LITERAL_RANGE,
                format!(
                    "{} holds dates from 1970 to 2106; this one is outside",
                    t.name()
                ),
                span,
            );
            return None;
        }
        Some((ConstVal::Int(v), Ty::Elem(t)))
    }

    /// `a op b` with a date type on the left (already typed by [`date_arith_type`]).
    pub(super) fn date_arith(
        &mut self,
        op: Op,
        a: &'s Expr,
        b: &'s Expr,
        l: ElemType,
        r: ElemType,
    ) -> Val {
        let x = self.emit_as(a, Ty::Elem(l));
        let y = self.emit_as(b, Ty::Elem(r));
        self.date_op(op, x, y, l, r)
    }

    /// The IR of `x op y` for the date arithmetic of table 30.
    fn date_op(&mut self, op: Op, x: Value, y: Value, l: ElemType, r: ElemType) -> Val {
        use ElemType::*;
        let k = |cx: &mut Self, n: i64| cx.b.iconst(Type::I32, n);
        let (v, t) = match (op, l, r) {
            (Op::Add, Tod, Time) | (Op::Sub, Tod, Time) => {
                // Wraps around midnight.
                let bop = if op == Op::Add {
                    BinaryOp::Iadd
                } else {
                    BinaryOp::Isub
                };
                let s = self.b.binary(bop, x, y);
                let day = k(self, MS_PER_DAY);
                let m = self.b.binary(BinaryOp::Srem, s, day);
                let zero = k(self, 0);
                let neg = self.b.icmp(plcc_ir::IntCC::Slt, m, zero);
                let up = self.b.binary(BinaryOp::Iadd, m, day);
                (self.b.select(neg, up, m), Tod)
            }
            (Op::Add, Dt, Time) | (Op::Sub, Dt, Time) => {
                let thousand = k(self, 1000);
                let secs = self.b.binary(BinaryOp::Sdiv, y, thousand);
                let bop = if op == Op::Add {
                    BinaryOp::Iadd
                } else {
                    BinaryOp::Isub
                };
                (self.b.binary(bop, x, secs), Dt)
            }
            (Op::Sub, Date, Date) | (Op::Sub, Dt, Dt) => {
                let d = self.b.binary(BinaryOp::Isub, x, y);
                let thousand = k(self, 1000);
                (self.b.binary(BinaryOp::Imul, d, thousand), Time)
            }
            (Op::Sub, Tod, Tod) => (self.b.binary(BinaryOp::Isub, x, y), Time),
            (Op::Add, LTod, LTime) | (Op::Sub, LTod, LTime) => {
                // Wraps around midnight.
                let bop = if op == Op::Add {
                    BinaryOp::Iadd
                } else {
                    BinaryOp::Isub
                };
                let s = self.b.binary(bop, x, y);
                let day = self.b.iconst(Type::I64, NS_PER_DAY);
                let m = self.b.binary(BinaryOp::Srem, s, day);
                let zero = self.b.iconst(Type::I64, 0);
                let neg = self.b.icmp(plcc_ir::IntCC::Slt, m, zero);
                let up = self.b.binary(BinaryOp::Iadd, m, day);
                (self.b.select(neg, up, m), LTod)
            }
            (Op::Add, LDt, LTime) => (self.b.binary(BinaryOp::Iadd, x, y), LDt),
            (Op::Sub, LDt, LTime) => (self.b.binary(BinaryOp::Isub, x, y), LDt),
            (Op::Sub, LDate, LDate) | (Op::Sub, LDt, LDt) | (Op::Sub, LTod, LTod) => {
                (self.b.binary(BinaryOp::Isub, x, y), LTime)
            }
            _ => return self.error_val(),
        };
        Val { v, ty: Ty::Elem(t) }
    }

    /// Emits a call of a function of table 30 with its two arguments.
    pub(super) fn date_fn_call(&mut self, f: DateFn, xs: &[&'s Expr]) -> Option<Val> {
        match f {
            DateFn::Op(op, a, b) => {
                let x = self.emit_as(xs[0], Ty::Elem(a));
                let y = self.emit_as(xs[1], Ty::Elem(b));
                Some(self.date_op(op, x, y, a, b))
            }
            DateFn::ConcatLDateLTod => {
                let d = self.emit_as(xs[0], Ty::Elem(ElemType::LDate));
                let t = self.emit_as(xs[1], Ty::Elem(ElemType::LTod));
                let v = self.b.binary(BinaryOp::Iadd, d, t);
                Some(Val {
                    v,
                    ty: Ty::Elem(ElemType::LDt),
                })
            }
            DateFn::ConcatDateTod => {
                let d = self.emit_as(xs[0], Ty::Elem(ElemType::Date));
                let t = self.emit_as(xs[1], Ty::Elem(ElemType::Tod));
                let thousand = self.b.iconst(Type::I32, 1000);
                let secs = self.b.binary(BinaryOp::Udiv, t, thousand);
                let v = self.b.binary(BinaryOp::Iadd, d, secs);
                Some(Val {
                    v,
                    ty: Ty::Elem(ElemType::Dt),
                })
            }
        }
    }

    /// `ADD`, `SUB`, `MUL` or `DIV` (`op`) called with a duration or a date among its
    /// inputs `xs`: two inputs typed by [`time_fn_type`], then computed exactly as the
    /// operator (`+`, `-`, `*`, `/`) computes them.
    pub(super) fn time_arith_fn(
        &mut self,
        op: Op,
        xs: &[&'s Expr],
        name: &str,
        want: Option<Ty>,
        span: Span,
    ) -> Option<Val> {
        if xs.len() != 2 {
            for x in xs {
                let _ = self.emit(x, None);
            }
            let d = plcc_ir::diag::Diagnostic::error(
                codes::E_ARG_COUNT,
                format!(
                    "`{name}` on durations and dates takes 2 arguments, {} given",
                    xs.len()
                ),
                span,
            )
            .with_note(format!(
                "IEC 61131-3 gives `{name}` more inputs on numbers only; nest the calls"
            ));
            self.l.diags.push(d);
            return None;
        }
        let (l, r) = (self.infer(xs[0]), self.infer(xs[1]));
        if l == Ty::Error || r == Ty::Error {
            let _ = self.emit(xs[0], None);
            let _ = self.emit(xs[1], None);
            return None;
        }
        if time_fn_type(op, l, r).is_none() {
            let _ = self.emit(xs[0], None);
            let _ = self.emit(xs[1], None);
            let name_of = |cx: &Self, t: Ty| match t {
                Ty::AnyInt => "an integer literal".to_string(),
                Ty::AnyReal => "a real literal".to_string(),
                t => cx.l.ty_name(t),
            };
            let (a, b) = (name_of(self, l), name_of(self, r));
            let d = plcc_ir::diag::Diagnostic::error(
                codes::E_TYPE_MISMATCH,
                format!("`{name}` is not defined on {a} and {b}"),
                span,
            )
            .with_note(format!(
                "on durations and dates, `{name}` takes {}",
                time_fn_forms(op)
            ));
            self.l.diags.push(d);
            return None;
        }
        let v = self.binary(op, xs[0], xs[1], want, span);
        (v.ty != Ty::Error).then_some(v)
    }

    /// A conversion from or to a date type (`v` is of type `from`): between the date
    /// types as the standard says (DT_TO_DATE keeps the day, DT_TO_TOD the time of
    /// day, TOD and TIME are both milliseconds), with numbers as the count itself (as
    /// CODESYS does: DT_TO_DWORD gives the seconds). `None` if there is no such
    /// conversion.
    pub(super) fn date_conversion(
        &mut self,
        v: Value,
        from: ElemType,
        to: ElemType,
    ) -> Option<Value> {
        use ElemType::*;
        let k = |cx: &mut Self, n: i64| cx.b.iconst(Type::I32, n);
        let numeric = |t: ElemType| (t.is_integer() || t.is_bit_string()) && t != Bool;
        Some(match (from, to) {
            (a, b) if a == b => v,
            (Dt, Date) => {
                let day = k(self, SECS_PER_DAY);
                let r = self.b.binary(BinaryOp::Urem, v, day);
                self.b.binary(BinaryOp::Isub, v, r)
            }
            (Dt, Tod) => {
                let day = k(self, SECS_PER_DAY);
                let r = self.b.binary(BinaryOp::Urem, v, day);
                let thousand = k(self, 1000);
                self.b.binary(BinaryOp::Imul, r, thousand)
            }
            (Date, Dt) | (Tod, Time) | (Time, Tod) => v,
            (LDt, LDate) => {
                let day = self.b.iconst(Type::I64, NS_PER_DAY);
                let r = self.b.binary(BinaryOp::Urem, v, day);
                self.b.binary(BinaryOp::Isub, v, r)
            }
            (LDt, LTod) => {
                let day = self.b.iconst(Type::I64, NS_PER_DAY);
                self.b.binary(BinaryOp::Urem, v, day)
            }
            (LDate, LDt) | (LTod, LTime) | (LTime, LTod) => v,
            // Between a short and a long form: seconds (milliseconds) and nanoseconds.
            (Date, LDate) | (LDate, Date) | (Dt, LDt) | (LDt, Dt) | (Tod, LTod) | (LTod, Tod) => {
                self.convert(v, from, to)
            }
            (Dt, LDate) | (Dt, LTod) | (Date, LDt) => {
                let long = self.convert(v, Dt, LDt);
                self.date_conversion(long, LDt, to)?
            }
            (LDt, Date) | (LDt, Tod) | (LDate, Dt) => {
                let mid = match to {
                    Date => LDate,
                    Tod => LTod,
                    _ => LDt,
                };
                let m = self.date_conversion(v, from, mid)?;
                self.convert(m, mid, to)
            }
            (Date | Tod | Dt, n) if numeric(n) => self.convert(v, UDInt, n),
            (n, Date | Tod | Dt) if numeric(n) => self.convert(v, n, UDInt),
            (Date | Tod | Dt, r) if r.is_real() => self.convert(v, UDInt, r),
            (LDate | LTod | LDt, n) if numeric(n) => self.convert(v, ULInt, n),
            (n, LDate | LTod | LDt) if numeric(n) => self.convert(v, n, ULInt),
            (LDate | LTod | LDt, r) if r.is_real() => self.convert(v, ULInt, r),
            _ => return None,
        })
    }
}
