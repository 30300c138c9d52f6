//! The declarations of the view of a PLCopen file: data types, variable blocks with
//! their initial values, and the configurations with their resources, tasks and
//! program instances, written as IEC text (`to_il` writes the bodies).

use super::map::Out;
use super::xml::{Config, Type, Value, Var, VarGroup};

/// Text safe inside a `(* *)` comment.
pub(super) fn comment_safe(s: &str) -> String {
    s.replace("(*", "( *").replace("*)", "* )")
}

pub(super) fn write_group(o: &mut Out, g: &VarGroup) {
    o.push(g.section.keyword());
    if g.constant {
        o.push(" CONSTANT");
    }
    if g.retain {
        o.push(" RETAIN");
    }
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
    let mut s = format!("\nCONFIGURATION {}\n", c.name.value);
    for r in &c.resources {
        s.push_str(&format!("  RESOURCE {} ON PLC\n", r.name.value));
        for t in &r.tasks {
            let mut props = Vec::new();
            if let Some(i) = &t.interval {
                props.push(format!("INTERVAL := {}", iec_duration(&i.value)));
            }
            if let Some(p) = &t.priority {
                props.push(format!("PRIORITY := {}", p.value));
            }
            s.push_str(&format!(
                "    TASK {}({});\n",
                t.name.value,
                props.join(", ")
            ));
        }
        for t in &r.tasks {
            for i in &t.instances {
                s.push_str(&format!(
                    "    PROGRAM {} WITH {} : {};\n",
                    i.name.value, t.name.value, i.type_name.value
                ));
            }
        }
        for i in &r.instances {
            s.push_str(&format!(
                "    PROGRAM {} : {};\n",
                i.name.value, i.type_name.value
            ));
        }
        s.push_str("  END_RESOURCE\n");
    }
    s.push_str("END_CONFIGURATION\n");
    o.push(&s);
}

/// A task interval as an IEC TIME literal: PLCopen files write `T#10ms` (TC6 2.01),
/// an XML duration such as `PT0.01S`, or the old schema's `00:00:00.100000`
/// (hours, minutes, seconds with a fraction), which Beremiz converts on loading.
fn iec_duration(text: &str) -> String {
    let t = text.trim();
    if let [h, m, sec] = t.split(':').collect::<Vec<_>>()[..] {
        let num = |x: &str| {
            (!x.is_empty() && x.bytes().all(|c| c.is_ascii_digit() || c == b'.'))
                .then(|| x.parse::<f64>().ok())
                .flatten()
        };
        if let (Some(h), Some(m), Some(sec)) = (num(h), num(m), num(sec)) {
            let ms = (h * 3600.0 + m * 60.0 + sec) * 1000.0;
            return format!("T#{}ms", ms.round() as i64);
        }
    }
    let Some(rest) = t.strip_prefix("PT").or_else(|| t.strip_prefix("pt")) else {
        return t.to_string();
    };
    // PTnHnMn.nS
    let mut ms = 0f64;
    let mut num = String::new();
    for ch in rest.chars() {
        match ch.to_ascii_uppercase() {
            'H' => {
                ms += num.parse::<f64>().unwrap_or(0.0) * 3_600_000.0;
                num.clear();
            }
            'M' => {
                ms += num.parse::<f64>().unwrap_or(0.0) * 60_000.0;
                num.clear();
            }
            'S' => {
                ms += num.parse::<f64>().unwrap_or(0.0) * 1000.0;
                num.clear();
            }
            c => num.push(c),
        }
    }
    format!("T#{}ms", ms.round() as i64)
}
