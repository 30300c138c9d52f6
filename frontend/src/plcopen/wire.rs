//! The pieces the lowering of graphical bodies ([`super::body`]) builds statements
//! from: [`Part`]s of text mapped to the XML they stand for, the [`Line`]s they make,
//! and [`X`], the value on a wire: a formula over terms (AND and OR of contacts,
//! variables and outputs), written as ST by [`render`]; what a formula reads
//! ([`reads`], [`reads_any`]) decides when a value must be kept before a statement
//! writes what it reads.

use super::map::Out;
use super::xml::{Element, Text};
use rustc_hash::FxHashMap;
use std::rc::Rc;

// ------------------------------------------------------------------ lines

/// A piece of a statement, with the XML text it stands for.
#[derive(Clone, Debug)]
pub(super) struct Part {
    pub(super) s: String,
    pub(super) from: Option<Text>,
}

pub(super) fn part(s: impl Into<String>) -> Part {
    Part {
        s: s.into(),
        from: None,
    }
}

pub(super) fn text_part(t: &Text) -> Part {
    Part {
        s: t.value.clone(),
        from: Some(t.clone()),
    }
}

/// One line of the lowered body: a statement, a label or a comment.
#[derive(Clone, Debug)]
pub(super) struct Line {
    pub(super) parts: Vec<Part>,
    /// The element the line comes from.
    pub(super) elem: Option<usize>,
    /// A label (not indented).
    pub(super) label: bool,
}

impl Line {
    /// Writes the line, mapped to its element.
    pub(super) fn write(&self, o: &mut Out, elems: &[Element]) {
        let start = o.pos();
        if !self.label {
            o.push("    ");
        }
        for p in &self.parts {
            match &p.from {
                Some(t) => o.push_as(&p.s, t),
                None => o.push(&p.s),
            }
        }
        if let Some(e) = self.elem {
            o.mark(start, elems[e].tag.clone());
        }
        o.push("\n");
    }
}

// ------------------------------------------------------------------ values

/// A value on a wire: a formula over terms.
#[derive(Clone, Debug)]
pub(super) enum X {
    True,
    /// A variable, an expression, an output (`ton0.Q`), a hidden variable.
    Term(Vec<Part>),
    Not(Rc<X>),
    /// A conjunction, kept as a tree (its operands are flattened when it is written):
    /// the values of a rung's elements share their prefix, so a series of n contacts
    /// costs n nodes, not n² operands.
    And(Rc<X>, Rc<X>),
    Or(Vec<X>),
}

/// True if `s` needs no parentheses as an operand (a name, a member, an element).
pub(super) fn simple(s: &str) -> bool {
    let s = s.trim();
    !s.is_empty()
        && s.bytes().all(|b| {
            b.is_ascii_alphanumeric() || matches!(b, b'_' | b'.' | b'[' | b']' | b'%' | b'#')
        })
}

pub(super) fn term(t: &Text) -> X {
    X::Term(vec![text_part(t)])
}

pub(super) fn named(s: impl Into<String>) -> X {
    X::Term(vec![part(s)])
}

pub(super) fn not(x: X) -> X {
    match x {
        X::Not(inner) => Rc::unwrap_or_clone(inner),
        x => X::Not(Rc::new(x)),
    }
}

pub(super) fn and(a: X, b: X) -> X {
    match (a, b) {
        (X::True, x) | (x, X::True) => x,
        (a, b) => X::And(Rc::new(a), Rc::new(b)),
    }
}

/// The operands of a conjunction, left to right, nested conjunctions flattened
/// (without recursion: a long rung is a deep tree).
pub(super) fn conjuncts(x: &X) -> Vec<&X> {
    let mut out = Vec::new();
    let mut stack = vec![x];
    while let Some(x) = stack.pop() {
        match x {
            X::And(a, b) => {
                stack.push(b);
                stack.push(a);
            }
            x => out.push(x),
        }
    }
    out
}

pub(super) fn or(xs: Vec<X>) -> X {
    let mut v = Vec::new();
    for x in xs {
        match x {
            X::True => return X::True,
            X::Or(inner) => v.extend(inner),
            x => v.push(x),
        }
    }
    match v.len() {
        1 => v.pop().expect("one"),
        _ => X::Or(v),
    }
}

/// The value as ST: `top` when it is a whole statement's value or argument.
pub(super) fn render(x: &X, top: bool, out: &mut Vec<Part>) {
    match x {
        X::True => out.push(part("TRUE")),
        X::Term(p) => {
            let text: String = p.iter().map(|p| p.s.as_str()).collect();
            let paren = !top && !simple(&text);
            if paren {
                out.push(part("("));
            }
            out.extend(p.iter().cloned());
            if paren {
                out.push(part(")"));
            }
        }
        X::Not(inner) => {
            out.push(part("NOT("));
            render(inner, true, out);
            out.push(part(")"));
        }
        X::And(..) => {
            for (i, x) in conjuncts(x).into_iter().enumerate() {
                if i > 0 {
                    out.push(part(" AND "));
                }
                if let X::Or(_) = x {
                    out.push(part("("));
                    render(x, true, out);
                    out.push(part(")"));
                } else {
                    render(x, false, out);
                }
            }
        }
        X::Or(v) => {
            for (i, x) in v.iter().enumerate() {
                if i > 0 {
                    out.push(part(" OR "));
                }
                render(x, false, out);
            }
        }
    }
}

/// The names a piece of ST text reads (identifiers, upper-case), for deciding whether
/// a statement that writes some of them changes it.
pub(super) fn idents(s: &str, out: &mut Vec<String>) {
    let b = s.as_bytes();
    let mut i = 0;
    while i < b.len() {
        let c = b[i];
        if c == b'\'' || c == b'"' {
            // A string literal.
            i += 1;
            while i < b.len() && b[i] != c {
                i += 1;
            }
            i += 1;
        } else if c.is_ascii_alphabetic() || c == b'_' {
            let start = i;
            while i < b.len() && (b[i].is_ascii_alphanumeric() || b[i] == b'_') {
                i += 1;
            }
            // `T#5s`: a literal's prefix, not a name.
            if i < b.len() && b[i] == b'#' {
                while i < b.len()
                    && (b[i].is_ascii_alphanumeric()
                        || matches!(b[i], b'_' | b'#' | b'.' | b':' | b'-'))
                {
                    i += 1;
                }
                continue;
            }
            // `x.member`: the member is not a variable of the POU.
            if s[..start].trim_end().ends_with('.') {
                continue;
            }
            out.push(s[start..i].to_ascii_uppercase());
        } else if c.is_ascii_digit() {
            while i < b.len()
                && (b[i].is_ascii_alphanumeric() || matches!(b[i], b'_' | b'.' | b'#'))
            {
                i += 1;
            }
        } else {
            i += 1;
        }
    }
}

pub(super) fn reads(x: &X, out: &mut Vec<String>) {
    match x {
        X::True => {}
        X::Term(p) => {
            for p in p {
                idents(&p.s, out);
            }
        }
        X::Not(i) => reads(i, out),
        X::And(..) => conjuncts(x).into_iter().for_each(|x| reads(x, out)),
        X::Or(v) => v.iter().for_each(|x| reads(x, out)),
    }
}

/// True if `x` reads one of `names`. `seen` holds the answers for the shared parts
/// of earlier values (by address): the values of a rung's elements are built on
/// each other, and each shared part is read once.
pub(super) fn reads_any(x: &X, names: &[&String], seen: &mut FxHashMap<*const X, bool>) -> bool {
    match x {
        X::True => false,
        X::Term(_) => {
            let mut r = Vec::new();
            reads(x, &mut r);
            r.iter().any(|n| names.contains(&n))
        }
        X::Not(i) => shared_reads_any(i, names, seen),
        X::And(a, b) => shared_reads_any(a, names, seen) || shared_reads_any(b, names, seen),
        X::Or(v) => v.iter().any(|x| reads_any(x, names, seen)),
    }
}

pub(super) fn shared_reads_any(
    x: &Rc<X>,
    names: &[&String],
    seen: &mut FxHashMap<*const X, bool>,
) -> bool {
    let key = Rc::as_ptr(x);
    if let Some(&r) = seen.get(&key) {
        return r;
    }
    let r = reads_any(x, names, seen);
    seen.insert(key, r);
    r
}

/// The variable a statement writing `expr` changes: its first name.
pub(super) fn root(expr: &str) -> String {
    let mut v = Vec::new();
    idents(expr, &mut v);
    v.into_iter().next().unwrap_or_default()
}
