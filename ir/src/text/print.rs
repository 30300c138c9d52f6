//! The printer of the text form (see `docs/ir.md`).
//!
//! The printer never panics, even on an invalid module (the verifier prints the
//! instructions it complains about): ids out of range print as `%?agg7`, `@?func3`,
//! `v9: ?` and the like, which do not parse back.

use crate::diag::Span;
use crate::entities::{AggId, DataId, FuncId, Inst, SlotId, TableId, Value};
use crate::function::Function;
use crate::inst::{BlockCall, InstData};
use crate::module::{AggDef, Module};
use crate::types::{ElemType, MemType, Type};
use std::fmt::{self, Write};

/// What the printer writes besides the IR itself.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
pub struct PrintOptions {
    /// Write the source location of instructions and functions (`!F:S..E`).
    pub locations: bool,
    /// Number the values and blocks of each function afresh in the order they first
    /// appear in its text (`block0`, `v0`, `v1`, ...), so that two functions that
    /// differ only in how their builders numbered them print the same.
    pub canonical: bool,
}

impl PrintOptions {
    /// The text with source locations, as the round trip through the parser keeps it.
    pub const LOCATED: PrintOptions = PrintOptions {
        locations: true,
        canonical: false,
    };
}

/// Prints a whole module in the text form.
pub fn print_module(m: &Module, opts: &PrintOptions) -> String {
    let mut sections: Vec<String> = Vec::new();
    if !m.files.is_empty() {
        let mut s = String::new();
        for (i, name) in m.files.iter().enumerate() {
            s.push_str("file ");
            s.push_str(&i.to_string());
            s.push(' ');
            write_quoted(&mut s, name);
            s.push('\n');
        }
        sections.push(s);
    }
    if m.unchecked_pointers {
        sections.push("unchecked_pointers\n".to_string());
    }
    if !m.aggs.is_empty() {
        let mut s = String::new();
        for agg in &m.aggs {
            write_agg(&mut s, m, agg);
        }
        sections.push(s);
    }
    if !m.data.is_empty() {
        let mut s = String::new();
        for d in &m.data {
            s.push_str("data ");
            write_name(&mut s, '@', &d.name);
            s.push_str(": ");
            write_mem_type(&mut s, m, d.ty);
            write_elem(&mut s, d.elem);
            s.push(' ');
            s.push_str(d.kind.name());
            write_location(&mut s, d.location.as_deref());
            s.push('\n');
        }
        sections.push(s);
    }
    if !m.tables.is_empty() {
        let mut s = String::new();
        for (i, t) in m.tables.iter().enumerate() {
            let _ = write!(s, "table {} ", TableId::new(i));
            write_quoted(&mut s, &t.name);
            s.push_str(" (");
            for (k, p) in t.params.iter().enumerate() {
                if k > 0 {
                    s.push_str(", ");
                }
                s.push_str(p.name());
            }
            s.push(')');
            if let Some(r) = t.result {
                s.push_str(" -> ");
                s.push_str(r.name());
            }
            s.push_str(" = [");
            for (k, e) in t.entries.iter().enumerate() {
                if k > 0 {
                    s.push_str(", ");
                }
                match e {
                    Some(f) => write_func_ref(&mut s, m, *f),
                    None => s.push('-'),
                }
            }
            s.push_str("]\n");
        }
        sections.push(s);
    }
    for f in &m.funcs {
        sections.push(print_function(m, f, opts));
    }
    if !m.programs.is_empty()
        || m.init_globals.is_some()
        || m.globals.is_some()
        || m.configuration.is_some()
    {
        let mut s = String::new();
        for p in &m.programs {
            s.push_str("program ");
            write_quoted(&mut s, &p.name);
            s.push_str(" data ");
            write_data_ref(&mut s, m, p.data);
            s.push_str(" body ");
            write_func_ref(&mut s, m, p.body);
            s.push_str(" init ");
            write_func_ref(&mut s, m, p.init);
            if let Some(us) = p.interval_us {
                let _ = write!(s, " interval_us {us}");
            }
            if let Some(prio) = p.priority {
                let _ = write!(s, " priority {prio}");
            }
            s.push('\n');
        }
        if let Some(f) = m.init_globals {
            s.push_str("init_globals ");
            write_func_ref(&mut s, m, f);
            s.push('\n');
        }
        if let Some(d) = m.globals {
            s.push_str("globals ");
            write_data_ref(&mut s, m, d);
            s.push('\n');
        }
        if let Some(c) = &m.configuration {
            s.push_str("configuration ");
            write_quoted(&mut s, &c.name);
            s.push('\n');
            for r in &c.resources {
                s.push_str("resource ");
                write_quoted(&mut s, &r.name);
                for (kw, list) in [("programs", &r.programs), ("globals", &r.globals)] {
                    if !list.is_empty() {
                        s.push(' ');
                        s.push_str(kw);
                        for n in list.iter() {
                            s.push(' ');
                            write_quoted(&mut s, n);
                        }
                    }
                }
                s.push('\n');
            }
        }
        sections.push(s);
    }
    sections.join("\n")
}

/// Prints one function of `m` (or one being built for `m`) in the text form.
pub fn print_function(m: &Module, f: &Function, opts: &PrintOptions) -> String {
    let mut s = String::new();
    s.push_str("func ");
    write_name(&mut s, '@', &f.name);
    s.push('(');
    for (i, t) in f.params.iter().enumerate() {
        if i > 0 {
            s.push_str(", ");
        }
        s.push_str(t.name());
    }
    s.push(')');
    if let Some(r) = f.ret {
        s.push_str(" -> ");
        s.push_str(r.name());
    }
    s.push(' ');
    s.push_str(f.kind.name());
    if opts.locations {
        if let Some(span) = f.span {
            s.push(' ');
            write_span(&mut s, span);
        }
    }
    s.push_str(" {\n");
    for (i, slot) in f.slots.iter().enumerate() {
        let _ = write!(s, "    {} = slot ", SlotId::new(i));
        write_mem_type(&mut s, m, slot.ty);
        s.push(' ');
        write_quoted(&mut s, &slot.name);
        s.push('\n');
    }
    for (n, &b) in f.layout.iter().enumerate() {
        if n > 0 {
            s.push('\n');
        }
        let _ = write!(s, "{b}");
        let params: &[Value] = f.blocks.get(b.index()).map_or(&[], |d| &d.params);
        if !params.is_empty() {
            s.push('(');
            for (i, &v) in params.iter().enumerate() {
                if i > 0 {
                    s.push_str(", ");
                }
                let _ = write!(s, "{v}: ");
                match f.values.get(v.index()) {
                    Some(d) => s.push_str(d.ty.name()),
                    None => s.push('?'),
                }
            }
            s.push(')');
        }
        s.push_str(":\n");
        let insts: &[Inst] = f.blocks.get(b.index()).map_or(&[], |d| &d.insts);
        for &i in insts {
            s.push_str("    ");
            write_inst(&mut s, m, f, i, opts.locations);
            s.push('\n');
        }
    }
    s.push_str("}\n");
    if opts.canonical {
        canonical_numbers(&s)
    } else {
        s
    }
}

/// `text` (one function) with its values `vN` and blocks `blockN` renamed in the
/// order they first appear, from 0. Names from the source are left alone: a word
/// inside quotes or right after `@`, `%`, `.` or `$` (`@v1`, `%main.v1`).
pub(super) fn canonical_numbers(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let mut names: std::collections::HashMap<&str, String> = std::collections::HashMap::new();
    let mut counts = [0usize; 2];
    let mut rest = text;
    let mut prev = ' ';
    let mut quoted = false;
    while let Some(c) = rest.chars().next() {
        let len = rest
            .find(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
            .unwrap_or(rest.len());
        if len == 0 {
            if quoted && c == '\\' {
                // An escape: the backslash and the character it escapes.
                let n = rest[1..].chars().next().map_or(0, char::len_utf8);
                out.push_str(&rest[..1 + n]);
                rest = &rest[1 + n..];
                prev = ' ';
                continue;
            }
            if c == '"' {
                quoted = !quoted;
            }
            out.push(c);
            prev = c;
            rest = &rest[c.len_utf8()..];
            continue;
        }
        let word = &rest[..len];
        rest = &rest[len..];
        let numbered = |p: &str| {
            word.strip_prefix(p)
                .is_some_and(|n| !n.is_empty() && n.bytes().all(|b| b.is_ascii_digit()))
        };
        let kind = if quoted || matches!(prev, '@' | '%' | '.' | '$') {
            None
        } else if numbered("v") {
            Some(0)
        } else if numbered("block") {
            Some(1)
        } else {
            None
        };
        match kind {
            Some(k) => {
                let new = names.entry(word).or_insert_with(|| {
                    counts[k] += 1;
                    format!("{}{}", ["v", "block"][k], counts[k] - 1)
                });
                out.push_str(new);
            }
            None => out.push_str(word),
        }
        prev = word.chars().last().unwrap_or(' ');
    }
    out
}

/// Prints one instruction (`v5 = iadd v3, v4`) without location or indentation.
pub fn print_inst(m: &Module, f: &Function, inst: Inst) -> String {
    let mut s = String::new();
    write_inst(&mut s, m, f, inst, false);
    s
}

impl fmt::Display for Module {
    /// The text form without locations.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&print_module(self, &PrintOptions::default()))
    }
}

/// True if `s` can be written without quotes after `%` or `@`.
pub(crate) fn is_plain_name(s: &str) -> bool {
    let mut chars = s.chars();
    match chars.next() {
        Some(c) if c.is_ascii_alphabetic() || c == '_' => {}
        _ => return false,
    }
    chars.all(|c| c.is_ascii_alphanumeric() || matches!(c, '_' | '$' | '.'))
}

/// True if a field name can be written without quotes (no dots: `%S.f` splits at the
/// last dot).
pub(crate) fn is_plain_field(s: &str) -> bool {
    is_plain_name(s) && !s.contains('.')
}

/// Writes `s` as a quoted string with escapes.
pub(crate) fn write_quoted(out: &mut String, s: &str) {
    out.push('"');
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            '\r' => out.push_str("\\r"),
            '\t' => out.push_str("\\t"),
            c if c.is_control() => {
                let _ = write!(out, "\\u{{{:x}}}", c as u32);
            }
            c => out.push(c),
        }
    }
    out.push('"');
}

/// Writes a name after its sigil, quoted when needed.
pub(crate) fn write_name(out: &mut String, sigil: char, name: &str) {
    out.push(sigil);
    if is_plain_name(name) {
        out.push_str(name);
    } else {
        write_quoted(out, name);
    }
}

fn write_span(out: &mut String, span: Span) {
    let _ = write!(out, "!{}:{}..{}", span.file.0, span.start, span.end);
}

fn write_location(out: &mut String, loc: Option<&str>) {
    if let Some(l) = loc {
        out.push_str(" at ");
        write_quoted(out, l);
    }
}

fn write_elem(out: &mut String, elem: Option<ElemType>) {
    if let Some(e) = elem {
        out.push(' ');
        out.push_str(e.name());
    }
}

fn write_agg_ref(out: &mut String, m: &Module, id: AggId) {
    match m.aggs.get(id.index()) {
        Some(a) => write_name(out, '%', a.name()),
        None => {
            let _ = write!(out, "%?{id}");
        }
    }
}

fn write_data_ref(out: &mut String, m: &Module, id: DataId) {
    match m.data.get(id.index()) {
        Some(d) => write_name(out, '@', &d.name),
        None => {
            let _ = write!(out, "@?{id}");
        }
    }
}

fn write_func_ref(out: &mut String, m: &Module, id: FuncId) {
    match m.funcs.get(id.index()) {
        Some(f) => write_name(out, '@', &f.name),
        None => {
            let _ = write!(out, "@?{id}");
        }
    }
}

fn write_mem_type(out: &mut String, m: &Module, t: MemType) {
    match t {
        MemType::Scalar(t) => out.push_str(t.name()),
        MemType::Agg(a) => write_agg_ref(out, m, a),
    }
}

fn write_agg(out: &mut String, m: &Module, agg: &AggDef) {
    match agg {
        AggDef::Struct(s) => {
            out.push_str("struct ");
            write_name(out, '%', &s.name);
            out.push(' ');
            out.push_str(s.kind.name());
            out.push_str(" {\n");
            for f in &s.fields {
                out.push_str("    ");
                out.push_str(f.role.name());
                out.push(' ');
                if is_plain_field(&f.name) {
                    out.push_str(&f.name);
                } else {
                    write_quoted(out, &f.name);
                }
                out.push_str(": ");
                write_mem_type(out, m, f.ty);
                write_elem(out, f.elem);
                write_location(out, f.location.as_deref());
                out.push('\n');
            }
            out.push_str("}\n");
        }
        AggDef::Array(a) => {
            out.push_str("array ");
            write_name(out, '%', &a.name);
            let _ = write!(out, " = [{} x ", a.len);
            write_mem_type(out, m, a.elem);
            write_elem(out, a.elem_type);
            let _ = writeln!(out, "] lower {}", a.lower);
        }
    }
}

/// The text of a float constant: a decimal that reads back to the same bits, else the
/// raw bits in hex.
pub(crate) fn format_float(ty: Type, bits: u64) -> String {
    match ty {
        Type::F32 if bits <= u32::MAX as u64 => {
            let x = f32::from_bits(bits as u32);
            let s = format!("{x:?}");
            if s.parse::<f32>().map(f32::to_bits) == Ok(bits as u32) {
                return s;
            }
        }
        Type::F64 => {
            let x = f64::from_bits(bits);
            let s = format!("{x:?}");
            if s.parse::<f64>().map(f64::to_bits) == Ok(bits) {
                return s;
            }
        }
        _ => {}
    }
    format!("{bits:#x}")
}

fn write_args(out: &mut String, args: &[Value]) {
    for (i, a) in args.iter().enumerate() {
        if i > 0 {
            out.push_str(", ");
        }
        let _ = write!(out, "{a}");
    }
}

fn write_block_call(out: &mut String, bc: &BlockCall) {
    let _ = write!(out, "{}", bc.block);
    if !bc.args.is_empty() {
        out.push('(');
        write_args(out, &bc.args);
        out.push(')');
    }
}

fn write_inst(out: &mut String, m: &Module, f: &Function, inst: Inst, locations: bool) {
    let Some(data) = f.insts.get(inst.index()) else {
        let _ = write!(out, "<no {inst}>");
        return;
    };
    if let Some(Some(r)) = f.results.get(inst.index()) {
        let _ = write!(out, "{r} = ");
    }
    match data {
        InstData::Iconst { ty, imm } => {
            let _ = write!(out, "iconst.{ty} {imm}");
        }
        InstData::SizeOf { ty, of } => {
            let _ = write!(out, "sizeof.{ty} ");
            write_mem_type(out, m, *of);
        }
        InstData::Fconst { ty, bits } => {
            let _ = write!(out, "fconst.{ty} {}", format_float(*ty, *bits));
        }
        InstData::Unary { op, arg } => {
            let _ = write!(out, "{} {arg}", op.name());
        }
        InstData::Binary { op, args } => {
            let _ = write!(out, "{} {}, {}", op.name(), args[0], args[1]);
        }
        InstData::Icmp { cond, args } => {
            let _ = write!(out, "icmp {} {}, {}", cond.name(), args[0], args[1]);
        }
        InstData::Fcmp { cond, args } => {
            let _ = write!(out, "fcmp {} {}, {}", cond.name(), args[0], args[1]);
        }
        InstData::Convert { op, ty, arg } => {
            let _ = write!(out, "{}.{ty} {arg}", op.name());
        }
        InstData::Select {
            cond,
            if_true,
            if_false,
        } => {
            let _ = write!(out, "select {cond}, {if_true}, {if_false}");
        }
        InstData::GlobalAddr { data } => {
            out.push_str("global_addr ");
            write_data_ref(out, m, *data);
        }
        InstData::SlotAddr { slot } => {
            let _ = write!(out, "slot_addr {slot}");
        }
        InstData::FieldAddr { base, agg, field } => {
            let _ = write!(out, "field_addr {base}, ");
            write_agg_ref(out, m, *agg);
            out.push('.');
            let name = match m.aggs.get(agg.index()) {
                Some(AggDef::Struct(s)) => s.fields.get(*field as usize).map(|f| &f.name),
                _ => None,
            };
            match name {
                Some(n) if is_plain_field(n) => out.push_str(n),
                Some(n) => write_quoted(out, n),
                None => {
                    let _ = write!(out, "?{field}");
                }
            }
        }
        InstData::ElemAddr { base, agg, index } => {
            let _ = write!(out, "elem_addr {base}, ");
            write_agg_ref(out, m, *agg);
            let _ = write!(out, ", {index}");
        }
        InstData::Load { ty, addr } => {
            let _ = write!(out, "load.{ty} {addr}");
        }
        InstData::Store { value, addr } => {
            let _ = write!(out, "store {value}, {addr}");
        }
        InstData::Call { func, args } => {
            out.push_str("call ");
            write_func_ref(out, m, *func);
            out.push('(');
            write_args(out, args);
            out.push(')');
        }
        InstData::InlineC { code, agg, data } => {
            out.push_str("inline_c ");
            write_agg_ref(out, m, *agg);
            let _ = write!(out, ", {data}, ");
            write_quoted(out, code);
        }
        InstData::CallTable { table, index, args } => {
            let _ = write!(out, "call_table {table}, {index}(");
            write_args(out, args);
            out.push(')');
        }
        InstData::Intrinsic { op, args } => {
            out.push_str(op.name());
            if !args.is_empty() {
                out.push(' ');
                write_args(out, args);
            }
        }
        InstData::Jump { dest } => {
            out.push_str("jump ");
            write_block_call(out, dest);
        }
        InstData::Brif {
            cond,
            then_dest,
            else_dest,
        } => {
            let _ = write!(out, "brif {cond}, ");
            write_block_call(out, then_dest);
            out.push_str(", ");
            write_block_call(out, else_dest);
        }
        InstData::BrTable {
            arg,
            default,
            table,
        } => {
            let _ = write!(out, "br_table {arg}, ");
            write_block_call(out, default);
            out.push_str(", [");
            for (k, d) in table.iter().enumerate() {
                if k > 0 {
                    out.push_str(", ");
                }
                write_block_call(out, d);
            }
            out.push(']');
        }
        InstData::Return { value } => {
            out.push_str("return");
            if let Some(v) = value {
                let _ = write!(out, " {v}");
            }
        }
    }
    if locations {
        if let Some(Some(span)) = f.spans.get(inst.index()) {
            out.push_str("   ");
            write_span(out, *span);
        }
    }
}
