//! References: `REF_TO t`, `REF(x)`, `r^`, `NULL`, `r REF= x` (IEC 61131-3 edition 3),
//! and `SIZEOF`.
//!
//! A reference is an IR `ptr`; NULL is `iconst.ptr 0`. Reading or writing through a
//! reference that is NULL reads 0 (the type's default), drops the write and raises
//! the fault flag, like an array index out of bounds. `REF()` takes only variables
//! that live as long as the program (PROGRAM and FB instance variables, globals, and
//! their elements and fields), as the standard requires, so a reference never
//! outlives what it points to and every machine stays memory-safe.

use super::body::{BodyCx, Place};
use super::expr::Val;
use super::Storage;
use crate::ast::{BinaryOp as Op, Expr, ExprKind, VarKind};
use crate::codes;
use crate::types::{RefTy, Ty};
use plcc_ir::diag::Span;
use plcc_ir::{BinaryOp, ConvOp, ElemType, IntCC, Type, Value};

impl<'s> BodyCx<'_, 's> {
    /// The null reference.
    pub(super) fn null_val(&mut self) -> Val {
        let v = self.b.iconst(Type::Ptr, 0);
        Val { v, ty: Ty::Null }
    }

    /// True if `e` is the name `NULL` (and no variable is called so).
    pub(super) fn is_null_name(&self, e: &Expr) -> bool {
        match &e.kind {
            ExprKind::Name(id) => {
                self.l.sym_name(id.sym).eq_ignore_ascii_case("NULL")
                    && self.l.pou(self.pou).var(id.sym).is_none()
            }
            ExprKind::Paren(x) => self.is_null_name(x),
            _ => false,
        }
    }

    /// The type `r^` has.
    pub(super) fn deref_type(&self, r: Ty) -> Ty {
        match r {
            Ty::Ref(id) => self.l.types.get_ref(id).target,
            _ => Ty::Error,
        }
    }

    /// A REFERENCE TO type stands for its target.
    pub(super) fn auto_deref_ty(&self, t: Ty) -> Ty {
        match t {
            Ty::Ref(id) if self.l.types.get_ref(id).auto => self.l.types.get_ref(id).target,
            t => t,
        }
    }

    /// A REFERENCE TO variable stands for the variable it points to.
    pub(super) fn auto_deref(&mut self, p: Place) -> Place {
        let Ty::Ref(id) = p.ty else { return p };
        let r = self.l.types.get_ref(id);
        if !r.auto {
            return p;
        }
        let v = self.load_place(&p);
        self.pointee(v, r)
    }

    /// The place a reference value `v` points to, guarded by it not being NULL.
    fn pointee(&mut self, v: Value, r: RefTy) -> Place {
        let null = self.b.iconst(Type::Ptr, 0);
        let ok = self.b.icmp(IntCC::Ne, v, null);
        Place {
            addr: v,
            ty: r.target,
            access: super::body::Access::ReadWrite,
            bit: None,
            guard: Some(ok),
            tag: r.tag,
        }
    }

    /// `r^`: the place a reference points to, guarded by the reference not being
    /// NULL.
    pub(super) fn deref_place(&mut self, e: &'s Expr, inner: &'s Expr) -> Option<Place> {
        let is_place = matches!(
            inner.kind,
            ExprKind::Name(_) | ExprKind::Member(..) | ExprKind::Index(..) | ExprKind::Paren(_)
        ) && !self.is_null_name(inner)
            && matches!(self.infer_raw(inner), Ty::Ref(_));
        let v = if is_place {
            let p = self.place_raw(inner)?;
            let v = self.load_place(&p);
            Val { v, ty: p.ty }
        } else {
            self.emit(inner, None)
        };
        let Ty::Ref(id) = v.ty else {
            if v.ty != Ty::Error {
                let t = self.l.ty_name(v.ty);
                self.l.error(
                    codes::E_TYPE_MISMATCH,
                    format!("only a reference can be dereferenced with `^`, not {t}"),
                    e.span,
                );
            }
            return None;
        };
        let r = self.l.types.get_ref(id);
        if let Some(k) = r.iface {
            let n = self.l.classes.ifaces[k].display.clone();
            self.l.error(
                codes::E_TYPE_MISMATCH,
                format!("a value of the interface `{n}` is not dereferenced: call its methods and use its properties on it directly"),
                e.span,
            );
            return None;
        }
        Some(self.pointee(v.v, r))
    }

    /// `REF(x)` (or CODESYS `ADR(x)`): the address of a variable that lives as long
    /// as the program. An element whose index is out of bounds gives NULL (and
    /// raises the fault flag).
    pub(super) fn ref_of(&mut self, x: &'s Expr, name: &str, pointer: bool) -> Option<Val> {
        if pointer && !self.l.codesys {
            self.l.error(
                codes::E_UNSUPPORTED,
                format!("`{name}` is CODESYS's: compile with `--dialect codesys`, or use `REF`"),
                x.span,
            );
            return None;
        }
        if pointer && self.not_static(x).is_some() {
            // CODESYS lets a program keep the address of a temporary past its call.
            self.l.module.unchecked_pointers = true;
        } else if let Some(why) = self.not_static(x) {
            self.l.diags.push(
                plcc_ir::diag::Diagnostic::error(
                    codes::E_NOT_A_PLACE,
                    format!("`{name}` needs a variable that lives as long as the program, not {why}"),
                    x.span,
                )
                .with_note("a reference to it would outlive it: use a PROGRAM or FUNCTION_BLOCK variable, or a global"),
            );
            return None;
        }
        let saved = self.in_init;
        // An initial value may take the address of a variable of the same instance.
        self.in_init = false;
        let p = self.place(x);
        self.in_init = saved;
        let p = p?;
        if p.bit.is_some() {
            self.l.error(
                codes::E_NOT_A_PLACE,
                format!("`{name}` cannot take the address of a single bit"),
                x.span,
            );
            return None;
        }
        if p.ty == Ty::Error {
            return None;
        }
        let r = self.l.types.reference(RefTy {
            iface: None,
            target: p.ty,
            tag: None,
            pointer,
            auto: false,
        });
        let v = match p.guard {
            None => p.addr,
            Some(g) => {
                self.guarded(Some(g), |_| {});
                let null = self.b.iconst(Type::Ptr, 0);
                self.b.select(g, p.addr, null)
            }
        };
        Some(Val { v, ty: Ty::Ref(r) })
    }

    /// Why `e` does not name a variable that lives as long as the program (`None`
    /// if it does). Elements, fields and members live as long as the variable they
    /// are in; what a reference points to lives as long as the program.
    fn not_static(&self, e: &Expr) -> Option<&'static str> {
        match &e.kind {
            ExprKind::Paren(x) | ExprKind::Member(x, _) | ExprKind::Index(x, _) => {
                self.not_static(x)
            }
            ExprKind::Bit(x, _) => self.not_static(x),
            ExprKind::Deref(_) => None,
            ExprKind::Name(id) => {
                if self.temps.contains_key(&id.sym) {
                    return Some("a temporary");
                }
                let pou = self.l.pou(self.pou);
                let Some(vi) = pou.var(id.sym) else {
                    if pou.kind == crate::ast::PouKind::Function && pou.name.sym == id.sym {
                        return Some("the result of a FUNCTION");
                    }
                    // A global (or an error reported where the place is resolved).
                    return None;
                };
                let v = &pou.vars[vi as usize];
                if pou.kind == crate::ast::PouKind::Function {
                    return Some(match v.section {
                        VarKind::External => return None,
                        VarKind::InOut => "a VAR_IN_OUT (it may be a temporary of the caller)",
                        _ => "a variable of a FUNCTION (it lives for one call)",
                    });
                }
                match v.section {
                    VarKind::Temp => Some("a VAR_TEMP (it lives for one call)"),
                    VarKind::InOut => Some("a VAR_IN_OUT (it may be a temporary of the caller)"),
                    _ => match self.l.ir[self.pou.0 as usize].storage[vi as usize] {
                        Some(Storage::Slot(_)) => Some("a temporary"),
                        _ => None,
                    },
                }
            }
            _ => Some("a value"),
        }
    }

    /// `target REF= source`: the reference `target` now points to `source`.
    pub(super) fn ref_assign(&mut self, target: &'s Expr, source: &'s Expr, span: Span) {
        let Some(place) = self.place_raw(target) else {
            return;
        };
        let Ty::Ref(id) = place.ty else {
            if place.ty != Ty::Error {
                let t = self.l.ty_name(place.ty);
                self.l.error(
                    codes::E_TYPE_MISMATCH,
                    format!("`REF=` assigns to a reference, not to a {t}"),
                    target.span,
                );
            }
            return;
        };
        if !self.check_writable(&place, target.span) {
            return;
        }
        let v = if self.is_null_name(source) {
            self.null_val()
        } else {
            match self.ref_of(source, "REF=", self.l.types.get_ref(id).pointer) {
                Some(v) => v,
                None => return,
            }
        };
        let v = self.coerce(v, place.ty, span);
        self.store_place(&place, v);
    }

    /// True if a reference of type `from` may be assigned to one of type `to`: the
    /// same target type (any target between CODESYS pointers), or NULL.
    pub(super) fn ref_fits(&self, from: Ty, to: Ty) -> bool {
        match (from, to) {
            (Ty::Null, Ty::Ref(_)) => true,
            (Ty::Ref(a), Ty::Ref(b)) => {
                let (a, b) = (self.l.types.get_ref(a), self.l.types.get_ref(b));
                if let Some(k) = b.iface {
                    // An interface from one that extends it, or from a reference to
                    // an instance of a class implementing it.
                    return match (a.iface, a.target) {
                        (Some(j), _) => self.l.iface_closure(j).contains(&k),
                        (None, Ty::Fb(d)) => self.l.implements(d, k),
                        _ => false,
                    };
                }
                if a.iface.is_some() {
                    return false;
                }
                if let (Ty::Fb(d), Ty::Fb(c)) = (a.target, b.target) {
                    // A derived instance is a base instance.
                    if self.l.derives_from(d, c) {
                        return true;
                    }
                }
                a.target == b.target || (a.pointer && b.pointer)
            }
            _ => false,
        }
    }

    /// The address of an instance given where an interface is expected (`itf :=
    /// inst;`), if `e` names an instance of a class implementing it. A missing
    /// instance (an element out of bounds) gives NULL.
    pub(super) fn instance_as_iface(&mut self, e: &'s Expr, to: Ty) -> Option<Value> {
        let Ty::Ref(r) = to else { return None };
        let k = self.l.types.get_ref(r).iface?;
        let Ty::Fb(d) = self.infer(e) else {
            return None;
        };
        let p = self.place(e)?;
        if !self.l.implements(d, k) {
            let n = self.l.pou(d).display.clone();
            let i = self.l.classes.ifaces[k].display.clone();
            self.l.error(
                codes::E_TYPE_MISMATCH,
                format!("`{n}` does not implement the interface `{i}`"),
                e.span,
            );
            return Some(self.b.iconst(Type::Ptr, 0));
        }
        Some(match p.guard {
            Some(g) => {
                let null = self.b.iconst(Type::Ptr, 0);
                self.b.select(g, p.addr, null)
            }
            None => p.addr,
        })
    }

    /// A CODESYS pointer given the address of another type (`POINTER TO DWORD` from
    /// `ADR(byte_var)`) may reach past its target: the module is unchecked.
    pub(super) fn note_pointer_cast(&mut self, from: Ty, to: Ty) {
        if let (Ty::Ref(a), Ty::Ref(b)) = (from, to) {
            let (a, b) = (self.l.types.get_ref(a), self.l.types.get_ref(b));
            let upcast = b.iface.is_some()
                || matches!((a.target, b.target), (Ty::Fb(d), Ty::Fb(c)) if self.l.derives_from(d, c));
            if a.target != b.target && !upcast {
                self.l.module.unchecked_pointers = true;
            }
        }
    }

    /// An interface compared with an integer (`itf = 0`).
    pub(super) fn is_iface_zero(&self, l: Ty, r: Ty) -> bool {
        let is_iface = |t: Ty| matches!(t, Ty::Ref(id) if self.l.types.get_ref(id).iface.is_some());
        (is_iface(l) && r == Ty::AnyInt) || (is_iface(r) && l == Ty::AnyInt)
    }

    /// `itf = 0`, `itf <> 0` (CODESYS's test of an interface variable, as NULL).
    pub(super) fn iface_compare(
        &mut self,
        eq: bool,
        a: &'s Expr,
        b: &'s Expr,
        lt: Ty,
        rt: Ty,
    ) -> Option<Val> {
        let is_iface =
            |cx: &Self, t: Ty| matches!(t, Ty::Ref(id) if cx.l.types.get_ref(id).iface.is_some());
        let (itf, zero) = if is_iface(self, lt) && rt == Ty::AnyInt {
            (a, b)
        } else if is_iface(self, rt) && lt == Ty::AnyInt {
            (b, a)
        } else {
            return None;
        };
        if self.l.const_int_in(zero, Some(self.pou)) != Some(0) {
            return None;
        }
        let x = self.emit(itf, None);
        let null = self.b.iconst(Type::Ptr, 0);
        let cc = if eq { IntCC::Eq } else { IntCC::Ne };
        let v = self.b.icmp(cc, x.v, null);
        Some(Val { v, ty: Ty::BOOL })
    }

    /// `=` and `<>` between references (or NULL).
    pub(super) fn compare_refs(&mut self, eq: bool, a: &'s Expr, b: &'s Expr) -> Val {
        let x = self.emit(a, None);
        let y = self.emit(b, None);
        let cc = if eq { IntCC::Eq } else { IntCC::Ne };
        let v = self.b.icmp(cc, x.v, y.v);
        Val { v, ty: Ty::BOOL }
    }

    /// `SIZEOF(x)`: the bytes a variable (or a type named as an argument) takes on
    /// the target that runs the code (`sizeof` in the IR, which each backend answers
    /// with its layout). Typed like an integer literal: the type its context wants.
    pub(super) fn size_of(&mut self, x: &'s Expr, want: Option<Ty>, span: Span) -> Option<Val> {
        let ty = match &x.kind {
            ExprKind::Name(id)
                if self.infer(x) == Ty::Error && !self.l.sym_name(id.sym).is_empty() =>
            {
                // A type name.
                let (t, _) = self.l.resolve_type_tagged_named(*id);
                t
            }
            _ => {
                let saved = self.in_init;
                self.in_init = false;
                let t = self.infer(x);
                self.in_init = saved;
                if t == Ty::Error {
                    let _ = self.emit(x, None);
                }
                t
            }
        };
        if ty == Ty::Error {
            return None;
        }
        let Some((mt, _)) = self.l.mem_type(ty) else {
            let t = self.l.ty_name(ty);
            self.l
                .error(codes::E_TYPE_MISMATCH, format!("SIZEOF of {t}"), span);
            return None;
        };
        // The target answers (`sizeof` in the IR); the host's size checks that the
        // result type can hold it.
        let host =
            plcc_ir::layout::Layout::compute(&self.l.module, plcc_ir::layout::LayoutRules::HOST);
        let ty = super::typing::concretize(Ty::AnyInt, want);
        if let Err(msg) = super::consts::ConstVal::Int(host.size_of(mt) as i128).coerce(ty) {
            self.l.error(codes::E_LITERAL_RANGE, msg, span);
            return None;
        }
        let v = match ty.ir() {
            Some(t) if t.is_float() => {
                let n = self.b.size_of(Type::I64, mt);
                self.b.convert(ConvOp::SiToF, t, n)
            }
            Some(t) => self.b.size_of(t, mt),
            None => return None,
        };
        Some(Val { v, ty })
    }

    /// Emits `e` as a reference value of type `to` (or reports it).
    pub(super) fn emit_ref(&mut self, e: &'s Expr, to: Ty) -> Value {
        if self.is_null_name(e) {
            return self.b.iconst(Type::Ptr, 0);
        }
        if let Some(v) = self.instance_as_iface(e, to) {
            return v;
        }
        let v = self.emit(e, Some(to));
        if v.ty == Ty::Error || self.ref_fits(v.ty, to) {
            self.note_pointer_cast(v.ty, to);
            return v.v;
        }
        self.coerce(v, to, e.span)
    }
}

/// A bit string as the unsigned integer of its width (CODESYS mixes them freely).
fn as_unsigned(t: Ty) -> Ty {
    match t {
        Ty::Elem(ElemType::Byte) => Ty::Elem(ElemType::USInt),
        Ty::Elem(ElemType::Word) => Ty::Elem(ElemType::UInt),
        Ty::Elem(ElemType::DWord) => Ty::Elem(ElemType::UDInt),
        Ty::Elem(ElemType::LWord) => Ty::Elem(ElemType::ULInt),
        t => t,
    }
}

/// Integers and bit strings other than BOOL.
fn int_like(t: Ty) -> bool {
    t.is_int_like()
}

impl<'s> BodyCx<'_, 's> {
    /// True if `t` is a CODESYS `POINTER TO`.
    fn is_pointer(&self, t: Ty) -> bool {
        matches!(t, Ty::Ref(id) if self.l.types.get_ref(id).pointer)
    }

    /// The type of `l op r` in the CODESYS dialect where IEC 61131-3 has none:
    /// pointer arithmetic and comparisons, and bit strings mixed with numbers.
    pub(super) fn codesys_binary_type(
        &self,
        op: Op,
        l: Ty,
        r: Ty,
    ) -> Option<super::typing::BinTyping> {
        if !self.l.codesys {
            return None;
        }
        let cmp = matches!(op, Op::Eq | Op::Ne | Op::Lt | Op::Le | Op::Gt | Op::Ge);
        let (lp, rp) = (self.is_pointer(l), self.is_pointer(r));
        if lp || rp {
            let result = match op {
                _ if cmp && (lp || int_like(l)) && (rp || int_like(r)) => Ty::BOOL,
                Op::Add if lp && int_like(r) => l,
                Op::Add if rp && int_like(l) => r,
                Op::Sub if lp && int_like(r) => l,
                Op::Sub if lp && rp => Ty::Elem(ElemType::DWord),
                _ => return None,
            };
            return Some(super::typing::BinTyping {
                operand: if lp { l } else { r },
                right: Some(if lp { r } else { l }),
                result,
            });
        }
        let (l2, r2) = (as_unsigned(l), as_unsigned(r));
        if (l2, r2) == (l, r) {
            return None;
        }
        super::typing::binary_typing(op, l2, r2, &|_| String::new()).ok()
    }

    /// `l op r` with a CODESYS pointer on one side: addresses as numbers.
    pub(super) fn pointer_binary(&mut self, op: Op, a: &'s Expr, b: &'s Expr, result: Ty) -> Val {
        let x = self.emit(a, None);
        let y = self.emit(b, None);
        let is_ptr = |t: Ty| matches!(t, Ty::Ref(_) | Ty::Null);
        if is_ptr(x.ty) && is_ptr(y.ty) && !matches!(op, Op::Add | Op::Sub) {
            // Two addresses compare as they are, with no number in between.
            let cc = match op {
                Op::Eq => IntCC::Eq,
                Op::Ne => IntCC::Ne,
                Op::Lt => IntCC::Ult,
                Op::Le => IntCC::Ule,
                Op::Gt => IntCC::Ugt,
                _ => IntCC::Uge,
            };
            let v = self.b.icmp(cc, x.v, y.v);
            return Val { v, ty: result };
        }
        let xi = self.address_value(x);
        let yi = self.address_value(y);
        let v = match op {
            Op::Add | Op::Sub => {
                let bop = if op == Op::Add {
                    BinaryOp::Iadd
                } else {
                    BinaryOp::Isub
                };
                let s = self.b.binary(bop, xi, yi);
                if let Ty::Ref(_) = result {
                    self.l.module.unchecked_pointers = true;
                    self.b.convert(ConvOp::IntToPtr, Type::Ptr, s)
                } else {
                    self.b.convert(ConvOp::Itrunc, Type::I32, s)
                }
            }
            _ => {
                let cc = match op {
                    Op::Eq => IntCC::Eq,
                    Op::Ne => IntCC::Ne,
                    Op::Lt => IntCC::Ult,
                    Op::Le => IntCC::Ule,
                    Op::Gt => IntCC::Ugt,
                    _ => IntCC::Uge,
                };
                self.b.icmp(cc, xi, yi)
            }
        };
        Val { v, ty: result }
    }

    /// A pointer's address, or an integer, as an `i64` (integers zero-extended as
    /// addresses are).
    fn address_value(&mut self, v: Val) -> Value {
        match v.ty {
            Ty::Ref(_) | Ty::Null => self.b.convert(ConvOp::PtrToInt, Type::I64, v.v),
            t => match t.ir() {
                Some(Type::I64) => v.v,
                Some(it) if it.is_int() => self.b.convert(ConvOp::Uext, Type::I64, v.v),
                _ => self.b.iconst(Type::I64, 0),
            },
        }
    }

    /// True if CODESYS converts `from` to `to` without being asked: a pointer to or
    /// from an integer or bit string, a bit string to or from a number that holds it.
    pub(super) fn codesys_implicit(&self, from: Ty, to: Ty) -> bool {
        if !self.l.codesys {
            return false;
        }
        match (from, to) {
            (Ty::Ref(_), t) | (t, Ty::Ref(_)) if self.is_pointer(from) || self.is_pointer(to) => {
                int_like(t) || (self.is_pointer(from) && self.is_pointer(to))
            }
            (Ty::Elem(a), Ty::Elem(b)) => {
                let numeric = |e: ElemType| {
                    e != ElemType::Bool && (e.is_integer() || e.is_bit_string() || e.is_real())
                };
                // Between integers and bit strings of any widths (narrowing wraps),
                // and from them to a real.
                // Between reals, and from them to a real.
                numeric(a) && numeric(b) && (!a.is_real() || b.is_real())
            }
            _ => false,
        }
    }

    /// Emits the conversion [`Self::codesys_implicit`] allows.
    pub(super) fn codesys_convert(&mut self, v: Value, from: Ty, to: Ty) -> Value {
        match (from, to) {
            (Ty::Ref(_), Ty::Ref(_)) => v,
            (Ty::Ref(_), t) => {
                let it = t.ir().unwrap_or(Type::I32);
                self.b.convert(ConvOp::PtrToInt, it, v)
            }
            (_, Ty::Ref(_)) => {
                self.l.module.unchecked_pointers = true;
                self.b.convert(ConvOp::IntToPtr, Type::Ptr, v)
            }
            (Ty::Elem(a), Ty::Elem(b)) => self.convert(v, a, b),
            _ => v,
        }
    }
}

impl<'s> BodyCx<'_, 's> {
    /// In the CODESYS dialect an integer literal too large for the other operand's
    /// type (`i * 60000` with `i` an INT) makes the operation DINT (or LINT), as
    /// CODESYS types it; IEC 61131-3 reports the literal instead.
    pub(super) fn codesys_widen_for_literal(
        &mut self,
        operand: Ty,
        a: &'s Expr,
        b: &'s Expr,
    ) -> Ty {
        let Some(e) = operand.elem().filter(|e| {
            self.l.codesys && *e != ElemType::Bool && (e.is_integer() || e.is_bit_string())
        }) else {
            return operand;
        };
        let mut need = e;
        for x in [a, b] {
            if self.infer(x) != Ty::AnyInt {
                continue;
            }
            let Some((super::consts::ConstVal::Int(v), _)) = self.l.const_eval(x, self.pou) else {
                continue;
            };
            let fits = |t: ElemType| {
                let range = match t {
                    ElemType::Byte => Some((0, u8::MAX as i128)),
                    ElemType::Word => Some((0, u16::MAX as i128)),
                    ElemType::DWord => Some((0, u32::MAX as i128)),
                    ElemType::LWord => Some((0, u64::MAX as i128)),
                    t => crate::types::int_range(t),
                };
                range.is_some_and(|(lo, hi)| v >= lo && v <= hi)
            };
            if !fits(need) {
                need = if fits(ElemType::DInt) {
                    ElemType::DInt
                } else {
                    ElemType::LInt
                };
            }
        }
        if need == e {
            operand
        } else {
            Ty::Elem(need)
        }
    }
}
