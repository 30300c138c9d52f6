//! Partial access of bit strings and integers: `w.%B1` (a byte), `.%W0` (a word),
//! `.%D1` (a double word), `.%L0`, numbered from the least significant part.

use super::body::BodyCx;
use super::expr::Val;
use crate::ast::Expr;
use crate::codes;
use crate::types::Ty;
use plcc_ir::{BinaryOp, ConvOp, ElemType, Type, Value};

impl<'s> BodyCx<'_, 's> {
    /// The part's type and its shift in the word, after checking that the word has
    /// such a part.
    fn partial_layout(
        &mut self,
        word: Ty,
        size: u8,
        n: u32,
        e: &'s Expr,
    ) -> Option<(ElemType, ElemType, u32)> {
        let part = match size {
            8 => ElemType::Byte,
            16 => ElemType::Word,
            32 => ElemType::DWord,
            64 => ElemType::LWord,
            _ => return None,
        };
        let we = match word.elem() {
            Some(w) if w != ElemType::Bool && (w.is_bit_string() || w.is_integer()) => w,
            _ => {
                if word != Ty::Error {
                    let t = self.l.ty_name(word);
                    self.l.error(
                        codes::E_TYPE_MISMATCH,
                        format!("partial access needs a bit string or an integer, not {t}"),
                        e.span,
                    );
                }
                return None;
            }
        };
        let bits = we.ir_type().bits();
        let shift = n as u64 * size as u64;
        if shift + size as u64 > bits as u64 {
            let parts = bits / size as u32;
            let which = match parts {
                0 => format!("a {} has no part of {size} bits", we.name()),
                1 => format!("a {} has one part of {size} bits: number 0", we.name()),
                n => format!(
                    "a {} has {n} parts of {size} bits: numbers 0 to {}",
                    we.name(),
                    n - 1
                ),
            };
            self.l.error(codes::E_BAD_INDEX, which, e.span);
            return None;
        }
        Some((we, part, shift as u32))
    }

    /// Reads `base.%Bn` (and the other sizes).
    pub(super) fn partial_read(&mut self, e: &'s Expr, base: &'s Expr, size: u8, n: u32) -> Val {
        let Some(p) = self.place(base) else {
            return self.error_val();
        };
        let Some((we, part, shift)) = self.partial_layout(p.ty, size, n, e) else {
            return self.error_val();
        };
        let w = self.load_place(&p);
        let v = self.extract(w, we.ir_type(), part.ir_type(), shift);
        Val {
            v,
            ty: Ty::Elem(part),
        }
    }

    fn extract(&mut self, w: Value, wt: Type, pt: Type, shift: u32) -> Value {
        let s = self.b.iconst(wt, shift as i64);
        let moved = self.b.binary(BinaryOp::Ushr, w, s);
        if wt == pt {
            moved
        } else {
            self.b.convert(ConvOp::Itrunc, pt, moved)
        }
    }

    /// `base.%Bn := value`: the other parts of the word keep their bits.
    pub(super) fn partial_write(
        &mut self,
        e: &'s Expr,
        base: &'s Expr,
        size: u8,
        n: u32,
        value: &'s Expr,
    ) {
        let Some(p) = self.place(base) else {
            let _ = self.emit(value, None);
            return;
        };
        let Some((we, part, shift)) = self.partial_layout(p.ty, size, n, e) else {
            let _ = self.emit(value, None);
            return;
        };
        if !self.check_writable(&p, e.span) {
            return;
        }
        let v = self.emit_as(value, Ty::Elem(part));
        let (wt, pt) = (we.ir_type(), part.ir_type());
        let pp = p;
        self.guarded(p.guard, |cx| {
            let old = cx.b.load(wt, pp.addr);
            let wide = if wt == pt {
                v
            } else {
                cx.b.convert(ConvOp::Uext, wt, v)
            };
            let s = cx.b.iconst(wt, shift as i64);
            let moved = cx.b.binary(BinaryOp::Ishl, wide, s);
            let ones = cx.b.iconst(pt, -1);
            let ones = if wt == pt {
                ones
            } else {
                cx.b.convert(ConvOp::Uext, wt, ones)
            };
            let mask = cx.b.binary(BinaryOp::Ishl, ones, s);
            let keep = cx.b.unary(plcc_ir::UnaryOp::Bnot, mask);
            let kept = cx.b.binary(BinaryOp::Band, old, keep);
            let new = cx.b.binary(BinaryOp::Bor, kept, moved);
            cx.b.store(new, pp.addr);
        });
    }
}
