//! TIME, LTIME, DATE, TIME_OF_DAY, DATE_AND_TIME, LDATE, LTOD and LDT to and from
//! STRING and WSTRING (`TIME_TO_STRING`, `TO_STRING`, `STRING_TO_DT`, ...), in the
//! forms of IEC 61131-3 literals: `T#1h2m3s4ms`, `LTIME#1s5ns`, `D#2024-05-01`,
//! `TOD#12:34:56.789`, `DT#2024-05-01-12:34:56`, `LDT#2024-05-01-12:34:56.000000001`.
//! The helpers of `stdlib/timestrings.st` do the work (the forms are described
//! there), so every target runs the same code.

use super::body::BodyCx;
use super::expr::Val;
use crate::types::{StrTy, Ty};
use plcc_ir::{BinaryOp, ConvOp, ElemType, Type, Value};

/// The KIND argument of the date helpers.
fn date_kind(e: ElemType) -> Option<i64> {
    match e {
        ElemType::Date => Some(0),
        ElemType::Tod => Some(1),
        ElemType::Dt => Some(2),
        _ => None,
    }
}

/// The KIND argument of the long date helpers (nanoseconds).
fn long_date_kind(e: ElemType) -> Option<i64> {
    match e {
        ElemType::LDate => Some(0),
        ElemType::LTod => Some(1),
        ElemType::LDt => Some(2),
        _ => None,
    }
}

/// True for the types these conversions handle.
pub(super) fn is_time_like(e: ElemType) -> bool {
    e.is_duration() || date_kind(e).is_some() || long_date_kind(e).is_some()
}

impl<'s> BodyCx<'_, 's> {
    /// Writes the literal of the TIME, LTIME or date value `v` of type `e` into the
    /// string `d` of type `rs`.
    pub(super) fn format_time(&mut self, d: Value, rs: StrTy, v: Value, e: ElemType) {
        let dc = self.b.iconst(Type::I16, rs.cap as i64);
        if let Some(kind) = long_date_kind(e) {
            let k = self.b.iconst(Type::I16, kind);
            self.call_helper(rs.wide, "FROM_LDATE", vec![d, dc, v, k]);
            return;
        }
        match date_kind(e) {
            Some(kind) => {
                let k = self.b.iconst(Type::I16, kind);
                self.call_helper(rs.wide, "FROM_DATE", vec![d, dc, v, k]);
            }
            None => {
                let long = e == ElemType::LTime;
                let x = if long {
                    v
                } else {
                    self.b.convert(ConvOp::Sext, Type::I64, v)
                };
                let l = self.b.iconst(Type::I1, long as i64);
                self.call_helper(rs.wide, "FROM_TIME", vec![d, dc, x, l]);
            }
        }
    }

    /// The TIME, LTIME or date value of type `to` that the string `s` (capacity in
    /// `st`) is the literal of; the type's zero if it is not one.
    pub(super) fn parse_time(&mut self, s: Value, st: StrTy, to: ElemType) -> Option<Val> {
        let cap = self.b.iconst(Type::I16, st.cap as i64);
        if let Some(kind) = long_date_kind(to) {
            let k = self.b.iconst(Type::I16, kind);
            let v = self.call_helper(st.wide, "TO_LDATE", vec![s, cap, k])?;
            return Some(Val {
                v,
                ty: Ty::Elem(to),
            });
        }
        let v = match date_kind(to) {
            Some(kind) => {
                let k = self.b.iconst(Type::I16, kind);
                self.call_helper(st.wide, "TO_DATE", vec![s, cap, k])?
            }
            None => {
                let ns = self.call_helper(st.wide, "TO_TIME", vec![s, cap])?;
                if to == ElemType::LTime {
                    ns
                } else {
                    let million = self.b.iconst(Type::I64, 1_000_000);
                    let ms = self.b.binary(BinaryOp::Sdiv, ns, million);
                    self.b.convert(ConvOp::Itrunc, Type::I32, ms)
                }
            }
        };
        Some(Val {
            v,
            ty: Ty::Elem(to),
        })
    }
}
