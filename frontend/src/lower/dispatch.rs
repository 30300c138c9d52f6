//! Run-time binding: a call of a method that a derived class overrides, or a call
//! through an interface, runs the method of the instance's actual class. Every class
//! instance holds its class id in its first field (`__class`, set by its init
//! function); such a call goes to a dispatch function of the method's signature that
//! loads the id and calls the class's method. An id no class of the family has (an
//! uninitialised instance) raises the fault flag and gives the result type's zero.
//!
//! The dispatch function is the one place that chooses: a `call_table` on the id,
//! through a function table with an entry per class id (the IR's run-time bound
//! calls).
//!
//! Also here: the checks of a class's members against its bases and interfaces
//! (overriding, ABSTRACT, FINAL), and the bodies of bases run on derived instances.

use super::body::BodyCx;
use super::classes::DispatchKey;
use super::{Lowerer, MemberRef};
use crate::ast::{PouKind, VarKind};
use crate::codes;
use crate::types::{PouId, Ty};
use plcc_ir::diag::Diagnostic;
use plcc_ir::{FuncId, FuncKind, Function, Type};

/// The IR type of a class id.
pub(crate) const CLASS_ID: Type = Type::I16;

impl<'s> Lowerer<'s> {
    /// The implementation of member `m` (a method or accessor, by its name and kind)
    /// in class `d`, if `d` has a concrete one.
    fn member_in(&self, d: PouId, m: PouId) -> Option<PouId> {
        let sym = self.pou(m).name.sym;
        let found = match self.pou(m).member? {
            MemberRef::Method(_) => self.find_method(d, sym),
            MemberRef::Get(_) => self.find_property(d, sym).and_then(|p| p.0),
            MemberRef::Set(_) => self.find_property(d, sym).and_then(|p| p.1),
        }?;
        (!self.is_abstract_member(found) && self.pou(found).owner.is_some()).then_some(found)
    }

    /// The classes a dispatch on `key` chooses among.
    fn family(&self, key: DispatchKey) -> Vec<PouId> {
        let mut v: Vec<PouId> = self.classes.class_id.keys().copied().collect();
        v.sort_by_key(|p| self.classes.class_id[p]);
        v.retain(|&d| {
            self.used[d.0 as usize]
                && match key {
                    DispatchKey::Class(c) => self.derives_from(d, c),
                    DispatchKey::Iface(k) => self.implements(d, k),
                }
        });
        v
    }

    /// The members a call of `m` on an instance seen as `key` may run.
    pub(crate) fn dispatch_callees(&self, key: DispatchKey, m: PouId) -> Vec<PouId> {
        let mut v: Vec<PouId> = self
            .family(key)
            .into_iter()
            .filter_map(|d| self.member_in(d, m))
            .collect();
        v.sort();
        v.dedup();
        v
    }

    /// The function a call of member `m` runs on an instance seen as `key`: the
    /// method itself when no class of the family overrides it, else a dispatch
    /// function.
    pub(crate) fn method_target(&mut self, key: DispatchKey, m: PouId) -> Option<FuncId> {
        let family = self.family(key);
        let impls: Vec<(u32, Option<PouId>)> = family
            .iter()
            .map(|&d| (self.classes.class_id[&d], self.member_in(d, m)))
            .collect();
        if let DispatchKey::Class(_) = key {
            if impls.iter().all(|&(_, i)| i == Some(m)) {
                return self.ir[m.0 as usize].body;
            }
        }
        let kind = match self.pou(m).member? {
            MemberRef::Method(_) => 0u8,
            MemberRef::Get(_) => 1,
            MemberRef::Set(_) => 2,
        };
        let cache = (key, self.pou(m).name.sym, kind);
        if let Some(&f) = self.classes.dispatchers.get(&cache) {
            return Some(f);
        }
        let (params, ret) = self.member_signature(m);
        let what = match key {
            DispatchKey::Class(c) => self.pou(c).display.clone(),
            DispatchKey::Iface(k) => self.classes.ifaces[k].display.clone(),
        };
        let name = format!(
            "{what}.{}$dispatch",
            self.pou(m).display.rsplit('.').next().unwrap_or("")
        );
        let mut f = Function::new(name, FuncKind::Helper, params.clone(), ret);
        f.span = Some(self.pou(m).name.span);
        let fid = self.module.add_func(f);
        self.classes.dispatchers.insert(cache, fid);
        let has_class = family.iter().any(|&d| self.ir[d.0 as usize].agg.is_some());
        // The table: an entry per class id, the class's method where the family has
        // it (an id outside the family, 0 for an instance never initialised, has
        // none: the call raises the fault flag and gives 0).
        let len = impls
            .iter()
            .map(|&(id, _)| id as usize + 1)
            .max()
            .unwrap_or(0);
        let mut entries = vec![None; len];
        for &(id, i) in &impls {
            entries[id as usize] = i.and_then(|i| self.ir[i.0 as usize].body);
        }
        let table = self.module.add_table(plcc_ir::Table {
            name: self.module.funcs[fid.index()].name.clone(),
            params: params.clone(),
            result: ret,
            entries,
        });
        self.with_function(fid, |_, func| {
            let mut b = plcc_ir::FuncBuilder::new(func);
            let args = b.params();
            let r = if has_class {
                // The class id is the first field of every class, at the
                // instance's own address: loaded as such, not as a field of some
                // class's struct (the instance may be of any class of the family).
                let id = b.load(CLASS_ID, args[0]);
                b.call_table(table, ret, id, args)
            } else {
                // No class of the family exists: every call is a fault.
                b.intrinsic(plcc_ir::Intrinsic::RaiseFault, vec![]);
                ret.map(|t| {
                    if t.is_float() {
                        b.fconst(t, 0.0)
                    } else {
                        b.iconst(t, 0)
                    }
                })
            };
            b.ret(r);
        });
        Some(fid)
    }

    /// The IR parameters and result of a member's function (the instance address
    /// first), made from its declaration (an interface's members have no function).
    fn member_signature(&mut self, m: PouId) -> (Vec<Type>, Option<Type>) {
        if let Some(f) = self.ir[m.0 as usize].body {
            let f = &self.module.funcs[f.index()];
            return (f.params.clone(), f.ret);
        }
        let mut params = vec![Type::Ptr];
        for v in &self.pou(m).vars {
            params.push(match v.section {
                VarKind::Input if v.ty.is_aggregate() => Type::Ptr,
                VarKind::Input => v.ty.ir().unwrap_or(Type::I32),
                VarKind::InOut | VarKind::Output => Type::Ptr,
                _ => continue,
            });
        }
        let ret = self.pou(m).ret;
        if ret.is_aggregate() {
            params.push(Type::Ptr);
            (params, None)
        } else {
            (params, ret.ir())
        }
    }

    /// The function running the body of `base` (or of its nearest ancestor with a
    /// body) on an instance of `class`; `None` when no ancestor has a body.
    pub(crate) fn body_copy(&mut self, class: PouId, base: PouId) -> Option<FuncId> {
        // In CODESYS the base's own body, even empty, is the one `SUPER^()` runs.
        let owner = if self.codesys {
            Some(base).filter(|&b| !self.pou_ast(b).body.stmts.is_empty())?
        } else {
            self.body_owner(base)?
        };
        if let Some(&f) = self.classes.body_copies.get(&(class, owner)) {
            return Some(f);
        }
        let name = format!(
            "{}$SUPER.{}",
            self.pou(class).display,
            self.pou(owner).display
        );
        let mut f = Function::new(name, FuncKind::FbBody, vec![Type::Ptr], None);
        f.span = Some(self.pou(owner).name.span);
        let fid = self.module.add_func(f);
        self.classes.body_copies.insert((class, owner), fid);
        self.classes.pending_copies.push((class, owner, fid));
        Some(fid)
    }

    /// The nearest of `p` and its bases that has a body.
    pub(crate) fn body_owner(&self, p: PouId) -> Option<PouId> {
        self.lineage(p)
            .into_iter()
            .find(|&c| !self.pou_ast(c).body.stmts.is_empty())
    }

    /// Lowers the bases' bodies that `SUPER^()` runs on derived instances.
    pub(super) fn lower_body_copies(&mut self) {
        while let Some((class, owner, fid)) = self.classes.pending_copies.pop() {
            self.with_function(fid, |l, func| {
                let mut cx = BodyCx::new(l, func, owner, false);
                cx.this_class = Some(class);
                let stmts = &cx.l.pou_ast(owner).body.stmts;
                cx.lower_body(stmts);
            });
        }
    }

    /// Checks every class against its bases and interfaces: overriding methods keep
    /// the signature and do not override FINAL ones; a concrete class implements
    /// every ABSTRACT method and every method of its interfaces; no variable is an
    /// instance of an ABSTRACT function block.
    pub(super) fn check_classes(&mut self) {
        let classes: Vec<PouId> = self.classes.class_id.keys().copied().collect();
        let mut classes = classes;
        classes.sort();
        for &c in &classes {
            let ast = self.pou_ast(c);
            let is_abstract = ast.oo.modifiers.abstract_.is_some();
            // Own methods against the bases'.
            let own: Vec<(crate::intern::Symbol, PouId)> = self
                .classes
                .methods
                .iter()
                .filter(|((o, _), _)| *o == c)
                .map(|((_, s), &m)| (*s, m))
                .collect();
            let props: Vec<(crate::intern::Symbol, PouId)> = self
                .classes
                .props
                .iter()
                .filter(|((o, _), _)| *o == c)
                .filter_map(|((_, s), &(g, st))| Some((*s, g.or(st)?)))
                .collect();
            // A variable may not hide one of a base (VAR_TEMPs excepted).
            if let Some(b) = self.pou(c).base {
                for v in self.pou(c).vars.clone() {
                    if v.section == VarKind::Temp {
                        continue;
                    }
                    let Some((d, vi)) = self.class_var(b, v.name.sym) else {
                        continue;
                    };
                    if self.pou(d).vars[vi].section == VarKind::Temp {
                        continue;
                    }
                    let dn = self.pou(d).display.clone();
                    let at = self.pou(d).vars[vi].name.span;
                    self.diags.push(
                        Diagnostic::error(
                            codes::E_DUPLICATE,
                            format!("`{}` is declared in the base `{dn}` too: a derived function block cannot declare a variable of its base again", v.display),
                            v.name.span,
                        )
                        .with_secondary(at, "declared here"),
                    );
                }
            }
            for &(sym, m) in own.iter().chain(props.iter()) {
                if let Some((d, vi)) = self.class_var(c, sym) {
                    let n = self.text(self.pou(m).name.span).to_string();
                    let cn = self.pou(c).display.clone();
                    let at = self.pou(d).vars[vi].name.span;
                    self.diags.push(
                        Diagnostic::error(
                            codes::E_DUPLICATE,
                            format!("`{n}` is declared twice in `{cn}`: a variable and a method or property (names ignore case)"),
                            self.pou(m).name.span,
                        )
                        .with_secondary(at, "the variable"),
                    );
                }
            }
            for (sym, m) in own {
                let span = self.pou(m).name.span;
                if self.is_abstract_member(m) && !is_abstract {
                    let n = self.pou(m).display.clone();
                    self.error(
                        codes::E_ABSTRACT,
                        format!("`{n}` is ABSTRACT, so its FUNCTION_BLOCK must be ABSTRACT too"),
                        span,
                    );
                }
                let over = self.pou(c).base.and_then(|b| self.find_method(b, sym));
                let Some(over) = over else {
                    if let Some(o) = self.member_modifiers(m).and_then(|x| x.override_) {
                        let n = self.pou(m).display.clone();
                        self.error(
                            codes::E_OO_DECLARATION,
                            format!("`{n}` is OVERRIDE, but no base of its FUNCTION_BLOCK has a method of that name"),
                            o,
                        );
                    }
                    continue;
                };
                if let Some(f) = self.member_modifiers(over).and_then(|x| x.final_) {
                    let n = self.pou(over).display.clone();
                    self.diags.push(
                        Diagnostic::error(
                            codes::E_FINAL,
                            format!("`{n}` is FINAL: it cannot be overridden"),
                            span,
                        )
                        .with_secondary(f, "declared FINAL here"),
                    );
                }
                self.check_same_signature(m, over);
            }
            if is_abstract {
                continue;
            }
            // Abstract methods left unimplemented.
            let mut names: Vec<crate::intern::Symbol> = Vec::new();
            for a in self.lineage(c) {
                for (&(o, s), _) in self.classes.methods.iter() {
                    if o == a && !names.contains(&s) {
                        names.push(s);
                    }
                }
            }
            for s in names {
                if let Some(m) = self.find_method(c, s) {
                    if self.is_abstract_member(m) && self.pou(m).owner != Some(c) {
                        let n = self.pou(m).display.clone();
                        let cn = self.pou(c).display.clone();
                        let span = self.pou(c).name.span;
                        self.error(
                            codes::E_ABSTRACT,
                            format!("`{cn}` does not implement the ABSTRACT method `{n}`: implement it, or declare `{cn}` ABSTRACT"),
                            span,
                        );
                    }
                }
            }
            // Interface members.
            let mut ifs: Vec<usize> = Vec::new();
            for a in self.lineage(c) {
                for &k in self.classes.implements.get(&a).into_iter().flatten() {
                    for j in self.iface_closure(k) {
                        if !ifs.contains(&j) {
                            ifs.push(j);
                        }
                    }
                }
            }
            for k in ifs {
                let itf = self.classes.ifaces[k].clone();
                let mut ms: Vec<_> = itf.methods.iter().map(|(&s, &m)| (s, m)).collect();
                ms.sort_by_key(|x| x.1);
                for (s, im) in ms {
                    match self.find_method(c, s) {
                        Some(m) => self.check_same_signature(m, im),
                        None => {
                            let cn = self.pou(c).display.clone();
                            let n = self.pou(im).display.clone();
                            let span = self.pou(c).name.span;
                            self.diags.push(
                                Diagnostic::error(
                                    codes::E_ABSTRACT,
                                    format!("`{cn}` does not implement the method `{n}` of its interface"),
                                    span,
                                )
                                .with_secondary(self.pou(im).name.span, "declared here"),
                            );
                        }
                    }
                }
                let mut ps: Vec<_> = itf.props.iter().map(|(&s, &p)| (s, p)).collect();
                ps.sort_by_key(|x| (x.1 .0, x.1 .1));
                for (s, (g, st)) in ps {
                    let have = self.find_property(c, s).unwrap_or((None, None));
                    for (want, got, what) in [(g, have.0, "GET"), (st, have.1, "SET")] {
                        let Some(w) = want else { continue };
                        if got.is_none() {
                            let cn = self.pou(c).display.clone();
                            let n = self.text(self.pou(w).name.span).to_string();
                            let span = self.pou(c).name.span;
                            self.diags.push(
                                Diagnostic::error(
                                    codes::E_ABSTRACT,
                                    format!("`{cn}` does not implement {what} of the property `{n}` of its interface"),
                                    span,
                                )
                                .with_secondary(self.pou(w).name.span, "declared here"),
                            );
                        }
                    }
                }
            }
        }
        // Instances of abstract function blocks.
        for i in 0..self.pous.len() {
            if !self.used[i] || self.pous[i].std {
                continue;
            }
            let vars = self.pous[i].vars.clone();
            for v in vars {
                if matches!(v.section, VarKind::InOut | VarKind::External) {
                    continue;
                }
                let mut fbs = Vec::new();
                self.fbs_in(v.ty, &mut fbs);
                for fb in fbs {
                    if self.pou(fb).kind != PouKind::FunctionBlock || self.pou(fb).std {
                        continue;
                    }
                    if let Some(a) = self.pou_ast(fb).oo.modifiers.abstract_ {
                        let n = self.pou(fb).display.clone();
                        self.diags.push(
                            Diagnostic::error(
                                codes::E_ABSTRACT,
                                format!("`{n}` is ABSTRACT: it cannot have instances, only FUNCTION_BLOCKs that extend it"),
                                v.name.span,
                            )
                            .with_secondary(a, "declared ABSTRACT here"),
                        );
                    }
                }
            }
        }
    }

    /// A method overriding (or implementing) `over` keeps its signature: the result
    /// type and the parameters, in order, with their sections and types.
    fn check_same_signature(&mut self, m: PouId, over: PouId) {
        let sig = |l: &Lowerer<'s>, p: PouId| -> (Ty, Vec<(VarKind, Ty)>) {
            let info = l.pou(p);
            (
                info.ret,
                info.vars
                    .iter()
                    .filter(|v| {
                        matches!(v.section, VarKind::Input | VarKind::Output | VarKind::InOut)
                    })
                    .map(|v| (v.section, v.ty))
                    .collect(),
            )
        };
        if sig(self, m) != sig(self, over) {
            let n = self.pou(m).display.clone();
            let o = self.pou(over).display.clone();
            let span = self.pou(m).name.span;
            self.diags.push(
                Diagnostic::error(
                    codes::E_OO_DECLARATION,
                    format!("`{n}` must have the signature of `{o}`, which it overrides or implements: the same result type and the same inputs, outputs and in-outs, in order"),
                    span,
                )
                .with_secondary(self.pou(over).name.span, "declared here"),
            );
        }
    }
}
