//! The C names of everything the module declares, as matiec names them: IEC names
//! upper-cased, a POU's struct type named after the POU, `NAME_body__` and
//! `NAME_init__` for the code of PROGRAM and FUNCTION_BLOCK types, program instances
//! `RES0__INSTANCE`, globals `CONFIG0__NAME`.
//!
//! Names the IR made up (`u$scan`, `$globals`) become C identifiers the same way
//! (`U_SCAN`, `PLCC_GLOBALS`); every name is unique among all the module's C names,
//! a clash taking a numbered suffix.

use plcc_ir::module::{AggDef, DataKind, StructKind};
use plcc_ir::{AggId, FuncKind, Module, Type};
use std::collections::HashSet;

/// The configuration's name in C (matiec's `CONFIG0__G1`); the IR does not keep the
/// source's, and the editors always call it `Config0`.
pub const CONFIG: &str = "Config0";
/// The resource's name in C (`RES0__INSTANCE0`).
pub const RESOURCE: &str = "Res0";

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
}

/// An IEC or IR name as a C identifier: upper-cased, other characters than letters,
/// digits and `_` turned into `_`, and `PLCC` before a name that would start with `_`
/// or a digit (C reserves `_X…`; plcc's own names start with `__plcc`).
pub fn ident(name: &str) -> String {
    let mut s: String = name
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '_' {
                c.to_ascii_uppercase()
            } else {
                '_'
            }
        })
        .collect();
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

struct Taken(HashSet<String>);

impl Taken {
    fn take(&mut self, want: String) -> String {
        if !RESERVED.contains(&want.as_str()) && self.0.insert(want.clone()) {
            return want;
        }
        (2..)
            .map(|k| format!("{want}_{k}"))
            .find(|n| self.0.insert(n.clone()))
            .expect("a free name")
    }
}

impl Names {
    /// Names everything in `module`.
    pub fn new(module: &Module) -> Names {
        let mut taken = Taken(HashSet::new());
        let aggs: Vec<String> = module
            .aggs
            .iter()
            .map(|a| taken.take(ident(a.name())))
            .collect();
        let fields = module
            .aggs
            .iter()
            .map(|a| match a {
                AggDef::Struct(s) => {
                    let mut t = Taken(HashSet::new());
                    s.fields.iter().map(|f| t.take(ident(&f.name))).collect()
                }
                AggDef::Array(_) => Vec::new(),
            })
            .collect();
        let config = ident(CONFIG);
        let resource = ident(RESOURCE);
        let data = module
            .data
            .iter()
            .map(|d| {
                let scope = if d.kind == DataKind::Program {
                    &resource
                } else {
                    &config
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
        Names {
            aggs,
            fields,
            data,
            funcs,
            forms,
        }
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
