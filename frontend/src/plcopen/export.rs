//! Writing a project as PLCopen XML (`--emit plcopen`): the syntax trees of ST, IL
//! and STL files as one TC6 2.01 project, laid out as Beremiz and OpenPLC Editor
//! write theirs, so that those editors open it (and plcc's own reader reads it back
//! to the same program).
//!
//! | source | XML |
//! |--------|-----|
//! | `TYPE` | `<dataType>` with its `<baseType>` and `<initialValue>` |
//! | PROGRAM, FUNCTION, FUNCTION_BLOCK | `<pou>`: `<interface>` (`<returnType>` and one group per VAR block), `<actions>`, `<body>` |
//! | an ST body | `<ST>`: the body's text as written, comments included |
//! | an IL body | `<IL>`: the same |
//! | an STL body | `<ST>`: printed as ST ([`crate::print`]) |
//! | `VAR_GLOBAL` at the top level | the configuration's `<globalVars>` |
//! | CONFIGURATION, RESOURCE, TASK, program instances | `<configuration>`, `<resource>`, `<task>`, `<pouInstance>` |
//! | no CONFIGURATION | `config`, `resource1`, one task `task0` of `T#20ms` (what OpenPLC Editor starts a project with) running an instance of each PROGRAM |
//!
//! What TC6 2.01 has no text form for is refused with E0601 at the declaration: the
//! object-oriented parts (METHOD, PROPERTY, INTERFACE, CLASS, EXTENDS, IMPLEMENTS),
//! textual charts, `REFERENCE TO` (and `REF_TO` in the CODESYS dialect, `POINTER TO`
//! outside it: both are `<pointer>`), STRUCTs that extend others, R_EDGE
//! and F_EDGE inputs, VAR_ACCESS, VAR_CONFIG and program arguments in a
//! configuration.

use crate::ast::*;
use crate::codes;
use crate::intern::Interner;
use crate::print::Printer;
use crate::source::SourceMap;
use crate::Lang;
use plcc_ir::diag::{Diagnostic, Span};
use std::ops::Range;

/// One file of the project: its syntax tree, its language, and for IL the byte
/// ranges of the bodies its IL parser read as IL.
pub struct ExportUnit<'a> {
    /// The tree.
    pub unit: &'a SourceUnit,
    /// Its language.
    pub lang: Lang,
    /// For IL files, the bodies written in IL (the rest are ST).
    pub il_bodies: Vec<Range<usize>>,
}

/// The project `name` made of `units`, or why it cannot be written.
pub fn export(
    units: &[ExportUnit<'_>],
    sources: &SourceMap,
    interner: &Interner,
    name: &str,
    codesys: bool,
) -> Result<String, Vec<Diagnostic>> {
    let mut w = Writer {
        sources,
        interner,
        codesys,
        out: String::new(),
        depth: 0,
        diags: Vec::new(),
    };
    w.project(units, name);
    if w.diags.is_empty() {
        Ok(w.out)
    } else {
        Err(w.diags)
    }
}

struct Writer<'a> {
    sources: &'a SourceMap,
    interner: &'a Interner,
    /// The build is in the CODESYS dialect: the header names CODESYS's dialect (so
    /// that a `<pointer>` reads as `POINTER TO`) and a configuration made for
    /// PROGRAMs names each instance after its PROGRAM, as CODESYS's tasks call them.
    codesys: bool,
    out: String,
    depth: usize,
    diags: Vec<Diagnostic>,
}

/// `&`, `<`, `>` and `"` as XML writes them in attributes and text.
fn escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            c => out.push(c),
        }
    }
    out
}

/// The XML element of an elementary type that TC6 2.01 names, if `upper` is one.
fn elementary(upper: &str) -> Option<&'static str> {
    Some(match upper {
        "BOOL" => "BOOL",
        "BYTE" => "BYTE",
        "WORD" => "WORD",
        "DWORD" => "DWORD",
        "LWORD" => "LWORD",
        "SINT" => "SINT",
        "INT" => "INT",
        "DINT" => "DINT",
        "LINT" => "LINT",
        "USINT" => "USINT",
        "UINT" => "UINT",
        "UDINT" => "UDINT",
        "ULINT" => "ULINT",
        "REAL" => "REAL",
        "LREAL" => "LREAL",
        "TIME" => "TIME",
        "DATE" => "DATE",
        "DT" | "DATE_AND_TIME" => "DT",
        "TOD" | "TIME_OF_DAY" => "TOD",
        "STRING" => "string",
        "WSTRING" => "wstring",
        _ => return None,
    })
}

impl Writer<'_> {
    // ------------------------------------------------------------------ XML

    fn indent(&mut self) {
        for _ in 0..self.depth {
            self.out.push_str("  ");
        }
    }

    fn attrs(&mut self, attrs: &[(&str, &str)]) {
        for (k, v) in attrs {
            self.out.push_str(&format!(" {k}=\"{}\"", escape(v)));
        }
    }

    fn open(&mut self, tag: &str, attrs: &[(&str, &str)]) {
        self.indent();
        self.out.push('<');
        self.out.push_str(tag);
        self.attrs(attrs);
        self.out.push_str(">\n");
        self.depth += 1;
    }

    fn close(&mut self, tag: &str) {
        self.depth -= 1;
        self.indent();
        self.out.push_str(&format!("</{tag}>\n"));
    }

    fn empty(&mut self, tag: &str, attrs: &[(&str, &str)]) {
        self.indent();
        self.out.push('<');
        self.out.push_str(tag);
        self.attrs(attrs);
        self.out.push_str("/>\n");
    }

    /// A text body: `<tag><xhtml:p><![CDATA[text]]></xhtml:p></tag>`.
    fn text_body(&mut self, tag: &str, text: &str) {
        self.open(tag, &[]);
        self.indent();
        // `]]>` cannot stand in CDATA: it is split over two sections.
        let text = text.replace("]]>", "]]]]><![CDATA[>");
        self.out
            .push_str(&format!("<xhtml:p><![CDATA[{text}]]></xhtml:p>\n"));
        self.close(tag);
    }

    // ------------------------------------------------------------------ helpers

    fn name(&self, id: &Ident) -> String {
        Printer::new(self.interner)
            .with_sources(self.sources)
            .name(id)
    }

    fn expr(&self, e: &Expr) -> String {
        Printer::new(self.interner)
            .with_sources(self.sources)
            .expr(e)
    }

    fn refuse(&mut self, what: &str, span: Span) {
        self.diags.push(
            Diagnostic::error(
                codes::E_UNSUPPORTED,
                format!("{what} cannot be written as PLCopen XML (TC6 2.01 has no form for it)"),
                span,
            )
            .with_note("`--emit plcopen` writes POUs, types, variables, actions and configurations; `--emit st` prints any build"),
        );
    }

    // ------------------------------------------------------------------ project

    fn project(&mut self, units: &[ExportUnit<'_>], name: &str) {
        let now = "1970-01-01T00:00:00";
        self.out
            .push_str("<?xml version='1.0' encoding='utf-8'?>\n");
        self.open(
            "project",
            &[
                ("xmlns:ns1", "http://www.plcopen.org/xml/tc6_0201"),
                ("xmlns:xhtml", "http://www.w3.org/1999/xhtml"),
                ("xmlns:xsd", "http://www.w3.org/2001/XMLSchema"),
                ("xmlns", "http://www.plcopen.org/xml/tc6_0201"),
            ],
        );
        self.empty(
            "fileHeader",
            &[
                ("companyName", "Unknown"),
                (
                    "productName",
                    if self.codesys {
                        "plcc (CODESYS dialect)"
                    } else {
                        "plcc"
                    },
                ),
                ("productVersion", env!("CARGO_PKG_VERSION")),
                ("creationDateTime", now),
            ],
        );
        self.open(
            "contentHeader",
            &[("name", name), ("modificationDateTime", now)],
        );
        self.open("coordinateInfo", &[]);
        for lang in ["fbd", "ld", "sfc"] {
            self.open(lang, &[]);
            self.empty("scaling", &[("x", "0"), ("y", "0")]);
            self.close(lang);
        }
        self.close("coordinateInfo");
        self.close("contentHeader");
        self.open("types", &[]);
        let items = || {
            units
                .iter()
                .flat_map(|u| u.unit.items.iter().map(move |i| (u, i)))
        };
        let types: Vec<&TypeDecl> = items()
            .filter_map(|(_, i)| match i {
                Item::Type(t) => Some(t),
                _ => None,
            })
            .collect();
        if types.is_empty() {
            self.empty("dataTypes", &[]);
        } else {
            self.open("dataTypes", &[]);
            for t in types {
                self.data_type(t);
            }
            self.close("dataTypes");
        }
        // `ACTION P.A:` at the top level: an action of P.
        let outside: Vec<(&ExportUnit, &Action)> = items()
            .filter_map(|(u, i)| match i {
                Item::Action(a) => Some((u, a)),
                _ => None,
            })
            .collect();
        self.open("pous", &[]);
        for (u, item) in items() {
            match item {
                Item::Pou(p) => {
                    let own: Vec<(&ExportUnit, &Action)> = p
                        .actions
                        .iter()
                        .map(|a| (u, a))
                        .chain(
                            outside
                                .iter()
                                .copied()
                                .filter(|(_, a)| a.pou.is_some_and(|o| o.sym == p.name.sym)),
                        )
                        .collect();
                    self.pou(p, u, &own);
                }
                Item::Interface(i) => self.refuse("an INTERFACE", i.span),
                _ => {}
            }
        }
        self.close("pous");
        let pou_named = |sym| items().any(|(_, i)| matches!(i, Item::Pou(p) if p.name.sym == sym));
        for (_, a) in &outside {
            if !a.pou.is_some_and(|p| pou_named(p.sym)) {
                self.refuse("an ACTION of no POU of the files", a.span);
            }
        }
        self.close("types");
        self.open("instances", &[]);
        self.open("configurations", &[]);
        let globals: Vec<&VarBlock> = items()
            .filter_map(|(_, i)| match i {
                Item::Globals(b) => Some(b),
                _ => None,
            })
            .collect();
        let configs: Vec<&Configuration> = items()
            .filter_map(|(_, i)| match i {
                Item::Configuration(c) => Some(c),
                _ => None,
            })
            .collect();
        if configs.is_empty() {
            let programs: Vec<String> = items()
                .filter_map(|(_, i)| match i {
                    Item::Pou(p) if p.kind == PouKind::Program => Some(self.name(&p.name)),
                    _ => None,
                })
                .collect();
            self.open("configuration", &[("name", "config")]);
            self.open("resource", &[("name", "resource1")]);
            self.open(
                "task",
                &[("name", "task0"), ("priority", "0"), ("interval", "T#20ms")],
            );
            for (k, p) in programs.iter().enumerate() {
                let inst = if self.codesys {
                    p.clone()
                } else {
                    format!("instance{k}")
                };
                self.empty("pouInstance", &[("name", &inst), ("typeName", p)]);
            }
            self.close("task");
            self.close("resource");
            for b in &globals {
                self.var_group(b, "globalVars");
            }
            self.close("configuration");
        }
        for (k, c) in configs.iter().enumerate() {
            // The top-level globals go to the first configuration.
            let extra: &[&VarBlock] = if k == 0 { &globals } else { &[] };
            self.configuration(c, extra);
        }
        self.close("configurations");
        self.close("instances");
        self.close("project");
    }

    fn data_type(&mut self, t: &TypeDecl) {
        if t.extends.is_some() {
            self.refuse("a STRUCT that EXTENDS another", t.span);
            return;
        }
        let name = self.name(&t.name);
        self.open("dataType", &[("name", &name)]);
        self.open("baseType", &[]);
        self.type_spec(&t.spec);
        self.close("baseType");
        if let Some(i) = &t.init {
            self.open("initialValue", &[]);
            self.value(i);
            self.close("initialValue");
        }
        self.close("dataType");
    }

    /// A POU and its actions (those written inside it and after it).
    fn pou(&mut self, p: &Pou, u: &ExportUnit<'_>, actions: &[(&ExportUnit<'_>, &Action)]) {
        let oo = &p.oo;
        if let Some(c) = oo.class {
            return self.refuse("a CLASS", c);
        }
        if let Some(m) = oo.methods.first() {
            return self.refuse("a METHOD", m.pou.span);
        }
        if let Some(pr) = oo.properties.first() {
            return self.refuse("a PROPERTY", pr.span);
        }
        if p.extends.is_some() || !oo.implements.is_empty() {
            return self.refuse("a POU that EXTENDS or IMPLEMENTS", p.span);
        }
        if let Some(s) = &p.sfc {
            return self.refuse("a sequential function chart in text form", s.span);
        }
        let name = self.name(&p.name);
        let kind = match p.kind {
            PouKind::Program => "program",
            PouKind::Function => "function",
            PouKind::FunctionBlock => "functionBlock",
        };
        self.open("pou", &[("name", &name), ("pouType", kind)]);
        self.open("interface", &[]);
        if let Some(t) = &p.return_type {
            self.open("returnType", &[]);
            self.type_spec(t);
            self.close("returnType");
        }
        for b in &p.var_blocks {
            let tag = match b.kind {
                VarKind::Input => "inputVars",
                VarKind::Output => "outputVars",
                VarKind::InOut => "inOutVars",
                VarKind::Var | VarKind::Stat | VarKind::Inst => "localVars",
                VarKind::Temp => "tempVars",
                VarKind::External => "externalVars",
                VarKind::Global => "globalVars",
                VarKind::Access | VarKind::Config => {
                    self.refuse("VAR_ACCESS or VAR_CONFIG", b.span);
                    continue;
                }
            };
            self.var_group(b, tag);
        }
        self.close("interface");
        if !actions.is_empty() {
            self.open("actions", &[]);
            for &(au, a) in actions {
                if let Some(s) = &a.sfc {
                    self.refuse("an ACTION written as a chart", s.span);
                    continue;
                }
                let name = self.name(&a.name);
                self.open("action", &[("name", &name)]);
                self.body(&a.body, None, au);
                self.close("action");
            }
            self.close("actions");
        }
        let decls_end = p
            .var_blocks
            .iter()
            .map(|b| b.span)
            .filter(|s| s.file == p.body.span.file && s.end <= p.body.span.start)
            .map(|s| s.end)
            .max();
        self.body(&p.body, decls_end, u);
        self.close("pou");
    }

    /// `<body>` with the body's text as written (from `from`, if given, to take the
    /// comments before its first statement), or printed as ST for STL.
    fn body(&mut self, b: &Body, from: Option<u32>, u: &ExportUnit<'_>) {
        self.open("body", &[]);
        let text = &self.sources.get(b.span.file).text;
        let mut start = from.unwrap_or(b.span.start) as usize;
        // From the start of the first line, so that every line keeps its indentation
        // and the body can be dedented.
        if let Some(before) = text.get(..start) {
            let line = before.rfind('\n').map_or(0, |i| i + 1);
            if before[line..].trim().is_empty() {
                start = line;
            }
        }
        let range = start..b.span.end as usize;
        let is_il = u.lang == Lang::Il
            && u.il_bodies
                .iter()
                .any(|r| r.start <= b.span.start as usize && b.span.start as usize <= r.end);
        if u.lang == Lang::Stl || text.get(range.clone()).is_none() {
            let st = Printer::new(self.interner)
                .with_sources(self.sources)
                .stmts(&b.stmts);
            self.text_body("ST", &st);
        } else {
            let body = text[range].trim_matches('\n').to_string();
            let body = format!("{}\n", dedent(&body));
            self.text_body(if is_il { "IL" } else { "ST" }, &body);
        }
        self.close("body");
    }

    fn var_group(&mut self, b: &VarBlock, tag: &str) {
        let mut attrs: Vec<(&str, &str)> = Vec::new();
        if b.constant {
            attrs.push(("constant", "true"));
        }
        if b.retain {
            attrs.push(("retain", "true"));
        }
        let list = b.list.map(|l| self.name(&l));
        if let Some(l) = &list {
            attrs.push(("name", l));
        }
        self.open(tag, &attrs);
        for d in &b.decls {
            if let Some((_, span)) = d.edge {
                self.refuse("an R_EDGE or F_EDGE input", span);
                continue;
            }
            for n in &d.names {
                let name = self.name(n);
                let mut attrs = vec![("name", name.as_str())];
                if let Some((loc, _)) = &d.location {
                    attrs.push(("address", loc));
                }
                self.open("variable", &attrs);
                self.open("type", &[]);
                self.type_spec(&d.ty);
                self.close("type");
                if let Some(i) = &d.init {
                    self.open("initialValue", &[]);
                    self.value(i);
                    self.close("initialValue");
                }
                self.close("variable");
            }
        }
        self.close(tag);
    }

    fn type_spec(&mut self, t: &TypeSpec) {
        match t {
            TypeSpec::Named(id) => {
                let upper = self.interner.name(id.sym).to_ascii_uppercase();
                match elementary(&upper) {
                    Some(e) => self.empty(e, &[]),
                    None => {
                        let n = self.name(id);
                        self.empty("derived", &[("name", &n)]);
                    }
                }
            }
            TypeSpec::String { wide, len, .. } => {
                let tag = if *wide { "wstring" } else { "string" };
                match len {
                    Some(n) => {
                        let n = self.expr(n);
                        self.empty(tag, &[("length", &n)]);
                    }
                    None => self.empty(tag, &[]),
                }
            }
            TypeSpec::Array { dims, elem, span } => {
                self.open("array", &[]);
                for d in dims {
                    match d {
                        Some((lo, hi)) => {
                            let (lo, hi) = (self.expr(lo), self.expr(hi));
                            self.empty("dimension", &[("lower", &lo), ("upper", &hi)]);
                        }
                        None => self.refuse("an ARRAY[*]", *span),
                    }
                }
                self.open("baseType", &[]);
                self.type_spec(elem);
                self.close("baseType");
                self.close("array");
            }
            TypeSpec::Subrange { base, lo, hi, .. } => {
                let upper = self.interner.name(base.sym).to_ascii_uppercase();
                let tag = if upper.starts_with('U') {
                    "subrangeUnsigned"
                } else {
                    "subrangeSigned"
                };
                self.open(tag, &[]);
                let (lo, hi) = (self.expr(lo), self.expr(hi));
                self.empty("range", &[("lower", &lo), ("upper", &hi)]);
                self.open("baseType", &[]);
                self.type_spec(&TypeSpec::Named(*base));
                self.close("baseType");
                self.close(tag);
            }
            TypeSpec::Enum { values, base, .. } => {
                self.open("enum", &[]);
                self.open("values", &[]);
                for (v, init) in values {
                    let n = self.name(v);
                    match init {
                        Some(i) => {
                            let i = self.expr(i);
                            self.empty("value", &[("name", &n), ("value", &i)]);
                        }
                        None => self.empty("value", &[("name", &n)]),
                    }
                }
                self.close("values");
                if let Some(b) = base {
                    self.open("baseType", &[]);
                    self.type_spec(&TypeSpec::Named(*b));
                    self.close("baseType");
                }
                self.close("enum");
            }
            TypeSpec::Struct { fields, .. } => {
                self.open("struct", &[]);
                for f in fields {
                    for n in &f.names {
                        let name = self.name(n);
                        self.open("variable", &[("name", &name)]);
                        self.open("type", &[]);
                        self.type_spec(&f.ty);
                        self.close("type");
                        if let Some(i) = &f.init {
                            self.open("initialValue", &[]);
                            self.value(i);
                            self.close("initialValue");
                        }
                        self.close("variable");
                    }
                }
                self.close("struct");
            }
            // TC6's `<pointer>` is the standard's REF_TO, and CODESYS's POINTER TO in
            // its exports.
            TypeSpec::Pointer { target, .. } if self.codesys => self.pointer(target),
            TypeSpec::Ref { target, .. } if !self.codesys => self.pointer(target),
            TypeSpec::Pointer { span, .. } => {
                self.refuse("a POINTER TO outside the CODESYS dialect", *span)
            }
            TypeSpec::Ref { span, .. } => self.refuse("a REF_TO in the CODESYS dialect", *span),
            TypeSpec::Reference { span, .. } => self.refuse("a REFERENCE TO type", *span),
        }
    }

    fn pointer(&mut self, target: &TypeSpec) {
        self.open("pointer", &[]);
        self.open("baseType", &[]);
        self.type_spec(target);
        self.close("baseType");
        self.close("pointer");
    }

    fn value(&mut self, i: &Init) {
        match i {
            Init::Expr(e) => {
                let v = self.expr(e);
                self.empty("simpleValue", &[("value", &v)]);
            }
            Init::Array { elems, .. } => {
                self.open("arrayValue", &[]);
                for el in elems {
                    let rep = el.repeat.as_ref().map(|r| self.expr(r));
                    let attrs: Vec<(&str, &str)> = rep
                        .as_deref()
                        .map(|r| ("repetitionValue", r))
                        .into_iter()
                        .collect();
                    match &el.value {
                        Some(v) => {
                            self.open("value", &attrs);
                            self.value(v);
                            self.close("value");
                        }
                        None => self.empty("value", &attrs),
                    }
                }
                self.close("arrayValue");
            }
            Init::Struct { fields, .. } => {
                self.open("structValue", &[]);
                for (n, v) in fields {
                    let n = self.name(n);
                    self.open("value", &[("member", &n)]);
                    self.value(v);
                    self.close("value");
                }
                self.close("structValue");
            }
        }
    }

    fn configuration(&mut self, c: &Configuration, globals: &[&VarBlock]) {
        let name = self.name(&c.name);
        self.open("configuration", &[("name", &name)]);
        for r in &c.resources {
            let name = self.name(&r.name);
            self.open("resource", &[("name", &name)]);
            for t in &r.tasks {
                let mut attrs = vec![("name".to_string(), self.name(&t.name))];
                for (k, v) in &t.props {
                    let key = self.interner.name(k.sym).to_ascii_lowercase();
                    attrs.push((key, self.expr(v)));
                }
                if !attrs.iter().any(|(k, _)| k == "priority") {
                    attrs.push(("priority".into(), "0".into()));
                }
                let attrs: Vec<(&str, &str)> = attrs
                    .iter()
                    .map(|(k, v)| (k.as_str(), v.as_str()))
                    .collect();
                self.open("task", &attrs);
                for p in r
                    .programs
                    .iter()
                    .filter(|p| p.task.is_some_and(|x| x.sym == t.name.sym))
                {
                    self.pou_instance(p);
                }
                self.close("task");
            }
            for p in r.programs.iter().filter(|p| p.task.is_none()) {
                self.pou_instance(p);
            }
            for b in &r.var_blocks {
                self.var_group(b, "globalVars");
            }
            self.close("resource");
        }
        for b in c.var_blocks.iter().chain(globals.iter().copied()) {
            self.var_group(b, "globalVars");
        }
        self.close("configuration");
    }

    fn pou_instance(&mut self, p: &ProgramConfig) {
        if !p.args.is_empty() {
            self.refuse("a program instance with arguments", p.span);
        }
        let (name, ty) = (self.name(&p.name), self.name(&p.pou));
        self.empty("pouInstance", &[("name", &name), ("typeName", &ty)]);
    }
}

/// `text` without the indentation all its lines share (blank lines aside).
fn dedent(text: &str) -> String {
    let common = text
        .lines()
        .filter(|l| !l.trim().is_empty())
        .map(|l| l.len() - l.trim_start_matches([' ', '\t']).len())
        .min()
        .unwrap_or(0);
    text.lines()
        .map(|l| l.get(common..).unwrap_or(l.trim_start()))
        .collect::<Vec<_>>()
        .join("\n")
}
