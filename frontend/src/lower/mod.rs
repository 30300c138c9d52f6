//! Semantic analysis and lowering to the IR, in one pass over the syntax tree.
//!
//! The work goes in phases: collect every POU of every file (and the standard function
//! blocks) and every TYPE declaration, resolve the types, then the POUs' interfaces
//! (variables and types), give each POU an IR shell (the instance struct, the body and
//! init functions), then check and lower every body.
//! Type checking and IR emission happen together: an expression's type is inferred
//! first (so that untyped literals take the type their context wants), then it is
//! emitted. Errors become diagnostics with codes and spans; an expression with an
//! error has type [`Ty::Error`], which every later check accepts silently, so one
//! mistake gives one diagnostic.

mod actions;
mod aggregates;
mod bcd;
mod body;
mod builtins;
mod calls;
mod case;
mod classes;
mod consts;
mod dates;
mod decls;
mod dispatch;
mod en_eno;
mod expr;
mod init;
mod literals;
mod methods;
#[cfg(test)]
mod oo_tests;
mod partial;
mod places;
mod properties;
mod prototypes;
mod qualified;
mod refs;
mod selection;
mod split;
mod stmt;
mod strings;
mod tasks;
mod timestr;
mod typing;
mod unknown;
mod usertypes;

use crate::ast::{self, Ident, PouKind, SourceUnit, VarKind};
use crate::codes;
use crate::intern::{Interner, Symbol};
use crate::source::SourceMap;
use crate::types::{ArrayId, PouId, TagId, Ty, TypeTable};
use plcc_ir::diag::{Diagnostic, Span};
use plcc_ir::{AggId, FuncId, Module};
use rustc_hash::FxHashMap;

pub use builtins::STANDARD_FUNCTIONS;
pub use consts::ConstVal;
pub use split::ParallelBodies;

/// A node of the call graph the recursion check walks: a POU's body, or an ACTION
/// (a body of its own, called by name).
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
pub(crate) enum CallNode {
    /// The body of a POU.
    Pou(PouId),
    /// An ACTION, by its function.
    Action(FuncId),
}

/// What to build.
#[derive(Clone, Debug, Default)]
pub struct LowerOptions {
    /// The PROGRAMs to instantiate and run, by name; all of them when empty.
    pub programs: Vec<String>,
    /// The CODESYS dialect: `POINTER TO`, `ADR` of anything and pointers as numbers
    /// (the module is then [`plcc_ir::Module::unchecked_pointers`]), `VAR_INPUT
    /// CONSTANT`, implicit conversions between bit strings and numbers.
    pub codesys: bool,
    /// The dialect was chosen (`--dialect`). Otherwise a PLCopen file written by a
    /// CODESYS-based editor puts the build in the CODESYS dialect
    /// ([`crate::plcopen::Dialect`]).
    pub dialect_given: bool,
    /// How PLCopen XML files are read (the profile, the rung rules).
    pub plcopen: crate::plcopen::Options,
    /// How sequential function charts evolve (`--sfc`).
    pub sfc: crate::sfc::Profile,
    /// Library files (`--lib`): declarations for the rest of the build. Their PROGRAMs
    /// run only when `programs` or a configuration names them.
    pub library: Vec<plcc_ir::diag::FileId>,
    /// Keep the C code of pragmas where statements stand (`inline_c` in the IR), for
    /// a target that copies it into its output (`c`); otherwise such pragmas are
    /// skipped with warning W0010.
    pub inline_c: bool,
    /// Diagnostics only (`plcc check`, the language server): each function's body is
    /// dropped as soon as it is lowered, so that memory stays near the syntax trees'
    /// and the next body reuses it. [`crate::Compiled::module`] then holds the
    /// functions' signatures, the globals and the tables, but no bodies.
    pub check_only: bool,
    /// What to print of the build's files ([`crate::Compiled::printed`]).
    pub print: PrintAs,
    /// When the POU bodies are lowered on two threads (the result is the same).
    pub parallel_bodies: ParallelBodies,
}

/// What [`crate::compile`] prints of a build that compiles.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
pub enum PrintAs {
    /// Nothing.
    #[default]
    Nothing,
    /// Structured Text ([`crate::print`]; `--emit st`).
    St,
    /// A PLCopen XML project ([`crate::plcopen::export`]; `--emit plcopen`).
    Plcopen,
}

/// One declared variable of a POU.
#[derive(Clone, Debug)]
pub struct VarInfo {
    /// The name as declared.
    pub name: Ident,
    /// The declared spelling (for the IR and the runner).
    pub display: String,
    /// Its section.
    pub section: VarKind,
    /// `CONSTANT` of an elementary type: folded to its value.
    pub constant: bool,
    /// `CONSTANT` of a string, array or STRUCT type: a variable that may not be
    /// written.
    pub read_only: bool,
    /// The type.
    pub ty: Ty,
    /// Its derived type (alias, subrange), whose initial value and range apply.
    pub tag: Option<TagId>,
    /// Index of its declaration: (var block, declaration) in the POU's AST.
    pub decl: (u32, u32),
    /// `AT %...`, if located.
    pub location: Option<String>,
}

/// Where a variable lives once lowered.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum Storage {
    /// A field of the instance struct (PROGRAM/FB variables).
    Field(u32),
    /// A stack slot of the body function (FUNCTION variables, VAR_TEMP).
    Slot(plcc_ir::SlotId),
    /// A VAR CONSTANT folded to its value (index into the POU's constants).
    Const(u32),
}

/// One POU with its resolved interface.
#[derive(Clone, Debug)]
pub struct PouInfo {
    /// Its name.
    pub name: Ident,
    /// The declared spelling.
    pub display: String,
    /// PROGRAM, FUNCTION or FUNCTION_BLOCK.
    pub kind: PouKind,
    /// Which parsed unit and item it is.
    pub unit: u32,
    /// Item index within the unit.
    pub item: u32,
    /// Its variables in declaration order.
    pub vars: Vec<VarInfo>,
    /// Variable lookup by name.
    pub lookup: FxHashMap<Symbol, u32>,
    /// A FUNCTION's result type (`Void` if none; `Void` for the others).
    pub ret: Ty,
    /// The derived type of a FUNCTION's result, if any.
    pub ret_tag: Option<TagId>,
    /// Part of the built-in standard library.
    pub std: bool,
    /// A METHOD or property accessor: the FUNCTION_BLOCK (or PROGRAM) it belongs to.
    /// Interface members have none.
    pub owner: Option<PouId>,
    /// A METHOD or property accessor: which member of its item it is.
    pub member: Option<MemberRef>,
    /// `EXTENDS base` of a FUNCTION_BLOCK, resolved.
    pub base: Option<PouId>,
}

/// Which member of a POU's (or an INTERFACE's) AST a method POU is.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum MemberRef {
    /// `oo.methods[i]`.
    Method(u32),
    /// The getter of `oo.properties[i]`.
    Get(u32),
    /// The setter of `oo.properties[i]`.
    Set(u32),
}

impl PouInfo {
    /// The variable with this name.
    pub fn var(&self, sym: Symbol) -> Option<u32> {
        self.lookup.get(&sym).copied()
    }
}

/// The IR objects made for a POU.
#[derive(Clone, Debug, Default)]
struct PouIr {
    /// The instance struct (PROGRAM, FUNCTION_BLOCK).
    agg: Option<AggId>,
    /// The body function.
    body: Option<FuncId>,
    /// The init function (PROGRAM, FUNCTION_BLOCK).
    init: Option<FuncId>,
    /// How each variable is stored (filled when the body is lowered, for fields
    /// before).
    storage: Vec<Option<Storage>>,
    /// Values of VAR CONSTANTs (indexed by `Storage::Const`).
    consts: Vec<ConstVal>,
    /// For FUNCTIONs: parameter index of each input/in-out/output variable.
    param_of: Vec<Option<u32>>,
    /// For FUNCTIONs returning a STRUCT or an array: the parameter that points where
    /// the caller wants the result.
    result_param: Option<u32>,
}

/// The state of one build: parsed units, the POU table, the module being built.
pub struct Lowerer<'s> {
    pub(crate) sources: &'s SourceMap,
    pub(crate) interner: &'s mut Interner,
    pub(crate) units: &'s [&'s SourceUnit],
    /// The POU table, shared with [`Lowerer::fork`]'s copies (it does not change
    /// once the interfaces are resolved; before, [`Lowerer::pous_mut`] writes it).
    pub(crate) pous: std::sync::Arc<Vec<PouInfo>>,
    pub(crate) pou_by_name: FxHashMap<Symbol, PouId>,
    pub(crate) types: TypeTable,
    pub(crate) user: usertypes::UserTypes<'s>,
    pub(crate) diags: Vec<Diagnostic>,
    pub(crate) module: Module,
    ir: Vec<PouIr>,
    array_aggs: FxHashMap<(ArrayId, u32), AggId>,
    /// FUNCTIONs under `{disable code generation}` (see `prototypes`).
    prototypes: Vec<&'s ast::Pou>,
    /// The function of each action, by its POU and name.
    actions: FxHashMap<(PouId, Symbol), FuncId>,
    /// The actions to lower: POU, function, declaration.
    action_bodies: Vec<(PouId, FuncId, &'s ast::Action)>,
    /// The IR array of each string type.
    string_aggs: FxHashMap<crate::types::StrTy, AggId>,
    helpers: FxHashMap<String, FuncId>,
    /// Calls between POUs and actions (caller, callee, span), for the recursion check.
    calls: Vec<(CallNode, CallNode, Span)>,
    /// POUs whose IR is wanted (user POUs, and standard FBs that are used).
    used: Vec<bool>,
    /// Standard-library FUNCTIONs first used while lowering, whose bodies are still
    /// to be lowered.
    pending: Vec<PouId>,
    /// Names declared by constructs reported as not supported (variables of
    /// sections plcc does not compile): using them gives no second error.
    unsupported_names: rustc_hash::FxHashSet<Symbol>,
    /// Uses of block names nothing declares, merged at the end (see `unknown`).
    unknown_uses: Vec<unknown::UnknownUse>,
    /// The synthetic POU holding every VAR_GLOBAL (see `crate::GLOBALS_POU`).
    pub(crate) globals_pou: Option<PouId>,
    /// The data object of the globals.
    pub(crate) globals_data: Option<plcc_ir::DataId>,
    /// Files in the CPDev dialect (`.cst`, see `Lang::Cst`).
    pub(crate) cpdev_files: Vec<plcc_ir::diag::FileId>,
    /// The CODESYS dialect (`LowerOptions::codesys`).
    pub(crate) codesys: bool,
    /// [`LowerOptions::inline_c`].
    pub(crate) inline_c: bool,
    /// Drop each body once lowered ([`LowerOptions::check_only`]).
    pub(crate) drop_bodies: bool,
    /// The PROGRAMs to run (`LowerOptions::programs`).
    run_programs: Vec<String>,
    /// The library files (`LowerOptions::library`).
    library: Vec<plcc_ir::diag::FileId>,
    /// The data objects of PROGRAM instances, by instance name (see
    /// `Lowerer::program_data`).
    program_data: FxHashMap<String, plcc_ir::DataId>,
    /// How many reference targets are being resolved (see `TypeState::Building`).
    pub(crate) ref_depth: u32,
    /// METHODs, PROPERTYs, INTERFACEs, class ids (see `classes`).
    pub(crate) classes: classes::Classes,
    /// The types given to compiler temporaries (IL's spilled current results), for
    /// printing the build as ST.
    pub(crate) temp_types: crate::print::TempTypes,
    /// The function each body is built in, its tables' room kept from one body to
    /// the next ([`Function::take_exact`](plcc_ir::Function::take_exact)).
    scratch: Option<plcc_ir::Function>,
    /// The standard function each name called so far means, if any
    /// ([`Lowerer::builtin`]).
    builtins: rustc_hash::FxHashMap<crate::intern::Symbol, Option<builtins::Builtin>>,
}

/// What [`Lowerer::run`] made.
pub struct Lowered {
    /// The module, if there were no errors.
    pub module: Option<Module>,
    /// Errors and warnings.
    pub diagnostics: Vec<Diagnostic>,
    /// The type of each compiler temporary ([`crate::ast::StmtKind::Let`]).
    pub temp_types: crate::print::TempTypes,
}

impl<'s> Lowerer<'s> {
    /// A lowerer over parsed units (the standard library's first; see [`Lowerer::run`]).
    pub fn new(
        sources: &'s SourceMap,
        interner: &'s mut Interner,
        units: &'s [&'s SourceUnit],
    ) -> Lowerer<'s> {
        let mut module = Module::new();
        module.files = sources.iter().map(|(_, f)| f.name.clone()).collect();
        Lowerer {
            sources,
            interner,
            units,
            pous: Default::default(),
            pou_by_name: FxHashMap::default(),
            types: TypeTable::default(),
            user: Default::default(),
            diags: Vec::new(),
            module,
            ir: Vec::new(),
            array_aggs: FxHashMap::default(),
            string_aggs: FxHashMap::default(),
            prototypes: Vec::new(),
            actions: FxHashMap::default(),
            action_bodies: Vec::new(),
            helpers: FxHashMap::default(),
            calls: Vec::new(),
            used: Vec::new(),
            pending: Vec::new(),
            unsupported_names: Default::default(),
            unknown_uses: Vec::new(),
            globals_pou: None,
            globals_data: None,
            cpdev_files: Vec::new(),
            codesys: false,
            inline_c: false,
            drop_bodies: false,
            run_programs: Vec::new(),
            library: Vec::new(),
            program_data: FxHashMap::default(),
            ref_depth: 0,
            classes: Default::default(),
            temp_types: Default::default(),
            scratch: None,
            builtins: Default::default(),
        }
    }

    /// Runs every phase. `std_units` is the number of leading units that hold the
    /// standard library. Returns the module (if there were no errors), every
    /// diagnostic and what the compiler temporaries became.
    pub fn run(mut self, std_units: usize, opts: &LowerOptions) -> Lowered {
        self.codesys = opts.codesys;
        self.inline_c = opts.inline_c;
        self.drop_bodies = opts.check_only;
        self.run_programs = opts.programs.clone();
        self.library = opts.library.clone();
        self.collect_pous(std_units);
        self.collect_classes();
        self.collect_types();
        self.report_unsupported_items();
        self.resolve_user_types();
        self.check_prototypes();
        for i in 0..self.pous.len() {
            self.resolve_interface(PouId(i as u32));
        }
        if !self.check_containment() {
            self.merge_unknown_blocks();
            return Lowered {
                module: None,
                diagnostics: self.diags,
                temp_types: self.temp_types,
            };
        }
        self.check_externals();
        self.mark_used();
        self.create_shells();
        self.create_actions();
        self.create_globals();
        self.lower_bodies(opts.parallel_bodies);
        self.lower_actions();
        self.lower_body_copies();
        self.check_classes();
        while let Some(p) = self.pending.pop() {
            self.lower_pou(p);
        }
        self.check_recursion();
        self.instantiate_programs(opts);
        // The configuration's connections may use string helpers too.
        while let Some(p) = self.pending.pop() {
            self.lower_pou(p);
        }
        self.merge_unknown_blocks();
        // A STRUCT's field initialisers are lowered for every variable of the type, so
        // their mistakes would be reported once per variable.
        let mut seen = rustc_hash::FxHashSet::default();
        self.diags
            .retain(|d| seen.insert((d.code, d.span, d.message.clone())));
        let has_errors = self.diags.iter().any(|d| d.is_error());
        Lowered {
            module: (!has_errors).then_some(self.module),
            diagnostics: self.diags,
            temp_types: self.temp_types,
        }
    }

    /// Makes a FUNCTION of the standard library (a string helper) callable: its IR
    /// shell at once, its body after the POUs being lowered. Only what is called gets
    /// into the module.
    pub(crate) fn use_std_function(&mut self, p: PouId) {
        if self.used[p.0 as usize] {
            return;
        }
        self.used[p.0 as usize] = true;
        self.create_function_shell(p);
        self.pending.push(p);
    }

    pub(crate) fn error(&mut self, code: &'static str, msg: impl Into<String>, span: Span) {
        self.diags.push(Diagnostic::error(code, msg, span));
    }

    /// The first word of a span: the keyword of a section that spans many lines.
    pub(crate) fn keyword_span(&self, span: Span) -> Span {
        let text = self.text(span);
        let len = text
            .find(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
            .unwrap_or(text.len());
        Span::new(span.file, span.start, span.start + len.max(1) as u32)
    }

    pub(crate) fn text(&self, span: Span) -> &str {
        self.sources.get(span.file).slice(span)
    }

    pub(crate) fn sym_name(&self, sym: Symbol) -> &str {
        self.interner.name(sym)
    }

    /// True for a name declared by a construct already reported as not supported.
    pub(crate) fn is_unsupported_name(&self, sym: Symbol) -> bool {
        self.unsupported_names.contains(&sym)
    }

    /// The POU table, to add to or change (while POUs and interfaces are collected:
    /// no copy shares it then).
    pub(crate) fn pous_mut(&mut self) -> &mut Vec<PouInfo> {
        std::sync::Arc::make_mut(&mut self.pous)
    }

    pub(crate) fn pou(&self, id: PouId) -> &PouInfo {
        &self.pous[id.0 as usize]
    }

    /// The standard function the name `sym` calls, if any: looked up by its
    /// spelling once per name.
    fn builtin(&mut self, sym: crate::intern::Symbol) -> Option<builtins::Builtin> {
        if let Some(&b) = self.builtins.get(&sym) {
            return b;
        }
        let b = builtins::Builtin::lookup(self.interner.name(sym));
        self.builtins.insert(sym, b);
        b
    }

    pub(crate) fn pou_ast(&self, id: PouId) -> &'s ast::Pou {
        let p = &self.pous[id.0 as usize];
        let (methods, props) = match &self.units[p.unit as usize].items[p.item as usize] {
            ast::Item::Pou(pou) => match p.member {
                None => return pou,
                Some(_) => (&pou.oo.methods, &pou.oo.properties),
            },
            ast::Item::Interface(i) => (&i.methods, &i.properties),
            _ => unreachable!("POU table points at a POU"),
        };
        match p.member {
            Some(MemberRef::Method(i)) => &methods[i as usize].pou,
            Some(MemberRef::Get(i)) => props[i as usize].get.as_ref().expect("a getter"),
            Some(MemberRef::Set(i)) => props[i as usize].set.as_ref().expect("a setter"),
            None => unreachable!("an interface member"),
        }
    }

    /// The name of a type for messages.
    pub(crate) fn ty_name(&self, ty: Ty) -> String {
        match ty {
            Ty::Elem(e) => e.name().to_string(),
            Ty::Fb(p) => self.pou(p).display.clone(),
            Ty::Array(a) => {
                let a = self.types.get(a);
                let dims: Vec<String> = a.dims.iter().map(|(l, h)| format!("{l}..{h}")).collect();
                let elem = match a.elem_tag {
                    Some(t) => self.user.tags[t.0 as usize].name.clone(),
                    None => self.ty_name(a.elem),
                };
                format!("ARRAY[{}] OF {elem}", dims.join(", "))
            }
            Ty::Struct(s) => self.user.structs[s.0 as usize].display.clone(),
            Ty::Enum(e, _) => self.user.enums[e.0 as usize].display.clone(),
            Ty::Str(s) => s.name(),
            Ty::Ref(r) => {
                let r = self.types.get_ref(r);
                if let Some(k) = r.iface {
                    return self.classes.ifaces[k].display.clone();
                }
                let t = match r.tag {
                    Some(t) => self.user.tags[t.0 as usize].name.clone(),
                    None => self.ty_name(r.target),
                };
                if r.auto {
                    format!("REFERENCE TO {t}")
                } else if r.pointer {
                    format!("POINTER TO {t}")
                } else {
                    format!("REF_TO {t}")
                }
            }
            Ty::Null => "NULL".to_string(),
            Ty::AnyInt => "an integer literal".to_string(),
            Ty::AnyReal => "a real literal".to_string(),
            Ty::Void => "no value".to_string(),
            Ty::Error => "?".to_string(),
        }
    }

    fn report_unsupported_items(&mut self) {
        let mut errs = Vec::new();
        let units = self.units;
        for unit in units {
            for item in &unit.items {
                if let ast::Item::Pou(p) = item {
                    for b in &p.var_blocks {
                        for d in &b.decls {
                            if matches!(
                                b.kind,
                                VarKind::External
                                    | VarKind::Global
                                    | VarKind::Access
                                    | VarKind::Config
                                    | VarKind::Stat
                            ) {
                                self.unsupported_names.extend(d.names.iter().map(|n| n.sym));
                            }
                        }
                    }
                }
                let (what, span) = match item {
                    ast::Item::Pou(p) if self.prototypes.iter().any(|q| std::ptr::eq(*q, p)) => {
                        continue
                    }
                    ast::Item::Pou(p) => {
                        // One error per kind of member and POU.
                        let mut seen: Vec<&str> = Vec::new();
                        for &m in &p.unsupported_members {
                            let word = self.text(m).split_whitespace().next().unwrap_or("");
                            let what = match word.to_ascii_uppercase().as_str() {
                                _ if self.text(m).contains("..") => "extensible inputs (`IN 1 ..`)",
                                "STEP" | "INITIAL_STEP" | "TRANSITION" => {
                                    "sequential function charts (STEP, TRANSITION)"
                                }
                                "METHOD" | "PROPERTY" => {
                                    "METHODs and PROPERTYs inside a METHOD or PROPERTY"
                                }
                                _ => "object-oriented members (INTERFACE, CLASS)",
                            };
                            if !seen.contains(&what) {
                                seen.push(what);
                                errs.push((what, m));
                            }
                        }
                        continue;
                    }
                    // Checked when resolved (`resolve_user_types`).
                    ast::Item::Type(_) => continue,
                    ast::Item::Globals(b) => {
                        for d in &b.decls {
                            self.unsupported_names.extend(d.names.iter().map(|n| n.sym));
                        }
                        ("VAR_GLOBAL", self.keyword_span(b.span))
                    }
                    // Checked when instantiated (`tasks`).
                    ast::Item::Configuration(_) => continue,
                    // Checked when created (`actions`).
                    ast::Item::Action(_) => continue,
                    // Checked when resolved (`classes`).
                    ast::Item::Interface(_) => continue,
                };
                errs.push((what, span));
            }
        }
        for (what, span) in errs {
            self.error(
                codes::E_UNSUPPORTED,
                format!("not supported yet: {what}"),
                span,
            );
        }
    }
}

/// The source of the standard function blocks (TON, CTU, R_TRIG, ...) and helper
/// FUNCTIONs, written in ST and parsed as the first unit of every build, with the
/// byte offsets where its lines start.
pub fn std_library_source() -> (&'static str, &'static [u32]) {
    static SOURCE: std::sync::OnceLock<(String, Vec<u32>)> = std::sync::OnceLock::new();
    let (text, lines) = SOURCE.get_or_init(|| {
        let strings = format!(
            "{}\n{}",
            include_str!("../stdlib/strings.st"),
            include_str!("../stdlib/timestrings.st")
        );
        // The WSTRING helpers are the STRING ones over 16-bit characters.
        let wide = strings.replace("BYTE", "WORD").replace("__STR_", "__WSTR_");
        let text = format!(
            "{}\n{strings}\n{wide}\n{}",
            include_str!("../stdlib/std_fbs.st"),
            include_str!("../stdlib/sfc.st")
        );
        let lines = crate::source::line_starts(&text);
        (text, lines)
    });
    (text, lines)
}
