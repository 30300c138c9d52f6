//! Declarations: the POU table, variable interfaces, types, and the IR shells (instance
//! structs, function signatures) every body is lowered into.

use super::consts::{self, ConstVal};
use super::usertypes::TagDefault;
use super::{CallNode, Lowerer, PouInfo, PouIr, Storage, VarInfo};
use crate::ast::{self, PouKind, TypeSpec, VarKind};
use crate::codes;
use crate::types::{ArrayId, ArrayTy, PouId, TagId, Ty};
use plcc_ir::diag::Span;
use plcc_ir::{
    AggDef, AggId, ArrayDef, Field, FieldRole, FuncId, FuncKind, Function, MemType, StructDef,
    StructKind, Type,
};
use rustc_hash::FxHashMap;

/// The largest array the front end accepts (elements), so that a typo such as
/// `ARRAY[0..1000000000]` is an error rather than gigabytes of memory.
const MAX_ARRAY_ELEMENTS: u64 = 1 << 24;

impl<'s> Lowerer<'s> {
    /// Fills the POU table from every unit. User POUs shadow standard ones of the same
    /// name; two user POUs with one name are an error.
    pub(super) fn collect_pous(&mut self, std_units: usize) {
        let units = self.units;
        for (u, unit) in units.iter().enumerate() {
            let regions = if u < std_units {
                Vec::new()
            } else {
                self.prototype_regions(unit.file)
            };
            for (i, item) in unit.items.iter().enumerate() {
                let ast::Item::Pou(p) = item else { continue };
                if Self::is_prototype(p, &regions) {
                    self.prototypes.push(p);
                    continue;
                }
                let is_std = u < std_units;
                let id = PouId(self.pous.len() as u32);
                if let Some(&prev) = self.pou_by_name.get(&p.name.sym) {
                    let prev_info = &self.pous[prev.0 as usize];
                    if !prev_info.std {
                        let prev_span = prev_info.name.span;
                        let name = self.text(p.name.span).to_string();
                        self.diags.push(
                            plcc_ir::diag::Diagnostic::error(
                                codes::E_DUPLICATE,
                                format!("`{name}` is declared twice"),
                                p.name.span,
                            )
                            .with_label("second declaration")
                            .with_secondary(prev_span, "first declared here"),
                        );
                        continue;
                    }
                    if prev_info.kind == PouKind::FunctionBlock && !is_std {
                        let name = self.text(p.name.span).to_string();
                        self.diags.push(
                            plcc_ir::diag::Diagnostic::warning(
                                codes::W_STD_FB_REDECLARED,
                                format!("`{name}` replaces the standard function block of that name in this project"),
                                p.name.span,
                            )
                            .with_note(format!("every `{name}` instance and call of the project uses this declaration")),
                        );
                    }
                }
                let is_globals = self.interner.name(p.name.sym) == crate::GLOBALS_POU;
                let display = if is_globals {
                    crate::GLOBALS_POU.to_string()
                } else {
                    self.text(p.name.span).to_string()
                };
                if is_globals {
                    self.globals_pou = Some(id);
                }
                self.pous_mut().push(PouInfo {
                    name: p.name,
                    display,
                    kind: p.kind,
                    unit: u as u32,
                    item: i as u32,
                    vars: Vec::new(),
                    lookup: FxHashMap::default(),
                    ret: Ty::Void,
                    ret_tag: None,
                    std: is_std,
                    owner: None,
                    member: None,
                    base: None,
                });
                self.ir.push(PouIr::default());
                self.used.push(false);
                self.pou_by_name.insert(p.name.sym, id);
            }
        }
    }

    /// Resolves the variables and result type of a POU.
    pub(super) fn resolve_interface(&mut self, id: PouId) {
        let pou = self.pou_ast(id);
        let declared: usize = pou.var_blocks.iter().map(|b| b.decls.len()).sum();
        let mut vars: Vec<VarInfo> = Vec::with_capacity(declared + 1);
        let mut lookup = FxHashMap::with_capacity_and_hasher(declared + 1, Default::default());
        let kind = pou.kind;
        if kind == PouKind::Function {
            let (ret, ret_tag) = match &pou.return_type {
                Some(spec) => self.resolve_type_tagged(spec, Some(id)),
                None => (Ty::Void, None),
            };
            let at = pou.return_type.as_ref().map_or(pou.name.span, |s| s.span());
            if let Ty::Fb(_) = ret {
                self.error(
                    codes::E_UNSUPPORTED,
                    "not supported yet: FUNCTIONs returning a function block",
                    at,
                );
            } else if self.contains_fb(ret) {
                self.error(
                    codes::E_UNSUPPORTED,
                    "not supported yet: FUNCTIONs returning a STRUCT or an array that holds function block instances",
                    at,
                );
            }
            let info = &mut self.pous_mut()[id.0 as usize];
            info.ret_tag = ret_tag;
            info.ret = ret;
        }
        for (bi, block) in pou.var_blocks.iter().enumerate() {
            match block.kind {
                VarKind::Var
                | VarKind::Input
                | VarKind::Output
                | VarKind::InOut
                | VarKind::Temp
                | VarKind::External => {}
                VarKind::Inst if self.pous[id.0 as usize].owner.is_some() => {}
                VarKind::Inst => {
                    let at = self.keyword_span(block.span);
                    self.error(
                        codes::E_OO_DECLARATION,
                        "VAR_INST declares variables of a METHOD kept in its instance: only a METHOD of a FUNCTION_BLOCK or PROGRAM has them",
                        at,
                    );
                    continue;
                }
                VarKind::Global | VarKind::Access | VarKind::Config | VarKind::Stat => {
                    let what = match block.kind {
                        VarKind::Global => "VAR_GLOBAL inside a POU",
                        VarKind::Access => "VAR_ACCESS",
                        VarKind::Config => "VAR_CONFIG",
                        _ => "VAR_STAT",
                    };
                    let at = self.keyword_span(block.span);
                    self.error(
                        codes::E_UNSUPPORTED,
                        format!("not supported yet: {what}"),
                        at,
                    );
                    continue;
                }
            }
            // CODESYS's `VAR_INPUT CONSTANT` is an input the callee does not change.
            let codesys_input_constant =
                self.codesys && block.constant && block.kind == VarKind::Input;
            if block.constant && block.kind != VarKind::Var && !codesys_input_constant {
                self.error(
                    codes::E_BAD_DECLARATION,
                    "only VAR blocks can be CONSTANT",
                    block.span,
                );
            }
            for (di, decl) in block.decls.iter().enumerate() {
                let (ty, tag) = self.resolve_type_tagged(&decl.ty, Some(id));
                if let Ty::Fb(_) = ty {
                    // An instance as a VAR_IN_OUT is passed by address; as a VAR_INPUT
                    // or VAR_OUTPUT of a function block or PROGRAM it lives in the
                    // instance and is copied in from the call (or out with `=>`).
                    if kind == PouKind::Function
                        && matches!(block.kind, VarKind::Input | VarKind::Output)
                    {
                        self.error(
                            codes::E_UNSUPPORTED,
                            "not supported yet: function block instances as inputs or outputs of FUNCTIONs (use VAR_IN_OUT)",
                            decl.ty.span(),
                        );
                    }
                } else if kind != PouKind::Program
                    && matches!(block.kind, VarKind::Input | VarKind::Output)
                    && self.contains_fb(ty)
                {
                    // Inputs and outputs are copied, and an instance is not.
                    self.error(
                        codes::E_UNSUPPORTED,
                        "not supported yet: STRUCTs or arrays holding function block instances as inputs or outputs of FUNCTIONs and function blocks (use VAR_IN_OUT)",
                        decl.ty.span(),
                    );
                }
                for name in &decl.names {
                    if let Some(&prev) = lookup.get(&name.sym) {
                        let prev: &VarInfo = &vars[prev as usize];
                        let prev_span = prev.name.span;
                        let n = self.text(name.span).to_string();
                        self.diags.push(
                            plcc_ir::diag::Diagnostic::error(
                                codes::E_DUPLICATE,
                                format!("variable `{n}` is declared twice"),
                                name.span,
                            )
                            .with_secondary(prev_span, "first declared here"),
                        );
                        continue;
                    }
                    let setter = matches!(
                        self.pous[id.0 as usize].member,
                        Some(super::MemberRef::Set(_))
                    );
                    if kind == PouKind::Function && name.sym == pou.name.sym && !setter {
                        self.error(
                            codes::E_DUPLICATE,
                            "a variable cannot have the name of its FUNCTION (that name is the result)",
                            name.span,
                        );
                        continue;
                    }
                    lookup.insert(name.sym, vars.len() as u32);
                    vars.push(VarInfo {
                        name: *name,
                        // A declaration plcc adds (the implicit ENO of `crate::eno`)
                        // points at text of another name: it is shown as interned.
                        display: match self.text(name.span) {
                            t if t.eq_ignore_ascii_case(self.interner.name(name.sym)) => {
                                t.to_string()
                            }
                            _ => self.interner.name(name.sym).to_string(),
                        },
                        section: block.kind,
                        constant: block.constant && !codesys_input_constant && !ty.is_aggregate(),
                        read_only: block.constant && !codesys_input_constant && ty.is_aggregate(),
                        ty,
                        tag,
                        decl: (bi as u32, di as u32),
                        location: decl.location.as_ref().map(|(l, _)| l.to_string()),
                    });
                }
            }
        }
        let info = &mut self.pous_mut()[id.0 as usize];
        info.vars = vars;
        info.lookup = lookup;
        let n = self.pous[id.0 as usize].vars.len();
        self.ir[id.0 as usize].storage = vec![None; n];
        self.ir[id.0 as usize].param_of = vec![None; n];
    }

    /// Resolves a type as written, with its derived-type tag (the initial value and
    /// range of an alias or subrange). Constants in it (array bounds, subrange bounds)
    /// are looked up in `scope` and the globals. Errors give [`Ty::Error`].
    pub(super) fn resolve_type_tagged(
        &mut self,
        spec: &'s TypeSpec,
        scope: Option<PouId>,
    ) -> (Ty, Option<TagId>) {
        match spec {
            TypeSpec::Named(id) => self.resolve_type_tagged_named(*id),
            TypeSpec::Array { dims, elem, span } => {
                let (elem_ty, elem_tag) = self.resolve_type_tagged(elem, scope);
                if elem_ty == Ty::Error {
                    return (Ty::Error, None);
                }
                let mut bounds = Vec::new();
                for d in dims {
                    let Some((lo, hi)) = d else {
                        self.error(
                            codes::E_UNSUPPORTED,
                            "not supported yet: variable-length arrays ARRAY[*]",
                            *span,
                        );
                        return (Ty::Error, None);
                    };
                    let lo_v = self.const_int_in(lo, scope);
                    let hi_v = self.const_int_in(hi, scope);
                    let (Some(l), Some(h)) = (lo_v, hi_v) else {
                        return (Ty::Error, None);
                    };
                    let (Ok(l), Ok(h)) = (i64::try_from(l), i64::try_from(h)) else {
                        self.error(
                            codes::E_BAD_DECLARATION,
                            format!("array bounds {l}..{h}: a bound is outside the range of LINT"),
                            lo.span.to(hi.span),
                        );
                        return (Ty::Error, None);
                    };
                    if h < l {
                        self.error(
                            codes::E_BAD_DECLARATION,
                            format!(
                                "array bounds {l}..{h}: the upper bound is below the lower bound"
                            ),
                            lo.span.to(hi.span),
                        );
                        return (Ty::Error, None);
                    }
                    bounds.push((l, h));
                }
                let mut a = ArrayTy {
                    elem: elem_ty,
                    dims: bounds,
                    elem_tag,
                };
                // ARRAY[..] OF ARRAY[..] OF T is one array with more dimensions.
                if let Ty::Array(inner) = elem_ty {
                    let inner = self.types.get(inner).clone();
                    a.dims.extend(inner.dims);
                    a.elem = inner.elem;
                    a.elem_tag = inner.elem_tag;
                }
                let total = a.total() as u128 * self.cells(a.elem);
                if total > MAX_ARRAY_ELEMENTS as u128 {
                    let count = match a.total() {
                        u64::MAX => "2^64 or more".to_string(),
                        n => n.to_string(),
                    };
                    self.error(
                        codes::E_BAD_DECLARATION,
                        format!("array of {count} elements is too large"),
                        *span,
                    );
                    return (Ty::Error, None);
                }
                (Ty::Array(self.types.array(a)), None)
            }
            TypeSpec::String { wide, len, .. } => {
                let cap = match len {
                    None => crate::types::StrTy::DEFAULT_CAP,
                    Some(e) => {
                        let Some(n) = self.const_int_in(e, scope) else {
                            return (Ty::Error, None);
                        };
                        if n < 1 || n > crate::types::StrTy::MAX_CAP as i128 {
                            self.error(
                                codes::E_BAD_DECLARATION,
                                format!(
                                    "a string holds 1 to {} characters, not {n}",
                                    crate::types::StrTy::MAX_CAP
                                ),
                                e.span,
                            );
                            return (Ty::Error, None);
                        }
                        n as u32
                    }
                };
                (Ty::Str(crate::types::StrTy { wide: *wide, cap }), None)
            }
            TypeSpec::Subrange { base, lo, hi, span } => {
                let display = self.text(*span).to_string();
                self.define_subrange(display, *base, lo, hi, None, scope)
            }
            TypeSpec::Enum { values, base, span } => {
                let display = self.text(*span).to_string();
                (self.define_enum(display, values, *base, None), None)
            }
            TypeSpec::Struct { fields, .. } => (
                self.define_struct("STRUCT".to_string(), fields, scope),
                None,
            ),
            TypeSpec::Pointer { span, .. } if !self.codesys => {
                self.diags.push(plcc_ir::diag::Diagnostic::error(
                    codes::E_UNSUPPORTED,
                    "`POINTER TO` is CODESYS's: compile with `--dialect codesys`, or use `REF_TO`",
                    *span,
                ));
                (Ty::Error, None)
            }
            TypeSpec::Ref { target, .. }
            | TypeSpec::Pointer { target, .. }
            | TypeSpec::Reference { target, .. } => {
                // A STRUCT being defined may be the target (`next : REF_TO Node`).
                self.ref_depth += 1;
                let (t, _) = self.resolve_type_tagged(target, scope);
                self.ref_depth -= 1;
                if t == Ty::Error {
                    return (Ty::Error, None);
                }
                // Without the target's derived-type tag, so that references to the
                // same type are one type.
                let r = crate::types::RefTy {
                    iface: None,
                    target: t,
                    tag: None,
                    pointer: matches!(spec, TypeSpec::Pointer { .. }),
                    auto: matches!(spec, TypeSpec::Reference { .. }),
                };
                (Ty::Ref(self.types.reference(r)), None)
            }
        }
    }

    /// Resolves a type by name: elementary, declared by TYPE, or a function block.
    pub(super) fn resolve_type_tagged_named(&mut self, id: ast::Ident) -> (Ty, Option<TagId>) {
        let name = self.sym_name(id.sym).to_string();
        if let Some(e) = plcc_ir::ElemType::from_name(&name) {
            if e == plcc_ir::ElemType::Ref {
                self.error(
                    codes::E_UNKNOWN_TYPE,
                    format!("unknown type `{}`", self.text(id.span)),
                    id.span,
                );
                return (Ty::Error, None);
            }
            return (Ty::Elem(e), None);
        }
        if let Some(&i) = self.user.by_name.get(&id.sym) {
            return self.resolve_named_type(i, id.span);
        }
        if let Some(&k) = self.classes.iface_by_name.get(&id.sym) {
            // A variable of an interface type holds the address of an instance.
            let r = crate::types::RefTy {
                iface: Some(k),
                target: Ty::Void,
                tag: None,
                pointer: false,
                auto: false,
            };
            return (Ty::Ref(self.types.reference(r)), None);
        }
        if let Some(&p) = self.pou_by_name.get(&id.sym) {
            return match self.pou(p).kind {
                PouKind::FunctionBlock => (Ty::Fb(p), None),
                k => {
                    let what = if k == PouKind::Program {
                        "PROGRAM"
                    } else {
                        "FUNCTION"
                    };
                    self.error(
                        codes::E_NOT_A_TYPE,
                        format!("`{}` is a {what}, not a type", self.text(id.span)),
                        id.span,
                    );
                    (Ty::Error, None)
                }
            };
        }
        let written = self.text(id.span).to_string();
        let mut d = plcc_ir::diag::Diagnostic::error(
            codes::E_UNKNOWN_TYPE,
            format!("unknown type `{written}`"),
            id.span,
        );
        if let Some((lib, _)) = written.split_once('.') {
            // A CPDev `LIBRARY.TYPE`: say that the library is not the problem.
            d = d.with_note(format!(
                "the qualifier `{lib}` names the library the type comes from; \
                 plcc looks the type up as `{name}` and knows no such type"
            ));
        }
        self.unknown_block(id, d);
        (Ty::Error, None)
    }

    /// Evaluates a constant integer expression (array bounds) in `scope` and the
    /// globals; reports what is wrong.
    pub(super) fn const_int_in(&mut self, e: &ast::Expr, scope: Option<PouId>) -> Option<i128> {
        match self.const_eval_in(e, scope, None) {
            Some((ConstVal::Int(v), _)) => Some(v),
            Some(_) => {
                self.error(
                    codes::E_NOT_CONSTANT,
                    "expected an integer constant",
                    e.span,
                );
                None
            }
            None => {
                self.error(
                    codes::E_NOT_CONSTANT,
                    "expected a constant expression (literals and VAR CONSTANTs)",
                    e.span,
                );
                None
            }
        }
    }

    /// Evaluates a constant expression in the scope of a POU: literals, operators and
    /// the POU's VAR CONSTANTs.
    pub(super) fn const_eval(&mut self, e: &ast::Expr, pou: PouId) -> Option<(ConstVal, Ty)> {
        self.const_eval_as(e, pou, None)
    }

    /// [`Self::const_eval`] for a value of type `want` (which gives untyped literals
    /// a width where one is needed).
    pub(super) fn const_eval_as(
        &mut self,
        e: &ast::Expr,
        pou: PouId,
        want: Option<Ty>,
    ) -> Option<(ConstVal, Ty)> {
        self.const_eval_in(e, Some(pou), want)
    }

    /// [`Self::const_eval_as`] in the scope of a POU, or of the globals alone (`None`:
    /// in TYPE declarations).
    pub(super) fn const_eval_in(
        &mut self,
        e: &ast::Expr,
        scope: Option<PouId>,
        want: Option<Ty>,
    ) -> Option<(ConstVal, Ty)> {
        let own = scope.map(|p| self.pou_ast(p));
        // A POU's own constants first, then the global ones.
        let globals = self
            .globals_pou
            .filter(|&g| Some(g) != scope)
            .map(|g| self.pou_ast(g));
        let all_globals = self.globals_pou.map(|g| self.pou_ast(g));
        let interner = &*self.interner;
        type Eval<'e> = dyn Fn(&ast::Expr, u32, Option<Ty>) -> Option<(ConstVal, Ty)> + 'e;
        type Sym = crate::intern::Symbol;
        let declares = |a: &ast::Pou, sym: Sym| {
            a.var_blocks
                .iter()
                .flat_map(|b| &b.decls)
                .any(|d| d.names.iter().any(|n| n.sym == sym))
        };
        let lookup = |list: Option<Sym>, sym: Sym, depth: u32, this: &Eval<'_>| {
            // `GVL.c`: a constant of the global variable list `GVL`, where `GVL` names
            // no variable of the POU.
            if list.is_some_and(|l| own.is_some_and(|a| declares(a, l))) {
                return None;
            }
            let scopes = match list {
                None => own.into_iter().chain(globals),
                Some(_) => None.into_iter().chain(all_globals),
            };
            for block in scopes.flat_map(|a| a.var_blocks.iter()) {
                if !block.constant || list.is_some_and(|l| block.list.is_none_or(|n| n.sym != l)) {
                    continue;
                }
                for decl in &block.decls {
                    if decl.names.iter().any(|n| n.sym == sym) {
                        let Some(ast::Init::Expr(init)) = &decl.init else {
                            return None;
                        };
                        // The constant's declared type wins over the literal's.
                        let declared = match &decl.ty {
                            TypeSpec::Named(id) => {
                                plcc_ir::ElemType::from_name(interner.name(id.sym)).map(Ty::Elem)
                            }
                            _ => None,
                        };
                        let (v, t) = this(init, depth + 1, declared)?;
                        return Some((v, declared.unwrap_or(t)));
                    }
                }
            }
            None
        };
        consts::eval(e, interner, &lookup, want)
    }

    /// Checks every VAR_EXTERNAL against the global it names: it must exist and have
    /// the same type.
    pub(super) fn check_externals(&mut self) {
        let g = self.globals_pou;
        let mut errs = Vec::new();
        let mut broken = Vec::new();
        for (pi, p) in self.pous.iter().enumerate() {
            for (vi, v) in p
                .vars
                .iter()
                .enumerate()
                .filter(|(_, v)| v.section == VarKind::External)
            {
                let before = errs.len();
                let global = g.and_then(|g| {
                    let gp = &self.pous[g.0 as usize];
                    gp.var(v.name.sym).map(|i| gp.vars[i as usize].ty)
                });
                match global {
                    None => errs.push((
                        codes::E_UNDECLARED,
                        format!(
                            "there is no global variable (VAR_GLOBAL) named `{}`",
                            v.display
                        ),
                        v.name.span,
                    )),
                    Some(t) if t != v.ty && t != Ty::Error && v.ty != Ty::Error => errs.push((
                        codes::E_TYPE_MISMATCH,
                        format!(
                            "`{}` is declared here as {}, but the global is {}",
                            v.display,
                            self.ty_name(v.ty),
                            self.ty_name(t)
                        ),
                        v.name.span,
                    )),
                    _ => {}
                }
                if errs.len() > before {
                    broken.push((pi, vi));
                }
            }
        }
        for (code, msg, span) in errs {
            self.error(code, msg, span);
        }
        // Uses of a broken external report nothing more.
        for (pi, vi) in broken {
            self.pous_mut()[pi].vars[vi].ty = Ty::Error;
        }
    }

    /// The data object of the globals and `init_globals`, which cold start runs
    /// first.
    pub(super) fn create_globals(&mut self) {
        let Some(g) = self.globals_pou else { return };
        let ir = &self.ir[g.0 as usize];
        let (Some(agg), Some(init)) = (ir.agg, ir.init) else {
            return;
        };
        let data = self.module.add_data(plcc_ir::DataDef {
            name: crate::GLOBALS_DATA.to_string(),
            ty: MemType::Agg(agg),
            elem: None,
            kind: plcc_ir::DataKind::Global,
            location: None,
        });
        self.globals_data = Some(data);
        self.module.globals = Some(data);
        let mut f = Function::new("$globals$cold_start", FuncKind::Init, vec![], None);
        {
            let mut b = plcc_ir::FuncBuilder::new(&mut f);
            let addr = b.global_addr(data);
            b.call(init, None, vec![addr]);
            b.ret(None);
        }
        self.module.init_globals = Some(self.module.add_func(f));
    }

    /// Reports function blocks that contain an instance of themselves (directly, in
    /// an array, or through other function blocks): they would be infinitely large.
    /// Returns false if there is one (no IR can be built then).
    pub(super) fn check_containment(&mut self) -> bool {
        let n = self.pous.len();
        // Edges: POU -> (FB type of a variable, the variable's name span).
        let mut edges: Vec<Vec<(usize, Span)>> = vec![Vec::new(); n];
        for (i, p) in self.pous.iter().enumerate() {
            if let Some(b) = p.base {
                edges[i].push((b.0 as usize, p.name.span));
            }
            for v in &p.vars {
                if v.section == VarKind::InOut {
                    continue;
                }
                let mut fbs = Vec::new();
                self.fbs_in(v.ty, &mut fbs);
                for fb in fbs {
                    edges[i].push((fb.0 as usize, v.name.span));
                }
            }
        }
        let mut colour = vec![0u8; n];
        let mut ok = true;
        for start in 0..n {
            if colour[start] != 0 {
                continue;
            }
            let mut stack: Vec<(usize, usize)> = vec![(start, 0)];
            colour[start] = 1;
            while let Some(&mut (node, ref mut next)) = stack.last_mut() {
                if *next < edges[node].len() {
                    let (to, span) = edges[node][*next];
                    *next += 1;
                    if colour[to] == 1 {
                        let chain: Vec<String> = stack
                            .iter()
                            .skip_while(|(x, _)| *x != to)
                            .map(|(x, _)| self.pous[*x].display.clone())
                            .chain(std::iter::once(self.pous[to].display.clone()))
                            .collect();
                        self.diags.push(
                            plcc_ir::diag::Diagnostic::error(
                                codes::E_CONTAINS_ITSELF,
                                format!(
                                    "`{}` contains an instance of itself: {}",
                                    self.pous[to].display,
                                    chain.join(" -> ")
                                ),
                                span,
                            )
                            .with_label("this instance closes the chain"),
                        );
                        ok = false;
                    } else if colour[to] == 0 {
                        colour[to] = 1;
                        stack.push((to, 0));
                    }
                } else {
                    colour[node] = 2;
                    stack.pop();
                }
            }
        }
        ok
    }

    /// Marks the POUs whose IR is wanted: every user POU and the standard FBs they use.
    pub(super) fn mark_used(&mut self) {
        let mut stack: Vec<PouId> = Vec::new();
        for (i, p) in self.pous.iter().enumerate() {
            if !p.std {
                stack.push(PouId(i as u32));
            }
        }
        // Only user POUs that are still the ones their name resolves to, and the
        // members of classes.
        stack.retain(|&id| {
            self.pou_by_name.get(&self.pou(id).name.sym) == Some(&id)
                || self.pou(id).owner.is_some()
        });
        while let Some(id) = stack.pop() {
            if self.used[id.0 as usize] {
                continue;
            }
            self.used[id.0 as usize] = true;
            let tys: Vec<Ty> = self.pou(id).vars.iter().map(|v| v.ty).collect();
            let ret = self.pou(id).ret;
            for t in tys.into_iter().chain(std::iter::once(ret)) {
                self.fbs_in(t, &mut stack);
                // A reference to an instance needs its type, not its contents.
                if let Ty::Ref(r) = t {
                    if let Ty::Fb(p) = self.types.get_ref(r).target {
                        stack.push(p);
                    }
                }
            }
            // Standard FBs called by name in a body are found when lowering; a std FB
            // that is only used through a variable is covered above.
        }
    }

    /// Creates the instance structs and the (empty) functions of every used POU, so
    /// that bodies can refer to any of them.
    pub(super) fn create_shells(&mut self) {
        // Structs first (empty), so fields can refer to any of them.
        for i in 0..self.pous.len() {
            if !self.used[i] {
                continue;
            }
            let p = &self.pous[i];
            let kind = match p.kind {
                PouKind::Program => StructKind::Program,
                PouKind::FunctionBlock => StructKind::FunctionBlock,
                PouKind::Function => continue,
            };
            let agg = self.module.add_agg(AggDef::Struct(StructDef {
                name: p.display.clone(),
                kind,
                fields: Vec::new(),
            }));
            self.ir[i].agg = Some(agg);
        }
        // Bases before the FBs that extend them (their fields come first).
        let mut order: Vec<usize> = (0..self.pous.len()).collect();
        order.sort_by_key(|&i| self.lineage(PouId(i as u32)).len());
        for i in order {
            if !self.used[i] {
                continue;
            }
            let id = PouId(i as u32);
            match self.pous[i].kind {
                PouKind::Function => self.create_function_shell(id),
                PouKind::Program | PouKind::FunctionBlock => self.create_instance_shell(id),
            }
        }
    }

    pub(super) fn create_function_shell(&mut self, id: PouId) {
        let mut params = Vec::new();
        if self.pou(id).owner.is_some() {
            // A METHOD or accessor: the instance's address first.
            params.push(Type::Ptr);
        }
        let n = self.pou(id).vars.len();
        for vi in 0..n {
            let v = &self.pous[id.0 as usize].vars[vi];
            let ty = match v.section {
                // A STRUCT or array input is passed by address; the callee copies it.
                VarKind::Input if v.ty.is_aggregate() => Type::Ptr,
                VarKind::Input => v.ty.ir().unwrap_or(Type::I32),
                VarKind::InOut | VarKind::Output => Type::Ptr,
                _ => continue,
            };
            self.ir[id.0 as usize].param_of[vi] = Some(params.len() as u32);
            params.push(ty);
        }
        let ret_ty = self.pou(id).ret;
        let ret = if ret_ty.is_aggregate() {
            // The caller passes where the result goes, as a last parameter.
            self.ir[id.0 as usize].result_param = Some(params.len() as u32);
            params.push(Type::Ptr);
            None
        } else {
            ret_ty.ir()
        };
        let mut f = Function::new(
            self.pou(id).display.clone(),
            FuncKind::Function,
            params,
            ret,
        );
        f.span = Some(self.pou(id).name.span);
        let fid = self.module.add_func(f);
        self.ir[id.0 as usize].body = Some(fid);
    }

    fn create_instance_shell(&mut self, id: PouId) {
        let agg = self.ir[id.0 as usize].agg.expect("instance struct");
        let is_std = self.pou(id).std;
        let mut fields = Vec::new();
        if let Some(b) = self.pou(id).base {
            // The base's fields first, the class id among them: a derived
            // instance's address is a valid base address.
            if let Some(AggDef::Struct(s)) = self.ir[b.0 as usize]
                .agg
                .map(|a| &self.module.aggs[a.index()])
            {
                fields = s.fields.clone();
            }
        } else if self.is_class(id) {
            fields.push(Field {
                name: "__class".to_string(),
                ty: MemType::Scalar(super::dispatch::CLASS_ID),
                elem: None,
                role: FieldRole::Hidden,
                location: None,
            });
        }
        let n = self.pou(id).vars.len();
        for vi in 0..n {
            let v = self.pous[id.0 as usize].vars[vi].clone();
            if v.constant {
                self.fold_constant(id, vi);
                continue;
            }
            if matches!(v.section, VarKind::Temp | VarKind::External) {
                continue;
            }
            // `__` starts no IEC name: the compiler's own variables (an SFC's clock
            // and controls), and the inputs of its own FBs, are not listed.
            let internal =
                v.display.starts_with("__") || is_std && self.pou(id).display.starts_with("__");
            let role = match v.section {
                VarKind::Input | VarKind::Var if internal => FieldRole::Hidden,
                VarKind::Input => FieldRole::Input,
                VarKind::Output => FieldRole::Output,
                VarKind::InOut => FieldRole::InOut,
                _ if is_std => FieldRole::Hidden,
                _ => FieldRole::Var,
            };
            let (ty, elem) = if role == FieldRole::InOut {
                (MemType::Scalar(Type::Ptr), None)
            } else {
                match self.mem_type(v.ty) {
                    Some(t) => t,
                    None => continue,
                }
            };
            self.ir[id.0 as usize].storage[vi] = Some(Storage::Field(fields.len() as u32));
            fields.push(Field {
                name: v.display.clone(),
                ty,
                elem,
                role,
                location: v.location.clone(),
            });
        }
        // The VAR_INST variables of its METHODs live in the instance.
        self.method_instance_fields(id, &mut fields);
        if let AggDef::Struct(s) = &mut self.module.aggs[agg.index()] {
            s.fields = fields;
        }
        let (kind, name) = match self.pou(id).kind {
            PouKind::Program => (FuncKind::ProgramBody, self.pou(id).display.clone()),
            _ => (FuncKind::FbBody, self.pou(id).display.clone()),
        };
        let mut body = Function::new(name.clone(), kind, vec![Type::Ptr], None);
        body.span = Some(self.pou(id).name.span);
        let body = self.module.add_func(body);
        let mut init = Function::new(
            format!("{name}$init"),
            FuncKind::Init,
            vec![Type::Ptr],
            None,
        );
        init.span = Some(self.pou(id).name.span);
        let init = self.module.add_func(init);
        let ir = &mut self.ir[id.0 as usize];
        ir.body = Some(body);
        ir.init = Some(init);
    }

    /// Folds a VAR CONSTANT to its value; a constant needs a constant initial value.
    pub(super) fn fold_constant(&mut self, id: PouId, vi: usize) {
        let v = self.pous[id.0 as usize].vars[vi].clone();
        let ast = self.pou_ast(id);
        let decl = &ast.var_blocks[v.decl.0 as usize].decls[v.decl.1 as usize];
        if let Ty::Enum(eid, _) = v.ty {
            let default = self.user.enums[eid.0 as usize].default;
            let value = match &decl.init {
                None => default,
                Some(ast::Init::Expr(e)) => self.enum_const(e, eid).unwrap_or_else(|| {
                    self.not_an_enum_value(e.span, eid);
                    default
                }),
                Some(other) => {
                    self.not_an_enum_value(other.span(), eid);
                    default
                }
            };
            self.record_constant(id, vi, ConstVal::Int(value));
            return;
        }
        let tag = v.tag.map(|t| {
            (
                self.user.tags[t.0 as usize].range,
                self.user.tags[t.0 as usize].default,
            )
        });
        let value = match &decl.init {
            Some(ast::Init::Expr(e)) => match self.const_eval_as(e, id, Some(v.ty)) {
                Some((c, _)) => Some(c),
                None => {
                    self.error(
                        codes::E_NOT_CONSTANT,
                        "the initial value of a CONSTANT must be a constant expression",
                        e.span,
                    );
                    None
                }
            },
            Some(other) => {
                self.error(
                    codes::E_UNSUPPORTED,
                    "not supported yet: constants of array or structured types",
                    other.span(),
                );
                None
            }
            None => match tag {
                Some((_, TagDefault::Value(x))) => Some(ConstVal::Int(x)),
                Some((_, TagDefault::Init(ast::Init::Expr(e)))) => self
                    .const_eval_in(e, None, Some(v.ty))
                    .map(|(c, _)| c)
                    .or(Some(ConstVal::zero_of(v.ty))),
                _ => Some(ConstVal::zero_of(v.ty)),
            },
        };
        // After an error the constant still gets a value (the type's zero), so that
        // lowering the POU's init and body does not report it a second time.
        let failed = ConstVal::zero_of(v.ty);
        let Some(mut value) = value else {
            if v.ty.elem().is_some() {
                self.record_constant(id, vi, failed);
            }
            return;
        };
        if v.ty.elem().is_none() {
            if v.ty != Ty::Error {
                self.error(
                    codes::E_UNSUPPORTED,
                    "not supported yet: constants that are not of an elementary type",
                    v.name.span,
                );
            }
            return;
        }
        let span = decl.init.as_ref().map_or(v.name.span, |i| i.span());
        match value.coerce(v.ty) {
            Ok(c) => value = c,
            Err(msg) => {
                self.error(codes::E_TYPE_MISMATCH, msg, span);
                value = failed;
            }
        }
        if let (Some((Some((lo, hi)), _)), ConstVal::Int(x)) = (tag, value) {
            if x < lo || x > hi {
                let name = self.user.tags[v.tag.expect("tagged").0 as usize]
                    .name
                    .clone();
                self.error(
                    codes::E_LITERAL_RANGE,
                    format!("{x} is out of the range of {name} ({lo}..{hi})"),
                    span,
                );
            }
        }
        self.record_constant(id, vi, value);
    }

    fn record_constant(&mut self, id: PouId, vi: usize, value: ConstVal) {
        let ir = &mut self.ir[id.0 as usize];
        ir.storage[vi] = Some(Storage::Const(ir.consts.len() as u32));
        ir.consts.push(value);
    }

    /// The IR memory type of a variable type (and its IEC type for scalars).
    pub(super) fn mem_type(&mut self, ty: Ty) -> Option<(MemType, Option<plcc_ir::ElemType>)> {
        match ty {
            Ty::Elem(e) => Some((MemType::Scalar(e.ir_type()), Some(e))),
            Ty::Fb(p) => self.ir[p.0 as usize].agg.map(|a| (MemType::Agg(a), None)),
            Ty::Array(a) => Some((MemType::Agg(self.array_agg(a, 0)), None)),
            Ty::Struct(s) => Some((MemType::Agg(self.struct_agg(s)), None)),
            Ty::Enum(_, e) => Some((MemType::Scalar(e.ir_type()), Some(e))),
            Ty::Str(s) => Some((MemType::Agg(self.string_agg(s)), None)),
            // Not listed by the runner: addresses differ between machines.
            Ty::Ref(_) => Some((MemType::Scalar(plcc_ir::Type::Ptr), None)),
            _ => None,
        }
    }

    /// The IR array for dimension `dim` (and the ones after it) of an array type.
    pub(super) fn array_agg(&mut self, a: ArrayId, dim: u32) -> AggId {
        if let Some(&agg) = self.array_aggs.get(&(a, dim)) {
            return agg;
        }
        let at = self.types.get(a).clone();
        let (elem, elem_type) = if (dim as usize) + 1 < at.dims.len() {
            (MemType::Agg(self.array_agg(a, dim + 1)), None)
        } else {
            self.mem_type(at.elem)
                .unwrap_or((MemType::Scalar(Type::I8), None))
        };
        let (lo, hi) = at.dims[dim as usize];
        let name = format!("arr{}", self.module.aggs.len());
        let agg = self.module.add_agg(AggDef::Array(ArrayDef {
            name,
            elem,
            elem_type,
            len: (hi - lo + 1) as u32,
            lower: lo,
        }));
        self.array_aggs.insert((a, dim), agg);
        agg
    }

    /// Reports calls that form a cycle (IEC 61131-3 forbids recursion), through
    /// POU bodies and ACTIONs alike.
    pub(super) fn check_recursion(&mut self) {
        // Nodes: the POUs, then the actions.
        let n_pous = self.pous.len();
        let mut actions: Vec<FuncId> = self.actions.values().copied().collect();
        actions.sort_unstable_by_key(|f| f.index());
        let index = |node: CallNode| match node {
            CallNode::Pou(p) => p.0 as usize,
            CallNode::Action(f) => {
                n_pous
                    + actions
                        .binary_search_by_key(&f.index(), |a| a.index())
                        .expect("an action")
            }
        };
        let n = n_pous + actions.len();
        let mut edges: Vec<Vec<(usize, Span)>> = vec![Vec::new(); n];
        for &(from, to, span) in &self.calls {
            edges[index(from)].push((index(to), span));
        }
        let display = |x: usize| {
            if x < n_pous {
                self.pous[x].display.clone()
            } else {
                self.module.funcs[actions[x - n_pous].index()].name.clone()
            }
        };
        // Iterative DFS with colours; a back edge closes a cycle.
        let mut colour = vec![0u8; n];
        let mut reported = vec![false; n];
        let mut found = Vec::new();
        for start in 0..n {
            if colour[start] != 0 {
                continue;
            }
            let mut stack: Vec<(usize, usize)> = vec![(start, 0)];
            colour[start] = 1;
            while let Some(&mut (node, ref mut next)) = stack.last_mut() {
                if *next < edges[node].len() {
                    let (t, span) = edges[node][*next];
                    *next += 1;
                    if colour[t] == 1 {
                        if !reported[t] {
                            reported[t] = true;
                            let path: Vec<String> = stack
                                .iter()
                                .skip_while(|(x, _)| *x != t)
                                .map(|(x, _)| display(*x))
                                .chain(std::iter::once(display(t)))
                                .collect();
                            found.push((path.join(" -> "), span));
                        }
                    } else if colour[t] == 0 {
                        colour[t] = 1;
                        stack.push((t, 0));
                    }
                } else {
                    colour[node] = 2;
                    stack.pop();
                }
            }
        }
        for (path, span) in found {
            self.diags.push(
                plcc_ir::diag::Diagnostic::error(
                    codes::E_RECURSION,
                    format!("recursion is not allowed: {path}"),
                    span,
                )
                .with_label("this call closes the cycle")
                .with_note("IEC 61131-3 forbids recursive calls, so every frame can be static"),
            );
        }
    }
}
