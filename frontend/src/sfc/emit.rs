//! Writes a chart's POU as ST: one call of the body is one evolution of the chart.
//!
//! The variables: a `__SFC_STEP` per step, named as the step (`S.X`, `S.T`,
//! `S.__PREV`); per action, its control named as the action (`A.Q`): the standard's
//! `__SFC_ACTION_CONTROL` FB, or matiec's `__SFC_MATIEC_ACTION` state; a BOOL variable
//! used as an action gets a control named `__SFC_V_<name>`; an action a chart shares
//! with an earlier chart of the POU a control `<prefix>K_<name>`. The ACTIONs the chart
//! drives are renamed `__SFC_A_<name>` (their names belong to their controls). The
//! clock: `__SFC_LAST` (the clock at the last call) and `__SFC_DT` (the time since).
//! An ACTION written as a chart evolves once per execution of the action; its
//! hidden variables start `__SFC_IN_<action>_` and its steps are variables of the
//! POU as the body's are (step names are unique in the POU, as in CODESYS).
//!
//! The body, under [`Profile::Iec`]: advance the active steps' T; test the transitions
//! in evaluation order on the states the previous call left, a firing one
//! deactivating its steps at once (so one branch of a selective divergence fires);
//! activate the steps after the fired ones (T := 0); run every action control and
//! the actions whose A is TRUE, in declaration order. [`Profile::Codesys`] runs the
//! actions before the transitions. [`Profile::Matiec`] follows matiec's algorithm
//! step by step (reference §6.2; docs/sfc.md).

use super::check::{Facts, Qual, Target};
use super::Profile;
use crate::ast::{Pou, PouKind, Sfc};
use crate::plcopen::map::Out;
use crate::plcopen::xml::{Piece, Text};
use plcc_ir::diag::Span;
use std::fmt::Write as _;

/// A chart of a POU: its body's, or an ACTION's written as a chart.
pub(super) struct Chart<'a> {
    /// The chart.
    pub sfc: &'a Sfc,
    /// The ACTION it is the body of (an index in the POU's `actions`); `None` for the
    /// POU's body.
    pub action: Option<usize>,
    /// What the checks found.
    pub facts: Facts,
}

/// Writes `pou`, whose body or actions are `charts`, as ST to `out`.
pub(super) fn pou<'a>(
    out: &mut Out,
    pou: &'a Pou,
    charts: &[Chart<'a>],
    text: &'a str,
    profile: Profile,
) {
    let writer = |c: &Chart<'a>| W::new(text, pou, c);
    // The header and declarations, as written.
    let header_end = pou
        .var_blocks
        .iter()
        .map(|b| b.span.end)
        .chain(std::iter::once(pou.name.span.end))
        .max()
        .unwrap_or(pou.name.span.end);
    // Copies the POU's own text (any chart's writer does).
    let first = writer(&charts[0]);
    first.copy(out, Span::new(pou.span.file, pou.span.start, header_end));
    out.push("\nVAR\n");
    for c in charts {
        writer(c).variables(out, &c.facts, profile);
    }
    out.push("END_VAR\nVAR_TEMP\n");
    for c in charts {
        writer(c).temporaries(out);
    }
    out.push("END_VAR\n");
    // The body: the chart's evolution, or the body as written.
    match charts.iter().find(|c| c.action.is_none()) {
        Some(c) => writer(c).evolution(out, &c.facts, profile),
        None => {
            if pou.body.span.end > pou.body.span.start {
                first.copy(out, pou.body.span);
                out.push("\n");
            }
        }
    }
    // The actions: those a chart drives renamed, those written as charts their
    // chart's evolution, the others as written.
    let driven = |k: usize| {
        charts.iter().any(|c| {
            c.facts.actions.contains(&k) || c.facts.step_actions.iter().any(|a| a.action == Some(k))
        })
    };
    for (k, a) in pou.actions.iter().enumerate() {
        let start = out.pos();
        out.push(if driven(k) {
            "ACTION __SFC_A_"
        } else {
            "ACTION "
        });
        first.copy(out, a.name.span);
        out.push(":\n");
        if let Some(c) = charts.iter().find(|c| c.action == Some(k)) {
            writer(c).evolution(out, &c.facts, profile);
        } else if a.body.span.end > a.body.span.start {
            first.copy(out, a.body.span);
        }
        out.push("\nEND_ACTION\n");
        out.mark(start, a.span.start..a.span.end);
    }
    // The transitions written in IL, each an action storing its result.
    for c in charts {
        let w = writer(c);
        for (k, t) in c.sfc.transitions.iter().enumerate() {
            let (true, Some(cond)) = (t.il, t.condition) else {
                continue;
            };
            let start = out.pos();
            let _ = writeln!(out.text, "ACTION {}TC{k}:", w.p);
            w.copy_expr(out, cond);
            let _ = writeln!(out.text, "\nST {}C{k}\nEND_ACTION", w.p);
            out.mark(start, t.head.start..t.head.end);
        }
    }
    out.push(match pou.kind {
        PouKind::Program => "END_PROGRAM\n\n",
        PouKind::FunctionBlock => "END_FUNCTION_BLOCK\n\n",
        PouKind::Function => "END_FUNCTION\n\n",
    });
}

/// The writer of one chart of a POU.
pub(super) struct W<'a> {
    text: &'a str,
    chart: &'a Sfc,
    pou: &'a Pou,
    /// The prefix of the chart's hidden variables (`__SFC_` for the body's chart,
    /// `__SFC_IN_<action>_` for an action's).
    p: String,
    /// The chart's steps whose names an earlier chart of the POU has taken.
    renamed: Vec<usize>,
}

impl<'a> W<'a> {
    /// The writer of `chart`, a chart of `pou`.
    fn new(text: &'a str, pou: &'a Pou, chart: &Chart<'a>) -> W<'a> {
        W {
            text,
            chart: chart.sfc,
            pou,
            renamed: chart.facts.renamed.clone(),
            p: match chart.action {
                None => "__SFC_".to_string(),
                Some(i) => {
                    let n = pou.actions[i].name.span;
                    format!("__SFC_IN_{}_", &text[n.start as usize..n.end as usize])
                }
            },
        }
    }

    /// Copies the file's text at `span`, mapped byte for byte.
    fn copy(&self, out: &mut Out, span: Span) {
        let value = self.source(span);
        out.push_text(&Text {
            value: value.to_string(),
            range: span.start..span.end,
            exact: vec![Piece {
                at: 0,
                src: span.start,
                len: span.end - span.start,
            }],
        });
    }

    /// Generated text made from the element at `from`.
    fn gen(&self, out: &mut Out, s: &str, from: Span) {
        let start = out.pos();
        out.push(s);
        out.mark(start, from.start..from.end);
    }

    /// The file's text at `span`.
    pub(super) fn source(&self, span: Span) -> &str {
        &self.text[span.start as usize..span.end as usize]
    }

    /// The name of step `k`: as written, or `<prefix>S_<name>` when an earlier chart
    /// of the POU has a step of that name.
    pub(super) fn step_name(&self, k: usize) -> String {
        let n = self.source(self.chart.steps[k].name.span);
        if self.renamed.contains(&k) {
            format!("{}S_{n}", self.p)
        } else {
            n.to_string()
        }
    }

    /// The text of an expression of the chart (a condition, a duration) at `span`,
    /// the flags of its renamed steps (`S.X`) renamed, with the pieces copied as
    /// written.
    fn expr(&self, span: Span) -> Text {
        let src = self.source(span);
        let b = src.as_bytes();
        let mut value = String::new();
        let mut exact = Vec::new();
        let mut copied = 0;
        let mut i = 0;
        let ident = |c: u8| c.is_ascii_alphanumeric() || c == b'_';
        while i < b.len() {
            if !(b[i].is_ascii_alphabetic() || b[i] == b'_') || (i > 0 && ident(b[i - 1])) {
                i += 1;
                continue;
            }
            let start = i;
            while i < b.len() && ident(b[i]) {
                i += 1;
            }
            let word = &src[start..i];
            let dot = src[i..].trim_start().starts_with('.');
            let step = self.renamed.iter().find(|&&k| {
                self.source(self.chart.steps[k].name.span)
                    .eq_ignore_ascii_case(word)
            });
            if let (true, Some(&k)) = (dot, step) {
                exact.push(Piece {
                    at: value.len() as u32,
                    src: span.start + copied as u32,
                    len: (start - copied) as u32,
                });
                value.push_str(&src[copied..start]);
                value.push_str(&self.step_name(k));
                copied = i;
            }
        }
        exact.push(Piece {
            at: value.len() as u32,
            src: span.start + copied as u32,
            len: (b.len() - copied) as u32,
        });
        value.push_str(&src[copied..]);
        Text {
            value,
            range: span.start..span.end,
            exact,
        }
    }

    /// Copies an expression of the chart (see [`Self::expr`]).
    fn copy_expr(&self, out: &mut Out, span: Span) {
        out.push_text(&self.expr(span));
    }

    /// The text of an expression of the chart (see [`Self::expr`]).
    pub(super) fn expr_text(&self, span: Span) -> String {
        self.expr(span).value
    }

    /// The name of ACTION `i` as written.
    fn action_name(&self, i: usize) -> &str {
        self.source(self.pou.actions[i].name.span)
    }

    /// The name of the control of `target`.
    pub(super) fn control(&self, t: Target, facts: &Facts) -> String {
        match t {
            Target::Action(i) if facts.borrowed.contains(&i) => {
                format!("{}K_{}", self.p, self.action_name(i))
            }
            Target::Action(i) => self.action_name(i).to_string(),
            Target::Var(v) => {
                format!("{}V_{}", self.p, self.source(facts.vars[v].span))
            }
        }
    }

    /// The chart's variables: its steps, the controls of what it drives, its
    /// clock.
    fn variables(&self, out: &mut Out, facts: &Facts, profile: Profile) {
        for (k, s) in self.chart.steps.iter().enumerate() {
            let start = out.pos();
            out.push("  ");
            if self.renamed.contains(&k) {
                out.push(&self.step_name(k));
            } else {
                self.copy(out, s.name.span);
            }
            out.push(if s.initial {
                " : __SFC_STEP := (X := TRUE);\n"
            } else {
                " : __SFC_STEP;\n"
            });
            out.mark(start, s.span.start..s.span.end);
        }
        let control_ty = match profile {
            Profile::Matiec => "__SFC_MATIEC_ACTION",
            _ => "__SFC_ACTION",
        };
        for &i in &facts.actions {
            let a = &self.pou.actions[i];
            let start = out.pos();
            out.push("  ");
            if facts.borrowed.contains(&i) {
                out.push(&self.control(Target::Action(i), facts));
            } else {
                self.copy(out, a.name.span);
            }
            let _ = writeln!(out.text, " : {control_ty};");
            out.mark(start, a.name.span.start..a.name.span.end);
        }
        for (v, name) in facts.vars.iter().enumerate() {
            let c = self.control(Target::Var(v), facts);
            self.gen(out, &format!("  {c} : {control_ty};\n"), name.span);
        }
        if profile != Profile::Matiec {
            for t in targets(facts) {
                for (name, ty, init) in super::control::state(self, t, facts) {
                    let _ = writeln!(out.text, "  {name} : {ty}{init};");
                }
            }
        }
        let p = &self.p;
        for k in Self::stepped(facts) {
            let _ = writeln!(out.text, "  {p}W{k} : BOOL;");
        }
        for (k, t) in self.chart.transitions.iter().enumerate() {
            if t.il {
                let _ = writeln!(out.text, "  {p}C{k} : BOOL;");
            }
        }
        let _ = writeln!(out.text, "  {p}STARTED : BOOL;\n  {p}LAST : TIME;");
    }

    /// The chart's temporaries: the time since the last call, the fired flags.
    fn temporaries(&self, out: &mut Out) {
        let p = &self.p;
        let _ = writeln!(out.text, "  {p}DT : TIME;");
        for k in 0..self.chart.transitions.len() {
            let _ = writeln!(out.text, "  {p}F{k} : BOOL;");
        }
    }

    /// One evolution of the chart under `profile`.
    fn evolution(&self, out: &mut Out, facts: &Facts, profile: Profile) {
        self.clock(out);
        // CODESYS's SFC flags, when the POU declares them: SFCInit and SFCReset put
        // the chart back in its initial state; under SFCInit (and SFCPause) nothing
        // else happens.
        let flag =
            |k: super::check::SfcFlag| facts.flags.iter().find(|f| f.0 == k).map(|f| f.1.clone());
        let (init, reset, pause) = (
            flag(super::check::SfcFlag::Init),
            flag(super::check::SfcFlag::Reset),
            flag(super::check::SfcFlag::Pause),
        );
        let resets: Vec<String> = init.iter().chain(&reset).cloned().collect();
        if !resets.is_empty() {
            let _ = writeln!(out.text, "IF {} THEN", resets.join(" OR "));
            self.reset(out, facts, profile);
            out.push("END_IF;\n");
        }
        let stops: Vec<String> = init.iter().chain(&pause).cloned().collect();
        if !stops.is_empty() {
            let _ = writeln!(out.text, "IF NOT ({}) THEN", stops.join(" OR "));
        }
        self.step_times(out);
        match profile {
            Profile::Iec => {
                self.transitions(out, facts, true);
                self.step_actions(out, facts);
                self.actions_iec(out, facts);
            }
            Profile::Codesys => {
                self.step_actions(out, facts);
                self.actions_iec(out, facts);
                self.transitions(out, facts, true);
            }
            Profile::Matiec => self.matiec(out, facts),
        }
        if !stops.is_empty() {
            out.push("END_IF;\n");
        }
    }

    /// The chart put back in its initial state (CODESYS's SFCInit, SFCReset): the
    /// initial steps active, the others not, times zero, every action control and
    /// step action as at cold start.
    fn reset(&self, out: &mut Out, facts: &Facts, profile: Profile) {
        for (k, s) in self.chart.steps.iter().enumerate() {
            let n = self.step_name(k);
            let x = if s.initial { "TRUE" } else { "FALSE" };
            let _ = writeln!(
                out.text,
                "  {n}.X := {x}; {n}.T := T#0s; {n}.__PREV := FALSE;"
            );
        }
        for t in targets(facts) {
            let c = self.control(t, facts);
            if profile == Profile::Matiec {
                let _ = writeln!(
                    out.text,
                    "  {c}.Q := FALSE; {c}.__STORED := FALSE; {c}.__SET := FALSE; {c}.__RESET := FALSE; \
                     {c}.__SET_REMAINING := T#0s; {c}.__RESET_REMAINING := T#0s;"
                );
            } else {
                let _ = writeln!(
                    out.text,
                    "  {c}.Q := FALSE; {c}.A := FALSE; {c}.__QPREV := FALSE;"
                );
                for (name, ty, init) in super::control::state(self, t, facts) {
                    let v = match (ty, init.contains("TRUE")) {
                        ("BOOL", true) => "TRUE",
                        ("BOOL", false) => "FALSE",
                        _ => "T#0s",
                    };
                    let _ = writeln!(out.text, "  {name} := {v};");
                }
            }
        }
        let p = &self.p;
        for k in Self::stepped(facts) {
            let _ = writeln!(out.text, "  {p}W{k} := FALSE;");
        }
    }

    /// The time since the last call.
    fn clock(&self, out: &mut Out) {
        let p = &self.p;
        let _ = write!(
            out.text,
            "IF NOT {p}STARTED THEN\n  {p}STARTED := TRUE;\n  {p}LAST := __PLC_CLOCK();\nEND_IF;\n\
             {p}DT := __PLC_CLOCK() - {p}LAST;\n{p}LAST := {p}LAST + {p}DT;\n",
        );
    }

    /// The active steps' T advanced (and every step's PREV kept).
    fn step_times(&self, out: &mut Out) {
        let p = &self.p;
        for (k, s) in self.chart.steps.iter().enumerate() {
            let n = self.step_name(k);
            self.gen(
                out,
                &format!("{n}.__PREV := {n}.X;\nIF {n}.X THEN {n}.T := {n}.T + {p}DT; END_IF;\n"),
                s.name.span,
            );
        }
    }

    /// `S1.X AND S2.X`: all the steps before transition `t` are active.
    fn sources_active(&self, facts: &Facts, t: usize) -> String {
        facts.from[t]
            .iter()
            .map(|&k| format!("{}.X", self.step_name(k)))
            .collect::<Vec<_>>()
            .join(" AND ")
    }

    /// The fire test of every transition in evaluation order (a fired one
    /// deactivating its steps at once when `exclusive`, else only prioritised
    /// ones), then the activation of the steps after the fired ones.
    fn transitions(&self, out: &mut Out, facts: &Facts, exclusive: bool) {
        // The blocks of graphical conditions, computed for the tests (not under
        // matiec, which runs them with the actions, after the tests: one scan late).
        if let Some(i) = facts.compute {
            self.copy(out, self.pou.actions[i].name.span);
            out.push("();\n");
        }
        for &t in &facts.order {
            let tr = &self.chart.transitions[t];
            let start = out.pos();
            let _ = write!(
                out.text,
                "{p}F{t} := FALSE;\nIF {} THEN\n",
                self.sources_active(facts, t),
                p = self.p
            );
            if tr.il {
                // The IL list is an action of its own that stores its result.
                let _ = write!(out.text, "  {p}TC{t}();\n  IF ({p}C{t}", p = self.p);
            } else {
                out.push("  IF (");
                if let Some(c) = tr.condition {
                    self.copy_expr(out, c);
                }
            }
            let _ = write!(out.text, ") THEN\n    {}F{t} := TRUE;\n", self.p);
            if exclusive || tr.priority.is_some() {
                for &k in &facts.from[t] {
                    let _ = writeln!(out.text, "    {}.X := FALSE;", self.step_name(k));
                }
            }
            out.push("  END_IF;\nEND_IF;\n");
            out.mark(start, tr.head.start..tr.head.end);
        }
        if !exclusive {
            for (t, tr) in self.chart.transitions.iter().enumerate() {
                if tr.priority.is_some() {
                    continue;
                }
                let start = out.pos();
                let _ = writeln!(out.text, "IF {}F{t} THEN", self.p);
                for &k in &facts.from[t] {
                    let _ = writeln!(out.text, "  {}.X := FALSE;", self.step_name(k));
                }
                out.push("END_IF;\n");
                out.mark(start, tr.head.start..tr.head.end);
            }
        }
        for (t, tr) in self.chart.transitions.iter().enumerate() {
            let start = out.pos();
            let _ = writeln!(out.text, "IF {}F{t} THEN", self.p);
            for &k in &facts.to[t] {
                let n = self.step_name(k);
                let _ = writeln!(out.text, "  {n}.X := TRUE;\n  {n}.T := T#0s;");
            }
            out.push("END_IF;\n");
            out.mark(start, tr.head.start..tr.head.end);
        }
    }

    /// The steps (indexes) that have step actions, in text order.
    fn stepped(facts: &Facts) -> Vec<usize> {
        let mut out: Vec<usize> = facts.step_actions.iter().map(|a| a.step).collect();
        out.sort_unstable();
        out.dedup();
        out
    }

    /// CODESYS's step actions, in its order: the exit actions of the steps left
    /// since the last time, the entry actions of the steps entered, then the actions
    /// of the active steps; each step in text order. `<prefix>W<k>` is whether step k
    /// was active then.
    fn step_actions(&self, out: &mut Out, facts: &Facts) {
        if facts.step_actions.is_empty() {
            return;
        }
        let p = &self.p;
        for (qual, cond) in [
            (Qual::Exit, "NOT {n}.X AND {w}"),
            (Qual::Entry, "{n}.X AND NOT {w}"),
            (Qual::Active, "{n}.X"),
        ] {
            if qual == Qual::Active {
                for k in Self::stepped(facts) {
                    let _ = writeln!(out.text, "{p}W{k} := {}.X;", self.step_name(k));
                }
            }
            for a in facts.step_actions.iter().filter(|a| a.qual == qual) {
                let test = cond
                    .replace("{n}", &self.step_name(a.step))
                    .replace("{w}", &format!("{p}W{}", a.step));
                let start = out.pos();
                let _ = write!(out.text, "IF {test} THEN ");
                match a.action {
                    Some(i) => {
                        let _ = write!(out.text, "__SFC_A_{}", self.action_name(i));
                    }
                    // An FB instance's action, as written.
                    None => self.copy(out, a.name),
                }
                out.push("(); END_IF;\n");
                let from = self.chart.steps[a.step].span;
                out.mark(start, from.start..from.end);
            }
        }
    }

    /// The standard's action control: each control called with its associations
    /// combined, each action run while its A is TRUE, in declaration order; a BOOL
    /// variable action takes its control's Q.
    fn actions_iec(&self, out: &mut Out, facts: &Facts) {
        for t in targets(facts) {
            let c = self.control(t, facts);
            let from = match t {
                Target::Action(i) => self.pou.actions[i].name.span,
                Target::Var(v) => facts.vars[v].span,
            };
            let start = out.pos();
            super::control::write(self, out, t, facts);
            match t {
                Target::Action(i) => {
                    let a = self.action_name(i);
                    let _ = writeln!(out.text, "IF {c}.A THEN __SFC_A_{a}(); END_IF;");
                }
                Target::Var(v) => {
                    self.copy(out, facts.vars[v].span);
                    let _ = writeln!(out.text, " := {c}.Q;");
                }
            }
            out.mark(start, from.start..from.end);
        }
    }

    /// matiec's evolution (reference §6.2, steps 3 to 10; 1 and 2 are [`Self::clock`]).
    fn matiec(&self, out: &mut Out, facts: &Facts) {
        let targets = targets(facts);
        // 3: the states start off; stored timers count down.
        for &t in &targets {
            let c = self.control(t, facts);
            let _ = write!(
                out.text,
                "{c}.Q := FALSE;\n{c}.__SET := FALSE;\n{c}.__RESET := FALSE;\n\
                 IF {c}.__SET_REMAINING > T#0s THEN\n  {c}.__SET_REMAINING := {c}.__SET_REMAINING - {p}DT;\n  \
                 IF {c}.__SET_REMAINING <= T#0s THEN {c}.__SET_REMAINING := T#0s; {c}.__SET := TRUE; END_IF;\nEND_IF;\n\
                 IF {c}.__RESET_REMAINING > T#0s THEN\n  {c}.__RESET_REMAINING := {c}.__RESET_REMAINING - {p}DT;\n  \
                 IF {c}.__RESET_REMAINING <= T#0s THEN {c}.__RESET_REMAINING := T#0s; {c}.__RESET := TRUE; END_IF;\nEND_IF;\n",
                p = self.p
            );
        }
        // 4 to 6: transitions.
        self.transitions(out, facts, false);
        // 7: associations, step by step in text order; the last write wins.
        for a in &facts.assocs {
            let c = self.control(a.target, facts);
            let n = self.step_name(a.step);
            let var = match a.target {
                Target::Var(v) => Some(self.source(facts.vars[v].span).to_string()),
                Target::Action(_) => None,
            };
            let on = match &var {
                Some(v) => format!("{v} := TRUE;"),
                None => format!("{c}.Q := TRUE;"),
            };
            let off = match &var {
                Some(v) => format!("{v} := FALSE;"),
                None => format!("{c}.Q := FALSE;"),
            };
            let activated = format!("{n}.X AND NOT {n}.__PREV");
            let deactivated = format!("NOT {n}.X AND {n}.__PREV");
            let start = out.pos();
            let dur = |w: &Self, out: &mut Out| {
                out.push("(");
                w.copy_expr(out, a.duration.expect("timed"));
                out.push(")");
            };
            match a.qual {
                // Not among the associations (see `Facts::step_actions`).
                Qual::Entry | Qual::Active | Qual::Exit => {}
                Qual::N => {
                    let _ = writeln!(
                        out.text,
                        "IF {n}.X THEN {on} ELSIF {deactivated} THEN {off} END_IF;"
                    );
                }
                Qual::Bare => {
                    if var.is_none() {
                        let _ = writeln!(out.text, "IF {n}.X THEN {on} END_IF;");
                    }
                }
                Qual::S => {
                    let _ = writeln!(out.text, "IF {n}.X THEN {c}.__SET := TRUE; END_IF;");
                }
                Qual::R => {
                    let _ = writeln!(out.text, "IF {n}.X THEN {c}.__RESET := TRUE; END_IF;");
                }
                Qual::L => {
                    let _ = write!(out.text, "IF {n}.X AND {n}.T < ");
                    dur(self, out);
                    let _ = writeln!(
                        out.text,
                        " THEN {on} ELSIF {n}.X OR {n}.__PREV THEN {off} END_IF;"
                    );
                }
                Qual::D => {
                    let _ = write!(out.text, "IF {n}.X AND {n}.T >= ");
                    dur(self, out);
                    let _ = writeln!(
                        out.text,
                        " THEN {on} ELSIF {deactivated} THEN {off} END_IF;"
                    );
                }
                Qual::P | Qual::P1 => {
                    let _ = writeln!(out.text, "IF {activated} THEN {on} ELSE {off} END_IF;");
                }
                Qual::P0 => {
                    let _ = writeln!(out.text, "IF {deactivated} THEN {on} ELSE {off} END_IF;");
                }
                Qual::Sl => {
                    let _ = write!(
                        out.text,
                        "IF {activated} THEN {c}.__SET := TRUE; {c}.__RESET_REMAINING := "
                    );
                    dur(self, out);
                    out.push("; END_IF;\n");
                }
                Qual::Sd => {
                    let _ = write!(out.text, "IF {activated} THEN {c}.__SET_REMAINING := ");
                    dur(self, out);
                    out.push("; END_IF;\n");
                }
                Qual::Ds => {
                    let _ = write!(out.text, "IF {activated} THEN {c}.__SET_REMAINING := ");
                    dur(self, out);
                    let _ = writeln!(
                        out.text,
                        "; ELSIF {deactivated} THEN {c}.__SET_REMAINING := T#0s; END_IF;"
                    );
                }
            }
            let from = self.chart.steps[a.step].span;
            out.mark(start, from.start..from.end);
        }
        // 8: stored states.
        for &t in &targets {
            let c = self.control(t, facts);
            let _ = write!(
                out.text,
                "IF {c}.__SET THEN {c}.__STORED := TRUE; {c}.__SET_REMAINING := T#0s; END_IF;\n\
                 IF {c}.__RESET THEN {c}.__STORED := FALSE; {c}.__RESET_REMAINING := T#0s; END_IF;\n\
                 {c}.Q := {c}.Q OR {c}.__STORED;\n"
            );
        }
        // 9: BOOL variables set or reset.
        for v in 0..facts.vars.len() {
            let c = self.control(Target::Var(v), facts);
            let start = out.pos();
            let _ = write!(out.text, "IF {c}.__RESET THEN ");
            self.copy(out, facts.vars[v].span);
            let _ = write!(out.text, " := FALSE; ELSIF {c}.__SET THEN ");
            self.copy(out, facts.vars[v].span);
            out.push(" := TRUE; END_IF;\n");
            out.mark(start, facts.vars[v].span.start..facts.vars[v].span.end);
        }
        self.step_actions(out, facts);
        // 10: the actions whose state is on, in declaration order.
        for &i in &facts.actions {
            let c = self.control(Target::Action(i), facts);
            let a = self.action_name(i);
            let _ = writeln!(out.text, "IF {c}.Q THEN __SFC_A_{a}(); END_IF;");
        }
    }
}

/// What the chart drives: its ACTIONs in declaration order, then its BOOL variables in
/// order of first use.
fn targets(facts: &Facts) -> Vec<Target> {
    facts
        .actions
        .iter()
        .map(|&i| Target::Action(i))
        .chain((0..facts.vars.len()).map(Target::Var))
        .collect()
}
