//! The C header that comes with an object file: the memory layout of every aggregate
//! and data object, the runtime context, and the entry points, so that a C host
//! runtime can drive the scan and reach any variable.

use crate::codegen::DataLayout;
use crate::runtime::{data_symbol, func_symbol, mangle, DATA_SYMBOL, RT_SYMBOL};
use plcc_ir::{AggDef, AggId, ElemType, MemType, Module, Type};
use std::collections::HashSet;
use std::fmt::Write;

/// C (and C++) keywords and names the standard headers we include define as macros.
const RESERVED: &[&str] = &[
    "auto",
    "break",
    "case",
    "char",
    "const",
    "continue",
    "default",
    "do",
    "double",
    "else",
    "enum",
    "extern",
    "float",
    "for",
    "goto",
    "if",
    "inline",
    "int",
    "long",
    "register",
    "restrict",
    "return",
    "short",
    "signed",
    "sizeof",
    "static",
    "struct",
    "switch",
    "typedef",
    "union",
    "unsigned",
    "void",
    "volatile",
    "while",
    "bool",
    "true",
    "false",
    "alignas",
    "alignof",
    "asm",
    "typeof",
    "typeof_unqual",
    "nullptr",
    "static_assert",
    "thread_local",
    "constexpr",
    "class",
    "new",
    "delete",
    "this",
    "template",
    "namespace",
    "private",
    "public",
    "protected",
    "virtual",
    "operator",
    "friend",
    "try",
    "catch",
    "throw",
    "using",
    "explicit",
    "mutable",
    "typename",
    "and",
    "or",
    "not",
    "xor",
    "bitand",
    "bitor",
    "compl",
    "and_eq",
    "or_eq",
    "xor_eq",
    "not_eq",
    "NULL",
    "offsetof",
    "wchar_t",
    "char8_t",
    "char16_t",
    "char32_t",
    "decltype",
    "noexcept",
    "export",
    "module",
    "import",
    "concept",
    "requires",
    "co_await",
    "co_return",
    "co_yield",
    "consteval",
    "constinit",
    "reinterpret_cast",
    "static_cast",
    "const_cast",
    "dynamic_cast",
    "typeid",
];

fn is_plain_ident(s: &str) -> bool {
    let mut chars = s.chars();
    matches!(chars.next(), Some(c) if c.is_ascii_alphabetic())
        && s.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
}

/// A C name for a struct member: the source name when C can take it as it is, else a
/// spelling derived from it; unique within the struct.
fn member_name(name: &str, index: usize, used: &mut HashSet<String>) -> String {
    let upper_macro = name.bytes().all(|b| !b.is_ascii_lowercase())
        && (name.ends_with("_MAX") || name.ends_with("_MIN") || name.ends_with("_C"));
    let ok = is_plain_ident(name)
        && !RESERVED.contains(&name)
        && !upper_macro
        && !name.starts_with("plcc_");
    let mut s = if ok {
        name.to_string()
    } else {
        let clean: String = name
            .chars()
            .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
            .collect();
        format!("f{index}_{clean}")
    };
    while !used.insert(s.clone()) {
        s.push('_');
    }
    s
}

fn c_scalar(ty: Type, elem: Option<ElemType>) -> &'static str {
    use ElemType::*;
    match elem {
        Some(Bool) => "uint8_t",
        Some(SInt) => "int8_t",
        Some(Int) => "int16_t",
        Some(DInt | Time) => "int32_t",
        Some(LInt | LTime) => "int64_t",
        Some(USInt | Byte | Char) => "uint8_t",
        Some(UInt | Word | WChar) => "uint16_t",
        Some(UDInt | DWord | Date | Tod | Dt) => "uint32_t",
        Some(ULInt | LWord | LDate | LTod | LDt) => "uint64_t",
        Some(Real) => "float",
        Some(LReal) => "double",
        Some(Ref) => "void *",
        None => match ty {
            Type::I1 => "uint8_t",
            Type::I8 => "int8_t",
            Type::I16 => "int16_t",
            Type::I32 => "int32_t",
            Type::I64 => "int64_t",
            Type::F32 => "float",
            Type::F64 => "double",
            Type::Ptr => "void *",
        },
    }
}

/// The C spelling of an aggregate type.
fn agg_type(module: &Module, id: AggId) -> String {
    match module.agg(id) {
        AggDef::Struct(s) => format!("struct {}", mangle("plcc_s_", &s.name)),
        AggDef::Array(a) => mangle("plcc_a_", &a.name),
    }
}

/// `T name` for a member or object of memory type `t`.
fn declaration(module: &Module, t: MemType, elem: Option<ElemType>, name: &str) -> String {
    match t {
        MemType::Scalar(ty) => {
            let c = c_scalar(ty, elem);
            if c.ends_with('*') {
                format!("{c}{name}")
            } else {
                format!("{c} {name}")
            }
        }
        MemType::Agg(a) => format!("{} {name}", agg_type(module, a)),
    }
}

fn describe(module: &Module, t: MemType, elem: Option<ElemType>) -> String {
    match (t, elem) {
        (_, Some(e)) => e.name().to_string(),
        (MemType::Scalar(ty), None) => ty.name().to_string(),
        (MemType::Agg(a), None) => module.agg(a).name().to_string(),
    }
}

fn comment(s: &str) -> String {
    s.replace("*/", "* /")
}

/// Aggregates in an order where each comes after those it contains.
fn agg_order(module: &Module) -> Vec<AggId> {
    fn visit(module: &Module, id: AggId, seen: &mut [bool], out: &mut Vec<AggId>) {
        if seen[id.index()] {
            return;
        }
        seen[id.index()] = true;
        let mut dep = |t: MemType| {
            if let MemType::Agg(a) = t {
                visit(module, a, seen, out);
            }
        };
        match module.agg(id) {
            AggDef::Struct(s) => s.fields.iter().for_each(|f| dep(f.ty)),
            AggDef::Array(a) => dep(a.elem),
        }
        out.push(id);
    }
    let mut seen = vec![false; module.aggs.len()];
    let mut out = Vec::with_capacity(module.aggs.len());
    for i in 0..module.aggs.len() {
        visit(module, AggId::new(i), &mut seen, &mut out);
    }
    out
}

/// The header for `module` compiled for `triple`.
pub(crate) fn generate(module: &Module, dl: &DataLayout, triple: &str) -> String {
    let mut h = String::new();
    let w = &mut h;
    let _ = writeln!(
        w,
        "/* Generated by plcc for {triple}: the memory layout and entry points of the \
         compiled PLC program.\n * Data lives in one block, `{DATA_SYMBOL}`; every data \
         object is also a symbol of its own inside it.\n * Offsets are in bytes; BOOLs take \
         one byte holding 0 or 1. */"
    );
    let _ = writeln!(w, "#ifndef PLCC_PROGRAM_H\n#define PLCC_PROGRAM_H\n");
    let _ = writeln!(w, "#include <stddef.h>\n#include <stdint.h>\n");
    let _ = writeln!(
        w,
        "#ifdef __cplusplus\nextern \"C\" {{\n#define PLCC_ASSERT(c, m) static_assert(c, m)\n\
         #else\n#define PLCC_ASSERT(c, m) _Static_assert(c, m)\n#endif\n"
    );
    let _ = writeln!(
        w,
        "/* The runtime context the code reads the clock from and raises the fault flag in. */\n\
         typedef struct plcc_runtime {{\n    \
         int32_t clock_ms;    /* offset 0: the PLC clock in ms (TIME), set before each scan */\n    \
         int32_t _plcc_pad0;\n    \
         int64_t clock_ns;    /* offset 8: the same instant in ns (LTIME) */\n    \
         uint8_t fault;       /* offset 16: set to 1 by a runtime fault; the host clears it */\n    \
         uint8_t stop;        /* offset 17: nonzero asks a running scan to stop (watchdog) */\n    \
         uint8_t _plcc_pad1[6];\n\
         }} plcc_runtime;\n\
         PLCC_ASSERT(offsetof(plcc_runtime, clock_ns) == 8, \"plcc layout\");\n\
         PLCC_ASSERT(offsetof(plcc_runtime, fault) == 16, \"plcc layout\");\n\
         PLCC_ASSERT(offsetof(plcc_runtime, stop) == 17, \"plcc layout\");\n\
         PLCC_ASSERT(sizeof(plcc_runtime) == 24, \"plcc layout\");\n\
         extern plcc_runtime {RT_SYMBOL};\n"
    );

    for id in agg_order(module) {
        let al = dl.layout.agg(id);
        match module.agg(id) {
            AggDef::Array(a) => {
                let name = mangle("plcc_a_", &a.name);
                let _ = writeln!(
                    w,
                    "/* array {}: {} x {}, indexed from {}; stride {}, {} bytes */",
                    comment(&a.name),
                    a.len,
                    comment(&describe(module, a.elem, a.elem_type)),
                    a.lower,
                    al.stride,
                    al.size
                );
                let _ = writeln!(
                    w,
                    "typedef {}[{}];",
                    declaration(module, a.elem, a.elem_type, &name),
                    a.len
                );
                let _ = writeln!(
                    w,
                    "PLCC_ASSERT(sizeof({name}) == {}, \"plcc layout\");\n",
                    al.size
                );
            }
            AggDef::Struct(s) => {
                let tag = mangle("plcc_s_", &s.name);
                let _ = writeln!(
                    w,
                    "/* {} {}: {} bytes, aligned to {} */",
                    s.kind.name(),
                    comment(&s.name),
                    al.size,
                    al.align
                );
                let _ = writeln!(w, "struct {tag} {{");
                let mut used = HashSet::new();
                let mut at: u64 = 0;
                let mut pads = 0;
                let mut names = Vec::with_capacity(s.fields.len());
                for (i, f) in s.fields.iter().enumerate() {
                    let off = al.field_offsets[i] as u64;
                    if off > at {
                        let _ = writeln!(w, "    uint8_t _plcc_pad{pads}[{}];", off - at);
                        pads += 1;
                    }
                    let name = member_name(&f.name, i, &mut used);
                    let mut note = format!(
                        "offset {off}: {} {}",
                        f.role.name(),
                        describe(module, f.ty, f.elem)
                    );
                    if name != f.name {
                        let _ = write!(note, " `{}`", f.name);
                    }
                    if let Some(loc) = &f.location {
                        let _ = write!(note, " at {loc}");
                    }
                    let _ = writeln!(
                        w,
                        "    {}; /* {} */",
                        declaration(module, f.ty, f.elem, &name),
                        comment(&note)
                    );
                    at = off + dl.layout.size_of(f.ty) as u64;
                    names.push(name);
                }
                if (al.size as u64) > at {
                    let _ = writeln!(w, "    uint8_t _plcc_pad{pads}[{}];", al.size as u64 - at);
                }
                let _ = writeln!(w, "}};");
                for (i, name) in names.iter().enumerate() {
                    let _ = writeln!(
                        w,
                        "PLCC_ASSERT(offsetof(struct {tag}, {name}) == {}, \"plcc layout\");",
                        al.field_offsets[i]
                    );
                }
                let _ = writeln!(
                    w,
                    "PLCC_ASSERT(sizeof(struct {tag}) == {}, \"plcc layout\");\n",
                    al.size
                );
            }
        }
    }

    let _ = writeln!(
        w,
        "/* Data memory: {} bytes; each object at its offset in it. */\n\
         #define PLCC_DATA_SIZE {}\n\
         extern unsigned char {DATA_SYMBOL}[];",
        dl.size, dl.size
    );
    for (i, d) in module.data.iter().enumerate() {
        let _ = writeln!(
            w,
            "extern {}; /* {} `{}`, offset {}{} */",
            declaration(module, d.ty, d.elem, &data_symbol(&d.name)),
            d.kind.name(),
            comment(&d.name),
            dl.offsets[i],
            d.location
                .as_ref()
                .map(|l| format!(", at {}", comment(l)))
                .unwrap_or_default()
        );
    }
    let _ = writeln!(w);

    let _ = writeln!(w, "/* Entry points. */");
    let mut declared = HashSet::new();
    if let Some(g) = module.init_globals {
        let name = func_symbol(&module.func(g).name);
        let _ = writeln!(w, "void {name}(void); /* initialises the globals */");
        declared.insert(name);
    }
    for p in &module.programs {
        for (f, what) in [(p.body, "body"), (p.init, "init")] {
            let name = func_symbol(&module.func(f).name);
            if declared.insert(name.clone()) {
                let _ = writeln!(
                    w,
                    "void {name}(void *instance); /* program `{}` {what} */",
                    comment(&p.name)
                );
            }
        }
    }
    let _ = writeln!(w);

    // Cold start, clock and scan, as the JIT does them, for a host runtime to call.
    let _ = writeln!(
        w,
        "/* Cold start: clears the fault and the clock, then runs every init. Memory is not\n \
         * zeroed first: the init functions store every variable's initial value. */\n\
         static inline void plcc_cold_start(void) {{\n    \
         {RT_SYMBOL}.clock_ms = 0;\n    {RT_SYMBOL}.clock_ns = 0;\n    {RT_SYMBOL}.fault = 0;"
    );
    if let Some(g) = module.init_globals {
        let _ = writeln!(w, "    {}();", func_symbol(&module.func(g).name));
    }
    for p in &module.programs {
        let _ = writeln!(
            w,
            "    {}(&{});",
            func_symbol(&module.func(p.init).name),
            data_symbol(&module.data[p.data.index()].name)
        );
    }
    let _ = writeln!(
        w,
        "}}\n\n/* Sets the clock the next scan sees (microseconds since cold start). */\n\
         static inline void plcc_set_clock_us(int64_t us) {{\n    \
         int64_t ms = us / 1000 - (us % 1000 < 0);\n    \
         {RT_SYMBOL}.clock_ms = (int32_t)(uint32_t)(uint64_t)ms;\n    \
         {RT_SYMBOL}.clock_ns = (int64_t)((uint64_t)us * 1000u);\n}}\n\n\
         /* One scan: every program body once, in order. */\n\
         static inline void plcc_scan(void) {{"
    );
    for p in &module.programs {
        let _ = writeln!(
            w,
            "    {}(&{});",
            func_symbol(&module.func(p.body).name),
            data_symbol(&module.data[p.data.index()].name)
        );
    }
    let _ = writeln!(w, "}}\n\n#ifdef __cplusplus\n}}\n#endif\n#endif");
    h
}
