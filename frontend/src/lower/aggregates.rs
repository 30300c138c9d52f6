//! Whole STRUCTs and arrays as values: assignment, passing to and from FUNCTIONs and
//! function blocks. The IR has no aggregate values, so a whole STRUCT or array is
//! always handled through its address and copied scalar by scalar.

use super::body::{BodyCx, Place};
use super::Storage;
use crate::ast::{Expr, ExprKind, VarKind};
use crate::codes;
use crate::types::{ArrayId, PouId, Ty};
use plcc_ir::diag::Span;
use plcc_ir::{Type, Value};

/// True for the values that are handled through their address and copied whole when
/// passed: STRUCTs, arrays, strings, and function block instances (as VAR_INPUTs and
/// VAR_OUTPUTs of function blocks and PROGRAMs).
pub(super) fn copied_whole(ty: Ty) -> bool {
    ty.is_aggregate() || matches!(ty, Ty::Fb(_))
}

/// Arrays up to this many elements per dimension are copied element by element in
/// straight-line code; longer ones in a loop.
const UNROLL_MAX: u64 = 4;

impl<'s> BodyCx<'_, 's> {
    /// Copies a value of type `ty` from `src` to `dst`, recursively.
    pub(super) fn copy_value(&mut self, dst: Value, src: Value, ty: Ty) {
        match ty {
            Ty::Struct(s) => {
                let agg = self.l.struct_agg(s);
                let st = &self.l.user.structs[s.0 as usize];
                let fields: Vec<(u32, Ty)> = st
                    .fields
                    .iter()
                    .zip(&st.ir_fields)
                    .filter_map(|(f, ir)| ir.map(|i| (i, f.ty)))
                    .collect();
                for (fi, fty) in fields {
                    let d = self.b.field_addr(dst, agg, fi);
                    let s = self.b.field_addr(src, agg, fi);
                    self.copy_value(d, s, fty);
                }
            }
            Ty::Array(a) => self.copy_array(dst, src, a, 0),
            Ty::Str(s) => self.copy_string(dst, s, src),
            Ty::Fb(p) => self.copy_instance(dst, src, p),
            _ => {
                if let Some(t) = ty.ir() {
                    let v = self.b.load(t, src);
                    self.b.store(v, dst);
                }
            }
        }
    }

    /// Copies a function block instance (an FB instance given as a VAR_INPUT, or an
    /// FB-typed VAR_OUTPUT read with `=>`): every field of its instance struct, its
    /// internal state included; a VAR_IN_OUT field keeps the address it holds.
    fn copy_instance(&mut self, dst: Value, src: Value, p: PouId) {
        let Some(agg) = self.l.ir[p.0 as usize].agg else {
            return;
        };
        let fields: Vec<(u32, Ty, bool)> = self
            .l
            .pou(p)
            .vars
            .iter()
            .zip(&self.l.ir[p.0 as usize].storage)
            .filter_map(|(v, st)| match st {
                Some(Storage::Field(fi)) => Some((*fi, v.ty, v.section == VarKind::InOut)),
                _ => None,
            })
            .collect();
        for (fi, fty, inout) in fields {
            let d = self.b.field_addr(dst, agg, fi);
            let s = self.b.field_addr(src, agg, fi);
            if inout {
                let a = self.b.load(Type::Ptr, s);
                self.b.store(a, d);
            } else {
                self.copy_value(d, s, fty);
            }
        }
    }

    /// Copies dimension `dim` (and the ones after it) of an array.
    fn copy_array(&mut self, dst: Value, src: Value, a: ArrayId, dim: u32) {
        let at = self.l.types.get(a).clone();
        let agg = self.l.array_agg(a, dim);
        let len = at.len(dim as usize);
        let inner = (dim as usize) + 1 < at.dims.len();
        let element = |cx: &mut Self, i: Value| {
            let d = cx.b.elem_addr(dst, agg, i);
            let s = cx.b.elem_addr(src, agg, i);
            if inner {
                cx.copy_array(d, s, a, dim + 1);
            } else {
                cx.copy_value(d, s, at.elem);
            }
        };
        if len <= UNROLL_MAX {
            for k in 0..len {
                let i = self.b.iconst(Type::I32, k as i64);
                element(self, i);
            }
            return;
        }
        self.counted_loop(Type::I32, len as i64, element);
    }

    /// Reports an attempt to copy a value that holds function block instances; true
    /// if the value can be copied.
    pub(super) fn check_copyable(&mut self, ty: Ty, span: Span) -> bool {
        if !self.l.contains_fb(ty) {
            return true;
        }
        let t = self.l.ty_name(ty);
        self.l.error(
            codes::E_UNSUPPORTED,
            format!("not supported yet: copying a whole {t} (it holds function block instances)"),
            span,
        );
        false
    }

    /// The address of a whole STRUCT or array of type `ty` that `e` gives: a
    /// variable (or member, element) of exactly that type, or the result of a FUNCTION
    /// returning one. Reports anything else.
    pub(super) fn agg_source(&mut self, e: &'s Expr, ty: Ty) -> Option<Value> {
        if let Ty::Str(s) = ty {
            // Any string of the same width: the receiver cuts it to its capacity.
            return self.emit_string(e, Some(s.wide)).map(|v| v.v);
        }
        let mut inner = e;
        while let ExprKind::Paren(x) = &inner.kind {
            inner = x;
        }
        let found = self.infer(inner);
        if found != ty && found != Ty::Error {
            let (a, b) = (self.l.ty_name(ty), self.l.ty_name(found));
            self.l.error(
                codes::E_TYPE_MISMATCH,
                format!("expected {a}, found {b}"),
                e.span,
            );
            return None;
        }
        if found != ty {
            let before = self.l.diags.len();
            let v = self.emit(inner, Some(ty));
            let reported = self.l.diags[before..].iter().any(|d| d.is_error());
            if !reported && v.ty != Ty::Error {
                let (a, b) = (self.l.ty_name(ty), self.l.ty_name(v.ty));
                self.l.error(
                    codes::E_TYPE_MISMATCH,
                    format!("expected {a}, found {b}"),
                    e.span,
                );
            } else if !reported {
                let a = self.l.ty_name(ty);
                self.l.error(
                    codes::E_TYPE_MISMATCH,
                    format!("expected a whole {a} here"),
                    e.span,
                );
            }
            return None;
        }
        if let ExprKind::Call { callee, args } = &inner.kind {
            let is_user_fn =
                match &callee.kind {
                    ExprKind::Name(id) => {
                        self.l.pou(self.pou).var(id.sym).is_none()
                            && self.l.pou_by_name.get(&id.sym).is_some_and(|&p| {
                                self.l.pou(p).kind == crate::ast::PouKind::Function
                            })
                    }
                    _ => false,
                };
            if !is_user_fn {
                let t = self.l.ty_name(ty);
                self.l.error(
                    codes::E_TYPE_MISMATCH,
                    format!("a standard function cannot give a whole {t}"),
                    e.span,
                );
                return None;
            }
            return self
                .call_expr(callee, args, Some(ty), inner.span)
                .filter(|v| v.ty == ty)
                .map(|v| v.v);
        }
        let p = self.place(inner)?;
        Some(self.readable_addr(&p))
    }

    /// The address to read a whole STRUCT or array from. An element whose index was
    /// out of bounds reads as the type's default (a scratch copy), and raises the
    /// fault flag.
    pub(super) fn readable_addr(&mut self, p: &Place) -> Value {
        let Some(guard) = p.guard else {
            return p.addr;
        };
        let Some((mt, _)) = self.l.mem_type(p.ty) else {
            return p.addr;
        };
        let scratch = self.b.slot("out_of_bounds", mt);
        let scratch_addr = self.b.slot_addr(scratch);
        self.init_var(scratch_addr, p.ty, p.tag, None);
        self.guarded(Some(guard), |_| {});
        self.b.select(guard, p.addr, scratch_addr)
    }

    /// `target := value` for a whole STRUCT or array: a copy, element by element. A
    /// target element whose index was out of bounds is not written.
    pub(super) fn assign_aggregate(&mut self, place: &Place, value: &'s Expr, span: Span) {
        if !self.check_copyable(place.ty, span) {
            self.check_only_value(value);
            return;
        }
        let Some(src) = self.agg_source(value, place.ty) else {
            return;
        };
        let (dst, ty) = (place.addr, place.ty);
        self.guarded(place.guard, |cx| cx.copy_value(dst, src, ty));
    }

    /// Emits an expression only for its own errors (its value is not used).
    fn check_only_value(&mut self, value: &'s Expr) {
        if !matches!(value.kind, ExprKind::Literal(_)) {
            let _ = self.emit(value, None);
        }
    }

    /// `output => target` (or a positional argument in an output's place) after a
    /// call, for a whole STRUCT or array output at `src`.
    pub(super) fn assign_output_agg(
        &mut self,
        src: Value,
        ty: Ty,
        negated: bool,
        target: &'s Expr,
        span: Span,
    ) {
        if negated {
            self.l.error(
                codes::E_TYPE_MISMATCH,
                "only a BOOL output can be negated",
                span,
            );
            return;
        }
        let Some(place) = self.place(target) else {
            return;
        };
        if !self.check_writable(&place, target.span) {
            return;
        }
        if let (Ty::Str(d), Ty::Str(s)) = (place.ty, ty) {
            if d.wide == s.wide {
                let dst = place.addr;
                self.guarded(place.guard, |cx| cx.copy_string(dst, d, src));
                return;
            }
        }
        if place.ty != ty {
            if place.ty != Ty::Error {
                let (a, b) = (self.l.ty_name(place.ty), self.l.ty_name(ty));
                self.l.error(
                    codes::E_TYPE_MISMATCH,
                    format!("expected {a}, found {b}"),
                    target.span,
                );
            }
            return;
        }
        let dst = place.addr;
        self.guarded(place.guard, |cx| cx.copy_value(dst, src, ty));
    }
}
