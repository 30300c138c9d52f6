//! The DCP project description: the XML that tells a CPDev runtime the task (cycle,
//! body address), the memory sizes, where every variable lives, and the listing.
//!
//! The form follows the descriptions the CPDev compiler writes (see the samples in
//! `reference/cpdev-samples/`): `<GLOBAL>` for global variables, `<TASKS>`,
//! `<MEMORY_MAP>` for code and data, `<MNEMONIC_MAP>` with the listing, and
//! `<DATA_MAP>` with the program instances and their variables (relative `rdlabel`
//! and absolute `gdlabel` addresses).

use crate::build::{Build, FAULT_NAME};
use crate::isa::Mode;
use plcc_ir::backend::Options;
use plcc_ir::module::{AggDef, DataKind, FieldRole, StructKind};
use plcc_ir::types::MemType;
use plcc_ir::Module;
use std::fmt::Write;

/// Escapes text for XML attributes and content.
pub fn escape(s: &str) -> String {
    let mut o = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => o.push_str("&amp;"),
            '<' => o.push_str("&lt;"),
            '>' => o.push_str("&gt;"),
            '"' => o.push_str("&quot;"),
            c if (c as u32) < 0x20 && c != '\n' && c != '\t' => o.push(' '),
            c => o.push(c),
        }
    }
    o
}

fn addr(a: u64, mode: Mode) -> String {
    if mode == Mode::M16 {
        format!("{a:04x}")
    } else {
        format!("{a:08x}")
    }
}

/// How a variable is described: `Type`, `PType`, `TypeStatus` and any further
/// attributes (an array's element type and bounds, what a DATE holds).
struct Desc {
    ty: String,
    pty: String,
    status: &'static str,
    extra: String,
    /// `(lower, upper)` of each dimension, outermost first.
    dims: Vec<(i64, i64)>,
    /// An array's elements when they are STRUCTs or FBs: their type, and the index
    /// of the first one (`[0][1]`).
    agg_elems: Option<(MemType, String)>,
}

/// The IEC name of a scalar: its source type, else the IR type's natural one (the
/// front ends give every user variable its source type).
fn scalar_name(t: plcc_ir::types::Type, elem: Option<plcc_ir::ElemType>, mode: Mode) -> String {
    use plcc_ir::types::Type;
    use plcc_ir::ElemType as E;
    let addr_word = if mode == Mode::M16 { "WORD" } else { "DWORD" };
    match elem {
        // plcc keeps DATE and DT as seconds and TOD as ms in a 32-bit count, not in
        // CPDev's day/month/year and csec/s/min/h layouts: they are described by
        // what they hold, so that no CPDev tool decodes them wrongly.
        Some(E::Date | E::Tod | E::Dt) => "UDINT".into(),
        Some(E::Ref) => addr_word.into(),
        Some(e) => e.name().into(),
        None => match t {
            Type::I1 => "BOOL",
            Type::I8 => "BYTE",
            Type::I16 => "INT",
            Type::I32 => "DINT",
            Type::I64 => "LINT",
            Type::F32 => "REAL",
            Type::F64 => "LREAL",
            Type::Ptr => addr_word,
        }
        .into(),
    }
}

fn describe(
    module: &Module,
    b: &Build,
    name: &str,
    t: MemType,
    elem: Option<plcc_ir::ElemType>,
) -> Desc {
    use plcc_ir::ElemType as E;
    let mode = b.settings.mode;
    match t {
        MemType::Scalar(st) => {
            let n = scalar_name(st, elem, mode);
            let extra = match elem {
                Some(E::Date) => " PlccType=\"DATE\" Encoding=\"seconds since 1970-01-01\"",
                Some(E::Dt) => " PlccType=\"DATE_AND_TIME\" Encoding=\"seconds since 1970-01-01\"",
                Some(E::Tod) => " PlccType=\"TIME_OF_DAY\" Encoding=\"ms since midnight\"",
                Some(E::Ref) => " PlccType=\"REF_TO\" Encoding=\"absolute address\"",
                _ => "",
            };
            Desc {
                pty: format!("$DEFAULT.{n}"),
                ty: n,
                status: "build-in type",
                extra: extra.into(),
                dims: Vec::new(),
                agg_elems: None,
            }
        }
        MemType::Agg(a) => match module.agg(a) {
            AggDef::Array(_) => {
                // Nested arrays are the dimensions of one (ARRAY[1..2, 0..3]).
                let mut dims = Vec::new();
                let mut first = String::new();
                let mut inner = t;
                let mut inner_elem = elem;
                while let MemType::Agg(x) = inner {
                    let AggDef::Array(arr) = module.agg(x) else {
                        break;
                    };
                    dims.push((arr.lower, arr.lower + arr.len as i64 - 1));
                    let _ = write!(first, "[{}]", arr.lower);
                    inner = arr.elem;
                    inner_elem = arr.elem_type;
                }
                let base = match inner {
                    MemType::Scalar(st) => scalar_name(st, inner_elem, mode),
                    MemType::Agg(x) => module.agg(x).name().to_string(),
                };
                let base_p = match inner {
                    MemType::Scalar(_) => format!("$DEFAULT.{base}"),
                    MemType::Agg(_) => format!("plcc.{base}"),
                };
                let ty = format!("?{}?ARRAY?{:02}", name.to_uppercase(), a.index());
                // plcc's STRING[n] (the front end's `strN`, `wstrN`): n + 1 characters
                // ended by a 0, not CPDev's length-prefixed layout.
                let aname = module.agg(a).name();
                let string = ["wstr", "str"].iter().find_map(|p| {
                    let n = aname.strip_prefix(p)?;
                    (!n.is_empty() && n.bytes().all(|c| c.is_ascii_digit())).then(|| {
                        let kind = if *p == "wstr" { "WSTRING" } else { "STRING" };
                        format!(" PlccType=\"{kind}[{n}]\" Encoding=\"characters ended by a 0\"")
                    })
                });
                Desc {
                    pty: format!("plcc.{ty}"),
                    ty,
                    status: "array",
                    extra: format!(
                        " ArrayBase=\"{}\" ArrayBaseP=\"{}\" ElementSize=\"{}\"{}",
                        escape(&base),
                        escape(&base_p),
                        b.layout.size_of(inner),
                        string.unwrap_or_default()
                    ),
                    dims,
                    agg_elems: matches!(inner, MemType::Agg(_)).then_some((inner, first)),
                }
            }
            AggDef::Struct(st) => {
                let n = st.name.clone();
                Desc {
                    pty: format!("plcc.{n}"),
                    ty: n,
                    status: match st.kind {
                        StructKind::Program => "program",
                        StructKind::FunctionBlock => "function block",
                        _ => "struct",
                    },
                    extra: String::new(),
                    dims: Vec::new(),
                    agg_elems: None,
                }
            }
        },
    }
}

/// The VFlags of a variable in the role it has in its POU.
fn vflags(role: Option<FieldRole>, global: bool) -> u32 {
    let r = match role {
        Some(FieldRole::Input) => 0x10,
        Some(FieldRole::Output) => 0x20,
        _ => 0,
    };
    r | if global { 0x4000 } else { 0 }
}

/// Writes the variables of an object of type `t` at `rel` (relative to its parent)
/// and `abs`, with its members nested (a STRUCT's or an FB's fields; an array's
/// bounds, and the members of its first element when the elements are aggregates).
#[allow(clippy::too_many_arguments)]
fn obj(
    out: &mut String,
    module: &Module,
    b: &Build,
    name: &str,
    pname: &str,
    t: MemType,
    elem: Option<plcc_ir::ElemType>,
    rel: u64,
    abs: u64,
    depth: usize,
    flags: u32,
) {
    let mode = b.settings.mode;
    let ind = "  ".repeat(depth);
    let size = b.layout.size_of(t);
    let d = describe(module, b, name, t, elem);
    let _ = write!(
        out,
        "{ind}<OBJ ObjType=\"VAR\" LName=\"{}\" PName=\"{}\" Addr=\"{}\" AdrType=\"rdlabel\" CAddr=\"{}\" CAdrType=\"gdlabel\" Size=\"{size}\" Type=\"{}\" PType=\"{}\" TypeStatus=\"{}\" VFlags=\"{flags:08x}\"{}",
        escape(name),
        escape(pname),
        addr(rel, mode),
        addr(abs, mode),
        escape(&d.ty),
        escape(&d.pty),
        d.status,
        d.extra
    );
    let MemType::Agg(a) = t else {
        out.push_str(" />\n");
        return;
    };
    out.push_str(">\n");
    match module.agg(a) {
        AggDef::Struct(s) => {
            for (i, f) in s.fields.iter().enumerate() {
                if f.role == FieldRole::Hidden {
                    continue;
                }
                let off = b.layout.field_offset(a, i as u32) as u64;
                obj(
                    out,
                    module,
                    b,
                    &f.name,
                    &format!("{pname}.{}", f.name),
                    f.ty,
                    f.elem,
                    off,
                    abs + off,
                    depth + 1,
                    vflags(Some(f.role), false),
                );
            }
        }
        AggDef::Array(_) => {
            let _ = writeln!(out, "{ind}  <DIMENSIONS>");
            for (k, (lo, hi)) in d.dims.iter().enumerate() {
                let _ = writeln!(
                    out,
                    "{ind}    <LEVEL No=\"{k}\" LoBound=\"{lo}\" UpBound=\"{hi}\" />"
                );
            }
            let _ = writeln!(out, "{ind}  </DIMENSIONS>");
            let up = name.to_uppercase();
            for (k, (lo, hi)) in d.dims.iter().enumerate() {
                for (what, v) in [("LOW", lo), ("UPR", hi)] {
                    let _ = writeln!(
                        out,
                        "{ind}  <OBJ ObjType=\"VAR\" LName=\"?{}?{what}?{k:02}\" Addr=\"#null\" Size=\"2\" Type=\"INT\" PType=\"$DEFAULT.INT\" TypeStatus=\"build-in type\" VFlags=\"00100004\" ConstValue=\"{v}\" />",
                        escape(&up)
                    );
                }
            }
            // Elements that are STRUCTs or FBs: the first one's members, from which
            // every element's follow (ElementSize apart).
            if let Some((inner, first)) = &d.agg_elems {
                obj(
                    out,
                    module,
                    b,
                    &format!("{name}{first}"),
                    &format!("{pname}{first}"),
                    *inner,
                    None,
                    0,
                    abs,
                    depth + 1,
                    0,
                );
            }
        }
    }
    let _ = writeln!(out, "{ind}</OBJ>");
}

/// The global variables: each field of a global data object of struct type (the
/// front ends gather the VAR_GLOBALs in one), else the object itself. State the
/// front end added (a task's timing) is not listed.
fn globals(module: &Module, b: &Build) -> Vec<(String, MemType, Option<plcc_ir::ElemType>, u64)> {
    let mut v = Vec::new();
    for (i, d) in module.data.iter().enumerate() {
        if d.kind != DataKind::Global {
            continue;
        }
        let base = b.data_addrs[i] as u64;
        match d.ty {
            MemType::Agg(a) if matches!(module.agg(a), AggDef::Struct(_)) => {
                let AggDef::Struct(s) = module.agg(a) else {
                    continue;
                };
                for (k, f) in s.fields.iter().enumerate() {
                    if f.role == FieldRole::Hidden {
                        continue;
                    }
                    let off = b.layout.field_offset(a, k as u32) as u64;
                    v.push((f.name.clone(), f.ty, f.elem, base + off));
                }
            }
            _ => v.push((d.name.clone(), d.ty, d.elem, base)),
        }
    }
    v
}

/// The DCP of a build.
pub fn write(module: &Module, b: &Build, options: &Options) -> String {
    let mode = b.settings.mode;
    let stem = options
        .output_stem
        .clone()
        .unwrap_or_else(|| "program".into());
    let mut o = String::new();
    o.push_str("<?xml version=\"1.0\" encoding=\"utf-8\" standalone=\"yes\"?>\n");
    o.push_str("<CPDEV version=\"1.0\">\n");
    let _ = writeln!(
        o,
        "  <TARGET RawCompilerVersion=\"00000100\" StringCompilerVersion=\"plcc {}\" Mode=\"{}\"{} Port=\"{}\">",
        env!("CARGO_PKG_VERSION"),
        match mode {
            Mode::M16 => "mach16b",
            Mode::M32 => "mach32b",
            Mode::M32A => "mach32bA",
        },
        if mode == Mode::M16 { "" } else { " AddressSize=\"8\"" },
        b.settings.port.name()
    );
    o.push_str("    <GLOBAL>\n");
    let mut vars = globals(module, b);
    // The fault word: 1 once a runtime fault (division by zero, an index out of
    // range, a NULL dereference) was raised; the VM itself never acts on it.
    vars.push((
        FAULT_NAME.to_string(),
        MemType::Scalar(plcc_ir::types::Type::I16),
        Some(plcc_ir::ElemType::Word),
        b.fault_addr as u64,
    ));
    for (name, t, elem, a) in &vars {
        let d = describe(module, b, name, *t, *elem);
        let _ = writeln!(
            o,
            "      <VAR LName=\"{}\" PName=\"plcc.{}\" Addr=\"{}\" AdrType=\"gdlabel\" Size=\"{}\" Type=\"{}\" PType=\"{}\" VarFlags=\"00004000\"{} />",
            escape(name),
            escape(name),
            addr(*a, mode),
            b.layout.size_of(*t),
            escape(&d.ty),
            escape(&d.pty),
            d.extra
        );
    }
    o.push_str("    </GLOBAL>\n");
    let _ = writeln!(
        o,
        "    <VMACH>\n      <FILE_LOC>{}</FILE_LOC>\n    </VMACH>",
        match mode {
            Mode::M16 => "VM-Univ.xml",
            Mode::M32 => "VM-Praxis32.xml",
            Mode::M32A => "VM-Praxis32ARM.xml",
        }
    );
    o.push_str("    <TASKS>\n");
    let _ = writeln!(
        o,
        "      <TASK LName=\"TASK\" PName=\"plcc.TASK\" LoopType=\"0\" Cycle=\"{}\" CycleUnit=\"ms\" BodyCodeAddres=\"{}\" TaskFlags=\"00000000\" />",
        b.settings
            .cycle_ms
            .or_else(|| {
                // Whole milliseconds, as CPDev counts them: `build` refuses tasks
                // finer than that.
                module
                    .task_tick_us()
                    .map(|us| u32::try_from(us.div_ceil(1000)).unwrap_or(u32::MAX))
            })
            .unwrap_or(100),
        addr(b.loop_addr as u64, mode)
    );
    o.push_str("    </TASKS>\n");
    let _ = writeln!(
        o,
        "    <MEMORY_MAP Type=\"code\">\n      <file LoadAddr=\"0\" Size=\"{}\">{}.xcp</file>\n    </MEMORY_MAP>",
        b.image.code.len(),
        escape(&stem)
    );
    let _ = writeln!(
        o,
        "    <MEMORY_MAP Type=\"data\">\n      <file LoadAddr=\"0\" Size=\"{}\">#dummy</file>\n    </MEMORY_MAP>",
        b.data_size
    );
    o.push_str("    <MNEMONIC_MAP Type=\"code\">\n");
    o.push_str(&escape(&b.image.listing));
    o.push_str("</MNEMONIC_MAP>\n");
    o.push_str("    <DATA_MAP>\n");
    for (name, t, elem, a) in vars {
        obj(
            &mut o,
            module,
            b,
            &name,
            &format!("plcc.{name}"),
            t,
            elem,
            a,
            a,
            3,
            0x4000,
        );
    }
    let _ = writeln!(
        o,
        "      <OBJ ObjType=\"TASK\" LName=\"TASK\" PName=\"plcc.TASK\" Addr=\"{}\" AdrType=\"gdlabel\" Size=\"{}\">",
        addr(0, mode),
        b.data_size
    );
    for p in &b.programs {
        let d = &module.data[p.data.index()];
        obj(
            &mut o,
            module,
            b,
            &p.name,
            &format!("plcc.TASK.{}", p.name),
            d.ty,
            d.elem,
            p.addr as u64,
            p.addr as u64,
            4,
            0,
        );
    }
    o.push_str("      </OBJ>\n");
    o.push_str("    </DATA_MAP>\n");
    o.push_str("  </TARGET>\n</CPDEV>\n");
    o
}
