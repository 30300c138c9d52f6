//! Unit tests of the lowering of graphical bodies to ST (`body`): function block
//! diagrams, the profiles, values kept before a write, loops cut at blocks.

use super::*;

/// A project with one PROGRAM `p` (BOOL `a`..`h`, `q1`..`q5`; INT `n`, `m`, `k`, `x`,
/// `y`; an SR `sr0`; a CTU `c0`) whose body is `elems` in language `lang`.
fn project(lang: &str, elems: &str) -> String {
    let mut vars = String::new();
    for v in [
        "a", "b", "c", "d", "e", "f", "g", "h", "q1", "q2", "q3", "q4", "q5",
    ] {
        vars.push_str(&format!(
            "<variable name=\"{v}\"><type><BOOL/></type></variable>"
        ));
    }
    for v in ["n", "m", "k", "x", "y"] {
        vars.push_str(&format!(
            "<variable name=\"{v}\"><type><INT/></type></variable>"
        ));
    }
    vars.push_str("<variable name=\"sr0\"><type><derived name=\"SR\"/></type></variable>");
    vars.push_str("<variable name=\"c0\"><type><derived name=\"CTU\"/></type></variable>");
    format!(
        r#"<project xmlns="http://www.plcopen.org/xml/tc6_0201">
<types><pous><pou name="p" pouType="program">
<interface><localVars>{vars}</localVars></interface>
<body><{lang}>
{elems}
</{lang}></body></pou></pous></types></project>"#
    )
}

fn conns(from: &[(u32, &str)]) -> String {
    from.iter()
        .map(|(f, p)| {
            if p.is_empty() {
                format!("<connection refLocalId=\"{f}\"/>")
            } else {
                format!("<connection refLocalId=\"{f}\" formalParameter=\"{p}\"/>")
            }
        })
        .collect()
}

fn in_var(id: u32, expr: &str) -> String {
    format!("<inVariable localId=\"{id}\"><connectionPointOut/><expression>{expr}</expression></inVariable>\n")
}

fn out_var(id: u32, expr: &str, from: &[(u32, &str)]) -> String {
    format!(
        "<outVariable localId=\"{id}\"><connectionPointIn>{}</connectionPointIn><expression>{expr}</expression></outVariable>\n",
        conns(from)
    )
}

/// An input of a block: (pin, attributes, connections).
type Pin<'a> = (&'a str, &'a str, &'a [(u32, &'a str)]);

/// A block: `inputs` are (pin, attributes, connections), `outputs` (pin, attributes).
fn block(
    id: u32,
    ty: &str,
    instance: Option<&str>,
    inputs: &[Pin],
    outputs: &[(&str, &str)],
) -> String {
    let inst = instance.map_or(String::new(), |i| format!(" instanceName=\"{i}\""));
    let ins: String = inputs
        .iter()
        .map(|(p, attrs, c)| {
            format!(
                "<variable formalParameter=\"{p}\"{attrs}><connectionPointIn>{}</connectionPointIn></variable>",
                conns(c)
            )
        })
        .collect();
    let outs: String = outputs
        .iter()
        .map(|(p, attrs)| {
            format!("<variable formalParameter=\"{p}\"{attrs}><connectionPointOut/></variable>")
        })
        .collect();
    format!(
        "<block localId=\"{id}\" typeName=\"{ty}\"{inst}><inputVariables>{ins}</inputVariables><inOutVariables/><outputVariables>{outs}</outputVariables></block>\n"
    )
}

fn contact(id: u32, var: &str, from: &[u32], attrs: &str) -> String {
    let c: Vec<(u32, &str)> = from.iter().map(|&f| (f, "")).collect();
    format!(
        "<contact localId=\"{id}\"{attrs}><connectionPointIn>{}</connectionPointIn><variable>{var}</variable></contact>\n",
        conns(&c)
    )
}

fn coil(id: u32, var: &str, from: &[u32], attrs: &str) -> String {
    let c: Vec<(u32, &str)> = from.iter().map(|&f| (f, "")).collect();
    format!(
        "<coil localId=\"{id}\"{attrs}><connectionPointIn>{}</connectionPointIn><variable>{var}</variable></coil>\n",
        conns(&c)
    )
}

const RAIL: &str = "<leftPowerRail localId=\"1\"/>\n";

/// The statements of `p` under `profile` (comments dropped).
fn body(lang: &str, elems: &str, profile: Profile) -> String {
    let opts = Options {
        profile,
        strict_rungs: false,
    };
    let mut diags = Vec::new();
    let c = convert(
        plcc_ir::diag::FileId(1),
        "t.xml",
        &project(lang, elems),
        &opts,
        &mut diags,
    );
    assert!(diags.iter().all(|d| !d.is_error()), "{diags:#?}");
    let text = c.expect("converted").il;
    let p = &text[text.find("PROGRAM p").expect("the program")..];
    let p = &p[..p.find("END_PROGRAM").expect("its end")];
    let start = p.rfind("END_VAR\n").map_or(0, |i| i + 8);
    p[start..]
        .lines()
        .map(str::trim)
        .filter(|l| !l.starts_with("(*"))
        .collect::<Vec<_>>()
        .join("\n")
}

fn iec(lang: &str, elems: &str) -> String {
    body(lang, elems, Profile::Iec)
}

#[test]
fn fbd_functions_keep_their_results_and_fbs_are_called_on_their_instance() {
    let elems = [
        in_var(1, "n"),
        in_var(2, "m"),
        block(
            3,
            "ADD",
            None,
            &[("IN1", "", &[(1, "")]), ("IN2", "", &[(2, "")])],
            &[("OUT", "")],
        ),
        out_var(4, "x", &[(3, "OUT")]),
        in_var(5, "a"),
        block(
            6,
            "CTU",
            Some("c0"),
            &[
                ("CU", " edge=\"rising\"", &[(5, "")]),
                ("R", "", &[]),
                ("PV", "", &[(3, "OUT")]),
            ],
            &[("Q", ""), ("CV", "")],
        ),
        out_var(7, "k", &[(6, "CV")]),
    ]
    .concat();
    assert_eq!(
        iec("FBD", &elems),
        "_TMP_ADD3_OUT := ADD(n, m);\nx := _TMP_ADD3_OUT;\nR_TRIG1(CLK := a);\nc0(CU := R_TRIG1.Q, PV := _TMP_ADD3_OUT);\nk := c0.CV;"
    );
}

#[test]
fn an_unwired_function_input_takes_its_default_not_the_next_wire() {
    let elems = [
        in_var(1, "n"),
        in_var(2, "m"),
        block(
            3,
            "LIMIT",
            None,
            &[
                ("MN", "", &[]),
                ("IN", "", &[(1, "")]),
                ("MX", "", &[(2, "")]),
            ],
            &[("OUT", "")],
        ),
        out_var(4, "x", &[(3, "OUT")]),
    ]
    .concat();
    assert_eq!(
        iec("FBD", &elems),
        "_TMP_LIMIT3_OUT := LIMIT(MN := 0, IN := n, MX := m);\nx := _TMP_LIMIT3_OUT;"
    );
}

#[test]
fn an_unwired_comparison_input_beside_a_literal_takes_the_literals_kind() {
    // EQ's output is BOOL; its other input, an untyped 4, says IN1 is a number.
    let elems = [
        in_var(1, "4"),
        block(
            2,
            "EQ",
            None,
            &[("IN1", "", &[]), ("IN2", "", &[(1, "")])],
            &[("OUT", "")],
        ),
        out_var(3, "x", &[(2, "OUT")]),
    ]
    .concat();
    assert_eq!(
        iec("FBD", &elems),
        "_TMP_EQ2_OUT := EQ(IN1 := 0, IN2 := 4);\nx := _TMP_EQ2_OUT;"
    );
}

#[test]
fn a_block_fed_by_another_loop_waits_for_it() {
    // Two loops, each through one ADD; the first drawn (3) also reads the other's
    // output: the other (2), whose only missing input is its own loop, runs first.
    let elems = [
        block(
            3,
            "ADD",
            None,
            &[("IN1", "", &[(3, "OUT")]), ("IN2", "", &[(2, "OUT")])],
            &[("OUT", "")],
        ),
        in_var(1, "DINT#1"),
        block(
            2,
            "ADD",
            None,
            &[("IN1", "", &[(2, "OUT")]), ("IN2", "", &[(1, "")])],
            &[("OUT", "")],
        ),
        out_var(4, "x", &[(3, "OUT")]),
    ]
    .concat();
    let st = iec("FBD", &elems);
    let first = |s: &str| st.find(s).unwrap_or_else(|| panic!("`{s}` in\n{st}"));
    assert!(
        first("_TMP_ADD2_OUT := ADD") < first("_TMP_ADD3_OUT := ADD"),
        "{st}"
    );
}

#[test]
fn a_variable_fed_by_a_disabled_function_is_not_written() {
    let elems = [
        in_var(1, "a"),
        in_var(2, "n"),
        block(
            3,
            "MUL",
            None,
            &[
                ("EN", "", &[(1, "")]),
                ("IN1", "", &[(2, "")]),
                ("IN2", "", &[(2, "")]),
            ],
            &[("ENO", ""), ("OUT", "")],
        ),
        out_var(4, "x", &[(3, "OUT")]),
    ]
    .concat();
    assert_eq!(
        iec("FBD", &elems),
        "_TMP_MUL3_OUT := MUL(EN := a, IN1 := n, IN2 := n, ENO => _TMP_MUL3_ENO);\nIF _TMP_MUL3_ENO THEN x := _TMP_MUL3_OUT; END_IF;"
    );
}

#[test]
fn feedback_reads_the_previous_scan_at_the_block() {
    // SR's Q1 wired back, negated, to its R; ADD's OUT to its own IN2.
    let elems = [
        in_var(1, "a"),
        block(
            2,
            "SR",
            Some("sr0"),
            &[
                ("S1", "", &[(1, "")]),
                ("R", " negated=\"true\"", &[(2, "Q1")]),
            ],
            &[("Q1", "")],
        ),
        out_var(3, "q1", &[(2, "Q1")]),
        in_var(4, "n"),
        block(
            5,
            "ADD",
            None,
            &[("IN1", "", &[(4, "")]), ("IN2", "", &[(5, "OUT")])],
            &[("OUT", "")],
        ),
        out_var(6, "x", &[(5, "OUT")]),
    ]
    .concat();
    assert_eq!(
        iec("FBD", &elems),
        "sr0(S1 := a, R := NOT(sr0.Q1));\nq1 := sr0.Q1;\n_TMP_ADD5_OUT := ADD(n, _TMP_ADD5_OUT);\nx := _TMP_ADD5_OUT;"
    );
}

#[test]
fn a_contact_is_read_once_even_after_a_coil_writes_its_variable() {
    // a -> (R a) -> coil q1: q1 gets a as it was before the reset.
    let elems = [
        RAIL.to_string(),
        contact(2, "a", &[1], ""),
        coil(3, "a", &[2], " storage=\"reset\""),
        coil(4, "q1", &[3], ""),
    ]
    .concat();
    assert_eq!(
        iec("LD", &elems),
        "_P2 := a;\nIF _P2 THEN a := FALSE; END_IF;\nq1 := _P2;"
    );
    // The editors read it again for each statement.
    assert_eq!(
        body("LD", &elems, Profile::Openplc3),
        "IF a THEN a := FALSE; END_IF;\nq1 := a;"
    );
}

#[test]
fn profiles_differ_where_the_reference_says() {
    // Coils in series, the first with two wires (f, g): the standard and xml2st pass
    // on f OR g, OpenPLC Editor v3 and Beremiz the AND.
    let chain = [
        RAIL.to_string(),
        contact(2, "f", &[1], ""),
        contact(3, "g", &[1], ""),
        coil(4, "q2", &[2, 3], ""),
        coil(5, "q3", &[4], ""),
    ]
    .concat();
    assert_eq!(iec("LD", &chain), "q2 := f OR g;\nq3 := f OR g;");
    assert_eq!(
        body("LD", &chain, Profile::Xml2st),
        "q2 := f OR g;\nq3 := f OR g;"
    );
    assert_eq!(
        body("LD", &chain, Profile::Openplc3),
        "q2 := f OR g;\nq3 := f AND g;"
    );
    assert_eq!(
        body("LD", &chain, Profile::Beremiz),
        "q2 := f OR g;\nq3 := f AND g;"
    );
    // A rising contact feeding two coils: one detector in the standard, one per coil
    // in the editors.
    let edge = [
        RAIL.to_string(),
        contact(2, "d", &[1], " edge=\"rising\""),
        coil(3, "q3", &[2], ""),
        coil(4, "q4", &[2], ""),
    ]
    .concat();
    assert_eq!(
        iec("LD", &edge),
        "R_TRIG1(CLK := d);\nq3 := R_TRIG1.Q;\nq4 := R_TRIG1.Q;"
    );
    assert_eq!(
        body("LD", &edge, Profile::Openplc3),
        "R_TRIG1(CLK := d);\nq3 := R_TRIG1.Q;\nR_TRIG2(CLK := d);\nq4 := R_TRIG2.Q;"
    );
}

#[test]
fn editors_call_unpulled_blocks_after_every_coil() {
    // Rung 1 (top): TON-like SR block fed by a, its output wired to nothing.
    // Rung 2 (below): contact sr0.Q1 drives q1. Document order puts the coil first.
    let elems = [
        "<leftPowerRail localId=\"1\"><position x=\"0\" y=\"0\"/></leftPowerRail>\n".to_string(),
        "<contact localId=\"2\"><position x=\"50\" y=\"10\"/><connectionPointIn><connection refLocalId=\"1\"/></connectionPointIn><variable>a</variable></contact>\n".to_string(),
        "<block localId=\"3\" typeName=\"SR\" instanceName=\"sr0\"><position x=\"100\" y=\"10\"/><inputVariables><variable formalParameter=\"S1\"><connectionPointIn><connection refLocalId=\"2\"/></connectionPointIn></variable><variable formalParameter=\"R\"><connectionPointIn/></variable></inputVariables><inOutVariables/><outputVariables><variable formalParameter=\"Q1\"><connectionPointOut/></variable></outputVariables></block>\n".to_string(),
        "<contact localId=\"4\"><position x=\"50\" y=\"100\"/><connectionPointIn><connection refLocalId=\"1\"/></connectionPointIn><variable>sr0.Q1</variable></contact>\n".to_string(),
        "<coil localId=\"5\"><position x=\"150\" y=\"100\"/><connectionPointIn><connection refLocalId=\"4\"/></connectionPointIn><variable>q1</variable></coil>\n".to_string(),
    ]
    .concat();
    assert_eq!(iec("LD", &elems), "sr0(S1 := a);\nq1 := sr0.Q1;");
    assert_eq!(
        body("LD", &elems, Profile::Xml2st),
        "sr0(S1 := a);\nq1 := sr0.Q1;"
    );
    assert_eq!(
        body("LD", &elems, Profile::Openplc3),
        "q1 := sr0.Q1;\nsr0(S1 := a);"
    );
}

#[test]
fn jumps_run_in_the_standard_and_are_ignored_by_the_editors() {
    let elems = [
        RAIL.to_string(),
        contact(2, "a", &[1], ""),
        "<jump localId=\"3\" label=\"skip\"><connectionPointIn><connection refLocalId=\"2\"/></connectionPointIn></jump>\n".to_string(),
        contact(4, "b", &[1], ""),
        coil(5, "q1", &[4], ""),
        "<label localId=\"6\" label=\"skip\"/>\n".to_string(),
    ]
    .concat();
    assert_eq!(
        iec("LD", &elems),
        "IF a THEN JMP skip; END_IF;\nq1 := b;\nskip:"
    );
    assert_eq!(body("LD", &elems, Profile::Openplc3), "q1 := b;");
}

#[test]
fn a_loop_through_contacts_only_is_an_error_and_through_a_block_is_not() {
    let mut diags = Vec::new();
    let looped = [
        RAIL.to_string(),
        contact(2, "a", &[3], ""),
        contact(3, "b", &[2], ""),
        coil(4, "q1", &[3], ""),
    ]
    .concat();
    let c = convert(
        plcc_ir::diag::FileId(1),
        "t.xml",
        &project("LD", &looped),
        &Options::default(),
        &mut diags,
    );
    assert!(c.is_none());
    assert!(
        diags.iter().any(|d| d.code == crate::codes::LD_LOOP),
        "{diags:#?}"
    );
}

#[test]
fn fbd_networks_are_drawn_as_netlists() {
    let elems = [
        in_var(1, "n"),
        block(
            2,
            "ADD",
            None,
            &[("IN1", "", &[(1, "")]), ("IN2", "", &[(2, "OUT")])],
            &[("OUT", "")],
        ),
        out_var(3, "x", &[(2, "OUT")]),
    ]
    .concat();
    let mut diags = Vec::new();
    let c = convert(
        plcc_ir::diag::FileId(1),
        "t.xml",
        &project("FBD", &elems),
        &Options::default(),
        &mut diags,
    )
    .expect("converted");
    assert_eq!(
        c.ld_text,
        "(* PROGRAM p *)\nnetwork 1\n  #2 [ADD] IN1 <- {n}, IN2 <- #2.OUT\n  #3 {=x} <- #2.OUT\n"
    );
}
