//! CODESYS's object orientation in the view: a POU's EXTENDS and IMPLEMENTS, its
//! METHODs and PROPERTYs (after its body, as CODESYS writes them in text), and the
//! project's INTERFACEs, written as the ST front end reads them in the CODESYS
//! dialect.

use super::decls::{write_group, write_type};
use super::graph::Graph;
use super::map::Out;
use super::view::write_text;
use super::wire::Line;
use super::xml::{Accessor, Body, Interface, Method, Mods, Oo, Property, Text};

/// A name of a base or an interface. CODESYS qualifies a library's by the
/// library's namespace (`COL.LinkedListElementBase`); plcc has no CODESYS library,
/// and a project (or a `--lib` file) declares such a block by its plain name: the
/// last part is written, mapped back to the whole element.
pub(super) fn push_name(o: &mut Out, t: &Text) {
    match t.value.rsplit_once('.') {
        Some((_, last)) if !last.trim().is_empty() => o.push_as(last.trim(), t),
        _ => o.push_text(t),
    }
}

/// ` EXTENDS b IMPLEMENTS i, j` after a POU's name.
pub(super) fn write_inheritance(o: &mut Out, oo: &Oo) {
    if let Some(b) = &oo.extends {
        o.push(" EXTENDS ");
        push_name(o, b);
    }
    for (k, i) in oo.implements.iter().enumerate() {
        o.push(if k == 0 { " IMPLEMENTS " } else { ", " });
        push_name(o, i);
    }
}

/// ABSTRACT, FINAL and the access specifier, each followed by a space.
pub(super) fn write_mods(o: &mut Out, m: &Mods) {
    if m.abstract_ {
        o.push("ABSTRACT ");
    }
    if m.final_ {
        o.push("FINAL ");
    }
    if let Some(a) = &m.access {
        o.push_as(&a.value, a);
        o.push(" ");
    }
}

/// The lowered graphical bodies of a POU's methods (`None`: a textual body).
pub(super) type MethodLines<'g> = [Option<(&'g Graph<'g>, Vec<Line>)>];

/// A POU's methods and properties, after its body; `lines[k]`: the lowered LD or
/// FBD body of method `k`.
pub(super) fn write_members(o: &mut Out, oo: &Oo, lines: &MethodLines) {
    for (k, m) in oo.methods.iter().enumerate() {
        write_method(o, m, true, lines.get(k).and_then(Option::as_ref));
    }
    for p in &oo.properties {
        write_property(o, p, true);
    }
}

/// `METHOD [modifiers] M [: T]`, its variables and body, `END_METHOD`.
fn write_method(o: &mut Out, m: &Method, with_mods: bool, lowered: Option<&(&Graph, Vec<Line>)>) {
    let start = o.pos();
    o.push("METHOD ");
    if with_mods {
        write_mods(o, &m.mods);
    }
    o.push_text(&m.name);
    if let Some(r) = &m.ret {
        o.push(" : ");
        write_type(o, r, 1);
    }
    o.mark(start, m.tag.clone());
    o.push("\n");
    for g in &m.groups {
        write_group(o, g);
    }
    match lowered {
        Some((g, lines)) => {
            for line in lines {
                line.write(o, g.elems);
            }
        }
        None => write_member_body(o, &m.body),
    }
    let start = o.pos();
    o.push("END_METHOD");
    o.mark(start, m.tag.clone());
    o.push("\n");
}

/// `PROPERTY [modifiers] P : T`, its accessors, `END_PROPERTY`.
fn write_property(o: &mut Out, p: &Property, with_mods: bool) {
    let start = o.pos();
    o.push("PROPERTY ");
    if with_mods {
        write_mods(o, &p.mods);
    }
    o.push_text(&p.name);
    o.push(" : ");
    write_type(o, &p.ty, 1);
    o.mark(start, p.tag.clone());
    o.push("\n");
    let accessors = [("GET", &p.get), ("SET", &p.set)];
    for (kw, acc) in accessors {
        if let Some(a) = acc {
            write_accessor(o, kw, a);
        }
    }
    let start = o.pos();
    o.push("END_PROPERTY");
    o.mark(start, p.tag.clone());
    o.push("\n");
}

fn write_accessor(o: &mut Out, kw: &str, a: &Accessor) {
    let start = o.pos();
    o.push(kw);
    o.mark(start, a.tag.clone());
    o.push("\n");
    for g in &a.groups {
        write_group(o, g);
    }
    write_member_body(o, &a.body);
    let start = o.pos();
    o.push("END_");
    o.push(kw);
    o.mark(start, a.tag.clone());
    o.push("\n");
}

/// The body of a method or an accessor: its text (ST or IL), or nothing.
fn write_member_body(o: &mut Out, b: &Body) {
    if let Body::St(t) | Body::Il(t) = b {
        if !t.value.trim().is_empty() {
            write_text(o, t);
        }
    }
}

/// `INTERFACE I [EXTENDS a, b]` with its methods and properties.
pub(super) fn write_interface(o: &mut Out, i: &Interface) {
    o.push("\n");
    let start = o.pos();
    o.push("INTERFACE ");
    o.push_text(&i.name);
    for (k, e) in i.extends.iter().enumerate() {
        o.push(if k == 0 { " EXTENDS " } else { ", " });
        push_name(o, e);
    }
    o.mark(start, i.tag.clone());
    o.push("\n");
    for m in &i.methods {
        write_method(o, m, false, None);
    }
    for p in &i.properties {
        write_property(o, p, false);
    }
    let start = o.pos();
    o.push("END_INTERFACE");
    o.mark(start, i.tag.clone());
    o.push("\n");
}
