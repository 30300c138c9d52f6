//! Declarations: POUs and their members, types, variable blocks, configurations,
//! charts.

use super::{Printer, TempType};
use crate::ast::*;

impl Printer<'_> {
    pub(super) fn item(&mut self, item: &Item) {
        match item {
            Item::Pou(p) => self.pou(p, None, &Modifiers::default()),
            Item::Type(t) => {
                self.push("TYPE");
                self.end_line();
                self.depth += 1;
                self.type_declaration(t);
                self.depth -= 1;
                self.line();
                self.push("END_TYPE");
                self.end_line();
            }
            Item::Globals(b) => self.var_block(b, None),
            Item::Configuration(c) => self.configuration(c),
            Item::Action(a) => self.action(a),
            Item::Interface(i) => self.interface(i),
        }
    }

    /// A POU, a METHOD (`member`: its keyword) or a property's accessor.
    fn pou(&mut self, p: &Pou, member: Option<&str>, modifiers: &Modifiers) {
        let keyword = match (member, p.kind, &p.oo.class) {
            (Some(k), ..) => k,
            (None, _, Some(_)) => "CLASS",
            (None, PouKind::Program, _) => "PROGRAM",
            (None, PouKind::Function, _) => "FUNCTION",
            (None, PouKind::FunctionBlock, _) => "FUNCTION_BLOCK",
        };
        self.line();
        self.push(keyword);
        let accessor = matches!(member, Some("GET" | "SET"));
        if !accessor {
            self.modifiers(if member.is_some() {
                modifiers
            } else {
                &p.oo.modifiers
            });
            self.push(" ");
            self.push_name(&p.name);
            if let Some(t) = &p.return_type {
                self.push(" : ");
                self.type_text(t);
            }
        }
        if let Some(base) = &p.extends {
            self.push(" EXTENDS ");
            self.push_name(base);
        }
        if !p.oo.implements.is_empty() {
            self.push(" IMPLEMENTS ");
            self.push_names(&p.oo.implements);
        }
        self.end_line();
        self.depth += 1;
        // A setter's first block is the input the parser declared for the value.
        let skip = usize::from(member == Some("SET"));
        for (k, b) in p.var_blocks.iter().enumerate().skip(skip) {
            let access =
                p.oo.var_access
                    .iter()
                    .find(|(i, ..)| *i as usize == k)
                    .map(|(_, a, _)| *a);
            self.var_block(b, access);
        }
        self.temporaries(p);
        for m in &p.oo.methods {
            self.pou(&m.pou, Some("METHOD"), &m.modifiers);
        }
        for prop in &p.oo.properties {
            self.property(prop);
        }
        match &p.sfc {
            Some(chart) => self.chart(chart),
            None => {
                // The comments after the declarations belong to the body.
                let decls_end = p
                    .var_blocks
                    .iter()
                    .filter(|b| b.span.file == p.body.span.file && b.span.end <= p.body.span.start)
                    .map(|b| b.span.end)
                    .max();
                self.body(&p.body, decls_end);
            }
        }
        for a in &p.actions {
            self.action(a);
        }
        let end = match keyword {
            "CLASS" => "END_CLASS",
            "PROGRAM" => "END_PROGRAM",
            "FUNCTION" => "END_FUNCTION",
            "FUNCTION_BLOCK" => "END_FUNCTION_BLOCK",
            "METHOD" => "END_METHOD",
            "GET" => "END_GET",
            _ => "END_SET",
        };
        self.comments_before(p.span.file, p.span.end.saturating_sub(end.len() as u32));
        self.depth -= 1;
        self.line();
        self.push(end);
        self.end_line();
    }

    /// The statements of a body and the comments among them (and after offset
    /// `from`, if given, before them).
    fn body(&mut self, b: &Body, from: Option<u32>) {
        self.start_body(b.span.file, from.unwrap_or(b.span.start));
        self.statements(&b.stmts);
        self.comments_before(b.span.file, b.span.end);
    }

    /// A `VAR_TEMP` block declaring the compiler temporaries of `p`'s body and
    /// actions, when the types are known.
    fn temporaries(&mut self, p: &Pou) {
        let Some(temps) = self.temps else {
            return;
        };
        let mut names = Vec::new();
        let bodies = std::iter::once(&p.body).chain(p.actions.iter().map(|a| &a.body));
        for body in bodies {
            crate::visit::each_stmt(&body.stmts, &mut |s| {
                if let StmtKind::Let { name, .. } = &s.kind {
                    if let Some(TempType::Value(t)) = temps.get(&(name.span.file, name.sym)) {
                        if !names.iter().any(|(n, _): &(Ident, &str)| n.sym == name.sym) {
                            names.push((*name, t.as_str()));
                        }
                    }
                }
            });
        }
        if names.is_empty() {
            return;
        }
        self.line();
        self.push("VAR_TEMP");
        self.end_line();
        self.depth += 1;
        for (name, ty) in names {
            self.line();
            self.push_name(&name);
            self.push(" : ");
            self.push(ty);
            self.push(";");
            self.end_line();
        }
        self.depth -= 1;
        self.line();
        self.push("END_VAR");
        self.end_line();
    }

    fn modifiers(&mut self, m: &Modifiers) {
        if m.abstract_.is_some() {
            self.push(" ABSTRACT");
        }
        if m.final_.is_some() {
            self.push(" FINAL");
        }
        if m.override_.is_some() {
            self.push(" OVERRIDE");
        }
        if let Some((a, _)) = m.access {
            self.push(" ");
            self.push(access(a));
        }
    }

    fn property(&mut self, p: &Property) {
        self.line();
        self.push("PROPERTY");
        self.modifiers(&p.modifiers);
        self.push(" ");
        self.push_name(&p.name);
        self.push(" : ");
        self.type_text(&p.ty);
        self.end_line();
        self.depth += 1;
        if let Some(g) = &p.get {
            self.pou(g, Some("GET"), &Modifiers::default());
        }
        if let Some(s) = &p.set {
            self.pou(s, Some("SET"), &Modifiers::default());
        }
        self.depth -= 1;
        self.line();
        self.push("END_PROPERTY");
        self.end_line();
    }

    fn interface(&mut self, i: &Interface) {
        self.line();
        self.push("INTERFACE ");
        self.push_name(&i.name);
        if !i.extends.is_empty() {
            self.push(" EXTENDS ");
            self.push_names(&i.extends);
        }
        self.end_line();
        self.depth += 1;
        for m in &i.methods {
            self.pou(&m.pou, Some("METHOD"), &m.modifiers);
        }
        for p in &i.properties {
            self.property(p);
        }
        self.depth -= 1;
        self.line();
        self.push("END_INTERFACE");
        self.end_line();
    }

    fn action(&mut self, a: &Action) {
        self.line();
        self.push("ACTION ");
        if let Some(p) = &a.pou {
            self.push_name(p);
            self.push(".");
        }
        self.push_name(&a.name);
        self.push(":");
        self.end_line();
        match &a.sfc {
            Some(chart) => self.chart(chart),
            None => {
                self.depth += 1;
                self.body(&a.body, None);
                self.depth -= 1;
            }
        }
        self.line();
        self.push("END_ACTION");
        self.end_line();
    }

    /// A chart's steps and transitions; conditions and durations as written.
    fn chart(&mut self, c: &Sfc) {
        for s in &c.steps {
            self.line();
            self.push(if s.initial { "INITIAL_STEP " } else { "STEP " });
            self.push_name(&s.name);
            self.push(":");
            self.end_line();
            self.depth += 1;
            for a in &s.assocs {
                self.line();
                match a.qualified {
                    Some(q) => {
                        let t = self.copied(q);
                        self.push(&t);
                    }
                    None => self.push_name(&a.action),
                }
                self.push("(");
                if let Some(q) = &a.qualifier {
                    self.push_name(q);
                }
                if let Some(d) = a.duration {
                    let t = self.copied(d);
                    self.push(", ");
                    self.push(&t);
                }
                for i in &a.indicators {
                    self.push(", ");
                    self.push_name(i);
                }
                self.push(");");
                self.end_line();
            }
            self.depth -= 1;
            self.line();
            self.push("END_STEP");
            self.end_line();
        }
        for t in &c.transitions {
            self.line();
            self.push("TRANSITION");
            if let Some(n) = &t.name {
                self.push(" ");
                self.push_name(n);
            }
            if let Some((p, _)) = t.priority {
                self.push(&format!(" (PRIORITY := {p})"));
            }
            self.push(" FROM ");
            self.steps(&t.from);
            self.push(" TO ");
            self.steps(&t.to);
            let cond = t.condition.map(|c| self.copied(c)).unwrap_or_default();
            if t.il {
                self.push(" :");
                self.end_line();
                self.depth += 1;
                for l in cond.lines() {
                    self.line();
                    self.push(l.trim());
                    self.end_line();
                }
                self.depth -= 1;
                self.line();
            } else {
                self.push(" := ");
                self.push(&cond);
                self.push("; ");
            }
            self.push("END_TRANSITION");
            self.end_line();
        }
    }

    /// One step, or several in parentheses.
    fn steps(&mut self, steps: &[Ident]) {
        if steps.len() == 1 {
            self.push_name(&steps[0]);
        } else {
            self.push("(");
            self.push_names(steps);
            self.push(")");
        }
    }

    pub(super) fn var_block(&mut self, b: &VarBlock, access_spec: Option<AccessSpec>) {
        self.line();
        self.push(b.kind.keyword());
        if let Some(a) = access_spec {
            self.push(" ");
            self.push(access(a));
        }
        if b.constant {
            self.push(" CONSTANT");
        }
        if b.retain {
            self.push(" RETAIN");
        }
        if let Some(l) = &b.list {
            self.push(" ");
            self.push_name(l);
        }
        self.end_line();
        self.depth += 1;
        for d in &b.decls {
            self.comments_before(d.span.file, d.span.start);
            self.line();
            self.declaration(d);
            self.trailing_comment(d.span.file, d.span.end);
            self.end_line();
        }
        self.depth -= 1;
        self.line();
        self.push("END_VAR");
        self.end_line();
    }

    /// `a, b AT %IX0.0 : T R_EDGE := init;`
    pub(super) fn declaration(&mut self, d: &VarDecl) {
        self.push_names(&d.names);
        if let Some((loc, _)) = &d.location {
            self.push(" AT ");
            self.push(loc);
        }
        self.push(" : ");
        self.type_text(&d.ty);
        if let Some((rising, _)) = d.edge {
            self.push(if rising { " R_EDGE" } else { " F_EDGE" });
        }
        if let Some(i) = &d.init {
            self.push(" := ");
            self.init(i);
        }
        self.push(";");
    }

    pub(super) fn type_declaration(&mut self, t: &TypeDecl) {
        self.line();
        self.push_name(&t.name);
        if let Some(base) = &t.extends {
            self.push(" EXTENDS ");
            self.push_name(base);
        }
        self.push(" : ");
        self.type_text(&t.spec);
        if let Some(i) = &t.init {
            self.push(" := ");
            self.init(i);
        }
        self.push(";");
        self.end_line();
    }

    pub(super) fn type_text(&mut self, t: &TypeSpec) {
        match t {
            TypeSpec::Named(id) => self.push_name(id),
            TypeSpec::String { wide, len, .. } => {
                self.push(if *wide { "WSTRING" } else { "STRING" });
                if let Some(n) = len {
                    self.push("[");
                    self.expression(n, 0);
                    self.push("]");
                }
            }
            TypeSpec::Array { dims, elem, .. } => {
                self.push("ARRAY[");
                for (k, d) in dims.iter().enumerate() {
                    if k > 0 {
                        self.push(", ");
                    }
                    match d {
                        Some((lo, hi)) => {
                            self.expression(lo, 0);
                            self.push("..");
                            self.expression(hi, 0);
                        }
                        None => self.push("*"),
                    }
                }
                self.push("] OF ");
                self.type_text(elem);
            }
            TypeSpec::Subrange { base, lo, hi, .. } => {
                self.push_name(base);
                self.push("(");
                self.expression(lo, 0);
                self.push("..");
                self.expression(hi, 0);
                self.push(")");
            }
            TypeSpec::Enum { values, base, .. } => {
                self.push("(");
                for (k, (v, init)) in values.iter().enumerate() {
                    if k > 0 {
                        self.push(", ");
                    }
                    self.push_name(v);
                    if let Some(i) = init {
                        self.push(" := ");
                        self.expression(i, 0);
                    }
                }
                self.push(")");
                if let Some(b) = base {
                    self.push(" ");
                    self.push_name(b);
                }
            }
            TypeSpec::Struct { fields, .. } => {
                self.push("STRUCT");
                self.end_line();
                self.depth += 1;
                for f in fields {
                    self.line();
                    self.declaration(f);
                    self.end_line();
                }
                self.depth -= 1;
                self.line();
                self.push("END_STRUCT");
            }
            TypeSpec::Ref { target, .. } => {
                self.push("REF_TO ");
                self.type_text(target);
            }
            TypeSpec::Reference { target, .. } => {
                self.push("REFERENCE TO ");
                self.type_text(target);
            }
            TypeSpec::Pointer { target, .. } => {
                self.push("POINTER TO ");
                self.type_text(target);
            }
        }
    }

    fn init(&mut self, i: &Init) {
        match i {
            Init::Expr(e) => self.expression(e, 0),
            Init::Array { elems, .. } => {
                self.push("[");
                for (k, el) in elems.iter().enumerate() {
                    if k > 0 {
                        self.push(", ");
                    }
                    if let Some(r) = &el.repeat {
                        self.expression(r, 0);
                        self.push("(");
                        if let Some(v) = &el.value {
                            self.init(v);
                        }
                        self.push(")");
                    } else if let Some(v) = &el.value {
                        self.init(v);
                    }
                }
                self.push("]");
            }
            Init::Struct { fields, .. } => {
                self.push("(");
                for (k, (name, v)) in fields.iter().enumerate() {
                    if k > 0 {
                        self.push(", ");
                    }
                    self.push_name(name);
                    self.push(" := ");
                    self.init(v);
                }
                self.push(")");
            }
        }
    }

    fn configuration(&mut self, c: &Configuration) {
        self.line();
        self.push("CONFIGURATION ");
        self.push_name(&c.name);
        self.end_line();
        self.depth += 1;
        for b in &c.var_blocks {
            self.var_block(b, None);
        }
        for r in &c.resources {
            self.line();
            self.push("RESOURCE ");
            self.push_name(&r.name);
            if let Some(on) = &r.on {
                self.push(" ON ");
                self.push_name(on);
            }
            self.end_line();
            self.depth += 1;
            for b in &r.var_blocks {
                self.var_block(b, None);
            }
            for t in &r.tasks {
                self.line();
                self.push("TASK ");
                self.push_name(&t.name);
                self.push("(");
                for (k, (n, v)) in t.props.iter().enumerate() {
                    if k > 0 {
                        self.push(", ");
                    }
                    self.push_name(n);
                    self.push(" := ");
                    self.expression(v, 0);
                }
                self.push(");");
                self.end_line();
            }
            for p in &r.programs {
                self.line();
                self.push("PROGRAM ");
                self.push_name(&p.name);
                if let Some(t) = &p.task {
                    self.push(" WITH ");
                    self.push_name(t);
                }
                self.push(" : ");
                self.push_name(&p.pou);
                if !p.args.is_empty() {
                    self.push("(");
                    self.arguments(&p.args);
                    self.push(")");
                }
                self.push(";");
                self.end_line();
            }
            self.depth -= 1;
            self.line();
            self.push("END_RESOURCE");
            self.end_line();
        }
        self.depth -= 1;
        self.line();
        self.push("END_CONFIGURATION");
        self.end_line();
    }
}

fn access(a: AccessSpec) -> &'static str {
    match a {
        AccessSpec::Public => "PUBLIC",
        AccessSpec::Private => "PRIVATE",
        AccessSpec::Protected => "PROTECTED",
        AccessSpec::Internal => "INTERNAL",
    }
}
