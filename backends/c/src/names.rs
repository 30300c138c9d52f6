//! The C names of everything the module declares, as matiec names them: IEC names
//! upper-cased, a POU's struct type named after the POU, `NAME_body__` and
//! `NAME_init__` for the code of PROGRAM and FUNCTION_BLOCK types, program instances
//! `RES0__INSTANCE`, globals `CONFIG0__NAME`.
//!
//! Names the IR made up (`u$scan`, `$globals`) become C identifiers the same way
//! (`U_SCAN`, `PLCC_GLOBALS`); every name is unique among all the module's C names,
//! a clash taking a numbered suffix.

use crate::repr::{Repr, Reprs};
use plcc_ir::diag::Diagnostic;
use plcc_ir::module::{AggDef, DataKind, StructKind};
use plcc_ir::names::Namer;
use plcc_ir::types::MemType;
use plcc_ir::vars::{PathStep, VarRef};
use plcc_ir::{AggId, DataId, FuncKind, Module, Type};
use std::collections::HashSet;

/// The configuration's name when the source has none (the editors always call it
/// `Config0`).
pub const CONFIG: &str = "Config0";
/// The resource's name when the source has none (`RES0__INSTANCE0`).
pub const RESOURCE: &str = "Res0";

/// A resource: its name as spelled, its file's and in C.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ResourceName {
    /// As the source spells it.
    pub spelled: String,
    /// Its file's name without `.c`: as spelled, unless that is the configuration's
    /// file (a resource named like its configuration) or another resource's, when it
    /// takes `_resource` (and a number).
    pub file: String,
    /// In C, upper-cased (`RES0`).
    pub c: String,
}

/// How a function is called in C.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum FuncForm {
    /// `RET NAME(args)` with the IR's parameters.
    Plain,
    /// `void NAME_body__(NAME *data__)`: the body of the PROGRAM or FB type `agg`.
    Body(AggId),
    /// `void NAME_init__(NAME *data__, BOOL retain)`: its cold-start code.
    Init(AggId),
}

/// The C names of a module.
#[derive(Clone, Debug)]
pub struct Names {
    /// Type name of each aggregate.
    pub aggs: Vec<String>,
    /// Field names of each struct (empty for arrays); array elements are `table`.
    pub fields: Vec<Vec<String>>,
    /// Each data object's variable.
    pub data: Vec<String>,
    /// Each function's name.
    pub funcs: Vec<String>,
    /// How each function is called.
    pub forms: Vec<FuncForm>,
    /// How each field is held (wrapped, located or plain) and the located variables.
    pub repr: Reprs,
    /// The configuration's name as spelled (its files are `NAME.c`, `NAME.h`).
    pub config: String,
    /// The configuration's name in C (`CONFIG0`).
    pub config_c: String,
    /// The resources (at least one).
    pub resources: Vec<ResourceName>,
    /// The resource of each program entry.
    pub program_resource: Vec<usize>,
    /// The data object of the globals, whose fields are variables of their own in C.
    pub globals_data: Option<DataId>,
    /// The C variable of each global (each field of the globals' struct):
    /// `CONFIG0__G1`, or `RES0__G2` for a resource's global.
    pub globals: Vec<String>,
    /// The resource each global is declared in (`None`: the configuration).
    pub global_scope: Vec<Option<usize>>,
}

/// An IEC or IR name as a C identifier: upper-cased, other characters than letters,
/// digits and `_` turned into `_`, and `PLCC` before a name that would start with `_`
/// or a digit (C reserves `_X…`; plcc's own names start with `__plcc`).
pub fn ident(name: &str) -> String {
    let mut s = plcc_ir::names::identifier(name).to_ascii_uppercase();
    if s.is_empty() || s.starts_with('_') || s.starts_with(|c: char| c.is_ascii_digit()) {
        s = if s.starts_with('_') {
            format!("PLCC{s}")
        } else {
            format!("PLCC_{s}")
        };
    }
    s
}

/// Names C, its headers or the harness use, which no generated name may take.
const RESERVED: &[&str] = &[
    "TRUE", "FALSE", "BOOL", "SINT", "INT", "DINT", "LINT", "USINT", "UINT", "UDINT", "ULINT",
    "BYTE", "WORD", "DWORD", "LWORD", "REAL", "LREAL", "TIME", "DATE", "TOD", "DT", "STRING",
    "LTIME", "STEP", "ACTION", "NULL", "EOF", "ERANGE", "EDOM", "INFINITY", "NAN",
];

/// The function blocks of matiec's standard library, which a runtime's headers
/// define (`TON`, `TON_init__`, `TON_body__`): plcc's own (compiled from ST, with
/// plcc's layout) are named `PLCC_TON` in C so that the C builds against those
/// headers too.
pub const RUNTIME_BLOCKS: &[&str] = &[
    "R_TRIG",
    "F_TRIG",
    "SR",
    "RS",
    "TP",
    "TON",
    "TOF",
    "CTU",
    "CTU_DINT",
    "CTU_LINT",
    "CTU_UDINT",
    "CTU_ULINT",
    "CTD",
    "CTD_DINT",
    "CTD_LINT",
    "CTD_UDINT",
    "CTD_ULINT",
    "CTUD",
    "CTUD_DINT",
    "CTUD_LINT",
    "CTUD_UDINT",
    "CTUD_ULINT",
    "DERIVATIVE",
    "HYSTERESIS",
    "INTEGRAL",
    "PID",
    "RAMP",
    "RTC",
    "SEMA",
];

/// The names given so far in one scope (the module's, or a struct's fields): none
/// of C's and the headers' reserved names.
struct Taken(Namer);

impl Taken {
    fn new() -> Taken {
        let mut n = Namer::new(false);
        n.reserve(RESERVED.iter().copied());
        Taken(n)
    }

    fn take(&mut self, want: String) -> String {
        self.0.unique(&want)
    }
}

impl Names {
    /// Names everything in `module` and decides how each variable is held (which
    /// checks its located variables).
    pub fn new(module: &Module) -> Result<Names, Vec<Diagnostic>> {
        let repr = Reprs::new(module)?;
        let mut taken = Taken::new();
        let aggs: Vec<String> = module
            .aggs
            .iter()
            .map(|a| {
                let name = ident(a.name());
                let fb = matches!(a, AggDef::Struct(s) if s.kind == StructKind::FunctionBlock);
                if fb && RUNTIME_BLOCKS.contains(&name.as_str()) {
                    taken.take(format!("PLCC_{name}"))
                } else {
                    taken.take(name)
                }
            })
            .collect();
        let fields = module
            .aggs
            .iter()
            .map(|a| match a {
                AggDef::Struct(s) => {
                    let mut t = Taken::new();
                    s.fields.iter().map(|f| t.take(ident(&f.name))).collect()
                }
                AggDef::Array(_) => Vec::new(),
            })
            .collect();
        let conf = module.configuration.as_ref();
        let config = conf.map_or(CONFIG.to_string(), |c| c.name.clone());
        let config_c = ident(&config);
        let mut resources: Vec<ResourceName> = conf
            .map(|c| {
                c.resources
                    .iter()
                    .map(|r| ResourceName {
                        spelled: r.name.clone(),
                        file: r.name.clone(),
                        c: ident(&r.name),
                    })
                    .collect()
            })
            .unwrap_or_default();
        if resources.is_empty() {
            resources.push(ResourceName {
                spelled: RESOURCE.into(),
                file: RESOURCE.into(),
                c: ident(RESOURCE),
            });
        }
        // File names differ even where file systems ignore case.
        let mut files: HashSet<String> = HashSet::from([config.to_ascii_lowercase()]);
        for r in &mut resources {
            let mut k = 1;
            while !files.insert(r.file.to_ascii_lowercase()) {
                r.file = match k {
                    1 => format!("{}_resource", r.spelled),
                    _ => format!("{}_resource{k}", r.spelled),
                };
                k += 1;
            }
        }
        let in_resource = |name: &str, list: fn(&plcc_ir::Resource) -> &Vec<String>| {
            conf.and_then(|c| {
                c.resources
                    .iter()
                    .position(|r| list(r).iter().any(|n| n.eq_ignore_ascii_case(name)))
            })
        };
        let program_resource: Vec<usize> = module
            .programs
            .iter()
            .map(|p| in_resource(&p.name, |r| &r.programs).unwrap_or(0))
            .collect();
        let globals_data = module.globals;
        let mut globals = Vec::new();
        let mut global_scope = Vec::new();
        if let Some(AggDef::Struct(s)) =
            globals_data.and_then(|g| match module.data[g.index()].ty {
                MemType::Agg(a) => Some(module.agg(a)),
                MemType::Scalar(_) => None,
            })
        {
            for f in &s.fields {
                let scope = in_resource(&f.name, |r| &r.globals);
                let prefix = scope.map_or(&config_c, |r| &resources[r].c);
                globals.push(taken.take(format!("{prefix}__{}", ident(&f.name))));
                global_scope.push(scope);
            }
        }
        let data = module
            .data
            .iter()
            .enumerate()
            .map(|(k, d)| {
                if Some(DataId::new(k)) == globals_data {
                    // Never named: its fields are.
                    return String::new();
                }
                let scope = match module.programs.iter().position(|p| p.data.index() == k) {
                    Some(p) if d.kind == DataKind::Program => &resources[program_resource[p]].c,
                    _ if d.kind == DataKind::Program => &resources[0].c,
                    _ => &config_c,
                };
                taken.take(format!("{scope}__{}", ident(&d.name)))
            })
            .collect();
        let forms: Vec<FuncForm> = module.funcs.iter().map(|f| form(module, f)).collect();
        let funcs = module
            .funcs
            .iter()
            .zip(&forms)
            .map(|(f, form)| {
                taken.take(match *form {
                    FuncForm::Plain => ident(&f.name),
                    FuncForm::Body(a) => format!("{}_body__", aggs[a.index()]),
                    FuncForm::Init(a) => format!("{}_init__", aggs[a.index()]),
                })
            })
            .collect();
        Ok(Names {
            aggs,
            fields,
            data,
            funcs,
            forms,
            repr,
            config,
            config_c,
            resources,
            program_resource,
            globals_data,
            globals,
            global_scope,
        })
    }

    /// How global `g` (field `g` of the globals' struct) is held.
    pub fn global_repr(&self, module: &Module, g: usize) -> Repr {
        match self.globals_data.map(|d| module.data[d.index()].ty) {
            Some(MemType::Agg(a)) => self.repr.field(a, g as u32),
            _ => Repr::Plain,
        }
    }

    /// True if data object `d` holds the globals (each a C variable of its own).
    pub fn is_globals(&self, d: DataId) -> bool {
        self.globals_data == Some(d)
    }

    /// The C lvalue of a scalar variable's value (`RES0__MAIN.T.Q.value`, or
    /// `(*RES0__MAIN.START.value)` for a located one).
    pub fn value_expr(&self, v: &VarRef) -> String {
        let mut s = self.data[v.root.index()].clone();
        for (k, step) in v.steps.iter().enumerate() {
            match *step {
                PathStep::Field(agg, f) => {
                    if k == 0 && self.is_globals(v.root) {
                        s = self.globals[f as usize].clone();
                    } else {
                        s.push('.');
                        s.push_str(&self.fields[agg.index()][f as usize]);
                    }
                    match self.repr.field(agg, f) {
                        Repr::Plain => {}
                        Repr::Var(_) | Repr::AggVar => s.push_str(".value"),
                        Repr::Located(_) => s = format!("(*{s}.value)"),
                    }
                }
                PathStep::Elem(_, i) => s.push_str(&format!(".table[{i}]")),
            }
        }
        s
    }
}

/// The POU type (a PROGRAM or FUNCTION_BLOCK struct) named `name`, if any.
fn pou_struct(module: &Module, name: &str) -> Option<AggId> {
    module
        .aggs
        .iter()
        .position(|a| match a {
            AggDef::Struct(s) => {
                s.name == name && matches!(s.kind, StructKind::Program | StructKind::FunctionBlock)
            }
            AggDef::Array(_) => false,
        })
        .map(AggId::new)
}

fn form(module: &Module, f: &plcc_ir::Function) -> FuncForm {
    if f.params != [Type::Ptr] || f.ret.is_some() {
        return FuncForm::Plain;
    }
    match f.kind {
        FuncKind::ProgramBody | FuncKind::FbBody => {
            pou_struct(module, &f.name).map_or(FuncForm::Plain, FuncForm::Body)
        }
        FuncKind::Init => f
            .name
            .strip_suffix("$init")
            .and_then(|n| pou_struct(module, n))
            .map_or(FuncForm::Plain, FuncForm::Init),
        _ => FuncForm::Plain,
    }
}

/// The C type of an SSA value of type `ty` (integers unsigned: signed operations
/// convert explicitly).
pub fn value_type(ty: Type) -> &'static str {
    match ty {
        Type::I1 | Type::I8 => "uint8_t",
        Type::I16 => "uint16_t",
        Type::I32 => "uint32_t",
        Type::I64 => "uint64_t",
        Type::F32 => "float",
        Type::F64 => "double",
        Type::Ptr => "unsigned char *",
    }
}

/// The signed C type of an integer type's width.
pub fn signed_type(ty: Type) -> &'static str {
    match ty {
        Type::I1 | Type::I8 => "int8_t",
        Type::I16 => "int16_t",
        Type::I32 => "int32_t",
        _ => "int64_t",
    }
}

/// The unsigned type integer arithmetic of `ty` is done in (at least `unsigned int`
/// wide, so that no promotion to `int` can overflow).
pub fn wide_type(ty: Type) -> &'static str {
    if ty == Type::I64 {
        "uint64_t"
    } else {
        "uint32_t"
    }
}

/// The C type of a scalar in memory: the IEC name where matiec's C type holds the
/// IR's representation, else the plain C type of the IR type (TIME, DATE, TOD and DT
/// are 32-bit counts in plcc, time specs in matiec; CHAR and WCHAR are plain bytes
/// and words; references are pointers).
pub fn field_type(ty: Type, elem: Option<plcc_ir::ElemType>) -> &'static str {
    use plcc_ir::ElemType as E;
    match elem {
        Some(e) if e.ir_type() == ty => match e {
            E::Bool => "BOOL",
            E::SInt => "SINT",
            E::Int => "INT",
            E::DInt => "DINT",
            E::LInt => "LINT",
            E::USInt => "USINT",
            E::UInt => "UINT",
            E::UDInt => "UDINT",
            E::ULInt => "ULINT",
            E::Byte => "BYTE",
            E::Word => "WORD",
            E::DWord => "DWORD",
            E::LWord => "LWORD",
            E::Real => "REAL",
            E::LReal => "LREAL",
            _ => value_type(ty),
        },
        _ => value_type(ty),
    }
}
