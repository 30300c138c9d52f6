//! Ladder rungs to Instruction List: the IL view of a PLCopen file.
//!
//! The file becomes one IEC source text: the data types as `TYPE`, the globals of the
//! configurations as `VAR_GLOBAL`, every POU with its interface as declarations and
//! its body as IL (ladder), or as written (ST and IL bodies). The IL front end then
//! compiles it like any `.il` file, and `--emit il` prints it.
//!
//! A rung becomes IL in its order of evaluation (see `graph`): contacts build up the
//! current result (CR), series as AND, parallel branches as OR, nested blocks with
//! `AND(` / `OR(` (the seed's method); each coil stores the CR (`ST`, `STN`, `S`,
//! `R`), and a coil, a block or a branch that follows goes on from the CR when it
//! holds what they need (`ST x` then `ST y` for coils in parallel, `ST x` then `AND c`
//! for a contact after a coil). What cannot go on from the CR is loaded again; a value
//! needed twice that is more than one contact is kept in a temporary (`_TMPn`, a
//! VAR_TEMP, `n` the localId of the element it leaves), so the contacts before it are
//! read once.
//!
//! Hidden variables, named after the element's localId so that an IL twin can name
//! them too:
//! - `_R_TRIGn`, `_F_TRIGn` (VAR): the edge detector of rising and falling contact or
//!   coil `n`. A contact's detector is called at the start of its rung.
//! - `_TMPn` (VAR_TEMP BOOL): the power leaving element `n`, when needed again.
//! - `_OLDn` (VAR_TEMP BOOL): the variable of contact `n`, read before a coil or block
//!   of the rung writes it, when the contact's power is used after that write (so
//!   that every contact reads its variable once, when it is evaluated).
//! - `_ENOn` (VAR_TEMP BOOL): ENO of block `n`, its EN (plcc's blocks do not fail).
//! - `_OUTn` (VAR_TEMP): the result of function block `n`, when it is not used at once.
//! - `_INn_P` (VAR_TEMP BOOL): input `P` of function block `n` when it is a branch of
//!   contacts rather than a value.
//! - label `_SKIPn`: the end of block `n` when its EN is not always TRUE: EN FALSE
//!   jumps over the call, so the block does not run, its outputs keep their values
//!   (a function's result is 0) and ENO is FALSE.

use super::decls::comment_safe;
use super::graph::{input_name, output_name, Graph, Src};
use super::map::Out;
use super::xml::{Edge, Element, Kind, PouKind, Project, Storage, Text, Type, Var, VarGroup};
use crate::codes;
use plcc_ir::diag::{Diagnostic, FileId};
use rustc_hash::{FxHashMap, FxHashSet};

// ------------------------------------------------------------------ hidden names

/// What a hidden variable or label is for.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
enum Hidden {
    RTrig(usize),
    FTrig(usize),
    Tmp(usize),
    Old(usize),
    Eno(usize),
    Out(usize),
    In(usize, usize),
    Skip(usize),
}

/// The names of the hidden variables and labels of one POU, chosen so that none
/// clashes with a name the POU can see.
pub(super) struct Names<'g> {
    taken: FxHashSet<String>,
    made: FxHashMap<Hidden, String>,
    elems: &'g [Element],
    /// Hidden VAR declarations (edge detectors), in order.
    vars: Vec<(String, String)>,
    /// Hidden VAR_TEMP declarations, in order.
    temps: Vec<(String, String)>,
}

impl<'g> Names<'g> {
    pub(super) fn new(
        project: &Project,
        pou: &super::xml::Pou,
        globals: &[&Var],
        g: &Graph<'g>,
    ) -> Self {
        let mut taken = FxHashSet::default();
        let mut add = |s: &str| {
            taken.insert(s.to_ascii_uppercase());
        };
        for p in &project.pous {
            add(&p.name.value);
        }
        for t in &project.types {
            add(&t.name.value);
        }
        for v in globals {
            add(&v.name.value);
        }
        for grp in &pou.groups {
            for v in &grp.vars {
                add(&v.name.value);
            }
        }
        for e in g.elems {
            if let Kind::Label { label } = &e.kind {
                add(&label.value);
            }
        }
        Names {
            taken,
            made: FxHashMap::default(),
            elems: g.elems,
            vars: Vec::new(),
            temps: Vec::new(),
        }
    }

    fn get(&mut self, h: Hidden) -> String {
        if let Some(n) = self.made.get(&h) {
            return n.clone();
        }
        let id = |e: usize| self.elems[e].id;
        let base = match h {
            Hidden::RTrig(e) => format!("_R_TRIG{}", id(e)),
            Hidden::FTrig(e) => format!("_F_TRIG{}", id(e)),
            Hidden::Tmp(e) => format!("_TMP{}", id(e)),
            Hidden::Old(e) => format!("_OLD{}", id(e)),
            Hidden::Eno(e) => format!("_ENO{}", id(e)),
            Hidden::Out(e) => format!("_OUT{}", id(e)),
            Hidden::In(e, p) => {
                let port = input_name(&self.elems[e].kind, p).unwrap_or("IN");
                format!("_IN{}_{}", id(e), port)
            }
            Hidden::Skip(e) => format!("_SKIP{}", id(e)),
        };
        let mut name = base.clone();
        let mut k = 1;
        while self.taken.contains(&name.to_ascii_uppercase()) {
            name = format!("{base}_{k}");
            k += 1;
        }
        self.taken.insert(name.to_ascii_uppercase());
        self.made.insert(h, name.clone());
        name
    }

    /// Declares a hidden variable (once).
    fn declare(&mut self, name: &str, ty: &str, temp: bool) {
        let list = if temp {
            &mut self.temps
        } else {
            &mut self.vars
        };
        if !list.iter().any(|(n, _)| n == name) {
            list.push((name.to_string(), ty.to_string()));
        }
    }
}

pub(super) fn write_hidden(o: &mut Out, n: &Names) {
    for (kw, list) in [("VAR", &n.vars), ("VAR_TEMP", &n.temps)] {
        if list.is_empty() {
            continue;
        }
        o.push(kw);
        o.push("\n");
        for (name, ty) in list {
            o.push(&format!("    {name} : {ty};\n"));
        }
        o.push("END_VAR\n");
    }
}

// ------------------------------------------------------------------ IL lines

/// A piece of an operand, with the XML text it stands for.
#[derive(Clone, Debug)]
struct Part {
    s: String,
    from: Option<Text>,
}

fn part(s: impl Into<String>) -> Part {
    Part {
        s: s.into(),
        from: None,
    }
}

fn text_part(t: &Text) -> Part {
    Part {
        s: t.value.clone(),
        from: Some(t.clone()),
    }
}

/// One line of IL.
#[derive(Clone, Debug)]
pub(super) struct Line {
    /// A label (its name is the operand) rather than an instruction.
    label: bool,
    /// The operator (`LD`, `AND(`, `CAL`...), or the comment text of a comment line.
    op: String,
    /// The operand, in pieces.
    operand: Vec<Part>,
    /// The element the line comes from.
    elem: Option<usize>,
    /// A comment line.
    comment: bool,
}

impl Line {
    pub(super) fn write(&self, o: &mut Out, elems: &[Element]) {
        if self.comment {
            o.push(&format!("(* {} *)\n", comment_safe(&self.op)));
            return;
        }
        let start = o.pos();
        if !self.label {
            o.push("    ");
        }
        if !self.op.is_empty() {
            o.push(&self.op);
            if !self.operand.is_empty() {
                o.push(" ");
            }
        }
        for p in &self.operand {
            match &p.from {
                Some(t) => o.push_as(&p.s, t),
                None => o.push(&p.s),
            }
        }
        if self.label {
            o.push(":");
        }
        if let Some(e) = self.elem {
            o.mark(start, elems[e].tag.clone());
        }
        o.push("\n");
    }
}

// ------------------------------------------------------------------ formulas

/// What an operand of a formula is.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
enum AtomKind {
    /// A variable or literal, read when loaded.
    Plain,
    /// A hidden temporary that must have been stored (the key says which).
    Temp(Hidden),
}

/// An operand of a formula.
#[derive(Clone, Debug)]
struct Atom {
    parts: Vec<Part>,
    neg: bool,
    elem: usize,
    kind: AtomKind,
}

impl Atom {
    fn text(&self) -> String {
        self.parts.iter().map(|p| p.s.as_str()).collect()
    }
}

/// The power (or value) on a wire, as a formula over operands.
#[derive(Clone, Debug)]
enum F {
    True,
    Atom(Atom),
    And(Vec<F>),
    Or(Vec<F>),
    Not(Box<F>),
    /// The value leaving element `.0`, which several elements use.
    Node(usize, Box<F>),
}

impl F {
    fn strip(&self) -> &F {
        match self {
            F::Node(_, f) => f.strip(),
            f => f,
        }
    }

    /// The number of operands.
    fn size(&self) -> usize {
        match self {
            F::True => 0,
            F::Atom(_) => 1,
            F::And(v) | F::Or(v) => v.iter().map(F::size).sum(),
            F::Not(f) | F::Node(_, f) => f.size(),
        }
    }
}

/// The same value (up to `Node` wrappers).
fn same(a: &F, b: &F) -> bool {
    match (a.strip(), b.strip()) {
        (F::True, F::True) => true,
        (F::Atom(x), F::Atom(y)) => x.neg == y.neg && x.text() == y.text(),
        (F::And(x), F::And(y)) | (F::Or(x), F::Or(y)) => {
            x.len() == y.len() && x.iter().zip(y).all(|(p, q)| same(p, q))
        }
        (F::Not(x), F::Not(y)) => same(x, y),
        _ => false,
    }
}

fn and2(a: F, b: F) -> F {
    match (a, b) {
        (F::True, b) => b,
        (a, F::True) => a,
        (F::And(mut v), b) => {
            v.push(b);
            F::And(v)
        }
        (a, b) => F::And(vec![a, b]),
    }
}

#[derive(Copy, Clone, PartialEq, Eq)]
enum Op {
    And,
    Or,
}

impl Op {
    fn word(self) -> &'static str {
        match self {
            Op::And => "AND",
            Op::Or => "OR",
        }
    }
}

// ------------------------------------------------------------------ emission

/// What the emission of a POU needs besides the graph.
pub(super) struct PouCtx<'a> {
    pub(super) project: &'a Project,
    pub(super) pou: &'a str,
    pub(super) pou_vars: &'a [VarGroup],
    pub(super) globals: &'a [&'a Var],
    pub(super) file: FileId,
}

/// The IL lines of a ladder body (two passes: the first finds which temporaries are
/// read, the second stores only those).
pub(super) fn emit_body<'g>(
    g: &Graph<'g>,
    ctx: &PouCtx,
    names: &mut Names<'g>,
    diags: &mut Vec<Diagnostic>,
) -> Vec<Line> {
    let mut first = Em::new(g, ctx, names, None);
    first.body();
    let read = std::mem::take(&mut first.read);
    let mut second = Em::new(g, ctx, names, Some(read));
    second.body();
    let lines = std::mem::take(&mut second.lines);
    let decls = std::mem::take(&mut second.decls);
    diags.append(&mut second.diags);
    for (name, ty, temp) in decls {
        names.declare(&name, &ty, temp);
    }
    lines
}

struct Em<'a, 'g> {
    g: &'a Graph<'g>,
    ctx: &'a PouCtx<'a>,
    names: &'a mut Names<'g>,
    /// The temporaries to store: `None` in the first pass (all of them).
    want: Option<FxHashSet<Hidden>>,
    /// The temporaries read.
    read: FxHashSet<Hidden>,
    /// Temporaries stored so far.
    stored: FxHashSet<Hidden>,
    lines: Vec<Line>,
    cr: Option<F>,
    /// Contacts read from a hidden variable (edge detector, saved value).
    atoms: FxHashMap<usize, Atom>,
    /// Contacts whose reading was taken before a write (saved or not).
    saved: Vec<usize>,
    /// Contacts whose variable an effect after them in their rung writes: their power
    /// is kept in a temporary if it is loaded again.
    rewritten: FxHashSet<usize>,
    /// Hidden declarations: (name, type, VAR_TEMP).
    decls: Vec<(String, String, bool)>,
    diags: Vec<Diagnostic>,
    /// The number of the rung being converted.
    rung: usize,
}

/// The identifier a variable expression starts with, upper-cased (`T1` of `T1.Q`).
fn base(s: &str) -> String {
    s.trim()
        .split(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
        .next()
        .unwrap_or("")
        .to_ascii_uppercase()
}

impl<'a, 'g> Em<'a, 'g> {
    fn new(
        g: &'a Graph<'g>,
        ctx: &'a PouCtx<'a>,
        names: &'a mut Names<'g>,
        want: Option<FxHashSet<Hidden>>,
    ) -> Self {
        Em {
            g,
            ctx,
            names,
            want,
            read: FxHashSet::default(),
            stored: FxHashSet::default(),
            lines: Vec::new(),
            cr: None,
            atoms: FxHashMap::default(),
            saved: Vec::new(),
            rewritten: FxHashSet::default(),
            decls: Vec::new(),
            diags: Vec::new(),
            rung: 0,
        }
    }

    fn wants(&self, h: Hidden) -> bool {
        self.want.as_ref().is_none_or(|w| w.contains(&h))
    }

    fn name(&mut self, h: Hidden) -> String {
        self.names.get(h)
    }

    fn declare(&mut self, h: Hidden, ty: &str, temp: bool) -> String {
        let n = self.name(h);
        self.decls.push((n.clone(), ty.to_string(), temp));
        n
    }

    fn line(&mut self, op: impl Into<String>, operand: Vec<Part>, elem: Option<usize>) {
        self.lines.push(Line {
            label: false,
            op: op.into(),
            operand,
            elem,
            comment: false,
        });
    }

    fn body(&mut self) {
        for rung in &self.g.rungs {
            self.cr = None;
            self.rung = rung.number;
            self.lines.push(Line {
                label: false,
                op: format!("rung {}", rung.number),
                operand: Vec::new(),
                elem: None,
                comment: true,
            });
            self.edges(&rung.order);
            self.rewritten = self.rewritten_contacts(&rung.order);
            let last_use = self.last_uses(&rung.order);
            for (i, &e) in rung.order.iter().enumerate() {
                if !self.is_effect(e) {
                    continue;
                }
                self.save_before(e, i, &rung.order, &last_use);
                self.effect(e);
            }
        }
    }

    // ------------------------------------------------------------ edges, hazards

    /// Calls the edge detectors of the rung's rising and falling contacts.
    fn edges(&mut self, order: &[usize]) {
        for &e in order {
            let Kind::Contact {
                var, edge, negated, ..
            } = &self.g.elems[e].kind
            else {
                continue;
            };
            let (h, ty) = match edge {
                Edge::None => continue,
                Edge::Rising => (Hidden::RTrig(e), "R_TRIG"),
                Edge::Falling => (Hidden::FTrig(e), "F_TRIG"),
            };
            let inst = self.declare(h, ty, false);
            self.line(
                "CAL",
                vec![part(format!("{inst}(CLK := ")), text_part(var), part(")")],
                Some(e),
            );
            self.atoms.insert(
                e,
                Atom {
                    parts: vec![part(format!("{inst}.Q"))],
                    neg: *negated,
                    elem: e,
                    kind: AtomKind::Plain,
                },
            );
        }
    }

    fn is_effect(&self, e: usize) -> bool {
        match &self.g.elems[e].kind {
            Kind::Coil { .. }
            | Kind::Block { .. }
            | Kind::Jump { .. }
            | Kind::Return
            | Kind::Label { .. } => true,
            Kind::OutVariable { .. } | Kind::InOutVariable { .. } => !self.fed_by_block(e),
            _ => false,
        }
    }

    /// True for a variable whose one input is an output of a block (the block stores
    /// it).
    fn fed_by_block(&self, e: usize) -> bool {
        match self.g.ins[e].first().map(Vec::as_slice) {
            Some([s]) => matches!(self.g.elems[s.elem].kind, Kind::Block { .. }),
            _ => false,
        }
    }

    /// The contacts whose power flows, through contacts and coils only, into input
    /// `port` of `e`.
    fn contacts_into(&self, e: usize, port: usize, out: &mut Vec<usize>) {
        let mut stack: Vec<usize> = self.g.ins[e][port].iter().map(|s| s.elem).collect();
        let mut seen = FxHashSet::default();
        while let Some(x) = stack.pop() {
            if !seen.insert(x) {
                continue;
            }
            match &self.g.elems[x].kind {
                Kind::Contact { .. } => {
                    out.push(x);
                    stack.extend(self.g.ins[x][0].iter().map(|s| s.elem));
                }
                Kind::Coil { .. } => stack.extend(self.g.ins[x][0].iter().map(|s| s.elem)),
                _ => {}
            }
        }
    }

    /// For every contact of the rung, the position of the last effect that uses its
    /// power.
    fn last_uses(&self, order: &[usize]) -> FxHashMap<usize, usize> {
        let mut last = FxHashMap::default();
        for (i, &e) in order.iter().enumerate() {
            if !self.is_effect(e) {
                continue;
            }
            let mut cs = Vec::new();
            for port in 0..self.g.ins[e].len() {
                self.contacts_into(e, port, &mut cs);
            }
            for c in cs {
                last.insert(c, i);
            }
        }
        last
    }

    /// The contacts of a rung whose variable an effect after them writes.
    fn rewritten_contacts(&self, order: &[usize]) -> FxHashSet<usize> {
        let mut out = FxHashSet::default();
        for (i, &e) in order.iter().enumerate() {
            if !self.is_effect(e) {
                continue;
            }
            let writes = self.writes(e);
            for &c in &order[..i] {
                if let Kind::Contact { var, edge, .. } = &self.g.elems[c].kind {
                    if *edge == Edge::None && writes.contains(&base(&var.value)) {
                        out.insert(c);
                    }
                }
            }
        }
        out
    }

    /// The variables (their first identifiers) an effect writes.
    fn writes(&self, e: usize) -> Vec<String> {
        let el = &self.g.elems[e];
        match &el.kind {
            Kind::Coil { var, .. } => vec![base(&var.value)],
            Kind::OutVariable { expr, .. } | Kind::InOutVariable { expr } => {
                vec![base(&expr.value)]
            }
            Kind::Block { instance, .. } => {
                let mut w: Vec<String> = instance.iter().map(|i| base(&i.value)).collect();
                for port in &self.g.outs[e] {
                    for &(c, _) in port {
                        if let Kind::OutVariable { expr, .. } | Kind::InOutVariable { expr } =
                            &self.g.elems[c].kind
                        {
                            w.push(base(&expr.value));
                        }
                    }
                }
                for srcs in &self.g.ins[e] {
                    for s in srcs {
                        if let Kind::InOutVariable { expr } = &self.g.elems[s.elem].kind {
                            w.push(base(&expr.value));
                        }
                    }
                }
                w
            }
            _ => Vec::new(),
        }
    }

    /// Before effect `e` (at `i` in the order) writes a variable that an earlier
    /// contact read and whose power is used after `e`: save that contact's reading.
    fn save_before(&mut self, e: usize, i: usize, order: &[usize], last: &FxHashMap<usize, usize>) {
        let writes = self.writes(e);
        if writes.is_empty() {
            return;
        }
        // The contacts in `e`'s own inputs are loaded before it writes.
        let mut own = Vec::new();
        for port in 0..self.g.ins[e].len() {
            self.contacts_into(e, port, &mut own);
        }
        for &c in &order[..i] {
            if own.contains(&c) {
                continue;
            }
            let Kind::Contact {
                var, negated, edge, ..
            } = &self.g.elems[c].kind
            else {
                continue;
            };
            if *edge != Edge::None || self.saved.contains(&c) {
                continue;
            }
            if !writes.contains(&base(&var.value)) || last.get(&c).is_none_or(|&l| l <= i) {
                continue;
            }
            // The CR holds the reading either way, so that both passes go on from the
            // same CR; only a saved reading that is loaded again needs its variable.
            let h = Hidden::Old(c);
            self.saved.push(c);
            self.line("LD", vec![text_part(var)], Some(c));
            if !self.wants(h) {
                self.cr = Some(F::Atom(Atom {
                    parts: vec![text_part(var)],
                    neg: false,
                    elem: c,
                    kind: AtomKind::Plain,
                }));
                continue;
            }
            let name = self.declare(h, "BOOL", true);
            self.line("ST", vec![part(name.clone())], Some(c));
            let reading = |neg| Atom {
                parts: vec![part(name.clone())],
                neg,
                elem: c,
                kind: AtomKind::Temp(h),
            };
            self.cr = Some(F::Atom(reading(false)));
            self.atoms.insert(c, reading(*negated));
        }
    }

    // ------------------------------------------------------------ values

    /// The power or value at input `port` of `e` (its sources ORed).
    fn input(&mut self, e: usize, port: usize) -> F {
        let srcs = self.g.ins[e][port].clone();
        match srcs.as_slice() {
            [] => F::True,
            [s] => self.value(*s),
            many => {
                let terms = many.iter().map(|&s| self.value(s)).collect();
                factor(terms)
            }
        }
    }

    /// The number of inputs an output feeds (right rails excluded).
    fn uses(&self, s: Src) -> usize {
        self.g.outs[s.elem][s.port]
            .iter()
            .filter(|&&(c, _)| !matches!(self.g.elems[c].kind, Kind::RightRail))
            .count()
    }

    /// The value leaving an output.
    fn value(&mut self, s: Src) -> F {
        let e = s.elem;
        let f = match &self.g.elems[e].kind {
            Kind::LeftRail => return F::True,
            Kind::Contact { var, negated, .. } => {
                let atom = self.atoms.get(&e).cloned().unwrap_or_else(|| Atom {
                    parts: vec![text_part(var)],
                    neg: *negated,
                    elem: e,
                    kind: AtomKind::Plain,
                });
                let inp = self.input(e, 0);
                and2(inp, F::Atom(atom))
            }
            Kind::Coil { .. } => self.input(e, 0),
            Kind::InVariable { expr, negated } => {
                return F::Atom(Atom {
                    parts: vec![text_part(expr)],
                    neg: *negated,
                    elem: e,
                    kind: AtomKind::Plain,
                })
            }
            Kind::InOutVariable { expr } => {
                return F::Atom(Atom {
                    parts: vec![text_part(expr)],
                    neg: false,
                    elem: e,
                    kind: AtomKind::Plain,
                })
            }
            Kind::Block { .. } => return self.block_output(s),
            _ => return F::True,
        };
        if (self.uses(s) >= 2 && f.size() >= 2) || self.rewritten.contains(&e) {
            F::Node(e, Box::new(f))
        } else {
            f
        }
    }

    /// The value of output `s.port` of block `s.elem`.
    fn block_output(&mut self, s: Src) -> F {
        let e = s.elem;
        let Kind::Block {
            instance,
            outputs,
            inputs,
            ..
        } = &self.g.elems[e].kind
        else {
            return F::True;
        };
        let pname = output_name(&self.g.elems[e].kind, s.port)
            .unwrap_or("")
            .to_string();
        let port = outputs.get(s.port);
        let neg = port.is_some_and(|p| p.negated);
        if pname.eq_ignore_ascii_case("ENO") {
            let en = inputs.iter().position(|p| {
                p.name
                    .as_ref()
                    .is_some_and(|n| n.value.eq_ignore_ascii_case("EN"))
            });
            let guarded = en.is_some_and(|p| !self.en_always(e, p));
            if !guarded {
                return if neg {
                    F::Not(Box::new(F::True))
                } else {
                    F::True
                };
            }
            let name = self.name(Hidden::Eno(e));
            return F::Atom(Atom {
                parts: vec![part(name)],
                neg,
                elem: e,
                kind: AtomKind::Temp(Hidden::Eno(e)),
            });
        }
        match instance {
            Some(inst) => {
                let mut parts = vec![text_part(inst), part(".")];
                match port.and_then(|p| p.name.as_ref()) {
                    Some(n) => parts.push(text_part(n)),
                    None => parts.push(part(pname)),
                }
                F::Atom(Atom {
                    parts,
                    neg,
                    elem: e,
                    kind: AtomKind::Plain,
                })
            }
            None => {
                let name = self.name(Hidden::Out(e));
                F::Atom(Atom {
                    parts: vec![part(name)],
                    neg,
                    elem: e,
                    kind: AtomKind::Temp(Hidden::Out(e)),
                })
            }
        }
    }

    /// True if input `port` of `e` is wired to the left rail alone.
    fn en_always(&self, e: usize, port: usize) -> bool {
        matches!(self.g.ins[e][port].as_slice(), [s] if matches!(self.g.elems[s.elem].kind, Kind::LeftRail))
    }

    // ------------------------------------------------------------ loading the CR

    /// Makes the CR hold `f`, going on from what it holds where possible.
    fn load(&mut self, f: &F, elem: usize) {
        let reached = match self.cr.clone() {
            Some(cr) => self.reach(&cr, f, elem),
            None => false,
        };
        if !reached {
            self.fresh(f, elem);
        }
        self.cr = Some(f.clone());
    }

    /// Emits what turns the CR from `cr` into `f`, if `f` is `cr` combined with more
    /// (and nothing if not: then it returns false).
    fn reach(&mut self, cr: &F, f: &F, elem: usize) -> bool {
        if same(cr, f) {
            self.keep(f);
            return true;
        }
        match f {
            F::Node(n, inner) => {
                if self.stored.contains(&Hidden::Tmp(*n)) || !self.reach(cr, inner, *n) {
                    return false;
                }
                self.keep(f);
                true
            }
            F::And(v) | F::Or(v) => {
                let op = if matches!(f, F::And(_)) {
                    Op::And
                } else {
                    Op::Or
                };
                // `cr` is a prefix of the same operation.
                if let (F::And(w), Op::And) | (F::Or(w), Op::Or) = (cr.strip(), op) {
                    if w.len() < v.len() && w.iter().zip(v).all(|(a, b)| same(a, b)) {
                        for x in &v[w.len()..] {
                            self.op(op, x, elem);
                        }
                        return true;
                    }
                }
                // The first operand can be reached from `cr`.
                if self.reach(cr, &v[0], elem) {
                    for x in &v[1..] {
                        self.op(op, x, elem);
                    }
                    return true;
                }
                // `cr` is another operand (the operations commute: operands are values).
                if let Some(i) = v.iter().position(|x| same(x, cr)) {
                    self.keep(&v[i]);
                    for (j, x) in v.iter().enumerate() {
                        if j != i {
                            self.op(op, x, elem);
                        }
                    }
                    return true;
                }
                false
            }
            _ => false,
        }
    }

    /// The CR holds `f`: if `f` is the value of an element needed again later, keep it
    /// in its temporary (the first time).
    fn keep(&mut self, f: &F) {
        if let F::Node(n, _) = f {
            let h = Hidden::Tmp(*n);
            if self.wants(h) && !self.stored.contains(&h) {
                let name = self.declare(h, "BOOL", true);
                self.line("ST", vec![part(name)], Some(*n));
                self.stored.insert(h);
            }
        }
    }

    /// Reads a temporary (recording that it is needed).
    fn read_temp(&mut self, h: Hidden) {
        self.read.insert(h);
    }

    /// Emits `f` into a CR that holds nothing of use.
    fn fresh(&mut self, f: &F, elem: usize) {
        match f {
            F::True => self.line("LD", vec![part("TRUE")], Some(elem)),
            F::Atom(a) => {
                if let AtomKind::Temp(h) = a.kind {
                    self.read_temp(h);
                }
                let op = if a.neg { "LDN" } else { "LD" };
                self.line(op, a.parts.clone(), Some(a.elem));
            }
            F::And(v) | F::Or(v) => {
                let op = if matches!(f, F::And(_)) {
                    Op::And
                } else {
                    Op::Or
                };
                self.fresh(&v[0], elem);
                for x in &v[1..] {
                    self.op(op, x, elem);
                }
            }
            F::Not(x) => {
                self.fresh(x, elem);
                self.line("NOT", Vec::new(), Some(elem));
            }
            F::Node(n, inner) => {
                let h = Hidden::Tmp(*n);
                if self.stored.contains(&h) {
                    self.read_temp(h);
                    let name = self.name(h);
                    self.line("LD", vec![part(name)], Some(*n));
                    return;
                }
                self.fresh(inner, *n);
                self.keep(f);
            }
        }
    }

    /// Emits `CR := CR op f`.
    fn op(&mut self, op: Op, f: &F, elem: usize) {
        match f {
            F::Atom(a) => {
                if let AtomKind::Temp(h) = a.kind {
                    self.read_temp(h);
                }
                let word = format!("{}{}", op.word(), if a.neg { "N" } else { "" });
                self.line(word, a.parts.clone(), Some(a.elem));
            }
            F::True => self.line(op.word(), vec![part("TRUE")], Some(elem)),
            F::Node(n, inner) => {
                let h = Hidden::Tmp(*n);
                if self.stored.contains(&h) {
                    self.read_temp(h);
                    let name = self.name(h);
                    self.line(op.word(), vec![part(name)], Some(*n));
                } else if self.wants(h) {
                    self.paren(op, f, elem);
                } else {
                    self.op(op, inner, *n);
                }
            }
            F::And(v) if op == Op::And => {
                for x in v {
                    self.op(op, x, elem);
                }
            }
            F::Or(v) if op == Op::Or => {
                for x in v {
                    self.op(op, x, elem);
                }
            }
            _ => self.paren(op, f, elem),
        }
    }

    /// `op(` ... `)`: the operation deferred over a nested formula.
    fn paren(&mut self, op: Op, f: &F, elem: usize) {
        let at = self.lines.len();
        self.fresh(f, elem);
        // `AND( x` rather than `AND(` then `LD x`.
        let first = &self.lines[at];
        if first.op == "LD" && !first.label && !first.comment {
            let first = self.lines.remove(at);
            self.lines.insert(
                at,
                Line {
                    op: format!("{}(", op.word()),
                    ..first
                },
            );
        } else {
            self.lines.insert(
                at,
                Line {
                    label: false,
                    op: format!("{}(", op.word()),
                    operand: Vec::new(),
                    elem: Some(elem),
                    comment: false,
                },
            );
        }
        self.line(")", Vec::new(), Some(elem));
    }

    /// An operand for `f`, if it is a single value (not negated).
    fn operand(&mut self, f: &F) -> Option<Vec<Part>> {
        match f {
            F::True => Some(vec![part("TRUE")]),
            F::Atom(a) if !a.neg => {
                if let AtomKind::Temp(h) = a.kind {
                    self.read_temp(h);
                }
                Some(a.parts.clone())
            }
            F::Node(n, inner) => {
                let h = Hidden::Tmp(*n);
                if self.stored.contains(&h) {
                    self.read_temp(h);
                    Some(vec![part(self.name(h))])
                } else {
                    self.operand(inner)
                }
            }
            _ => None,
        }
    }

    // ------------------------------------------------------------ effects

    fn effect(&mut self, e: usize) {
        let el = &self.g.elems[e];
        match &el.kind {
            Kind::Coil {
                var,
                negated,
                storage,
                edge,
            } => {
                let f = self.input(e, 0);
                self.load(&f, e);
                if *edge != Edge::None {
                    if *storage != Storage::None {
                        self.unsupported(e, "a set or reset coil that also detects an edge");
                        return;
                    }
                    let (h, ty) = if *edge == Edge::Rising {
                        (Hidden::RTrig(e), "R_TRIG")
                    } else {
                        (Hidden::FTrig(e), "F_TRIG")
                    };
                    let inst = self.declare(h, ty, false);
                    self.line("ST", vec![part(format!("{inst}.CLK"))], Some(e));
                    self.line("CAL", vec![part(inst.clone())], Some(e));
                    self.line(
                        if *negated { "LDN" } else { "LD" },
                        vec![part(format!("{inst}.Q"))],
                        Some(e),
                    );
                    self.line("ST", vec![text_part(var)], Some(e));
                    self.cr = None;
                    return;
                }
                let op = match (storage, negated) {
                    (Storage::Set, _) => "S",
                    (Storage::Reset, _) => "R",
                    (Storage::None, false) => "ST",
                    (Storage::None, true) => "STN",
                };
                self.line(op, vec![text_part(var)], Some(e));
            }
            Kind::OutVariable { expr, negated } => {
                let f = self.input(e, 0);
                self.load(&f, e);
                let op = if *negated { "STN" } else { "ST" };
                self.line(op, vec![text_part(expr)], Some(e));
            }
            Kind::InOutVariable { expr } => {
                if self.g.ins[e][0].is_empty() {
                    return;
                }
                let f = self.input(e, 0);
                self.load(&f, e);
                self.line("ST", vec![text_part(expr)], Some(e));
            }
            Kind::Jump { label } => {
                let f = self.input(e, 0);
                if matches!(f.strip(), F::True) {
                    self.line("JMP", vec![text_part(label)], Some(e));
                } else {
                    self.load(&f, e);
                    self.line("JMPC", vec![text_part(label)], Some(e));
                }
                self.cr = None;
            }
            Kind::Return => {
                let f = self.input(e, 0);
                if matches!(f.strip(), F::True) {
                    self.line("RET", Vec::new(), Some(e));
                } else {
                    self.load(&f, e);
                    self.line("RETC", Vec::new(), Some(e));
                }
                self.cr = None;
            }
            Kind::Label { label } => {
                self.lines.push(Line {
                    label: true,
                    op: String::new(),
                    operand: vec![text_part(label)],
                    elem: Some(e),
                    comment: false,
                });
                self.cr = None;
            }
            Kind::Block { .. } => self.block(e),
            _ => {}
        }
    }

    fn unsupported(&mut self, e: usize, what: &str) {
        let el = &self.g.elems[e];
        let span = plcc_ir::diag::Span::new(self.ctx.file, el.tag.start, el.tag.end);
        if self.want.is_some() {
            self.diags.push(Diagnostic::error(
                codes::E_UNSUPPORTED,
                format!(
                    "not supported yet: {what} ({} (localId {}) in rung {} of `{}`)",
                    el.kind.describe(),
                    el.id,
                    self.rung,
                    self.ctx.pou
                ),
                span,
            ));
        }
    }

    fn block(&mut self, e: usize) {
        let el = &self.g.elems[e];
        let Kind::Block {
            ty,
            instance,
            inputs,
            in_outs,
            ..
        } = &el.kind
        else {
            return;
        };
        if inputs
            .iter()
            .chain(in_outs)
            .any(|p| p.edge.is_some_and(|x| x != Edge::None))
        {
            self.unsupported(e, "an edge on a block input");
            return;
        }
        let en = inputs.iter().position(|p| {
            p.name
                .as_ref()
                .is_some_and(|n| n.value.eq_ignore_ascii_case("EN"))
        });
        let guarded = en.filter(|&p| !self.en_always(e, p));
        if let Some(p) = guarded {
            let f = self.input(e, p);
            let f = if inputs[p].negated {
                F::Not(Box::new(f))
            } else {
                f
            };
            self.load(&f, e);
            let eno = Hidden::Eno(e);
            if self.wants(eno) && self.eno_used(e) {
                let name = self.declare(eno, "BOOL", true);
                self.line("ST", vec![part(name)], Some(e));
            }
            let skip = self.name(Hidden::Skip(e));
            self.line("JMPCN", vec![part(skip)], Some(e));
        }
        match instance {
            Some(inst) => self.fb_call(e, inst, en),
            None => self.function_call(e, ty, en),
        }
        if guarded.is_some() {
            let skip = self.name(Hidden::Skip(e));
            self.lines.push(Line {
                label: true,
                op: String::new(),
                operand: vec![part(skip)],
                elem: Some(e),
                comment: false,
            });
            self.cr = None;
        }
    }

    fn eno_used(&self, e: usize) -> bool {
        let k = &self.g.elems[e].kind;
        (0..self.g.outs[e].len()).any(|p| {
            output_name(k, p).is_some_and(|n| n.eq_ignore_ascii_case("ENO"))
                && !self.g.outs[e][p].is_empty()
        })
    }

    /// The output variables connected to output `port` of block `e`: (expression,
    /// negated).
    fn out_vars(&self, e: usize, port: usize) -> Vec<(Text, bool)> {
        self.g.outs[e][port]
            .iter()
            .filter_map(|&(c, _)| match &self.g.elems[c].kind {
                Kind::OutVariable { expr, negated } if self.fed_by_block(c) => {
                    Some((expr.clone(), *negated))
                }
                Kind::InOutVariable { expr } if self.fed_by_block(c) => Some((expr.clone(), false)),
                _ => None,
            })
            .collect()
    }

    fn fb_call(&mut self, e: usize, inst: &Text, en: Option<usize>) {
        let Kind::Block {
            inputs,
            in_outs,
            outputs,
            ..
        } = &self.g.elems[e].kind
        else {
            return;
        };
        let mut args: Vec<Vec<Part>> = Vec::new();
        let n_in = inputs.len();
        for (port, p) in inputs.iter().chain(in_outs).enumerate() {
            if Some(port) == en || self.g.ins[e][port].is_empty() {
                continue;
            }
            let pname = p.name.as_ref().expect("checked when read");
            let f = self.input(e, port);
            let operand = if p.negated { None } else { self.operand(&f) };
            if port >= n_in && operand.is_none() {
                self.unsupported(
                    e,
                    "an in-out parameter connected to anything but a variable",
                );
                continue;
            }
            match operand {
                Some(mut o) => {
                    let mut a = vec![text_part(pname), part(" := ")];
                    a.append(&mut o);
                    args.push(a);
                }
                None => {
                    self.load(&f, e);
                    let op = if p.negated { "STN" } else { "ST" };
                    self.line(
                        op,
                        vec![text_part(inst), part("."), text_part(pname)],
                        Some(e),
                    );
                }
            }
        }
        for (port, p) in outputs.iter().enumerate() {
            let pname = p.name.as_ref().expect("checked when read");
            if pname.value.eq_ignore_ascii_case("ENO") {
                continue;
            }
            for (var, neg) in self.out_vars(e, port) {
                let mut a = Vec::new();
                if neg != p.negated {
                    a.push(part("NOT "));
                }
                a.extend([text_part(pname), part(" => "), text_part(&var)]);
                args.push(a);
            }
        }
        let mut operand = vec![text_part(inst)];
        if !args.is_empty() {
            operand.push(part("("));
            for (i, a) in args.into_iter().enumerate() {
                if i > 0 {
                    operand.push(part(", "));
                }
                operand.extend(a);
            }
            operand.push(part(")"));
        }
        self.line("CAL", operand, Some(e));
        self.cr = None;
    }

    fn function_call(&mut self, e: usize, ty: &Text, en: Option<usize>) {
        let Kind::Block {
            inputs,
            outputs,
            in_outs,
            ..
        } = &self.g.elems[e].kind
        else {
            return;
        };
        if !in_outs.is_empty() {
            self.unsupported(e, "in-out parameters of a function in a ladder block");
            return;
        }
        // Inputs other than EN, as formulas.
        let mut args: Vec<(usize, F)> = Vec::new();
        for (port, p) in inputs.iter().enumerate() {
            if Some(port) == en {
                continue;
            }
            let f = self.input(e, port);
            let f = if p.negated { F::Not(Box::new(f)) } else { f };
            args.push((port, f));
        }
        // Every input after the first must be an operand: keep the others in
        // temporaries first.
        let mut operands: Vec<Vec<Part>> = Vec::new();
        for (port, f) in args.iter().skip(1) {
            match self.operand(f) {
                Some(o) => operands.push(o),
                None => {
                    self.load(f, e);
                    let name = self.declare(Hidden::In(e, *port), "BOOL", true);
                    self.line("ST", vec![part(name.clone())], Some(e));
                    operands.push(vec![part(name)]);
                }
            }
        }
        let word = vec![text_part(ty)];
        let mut operand: Vec<Part> = Vec::new();
        for (i, o) in operands.into_iter().enumerate() {
            if i > 0 {
                operand.push(part(", "));
            }
            operand.extend(o);
        }
        match args.first() {
            Some((_, f)) => {
                let f = f.clone();
                self.load(&f, e);
                let op = ty.value.to_ascii_uppercase();
                if op == "NOT" && operand.is_empty() {
                    self.line("NOT", Vec::new(), Some(e));
                } else {
                    // The function's name is the operator; its text maps to typeName.
                    let mut l = Line {
                        label: false,
                        op: String::new(),
                        operand: word,
                        elem: Some(e),
                        comment: false,
                    };
                    if !operand.is_empty() {
                        l.operand.push(part(" "));
                        l.operand.extend(operand);
                    }
                    self.lines.push(l);
                }
            }
            None => {
                // No input: a formal call with no arguments.
                let mut w = word;
                w.push(part("()"));
                self.lines.push(Line {
                    label: false,
                    op: String::new(),
                    operand: w,
                    elem: Some(e),
                    comment: false,
                });
            }
        }
        // The result is in the CR.
        let out = Hidden::Out(e);
        let result_port = outputs.iter().position(|p| {
            p.name
                .as_ref()
                .is_some_and(|n| !n.value.eq_ignore_ascii_case("ENO"))
        });
        for (port, p) in outputs.iter().enumerate() {
            let is_eno = p
                .name
                .as_ref()
                .is_some_and(|n| n.value.eq_ignore_ascii_case("ENO"));
            if is_eno || Some(port) == result_port {
                continue;
            }
            if !self.g.outs[e][port].is_empty() {
                self.unsupported(
                    e,
                    "outputs of a function other than its result, in a ladder block",
                );
            }
        }
        let Some(rp) = result_port else {
            self.cr = None;
            return;
        };
        let negated = outputs[rp].negated;
        if self.wants(out) && self.result_used_elsewhere(e, rp) {
            match self.result_type(e, rp) {
                Some(t) => {
                    let name = self.declare(out, &t, true);
                    let op = if negated { "STN" } else { "ST" };
                    self.line(op, vec![part(name)], Some(e));
                }
                None => {
                    if self.want.is_some() {
                        let el = &self.g.elems[e];
                        let span =
                            plcc_ir::diag::Span::new(self.ctx.file, el.tag.start, el.tag.end);
                        self.diags.push(
                            Diagnostic::error(
                                codes::LD_OUTPUT_TYPE,
                                format!(
                                    "cannot tell the type of the output of {} (localId {}) in rung {} of `{}`, which is needed to keep it",
                                    el.kind.describe(),
                                    el.id,
                                    self.rung,
                                    self.ctx.pou
                                ),
                                span,
                            )
                            .with_note(
                                "connect a variable of the POU to one of the block's inputs, or its \
                                 output to a variable",
                            ),
                        );
                    }
                }
            }
        }
        for (var, neg) in self.out_vars(e, rp) {
            let op = if neg != negated { "STN" } else { "ST" };
            self.line(op, vec![text_part(&var)], Some(e));
        }
        let name = self.name(out);
        self.cr = Some(F::Atom(Atom {
            parts: vec![part(name)],
            neg: negated,
            elem: e,
            kind: AtomKind::Temp(out),
        }));
    }

    /// True if the result of function block `e` goes anywhere but output variables.
    fn result_used_elsewhere(&self, e: usize, port: usize) -> bool {
        self.g.outs[e][port].iter().any(|&(c, _)| {
            !matches!(
                self.g.elems[c].kind,
                Kind::OutVariable { .. } | Kind::InOutVariable { .. }
            ) || !self.fed_by_block(c)
        })
    }

    /// The type of the result of function block `e`, from what it is or what it is
    /// connected to.
    fn result_type(&self, e: usize, port: usize) -> Option<String> {
        let Kind::Block { ty, .. } = &self.g.elems[e].kind else {
            return None;
        };
        let name = ty.value.to_ascii_uppercase();
        // A function of the project.
        if let Some(p) =
            self.ctx.project.pous.iter().find(|p| {
                p.kind == PouKind::Function && p.name.value.eq_ignore_ascii_case(&ty.value)
            })
        {
            return p.ret.as_ref().and_then(type_text);
        }
        if matches!(name.as_str(), "GT" | "GE" | "EQ" | "NE" | "LE" | "LT") {
            return Some("BOOL".into());
        }
        if let Some((_, to)) = name.split_once("_TO_") {
            return Some(to.to_string());
        }
        // Connected to power flow: BOOL.
        if self.g.outs[e][port].iter().any(|&(c, _)| {
            matches!(
                self.g.elems[c].kind,
                Kind::Contact { .. } | Kind::Coil { .. } | Kind::Jump { .. } | Kind::Return
            )
        }) {
            return Some("BOOL".into());
        }
        // The type of a variable it is connected to.
        let mut candidates: Vec<String> = Vec::new();
        for &(c, _) in &self.g.outs[e][port] {
            if let Kind::OutVariable { expr, .. } | Kind::InOutVariable { expr } =
                &self.g.elems[c].kind
            {
                candidates.push(expr.value.clone());
            }
        }
        let passes_type = matches!(
            name.as_str(),
            "ADD"
                | "SUB"
                | "MUL"
                | "DIV"
                | "MOD"
                | "MOVE"
                | "ABS"
                | "NEG"
                | "MIN"
                | "MAX"
                | "LIMIT"
                | "AND"
                | "OR"
                | "XOR"
                | "NOT"
                | "SHL"
                | "SHR"
                | "ROL"
                | "ROR"
                | "EXPT"
                | "SQRT"
                | "SEL"
                | "MUX"
        );
        if passes_type {
            for srcs in &self.g.ins[e] {
                for s in srcs {
                    if let Kind::InVariable { expr, .. } = &self.g.elems[s.elem].kind {
                        candidates.push(expr.value.clone());
                    }
                }
            }
        }
        candidates.iter().find_map(|c| self.var_type(c))
    }

    /// The declared type of a plain variable name of the POU (or a global).
    fn var_type(&self, name: &str) -> Option<String> {
        let n = name.trim();
        if !n.bytes().all(|b| b.is_ascii_alphanumeric() || b == b'_') {
            return typed_literal(n);
        }
        self.ctx
            .pou_vars
            .iter()
            .flat_map(|g| &g.vars)
            .chain(self.ctx.globals.iter().copied())
            .find(|v| v.name.value.eq_ignore_ascii_case(n))
            .and_then(|v| type_text(&v.ty))
    }
}

/// The type of a typed literal (`INT#5`, `T#5s`).
fn typed_literal(s: &str) -> Option<String> {
    let (prefix, _) = s.split_once('#')?;
    let p = prefix.to_ascii_uppercase();
    Some(match p.as_str() {
        "T" | "TIME" => "TIME".into(),
        "LT" | "LTIME" => "LTIME".into(),
        "D" | "DATE" => "DATE".into(),
        "TOD" | "TIME_OF_DAY" => "TOD".into(),
        "DT" | "DATE_AND_TIME" => "DT".into(),
        _ if p.bytes().all(|b| b.is_ascii_alphabetic()) => p,
        _ => return None,
    })
}

/// A type as IEC text, if it is a simple one.
fn type_text(t: &Type) -> Option<String> {
    match t {
        Type::Named(n) => Some(n.value.clone()),
        Type::String { wide, len } => Some(format!(
            "{}{}",
            if *wide { "WSTRING" } else { "STRING" },
            len.as_ref()
                .map(|l| format!("[{}]", l.value))
                .unwrap_or_default()
        )),
        _ => None,
    }
}

/// `f1 OR f2 OR ...` with the operands the terms start with taken out once:
/// `(a AND b) OR (a AND c AND d)` is `a AND (b OR (c AND d))`, as the rung draws it
/// (the contact before a parallel block is read once).
fn factor(terms: Vec<F>) -> F {
    let mut groups: Vec<(F, Vec<Option<F>>)> = Vec::new();
    for t in terms {
        let (first, rest) = match t {
            F::And(mut v) if v.len() >= 2 => {
                let first = v.remove(0);
                let rest = if v.len() == 1 {
                    v.pop().expect("one")
                } else {
                    F::And(v)
                };
                (first, Some(rest))
            }
            other => (other, None),
        };
        match groups.iter_mut().find(|(f, _)| same(f, &first)) {
            Some((_, rests)) => rests.push(rest),
            None => groups.push((first, vec![rest])),
        }
    }
    let mut out = Vec::new();
    for (first, rests) in groups {
        if rests.len() == 1 || rests.iter().any(Option::is_none) {
            for r in rests {
                out.push(match r {
                    Some(r) => and_all(first.clone(), r),
                    None => first.clone(),
                });
            }
        } else {
            let inner = factor(rests.into_iter().flatten().collect());
            out.push(and_all(first, inner));
        }
    }
    if out.len() == 1 {
        out.pop().expect("one")
    } else {
        F::Or(out)
    }
}

/// `first AND rest`, flattened.
fn and_all(first: F, rest: F) -> F {
    match rest {
        F::And(v) => {
            let mut all = vec![first];
            all.extend(v);
            F::And(all)
        }
        r => F::And(vec![first, r]),
    }
}
