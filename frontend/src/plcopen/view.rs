//! The view of a PLCopen file: the whole project written as one IEC source text.
//!
//! The data types become `TYPE`, the globals (of the project, the configurations
//! and the resources) `VAR_GLOBAL`, every POU its interface as declarations, its
//! body and its actions (as CODESYS writes them: `ACTION a: ... END_ACTION` inside
//! the POU): graphical bodies (LD, FBD) as the lowering writes them, ST and IL
//! bodies as written, charts (SFC) as textual SFC (`sfc`); then the configurations. The front end compiles that text like
//! any source file, and `--emit il` prints it.

use super::body::{emit_body, write_hidden, Names, PouCtx};
use super::decls::{comment_safe, write_config, write_group, write_type, write_value};
use super::graph::Graph;
use super::map::Out;
use super::members::{push_name, write_inheritance, write_interface, write_members, write_mods};
use super::sfc;
use super::wire::Line;
use super::xml::{Body, Pou, PouKind, Project, Text, Var, VarGroup};
use plcc_ir::diag::{Diagnostic, FileId};

/// The checked graphs of a project's graphical bodies.
pub(crate) struct Graphs<'a, 'm> {
    /// `bodies[i]`: of the body of POU `i` (LD or FBD).
    pub bodies: &'a [Option<Graph<'m>>],
    /// `actions[i][k]`: of the body of action `k` of POU `i`.
    pub actions: &'a [Vec<Option<Graph<'m>>>],
    /// `charts[i]`: of the graphical conditions of the chart of POU `i` (SFC).
    pub charts: &'a [Option<Graph<'m>>],
    /// `transitions[i][k]`: of the body of transition `k` of POU `i`.
    pub transitions: &'a [Vec<Option<Graph<'m>>>],
    /// `methods[i][k]`: of the body of method `k` of POU `i` (LD or FBD).
    pub methods: &'a [Vec<Option<Graph<'m>>>],
}

/// Writes the view of a project. Errors (a block output whose type cannot be told,
/// a construct not supported) go to `diags`.
pub(crate) fn write(
    project: &Project,
    graphs: &Graphs,
    file: FileId,
    file_name: &str,
    opts: &super::Options,
    diags: &mut Vec<Diagnostic>,
) -> Out {
    let mut o = Out::default();
    o.push(&format!(
        "(* {}, as IEC 61131-3 text: made by plcc from its PLCopen XML. *)\n",
        comment_safe(file_name)
    ));
    if !project.types.is_empty() {
        o.push("\nTYPE\n");
        for t in &project.types {
            let start = o.pos();
            o.push("    ");
            o.push_text(&t.name);
            if let Some(b) = &t.extends {
                o.push(" EXTENDS ");
                push_name(&mut o, b);
            }
            o.push(" : ");
            write_type(&mut o, &t.ty, 1);
            if let Some(v) = &t.init {
                o.push(" := ");
                write_value(&mut o, v);
            }
            o.push(";");
            o.mark(start, t.name.range.clone());
            o.push("\n");
        }
        o.push("END_TYPE\n");
    }
    for g in global_groups(project) {
        if !g.vars.is_empty() {
            o.push("\n");
            write_group(&mut o, g);
        }
    }
    for i in &project.interfaces {
        write_interface(&mut o, i);
    }
    let globals: Vec<&Var> = global_groups(project).flat_map(|g| &g.vars).collect();
    let cx = Cx {
        project,
        globals: &globals,
        file,
        opts,
    };
    for (i, pou) in project.pous.iter().enumerate() {
        let body = graphs.bodies.get(i).and_then(Option::as_ref);
        let actions = graphs.actions.get(i).map_or(&[][..], Vec::as_slice);
        if let Body::Sfc(sfc) = &pou.body {
            let inp = sfc::Inputs {
                pou,
                sfc,
                graph: graphs.charts.get(i).and_then(Option::as_ref),
                transitions: graphs.transitions.get(i).map_or(&[][..], Vec::as_slice),
                actions,
                action: None,
            };
            let methods = graphs.methods.get(i).map_or(&[][..], Vec::as_slice);
            write_chart(&mut o, &cx, &inp, methods, diags);
            continue;
        }
        let transitions = graphs.transitions.get(i).map_or(&[][..], Vec::as_slice);
        let methods = graphs.methods.get(i).map_or(&[][..], Vec::as_slice);
        write_pou(&mut o, &cx, pou, body, actions, transitions, methods, diags);
    }
    for c in &project.configs {
        write_config(&mut o, c);
    }
    o
}

/// Every global variable group: the project's, then each configuration's and its
/// resources'.
fn global_groups(project: &Project) -> impl Iterator<Item = &VarGroup> {
    project
        .globals
        .iter()
        .chain(project.configs.iter().flat_map(|c| {
            c.globals
                .iter()
                .chain(c.resources.iter().flat_map(|r| &r.globals))
        }))
}

/// What every POU of the view is written with.
struct Cx<'a> {
    project: &'a Project,
    globals: &'a [&'a Var],
    file: FileId,
    opts: &'a super::Options,
}

/// The start of a POU: its head and its interface.
fn write_head(o: &mut Out, pou: &Pou) -> &'static str {
    o.push("\n");
    let (head, end) = match pou.kind {
        PouKind::Program => ("PROGRAM ", "END_PROGRAM"),
        PouKind::Function => ("FUNCTION ", "END_FUNCTION"),
        PouKind::FunctionBlock => ("FUNCTION_BLOCK ", "END_FUNCTION_BLOCK"),
    };
    let start = o.pos();
    o.push(head);
    write_mods(o, &pou.oo.mods);
    o.push_text(&pou.name);
    if let Some(r) = &pou.ret {
        o.push(" : ");
        write_type(o, r, 1);
    }
    write_inheritance(o, &pou.oo);
    o.mark(start, pou.tag.clone());
    o.push("\n");
    for g in &pou.groups {
        write_group(o, g);
    }
    end
}

/// A POU whose body is a sequential function chart: its interface, the hidden
/// variables of its graphical conditions and actions, and the chart as textual SFC
/// (with the actions it uses inside, `ACTION a: ... END_ACTION`).
fn write_chart(
    o: &mut Out,
    cx: &Cx,
    inp: &sfc::Inputs,
    methods: &[Option<Graph>],
    diags: &mut Vec<Diagnostic>,
) {
    let pou = inp.pou;
    let mut names = Names::new(cx.project, pou, cx.globals);
    let ctx = PouCtx {
        project: cx.project,
        pou: &pou.name.value,
        pou_vars: &pou.groups,
        globals: cx.globals,
        file: cx.file,
        opts: cx.opts,
    };
    let chart = sfc::plan(*inp, &ctx, &mut names, diags);
    let method_lines = lower_methods(cx, pou, methods, &mut names, diags);
    let end = write_head(o, pou);
    write_hidden(o, &names);
    if let Some(chart) = &chart {
        sfc::write(o, chart);
    }
    write_members(o, &pou.oo, &method_lines);
    o.push(end);
    o.push("\n");
}

/// A POU: its interface, body and actions. The graphical bodies (of the POU and of
/// its actions) are lowered first, with one set of hidden names, so that their
/// hidden variables are declared once, in the POU, before the code. An action
/// written as a chart is written as textual SFC, followed by the actions its chart
/// uses (which are not written again).
#[allow(clippy::too_many_arguments)]
fn write_pou(
    o: &mut Out,
    cx: &Cx,
    pou: &Pou,
    body: Option<&Graph>,
    actions: &[Option<Graph>],
    transitions: &[Option<Graph>],
    methods: &[Option<Graph>],
    diags: &mut Vec<Diagnostic>,
) {
    let end = write_head(o, pou);
    let graphs = body.is_some()
        || actions.iter().any(Option::is_some)
        || methods.iter().any(Option::is_some);
    let mut names = graphs.then(|| Names::new(cx.project, pou, cx.globals));
    // The actions written as charts, planned first.
    let mut charts: Vec<Option<sfc::Chart>> = Vec::new();
    for (k, a) in pou.actions.iter().enumerate() {
        let Body::Sfc(s) = &a.body else {
            charts.push(None);
            continue;
        };
        let inp = sfc::Inputs {
            pou,
            sfc: s,
            graph: actions.get(k).and_then(Option::as_ref),
            transitions,
            actions,
            action: Some(k),
        };
        let ctx = PouCtx {
            project: cx.project,
            pou: &pou.name.value,
            pou_vars: &pou.groups,
            globals: cx.globals,
            file: cx.file,
            opts: cx.opts,
        };
        let names = names.get_or_insert_with(|| Names::new(cx.project, pou, cx.globals));
        charts.push(sfc::plan(inp, &ctx, names, diags));
    }
    let by_charts: Vec<String> = charts
        .iter()
        .flatten()
        .flat_map(|c| c.action_names())
        .collect();
    let by_chart = |a: &super::xml::NamedBody| {
        by_charts
            .iter()
            .any(|n| n.eq_ignore_ascii_case(&a.name.value))
    };
    let mut lower = |g: &Graph, label: &str, diags: &mut Vec<Diagnostic>| -> Vec<Line> {
        let ctx = PouCtx {
            project: cx.project,
            pou: label,
            pou_vars: &pou.groups,
            globals: cx.globals,
            file: cx.file,
            opts: cx.opts,
        };
        let names = names.as_mut().expect("made for every graph");
        emit_body(g, &ctx, names, diags)
    };
    let body_lines = body.map(|g| lower(g, &pou.name.value, diags));
    let action_lines: Vec<Option<Vec<Line>>> = pou
        .actions
        .iter()
        .zip(
            actions
                .iter()
                .map(Option::as_ref)
                .chain(std::iter::repeat(None)),
        )
        .map(|(a, g)| {
            g.filter(|_| !by_chart(a) && !matches!(a.body, Body::Sfc(_)))
                .map(|g| lower(g, &format!("{}.{}", pou.name.value, a.name.value), diags))
        })
        .collect();
    let method_lines = match names.as_mut() {
        Some(n) => lower_methods(cx, pou, methods, n, diags),
        None => Vec::new(),
    };
    if let Some(n) = &names {
        write_hidden(o, n);
    }
    write_body(o, &pou.body, body.zip(body_lines.as_deref()));
    write_members(o, &pou.oo, &method_lines);
    let mut written = Vec::new();
    for (k, a) in pou.actions.iter().enumerate() {
        if by_chart(a) {
            continue;
        }
        let start = o.pos();
        o.push("ACTION ");
        o.push_text(&a.name);
        o.push(":");
        o.mark(start, a.tag.clone());
        o.push("\n");
        if let Some(c) = &charts[k] {
            sfc::write_elements(o, c);
        } else {
            let g = actions.get(k).and_then(Option::as_ref);
            write_body(o, &a.body, g.zip(action_lines[k].as_deref()));
        }
        o.push("END_ACTION\n");
        if let Some(c) = &charts[k] {
            sfc::write_actions(o, c, &mut written);
        }
    }
    o.push(end);
    o.push("\n");
}

/// The graphical bodies of a POU's methods lowered to ST, with the POU's hidden
/// names: their edge detectors and kept results are variables of the instance (a
/// method's own VAR are temporary), so they keep their values from one call to the
/// next. A method's body reads its own variables, then the POU's.
fn lower_methods<'g>(
    cx: &Cx,
    pou: &Pou,
    methods: &'g [Option<Graph<'g>>],
    names: &mut Names,
    diags: &mut Vec<Diagnostic>,
) -> Vec<Option<(&'g Graph<'g>, Vec<Line>)>> {
    let mut out = Vec::new();
    for (m, g) in pou.oo.methods.iter().zip(methods) {
        let Some(g) = g else {
            out.push(None);
            continue;
        };
        let vars: Vec<VarGroup> = m.groups.iter().chain(&pou.groups).cloned().collect();
        let label = format!("{}.{}", pou.name.value, m.name.value);
        let ctx = PouCtx {
            project: cx.project,
            pou: &label,
            pou_vars: &vars,
            globals: cx.globals,
            file: cx.file,
            opts: cx.opts,
        };
        out.push(Some((g, emit_body(g, &ctx, names, diags))));
    }
    out
}

/// A body: the lines lowered from its graph, or its text as written.
fn write_body(o: &mut Out, body: &Body, lowered: Option<(&Graph, &[Line])>) {
    match (body, lowered) {
        (Body::Graph(..), Some((g, lines))) => {
            for line in lines {
                line.write(o, g.elems);
            }
        }
        (Body::St(t) | Body::Il(t), _) => write_text(o, t),
        _ => {}
    }
}

/// An ST or IL body as written, on lines of its own.
pub(super) fn write_text(o: &mut Out, t: &Text) {
    o.push("    ");
    o.push_text(t);
    if !t.value.ends_with('\n') {
        o.push("\n");
    }
}
