//! Sequential function charts written as textual SFC, as the editors' translator
//! (PLCGenerator) writes them (the reference's §5).
//!
//! Two passes, as in the translator:
//!
//! 1. **Registration** ([`plan`]): the chart's elements in document order. A step
//!    registers the transitions before it (directly, through a selection convergence,
//!    or through a simultaneous divergence, possibly after a selection convergence) and
//!    becomes their target; a jump does the same for its target step; an action block
//!    registers its step and the step's associations (a POU action is registered, and
//!    lowered, on its first use; an inline action becomes `<STEP>_INLINE<k>`); a
//!    transition registers the steps before it (directly, through a selection
//!    divergence, or through a simultaneous convergence, possibly before a selection
//!    divergence) as its sources, and its condition is computed then: an inline ST
//!    expression, a POU transition (ST pasted, IL after `:`, LD or FBD: the value of
//!    its coil or output variable named after it), or a graphical condition drawn in
//!    the chart. The blocks and edge detectors that graphical conditions need are
//!    called in an action `COMPUTE_FUNCTION_BLOCKS`, associated with qualifier S as
//!    the last association of the first initial step.
//! 2. **Emission** (`write`): depth first from each initial step, in registration
//!    order: the step with its associations, the actions it uses not written yet, then
//!    each of its transitions, followed at once by its target steps. Each element is
//!    written once. What no initial step reaches is dropped, with a warning (the
//!    translator drops it silently); a chart without an initial step is an error.
//!
//! The text order decides the order of evaluation of the chart (matiec's, which the
//! textual SFC of the lowering follows), hence the care for the translator's order.

use super::body::{emit_body, emit_condition, CondState, Names, PouCtx};
use super::graph::Graph;
use super::map::Out;
use super::view::write_text;
use super::wire::Line;
use super::xml::{ActionTarget, Body, Cond, Kind, NodeKind, Pou, Sfc, SfcNode, Text};
use crate::codes;
use plcc_ir::diag::{Diagnostic, Span};
use rustc_hash::FxHashMap;
use std::ops::Range;

/// The name of the action that calls the blocks of graphical conditions.
pub(super) const COMPUTE: &str = "COMPUTE_FUNCTION_BLOCKS";

/// What the chart of one POU (or of one of its actions) is made from.
#[derive(Clone, Copy)]
pub(super) struct Inputs<'a, 'm> {
    /// The POU.
    pub pou: &'a Pou,
    /// Its chart.
    pub sfc: &'a Sfc,
    /// The graph of the chart's graphical elements (its graphical conditions).
    pub graph: Option<&'a Graph<'m>>,
    /// The graphs of the POU's transitions (`pou.transitions`), where graphical.
    pub transitions: &'a [Option<Graph<'m>>],
    /// The graphs of the POU's actions (`pou.actions`), where graphical (for an
    /// action written as a chart, the graph of its graphical conditions).
    pub actions: &'a [Option<Graph<'m>>],
    /// The action whose body the chart is (an index in `pou.actions`); `None` for
    /// the POU's body.
    pub action: Option<usize>,
}

/// A chart ready to be written: its steps, actions and transitions in text order.
pub(super) struct Chart<'a, 'm> {
    items: Vec<Item<'a, 'm>>,
}

enum Item<'a, 'm> {
    Step {
        node: &'a SfcNode,
        name: &'a Text,
        initial: bool,
        assocs: Vec<Assoc<'a>>,
    },
    Action {
        name: String,
        /// The POU action's name, for the map.
        text: Option<&'a Text>,
        tag: Range<u32>,
        body: ActionBody<'a, 'm>,
    },
    Transition {
        node: &'a SfcNode,
        priority: Option<&'a Text>,
        from: Vec<String>,
        to: Vec<String>,
        cond: CondText<'a, 'm>,
    },
}

/// An association of a step: `name(qualifier[, duration][, indicator]);`.
#[derive(Clone)]
struct Assoc<'a> {
    name: String,
    /// The reference's name in the XML, for the map.
    text: Option<&'a Text>,
    qualifier: Option<&'a Text>,
    /// A CODESYS step action's kind (`ENTRY`, `ACTIVE`, `EXIT`), written as its
    /// qualifier.
    step_action: Option<&'static str>,
    duration: Option<&'a Text>,
    indicator: Option<&'a Text>,
    tag: Option<Range<u32>>,
}

enum ActionBody<'a, 'm> {
    /// ST or IL, as written.
    Text(&'a Text),
    /// Lowered from LD or FBD.
    Lines(Vec<Line>, &'a Graph<'m>),
    /// The calls of `COMPUTE_FUNCTION_BLOCKS`, each with the graph it comes from.
    Compute(Vec<(Line, &'a Graph<'m>)>),
    /// An action written as a chart: its steps and transitions (the actions it
    /// uses are written after it, at the POU's level).
    Chart(Chart<'a, 'm>),
    Empty,
}

enum CondText<'a, 'm> {
    /// `:= <ST expression>;`
    Inline(&'a Text),
    /// A POU transition in ST, pasted as is (it reads `:= expr;`).
    St(&'a Text),
    /// A POU transition in IL: `:` and the list.
    Il(&'a Text),
    /// A graphical condition: `:= <value>;`.
    Lowered(Line, &'a Graph<'m>),
    /// None (after an error).
    None,
}

struct StepInfo<'a> {
    node: usize,
    name: &'a Text,
    initial: bool,
    transitions: Vec<usize>,
    assocs: Vec<Assoc<'a>>,
}

struct TransInfo<'a, 'm> {
    node: usize,
    from: Vec<usize>,
    to: Vec<String>,
    cond: Option<CondText<'a, 'm>>,
}

struct ActionInfo<'a, 'm> {
    name: String,
    text: Option<&'a Text>,
    tag: Range<u32>,
    body: Option<ActionBody<'a, 'm>>,
}

struct Reg<'a, 'm, 'c, 'd> {
    inp: Inputs<'a, 'm>,
    /// The name of the action of the blocks of graphical conditions:
    /// `COMPUTE_FUNCTION_BLOCKS`, with `_<action>` for an action's chart.
    compute_name: String,
    ctx: &'c PouCtx<'c>,
    names: &'d mut Names,
    diags: &'d mut Vec<Diagnostic>,
    /// `localId` to node index.
    index: FxHashMap<u64, usize>,
    steps: Vec<StepInfo<'a>>,
    step_by_name: FxHashMap<String, usize>,
    trans: Vec<TransInfo<'a, 'm>>,
    trans_of_node: FxHashMap<usize, usize>,
    actions: Vec<ActionInfo<'a, 'm>>,
    action_by_name: FxHashMap<String, usize>,
    initial: Vec<usize>,
    inline: u32,
    compute: Vec<(Line, &'a Graph<'m>)>,
    /// What the conditions read from each graph computed: key 0 the chart, k + 1 the
    /// POU's transition k.
    states: FxHashMap<usize, CondState>,
}

/// Registers the chart of a POU and puts it in text order; lowers its graphical
/// conditions and the graphical bodies of the actions it uses (hidden variables go to
/// `names`). `None` after an error (reported to `diags`).
pub(super) fn plan<'a, 'm>(
    inp: Inputs<'a, 'm>,
    ctx: &PouCtx,
    names: &mut Names,
    diags: &mut Vec<Diagnostic>,
) -> Option<Chart<'a, 'm>> {
    let before = diags.iter().filter(|d| d.is_error()).count();
    for n in &inp.sfc.nodes {
        if let NodeKind::Step { name, .. } = &n.kind {
            names.take(&name.value);
        }
    }
    for a in &inp.pou.actions {
        names.take(&a.name.value);
        // The steps of actions written as charts are variables of the POU too.
        if let Body::Sfc(s) = &a.body {
            for n in &s.nodes {
                if let NodeKind::Step { name, .. } = &n.kind {
                    names.take(&name.value);
                }
            }
        }
    }
    let compute_name = match inp.action {
        None => COMPUTE.to_string(),
        Some(k) => format!("{COMPUTE}_{}", inp.pou.actions[k].name.value),
    };
    names.take(&compute_name);
    let mut r = Reg {
        inp,
        compute_name,
        ctx,
        names,
        diags,
        index: FxHashMap::default(),
        steps: Vec::new(),
        step_by_name: FxHashMap::default(),
        trans: Vec::new(),
        trans_of_node: FxHashMap::default(),
        actions: Vec::new(),
        action_by_name: FxHashMap::default(),
        initial: Vec::new(),
        inline: 0,
        compute: Vec::new(),
        states: FxHashMap::default(),
    };
    r.index_nodes();
    for (i, n) in inp.sfc.nodes.iter().enumerate() {
        match &n.kind {
            NodeKind::Step { .. } => r.step(i),
            NodeKind::ActionBlock { .. } => r.action_block(i),
            NodeKind::Transition { .. } => {
                r.transition(i);
            }
            NodeKind::Jump { .. } => r.jump(i),
            _ => {}
        }
    }
    let Some(&first) = r.initial.first() else {
        let d = Diagnostic::error(
            codes::SFC_NO_INITIAL_STEP,
            format!("the chart of `{}` has no initial step", r.label()),
            r.span(inp.sfc.tag.clone()),
        )
        .with_note("mark the step the chart starts from with `initialStep=\"true\"`");
        r.diags.push(d);
        return None;
    };
    if !r.compute.is_empty() {
        r.steps[first].assocs.push(Assoc {
            name: r.compute_name.clone(),
            text: None,
            qualifier: None,
            step_action: None,
            duration: None,
            indicator: None,
            tag: None,
        });
        let calls = std::mem::take(&mut r.compute);
        r.add_action(ActionInfo {
            name: r.compute_name.clone(),
            text: None,
            tag: inp.sfc.tag.clone(),
            body: Some(ActionBody::Compute(calls)),
        });
    }
    r.check_sources();
    let chart = r.emit();
    let after = diags.iter().filter(|d| d.is_error()).count();
    (after == before).then_some(chart)
}

impl<'a, 'm, 'c> Reg<'a, 'm, 'c, '_> {
    fn span(&self, r: Range<u32>) -> Span {
        Span::new(self.ctx.file, r.start, r.end)
    }

    fn node(&self, i: usize) -> &'a SfcNode {
        &self.inp.sfc.nodes[i]
    }

    fn pou_name(&self) -> &'a str {
        &self.inp.pou.name.value
    }

    /// The chart's owner in messages: `P`, or `P.A` for an action's chart.
    fn label(&self) -> String {
        match self.inp.action {
            None => self.pou_name().to_string(),
            Some(k) => format!("{}.{}", self.pou_name(), self.inp.pou.actions[k].name.value),
        }
    }

    fn describe(&self, i: usize) -> String {
        let n = self.node(i);
        format!("{} (localId {})", n.kind.describe(), n.id)
    }

    fn error(&mut self, code: &'static str, msg: String, at: Range<u32>) {
        let d = Diagnostic::error(code, msg, self.span(at));
        self.diags.push(d);
    }

    /// Indexes the nodes by `localId`; reports steps that share a name.
    fn index_nodes(&mut self) {
        let mut names: FxHashMap<String, usize> = FxHashMap::default();
        for (i, n) in self.inp.sfc.nodes.iter().enumerate() {
            self.index.entry(n.id).or_insert(i);
            if let NodeKind::Step { name, .. } = &n.kind {
                let key = name.value.to_ascii_uppercase();
                if let Some(&first) = names.get(&key) {
                    let d = Diagnostic::error(
                        codes::SFC_BAD_ELEMENT,
                        format!(
                            "the chart of `{}` has two steps named `{}`",
                            self.pou_name(),
                            name.value
                        ),
                        self.span(n.tag.clone()),
                    )
                    .with_secondary(self.span(self.node(first).tag.clone()), "the first one");
                    self.diags.push(d);
                } else {
                    names.insert(key, i);
                }
            }
        }
    }

    /// The node connected to input `port` of node `i`, when exactly one is (as the
    /// translator reads it).
    fn source(&mut self, i: usize, port: usize) -> Option<usize> {
        let conns = self.node(i).ins.get(port)?;
        let [c] = conns.as_slice() else {
            return None;
        };
        match self.index.get(&c.from) {
            Some(&j) => Some(j),
            None => {
                let msg = format!(
                    "{} of `{}` is connected to localId {}, which is no element of the chart",
                    self.describe(i),
                    self.pou_name(),
                    c.from
                );
                self.error(codes::SFC_BAD_ELEMENT, msg, c.range.clone());
                None
            }
        }
    }

    /// The nodes connected to the inputs of convergence `c`; a convergence of the
    /// same kind on an input (CODESYS nests them: a branch closed inside a branch)
    /// gives its own inputs.
    fn convergence_inputs(&mut self, c: usize) -> Vec<usize> {
        let mut out = Vec::new();
        let mut work = vec![c];
        let mut seen = vec![c];
        while let Some(c) = work.pop() {
            for p in 0..self.node(c).ins.len() {
                let Some(x) = self.source(c, p) else { continue };
                let same = std::mem::discriminant(&self.node(x).kind)
                    == std::mem::discriminant(&self.node(c).kind);
                if same {
                    if !seen.contains(&x) {
                        seen.push(x);
                        work.push(x);
                    }
                } else {
                    out.push(x);
                }
            }
        }
        out
    }

    /// The node before divergence `d`, through divergences of the same kind
    /// (CODESYS nests them: a branch opened inside a branch).
    fn divergence_source(&mut self, d: usize) -> Option<usize> {
        let mut d = d;
        let mut seen = vec![d];
        loop {
            let x = self.source(d, 0)?;
            if std::mem::discriminant(&self.node(x).kind)
                != std::mem::discriminant(&self.node(d).kind)
            {
                return Some(x);
            }
            if seen.contains(&x) {
                return None;
            }
            seen.push(x);
            d = x;
        }
    }

    /// The transitions right before step or jump `i`.
    fn transitions_before(&mut self, i: usize) -> Vec<usize> {
        let Some(t) = self.source(i, 0) else {
            return Vec::new();
        };
        let found = match &self.node(t).kind {
            NodeKind::Transition { .. } => vec![t],
            NodeKind::SelectionConvergence => self.convergence_inputs(t),
            NodeKind::SimultaneousDivergence => match self.divergence_source(t) {
                Some(x) if matches!(self.node(x).kind, NodeKind::Transition { .. }) => vec![x],
                Some(x) if matches!(self.node(x).kind, NodeKind::SelectionConvergence) => {
                    self.convergence_inputs(x)
                }
                _ => Vec::new(),
            },
            _ => {
                let msg = format!(
                    "{} of `{}` follows {}, not a transition",
                    self.describe(i),
                    self.pou_name(),
                    self.describe(t)
                );
                self.error(codes::SFC_BAD_ELEMENT, msg, self.node(i).tag.clone());
                Vec::new()
            }
        };
        found
            .into_iter()
            .filter(|&x| matches!(self.node(x).kind, NodeKind::Transition { .. }))
            .collect()
    }

    /// The steps right before transition `i`.
    fn steps_before(&mut self, i: usize) -> Vec<usize> {
        let Some(s) = self.source(i, 0) else {
            return Vec::new();
        };
        let found = match &self.node(s).kind {
            NodeKind::Step { .. } => vec![s],
            NodeKind::SelectionDivergence => match self.divergence_source(s) {
                Some(x) if matches!(self.node(x).kind, NodeKind::Step { .. }) => vec![x],
                Some(x) if matches!(self.node(x).kind, NodeKind::SimultaneousConvergence) => {
                    self.convergence_inputs(x)
                }
                _ => Vec::new(),
            },
            NodeKind::SimultaneousConvergence => self.convergence_inputs(s),
            _ => Vec::new(),
        };
        found
            .into_iter()
            .filter(|&x| matches!(self.node(x).kind, NodeKind::Step { .. }))
            .collect()
    }

    /// Registers step `i` (once per name) and makes it the target of the transitions
    /// before it.
    fn step(&mut self, i: usize) {
        let NodeKind::Step {
            name,
            initial,
            step_actions,
        } = &self.node(i).kind
        else {
            return;
        };
        let key = name.value.to_ascii_uppercase();
        if self.step_by_name.contains_key(&key) {
            return;
        }
        let idx = self.steps.len();
        // CODESYS's step actions, as plcc's pseudo-qualifiers ENTRY, ACTIVE, EXIT.
        let mut assocs = Vec::new();
        for (kind, action) in step_actions {
            self.pou_action(action);
            assocs.push(Assoc {
                name: action.value.clone(),
                text: Some(action),
                qualifier: None,
                step_action: Some(kind),
                duration: None,
                indicator: None,
                tag: Some(action.range.clone()),
            });
        }
        self.steps.push(StepInfo {
            node: i,
            name,
            initial: *initial,
            transitions: Vec::new(),
            assocs,
        });
        self.step_by_name.insert(key, idx);
        if *initial {
            self.initial.push(idx);
        }
        self.lead_to(i, &name.value.clone());
    }

    /// The transitions before element `i` lead to the step `step`.
    fn lead_to(&mut self, i: usize, step: &str) {
        for t in self.transitions_before(i) {
            if let Some(ti) = self.transition(t) {
                self.trans[ti].to.push(step.to_string());
            }
        }
    }

    /// A jump: the transitions before it lead to its target.
    fn jump(&mut self, i: usize) {
        let NodeKind::Jump { target } = &self.node(i).kind else {
            return;
        };
        let exists = self.inp.sfc.nodes.iter().any(|n| {
            matches!(&n.kind, NodeKind::Step { name, .. } if name.value.eq_ignore_ascii_case(&target.value))
        });
        if !exists {
            let d = Diagnostic::error(
                codes::SFC_JUMP_TARGET,
                format!(
                    "{} of `{}` names no step of the chart",
                    self.describe(i),
                    self.pou_name()
                ),
                self.span(target.range.clone()),
            )
            .with_label("no step has this name");
            self.diags.push(d);
            // The transitions before it still lead somewhere (no second error).
        }
        self.lead_to(i, &target.value.clone());
    }

    /// An action block: its step registered, and the step's associations.
    fn action_block(&mut self, i: usize) {
        let NodeKind::ActionBlock { actions } = &self.node(i).kind else {
            return;
        };
        let Some(s) = self.source(i, 0) else {
            return;
        };
        let NodeKind::Step { name, .. } = &self.node(s).kind else {
            let msg = format!(
                "{} of `{}` hangs on {}, not on a step",
                self.describe(i),
                self.pou_name(),
                self.describe(s)
            );
            self.error(codes::SFC_BAD_ELEMENT, msg, self.node(i).tag.clone());
            return;
        };
        self.step(s);
        let Some(&si) = self.step_by_name.get(&name.value.to_ascii_uppercase()) else {
            return;
        };
        for a in actions {
            let (content, text) = match &a.target {
                ActionTarget::Reference(x) => {
                    self.pou_action(x);
                    (x.value.clone(), Some(x))
                }
                ActionTarget::Inline(body) => {
                    self.inline += 1;
                    let n = format!("{}_INLINE{}", name.value.to_ascii_uppercase(), self.inline);
                    self.names.take(&n);
                    self.add_action(ActionInfo {
                        name: n.clone(),
                        text: None,
                        tag: a.tag.clone(),
                        body: Some(ActionBody::Text(body)),
                    });
                    (n, None)
                }
            };
            self.steps[si].assocs.push(Assoc {
                name: content,
                text,
                qualifier: a.qualifier.as_ref(),
                step_action: None,
                duration: a.duration.as_ref(),
                indicator: a.indicator.as_ref(),
                tag: Some(a.tag.clone()),
            });
        }
    }

    fn add_action(&mut self, a: ActionInfo<'a, 'm>) {
        let key = a.name.to_ascii_uppercase();
        if self.action_by_name.contains_key(&key) {
            return;
        }
        self.action_by_name.insert(key, self.actions.len());
        self.actions.push(a);
    }

    /// Registers the POU's action `x` on its first use, its graphical body lowered;
    /// nothing when the POU has no such action (`x` is a BOOL variable).
    fn pou_action(&mut self, x: &Text) {
        if self
            .action_by_name
            .contains_key(&x.value.to_ascii_uppercase())
        {
            return;
        }
        let pou = self.inp.pou;
        let Some(k) = pou
            .actions
            .iter()
            .position(|a| a.name.value.eq_ignore_ascii_case(&x.value))
        else {
            return;
        };
        let a = &pou.actions[k];
        let body = match (&a.body, self.inp.actions.get(k).and_then(Option::as_ref)) {
            (Body::St(t) | Body::Il(t), _) => ActionBody::Text(t),
            (Body::Sfc(sfc), graph) => {
                let inner = Inputs {
                    sfc,
                    graph,
                    action: Some(k),
                    ..self.inp
                };
                match plan(inner, self.ctx, self.names, self.diags) {
                    Some(c) => ActionBody::Chart(c),
                    None => ActionBody::Empty,
                }
            }
            (Body::Graph(..), Some(g)) => {
                let label = format!("{}.{}", pou.name.value, a.name.value);
                let ctx = self.sub_ctx(&label);
                ActionBody::Lines(emit_body(g, &ctx, self.names, self.diags), g)
            }
            _ => ActionBody::Empty,
        };
        self.add_action(ActionInfo {
            name: a.name.value.clone(),
            text: Some(&a.name),
            tag: a.tag.clone(),
            body: Some(body),
        });
    }

    fn sub_ctx<'l>(&self, label: &'l str) -> PouCtx<'l>
    where
        'c: 'l,
    {
        PouCtx {
            project: self.ctx.project,
            pou: label,
            pou_vars: self.ctx.pou_vars,
            globals: self.ctx.globals,
            file: self.ctx.file,
            opts: self.ctx.opts,
        }
    }
}

impl<'a, 'm> Reg<'a, 'm, '_, '_> {
    /// Registers transition `i` (once): its source steps, and its condition computed
    /// now (the order of the calls of `COMPUTE_FUNCTION_BLOCKS` is that of
    /// registration). `None` if `i` is not a transition.
    fn transition(&mut self, i: usize) -> Option<usize> {
        if let Some(&t) = self.trans_of_node.get(&i) {
            return Some(t);
        }
        if !matches!(self.node(i).kind, NodeKind::Transition { .. }) {
            return None;
        }
        let steps = self.steps_before(i);
        let ti = self.trans.len();
        self.trans.push(TransInfo {
            node: i,
            from: Vec::new(),
            to: Vec::new(),
            cond: None,
        });
        self.trans_of_node.insert(i, ti);
        let cond = self.condition(i);
        self.trans[ti].cond = Some(cond);
        for s in steps {
            self.step(s);
            let NodeKind::Step { name, .. } = &self.node(s).kind else {
                continue;
            };
            if let Some(&si) = self.step_by_name.get(&name.value.to_ascii_uppercase()) {
                self.trans[ti].from.push(si);
                self.steps[si].transitions.push(ti);
            }
        }
        Some(ti)
    }

    /// The condition of transition `i`, computed.
    fn condition(&mut self, i: usize) -> CondText<'a, 'm> {
        let node = self.node(i);
        let NodeKind::Transition { cond, .. } = &node.kind else {
            return CondText::None;
        };
        let pou = self.inp.pou;
        match cond {
            Cond::None => {
                let msg = format!(
                    "{} of `{}` has no condition",
                    self.describe(i),
                    pou.name.value
                );
                self.error(codes::SFC_NO_CONDITION, msg, node.tag.clone());
                CondText::None
            }
            Cond::Inline(t) => CondText::Inline(t),
            Cond::Reference(name) => {
                let Some(k) = pou
                    .transitions
                    .iter()
                    .position(|t| t.name.value.eq_ignore_ascii_case(&name.value))
                else {
                    let d = Diagnostic::error(
                        codes::SFC_NO_CONDITION,
                        format!(
                            "{} of `{}` refers to transition `{}`, which the POU does not define",
                            self.describe(i),
                            pou.name.value,
                            name.value
                        ),
                        self.span(name.range.clone()),
                    )
                    .with_label("no `<transition>` of the POU has this name");
                    self.diags.push(d);
                    return CondText::None;
                };
                let t = &pou.transitions[k];
                match &t.body {
                    Body::St(text) => CondText::St(text),
                    Body::Il(text) => CondText::Il(text),
                    Body::Graph(..) => {
                        // The graph is missing after an error in it (reported).
                        let Some(g) = self.inp.transitions.get(k).and_then(Option::as_ref) else {
                            return CondText::None;
                        };
                        let sink = g.elems.iter().position(|e| match &e.kind {
                            Kind::Coil { var, .. } => var.value.eq_ignore_ascii_case(&name.value),
                            Kind::OutVariable { expr, .. } => {
                                expr.value.eq_ignore_ascii_case(&name.value)
                            }
                            _ => false,
                        });
                        let Some(sink) = sink else {
                            let d = Diagnostic::error(
                                codes::SFC_TRANSITION_BODY,
                                format!(
                                    "transition `{}` of `{}` has no coil or output variable named `{}`, \
                                     which would give its value",
                                    t.name.value, pou.name.value, t.name.value
                                ),
                                self.span(t.tag.clone()),
                            )
                            .with_note(format!(
                                "write the condition to a coil `{0}` (LD) or an output variable `{0}` (FBD)",
                                t.name.value
                            ));
                            self.diags.push(d);
                            return CondText::None;
                        };
                        let label = format!("{}.{}", pou.name.value, t.name.value);
                        self.lower(g, sink, k + 1, &label)
                    }
                    _ => {
                        let d = Diagnostic::error(
                            codes::SFC_TRANSITION_BODY,
                            format!(
                                "transition `{}` of `{}` has no body to give its value",
                                t.name.value, pou.name.value
                            ),
                            self.span(t.tag.clone()),
                        );
                        self.diags.push(d);
                        CondText::None
                    }
                }
            }
            Cond::Graphic { sink } => {
                let Some(g) = self.inp.graph else {
                    return CondText::None;
                };
                let Some(e) = g
                    .elems
                    .iter()
                    .rposition(|e| e.id == *sink && matches!(e.kind, Kind::OutVariable { .. }))
                else {
                    return CondText::None;
                };
                if g.ins[e][0].is_empty() {
                    let msg = format!(
                        "the graphical condition of {} of `{}` is connected to nothing",
                        self.describe(i),
                        pou.name.value
                    );
                    self.error(codes::SFC_NO_CONDITION, msg, node.tag.clone());
                    return CondText::None;
                }
                let label = pou.name.value.clone();
                self.lower(g, e, 0, &label)
            }
        }
    }

    /// The value reaching `sink` of graph `g` (state `key`): the condition, with the
    /// calls it needs added to `COMPUTE_FUNCTION_BLOCKS`.
    fn lower(
        &mut self,
        g: &'a Graph<'m>,
        sink: usize,
        key: usize,
        label: &str,
    ) -> CondText<'a, 'm> {
        let ctx = PouCtx {
            project: self.ctx.project,
            pou: label,
            pou_vars: self.ctx.pou_vars,
            globals: self.ctx.globals,
            file: self.ctx.file,
            opts: self.ctx.opts,
        };
        let state = self.states.entry(key).or_default();
        let (calls, cond) = emit_condition(g, sink, state, &ctx, self.names, self.diags);
        self.compute.extend(calls.into_iter().map(|l| (l, g)));
        CondText::Lowered(cond, g)
    }

    /// A transition with no step before it can never fire: an error wherever it is.
    fn check_sources(&mut self) {
        for ti in 0..self.trans.len() {
            if self.trans[ti].from.is_empty() {
                let i = self.trans[ti].node;
                let msg = format!(
                    "{} of `{}` has no step before it",
                    self.describe(i),
                    self.pou_name()
                );
                self.error(
                    codes::SFC_TRANSITION_UNCONNECTED,
                    msg,
                    self.node(i).tag.clone(),
                );
            }
        }
    }

    /// The chart in text order, depth first from each initial step; what is not
    /// reached is dropped, with a warning.
    fn emit(mut self) -> Chart<'a, 'm> {
        let mut e = Emit {
            steps: vec![false; self.steps.len()],
            trans: vec![false; self.trans.len()],
            actions: vec![false; self.actions.len()],
            items: Vec::new(),
        };
        for k in 0..self.initial.len() {
            let s = self.initial[k];
            self.emit_step(&mut e, s);
        }
        // What is not reached.
        let pou = self.pou_name();
        for (si, s) in self.steps.iter().enumerate() {
            if !e.steps[si] {
                let d = Diagnostic::warning(
                    codes::W_SFC_DROPPED,
                    format!(
                        "step `{}` of `{pou}` cannot be reached from an initial step: dropped",
                        s.name.value
                    ),
                    self.span(self.node(s.node).tag.clone()),
                );
                self.diags.push(d);
            }
        }
        for (ti, t) in self.trans.iter().enumerate() {
            if !e.trans[ti] && !t.from.is_empty() {
                let d = Diagnostic::warning(
                    codes::W_SFC_DROPPED,
                    format!(
                        "{} of `{pou}` cannot be reached from an initial step: dropped",
                        self.describe(t.node)
                    ),
                    self.span(self.node(t.node).tag.clone()),
                );
                self.diags.push(d);
            }
        }
        // The POU's actions no chart uses (those of actions' charts count; an action's
        // chart leaves this to its POU's).
        let mut written = Vec::new();
        action_names(&e.items, &mut written);
        for a in self
            .inp
            .pou
            .actions
            .iter()
            .filter(|_| self.inp.action.is_none())
        {
            let used = written
                .iter()
                .any(|n| n.eq_ignore_ascii_case(&a.name.value));
            if !used {
                let d = Diagnostic::warning(
                    codes::W_SFC_DROPPED,
                    format!(
                        "action `{}` of `{pou}` is used by no step the chart reaches: dropped",
                        a.name.value
                    ),
                    self.span(a.tag.clone()),
                );
                self.diags.push(d);
            }
        }
        Chart { items: e.items }
    }

    fn emit_step(&mut self, e: &mut Emit<'a, 'm>, si: usize) {
        if e.steps[si] {
            return;
        }
        e.steps[si] = true;
        let s = &self.steps[si];
        let node = self.node(s.node);
        let assocs = s.assocs.clone();
        let transitions = s.transitions.clone();
        e.items.push(Item::Step {
            node,
            name: s.name,
            initial: s.initial,
            assocs: assocs.clone(),
        });
        for a in &assocs {
            if let Some(&ai) = self.action_by_name.get(&a.name.to_ascii_uppercase()) {
                if !e.actions[ai] {
                    e.actions[ai] = true;
                    let info = &mut self.actions[ai];
                    e.items.push(Item::Action {
                        name: info.name.clone(),
                        text: info.text,
                        tag: info.tag.clone(),
                        body: info.body.take().unwrap_or(ActionBody::Empty),
                    });
                }
            }
        }
        for t in transitions {
            self.emit_transition(e, t);
        }
    }

    fn emit_transition(&mut self, e: &mut Emit<'a, 'm>, ti: usize) {
        if e.trans[ti] {
            return;
        }
        e.trans[ti] = true;
        let t = &mut self.trans[ti];
        let node_idx = t.node;
        let node = self.inp.sfc.nodes.get(node_idx).expect("a node");
        let from: Vec<String> = t
            .from
            .iter()
            .map(|&s| self.steps[s].name.value.clone())
            .collect();
        let to = t.to.clone();
        let cond = t.cond.take().unwrap_or(CondText::None);
        let NodeKind::Transition { priority, .. } = &node.kind else {
            return;
        };
        if to.is_empty() {
            let msg = format!(
                "{} of `{}` has no step after it",
                self.describe(node_idx),
                self.pou_name()
            );
            self.error(codes::SFC_TRANSITION_UNCONNECTED, msg, node.tag.clone());
        }
        e.items.push(Item::Transition {
            node,
            priority: priority.as_ref(),
            from,
            to: to.clone(),
            cond,
        });
        for name in to {
            if let Some(&si) = self.step_by_name.get(&name.to_ascii_uppercase()) {
                self.emit_step(e, si);
            }
        }
    }
}

impl Chart<'_, '_> {
    /// The names of the actions the chart writes (its own and those of the charts
    /// of its actions).
    pub(super) fn action_names(&self) -> Vec<String> {
        let mut out = Vec::new();
        action_names(&self.items, &mut out);
        out
    }
}

/// The names of the actions among `items`, and among those of the charts of actions.
fn action_names(items: &[Item], out: &mut Vec<String>) {
    for i in items {
        if let Item::Action { name, body, .. } = i {
            out.push(name.clone());
            if let ActionBody::Chart(c) = body {
                action_names(&c.items, out);
            }
        }
    }
}

struct Emit<'a, 'm> {
    steps: Vec<bool>,
    trans: Vec<bool>,
    actions: Vec<bool>,
    items: Vec<Item<'a, 'm>>,
}

// ------------------------------------------------------------------ text

/// Writes a chart (the body of its POU, actions included) as textual SFC, mapped to
/// the XML elements it comes from.
pub(super) fn write(o: &mut Out, chart: &Chart) {
    write_items(o, chart, true, true, &mut Vec::new());
}

/// Writes the steps and transitions of an action's chart (the ACTION's body).
pub(super) fn write_elements(o: &mut Out, chart: &Chart) {
    write_items(o, chart, true, false, &mut Vec::new());
}

/// Writes the actions an action's chart uses (after the ACTION), but those in
/// `written` (an action several charts use is written once); adds their names.
pub(super) fn write_actions(o: &mut Out, chart: &Chart, written: &mut Vec<String>) {
    write_items(o, chart, false, true, written);
}

/// The items of `chart`: its steps and transitions when `elements`, its actions
/// (and those of the charts of its actions, after them) when `actions`, but those
/// in `written`.
fn write_items(
    o: &mut Out,
    chart: &Chart,
    elements: bool,
    actions: bool,
    written: &mut Vec<String>,
) {
    for item in &chart.items {
        let is_action = matches!(item, Item::Action { .. });
        if (is_action && !actions) || (!is_action && !elements) {
            continue;
        }
        if let Item::Action { name, .. } = item {
            if written.iter().any(|w| w.eq_ignore_ascii_case(name)) {
                continue;
            }
            written.push(name.clone());
        }
        match item {
            Item::Step {
                node,
                name,
                initial,
                assocs,
            } => {
                let start = o.pos();
                o.push(if *initial { "INITIAL_STEP " } else { "STEP " });
                o.push_text(name);
                o.push(":");
                o.mark(start, node.tag.clone());
                o.push("\n");
                for a in assocs {
                    write_assoc(o, a, &node.tag);
                }
                o.push("END_STEP\n");
            }
            Item::Action {
                name,
                text,
                tag,
                body,
            } => {
                let start = o.pos();
                o.push("ACTION ");
                match text {
                    Some(t) => o.push_as(name, t),
                    None => o.push(name),
                }
                o.push(":");
                o.mark(start, tag.clone());
                o.push("\n");
                match body {
                    ActionBody::Text(t) => write_text(o, t),
                    ActionBody::Lines(lines, g) => {
                        for l in lines {
                            l.write(o, g.elems);
                        }
                    }
                    ActionBody::Compute(calls) => {
                        for (l, g) in calls {
                            l.write(o, g.elems);
                        }
                    }
                    ActionBody::Chart(c) => write_elements(o, c),
                    ActionBody::Empty => {}
                }
                o.push("END_ACTION\n");
                if let ActionBody::Chart(c) = body {
                    write_actions(o, c, written);
                }
            }
            Item::Transition {
                node,
                priority,
                from,
                to,
                cond,
            } => {
                let start = o.pos();
                o.push("TRANSITION");
                if let Some(p) = priority {
                    o.push(" (PRIORITY := ");
                    o.push_text(p);
                    o.push(")");
                }
                o.push(" FROM ");
                o.push(&step_list(from));
                o.push(" TO ");
                o.push(&step_list(to));
                if let CondText::Il(_) = cond {
                    o.push(":");
                }
                o.mark(start, node.tag.clone());
                o.push("\n");
                match cond {
                    CondText::Inline(t) => {
                        let start = o.pos();
                        o.push("    := ");
                        o.push_text(t);
                        o.push(";");
                        o.mark(start, node.tag.clone());
                        o.push("\n");
                    }
                    CondText::St(t) | CondText::Il(t) => write_text(o, t),
                    CondText::Lowered(l, g) => l.write(o, g.elems),
                    CondText::None => {}
                }
                o.push("END_TRANSITION\n");
            }
        }
    }
}

/// `name(Q[, duration][, indicator]);`, the qualifier N when none is given.
fn write_assoc(o: &mut Out, a: &Assoc, step_tag: &Range<u32>) {
    let start = o.pos();
    o.push("    ");
    match a.text {
        Some(t) => o.push_as(&a.name, t),
        None => o.push(&a.name),
    }
    o.push("(");
    match a.qualifier {
        _ if a.step_action.is_some() => o.push(a.step_action.unwrap_or("N")),
        Some(q) => o.push_as(&q.value.to_ascii_uppercase(), q),
        None if a.name.starts_with(COMPUTE) => o.push("S"),
        None => o.push("N"),
    }
    for x in [a.duration, a.indicator].into_iter().flatten() {
        o.push(", ");
        o.push_text(x);
    }
    o.push(");");
    o.mark(start, a.tag.clone().unwrap_or_else(|| step_tag.clone()));
    o.push("\n");
}

/// `S` or `(S1, S2)`.
fn step_list(names: &[String]) -> String {
    match names {
        [one] => one.clone(),
        _ => format!("({})", names.join(", ")),
    }
}
