//! Places: the memory an expression names (a variable, an FB member, a STRUCT field,
//! an array element, a bit), resolved by `place`, and loads and stores through them
//! (an element whose index was out of bounds reads 0 and drops the write, raising the
//! fault flag).

use super::body::{BodyCx, Named, Place};
use super::consts::ConstVal;
use crate::ast::{Expr, ExprKind};
use crate::codes;
use crate::types::Ty;
use plcc_ir::{BinaryOp, ConvOp, ElemType, IntCC, Type, Value};

impl<'s> BodyCx<'_, 's> {
    /// Reads a place (a whole variable or one bit of it). An element whose index was
    /// out of bounds reads as 0 and raises the fault flag: one branch, the read on one
    /// side and the fault on the other.
    pub(super) fn load_place(&mut self, p: &Place) -> Value {
        let Some(g) = p.guard else {
            return self.load_unguarded(p);
        };
        let ok = self.b.create_block();
        let bad = self.b.create_block();
        let join = self.b.create_block();
        let t = p.ty.ir().unwrap_or(Type::I32);
        let r = self.b.block_param(join, t);
        self.b.brif(g, ok, vec![], bad, vec![]);
        self.b.switch_to(ok);
        let v = self.load_unguarded(p);
        self.b.jump(join, vec![v]);
        self.b.switch_to(bad);
        self.b.intrinsic(plcc_ir::Intrinsic::RaiseFault, vec![]);
        let z = self.zero(p.ty);
        self.b.jump(join, vec![z]);
        self.b.switch_to(join);
        r
    }

    /// Runs `body` only when the guard (an in-bounds flag) holds; otherwise raises the
    /// fault flag. Without a guard, just runs `body`.
    pub(super) fn guarded(&mut self, guard: Option<Value>, body: impl FnOnce(&mut Self)) {
        let Some(g) = guard else {
            body(self);
            return;
        };
        let ok = self.b.create_block();
        let bad = self.b.create_block();
        let join = self.b.create_block();
        self.b.brif(g, ok, vec![], bad, vec![]);
        self.b.switch_to(ok);
        body(self);
        self.b.jump(join, vec![]);
        self.b.switch_to(bad);
        self.b.intrinsic(plcc_ir::Intrinsic::RaiseFault, vec![]);
        self.b.jump(join, vec![]);
        self.b.switch_to(join);
    }

    fn load_unguarded(&mut self, p: &Place) -> Value {
        match p.bit {
            Some((bit, word_ty)) => {
                let t = word_ty.ir().expect("bit-addressable word");
                let w = self.b.load(t, p.addr);
                let mask = self.b.iconst(t, 1i64 << bit);
                let m = self.b.binary(BinaryOp::Band, w, mask);
                let z = self.b.iconst(t, 0);
                self.b.icmp(IntCC::Ne, m, z)
            }
            None => match p.ty.ir() {
                Some(t) => self.b.load(t, p.addr),
                None => self.b.iconst(Type::I32, 0),
            },
        }
    }

    /// Writes a place (a read-modify-write for a single bit); a write to an element
    /// whose index was out of bounds is dropped and raises the fault flag.
    pub(super) fn store_place(&mut self, p: &Place, v: Value) {
        let p = *p;
        self.guarded(p.guard, |cx| cx.store_unguarded(&p, v));
    }

    fn store_unguarded(&mut self, p: &Place, v: Value) {
        match p.bit {
            Some((bit, word_ty)) => {
                let t = word_ty.ir().expect("bit-addressable word");
                let w = self.b.load(t, p.addr);
                let clear = self.b.iconst(t, !(1i64 << bit));
                let kept = self.b.binary(BinaryOp::Band, w, clear);
                let vb = self.b.convert(ConvOp::Uext, t, v);
                let sh = self.b.iconst(t, bit as i64);
                let moved = self.b.binary(BinaryOp::Ishl, vb, sh);
                let nw = self.b.binary(BinaryOp::Bor, kept, moved);
                self.b.store(nw, p.addr);
            }
            None => self.b.store(v, p.addr),
        }
    }

    /// Resolves an expression that names memory: a variable, an FB member, an array
    /// element, a bit.
    pub(super) fn place(&mut self, e: &'s Expr) -> Option<Place> {
        let p = self.place_raw(e)?;
        Some(self.auto_deref(p))
    }

    /// Like [`Self::place`], but a REFERENCE TO variable is the reference itself.
    pub(super) fn place_raw(&mut self, e: &'s Expr) -> Option<Place> {
        match &e.kind {
            ExprKind::Paren(x) => self.place(x),
            ExprKind::Name(id) => match self.resolve_name(*id, true, None) {
                Named::Place(p) => Some(p),
                Named::Const(..) => {
                    let n = self.l.text(id.span).to_string();
                    self.l.error(
                        codes::E_WRITE_CONSTANT,
                        format!("`{n}` is a constant"),
                        id.span,
                    );
                    None
                }
                Named::Error => None,
            },
            ExprKind::Member(base, name) if self.self_ref(base).is_some() => {
                let r = self.self_ref(base)?;
                self.self_member_place(r, *name)
            }
            ExprKind::Deref(_) if self.self_ref(e).is_some() => {
                let r = self.self_ref(e)?;
                self.self_ref_place(r)
            }
            ExprKind::Member(base, name) => {
                if let Some(q) = self.qualifier(base) {
                    return match self.qualified(q, base, *name) {
                        Named::Place(p) => Some(p),
                        Named::Const(..) => {
                            let n = self.l.text(e.span).to_string();
                            self.l.error(
                                codes::E_WRITE_CONSTANT,
                                format!("`{n}` is a constant"),
                                e.span,
                            );
                            None
                        }
                        Named::Error => None,
                    };
                }
                if matches!(base.kind, ExprKind::Call { .. }) && self.infer(base).is_aggregate() {
                    self.l.error(
                        codes::E_UNSUPPORTED,
                        "not supported yet: a member of a FUNCTION's result; assign the result to a variable first",
                        e.span,
                    );
                    return None;
                }
                let bp = self.place(base)?;
                match bp.ty {
                    Ty::Fb(fb) => {
                        let mut p = self.member_place(bp.addr, fb, *name, false)?;
                        p.guard = bp.guard;
                        // Writing an input of a member instance of an instance we may
                        // not write is still not allowed.
                        if bp.access != super::body::Access::ReadWrite
                            && p.access == super::body::Access::ReadWrite
                        {
                            p.access = bp.access;
                        }
                        Some(p)
                    }
                    Ty::Struct(s) => {
                        let Some(fi) = self.l.struct_field(s, name.sym) else {
                            let st = &self.l.user.structs[s.0 as usize];
                            let names: Vec<&str> =
                                st.fields.iter().map(|f| f.display.as_str()).collect();
                            let note = format!("its fields are {}", names.join(", "));
                            let msg = format!(
                                "STRUCT {} has no field `{}`",
                                st.display,
                                self.l.text(name.span)
                            );
                            self.l.diags.push(
                                plcc_ir::diag::Diagnostic::error(
                                    codes::E_NO_MEMBER,
                                    msg,
                                    name.span,
                                )
                                .with_note(note),
                            );
                            return None;
                        };
                        let agg = self.l.struct_agg(s);
                        let st = &self.l.user.structs[s.0 as usize];
                        let ir_fi = st.ir_fields[fi]?;
                        let f = &st.fields[fi];
                        let (ty, tag) = (f.ty, f.tag);
                        let addr = self.b.field_addr(bp.addr, agg, ir_fi);
                        Some(Place {
                            addr,
                            ty,
                            // A field of an input or of another instance's output is
                            // that input or output.
                            access: bp.access,
                            bit: None,
                            guard: bp.guard,
                            tag,
                        })
                    }
                    Ty::Error => None,
                    t => {
                        let tn = self.l.ty_name(t);
                        let n = self.l.text(name.span).to_string();
                        let iface =
                            matches!(t, Ty::Ref(r) if self.l.types.get_ref(r).iface.is_some());
                        let msg = if iface {
                            format!("the interface `{tn}` has no method or property named `{n}`")
                        } else {
                            format!("a value of type {tn} has no member `{n}`")
                        };
                        self.l.error(codes::E_NO_MEMBER, msg, name.span);
                        None
                    }
                }
            }
            ExprKind::Bit(base, bit) => {
                let bp = self.place(base)?;
                let bits = match bp.ty.elem() {
                    Some(e) if e != ElemType::Bool && (e.is_bit_string() || e.is_integer()) => {
                        e.ir_type().bits()
                    }
                    _ => {
                        if bp.ty != Ty::Error {
                            let tn = self.l.ty_name(bp.ty);
                            self.l.error(
                                codes::E_TYPE_MISMATCH,
                                format!("bit access needs a bit string or an integer, not {tn}"),
                                e.span,
                            );
                        }
                        return None;
                    }
                };
                let n = match self.l.const_eval(bit, self.pou) {
                    Some((ConstVal::Int(n), _)) if n >= 0 && (n as u32) < bits => n as u8,
                    _ => {
                        self.l.error(
                            codes::E_BAD_INDEX,
                            format!("bit number must be a constant from 0 to {}", bits - 1),
                            bit.span,
                        );
                        return None;
                    }
                };
                Some(Place {
                    addr: bp.addr,
                    ty: Ty::BOOL,
                    access: bp.access,
                    bit: Some((n, bp.ty)),
                    guard: bp.guard,
                    tag: None,
                })
            }
            ExprKind::Index(..) => {
                let (base, idx) = index_chain(e);
                let bp = self.place(base)?;
                let Ty::Array(a) = bp.ty else {
                    if bp.ty != Ty::Error {
                        let tn = self.l.ty_name(bp.ty);
                        self.l.error(
                            codes::E_BAD_INDEX,
                            format!("a value of type {tn} cannot be indexed"),
                            e.span,
                        );
                    }
                    return None;
                };
                let at = self.l.types.get(a).clone();
                if idx.len() != at.dims.len() {
                    self.l.error(
                        codes::E_BAD_INDEX,
                        format!(
                            "this array has {} dimension(s), not {}",
                            at.dims.len(),
                            idx.len()
                        ),
                        e.span,
                    );
                    return None;
                }
                let mut addr = bp.addr;
                let mut guard = bp.guard;
                for (d, &ie) in idx.iter().enumerate() {
                    let agg = self.l.array_agg(a, d as u32);
                    let (a2, g) = self.index(addr, agg, at.dims[d], ie)?;
                    addr = a2;
                    guard = match (guard, g) {
                        (Some(prev), Some(g)) => Some(self.b.binary(BinaryOp::Band, prev, g)),
                        (prev, g) => prev.or(g),
                    };
                }
                Some(Place {
                    addr,
                    ty: at.elem,
                    access: bp.access,
                    bit: None,
                    guard,
                    tag: at.elem_tag,
                })
            }
            ExprKind::Deref(inner) => self.deref_place(e, inner),
            ExprKind::Call { .. } => {
                self.l.error(
                    codes::E_NOT_A_PLACE,
                    "a call result cannot be assigned or passed by reference",
                    e.span,
                );
                None
            }
            _ => {
                self.l.error(
                    codes::E_NOT_A_PLACE,
                    "this expression is not a variable",
                    e.span,
                );
                None
            }
        }
    }

    /// The address of element `ie` of the array `agg` with source bounds `(lo, hi)`,
    /// and an `i1` that says whether the index was in bounds (`None` when it is known
    /// to be). An index outside addresses element `lo` instead, so every target stays
    /// memory-safe; the access through the place then reads 0 or drops the write, and
    /// raises the fault flag.
    fn index(
        &mut self,
        base: Value,
        agg: plcc_ir::AggId,
        (lo, hi): (i64, i64),
        ie: &'s Expr,
    ) -> Option<(Value, Option<Value>)> {
        let it = self.infer(ie);
        let want = if it.is_literal() || it == Ty::Error {
            Ty::DINT
        } else {
            it
        };
        let iv = self.emit(ie, Some(want));
        let (v, e) = match iv.ty {
            Ty::Elem(e) if e.is_integer() || (e.is_bit_string() && e != ElemType::Bool) => {
                (iv.v, e)
            }
            Ty::Error => return None,
            t => {
                let tn = self.l.ty_name(t);
                self.l.error(
                    codes::E_BAD_INDEX,
                    format!("an array index must be an integer, not {tn}"),
                    ie.span,
                );
                return None;
            }
        };
        // Compute in 64 bits when the index or a bound needs it, else in 32.
        let bounds_wide = i32::try_from(lo).is_err() || i32::try_from(hi).is_err();
        let wide = bounds_wide
            || e.ir_type() == Type::I64
            || (e == ElemType::UDInt || e == ElemType::DWord);
        let t = if wide { Type::I64 } else { Type::I32 };
        let w = self.convert(v, e, if wide { ElemType::LInt } else { ElemType::DInt });
        let lo_c = self.b.iconst(t, lo);
        let zero_based = self.b.binary(BinaryOp::Isub, w, lo_c);
        if self.index_in_bounds(ie, lo, hi) {
            return Some((self.b.elem_addr(base, agg, zero_based), None));
        }
        let len = self.b.iconst(t, hi - lo + 1);
        let inside = self.b.icmp(IntCC::Ult, zero_based, len);
        let z = self.b.iconst(t, 0);
        let clamped = self.b.select(inside, zero_based, z);
        Some((self.b.elem_addr(base, agg, clamped), Some(inside)))
    }

    /// True if an index expression is known to lie in `lo..=hi`: a constant, or a FOR
    /// control variable with constant bounds that its body never writes.
    fn index_in_bounds(&mut self, ie: &'s Expr, lo: i64, hi: i64) -> bool {
        let mut e = ie;
        while let ExprKind::Paren(x) = &e.kind {
            e = x;
        }
        let range = match &e.kind {
            ExprKind::Name(id) => self
                .known_ranges
                .iter()
                .rev()
                .find(|(s, _, _)| *s == id.sym)
                .map(|&(_, a, b)| (a, b)),
            _ => None,
        };
        let range = range.or_else(|| match self.l.const_eval(ie, self.pou) {
            Some((ConstVal::Int(v), _)) => Some((v, v)),
            _ => None,
        });
        range.is_some_and(|(a, b)| a >= lo as i128 && b <= hi as i128)
    }
}

/// The array and every index of `a[i, j]`, `a[i][j]` or `a[i][j, k]`: ARRAY OF ARRAY
/// is one array with more dimensions, so indexes of nested subscripts add up (an
/// element is never itself an array).
pub(super) fn index_chain(e: &Expr) -> (&Expr, Vec<&Expr>) {
    let mut base = e;
    let mut lists = Vec::new();
    while let ExprKind::Index(b, idx) = &base.kind {
        lists.push(idx);
        base = b;
    }
    let idx = lists.into_iter().rev().flat_map(|l| l.iter()).collect();
    (base, idx)
}
