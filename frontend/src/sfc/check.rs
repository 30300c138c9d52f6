//! The rules a chart must keep before it is written as ST, and what the writer needs
//! to know about it ([`Facts`]).

use crate::ast::{self, Ident, Pou, Sfc};
use crate::codes;
use crate::intern::{Interner, Symbol};
use plcc_ir::diag::{Diagnostic, Span};
use std::collections::HashMap;

/// An action qualifier (IEC 61131-3, table 76).
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub(super) enum Qual {
    /// Non-stored: while the step is active.
    N,
    /// Reset a stored action.
    R,
    /// Set (stored).
    S,
    /// Time limited.
    L,
    /// Time delayed.
    D,
    /// Pulse (at activation).
    P,
    /// Pulse at activation (edition 3).
    P1,
    /// Pulse at deactivation (edition 3).
    P0,
    /// Stored and time delayed.
    Sd,
    /// Delayed and stored.
    Ds,
    /// Stored and time limited.
    Sl,
    /// Written without a qualifier (`A();`).
    Bare,
    /// CODESYS's entry step action (plcc's `A(ENTRY);`): once when the step becomes
    /// active.
    Entry,
    /// CODESYS's step action (`A(ACTIVE);`): every scan the step is active.
    Active,
    /// CODESYS's exit step action (`A(EXIT);`): once when the step is left.
    Exit,
}

impl Qual {
    fn from_name(name: &str) -> Option<Qual> {
        Some(match name {
            "N" => Qual::N,
            "R" => Qual::R,
            "S" => Qual::S,
            "L" => Qual::L,
            "D" => Qual::D,
            "P" => Qual::P,
            "P1" => Qual::P1,
            "P0" => Qual::P0,
            "SD" => Qual::Sd,
            "DS" => Qual::Ds,
            "SL" => Qual::Sl,
            "ENTRY" => Qual::Entry,
            "ACTIVE" => Qual::Active,
            "EXIT" => Qual::Exit,
            _ => return None,
        })
    }

    /// L, D, SD, DS and SL take a duration.
    pub(super) fn timed(self) -> bool {
        matches!(self, Qual::L | Qual::D | Qual::Sd | Qual::Ds | Qual::Sl)
    }
}

/// What an association drives: an ACTION of the POU or a BOOL variable.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub(super) enum Target {
    /// The index of the ACTION in the POU's `actions`.
    Action(usize),
    /// The index of the variable in [`Facts::vars`].
    Var(usize),
}

/// One association, resolved.
#[derive(Clone, Debug)]
pub(super) struct Assoc {
    /// The step (its index in the chart).
    pub step: usize,
    /// What it drives.
    pub target: Target,
    /// Its qualifier.
    pub qual: Qual,
    /// Its duration, if timed.
    pub duration: Option<Span>,
}

/// CODESYS's SFC flags plcc implements (BOOL variables the POU declares with these
/// names; CODESYS's "SFC flags").
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub(super) enum SfcFlag {
    /// `SFCInit`: while TRUE, the chart is held in its initial state.
    Init,
    /// `SFCReset`: while TRUE, the chart is put back in its initial state at the
    /// start of each evolution, which then goes on.
    Reset,
    /// `SFCPause`: while TRUE, the chart does not evolve.
    Pause,
}

/// A CODESYS step action (`A(ENTRY);`, `inst.A(ACTIVE);`), resolved.
#[derive(Clone, Debug)]
pub(super) struct StepAction {
    /// The step (its index in the chart).
    pub step: usize,
    /// ENTRY, ACTIVE or EXIT.
    pub qual: Qual,
    /// The POU's ACTION it runs; `None` for an action of an FB instance.
    pub action: Option<usize>,
    /// The name as written (`A`, `inst.A`).
    pub name: Span,
}

/// What the writer needs about a chart that keeps the rules.
#[derive(Clone, Debug, Default)]
pub(super) struct Facts {
    /// The POU's ACTIONs that associations drive (indexes in `actions`), in
    /// declaration order; for the body's chart, every other ACTION of the POU too
    /// (see [`check_pou`]).
    pub actions: Vec<usize>,
    /// BOOL variables used as actions, in order of first use.
    pub vars: Vec<Ident>,
    /// Every association, step by step in text order, but step actions.
    pub assocs: Vec<Assoc>,
    /// CODESYS's step actions (ENTRY, ACTIVE, EXIT), step by step in text order:
    /// called directly, with no action control.
    pub step_actions: Vec<StepAction>,
    /// For each transition, its steps before and after (indexes in the chart).
    pub from: Vec<Vec<usize>>,
    /// See `from`.
    pub to: Vec<Vec<usize>>,
    /// The editors' `COMPUTE_FUNCTION_BLOCKS` action (the blocks of graphical
    /// conditions), outside the matiec profile: run before the transitions are
    /// tested, not through its association (the index in the POU's actions).
    pub compute: Option<usize>,
    /// The steps whose names an earlier chart of the POU has: they are declared as
    /// `<prefix>S_<name>` (CODESYS scopes step names by chart).
    pub renamed: Vec<usize>,
    /// CODESYS's SFC flags the POU declares, with their names as declared.
    pub flags: Vec<(SfcFlag, String)>,
    /// Actions of `actions` that an earlier chart of the POU drives too: their
    /// control in this chart is hidden (`<prefix>K_<action>`), their flags (`A.Q`)
    /// are the earlier chart's.
    pub borrowed: Vec<usize>,
    /// The order transitions are tested in: prioritised ones by ascending
    /// priority (equal ones in text order) inserted before the first of higher
    /// priority, unprioritised ones where they come (as matiec orders them).
    pub order: Vec<usize>,
}

/// The action in which the editors' translator puts the blocks and edge detectors of
/// graphical transition conditions (reference §5.3).
const COMPUTE_FUNCTION_BLOCKS: &str = "COMPUTE_FUNCTION_BLOCKS";

/// True for `COMPUTE_FUNCTION_BLOCKS`, and `COMPUTE_FUNCTION_BLOCKS_<action>` (the
/// blocks of an action's chart).
fn is_compute(name: &str) -> bool {
    name.strip_prefix(COMPUTE_FUNCTION_BLOCKS)
        .is_some_and(|rest| rest.is_empty() || rest.starts_with('_'))
}

fn err(code: &'static str, msg: impl Into<String>, span: Span) -> Diagnostic {
    Diagnostic::error(code, msg.into(), span)
}

/// Checks `chart`, the body of `pou`; `text` is the file's text. `None` when an
/// error was reported.
pub(super) fn check(
    pou: &Pou,
    chart: &Sfc,
    text: &str,
    interner: &Interner,
    profile: super::Profile,
    diags: &mut Vec<Diagnostic>,
) -> Option<Facts> {
    let name_of = |i: &Ident| text[i.span.start as usize..i.span.end as usize].to_string();
    let before = diags.len();
    let mut steps: HashMap<Symbol, usize> = HashMap::new();
    for (k, s) in chart.steps.iter().enumerate() {
        if let Some(&first) = steps.get(&s.name.sym) {
            diags.push(
                err(
                    codes::E_DUPLICATE,
                    format!("step `{}` is declared twice", name_of(&s.name)),
                    s.name.span,
                )
                .with_secondary(chart.steps[first].name.span, "first declared here"),
            );
        } else {
            steps.insert(s.name.sym, k);
        }
    }
    // A step is a variable of the POU (`S.X`): its name must be free.
    for s in &chart.steps {
        let var = pou
            .var_blocks
            .iter()
            .flat_map(|b| &b.decls)
            .flat_map(|d| &d.names)
            .find(|n| n.sym == s.name.sym);
        let action = pou.actions.iter().find(|a| a.name.sym == s.name.sym);
        if let Some(other) = var.map(|v| v.span).or(action.map(|a| a.name.span)) {
            diags.push(
                err(
                    codes::E_DUPLICATE,
                    format!(
                        "step `{}` has the name of a {} of `{}` (names ignore case)",
                        name_of(&s.name),
                        if var.is_some() { "variable" } else { "action" },
                        name_of(&pou.name)
                    ),
                    s.name.span,
                )
                .with_secondary(other, "declared here"),
            );
        }
    }
    if !chart.steps.iter().any(|s| s.initial) {
        diags.push(
            err(
                codes::SFC_TEXT_NO_INITIAL_STEP,
                format!(
                    "the chart of `{}` has no INITIAL_STEP: nothing would ever be active",
                    name_of(&pou.name)
                ),
                chart.span,
            )
            .with_note("mark the step the chart starts in: `INITIAL_STEP Start: … END_STEP`"),
        );
    }
    let mut facts = Facts::default();
    for t in &chart.transitions {
        let resolve = |list: &[Ident], diags: &mut Vec<Diagnostic>| -> Vec<usize> {
            list.iter()
                .filter_map(|i| match steps.get(&i.sym) {
                    Some(&k) => Some(k),
                    None => {
                        diags.push(err(
                            codes::SFC_TEXT_UNKNOWN_STEP,
                            format!("no step named `{}` in this chart", name_of(i)),
                            i.span,
                        ));
                        None
                    }
                })
                .collect()
        };
        let from = resolve(&t.from, diags);
        let to = resolve(&t.to, diags);
        facts.from.push(from);
        facts.to.push(to);
    }
    // Associations.
    let actions: HashMap<Symbol, usize> = pou
        .actions
        .iter()
        .enumerate()
        .map(|(k, a)| (a.name.sym, k))
        .collect();
    let mut used_actions = Vec::new();
    for (k, s) in chart.steps.iter().enumerate() {
        for a in &s.assocs {
            let qual = match &a.qualifier {
                None => Qual::Bare,
                Some(q) => match Qual::from_name(interner.name(q.sym)) {
                    Some(q) => q,
                    None => {
                        diags.push(
                            err(
                                codes::SFC_TEXT_QUALIFIER,
                                format!("`{}` is not an action qualifier", name_of(q)),
                                q.span,
                            )
                            .with_note(
                                "the qualifiers are N, R, S, L, D, P, P1, P0, SD, DS and SL \
                                 (and ENTRY, ACTIVE, EXIT for CODESYS's step actions)",
                            ),
                        );
                        continue;
                    }
                },
            };
            match (qual.timed(), a.duration) {
                (true, None) => diags.push(err(
                    codes::SFC_TEXT_QUALIFIER,
                    format!(
                        "qualifier {} needs a duration: `{}({}, T#2s);`",
                        interner.name(a.qualifier.expect("timed").sym),
                        name_of(&a.action),
                        interner.name(a.qualifier.expect("timed").sym)
                    ),
                    a.span,
                )),
                (false, Some(d)) => diags.push(err(
                    codes::SFC_TEXT_QUALIFIER,
                    "only the qualifiers L, D, SD, DS and SL take a duration",
                    d,
                )),
                _ => {}
            }
            let step_action = matches!(qual, Qual::Entry | Qual::Active | Qual::Exit);
            if let Some(name) = a.qualified {
                if step_action {
                    facts.step_actions.push(StepAction {
                        step: k,
                        qual,
                        action: None,
                        name,
                    });
                } else {
                    diags.push(err(
                        codes::SFC_TEXT_ACTION,
                        format!(
                            "`{}` is an action of an instance: only a step action (ENTRY, ACTIVE, EXIT) can run one",
                            &text[name.start as usize..name.end as usize]
                        ),
                        name,
                    ));
                }
                continue;
            }
            let target = match actions.get(&a.action.sym) {
                Some(&i)
                    if profile != super::Profile::Matiec
                        && is_compute(interner.name(a.action.sym)) =>
                {
                    facts.compute = Some(i);
                    continue;
                }
                Some(&i) if step_action => {
                    facts.step_actions.push(StepAction {
                        step: k,
                        qual,
                        action: Some(i),
                        name: a.action.span,
                    });
                    continue;
                }
                Some(&i) => {
                    if !used_actions.contains(&i) {
                        used_actions.push(i);
                    }
                    Target::Action(i)
                }
                None if step_action => {
                    diags.push(err(
                        codes::SFC_TEXT_ACTION,
                        format!(
                            "`{}` is no ACTION of `{}`: a step action (ENTRY, ACTIVE, EXIT) runs an action",
                            name_of(&a.action),
                            name_of(&pou.name)
                        ),
                        a.action.span,
                    ));
                    continue;
                }
                None if !declared_bool(pou, a.action.sym, interner) => {
                    diags.push(
                        err(
                            codes::SFC_TEXT_ACTION,
                            format!(
                                "`{}` is neither an ACTION of `{}` nor a BOOL variable: an association drives an action",
                                name_of(&a.action),
                                name_of(&pou.name)
                            ),
                            a.action.span,
                        )
                        .with_note("declare `ACTION name: … END_ACTION` in the POU, or use a BOOL variable"),
                    );
                    continue;
                }
                None => match facts.vars.iter().position(|v| v.sym == a.action.sym) {
                    Some(v) => Target::Var(v),
                    None => {
                        facts.vars.push(a.action);
                        Target::Var(facts.vars.len() - 1)
                    }
                },
            };
            facts.assocs.push(Assoc {
                step: k,
                target,
                qual,
                duration: a.duration,
            });
        }
    }
    used_actions.sort_unstable();
    facts.actions = used_actions;
    if diags[before..].iter().any(|d| d.is_error()) {
        return None;
    }
    // Evaluation order.
    for (k, t) in chart.transitions.iter().enumerate() {
        match t.priority {
            None => facts.order.push(k),
            Some((p, _)) => {
                let prio = |j: usize| chart.transitions[j].priority.map_or(0, |(q, _)| q);
                let at = facts
                    .order
                    .iter()
                    .position(|&j| prio(j) > p)
                    .unwrap_or(facts.order.len());
                facts.order.insert(at, k);
            }
        }
    }
    let reached = warn_structure(chart, &facts, &name_of, diags);
    if let Some(safety) = super::safety::check(chart, &facts) {
        if let Some((t, k)) = safety.unsafe_at {
            let tr = &chart.transitions[t];
            let msg = format!(
                "unsafe chart: transition #{} can activate step `{}` while it is active \
                 (a simultaneous branch closed by a selective convergence, or a loop that \
                 laps a branch)",
                t + 1,
                name_of(&chart.steps[k].name)
            );
            if profile == super::Profile::Matiec {
                diags.push(
                    Diagnostic::warning(codes::W_SFC_UNSAFE, msg, tr.head)
                        .with_note("matiec runs it: the step simply stays active"),
                );
            } else {
                diags.push(
                    err(codes::SFC_TEXT_UNSAFE, msg, tr.head)
                        .with_secondary(chart.steps[k].name.span, "this step")
                        .with_note("close a simultaneous divergence with a simultaneous convergence: `TRANSITION FROM (A, B) TO C`"),
                );
                return None;
            }
        }
        for t in safety.dead {
            if facts.from[t].iter().all(|&k| reached[k]) {
                diags.push(Diagnostic::warning(
                    codes::W_SFC_DEAD_TRANSITION,
                    format!(
                        "transition #{} never fires: its steps are never active together",
                        t + 1
                    ),
                    chart.transitions[t].head,
                ));
            }
        }
    }
    Some(facts)
}

/// Checks the charts of `pou`: `charts` holds each with the ACTION it is the body of
/// (`None` for the POU's body; that one first). Beyond each chart's own rules: step
/// names are unique in the POU, and no action written as a chart drives itself
/// through any chain of charts; an action driven by several charts is a warning.
/// `None` when an error was reported.
pub(super) fn check_pou(
    pou: &Pou,
    charts: &[(Option<usize>, &Sfc)],
    text: &str,
    interner: &Interner,
    profile: super::Profile,
    diags: &mut Vec<Diagnostic>,
) -> Option<Vec<Facts>> {
    let name_of = |i: &Ident| text[i.span.start as usize..i.span.end as usize].to_string();
    let facts: Vec<Option<Facts>> = charts
        .iter()
        .map(|&(_, c)| check(pou, c, text, interner, profile, diags))
        .collect();
    let before = diags.len();
    // Step names across the charts: a later chart's step of an earlier one's name
    // is renamed (CODESYS scopes step names by chart); its flags are read by that
    // name in its own chart only.
    let mut renamed: Vec<Vec<usize>> = vec![Vec::new(); charts.len()];
    let mut steps: HashMap<Symbol, usize> = HashMap::new();
    for (c, (_, chart)) in charts.iter().enumerate() {
        for (k, s) in chart.steps.iter().enumerate() {
            match steps.get(&s.name.sym) {
                Some(&first) if first != c => {
                    diags.push(
                        Diagnostic::warning(
                            codes::W_SFC_STEP_RENAMED,
                            format!(
                                "step `{}` has the name of a step of another chart of `{}`: here it is a step of its own, whose flags only this chart reads by that name",
                                name_of(&s.name),
                                name_of(&pou.name)
                            ),
                            s.name.span,
                        )
                    );
                    renamed[c].push(k);
                }
                Some(_) => {}
                None => {
                    steps.insert(s.name.sym, c);
                }
            }
        }
    }
    let mut facts: Vec<Facts> = facts.into_iter().collect::<Option<_>>()?;
    let flags = sfc_flags(pou, text, interner);
    for (f, r) in facts.iter_mut().zip(renamed) {
        f.renamed = r;
        f.flags = flags.clone();
    }
    // Actions driven by several charts: each chart has a control of its own, and
    // the action runs for each (as CODESYS runs it); its flags are the first
    // chart's.
    let mut driver: HashMap<usize, usize> = HashMap::new();
    for k in 0..facts.len() {
        for i in facts[k].actions.clone() {
            match driver.get(&i) {
                Some(&other) => {
                    let chart = |j: usize| match charts[j].0 {
                        None => format!("the chart of `{}`", name_of(&pou.name)),
                        Some(a) => {
                            format!("the chart of action `{}`", name_of(&pou.actions[a].name))
                        }
                    };
                    diags.push(
                        Diagnostic::warning(
                            codes::W_SFC_SHARED,
                            format!(
                                "action `{}` is driven by {} and by {}: it runs for each, and its flags are those of the first",
                                name_of(&pou.actions[i].name),
                                chart(other),
                                chart(k)
                            ),
                            charts[k].1.span,
                        )
                        .with_secondary(charts[other].1.span, "the first chart"),
                    );
                    facts[k].borrowed.push(i);
                }
                None => {
                    driver.insert(i, k);
                }
            }
        }
    }
    // Actions written as charts that drive themselves.
    for (k, &(me, c)) in charts.iter().enumerate() {
        let Some(me) = me else { continue };
        let mut seen = vec![false; charts.len()];
        let mut work = vec![k];
        let mut cycle = false;
        while let Some(j) = work.pop() {
            for &i in &facts[j].actions {
                if i == me {
                    cycle = true;
                }
                if let Some(n) = charts.iter().position(|&(a, _)| a == Some(i)) {
                    if !seen[n] {
                        seen[n] = true;
                        work.push(n);
                    }
                }
            }
        }
        if cycle {
            diags.push(err(
                codes::SFC_TEXT_RECURSIVE,
                format!(
                    "action `{}` is a chart that drives itself (through its own steps or \
                     other actions written as charts): it would run without end",
                    name_of(&pou.actions[me].name)
                ),
                c.span,
            ));
        }
    }
    if diags[before..].iter().any(|d| d.is_error()) {
        return None;
    }
    // Every other ACTION of a POU whose body is a chart has its flags (`A.Q`),
    // driven or not (one no step drives never runs; a step action's stay FALSE),
    // but the blocks of graphical conditions, called directly, and actions another
    // chart drives.
    if charts.first().is_some_and(|c| c.0.is_none()) {
        let driven: Vec<usize> = facts
            .iter()
            .skip(1)
            .flat_map(|f| f.actions.clone())
            .collect();
        let main = &mut facts[0];
        for k in 0..pou.actions.len() {
            if !main.actions.contains(&k) && main.compute != Some(k) && !driven.contains(&k) {
                main.actions.push(k);
            }
        }
        main.actions.sort_unstable();
    }
    Some(facts)
}

/// CODESYS's SFC flags among the BOOL variables `pou` declares.
fn sfc_flags(pou: &Pou, text: &str, interner: &Interner) -> Vec<(SfcFlag, String)> {
    let mut out = Vec::new();
    for b in &pou.var_blocks {
        for d in &b.decls {
            let bool_ty =
                matches!(&d.ty, ast::TypeSpec::Named(t) if interner.name(t.sym) == "BOOL");
            for n in d.names.iter().filter(|_| bool_ty) {
                let flag = match interner.name(n.sym) {
                    "SFCINIT" => SfcFlag::Init,
                    "SFCRESET" => SfcFlag::Reset,
                    "SFCPAUSE" => SfcFlag::Pause,
                    _ => continue,
                };
                out.push((
                    flag,
                    text[n.span.start as usize..n.span.end as usize].to_string(),
                ));
            }
        }
    }
    out
}

/// Warnings about the chart's shape: steps no token can reach, steps with no way out.
/// Returns which steps a token can reach.
fn warn_structure(
    chart: &Sfc,
    facts: &Facts,
    name_of: &dyn Fn(&Ident) -> String,
    diags: &mut Vec<Diagnostic>,
) -> Vec<bool> {
    let n = chart.steps.len();
    let mut reached = vec![false; n];
    let mut work: Vec<usize> = (0..n).filter(|&k| chart.steps[k].initial).collect();
    for &k in &work {
        reached[k] = true;
    }
    while let Some(k) = work.pop() {
        for (t, from) in facts.from.iter().enumerate() {
            if from.contains(&k) {
                for &s in &facts.to[t] {
                    if !reached[s] {
                        reached[s] = true;
                        work.push(s);
                    }
                }
            }
        }
    }
    for (k, s) in chart.steps.iter().enumerate() {
        if !reached[k] {
            diags.push(Diagnostic::warning(
                codes::W_SFC_UNREACHABLE,
                format!(
                    "step `{}` is never active: no transition leads to it from an initial step",
                    name_of(&s.name)
                ),
                s.name.span,
            ));
        } else if !facts.from.iter().any(|f| f.contains(&k)) {
            diags.push(Diagnostic::warning(
                codes::W_SFC_DEAD_END,
                format!(
                    "step `{}` has no way out: no transition leaves it, so the chart stays there",
                    name_of(&s.name)
                ),
                s.name.span,
            ));
        }
    }
    reached
}

/// False only when `name` is declared in `pou` with a type other than BOOL (a
/// variable declared elsewhere, a global, is left to the type checks).
fn declared_bool(pou: &Pou, name: Symbol, interner: &Interner) -> bool {
    for b in &pou.var_blocks {
        for d in &b.decls {
            if d.names.iter().any(|n| n.sym == name) {
                return matches!(&d.ty, ast::TypeSpec::Named(t) if interner.name(t.sym) == "BOOL");
            }
        }
    }
    true
}
