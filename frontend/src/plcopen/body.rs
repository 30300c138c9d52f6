//! Graphical bodies (LD and FBD) lowered to Structured Text statements.
//!
//! One algorithm for both languages, as in the editors (the reference's §2): the
//! value reaching an input is the OR of what its connections carry; a left rail
//! carries TRUE; a contact carries its (modified) variable AND its input; a coil
//! passes its power on; a block output is the instance's output (`ton0.Q`) or the
//! variable keeping a function's result (`_TMP_ADD5_OUT`); a continuation carries
//! what reaches its connector. The statements are the sinks': a coil or output
//! variable is assigned, a block is called, a jump or return is taken when powered.
//!
//! Two ways of walking, chosen by the profile ([`super::Profile`]):
//!
//! - **Once** (the standard's, the default): every element is evaluated once per
//!   scan, network by network, in [`order::network`]'s order. A contact's value is
//!   taken when it is evaluated: if a later statement of the network writes a
//!   variable that a value still to be used reads, that value is kept first in a
//!   `VAR_TEMP` (`_P<localId>`). Edge detectors: one per element or pin.
//! - **Expand** (the editors'): the statements are written in the editors' order
//!   ([`order::sinks`]) and each one's value is the whole formula back to the rail,
//!   read when the statement runs; blocks are called when a statement first needs
//!   them ("pulled"), or in their own place; an edge detector per visit. Jumps,
//!   labels and returns are ignored, as PLCGenerator ignores them.
//!
//! Hidden variables, declared in the POU: `R_TRIG<n>`/`F_TRIG<n>` edge detectors
//! (the smallest free number, as the editors name them), `_TMP_<TYPE><localId>_<pin>`
//! for a function's outputs and ENO (kept between scans, as the editors keep them),
//! `_P<localId>` for a value kept within a scan.

use super::graph::{eno_read, input_name, output_name, output_port, Graph, Src};
use super::map::Out;
use super::order;
use super::wire::{
    and, named, not, or, part, reads_any, render, root, term, text_part, Line, Part, X,
};
use super::wiretype::{
    control_input, hidden_part, is_result_pin, output_type, passes_type, source_type, Scope,
};
use super::xml::{Edge, Element, Kind, Project, Storage, Text, Var, VarGroup};
use super::{Options, Profile};
use crate::codes;
use plcc_ir::diag::{Diagnostic, FileId, Span};
use rustc_hash::{FxHashMap, FxHashSet};

// ------------------------------------------------------------------ names

/// The hidden variables of one POU (its body and its actions), named so that none
/// clashes with a name the POU can see.
pub(super) struct Names {
    taken: FxHashSet<String>,
    /// VAR declarations: (name, type).
    vars: Vec<(String, String)>,
    /// VAR_TEMP declarations: (name, type).
    temps: Vec<(String, String)>,
}

impl Names {
    /// The names of POU `pou` of `project`, with `globals` visible to it.
    pub(super) fn new(project: &Project, pou: &super::xml::Pou, globals: &[&Var]) -> Names {
        let mut taken = FxHashSet::default();
        let mut add = |s: &str| {
            taken.insert(s.to_ascii_uppercase());
        };
        for p in &project.pous {
            add(&p.name.value);
        }
        for t in &project.types {
            add(&t.name.value);
        }
        for v in globals {
            add(&v.name.value);
        }
        let methods = pou.oo.methods.iter().flat_map(|m| &m.groups);
        for grp in pou.groups.iter().chain(methods) {
            for v in &grp.vars {
                add(&v.name.value);
            }
        }
        Names {
            taken,
            vars: Vec::new(),
            temps: Vec::new(),
        }
    }

    /// Marks a name as taken (a step or an action of a chart).
    pub(super) fn take(&mut self, name: &str) {
        self.taken.insert(name.to_ascii_uppercase());
    }

    /// Marks the labels of a body as taken.
    fn labels(&mut self, elems: &[Element]) {
        for e in elems {
            if let Kind::Label { label } = &e.kind {
                self.taken.insert(label.value.to_ascii_uppercase());
            }
        }
    }

    fn free(&mut self, base: &str) -> String {
        let mut name = base.to_string();
        let mut k = 1;
        while self.taken.contains(&name.to_ascii_uppercase()) {
            name = format!("{base}_{k}");
            k += 1;
        }
        self.taken.insert(name.to_ascii_uppercase());
        name
    }

    /// A new edge detector instance: `R_TRIG<n>` or `F_TRIG<n>`, n the smallest free.
    fn detector(&mut self, rising: bool) -> String {
        let ty = if rising { "R_TRIG" } else { "F_TRIG" };
        let mut n = 1;
        while self.taken.contains(&format!("{ty}{n}")) {
            n += 1;
        }
        let name = format!("{ty}{n}");
        self.taken.insert(name.clone());
        self.vars.push((name.clone(), ty.to_string()));
        name
    }

    /// A variable kept between scans (VAR).
    fn var(&mut self, base: &str, ty: &str) -> String {
        let name = self.free(base);
        self.vars.push((name.clone(), ty.to_string()));
        name
    }

    /// A variable kept within a scan (VAR_TEMP).
    fn temp(&mut self, base: &str, ty: &str) -> String {
        let name = self.free(base);
        self.temps.push((name.clone(), ty.to_string()));
        name
    }
}

/// Writes the declarations of the hidden variables.
pub(super) fn write_hidden(o: &mut Out, n: &Names) {
    for (kw, list) in [("VAR", &n.vars), ("VAR_TEMP", &n.temps)] {
        if list.is_empty() {
            continue;
        }
        o.push(kw);
        o.push("\n");
        for (name, ty) in list {
            o.push(&format!("    {name} : {ty};\n"));
        }
        o.push("END_VAR\n");
    }
}

// ------------------------------------------------------------------ the walk

/// What the lowering of one body needs to know about its POU.
pub(super) struct PouCtx<'a> {
    /// The project.
    pub project: &'a Project,
    /// The POU's name.
    pub pou: &'a str,
    /// The POU's variable groups.
    pub pou_vars: &'a [VarGroup],
    /// The globals it can see.
    pub globals: &'a [&'a Var],
    /// The XML file.
    pub file: FileId,
    /// The profile and other options.
    pub opts: &'a Options,
}

/// Lowers a checked graphical body to ST lines; hidden variables go to `names`.
pub(super) fn emit_body(
    g: &Graph,
    ctx: &PouCtx,
    names: &mut Names,
    diags: &mut Vec<Diagnostic>,
) -> Vec<Line> {
    names.labels(g.elems);
    let mut l = Lower {
        g,
        ctx,
        names,
        diags,
        lines: Vec::new(),
        done: vec![false; g.elems.len()],
        memo: FxHashMap::default(),
        no_pull: 0,
        eno: FxHashMap::default(),
        results: FxHashMap::default(),
        pull: false,
    };
    if ctx.opts.profile == Profile::Iec {
        l.once();
    } else {
        l.expand();
    }
    let mut lines = l.lines;
    // A body that starts with a label or a jump (`JMP` is an IL operator too) would
    // be taken for Instruction List.
    let il_like = |l: &Line| l.label || l.parts.first().is_some_and(|p| p.s.starts_with("JMP "));
    if lines.iter().find(|l| l.elem.is_some()).is_some_and(il_like) {
        lines.insert(
            0,
            Line {
                parts: vec![part(";")],
                elem: None,
                label: false,
            },
        );
    }
    lines
}

/// What the conditions read from one graph have computed so far: the blocks called,
/// the variables holding ENOs and function results. Kept from one condition to the
/// next, so that a block is called once however many conditions read it.
#[derive(Default)]
pub(super) struct CondState {
    done: Vec<bool>,
    eno: FxHashMap<usize, String>,
    results: FxHashMap<(usize, usize), String>,
}

/// The value reaching the input of `sink` (a coil or an output variable of `g`) as a
/// transition condition, `:= <value>;`, and the statements it needs first: the calls
/// of the blocks it reads (pulled on demand, under every profile) and of its edge
/// detectors, which the chart runs in its `COMPUTE_FUNCTION_BLOCKS` action (as the
/// editors' translator does). Hidden variables go to `names`.
pub(super) fn emit_condition(
    g: &Graph,
    sink: usize,
    state: &mut CondState,
    ctx: &PouCtx,
    names: &mut Names,
    diags: &mut Vec<Diagnostic>,
) -> (Vec<Line>, Line) {
    if state.done.len() != g.elems.len() {
        state.done = vec![false; g.elems.len()];
    }
    let mut l = Lower {
        g,
        ctx,
        names,
        diags,
        lines: Vec::new(),
        done: std::mem::take(&mut state.done),
        memo: FxHashMap::default(),
        no_pull: 0,
        eno: std::mem::take(&mut state.eno),
        results: std::mem::take(&mut state.results),
        pull: true,
    };
    let x = l.input(sink, 0);
    let mut parts = vec![part(":= ")];
    render(&x, true, &mut parts);
    parts.push(part(";"));
    state.done = l.done;
    state.eno = l.eno;
    state.results = l.results;
    let cond = Line {
        parts,
        elem: Some(sink),
        label: false,
    };
    (l.lines, cond)
}

/// A value computed once (profile iec): the formula, and whether it is power flow
/// (a BOOL that a later write can change, kept in a temporary first).
struct Memo {
    x: X,
    power: bool,
}

struct Lower<'a, 'g, 'n, 'd> {
    g: &'a Graph<'g>,
    ctx: &'a PouCtx<'a>,
    names: &'n mut Names,
    diags: &'d mut Vec<Diagnostic>,
    lines: Vec<Line>,
    /// Blocks already called.
    done: Vec<bool>,
    /// Values of outputs already evaluated (profile iec).
    memo: FxHashMap<Src, Memo>,
    /// Inside the inputs of a block with an `executionOrderId`: do not pull.
    no_pull: u32,
    /// The variable holding a block's ENO, when made.
    eno: FxHashMap<usize, String>,
    /// The variables holding a function's outputs, by port.
    results: FxHashMap<(usize, usize), String>,
    /// Blocks are pulled when a value needs them, under every profile (a transition
    /// condition).
    pull: bool,
}

impl Lower<'_, '_, '_, '_> {
    fn elem(&self, e: usize) -> &Element {
        &self.g.elems[e]
    }

    fn span(&self, e: usize) -> Span {
        let r = &self.g.elems[e].tag;
        Span::new(self.ctx.file, r.start, r.end)
    }

    fn describe(&self, e: usize) -> String {
        let el = self.elem(e);
        format!("{} (localId {})", el.kind.describe(), el.id)
    }

    fn push(&mut self, parts: Vec<Part>, e: usize) {
        self.lines.push(Line {
            parts,
            elem: Some(e),
            label: false,
        });
    }

    fn unsupported(&mut self, e: usize, what: &str) {
        let msg = format!(
            "not supported yet: {what} ({} of `{}`)",
            self.describe(e),
            self.ctx.pou
        );
        self.diags
            .push(Diagnostic::error(codes::E_UNSUPPORTED, msg, self.span(e)));
    }

    // -------------------------------------------------------------- walks

    /// Profile iec: network by network, each element once, in data-flow order.
    fn once(&mut self) {
        for (n, rung) in self.g.rungs.iter().enumerate() {
            let order = match order::network(self.g, &rung.order) {
                Ok(o) => o,
                // Reported by the checks; nothing to lower.
                Err(_) => continue,
            };
            let at = self.lines.len();
            let commented = self.g.rungs.len() > 1;
            if commented {
                self.lines.push(Line {
                    parts: vec![part(format!("(* network {} *)", n + 1))],
                    elem: None,
                    label: false,
                });
            }
            for e in order {
                self.visit(e);
            }
            if commented && self.lines.len() == at + 1 {
                // Nothing came of it: no comment either.
                self.lines.pop();
            }
            // Values do not cross networks.
            self.memo.clear();
        }
    }

    fn visit(&mut self, e: usize) {
        let el = self.elem(e);
        match &el.kind {
            Kind::Contact { var, negated, edge } => {
                let (var, negated, edge) = (var.clone(), *negated, *edge);
                let input = self.input(e, 0);
                let t = self.modified(term(&var), negated, edge, e);
                self.memo.insert(
                    Src { elem: e, port: 0 },
                    Memo {
                        x: and(input, t),
                        power: true,
                    },
                );
            }
            Kind::Coil { var, .. } => {
                let var = var.clone();
                self.flush(&[root(&var.value)], e);
                let p = self.input(e, 0);
                self.coil(e, p.clone());
                let pass = self.coil_passthrough(e, p);
                self.memo.insert(
                    Src { elem: e, port: 0 },
                    Memo {
                        x: pass,
                        power: true,
                    },
                );
            }
            Kind::Block { .. } => {
                self.block(e);
                self.memo_outputs(e);
            }
            Kind::OutVariable { .. } | Kind::InOutVariable { .. } => self.variable(e),
            // An unconnected jump or return does nothing.
            Kind::Jump { .. } | Kind::Return if self.g.ins[e][0].is_empty() => {}
            Kind::Jump { label } => {
                let label = label.clone();
                let p = self.input(e, 0);
                let mut s = vec![part("JMP "), text_part(&label), part(";")];
                self.guarded(p, &mut s);
                self.push(s, e);
            }
            Kind::Return => {
                let p = self.input(e, 0);
                let mut s = vec![part("RETURN;")];
                self.guarded(p, &mut s);
                self.push(s, e);
            }
            Kind::Label { label } => {
                let label = label.clone();
                self.lines.push(Line {
                    parts: vec![text_part(&label), part(":")],
                    elem: Some(e),
                    label: true,
                });
            }
            _ => {}
        }
    }

    /// Wraps a statement in `IF p THEN ... END_IF;` unless p is TRUE.
    fn guarded(&self, p: X, s: &mut Vec<Part>) {
        if let X::True = p {
            return;
        }
        let mut head = vec![part("IF ")];
        render(&p, true, &mut head);
        head.push(part(" THEN "));
        head.append(s);
        head.push(part(" END_IF;"));
        *s = head;
    }

    /// Keeps in temporaries the values still to be used that read a variable the
    /// next statement writes (profile iec).
    fn flush(&mut self, writes: &[String], at: usize) {
        let writes: Vec<&String> = writes.iter().filter(|w| !w.is_empty()).collect();
        if writes.is_empty() || self.memo.is_empty() {
            return;
        }
        // In element order: a value is mostly built on those of elements before it,
        // whose shared parts `seen` then already holds.
        let mut memos: Vec<(&Src, &Memo)> = self.memo.iter().filter(|(_, m)| m.power).collect();
        memos.sort_by_key(|(s, _)| (s.elem, s.port));
        let mut seen = FxHashMap::default();
        let hit: Vec<Src> = memos
            .into_iter()
            .filter(|(_, m)| reads_any(&m.x, &writes, &mut seen))
            .map(|(s, _)| *s)
            .collect();
        for s in hit {
            let id = self.elem(s.elem).id;
            let name = self.names.temp(&format!("_P{id}"), "BOOL");
            let m = self.memo.get_mut(&s).expect("listed");
            let x = std::mem::replace(&mut m.x, named(name.clone()));
            let mut line = vec![part(name), part(" := ")];
            render(&x, true, &mut line);
            line.push(part(";"));
            self.push(line, at);
        }
    }

    /// Profile iec: what a block's outputs carry after its call.
    fn memo_outputs(&mut self, e: usize) {
        for port in 0..self.g.outs[e].len() {
            if self.g.outs[e][port].is_empty() {
                continue;
            }
            let x = self.output_term(e, port);
            let (negated, edge) = self.out_pin(e, port);
            let x = self.modified(x, negated, edge, e);
            self.memo
                .insert(Src { elem: e, port }, Memo { x, power: false });
        }
    }

    /// Profile xml2st, openplc3, beremiz: the editors' statements in their order.
    fn expand(&mut self) {
        let order = match self.ctx.opts.profile {
            Profile::Xml2st => order::Order::Position,
            Profile::Legacy => order::Order::PositionGrouped,
            _ => order::Order::Document,
        };
        for e in order::sinks(self.g.elems, order) {
            match &self.elem(e).kind {
                Kind::Coil { .. } => {
                    let p = self.input(e, 0);
                    self.coil(e, p);
                }
                Kind::OutVariable { .. } | Kind::InOutVariable { .. } => self.variable(e),
                Kind::Block { .. } if !self.done[e] => self.block(e),
                Kind::Connector { .. } => {
                    // Its value is computed (pulling blocks) where it is first used.
                    let _ = self.input(e, 0);
                }
                _ => {}
            }
        }
        if let Some(e) = self.g.elems.iter().position(|x| {
            matches!(
                x.kind,
                Kind::Jump { .. } | Kind::Label { .. } | Kind::Return
            )
        }) {
            let msg = format!(
                "{} of `{}` is ignored: under profile {}, jumps, labels and returns do nothing, \
                 as the editor's translator ignores them",
                self.describe(e),
                self.ctx.pou,
                self.ctx.opts.profile.name()
            );
            self.diags.push(Diagnostic::warning(
                codes::W_PLCOPEN_IGNORED,
                msg,
                self.span(e),
            ));
        }
    }

    // -------------------------------------------------------------- values

    /// The value reaching input `port` of element `e`: the OR of its connections.
    /// An unconnected contact or coil of a ladder takes the rail.
    fn input(&mut self, e: usize, port: usize) -> X {
        let srcs = self.g.ins[e].get(port).cloned().unwrap_or_default();
        if srcs.is_empty() {
            return X::True;
        }
        let xs: Vec<X> = srcs.iter().map(|&s| self.value(s)).collect();
        or(xs)
    }

    /// The value output `s` carries.
    fn value(&mut self, s: Src) -> X {
        if let Some(m) = self.memo.get(&s) {
            return m.x.clone();
        }
        let el = self.elem(s.elem);
        let iec = self.ctx.opts.profile == Profile::Iec;
        match &el.kind {
            Kind::LeftRail => X::True,
            Kind::InVariable { expr, negated } => {
                let x = term(expr);
                // The editors ignore `negated` on variables; the standard does not.
                if *negated && iec {
                    not(x)
                } else {
                    x
                }
            }
            Kind::InOutVariable { expr } => term(expr),
            Kind::Contact { var, negated, edge } => {
                let (var, negated, edge) = (var.clone(), *negated, *edge);
                let input = self.input(s.elem, 0);
                let t = self.modified(term(&var), negated, edge, s.elem);
                and(input, t)
            }
            Kind::Coil { .. } => {
                let p = self.input(s.elem, 0);
                self.coil_passthrough(s.elem, p)
            }
            Kind::Block { .. } => {
                // The editors pull a block when a statement needs it; the standard
                // runs it at its place, so a block not run yet (a loop cut there) is
                // read as it is: the previous scan's value.
                if !self.done[s.elem] && self.no_pull == 0 && (!iec || self.pull) {
                    self.block(s.elem);
                }
                let x = self.output_term(s.elem, s.port);
                let (negated, edge) = self.out_pin(s.elem, s.port);
                self.modified(x, negated, edge, s.elem)
            }
            _ => X::True,
        }
    }

    /// What a coil passes on to the elements after it: its power (the OR of its
    /// wires), or the AND of its wires as Beremiz and OpenPLC Editor v3 compute it.
    fn coil_passthrough(&mut self, e: usize, power: X) -> X {
        let srcs = &self.g.ins[e][0];
        if srcs.len() < 2
            || !matches!(
                self.ctx.opts.profile,
                Profile::Openplc3 | Profile::Beremiz | Profile::Legacy
            )
        {
            return power;
        }
        let srcs = srcs.clone();
        let mut x = X::True;
        for s in srcs {
            let v = self.value(s);
            x = and(x, v);
        }
        x
    }

    /// A term with a modifier: negation, or an edge detector called now.
    fn modified(&mut self, x: X, negated: bool, edge: Edge, e: usize) -> X {
        if negated {
            return not(x);
        }
        match edge {
            Edge::None => x,
            Edge::Rising | Edge::Falling => {
                let name = self.names.detector(edge == Edge::Rising);
                let mut line = vec![part(format!("{name}(CLK := "))];
                render(&x, true, &mut line);
                line.push(part(");"));
                self.push(line, e);
                named(format!("{name}.Q"))
            }
        }
    }

    /// (negated, edge) of output `port` of block `e`.
    fn out_pin(&self, e: usize, port: usize) -> (bool, Edge) {
        match output_port(&self.elem(e).kind, port) {
            Some(p) => (p.negated, p.edge.unwrap_or(Edge::None)),
            None => (false, Edge::None),
        }
    }

    // -------------------------------------------------------------- statements

    fn coil(&mut self, e: usize, p: X) {
        let Kind::Coil {
            var,
            negated,
            storage,
            edge,
        } = &self.elem(e).kind
        else {
            return;
        };
        let (var, negated, storage, edge) = (var.clone(), *negated, *storage, *edge);
        let mut s = vec![text_part(&var), part(" := ")];
        match (storage, edge) {
            (Storage::Set, _) | (Storage::Reset, _) => {
                let v = if storage == Storage::Set {
                    "TRUE"
                } else {
                    "FALSE"
                };
                let mut st = vec![text_part(&var), part(format!(" := {v};"))];
                if let X::True = p {
                } else {
                    self.guarded(p, &mut st);
                }
                self.push(st, e);
                return;
            }
            (_, Edge::Rising) | (_, Edge::Falling) => {
                let name = self.names.detector(edge == Edge::Rising);
                let mut call = vec![part(format!("{name}(CLK := "))];
                render(&p, true, &mut call);
                call.push(part(");"));
                self.push(call, e);
                s.push(part(format!("{name}.Q")));
            }
            _ => {
                let v = if negated { not(p) } else { p };
                render(&v, true, &mut s);
            }
        }
        s.push(part(";"));
        self.push(s, e);
    }

    /// An output or in-out variable: assigned the value wired to it (when it has one);
    /// fed by a block whose EN is wired, only when the block ran (its ENO).
    fn variable(&mut self, e: usize) {
        let expr = match &self.elem(e).kind {
            Kind::OutVariable { expr, .. } | Kind::InOutVariable { expr } => expr.clone(),
            _ => return,
        };
        let srcs = self.g.ins[e][0].clone();
        if srcs.is_empty() {
            return;
        }
        if self.ctx.opts.profile == Profile::Iec {
            self.flush(&[root(&expr.value)], e);
        }
        let v = self.input(e, 0);
        let negated = matches!(self.elem(e).kind, Kind::OutVariable { negated: true, .. })
            && self.ctx.opts.profile == Profile::Iec;
        let v = if negated { not(v) } else { v };
        let mut s = vec![text_part(&expr), part(" := ")];
        render(&v, true, &mut s);
        s.push(part(";"));
        if let [src] = srcs.as_slice() {
            let from_eno = output_name(&self.elem(src.elem).kind, src.port)
                .is_some_and(|n| n.eq_ignore_ascii_case("ENO"));
            // The standard guards the block's results, not ENO itself; the editors
            // guard whatever the block feeds.
            let guard = !from_eno || self.ctx.opts.profile != Profile::Iec;
            if guard && self.en_wired(src.elem) {
                if let Some(eno) = self.eno_of(src.elem) {
                    self.guarded(named(eno), &mut s);
                }
            }
        }
        self.push(s, e);
    }

    /// True if `e` is a block whose EN input is wired (to anything but the left rail
    /// alone, which is EN always TRUE).
    fn en_wired(&self, e: usize) -> bool {
        self.en_port(e).is_some()
    }

    /// The EN input of block `e`, if it is wired to anything but the left rail alone.
    fn en_port(&self, e: usize) -> Option<usize> {
        let k = &self.elem(e).kind;
        if !matches!(k, Kind::Block { .. }) {
            return None;
        }
        (0..self.g.ins[e].len()).find(|&p| {
            let srcs = &self.g.ins[e][p];
            input_name(k, p).is_some_and(|n| n.eq_ignore_ascii_case("EN"))
                && !srcs.is_empty()
                && !srcs
                    .iter()
                    .any(|s| matches!(self.elem(s.elem).kind, Kind::LeftRail))
        })
    }

    /// The variable holding ENO of block `e` (made when the block is called).
    fn eno_of(&mut self, e: usize) -> Option<String> {
        if !self.done[e]
            && self.no_pull == 0
            && (self.ctx.opts.profile != Profile::Iec || self.pull)
        {
            self.block(e);
        }
        self.eno.get(&e).cloned()
    }

    /// True if ENO of block `e` must be kept: something is wired to it, or a variable
    /// is fed by the block alone (its write is guarded by ENO).
    fn needs_eno(&self, e: usize) -> bool {
        if !self.en_wired(e) {
            return false;
        }
        let k = &self.elem(e).kind;
        (0..self.g.outs[e].len()).any(|p| {
            let is_eno = output_name(k, p).is_some_and(|n| n.eq_ignore_ascii_case("ENO"));
            self.g.outs[e][p].iter().any(|&(c, _)| {
                is_eno
                    || (matches!(
                        self.elem(c).kind,
                        Kind::OutVariable { .. } | Kind::InOutVariable { .. }
                    ) && self.g.ins[c][0].len() == 1)
            })
        })
    }

    /// The term an output of a block is read as.
    fn output_term(&mut self, e: usize, port: usize) -> X {
        let Kind::Block { ty, instance, .. } = &self.elem(e).kind else {
            return X::True;
        };
        let pin = output_name(&self.elem(e).kind, port)
            .unwrap_or("")
            .to_string();
        if pin.eq_ignore_ascii_case("ENO") {
            if let Some(n) = self.eno.get(&e) {
                return named(n.clone());
            }
            if self.en_wired(e) {
                // Read before the block runs (a loop back to it): the variable that
                // keeps its ENO, as the previous scan left it.
                return named(self.eno_var(e));
            }
            // ENO of a block whose EN is not wired: it always runs.
            return X::True;
        }
        // The output side of an in-out is the variable wired to its input side (an
        // in-out is in `inOutVariables`, or, as Beremiz writes it, an input and an
        // output of the same name).
        if let Kind::Block {
            inputs,
            outputs,
            in_outs,
            ..
        } = &self.elem(e).kind
        {
            if port >= outputs.len() && port - outputs.len() < in_outs.len() {
                let input = inputs.len() + (port - outputs.len());
                return self.input(e, input);
            }
            let same = inputs.iter().position(|p| {
                p.name
                    .as_ref()
                    .is_some_and(|n| n.value.eq_ignore_ascii_case(&pin))
            });
            if let Some(input) = same {
                if !self.g.ins[e][input].is_empty() {
                    return self.input(e, input);
                }
            }
        }
        match instance {
            Some(i) => {
                let i = i.clone();
                let pname = output_port(&self.elem(e).kind, port).and_then(|p| p.name.clone());
                let mut parts = vec![text_part(&i), part(".")];
                match pname {
                    Some(p) => parts.push(text_part(&p)),
                    None => parts.push(part(pin)),
                }
                X::Term(parts)
            }
            None => {
                let ty = ty.value.clone();
                match self.results.get(&(e, port)) {
                    Some(n) => named(n.clone()),
                    None => {
                        // Read before the function runs (a loop): its variable, which
                        // keeps the previous scan's result.
                        let n = self.result_var(e, port, &ty);
                        named(n)
                    }
                }
            }
        }
    }

    /// The variable keeping ENO of block `e`, declared on first use.
    fn eno_var(&mut self, e: usize) -> String {
        if let Some(n) = self.eno.get(&e) {
            return n.clone();
        }
        let id = self.elem(e).id;
        let ty = match &self.elem(e).kind {
            Kind::Block { ty, .. } => ty.value.to_ascii_uppercase(),
            _ => String::new(),
        };
        let name = self
            .names
            .var(&format!("_TMP_{}{id}_ENO", hidden_part(&ty)), "BOOL");
        self.eno.insert(e, name.clone());
        name
    }

    /// The variable keeping output `port` of function block `e`, declared on first use.
    fn result_var(&mut self, e: usize, port: usize, ty: &str) -> String {
        if let Some(n) = self.results.get(&(e, port)) {
            return n.clone();
        }
        let id = self.elem(e).id;
        let pin = output_name(&self.elem(e).kind, port)
            .unwrap_or("OUT")
            .to_string();
        let scope = Scope {
            project: self.ctx.project,
            pou_vars: self.ctx.pou_vars,
            globals: self.ctx.globals,
        };
        let t = match output_type(self.g, &scope, e, port, 0) {
            Some(t) => t,
            None => {
                let msg = format!(
                    "cannot tell the type of output `{pin}` of {} in `{}`, which is kept in a variable",
                    self.describe(e),
                    self.ctx.pou
                );
                self.diags.push(
                    Diagnostic::error(codes::LD_OUTPUT_TYPE, msg, self.span(e)).with_note(
                        "wire a variable of the POU to one of the block's inputs, or its output \
                         to a variable",
                    ),
                );
                "BOOL".to_string()
            }
        };
        let base = format!(
            "_TMP_{}{id}_{}",
            hidden_part(&ty.to_ascii_uppercase()),
            hidden_part(&pin.to_ascii_uppercase())
        );
        let name = self.names.var(&base, &t);
        self.results.insert((e, port), name.clone());
        name
    }

    /// Calls block `e` (once): a function block instance, or a function whose
    /// results go to variables.
    fn block(&mut self, e: usize) {
        if self.done[e] {
            return;
        }
        // Marked first: a loop back to this block reads its outputs as they are.
        self.done[e] = true;
        let Kind::Block { ty, instance, .. } = &self.elem(e).kind else {
            return;
        };
        let (ty, instance) = (ty.clone(), instance.clone());
        if instance.is_none() && ty.value.contains('.') && (self.en_wired(e) || eno_read(self.g, e))
        {
            self.unsupported(e, "EN and ENO of a method called as a block");
            return;
        }
        let pulls = self.elem(e).order.is_none() || self.ctx.opts.profile == Profile::Iec;
        if !pulls {
            self.no_pull += 1;
        }
        let args = self.arguments(e);
        if !pulls {
            self.no_pull -= 1;
        }
        let Some(mut args) = args else {
            return;
        };
        if self.needs_eno(e) || self.eno.contains_key(&e) {
            let name = self.eno_var(e);
            args.push(vec![part(format!("ENO => {name}"))]);
        }
        let writes: Vec<String> = match &instance {
            Some(i) => vec![root(&i.value)],
            None => Vec::new(),
        };
        match instance {
            Some(inst) => {
                if self.ctx.opts.profile == Profile::Iec {
                    self.flush(&writes, e);
                }
                let mut s = vec![text_part(&inst), part("(")];
                join(&mut s, args);
                s.push(part(");"));
                self.push(s, e);
            }
            None => self.function_call(e, &ty, args),
        }
    }

    /// The arguments of a block call, `name := value` for each wired input (EN
    /// included), in the XML's order; a negated or edge pin modifies its value.
    /// `None` after an error.
    fn arguments(&mut self, e: usize) -> Option<Vec<Vec<Part>>> {
        let Kind::Block {
            inputs,
            in_outs,
            instance,
            ..
        } = &self.elem(e).kind
        else {
            return None;
        };
        let n_in = inputs.len();
        let is_fb = instance.is_some();
        let pins: Vec<(Text, bool, Edge)> = inputs
            .iter()
            .chain(in_outs)
            .map(|p| {
                (
                    p.name.clone().unwrap_or_default(),
                    p.negated,
                    p.edge.unwrap_or(Edge::None),
                )
            })
            .collect();
        // A standard function needs every input: an unwired one takes its type's
        // default (a named argument), not the next wire (the editors' positional
        // shift, a translator bug).
        let ty = match &self.elem(e).kind {
            Kind::Block { ty, .. } => ty.value.clone(),
            _ => String::new(),
        };
        let standard = !is_fb && !self.project_pou(&ty);
        let en = self.en_port(e);
        let mut args = Vec::new();
        for (port, (pname, negated, edge)) in pins.into_iter().enumerate() {
            if pname.value.eq_ignore_ascii_case("EN") && Some(port) != en {
                // Not wired, or wired to the left rail: the block always runs.
                continue;
            }
            if self.g.ins[e][port].is_empty() {
                if port >= n_in {
                    let msg = format!(
                        "in-out `{}` of {} in `{}` is not connected: it needs a variable",
                        pname.value,
                        self.describe(e),
                        self.ctx.pou
                    );
                    self.diags
                        .push(Diagnostic::error(codes::LD_BLOCK_INPUT, msg, self.span(e)));
                    return None;
                }
                if standard && !pname.value.eq_ignore_ascii_case("EN") {
                    let d = self.default_input(e, &ty, &pname.value);
                    args.push(vec![text_part(&pname), part(format!(" := {d}"))]);
                }
                continue;
            }
            let v = self.input(e, port);
            let v = self.modified(v, negated, edge, e);
            if port >= n_in {
                let X::Term(_) = v else {
                    self.unsupported(e, "an in-out connected to anything but a variable");
                    return None;
                };
            }
            let mut a = vec![text_part(&pname), part(" := ")];
            render(&v, true, &mut a);
            args.push(a);
        }
        Some(args)
    }

    /// True if `name` is a POU of the project, or a method called as `inst.M` (no
    /// standard function has a `.` in its name).
    fn project_pou(&self, name: &str) -> bool {
        name.contains('.')
            || self
                .ctx
                .project
                .pous
                .iter()
                .any(|p| p.name.value.eq_ignore_ascii_case(name))
    }

    /// The value an unwired input of a standard function takes: its type's default.
    fn default_input(&self, e: usize, func: &str, pin: &str) -> &'static str {
        let f = func.to_ascii_uppercase();
        if f == "SEL" && pin.eq_ignore_ascii_case("G") {
            return "FALSE";
        }
        if (f == "MUX" && pin.eq_ignore_ascii_case("K"))
            || (matches!(f.as_str(), "SHL" | "SHR" | "ROL" | "ROR")
                && pin.eq_ignore_ascii_case("N"))
        {
            return "0";
        }
        let scope = Scope {
            project: self.ctx.project,
            pou_vars: self.ctx.pou_vars,
            globals: self.ctx.globals,
        };
        // The input's type: a conversion's source type; for a comparison or a
        // function whose inputs have one type, the type of the other inputs; else the
        // result's type.
        let k = &self.elem(e).kind;
        let from_inputs = || {
            self.g.ins[e].iter().enumerate().find_map(|(p, srcs)| {
                let other = input_name(k, p).unwrap_or("");
                if other.eq_ignore_ascii_case(pin) || control_input(&f, other) {
                    return None;
                }
                srcs.iter().find_map(|&s| source_type(self.g, &scope, s, 1))
            })
        };
        // The other inputs' untyped literals: the kind of value they are (an integer
        // literal makes the default `0`, which takes the literal's type).
        let from_literals = || {
            self.g.ins[e].iter().enumerate().find_map(|(p, srcs)| {
                let other = input_name(k, p).unwrap_or("");
                if other.eq_ignore_ascii_case(pin) || control_input(&f, other) {
                    return None;
                }
                srcs.iter().find_map(|&s| match &self.g.elems[s.elem].kind {
                    Kind::InVariable { expr, .. } => literal_kind(&expr.value),
                    _ => None,
                })
            })
        };
        let t = if let Some((src, _)) = f.split_once("_TO_") {
            Some(src.to_string())
        } else if matches!(f.as_str(), "GT" | "GE" | "EQ" | "NE" | "LE" | "LT") || passes_type(&f) {
            from_inputs().or_else(from_literals)
        } else {
            None
        };
        let t = t
            .or_else(|| {
                let port = (0..self.g.outs[e].len())
                    .find(|&p| !output_name(k, p).is_some_and(|n| n.eq_ignore_ascii_case("ENO")))
                    .unwrap_or(0);
                output_type(self.g, &scope, e, port, 0)
            })
            .unwrap_or_default()
            .to_ascii_uppercase();
        match t.as_str() {
            "BOOL" => "FALSE",
            "REAL" | "LREAL" => "0.0",
            "TIME" => "T#0s",
            "LTIME" => "LTIME#0s",
            "DATE" => "D#1970-01-01",
            "TOD" | "TIME_OF_DAY" => "TOD#00:00:00",
            "DT" | "DATE_AND_TIME" => "DT#1970-01-01-00:00:00",
            s if s.starts_with("STRING") => "''",
            s if s.starts_with("WSTRING") => "\"\"",
            _ => "0",
        }
    }

    /// A function call: `_TMP_<TYPE><id>_OUT := TYPE(args);`, other outputs by
    /// `name => variable`.
    fn function_call(&mut self, e: usize, ty: &Text, mut args: Vec<Vec<Part>>) {
        let Kind::Block { outputs, .. } = &self.elem(e).kind else {
            return;
        };
        let outs: Vec<String> = outputs
            .iter()
            .map(|p| p.name.as_ref().map(|n| n.value.clone()).unwrap_or_default())
            .collect();
        let scope = Scope {
            project: self.ctx.project,
            pou_vars: self.ctx.pou_vars,
            globals: self.ctx.globals,
        };
        // A method called as a block gives its result on the output its name, or
        // no output of the method, says (`wiretype::is_result_pin`).
        let method = scope.method_call(&ty.value);
        let primary = if let Some(m) = method {
            outs.iter().position(|n| is_result_pin(m, &ty.value, n))
        } else {
            outs.iter()
                .position(|n| n.eq_ignore_ascii_case("OUT"))
                .or_else(|| {
                    let rest: Vec<usize> = (0..outs.len())
                        .filter(|&i| !outs[i].eq_ignore_ascii_case("ENO"))
                        .collect();
                    (rest.len() == 1).then(|| rest[0])
                })
        };
        let standard = !self.project_pou(&ty.value);
        let used = |p: usize| !self.g.outs[e][p].is_empty();
        if standard && (0..outs.len()).all(|p| !used(p)) {
            // A standard function computes nothing but its results: none is used.
            return;
        }
        let k = &self.elem(e).kind;
        let mut named_form = !standard
            || self.g.ins[e].iter().enumerate().any(|(p, w)| {
                w.is_empty() && !input_name(k, p).is_some_and(|n| n.eq_ignore_ascii_case("EN"))
            });
        for (port, name) in outs.iter().enumerate() {
            if Some(port) == primary || name.eq_ignore_ascii_case("ENO") {
                continue;
            }
            if !self.g.outs[e][port].is_empty() {
                let v = self.result_var(e, port, &ty.value);
                args.push(vec![part(format!("{name} => {v}"))]);
                named_form = true;
            }
        }
        if self.eno.contains_key(&e) || self.en_wired(e) {
            named_form = true;
        }
        if named_form && ty.value.eq_ignore_ascii_case("NOT") {
            // `NOT(EN := .., IN := ..)` reads as the NOT operator: written out.
            self.not_with_en(e, ty, args, primary);
            return;
        }
        if !named_form {
            // `IN1 := a` becomes `a`: the positional form, in the XML's order.
            for a in &mut args {
                a.drain(..2);
            }
        }
        let mut s = Vec::new();
        if let Some(p) = primary {
            let v = self.result_var(e, p, &ty.value);
            s.push(part(format!("{v} := ")));
        }
        s.push(text_part(ty));
        s.push(part("("));
        join(&mut s, args);
        s.push(part(");"));
        self.push(s, e);
    }
}

impl Lower<'_, '_, '_, '_> {
    /// A NOT block in the named form (EN wired, or its input unwired), which ST
    /// cannot call by name: `IF en THEN r := NOT(in); eno := TRUE; ELSE r := <0>;
    /// eno := FALSE; END_IF;` (the EN and ENO parts only when EN is wired).
    fn not_with_en(&mut self, e: usize, ty: &Text, args: Vec<Vec<Part>>, primary: Option<usize>) {
        let (mut en, mut input, mut eno) = (None, None, None);
        for a in args {
            let head = a
                .first()
                .map(|p| p.s.to_ascii_uppercase())
                .unwrap_or_default();
            if head.starts_with("ENO =>") {
                eno = Some(head.trim_start_matches("ENO =>").trim().to_string());
            } else if head == "EN" {
                en = Some(a[2..].to_vec());
            } else if head.starts_with("IN") {
                // `IN := value` (wired) or `IN := FALSE` (a default, one part).
                input = Some(if a.len() > 2 {
                    a[2..].to_vec()
                } else {
                    vec![part(a[1].s.trim_start_matches(" := ").to_string())]
                });
            }
        }
        let input = input.unwrap_or_else(|| vec![part("FALSE")]);
        let target = primary.map(|p| self.result_var(e, p, &ty.value));
        let mut s = Vec::new();
        if let Some(en) = &en {
            s.push(part("IF "));
            s.extend(en.iter().cloned());
            s.push(part(" THEN "));
        }
        if let Some(t) = &target {
            s.push(part(format!("{t} := ")));
            s.push(text_part(ty));
            s.push(part("("));
            s.extend(input);
            s.push(part("); "));
        }
        if en.is_some() {
            if let Some(n) = &eno {
                s.push(part(format!("{n} := TRUE; ")));
            }
            s.push(part("ELSE "));
            if let Some(t) = &target {
                s.push(part(format!("{t} := {t} XOR {t}; ")));
            }
            if let Some(n) = &eno {
                s.push(part(format!("{n} := FALSE; ")));
            }
            s.push(part("END_IF;"));
        }
        self.push(s, e);
    }
}

fn join(s: &mut Vec<Part>, args: Vec<Vec<Part>>) {
    for (i, a) in args.into_iter().enumerate() {
        if i > 0 {
            s.push(part(", "));
        }
        s.extend(a);
    }
}

/// The kind of value an untyped literal is, as `default_input` names
/// types: `ANY_INT` for an integer (whose default `0` then takes the literal's
/// type), `REAL`, `BOOL`, `TIME`, `STRING`; `None` for anything else.
fn literal_kind(text: &str) -> Option<String> {
    let t = text.trim().to_ascii_uppercase();
    let kind = if t == "TRUE" || t == "FALSE" {
        "BOOL"
    } else if t.starts_with("T#") || t.starts_with("TIME#") {
        "TIME"
    } else if t.starts_with('\'') {
        "STRING"
    } else if t
        .trim_start_matches(['-', '+'])
        .starts_with(|c: char| c.is_ascii_digit())
    {
        if t.contains('#') {
            "ANY_INT"
        } else if t.contains(['.', 'E']) {
            "REAL"
        } else {
            "ANY_INT"
        }
    } else {
        return None;
    };
    Some(kind.to_string())
}
