//! The chart checks and the text written for a chart.

use crate::intern::Interner;
use crate::source::{SourceFile, SourceMap};
use plcc_ir::diag::Diagnostic;

/// Parses `text` as an ST file and expands its charts under `profile`: the
/// diagnostics, and the generated ST if any.
fn expand(text: &str, profile: super::Profile) -> (Vec<Diagnostic>, Option<String>) {
    let mut sources = SourceMap::default();
    let file = sources.add(SourceFile::new("t.st".to_string(), text.to_string()));
    let mut interner = Interner::new();
    let mut diags = Vec::new();
    let unit = crate::st::parse(file, text, &mut interner, &mut diags);
    let mut units = vec![unit];
    let views = super::expand(
        &mut units,
        &mut sources,
        &mut interner,
        profile,
        &[],
        &mut diags,
    );
    let st = views.first().map(|v| sources.get(v.st).text.to_string());
    (diags, st)
}

fn codes(d: &[Diagnostic]) -> Vec<&str> {
    d.iter().map(|d| d.code).collect()
}

#[test]
fn a_chart_needs_an_initial_step_known_steps_and_good_qualifiers() {
    let (d, st) = expand(
        "PROGRAM p VAR x : BOOL; END_VAR\n\
         STEP A: act(L); act(Q); act(N, T#1s); END_STEP\n\
         TRANSITION FROM A TO Nowhere := x; END_TRANSITION\n\
         ACTION act: x := TRUE; END_ACTION\n\
         END_PROGRAM",
        super::Profile::Iec,
    );
    assert!(st.is_none(), "a chart with errors is not written");
    let c = codes(&d);
    assert!(c.contains(&"E0780"), "{c:?}");
    assert!(c.contains(&"E0781"), "{c:?}");
    assert_eq!(c.iter().filter(|c| **c == "E0782").count(), 3, "{c:?}");
}

#[test]
fn unreachable_steps_and_dead_ends_are_warnings() {
    let (d, st) = expand(
        "PROGRAM p VAR x : BOOL; END_VAR\n\
         INITIAL_STEP A: END_STEP\n\
         TRANSITION FROM A TO B := x; END_TRANSITION\n\
         STEP B: END_STEP\n\
         STEP Island: END_STEP\n\
         TRANSITION FROM Island TO A := x; END_TRANSITION\n\
         END_PROGRAM",
        super::Profile::Iec,
    );
    assert_eq!(codes(&d), ["W0781", "W0780"]);
    assert!(st.is_some());
}

#[test]
fn the_profiles_order_the_phases() {
    let chart = "PROGRAM p VAR x : BOOL; n : INT; END_VAR\n\
         INITIAL_STEP A: act(N); END_STEP\n\
         TRANSITION FROM A TO B := x; END_TRANSITION\n\
         STEP B: END_STEP\n\
         TRANSITION FROM B TO A := NOT x; END_TRANSITION\n\
         ACTION act: n := n + 1; END_ACTION\n\
         END_PROGRAM";
    let pos = |st: &str, s: &str| st.find(s).unwrap_or_else(|| panic!("`{s}` in\n{st}"));
    let (_, iec) = expand(chart, super::Profile::Iec);
    let iec = iec.expect("written");
    assert!(pos(&iec, "__SFC_F0 := FALSE") < pos(&iec, "act("));
    let (_, cds) = expand(chart, super::Profile::Codesys);
    let cds = cds.expect("written");
    assert!(pos(&cds, "act(") < pos(&cds, "__SFC_F0 := FALSE"));
    let (_, mat) = expand(chart, super::Profile::Matiec);
    let mat = mat.expect("written");
    assert!(mat.contains("act : __SFC_MATIEC_ACTION"));
    assert!(mat.contains("IF act.Q THEN __SFC_A_act(); END_IF;"));
}

#[test]
fn a_chart_is_drawn_step_by_step() {
    let text = "PROGRAM p VAR go, full : BOOL; END_VAR\n\
         INITIAL_STEP Idle: END_STEP\n\
         TRANSITION (PRIORITY := 1) FROM Idle TO (Fill, Wait) := go; END_TRANSITION\n\
         STEP Fill: Valve(L, T#2s); END_STEP\n\
         STEP Wait: END_STEP\n\
         TRANSITION FROM (Fill, Wait) TO Idle := full; END_TRANSITION\n\
         STEP Lost: END_STEP\n\
         ACTION Valve: full := TRUE; END_ACTION\n\
         END_PROGRAM";
    let mut sources = SourceMap::default();
    let file = sources.add(SourceFile::new("t.st".to_string(), text.to_string()));
    let mut interner = Interner::new();
    let mut diags = Vec::new();
    let mut units = vec![crate::st::parse(file, text, &mut interner, &mut diags)];
    let views = super::expand(
        &mut units,
        &mut sources,
        &mut interner,
        super::Profile::Iec,
        &[],
        &mut diags,
    );
    assert_eq!(
        views[0].drawing,
        "PROGRAM p: 4 steps, 2 transitions\n\
         \n[[Idle]]  (initial)\n  +--> #1 go  ==> (Fill, Wait)  PRIORITY 1\n\
         \n[Fill]\n  | L  Valve (T#2s)\n  +--> #2 full  (with Wait)  --> Idle\n\
         \n[Wait]\n  +--> #2 (under Fill)\n\
         \n[Lost]  (never reached)\n  (no way out)\n"
    );
}

#[test]
fn unsafe_charts_are_errors_under_iec_and_warnings_under_matiec() {
    let chart = "PROGRAM p VAR go, x, y : BOOL; END_VAR\n\
         INITIAL_STEP S0: END_STEP\n\
         TRANSITION FROM S0 TO (A, B) := go; END_TRANSITION\n\
         STEP A: END_STEP\nSTEP B: END_STEP\n\
         TRANSITION FROM A TO C := x; END_TRANSITION\n\
         TRANSITION FROM B TO C := y; END_TRANSITION\n\
         STEP C: END_STEP\n\
         TRANSITION FROM C TO S0 := TRUE; END_TRANSITION\n\
         END_PROGRAM";
    let (d, st) = expand(chart, super::Profile::Iec);
    assert_eq!(codes(&d), ["E0784"]);
    assert!(st.is_none());
    let (d, st) = expand(chart, super::Profile::Matiec);
    assert_eq!(codes(&d), ["W0782"]);
    assert!(st.is_some());
    // Closed by a simultaneous convergence, it is safe.
    let safe = chart.replace(
        "TRANSITION FROM A TO C := x; END_TRANSITION\nTRANSITION FROM B TO C := y; END_TRANSITION",
        "TRANSITION FROM (A, B) TO C := x AND y; END_TRANSITION",
    );
    let (d, _) = expand(&safe, super::Profile::Iec);
    assert!(d.is_empty(), "{:?}", codes(&d));
}

#[test]
fn a_convergence_of_exclusive_branches_never_fires() {
    let (d, st) = expand(
        "PROGRAM p VAR x, y : BOOL; END_VAR\n\
         INITIAL_STEP S0: END_STEP\n\
         TRANSITION FROM S0 TO A := x; END_TRANSITION\n\
         TRANSITION FROM S0 TO B := y; END_TRANSITION\n\
         STEP A: END_STEP\nSTEP B: END_STEP\n\
         TRANSITION FROM (A, B) TO S0 := TRUE; END_TRANSITION\n\
         END_PROGRAM",
        super::Profile::Iec,
    );
    assert_eq!(codes(&d), ["W0783"]);
    assert!(st.is_some());
}

#[test]
fn action_charts_that_drive_each_other_are_refused() {
    let (d, st) = expand(
        "PROGRAM p VAR x : BOOL; END_VAR\n\
         INITIAL_STEP A: Sub1(N); END_STEP\n\
         TRANSITION FROM A TO A := x; END_TRANSITION\n\
         ACTION Sub1:\n  INITIAL_STEP B: Sub2(N); END_STEP\n  TRANSITION FROM B TO B := x; END_TRANSITION\nEND_ACTION\n\
         ACTION Sub2:\n  INITIAL_STEP C: Sub1(N); END_STEP\n  TRANSITION FROM C TO C := x; END_TRANSITION\nEND_ACTION\n\
         END_PROGRAM",
        super::Profile::Iec,
    );
    assert!(st.is_none());
    assert_eq!(
        codes(&d).iter().filter(|c| **c == "E0785").count(),
        2,
        "{d:#?}"
    );
}

#[test]
fn a_shared_action_and_a_repeated_step_name_across_charts() {
    let (d, st) = expand(
        "PROGRAM p VAR x : BOOL; n : INT; END_VAR\n\
         INITIAL_STEP Idle: Sub(N); Count(N); END_STEP\n\
         TRANSITION FROM Idle TO Idle := x; END_TRANSITION\n\
         ACTION Sub:\n  INITIAL_STEP Idle: Count(N); END_STEP\n  TRANSITION FROM Idle TO Idle := Idle.T > T#1s; END_TRANSITION\nEND_ACTION\n\
         ACTION Count: n := n + 1; END_ACTION\n\
         END_PROGRAM",
        super::Profile::Iec,
    );
    let st = st.expect("written");
    let c = codes(&d);
    assert!(c.contains(&"W0784"), "{c:?}");
    assert!(c.contains(&"W0785"), "{c:?}");
    // The inner chart's step is a variable of its own, read by its own condition;
    // the shared action has a control per chart and one body.
    assert!(
        st.contains("__SFC_IN_Sub_S_Idle : __SFC_STEP := (X := TRUE);"),
        "{st}"
    );
    assert!(st.contains("(__SFC_IN_Sub_S_Idle.T > T#1s)"), "{st}");
    assert!(st.contains("__SFC_IN_Sub_K_Count : __SFC_ACTION;"), "{st}");
    assert!(
        st.contains("IF __SFC_IN_Sub_K_Count.A THEN __SFC_A_Count(); END_IF;"),
        "{st}"
    );
    assert_eq!(st.matches("ACTION __SFC_A_Count:").count(), 1, "{st}");
}
