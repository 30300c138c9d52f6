//! BCD conversions (IEC 61131-3 table 22): `BYTE_BCD_TO_USINT`, `WORD_BCD_TO_UINT`,
//! ..., the generic `BCD_TO_<int>` (from the argument's bit string), and the reverse
//! `USINT_TO_BCD_BYTE`, ..., `<int>_TO_BCD` (to the bit string of the integer's width).
//!
//! Each nibble is a decimal digit. The work is done by the helpers of
//! `stdlib/bcd.st` (32-bit ones where the values fit, 64-bit ones for LWORD, LINT and
//! ULINT), so every target runs the same code. As in matiec, a bit string with a nibble
//! above 9 converts to 0, and a number converts digit by digit with the digits that do
//! not fit the result dropped (a negative number as matiec does: the digits of its
//! two's complement as a ULINT).

use super::body::BodyCx;
use super::expr::{concretize, Val};
use crate::ast::Expr;
use crate::codes;
use crate::types::Ty;
use plcc_ir::{ConvOp, ElemType, Type, Value};

/// A BCD conversion.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub(super) enum BcdFn {
    /// `BCD_TO_<int>` (`from` is `None`) and `<bits>_BCD_TO_<int>`.
    FromBcd {
        from: Option<ElemType>,
        to: ElemType,
    },
    /// `<int>_TO_BCD` (`to` is `None`: the bit string as wide as the integer) and
    /// `<int>_TO_BCD_<bits>`.
    ToBcd {
        from: ElemType,
        to: Option<ElemType>,
    },
}

fn bits(name: &str) -> Option<ElemType> {
    ElemType::from_name(name).filter(|e| e.is_bit_string() && *e != ElemType::Bool)
}

fn int(name: &str) -> Option<ElemType> {
    ElemType::from_name(name).filter(|e| e.is_integer())
}

/// The bit string as wide as an integer type.
fn bits_of(e: ElemType) -> ElemType {
    match e.ir_type() {
        Type::I8 => ElemType::Byte,
        Type::I16 => ElemType::Word,
        Type::I32 => ElemType::DWord,
        _ => ElemType::LWord,
    }
}

impl BcdFn {
    /// The BCD conversion with this (upper-case) name.
    pub(super) fn lookup(name: &str) -> Option<BcdFn> {
        if let Some(to) = name.strip_prefix("BCD_TO_") {
            return Some(BcdFn::FromBcd {
                from: None,
                to: int(to)?,
            });
        }
        if let Some((from, to)) = name.split_once("_BCD_TO_") {
            return Some(BcdFn::FromBcd {
                from: Some(bits(from)?),
                to: int(to)?,
            });
        }
        if let Some(from) = name.strip_suffix("_TO_BCD") {
            return Some(BcdFn::ToBcd {
                from: int(from)?,
                to: None,
            });
        }
        if let Some((from, to)) = name.split_once("_TO_BCD_") {
            return Some(BcdFn::ToBcd {
                from: int(from)?,
                to: Some(bits(to)?),
            });
        }
        None
    }

    /// The result type.
    pub(super) fn result(self) -> Ty {
        Ty::Elem(match self {
            BcdFn::FromBcd { to, .. } => to,
            BcdFn::ToBcd { from, to } => to.unwrap_or(bits_of(from)),
        })
    }
}

impl<'s> BodyCx<'_, 's> {
    /// Emits a BCD conversion of `x`.
    pub(super) fn bcd_call(&mut self, f: BcdFn, x: &'s Expr, name: &str) -> Option<Val> {
        let (from, to) = match f {
            BcdFn::FromBcd { from, to } => (from, to),
            BcdFn::ToBcd { from, to } => (Some(from), to.unwrap_or(bits_of(from))),
        };
        let v = match from {
            Some(t) => Val {
                v: self.emit_as(x, Ty::Elem(t)),
                ty: Ty::Elem(t),
            },
            None => {
                // A literal is taken as an LWORD.
                let t = match self.infer(x) {
                    Ty::AnyInt => Ty::Elem(ElemType::LWord),
                    t => concretize(t, None),
                };
                self.emit(x, Some(t))
            }
        };
        let xe = match v.ty {
            Ty::Error => return None,
            Ty::Elem(e) if e.is_bit_string() && e != ElemType::Bool => e,
            Ty::Elem(e) if matches!(f, BcdFn::ToBcd { .. }) => e,
            t => {
                let tn = self.l.ty_name(t);
                self.l.error(
                    codes::E_TYPE_MISMATCH,
                    format!("`{name}` converts from BYTE, WORD, DWORD or LWORD, not from {tn}"),
                    x.span,
                );
                return None;
            }
        };
        let wide = xe.ir_type() == Type::I64 || to.ir_type() == Type::I64;
        let r = match f {
            BcdFn::FromBcd { .. } => {
                let (helper, t) = if xe.ir_type() == Type::I64 {
                    ("__BCD_TO_ULINT", Type::I64)
                } else {
                    ("__BCD_TO_UDINT", Type::I32)
                };
                let a = self.resize(v.v, xe.ir_type(), t, false);
                let r = self.call_std(helper, vec![a])?;
                self.resize(r, t, to.ir_type(), false)
            }
            BcdFn::ToBcd { .. } => {
                // A negative number gives the digits of its two's complement as a
                // ULINT, as in matiec's C.
                let (helper, t) = if wide || xe.is_signed() {
                    ("__TO_BCD_LWORD", Type::I64)
                } else {
                    ("__TO_BCD_DWORD", Type::I32)
                };
                let a = self.resize(v.v, xe.ir_type(), t, xe.is_signed());
                let r = self.call_std(helper, vec![a])?;
                self.resize(r, t, to.ir_type(), false)
            }
        };
        Some(Val {
            v: r,
            ty: Ty::Elem(to),
        })
    }

    /// `v` of IR type `from` as a `to`: cut, or extended with its sign (`signed`) or
    /// with zeros.
    fn resize(&mut self, v: Value, from: Type, to: Type, signed: bool) -> Value {
        let bits = |t: Type| match t {
            Type::I8 => 8,
            Type::I16 => 16,
            Type::I32 => 32,
            _ => 64,
        };
        match bits(from).cmp(&bits(to)) {
            std::cmp::Ordering::Equal => v,
            std::cmp::Ordering::Greater => self.b.convert(ConvOp::Itrunc, to, v),
            std::cmp::Ordering::Less => {
                let op = if signed { ConvOp::Sext } else { ConvOp::Uext };
                self.b.convert(op, to, v)
            }
        }
    }

    /// Calls the standard library FUNCTION `name` with `args` in its declaration
    /// order: its result, if it has one.
    pub(super) fn call_std(&mut self, name: &str, args: Vec<Value>) -> Option<Value> {
        let sym = self.l.interner.intern(name);
        let p = *self.l.pou_by_name.get(&sym)?;
        self.l.use_std_function(p);
        let f = self.l.ir[p.0 as usize].body?;
        let ret = self.l.pou(p).ret.ir();
        self.b.call(f, ret, args)
    }
}
