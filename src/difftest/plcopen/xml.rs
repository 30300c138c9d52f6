//! The printer of the PLCopen model: a TC6 2.01 project as the editors write it
//! (every element with its size, position and connection points).

use super::{Class, Edge, Elem, Kind, Pin, Pou, Storage, Var, VarTy, Wire, XmlProg};
use std::fmt::Write;

/// Escapes text for XML.
fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

fn var(v: &Var, o: &mut String) {
    let ty = match &v.ty {
        VarTy::Elem(t) => format!("<{}/>", t.name()),
        VarTy::Fb(n) => format!("<derived name=\"{n}\"/>"),
    };
    let _ = write!(
        o,
        "          <variable name=\"{}\"><type>{ty}</type>",
        v.name
    );
    if let Some(i) = &v.init {
        let _ = write!(
            o,
            "<initialValue><simpleValue value=\"{}\"/></initialValue>",
            esc(i)
        );
    }
    o.push_str("</variable>\n");
}

fn interface(p: &Pou, o: &mut String) {
    o.push_str("      <interface>\n");
    for (class, tag) in [
        (Class::Input, "inputVars"),
        (Class::Output, "outputVars"),
        (Class::Local, "localVars"),
    ] {
        let vars: Vec<&Var> = p.vars.iter().filter(|v| v.class == class).collect();
        if vars.is_empty() {
            continue;
        }
        let _ = writeln!(o, "        <{tag}>");
        for v in vars {
            var(v, o);
        }
        let _ = writeln!(o, "        </{tag}>");
    }
    o.push_str("      </interface>\n");
}

fn edge(e: Edge) -> &'static str {
    match e {
        Edge::None => "",
        Edge::Rising => " edge=\"rising\"",
        Edge::Falling => " edge=\"falling\"",
    }
}

fn neg(n: bool) -> &'static str {
    if n {
        " negated=\"true\""
    } else {
        ""
    }
}

fn pos(e: &Elem) -> String {
    format!("<position x=\"{}\" y=\"{}\"/>", e.pos.0, e.pos.1)
}

fn point_in(wires: &[Wire], y: i64, o: &mut String) {
    let _ = write!(o, "<connectionPointIn><relPosition x=\"0\" y=\"{y}\"/>");
    for w in wires {
        match &w.pin {
            Some(p) => {
                let _ = write!(
                    o,
                    "<connection refLocalId=\"{}\" formalParameter=\"{p}\"/>",
                    w.from
                );
            }
            None => {
                let _ = write!(o, "<connection refLocalId=\"{}\"/>", w.from);
            }
        }
    }
    o.push_str("</connectionPointIn>");
}

fn point_out(x: i64, y: i64, o: &mut String) {
    let _ = write!(
        o,
        "<connectionPointOut><relPosition x=\"{x}\" y=\"{y}\"/></connectionPointOut>"
    );
}

fn pins(tag: &str, pins: &[Pin], input: bool, width: i64, o: &mut String) {
    let _ = write!(o, "<{tag}>");
    for (k, p) in pins.iter().enumerate() {
        let y = 30 + 20 * k as i64;
        let _ = write!(
            o,
            "<variable formalParameter=\"{}\"{}{}>",
            p.name,
            neg(p.negated),
            edge(p.edge)
        );
        if input {
            point_in(&p.wires, y, o);
        } else {
            point_out(width, y, o);
        }
        o.push_str("</variable>");
    }
    let _ = write!(o, "</{tag}>");
}

fn element(e: &Elem, o: &mut String) {
    let id = e.id;
    let order = match e.order {
        Some(n) => format!(" executionOrderId=\"{n}\""),
        None => String::new(),
    };
    o.push_str("          ");
    match &e.kind {
        Kind::LeftRail => {
            let _ = write!(
                o,
                "<leftPowerRail localId=\"{id}\" width=\"3\" height=\"40\">{}",
                pos(e)
            );
            o.push_str("<connectionPointOut formalParameter=\"\"><relPosition x=\"3\" y=\"20\"/></connectionPointOut></leftPowerRail>");
        }
        Kind::RightRail { wires } => {
            let _ = write!(
                o,
                "<rightPowerRail localId=\"{id}\" width=\"3\" height=\"40\">{}",
                pos(e)
            );
            for w in wires {
                point_in(std::slice::from_ref(w), 20, o);
            }
            o.push_str("</rightPowerRail>");
        }
        Kind::Contact {
            var,
            negated,
            edge: ed,
            wires,
        } => {
            let _ = write!(
                o,
                "<contact localId=\"{id}\"{}{}{order} width=\"21\" height=\"20\">{}",
                neg(*negated),
                edge(*ed),
                pos(e)
            );
            point_in(wires, 10, o);
            point_out(21, 10, o);
            let _ = write!(o, "<variable>{}</variable></contact>", esc(var));
        }
        Kind::Coil {
            var,
            negated,
            storage,
            edge: ed,
            wires,
        } => {
            let st = match storage {
                Storage::None => "",
                Storage::Set => " storage=\"set\"",
                Storage::Reset => " storage=\"reset\"",
            };
            let _ = write!(
                o,
                "<coil localId=\"{id}\"{}{st}{}{order} width=\"21\" height=\"20\">{}",
                neg(*negated),
                edge(*ed),
                pos(e)
            );
            point_in(wires, 10, o);
            point_out(21, 10, o);
            let _ = write!(o, "<variable>{}</variable></coil>", esc(var));
        }
        Kind::Block {
            ty,
            instance,
            inputs,
            outputs,
        } => {
            let inst = match instance {
                Some(i) => format!(" instanceName=\"{i}\""),
                None => String::new(),
            };
            let height = 40 + 20 * inputs.len().max(outputs.len()) as i64;
            let _ = write!(
                o,
                "<block localId=\"{id}\" typeName=\"{ty}\"{inst}{order} width=\"80\" height=\"{height}\">{}",
                pos(e)
            );
            pins("inputVariables", inputs, true, 80, o);
            o.push_str("<inOutVariables/>");
            pins("outputVariables", outputs, false, 80, o);
            o.push_str("</block>");
        }
        Kind::InVar { expr, negated } => {
            let _ = write!(
                o,
                "<inVariable localId=\"{id}\"{}{order} width=\"60\" height=\"20\">{}",
                neg(*negated),
                pos(e)
            );
            point_out(60, 10, o);
            let _ = write!(o, "<expression>{}</expression></inVariable>", esc(expr));
        }
        Kind::OutVar {
            expr,
            negated,
            wires,
        } => {
            let _ = write!(
                o,
                "<outVariable localId=\"{id}\"{}{order} width=\"60\" height=\"20\">{}",
                neg(*negated),
                pos(e)
            );
            point_in(wires, 10, o);
            let _ = write!(o, "<expression>{}</expression></outVariable>", esc(expr));
        }
        Kind::Connector { name, wires } => {
            let _ = write!(
                o,
                "<connector localId=\"{id}\" name=\"{name}\" width=\"40\" height=\"20\">{}",
                pos(e)
            );
            point_in(wires, 10, o);
            o.push_str("</connector>");
        }
        Kind::Continuation { name } => {
            let _ = write!(
                o,
                "<continuation localId=\"{id}\" name=\"{name}\" width=\"40\" height=\"20\">{}",
                pos(e)
            );
            point_out(40, 10, o);
            o.push_str("</continuation>");
        }
        Kind::Jump { label, wires } => {
            let _ = write!(
                o,
                "<jump localId=\"{id}\" label=\"{label}\" width=\"40\" height=\"20\">{}",
                pos(e)
            );
            point_in(wires, 10, o);
            o.push_str("</jump>");
        }
        Kind::Label { label } => {
            let _ = write!(
                o,
                "<label localId=\"{id}\" label=\"{label}\" width=\"40\" height=\"20\">{}</label>",
                pos(e)
            );
        }
        Kind::Return { wires } => {
            let _ = write!(
                o,
                "<return localId=\"{id}\" width=\"40\" height=\"20\">{}",
                pos(e)
            );
            point_in(wires, 10, o);
            o.push_str("</return>");
        }
    }
    o.push('\n');
}

fn pou(p: &Pou, o: &mut String) {
    let kind = if p.fb { "functionBlock" } else { "program" };
    let _ = writeln!(o, "    <pou name=\"{}\" pouType=\"{kind}\">", p.name);
    interface(p, o);
    let lang = if p.ld { "LD" } else { "FBD" };
    let _ = writeln!(o, "      <body>\n        <{lang}>");
    for e in &p.elems {
        element(e, o);
    }
    let _ = writeln!(o, "        </{lang}>\n      </body>\n    </pou>");
}

/// The project as PLCopen TC6 2.01 XML.
pub fn print(prog: &XmlProg) -> String {
    let mut o = String::from(
        "<?xml version=\"1.0\" encoding=\"utf-8\"?>\n\
<project xmlns=\"http://www.plcopen.org/xml/tc6_0201\" xmlns:xhtml=\"http://www.w3.org/1999/xhtml\">\n\
  <fileHeader companyName=\"plcc\" productName=\"difftest\" productVersion=\"1\" creationDateTime=\"2026-01-01T00:00:00\"/>\n\
  <contentHeader name=\"difftest\" modificationDateTime=\"2026-01-01T00:00:00\">\n\
    <coordinateInfo><fbd><scaling x=\"0\" y=\"0\"/></fbd><ld><scaling x=\"0\" y=\"0\"/></ld><sfc><scaling x=\"0\" y=\"0\"/></sfc></coordinateInfo>\n\
  </contentHeader>\n\
  <types>\n  <dataTypes/>\n  <pous>\n",
    );
    for p in &prog.pous {
        pou(p, &mut o);
    }
    o.push_str("  </pous>\n  </types>\n  <instances><configurations/></instances>\n</project>\n");
    o
}
