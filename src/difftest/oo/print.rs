//! The printer of the object-oriented part: interfaces, function blocks with
//! their methods and properties, `main`'s declarations and statements.

use super::{Oo, OoStmt, Recv, Sig};
use crate::difftest::gen::{Expr, T};
use crate::difftest::print::{expr_text, stmts_text};
use std::fmt::Write;

impl OoStmt {
    /// The statement's text at indentation `pad`.
    pub fn text(&self, pad: &str) -> String {
        let mut o = String::new();
        match self {
            OoStmt::Call {
                target,
                recv,
                method,
                args,
                named,
            } => {
                let (r, guard) = recv_text(recv);
                let mut call = format!("{r}.{method}(");
                for (i, a) in args.iter().enumerate() {
                    if i > 0 {
                        call.push_str(", ");
                    }
                    if let Some(n) = named.get(i) {
                        let _ = write!(call, "{n} := ");
                    }
                    call.push_str(&expr_text(a));
                }
                call.push(')');
                let line = match target {
                    Some(t) => format!("{t} := {call};"),
                    None => format!("{call};"),
                };
                match guard {
                    Some(g) => {
                        let _ =
                            writeln!(o, "{pad}IF {g} <> NULL THEN\n{pad}    {line}\n{pad}END_IF;");
                    }
                    None => {
                        let _ = writeln!(o, "{pad}{line}");
                    }
                }
            }
            OoStmt::Each {
                array,
                len,
                method,
                args,
                target,
                t,
            } => {
                let args: Vec<String> = args.iter().map(expr_text).collect();
                let call = format!("{array}[oo_k].{method}({})", args.join(", "));
                let value = match t {
                    T::Bool | T::Word => format!("{target} XOR {call}"),
                    _ => format!("{target} + {call}"),
                };
                let _ = writeln!(
                    o,
                    "{pad}FOR oo_k := 0 TO {} DO\n{pad}    IF {array}[oo_k] <> NULL THEN\n{pad}        {target} := {value};\n{pad}    END_IF;\n{pad}END_FOR;",
                    len - 1
                );
            }
            OoStmt::Bind { place, value } => {
                let (p, _) = recv_text(place);
                let v = match (place, value) {
                    (_, None) => "NULL".to_string(),
                    (Recv::Deref(_), Some(v)) => format!("REF({v})"),
                    (_, Some(v)) => v.clone(),
                };
                let p = match place {
                    Recv::Deref(r) => r.clone(),
                    _ => p,
                };
                let _ = writeln!(o, "{pad}{p} := {v};");
            }
            OoStmt::Invoke { inst, args } => {
                let args: Vec<String> = args
                    .iter()
                    .map(|(n, e)| format!("{n} := {}", expr_text(e)))
                    .collect();
                let _ = writeln!(o, "{pad}{inst}({});", args.join(", "));
            }
            OoStmt::Assign { target, value } => {
                let _ = writeln!(o, "{pad}{target} := {};", expr_text(value));
            }
            OoStmt::SetMember {
                inst,
                member,
                value,
            } => {
                let _ = writeln!(o, "{pad}{inst}.{member} := {};", expr_text(value));
            }
        }
        o
    }
}

/// The text of a receiver and of what its NULL guard compares, if it has one.
fn recv_text(r: &Recv) -> (String, Option<String>) {
    match r {
        Recv::Plain(n) => (n.clone(), None),
        Recv::Itf(n) => (n.clone(), Some(n.clone())),
        Recv::Elem(a, len, i) => {
            let t = format!("{a}[LIMIT(0, {}, {})]", expr_text(i), len - 1);
            (t.clone(), Some(t))
        }
        Recv::Deref(r) => (format!("{r}^"), Some(r.clone())),
    }
}

/// `name : T := init;` lines.
fn var_lines(o: &mut String, vars: &[(String, T, Expr)], pad: &str) {
    for (n, t, init) in vars {
        let _ = writeln!(o, "{pad}{n} : {} := {};", t.name(), expr_text(init));
    }
}

/// The loop variables (`k1`, `w2`) a body's text assigns, declared.
fn loop_vars(code: &str) -> String {
    let mut o = String::new();
    for c in ['k', 'w'] {
        let used: Vec<String> = (1..=6)
            .map(|i| format!("{c}{i}"))
            .filter(|v| code.contains(&format!("{v} :=")))
            .collect();
        if !used.is_empty() {
            let _ = writeln!(o, "    {} : INT;", used.join(", "));
        }
    }
    o
}

fn sig_header(o: &mut String, kw: &str, mods: &str, s: &Sig) {
    let _ = write!(o, "{kw}{mods} {}", s.name);
    if let Some(t) = s.result {
        let _ = write!(o, " : {}", t.name());
    }
    o.push('\n');
    if !s.inputs.is_empty() {
        o.push_str("VAR_INPUT\n");
        for (n, t) in &s.inputs {
            let _ = writeln!(o, "    {n} : {};", t.name());
        }
        o.push_str("END_VAR\n");
    }
}

impl Oo {
    /// The interfaces and function blocks, as ST.
    pub fn text(&self) -> String {
        let mut o = String::new();
        for i in &self.ifaces {
            let _ = write!(o, "INTERFACE {}", i.name);
            if let Some(e) = i.extends {
                let _ = write!(o, " EXTENDS {}", self.ifaces[e].name);
            }
            o.push('\n');
            for s in &i.methods {
                sig_header(&mut o, "METHOD", "", s);
                o.push_str("END_METHOD\n");
            }
            o.push_str("END_INTERFACE\n\n");
        }
        for c in &self.classes {
            o.push_str(if c.is_class {
                "CLASS "
            } else {
                "FUNCTION_BLOCK "
            });
            if c.is_abstract {
                o.push_str("ABSTRACT ");
            }
            if c.is_final {
                o.push_str("FINAL ");
            }
            o.push_str(&c.name);
            if let Some(b) = c.base {
                let _ = write!(o, " EXTENDS {}", self.classes[b].name);
            }
            if !c.implements.is_empty() {
                let names: Vec<&str> = c
                    .implements
                    .iter()
                    .map(|&i| self.ifaces[i].name.as_str())
                    .collect();
                let _ = write!(o, " IMPLEMENTS {}", names.join(", "));
            }
            o.push('\n');
            for (kw, vars) in [
                ("VAR_INPUT", &c.inputs),
                ("VAR_OUTPUT", &c.outputs),
                ("VAR", &c.vars),
            ] {
                if !vars.is_empty() {
                    let _ = writeln!(o, "{kw}");
                    var_lines(&mut o, vars, "    ");
                    o.push_str("END_VAR\n");
                }
            }
            for m in &c.methods {
                let mut mods = String::from(if m.public { " PUBLIC" } else { " PROTECTED" });
                if m.is_abstract {
                    mods.push_str(" ABSTRACT");
                }
                if m.is_final {
                    mods.push_str(" FINAL");
                }
                if m.over {
                    mods.push_str(" OVERRIDE");
                }
                sig_header(&mut o, "METHOD", &mods, &m.sig);
                if !m.is_abstract {
                    let body = stmts_text(&m.body, 1);
                    let loops = loop_vars(&body);
                    if !m.locals.is_empty() || !loops.is_empty() {
                        o.push_str("VAR\n");
                        var_lines(&mut o, &m.locals, "    ");
                        o.push_str(&loops);
                        o.push_str("END_VAR\n");
                    }
                    if !m.inst.is_empty() {
                        o.push_str("VAR_INST\n");
                        var_lines(&mut o, &m.inst, "    ");
                        o.push_str("END_VAR\n");
                    }
                    o.push_str(&body);
                }
                o.push_str("END_METHOD\n");
            }
            for p in &c.props {
                let _ = writeln!(o, "PROPERTY PUBLIC {} : {}", p.name, p.t.name());
                for (kw, body) in [("GET", &p.get), ("SET", &p.set)] {
                    let text = stmts_text(body, 1);
                    let _ = writeln!(o, "{kw}");
                    let loops = loop_vars(&text);
                    if !loops.is_empty() {
                        let _ = write!(o, "VAR\n{loops}END_VAR\n");
                    }
                    o.push_str(&text);
                    let _ = writeln!(o, "END_{kw}");
                }
                o.push_str("END_PROPERTY\n");
            }
            // The FB's own loop variables would clash with none of its members:
            // `k1`... are declared in the VAR section when the body uses them.
            if c.super_body {
                o.push_str("    SUPER^();\n");
            }
            o.push_str(&stmts_text(&c.body, 1));
            o.push_str(if c.is_class {
                "END_CLASS\n\n"
            } else {
                "END_FUNCTION_BLOCK\n\n"
            });
        }
        o
    }

    /// `main`'s declarations of the OO part (instances, interface variables and
    /// arrays, references, result variables, the loop variable `oo_k`); `code` is
    /// `main`'s body.
    pub fn decls(&self, code: &str) -> String {
        let mut o = String::new();
        for (n, c) in &self.insts {
            let _ = writeln!(o, "    {n} : {};", self.classes[*c].name);
        }
        for (n, i) in &self.itf_vars {
            let _ = writeln!(o, "    {n} : {};", self.ifaces[*i].name);
        }
        for (n, i, len) in &self.arrays {
            let _ = writeln!(
                o,
                "    {n} : ARRAY[0..{}] OF {};",
                len - 1,
                self.ifaces[*i].name
            );
        }
        for (n, c) in &self.refs {
            let _ = writeln!(o, "    {n} : REF_TO {};", self.classes[*c].name);
        }
        for (n, t) in &self.results {
            let _ = writeln!(o, "    {n} : {};", t.name());
        }
        if code.contains("oo_k :=") {
            o.push_str("    oo_k : INT;\n");
        }
        o
    }
}
