//! The declarations of the view of a PLCopen file: data types, variable blocks with
//! their initial values, and the configurations with their resources, tasks and
//! program instances, written as IEC text (`body` writes the graphical bodies).

use super::map::Out;
use super::xml::{duration_ms, Config, Section, Task, Text, Type, Value, Var, VarGroup};

/// Text safe inside a `(* *)` comment.
pub(super) fn comment_safe(s: &str) -> String {
    s.replace("(*", "( *").replace("*)", "* )")
}

/// A variable group: `VAR_INPUT` ... `END_VAR`, with its attributes. A CODESYS
/// global variable list keeps its name (`VAR_GLOBAL GVL`), by which its variables
/// may be qualified (`GVL.x`); a name that is not an identifier, or a name of
/// another group, is a comment.
pub(super) fn write_group(o: &mut Out, g: &VarGroup) {
    let list = g
        .name
        .as_ref()
        .filter(|n| g.section == Section::Global && crate::st::lexer::is_identifier(&n.value));
    if let Some(n) = g.name.as_ref().filter(|_| list.is_none()) {
        o.push(&format!("(* {} *)\n", comment_safe(&n.value)));
    }
    let start = o.pos();
    o.push(g.section.keyword());
    o.mark(start, g.tag.clone());
    if let Some(n) = list {
        o.push(" ");
        o.push_text(n);
    }
    let start = o.pos();
    if g.constant {
        o.push(" CONSTANT");
    }
    if g.retain {
        o.push(" RETAIN");
    } else if g.non_retain {
        o.push(" NON_RETAIN");
    }
    o.mark(start, g.tag.clone());
    o.push("\n");
    for v in &g.vars {
        o.push("    ");
        write_var(o, v, 1);
        o.push("\n");
    }
    o.push("END_VAR\n");
}

fn write_var(o: &mut Out, v: &Var, depth: usize) {
    let start = o.pos();
    o.push_text(&v.name);
    if let Some(a) = &v.address {
        o.push(" AT ");
        o.push_text(a);
    }
    o.push(" : ");
    write_type(o, &v.ty, depth);
    if let Some(i) = &v.init {
        o.push(" := ");
        write_value(o, i);
    }
    o.push(";");
    o.mark(start, v.name.range.clone());
}

pub(super) fn write_type(o: &mut Out, t: &Type, depth: usize) {
    match t {
        Type::Named(n) => o.push_text(n),
        Type::String { wide, len } => {
            o.push(if *wide { "WSTRING" } else { "STRING" });
            if let Some(l) = len {
                o.push("[");
                o.push_text(l);
                o.push("]");
            }
        }
        Type::Array { dims, elem } => {
            o.push("ARRAY[");
            for (i, (lo, hi)) in dims.iter().enumerate() {
                if i > 0 {
                    o.push(", ");
                }
                o.push_text(lo);
                o.push("..");
                o.push_text(hi);
            }
            o.push("] OF ");
            write_type(o, elem, depth);
        }
        Type::Enum { values, base } => {
            o.push("(");
            for (i, (n, v)) in values.iter().enumerate() {
                if i > 0 {
                    o.push(", ");
                }
                o.push_text(n);
                if let Some(v) = v {
                    o.push(" := ");
                    o.push_text(v);
                }
            }
            o.push(")");
            if let Some(b) = base {
                o.push(" ");
                write_type(o, b, depth);
            }
        }
        Type::Struct(fields) => {
            o.push("STRUCT\n");
            for f in fields {
                o.push(&"    ".repeat(depth + 1));
                write_var(o, f, depth + 1);
                o.push("\n");
            }
            o.push(&"    ".repeat(depth));
            o.push("END_STRUCT");
        }
        Type::Subrange { base, lo, hi } => {
            write_type(o, base, depth);
            o.push(" (");
            o.push_text(lo);
            o.push("..");
            o.push_text(hi);
            o.push(")");
        }
        Type::Ref(b) => {
            o.push("REF_TO ");
            write_type(o, b, depth);
        }
        Type::Pointer(b) => {
            o.push("POINTER TO ");
            write_type(o, b, depth);
        }
    }
}

pub(super) fn write_value(o: &mut Out, v: &Value) {
    match v {
        Value::Simple(t) => o.push_text(t),
        Value::Array(items) => {
            o.push("[");
            for (i, (rep, v)) in items.iter().enumerate() {
                if i > 0 {
                    o.push(", ");
                }
                match rep {
                    Some(r) => {
                        o.push_text(r);
                        o.push("(");
                        write_value(o, v);
                        o.push(")");
                    }
                    None => write_value(o, v),
                }
            }
            o.push("]");
        }
        Value::Struct(members) => {
            o.push("(");
            for (i, (m, v)) in members.iter().enumerate() {
                if i > 0 {
                    o.push(", ");
                }
                o.push_text(m);
                o.push(" := ");
                write_value(o, v);
            }
            o.push(")");
        }
    }
}

/// A configuration as IEC text: its resources, tasks and program instances (its
/// globals are the VAR_GLOBAL blocks written above), so the instances run as their
/// tasks say.
pub(super) fn write_config(o: &mut Out, c: &Config) {
    let start = o.pos();
    o.push("\nCONFIGURATION ");
    o.push_text(&c.name);
    o.mark(start, c.name.range.clone());
    o.push("\n");
    for r in &c.resources {
        let start = o.pos();
        o.push("  RESOURCE ");
        o.push_text(&r.name);
        o.push(" ON PLC");
        o.mark(start, r.name.range.clone());
        o.push("\n");
        for t in &r.tasks {
            write_task(o, t);
        }
        let with_task = r
            .tasks
            .iter()
            .flat_map(|t| t.instances.iter().map(move |i| (i, Some(t))));
        for (i, task) in with_task.chain(r.instances.iter().map(|i| (i, None))) {
            let start = o.pos();
            o.push("    PROGRAM ");
            o.push_text(&i.name);
            if let Some(t) = task {
                o.push(" WITH ");
                o.push_text(&t.name);
            }
            o.push(" : ");
            o.push_text(&i.type_name);
            o.push(";");
            o.mark(start, i.name.range.clone());
            o.push("\n");
        }
        o.push("  END_RESOURCE\n");
    }
    o.push("END_CONFIGURATION\n");
}

/// `TASK name(SINGLE := v, INTERVAL := t, PRIORITY := n);`. An interval of zero is
/// left out: such a task runs in every cycle, as matiec runs it.
fn write_task(o: &mut Out, t: &Task) {
    let start = o.pos();
    o.push("    TASK ");
    o.push_text(&t.name);
    o.push("(");
    let mut first = true;
    let mut prop = |o: &mut Out, name: &str, value: &Text, text: Option<String>| {
        if !first {
            o.push(", ");
        }
        first = false;
        let start = o.pos();
        o.push(name);
        o.push(" := ");
        match text {
            Some(s) => o.push_as(&s, value),
            None => o.push_text(value),
        }
        o.mark(start, value.range.clone());
    };
    if let Some(s) = &t.single {
        prop(o, "SINGLE", s, None);
    }
    if let Some(i) = &t.interval {
        match iec_duration(&i.value) {
            Some(None) => {}
            Some(Some(s)) => prop(o, "INTERVAL", i, Some(s)),
            None => prop(o, "INTERVAL", i, None),
        }
    }
    if let Some(p) = &t.priority {
        prop(o, "PRIORITY", p, None);
    }
    o.push(");");
    o.mark(start, t.name.range.clone());
    o.push("\n");
}

/// A task interval as an IEC TIME literal. PLCopen files write `T#10ms` (TC6 2.01,
/// kept as written), an XML duration such as `PT0.01S`, or the old schema's
/// `00:00:00.100000` (hours, minutes, seconds with a fraction), which Beremiz
/// converts on loading. `Some(None)` for a zero interval; `None` for text that is
/// none of these (written as it is, for the compiler to report).
fn iec_duration(text: &str) -> Option<Option<String>> {
    let ms = duration_ms(text)?;
    if ms == 0.0 {
        return Some(None);
    }
    if text.contains('#') {
        return Some(Some(text.trim().to_string()));
    }
    let us = (ms * 1000.0).round() as i64;
    Some(Some(if us % 1000 == 0 {
        format!("T#{}ms", us / 1000)
    } else {
        format!("T#{us}us")
    }))
}
