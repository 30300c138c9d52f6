//! The printer of the program model: the ST text of a [`Prog`], as the front end
//! reads it.

use super::gen::*;
use std::fmt::Write;

fn print_expr(e: &Expr, out: &mut String) {
    match e {
        Expr::Lit(_, s) | Expr::Var(_, s) => out.push_str(s),
        Expr::Elem(_, i) => {
            out.push_str("arr[");
            print_expr(i, out);
            out.push(']');
        }
        Expr::Bin(_, op, a, b) => {
            out.push('(');
            print_expr(a, out);
            let _ = write!(out, " {op} ");
            print_expr(b, out);
            out.push(')');
        }
        Expr::Un(_, op, a) => {
            let _ = write!(out, "({op} ");
            print_expr(a, out);
            out.push(')');
        }
        Expr::Call(_, f, args) => {
            out.push_str(f);
            out.push('(');
            for (i, a) in args.iter().enumerate() {
                if i > 0 {
                    out.push_str(", ");
                }
                print_expr(a, out);
            }
            out.push(')');
        }
        Expr::At(_, p) => print_path(p, out),
        Expr::Pow(p) => {
            if p.call {
                out.push_str("EXPT(");
                print_operand(&p.base, out);
                out.push_str(", ");
                print_operand(&p.exp, out);
                out.push(')');
            } else {
                out.push('(');
                print_operand(&p.base, out);
                out.push_str(" ** ");
                print_operand(&p.exp, out);
                out.push(')');
            }
        }
    }
}

fn print_path(p: &Path, out: &mut String) {
    for (i, part) in p.parts.iter().enumerate() {
        out.push_str(part);
        if let Some(e) = p.idx.get(i) {
            print_expr(e, out);
        }
    }
}

/// An integer as a literal of type `t` (REAL#-3.0, DINT#4, (-2)).
fn int_lit(t: T, v: i64) -> String {
    match t {
        T::Real | T::Lreal => format!("{}#{:?}", t.name(), v as f64),
        T::Int if v < 0 => format!("({v})"),
        T::Int => format!("{v}"),
        _ if v < 0 => format!("({}#{v})", t.name()),
        _ => format!("{}#{v}", t.name()),
    }
}

fn print_operand(o: &Operand, out: &mut String) {
    let (t, inner) = match o {
        Operand::Lit(t, v) => {
            out.push_str(&int_lit(*t, *v));
            return;
        }
        Operand::Clamp(t, lo, hi, e) => {
            let mut s = format!("LIMIT({}, ", int_lit(T::Int, *lo));
            print_expr(e, &mut s);
            let _ = write!(s, ", {})", int_lit(T::Int, *hi));
            (*t, s)
        }
        Operand::Choice(t, vals, e) => {
            let mut s = "MUX(LIMIT(0, ".to_string();
            print_expr(e, &mut s);
            let _ = write!(s, ", {})", vals.len() - 1);
            for v in vals {
                let _ = if *v < 0 {
                    write!(s, ", (INT#{v})")
                } else {
                    write!(s, ", INT#{v}")
                };
            }
            s.push(')');
            (*t, s)
        }
    };
    if t == T::Int {
        out.push_str(&inner);
    } else {
        let _ = write!(out, "INT_TO_{}({inner})", t.name());
    }
}

fn print_stmts(body: &[Stmt], ind: usize, out: &mut String) {
    let pad = "    ".repeat(ind);
    for s in body {
        match s {
            Stmt::Assign(v, e) => {
                let _ = write!(out, "{pad}{v} := ");
                print_expr(e, out);
                out.push_str(";\n");
            }
            Stmt::AssignElem(i, e) => {
                let _ = write!(out, "{pad}arr[");
                print_expr(i, out);
                out.push_str("] := ");
                print_expr(e, out);
                out.push_str(";\n");
            }
            Stmt::If(c, a, b) => {
                let _ = write!(out, "{pad}IF ");
                print_expr(c, out);
                out.push_str(" THEN\n");
                print_stmts(a, ind + 1, out);
                if !b.is_empty() {
                    let _ = writeln!(out, "{pad}ELSE");
                    print_stmts(b, ind + 1, out);
                }
                let _ = writeln!(out, "{pad}END_IF;");
            }
            Stmt::Fill(a, z, e) => {
                let _ = writeln!(out, "{pad}FOR k{ind} := {a} TO {z} DO");
                let _ = write!(out, "{pad}  arr[k{ind}] := ");
                print_expr(e, out);
                out.push_str(";\n");
                let _ = writeln!(out, "{pad}END_FOR;");
            }
            Stmt::For(a, z, step, body) => {
                let _ = writeln!(out, "{pad}FOR k{ind} := {a} TO {z} BY {step} DO");
                print_stmts(body, ind + 1, out);
                let _ = writeln!(out, "{pad}END_FOR;");
            }
            Stmt::Case(sel, arms, other) => {
                let _ = write!(out, "{pad}CASE ");
                print_expr(sel, out);
                out.push_str(" OF\n");
                for (labels, body) in arms {
                    let labels: Vec<String> = labels
                        .iter()
                        .map(|&(lo, hi)| match lo == hi {
                            true => lo.to_string(),
                            false => format!("{lo}..{hi}"),
                        })
                        .collect();
                    let _ = writeln!(out, "{pad}    {}:", labels.join(", "));
                    print_stmts(body, ind + 2, out);
                }
                if !other.is_empty() {
                    let _ = writeln!(out, "{pad}ELSE");
                    print_stmts(other, ind + 2, out);
                }
                let _ = writeln!(out, "{pad}END_CASE;");
            }
            Stmt::While(n, None, body) => {
                let _ = writeln!(out, "{pad}w{ind} := 0;\n{pad}WHILE w{ind} < {n} DO");
                print_stmts(body, ind + 1, out);
                let _ = writeln!(out, "{pad}    w{ind} := w{ind} + 1;\n{pad}END_WHILE;");
            }
            Stmt::While(n, Some((start, step)), body) => {
                let _ = write!(out, "{pad}w{ind} := ");
                print_expr(start, out);
                let _ = write!(out, ";\n{pad}ws{ind} := ");
                print_expr(step, out);
                let _ = writeln!(out, ";\n{pad}wt{ind} := 0;\n{pad}WHILE w{ind} < {n} DO");
                print_stmts(body, ind + 1, out);
                let _ = writeln!(
                    out,
                    "{pad}    wt{ind} := wt{ind} + 1;\n{pad}    IF wt{ind} > 4 THEN\n{pad}        EXIT;\n{pad}    END_IF;\n{pad}    w{ind} := w{ind} + ws{ind};\n{pad}END_WHILE;"
                );
            }
            Stmt::Raw(text) => {
                let _ = writeln!(out, "{pad}{text}");
            }
            Stmt::CallFb(a, b, target) => {
                let _ = write!(out, "{pad}fb(a := ");
                print_expr(a, out);
                out.push_str(", b := ");
                print_expr(b, out);
                let _ = writeln!(out, ");\n{pad}{target} := fb.r;");
            }
            Stmt::Set(p, e) => {
                out.push_str(&pad);
                print_path(p, out);
                out.push_str(" := ");
                print_expr(e, out);
                out.push_str(";\n");
            }
            Stmt::CallFbAt(i, a, b, target) => {
                let mut idx = String::new();
                print_expr(i, &mut idx);
                let _ = write!(out, "{pad}fbs[{idx}](a := ");
                print_expr(a, out);
                out.push_str(", b := ");
                print_expr(b, out);
                let _ = writeln!(out, ");\n{pad}{target} := fbs[{idx}].r;");
            }
            Stmt::InOut(fb, [x, s, d], k, target) => {
                out.push_str(&pad);
                if *fb {
                    out.push_str("f2(n := ");
                } else {
                    let _ = write!(out, "{target} := fio(x := ");
                }
                print_path(x, out);
                out.push_str(", s := ");
                print_path(s, out);
                out.push_str(", d := ");
                print_path(d, out);
                out.push_str(", k := ");
                print_expr(k, out);
                out.push_str(");\n");
                if *fb {
                    let _ = writeln!(out, "{pad}{target} := f2.r;");
                }
            }
            Stmt::Copy(a, b) => {
                out.push_str(&pad);
                print_path(a, out);
                out.push_str(" := ");
                print_path(b, out);
                out.push_str(";\n");
            }
            Stmt::Oo(o) => out.push_str(&o.text(&pad)),
            Stmt::Ref(r, None) => {
                let _ = writeln!(out, "{pad}{r} := NULL;");
            }
            Stmt::Ref(r, Some(p)) => {
                let _ = write!(out, "{pad}{r} := REF(");
                print_path(p, out);
                out.push_str(");\n");
            }
        }
    }
}

/// The text of an expression, as the printer writes it.
pub(crate) fn expr_text(e: &Expr) -> String {
    let mut s = String::new();
    print_expr(e, &mut s);
    s
}

/// The text of statements at indentation `ind` (the loops' control variables are
/// named by their depth: `k1`, `w2`).
pub(crate) fn stmts_text(body: &[Stmt], ind: usize) -> String {
    let mut s = String::new();
    print_stmts(body, ind, &mut s);
    s
}

impl Prog {
    /// The ST text: a FUNCTION, FBs, the types, PROGRAM `main` and the
    /// CONFIGURATION, if any.
    pub fn to_st(&self) -> String {
        let body = stmts_text(&self.body, 1);
        let mut o = self.prelude();
        let oo_decls = self.oo.as_ref().map_or(String::new(), |oo| oo.decls(&body));
        o.push_str("PROGRAM main\n");
        o.push_str(&self.decls(&body, &oo_decls));
        o.push_str(&body);
        o.push_str("END_PROGRAM\n");
        o.push_str(&self.config_text());
        o
    }

    /// The POUs and types before `main`: the FUNCTION `fun`, the FB `FB1`, the
    /// types, and the VAR_IN_OUT POUs when the program has them.
    pub(crate) fn prelude(&self) -> String {
        let mut o = String::new();
        let has = |d: &str| !self.dropped.iter().any(|x| x == d);
        if has("fun") {
            o.push_str(
                "FUNCTION fun : DINT\nVAR_INPUT x, y : DINT; END_VAR\n    IF y <> 0 THEN\n        fun := x / y + x MOD 3;\n    ELSE\n        fun := x * 2 - 1;\n    END_IF;\nEND_FUNCTION\n\n",
            );
        }
        if has("FB1") {
            o.push_str(
                "FUNCTION_BLOCK FB1\nVAR_INPUT a, b : INT; END_VAR\nVAR_OUTPUT r : INT; END_VAR\nVAR acc : INT; END_VAR\n    acc := acc + a - b;\n    r := acc * 2;\nEND_FUNCTION_BLOCK\n\n",
            );
        }
        if has("Rec") || has("Mode") {
            o.push_str("TYPE\n");
            if has("Rec") {
                o.push_str("    Rec : STRUCT\n        a : INT := 3;\n        b : REAL;\n        c : BOOL;\n        d : ARRAY[0..2] OF DINT := [1, 2, 3];\n    END_STRUCT;\n");
            }
            if has("Mode") {
                o.push_str("    Mode : (Idle, Run := 5, Stop);\n");
            }
            o.push_str("END_TYPE\n\n");
        }
        if let Some(oo) = &self.oo {
            o.push_str(&oo.text());
        }
        if self.inout {
            // Every access to a VAR_IN_OUT is through the address the caller passed;
            // the computed indexes make run-time addresses of those.
            o.push_str(
                "FUNCTION fio : DINT\nVAR_IN_OUT x : INT; s : Rec; d : ARRAY[0..2] OF DINT; END_VAR\nVAR_INPUT k : INT; END_VAR\n    x := x + k;\n    s.a := s.a - x;\n    s.d[LIMIT(0, k, 2)] := s.d[0] + INT_TO_DINT(x);\n    d[1] := d[2] * 2 + s.d[1];\n    s.c := NOT s.c;\n    fio := d[0] + INT_TO_DINT(s.a);\nEND_FUNCTION\n\n",
            );
            o.push_str(
                "FUNCTION_BLOCK FB2\nVAR_IN_OUT n : INT; s : Rec; d : ARRAY[0..2] OF DINT; END_VAR\nVAR_INPUT k : INT; END_VAR\nVAR_OUTPUT r : DINT; END_VAR\nVAR calls : INT; END_VAR\n    calls := calls + 1;\n    n := n * 2 + calls;\n    s.b := s.b + INT_TO_REAL(k);\n    s.d[LIMIT(0, n, 2)] := s.d[LIMIT(0, k, 2)] + d[1];\n    d[LIMIT(0, k, 2)] := INT_TO_DINT(s.a) - d[0];\n    r := s.d[0] + s.d[1] + s.d[2];\nEND_FUNCTION_BLOCK\n\n",
            );
        }
        o
    }

    /// The variable sections of `main` (or of a POU declared like it), through the
    /// last END_VAR: `code` is the text of the body, whose loop control variables
    /// are declared; `extra` is more declarations for the VAR section.
    pub(crate) fn decls(&self, code: &str, extra: &str) -> String {
        let mut o = String::new();
        let has = |d: &str| !self.dropped.iter().any(|x| x == d);
        if !self.inputs.is_empty() {
            o.push_str("VAR_INPUT\n");
            for (n, t) in &self.inputs {
                let _ = writeln!(o, "    {n} : {};", t.name());
            }
            o.push_str("END_VAR\n");
        }
        let outputs = self.outputs.min(self.vars.len());
        for (section, vars) in [
            ("VAR_OUTPUT", &self.vars[..outputs]),
            ("VAR", &self.vars[outputs..]),
        ] {
            if section == "VAR_OUTPUT" && vars.is_empty() {
                continue;
            }
            let _ = writeln!(o, "{section}");
            for (n, t, init) in vars {
                let _ = write!(o, "    {n} : {} := ", t.name());
                print_expr(init, &mut o);
                o.push_str(";\n");
            }
            if section == "VAR_OUTPUT" {
                o.push_str("END_VAR\n");
            }
        }
        let (et, lo, hi) = self.array;
        if has("arr") {
            let _ = writeln!(o, "    arr : ARRAY[{lo}..{hi}] OF {};", et.name());
        }
        for (name, decl) in [
            ("r1", "r1 : Rec"),
            ("r2", "r2 : Rec"),
            ("m1", "m1 : Mode := Mode#Run"),
        ] {
            if has(name) {
                let _ = writeln!(o, "    {decl};");
            }
        }
        // The loops' control variables, as many as the body uses.
        for c in ["k", "w", "ws", "wt"] {
            let used: Vec<String> = (1..=6)
                .map(|i| format!("{c}{i}"))
                .filter(|v| code.contains(&format!("{v} :=")))
                .collect();
            if !used.is_empty() {
                let _ = writeln!(o, "    {} : INT;", used.join(", "));
            }
        }
        if has("q") {
            o.push_str("    q : INT;\n");
        }
        if has("fb") {
            o.push_str("    fb : FB1;\n");
        }
        if let Some((lo, hi)) = self.recs {
            let _ = writeln!(o, "    recs : ARRAY[{lo}..{hi}] OF Rec;");
        }
        if let Some((lo, hi)) = self.fbs {
            let _ = writeln!(o, "    fbs : ARRAY[{lo}..{hi}] OF FB1;");
        }
        if self.inout {
            o.push_str("    f2 : FB2;\n");
        }
        if self.refs {
            o.push_str("    p1 : REF_TO INT := REF(q);\n    pr : REF_TO Rec := REF(r1);\n");
            o.push_str("    pd : REF_TO ARRAY[0..2] OF DINT := REF(r2.d);\n");
            let _ = writeln!(
                o,
                "    pa : REF_TO ARRAY[{lo}..{hi}] OF {} := REF(arr);",
                et.name()
            );
        }
        o.push_str(extra);
        o.push_str("END_VAR\n");
        o
    }

    /// The CONFIGURATION, if the program has one.
    fn config_text(&self) -> String {
        let mut o = String::new();
        if let Some(c) = &self.config {
            o.push_str("\nCONFIGURATION cfg\n");
            if !c.globals.is_empty() {
                o.push_str("    VAR_GLOBAL\n");
                for (n, t, init) in &c.globals {
                    let _ = write!(o, "        {n} : {} := ", t.name());
                    print_expr(init, &mut o);
                    o.push_str(";\n");
                }
                o.push_str("    END_VAR\n");
            }
            let pad = if c.resource {
                o.push_str("    RESOURCE res ON plc\n");
                "        "
            } else {
                "    "
            };
            for (i, (interval, priority)) in c.tasks.iter().enumerate() {
                let _ = writeln!(
                    o,
                    "{pad}TASK t{i} (INTERVAL := T#{interval}ms, PRIORITY := {priority});"
                );
            }
            for inst in &c.instances {
                let _ = write!(o, "{pad}PROGRAM {}", inst.name);
                if let Some(t) = inst.task {
                    let _ = write!(o, " WITH t{t}");
                }
                o.push_str(" : main");
                if !inst.conns.is_empty() {
                    o.push_str(" (");
                    for (i, k) in inst.conns.iter().enumerate() {
                        if i > 0 {
                            o.push_str(", ");
                        }
                        match k {
                            Conn::In(n, e) => {
                                let _ = write!(o, "{n} := ");
                                print_expr(e, &mut o);
                            }
                            Conn::Out(n, g) => {
                                let _ = write!(o, "{n} => {g}");
                            }
                        }
                    }
                    o.push(')');
                }
                o.push_str(";\n");
            }
            if c.resource {
                o.push_str("    END_RESOURCE\n");
            }
            o.push_str("END_CONFIGURATION\n");
        }
        o
    }
}
