//! A ladder body as a graph: connections resolved, rungs found, the order of
//! evaluation fixed, and the rung checks of the reference run.
//!
//! Networks (rungs) run by their smallest `executionOrderId` when the file numbers
//! its elements, then top to bottom.
//!
//! PLCopen XML has no rungs: a body is elements wired together by `localId`. A rung
//! is a set of elements connected to each other (the power rails, which every rung
//! touches, do not connect rungs). Rungs run top to bottom (by the topmost element's
//! position, or in document order when the file gives no positions).
//!
//! Within a rung, every element is evaluated once per scan, after the elements wired
//! to its inputs; among the elements ready at the same time the topmost, then the
//! leftmost, goes first. For a series-parallel rung this is the depth-first walk of
//! the seed (top to bottom, left to right, a parallel branch before what follows its
//! junction), and it also orders what the walk cannot: a block whose inputs come from
//! several branches runs after all of them.
//!
//! The checks (every error names the POU, the rung and the element's `localId`):
//! dangling connections, open circuits, short circuits (a bare wire in parallel with
//! contacts), upper parallel branches (a branch drawn above the line it joins), coils
//! straight on the left rail, blocks whose power input is not connected, feedback
//! loops, and bridges: a rung must be series-parallel between the left rail and its
//! outputs. The series-parallel reduction that decides the last one also gives the
//! rung's structure ([`Net`]), from which the ASCII ladder is drawn.

use super::xml::{Edge, Element, Kind};
use crate::codes;
use plcc_ir::diag::{Diagnostic, FileId, Span};
use rustc_hash::FxHashMap;

/// An output of an element: the element and the index of its output (a block's
/// outputs, then its in-outs; 0 for the others).
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
pub(crate) struct Src {
    /// Index of the element in the body.
    pub elem: usize,
    /// Index of the output.
    pub port: usize,
}

/// An input (or output) of an element: the element and the index of the port.
pub(crate) type Endpoint = (usize, usize);

/// For each element and input, the outputs connected to it.
pub(crate) type Inputs = Vec<Vec<Vec<Src>>>;

/// For each element and output, the inputs it is connected to.
pub(crate) type Outputs = Vec<Vec<Vec<Endpoint>>>;

/// The series-parallel structure of a rung.
#[derive(Clone, Debug)]
pub(crate) enum Net {
    /// One element.
    Elem(usize),
    /// A connection, labelled with the block output it leaves and the block input it
    /// enters when the block has several.
    Wire {
        /// The block output it leaves.
        from: Option<String>,
        /// The block input it enters.
        to: Option<String>,
    },
    /// Nets one after the other.
    Series(Vec<Net>),
    /// Nets side by side, top to bottom, between the same two points.
    Parallel(Vec<Net>),
}

/// A rung: its number (from 1), its elements in evaluation order, its structure.
#[derive(Debug)]
pub(crate) struct Rung {
    /// 1 for the first rung of the body.
    pub number: usize,
    /// The elements in the order they are evaluated.
    pub order: Vec<usize>,
    /// Its structure (when it is series-parallel).
    pub net: Option<Net>,
}

/// A checked body.
pub(crate) struct Graph<'m> {
    /// The elements, in document order.
    pub elems: &'m [Element],
    /// For each element and input: the outputs connected to it (they are ORed).
    pub ins: Inputs,
    /// For each element and output: the inputs it is connected to.
    pub outs: Outputs,
    /// The rungs in order.
    pub rungs: Vec<Rung>,
}

/// The number of inputs of an element.
pub(crate) fn input_count(k: &Kind) -> usize {
    match k {
        Kind::Block {
            inputs, in_outs, ..
        } => inputs.len() + in_outs.len(),
        Kind::LeftRail
        | Kind::InVariable { .. }
        | Kind::Label { .. }
        | Kind::Continuation { .. } => 0,
        _ => 1,
    }
}

/// The number of outputs of an element.
pub(crate) fn output_count(k: &Kind) -> usize {
    match k {
        Kind::Block {
            outputs, in_outs, ..
        } => outputs.len() + in_outs.len(),
        Kind::LeftRail
        | Kind::Contact { .. }
        | Kind::Coil { .. }
        | Kind::InVariable { .. }
        | Kind::InOutVariable { .. } => 1,
        _ => 0,
    }
}

/// The name of a block's input `port`.
pub(crate) fn input_name(k: &Kind, port: usize) -> Option<&str> {
    match k {
        Kind::Block {
            inputs, in_outs, ..
        } => inputs
            .iter()
            .chain(in_outs)
            .nth(port)
            .and_then(|p| p.name.as_ref())
            .map(|n| n.value.as_str()),
        _ => None,
    }
}

/// A block's output `port` (its outputs, then its in-outs).
pub(crate) fn output_port(k: &Kind, port: usize) -> Option<&super::xml::Port> {
    match k {
        Kind::Block {
            outputs, in_outs, ..
        } => outputs.iter().chain(in_outs).nth(port),
        _ => None,
    }
}

/// True if the ENO output of block `e` is wired to anything.
pub(crate) fn eno_read(g: &Graph, e: usize) -> bool {
    (0..g.outs[e].len()).any(|p| {
        output_name(&g.elems[e].kind, p).is_some_and(|n| n.eq_ignore_ascii_case("ENO"))
            && !g.outs[e][p].is_empty()
    })
}

/// The name of a block's output `port`.
pub(crate) fn output_name(k: &Kind, port: usize) -> Option<&str> {
    output_port(k, port)
        .and_then(|p| p.name.as_ref())
        .map(|n| n.value.as_str())
}

/// What the checks need to know about the POU.
pub(crate) struct Context<'a> {
    /// The file.
    pub file: FileId,
    /// The POU's name.
    pub pou: &'a str,
    /// The POU is a FUNCTION (no memory for edge contacts).
    pub function: bool,
    /// The ladder editor's style rules are errors (`--strict-rungs`).
    pub strict: bool,
    /// A ladder body (the style rules apply); else a function block diagram.
    pub ladder: bool,
}

/// Builds and checks the graph of a body. Errors go to `diags`; the graph is returned
/// only if there were none.
pub(crate) fn build<'m>(
    elems: &'m [Element],
    cx: &Context,
    diags: &mut Vec<Diagnostic>,
) -> Option<Graph<'m>> {
    let before = diags.iter().filter(|d| d.is_error()).count();
    let mut b = Builder {
        elems,
        cx,
        diags,
        index: FxHashMap::default(),
        rung_of: vec![usize::MAX; elems.len()],
        rung_numbers: Vec::new(),
        broken: vec![false; elems.len()],
    };
    b.index_ids();
    // Rungs first, so that the errors of resolution can name them.
    let rungs = b.rungs();
    let (ins, outs) = b.resolve();
    let mut g = Graph {
        elems,
        ins,
        outs,
        rungs: Vec::new(),
    };
    for (n, members) in rungs.into_iter().enumerate() {
        // A rung with a connection that could not be resolved is incomplete: its
        // other checks would only report consequences.
        if members.iter().any(|&e| b.broken[e]) {
            g.rungs.push(Rung {
                number: n + 1,
                order: members,
                net: None,
            });
            continue;
        }
        let rung = b.check_rung(&g, n + 1, members);
        g.rungs.push(rung);
    }
    let after = b.diags.iter().filter(|d| d.is_error()).count();
    (after == before).then_some(g)
}

struct Builder<'m, 'c, 'd> {
    elems: &'m [Element],
    cx: &'c Context<'c>,
    diags: &'d mut Vec<Diagnostic>,
    /// `localId` to element index.
    index: FxHashMap<u64, usize>,
    /// The rung of each element (index into the rung list), `usize::MAX` for rails.
    rung_of: Vec<usize>,
    /// The rung numbers known so far (for messages before the rungs are checked).
    rung_numbers: Vec<usize>,
    /// Elements with a connection that could not be resolved.
    broken: Vec<bool>,
}

impl Builder<'_, '_, '_> {
    fn span(&self, e: usize) -> Span {
        let r = &self.elems[e].tag;
        Span::new(self.cx.file, r.start, r.end)
    }

    /// `contact `start` (localId 7)`.
    fn name(&self, e: usize) -> String {
        let el = &self.elems[e];
        format!("{} (localId {})", el.kind.describe(), el.id)
    }

    /// `rung 3 of `main``, or `main` alone for an element in no rung.
    fn place(&self, e: usize) -> String {
        match self.rung_numbers.get(self.rung_of[e]) {
            Some(n) => format!("rung {n} of `{}`", self.cx.pou),
            None => format!("`{}`", self.cx.pou),
        }
    }

    fn index_ids(&mut self) {
        for (i, e) in self.elems.iter().enumerate() {
            if let Some(&first) = self.index.get(&e.id) {
                let d = Diagnostic::error(
                    codes::LD_BAD_ELEMENT,
                    format!(
                        "two elements of `{}` have localId {}: {} and {}",
                        self.cx.pou,
                        e.id,
                        self.elems[first].kind.describe(),
                        e.kind.describe()
                    ),
                    self.span(i),
                )
                .with_secondary(self.span(first), "the first one")
                .with_note("connections name elements by localId, which must be unique in a body");
                self.diags.push(d);
                continue;
            }
            self.index.insert(e.id, i);
            if self.cx.function {
                if let Kind::Contact { edge, .. } | Kind::Coil { edge, .. } = &e.kind {
                    if *edge != Edge::None {
                        let d = Diagnostic::error(
                            codes::LD_BAD_ELEMENT,
                            format!(
                                "{} in FUNCTION `{}` detects an edge, which needs memory from \
                                 one call to the next: a FUNCTION has none",
                                self.name(i),
                                self.cx.pou
                            ),
                            self.span(i),
                        )
                        .with_note("detect the edge in the PROGRAM or FUNCTION_BLOCK that calls the function");
                        self.diags.push(d);
                    }
                }
            }
        }
    }

    /// Resolves every connection: the inputs of each element, and the reverse.
    fn resolve(&mut self) -> (Inputs, Outputs) {
        let mut ins: Inputs = self
            .elems
            .iter()
            .map(|e| vec![Vec::new(); input_count(&e.kind)])
            .collect();
        let mut outs: Outputs = self
            .elems
            .iter()
            .map(|e| vec![Vec::new(); output_count(&e.kind)])
            .collect();
        let elems = self.elems;
        for (e, ports) in ins.iter_mut().enumerate() {
            if matches!(elems[e].kind, Kind::Connector { .. }) {
                continue;
            }
            for (port, slot) in ports.iter_mut().enumerate() {
                let conns = match &elems[e].kind {
                    Kind::Block {
                        inputs, in_outs, ..
                    } => &inputs.iter().chain(in_outs).nth(port).expect("port").conns,
                    _ => &elems[e].input.conns,
                };
                let mut srcs = Vec::new();
                for c in conns {
                    self.source(e, c, &mut srcs, 0);
                }
                // A connection written twice is one connection.
                let mut seen = rustc_hash::FxHashSet::default();
                srcs.retain(|s| seen.insert(*s));
                for s in &srcs {
                    outs[s.elem][s.port].push((e, port));
                }
                *slot = srcs;
            }
        }
        (ins, outs)
    }

    /// The outputs a connection of element `e` stands for (a continuation stands for
    /// what is connected to its connector).
    fn source(&mut self, e: usize, c: &super::xml::Conn, out: &mut Vec<Src>, depth: u32) {
        let span = Span::new(self.cx.file, c.range.start, c.range.end);
        let Some(&t) = self.index.get(&c.from) else {
            let d = Diagnostic::error(
                codes::LD_DANGLING,
                format!(
                    "dangling connection in {}: {} is connected to localId {}, which no element has",
                    self.place(e),
                    self.name(e),
                    c.from
                ),
                span,
            )
            .with_label("no element has this localId");
            self.diags.push(d);
            self.broken[e] = true;
            return;
        };
        let kind = &self.elems[t].kind;
        match kind {
            Kind::Block { .. } => {
                let count = output_count(kind);
                let port = match &c.param {
                    Some(p) => (0..count).find(|&i| {
                        output_name(kind, i).is_some_and(|n| n.eq_ignore_ascii_case(&p.value))
                    }),
                    None if count == 1 => Some(0),
                    None => None,
                };
                match port {
                    Some(port) => out.push(Src { elem: t, port }),
                    None => {
                        let what = match &c.param {
                            Some(p) => format!("its output `{}`, which it does not have", p.value),
                            None => "none of its outputs (`formalParameter` is missing)".into(),
                        };
                        let d = Diagnostic::error(
                            codes::LD_DANGLING,
                            format!(
                                "dangling connection in {}: {} is connected to {}, at {what}",
                                self.place(e),
                                self.name(e),
                                self.name(t)
                            ),
                            span,
                        )
                        .with_label("no such output");
                        self.diags.push(d);
                        self.broken[e] = true;
                    }
                }
            }
            Kind::Continuation { name } => {
                let name = name.value.clone();
                let conn = self.elems.iter().position(|x| {
                    matches!(&x.kind, Kind::Connector { name: n } if n.value.eq_ignore_ascii_case(&name))
                });
                match conn {
                    Some(k) if depth < 64 => {
                        for c2 in &self.elems[k].input.conns {
                            self.source(k, c2, out, depth + 1);
                        }
                    }
                    Some(_) => {}
                    None => {
                        let d = Diagnostic::error(
                            codes::LD_DANGLING,
                            format!(
                                "dangling connection in {}: {} has no connector named `{name}`",
                                self.place(e),
                                self.name(t)
                            ),
                            self.span(t),
                        );
                        self.diags.push(d);
                        self.broken[e] = true;
                    }
                }
            }
            k if output_count(k) == 1 => out.push(Src { elem: t, port: 0 }),
            _ => {
                let d = Diagnostic::error(
                    codes::LD_DANGLING,
                    format!(
                        "dangling connection in {}: {} is connected to {}, which has no output",
                        self.place(e),
                        self.name(e),
                        self.name(t)
                    ),
                    span,
                )
                .with_label("nothing comes out of that element");
                self.diags.push(d);
                self.broken[e] = true;
            }
        }
    }

    /// The order key of an element: its position, or its place in the document.
    fn key(&self, e: usize, positions: bool) -> (f64, f64, usize) {
        match (positions, self.elems[e].pos) {
            (true, Some((x, y))) => (y, x, e),
            _ => (0.0, 0.0, e),
        }
    }

    /// Groups the elements into rungs, in order; records each element's rung.
    fn rungs(&mut self) -> Vec<Vec<usize>> {
        let n = self.elems.len();
        let rail = |k: &Kind| matches!(k, Kind::LeftRail | Kind::RightRail);
        let mut parent: Vec<usize> = (0..n).collect();
        fn find(p: &mut [usize], mut x: usize) -> usize {
            while p[x] != x {
                p[x] = p[p[x]];
                x = p[x];
            }
            x
        }
        let join = |p: &mut Vec<usize>, a: usize, b: usize| {
            let (a, b) = (find(p, a), find(p, b));
            p[a] = b;
        };
        for e in 0..n {
            let k = &self.elems[e].kind;
            if rail(k) {
                continue;
            }
            let conns: Vec<u64> = match k {
                Kind::Block {
                    inputs, in_outs, ..
                } => inputs
                    .iter()
                    .chain(in_outs)
                    .flat_map(|p| p.conns.iter().map(|c| c.from))
                    .collect(),
                _ => self.elems[e].input.conns.iter().map(|c| c.from).collect(),
            };
            for from in conns {
                if let Some(&s) = self.index.get(&from) {
                    if !rail(&self.elems[s].kind) {
                        join(&mut parent, e, s);
                    }
                }
            }
            // A continuation is the other end of its connector.
            if let Kind::Continuation { name } = k {
                let conn = self.elems.iter().position(|x| {
                    matches!(&x.kind, Kind::Connector { name: m } if m.value.eq_ignore_ascii_case(&name.value))
                });
                if let Some(c) = conn {
                    join(&mut parent, e, c);
                }
            }
        }
        let mut groups: FxHashMap<usize, Vec<usize>> = FxHashMap::default();
        for e in 0..n {
            if !rail(&self.elems[e].kind) {
                let r = find(&mut parent, e);
                groups.entry(r).or_default().push(e);
            }
        }
        let positions = self
            .elems
            .iter()
            .filter(|e| !rail(&e.kind))
            .all(|e| e.pos.is_some());
        let mut list: Vec<Vec<usize>> = groups.into_values().collect();
        // The smallest `executionOrderId` first (ids number the blocks of a whole
        // body), then the topmost element.
        let key = |b: &Self, g: &[usize]| {
            let id = g
                .iter()
                .filter_map(|&e| b.elems[e].order)
                .min()
                .unwrap_or(u32::MAX);
            let (y, x, doc) = g
                .iter()
                .map(|&e| b.key(e, positions))
                .min_by(|a, c| a.partial_cmp(c).unwrap_or(std::cmp::Ordering::Equal))
                .unwrap_or((0.0, 0.0, 0));
            (id, y, x, doc)
        };
        list.sort_by(|a, c| {
            key(self, a)
                .partial_cmp(&key(self, c))
                .unwrap_or(std::cmp::Ordering::Equal)
        });
        for (i, g) in list.iter().enumerate() {
            for &e in g {
                self.rung_of[e] = i;
            }
        }
        self.rung_numbers = (1..=list.len()).collect();
        list
    }

    fn error(&mut self, code: &'static str, e: usize, msg: String) -> &mut Diagnostic {
        let d = Diagnostic::error(code, msg, self.span(e));
        self.diags.push(d);
        self.diags.last_mut().expect("just pushed")
    }

    /// A style rule of the ladder editor broken: a warning, or an error under
    /// `--strict-rungs`.
    fn rule(&mut self, code: &'static str, e: usize, msg: String) -> &mut Diagnostic {
        let span = self.span(e);
        self.rule_at(code, span, msg)
    }

    fn rule_at(&mut self, code: &'static str, span: Span, msg: String) -> &mut Diagnostic {
        let d = self.severity(code, msg, span);
        self.diags.push(d);
        self.diags.last_mut().expect("just pushed")
    }

    /// A diagnostic for a style rule: a warning, or an error under `--strict-rungs`.
    fn severity(&self, code: &'static str, msg: String, span: Span) -> Diagnostic {
        if self.cx.strict {
            Diagnostic::error(code, msg, span)
        } else {
            Diagnostic::warning(code, msg, span)
        }
    }

    fn _unused_rule_at(&mut self, code: &'static str, span: Span, msg: String) -> &mut Diagnostic {
        let d = Diagnostic::warning(code, msg, span);
        self.diags.push(d);
        self.diags.last_mut().expect("just pushed")
    }

    /// Orders and checks one rung.
    fn check_rung(&mut self, g: &Graph, number: usize, members: Vec<usize>) -> Rung {
        let errors_before = self.diags.len();
        let positions = members.iter().all(|&e| self.elems[e].pos.is_some());
        // Evaluation order: by data flow, loops cut at blocks; a loop through
        // contacts and coils alone has no meaning.
        let order = match super::order::network(g, &members) {
            Ok(o) => o,
            Err(stuck) => {
                let msg = format!(
                    "feedback loop in rung {number} of `{}`: the output of {} comes back to its \
                     own input through contacts and coils only",
                    self.cx.pou,
                    self.name(stuck)
                );
                self.error(codes::LD_LOOP, stuck, msg).notes.push(
                    "power flows from left to right only: a loop needs a block to cut it (the \
                     block reads the previous scan's value); or write the value with a coil and \
                     read it with a contact"
                        .into(),
                );
                return Rung {
                    number,
                    order: members,
                    net: None,
                };
            }
        };
        let _ = positions;
        if !self.cx.ladder {
            return Rung {
                number,
                order,
                net: None,
            };
        }
        self.open_circuits(g, number, &order);
        self.left_rail_coils(g, number, &order);
        self.short_circuits(g, number, &order);
        self.upper_parallels(g, number, &order);
        self.block_inputs(g, number, &order);
        let net = if self.diags.len() == errors_before || !self.cx.strict {
            self.series_parallel(g, number, &order)
        } else {
            None
        };
        Rung { number, order, net }
    }

    fn open_circuits(&mut self, g: &Graph, number: usize, order: &[usize]) {
        for &e in order {
            let k = &self.elems[e].kind;
            let needs_input = matches!(
                k,
                Kind::Contact { .. }
                    | Kind::Coil { .. }
                    | Kind::Jump { .. }
                    | Kind::Return
                    | Kind::OutVariable { .. }
            );
            if needs_input && g.ins[e][0].is_empty() {
                let msg = format!(
                    "open circuit in rung {number} of `{}`: nothing is connected to the left of {}",
                    self.cx.pou,
                    self.name(e)
                );
                let what = if matches!(k, Kind::Contact { .. } | Kind::Coil { .. }) {
                    "plcc takes it as connected to the left rail, as the editors do"
                } else {
                    "it does nothing"
                };
                self.rule(codes::LD_OPEN_CIRCUIT, e, msg)
                    .notes
                    .push(format!(
                        "{what}; connect it to the left rail or to the element before it"
                    ));
                continue;
            }
            if let Kind::Contact { .. } = k {
                let goes_on = g.outs[e][0]
                    .iter()
                    .any(|&(c, _)| !matches!(self.elems[c].kind, Kind::RightRail));
                if !goes_on {
                    let msg = format!(
                        "open circuit in rung {number} of `{}`: the power through {} reaches no coil",
                        self.cx.pou,
                        self.name(e)
                    );
                    self.rule(codes::LD_OPEN_CIRCUIT, e, msg).notes.push(
                        "the contact does nothing: connect its right side to a coil, a block or \
                         another contact"
                            .into(),
                    );
                }
            }
        }
    }

    fn left_rail_coils(&mut self, g: &Graph, number: usize, order: &[usize]) {
        for &e in order {
            if let Kind::Coil { .. } = self.elems[e].kind {
                let srcs = &g.ins[e][0];
                if srcs.len() == 1 && matches!(self.elems[srcs[0].elem].kind, Kind::LeftRail) {
                    let msg = format!(
                        "{} is connected straight to the left rail in rung {number} of `{}`",
                        self.name(e),
                        self.cx.pou
                    );
                    self.rule(codes::LD_COIL_ON_RAIL, e, msg).notes.push(
                        "the coil writes TRUE on every scan, as the editors run it; the ladder \
                         editor's style wants at least one contact before a coil"
                            .into(),
                    );
                }
            }
        }
    }

    /// True if `a` is wired, directly or through other elements, to an input of `b`.
    fn reaches(g: &Graph, a: usize, b: usize) -> bool {
        let mut stack = vec![b];
        let mut seen = vec![false; g.elems.len()];
        while let Some(x) = stack.pop() {
            for s in g.ins[x].iter().flatten() {
                if s.elem == a {
                    return true;
                }
                if !seen[s.elem] {
                    seen[s.elem] = true;
                    stack.push(s.elem);
                }
            }
        }
        false
    }

    fn short_circuits(&mut self, g: &Graph, number: usize, order: &[usize]) {
        for &e in order {
            'port: for port in 0..g.ins[e].len() {
                let srcs = &g.ins[e][port];
                for a in srcs {
                    for b in srcs {
                        if a.elem != b.elem && Self::reaches(g, a.elem, b.elem) {
                            let conn = self.connection_span(e, port, a.elem);
                            let msg = format!(
                                "short circuit in rung {number} of `{}`: a bare wire from {} to {} bypasses {}",
                                self.cx.pou,
                                self.name(a.elem),
                                self.name(e),
                                self.name(b.elem)
                            );
                            let d = self
                                .severity(codes::LD_SHORT_CIRCUIT, msg, conn)
                                .with_label("this connection is in parallel with the branch")
                                .with_secondary(self.span(b.elem), "this branch is always bypassed")
                                .with_note(
                                    "the parallel branch can never change the result; remove the \
                                     bare wire or put a contact on it",
                                );
                            self.diags.push(d);
                            continue 'port;
                        }
                    }
                }
            }
        }
    }

    /// The `<connection>` of input `port` of `e` that comes from element `from`.
    fn connection_span(&self, e: usize, port: usize, from: usize) -> Span {
        let conns = match &self.elems[e].kind {
            Kind::Block {
                inputs, in_outs, ..
            } => &inputs.iter().chain(in_outs).nth(port).expect("port").conns,
            _ => &self.elems[e].input.conns,
        };
        let id = self.elems[from].id;
        conns
            .iter()
            .find(|c| c.from == id)
            .map_or(self.span(e), |c| {
                Span::new(self.cx.file, c.range.start, c.range.end)
            })
    }

    /// The y of input `port` of `e`.
    fn in_y(&self, e: usize, port: usize) -> Option<f64> {
        match &self.elems[e].kind {
            Kind::Block {
                inputs, in_outs, ..
            } => inputs.iter().chain(in_outs).nth(port).and_then(|p| p.y),
            _ => self.elems[e].input.y,
        }
    }

    /// The y of output `port` of `e`.
    fn out_y(&self, e: usize, port: usize) -> Option<f64> {
        match &self.elems[e].kind {
            Kind::Block {
                outputs, in_outs, ..
            } => outputs.iter().chain(in_outs).nth(port).and_then(|p| p.y),
            _ => self.elems[e].out_y,
        }
    }

    /// Parallel branches drawn above their line. A junction (the vertical line where
    /// outputs are joined and passed on) is the set of outputs wired to the same
    /// inputs; its topmost wires are the main line, which must both enter and leave
    /// it: an output above every input it feeds is a branch joining from above, an
    /// input above every output feeding it a branch leaving upwards.
    fn upper_parallels(&mut self, g: &Graph, number: usize, order: &[usize]) {
        const SLACK: f64 = 0.5;
        // Positions that are all the same (a file written by a tool, not drawn) say
        // nothing about the drawing.
        let first = order.first().and_then(|&e| self.elems[e].pos);
        if order.iter().all(|&e| self.elems[e].pos == first) {
            return;
        }
        let rail = |e: usize| matches!(self.elems[e].kind, Kind::LeftRail | Kind::RightRail);
        let mut junctions: Vec<(Vec<Src>, Vec<Endpoint>)> = Vec::new();
        let mut index: FxHashMap<Vec<Src>, usize> = FxHashMap::default();
        for &e in order {
            for (port, srcs) in g.ins[e].iter().enumerate() {
                if srcs.is_empty() || srcs.iter().any(|s| rail(s.elem)) {
                    continue;
                }
                let mut key = srcs.clone();
                key.sort_by_key(|s| (s.elem, s.port));
                match index.get(&key) {
                    Some(&i) => junctions[i].1.push((e, port)),
                    None => {
                        index.insert(key.clone(), junctions.len());
                        junctions.push((key, vec![(e, port)]));
                    }
                }
            }
        }
        for (srcs, cons) in junctions {
            if srcs.len() < 2 && cons.len() < 2 {
                continue;
            }
            let top_out = srcs
                .iter()
                .filter_map(|s| self.out_y(s.elem, s.port).map(|y| (y, s.elem)))
                .min_by(|a, b| a.0.partial_cmp(&b.0).unwrap_or(std::cmp::Ordering::Equal));
            let top_in = cons
                .iter()
                .filter_map(|&(c, p)| self.in_y(c, p).map(|y| (y, c)))
                .min_by(|a, b| a.0.partial_cmp(&b.0).unwrap_or(std::cmp::Ordering::Equal));
            let (Some((yo, so)), Some((yi, ci))) = (top_out, top_in) else {
                continue;
            };
            // An output that also goes on along its own line is a fork there, and this
            // junction a branch down from it (a bridge, if anything: checked later).
            let goes_on = |b: &Self, s: Src| {
                let y = b.out_y(s.elem, s.port);
                g.outs[s.elem][s.port].iter().any(|&(c, p)| {
                    matches!((y, b.in_y(c, p)), (Some(a), Some(b)) if (a - b).abs() <= SLACK)
                })
            };
            let top_src = srcs.iter().copied().find(|s| s.elem == so);
            let (upper, other, verb) =
                if yo < yi - SLACK && !top_src.is_some_and(|s| goes_on(self, s)) {
                    (so, ci, "joins")
                } else if yi < yo - SLACK {
                    (ci, so, "leaves")
                } else {
                    continue;
                };
            let msg = format!(
                "upper parallel branch in rung {number} of `{}`: {} is above the line it {verb} at {}",
                self.cx.pou,
                self.name(upper),
                self.name(other)
            );
            let d = self
                .severity(codes::LD_UPPER_PARALLEL, msg, self.span(upper))
                .with_secondary(self.span(other), "the main line")
                .with_note(
                    "draw parallel branches below the main line, as the rung is read top to bottom",
                );
            self.diags.push(d);
        }
    }

    fn block_inputs(&mut self, g: &Graph, number: usize, order: &[usize]) {
        for &e in order {
            let Kind::Block {
                ty,
                instance,
                inputs,
                ..
            } = &self.elems[e].kind
            else {
                continue;
            };
            // A function needs every input; a function block its power input: EN if
            // it has one, else its first input (a timer's IN, a counter's CU).
            let required: Vec<usize> = if instance.is_none() {
                (0..inputs.len()).collect()
            } else {
                let en = inputs.iter().position(|p| {
                    p.name
                        .as_ref()
                        .is_some_and(|n| n.value.eq_ignore_ascii_case("EN"))
                });
                vec![en.unwrap_or(0)]
                    .into_iter()
                    .filter(|&i| i < inputs.len())
                    .collect()
            };
            for port in required {
                if !g.ins[e][port].is_empty() {
                    continue;
                }
                let pname = input_name(&self.elems[e].kind, port)
                    .unwrap_or("?")
                    .to_string();
                let what = if instance.is_some() {
                    "function block"
                } else {
                    "function"
                };
                let msg = format!(
                    "{} in rung {number} of `{}` has nothing connected to its input `{pname}`",
                    self.name(e),
                    self.cx.pou
                );
                let note = if instance.is_some() {
                    format!(
                        "the {what} {} takes its power on `{pname}`: connect a contact (or the left rail) to it",
                        ty.value
                    )
                } else {
                    format!(
                        "the {what} {} needs a value on every input: connect a variable, a contact or a block output to `{pname}`",
                        ty.value
                    )
                };
                self.rule(codes::LD_BLOCK_INPUT, e, msg).notes.push(note);
            }
        }
    }

    /// The series-parallel structure of the rung, or a bridge error.
    fn series_parallel(&mut self, g: &Graph, number: usize, order: &[usize]) -> Option<Net> {
        let pos_of: FxHashMap<usize, usize> =
            order.iter().enumerate().map(|(i, &e)| (e, i)).collect();
        let data_edge = |s: usize, c: usize| {
            let (sk, ck) = (&self.elems[s].kind, &self.elems[c].kind);
            (matches!(sk, Kind::InVariable { .. } | Kind::InOutVariable { .. })
                && matches!(ck, Kind::Block { .. }))
                || (matches!(sk, Kind::Block { .. })
                    && matches!(ck, Kind::OutVariable { .. } | Kind::InOutVariable { .. }))
        };
        // Vertices: 0 = S (the left rail), 1 = T (the right rail and every end),
        // 2 + 2k and 3 + 2k the input and output of the k-th element in the order.
        const S: usize = 0;
        const T: usize = 1;
        let vin = |e: usize| 2 + 2 * pos_of[&e];
        let vout = |e: usize| 3 + 2 * pos_of[&e];
        let mut raw: Vec<(usize, usize, usize, usize)> = Vec::new(); // (from elem, from port, to elem, to port)
        for &c in order {
            for (port, srcs) in g.ins[c].iter().enumerate() {
                for s in srcs {
                    if !data_edge(s.elem, c) {
                        raw.push((s.elem, s.port, c, port));
                    }
                }
            }
        }
        for &s in order {
            for (port, cons) in g.outs[s].iter().enumerate() {
                for &(c, cport) in cons {
                    if matches!(self.elems[c].kind, Kind::RightRail) {
                        raw.push((s, port, c, cport));
                    }
                }
            }
        }
        let is_rail = |e: usize| matches!(self.elems[e].kind, Kind::LeftRail | Kind::RightRail);
        let mut included = vec![false; self.elems.len()];
        for &(s, _, c, _) in &raw {
            if !is_rail(s) {
                included[s] = true;
            }
            if !is_rail(c) {
                included[c] = true;
            }
        }
        // Block ports are named on the wires when a block has several of them wired.
        let mut in_ports: FxHashMap<usize, Vec<usize>> = FxHashMap::default();
        let mut out_ports: FxHashMap<usize, Vec<usize>> = FxHashMap::default();
        for &(s, sp, c, cp) in &raw {
            in_ports.entry(c).or_default().push(cp);
            out_ports.entry(s).or_default().push(sp);
        }
        let several = |m: &FxHashMap<usize, Vec<usize>>, e: usize| {
            m.get(&e).is_some_and(|v| v.iter().any(|&p| p != v[0]))
        };
        let mut edges: Vec<(usize, usize, Net)> = Vec::new();
        let mut has_in = vec![false; self.elems.len()];
        let mut has_out = vec![false; self.elems.len()];
        // An input fed by several outputs is fed by a junction (the vertical line of
        // the drawing), shared by every input fed by the same outputs.
        let mut feeds: Vec<(Endpoint, Vec<Endpoint>)> = Vec::new();
        let mut feed_of: FxHashMap<(usize, usize), usize> = FxHashMap::default();
        for &(s, sp, c, cp) in &raw {
            match feed_of.get(&(c, cp)) {
                Some(&i) => feeds[i].1.push((s, sp)),
                None => {
                    feed_of.insert((c, cp), feeds.len());
                    feeds.push(((c, cp), vec![(s, sp)]));
                }
            }
        }
        let mut junctions: Vec<Vec<(usize, usize)>> = Vec::new();
        let mut junction_of: FxHashMap<Vec<(usize, usize)>, usize> = FxHashMap::default();
        let first_junction = 2 + 2 * order.len();
        let wire = |b: &Self, s: usize, sp: usize, c: Option<(usize, usize)>| {
            let from = (!is_rail(s) && several(&out_ports, s))
                .then(|| output_name(&b.elems[s].kind, sp).unwrap_or("").to_string());
            let to = c
                .filter(|&(c, _)| !is_rail(c) && several(&in_ports, c))
                .map(|(c, cp)| input_name(&b.elems[c].kind, cp).unwrap_or("").to_string());
            Net::Wire { from, to }
        };
        for ((c, cp), mut srcs) in feeds {
            srcs.sort();
            let to_v = if is_rail(c) { T } else { vin(c) };
            has_in[c] = true;
            for &(s, _) in &srcs {
                has_out[s] = true;
            }
            if let [(s, sp)] = srcs.as_slice() {
                let from_v = if is_rail(*s) { S } else { vout(*s) };
                edges.push((from_v, to_v, wire(self, *s, *sp, Some((c, cp)))));
                continue;
            }
            let j = match junction_of.get(&srcs) {
                Some(&j) => first_junction + j,
                None => {
                    junction_of.insert(srcs.clone(), junctions.len());
                    junctions.push(srcs.clone());
                    let j = first_junction + junctions.len() - 1;
                    for &(s, sp) in &srcs {
                        let from_v = if is_rail(s) { S } else { vout(s) };
                        edges.push((from_v, j, wire(self, s, sp, None)));
                    }
                    j
                }
            };
            // From the junction: only the input is named.
            let to = (!is_rail(c) && several(&in_ports, c)).then(|| {
                input_name(&self.elems[c].kind, cp)
                    .unwrap_or("")
                    .to_string()
            });
            edges.push((j, to_v, Net::Wire { from: None, to }));
        }
        for &e in order {
            if !included[e] {
                continue;
            }
            edges.push((vin(e), vout(e), Net::Elem(e)));
            if !has_in[e] {
                edges.push((
                    S,
                    vin(e),
                    Net::Wire {
                        from: None,
                        to: None,
                    },
                ));
            }
            if !has_out[e] {
                edges.push((
                    vout(e),
                    T,
                    Net::Wire {
                        from: None,
                        to: None,
                    },
                ));
            }
        }
        let positions = order.iter().all(|&e| self.elems[e].pos.is_some());
        type Key = (f64, f64, usize);
        const NO_KEY: Key = (f64::INFINITY, f64::INFINITY, usize::MAX);
        let min_key = |a: Key, b: Key| if b < a { b } else { a };
        let before = |a: &Key, b: &Key| a.partial_cmp(b).unwrap_or(std::cmp::Ordering::Equal);
        // The reduction: a vertex with one edge in and one out is a series connection;
        // two edges between the same vertices a parallel one. Branches of a parallel
        // connection are kept top to bottom (by the position of their first element).
        struct Ed {
            u: usize,
            v: usize,
            net: Net,
            key: Key,
        }
        let nv = first_junction + junctions.len();
        let mut vin_edges: Vec<Vec<usize>> = vec![Vec::new(); nv];
        let mut vout_edges: Vec<Vec<usize>> = vec![Vec::new(); nv];
        let mut eds: Vec<Option<Ed>> = Vec::new();
        // The top-left element of a net: where its branch is drawn.
        let net_key = |n: &Net| -> Key {
            let mut best = NO_KEY;
            let mut stack = vec![n];
            while let Some(x) = stack.pop() {
                match x {
                    Net::Elem(e) => best = min_key(best, self.key(*e, positions)),
                    Net::Series(v) | Net::Parallel(v) => stack.extend(v.iter()),
                    Net::Wire { .. } => {}
                }
            }
            best
        };
        let merge_parallel = |a: Net, b: Net| -> Net {
            let mut branches: Vec<Net> = Vec::new();
            for n in [a, b] {
                match n {
                    Net::Parallel(v) => branches.extend(v),
                    other => branches.push(other),
                }
            }
            let mut keyed: Vec<(Key, Net)> =
                branches.into_iter().map(|n| (net_key(&n), n)).collect();
            keyed.sort_by(|x, y| before(&x.0, &y.0));
            Net::Parallel(keyed.into_iter().map(|(_, n)| n).collect())
        };
        let add = |eds: &mut Vec<Option<Ed>>,
                   vin_edges: &mut Vec<Vec<usize>>,
                   vout_edges: &mut Vec<Vec<usize>>,
                   u: usize,
                   v: usize,
                   net: Net,
                   key: Key| {
            // A parallel edge already there takes this one in.
            if let Some(&p) = vout_edges[u]
                .iter()
                .find(|&&k| eds[k].as_ref().is_some_and(|e| e.v == v))
            {
                let old = eds[p].take().expect("alive");
                let k = min_key(old.key, key);
                let net = merge_parallel(old.net, net);
                eds[p] = Some(Ed { u, v, net, key: k });
                return;
            }
            let id = eds.len();
            eds.push(Some(Ed { u, v, net, key }));
            vout_edges[u].push(id);
            vin_edges[v].push(id);
        };
        for (u, v, net) in edges {
            let key = match &net {
                Net::Elem(e) => self.key(*e, positions),
                _ => NO_KEY,
            };
            add(&mut eds, &mut vin_edges, &mut vout_edges, u, v, net, key);
        }
        let mut work: Vec<usize> = (0..nv).rev().collect();
        while let Some(x) = work.pop() {
            if x == S || x == T || vin_edges[x].len() != 1 || vout_edges[x].len() != 1 {
                continue;
            }
            let (a, b) = (vin_edges[x][0], vout_edges[x][0]);
            if a == b {
                continue;
            }
            let first = eds[a].take().expect("alive");
            let second = eds[b].take().expect("alive");
            vin_edges[x].clear();
            vout_edges[x].clear();
            vout_edges[first.u].retain(|&k| k != a);
            vin_edges[second.v].retain(|&k| k != b);
            let mut items = match first.net {
                Net::Series(v) => v,
                Net::Wire {
                    from: None,
                    to: None,
                } => Vec::new(),
                other => vec![other],
            };
            match second.net {
                Net::Series(v) => items.extend(v),
                Net::Wire {
                    from: None,
                    to: None,
                } => {}
                other => items.push(other),
            }
            let net = match items.len() {
                0 => Net::Wire {
                    from: None,
                    to: None,
                },
                1 => items.pop().expect("one"),
                _ => Net::Series(items),
            };
            let key = min_key(first.key, second.key);
            add(
                &mut eds,
                &mut vin_edges,
                &mut vout_edges,
                first.u,
                second.v,
                net,
                key,
            );
            work.push(first.u);
            work.push(second.v);
        }
        let left: Vec<(usize, usize, &Net)> =
            eds.iter().flatten().map(|e| (e.u, e.v, &e.net)).collect();
        if let [(S, T, net)] = left.as_slice() {
            return Some((*net).clone());
        }
        if left.is_empty() {
            return Some(Net::Series(Vec::new()));
        }
        // Name the element where branches cross: the last one (in evaluation order)
        // whose output still feeds several places, else the first that still joins
        // several.
        let mut outd: FxHashMap<usize, usize> = FxHashMap::default();
        let mut ind: FxHashMap<usize, usize> = FxHashMap::default();
        for (u, v, _) in &left {
            *outd.entry(*u).or_default() += 1;
            *ind.entry(*v).or_default() += 1;
        }
        let culprit = order
            .iter()
            .rev()
            .copied()
            .find(|&e| {
                included[e] && outd.get(&vout(e)).copied().unwrap_or(0) >= 2 && pos_of[&e] > 0
            })
            .or_else(|| {
                order
                    .iter()
                    .copied()
                    .find(|&e| included[e] && ind.get(&vin(e)).copied().unwrap_or(0) >= 2)
            })
            .or_else(|| order.first().copied());
        if let Some(e) = culprit {
            let msg = format!(
                "bridge in rung {number} of `{}`: the connections at {} cross between parallel branches, so the rung is not series-parallel",
                self.cx.pou,
                self.name(e)
            );
            self.rule(codes::LD_BRIDGE, e, msg).notes.push(
                "power flows in the direction of the wires, so each coil gets the OR of every \
                 path from the left rail to it (as the editors compute it); the ladder editor's \
                 style wants series-parallel rungs: split the rung, or repeat the contacts on each \
                 branch"
                    .into(),
            );
        }
        None
    }
}
