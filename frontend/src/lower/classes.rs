//! Classes (IEC 61131-3 ed. 3, 6.6.5-6.6.8, and CODESYS): FUNCTION_BLOCKs (and, in the
//! CODESYS dialect, PROGRAMs) with METHODs and PROPERTYs, EXTENDS, IMPLEMENTS, and
//! INTERFACEs.
//!
//! Every METHOD and property accessor becomes a POU of its own (kind FUNCTION, its
//! `owner` the FB), whose IR function takes the instance's address first. A derived
//! FB's instance struct begins with its base's fields, so a derived instance's address
//! is a valid base address. Every FB that takes part in object orientation (has
//! methods or properties, extends or is extended, implements an interface) carries a
//! hidden class id as its first field (`__class`), set by its init function; calls
//! that a derived FB may override dispatch on it (`dispatch`).

use super::{Lowerer, MemberRef, PouInfo, PouIr};
use crate::ast::{self, AccessSpec, PouKind};
use crate::codes;
use crate::intern::Symbol;
use crate::types::{PouId, Ty};
use plcc_ir::diag::{Diagnostic, Span};
use plcc_ir::FuncId;
use rustc_hash::{FxHashMap, FxHashSet};

/// An INTERFACE.
#[derive(Clone, Debug)]
pub(crate) struct Iface {
    /// Its name as declared.
    pub display: String,
    /// Where it is declared.
    pub name: ast::Ident,
    /// The interfaces it extends.
    pub extends: Vec<usize>,
    /// Its own methods (POUs without a body) by name.
    pub methods: FxHashMap<Symbol, PouId>,
    /// Its own properties: getter and setter prototypes.
    pub props: FxHashMap<Symbol, (Option<PouId>, Option<PouId>)>,
}

/// The object-oriented parts of a build.
#[derive(Clone, Default)]
pub(crate) struct Classes {
    /// Every INTERFACE.
    pub ifaces: Vec<Iface>,
    /// Interfaces by name.
    pub iface_by_name: FxHashMap<Symbol, usize>,
    /// The methods a class declares itself, by class and name.
    pub methods: FxHashMap<(PouId, Symbol), PouId>,
    /// The properties a class declares itself: getter and setter.
    pub props: FxHashMap<(PouId, Symbol), (Option<PouId>, Option<PouId>)>,
    /// The interfaces a class names in IMPLEMENTS.
    pub implements: FxHashMap<PouId, Vec<usize>>,
    /// The class id of every class that takes part in object orientation (from 1).
    pub class_id: FxHashMap<PouId, u32>,
    /// Dispatch functions made so far (see `dispatch`).
    pub dispatchers: FxHashMap<(DispatchKey, Symbol, u8), FuncId>,
    /// Functions running an ancestor's body on a derived instance (`SUPER^()`), by
    /// (class, ancestor).
    pub body_copies: FxHashMap<(PouId, PouId), FuncId>,
    /// Body copies still to lower: class, ancestor, function.
    pub pending_copies: Vec<(PouId, PouId, FuncId)>,
}

/// What a dispatch function chooses among: the classes derived from one, or those
/// implementing an interface.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
pub(crate) enum DispatchKey {
    /// A FUNCTION_BLOCK and every class derived from it.
    Class(PouId),
    /// Every class implementing an interface.
    Iface(usize),
}

impl<'s> Lowerer<'s> {
    /// After the POU table: a POU per METHOD and accessor, the INTERFACEs, EXTENDS
    /// and IMPLEMENTS resolved, class ids given.
    pub(super) fn collect_classes(&mut self) {
        let units = self.units;
        let n = self.pous.len();
        for i in 0..n {
            let owner = PouId(i as u32);
            if self.pous[i].std {
                continue;
            }
            let pou = self.pou_ast(owner);
            let oo = &pou.oo;
            if (!oo.methods.is_empty() || !oo.properties.is_empty())
                && (pou.kind == PouKind::Function
                    || (pou.kind == PouKind::Program && !self.codesys))
            {
                let span = oo
                    .methods
                    .first()
                    .map(|m| m.pou.name.span)
                    .or(oo.properties.first().map(|p| p.name.span))
                    .unwrap_or(pou.name.span);
                let mut d = Diagnostic::error(
                    codes::E_OO_DECLARATION,
                    if pou.kind == PouKind::Function {
                        "a FUNCTION has no METHODs or PROPERTYs (it keeps no state between calls)"
                    } else {
                        "a PROGRAM has METHODs or PROPERTYs only in the CODESYS dialect"
                    },
                    span,
                );
                if pou.kind == PouKind::Program {
                    d = d.with_note("`--dialect codesys` accepts them");
                }
                self.diags.push(d);
                continue;
            }
            for (k, m) in oo.methods.iter().enumerate() {
                if let Some(id) = self.add_member(owner, m.pou.name, MemberRef::Method(k as u32)) {
                    self.classes.methods.insert((owner, m.pou.name.sym), id);
                }
            }
            for (k, p) in oo.properties.iter().enumerate() {
                let get = p
                    .get
                    .as_ref()
                    .and_then(|_| self.add_member(owner, p.name, MemberRef::Get(k as u32)));
                let set = p
                    .set
                    .as_ref()
                    .and_then(|_| self.add_member(owner, p.name, MemberRef::Set(k as u32)));
                self.classes.props.insert((owner, p.name.sym), (get, set));
            }
        }
        // Interfaces.
        for (u, unit) in units.iter().enumerate() {
            for (it, item) in unit.items.iter().enumerate() {
                let ast::Item::Interface(itf) = item else {
                    continue;
                };
                if self.classes.iface_by_name.contains_key(&itf.name.sym)
                    || self.pou_by_name.contains_key(&itf.name.sym)
                {
                    let n = self.text(itf.name.span).to_string();
                    self.error(
                        codes::E_DUPLICATE,
                        format!("`{n}` is declared twice"),
                        itf.name.span,
                    );
                    continue;
                }
                let idx = self.classes.ifaces.len();
                let mut methods = FxHashMap::default();
                for (k, m) in itf.methods.iter().enumerate() {
                    let id =
                        self.push_member_pou(u, it, None, m.pou.name, MemberRef::Method(k as u32));
                    methods.insert(m.pou.name.sym, id);
                }
                let mut props = FxHashMap::default();
                for (k, p) in itf.properties.iter().enumerate() {
                    // Neither accessor written: both.
                    let both = p.get.is_none() && p.set.is_none();
                    let get = (p.get.is_some()).then(|| {
                        self.push_member_pou(u, it, None, p.name, MemberRef::Get(k as u32))
                    });
                    let set = (p.set.is_some()).then(|| {
                        self.push_member_pou(u, it, None, p.name, MemberRef::Set(k as u32))
                    });
                    if both {
                        let n = self.text(p.name.span).to_string();
                        self.error(
                            codes::E_OO_DECLARATION,
                            format!("property `{n}` of an INTERFACE names its accessors: `GET END_GET`, `SET END_SET`"),
                            p.name.span,
                        );
                    }
                    props.insert(p.name.sym, (get, set));
                }
                self.classes.ifaces.push(Iface {
                    display: self.text(itf.name.span).to_string(),
                    name: itf.name,
                    extends: Vec::new(),
                    methods,
                    props,
                });
                self.classes.iface_by_name.insert(itf.name.sym, idx);
            }
        }
        // Interfaces extending interfaces.
        let mut k = 0;
        for unit in units.iter() {
            for item in &unit.items {
                let ast::Item::Interface(itf) = item else {
                    continue;
                };
                if self.classes.iface_by_name.get(&itf.name.sym) != Some(&k) {
                    continue;
                }
                let mut ext = Vec::new();
                for e in &itf.extends {
                    match self.classes.iface_by_name.get(&e.sym) {
                        Some(&j) => ext.push(j),
                        None => {
                            let n = self.text(e.span).to_string();
                            self.error(
                                codes::E_OO_DECLARATION,
                                format!(
                                    "`{n}` is not an INTERFACE, so it cannot be extended by one"
                                ),
                                e.span,
                            );
                        }
                    }
                }
                self.classes.ifaces[k].extends = ext;
                k += 1;
            }
        }
        for k in 0..self.classes.ifaces.len() {
            let mut seen = FxHashSet::default();
            if self.iface_cycle(k, &mut seen, &mut Vec::new()) {
                let span = self.classes.ifaces[k].name.span;
                self.error(
                    codes::E_OO_DECLARATION,
                    "this INTERFACE extends itself, through the interfaces it extends",
                    span,
                );
                self.classes.ifaces[k].extends.clear();
            }
        }
        // EXTENDS and IMPLEMENTS.
        for i in 0..n {
            let id = PouId(i as u32);
            if self.pous[i].std {
                continue;
            }
            let pou = self.pou_ast(id);
            if let Some(b) = pou.extends {
                match self.pou_by_name.get(&b.sym) {
                    Some(&base)
                        if self.pou(base).kind == PouKind::FunctionBlock
                            && pou.kind == PouKind::FunctionBlock
                            && !self.pou(base).std =>
                    {
                        if let Some(f) = self.pou_ast(base).oo.modifiers.final_ {
                            let n = self.pou(base).display.clone();
                            self.diags.push(
                                Diagnostic::error(
                                    codes::E_FINAL,
                                    format!("`{n}` is FINAL: it cannot be extended"),
                                    b.span,
                                )
                                .with_secondary(f, "declared FINAL here"),
                            );
                        }
                        if pou.oo.class.is_some() && self.pou_ast(base).oo.class.is_none() {
                            let n = self.pou(base).display.clone();
                            self.error(
                                codes::E_OO_DECLARATION,
                                format!("a CLASS extends only a CLASS: `{n}` is a FUNCTION_BLOCK"),
                                b.span,
                            );
                        }
                        // Kept even when FINAL, so that its uses give no more errors.
                        self.pous_mut()[i].base = Some(base);
                    }
                    _ => {
                        let n = self.text(b.span).to_string();
                        let msg = if pou.kind != PouKind::FunctionBlock {
                            "only a FUNCTION_BLOCK can extend another".to_string()
                        } else if self
                            .pou_by_name
                            .get(&b.sym)
                            .is_some_and(|&p| self.pou(p).std)
                        {
                            format!(
                                "`{n}` is a standard function block: not supported yet as a base"
                            )
                        } else {
                            format!("`{n}` is not a FUNCTION_BLOCK, so it cannot be extended")
                        };
                        self.error(codes::E_OO_DECLARATION, msg, b.span);
                    }
                }
            }
            if let Some(kw) = pou.oo.class {
                self.check_class(pou, kw);
            }
            let mut list = Vec::new();
            for itf in &pou.oo.implements {
                match self.classes.iface_by_name.get(&itf.sym) {
                    Some(&k) if pou.kind != PouKind::Function => list.push(k),
                    _ => {
                        let n = self.text(itf.span).to_string();
                        self.error(
                            codes::E_OO_DECLARATION,
                            format!("`{n}` is not an INTERFACE this POU can implement"),
                            itf.span,
                        );
                    }
                }
            }
            if !list.is_empty() {
                self.classes.implements.insert(id, list);
            }
        }
        // Circles.
        for i in 0..n {
            let mut seen = vec![PouId(i as u32)];
            let mut cur = self.pous[i].base;
            while let Some(c) = cur {
                if seen.contains(&c) {
                    let span = self.pous[i].name.span;
                    self.error(
                        codes::E_OO_DECLARATION,
                        "this FUNCTION_BLOCK extends itself, through its bases",
                        span,
                    );
                    self.pous_mut()[i].base = None;
                    break;
                }
                seen.push(c);
                cur = self.pous[c.0 as usize].base;
            }
        }
        // Class ids.
        let mut extended = FxHashSet::default();
        for p in self.pous.iter() {
            if let Some(b) = p.base {
                extended.insert(b);
            }
        }
        let mut next = 1u32;
        for i in 0..n {
            let id = PouId(i as u32);
            let p = &self.pous[i];
            if p.std || p.kind == PouKind::Function {
                continue;
            }
            let ast = self.pou_ast(id);
            let oo = p.base.is_some()
                || extended.contains(&id)
                || !ast.oo.methods.is_empty()
                || !ast.oo.properties.is_empty()
                || self.classes.implements.contains_key(&id);
            if oo {
                self.classes.class_id.insert(id, next);
                next += 1;
            }
        }
    }

    /// What a CLASS may not have (IEC 61131-3 ed. 3, 6.6.5): a body, inputs, outputs,
    /// in-outs or temporaries.
    fn check_class(&mut self, pou: &ast::Pou, kw: Span) {
        use ast::VarKind;
        let n = self.text(pou.name.span).to_string();
        for b in &pou.var_blocks {
            if !matches!(
                b.kind,
                VarKind::Input | VarKind::Output | VarKind::InOut | VarKind::Temp
            ) {
                continue;
            }
            let what = b.kind.keyword();
            self.diags.push(
                Diagnostic::error(
                    codes::E_OO_DECLARATION,
                    format!("a CLASS has no {what}: `{n}` is not called, only its METHODs are"),
                    b.span,
                )
                .with_secondary(kw, "declared a CLASS here")
                .with_note("declare the parameters in the METHODs, or make it a FUNCTION_BLOCK"),
            );
        }
        if !pou.body.stmts.is_empty() || pou.sfc.is_some() {
            self.diags.push(
                Diagnostic::error(
                    codes::E_OO_DECLARATION,
                    format!("a CLASS has no body: `{n}` is not called, only its METHODs are"),
                    pou.sfc.as_ref().map_or(pou.body.span, |c| c.span),
                )
                .with_secondary(kw, "declared a CLASS here")
                .with_note("move the statements into a METHOD, or make it a FUNCTION_BLOCK"),
            );
        }
    }

    fn iface_cycle(&self, k: usize, seen: &mut FxHashSet<usize>, path: &mut Vec<usize>) -> bool {
        if path.contains(&k) {
            return true;
        }
        if !seen.insert(k) {
            return false;
        }
        path.push(k);
        let ext = self.classes.ifaces[k].extends.clone();
        let r = ext.into_iter().any(|j| self.iface_cycle(j, seen, path));
        path.pop();
        r
    }

    /// A POU for a member of a class; `None` if the name is taken.
    fn add_member(&mut self, owner: PouId, name: ast::Ident, m: MemberRef) -> Option<PouId> {
        let info = &self.pous[owner.0 as usize];
        let (unit, item) = (info.unit as usize, info.item as usize);
        let taken = match m {
            MemberRef::Method(_) => {
                self.classes.methods.contains_key(&(owner, name.sym))
                    || self.classes.props.contains_key(&(owner, name.sym))
            }
            _ => {
                self.classes.methods.contains_key(&(owner, name.sym))
                    || (matches!(m, MemberRef::Get(_))
                        && self.classes.props.contains_key(&(owner, name.sym)))
            }
        };
        if taken {
            let n = self.text(name.span).to_string();
            let o = self.pou(owner).display.clone();
            self.error(
                codes::E_DUPLICATE,
                format!("`{n}` is declared twice in `{o}`"),
                name.span,
            );
            return None;
        }
        Some(self.push_member_pou(unit, item, Some(owner), name, m))
    }

    fn push_member_pou(
        &mut self,
        unit: usize,
        item: usize,
        owner: Option<PouId>,
        name: ast::Ident,
        m: MemberRef,
    ) -> PouId {
        let id = PouId(self.pous.len() as u32);
        let prefix = match owner {
            Some(o) => self.pou(o).display.clone(),
            None => match &self.units[unit].items[item] {
                ast::Item::Interface(i) => self.text(i.name.span).to_string(),
                _ => String::new(),
            },
        };
        let suffix = match m {
            MemberRef::Method(_) => "",
            MemberRef::Get(_) => ".get",
            MemberRef::Set(_) => ".set",
        };
        let display = format!("{prefix}.{}{suffix}", self.text(name.span));
        self.pous_mut().push(PouInfo {
            name,
            display,
            kind: PouKind::Function,
            unit: unit as u32,
            item: item as u32,
            vars: Vec::new(),
            lookup: FxHashMap::default(),
            ret: Ty::Void,
            ret_tag: None,
            std: false,
            owner,
            member: Some(m),
            base: None,
        });
        self.ir.push(PouIr::default());
        self.used.push(false);
        id
    }

    /// True for a class that carries a class id.
    pub(crate) fn is_class(&self, p: PouId) -> bool {
        self.classes.class_id.contains_key(&p)
    }

    /// `p` and its bases, nearest first.
    pub(crate) fn lineage(&self, p: PouId) -> Vec<PouId> {
        let mut v = vec![p];
        let mut cur = self.pou(p).base;
        while let Some(c) = cur {
            v.push(c);
            cur = self.pou(c).base;
        }
        v
    }

    /// True if `d` is `b` or derived from it.
    pub(crate) fn derives_from(&self, d: PouId, b: PouId) -> bool {
        self.lineage(d).contains(&b)
    }

    /// A variable of class `p` or of one of its bases: the declaring class and index.
    pub(crate) fn class_var(&self, p: PouId, sym: Symbol) -> Option<(PouId, usize)> {
        self.lineage(p)
            .into_iter()
            .find_map(|c| self.pou(c).var(sym).map(|v| (c, v as usize)))
    }

    /// The method `sym` of class `p`, its own or inherited (the nearest).
    pub(crate) fn find_method(&self, p: PouId, sym: Symbol) -> Option<PouId> {
        self.lineage(p)
            .into_iter()
            .find_map(|c| self.classes.methods.get(&(c, sym)).copied())
    }

    /// The property `sym` of class `p`: getter and setter, each the nearest.
    pub(crate) fn find_property(
        &self,
        p: PouId,
        sym: Symbol,
    ) -> Option<(Option<PouId>, Option<PouId>)> {
        let mut found = None;
        let mut get = None;
        let mut set = None;
        for c in self.lineage(p) {
            if let Some(&(g, s)) = self.classes.props.get(&(c, sym)) {
                found = Some(());
                get = get.or(g);
                set = set.or(s);
            }
        }
        found.map(|_| (get, set))
    }

    /// Every interface `k` is or extends.
    pub(crate) fn iface_closure(&self, k: usize) -> Vec<usize> {
        let mut out = vec![k];
        let mut i = 0;
        while i < out.len() {
            for &j in &self.classes.ifaces[out[i]].extends {
                if !out.contains(&j) {
                    out.push(j);
                }
            }
            i += 1;
        }
        out
    }

    /// The method `sym` of interface `k` or of one it extends.
    pub(crate) fn iface_method(&self, k: usize, sym: Symbol) -> Option<PouId> {
        self.iface_closure(k)
            .into_iter()
            .find_map(|j| self.classes.ifaces[j].methods.get(&sym).copied())
    }

    /// The property `sym` of interface `k` or of one it extends.
    pub(crate) fn iface_property(
        &self,
        k: usize,
        sym: Symbol,
    ) -> Option<(Option<PouId>, Option<PouId>)> {
        self.iface_closure(k)
            .into_iter()
            .find_map(|j| self.classes.ifaces[j].props.get(&sym).copied())
    }

    /// True if class `p` (or a base of it) implements interface `k` (or one that
    /// extends it).
    pub(crate) fn implements(&self, p: PouId, k: usize) -> bool {
        self.lineage(p).into_iter().any(|c| {
            self.classes
                .implements
                .get(&c)
                .is_some_and(|l| l.iter().any(|&i| self.iface_closure(i).contains(&k)))
        })
    }

    /// The access specifier of the VAR block of variable `vi` of POU `c`.
    pub(crate) fn var_access(&self, c: PouId, vi: usize) -> Option<(AccessSpec, Span)> {
        if self.pou(c).member.is_some() {
            return None;
        }
        let block = self.pou(c).vars[vi].decl.0;
        self.pou_ast(c)
            .oo
            .var_access
            .iter()
            .find(|(b, _, _)| *b == block)
            .map(|&(_, a, s)| (a, s))
    }

    /// The modifiers of a member POU.
    pub(crate) fn member_modifiers(&self, m: PouId) -> Option<&'s ast::Modifiers> {
        let p = self.pou(m);
        let item = &self.units[p.unit as usize].items[p.item as usize];
        let (methods, props) = match item {
            ast::Item::Pou(pou) => (&pou.oo.methods, &pou.oo.properties),
            ast::Item::Interface(i) => (&i.methods, &i.properties),
            _ => return None,
        };
        Some(match p.member? {
            MemberRef::Method(i) => &methods[i as usize].modifiers,
            MemberRef::Get(i) | MemberRef::Set(i) => &props[i as usize].modifiers,
        })
    }

    /// True if an ABSTRACT method.
    pub(crate) fn is_abstract_member(&self, m: PouId) -> bool {
        self.member_modifiers(m)
            .is_some_and(|x| x.abstract_.is_some())
    }

    /// Checks that the member `m` (a method, getter or setter of class `owner`) may be
    /// used from the current POU, whose class (if any) is `from`.
    pub(crate) fn check_access(&mut self, m: PouId, from: Option<PouId>, span: Span) {
        let Some(owner) = self.pou(m).owner else {
            return;
        };
        let Some(access) = self.member_modifiers(m).and_then(|x| x.access) else {
            return;
        };
        let ok = match access.0 {
            AccessSpec::Public | AccessSpec::Internal => true,
            AccessSpec::Private => from == Some(owner),
            AccessSpec::Protected => from.is_some_and(|f| self.derives_from(f, owner)),
        };
        if !ok {
            let n = self.pou(m).display.clone();
            let what = if access.0 == AccessSpec::Private {
                "PRIVATE: only its own FUNCTION_BLOCK can use it"
            } else {
                "PROTECTED: only its own FUNCTION_BLOCK and those derived from it can use it"
            };
            self.diags.push(
                Diagnostic::error(codes::E_ACCESS, format!("`{n}` is {what}"), span)
                    .with_secondary(access.1, "declared here"),
            );
        }
    }

    /// The own methods of class `c`, in declaration order.
    pub(crate) fn own_methods(&self, c: PouId) -> Vec<PouId> {
        let mut v: Vec<PouId> = self
            .classes
            .methods
            .iter()
            .filter(|((o, _), _)| *o == c)
            .map(|(_, &m)| m)
            .collect();
        v.sort();
        v
    }

    /// Appends to `fields` (the instance struct of class `c`) the VAR_INST variables
    /// of its methods, and records where they are.
    pub(super) fn method_instance_fields(&mut self, c: PouId, fields: &mut Vec<plcc_ir::Field>) {
        for m in self.own_methods(c) {
            for vi in 0..self.pou(m).vars.len() {
                let v = self.pou(m).vars[vi].clone();
                if v.section != ast::VarKind::Inst {
                    continue;
                }
                let Some((ty, elem)) = self.mem_type(v.ty) else {
                    continue;
                };
                self.ir[m.0 as usize].storage[vi] =
                    Some(super::Storage::Field(fields.len() as u32));
                // `M.n`; an override's own `n` beside the overridden method's
                // (both live in a derived instance) is told apart by its class.
                let mut name = format!("{}.{}", self.text(self.pou(m).name.span), v.display);
                if fields.iter().any(|f| f.name == name) {
                    name = format!("{}.{name}", self.pou(c).display);
                }
                fields.push(plcc_ir::Field {
                    name,
                    ty,
                    elem,
                    role: plcc_ir::FieldRole::Hidden,
                    location: None,
                });
            }
        }
    }
}
