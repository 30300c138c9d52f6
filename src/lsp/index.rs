//! What the language server knows of a workspace's names, from the syntax trees:
//! every declaration (POUs, their variables, METHODs and ACTIONs, types, their
//! fields and enumeration values, global variables, configurations, resources,
//! tasks, program instances), every use of a name with the scope it is used in, and
//! the resolution of a use to its declaration.
//!
//! The trees are the parsers' own, parsed again from the build's texts with one
//! interner, before the front end rewrites them for lowering (global blocks gathered
//! into one hidden POU, implicit ENO and edge memories added): what the user wrote,
//! with its spans. Resolution is syntactic and follows the language's scoping: a
//! METHOD's variables, then its FUNCTION_BLOCK's (and the bases' of `EXTENDS`), then
//! the globals, then POUs and types by name; `a.b` looks `b` up in the type of `a`
//! (an FB instance, a STRUCT, a PROGRAM or a global variable list).

use plcc_frontend::ast::*;
use plcc_frontend::intern::{Interner, Symbol};
use plcc_frontend::source::SourceMap;
use plcc_frontend::visit::{self, walk_expr as walk_expr_children, walk_stmt, Visitor};
use plcc_frontend::Lang;
use plcc_ir::diag::{FileId, Span};

/// How deep `EXTENDS` chains and type aliases are followed (a cycle is an error the
/// build reports; here it only stops the search).
const MAX_DEPTH: usize = 16;

/// The syntax trees of a workspace's textual files, with their names interned together.
pub struct Index {
    units: Vec<SourceUnit>,
    interner: Interner,
}

/// A declaration a name can resolve to.
#[derive(Clone, Copy, Debug)]
pub enum Decl<'a> {
    /// A PROGRAM, FUNCTION or FUNCTION_BLOCK.
    Pou(&'a Pou),
    /// A METHOD of a FUNCTION_BLOCK or an INTERFACE (its owner's name).
    Method(&'a Ident, &'a Method),
    /// A PROPERTY (its owner's name).
    Property(&'a Ident, &'a Property),
    /// An ACTION.
    Action(&'a Action),
    /// A variable: its name, its declaration, its block, and the name of the POU,
    /// METHOD, configuration or resource that declares it (`None` for a global list
    /// outside any).
    Var {
        /// The variable's name.
        name: &'a Ident,
        /// The declaration it is one of the names of.
        decl: &'a VarDecl,
        /// The block holding the declaration.
        block: &'a VarBlock,
        /// Who declares it.
        owner: Option<&'a Ident>,
    },
    /// A TYPE.
    Type(&'a TypeDecl),
    /// A field of a STRUCT type.
    Field {
        /// The field's name.
        name: &'a Ident,
        /// Its declaration.
        decl: &'a VarDecl,
        /// The STRUCT type.
        ty: &'a TypeDecl,
    },
    /// A value of an enumeration type.
    EnumValue {
        /// The value's name.
        name: &'a Ident,
        /// The enumeration type.
        ty: &'a TypeDecl,
    },
    /// An INTERFACE.
    Interface(&'a Interface),
    /// A CONFIGURATION.
    Config(&'a Configuration),
    /// A RESOURCE.
    Resource(&'a Resource),
    /// A TASK.
    Task(&'a TaskDecl),
    /// A program instance of a resource (`PROGRAM main WITH fast : Main;`).
    Instance(&'a ProgramConfig),
}

impl<'a> Decl<'a> {
    /// The declared name.
    pub fn name(&self) -> &'a Ident {
        match *self {
            Decl::Pou(p) => &p.name,
            Decl::Method(_, m) => &m.pou.name,
            Decl::Property(_, p) => &p.name,
            Decl::Action(a) => &a.name,
            Decl::Var { name, .. } | Decl::Field { name, .. } | Decl::EnumValue { name, .. } => {
                name
            }
            Decl::Type(t) => &t.name,
            Decl::Interface(i) => &i.name,
            Decl::Config(c) => &c.name,
            Decl::Resource(r) => &r.name,
            Decl::Task(t) => &t.name,
            Decl::Instance(p) => &p.name,
        }
    }

    /// The whole declaration's span (never smaller than the name's).
    pub fn span(&self) -> Span {
        let whole = match *self {
            Decl::Pou(p) => p.span,
            Decl::Method(_, m) => m.pou.span,
            Decl::Property(_, p) => p.span,
            Decl::Action(a) => a.span,
            Decl::Var { decl, .. } | Decl::Field { decl, .. } => decl.span,
            Decl::EnumValue { name, .. } => name.span,
            Decl::Type(t) => t.span,
            Decl::Interface(i) => i.span,
            Decl::Config(c) => c.span,
            Decl::Resource(r) => r.span,
            Decl::Task(t) => t.span,
            Decl::Instance(p) => p.span,
        };
        let name = self.name().span;
        if whole.file == name.file {
            whole.to(name)
        } else {
            name
        }
    }
}

/// Where a name is used: the POU (and the METHOD, ACTION or accessor inside it)
/// and the configuration and resource around it.
#[derive(Clone, Copy, Default)]
struct Scope<'a> {
    pou: Option<&'a Pou>,
    inner: Option<&'a Pou>,
    config: Option<&'a Configuration>,
    resource: Option<&'a Resource>,
}

/// One written name and what it is.
#[derive(Clone, Copy)]
enum Occ<'a> {
    /// A declaration's own name.
    Decl(Decl<'a>),
    /// A plain name in an expression or statement.
    Name(&'a Ident),
    /// A type's name (in a declaration, EXTENDS, IMPLEMENTS).
    Type(&'a Ident),
    /// `base.name`.
    Member(&'a Expr, &'a Ident),
    /// `callee(name := …)` or `callee(name => …)`.
    Param(&'a Expr, &'a Ident),
    /// `Type#value`.
    EnumValue(&'a Ident, &'a Ident),
    /// A parameter of a configuration's program instance: the PROGRAM, the name.
    PouParam(&'a Ident, &'a Ident),
}

impl<'a> Occ<'a> {
    fn ident(&self) -> &'a Ident {
        match *self {
            Occ::Decl(d) => d.name(),
            Occ::Name(i) | Occ::Type(i) | Occ::Member(_, i) | Occ::Param(_, i) => i,
            Occ::EnumValue(_, v) | Occ::PouParam(_, v) => v,
        }
    }
}

/// A type as far as member lookup needs it.
#[derive(Clone, Copy)]
enum Ty<'a> {
    Spec(&'a TypeSpec),
    Pou(&'a Pou),
    List(&'a VarBlock),
}

impl Index {
    /// Parses the textual files among `files` (ST, IL, STL; a PLCopen file has no
    /// text of the user's to point into) from `sources`, and the standard library
    /// if `sources` holds it.
    pub fn new(sources: &SourceMap, files: &[(FileId, Lang)]) -> Index {
        let mut interner = Interner::new();
        let mut diags = Vec::new();
        let mut units = Vec::new();
        for &(file, lang) in files {
            let text = &sources.get(file).text;
            let unit = match lang {
                Lang::St | Lang::Cst => {
                    plcc_frontend::st::parse(file, text, &mut interner, &mut diags)
                }
                Lang::Il => plcc_frontend::il::parse(file, text, &mut interner, &mut diags),
                Lang::Stl => plcc_frontend::stl::parse(file, text, &mut interner, &mut diags),
                Lang::Ld => continue,
            };
            units.push(unit);
        }
        // The standard library last: hovers over its blocks, completion of them.
        if let Some((file, f)) = sources
            .iter()
            .find(|(_, f)| f.name == plcc_frontend::STDLIB_NAME)
        {
            units.push(plcc_frontend::st::parse(
                file,
                &f.text,
                &mut interner,
                &mut diags,
            ));
        }
        Index { units, interner }
    }

    /// The syntax tree of one file, if it was parsed.
    pub fn unit(&self, file: FileId) -> Option<&SourceUnit> {
        self.units.iter().find(|u| u.file == file)
    }

    /// The declaration of the name at `offset` in `file`, with the span of the name
    /// as written there.
    pub fn resolve_at(&self, file: FileId, offset: u32) -> Option<(Span, Decl<'_>)> {
        let unit = self.unit(file)?;
        let mut found = None;
        walk_unit(unit, self, &mut |occ, scope| {
            let id = occ.ident();
            if found.is_none() && id.span.start <= offset && offset <= id.span.end {
                if let Some(d) = self.resolve(occ, scope) {
                    found = Some((id.span, d));
                }
            }
        });
        found
    }

    /// Every name written in `file` that resolves, with its declaration, in text
    /// order (one walk of the file: for semantic tokens).
    pub fn names_in(&self, file: FileId) -> Vec<(Span, Decl<'_>)> {
        let mut out = Vec::new();
        if let Some(unit) = self.unit(file) {
            walk_unit(unit, self, &mut |occ, scope| {
                if let Some(d) = self.resolve(occ, scope) {
                    out.push((occ.ident().span, d));
                }
            });
        }
        out.sort_by_key(|(s, _)| s.start);
        out.dedup_by_key(|(s, _)| s.start);
        out
    }

    /// Every place, in every file, where `target` is declared or used by name.
    pub fn references(&self, target: &Decl<'_>) -> Vec<Span> {
        let key = target.name().span;
        let mut out = Vec::new();
        for unit in &self.units {
            walk_unit(unit, self, &mut |occ, scope| {
                let id = occ.ident();
                if id.sym == target.name().sym
                    && self
                        .resolve(occ, scope)
                        .is_some_and(|d| d.name().span == key)
                {
                    out.push(id.span);
                }
            });
        }
        out.sort_by_key(|s| (s.file, s.start));
        out.dedup();
        out
    }

    /// The names visible at `offset` in `file`: the variables of the POU (and
    /// METHOD) around it, then the globals, POUs and types.
    pub fn visible_at(&self, file: FileId, offset: u32) -> Vec<Decl<'_>> {
        let mut out = Vec::new();
        let scope = self
            .unit(file)
            .map(|u| scope_at(u, offset))
            .unwrap_or_default();
        for p in [scope.inner, scope.pou].into_iter().flatten() {
            self.pou_members(p, &mut out, 0);
        }
        for d in self.globals() {
            out.push(d);
        }
        for unit in &self.units {
            for item in &unit.items {
                match item {
                    Item::Pou(p) => out.push(Decl::Pou(p)),
                    Item::Type(t) => out.push(Decl::Type(t)),
                    Item::Interface(i) => out.push(Decl::Interface(i)),
                    _ => {}
                }
            }
        }
        out
    }

    /// The interned symbol of a name, if any file uses it.
    pub fn sym(&self, name: &str) -> Option<Symbol> {
        self.interner.lookup(name)
    }

    // ----- resolution -----

    fn resolve<'a>(&'a self, occ: Occ<'a>, scope: Scope<'a>) -> Option<Decl<'a>> {
        match occ {
            Occ::Decl(d) => Some(d),
            Occ::Name(id) => self.lookup(id.sym, scope),
            Occ::Type(id) => self.global_name(id.sym),
            Occ::Member(base, id) => {
                let ty = self.type_of(base, scope, 0)?;
                self.member(ty, id.sym)
            }
            Occ::Param(callee, id) => {
                let ty = match self.resolve_expr(callee, scope)? {
                    Decl::Pou(p) => Ty::Pou(p),
                    Decl::Method(_, m) => Ty::Pou(&m.pou),
                    Decl::Var { decl, .. } => Ty::Spec(&decl.ty),
                    _ => return None,
                };
                self.member(ty, id.sym)
            }
            Occ::PouParam(pou, id) => match self.global_name(pou.sym)? {
                Decl::Pou(p) => self.pou_member(p, id.sym, 0),
                _ => None,
            },
            Occ::EnumValue(ty, value) => match self.global_name(ty.sym)? {
                Decl::Type(t) => enum_value(t, value.sym),
                _ => None,
            },
        }
    }

    /// What an expression naming something (a name or `a.b`) resolves to.
    fn resolve_expr<'a>(&'a self, e: &'a Expr, scope: Scope<'a>) -> Option<Decl<'a>> {
        match &e.kind {
            ExprKind::Name(id) => self.lookup(id.sym, scope),
            ExprKind::Member(base, id) => {
                let ty = self.type_of(base, scope, 0)?;
                self.member(ty, id.sym)
            }
            ExprKind::Paren(inner) => self.resolve_expr(inner, scope),
            _ => None,
        }
    }

    /// A plain name in a scope.
    fn lookup<'a>(&'a self, sym: Symbol, scope: Scope<'a>) -> Option<Decl<'a>> {
        for p in [scope.inner, scope.pou].into_iter().flatten() {
            if let Some(d) = self.pou_member(p, sym, 0) {
                return Some(d);
            }
            if p.name.sym == sym {
                return Some(Decl::Pou(p));
            }
        }
        if let Some(r) = scope.resource {
            if let Some(d) = r.tasks.iter().find(|t| t.name.sym == sym) {
                return Some(Decl::Task(d));
            }
            if let Some(d) = block_var(&r.var_blocks, sym, Some(&r.name)) {
                return Some(d);
            }
        }
        if let Some(c) = scope.config {
            if let Some(d) = block_var(&c.var_blocks, sym, Some(&c.name)) {
                return Some(d);
            }
        }
        if let Some(d) = self.globals().find(|d| d.name().sym == sym) {
            return Some(d);
        }
        if let Some(d) = self.global_name(sym) {
            return Some(d);
        }
        // A bare enumeration value.
        self.types().find_map(|t| enum_value(t, sym))
    }

    /// A POU, TYPE, INTERFACE or CONFIGURATION by name.
    fn global_name(&self, sym: Symbol) -> Option<Decl<'_>> {
        self.units
            .iter()
            .flat_map(|u| &u.items)
            .find_map(|item| match item {
                Item::Pou(p) if p.name.sym == sym => Some(Decl::Pou(p)),
                Item::Type(t) if t.name.sym == sym => Some(Decl::Type(t)),
                Item::Interface(i) if i.name.sym == sym => Some(Decl::Interface(i)),
                Item::Configuration(c) if c.name.sym == sym => Some(Decl::Config(c)),
                _ => None,
            })
    }

    fn types(&self) -> impl Iterator<Item = &TypeDecl> {
        self.units
            .iter()
            .flat_map(|u| &u.items)
            .filter_map(|item| match item {
                Item::Type(t) => Some(t),
                _ => None,
            })
    }

    /// Every global variable: of the global lists, the configurations and their resources.
    fn globals(&self) -> impl Iterator<Item = Decl<'_>> {
        self.units.iter().flat_map(|u| &u.items).flat_map(|item| {
            let mut out = Vec::new();
            match item {
                Item::Globals(b) => push_block(b, b.list.as_ref(), &mut out),
                Item::Configuration(c) => {
                    for b in &c.var_blocks {
                        push_block(b, Some(&c.name), &mut out);
                    }
                    for r in &c.resources {
                        for b in &r.var_blocks {
                            push_block(b, Some(&r.name), &mut out);
                        }
                    }
                }
                _ => {}
            }
            out
        })
    }

    /// A member of a POU by name: its variables, METHODs, PROPERTYs and ACTIONs,
    /// then its base's.
    fn pou_member<'a>(&'a self, p: &'a Pou, sym: Symbol, depth: usize) -> Option<Decl<'a>> {
        if let Some(d) = block_var(&p.var_blocks, sym, Some(&p.name)) {
            return Some(d);
        }
        if let Some(m) = p.oo.methods.iter().find(|m| m.pou.name.sym == sym) {
            return Some(Decl::Method(&p.name, m));
        }
        if let Some(pr) = p.oo.properties.iter().find(|pr| pr.name.sym == sym) {
            return Some(Decl::Property(&p.name, pr));
        }
        if let Some(a) = p.actions.iter().find(|a| a.name.sym == sym) {
            return Some(Decl::Action(a));
        }
        if let Some(a) = self.top_actions(p).find(|a| a.name.sym == sym) {
            return Some(Decl::Action(a));
        }
        let base = self.base(p, depth)?;
        self.pou_member(base, sym, depth + 1)
    }

    /// Every member of a POU and its bases (see [`Index::pou_member`]).
    fn pou_members<'a>(&'a self, p: &'a Pou, out: &mut Vec<Decl<'a>>, depth: usize) {
        for b in &p.var_blocks {
            push_block(b, Some(&p.name), out);
        }
        out.extend(p.oo.methods.iter().map(|m| Decl::Method(&p.name, m)));
        out.extend(p.oo.properties.iter().map(|pr| Decl::Property(&p.name, pr)));
        out.extend(p.actions.iter().map(Decl::Action));
        out.extend(self.top_actions(p).map(Decl::Action));
        if let Some(base) = self.base(p, depth) {
            self.pou_members(base, out, depth + 1);
        }
    }

    /// The ACTIONs written outside a POU for it (`ACTION Pou.Name:`).
    fn top_actions<'a>(&'a self, p: &'a Pou) -> impl Iterator<Item = &'a Action> {
        self.units
            .iter()
            .flat_map(|u| &u.items)
            .filter_map(move |item| match item {
                Item::Action(a) if a.pou.is_some_and(|o| o.sym == p.name.sym) => Some(a),
                _ => None,
            })
    }

    /// The FUNCTION_BLOCK a POU EXTENDS.
    fn base<'a>(&'a self, p: &'a Pou, depth: usize) -> Option<&'a Pou> {
        if depth >= MAX_DEPTH {
            return None;
        }
        match self.global_name(p.extends?.sym)? {
            Decl::Pou(b) => Some(b),
            _ => None,
        }
    }

    /// The type of an expression that names a variable (as far as member lookup
    /// needs it).
    fn type_of<'a>(&'a self, e: &'a Expr, scope: Scope<'a>, depth: usize) -> Option<Ty<'a>> {
        if depth >= MAX_DEPTH {
            return None;
        }
        let spec = match &e.kind {
            ExprKind::Name(_) | ExprKind::Member(..) => match self.resolve_expr(e, scope)? {
                Decl::Var { decl, .. } | Decl::Field { decl, .. } => &decl.ty,
                Decl::Pou(p) => return Some(Ty::Pou(p)),
                Decl::Property(_, pr) => &pr.ty,
                _ => return None,
            },
            ExprKind::Paren(inner) => return self.type_of(inner, scope, depth + 1),
            ExprKind::Index(base, _) => match self.type_of(base, scope, depth + 1)? {
                Ty::Spec(TypeSpec::Array { elem, .. }) => elem,
                _ => return None,
            },
            ExprKind::Deref(base) => match self.type_of(base, scope, depth + 1)? {
                Ty::Spec(
                    TypeSpec::Ref { target, .. }
                    | TypeSpec::Pointer { target, .. }
                    | TypeSpec::Reference { target, .. },
                ) => target,
                _ => return None,
            },
            _ => return None,
        };
        // A name alone may also be a global variable list's (`GVL.x`).
        if let ExprKind::Name(id) = &e.kind {
            if self.lookup(id.sym, scope).is_none() {
                return self.list(id.sym).map(Ty::List);
            }
        }
        Some(Ty::Spec(spec))
    }

    /// The global variable list named `sym`.
    fn list(&self, sym: Symbol) -> Option<&VarBlock> {
        self.units
            .iter()
            .flat_map(|u| &u.items)
            .find_map(|item| match item {
                Item::Globals(b) if b.list.is_some_and(|l| l.sym == sym) => Some(b),
                _ => None,
            })
    }

    /// A member of a type by name.
    fn member<'a>(&'a self, ty: Ty<'a>, sym: Symbol) -> Option<Decl<'a>> {
        let mut ty = ty;
        for _ in 0..MAX_DEPTH {
            match ty {
                Ty::Pou(p) => return self.pou_member(p, sym, 0),
                Ty::List(b) => return block_var(std::slice::from_ref(b), sym, None),
                Ty::Spec(
                    TypeSpec::Ref { target, .. }
                    | TypeSpec::Pointer { target, .. }
                    | TypeSpec::Reference { target, .. },
                ) => ty = Ty::Spec(target),
                Ty::Spec(TypeSpec::Named(id)) => match self.global_name(id.sym)? {
                    Decl::Pou(p) => ty = Ty::Pou(p),
                    Decl::Interface(i) => {
                        return i
                            .methods
                            .iter()
                            .find(|m| m.pou.name.sym == sym)
                            .map(|m| Decl::Method(&i.name, m))
                            .or_else(|| {
                                i.properties
                                    .iter()
                                    .find(|p| p.name.sym == sym)
                                    .map(|p| Decl::Property(&i.name, p))
                            })
                    }
                    Decl::Type(t) => return self.type_member(t, sym, 0),
                    _ => return None,
                },
                Ty::Spec(_) => return None,
            }
        }
        None
    }

    /// A field of a STRUCT type (or of the type an alias names, or of the base of
    /// `EXTENDS`), or a value of an enumeration type.
    fn type_member<'a>(&'a self, t: &'a TypeDecl, sym: Symbol, depth: usize) -> Option<Decl<'a>> {
        if depth >= MAX_DEPTH {
            return None;
        }
        match &t.spec {
            TypeSpec::Struct { fields, .. } => {
                for decl in fields {
                    if let Some(name) = decl.names.iter().find(|n| n.sym == sym) {
                        return Some(Decl::Field { name, decl, ty: t });
                    }
                }
                match self.global_name(t.extends?.sym)? {
                    Decl::Type(b) => self.type_member(b, sym, depth + 1),
                    _ => None,
                }
            }
            TypeSpec::Enum { .. } => enum_value(t, sym),
            TypeSpec::Named(id) => match self.global_name(id.sym)? {
                Decl::Type(b) => self.type_member(b, sym, depth + 1),
                _ => None,
            },
            _ => None,
        }
    }
}

/// The value `sym` of an enumeration type.
fn enum_value(t: &TypeDecl, sym: Symbol) -> Option<Decl<'_>> {
    match &t.spec {
        TypeSpec::Enum { values, .. } => values
            .iter()
            .find(|(v, _)| v.sym == sym)
            .map(|(name, _)| Decl::EnumValue { name, ty: t }),
        _ => None,
    }
}

/// A variable of `blocks` by name.
fn block_var<'a>(
    blocks: &'a [VarBlock],
    sym: Symbol,
    owner: Option<&'a Ident>,
) -> Option<Decl<'a>> {
    for block in blocks {
        for decl in &block.decls {
            if let Some(name) = decl.names.iter().find(|n| n.sym == sym) {
                return Some(Decl::Var {
                    name,
                    decl,
                    block,
                    owner,
                });
            }
        }
    }
    None
}

fn push_block<'a>(block: &'a VarBlock, owner: Option<&'a Ident>, out: &mut Vec<Decl<'a>>) {
    for decl in &block.decls {
        for name in &decl.names {
            out.push(Decl::Var {
                name,
                decl,
                block,
                owner,
            });
        }
    }
}

/// The scope around `offset` (the innermost POU, METHOD or accessor whose span holds it).
fn scope_at(unit: &SourceUnit, offset: u32) -> Scope<'_> {
    let inside = |s: Span| s.start <= offset && offset <= s.end;
    let mut scope = Scope::default();
    for item in &unit.items {
        match item {
            Item::Pou(p) if inside(p.span) => {
                scope.pou = Some(p);
                let accessors = p.oo.properties.iter().flat_map(|pr| [&pr.get, &pr.set]);
                scope.inner =
                    p.oo.methods
                        .iter()
                        .map(|m| &m.pou)
                        .chain(accessors.flatten())
                        .find(|m| inside(m.span));
            }
            Item::Configuration(c) if inside(c.span) => {
                scope.config = Some(c);
                scope.resource = c.resources.iter().find(|r| inside(r.span));
            }
            _ => {}
        }
    }
    scope
}

// ----- the walk over every written name -----

type Visit<'v, 'a> = &'v mut dyn FnMut(Occ<'a>, Scope<'a>);

fn walk_unit<'a>(unit: &'a SourceUnit, index: &'a Index, f: Visit<'_, 'a>) {
    for item in &unit.items {
        match item {
            Item::Pou(p) => walk_pou(p, Decl::Pou(p), Scope::default(), f),
            Item::Type(t) => {
                f(Occ::Decl(Decl::Type(t)), Scope::default());
                if let Some(b) = &t.extends {
                    f(Occ::Type(b), Scope::default());
                }
                walk_type_decl(t, f);
                if let Some(init) = &t.init {
                    walk_init(init, Scope::default(), f);
                }
            }
            Item::Globals(b) => walk_block(b, b.list.as_ref(), Scope::default(), f),
            Item::Configuration(c) => {
                let mut scope = Scope {
                    config: Some(c),
                    ..Scope::default()
                };
                f(Occ::Decl(Decl::Config(c)), scope);
                for b in &c.var_blocks {
                    walk_block(b, Some(&c.name), scope, f);
                }
                for r in &c.resources {
                    scope.resource = Some(r);
                    f(Occ::Decl(Decl::Resource(r)), scope);
                    for b in &r.var_blocks {
                        walk_block(b, Some(&r.name), scope, f);
                    }
                    for t in &r.tasks {
                        f(Occ::Decl(Decl::Task(t)), scope);
                        for (_, e) in &t.props {
                            walk_expr(e, scope, f);
                        }
                    }
                    for p in &r.programs {
                        f(Occ::Decl(Decl::Instance(p)), scope);
                        if let Some(t) = &p.task {
                            f(Occ::Name(t), scope);
                        }
                        f(Occ::Type(&p.pou), scope);
                        walk_args(&p.args, Callee::Pou(&p.pou), scope, f);
                    }
                }
            }
            Item::Action(a) => {
                let owner = a.pou.and_then(|o| match index.global_name(o.sym) {
                    Some(Decl::Pou(p)) => Some(p),
                    _ => None,
                });
                let scope = Scope {
                    pou: owner,
                    ..Scope::default()
                };
                if let Some(o) = &a.pou {
                    f(Occ::Type(o), scope);
                }
                f(Occ::Decl(Decl::Action(a)), scope);
                walk_stmts(&a.body.stmts, scope, f);
            }
            Item::Interface(i) => {
                f(Occ::Decl(Decl::Interface(i)), Scope::default());
                for e in &i.extends {
                    f(Occ::Type(e), Scope::default());
                }
                for m in &i.methods {
                    walk_pou(&m.pou, Decl::Method(&i.name, m), Scope::default(), f);
                }
                for p in &i.properties {
                    f(Occ::Decl(Decl::Property(&i.name, p)), Scope::default());
                    walk_type(&p.ty, f, Scope::default());
                }
            }
        }
    }
}

/// A POU, METHOD or accessor: its name, variables, body, and inner POUs.
fn walk_pou<'a>(p: &'a Pou, own: Decl<'a>, outer: Scope<'a>, f: Visit<'_, 'a>) {
    let scope = match outer.pou {
        None => Scope {
            pou: Some(p),
            ..outer
        },
        Some(_) => Scope {
            inner: Some(p),
            ..outer
        },
    };
    f(Occ::Decl(own), scope);
    if let Some(t) = &p.return_type {
        walk_type(t, f, scope);
    }
    if let Some(b) = &p.extends {
        f(Occ::Type(b), scope);
    }
    for i in &p.oo.implements {
        f(Occ::Type(i), scope);
    }
    for b in &p.var_blocks {
        walk_block(b, Some(&p.name), scope, f);
    }
    walk_stmts(&p.body.stmts, scope, f);
    for a in &p.actions {
        f(Occ::Decl(Decl::Action(a)), scope);
        walk_stmts(&a.body.stmts, scope, f);
    }
    for m in &p.oo.methods {
        walk_pou(&m.pou, Decl::Method(&p.name, m), scope, f);
    }
    for pr in &p.oo.properties {
        f(Occ::Decl(Decl::Property(&p.name, pr)), scope);
        walk_type(&pr.ty, f, scope);
        for acc in [&pr.get, &pr.set].into_iter().flatten() {
            let inner = Scope {
                inner: Some(acc),
                ..scope
            };
            for b in &acc.var_blocks {
                walk_block(b, Some(&pr.name), inner, f);
            }
            walk_stmts(&acc.body.stmts, inner, f);
        }
    }
}

fn walk_block<'a>(b: &'a VarBlock, owner: Option<&'a Ident>, scope: Scope<'a>, f: Visit<'_, 'a>) {
    for decl in &b.decls {
        for name in &decl.names {
            let d = Decl::Var {
                name,
                decl,
                block: b,
                owner,
            };
            f(Occ::Decl(d), scope);
        }
        walk_type(&decl.ty, f, scope);
        if let Some(init) = &decl.init {
            walk_init(init, scope, f);
        }
    }
}

fn walk_type_decl<'a>(t: &'a TypeDecl, f: Visit<'_, 'a>) {
    let scope = Scope::default();
    match &t.spec {
        TypeSpec::Struct { fields, .. } => {
            for decl in fields {
                for name in &decl.names {
                    f(Occ::Decl(Decl::Field { name, decl, ty: t }), scope);
                }
                walk_type(&decl.ty, f, scope);
                if let Some(init) = &decl.init {
                    walk_init(init, scope, f);
                }
            }
        }
        TypeSpec::Enum { values, base, .. } => {
            for (name, value) in values {
                f(Occ::Decl(Decl::EnumValue { name, ty: t }), scope);
                if let Some(v) = value {
                    walk_expr(v, scope, f);
                }
            }
            if let Some(b) = base {
                f(Occ::Type(b), scope);
            }
        }
        spec => walk_type(spec, f, scope),
    }
}

fn walk_type<'a>(t: &'a TypeSpec, f: Visit<'_, 'a>, scope: Scope<'a>) {
    match t {
        TypeSpec::Named(id) => f(Occ::Type(id), scope),
        TypeSpec::String { len, .. } => {
            if let Some(e) = len {
                walk_expr(e, scope, f);
            }
        }
        TypeSpec::Array { dims, elem, .. } => {
            for (lo, hi) in dims.iter().flatten() {
                walk_expr(lo, scope, f);
                walk_expr(hi, scope, f);
            }
            walk_type(elem, f, scope);
        }
        TypeSpec::Subrange { base, lo, hi, .. } => {
            f(Occ::Type(base), scope);
            walk_expr(lo, scope, f);
            walk_expr(hi, scope, f);
        }
        TypeSpec::Enum { values, base, .. } => {
            for (_, v) in values {
                if let Some(v) = v {
                    walk_expr(v, scope, f);
                }
            }
            if let Some(b) = base {
                f(Occ::Type(b), scope);
            }
        }
        TypeSpec::Struct { fields, .. } => {
            for decl in fields {
                walk_type(&decl.ty, f, scope);
            }
        }
        TypeSpec::Ref { target, .. }
        | TypeSpec::Reference { target, .. }
        | TypeSpec::Pointer { target, .. } => walk_type(target, f, scope),
    }
}

fn walk_init<'a>(init: &'a Init, scope: Scope<'a>, f: Visit<'_, 'a>) {
    match init {
        Init::Expr(e) => walk_expr(e, scope, f),
        Init::Array { elems, .. } => {
            for el in elems {
                if let Some(r) = &el.repeat {
                    walk_expr(r, scope, f);
                }
                if let Some(v) = &el.value {
                    walk_init(v, scope, f);
                }
            }
        }
        Init::Struct { fields, .. } => {
            for (_, v) in fields {
                walk_init(v, scope, f);
            }
        }
    }
}

/// The occurrences of names in statements and expressions, found by the front end's
/// visitor.
struct Names<'v, 'a> {
    scope: Scope<'a>,
    f: Visit<'v, 'a>,
}

impl<'a> Visitor<'a> for Names<'_, 'a> {
    fn visit_stmt(&mut self, s: &'a Stmt) {
        if let StmtKind::For { var, .. } = &s.kind {
            (self.f)(Occ::Name(var), self.scope);
        }
        walk_stmt(self, s);
    }

    fn visit_expr(&mut self, e: &'a Expr) {
        match &e.kind {
            ExprKind::Name(id) => (self.f)(Occ::Name(id), self.scope),
            ExprKind::Member(base, id) => {
                self.visit_expr(base);
                (self.f)(Occ::Member(base, id), self.scope);
            }
            ExprKind::EnumValue { ty, value } => {
                (self.f)(Occ::Type(ty), self.scope);
                (self.f)(Occ::EnumValue(ty, value), self.scope);
            }
            ExprKind::Call { callee, args } => {
                self.visit_expr(callee);
                walk_args(args, Callee::Expr(callee), self.scope, self.f);
            }
            _ => walk_expr_children(self, e),
        }
    }
}

fn walk_stmts<'a>(stmts: &'a [Stmt], scope: Scope<'a>, f: Visit<'_, 'a>) {
    visit::walk_stmts(&mut Names { scope, f }, stmts);
}

fn walk_expr<'a>(e: &'a Expr, scope: Scope<'a>, f: Visit<'_, 'a>) {
    Names { scope, f }.visit_expr(e);
}

fn walk_args<'a>(args: &'a [Arg], callee: Callee<'a>, scope: Scope<'a>, f: Visit<'_, 'a>) {
    for arg in args {
        match &arg.kind {
            ArgKind::Positional(v) => walk_expr(v, scope, f),
            ArgKind::Input { name, value } => {
                f(callee.param(name), scope);
                walk_expr(value, scope, f);
            }
            ArgKind::Output { name, target, .. } => {
                f(callee.param(name), scope);
                if let Some(t) = target {
                    walk_expr(t, scope, f);
                }
            }
        }
    }
}

/// What a call calls: an expression, or the POU of a configuration's program instance.
#[derive(Clone, Copy)]
enum Callee<'a> {
    Expr(&'a Expr),
    Pou(&'a Ident),
}

impl<'a> Callee<'a> {
    fn param(self, name: &'a Ident) -> Occ<'a> {
        match self {
            Callee::Expr(e) => Occ::Param(e, name),
            Callee::Pou(p) => Occ::PouParam(p, name),
        }
    }
}
