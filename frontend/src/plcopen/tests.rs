//! Unit tests of the ladder front end: bodies written by hand (no positions, so rungs
//! and branches go in document order) converted to IL, and the checks.

use super::*;
use crate::codes;
use plcc_ir::diag::Diagnostic;

/// A TC6 2.01 project with one PROGRAM `p` whose BOOL variables are `a` to `z` and
/// whose LD body holds `elems`.
fn project(elems: &str) -> String {
    let names = ('a'..='z')
        .map(String::from)
        .chain(["start", "run", "stop"].map(String::from));
    let vars: String = names
        .map(|c| format!("<variable name=\"{c}\"><type><BOOL/></type></variable>"))
        .collect();
    format!(
        r#"<project xmlns="http://www.plcopen.org/xml/tc6_0201">
<types><pous><pou name="p" pouType="program">
<interface><localVars>{vars}</localVars></interface>
<body><LD>
<leftPowerRail localId="1"/>
{elems}
</LD></body></pou></pous></types></project>"#
    )
}

fn contact(id: u32, var: &str, from: &[u32]) -> String {
    elem(id, "contact", var, from, "")
}

fn coil(id: u32, var: &str, from: &[u32]) -> String {
    elem(id, "coil", var, from, "")
}

fn elem(id: u32, tag: &str, var: &str, from: &[u32], attrs: &str) -> String {
    let conns: String = from
        .iter()
        .map(|f| format!("<connection refLocalId=\"{f}\"/>"))
        .collect();
    format!(
        "<{tag} localId=\"{id}\"{attrs}><connectionPointIn>{conns}</connectionPointIn><variable>{var}</variable></{tag}>\n"
    )
}

fn convert_text(xml: &str) -> (Option<Converted>, Vec<Diagnostic>) {
    let mut diags = Vec::new();
    let c = convert(FileId(1), "t.xml", xml, &Options::default(), &mut diags);
    (c, diags)
}

/// The statements of the body of `p` (after its declarations, to END_PROGRAM,
/// comments dropped).
fn body_st(elems: &str) -> String {
    let (c, diags) = convert_text(&project(elems));
    assert!(diags.is_empty(), "{diags:#?}");
    let text = c.expect("converted").il;
    let start = text.find("PROGRAM p").expect("the program");
    let body = &text[start..];
    let body = &body[..body.find("END_PROGRAM").expect("the end")];
    let start = body.rfind("END_VAR\n").map_or(0, |i| i + 8);
    body[start..]
        .lines()
        .map(str::trim)
        .filter(|l| !l.starts_with("(*"))
        .take_while(|l| *l != "END_PROGRAM")
        .collect::<Vec<_>>()
        .join("\n")
}

fn codes_of(elems: &str) -> Vec<&'static str> {
    let (c, diags) = convert_text(&project(elems));
    assert!(c.is_none() || diags.iter().all(|d| !d.is_error()));
    diags.iter().map(|d| d.code).collect()
}

#[test]
fn the_seeds_example() {
    // ((a AND b) OR c OR d) AND e, the seed's X0.0 ... X0.5.
    let il = body_st(
        &[
            contact(2, "a", &[1]),
            contact(3, "b", &[2]),
            contact(4, "c", &[1]),
            contact(5, "d", &[1]),
            contact(6, "e", &[3, 4, 5]),
            coil(7, "x", &[6]),
        ]
        .concat(),
    );
    assert_eq!(il, "x := (a AND b OR c OR d) AND e;");
}

#[test]
fn a_parallel_block_after_a_contact_is_the_or_of_its_paths() {
    // a AND (b OR (c AND d)): the contact before the block is read once.
    let il = body_st(
        &[
            contact(2, "a", &[1]),
            contact(3, "b", &[2]),
            contact(4, "c", &[2]),
            contact(5, "d", &[4]),
            coil(6, "x", &[3, 5]),
        ]
        .concat(),
    );
    assert_eq!(il, "x := a AND b OR a AND c AND d;");
}

#[test]
fn coils_in_parallel_and_in_series_pass_their_power_on() {
    let il = body_st(
        &[
            contact(2, "a", &[1]),
            coil(3, "x", &[2]),
            coil(4, "y", &[2]),
            contact(5, "b", &[4]),
            elem(6, "coil", "z", &[5], " negated=\"true\""),
        ]
        .concat(),
    );
    assert_eq!(il, "x := a;\ny := a;\nz := NOT(a AND b);");
}

#[test]
fn set_and_reset_coils() {
    let il = body_st(
        &[
            contact(2, "a", &[1]),
            elem(3, "coil", "x", &[2], " storage=\"set\""),
            contact(4, "b", &[1]),
            elem(5, "coil", "x", &[4], " storage=\"reset\""),
        ]
        .concat(),
    );
    assert_eq!(
        il,
        "IF a THEN x := TRUE; END_IF;\nIF b THEN x := FALSE; END_IF;"
    );
}

#[test]
fn a_fork_is_read_by_both_branches() {
    // a AND b feeds c->x and d->y.
    let il = body_st(
        &[
            contact(2, "a", &[1]),
            contact(3, "b", &[2]),
            contact(4, "c", &[3]),
            coil(5, "x", &[4]),
            contact(6, "d", &[3]),
            coil(7, "y", &[6]),
        ]
        .concat(),
    );
    assert_eq!(il, "x := a AND b AND c;\ny := a AND b AND d;");
    // Two coils on the fork.
    let il = body_st(
        &[
            contact(2, "a", &[1]),
            contact(3, "b", &[2]),
            coil(4, "x", &[3]),
            coil(5, "y", &[3]),
        ]
        .concat(),
    );
    assert_eq!(il, "x := a AND b;\ny := a AND b;");
}

#[test]
fn edge_contacts_call_their_detector_on_their_variable() {
    let il = body_st(
        &[
            contact(2, "a", &[1]),
            elem(3, "contact", "b", &[2], " edge=\"falling\""),
            coil(4, "x", &[3]),
        ]
        .concat(),
    );
    assert_eq!(il, "F_TRIG1(CLK := b);\nx := a AND F_TRIG1.Q;");
}

#[test]
fn edge_coils_detect_the_edge_of_their_power() {
    let il = body_st(
        &[
            contact(2, "a", &[1]),
            elem(3, "coil", "x", &[2], " edge=\"rising\""),
            contact(4, "b", &[3]),
            coil(5, "y", &[4]),
        ]
        .concat(),
    );
    assert_eq!(il, "R_TRIG1(CLK := a);\nx := R_TRIG1.Q;\ny := a AND b;");
}

#[test]
fn a_continuation_is_what_is_wired_to_its_connector() {
    let il = body_st(&[
        contact(2, "a", &[1]),
        "<connector localId=\"3\" name=\"c1\"><connectionPointIn><connection refLocalId=\"2\"/></connectionPointIn></connector>\n".to_string(),
        "<continuation localId=\"4\" name=\"c1\"/>\n".to_string(),
        contact(5, "b", &[4]),
        coil(6, "x", &[5]),
    ]
    .concat());
    assert_eq!(il, "x := a AND b;");
}

#[test]
fn variables_in_the_power_flow() {
    let il = body_st(&[
        "<inVariable localId=\"2\"><expression>a</expression></inVariable>\n".to_string(),
        contact(3, "b", &[2]),
        "<outVariable localId=\"4\" negated=\"true\"><connectionPointIn><connection refLocalId=\"3\"/></connectionPointIn><expression>x</expression></outVariable>\n".to_string(),
    ]
    .concat());
    assert_eq!(il, "x := NOT(a AND b);");
}

#[test]
fn rungs_and_branches_without_positions_go_in_document_order() {
    // Two rungs interleaved in the document: rung order follows the first element.
    let il = body_st(
        &[
            contact(2, "a", &[1]),
            contact(3, "b", &[1]),
            coil(4, "y", &[3]),
            coil(5, "x", &[2]),
        ]
        .concat(),
    );
    assert_eq!(il, "x := a;\ny := b;");
}

#[test]
fn hidden_names_avoid_the_names_of_the_pou() {
    // A variable named `R_TRIG1` already exists: the detector takes the next number.
    let xml = project(
        &[
            elem(2, "contact", "a", &[1], " edge=\"rising\""),
            coil(3, "x", &[2]),
        ]
        .concat(),
    )
    .replace(
        "<localVars>",
        "<localVars><variable name=\"r_trig1\"><type><BOOL/></type></variable>",
    );
    let (c, d) = convert_text(&xml);
    assert!(d.is_empty(), "{d:#?}");
    assert!(c.unwrap().il.contains("R_TRIG2(CLK := a);"));
}

#[test]
fn the_rung_checks() {
    // Open circuit: a coil with nothing on its left.
    assert_eq!(codes_of(&coil(2, "x", &[])), [codes::LD_OPEN_CIRCUIT]);
    // A contact whose power reaches no coil.
    assert_eq!(codes_of(&contact(2, "a", &[1])), [codes::LD_OPEN_CIRCUIT]);
    // Coil on the left rail.
    assert_eq!(codes_of(&coil(2, "x", &[1])), [codes::LD_COIL_ON_RAIL]);
    // Short circuit: the rail wired straight to x, in parallel with contact a.
    assert_eq!(
        codes_of(&[contact(2, "a", &[1]), coil(3, "x", &[2, 1])].concat()),
        [codes::LD_SHORT_CIRCUIT]
    );
    // Bridge: a -> c -> x, b -> d -> x, and a wire from a into d.
    assert_eq!(
        codes_of(
            &[
                contact(2, "a", &[1]),
                contact(3, "c", &[2]),
                contact(4, "b", &[1]),
                contact(5, "d", &[4, 2]),
                coil(6, "x", &[3, 5]),
            ]
            .concat()
        ),
        [codes::LD_BRIDGE]
    );
    // A loop.
    assert_eq!(
        codes_of(
            &[
                contact(2, "a", &[3]),
                contact(3, "b", &[2]),
                coil(4, "x", &[3])
            ]
            .concat()
        ),
        [codes::LD_LOOP]
    );
    // Dangling: no element 9 (and no consequence reported).
    assert_eq!(
        codes_of(&[contact(2, "a", &[1]), coil(3, "x", &[2, 9])].concat()),
        [codes::LD_DANGLING]
    );
}

#[test]
fn an_upper_parallel_branch_needs_positions() {
    let at = |id: u32, tag: &str, var: &str, from: &[u32], y: u32| {
        let conns: String = from
            .iter()
            .map(|f| format!("<connection refLocalId=\"{f}\"/>"))
            .collect();
        format!(
            "<{tag} localId=\"{id}\"><position x=\"0\" y=\"{y}\"/><connectionPointIn><relPosition x=\"0\" y=\"10\"/>{conns}</connectionPointIn><connectionPointOut><relPosition x=\"21\" y=\"10\"/></connectionPointOut><variable>{var}</variable></{tag}>"
        )
    };
    let body = |b_y| {
        [
            at(2, "contact", "a", &[1], 40),
            at(3, "contact", "b", &[1], b_y),
            at(4, "coil", "x", &[2, 3], 40),
        ]
        .concat()
    };
    assert_eq!(codes_of(&body(80)), Vec::<&str>::new());
    assert_eq!(codes_of(&body(0)), [codes::LD_UPPER_PARALLEL]);
}

#[test]
fn tc6_1_0_files_and_st_bodies() {
    let xml = r#"<?xml version="1.0"?>
<project xmlns="http://www.plcopen.org/xml/tc6.xsd" xmlns:xhtml="http://www.w3.org/1999/xhtml">
<types><dataTypes/><pous>
<pou name="twice" pouType="function"><interface><returnType><INT/></returnType>
<inputVars><variable name="n"><type><INT/></type></variable></inputVars></interface>
<body><ST><xhtml:p><![CDATA[twice := n * 2;]]></xhtml:p></ST></body></pou>
</pous></types>
<instances><configurations><configuration name="c"><resource name="r">
<task name="t" interval="T#20ms" priority="1"><pouInstance name="i" type="twice"/></task>
</resource></configuration></configurations></instances></project>"#;
    let (c, d) = convert_text(xml);
    assert!(d.is_empty(), "{d:#?}");
    let c = c.unwrap();
    assert!(c.il.contains("FUNCTION twice : INT"), "{}", c.il);
    assert!(c.il.contains("    twice := n * 2;\n"), "{}", c.il);
    assert!(c.il.contains("TASK t(INTERVAL := T#20ms, PRIORITY := 1);"));
    assert!(c.il.contains("PROGRAM i WITH t : twice;"));
    // The ST text maps back to the CDATA, byte for byte.
    let at = c.il.find("n * 2").unwrap() as u32;
    let mut d = Diagnostic::error(
        "E0201",
        "x",
        plcc_ir::diag::Span::new(FileId(7), at, at + 1),
    );
    c.map.remap(&mut d, FileId(7), FileId(1));
    let span = d.span.unwrap();
    assert_eq!(span.file, FileId(1));
    assert_eq!(&xml[span.start as usize..span.end as usize], "n");
}

/// An ST body written with entities (`&lt;`, `&amp;`, `&#62;`) and CRLF line ends,
/// as CODESYS exports it, maps back byte for byte between them and each entity to
/// itself: a diagnostic after them points at its word, not at the whole body.
#[test]
fn st_bodies_with_entities_map_byte_for_byte() {
    let xml = "<?xml version=\"1.0\"?>\r\n<project xmlns=\"http://www.plcopen.org/xml/tc6_0201\" xmlns:xhtml=\"http://www.w3.org/1999/xhtml\">\r\n<types><dataTypes/><pous>\r\n<pou name=\"p\" pouType=\"program\"><interface><localVars><variable name=\"n\"><type><INT/></type></variable></localVars></interface>\r\n<body><ST><xhtml:p>IF n &lt; 3 &amp;&amp; n &#62; 1 THEN\r\n  n := n + 1;\r\nEND_IF;\r\nn := later;</xhtml:p></ST></body></pou>\r\n</pous></types></project>";
    let (c, _) = convert_text(xml);
    let c = c.unwrap();
    assert!(
        c.il.contains("IF n < 3 && n > 1 THEN\n  n := n + 1;"),
        "{}",
        c.il
    );
    for word in ["later", "n + 1", " 3 ", "THEN", "END_IF"] {
        let at = c.il.find(word).unwrap() as u32;
        let mut d = Diagnostic::error(
            "E0201",
            "x",
            plcc_ir::diag::Span::new(FileId(7), at, at + word.len() as u32),
        );
        c.map.remap(&mut d, FileId(7), FileId(1));
        let span = d.span.unwrap();
        assert_eq!(
            &xml[span.start as usize..span.end as usize],
            word,
            "in\n{}",
            c.il
        );
    }
    // An entity maps to its own start.
    let at = c.il.find('<').unwrap() as u32;
    let mut d = Diagnostic::error(
        "E0201",
        "x",
        plcc_ir::diag::Span::new(FileId(7), at, at + 1),
    );
    c.map.remap(&mut d, FileId(7), FileId(1));
    assert!(xml[d.span.unwrap().start as usize..].starts_with("&lt;"));
}

/// Task intervals in each form the editors write: `T#20ms`, an XML duration and the
/// old schema's `HH:MM:SS.ffffff`.
#[test]
fn task_intervals_in_every_form() {
    for (interval, want) in [
        ("T#20ms", "T#20ms"),
        ("PT0.05S", "T#50ms"),
        ("00:00:00.100000", "T#100ms"),
        ("00:01:02.5", "T#62500ms"),
    ] {
        let xml = format!(
            r#"<?xml version="1.0"?>
<project xmlns="http://www.plcopen.org/xml/tc6_0201">
<types><dataTypes/><pous>
<pou name="p" pouType="program"><interface><localVars><variable name="n"><type><INT/></type></variable></localVars></interface>
<body><ST><xhtml:p xmlns:xhtml="http://www.w3.org/1999/xhtml"><![CDATA[n := n + 1;]]></xhtml:p></ST></body></pou>
</pous></types>
<instances><configurations><configuration name="c"><resource name="r">
<task name="t" interval="{interval}" priority="0"><pouInstance name="i" typeName="p"/></task>
</resource></configuration></configurations></instances></project>"#
        );
        let (c, d) = convert_text(&xml);
        assert!(d.is_empty(), "{interval}: {d:#?}");
        let il = c.unwrap().il;
        assert!(
            il.contains(&format!("TASK t(INTERVAL := {want}, PRIORITY := 0);")),
            "{interval}: {il}"
        );
    }
}

#[test]
fn not_xml_and_not_plcopen() {
    let (c, d) = convert_text("PROGRAM p END_PROGRAM");
    assert!(c.is_none());
    assert_eq!(d[0].code, codes::LD_MALFORMED_XML);
    let (c, d) = convert_text("<project/>");
    assert!(c.is_none());
    assert_eq!(d[0].code, codes::LD_BAD_PROJECT);
}

#[test]
fn ascii_ladder() {
    let (c, d) = convert_text(&project(
        &[
            contact(2, "start", &[1]),
            contact(3, "run", &[1]),
            elem(4, "contact", "stop", &[2, 3], " negated=\"true\""),
            coil(5, "run", &[4]),
        ]
        .concat(),
    ));
    assert!(d.is_empty(), "{d:#?}");
    assert_eq!(
        c.unwrap().ld_text,
        "(* PROGRAM p *)\nrung 1\n|--[start]--+--[/stop]--(run)--|\n|--[run]----+                  |\n"
    );
}

#[test]
fn deep_documents_and_long_rungs_do_not_overflow() {
    // 10,000 nested elements: read without a stack overflow (nothing to compile).
    let deep = format!(
        "<?xml version=\"1.0\"?><project xmlns=\"http://www.plcopen.org/xml/tc6_0201\">{}{}</project>",
        "<a>".repeat(10_000),
        "</a>".repeat(10_000)
    );
    let _ = convert_text(&deep);
    // A rung of 10,000 contacts in series converts to one long AND chain.
    let mut elems = String::new();
    // The left power rail is element 1.
    for i in 0..10_000u32 {
        elems.push_str(&contact(i + 2, "a", &[i + 1]));
    }
    elems.push_str(&coil(10_002, "q", &[10_001]));
    let (c, diags) = convert_text(&project(&elems));
    assert!(diags.iter().all(|d| !d.is_error()), "{diags:#?}");
    let il = c.expect("converted").il;
    assert!(
        il.matches("AND a").count() >= 9_999,
        "{}",
        &il[..il.len().min(500)]
    );
}
