//! User-defined types: `TYPE ... END_TYPE` declarations and the STRUCTs, enumerations
//! and subranges written directly in a declaration. They are resolved before any POU
//! interface (a POU may use a type declared later, in any file); STRUCTs get their IR
//! struct only when a variable of the type is laid out, so unused types cost nothing.

use super::consts::ConstVal;
use super::Lowerer;
use crate::ast::{self, Ident, TypeSpec};
use crate::codes;
use crate::intern::Symbol;
use crate::types::{int_range, EnumId, PouId, StructId, TagId, Ty};
use plcc_ir::diag::{Diagnostic, Span};
use plcc_ir::{AggDef, AggId, ElemType, Field, FieldRole, StructDef, StructKind};
use rustc_hash::FxHashMap;

/// The user types of a build.
#[derive(Clone, Default)]
pub(crate) struct UserTypes<'s> {
    /// The TYPE declarations, in source order.
    pub named: Vec<NamedType<'s>>,
    /// TYPE declarations by name.
    pub by_name: FxHashMap<Symbol, u32>,
    /// Every STRUCT type.
    pub structs: Vec<StructTy<'s>>,
    /// Every enumeration type.
    pub enums: Vec<EnumTy>,
    /// Every derived type's additions (name, initial value, range).
    pub tags: Vec<TypeTag<'s>>,
    /// The enumerations that declare a value of this name (an unqualified value is
    /// ambiguous when there are several).
    pub enum_values: FxHashMap<Symbol, Vec<EnumId>>,
}

/// One `name : spec` of a TYPE block.
#[derive(Clone)]
pub(crate) struct NamedType<'s> {
    /// The declaration.
    pub decl: &'s ast::TypeDecl,
    /// How far its resolution got.
    pub state: TypeState,
}

/// Resolution of a named type, which may refer to types declared after it.
#[derive(Copy, Clone, Debug, PartialEq)]
pub(crate) enum TypeState {
    /// Not looked at yet.
    Unresolved,
    /// Being resolved: meeting it again means it contains itself.
    Resolving,
    /// A STRUCT whose fields are being resolved: a reference to it is fine (its
    /// size does not depend on the STRUCT's), containing it is not.
    Building(StructId),
    /// Its type and the tag of its derived-type additions.
    Done(Ty, Option<TagId>),
}

/// A STRUCT type.
#[derive(Clone)]
pub(crate) struct StructTy<'s> {
    /// The type's name (`STRUCT` for one written in place).
    pub display: String,
    /// The fields in declaration order.
    pub fields: Vec<StructField<'s>>,
    /// The IR struct, once made.
    pub agg: Option<AggId>,
    /// The IR field of each field (a field of an erroneous type has none).
    pub ir_fields: Vec<Option<u32>>,
}

/// A field of a STRUCT.
#[derive(Clone)]
pub(crate) struct StructField<'s> {
    /// Its name.
    pub name: Ident,
    /// The declared spelling.
    pub display: String,
    /// Its type.
    pub ty: Ty,
    /// Its derived type, if any.
    pub tag: Option<TagId>,
    /// The initial value written in the STRUCT.
    pub init: Option<&'s ast::Init>,
}

/// An enumeration type.
#[derive(Clone)]
pub(crate) struct EnumTy {
    /// Its name (the values in parentheses for one written in place).
    pub display: String,
    /// The integer type that holds its values.
    pub base: ElemType,
    /// The values in declaration order.
    pub values: Vec<EnumValue>,
    /// The initial value of variables of the type: the declared one, else the first.
    pub default: i128,
}

/// One value of an enumeration.
#[derive(Clone)]
pub(crate) struct EnumValue {
    /// Its name.
    pub sym: Symbol,
    /// The declared spelling.
    pub display: String,
    /// Its number.
    pub value: i128,
}

/// What a derived type adds to its base: a name for messages, an initial value, the
/// bounds of a subrange.
#[derive(Clone)]
pub(crate) struct TypeTag<'s> {
    /// The derived type's name.
    pub name: String,
    /// A subrange's inclusive bounds.
    pub range: Option<(i128, i128)>,
    /// The initial value variables of the type get.
    pub default: TagDefault<'s>,
}

/// The initial value of a derived type.
#[derive(Copy, Clone)]
pub(crate) enum TagDefault<'s> {
    /// The one written in the TYPE declaration.
    Init(&'s ast::Init),
    /// A subrange's lower bound.
    Value(i128),
}

/// An unqualified enumeration value, looked up by name.
pub(crate) enum EnumLookup {
    /// No enumeration has it.
    None,
    /// The value of one enumeration.
    One(EnumId, ElemType, i128),
    /// Several enumerations have it and nothing says which.
    Ambiguous(Vec<EnumId>),
}

impl<'s> Lowerer<'s> {
    /// Registers every TYPE declaration; reports names declared twice or shared with a
    /// POU or an elementary type.
    pub(super) fn collect_types(&mut self) {
        let units = self.units;
        for unit in units {
            for item in &unit.items {
                let ast::Item::Type(t) = item else { continue };
                let name = self.text(t.name.span).to_string();
                let clash = if let Some(&prev) = self.user.by_name.get(&t.name.sym) {
                    Some(self.user.named[prev as usize].decl.name.span)
                } else {
                    self.pou_by_name
                        .get(&t.name.sym)
                        .filter(|&&p| !self.pou(p).std)
                        .map(|&p| self.pou(p).name.span)
                };
                if let Some(prev) = clash {
                    self.diags.push(
                        Diagnostic::error(
                            codes::E_DUPLICATE,
                            format!("`{name}` is declared twice"),
                            t.name.span,
                        )
                        .with_label("second declaration")
                        .with_secondary(prev, "first declared here"),
                    );
                    continue;
                }
                if ElemType::from_name(self.sym_name(t.name.sym)).is_some() {
                    self.error(
                        codes::E_DUPLICATE,
                        format!("`{name}` is an elementary type and cannot be declared again"),
                        t.name.span,
                    );
                    continue;
                }
                self.user
                    .by_name
                    .insert(t.name.sym, self.user.named.len() as u32);
                self.user.named.push(NamedType {
                    decl: t,
                    state: TypeState::Unresolved,
                });
            }
        }
    }

    /// Resolves every TYPE declaration, used or not, so that each one's errors are
    /// reported once.
    pub(super) fn resolve_user_types(&mut self) {
        for i in 0..self.user.named.len() {
            let span = self.user.named[i].decl.name.span;
            self.resolve_named_type(i as u32, span);
        }
    }

    /// The type a TYPE declaration defines. `at` is where it is used (for the error
    /// when a type contains itself).
    pub(super) fn resolve_named_type(&mut self, i: u32, at: Span) -> (Ty, Option<TagId>) {
        match self.user.named[i as usize].state {
            TypeState::Done(t, tag) => (t, tag),
            TypeState::Building(id) if self.ref_depth > 0 => (Ty::Struct(id), None),
            TypeState::Resolving | TypeState::Building(_) => {
                let name = self
                    .text(self.user.named[i as usize].decl.name.span)
                    .to_string();
                self.diags.push(
                    Diagnostic::error(
                        codes::E_CONTAINS_ITSELF,
                        format!("the type `{name}` contains itself"),
                        at,
                    )
                    .with_label("this use closes the chain")
                    .with_note("a value of it would be infinitely large"),
                );
                // Done already, so that the outer resolution does not report it again.
                self.user.named[i as usize].state = TypeState::Done(Ty::Error, None);
                (Ty::Error, None)
            }
            TypeState::Unresolved => {
                self.user.named[i as usize].state = TypeState::Resolving;
                let decl = self.user.named[i as usize].decl;
                let r = self.define_named_type(decl);
                let r = match self.user.named[i as usize].state {
                    // It contained itself: keep the error.
                    TypeState::Done(Ty::Error, None) => (Ty::Error, None),
                    _ => r,
                };
                self.user.named[i as usize].state = TypeState::Done(r.0, r.1);
                r
            }
        }
    }

    fn define_named_type(&mut self, decl: &'s ast::TypeDecl) -> (Ty, Option<TagId>) {
        let display = self.text(decl.name.span).to_string();
        match &decl.spec {
            TypeSpec::Struct { fields, .. } => {
                let id = self.reserve_struct(display.clone());
                if let Some(&i) = self.user.by_name.get(&decl.name.sym) {
                    self.user.named[i as usize].state = TypeState::Building(id);
                }
                let ty = self.fill_struct(id, fields, None);
                if let Some(b) = decl.extends {
                    self.inherit_fields(id, b);
                }
                match &decl.init {
                    Some(init) => (
                        ty,
                        Some(self.add_tag(display, None, TagDefault::Init(init))),
                    ),
                    None => (ty, None),
                }
            }
            TypeSpec::Enum { values, base, .. } => {
                let ty = self.define_enum(display, values, *base, decl.init.as_ref());
                (ty, None)
            }
            TypeSpec::Subrange { base, lo, hi, .. } => {
                self.define_subrange(display, *base, lo, hi, decl.init.as_ref(), None)
            }
            spec => {
                let (ty, tag) = self.resolve_type_tagged(spec, None);
                let Some(init) = &decl.init else {
                    return (ty, tag);
                };
                if ty == Ty::Error {
                    return (ty, tag);
                }
                let range = tag.and_then(|t| self.user.tags[t.0 as usize].range);
                if let (Ty::Elem(_), ast::Init::Expr(e)) = (ty, init) {
                    self.check_type_default(ty, range, e, &display);
                }
                (
                    ty,
                    Some(self.add_tag(display, range, TagDefault::Init(init))),
                )
            }
        }
    }

    /// Checks the initial value of a derived elementary type where it is declared.
    fn check_type_default(
        &mut self,
        ty: Ty,
        range: Option<(i128, i128)>,
        e: &ast::Expr,
        name: &str,
    ) {
        let Some((c, _)) = self.const_eval_in(e, None, Some(ty)) else {
            self.error(
                codes::E_NOT_CONSTANT,
                format!("the initial value of the type `{name}` must be a constant expression"),
                e.span,
            );
            return;
        };
        match c.coerce(ty) {
            Err(msg) => self.error(codes::E_TYPE_MISMATCH, msg, e.span),
            Ok(ConstVal::Int(v)) => {
                if let Some((lo, hi)) = range.filter(|(lo, hi)| v < *lo || v > *hi) {
                    self.error(
                        codes::E_LITERAL_RANGE,
                        format!("{v} is out of the range of {name} ({lo}..{hi})"),
                        e.span,
                    );
                }
            }
            Ok(_) => {}
        }
    }

    fn add_tag(
        &mut self,
        name: String,
        range: Option<(i128, i128)>,
        default: TagDefault<'s>,
    ) -> TagId {
        self.user.tags.push(TypeTag {
            name,
            range,
            default,
        });
        TagId(self.user.tags.len() as u32 - 1)
    }

    /// A STRUCT type from its field declarations. Constants in its field types are
    /// looked up in `scope` (a POU for a STRUCT written in a declaration) and the
    /// globals.
    pub(super) fn define_struct(
        &mut self,
        display: String,
        decls: &'s [ast::VarDecl],
        scope: Option<PouId>,
    ) -> Ty {
        let id = self.reserve_struct(display);
        self.fill_struct(id, decls, scope)
    }

    /// A new STRUCT type without fields yet, so that its fields can refer to it.
    fn reserve_struct(&mut self, display: String) -> StructId {
        self.user.structs.push(StructTy {
            display,
            fields: Vec::new(),
            agg: None,
            ir_fields: Vec::new(),
        });
        StructId(self.user.structs.len() as u32 - 1)
    }

    /// Resolves the fields of the STRUCT `id`.
    fn fill_struct(&mut self, id: StructId, decls: &'s [ast::VarDecl], scope: Option<PouId>) -> Ty {
        let mut fields: Vec<StructField<'s>> = Vec::new();
        for d in decls {
            let (ty, tag) = self.resolve_type_tagged(&d.ty, scope);
            if let Some((_, span)) = &d.location {
                self.error(
                    codes::E_UNSUPPORTED,
                    "not supported yet: located fields (AT) in a STRUCT",
                    *span,
                );
            }
            for name in &d.names {
                if let Some(prev) = fields.iter().find(|f| f.name.sym == name.sym) {
                    let n = self.text(name.span).to_string();
                    let prev = prev.name.span;
                    self.diags.push(
                        Diagnostic::error(
                            codes::E_DUPLICATE,
                            format!("field `{n}` is declared twice"),
                            name.span,
                        )
                        .with_secondary(prev, "first declared here"),
                    );
                    continue;
                }
                fields.push(StructField {
                    name: *name,
                    display: self.text(name.span).to_string(),
                    ty,
                    tag,
                    init: d.init.as_ref(),
                });
            }
        }
        self.user.structs[id.0 as usize].fields = fields;
        Ty::Struct(id)
    }

    /// `EXTENDS base` of a STRUCT: the base's fields first, then its own; a field
    /// of both is declared twice.
    fn inherit_fields(&mut self, id: StructId, base: Ident) {
        let b = match self.user.by_name.get(&base.sym) {
            Some(&i) => self.resolve_named_type(i, base.span).0,
            None => Ty::Error,
        };
        let Ty::Struct(b) = b else {
            let n = self.text(base.span).to_string();
            self.error(
                codes::E_OO_DECLARATION,
                format!("`{n}` is not a STRUCT type, so a STRUCT cannot extend it"),
                base.span,
            );
            return;
        };
        let mut fields = self.user.structs[b.0 as usize].fields.clone();
        let own = std::mem::take(&mut self.user.structs[id.0 as usize].fields);
        for f in own {
            if let Some(prev) = fields.iter().find(|x| x.name.sym == f.name.sym) {
                let prev = prev.name.span;
                self.diags.push(
                    Diagnostic::error(
                        codes::E_DUPLICATE,
                        format!("field `{}` is declared in the base STRUCT too", f.display),
                        f.name.span,
                    )
                    .with_secondary(prev, "declared here"),
                );
                continue;
            }
            fields.push(f);
        }
        self.user.structs[id.0 as usize].fields = fields;
    }

    /// An enumeration type. Values without a number follow the previous one (the
    /// first is 0); the base type is INT unless one is given.
    pub(super) fn define_enum(
        &mut self,
        display: String,
        values: &'s [(Ident, Option<ast::Expr>)],
        base: Option<Ident>,
        init: Option<&'s ast::Init>,
    ) -> Ty {
        let base_ty = match base {
            None => ElemType::Int,
            Some(b) => match ElemType::from_name(self.sym_name(b.sym)) {
                Some(e) if e.is_integer() || (e.is_bit_string() && e != ElemType::Bool) => e,
                _ => {
                    let n = self.text(b.span).to_string();
                    self.error(
                        codes::E_TYPE_MISMATCH,
                        format!(
                            "the base type of an enumeration must be an integer or bit-string type, not `{n}`"
                        ),
                        b.span,
                    );
                    ElemType::Int
                }
            },
        };
        let id = EnumId(self.user.enums.len() as u32);
        let mut out: Vec<EnumValue> = Vec::new();
        let mut spans: Vec<Span> = Vec::new();
        let mut next: i128 = 0;
        let (lo, hi) = int_range(base_ty).unwrap_or((i128::MIN, i128::MAX));
        for (name, value) in values {
            let v = match value {
                None => next,
                Some(e) => match self.const_eval_in(e, None, Some(Ty::Elem(base_ty))) {
                    Some((ConstVal::Int(v), _)) => v,
                    _ => {
                        self.error(
                            codes::E_NOT_CONSTANT,
                            "the value of an enumeration element must be an integer constant",
                            e.span,
                        );
                        next
                    }
                },
            };
            if v < lo || v > hi {
                let at = value.as_ref().map_or(name.span, |e| e.span);
                let mut d = Diagnostic::error(
                    codes::E_LITERAL_RANGE,
                    format!(
                        "the enumeration value {v} is out of the range of {} ({lo}..{hi})",
                        base_ty.name()
                    ),
                    at,
                );
                if base.is_none() {
                    d = d.with_note(
                        "an enumeration is an INT unless typed: write e.g. `(a, b := 70000) DINT`",
                    );
                }
                self.diags.push(d);
            }
            next = v.saturating_add(1);
            if let Some(k) = out.iter().position(|x| x.sym == name.sym) {
                let n = self.text(name.span).to_string();
                self.diags.push(
                    Diagnostic::error(
                        codes::E_DUPLICATE,
                        format!("the enumeration value `{n}` is declared twice"),
                        name.span,
                    )
                    .with_secondary(spans[k], "first declared here"),
                );
                continue;
            }
            out.push(EnumValue {
                sym: name.sym,
                display: self.text(name.span).to_string(),
                value: v,
            });
            spans.push(name.span);
            self.user.enum_values.entry(name.sym).or_default().push(id);
        }
        let first = out.first().map_or(0, |v| v.value);
        self.user.enums.push(EnumTy {
            display,
            base: base_ty,
            values: out,
            default: first,
        });
        let ty = Ty::Enum(id, base_ty);
        match init {
            None => {}
            Some(ast::Init::Expr(e)) => match self.enum_const(e, id) {
                Some(v) => self.user.enums[id.0 as usize].default = v,
                None => self.not_an_enum_value(e.span, id),
            },
            Some(other) => self.not_an_enum_value(other.span(), id),
        }
        ty
    }

    /// Reports a value that should be one of an enumeration's.
    pub(super) fn not_an_enum_value(&mut self, span: Span, id: EnumId) {
        let en = &self.user.enums[id.0 as usize];
        let names: Vec<&str> = en.values.iter().map(|v| v.display.as_str()).collect();
        let msg = format!("expected a value of the enumeration {}", en.display);
        let note = format!("its values are {}", names.join(", "));
        self.diags
            .push(Diagnostic::error(codes::E_TYPE_MISMATCH, msg, span).with_note(note));
    }

    /// A subrange `base (lo..hi)`: values of the base type; its default is the lower
    /// bound unless declared.
    pub(super) fn define_subrange(
        &mut self,
        display: String,
        base: Ident,
        lo: &ast::Expr,
        hi: &ast::Expr,
        init: Option<&'s ast::Init>,
        scope: Option<PouId>,
    ) -> (Ty, Option<TagId>) {
        let (base_ty, base_tag) = self.resolve_type_tagged_named(base);
        let Ty::Elem(e) = base_ty else {
            if base_ty != Ty::Error {
                let n = self.text(base.span).to_string();
                self.error(
                    codes::E_TYPE_MISMATCH,
                    format!("a subrange needs an integer base type, not `{n}`"),
                    base.span,
                );
            }
            return (Ty::Error, None);
        };
        if !e.is_integer() {
            self.error(
                codes::E_TYPE_MISMATCH,
                format!("a subrange needs an integer base type, not {}", e.name()),
                base.span,
            );
            return (Ty::Error, None);
        }
        let (Some(l), Some(h)) = (self.const_int_in(lo, scope), self.const_int_in(hi, scope))
        else {
            return (Ty::Error, None);
        };
        if h < l {
            self.error(
                codes::E_BAD_DECLARATION,
                format!("subrange {l}..{h}: the upper bound is below the lower bound"),
                lo.span.to(hi.span),
            );
            return (Ty::Error, None);
        }
        let (tl, th) = int_range(e).unwrap_or((l, h));
        let outer = base_tag
            .and_then(|t| self.user.tags[t.0 as usize].range)
            .unwrap_or((tl, th));
        for (v, at) in [(l, lo.span), (h, hi.span)] {
            if v < outer.0 || v > outer.1 {
                self.error(
                    codes::E_LITERAL_RANGE,
                    format!(
                        "the subrange bound {v} is out of the range of its base type ({}..{})",
                        outer.0, outer.1
                    ),
                    at,
                );
                return (Ty::Error, None);
            }
        }
        let default = match init {
            Some(i) => {
                if let ast::Init::Expr(x) = i {
                    self.check_type_default(base_ty, Some((l, h)), x, &display);
                }
                TagDefault::Init(i)
            }
            None => TagDefault::Value(l),
        };
        (base_ty, Some(self.add_tag(display, Some((l, h)), default)))
    }

    /// The IR struct of a STRUCT type, made on first use.
    pub(super) fn struct_agg(&mut self, id: StructId) -> AggId {
        if let Some(a) = self.user.structs[id.0 as usize].agg {
            return a;
        }
        let fields = self.user.structs[id.0 as usize].fields.clone();
        let mut ir = Vec::with_capacity(fields.len());
        let mut ir_fields = Vec::with_capacity(fields.len());
        for f in &fields {
            match self.mem_type(f.ty) {
                Some((ty, elem)) => {
                    ir_fields.push(Some(ir.len() as u32));
                    ir.push(Field {
                        name: f.display.clone(),
                        ty,
                        elem,
                        // `__` starts no IEC name: the compiler's own (an SFC step's
                        // state), not listed.
                        role: if f.display.starts_with("__") {
                            FieldRole::Hidden
                        } else {
                            FieldRole::Var
                        },
                        location: None,
                    });
                }
                None => ir_fields.push(None),
            }
        }
        let base = self.user.structs[id.0 as usize].display.clone();
        let name = self.unique_agg_name(&base);
        let agg = self.module.add_agg(AggDef::Struct(StructDef {
            name,
            kind: StructKind::Struct,
            fields: ir,
        }));
        let s = &mut self.user.structs[id.0 as usize];
        s.agg = Some(agg);
        s.ir_fields = ir_fields;
        agg
    }

    /// `base`, or `base$N` if an aggregate of that name exists (a STRUCT written in a
    /// declaration, or a type named like an IR array).
    fn unique_agg_name(&self, base: &str) -> String {
        let taken = |n: &str| {
            self.module.aggs.iter().any(|a| match a {
                AggDef::Struct(s) => s.name == n,
                AggDef::Array(a) => a.name == n,
            })
        };
        if !taken(base) {
            return base.to_string();
        }
        (1..)
            .map(|k| format!("{base}${k}"))
            .find(|n| !taken(n))
            .expect("a free name")
    }

    /// The field of a STRUCT with this name: its index.
    pub(super) fn struct_field(&self, id: StructId, sym: Symbol) -> Option<usize> {
        self.user.structs[id.0 as usize]
            .fields
            .iter()
            .position(|f| f.name.sym == sym)
    }

    /// The value of an enumeration's element by name.
    /// The enumeration type named `sym`, once the types are resolved.
    pub(super) fn enum_type_named(&self, sym: Symbol) -> Option<(EnumId, ElemType)> {
        let &i = self.user.by_name.get(&sym)?;
        match self.user.named[i as usize].state {
            TypeState::Done(Ty::Enum(id, base), _) => Some((id, base)),
            _ => None,
        }
    }

    pub(super) fn enum_value_of(&self, id: EnumId, sym: Symbol) -> Option<i128> {
        self.user.enums[id.0 as usize]
            .values
            .iter()
            .find(|v| v.sym == sym)
            .map(|v| v.value)
    }

    /// An unqualified enumeration value: the one of `want` if that is an enumeration
    /// with the name, else the only one with the name.
    pub(super) fn enum_named(&self, sym: Symbol, want: Option<Ty>) -> EnumLookup {
        let Some(ids) = self.user.enum_values.get(&sym) else {
            return EnumLookup::None;
        };
        let pick = |id: EnumId| {
            let v = self.enum_value_of(id, sym).expect("registered value");
            EnumLookup::One(id, self.enum_base(id), v)
        };
        if let Some(Ty::Enum(w, _)) = want {
            if ids.contains(&w) {
                return pick(w);
            }
        }
        match ids.as_slice() {
            [one] => pick(*one),
            _ => EnumLookup::Ambiguous(ids.clone()),
        }
    }

    /// The base type of an enumeration.
    pub(super) fn enum_base(&self, id: EnumId) -> ElemType {
        self.user.enums[id.0 as usize].base
    }

    /// `Type#Value`: the enumeration and the value, or what is wrong.
    pub(super) fn qualified_enum(
        &mut self,
        ty: Ident,
        value: Ident,
        report: bool,
    ) -> Option<(EnumId, ElemType, i128)> {
        let Some(&i) = self.user.by_name.get(&ty.sym) else {
            if report {
                let n = self.text(ty.span).to_string();
                self.error(
                    codes::E_UNKNOWN_TYPE,
                    format!("unknown type `{n}` before `#`"),
                    ty.span,
                );
            }
            return None;
        };
        let (t, _) = self.resolve_named_type(i, ty.span);
        let Ty::Enum(id, base) = t else {
            if report && t != Ty::Error {
                let n = self.text(ty.span).to_string();
                self.error(
                    codes::E_TYPE_MISMATCH,
                    format!("`{n}` is not an enumeration, so `{n}#...` names no value"),
                    ty.span,
                );
            }
            return None;
        };
        match self.enum_value_of(id, value.sym) {
            Some(v) => Some((id, base, v)),
            None => {
                if report {
                    let en = &self.user.enums[id.0 as usize];
                    let names: Vec<&str> = en.values.iter().map(|v| v.display.as_str()).collect();
                    let note = format!("its values are {}", names.join(", "));
                    let msg = format!(
                        "the enumeration {} has no value `{}`",
                        en.display,
                        self.text(value.span)
                    );
                    self.diags.push(
                        Diagnostic::error(codes::E_NO_MEMBER, msg, value.span).with_note(note),
                    );
                }
                None
            }
        }
    }

    /// An expression that names a value of enumeration `id` (`Red`, `Color#Red`), as
    /// a number; `None` (and no diagnostic) for anything else.
    pub(super) fn enum_const(&mut self, e: &ast::Expr, id: EnumId) -> Option<i128> {
        match &e.kind {
            ast::ExprKind::Paren(x) => self.enum_const(x, id),
            ast::ExprKind::Name(n) => self.enum_value_of(id, n.sym),
            ast::ExprKind::EnumValue { ty, value } => {
                match self.qualified_enum(**ty, *value, false) {
                    Some((eid, _, v)) if eid == id => Some(v),
                    _ => None,
                }
            }
            _ => None,
        }
    }

    /// The function block types a value of type `ty` holds (in arrays and STRUCTs too).
    pub(super) fn fbs_in(&self, ty: Ty, out: &mut Vec<crate::types::PouId>) {
        match ty {
            Ty::Fb(p) => out.push(p),
            Ty::Array(a) => self.fbs_in(self.types.get(a).elem, out),
            Ty::Struct(s) => {
                for f in &self.user.structs[s.0 as usize].fields {
                    self.fbs_in(f.ty, out);
                }
            }
            _ => {}
        }
    }

    /// True if a value of type `ty` holds a function block instance (and so cannot be
    /// copied).
    pub(super) fn contains_fb(&self, ty: Ty) -> bool {
        let mut v = Vec::new();
        self.fbs_in(ty, &mut v);
        !v.is_empty()
    }

    /// How many scalars a value of type `ty` holds, roughly (for the size limit).
    pub(super) fn cells(&self, ty: Ty) -> u128 {
        match ty {
            Ty::Fb(_) => 16,
            Ty::Array(a) => {
                let at = self.types.get(a);
                at.total() as u128 * self.cells(at.elem)
            }
            Ty::Struct(s) => self.user.structs[s.0 as usize]
                .fields
                .iter()
                .map(|f| self.cells(f.ty))
                .sum::<u128>()
                .max(1),
            _ => 1,
        }
    }
}
