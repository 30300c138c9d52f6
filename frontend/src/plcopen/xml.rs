//! PLCopen TC6 XML read into a model: data types, POUs (interfaces, bodies,
//! actions and transitions), global variables and configurations, with what
//! CODESYS-based editors keep in `<addData>` (applications, global variable lists,
//! POUs), and the dialect the file's header implies.
//!
//! Both `http://www.plcopen.org/xml/tc6.xsd` (TC6 1.0) and `tc6_0201` (2.01, also
//! `tc6_0200`) are read: elements are matched by their local names, which the versions
//! share, and the few attributes they spell differently are tried both ways. Every
//! string keeps where it is in the file ([`Text`]), so that diagnostics, and the IL
//! made from the model, can point back at the XML.
//!
//! The reading is split by subject: `types` (data types, variables, values),
//! `pou` (POUs), `oo` (CODESYS's methods, properties, inheritance and interfaces),
//! `instances` (configurations and CODESYS's vendor data), `elements` (the elements
//! of graphical bodies), `sfc` (sequential function charts).

use super::Dialect;
use crate::codes;
use plcc_ir::diag::{Diagnostic, FileId, Span};
use roxmltree::Node;
use std::ops::Range;

mod elements;
mod instances;
mod oo;
mod pou;
mod sfc;
mod types;

pub(crate) use instances::duration_ms;
pub(crate) use oo::{Accessor, Interface, Method, Mods, Oo, Property};
pub(crate) use sfc::{ActionTarget, Cond, NodeKind, Sfc, SfcNode};

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

/// A project: what the view of the file declares.
#[derive(Debug, Default)]
pub(crate) struct Project {
    /// `types/dataTypes`.
    pub types: Vec<DataType>,
    /// `types/pous`, then the POUs CODESYS keeps in `<addData>` (of a resource, an
    /// application or the project), in document order.
    pub pous: Vec<Pou>,
    /// CODESYS's interfaces (`interface` data of the project or an application).
    pub interfaces: Vec<Interface>,
    /// `instances/configurations`, then CODESYS's applications (a resource outside
    /// any configuration, made a configuration of the same name when it has tasks or
    /// program instances; else only its globals are kept, in `globals`).
    pub configs: Vec<Config>,
    /// Global variable lists outside any configuration: CODESYS keeps a project's
    /// GVLs in its `<addData>`.
    pub globals: Vec<VarGroup>,
    /// The dialect of the editor that wrote the file.
    pub dialect: Dialect,
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
    /// The STRUCT it extends (CODESYS's `datatypeinheritance`).
    pub extends: Option<Text>,
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
    /// `<actions>`: bodies that share the POU's variables, called by name.
    pub actions: Vec<NamedBody>,
    /// `<transitions>`: the conditions an SFC body refers to by name.
    pub transitions: Vec<NamedBody>,
    /// CODESYS's methods, properties, base and interfaces.
    pub oo: Oo,
    /// The start tag, for messages about the POU.
    pub tag: Range<u32>,
}

/// An `<action name="...">` or a `<transition name="...">` of a POU: a named body
/// in any language.
#[derive(Debug)]
pub(crate) struct NamedBody {
    /// Its name.
    pub name: Text,
    /// Its body.
    pub body: Body,
    /// Its tag name, for messages about it.
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
    /// A sequential function chart (the body of a POU only).
    Sfc(Sfc),
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
#[derive(Clone, Debug)]
pub(crate) struct VarGroup {
    /// Which section.
    pub section: Section,
    /// `name`: a CODESYS global variable list's name (`GVL`).
    pub name: Option<Text>,
    /// `constant="true"`.
    pub constant: bool,
    /// `retain="true"` or `persistent="true"`.
    pub retain: bool,
    /// `nonretain="true"`.
    pub non_retain: bool,
    /// Its tag name, for messages about the group.
    pub tag: Range<u32>,
    /// The variables.
    pub vars: Vec<Var>,
}

/// `<variable name="..." address="...">` with its type and initial value.
#[derive(Clone, Debug)]
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
#[derive(Clone, Debug)]
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
    /// `<pointer>` (a reference, `REF_TO`).
    Ref(Box<Type>),
    /// `<pointer>` in a file of a CODESYS-based editor: `POINTER TO`.
    Pointer(Box<Type>),
}

/// An initial value.
#[derive(Clone, Debug)]
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

/// `<task name="..." interval="..." priority="..." single="...">`.
#[derive(Debug)]
pub(crate) struct Task {
    /// Its name.
    pub name: Text,
    /// `interval`, or CODESYS's task settings where it is missing or zero.
    pub interval: Option<Text>,
    /// `priority`.
    pub priority: Option<Text>,
    /// `single`: the variable whose rising edge starts the task.
    pub single: Option<Text>,
    /// The program instances it runs.
    pub instances: Vec<Instance>,
}

/// `<pouInstance name="..." typeName="...">` (`type` in TC6 1.0).
#[derive(Debug)]
pub(crate) struct Instance {
    /// The instance's name.
    pub name: Text,
    /// The PROGRAM it instantiates (its own name when `typeName` is empty, as
    /// CODESYS writes it).
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
    let mut r = Reader {
        src,
        file,
        diags,
        dialect: Dialect::Iec,
    };
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
    /// The file's dialect (from its header): what `<pointer>` means.
    dialect: Dialect,
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

/// The `<data>` children of the `<addData>` of `n` whose `name` ends in `/kind`
/// (CODESYS's are `http://www.3s-software.com/plcopenxml/kind`).
fn add_data<'a, 'i>(n: Node<'a, 'i>, kind: &'static str) -> impl Iterator<Item = Node<'a, 'i>> {
    kids(n, "addData").flat_map(move |a| {
        kids(a, "data").filter(move |d| {
            d.attribute("name")
                .and_then(|s| s.rsplit_once('/'))
                .is_some_and(|(_, k)| k == kind)
        })
    })
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
                } else {
                    // Entities (`&lt;`) or line ends the parser normalised: the runs
                    // that are verbatim map byte for byte, each entity to itself.
                    exact.extend(entity_pieces(raw, s, value.len() as u32, r.start as u32));
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
        self.dialect = instances::dialect(root);
        let mut p = Project {
            dialect: self.dialect,
            ..Project::default()
        };
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
        self.instances(root, &mut p);
        types::quote_string_values(&mut p);
        Some(p)
    }
}

/// The pieces of a text node whose source `raw` holds entity references or `\r\n`
/// line ends that the parser decoded into `decoded`: every verbatim run maps byte for
/// byte (`at` counts from `at0` in the value, `src` from `src0` in the file), every
/// entity or line end maps its decoded bytes to its own start. Stops at the first
/// difference it cannot explain (what follows then maps to the element).
fn entity_pieces(raw: &str, decoded: &str, at0: u32, src0: u32) -> Vec<Piece> {
    /// Adds a piece, extending the last one when both run on together.
    fn add(out: &mut Vec<Piece>, at: u32, src: u32, len: u32) {
        match out.last_mut() {
            Some(p) if p.at + p.len == at && p.src + p.len == src => p.len += len,
            _ => out.push(Piece { at, src, len }),
        }
    }
    let (rb, db) = (raw.as_bytes(), decoded.as_bytes());
    let (mut i, mut j) = (0usize, 0usize);
    let mut out = Vec::new();
    while i < rb.len() && j < db.len() {
        let (at, src) = (at0 + j as u32, src0 + i as u32);
        if rb[i] == db[j] && rb[i] != b'&' {
            add(&mut out, at, src, 1);
            i += 1;
            j += 1;
        } else if rb[i] == b'\r' && db[j] == b'\n' {
            add(&mut out, at, src, 1);
            i += if rb.get(i + 1) == Some(&b'\n') { 2 } else { 1 };
            j += 1;
        } else if rb[i] == b'&' {
            let Some(end) = raw[i..].find(';').map(|k| i + k) else {
                break;
            };
            let Some(c) = entity(&raw[i + 1..end]) else {
                break;
            };
            let k = c.len_utf8();
            if decoded.get(j..j + k) != Some(c.encode_utf8(&mut [0; 4])) {
                break;
            }
            add(&mut out, at, src, k as u32);
            i = end + 1;
            j += k;
        } else {
            break;
        }
    }
    out
}

/// The character of an XML entity reference's name (`lt`, `#60`, `#x3C`).
fn entity(name: &str) -> Option<char> {
    match name {
        "lt" => Some('<'),
        "gt" => Some('>'),
        "amp" => Some('&'),
        "quot" => Some('"'),
        "apos" => Some('\''),
        _ => {
            let n = name.strip_prefix('#')?;
            let v = match n.strip_prefix(['x', 'X']) {
                Some(h) => u32::from_str_radix(h, 16).ok()?,
                None => n.parse().ok()?,
            };
            char::from_u32(v)
        }
    }
}
