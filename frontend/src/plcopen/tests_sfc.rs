//! Unit tests of sequential function charts: PLCopen `<SFC>` bodies written as
//! textual SFC in the view (the reference's §5), compared with what OpenPLC Editor
//! v3's translator writes for the samples of `../shared`, and small charts written
//! here for each element kind and each diagnostic.

use super::*;
use crate::codes;
use plcc_ir::diag::{Diagnostic, Severity, Span};

const SAMPLES: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../shared/reference/plcopen-semantics-samples"
);

fn convert_with(xml: &str, profile: Profile) -> (Option<Converted>, Vec<Diagnostic>) {
    let mut diags = Vec::new();
    let opts = Options {
        profile,
        ..Options::default()
    };
    let c = convert(FileId(1), "t.xml", xml, &opts, &mut diags);
    (c, diags)
}

/// The view of a file that converts with no error (warnings allowed).
fn view_of(xml: &str) -> String {
    let (c, d) = convert_with(xml, Profile::Iec);
    let errors: Vec<_> = d.iter().filter(|d| d.is_error()).collect();
    assert!(errors.is_empty(), "{errors:#?}");
    c.expect("converted").il
}

/// The diagnostics of a conversion.
fn diags_of(xml: &str) -> Vec<Diagnostic> {
    convert_with(xml, Profile::Iec).1
}

/// The XML text a diagnostic points at.
fn at<'x>(xml: &'x str, d: &Diagnostic) -> &'x str {
    let s: Span = d.span.expect("a span");
    &xml[s.start as usize..s.end as usize]
}

// ---------------------------------------------------------------- structure

/// A block of textual SFC, normalised for comparison.
#[derive(Debug, PartialEq)]
enum Block {
    Step {
        initial: bool,
        name: String,
        assocs: Vec<String>,
    },
    Action {
        name: String,
        body: String,
    },
    Transition {
        priority: Option<String>,
        from: Vec<String>,
        to: Vec<String>,
        cond: String,
    },
}

/// Removes white space (outside nothing: the texts compared hold no strings).
fn squeeze(s: &str) -> String {
    s.chars().filter(|c| !c.is_whitespace()).collect()
}

/// An ST condition normalised: the operands of a top-level AND sorted (the
/// translator writes a series of contacts last one first, plcc first one first).
fn norm_cond(s: &str) -> String {
    let s = s
        .trim()
        .trim_start_matches(":=")
        .trim()
        .trim_end_matches(';');
    let mut parts = Vec::new();
    let (mut depth, mut start) = (0i32, 0usize);
    let b = s.as_bytes();
    let mut i = 0;
    while i < b.len() {
        match b[i] {
            b'(' => depth += 1,
            b')' => depth -= 1,
            _ => {}
        }
        if depth == 0 && s[i..].starts_with(" AND ") {
            parts.push(squeeze(&s[start..i]));
            start = i + 5;
            i += 5;
            continue;
        }
        i += 1;
    }
    parts.push(squeeze(&s[start..]));
    parts.sort();
    parts.join("&")
}

/// The steps, actions and transitions of a text, in order: names, associations,
/// FROM/TO lists, priorities and conditions compared upper-case and without white
/// space; a condition's top-level AND operands sorted ([`norm_cond`]). Everything
/// outside the blocks (declarations) is left out.
fn blocks(text: &str) -> Vec<Block> {
    let lines: Vec<String> = text
        .lines()
        .map(|l| l.trim().to_ascii_uppercase())
        .filter(|l| !l.is_empty())
        .collect();
    let mut out = Vec::new();
    let mut i = 0;
    let until = |i: &mut usize, end: &str| -> Vec<String> {
        let mut body = Vec::new();
        *i += 1;
        while *i < lines.len() && lines[*i] != end {
            body.push(lines[*i].clone());
            *i += 1;
        }
        body
    };
    while i < lines.len() {
        let l = lines[i].clone();
        if let Some(rest) = l
            .strip_prefix("INITIAL_STEP ")
            .map(|r| (true, r))
            .or_else(|| l.strip_prefix("STEP ").map(|r| (false, r)))
        {
            let (initial, rest) = rest;
            let name = rest.trim_end_matches(':').trim().to_string();
            let assocs = until(&mut i, "END_STEP")
                .iter()
                .map(|a| squeeze(a))
                .collect();
            out.push(Block::Step {
                initial,
                name,
                assocs,
            });
        } else if let Some(rest) = l.strip_prefix("ACTION ") {
            let name = rest.trim_end_matches(':').trim().to_string();
            let body = until(&mut i, "END_ACTION").join(" ");
            out.push(Block::Action {
                name,
                body: squeeze(&body),
            });
        } else if let Some(rest) = l.strip_prefix("TRANSITION") {
            let il = rest.ends_with(':');
            let rest = rest.trim_end_matches(':');
            let (priority, rest) = match rest.split_once("(PRIORITY :=") {
                Some((_, r)) => {
                    let (p, r) = r.split_once(')').expect("(PRIORITY := n)");
                    (Some(p.trim().to_string()), r.to_string())
                }
                None => (None, rest.to_string()),
            };
            let (from, to) = rest
                .trim()
                .trim_start_matches("FROM")
                .split_once(" TO ")
                .expect("FROM .. TO ..");
            let list = |s: &str| -> Vec<String> {
                s.trim()
                    .trim_start_matches('(')
                    .trim_end_matches(')')
                    .split(',')
                    .map(|x| x.trim().to_string())
                    .collect()
            };
            let body = until(&mut i, "END_TRANSITION");
            let cond = if il {
                format!("IL:{}", body.join("|"))
            } else {
                norm_cond(&body.join(" "))
            };
            out.push(Block::Transition {
                priority,
                from: list(from),
                to: list(to),
                cond,
            });
        }
        i += 1;
    }
    out
}

/// Converts sample `name` under profile openplc3 and compares its chart with what
/// OpenPLC Editor v3 wrote for it.
fn compare_with_sample(name: &str) {
    let dir = std::path::Path::new(SAMPLES);
    if !dir.is_dir() {
        eprintln!("NOTICE: {SAMPLES} is absent: the SFC sample comparison {name} is skipped");
        return;
    }
    let xml = std::fs::read_to_string(dir.join(format!("{name}.xml"))).expect("sample");
    let want = std::fs::read_to_string(dir.join(format!("{name}.openplc-v3.st"))).expect("st");
    let (c, d) = convert_with(&xml, Profile::Openplc3);
    let errors: Vec<_> = d.iter().filter(|d| d.is_error()).collect();
    assert!(errors.is_empty(), "{errors:#?}");
    let have = c.expect("converted").il;
    assert!(blocks(&want).len() >= 4, "{want}");
    assert_eq!(blocks(&have), blocks(&want), "plcc's view:\n{have}");
}

#[test]
fn sample_sfc_graphical_as_openplc_v3_writes_it() {
    compare_with_sample("sfc_graphical");
}

#[test]
fn sample_sfc_named_transitions_as_openplc_v3_writes_it() {
    compare_with_sample("sfc_named_transitions");
}

#[test]
fn the_normalisation_sorts_and_operands_only_at_the_top() {
    assert_eq!(
        norm_cond(":= R_TRIG1.Q AND c;"),
        norm_cond(":= c AND R_TRIG1.Q;")
    );
    assert_ne!(
        norm_cond(":= a AND (b OR c);"),
        norm_cond(":= b AND (a OR c);")
    );
}

// ---------------------------------------------------------------- small charts

/// A project with program `P` (BOOLs a, b, c, x, y; INT n), `extra` after its
/// interface (actions, transitions) and the chart `sfc`.
fn chart(extra: &str, sfc: &str) -> String {
    let vars: String = ["a", "b", "c", "x", "y"]
        .iter()
        .map(|v| format!(r#"<variable name="{v}"><type><BOOL/></type></variable>"#))
        .collect();
    format!(
        r#"<?xml version="1.0" encoding="utf-8"?>
<project xmlns="http://www.plcopen.org/xml/tc6_0201" xmlns:xhtml="http://www.w3.org/1999/xhtml">
<types><dataTypes/><pous>
<pou name="P" pouType="program"><interface><localVars>{vars}<variable name="n"><type><INT/></type></variable></localVars></interface>{extra}<body><SFC>
{sfc}
</SFC></body></pou>
</pous></types>
<instances><configurations/></instances>
</project>"#
    )
}

/// `<step>`: `from` the localId before it (or none).
fn step(id: u64, name: &str, initial: bool, from: Option<u64>) -> String {
    let input = from.map_or(String::new(), |f| {
        format!(r#"<connectionPointIn><connection refLocalId="{f}"/></connectionPointIn>"#)
    });
    format!(
        r#"<step localId="{id}" name="{name}" initialStep="{initial}">{input}<connectionPointOut/></step>"#
    )
}

/// A `<transition>` after `from` with the inline ST condition `cond`.
fn trans(id: u64, from: u64, cond: &str) -> String {
    format!(
        r#"<transition localId="{id}"><connectionPointIn><connection refLocalId="{from}"/></connectionPointIn><condition><inline name=""><ST><xhtml:p><![CDATA[{cond}]]></xhtml:p></ST></inline></condition></transition>"#
    )
}

/// A `<transition>` after `from` with condition `cond` written out.
fn trans_with(id: u64, from: u64, attrs: &str, cond: &str) -> String {
    format!(
        r#"<transition localId="{id}"{attrs}><connectionPointIn><connection refLocalId="{from}"/></connectionPointIn>{cond}</transition>"#
    )
}

fn jump(id: u64, from: u64, target: &str) -> String {
    format!(
        r#"<jumpStep localId="{id}" targetName="{target}"><connectionPointIn><connection refLocalId="{from}"/></connectionPointIn></jumpStep>"#
    )
}

/// An element with one input per `from` (divergences take one, convergences several).
fn fork(kind: &str, id: u64, from: &[u64]) -> String {
    let ins: String = from
        .iter()
        .map(|f| {
            format!(r#"<connectionPointIn><connection refLocalId="{f}"/></connectionPointIn>"#)
        })
        .collect();
    format!(r#"<{kind} localId="{id}">{ins}<connectionPointOut/></{kind}>"#)
}

fn action_block(id: u64, step: u64, actions: &str) -> String {
    format!(
        r#"<actionBlock localId="{id}"><connectionPointIn><connection refLocalId="{step}"/></connectionPointIn>{actions}</actionBlock>"#
    )
}

/// A two-step loop: Init (initial) -a-> S1 -b-> jump to Init.
fn two_steps() -> String {
    [
        step(1, "Init", true, None),
        trans(2, 1, "a"),
        step(3, "S1", false, Some(2)),
        trans(4, 3, "b"),
        jump(5, 4, "Init"),
    ]
    .concat()
}

/// The part of a view from the first step on.
fn body(view: &str) -> &str {
    let i = view
        .find("INITIAL_STEP")
        .unwrap_or_else(|| panic!("{view}"));
    let j = view.rfind("END_PROGRAM").unwrap_or(view.len());
    &view[i..j]
}

#[test]
fn a_loop_of_steps_with_a_jump() {
    let v = view_of(&chart("", &two_steps()));
    assert_eq!(
        body(&v),
        "INITIAL_STEP Init:\nEND_STEP\nTRANSITION FROM Init TO S1\n    := a;\nEND_TRANSITION\n\
         STEP S1:\nEND_STEP\nTRANSITION FROM S1 TO Init\n    := b;\nEND_TRANSITION\n"
    );
}

/// An action written as a chart: its steps and transitions inside its ACTION, the
/// actions it uses after it (once, though the body's chart uses one of them too).
#[test]
fn an_action_written_as_a_chart() {
    let inner = [
        step(1, "SubA", true, None),
        action_block(
            2,
            1,
            r#"<action localId="0"><reference name="Count"/></action>"#,
        ),
        trans(3, 1, "x"),
        jump(4, 3, "SubA"),
    ]
    .concat();
    let actions = format!(
        r#"<actions><action name="Sub"><body><SFC>{inner}</SFC></body></action>
<action name="Count"><body><ST><xhtml:p><![CDATA[n := n + 1;]]></xhtml:p></ST></body></action></actions>"#
    );
    let sfc = format!(
        "{}{}",
        two_steps(),
        action_block(
            6,
            3,
            r#"<action localId="0"><reference name="Sub"/></action><action localId="0"><reference name="Count"/></action>"#
        )
    );
    let v = view_of(&chart(&actions, &sfc));
    assert_eq!(
        body(&v),
        "INITIAL_STEP Init:\nEND_STEP\nTRANSITION FROM Init TO S1\n    := a;\nEND_TRANSITION\n\
         STEP S1:\n    Sub(N);\n    Count(N);\nEND_STEP\n\
         ACTION Sub:\nINITIAL_STEP SubA:\n    Count(N);\nEND_STEP\n\
         TRANSITION FROM SubA TO SubA\n    := x;\nEND_TRANSITION\nEND_ACTION\n\
         ACTION Count:\n    n := n + 1;\nEND_ACTION\n\
         TRANSITION FROM S1 TO Init\n    := b;\nEND_TRANSITION\n"
    );
}

/// CODESYS's step actions (entry, active, exit), named in the step's `addData`, are
/// written with plcc's pseudo-qualifiers (in the order of the data), before the
/// step's action blocks.
#[test]
fn codesys_step_actions_from_add_data() {
    let attrs = |pairs: &[(&str, &str)]| -> String {
        let a: String = pairs
            .iter()
            .map(|(g, v)| format!(r#"<attribute guid="{g}">{v}</attribute>"#))
            .collect();
        format!(
            r#"<addData><data name="http://www.3s-software.com/plcopenxml/sfc/element" handleUnknown="implementation"><attributes xmlns="">{a}</attributes></data></addData>"#
        )
    };
    let s1 = attrs(&[
        ("38391c6d-6d4a-42f8-8ee7-9f45e5adafa8", "S1"),
        ("700a583f-b4d4-43e4-8c14-629c7cd3bec8", "Work"),
        ("a6b08bd8-b696-47e3-9cbf-7408b61c9ff8", "Enter"),
        ("a2621e18-7de3-4ea6-ae6d-89e9e0b7befd", "Leave"),
    ]);
    let sfc = [
        step(1, "Init", true, None),
        trans(2, 1, "a"),
        format!(
            r#"<step localId="3" name="S1"><connectionPointIn><connection refLocalId="2"/></connectionPointIn><connectionPointOut/>{s1}</step>"#
        ),
        trans(4, 3, "b"),
        jump(5, 4, "Init"),
    ]
    .concat();
    let body_of = |n: &str| {
        format!(
            r#"<action name="{n}"><body><ST><xhtml:p><![CDATA[n := n + 1;]]></xhtml:p></ST></body></action>"#
        )
    };
    let actions = format!(
        "<actions>{}{}{}</actions>",
        body_of("Enter"),
        body_of("Work"),
        body_of("Leave")
    );
    let v = view_of(&chart(&actions, &sfc));
    assert!(
        v.contains("STEP S1:\n    Work(ACTIVE);\n    Enter(ENTRY);\n    Leave(EXIT);\nEND_STEP\n"),
        "{v}"
    );
    assert!(v.contains("ACTION Enter:"), "{v}");
}

/// CODESYS nests convergences (a branch closed inside a branch): the transitions of
/// the inner one lead to the step after the outer one.
#[test]
fn nested_selection_convergences() {
    let sfc = [
        step(1, "Init", true, None),
        fork("selectionDivergence", 2, &[1]),
        trans(3, 2, "a"),
        trans(4, 2, "b"),
        trans(5, 2, "c"),
        fork("selectionConvergence", 6, &[3, 4]),
        fork("selectionConvergence", 7, &[6, 5]),
        step(8, "S1", false, Some(7)),
        trans(9, 8, "x"),
        jump(10, 9, "Init"),
    ]
    .concat();
    let v = view_of(&chart("", &sfc));
    for (from, cond) in [("Init", "a"), ("Init", "b"), ("Init", "c")] {
        let t = format!("TRANSITION FROM {from} TO S1\n    := {cond};");
        assert!(v.contains(&t), "{t} in\n{v}");
    }
}

#[test]
fn selection_and_simultaneous_sequences() {
    // Init -> (selection) t10 [PRIORITY 2] -> A, t11 -> B; A and B converge (selection)
    // into C; C -> t20 -> (simultaneous) D, E; D and E -> t30 -> Init.
    let sfc = [
        step(1, "Init", true, None),
        fork("selectionDivergence", 9, &[1]),
        trans_with(
            10,
            9,
            r#" priority="2""#,
            r#"<condition><inline name=""><ST><xhtml:p>a</xhtml:p></ST></inline></condition>"#,
        ),
        trans(11, 9, "b"),
        step(12, "A", false, Some(10)),
        step(13, "B", false, Some(11)),
        trans(14, 12, "x"),
        trans(15, 13, "y"),
        fork("selectionConvergence", 16, &[14, 15]),
        step(17, "C", false, Some(16)),
        trans(20, 17, "c"),
        fork("simultaneousDivergence", 21, &[20]),
        step(22, "D", false, Some(21)),
        step(23, "E", false, Some(21)),
        fork("simultaneousConvergence", 24, &[22, 23]),
        trans(30, 24, "TRUE"),
        jump(31, 30, "Init"),
    ]
    .concat();
    let v = view_of(&chart("", &sfc));
    let b = blocks(body(&v));
    let t = |p: Option<&str>, f: &[&str], to: &[&str], c: &str| Block::Transition {
        priority: p.map(str::to_string),
        from: f.iter().map(|s| s.to_ascii_uppercase()).collect(),
        to: to.iter().map(|s| s.to_ascii_uppercase()).collect(),
        cond: norm_cond(c),
    };
    let s = |name: &str, initial: bool| Block::Step {
        initial,
        name: name.to_ascii_uppercase(),
        assocs: vec![],
    };
    assert_eq!(
        b,
        vec![
            s("Init", true),
            t(Some("2"), &["Init"], &["A"], "A"),
            s("A", false),
            t(None, &["A"], &["C"], "X"),
            s("C", false),
            t(None, &["C"], &["D", "E"], "C"),
            s("D", false),
            t(None, &["D", "E"], &["Init"], "TRUE"),
            s("E", false),
            t(None, &["Init"], &["B"], "B"),
            s("B", false),
            t(None, &["B"], &["C"], "Y"),
        ],
        "{v}"
    );
}

#[test]
fn action_blocks_reference_actions_variables_and_inline_bodies() {
    let actions = r#"<actions>
<action name="Count"><body><ST><xhtml:p><![CDATA[n := n + 1;]]></xhtml:p></ST></body></action>
<action name="Lamp"><body><LD><leftPowerRail localId="1"><connectionPointOut formalParameter=""/></leftPowerRail><contact localId="2"><connectionPointIn><connection refLocalId="1"/></connectionPointIn><connectionPointOut/><variable>a</variable></contact><coil localId="3"><connectionPointIn><connection refLocalId="2"/></connectionPointIn><connectionPointOut/><variable>y</variable></coil><rightPowerRail localId="4"><connectionPointIn><connection refLocalId="3"/></connectionPointIn></rightPowerRail></LD></body></action>
<action name="Unused"><body><ST><xhtml:p>n := 0;</xhtml:p></ST></body></action>
</actions>"#;
    let acts = r#"<action localId="0"><reference name="Count"/></action>
<action localId="0" qualifier="L" duration="T#2s" indicator="c"><reference name="x"/></action>
<action localId="0" qualifier="S"><inline><ST><xhtml:p><![CDATA[x := TRUE;]]></xhtml:p></ST></inline></action>
<action localId="0" qualifier="P1"><reference name="Lamp"/></action>"#;
    let sfc = format!(
        "{}{}{}",
        two_steps(),
        action_block(6, 1, acts),
        action_block(
            7,
            3,
            r#"<action localId="0" qualifier="R"><reference name="Count"/></action><action localId="0"><inline><ST><xhtml:p>y := FALSE;</xhtml:p></ST></inline></action>"#
        )
    );
    let xml = chart(actions, &sfc);
    let v = view_of(&xml);
    assert_eq!(
        body(&v),
        "INITIAL_STEP Init:\n    Count(N);\n    x(L, T#2s, c);\n    INIT_INLINE1(S);\n    Lamp(P1);\nEND_STEP\n\
         ACTION Count:\n    n := n + 1;\nEND_ACTION\n\
         ACTION INIT_INLINE1:\n    x := TRUE;\nEND_ACTION\n\
         ACTION Lamp:\n    y := a;\nEND_ACTION\n\
         TRANSITION FROM Init TO S1\n    := a;\nEND_TRANSITION\n\
         STEP S1:\n    Count(R);\n    S1_INLINE2(N);\nEND_STEP\n\
         ACTION S1_INLINE2:\n    y := FALSE;\nEND_ACTION\n\
         TRANSITION FROM S1 TO Init\n    := b;\nEND_TRANSITION\n"
    );
    // The action no step uses is dropped, with a warning at it.
    let d = diags_of(&xml);
    assert_eq!(d.len(), 1, "{d:#?}");
    assert_eq!(d[0].code, codes::W_SFC_DROPPED);
    assert_eq!(d[0].severity, Severity::Warning);
    assert_eq!(at(&xml, &d[0]), "action");
    assert!(d[0].message.contains("`Unused`"), "{}", d[0].message);
}

#[test]
fn named_transitions_in_st_il_and_fbd() {
    let transitions = r#"<transitions>
<transition name="TST"><body><ST><xhtml:p><![CDATA[:= a AND NOT b;]]></xhtml:p></ST></body></transition>
<transition name="TIL"><body><IL><xhtml:p><![CDATA[LD a
ANDN c]]></xhtml:p></IL></body></transition>
<transition name="TFB"><body><FBD><inVariable localId="1"><connectionPointOut/><expression>n</expression></inVariable><inVariable localId="2"><connectionPointOut/><expression>3</expression></inVariable><block localId="3" typeName="GT"><inputVariables><variable formalParameter="IN1"><connectionPointIn><connection refLocalId="1"/></connectionPointIn></variable><variable formalParameter="IN2"><connectionPointIn><connection refLocalId="2"/></connectionPointIn></variable></inputVariables><inOutVariables/><outputVariables><variable formalParameter="OUT"><connectionPointOut/></variable></outputVariables></block><outVariable localId="4"><connectionPointIn><connection refLocalId="3" formalParameter="OUT"/></connectionPointIn><expression>TFB</expression></outVariable></FBD></body></transition>
</transitions>"#;
    let reference = |n: &str| format!(r#"<condition><reference name="{n}"/></condition>"#);
    let sfc = [
        step(1, "Init", true, None),
        trans_with(2, 1, "", &reference("TST")),
        step(3, "S1", false, Some(2)),
        trans_with(4, 3, "", &reference("TIL")),
        step(5, "S2", false, Some(4)),
        trans_with(6, 5, r#" priority="0""#, &reference("TFB")),
        jump(7, 6, "Init"),
    ]
    .concat();
    let v = view_of(&chart(transitions, &sfc));
    assert_eq!(
        body(&v),
        "INITIAL_STEP Init:\n    COMPUTE_FUNCTION_BLOCKS(S);\nEND_STEP\n\
         ACTION COMPUTE_FUNCTION_BLOCKS:\n    _TMP_GT3_OUT := GT(n, 3);\nEND_ACTION\n\
         TRANSITION FROM Init TO S1\n    := a AND NOT b;\nEND_TRANSITION\n\
         STEP S1:\nEND_STEP\n\
         TRANSITION FROM S1 TO S2:\n    LD a\nANDN c\nEND_TRANSITION\n\
         STEP S2:\nEND_STEP\n\
         TRANSITION (PRIORITY := 0) FROM S2 TO Init\n    := _TMP_GT3_OUT;\nEND_TRANSITION\n",
        "{v}"
    );
    assert!(v.contains("_TMP_GT3_OUT : BOOL;"), "{v}");
}

#[test]
fn a_graphical_condition_in_the_chart_with_an_edge() {
    // A rising contact on `c` drawn in the chart, from the left rail.
    let sfc = format!(
        "{}{}{}{}",
        step(1, "Init", true, None),
        r#"<leftPowerRail localId="40"><connectionPointOut formalParameter=""/></leftPowerRail><contact localId="41" edge="rising"><connectionPointIn><connection refLocalId="40"/></connectionPointIn><connectionPointOut/><variable>c</variable></contact>"#,
        trans_with(
            2,
            1,
            "",
            r#"<condition><connectionPointIn><connection refLocalId="41"/></connectionPointIn></condition>"#
        ),
        jump(3, 2, "Init"),
    );
    let xml = chart("", &sfc);
    let v = view_of(&xml);
    assert_eq!(
        body(&v),
        "INITIAL_STEP Init:\n    COMPUTE_FUNCTION_BLOCKS(S);\nEND_STEP\n\
         ACTION COMPUTE_FUNCTION_BLOCKS:\n    R_TRIG1(CLK := c);\nEND_ACTION\n\
         TRANSITION FROM Init TO Init\n    := R_TRIG1.Q;\nEND_TRANSITION\n",
        "{v}"
    );
    assert!(v.contains("R_TRIG1 : R_TRIG;"), "{v}");
    // The condition's line maps back to the transition.
    let (c, _) = convert_with(&xml, Profile::Iec);
    let c = c.unwrap();
    let start = c.il.find(":= R_TRIG1.Q").unwrap() as u32;
    let mut d = Diagnostic::error("E0201", "x", Span::new(FileId(7), start, start + 1));
    c.map.remap(&mut d, FileId(7), FileId(1));
    assert_eq!(at(&xml, &d), r#"<transition localId="2""#);
}

// ---------------------------------------------------------------- diagnostics

/// Each diagnostic of charts, its code written out (so that a renumbered code shows).
#[cfg(test)]
mod diagnostics {
    use super::*;

    #[test]
    fn a_macro_step_is_ignored_with_a_warning() {
        let xml = chart(
            "",
            &format!("{}<macroStep localId=\"9\" name=\"M\"/>", two_steps()),
        );
        let d = diags_of(&xml);
        assert_eq!(d.len(), 1, "{d:#?}");
        assert_eq!(d[0].code, "W0761");
        assert_eq!(at(&xml, &d[0]), r#"<macroStep localId="9""#);
    }

    #[test]
    fn an_island_is_dropped_with_warnings() {
        let island = [
            step(20, "S9", false, Some(23)),
            trans(21, 20, "a"),
            step(22, "S10", false, Some(21)),
            trans(23, 22, "b"),
        ]
        .concat();
        let xml = chart("", &format!("{}{island}", two_steps()));
        let d = diags_of(&xml);
        assert_eq!(
            d.iter().map(|d| d.code).collect::<Vec<_>>(),
            vec!["W0760"; 4],
            "{d:#?}"
        );
        assert!(d[0].message.contains("step `S9`"), "{}", d[0].message);
        assert_eq!(at(&xml, &d[0]), r#"<step localId="20""#);
        let v = view_of(&xml);
        assert!(!v.contains("S9") && !v.contains("S10"), "{v}");
    }

    /// The one error of a conversion: its code and the XML it points at.
    fn one_error(xml: &str) -> (&'static str, String, String) {
        let d: Vec<Diagnostic> = diags_of(xml).into_iter().filter(|d| d.is_error()).collect();
        assert_eq!(d.len(), 1, "{d:#?}");
        (d[0].code, at(xml, &d[0]).to_string(), d[0].message.clone())
    }

    #[test]
    fn a_chart_without_an_initial_step() {
        let sfc = two_steps().replace(r#"initialStep="true""#, r#"initialStep="false""#);
        let (code, place, msg) = one_error(&chart("", &sfc));
        assert_eq!(code, "E0761");
        assert_eq!(place, "SFC");
        assert!(msg.contains("`P`"), "{msg}");
    }

    #[test]
    fn a_jump_to_a_missing_step() {
        let sfc = two_steps().replace(r#"targetName="Init""#, r#"targetName="Inti""#);
        let (code, place, _) = one_error(&chart("", &sfc));
        assert_eq!(code, "E0762");
        assert_eq!(place, "Inti");
    }

    #[test]
    fn a_transition_without_a_step_before_or_after() {
        // Nothing before: its input is not connected.
        let sfc = format!(
            "{}{}",
            two_steps(),
            r#"<transition localId="8"><connectionPointIn/><condition><inline name=""><ST><xhtml:p>c</xhtml:p></ST></inline></condition></transition><step localId="9" name="S9"><connectionPointIn><connection refLocalId="8"/></connectionPointIn></step>"#
        );
        let xml = chart("", &sfc);
        let d: Vec<Diagnostic> = diags_of(&xml)
            .into_iter()
            .filter(|d| d.is_error())
            .collect();
        assert_eq!(d.len(), 1, "{d:#?}");
        assert_eq!(d[0].code, "E0763");
        assert_eq!(at(&xml, &d[0]), r#"<transition localId="8""#);
        assert!(d[0].message.contains("no step before"), "{}", d[0].message);
        // Nothing after.
        let sfc = [step(1, "Init", true, None), trans(2, 1, "a")].concat();
        let (code, place, msg) = one_error(&chart("", &sfc));
        assert_eq!(code, "E0763");
        assert_eq!(place, r#"<transition localId="2""#);
        assert!(msg.contains("no step after"), "{msg}");
    }

    #[test]
    fn timed_qualifiers_need_a_duration_and_dl_is_refused() {
        for (q, code) in [
            ("L", "E0764"),
            ("SD", "E0764"),
            ("DL", "E0765"),
            ("Q", "E0765"),
        ] {
            let a =
                format!(r#"<action localId="0" qualifier="{q}"><reference name="x"/></action>"#);
            let xml = chart("", &format!("{}{}", two_steps(), action_block(6, 1, &a)));
            let (got, place, _) = one_error(&xml);
            assert_eq!((got, place.as_str()), (code, q));
        }
    }

    #[test]
    fn conditions_that_cannot_be_used() {
        // A reference to a transition the POU does not have.
        let sfc = two_steps().replace(
            r#"<condition><inline name=""><ST><xhtml:p><![CDATA[a]]></xhtml:p></ST></inline></condition>"#,
            r#"<condition><reference name="T9"/></condition>"#,
        );
        let (code, place, _) = one_error(&chart("", &sfc));
        assert_eq!((code, place.as_str()), ("E0766", "T9"));
        // No condition at all.
        let sfc = two_steps().replace(
            r#"<condition><inline name=""><ST><xhtml:p><![CDATA[a]]></xhtml:p></ST></inline></condition>"#,
            "",
        );
        let (code, place, _) = one_error(&chart("", &sfc));
        assert_eq!(
            (code, place.as_str()),
            ("E0766", r#"<transition localId="2""#)
        );
    }

    #[test]
    fn a_graphical_transition_without_its_coil() {
        let transitions = r#"<transitions><transition name="T1"><body><FBD><inVariable localId="1"><connectionPointOut/><expression>a</expression></inVariable><outVariable localId="2"><connectionPointIn><connection refLocalId="1"/></connectionPointIn><expression>x</expression></outVariable></FBD></body></transition></transitions>"#;
        let sfc = two_steps().replace(
            r#"<condition><inline name=""><ST><xhtml:p><![CDATA[a]]></xhtml:p></ST></inline></condition>"#,
            r#"<condition><reference name="T1"/></condition>"#,
        );
        let (code, place, msg) = one_error(&chart(transitions, &sfc));
        assert_eq!((code, place.as_str()), ("E0767", "transition"));
        assert!(msg.contains("`T1`"), "{msg}");
    }

    #[test]
    fn two_steps_with_one_name() {
        let sfc = format!("{}{}", two_steps(), step(9, "S1", false, None));
        let (code, place, _) = one_error(&chart("", &sfc));
        assert_eq!((code, place.as_str()), ("E0760", r#"<step localId="9""#));
    }

    #[test]
    fn a_transition_body_written_as_a_chart_is_refused() {
        let t =
            r#"<transitions><transition name="T"><body><SFC/></body></transition></transitions>"#;
        let (code, _, _) = one_error(&chart(t, &two_steps()));
        assert_eq!(code, "E0602");
    }
}
