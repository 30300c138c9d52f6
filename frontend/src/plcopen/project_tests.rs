//! Unit tests of what a PLCopen project holds besides its bodies: globals at every
//! level, tasks and program instances, what CODESYS keeps in `<addData>`, the
//! dialect of the file, and the actions and transitions of POUs.

use super::*;
use crate::codes;
use crate::source::{SourceFile, SourceMap};
use crate::{Lang, LowerOptions};
use plcc_ir::diag::{Diagnostic, Span};

/// A TC6 2.01 project: `header` (a `<fileHeader>`, or nothing), then `types` (inside
/// `<types>`), `instances` (inside `<instances>`), `add_data` (the project's
/// `<addData>` content).
fn file(header: &str, pous: &str, instances: &str, add_data: &str) -> String {
    format!(
        r#"<?xml version="1.0" encoding="utf-8"?>
<project xmlns="http://www.plcopen.org/xml/tc6_0201" xmlns:xhtml="http://www.w3.org/1999/xhtml">
{header}
<types><dataTypes/><pous>{pous}</pous></types>
<instances><configurations>{instances}</configurations></instances>
<addData>{add_data}</addData>
</project>"#
    )
}

/// An ST body.
fn st(text: &str) -> String {
    format!("<body><ST><xhtml:p><![CDATA[{text}]]></xhtml:p></ST></body>")
}

/// A variable of an elementary type.
fn var(name: &str, ty: &str) -> String {
    format!(r#"<variable name="{name}"><type><{ty}/></type></variable>"#)
}

fn convert_text(xml: &str) -> (Option<Converted>, Vec<Diagnostic>) {
    let mut diags = Vec::new();
    let c = convert(FileId(1), "t.xml", xml, &Options::default(), &mut diags);
    (c, diags)
}

/// The view of a file that converts with no diagnostic at all.
fn view(xml: &str) -> String {
    let (c, d) = convert_text(xml);
    assert!(d.is_empty(), "{d:#?}");
    c.expect("converted").il
}

/// The codes of the diagnostics of a file's conversion.
fn codes_of(xml: &str) -> Vec<&'static str> {
    convert_text(xml).1.iter().map(|d| d.code).collect()
}

/// Compiles a PLCopen file with `opts`: the diagnostics (errors and warnings), and
/// whether a module was made.
fn compile_with(xml: &str, opts: &LowerOptions) -> (Vec<Diagnostic>, bool) {
    let mut sources = SourceMap::new();
    let f = sources.add(SourceFile::new("t.xml", xml));
    let c = crate::compile(&mut sources, &[(f, Lang::Ld)], opts);
    (c.diagnostics, c.module.is_some())
}

/// Compiles a PLCopen file, which must give no diagnostic at all.
fn compiles(xml: &str) {
    let (d, ok) = compile_with(xml, &LowerOptions::default());
    assert!(d.is_empty() && ok, "{d:#?}");
}

/// The text of the XML that a span of the view is mapped back to.
fn mapped<'x>(c: &Converted, xml: &'x str, at: &str) -> &'x str {
    let start = c.il.find(at).unwrap_or_else(|| panic!("{at} in {}", c.il)) as u32;
    let mut d = Diagnostic::error("E0201", "x", Span::new(FileId(7), start, start + 1));
    c.map.remap(&mut d, FileId(7), FileId(1));
    let s = d.span.unwrap();
    assert_eq!(s.file, FileId(1), "{at} is not mapped back");
    &xml[s.start as usize..s.end as usize]
}

// ---------------------------------------------------------------- globals

#[test]
fn globals_of_configurations_and_resources_with_addresses() {
    let pou = format!(
        r#"<pou name="main" pouType="program"><interface>
<externalVars>{}{}{}</externalVars></interface>{}</pou>"#,
        var("limit", "INT"),
        var("start", "BOOL"),
        var("lamp", "BOOL"),
        st("lamp := start AND limit > 2;")
    );
    let config = format!(
        r#"<configuration name="c">
<resource name="r">
<task name="t" interval="T#10ms" priority="0"><pouInstance name="m" typeName="main"/></task>
<globalVars><variable name="start" address="%IX0.0"><type><BOOL/></type></variable>
<variable name="lamp" address="%QX0.1"><type><BOOL/></type></variable></globalVars>
</resource>
<globalVars constant="true"><variable name="limit"><type><INT/></type><initialValue><simpleValue value="3"/></initialValue></variable></globalVars>
<globalVars nonretain="true">{}</globalVars>
</configuration>"#,
        var("spare", "WORD")
    );
    let xml = file("", &pou, &config, "");
    let v = view(&xml);
    assert!(
        v.contains("VAR_GLOBAL CONSTANT\n    limit : INT := 3;\nEND_VAR"),
        "{v}"
    );
    assert!(
        v.contains("VAR_GLOBAL NON_RETAIN\n    spare : WORD;\nEND_VAR"),
        "{v}"
    );
    assert!(v.contains("    start AT %IX0.0 : BOOL;\n"), "{v}");
    assert!(v.contains("    lamp AT %QX0.1 : BOOL;\n"), "{v}");
    // The address is the attribute's text.
    let (c, _) = convert_text(&xml);
    let c = c.unwrap();
    assert_eq!(mapped(&c, &xml, "%QX0.1"), "%");
    compiles(&xml);
}

#[test]
fn codesys_global_variable_lists_in_add_data() {
    let gvls = format!(
        r#"<data name="http://www.3s-software.com/plcopenxml/globalvars" handleUnknown="implementation">
<globalVars name="GVL_Main">{}</globalVars>
<globalVars name="GVL_Mixed" constant="true">
  {}{}
  <addData><data name="http://www.3s-software.com/plcopenxml/mixedattrsvarlist" handleUnknown="implementation">
    <MixedAttrsVarList>
      <globalVars name="GVL_Mixed" constant="true"><variable name="size"><type><INT/></type><initialValue><simpleValue value="8"/></initialValue></variable></globalVars>
      <globalVars name="GVL_Mixed">{}</globalVars>
    </MixedAttrsVarList>
  </data></addData>
</globalVars>
</data>"#,
        var("speed", "INT"),
        var("size", "INT"),
        var("used", "INT"),
        var("used", "INT")
    );
    let pou = format!(
        r#"<pou name="main" pouType="program"><interface/>{}</pou>"#,
        st("GVL_Mixed.used := size + GVL_Main.speed + GVL_Mixed.size;")
    );
    let xml = file("", &pou, "", &gvls);
    let v = view(&xml);
    // The mixed list's true lists, not the flattened one (CONSTANT, without the
    // initial value), with their names, which qualify their variables.
    assert!(
        v.contains(
            "VAR_GLOBAL GVL_Main\n    speed : INT;\nEND_VAR\n\n\
             VAR_GLOBAL GVL_Mixed CONSTANT\n    size : INT := 8;\nEND_VAR\n\n\
             VAR_GLOBAL GVL_Mixed\n    used : INT;\nEND_VAR\n"
        ),
        "{v}"
    );
    compiles(&xml);
}

// ---------------------------------------------------------------- tasks

/// A project with PROGRAM `p` and one resource holding `resource` (tasks, instances).
fn tasks_file(header: &str, resource: &str) -> String {
    let pou = format!(
        r#"<pou name="p" pouType="program"><interface><localVars>{}</localVars></interface>{}</pou>"#,
        var("n", "INT"),
        st("n := n + 1;")
    );
    let config = format!(
        r#"<configuration name="c"><resource name="r">{resource}
<globalVars>{}</globalVars></resource></configuration>"#,
        var("go", "BOOL")
    );
    file(header, &pou, &config, "")
}

#[test]
fn tasks_single_priority_and_instances() {
    let xml = tasks_file(
        "",
        r#"<task name="fast" interval="T#20ms" priority="3"><pouInstance name="i1" typeName="p"/></task>
<task name="every" interval="PT0S" priority="1"><pouInstance name="i2" typeName="p"/></task>
<task name="old" interval="00:00:00" priority="2"/>
<task name="once" single="go" priority="4"><pouInstance name="i3" typeName="p"/></task>
<pouInstance name="free" typeName="p"/>"#,
    );
    let v = view(&xml);
    for line in [
        "TASK fast(INTERVAL := T#20ms, PRIORITY := 3);",
        // A zero interval is left out: the task runs in every cycle.
        "TASK every(PRIORITY := 1);",
        "TASK old(PRIORITY := 2);",
        "TASK once(SINGLE := go, PRIORITY := 4);",
        "PROGRAM i1 WITH fast : p;",
        "PROGRAM i2 WITH every : p;",
        "PROGRAM free : p;",
    ] {
        assert!(v.contains(line), "{line} in {v}");
    }
    // What the compiler says about a task maps back to its attributes.
    let (c, _) = convert_text(&xml);
    let c = c.unwrap();
    assert_eq!(mapped(&c, &xml, "SINGLE"), "go");
    assert_eq!(mapped(&c, &xml, "PRIORITY := 3"), "3");
    assert_eq!(mapped(&c, &xml, "TASK fast"), "fast");
    // An event task compiles (the global `go` is its event).
    let (d, ok) = compile_with(&xml, &LowerOptions::default());
    assert!(ok && d.iter().all(|d| !d.is_error()), "{d:#?}");
    // An error about the event is at the attribute: `stop` is declared nowhere.
    let bad = xml.replace(r#"single="go""#, r#"single="stop""#);
    let (d, ok) = compile_with(&bad, &LowerOptions::default());
    assert!(!ok);
    let e = d.iter().find(|d| d.is_error()).unwrap();
    assert_eq!(e.code, codes::E_UNDECLARED, "{d:#?}");
    let s = e.span.unwrap();
    assert_eq!(&bad[s.start as usize..s.end as usize], "stop");
}

#[test]
fn a_task_of_several_variables_is_not_supported() {
    let xml = tasks_file("", r#"<task name="t" single="[a,b]" priority="0"/>"#);
    assert_eq!(codes_of(&xml), [codes::E_UNSUPPORTED]);
}

#[test]
fn codesys_task_settings_and_instances_of_programs_by_name() {
    // TwinCAT writes `PT0S` and the interval in the task settings; CODESYS writes an
    // instance of a PROGRAM with `typeName=""`.
    let settings = |kind: &str, interval: &str, unit: &str| {
        format!(
            r#"<addData><data name="http://www.3s-software.com/plcopenxml/tasksettings" handleUnknown="implementation">
<TaskSettings KindOfTask="{kind}" Interval="{interval}" IntervalUnit="{unit}"/></data></addData>"#
        )
    };
    let xml = tasks_file(
        "",
        &format!(
            r#"<task name="a" interval="PT0S" priority="1"><pouInstance name="p" typeName=""/>{}</task>
<task name="b" priority="2">{}</task>
<task name="c" interval="PT0.05S" priority="3">{}</task>
<task name="d" priority="4">{}</task>"#,
            settings("Cyclic", "10000", "us"),
            settings("Cyclic", "t#50ms", "ms"),
            settings("Cyclic", "20", "ms"),
            settings("Freewheeling", "20", "ms"),
        ),
    );
    let v = view(&xml);
    for line in [
        "TASK a(INTERVAL := T#10000us, PRIORITY := 1);",
        "TASK b(INTERVAL := t#50ms, PRIORITY := 2);",
        // The attribute, when it is not zero.
        "TASK c(INTERVAL := T#50ms, PRIORITY := 3);",
        "TASK d(PRIORITY := 4);",
        "PROGRAM p WITH a : p;",
    ] {
        assert!(v.contains(line), "{line} in {v}");
    }
    compiles(&xml);
}

#[test]
fn durations_in_every_form() {
    for (text, ms) in [
        ("T#20ms", Some(20.0)),
        ("t#1.5s", Some(1500.0)),
        ("TIME#1h_2m", Some(3_720_000.0)),
        ("T#500us", Some(0.5)),
        ("LT#1d", Some(86_400_000.0)),
        ("PT0.05S", Some(50.0)),
        ("PT1M30S", Some(90_000.0)),
        ("PT0S", Some(0.0)),
        ("00:00:00.100000", Some(100.0)),
        ("00:01:02.5", Some(62_500.0)),
        ("T#5x", None),
        ("20", None),
        ("D#2020-01-01", None),
    ] {
        assert_eq!(xml::duration_ms(text), ms, "{text}");
    }
}

// ---------------------------------------------------------------- CODESYS

/// A CODESYS "application" export: no configuration, and everything inside the
/// project's `<addData>`.
fn application(header: &str, pou_body: &str, locals: &str) -> String {
    let app = format!(
        r#"<data name="http://www.3s-software.com/plcopenxml/application" handleUnknown="implementation">
<resource name="App">
  <task name="PlcTask" interval="PT0S" priority="20"><pouInstance name="MAIN" typeName=""/>
    <addData><data name="http://www.3s-software.com/plcopenxml/tasksettings" handleUnknown="implementation">
      <TaskSettings KindOfTask="Cyclic" Interval="10" IntervalUnit="ms"/></data></addData>
  </task>
  <globalVars name="GVL">{}</globalVars>
  <addData><data name="http://www.3s-software.com/plcopenxml/pou" handleUnknown="implementation">
    <pou name="MAIN" pouType="program"><interface><localVars>{locals}</localVars></interface>{}</pou>
  </data></addData>
</resource></data>"#,
        var("count", "INT"),
        st(pou_body)
    );
    file(header, "", "", &app)
}

const CODESYS: &str =
    r#"<fileHeader companyName="" productName="CODESYS" productVersion="CODESYS V3.5 SP16"/>"#;

#[test]
fn codesys_applications_and_their_pous_in_add_data() {
    let xml = application(CODESYS, "count := count + 1;", "");
    let v = view(&xml);
    assert!(
        v.contains("VAR_GLOBAL GVL\n    count : INT;\nEND_VAR"),
        "{v}"
    );
    assert!(v.contains("PROGRAM MAIN\n"), "{v}");
    assert!(
        v.contains(
            "CONFIGURATION App\n  RESOURCE App ON PLC\n    \
             TASK PlcTask(INTERVAL := T#10ms, PRIORITY := 20);\n    \
             PROGRAM MAIN WITH PlcTask : MAIN;\n  END_RESOURCE\nEND_CONFIGURATION"
        ),
        "{v}"
    );
    compiles(&xml);
}

#[test]
fn the_dialect_follows_the_header() {
    let cases = [
        (CODESYS, Dialect::Codesys),
        (
            r#"<fileHeader companyName="WAGO" productName="e!COCKPIT" productVersion="e!COCKPIT"/>"#,
            Dialect::Codesys,
        ),
        (
            r#"<fileHeader companyName="Beckhoff Automation GmbH" productName="TwinCAT PLC Control" productVersion="3.5"/>"#,
            Dialect::Codesys,
        ),
        (
            r#"<fileHeader companyName="Beremiz" productName="Beremiz" productVersion="1"/>"#,
            Dialect::Iec,
        ),
        (
            r#"<fileHeader companyName="Unknown" productName="Unnamed" productVersion="1"/>"#,
            Dialect::Iec,
        ),
        ("", Dialect::Iec),
    ];
    for (header, want) in cases {
        let xml = file(header, "", "", "");
        let (c, d) = convert_text(&xml);
        assert!(d.is_empty(), "{d:#?}");
        assert_eq!(c.unwrap().dialect, want, "{header}");
    }
    // CODESYS's vendor data in the content header, whatever the file header says.
    let xml = file(
        r#"<fileHeader companyName="ACME" productName="Machine" productVersion="1"/>
<contentHeader name="x"><addData><data name="http://www.3s-software.com/plcopenxml/projectinformation" handleUnknown="implementation"><ProjectInformation/></data></addData></contentHeader>"#,
        "",
        "",
        "",
    );
    assert_eq!(convert_text(&xml).0.unwrap().dialect, Dialect::Codesys);
}

#[test]
fn a_codesys_file_compiles_in_the_codesys_dialect_unless_told_otherwise() {
    let locals = r#"<variable name="p"><type><pointer><baseType><INT/></baseType></pointer></type></variable>"#;
    let xml = application(CODESYS, "p := ADR(count);\np^ := p^ + 1;", locals);
    // `<pointer>` is CODESYS's POINTER TO in a CODESYS file, a reference elsewhere.
    assert!(view(&xml).contains("    p : POINTER TO INT;\n"));
    compiles(&xml);
    // `--dialect iec` is obeyed.
    let iec = LowerOptions {
        dialect_given: true,
        ..LowerOptions::default()
    };
    let (d, ok) = compile_with(&xml, &iec);
    assert!(!ok && d.iter().any(|d| d.is_error()), "{d:#?}");
    // In a file from another editor (and without CODESYS's vendor data) it is a
    // reference: REF_TO.
    let pou = format!(
        r#"<pou name="main" pouType="program"><interface><localVars>{locals}</localVars></interface>{}</pou>"#,
        st("p := REF(p);")
    );
    assert!(view(&file("", &pou, "", "")).contains("    p : REF_TO INT;\n"));
}

#[test]
fn methods_and_var_lists() {
    // CODESYS's methods, in the POU's `<addData>`: written after the body.
    let method = |n: &str| {
        format!(
            r#"<data name="http://www.3s-software.com/plcopenxml/method" handleUnknown="implementation"><Method name="{n}"><interface/>{}</Method></data>"#,
            st("n := n + 1;")
        )
    };
    let pou = format!(
        r#"<pou name="fb" pouType="functionBlock"><interface><localVars>{}</localVars></interface>{}<addData>{}{}</addData></pou>"#,
        var("n", "INT"),
        st(""),
        method("Start"),
        method("Stop")
    );
    let xml = file("", &pou, "", "");
    let v = view(&xml);
    assert!(
        v.contains("METHOD Start\n    n := n + 1;\nEND_METHOD\nMETHOD Stop\n"),
        "{v}"
    );
    compiles(&xml);
    // `<varList>` is no variable section: skipped, with one warning for the POU.
    let pou = format!(
        r#"<pou name="p" pouType="program"><interface><localVars>{}</localVars>
<varList>{}</varList><varList><variable name=""><type><derived name=""/></type></variable></varList>
</interface>{}</pou>"#,
        var("x", "INT"),
        var("x", "INT"),
        st("x := 1;")
    );
    let xml = file("", &pou, "", "");
    let (c, d) = convert_text(&xml);
    assert_eq!(d.len(), 1, "{d:#?}");
    assert_eq!(d[0].code, codes::W_PLCOPEN_SKIPPED);
    assert!(!d[0].is_error());
    assert!(d[0].message.starts_with("2 `<varList>` elements"), "{d:#?}");
    let s = d[0].span.unwrap();
    assert_eq!(&xml[s.start as usize..s.end as usize], "varList");
    assert_eq!(c.unwrap().il.matches("x : INT;").count(), 1);
}

// ---------------------------------------------------------------- actions

/// An LD body: `in` through a rising contact to coil `out` (localIds 1 to 4).
fn ld_rising(input: &str, out: &str) -> String {
    format!(
        r#"<body><LD><leftPowerRail localId="1"/>
<contact localId="2" edge="rising"><connectionPointIn><connection refLocalId="1"/></connectionPointIn><variable>{input}</variable></contact>
<coil localId="3"><connectionPointIn><connection refLocalId="2"/></connectionPointIn><variable>{out}</variable></coil>
<rightPowerRail localId="4"><connectionPointIn><connection refLocalId="3"/></connectionPointIn></rightPowerRail>
</LD></body>"#
    )
}

#[test]
fn actions_in_st_il_and_ld() {
    let ld = ld_rising("a", "x");
    let fb = format!(
        r#"<pou name="fb" pouType="functionBlock"><interface><inputVars>{}{}</inputVars>
<outputVars>{}{}{}</outputVars></interface>{ld}
<actions>
<action name="clear">{}</action>
<action name="add2"><body><IL><xhtml:p><![CDATA[LD n
ADD 2
ST n]]></xhtml:p></IL></body></action>
<action name="edge">{}</action>
</actions></pou>"#,
        var("a", "BOOL"),
        var("b", "BOOL"),
        var("x", "BOOL"),
        var("y", "BOOL"),
        var("n", "INT"),
        st("n := 0;"),
        ld_rising("b", "y"),
    );
    let main = format!(
        r#"<pou name="main" pouType="program"><interface><localVars>
<variable name="f"><type><derived name="fb"/></type></variable>{}</localVars></interface>{}
<actions><action name="step">{}</action></actions></pou>"#,
        var("k", "INT"),
        st("f(); f.add2(); step();\nIF k > 2 THEN f.clear(); END_IF;"),
        st("k := k + 1;"),
    );
    let xml = file("", &format!("{fb}{main}"), "", "");
    let v = view(&xml);
    // The hidden variables of the body and of the LD action are declared once, in
    // the POU, before the code, with different names.
    let fb_text = &v[v.find("FUNCTION_BLOCK fb").unwrap()..v.find("END_FUNCTION_BLOCK").unwrap()];
    assert_eq!(fb_text.matches(": R_TRIG;").count(), 2, "{fb_text}");
    assert!(fb_text.contains("R_TRIG1 : R_TRIG;"), "{fb_text}");
    assert!(fb_text.contains("R_TRIG2 : R_TRIG;"), "{fb_text}");
    assert!(
        fb_text.find(": R_TRIG;").unwrap() < fb_text.find("ACTION clear:").unwrap(),
        "{fb_text}"
    );
    for part in [
        "ACTION clear:\n    n := 0;\nEND_ACTION\n",
        "ACTION add2:\n    LD n\nADD 2\nST n\nEND_ACTION\n",
        "ACTION edge:\n",
    ] {
        assert!(fb_text.contains(part), "{part} in {fb_text}");
    }
    assert!(
        v.contains("ACTION step:\n    k := k + 1;\nEND_ACTION\nEND_PROGRAM"),
        "{v}"
    );
    // The action's header maps back to the action's element.
    let (c, _) = convert_text(&xml);
    assert_eq!(mapped(&c.unwrap(), &xml, "ACTION step"), "action");
    compiles(&xml);
}

#[test]
fn errors_in_actions_name_the_action() {
    let pou = |actions: &str| {
        file(
            "",
            &format!(
                r#"<pou name="p" pouType="program"><interface><localVars>{}</localVars></interface>{}<actions>{actions}</actions></pou>"#,
                var("x", "BOOL"),
                st("x := TRUE;")
            ),
            "",
            "",
        )
    };
    let (_, d) = convert_text(&pou(r#"<action name="a"><body><SFC/></body></action>"#));
    assert_eq!(d.len(), 1, "{d:#?}");
    assert_eq!(d[0].code, codes::SFC_NO_INITIAL_STEP);
    assert!(d[0].message.contains("`p.a`"), "{}", d[0].message);
    let (_, d) = convert_text(&pou(&format!(
        r#"<action name="a">{0}</action><action name="A">{0}</action>"#,
        st("x := FALSE;")
    )));
    assert_eq!(d.len(), 1, "{d:#?}");
    assert_eq!(d[0].code, codes::E_DUPLICATE);
    // A rung check in an action's ladder names it.
    let open = r#"<action name="a"><body><LD><leftPowerRail localId="1"/>
<coil localId="3"><connectionPointIn/><variable>x</variable></coil></LD></body></action>"#;
    let mut strict = Vec::new();
    let opts = Options {
        strict_rungs: true,
        ..Options::default()
    };
    assert!(convert(FileId(1), "t.xml", &pou(open), &opts, &mut strict).is_none());
    assert!(
        strict.iter().any(|d| d.message.contains("`p.a`")),
        "{strict:#?}"
    );
    // A FUNCTION has no actions: the compiler says so, at the action.
    let xml = file(
        "",
        &format!(
            r#"<pou name="f" pouType="function"><interface><returnType><INT/></returnType></interface>{}
<actions><action name="a">{}</action></actions></pou>"#,
            st("f := 1;"),
            st("f := 2;")
        ),
        "",
        "",
    );
    let (d, ok) = compile_with(&xml, &LowerOptions::default());
    assert!(!ok);
    let e = d.iter().find(|d| d.is_error()).unwrap();
    assert_eq!(e.code, codes::E_BAD_DECLARATION, "{d:#?}");
    let s = e.span.unwrap();
    assert_eq!(s.file, FileId(0));
    assert_eq!(&xml[s.start as usize - 6..s.end as usize], "name=\"a");
}

#[test]
fn transitions_are_read() {
    let xml = file(
        "",
        &format!(
            r#"<pou name="p" pouType="program"><interface><localVars>{}</localVars></interface>{}
<transitions><transition name="t1"><body><ST><xhtml:p><![CDATA[x AND NOT x]]></xhtml:p></ST></body></transition>
<transition name="t2">{}</transition></transitions></pou>"#,
            var("x", "BOOL"),
            st("x := TRUE;"),
            ld_rising("x", "t2")
        ),
        "",
        "",
    );
    let mut d = Vec::new();
    let p = xml::read(FileId(1), &xml, &mut d).unwrap();
    assert!(d.is_empty(), "{d:#?}");
    let t = &p.pous[0].transitions;
    assert_eq!(t.len(), 2);
    assert_eq!(t[0].name.value, "t1");
    assert!(matches!(&t[0].body, xml::Body::St(s) if s.value == "x AND NOT x"));
    assert!(matches!(&t[1].body, xml::Body::Graph(xml::Graphic::Ld, e) if e.len() == 4));
    // Only a chart (an SFC body) uses them: beside an ST body the view has no trace of them.
    assert!(!view(&xml).contains("t1"));
}

// ---------------------------------------------------------------- values

#[test]
fn string_values_without_quotes_are_quoted_as_the_editors_quote_them() {
    let types = r#"<dataTypes>
<dataType name="Name"><baseType><string length="20"/></baseType><initialValue><simpleValue value="anon"/></initialValue></dataType>
<dataType name="Label"><baseType><derived name="Name"/></baseType></dataType>
<dataType name="Rec"><baseType><struct><variable name="tag"><type><derived name="Label"/></type><initialValue><simpleValue value="t"/></initialValue></variable></struct></baseType></dataType>
</dataTypes>"#;
    let vars = r#"<variable name="a"><type><string/></type><initialValue><simpleValue value="it's $5"/></initialValue></variable>
<variable name="b"><type><wstring/></type><initialValue><simpleValue value="wide"/></initialValue></variable>
<variable name="c"><type><derived name="Label"/></type><initialValue><simpleValue value="x"/></initialValue></variable>
<variable name="d"><type><string/></type><initialValue><simpleValue value="'kept'"/></initialValue></variable>
<variable name="e"><type><INT/></type><initialValue><simpleValue value="5"/></initialValue></variable>"#;
    let pou = format!(
        r#"<pou name="main" pouType="program"><interface><localVars>{vars}</localVars></interface>{}</pou>"#,
        st("e := e + 1;")
    );
    let text = |header: &str| file(header, &pou, "", "").replace("<dataTypes/>", types);
    let xml = text("");
    let v = view(&xml);
    for decl in [
        "Name : STRING[20] := 'anon';",
        "tag : Label := 't';",
        "a : STRING := 'it$'s $$5';",
        "b : WSTRING := \"wide\";",
        "c : Label := 'x';",
        "d : STRING := 'kept';",
        "e : INT := 5;",
    ] {
        assert!(v.contains(decl), "{decl} in {v}");
    }
    // Quoted, the value still maps back to the attribute's text.
    let (c, _) = convert_text(&xml);
    assert_eq!(mapped(&c.unwrap(), &xml, "x';"), "x");
    compiles(&xml);
    // CODESYS writes initial values as expressions: they are kept as written.
    let v = view(&text(CODESYS));
    assert!(v.contains("c : Label := x;"), "{v}");
}

// ---------------------------------------------------------------- CODESYS OO

/// CODESYS's `<data name=".../kind">` holding `inner`.
fn data(kind: &str, inner: &str) -> String {
    format!(
        r#"<data name="http://www.3s-software.com/plcopenxml/{kind}" handleUnknown="implementation">{inner}</data>"#
    )
}

#[test]
fn codesys_methods_properties_inheritance_and_interfaces() {
    let itf = data(
        "interface",
        r#"<Interface name="I_Dev"><Methods><Method name="Run"><interface><returnType><INT/></returnType>
<inputVars><variable name="k"><type><INT/></type></variable></inputVars></interface><addData/></Method></Methods>
<Properties><Property name="Ready"><interface><returnType><BOOL/></returnType></interface><GetAccessor/></Property></Properties>
</Interface>"#,
    );
    let run = data(
        "method",
        &format!(
            r#"<Method name="Run"><interface><returnType><INT/></returnType><inputVars>{}</inputVars>
<addData>{}</addData></interface>{}</Method>"#,
            var("k", "INT"),
            data("accessmodifiers", r#"<AccessModifiers Public="true"/>"#),
            st("n := n + k; Run := n;")
        ),
    );
    let helper = data(
        "method",
        &format!(
            r#"<Method name="Twice"><interface><returnType><INT/></returnType><addData>{}</addData></interface>{}
<InterfaceAsPlainText><xhtml:p>METHOD PROTECTED Twice : INT</xhtml:p></InterfaceAsPlainText></Method>"#,
            data("accessmodifiers", r#"<AccessModifiers Protected="true"/>"#),
            st("Twice := 2 * n;")
        ),
    );
    let ready = data(
        "property",
        &format!(
            r#"<Property name="Ready"><interface><returnType><BOOL/></returnType></interface>
<GetAccessor>{}</GetAccessor>
<SetAccessor><interface><localVars>{}</localVars></interface>{}</SetAccessor></Property>"#,
            st("Ready := n > 0;"),
            var("v", "BOOL"),
            st("v := Ready; IF NOT v THEN n := 0; END_IF;")
        ),
    );
    let base = format!(
        r#"<pou name="Base" pouType="functionBlock"><interface><localVars>{}</localVars>
<addData>{}</addData></interface>{}<addData>{run}{helper}{ready}{}</addData></pou>"#,
        var("n", "INT"),
        data(
            "pouinheritance",
            "<Inheritance><Implements>I_Dev</Implements></Inheritance>"
        ),
        st(""),
        data(
            "interfaceasplaintext",
            "<InterfaceAsPlainText><xhtml:p>{attribute 'reflection'}\nFUNCTION_BLOCK INTERNAL ABSTRACT Base IMPLEMENTS I_Dev</xhtml:p></InterfaceAsPlainText>"
        ),
    );
    let run2 = data(
        "method",
        &format!(
            r#"<Method name="Run"><interface><returnType><INT/></returnType><inputVars>{}</inputVars></interface>{}</Method>"#,
            var("k", "INT"),
            st("Run := SUPER^.Run(k) + Twice();")
        ),
    );
    let derived = format!(
        r#"<pou name="Derived" pouType="functionBlock"><interface><addData>{}</addData></interface>{}<addData>{run2}</addData></pou>"#,
        data(
            "pouinheritance",
            "<Inheritance><Extends>Base</Extends></Inheritance>"
        ),
        st(""),
    );
    let main = format!(
        r#"<pou name="main" pouType="program"><interface><localVars>
<variable name="d"><type><derived name="Derived"/></type></variable>
<variable name="i"><type><derived name="I_Dev"/></type></variable>{}{}</localVars></interface>{}</pou>"#,
        var("r", "INT"),
        var("ok", "BOOL"),
        st("i := d; r := i.Run(k := 1); ok := i.Ready; d.Ready := FALSE;")
    );
    let xml = file(CODESYS, &format!("{base}{derived}{main}"), "", &itf);
    let v = view(&xml);
    for want in [
        "INTERFACE I_Dev\nMETHOD Run : INT\nVAR_INPUT\n    k : INT;\nEND_VAR\nEND_METHOD\n\
         PROPERTY Ready : BOOL\nGET\nEND_GET\nEND_PROPERTY\nEND_INTERFACE\n",
        "FUNCTION_BLOCK ABSTRACT Base IMPLEMENTS I_Dev\n",
        "METHOD PUBLIC Run : INT\n",
        "METHOD PROTECTED Twice : INT\n",
        "PROPERTY Ready : BOOL\nGET\n    Ready := n > 0;\nEND_GET\nSET\nVAR\n    v : BOOL;\nEND_VAR\n",
        "FUNCTION_BLOCK Derived EXTENDS Base\n",
    ] {
        assert!(v.contains(want), "{want}\nnot in\n{v}");
    }
    // Names map back to the XML exactly.
    let (c, _) = convert_text(&xml);
    let c = c.unwrap();
    let at = mapped(&c, &xml, "Base\n    \n").as_ptr() as usize - xml.as_ptr() as usize;
    assert!(xml[at..].starts_with("Base</Extends>"), "{}", &xml[at..]);
    assert_eq!(mapped(&c, &xml, "PROTECTED"), "AccessModifiers");
    let (d, ok) = compile_with(&xml, &LowerOptions::default());
    assert!(d.is_empty() && ok, "{d:#?}");
}

#[test]
fn codesys_oo_errors_point_at_the_xml() {
    let fb = |members: &str, iface_add: &str| {
        format!(
            r#"<pou name="fb" pouType="functionBlock"><interface><localVars>{}</localVars><addData>{iface_add}</addData></interface>{}<addData>{members}</addData></pou>"#,
            var("n", "INT"),
            st("")
        )
    };
    // A method without a name.
    let xml = file(
        CODESYS,
        &fb(
            &data(
                "method",
                &format!("<Method><interface/>{}</Method>", st("")),
            ),
            "",
        ),
        "",
        "",
    );
    let (_, d) = convert_text(&xml);
    assert_eq!(d.len(), 1, "{d:#?}");
    assert_eq!(d[0].code, codes::LD_BAD_PROJECT);
    assert!(d[0].message.contains("`<Method>` needs a `name`"), "{d:#?}");
    let s = d[0].span.unwrap();
    assert_eq!(&xml[s.start as usize..s.end as usize], "Method");
    // An accessor with inputs.
    let bad_set = data(
        "property",
        &format!(
            r#"<Property name="P"><interface><returnType><INT/></returnType></interface>
<SetAccessor><interface><inputVars>{}</inputVars></interface>{}</SetAccessor></Property>"#,
            var("x", "INT"),
            st("n := P;")
        ),
    );
    let xml = file(CODESYS, &fb(&bad_set, ""), "", "");
    let (_, d) = convert_text(&xml);
    assert_eq!(d.len(), 1, "{d:#?}");
    assert_eq!(d[0].code, codes::LD_BAD_PROJECT);
    assert!(
        d[0].message
            .contains("the SET accessor of property `fb.P` declares inputs"),
        "{d:#?}"
    );
    let s = d[0].span.unwrap();
    assert_eq!(&xml[s.start as usize..s.end as usize], "interface");
    // An element that is no accessor; a property without a type.
    let odd = data(
        "property",
        r#"<Property name="P"><interface><returnType><INT/></returnType></interface><Getter/></Property>
<Property name="Q"><GetAccessor/></Property>"#,
    );
    let xml = file(CODESYS, &fb(&odd, ""), "", "");
    let (_, d) = convert_text(&xml);
    let texts: Vec<&str> = d
        .iter()
        .map(|d| {
            let s = d.span.unwrap();
            &xml[s.start as usize..s.end as usize]
        })
        .collect();
    assert_eq!(texts, ["Getter", "Property"], "{d:#?}");
    assert!(
        d[1].message.contains("property `fb.Q` has no type"),
        "{d:#?}"
    );
    // An accessor's body in FBD: not supported yet (a method's is).
    let fbd = data(
        "property",
        r#"<Property name="P"><interface><returnType><INT/></returnType></interface><GetAccessor><body><FBD/></body></GetAccessor></Property>"#,
    );
    assert_eq!(
        codes_of(&file(CODESYS, &fb(&fbd, ""), "", "")),
        [codes::E_LANGUAGE_UNSUPPORTED]
    );
    // EXTENDS of an unknown FB: the lowering's error, at the name in `<Extends>`;
    // a library's (qualified) name at the whole element.
    for (base, at) in [
        ("Nothing", "Nothing"),
        ("COL.Base", "<Extends>COL.Base</Extends>"),
    ] {
        let inh = data(
            "pouinheritance",
            &format!("<Inheritance><Extends>{base}</Extends></Inheritance>"),
        );
        let xml = file(CODESYS, &fb("", &inh), "", "");
        let (d, ok) = compile_with(&xml, &LowerOptions::default());
        assert!(!ok);
        assert_eq!(d.len(), 1, "{d:#?}");
        assert_eq!(d[0].code, codes::E_OO_DECLARATION);
        assert!(d[0].message.contains("is not a FUNCTION_BLOCK"), "{d:#?}");
        let s = d[0].span.unwrap();
        assert_eq!(&xml[s.start as usize..s.end as usize], at);
    }
    // Methods of a FUNCTION.
    let f = format!(
        r#"<pou name="f" pouType="function"><interface><returnType><INT/></returnType></interface>{}<addData>{}</addData></pou>"#,
        st("f := 1;"),
        data(
            "method",
            &format!(r#"<Method name="M"><interface/>{}</Method>"#, st(""))
        )
    );
    assert_eq!(
        codes_of(&file(CODESYS, &f, "", "")),
        [codes::E_OO_DECLARATION]
    );
}

#[test]
fn methods_called_as_fbd_blocks_through_an_interface() {
    // I_B extends I_A, which declares Get : INT (input k, output flag); `i.Get`
    // drawn as a block with its result on an output named as nothing of the method.
    let itf = data(
        "interface",
        r#"<Interface name="I_A"><Methods><Method name="Get"><interface><returnType><INT/></returnType>
<inputVars><variable name="k"><type><INT/></type></variable></inputVars>
<outputVars><variable name="flag"><type><BOOL/></type></variable></outputVars></interface></Method></Methods></Interface>"#,
    ) + &data(
        "interface",
        "<Interface name=\"I_B\"><Inheritance><Extends>I_A</Extends></Inheritance></Interface>",
    );
    let get = data(
        "method",
        &format!(
            r#"<Method name="Get"><interface><returnType><INT/></returnType><inputVars>{}</inputVars>
<outputVars>{}</outputVars></interface>{}</Method>"#,
            var("k", "INT"),
            var("flag", "BOOL"),
            st("Get := 2 * k; flag := k > 1;")
        ),
    );
    let fb = format!(
        r#"<pou name="Impl" pouType="functionBlock"><interface><addData>{}</addData></interface>{}<addData>{get}</addData></pou>"#,
        data(
            "pouinheritance",
            "<Inheritance><Implements>I_B</Implements></Inheritance>"
        ),
        st("")
    );
    let main = format!(
        r#"<pou name="main" pouType="program"><interface><localVars>
<variable name="impl"><type><derived name="Impl"/></type></variable>
<variable name="i"><type><derived name="I_B"/></type></variable>{}{}{}</localVars></interface>
<body><FBD>
<inVariable localId="1"><connectionPointOut/><expression>n</expression></inVariable>
<block localId="2" typeName="i.Get"><inputVariables><variable formalParameter="k"><connectionPointIn><connection refLocalId="1"/></connectionPointIn></variable></inputVariables>
<inOutVariables/><outputVariables><variable formalParameter="Result"><connectionPointOut/></variable><variable formalParameter="flag"><connectionPointOut/></variable></outputVariables></block>
<outVariable localId="3"><connectionPointIn><connection refLocalId="2" formalParameter="Result"/></connectionPointIn><expression>r</expression></outVariable>
<outVariable localId="4"><connectionPointIn><connection refLocalId="2" formalParameter="flag"/></connectionPointIn><expression>f</expression></outVariable>
</FBD></body></pou>"#,
        var("n", "INT"),
        var("r", "INT"),
        var("f", "BOOL"),
    );
    let xml = file(CODESYS, &format!("{fb}{main}"), "", &itf);
    let v = view(&xml);
    assert!(
        v.contains("    _TMP_I_GET2_RESULT : INT;\n")
            && v.contains("_TMP_I_GET2_RESULT := i.Get(k := n, flag => _TMP_I_GET2_FLAG);"),
        "{v}"
    );
    // (`i` holds no instance: the call faults at run time, and compiles.)
    let (d, ok) = compile_with(&xml, &LowerOptions::default());
    assert!(d.is_empty() && ok, "{d:#?}");
}

#[test]
fn en_of_a_method_called_as_a_block_is_not_supported() {
    let m = data(
        "method",
        &format!(
            r#"<Method name="M"><interface><returnType><INT/></returnType></interface>{}</Method>"#,
            st("M := 1;")
        ),
    );
    let fb = format!(
        r#"<pou name="F" pouType="functionBlock"><interface/>{}<addData>{m}</addData></pou>"#,
        st("")
    );
    let main = format!(
        r#"<pou name="main" pouType="program"><interface><localVars>
<variable name="f"><type><derived name="F"/></type></variable>{}{}</localVars></interface>
<body><FBD>
<inVariable localId="1"><connectionPointOut/><expression>go</expression></inVariable>
<block localId="2" typeName="f.M"><inputVariables><variable formalParameter="EN"><connectionPointIn><connection refLocalId="1"/></connectionPointIn></variable></inputVariables>
<inOutVariables/><outputVariables><variable formalParameter="M"><connectionPointOut/></variable></outputVariables></block>
<outVariable localId="3"><connectionPointIn><connection refLocalId="2" formalParameter="M"/></connectionPointIn><expression>r</expression></outVariable>
</FBD></body></pou>"#,
        var("go", "BOOL"),
        var("r", "INT"),
    );
    let xml = file(CODESYS, &format!("{fb}{main}"), "", "");
    let (_, d) = convert_text(&xml);
    assert_eq!(d.len(), 1, "{d:#?}");
    assert_eq!(d[0].code, codes::E_UNSUPPORTED);
    assert!(
        d[0].message
            .contains("EN and ENO of a method called as a block (block f.M (localId 2) of `main`)"),
        "{d:#?}"
    );
}
