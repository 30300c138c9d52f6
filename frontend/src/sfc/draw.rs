//! A chart drawn as text (`--emit sfc-text`): each step with its actions, and under
//! it the transitions that leave it, where they lead and on what condition.
//!
//! ```text
//! PROGRAM main: 3 steps, 3 transitions
//!
//! [[Idle]]  (initial)
//!   +--> #1 go  ==> (Fill, Heat)
//!
//! [Fill]
//!   | N  valve
//!   +--> #2 full  --> Idle
//! ```
//!
//! `[[S]]` is an initial step, `[S]` another; `| Q action (duration)` an association;
//! `+--> #k cond --> S` a transition (number k in text order; `==>` when it activates
//! several steps at once, `(with A, B)` when it waits for several steps, `PRIORITY p`
//! when it has one). A step no transition reaches, or that none leaves, is marked.
//! An action written as a chart is drawn after its POU's (`PROGRAM main, ACTION Sub: …`).

use crate::ast::{Pou, PouKind, Sfc};
use std::fmt::Write as _;

/// The drawing of `chart`, the body of `pou` or of its ACTION `action`; `text` is the
/// file's text.
pub(super) fn draw(pou: &Pou, action: Option<usize>, chart: &Sfc, text: &str) -> String {
    let src = |s: plcc_ir::diag::Span| {
        text[s.start as usize..s.end as usize]
            .split_whitespace()
            .collect::<Vec<_>>()
            .join(" ")
    };
    let kind = match pou.kind {
        PouKind::Program => "PROGRAM",
        PouKind::FunctionBlock => "FUNCTION_BLOCK",
        PouKind::Function => "FUNCTION",
    };
    let mut o = String::new();
    let _ = write!(o, "{kind} {}", src(pou.name.span));
    if let Some(a) = action {
        let _ = write!(o, ", ACTION {}", src(pou.actions[a].name.span));
    }
    let _ = writeln!(
        o,
        ": {} steps, {} transitions",
        chart.steps.len(),
        chart.transitions.len()
    );
    let names: Vec<String> = chart.steps.iter().map(|s| src(s.name.span)).collect();
    let same = |a: &crate::ast::Ident, k: usize| a.sym == chart.steps[k].name.sym;
    for (k, s) in chart.steps.iter().enumerate() {
        o.push('\n');
        let reached = s.initial
            || chart
                .transitions
                .iter()
                .any(|t| t.to.iter().any(|i| same(i, k)));
        let (l, r) = if s.initial { ("[[", "]]") } else { ("[", "]") };
        let _ = write!(o, "{l}{}{r}", names[k]);
        if s.initial {
            o.push_str("  (initial)");
        }
        if !reached {
            o.push_str("  (never reached)");
        }
        o.push('\n');
        for a in &s.assocs {
            let q = a.qualifier.map_or("N".to_string(), |q| src(q.span));
            let _ = write!(o, "  | {q:<2} {}", src(a.action.span));
            if let Some(d) = a.duration {
                let _ = write!(o, " ({})", src(d));
            }
            o.push('\n');
        }
        let mut leaves = false;
        for (n, t) in chart.transitions.iter().enumerate() {
            // Listed under the first step it leaves.
            if !t.from.first().is_some_and(|f| same(f, k)) {
                continue;
            }
            leaves = true;
            let cond = match (t.condition, t.il) {
                (Some(c), false) => src(c),
                (Some(c), true) => format!("IL: {}", src(c)),
                (None, _) => "?".into(),
            };
            let _ = write!(o, "  +--> #{} {cond}", n + 1);
            if t.from.len() > 1 {
                let others: Vec<String> = t.from[1..].iter().map(|i| src(i.span)).collect();
                let _ = write!(o, "  (with {})", others.join(", "));
            }
            let to: Vec<String> = t.to.iter().map(|i| src(i.span)).collect();
            if to.len() > 1 {
                let _ = write!(o, "  ==> ({})", to.join(", "));
            } else {
                let _ = write!(o, "  --> {}", to.join(""));
            }
            if let Some((p, _)) = t.priority {
                let _ = write!(o, "  PRIORITY {p}");
            }
            o.push('\n');
        }
        for (n, t) in chart.transitions.iter().enumerate() {
            if t.from.iter().skip(1).any(|i| same(i, k)) {
                leaves = true;
                let _ = writeln!(o, "  +--> #{} (under {})", n + 1, src(t.from[0].span));
            }
        }
        if !leaves {
            o.push_str("  (no way out)\n");
        }
    }
    o
}
