//! PLCopen TC6 XML read into a model: data types, POUs (interfaces and bodies) and
//! configurations.
//!
//! Both `http://www.plcopen.org/xml/tc6.xsd` (TC6 1.0) and `tc6_0201` (2.01, also
//! `tc6_0200`) are read: elements are matched by their local names, which the versions
//! share, and the few attributes they spell differently are tried both ways. Every
//! string keeps where it is in the file ([`Text`]), so that diagnostics, and the IL
//! made from the model, can point back at the XML.

use crate::codes;
use plcc_ir::diag::{Diagnostic, FileId, Span};
use roxmltree::Node;
use std::ops::Range;

mod elements;

/// The namespaces of PLCopen TC6 project files.
const NAMESPACES: [&str; 3] = [
    "http://www.plcopen.org/xml/tc6.xsd",
    "http://www.plcopen.org/xml/tc6_0200",
    "http://www.plcopen.org/xml/tc6_0201",
];

/// A part of a [`Text`]'s value that is written verbatim in the file.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Piece {
    /// Offset in the value.
    pub at: u32,
    /// Offset in the file.
    pub src: u32,
    /// Length in bytes.
    pub len: u32,
}

/// A string read from the file and where it is.
#[derive(Clone, Debug, Default)]
pub(crate) struct Text {
    /// The value (entities resolved, trimmed where the format says so).
    pub value: String,
    /// The element or attribute that holds it, for messages about the whole of it.
    pub range: Range<u32>,
    /// The parts of the value written verbatim in the file (none when escaped).
    pub exact: Vec<Piece>,
}

impl Text {
    /// The text with surrounding white space removed (pieces adjusted).
    fn trimmed(mut self) -> Text {
        let start = self.value.len() - self.value.trim_start().len();
        let kept = self.value.trim().len();
        if start == 0 && kept == self.value.len() {
            return self;
        }
        self.value = self.value[start..start + kept].to_string();
        let (lo, hi) = (start as u32, (start + kept) as u32);
        self.exact = self
            .exact
            .iter()
            .filter_map(|p| {
                let s = p.at.max(lo);
                let e = (p.at + p.len).min(hi);
                (s < e).then(|| Piece {
                    at: s - lo,
                    src: p.src + (s - p.at),
                    len: e - s,
                })
            })
            .collect();
        self
    }
}

/// The kind of a POU.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub(crate) enum PouKind {
    /// `program`
    Program,
    /// `function`
    Function,
    /// `functionBlock`
    FunctionBlock,
}

/// A project: what the generated IL file declares.
#[derive(Debug, Default)]
pub(crate) struct Project {
    /// `types/dataTypes`.
    pub types: Vec<DataType>,
    /// `types/pous`.
    pub pous: Vec<Pou>,
    /// `instances/configurations`.
    pub configs: Vec<Config>,
}

/// `<dataType name="...">`.
#[derive(Debug)]
pub(crate) struct DataType {
    /// Its name.
    pub name: Text,
    /// Its definition.
    pub ty: Type,
    /// Its initial value.
    pub init: Option<Value>,
}

/// `<pou name="..." pouType="...">`.
#[derive(Debug)]
pub(crate) struct Pou {
    /// Its name.
    pub name: Text,
    /// Program, function or function block.
    pub kind: PouKind,
    /// A function's `returnType`.
    pub ret: Option<Type>,
    /// The variable groups of its interface, in order.
    pub groups: Vec<VarGroup>,
    /// Its body.
    pub body: Body,
    /// The start tag, for messages about the POU.
    pub tag: Range<u32>,
}

/// A POU body.
#[derive(Debug)]
pub(crate) enum Body {
    /// No body (a function block declared for its interface only).
    None,
    /// Structured Text.
    St(Text),
    /// Instruction List.
    Il(Text),
    /// A ladder diagram or a function block diagram: its elements in document order.
    Graph(Graphic, Vec<Element>),
}

/// The language of a graphical body.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub(crate) enum Graphic {
    /// `<LD>`
    Ld,
    /// `<FBD>`
    Fbd,
}

/// The section of a variable group.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub(crate) enum Section {
    /// `inputVars`
    Input,
    /// `outputVars`
    Output,
    /// `inOutVars`
    InOut,
    /// `localVars`
    Local,
    /// `tempVars`
    Temp,
    /// `externalVars`
    External,
    /// `globalVars`
    Global,
}

impl Section {
    /// The IEC keyword of the section.
    pub fn keyword(self) -> &'static str {
        match self {
            Section::Input => "VAR_INPUT",
            Section::Output => "VAR_OUTPUT",
            Section::InOut => "VAR_IN_OUT",
            Section::Local => "VAR",
            Section::Temp => "VAR_TEMP",
            Section::External => "VAR_EXTERNAL",
            Section::Global => "VAR_GLOBAL",
        }
    }
}

/// `<inputVars>`, `<localVars>`... of an interface, a configuration or a resource.
#[derive(Debug)]
pub(crate) struct VarGroup {
    /// Which section.
    pub section: Section,
    /// `constant="true"`.
    pub constant: bool,
    /// `retain="true"` or `persistent="true"`.
    pub retain: bool,
    /// The variables.
    pub vars: Vec<Var>,
}

/// `<variable name="..." address="...">` with its type and initial value.
#[derive(Debug)]
pub(crate) struct Var {
    /// Its name.
    pub name: Text,
    /// Its type.
    pub ty: Type,
    /// `address="%IX0.0"`.
    pub address: Option<Text>,
    /// `<initialValue>`.
    pub init: Option<Value>,
}

/// A type as the XML writes it.
#[derive(Debug)]
pub(crate) enum Type {
    /// An elementary type (`<INT/>`) or a derived one (`<derived name="T"/>`).
    Named(Text),
    /// `<string length="..."/>`, `<wstring/>`.
    String {
        /// WSTRING
        wide: bool,
        /// The length, if given.
        len: Option<Text>,
    },
    /// `<array>` with its dimensions `(lower, upper)`.
    Array {
        /// The dimensions.
        dims: Vec<(Text, Text)>,
        /// The element type.
        elem: Box<Type>,
    },
    /// `<enum>`: values with optional numbers, and an optional base type.
    Enum {
        /// The values.
        values: Vec<(Text, Option<Text>)>,
        /// The base type.
        base: Option<Box<Type>>,
    },
    /// `<struct>`.
    Struct(Vec<Var>),
    /// `<subrangeSigned>`, `<subrangeUnsigned>`.
    Subrange {
        /// The base type.
        base: Box<Type>,
        /// Lower bound.
        lo: Text,
        /// Upper bound.
        hi: Text,
    },
    /// `<pointer>` (a reference).
    Ref(Box<Type>),
}

/// An initial value.
#[derive(Debug)]
pub(crate) enum Value {
    /// `<simpleValue value="..."/>`
    Simple(Text),
    /// `<arrayValue>`: elements with an optional repetition count.
    Array(Vec<(Option<Text>, Value)>),
    /// `<structValue>`: member values.
    Struct(Vec<(Text, Value)>),
}

/// `<configuration>`.
#[derive(Debug)]
pub(crate) struct Config {
    /// Its name.
    pub name: Text,
    /// Its global variables.
    pub globals: Vec<VarGroup>,
    /// Its resources.
    pub resources: Vec<Resource>,
}

/// `<resource>`.
#[derive(Debug)]
pub(crate) struct Resource {
    /// Its name.
    pub name: Text,
    /// Its global variables.
    pub globals: Vec<VarGroup>,
    /// Its tasks.
    pub tasks: Vec<Task>,
    /// Program instances outside any task.
    pub instances: Vec<Instance>,
}

/// `<task name="..." interval="..." priority="...">`.
#[derive(Debug)]
pub(crate) struct Task {
    /// Its name.
    pub name: Text,
    /// `interval`.
    pub interval: Option<Text>,
    /// `priority`.
    pub priority: Option<Text>,
    /// The program instances it runs.
    pub instances: Vec<Instance>,
}

/// `<pouInstance name="..." typeName="...">` (`type` in TC6 1.0).
#[derive(Debug)]
pub(crate) struct Instance {
    /// The instance's name.
    pub name: Text,
    /// The PROGRAM it instantiates.
    pub type_name: Text,
}

/// `edge` of a contact or coil.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub(crate) enum Edge {
    /// `none`
    None,
    /// `rising`
    Rising,
    /// `falling`
    Falling,
}

/// `storage` of a coil.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub(crate) enum Storage {
    /// `none`: the coil writes its power.
    None,
    /// `set`
    Set,
    /// `reset`
    Reset,
}

/// An element of a ladder body.
#[derive(Debug)]
pub(crate) struct Element {
    /// `localId`.
    pub id: u64,
    /// From `<` through the `localId` attribute: what diagnostics underline.
    pub tag: Range<u32>,
    /// `<position x y>`, if given.
    pub pos: Option<(f64, f64)>,
    /// What it is.
    pub kind: Kind,
    /// The input of a single-input element (contact, coil, variable, jump, return,
    /// connector; the right rail's inputs all together); empty for the others.
    pub input: Port,
    /// Absolute y of its output connection point, if known.
    pub out_y: Option<f64>,
    /// `executionOrderId`, when given and not 0.
    pub order: Option<u32>,
}

/// An input or output of an element: its name (blocks), its modifiers and, for an
/// input, what is connected to it.
#[derive(Debug, Default)]
pub(crate) struct Port {
    /// `formalParameter` of a block's variable.
    pub name: Option<Text>,
    /// `negated="true"`.
    pub negated: bool,
    /// `edge` of a block input.
    pub edge: Option<Edge>,
    /// The connections (of an input).
    pub conns: Vec<Conn>,
    /// Absolute y of the connection point, if known.
    pub y: Option<f64>,
}

/// `<connection refLocalId="..." formalParameter="..."/>`.
#[derive(Debug)]
pub(crate) struct Conn {
    /// The element it comes from.
    pub from: u64,
    /// The output of that element (a block's), if named.
    pub param: Option<Text>,
    /// Where the connection is written.
    pub range: Range<u32>,
}

/// The kinds of ladder elements.
#[derive(Debug)]
pub(crate) enum Kind {
    /// `leftPowerRail`
    LeftRail,
    /// `rightPowerRail`
    RightRail,
    /// `contact`
    Contact {
        /// Its variable.
        var: Text,
        /// Normally closed.
        negated: bool,
        /// Rising or falling edge.
        edge: Edge,
    },
    /// `coil`
    Coil {
        /// Its variable.
        var: Text,
        /// Writes the inverse of its power.
        negated: bool,
        /// Set or reset coil.
        storage: Storage,
        /// Rising or falling edge coil.
        edge: Edge,
    },
    /// `block`: a function or a function block instance.
    Block {
        /// `typeName`.
        ty: Text,
        /// `instanceName` (function blocks only).
        instance: Option<Text>,
        /// `inputVariables`.
        inputs: Vec<Port>,
        /// `inOutVariables`.
        in_outs: Vec<Port>,
        /// `outputVariables`.
        outputs: Vec<Port>,
    },
    /// `inVariable`
    InVariable {
        /// Its expression.
        expr: Text,
        /// `negated`.
        negated: bool,
    },
    /// `outVariable`
    OutVariable {
        /// Its expression.
        expr: Text,
        /// `negated`.
        negated: bool,
    },
    /// `inOutVariable`
    InOutVariable {
        /// Its expression.
        expr: Text,
    },
    /// `jump`
    Jump {
        /// The label it jumps to.
        label: Text,
    },
    /// `label`
    Label {
        /// Its name.
        label: Text,
    },
    /// `return`
    Return,
    /// `connector`: the start of a named connection.
    Connector {
        /// Its name.
        name: Text,
    },
    /// `continuation`: the other end of a named connection.
    Continuation {
        /// Its name.
        name: Text,
    },
}

impl Kind {
    /// The element as messages name it: `contact `start``.
    pub fn describe(&self) -> String {
        match self {
            Kind::LeftRail => "the left power rail".into(),
            Kind::RightRail => "the right power rail".into(),
            Kind::Contact { var, .. } => format!("contact `{}`", var.value),
            Kind::Coil { var, .. } => format!("coil `{}`", var.value),
            Kind::Block { ty, instance, .. } => match instance {
                Some(i) => format!("block {} `{}`", ty.value, i.value),
                None => format!("block {}", ty.value),
            },
            Kind::InVariable { expr, .. } => format!("input variable `{}`", expr.value),
            Kind::OutVariable { expr, .. } => format!("output variable `{}`", expr.value),
            Kind::InOutVariable { expr } => format!("in-out variable `{}`", expr.value),
            Kind::Jump { label } => format!("jump to `{}`", label.value),
            Kind::Label { label } => format!("label `{}`", label.value),
            Kind::Return => "return".into(),
            Kind::Connector { name } => format!("connector `{}`", name.value),
            Kind::Continuation { name } => format!("continuation `{}`", name.value),
        }
    }
}

/// Reads a project file. `None` after an error that leaves nothing to read (the file
/// is not XML, or not a PLCopen project); other errors are reported and the element
/// concerned is skipped.
pub(crate) fn read(file: FileId, src: &str, diags: &mut Vec<Diagnostic>) -> Option<Project> {
    let opts = roxmltree::ParsingOptions {
        allow_dtd: true,
        ..Default::default()
    };
    let doc = match roxmltree::Document::parse_with_options(src, opts) {
        Ok(d) => d,
        Err(e) => {
            let pos = e.pos();
            let at = offset_of(src, pos.row, pos.col);
            // The parser's message ends with the position, which the caret shows.
            let text = e.to_string();
            let reason = match text.rsplit_once(" at ") {
                Some((r, p)) if p.bytes().all(|b| b.is_ascii_digit() || b == b':') => r,
                _ => text.as_str(),
            };
            diags.push(
                Diagnostic::error(
                    codes::LD_MALFORMED_XML,
                    format!("the file is not well-formed XML: {reason}"),
                    Span::new(file, at, at),
                )
                .with_label("the XML is broken here"),
            );
            return None;
        }
    };
    let mut r = Reader { src, file, diags };
    r.project(doc.root_element())
}

/// The byte offset of a 1-based row and column (in characters).
fn offset_of(src: &str, row: u32, col: u32) -> u32 {
    let mut line_start = 0usize;
    for _ in 1..row {
        match src[line_start..].find('\n') {
            Some(i) => line_start += i + 1,
            None => break,
        }
    }
    let rest = &src[line_start..];
    let line_end = rest.find('\n').unwrap_or(rest.len());
    let col_bytes = rest[..line_end]
        .char_indices()
        .nth(col.saturating_sub(1) as usize)
        .map_or(line_end, |(i, _)| i);
    (line_start + col_bytes) as u32
}

struct Reader<'a, 's> {
    src: &'s str,
    file: FileId,
    diags: &'a mut Vec<Diagnostic>,
}

fn range32(r: Range<usize>) -> Range<u32> {
    r.start as u32..r.end as u32
}

/// The element children of `n` with the local name `name`.
fn kids<'a, 'i>(n: Node<'a, 'i>, name: &'static str) -> impl Iterator<Item = Node<'a, 'i>> {
    n.children()
        .filter(move |c| c.is_element() && c.tag_name().name() == name)
}

/// The first element child of `n` named `name`.
fn kid<'a, 'i>(n: Node<'a, 'i>, name: &'static str) -> Option<Node<'a, 'i>> {
    kids(n, name).next()
}

/// The element children of `n`.
fn elements<'a, 'i>(n: Node<'a, 'i>) -> impl Iterator<Item = Node<'a, 'i>> {
    n.children().filter(|c| c.is_element())
}

/// True for `true` and `1` (XML Schema booleans).
fn truthy(v: &str) -> bool {
    matches!(v.trim(), "true" | "1")
}

impl Reader<'_, '_> {
    fn span(&self, r: Range<u32>) -> Span {
        Span::new(self.file, r.start, r.end)
    }

    /// The tag name of an element (after its `<`).
    fn qname(&self, n: Node) -> Range<u32> {
        let start = n.range().start + 1;
        let len = self.src[start.min(self.src.len())..]
            .bytes()
            .take_while(|b| b.is_ascii_alphanumeric() || matches!(b, b'_' | b'-' | b'.' | b':'))
            .count();
        start as u32..(start + len) as u32
    }

    /// From `<` through the `localId` attribute if there is one, else the tag name.
    fn tag(&self, n: Node) -> Range<u32> {
        let start = n.range().start as u32;
        match n.attribute_node("localId") {
            Some(a) => start..(a.range_value().end as u32 + 1).min(self.src.len() as u32),
            None => self.qname(n),
        }
    }

    fn error(&mut self, code: &'static str, msg: impl Into<String>, at: Range<u32>) {
        let d = Diagnostic::error(code, msg, self.span(at));
        self.diags.push(d);
    }

    /// The value of an attribute as a [`Text`].
    fn attr(&self, n: Node, name: &str) -> Option<Text> {
        let a = n.attribute_node(name)?;
        let r = a.range_value();
        let value = a.value().to_string();
        let exact = if self.src.get(r.clone()) == Some(value.as_str()) {
            vec![Piece {
                at: 0,
                src: r.start as u32,
                len: value.len() as u32,
            }]
        } else {
            Vec::new()
        };
        Some(
            Text {
                value,
                range: range32(r),
                exact,
            }
            .trimmed(),
        )
    }

    /// An attribute that must be there; reports it missing.
    fn need_attr(&mut self, n: Node, name: &str) -> Option<Text> {
        let t = self.attr(n, name);
        if t.as_ref().is_none_or(|t| t.value.is_empty()) {
            let what = n.tag_name().name().to_string();
            self.error(
                codes::LD_BAD_PROJECT,
                format!("`<{what}>` needs a `{name}` attribute"),
                self.qname(n),
            );
            return None;
        }
        t
    }

    /// The text of an element (all its descendant text nodes), untrimmed.
    fn text(&self, n: Node) -> Text {
        let mut value = String::new();
        let mut exact = Vec::new();
        for t in n.descendants().filter(|d| d.is_text()) {
            let s = t.text().unwrap_or("");
            let r = t.range();
            if let Some(raw) = self.src.get(r.clone()) {
                if let Some(i) = raw.find(s) {
                    if !s.is_empty() {
                        exact.push(Piece {
                            at: value.len() as u32,
                            src: (r.start + i) as u32,
                            len: s.len() as u32,
                        });
                    }
                }
            }
            value.push_str(s);
        }
        Text {
            value,
            range: range32(n.range()),
            exact,
        }
    }

    fn project(&mut self, root: Node) -> Option<Project> {
        let ns = root.tag_name().namespace().unwrap_or("");
        if root.tag_name().name() != "project" || !NAMESPACES.contains(&ns) {
            let found = if ns.is_empty() {
                format!("`<{}>`", root.tag_name().name())
            } else {
                format!("`<{}>` in namespace `{ns}`", root.tag_name().name())
            };
            self.diags.push(
                Diagnostic::error(
                    codes::LD_BAD_PROJECT,
                    format!("not a PLCopen TC6 project: the root element is {found}"),
                    self.span(self.qname(root)),
                )
                .with_label("expected the `<project>` of a PLCopen TC6 file")
                .with_note(format!(
                    "a PLCopen XML file is a `<project>` in one of the namespaces {}",
                    NAMESPACES.join(", ")
                )),
            );
            return None;
        }
        let mut p = Project::default();
        if let Some(types) = kid(root, "types") {
            if let Some(dts) = kid(types, "dataTypes") {
                for dt in kids(dts, "dataType") {
                    if let Some(d) = self.data_type(dt) {
                        p.types.push(d);
                    }
                }
            }
            if let Some(pous) = kid(types, "pous") {
                for pou in kids(pous, "pou") {
                    if let Some(x) = self.pou(pou) {
                        p.pous.push(x);
                    }
                }
            }
        }
        if let Some(inst) = kid(root, "instances") {
            if let Some(cs) = kid(inst, "configurations") {
                for c in kids(cs, "configuration") {
                    if let Some(x) = self.config(c) {
                        p.configs.push(x);
                    }
                }
            }
        }
        Some(p)
    }

    fn data_type(&mut self, n: Node) -> Option<DataType> {
        let name = self.need_attr(n, "name")?;
        let Some(base) = kid(n, "baseType") else {
            self.error(
                codes::LD_BAD_PROJECT,
                format!("data type `{}` has no `<baseType>`", name.value),
                self.qname(n),
            );
            return None;
        };
        let ty = self.type_in(base)?;
        let init = kid(n, "initialValue").and_then(|v| self.value_in(v));
        Some(DataType { name, ty, init })
    }

    fn pou(&mut self, n: Node) -> Option<Pou> {
        let name = self.need_attr(n, "name")?;
        let kind_text = self.need_attr(n, "pouType")?;
        let kind = match kind_text.value.as_str() {
            "program" => PouKind::Program,
            "function" => PouKind::Function,
            "functionBlock" => PouKind::FunctionBlock,
            other => {
                self.error(
                    codes::LD_BAD_PROJECT,
                    format!(
                        "unknown pouType `{other}` of POU `{}` (expected program, function or functionBlock)",
                        name.value
                    ),
                    kind_text.range.clone(),
                );
                return None;
            }
        };
        let mut ret = None;
        let mut groups = Vec::new();
        if let Some(iface) = kid(n, "interface") {
            for g in elements(iface) {
                match g.tag_name().name() {
                    "returnType" => ret = self.type_in(g),
                    "documentation" | "addData" => {}
                    _ => {
                        if let Some(grp) = self.group(g) {
                            groups.push(grp);
                        }
                    }
                }
            }
        }
        if kind == PouKind::Function && ret.is_none() {
            // A function without a result type is allowed (called as a statement).
        }
        let tag = self.tag(n);
        for a in kids(n, "actions").chain(kids(n, "transitions")) {
            if elements(a).next().is_some() {
                let what = if a.tag_name().name() == "actions" {
                    "actions of a POU in PLCopen XML"
                } else {
                    "transitions (sequential function charts)"
                };
                self.error(
                    codes::E_UNSUPPORTED,
                    format!("not supported yet: {what}"),
                    self.qname(a),
                );
            }
        }
        let bodies: Vec<Node> = kids(n, "body").collect();
        if bodies.len() > 1 {
            self.error(
                codes::E_UNSUPPORTED,
                format!("not supported yet: several bodies in POU `{}`", name.value),
                self.qname(bodies[1]),
            );
        }
        let body = match bodies.first() {
            None => Body::None,
            Some(&b) => self.body(b, &name.value)?,
        };
        Some(Pou {
            name,
            kind,
            ret,
            groups,
            body,
            tag,
        })
    }

    fn body(&mut self, b: Node, pou: &str) -> Option<Body> {
        let Some(lang) = elements(b).find(|e| {
            !matches!(
                e.tag_name().name(),
                "documentation" | "addData" | "vendorData"
            )
        }) else {
            return Some(Body::None);
        };
        Some(match lang.tag_name().name() {
            "ST" => Body::St(self.text(lang).trimmed()),
            "IL" => Body::Il(self.text(lang).trimmed()),
            "LD" | "FBD" => {
                // A body with a malformed element is not checked further: its rungs
                // would be incomplete, and every check would report consequences.
                let before = self.diags.iter().filter(|d| d.is_error()).count();
                let elems = self.ld(lang, pou);
                if self.diags.iter().filter(|d| d.is_error()).count() > before {
                    return Some(Body::None);
                }
                let g = if lang.tag_name().name() == "LD" {
                    Graphic::Ld
                } else {
                    Graphic::Fbd
                };
                Body::Graph(g, elems)
            }
            other => {
                let what = match other {
                    "SFC" => "sequential function charts (SFC)",
                    _ => "this body language",
                };
                self.diags.push(
                    Diagnostic::error(
                        codes::E_LANGUAGE_UNSUPPORTED,
                        format!("not supported yet: {what}, in POU `{pou}`"),
                        self.span(self.qname(lang)),
                    )
                    .with_note("plcc compiles LD, FBD, ST and IL bodies of PLCopen XML files"),
                );
                return None;
            }
        })
    }

    fn group(&mut self, g: Node) -> Option<VarGroup> {
        let section = match g.tag_name().name() {
            "inputVars" => Section::Input,
            "outputVars" => Section::Output,
            "inOutVars" => Section::InOut,
            "localVars" => Section::Local,
            "tempVars" => Section::Temp,
            "externalVars" => Section::External,
            "globalVars" => Section::Global,
            "accessVars" => {
                self.error(
                    codes::E_UNSUPPORTED,
                    "not supported yet: access variables",
                    self.qname(g),
                );
                return None;
            }
            other => {
                self.error(
                    codes::LD_BAD_PROJECT,
                    format!("unknown variable section `<{other}>`"),
                    self.qname(g),
                );
                return None;
            }
        };
        Some(self.vars(g, section))
    }

    fn vars(&mut self, g: Node, section: Section) -> VarGroup {
        let constant = g.attribute("constant").is_some_and(truthy);
        let retain = g.attribute("retain").is_some_and(truthy)
            || g.attribute("persistent").is_some_and(truthy);
        let vars = kids(g, "variable").filter_map(|v| self.var(v)).collect();
        VarGroup {
            section,
            constant,
            retain,
            vars,
        }
    }

    fn var(&mut self, v: Node) -> Option<Var> {
        let name = self.need_attr(v, "name")?;
        let Some(t) = kid(v, "type") else {
            self.error(
                codes::LD_BAD_PROJECT,
                format!("variable `{}` has no `<type>`", name.value),
                self.qname(v),
            );
            return None;
        };
        let ty = self.type_in(t)?;
        let address = self.attr(v, "address").filter(|a| !a.value.is_empty());
        let init = kid(v, "initialValue").and_then(|i| self.value_in(i));
        Some(Var {
            name,
            ty,
            address,
            init,
        })
    }

    /// The type inside `<type>`, `<baseType>` or `<returnType>`.
    fn type_in(&mut self, n: Node) -> Option<Type> {
        let Some(t) = elements(n).next() else {
            self.error(
                codes::LD_BAD_PROJECT,
                "a type element is empty",
                self.qname(n),
            );
            return None;
        };
        self.type_of(t)
    }

    fn type_of(&mut self, t: Node) -> Option<Type> {
        let tag = t.tag_name().name();
        let qname = self.qname(t);
        let named = |value: &str| Text {
            value: value.to_string(),
            range: qname.clone(),
            exact: vec![Piece {
                at: 0,
                src: qname.start,
                len: value.len() as u32,
            }],
        };
        Some(match tag {
            "derived" => Type::Named(self.need_attr(t, "name")?),
            "string" | "wstring" => Type::String {
                wide: tag == "wstring",
                len: self.attr(t, "length"),
            },
            "array" => {
                let mut dims = Vec::new();
                for d in kids(t, "dimension") {
                    let lo = self.need_attr(d, "lower")?;
                    let hi = self.need_attr(d, "upper")?;
                    dims.push((lo, hi));
                }
                let Some(b) = kid(t, "baseType") else {
                    self.error(codes::LD_BAD_PROJECT, "an array has no `<baseType>`", qname);
                    return None;
                };
                Type::Array {
                    dims,
                    elem: Box::new(self.type_in(b)?),
                }
            }
            "enum" => {
                let mut values = Vec::new();
                if let Some(vs) = kid(t, "values") {
                    for v in kids(vs, "value") {
                        let name = self.need_attr(v, "name")?;
                        values.push((name, self.attr(v, "value")));
                    }
                }
                let base = match kid(t, "baseType") {
                    Some(b) => Some(Box::new(self.type_in(b)?)),
                    None => None,
                };
                Type::Enum { values, base }
            }
            "struct" => Type::Struct(kids(t, "variable").filter_map(|v| self.var(v)).collect()),
            "subrangeSigned" | "subrangeUnsigned" => {
                let Some(r) = kid(t, "range") else {
                    self.error(codes::LD_BAD_PROJECT, "a subrange has no `<range>`", qname);
                    return None;
                };
                let lo = self.need_attr(r, "lower")?;
                let hi = self.need_attr(r, "upper")?;
                let Some(b) = kid(t, "baseType") else {
                    self.error(
                        codes::LD_BAD_PROJECT,
                        "a subrange has no `<baseType>`",
                        qname,
                    );
                    return None;
                };
                Type::Subrange {
                    base: Box::new(self.type_in(b)?),
                    lo,
                    hi,
                }
            }
            "pointer" => {
                let Some(b) = kid(t, "baseType") else {
                    self.error(
                        codes::LD_BAD_PROJECT,
                        "a pointer has no `<baseType>`",
                        qname,
                    );
                    return None;
                };
                Type::Ref(Box::new(self.type_in(b)?))
            }
            // The elementary types are elements named after them (`<INT/>`, `<TIME/>`).
            _ if !tag.is_empty()
                && tag
                    .bytes()
                    .all(|b| b.is_ascii_uppercase() || b.is_ascii_digit() || b == b'_') =>
            {
                let t = named(tag);
                Type::Named(t)
            }
            other => {
                self.error(
                    codes::LD_BAD_PROJECT,
                    format!("unknown type element `<{other}>`"),
                    qname,
                );
                return None;
            }
        })
    }

    /// The value inside `<initialValue>` (or an array or struct member).
    fn value_in(&mut self, n: Node) -> Option<Value> {
        let Some(v) = elements(n).next() else {
            self.error(
                codes::LD_BAD_PROJECT,
                "an initial value is empty",
                self.qname(n),
            );
            return None;
        };
        match v.tag_name().name() {
            "simpleValue" => Some(Value::Simple(self.need_attr(v, "value")?)),
            "arrayValue" => {
                let mut out = Vec::new();
                for e in kids(v, "value") {
                    let rep = self.attr(e, "repetitionValue");
                    out.push((rep, self.value_in(e)?));
                }
                Some(Value::Array(out))
            }
            "structValue" => {
                let mut out = Vec::new();
                for e in kids(v, "value") {
                    let m = self.need_attr(e, "member")?;
                    out.push((m, self.value_in(e)?));
                }
                Some(Value::Struct(out))
            }
            other => {
                self.error(
                    codes::LD_BAD_PROJECT,
                    format!("unknown value element `<{other}>`"),
                    self.qname(v),
                );
                None
            }
        }
    }

    fn config(&mut self, c: Node) -> Option<Config> {
        let name = self.need_attr(c, "name")?;
        let globals = kids(c, "globalVars")
            .map(|g| self.vars(g, Section::Global))
            .collect();
        let mut resources = Vec::new();
        for r in kids(c, "resource") {
            let Some(rname) = self.need_attr(r, "name") else {
                continue;
            };
            let globals = kids(r, "globalVars")
                .map(|g| self.vars(g, Section::Global))
                .collect();
            let mut tasks = Vec::new();
            for t in kids(r, "task") {
                let Some(tname) = self.need_attr(t, "name") else {
                    continue;
                };
                let instances = kids(t, "pouInstance")
                    .filter_map(|i| self.instance(i))
                    .collect();
                tasks.push(Task {
                    name: tname,
                    interval: self.attr(t, "interval"),
                    priority: self.attr(t, "priority"),
                    instances,
                });
            }
            let instances = kids(r, "pouInstance")
                .filter_map(|i| self.instance(i))
                .collect();
            resources.push(Resource {
                name: rname,
                globals,
                tasks,
                instances,
            });
        }
        Some(Config {
            name,
            globals,
            resources,
        })
    }

    fn instance(&mut self, i: Node) -> Option<Instance> {
        let name = self.need_attr(i, "name")?;
        // `typeName` in TC6 2.01, `type` in 1.0.
        let type_name = match self.attr(i, "typeName").or_else(|| self.attr(i, "type")) {
            Some(t) if !t.value.is_empty() => t,
            _ => {
                self.error(
                    codes::LD_BAD_PROJECT,
                    "`<pouInstance>` needs a `typeName` attribute",
                    self.qname(i),
                );
                return None;
            }
        };
        Some(Instance { name, type_name })
    }
}
