//! The BCD conversions of IEC 61131-3: edition 3's `BYTE_BCD_TO_USINT` …
//! `LWORD_BCD_TO_ULINT` and `USINT_TO_BCD_BYTE` … `ULINT_TO_BCD_LWORD` (table 23),
//! their overloaded forms `BCD_TO_USINT(IN)` and `USINT_TO_BCD(IN)`, and edition 2's
//! `*_BCD_TO_**` and `**_TO_BCD_*` on the other integer types (`BCD_TO_INT`,
//! `INT_TO_BCD`).
//!
//! A BCD bit string holds one decimal digit per 4 bits, the least significant digit
//! in the low bits: `WORD#16#0151` is 151. The standard makes a nibble above 9, a
//! negative number and a number with more digits than the bit string holds an error;
//! plcc then gives 0 and sets ENO to FALSE (the standard's signal of an error in a
//! function, 6.6.1.4), as matiec does for an invalid BCD input (Beremiz's `python`
//! example watches ENO for it). No fault is raised: the program is told through ENO.
//! Everything is computed inline on the bit string's width, digit by digit, so every
//! target runs it.

use super::body::BodyCx;
use super::expr::Val;
use crate::ast::Expr;
use crate::types::Ty;
use plcc_ir::{BinaryOp, ElemType, IntCC, Type, Value};

/// A BCD conversion.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub(super) enum BcdFn {
    /// `[B_]BCD_TO_I`: the number the BCD bit string `B` holds, as the integer `I`
    /// (`from` is `None` for the overloaded form: the argument's type).
    FromBcd {
        from: Option<ElemType>,
        to: ElemType,
    },
    /// `I_TO_BCD[_B]`: the integer `I` as a BCD bit string `B` (`None`: the bit string
    /// of `I`'s width).
    ToBcd {
        from: ElemType,
        to: Option<ElemType>,
    },
}

/// BYTE, WORD, DWORD and LWORD.
fn bit_string(e: ElemType) -> bool {
    e.is_bit_string() && e != ElemType::Bool
}

/// The bit string of `e`'s width (the width of a BCD holding it).
fn bits_of_width(e: ElemType) -> ElemType {
    match e.ir_type().bits() {
        8 => ElemType::Byte,
        16 => ElemType::Word,
        32 => ElemType::DWord,
        _ => ElemType::LWord,
    }
}

impl BcdFn {
    /// The BCD conversion with this (upper-case) name.
    pub(super) fn lookup(name: &str) -> Option<BcdFn> {
        let elem = |s: &str| ElemType::from_name(s);
        let int = |s: &str| elem(s).filter(|e| e.is_integer());
        let bits = |s: &str| elem(s).filter(|e| bit_string(*e));
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
        let (from, to) = name.split_once("_TO_BCD_")?;
        Some(BcdFn::ToBcd {
            from: int(from)?,
            to: Some(bits(to)?),
        })
    }

    /// The result type.
    pub(super) fn result(self) -> Ty {
        match self {
            BcdFn::FromBcd { to, .. } => Ty::Elem(to),
            BcdFn::ToBcd { from, to } => Ty::Elem(to.unwrap_or_else(|| bits_of_width(from))),
        }
    }
}

impl<'s> BodyCx<'_, 's> {
    /// Emits a BCD conversion of `x`; sets ENO to FALSE (through `eno_ok`) when the
    /// input has no value in the result's type.
    pub(super) fn bcd_call(&mut self, f: BcdFn, x: &'s Expr, name: &str) -> Option<Val> {
        match f {
            BcdFn::FromBcd { from, to } => {
                let v = match from {
                    Some(b) => {
                        let v = self.emit_as(x, Ty::Elem(b));
                        Val { v, ty: Ty::Elem(b) }
                    }
                    // An untyped literal is a BCD of the result's width.
                    None => self.emit(x, Some(Ty::Elem(bits_of_width(to)))),
                };
                let b = match v.ty {
                    Ty::Elem(b) if bit_string(b) => b,
                    Ty::Error => return None,
                    t => return self.bad_arg(name, "a BYTE, WORD, DWORD or LWORD", t, x.span),
                };
                let (n, bad) = self.decode_bcd(v.v, b.ir_type());
                let zero = self.b.iconst(b.ir_type(), 0);
                let n = self.b.select(bad, zero, n);
                self.set_eno_error(bad);
                // The number fits the width of the bit string, unsigned.
                let v = self.convert(n, bits_of_width(b), to);
                Some(Val {
                    v,
                    ty: Ty::Elem(to),
                })
            }
            BcdFn::ToBcd { from, to } => {
                let to = to.unwrap_or_else(|| bits_of_width(from));
                let v = self.emit_as(x, Ty::Elem(from));
                let (ft, tt) = (from.ir_type(), to.ir_type());
                // Digit by digit in the wider of the two widths, unsigned.
                let wide = if tt.bits() > ft.bits() { tt } else { ft };
                let u = if wide == ft {
                    v
                } else {
                    self.b.convert(plcc_ir::ConvOp::Uext, wide, v)
                };
                let (bcd, left) = self.encode_bcd(u, wide, tt.bits() / 4);
                let zero = self.b.iconst(wide, 0);
                let mut bad = self.b.icmp(IntCC::Ne, left, zero);
                if from.is_signed() {
                    let z = self.b.iconst(ft, 0);
                    let neg = self.b.icmp(IntCC::Slt, v, z);
                    bad = self.b.binary(BinaryOp::Bor, bad, neg);
                }
                let bcd = self.b.select(bad, zero, bcd);
                self.set_eno_error(bad);
                let v = if wide == tt {
                    bcd
                } else {
                    self.b.convert(plcc_ir::ConvOp::Itrunc, tt, bcd)
                };
                Some(Val {
                    v,
                    ty: Ty::Elem(to),
                })
            }
        }
    }

    /// The number the BCD `x` (of IR type `t`) holds, and whether a nibble is above 9.
    fn decode_bcd(&mut self, x: Value, t: Type) -> (Value, Value) {
        let mut n = self.b.iconst(t, 0);
        let mut bad = self.b.iconst(Type::I1, 0);
        let (fifteen, nine, ten) = (
            self.b.iconst(t, 15),
            self.b.iconst(t, 9),
            self.b.iconst(t, 10),
        );
        // From the most significant digit: n = n * 10 + d. The largest value (all
        // nibbles 15) still fits the width, so nothing wraps.
        for i in (0..t.bits() / 4).rev() {
            let sh = self.b.iconst(t, 4 * i as i64);
            let s = self.b.binary(BinaryOp::Ushr, x, sh);
            let d = self.b.binary(BinaryOp::Band, s, fifteen);
            let over = self.b.icmp(IntCC::Ugt, d, nine);
            bad = self.b.binary(BinaryOp::Bor, bad, over);
            let m = self.b.binary(BinaryOp::Imul, n, ten);
            n = self.b.binary(BinaryOp::Iadd, m, d);
        }
        (n, bad)
    }

    /// The `digits` low decimal digits of the unsigned `x` (of IR type `t`) as BCD,
    /// and what is left of `x` above them (0 if they are all its digits).
    fn encode_bcd(&mut self, x: Value, t: Type, digits: u32) -> (Value, Value) {
        let ten = self.b.iconst(t, 10);
        let mut bcd = self.b.iconst(t, 0);
        let mut q = x;
        for i in 0..digits {
            let d = self.b.binary(BinaryOp::Urem, q, ten);
            q = self.b.binary(BinaryOp::Udiv, q, ten);
            let sh = self.b.iconst(t, 4 * i as i64);
            let p = self.b.binary(BinaryOp::Ishl, d, sh);
            bcd = self.b.binary(BinaryOp::Bor, bcd, p);
        }
        (bcd, q)
    }
}
