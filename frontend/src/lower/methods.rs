//! METHODs: their bodies see the variables of their FUNCTION_BLOCK (and its bases)
//! through the instance address, their first parameter; calls `inst.M(...)`, `M()`
//! and `THIS^.M()` inside the FB, `SUPER^.M()` (the base's method, bound statically)
//! and `SUPER^()` (the base's body run on this instance).

use super::body::{Access, BodyCx, Named, Place};
use super::expr::Val;
use super::Storage;
use crate::ast::{self, Expr, ExprKind, VarKind};
use crate::codes;
use crate::types::{PouId, Ty};
use plcc_ir::diag::Span;
use plcc_ir::{FuncId, Type, Value};

/// `THIS^` or `SUPER^`.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub(super) enum SelfRef {
    /// `THIS^`: the instance, of the class being written.
    This(PouId),
    /// `SUPER^`: the instance seen as its base.
    Super(PouId),
}

impl<'s> BodyCx<'_, 's> {
    /// The class whose code is being lowered: a METHOD's owner, the POU of a body
    /// (even when it runs on a derived instance).
    pub(super) fn lexical_class(&self) -> Option<PouId> {
        self.this_class?;
        let p = self.l.pou(self.pou);
        Some(p.owner.unwrap_or(self.pou))
    }

    /// `THIS^` or `SUPER^` (`e` is the dereference).
    pub(super) fn self_ref(&self, e: &Expr) -> Option<SelfRef> {
        let ExprKind::Deref(x) = &e.kind else {
            return None;
        };
        let ExprKind::Name(id) = &x.kind else {
            return None;
        };
        if self.l.pou(self.pou).var(id.sym).is_some() {
            return None;
        }
        let class = self.lexical_class()?;
        match self.l.sym_name(id.sym) {
            "THIS" => Some(SelfRef::This(class)),
            "SUPER" => self.l.pou(class).base.map(SelfRef::Super),
            _ => None,
        }
    }

    /// The place of `THIS^` or `SUPER^`.
    pub(super) fn self_ref_place(&self, r: SelfRef) -> Option<Place> {
        let me = self.self_ptr?;
        let (SelfRef::This(c) | SelfRef::Super(c)) = r;
        Some(Place::new(me, Ty::Fb(c)))
    }

    /// The type of a variable of the class seen from here (see
    /// [`Self::class_member_var`]).
    pub(super) fn class_name_type(&self, sym: crate::intern::Symbol) -> Option<Ty> {
        self.this_class?;
        let pou = self.l.pou(self.pou);
        let start = match pou.owner {
            Some(o) => o,
            None => pou.base?,
        };
        let (c, vi) = self.l.class_var(start, sym)?;
        Some(self.l.pou(c).vars[vi].ty)
    }

    /// A variable of the class seen from a METHOD (the FB's and its bases'), or an
    /// inherited one seen from a body.
    pub(super) fn class_member_var(&mut self, id: ast::Ident) -> Option<Named> {
        let this_class = self.this_class?;
        let pou = self.l.pou(self.pou);
        let start = match pou.owner {
            Some(o) => o,
            None => pou.base?,
        };
        let (c, vi) = self.l.class_var(start, id.sym)?;
        let v = self.l.pou(c).vars[vi].clone();
        if !self.var_accessible(c, vi, id.span) {
            return Some(Named::Error);
        }
        Some(self.class_field(c, vi, this_class, &v, id.span))
    }

    /// Variable `vi` of class `c`, a field of the instance (of class `class`) at
    /// `self_ptr`.
    fn class_field(
        &mut self,
        c: PouId,
        vi: usize,
        class: PouId,
        v: &super::VarInfo,
        span: Span,
    ) -> Named {
        match self.l.ir[c.0 as usize].storage[vi] {
            Some(Storage::Const(k)) => {
                Named::Const(self.l.ir[c.0 as usize].consts[k as usize], v.ty)
            }
            Some(Storage::Field(f)) => {
                if self.in_init {
                    self.l.error(
                        codes::E_NOT_CONSTANT,
                        "an initial value can only use literals and constants",
                        span,
                    );
                    return Named::Error;
                }
                let Some(agg) = self.l.ir[class.0 as usize].agg else {
                    return Named::Error;
                };
                let Some(this) = self.self_ptr else {
                    return Named::Error;
                };
                let fa = self.b.field_addr(this, agg, f);
                let addr = if v.section == VarKind::InOut {
                    self.b.load(Type::Ptr, fa)
                } else {
                    fa
                };
                Named::Place(Place {
                    addr,
                    ty: v.ty,
                    access: if v.read_only {
                        Access::Constant
                    } else {
                        Access::ReadWrite
                    },
                    bit: None,
                    guard: None,
                    tag: v.tag,
                })
            }
            // VAR_TEMP of the FB: its body's only.
            _ => Named::Error,
        }
    }

    /// Checks the access specifier of the VAR block of variable `vi` of class `c`
    /// from the code being lowered (E0803); true if it may be used.
    pub(super) fn var_accessible(&mut self, c: PouId, vi: usize, span: Span) -> bool {
        let Some((access, at)) = self.l.var_access(c, vi) else {
            return true;
        };
        let from = self.lexical_class();
        let ok = match access {
            ast::AccessSpec::Public | ast::AccessSpec::Internal => true,
            ast::AccessSpec::Private => from == Some(c),
            ast::AccessSpec::Protected => from.is_some_and(|f| self.l.derives_from(f, c)),
        };
        if !ok {
            let n = self.l.pou(c).vars[vi].display.clone();
            let cn = self.l.pou(c).display.clone();
            let what = if access == ast::AccessSpec::Private {
                format!("`{n}` is a PRIVATE variable of `{cn}`: only `{cn}` can use it")
            } else {
                format!("`{n}` is a PROTECTED variable of `{cn}`: only `{cn}` and the function blocks derived from it can use it")
            };
            self.l.diags.push(
                plcc_ir::diag::Diagnostic::error(codes::E_ACCESS, what, span)
                    .with_secondary(at, "declared here"),
            );
        }
        ok
    }

    /// The type of property `sym` of class `p` (its getter's result, else its
    /// setter's value), `Error` if it has none.
    pub(super) fn property_type(&self, p: PouId, sym: crate::intern::Symbol) -> Ty {
        match self.l.find_property(p, sym) {
            Some((Some(g), _)) => self.l.pou(g).ret,
            Some((None, Some(s))) => self.l.pou(s).vars.first().map_or(Ty::Error, |v| v.ty),
            _ => Ty::Error,
        }
    }

    /// `THIS^.x`, `SUPER^.x`: a variable of the class (any section) at the instance.
    pub(super) fn self_member_place(&mut self, r: SelfRef, name: ast::Ident) -> Option<Place> {
        let (SelfRef::This(c) | SelfRef::Super(c)) = r;
        let class = self.this_class?;
        let Some((d, vi)) = self.l.class_var(c, name.sym) else {
            let n = self.l.text(name.span).to_string();
            let cn = self.l.pou(c).display.clone();
            self.l.error(
                codes::E_NO_MEMBER,
                format!("function block `{cn}` has no variable named `{n}`"),
                name.span,
            );
            return None;
        };
        let v = self.l.pou(d).vars[vi].clone();
        match self.class_field(d, vi, class, &v, name.span) {
            Named::Place(p) => Some(p),
            _ => None,
        }
    }

    /// The method a call's callee names, with the instance it runs on and whether the
    /// call is bound statically (`SUPER^.M()`): `M()` inside a class, `inst.M()`,
    /// `THIS^.M()`, `SUPER^.M()`, `ref^.M()`.
    pub(super) fn method_callee<'e>(
        &mut self,
        callee: &'e Expr,
    ) -> Option<(Expr2<'e>, PouId, bool)> {
        match &callee.kind {
            ExprKind::Name(id) => {
                if self.l.pou(self.pou).var(id.sym).is_some() {
                    return None;
                }
                let class = self.lexical_class()?;
                let m = self.l.find_method(class, id.sym)?;
                Some((Expr2::This(class), m, false))
            }
            ExprKind::Member(base, name) => {
                if let Some(r) = self.self_ref(base) {
                    let (SelfRef::This(c) | SelfRef::Super(c)) = r;
                    let m = self.l.find_method(c, name.sym)?;
                    return Some((Expr2::This(c), m, matches!(r, SelfRef::Super(_))));
                }
                if let Some(q) = self.qualifier(base) {
                    // CODESYS: `Prog.M()`, a METHOD of a PROGRAM's running instance.
                    let super::qualified::Qualifier::Program(p) = q else {
                        return None;
                    };
                    let m = self.l.find_method(p, name.sym)?;
                    return Some((Expr2::Program(p, base), m, false));
                }
                match self.infer(base) {
                    Ty::Fb(p) => {
                        let m = self.l.find_method(p, name.sym)?;
                        Some((Expr2::Place(base), m, false))
                    }
                    Ty::Ref(r) => {
                        let t = self.l.types.get_ref(r);
                        if let Some(k) = t.iface {
                            let m = self.l.iface_method(k, name.sym)?;
                            return Some((Expr2::Iface(base, k), m, false));
                        }
                        None
                    }
                    _ => None,
                }
            }
            _ => None,
        }
    }

    /// Calls method `m` on the instance `on`; its result, if it has one.
    pub(super) fn method_call(
        &mut self,
        on: Expr2<'s>,
        m: PouId,
        statically: bool,
        args: &'s [ast::Arg],
        span: Span,
    ) -> Option<Val> {
        let from = self.lexical_class();
        self.l.check_access(m, from, span);
        if statically && self.l.is_abstract_member(m) {
            let n = self.l.pou(m).display.clone();
            self.l.error(
                codes::E_ABSTRACT,
                format!("`{n}` is ABSTRACT: it has no body to call"),
                span,
            );
        }
        let (addr, guard, target) = self.receiver(on, m, statically, span)?;
        self.call_on(addr, guard, m, target, args, span)
    }

    /// The instance a member `m` is called on: its address, a guard when it may be
    /// missing (a NULL reference or interface, an element out of bounds), and the
    /// function to call (`m`'s own, or a dispatcher).
    pub(super) fn receiver(
        &mut self,
        on: Expr2<'s>,
        m: PouId,
        statically: bool,
        span: Span,
    ) -> Option<(Value, Option<Value>, FuncId)> {
        // The recursion check sees a call bound at run time as a call of every
        // method it may run.
        if !statically {
            let key = match on {
                Expr2::This(c) => Some(super::classes::DispatchKey::Class(c)),
                Expr2::Place(e) => match self.infer(e) {
                    Ty::Fb(c) => Some(super::classes::DispatchKey::Class(c)),
                    _ => None,
                },
                Expr2::Iface(_, k) => Some(super::classes::DispatchKey::Iface(k)),
                Expr2::Program(p, _) => Some(super::classes::DispatchKey::Class(p)),
            };
            if let Some(key) = key {
                for i in self.l.dispatch_callees(key, m) {
                    self.l
                        .calls
                        .push((self.caller, super::CallNode::Pou(i), span));
                }
            }
        }
        Some(match on {
            Expr2::This(c) => {
                let me = self.self_ptr?;
                let f = if statically {
                    self.l.ir[m.0 as usize].body?
                } else {
                    self.l
                        .method_target(super::classes::DispatchKey::Class(c), m)?
                };
                (me, None, f)
            }
            Expr2::Place(e) => {
                let p = self.place(e)?;
                let Ty::Fb(c) = p.ty else { return None };
                let f = self
                    .l
                    .method_target(super::classes::DispatchKey::Class(c), m)?;
                (p.addr, p.guard, f)
            }
            Expr2::Program(p, base) => {
                let inst = if self.this_class == Some(p) {
                    self.self_ptr.map(|me| Place::new(me, Ty::Fb(p)))
                } else {
                    let what = self.l.text(base.span).to_string();
                    self.program_place(p, base, &what)
                }?;
                let f = self
                    .l
                    .method_target(super::classes::DispatchKey::Class(p), m)?;
                (inst.addr, None, f)
            }
            Expr2::Iface(e, k) => {
                let v = self.emit(e, None);
                let null = self.b.iconst(Type::Ptr, 0);
                let ok = self.b.icmp(plcc_ir::IntCC::Ne, v.v, null);
                let f = self
                    .l
                    .method_target(super::classes::DispatchKey::Iface(k), m)?;
                (v.v, Some(ok), f)
            }
        })
    }

    /// A call of `target` (method `m`'s function or dispatcher) on the instance at
    /// `addr`, skipped with the fault flag raised when `guard` is false.
    pub(super) fn call_on(
        &mut self,
        addr: Value,
        guard: Option<Value>,
        m: PouId,
        target: FuncId,
        args: &'s [ast::Arg],
        span: Span,
    ) -> Option<Val> {
        let Some(g) = guard else {
            return self.func_call_with(m, args, span, Some((addr, target)));
        };
        let ret = self.l.pou(m).ret;
        let result = match ret {
            Ty::Void => None,
            t => Some(self.scratch(t)),
        };
        let call = self.b.create_block();
        let bad = self.b.create_block();
        let join = self.b.create_block();
        self.b.brif(g, call, vec![], bad, vec![]);
        self.b.switch_to(bad);
        self.b.intrinsic(plcc_ir::Intrinsic::RaiseFault, vec![]);
        self.b.jump(join, vec![]);
        self.b.switch_to(call);
        let v = self.func_call_with(m, args, span, Some((addr, target)));
        if let (Some(v), Some(slot)) = (v, result) {
            if ret.is_aggregate() {
                self.copy_value(slot, v.v, ret);
            } else {
                self.b.store(v.v, slot);
            }
        }
        self.b.jump(join, vec![]);
        self.b.switch_to(join);
        result.map(|slot| {
            if ret.is_aggregate() || matches!(ret, Ty::Str(_)) {
                Val { v: slot, ty: ret }
            } else {
                let v = self.b.load(ret.ir().unwrap_or(Type::I32), slot);
                Val { v, ty: ret }
            }
        })
    }

    /// A temporary of type `ty` holding its initial value (what a skipped call gives).
    fn scratch(&mut self, ty: Ty) -> Value {
        let mt = self
            .l
            .mem_type(ty)
            .map(|m| m.0)
            .unwrap_or(plcc_ir::MemType::Scalar(Type::I64));
        let s = self.b.slot("skipped", mt);
        let a = self.b.slot_addr(s);
        self.init_var(a, ty, None, None);
        a
    }

    /// `SUPER^()`: the base's body run on this instance.
    pub(super) fn super_body_call(&mut self, span: Span) -> bool {
        let (Some(class), Some(lex), Some(me)) =
            (self.this_class, self.lexical_class(), self.self_ptr)
        else {
            return false;
        };
        let Some(base) = self.l.pou(lex).base else {
            return false;
        };
        if let Some(f) = self.l.body_copy(class, base) {
            self.l
                .calls
                .push((self.caller, super::CallNode::Pou(base), span));
            self.b.call(f, None, vec![me]);
        }
        true
    }
}

/// What a method is called on.
#[derive(Copy, Clone)]
pub(super) enum Expr2<'e> {
    /// `THIS^` (or `SUPER^`, or no prefix inside a class), of the given class.
    This(PouId),
    /// An instance, by the expression naming it.
    Place(&'e Expr),
    /// A value of an interface type, by its expression.
    Iface(&'e Expr, usize),
    /// The running instance of a PROGRAM (CODESYS `Prog.M()`), by its qualifier.
    Program(PouId, &'e Expr),
}
