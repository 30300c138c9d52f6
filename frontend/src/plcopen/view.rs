//! The view of a PLCopen file: the whole project written as one IEC source text.
//!
//! The data types become `TYPE`, the globals of the configurations and resources
//! `VAR_GLOBAL`, every POU its interface as declarations and its body: graphical
//! bodies (LD, FBD) as the lowering writes them, ST and IL bodies as written; then the
//! configurations. The front end compiles that text like any source file, and
//! `--emit il` prints it.

use super::body::{emit_body, write_hidden, Names, PouCtx};
use super::decls::{comment_safe, write_config, write_group, write_type, write_value};
use super::graph::Graph;
use super::map::Out;
use super::xml::{Body, PouKind, Project, Var};
use plcc_ir::diag::{Diagnostic, FileId};

/// Writes the view of a project. `graphs[i]` is the checked graph of POU `i`'s
/// ladder body. Errors (a block output whose type cannot be told, a construct not
/// supported) go to `diags`.
pub(crate) fn write(
    project: &Project,
    graphs: &[Option<Graph>],
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
    for c in &project.configs {
        let groups = c
            .globals
            .iter()
            .chain(c.resources.iter().flat_map(|r| &r.globals));
        for g in groups {
            if !g.vars.is_empty() {
                o.push("\n");
                write_group(&mut o, g);
            }
        }
    }
    let globals: Vec<&Var> = project
        .configs
        .iter()
        .flat_map(|c| {
            c.globals
                .iter()
                .chain(c.resources.iter().flat_map(|r| &r.globals))
        })
        .flat_map(|g| &g.vars)
        .collect();
    for (i, pou) in project.pous.iter().enumerate() {
        o.push("\n");
        let (head, end) = match pou.kind {
            PouKind::Program => ("PROGRAM ", "END_PROGRAM"),
            PouKind::Function => ("FUNCTION ", "END_FUNCTION"),
            PouKind::FunctionBlock => ("FUNCTION_BLOCK ", "END_FUNCTION_BLOCK"),
        };
        let start = o.pos();
        o.push(head);
        o.push_text(&pou.name);
        if let Some(r) = &pou.ret {
            o.push(" : ");
            write_type(&mut o, r, 1);
        }
        o.mark(start, pou.tag.clone());
        o.push("\n");
        for g in &pou.groups {
            write_group(&mut o, g);
        }
        match (&pou.body, graphs.get(i).and_then(Option::as_ref)) {
            (Body::Graph(..), Some(g)) => {
                let mut names = Names::new(project, pou, &globals);
                let ctx = PouCtx {
                    project,
                    pou: &pou.name.value,
                    pou_vars: &pou.groups,
                    globals: &globals,
                    file,
                    opts,
                };
                let lines = emit_body(g, &ctx, &mut names, diags);
                write_hidden(&mut o, &names);
                for line in &lines {
                    line.write(&mut o, g.elems);
                }
            }
            (Body::St(t), _) | (Body::Il(t), _) => {
                o.push("    ");
                o.push_text(t);
                if !t.value.ends_with('\n') {
                    o.push("\n");
                }
            }
            _ => {}
        }
        o.push(end);
        o.push("\n");
    }
    for c in &project.configs {
        write_config(&mut o, c);
    }
    o
}
