//! The standard's action control (IEC 61131-3, ACTION_CONTROL), written inline for
//! each action with only the parts its associations use.
//!
//! ACTION_CONTROL is a function block of RS flip-flops, TON timers and edge
//! detectors, one of each per qualifier; an instance of it per action costs about
//! 100 bytes, too many for an 8-bit chip. The statements here are the same logic,
//! part by part in the block's order, for the qualifiers the action has, with state
//! in hidden variables `__SFC_<action>_<part>` of the POU (a TON keeps only what its
//! Q needs: running, start). The action's flags are `A.Q` and `A.A`
//! (`__SFC_ACTION` of the standard library): Q the action's state, A TRUE while Q
//! is and for the scan after Q falls (the final execution).

use super::check::{Facts, Qual, Target};
use super::emit::W;
use crate::plcopen::map::Out;
use std::fmt::Write as _;

/// The hidden state variables of the control of `t` (name, type, initial value).
pub(super) fn state(
    w: &W<'_>,
    t: Target,
    facts: &Facts,
) -> Vec<(String, &'static str, &'static str)> {
    let c = w.control(t, facts);
    let used = |q: &[Qual]| {
        facts
            .assocs
            .iter()
            .any(|a| a.target == t && q.contains(&a.qual))
    };
    let mut out = Vec::new();
    let timer = |out: &mut Vec<_>, part: &str| {
        out.push((format!("__SFC_{c}_{part}RUN"), "BOOL", ""));
        out.push((format!("__SFC_{c}_{part}START"), "TIME", ""));
        out.push((format!("__SFC_{c}_{part}Q"), "BOOL", ""));
    };
    if used(&[Qual::S]) {
        out.push((format!("__SFC_{c}_S"), "BOOL", ""));
    }
    if used(&[Qual::L]) {
        timer(&mut out, "L");
    }
    if used(&[Qual::D]) {
        timer(&mut out, "D");
    }
    if used(&[Qual::P]) {
        out.push((format!("__SFC_{c}_PM"), "BOOL", ""));
        out.push((format!("__SFC_{c}_PQ"), "BOOL", ""));
    }
    if used(&[Qual::P1]) {
        out.push((format!("__SFC_{c}_P1M"), "BOOL", ""));
        out.push((format!("__SFC_{c}_P1Q"), "BOOL", ""));
    }
    if used(&[Qual::P0]) {
        out.push((format!("__SFC_{c}_P0M"), "BOOL", " := TRUE"));
        out.push((format!("__SFC_{c}_P0Q"), "BOOL", ""));
    }
    if used(&[Qual::Sd]) {
        out.push((format!("__SFC_{c}_SD"), "BOOL", ""));
        timer(&mut out, "SD");
    }
    if used(&[Qual::Ds]) {
        timer(&mut out, "DS");
        out.push((format!("__SFC_{c}_DS"), "BOOL", ""));
    }
    if used(&[Qual::Sl]) {
        out.push((format!("__SFC_{c}_SL"), "BOOL", ""));
        timer(&mut out, "SL");
    }
    out
}

/// A TON's Q as ACTION_CONTROL's timers give it: TRUE once `input` has been TRUE
/// for the duration `pt`, FALSE as soon as it is not.
fn ton(out: &mut Out, c: &str, part: &str, input: &str, pt: &str) {
    let (run, start, q) = (
        format!("__SFC_{c}_{part}RUN"),
        format!("__SFC_{c}_{part}START"),
        format!("__SFC_{c}_{part}Q"),
    );
    let _ = write!(
        out.text,
        "IF NOT ({input}) THEN\n  {run} := FALSE;\n  {q} := FALSE;\nELSIF NOT {q} THEN\n  \
         IF NOT {run} THEN {run} := TRUE; {start} := __PLC_CLOCK(); END_IF;\n  \
         IF __PLC_CLOCK() - {start} >= {pt} THEN {q} := TRUE; END_IF;\nEND_IF;\n"
    );
}

/// The statements of the control of `t`: its associations combined, the flags Q
/// and A set.
pub(super) fn write(w: &W<'_>, out: &mut Out, t: Target, facts: &Facts) {
    let c = w.control(t, facts);
    let mine: Vec<_> = facts.assocs.iter().filter(|a| a.target == t).collect();
    // The OR of the active steps of the associations with these qualifiers.
    let input = |q: &[Qual]| -> Option<String> {
        let steps: Vec<String> = mine
            .iter()
            .filter(|a| q.contains(&a.qual))
            .map(|a| format!("{}.X", w.step_name(a.step)))
            .collect();
        (!steps.is_empty()).then(|| steps.join(" OR "))
    };
    // The duration: the timed association's whose step is active (the first
    // one's when none is).
    let timed: Vec<_> = mine.iter().filter(|a| a.qual.timed()).collect();
    let pt = if timed.is_empty() {
        String::new()
    } else {
        let dur =
            |a: &super::check::Assoc| format!("({})", w.expr_text(a.duration.expect("timed")));
        let mut e = dur(timed[0]);
        for a in timed.iter().skip(1) {
            e = format!("SEL({}.X, {e}, {})", w.step_name(a.step), dur(a));
        }
        e
    };
    let r = input(&[Qual::R]).unwrap_or_else(|| "FALSE".into());
    let mut q_terms = Vec::new();
    if let Some(n) = input(&[Qual::N, Qual::Bare]) {
        q_terms.push(format!("({n})"));
    }
    if let Some(s) = input(&[Qual::S]) {
        let ff = format!("__SFC_{c}_S");
        let _ = writeln!(out.text, "{ff} := NOT ({r}) AND (({s}) OR {ff});");
        q_terms.push(ff);
    }
    if let Some(l) = input(&[Qual::L]) {
        ton(out, &c, "L", &l, &pt);
        q_terms.push(format!("(({l}) AND NOT __SFC_{c}_LQ)"));
    }
    if let Some(d) = input(&[Qual::D]) {
        ton(out, &c, "D", &d, &pt);
        q_terms.push(format!("__SFC_{c}_DQ"));
    }
    for (q, part) in [(Qual::P, "P"), (Qual::P1, "P1")] {
        if let Some(p) = input(&[q]) {
            let (m, pulse) = (
                format!("__SFC_{c}_{part}M"),
                format!("(({p}) AND NOT __SFC_{c}_{part}M)"),
            );
            let _ = writeln!(out.text, "__SFC_{c}_{part}Q := {pulse};\n{m} := {p};");
            q_terms.push(format!("__SFC_{c}_{part}Q"));
        }
    }
    if let Some(p0) = input(&[Qual::P0]) {
        let m = format!("__SFC_{c}_P0M");
        let _ = writeln!(
            out.text,
            "__SFC_{c}_P0Q := NOT ({p0}) AND NOT {m};\n{m} := NOT ({p0});"
        );
        q_terms.push(format!("__SFC_{c}_P0Q"));
    }
    if let Some(sd) = input(&[Qual::Sd]) {
        let ff = format!("__SFC_{c}_SD");
        let _ = writeln!(out.text, "{ff} := NOT ({r}) AND (({sd}) OR {ff});");
        ton(out, &c, "SD", &ff, &pt);
        q_terms.push(format!("__SFC_{c}_SDQ"));
    }
    if let Some(ds) = input(&[Qual::Ds]) {
        let ff = format!("__SFC_{c}_DS");
        ton(out, &c, "DS", &ds, &pt);
        let _ = writeln!(out.text, "{ff} := NOT ({r}) AND (__SFC_{c}_DSQ OR {ff});");
        q_terms.push(ff);
    }
    if let Some(sl) = input(&[Qual::Sl]) {
        let ff = format!("__SFC_{c}_SL");
        let _ = writeln!(out.text, "{ff} := NOT ({r}) AND (({sl}) OR {ff});");
        ton(out, &c, "SL", &ff, &pt);
        q_terms.push(format!("({ff} AND NOT __SFC_{c}_SLQ)"));
    }
    let q = if q_terms.is_empty() {
        "FALSE".to_string()
    } else {
        q_terms.join(" OR ")
    };
    let _ = writeln!(
        out.text,
        "{c}.Q := {q};\n{c}.A := {c}.Q OR {c}.__QPREV;\n{c}.__QPREV := {c}.Q;"
    );
}
