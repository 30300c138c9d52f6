//! PROPERTYs: read and written like variables (`x := inst.P;`, `inst.P := 3;`, `P`
//! inside the class, `THIS^.P`, `itf.P` through an interface), each access a call of
//! the getter or the setter, bound at run time as methods are.

use super::body::BodyCx;
use super::expr::Val;
use super::methods::{Expr2, SelfRef};
use crate::ast::{Expr, ExprKind};
use crate::codes;
use crate::intern::Symbol;
use crate::types::{PouId, Ty};
use plcc_ir::diag::Span;

/// A property access: what it is on, and its getter and setter.
pub(super) struct PropAccess<'e> {
    on: Expr2<'e>,
    /// Bound statically (`SUPER^.P`).
    statically: bool,
    get: Option<PouId>,
    set: Option<PouId>,
    name: Symbol,
}

impl<'s> BodyCx<'_, 's> {
    /// The property `e` names, if it names one: `inst.P`, `THIS^.P`, `SUPER^.P`,
    /// `itf.P`, or `P` inside the class (where no variable has the name).
    pub(super) fn property_of<'e>(&mut self, e: &'e Expr) -> Option<PropAccess<'e>> {
        match &e.kind {
            ExprKind::Name(id) => {
                if self.l.pou(self.pou).var(id.sym).is_some()
                    || self.temps.contains_key(&id.sym)
                    || self.class_name_type(id.sym).is_some()
                {
                    return None;
                }
                // Inside an accessor, its own name is its value.
                if self.l.pou(self.pou).name.sym == id.sym && self.l.pou(self.pou).member.is_some()
                {
                    return None;
                }
                let class = self.lexical_class()?;
                let (get, set) = self.l.find_property(class, id.sym)?;
                Some(PropAccess {
                    on: Expr2::This(class),
                    statically: false,
                    get,
                    set,
                    name: id.sym,
                })
            }
            ExprKind::Member(base, name) => {
                if let Some(r) = self.self_ref(base) {
                    let (SelfRef::This(c) | SelfRef::Super(c)) = r;
                    let (get, set) = self.l.find_property(c, name.sym)?;
                    return Some(PropAccess {
                        on: Expr2::This(c),
                        statically: matches!(r, SelfRef::Super(_)),
                        get,
                        set,
                        name: name.sym,
                    });
                }
                if self.qualifier(base).is_some() {
                    return None;
                }
                match self.infer(base) {
                    Ty::Fb(p) => {
                        if self.l.class_var(p, name.sym).is_some() {
                            return None;
                        }
                        let (get, set) = self.l.find_property(p, name.sym)?;
                        Some(PropAccess {
                            on: Expr2::Place(base),
                            statically: false,
                            get,
                            set,
                            name: name.sym,
                        })
                    }
                    Ty::Ref(r) => {
                        let k = self.l.types.get_ref(r).iface?;
                        let (get, set) = self.l.iface_property(k, name.sym)?;
                        Some(PropAccess {
                            on: Expr2::Iface(base, k),
                            statically: false,
                            get,
                            set,
                            name: name.sym,
                        })
                    }
                    _ => None,
                }
            }
            _ => None,
        }
    }

    /// The type of the property `e` names, if it names one.
    pub(super) fn property_ty(&mut self, e: &Expr) -> Option<Ty> {
        let p = self.property_of(e)?;
        Some(match (p.get, p.set) {
            (Some(g), _) => self.l.pou(g).ret,
            (None, Some(s)) => self.l.pou(s).vars.first().map_or(Ty::Error, |v| v.ty),
            _ => Ty::Error,
        })
    }

    /// Reads a property: a call of its getter.
    pub(super) fn property_read(&mut self, p: PropAccess<'s>, span: Span) -> Val {
        let Some(get) = p.get else {
            let n = self.l.sym_name(p.name).to_string();
            self.l.error(
                codes::E_NOT_A_PLACE,
                format!("property `{n}` has no GET: it can only be written"),
                span,
            );
            return self.error_val();
        };
        let Some((addr, guard, target)) = self.receiver(p.on, get, p.statically, span) else {
            return self.error_val();
        };
        self.l.check_access(get, self.lexical_class(), span);
        match self.call_on(addr, guard, get, target, &[], span) {
            Some(v) => v,
            None => self.error_val(),
        }
    }

    /// Writes a property: a call of its setter with `value`.
    pub(super) fn property_write(&mut self, p: PropAccess<'s>, value: &'s Expr, span: Span) {
        let Some(set) = p.set else {
            let n = self.l.sym_name(p.name).to_string();
            self.l.error(
                codes::E_NOT_A_PLACE,
                format!("property `{n}` has no SET: it can only be read"),
                span,
            );
            let _ = self.emit(value, None);
            return;
        };
        self.l.check_access(set, self.lexical_class(), span);
        let Some((addr, guard, target)) = self.receiver(p.on, set, p.statically, span) else {
            return;
        };
        let Some(v) = self.l.pou(set).vars.first().cloned() else {
            return;
        };
        let arg = if v.ty.is_aggregate() {
            match self.agg_source(value, v.ty) {
                Some(a) => a,
                None => return,
            }
        } else {
            self.check_range(v.tag, value);
            self.emit_as(value, v.ty)
        };
        self.l
            .calls
            .push((self.caller, super::CallNode::Pou(set), span));
        let skip = guard.map(|g| {
            let call = self.b.create_block();
            let bad = self.b.create_block();
            let join = self.b.create_block();
            self.b.brif(g, call, vec![], bad, vec![]);
            self.b.switch_to(bad);
            self.b.intrinsic(plcc_ir::Intrinsic::RaiseFault, vec![]);
            self.b.jump(join, vec![]);
            self.b.switch_to(call);
            join
        });
        self.b.call(target, None, vec![addr, arg]);
        if let Some(join) = skip {
            self.b.jump(join, vec![]);
            self.b.switch_to(join);
        }
    }
}
