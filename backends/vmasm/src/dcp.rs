//! The DCP project description: the XML that tells a CPDev runtime the task (cycle,
//! body address), the memory sizes, where every variable lives, and the listing.
//!
//! The form follows the descriptions the CPDev compiler writes (see the samples in
//! `reference/cpdev-samples/`): `<GLOBAL>` for global variables, `<TASKS>`,
//! `<MEMORY_MAP>` for code and data, `<MNEMONIC_MAP>` with the listing, and
//! `<DATA_MAP>` with the program instances and their variables (relative `rdlabel`
//! and absolute `gdlabel` addresses).

use crate::build::Build;
use crate::isa::Mode;
use plcc_ir::backend::Options;
use plcc_ir::module::{AggDef, DataKind};
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

fn type_names(module: &Module, t: MemType, elem: Option<plcc_ir::ElemType>) -> (String, String) {
    match (t, elem) {
        (MemType::Scalar(_), Some(e)) => (e.name().to_string(), format!("$DEFAULT.{}", e.name())),
        (MemType::Scalar(s), None) => (s.to_string(), format!("$DEFAULT.{s}")),
        (MemType::Agg(a), _) => {
            let n = module.agg(a).name().to_string();
            (n.clone(), format!("plcc.{n}"))
        }
    }
}

/// Writes the variables of an object of type `t` at `rel` (relative to its parent)
/// and `abs`, with its members nested.
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
) {
    let mode = b.settings.mode;
    let ind = "  ".repeat(depth);
    let size = b.layout.size_of(t);
    let (ty, pty) = type_names(module, t, elem);
    let _ = write!(
        out,
        "{ind}<OBJ ObjType=\"VAR\" LName=\"{}\" PName=\"{}\" Addr=\"{}\" AdrType=\"rdlabel\" CAddr=\"{}\" CAdrType=\"gdlabel\" Size=\"{size}\" Type=\"{}\" PType=\"{}\"",
        escape(name),
        escape(pname),
        addr(rel, mode),
        addr(abs, mode),
        escape(&ty),
        escape(&pty)
    );
    match t {
        MemType::Scalar(_) => out.push_str(" />\n"),
        MemType::Agg(a) => {
            out.push_str(">\n");
            match module.agg(a) {
                AggDef::Struct(s) => {
                    for (i, f) in s.fields.iter().enumerate() {
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
                        );
                    }
                }
                AggDef::Array(arr) => {
                    let hi = arr.lower + arr.len as i64 - 1;
                    let _ = writeln!(
                        out,
                        "{ind}  <DIMENSIONS>\n{ind}    <LEVEL No=\"0\" LoBound=\"{}\" UpBound=\"{hi}\" />\n{ind}  </DIMENSIONS>",
                        arr.lower
                    );
                }
            }
            let _ = writeln!(out, "{ind}</OBJ>");
        }
    }
}

/// The global variables: each field of a global data object of struct type (the
/// front ends gather the VAR_GLOBALs in one), else the object itself.
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
        "  <TARGET RawCompilerVersion=\"00000100\" StringCompilerVersion=\"plcc {}\" Mode=\"{}\">",
        env!("CARGO_PKG_VERSION"),
        match mode {
            Mode::M16 => "mach16b",
            Mode::M32 => "mach32b",
            Mode::M32A => "mach32bA",
        }
    );
    o.push_str("    <GLOBAL>\n");
    for (name, t, elem, a) in globals(module, b) {
        let (ty, pty) = type_names(module, t, elem);
        let _ = writeln!(
            o,
            "      <VAR LName=\"{}\" PName=\"plcc.{}\" Addr=\"{}\" AdrType=\"gdlabel\" Size=\"{}\" Type=\"{}\" PType=\"{}\" VarFlags=\"00000000\" />",
            escape(&name),
            escape(&name),
            addr(a, mode),
            b.layout.size_of(t),
            escape(&ty),
            escape(&pty)
        );
    }
    o.push_str("    </GLOBAL>\n");
    o.push_str("    <VMACH>\n      <FILE_LOC>VM-Univ.xml</FILE_LOC>\n    </VMACH>\n");
    o.push_str("    <TASKS>\n");
    let _ = writeln!(
        o,
        "      <TASK LName=\"TASK\" PName=\"plcc.TASK\" LoopType=\"0\" Cycle=\"{}\" CycleUnit=\"ms\" BodyCodeAddres=\"{}\" TaskFlags=\"00000000\" />",
        b.settings
            .cycle_ms
            .or_else(|| module.programs.iter().filter_map(|p| p.interval_ms).min())
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
    for (name, t, elem, a) in globals(module, b) {
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
        );
    }
    o.push_str("      </OBJ>\n");
    o.push_str("    </DATA_MAP>\n");
    o.push_str("  </TARGET>\n</CPDEV>\n");
    o
}
