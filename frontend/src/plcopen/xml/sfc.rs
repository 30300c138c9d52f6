//! Sequential function charts (`<SFC>` bodies): steps, transitions, divergences and
//! convergences, jumps, action blocks and macro steps, with the graphical elements
//! (variables, contacts, blocks...) that transition conditions are drawn with.
//!
//! Only what the editors' translator (PLCGenerator) reads is kept; how the chart is
//! written as textual SFC is `plcopen::sfc`'s business. The checks made here are those
//! of one element alone: qualifiers and their durations, priorities, names.

use super::*;

/// An `<SFC>` body.
#[derive(Debug)]
pub(crate) struct Sfc {
    /// The chart's elements, in document order.
    pub nodes: Vec<SfcNode>,
    /// The graphical elements of the body (LD and FBD elements, which graphical
    /// conditions are drawn with), in document order, followed by one output variable
    /// per transition with a graphical condition ([`Cond::Graphic`]): the sink whose
    /// value is the condition.
    pub graphic: Vec<Element>,
    /// The `<SFC>` tag name, for messages about the whole chart.
    pub tag: Range<u32>,
}

/// An element of a chart.
#[derive(Debug)]
pub(crate) struct SfcNode {
    /// `localId`.
    pub id: u64,
    /// From `<` through the `localId` attribute: what diagnostics underline.
    pub tag: Range<u32>,
    /// What it is.
    pub kind: NodeKind,
    /// The connections of each `connectionPointIn` (a convergence has several; a step,
    /// transition, jump, action block or divergence one).
    pub ins: Vec<Vec<Conn>>,
}

/// The kinds of chart elements.
#[derive(Debug)]
pub(crate) enum NodeKind {
    /// `step`
    Step {
        /// Its name.
        name: Text,
        /// `initialStep="true"`.
        initial: bool,
        /// CODESYS's step actions (entry, active, exit), from the step's `addData`:
        /// the kind (`ENTRY`, `ACTIVE`, `EXIT`, as plcc's textual SFC writes them)
        /// and the action's name.
        step_actions: Vec<(&'static str, Text)>,
    },
    /// `macroStep`: ignored (with a warning), as the editors ignore it.
    MacroStep,
    /// `transition`
    Transition {
        /// `priority`, when given (a number).
        priority: Option<Text>,
        /// Its condition.
        cond: Cond,
    },
    /// `selectionDivergence`: one step, several transitions after it.
    SelectionDivergence,
    /// `selectionConvergence`: several transitions, one step after them.
    SelectionConvergence,
    /// `simultaneousDivergence`: one transition, several steps after it.
    SimultaneousDivergence,
    /// `simultaneousConvergence`: several steps, one transition after them.
    SimultaneousConvergence,
    /// `jumpStep`: the transition before it leads to the step `target`.
    Jump {
        /// `targetName`.
        target: Text,
    },
    /// `actionBlock`: the actions of the step it hangs on.
    ActionBlock {
        /// Its `<action>` children, in order.
        actions: Vec<Action>,
    },
}

impl NodeKind {
    /// The element as messages name it.
    pub fn describe(&self) -> String {
        match self {
            NodeKind::Step { name, .. } => format!("step `{}`", name.value),
            NodeKind::MacroStep => "a macro step".into(),
            NodeKind::Transition { .. } => "a transition".into(),
            NodeKind::SelectionDivergence => "a selection divergence".into(),
            NodeKind::SelectionConvergence => "a selection convergence".into(),
            NodeKind::SimultaneousDivergence => "a simultaneous divergence".into(),
            NodeKind::SimultaneousConvergence => "a simultaneous convergence".into(),
            NodeKind::Jump { target } => format!("the jump to `{}`", target.value),
            NodeKind::ActionBlock { .. } => "an action block".into(),
        }
    }
}

/// The condition of a transition.
#[derive(Debug)]
pub(crate) enum Cond {
    /// None given (or one that cannot be used, already reported).
    None,
    /// `<inline><ST>`: an ST expression.
    Inline(Text),
    /// `<reference name="T">`: the POU's transition `T`.
    Reference(Text),
    /// `<connectionPointIn>`: drawn in the chart; its value is what reaches the output
    /// variable with this `localId` (the transition's own) in [`Sfc::graphic`].
    Graphic {
        /// The `localId` of that output variable.
        sink: u64,
    },
}

/// An `<action>` of an action block.
#[derive(Debug)]
pub(crate) struct Action {
    /// `qualifier`; `None` when absent (N).
    pub qualifier: Option<Text>,
    /// `duration`, verbatim (`T#2s`).
    pub duration: Option<Text>,
    /// `indicator`: a variable.
    pub indicator: Option<Text>,
    /// What it runs.
    pub target: ActionTarget,
    /// The `<action>` tag name, for messages.
    pub tag: Range<u32>,
}

/// What an action of an action block runs.
#[derive(Debug)]
pub(crate) enum ActionTarget {
    /// `<reference name="X">`: the POU's action X, or a BOOL variable.
    Reference(Text),
    /// `<inline><ST>`: an ST body of its own.
    Inline(Text),
}

/// The qualifiers of textual SFC.
const QUALIFIERS: [&str; 11] = ["N", "R", "S", "P", "P0", "P1", "L", "D", "SD", "DS", "SL"];

/// The qualifiers that need a duration.
pub(crate) const TIMED: [&str; 5] = ["L", "D", "SD", "DS", "SL"];

/// The graphical elements a chart may hold (for its conditions).
const GRAPHIC: [&str; 13] = [
    "leftPowerRail",
    "rightPowerRail",
    "contact",
    "coil",
    "block",
    "inVariable",
    "outVariable",
    "inOutVariable",
    "jump",
    "label",
    "return",
    "connector",
    "continuation",
];

impl Reader<'_, '_> {
    /// An `<SFC>` body of POU `pou`.
    pub(super) fn sfc(&mut self, body: Node, pou: &str) -> Sfc {
        let mut nodes = Vec::new();
        let mut graphic = Vec::new();
        let mut sinks = Vec::new();
        for e in elements(body) {
            let name = e.tag_name().name();
            if matches!(
                name,
                "comment" | "documentation" | "addData" | "vendorElement"
            ) {
                continue;
            }
            if GRAPHIC.contains(&name) {
                if let Some(el) = self.element(e, name, pou) {
                    graphic.push(el);
                }
                continue;
            }
            if let Some(n) = self.sfc_node(e, name, pou, &mut sinks) {
                nodes.push(n);
            }
        }
        graphic.extend(sinks);
        Sfc {
            nodes,
            graphic,
            tag: self.qname(body),
        }
    }

    /// One element of a chart; `sinks` gets the output variable that stands for a
    /// graphical condition.
    fn sfc_node(
        &mut self,
        e: Node,
        name: &str,
        pou: &str,
        sinks: &mut Vec<Element>,
    ) -> Option<SfcNode> {
        let tag = self.tag(e);
        let Some(id_text) = self.attr(e, "localId") else {
            self.error(
                codes::SFC_BAD_ELEMENT,
                format!("`<{name}>` in the chart of `{pou}` needs a `localId` attribute"),
                tag,
            );
            return None;
        };
        let id = self.local_id(id_text, codes::SFC_BAD_ELEMENT)?;
        let kind = match name {
            "step" => {
                let Some(name) = self.attr(e, "name").filter(|n| !n.value.is_empty()) else {
                    self.error(
                        codes::SFC_BAD_ELEMENT,
                        format!("a step (localId {id}) of `{pou}` has no `name`"),
                        tag,
                    );
                    return None;
                };
                let initial = e.attribute("initialStep").is_some_and(truthy);
                let step_actions = self.step_actions(e);
                NodeKind::Step {
                    name,
                    initial,
                    step_actions,
                }
            }
            "macroStep" => {
                let d = Diagnostic::warning(
                    codes::W_SFC_MACRO_STEP,
                    format!("a macro step (localId {id}) of `{pou}` is ignored"),
                    self.span(tag.clone()),
                )
                .with_note("the editors' translator ignores macro steps too");
                self.diags.push(d);
                NodeKind::MacroStep
            }
            "transition" => {
                let priority = self.attr(e, "priority").filter(|p| !p.value.is_empty());
                if let Some(p) = &priority {
                    if p.value.parse::<u32>().is_err() {
                        self.error(
                            codes::SFC_BAD_ELEMENT,
                            format!("`priority=\"{}\"` is not a number", p.value),
                            p.range.clone(),
                        );
                        return None;
                    }
                }
                let cond = self.condition(e, id, &tag, pou, sinks);
                NodeKind::Transition { priority, cond }
            }
            "selectionDivergence" => NodeKind::SelectionDivergence,
            "selectionConvergence" => NodeKind::SelectionConvergence,
            "simultaneousDivergence" => NodeKind::SimultaneousDivergence,
            "simultaneousConvergence" => NodeKind::SimultaneousConvergence,
            "jumpStep" => {
                let target = self.need_attr(e, "targetName")?;
                NodeKind::Jump { target }
            }
            "actionBlock" => {
                let actions = kids(e, "action")
                    .filter_map(|a| self.sfc_action(a, pou))
                    .collect();
                NodeKind::ActionBlock { actions }
            }
            other => {
                self.error(
                    codes::SFC_BAD_ELEMENT,
                    format!("`<{other}>` in the chart of `{pou}` is not an element of a sequential function chart"),
                    tag,
                );
                return None;
            }
        };
        let ins = kids(e, "connectionPointIn")
            .map(|cp| self.point_conns(cp))
            .collect();
        Some(SfcNode { id, tag, kind, ins })
    }

    /// The `<condition>` of transition `id`.
    fn condition(
        &mut self,
        e: Node,
        id: u64,
        tag: &Range<u32>,
        pou: &str,
        sinks: &mut Vec<Element>,
    ) -> Cond {
        let Some(c) = kid(e, "condition") else {
            return Cond::None;
        };
        if let Some(r) = kid(c, "reference") {
            return match self.need_attr(r, "name") {
                Some(n) => Cond::Reference(n),
                None => Cond::None,
            };
        }
        if let Some(i) = kid(c, "inline") {
            let lang = elements(i).find(|l| l.tag_name().name() != "documentation");
            return match lang {
                Some(st) if st.tag_name().name() == "ST" => Cond::Inline(self.text(st).trimmed()),
                other => {
                    let what = other.map_or("nothing".to_string(), |l| {
                        format!("`<{}>`", l.tag_name().name())
                    });
                    let d = Diagnostic::error(
                        codes::SFC_NO_CONDITION,
                        format!(
                            "the inline condition of a transition (localId {id}) of `{pou}` holds {what}, not ST"
                        ),
                        self.span(self.qname(i)),
                    )
                    .with_note("only ST inline conditions are read, as in the editors' translator");
                    self.diags.push(d);
                    Cond::None
                }
            };
        }
        if kid(c, "connectionPointIn").is_some() {
            let conns = self.conns(c);
            sinks.push(Element {
                id,
                tag: tag.clone(),
                pos: None,
                kind: Kind::OutVariable {
                    expr: Text {
                        value: "the transition's condition".into(),
                        range: tag.clone(),
                        exact: Vec::new(),
                    },
                    negated: false,
                },
                input: Port {
                    conns,
                    ..Port::default()
                },
                out_y: None,
                order: None,
            });
            return Cond::Graphic { sink: id };
        }
        Cond::None
    }

    /// An `<action>` of an action block; its qualifier checked.
    fn sfc_action(&mut self, a: Node, pou: &str) -> Option<Action> {
        let tag = self.qname(a);
        let qualifier = self.attr(a, "qualifier").filter(|q| !q.value.is_empty());
        let duration = self.attr(a, "duration").filter(|q| !q.value.is_empty());
        let indicator = self.attr(a, "indicator").filter(|q| !q.value.is_empty());
        let target = if let Some(r) = kid(a, "reference") {
            ActionTarget::Reference(self.need_attr(r, "name")?)
        } else if let Some(i) = kid(a, "inline") {
            match elements(i).find(|l| l.tag_name().name() != "documentation") {
                Some(st) if st.tag_name().name() == "ST" => {
                    ActionTarget::Inline(self.text(st).trimmed())
                }
                _ => {
                    self.error(
                        codes::SFC_BAD_ELEMENT,
                        format!("an inline action of `{pou}` is not written in ST"),
                        self.qname(i),
                    );
                    return None;
                }
            }
        } else {
            self.error(
                codes::SFC_BAD_ELEMENT,
                format!("an action of an action block of `{pou}` has neither `<reference>` nor `<inline>`"),
                tag,
            );
            return None;
        };
        if let Some(q) = &qualifier {
            let upper = q.value.to_ascii_uppercase();
            if upper == "DL" {
                let d = Diagnostic::error(
                    codes::SFC_QUALIFIER,
                    "qualifier DL (delayed and time limited) is not one of textual SFC",
                    self.span(q.range.clone()),
                )
                .with_note("the PLCopen schema has DL, but IEC compilers (and the editors' matiec) reject it; use D or L");
                self.diags.push(d);
                return None;
            }
            if !QUALIFIERS.contains(&upper.as_str()) {
                self.error(
                    codes::SFC_QUALIFIER,
                    format!(
                        "unknown qualifier `{}` (expected one of {})",
                        q.value,
                        QUALIFIERS.join(", ")
                    ),
                    q.range.clone(),
                );
                return None;
            }
            if TIMED.contains(&upper.as_str()) && duration.is_none() {
                let d = Diagnostic::error(
                    codes::SFC_NO_DURATION,
                    format!("qualifier {upper} needs a duration, and this action has none"),
                    self.span(q.range.clone()),
                )
                .with_note("give the action a `duration` attribute, e.g. `duration=\"T#2s\"`");
                self.diags.push(d);
                return None;
            }
        }
        Some(Action {
            qualifier,
            duration,
            indicator,
            target,
            tag,
        })
    }
}

/// The `guid`s under which CODESYS's `sfc/element` data of a step names its step
/// actions, with plcc's textual name of each kind (in CODESYS's order of execution:
/// exit, entry, active).
const STEP_ACTION_GUIDS: [(&str, &str); 3] = [
    ("a2621e18-7de3-4ea6-ae6d-89e9e0b7befd", "EXIT"),
    ("a6b08bd8-b696-47e3-9cbf-7408b61c9ff8", "ENTRY"),
    ("700a583f-b4d4-43e4-8c14-629c7cd3bec8", "ACTIVE"),
];

impl Reader<'_, '_> {
    /// CODESYS's step actions of step `e` (its `addData`), each with its kind.
    fn step_actions(&self, e: Node) -> Vec<(&'static str, Text)> {
        let mut out = Vec::new();
        for d in add_data(e, "element") {
            for attrs in kids(d, "attributes") {
                for a in kids(attrs, "attribute") {
                    let guid = a.attribute("guid").unwrap_or("");
                    let Some(&(_, kind)) = STEP_ACTION_GUIDS.iter().find(|(g, _)| *g == guid)
                    else {
                        continue;
                    };
                    let t = self.text(a).trimmed();
                    if !t.value.is_empty() {
                        out.push((kind, t));
                    }
                }
            }
        }
        out
    }
}
