//! The PLCopen front end: projects in PLCopen TC6 XML (LD and FBD diagrams, ST and
//! IL bodies, types, globals, configurations).
//!
//! A `.xml` file is a PLCopen project (what Beremiz, OpenPLC Editor and CODESYS
//! export). It goes through:
//!
//! 1. `xml`: the file read into a model (data types, POUs with their interfaces,
//!    LD, FBD, ST or IL bodies and actions, globals, configurations, and what
//!    CODESYS keeps in `<addData>`), every string with its place in the file, and
//!    the dialect its header implies ([`Dialect`]);
//! 2. `graph`: each graphical body's connections resolved, its networks found, the
//!    ladder editor's style rules checked (warnings, errors under `--strict-rungs`;
//!    messages name the POU, the rung and the element's `localId`, at the element in
//!    the XML);
//! 3. `body` (with `order` and `wiretype`): each LD and FBD body lowered to ST
//!    statements, with the meaning of the chosen [`Profile`]; `sfc`: each sequential
//!    function chart written as textual SFC, as the editors' translator writes it;
//! 4. `view`: the whole file written as IEC source text (declarations by `decls`),
//!    with a map from that text back to the XML (`map`);
//! 5. the front end's parser, which compiles that text like any source file;
//!    diagnostics about it are moved back to the XML where the map knows where they
//!    come from.
//!
//! `--emit st` prints the text of step 4, `--emit ld-text` the diagrams drawn by
//! `text`.

mod body;
mod decls;
pub mod export;
pub(crate) mod graph;
pub mod map;
mod members;
mod order;
mod sfc;
pub(crate) mod text;
mod view;
mod wire;
mod wiretype;
pub(crate) mod xml;

#[cfg(test)]
mod project_tests;
#[cfg(test)]
mod tests;
#[cfg(test)]
mod tests_body;
#[cfg(test)]
mod tests_sfc;

use plcc_ir::diag::{Diagnostic, FileId};

/// Whose meaning a diagram gets where the standard and the editors differ
/// (`--plcopen-order`, docs/plcopen.md).
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
pub enum Profile {
    /// IEC 61131-3: each element evaluated once per scan, network by network, in
    /// data-flow order (then `executionOrderId`, then position); jumps, labels and
    /// returns run; a coil passes on its power.
    #[default]
    Iec,
    /// OpenPLC Editor v4's translator (xml2st): every statement's formula read when it
    /// runs, statements sorted by position, one edge detector per visit.
    Xml2st,
    /// OpenPLC Editor v3: as xml2st, in document order (variables and coils, then
    /// blocks, then connectors), and a coil with several wires passes on their AND.
    Openplc3,
    /// Beremiz: as OpenPLC Editor v3.
    Beremiz,
    /// The Python-2 era of both editors (Beremiz up to 2022, OpenPLC Editor up to
    /// 2.x): as OpenPLC Editor v3, but variables and coils sorted by position, then
    /// blocks sorted by position, then connectors.
    Legacy,
}

impl Profile {
    /// The profile named on the command line.
    pub fn from_name(s: &str) -> Option<Profile> {
        Some(match s.to_ascii_lowercase().as_str() {
            "iec" => Profile::Iec,
            "xml2st" | "openplc4" | "openplc-v4" => Profile::Xml2st,
            "openplc3" | "openplc-v3" => Profile::Openplc3,
            "beremiz" => Profile::Beremiz,
            "legacy" => Profile::Legacy,
            _ => return None,
        })
    }

    /// Its name.
    pub fn name(self) -> &'static str {
        match self {
            Profile::Iec => "iec",
            Profile::Xml2st => "xml2st",
            Profile::Openplc3 => "openplc3",
            Profile::Beremiz => "beremiz",
            Profile::Legacy => "legacy",
        }
    }
}

/// How PLCopen files are read.
#[derive(Clone, Debug, Default)]
pub struct Options {
    /// The meaning of diagrams where the standard and the editors differ.
    pub profile: Profile,
    /// The ladder editor's style rules (open circuits, short circuits, upper parallel
    /// branches, bridges, coils on the left rail) are errors rather than warnings.
    pub strict_rungs: bool,
}

/// The dialect a PLCopen file is written in, as its header tells.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
pub enum Dialect {
    /// IEC 61131-3 (Beremiz, OpenPLC and any other editor).
    #[default]
    Iec,
    /// CODESYS's (CODESYS, WAGO e!COCKPIT, Beckhoff TwinCAT): `POINTER TO`, `ADR`...
    /// (`LowerOptions::codesys`).
    Codesys,
}

/// A PLCopen file converted: its view (the project as IEC text), the map back to the
/// XML, and its drawing.
pub struct Converted {
    /// The view: IEC source text, the graphical bodies lowered to ST.
    pub il: String,
    /// From the view back to the XML.
    pub map: map::SpanMap,
    /// The ladder bodies drawn as ASCII (`--emit ld-text`).
    pub ld_text: String,
    /// The dialect of the editor that wrote the file.
    pub dialect: Dialect,
}

/// The stack of the thread that converts a file: the conversion recurses along a
/// rung's structure (its formulas and the IL made from them), and a machine-made rung
/// of thousands of elements must not overflow the stack of the caller's thread.
const STACK: usize = 256 << 20;

/// Reads, checks and converts one PLCopen XML file. `None` if it has errors (reported
/// to `diags`, at the XML); never panics.
pub fn convert(
    file: FileId,
    name: &str,
    text: &str,
    opts: &Options,
    diags: &mut Vec<Diagnostic>,
) -> Option<Converted> {
    std::thread::scope(|s| {
        let mut own = Vec::new();
        let job = std::thread::Builder::new()
            .name("plcc-ladder".into())
            .stack_size(STACK)
            .spawn_scoped(s, || {
                let r = convert_here(file, name, text, opts, &mut own);
                (r, own)
            });
        match job.map(|h| h.join()) {
            Ok(Ok((r, mut more))) => {
                diags.append(&mut more);
                r
            }
            // A panic in the conversion is a bug: report it rather than go on.
            Ok(Err(p)) => std::panic::resume_unwind(p),
            // No thread to be had: convert on this one.
            Err(_) => convert_here(file, name, text, opts, diags),
        }
    })
}

fn convert_here(
    file: FileId,
    name: &str,
    text: &str,
    opts: &Options,
    diags: &mut Vec<Diagnostic>,
) -> Option<Converted> {
    let errors = |d: &[Diagnostic]| d.iter().filter(|x| x.is_error()).count();
    let before = errors(diags);
    let project = xml::read(file, text, diags)?;
    let function = |pou: &xml::Pou| pou.kind == xml::PouKind::Function;
    let graphs: Vec<Option<graph::Graph>> = project
        .pous
        .iter()
        .map(|pou| build_graph(&pou.body, &pou.name.value, function(pou), file, opts, diags))
        .collect();
    // The graphs of the actions' graphical bodies, POU by POU.
    let actions: Vec<Vec<Option<graph::Graph>>> = project
        .pous
        .iter()
        .map(|pou| {
            pou.actions
                .iter()
                .map(|a| {
                    let label = format!("{}.{}", pou.name.value, a.name.value);
                    match &a.body {
                        xml::Body::Sfc(s) => {
                            chart_graph(s, &label, function(pou), file, opts, diags)
                        }
                        b => build_graph(b, &label, function(pou), file, opts, diags),
                    }
                })
                .collect()
        })
        .collect();
    // The graphs of the methods' graphical bodies (CODESYS), POU by POU.
    let methods: Vec<Vec<Option<graph::Graph>>> = project
        .pous
        .iter()
        .map(|pou| {
            pou.oo
                .methods
                .iter()
                .map(|m| {
                    let label = format!("{}.{}", pou.name.value, m.name.value);
                    build_graph(&m.body, &label, function(pou), file, opts, diags)
                })
                .collect()
        })
        .collect();
    // The graphs of the charts' graphical conditions, and of the POUs' transitions.
    let charts: Vec<Option<graph::Graph>> = project
        .pous
        .iter()
        .map(|pou| match &pou.body {
            xml::Body::Sfc(s) => chart_graph(s, &pou.name.value, function(pou), file, opts, diags),
            _ => None,
        })
        .collect();
    let transitions: Vec<Vec<Option<graph::Graph>>> = project
        .pous
        .iter()
        .map(|pou| {
            pou.transitions
                .iter()
                .map(|t| {
                    let label = format!("{}.{}", pou.name.value, t.name.value);
                    build_graph(&t.body, &label, function(pou), file, opts, diags)
                })
                .collect()
        })
        .collect();
    if errors(diags) > before {
        return None;
    }
    let graphs = view::Graphs {
        bodies: &graphs,
        actions: &actions,
        charts: &charts,
        transitions: &transitions,
        methods: &methods,
    };
    let out = view::write(&project, &graphs, file, name, opts, diags);
    if errors(diags) > before {
        return None;
    }
    let ld_text = text::render(&project, graphs.bodies);
    Some(Converted {
        il: out.text,
        map: out.map,
        ld_text,
        dialect: project.dialect,
    })
}

/// The graph of the graphical conditions of a chart (`label` names its POU, or `P.A`
/// for an action written as a chart).
fn chart_graph<'m>(
    s: &'m xml::Sfc,
    label: &str,
    function: bool,
    file: FileId,
    opts: &Options,
    diags: &mut Vec<Diagnostic>,
) -> Option<graph::Graph<'m>> {
    let cx = graph::Context {
        file,
        pou: label,
        function,
        strict: opts.strict_rungs,
        ladder: false,
    };
    graph::build(&s.graphic, &cx, diags)
}

/// The checked graph of a graphical body (LD or FBD); `None` for any other body, or
/// after an error. `label` names the body in messages (`P`, or `P.A` for an action).
fn build_graph<'m>(
    body: &'m xml::Body,
    label: &str,
    function: bool,
    file: FileId,
    opts: &Options,
    diags: &mut Vec<Diagnostic>,
) -> Option<graph::Graph<'m>> {
    let xml::Body::Graph(lang, elems) = body else {
        return None;
    };
    let cx = graph::Context {
        file,
        pou: label,
        function,
        strict: opts.strict_rungs,
        ladder: *lang == xml::Graphic::Ld,
    };
    graph::build(elems, &cx, diags)
}

/// A PLCopen file of a build and its view.
pub struct View {
    /// The XML file.
    pub xml: FileId,
    /// Its view, a source file of the build too.
    pub il: FileId,
    /// From the view back to the XML.
    pub map: map::SpanMap,
    /// The ladder bodies drawn as ASCII.
    pub ld_text: String,
    /// The dialect of the editor that wrote the XML file.
    pub dialect: Dialect,
}

/// Moves the spans of diagnostics about views back to their XML files.
pub fn remap_all(views: &[View], diags: &mut [Diagnostic]) {
    for d in diags {
        for v in views {
            v.map.remap(d, v.il, v.xml);
        }
    }
}

/// The name of the view of the PLCopen file `name`, as diagnostics and listings
/// show it.
pub fn il_view_name(name: &str) -> String {
    format!("{name} (as ST)")
}
