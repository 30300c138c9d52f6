//! The twin of a generated program: its diagrams written as Structured Text by the
//! rules docs/plcopen.md gives for the standard's meaning (profile `iec`), without
//! plcc's lowering. The XML and its twin run side by side; where they differ, plcc's
//! lowering and its documentation disagree.
//!
//! The rules, as the twin applies them:
//!
//! - a body is cut into networks (elements wired to each other; rails join nothing;
//!   a continuation joins its connector), run by their smallest `executionOrderId`
//!   (networks without one last), then top to bottom by their topmost, then leftmost
//!   element, then the first in the document;
//! - within a network an element runs once, after everything wired to its inputs;
//!   among those ready together the smaller `executionOrderId` first (none counts
//!   as 0), then the topmost, the leftmost, the first in the document; when nothing
//!   is ready, the loop is cut at its first block (by the same order; among the
//!   loops whose other inputs are computed), which reads on the wires that come
//!   back the outputs as they were before its call;
//! - a contact's power is its input AND its variable, read when it runs (an edge
//!   detector of its own called then); a coil writes its variable and passes its
//!   power (the OR of its wires) on; an input variable is read where it is used;
//! - a block: the wired inputs (negated, or through a detector of their own), an
//!   unwired function input its type's default, an unwired FB input keeps its
//!   value; with EN wired to anything but the left rail, it runs only when EN is
//!   TRUE (a function's result is then its type's default, ENO FALSE); an output
//!   variable fed by such a block alone is written only when it ran; a function no
//!   one reads does not run;
//! - jumps, returns and labels run.
//!
//! The twin writes functions as operators where ST has them (`a + b`, `a > b`), so
//! the two go through different parts of the compiler.

use super::{networks, Edge, Kind, Pou, Storage, Ty, VarTy, Wire, XmlProg};
use std::collections::{BTreeMap, BTreeSet};
use std::fmt::Write;

/// A type's default, as an ST literal.
fn default(t: Ty) -> &'static str {
    match t {
        Ty::Bool => "FALSE",
        Ty::Int => "INT#0",
        Ty::Dint => "DINT#0",
        Ty::Real => "REAL#0.0",
        Ty::Time => "T#0s",
    }
}

fn paren(s: &str) -> String {
    format!("({s})")
}

struct Tw<'a> {
    p: &'a Pou,
    /// `localId` to document index.
    at: BTreeMap<u64, usize>,
    /// Hidden variables: (name, type).
    hidden: Vec<(String, String)>,
    lines: Vec<String>,
    done: BTreeSet<u64>,
    detectors: usize,
    /// Give no twin where plcc is known to differ from its documentation.
    avoid: bool,
}

impl<'a> Tw<'a> {
    fn elem(&self, id: u64) -> &'a super::Elem {
        &self.p.elems[self.at[&id]]
    }

    /// The sort key of an element: (executionOrderId, y, x, document index).
    fn key(&self, id: u64) -> (u32, i64, i64, usize) {
        let e = self.elem(id);
        (e.order.unwrap_or(0), e.pos.1, e.pos.0, self.at[&id])
    }

    /// What a connection stands for: (element, output pin), a continuation replaced
    /// by what is wired to its connector.
    fn sources(&self, w: &Wire, depth: u32) -> Vec<(u64, Option<String>)> {
        let Some(&i) = self.at.get(&w.from) else {
            return Vec::new();
        };
        match &self.p.elems[i].kind {
            Kind::Continuation { name } if depth < 16 => self
                .p
                .elems
                .iter()
                .filter_map(|c| match &c.kind {
                    Kind::Connector { name: n, wires } if n == name => Some(wires),
                    _ => None,
                })
                .flatten()
                .flat_map(|w2| self.sources(w2, depth + 1))
                .collect(),
            Kind::Continuation { .. } => Vec::new(),
            _ => vec![(w.from, w.pin.clone())],
        }
    }

    fn all_sources(&self, wires: &[Wire]) -> Vec<(u64, Option<String>)> {
        wires.iter().flat_map(|w| self.sources(w, 0)).collect()
    }

    /// The elements `id` reads (its inputs' sources).
    fn deps(&self, id: u64) -> Vec<u64> {
        match &self.elem(id).kind {
            Kind::Connector { .. } | Kind::RightRail { .. } => Vec::new(),
            k => k
                .wires()
                .into_iter()
                .flat_map(|w| self.sources(w, 0))
                .map(|(s, _)| s)
                .collect(),
        }
    }

    fn new_detector(&mut self, rising: bool) -> String {
        self.detectors += 1;
        let name = format!("zz_det{}", self.detectors);
        let ty = if rising { "R_TRIG" } else { "F_TRIG" };
        self.hidden.push((name.clone(), ty.into()));
        name
    }

    /// A value through an edge detector called now.
    fn detect(&mut self, v: &str, rising: bool) -> String {
        let d = self.new_detector(rising);
        self.lines.push(format!("{d}(CLK := {v});"));
        format!("{d}.Q")
    }

    /// True if block `id` has EN wired to anything but the left rail.
    fn en_wired(&self, id: u64) -> bool {
        let Kind::Block { inputs, .. } = &self.elem(id).kind else {
            return false;
        };
        inputs.iter().any(|p| {
            p.name == "EN" && {
                let s = self.all_sources(&p.wires);
                !s.is_empty()
                    && !s
                        .iter()
                        .any(|(x, _)| matches!(self.elem(*x).kind, Kind::LeftRail))
            }
        })
    }

    /// Something reads an output of block `id`.
    fn read(&self, id: u64, pin: Option<&str>) -> bool {
        self.p.elems.iter().any(|e| {
            !matches!(e.kind, Kind::Connector { .. } | Kind::RightRail { .. })
                && e.kind.wires().into_iter().any(|w| {
                    self.sources(w, 0)
                        .iter()
                        .any(|(s, q)| *s == id && (pin.is_none() || q.as_deref() == pin))
                })
        })
    }

    /// The value on output `pin` of element `id`; `None` where the rules give it
    /// none (read before it runs, and not a block's stored output).
    fn value(&self, id: u64, pin: Option<&str>) -> Option<String> {
        let e = self.elem(id);
        let done = self.done.contains(&id);
        match &e.kind {
            Kind::LeftRail => Some("TRUE".into()),
            Kind::InVar { expr, negated } => Some(if *negated {
                format!("NOT {}", paren(expr))
            } else {
                paren(expr)
            }),
            Kind::Contact { .. } | Kind::Coil { .. } if done => Some(format!("zz_p{id}")),
            Kind::Block {
                instance, outputs, ..
            } => {
                let pin = pin?;
                let p = outputs.iter().find(|p| p.name == pin)?;
                let raw = if pin == "ENO" {
                    if self.en_wired(id) {
                        format!("zz_eno{id}")
                    } else {
                        "TRUE".into()
                    }
                } else {
                    match instance {
                        Some(i) => format!("{i}.{pin}"),
                        None => format!("zz_f{id}"),
                    }
                };
                match (p.negated, p.edge) {
                    (true, Edge::None) => Some(format!("NOT {raw}")),
                    (false, Edge::None) => Some(raw),
                    (false, _) if done => Some(format!("zz_o{id}_{pin}.Q")),
                    _ => None,
                }
            }
            _ => None,
        }
    }

    /// The OR of what `wires` carry; `None` if one has no value yet or a non-BOOL
    /// input has several.
    fn input(&self, wires: &[Wire], ty: Ty) -> Option<String> {
        let srcs = self.all_sources(wires);
        if srcs.len() > 1 && ty != Ty::Bool {
            return None;
        }
        let vals: Option<Vec<String>> = srcs
            .iter()
            .map(|(s, p)| self.value(*s, p.as_deref()))
            .collect();
        let vals = vals?;
        Some(match vals.len() {
            0 => "TRUE".into(),
            1 => vals[0].clone(),
            _ => paren(&vals.join(" OR ")),
        })
    }

    fn contact(&mut self, id: u64) -> Option<()> {
        let Kind::Contact {
            var,
            negated,
            edge,
            wires,
        } = &self.elem(id).kind
        else {
            return None;
        };
        let input = self.input(wires, Ty::Bool)?;
        let term = match (negated, edge) {
            (true, Edge::None) => format!("NOT {var}"),
            (false, Edge::None) => var.clone(),
            (false, e) => self.detect(var, *e == Edge::Rising),
            _ => return None,
        };
        self.hidden.push((format!("zz_p{id}"), "BOOL".into()));
        self.lines.push(format!("zz_p{id} := {input} AND {term};"));
        Some(())
    }

    fn coil(&mut self, id: u64) -> Option<()> {
        let Kind::Coil {
            var,
            negated,
            storage,
            edge,
            wires,
        } = &self.elem(id).kind
        else {
            return None;
        };
        let input = self.input(wires, Ty::Bool)?;
        let p = format!("zz_p{id}");
        self.hidden.push((p.clone(), "BOOL".into()));
        self.lines.push(format!("{p} := {input};"));
        let s = match (negated, storage, edge) {
            (false, Storage::None, Edge::None) => format!("{var} := {p};"),
            (true, Storage::None, Edge::None) => format!("{var} := NOT {p};"),
            (false, Storage::Set, Edge::None) => format!("IF {p} THEN {var} := TRUE; END_IF;"),
            (false, Storage::Reset, Edge::None) => {
                format!("IF {p} THEN {var} := FALSE; END_IF;")
            }
            (false, Storage::None, e) => {
                let q = self.detect(&p, *e == Edge::Rising);
                format!("{var} := {q};")
            }
            _ => return None,
        };
        self.lines.push(s);
        Some(())
    }

    /// A function as an expression over its inputs (by name).
    fn function(ty: &str, args: &BTreeMap<String, String>) -> Option<String> {
        let a = |n: &str| args.get(n).cloned();
        let ins: Vec<String> = ["IN1", "IN2", "IN3"].iter().filter_map(|n| a(n)).collect();
        let op = |o: &str| paren(&ins.join(&format!(" {o} ")));
        Some(match ty {
            "ADD" => op("+"),
            "MUL" => op("*"),
            "SUB" => op("-"),
            "DIV" => op("/"),
            "MOD" => op("MOD"),
            "AND" => op("AND"),
            "OR" => op("OR"),
            "XOR" => op("XOR"),
            "GT" => op(">"),
            "GE" => op(">="),
            "EQ" => op("="),
            "NE" => op("<>"),
            "LT" => op("<"),
            "LE" => op("<="),
            "NOT" => format!("(NOT {})", a("IN")?),
            "MOVE" => a("IN")?,
            "MAX" | "MIN" => format!("{ty}({})", ins.join(", ")),
            "SEL" => format!("SEL({}, {}, {})", a("G")?, a("IN0")?, a("IN1")?),
            "LIMIT" => format!("LIMIT({}, {}, {})", a("MN")?, a("IN")?, a("MX")?),
            _ => format!("{ty}({})", a("IN")?),
        })
    }

    fn block(&mut self, id: u64) -> Option<()> {
        let Kind::Block {
            ty,
            instance,
            inputs,
            outputs,
        } = &self.elem(id).kind
        else {
            return None;
        };
        let en = self.en_wired(id);
        let mut en_value = None;
        let mut args: BTreeMap<String, String> = BTreeMap::new();
        let mut order: Vec<String> = Vec::new();
        for pin in inputs {
            if pin.name == "EN" && !en {
                continue;
            }
            let v = if self.all_sources(&pin.wires).is_empty() {
                match instance {
                    // An unwired input of an FB keeps its value.
                    Some(_) => continue,
                    None => default(pin.ty).to_string(),
                }
            } else {
                let v = self.input(&pin.wires, pin.ty)?;
                match (pin.negated, pin.edge) {
                    (true, Edge::None) => format!("NOT {v}"),
                    (false, Edge::None) => v,
                    (false, e) => self.detect(&v, e == Edge::Rising),
                    _ => return None,
                }
            };
            if pin.name == "EN" {
                en_value = Some(v);
            } else {
                order.push(pin.name.clone());
                args.insert(pin.name.clone(), v);
            }
        }
        let guard = |body: String, off: String| match &en_value {
            Some(e) => format!("IF {e} THEN {body} ELSE {off} END_IF;"),
            None => body,
        };
        let eno = format!("zz_eno{id}");
        if en {
            self.hidden.push((eno.clone(), "BOOL".into()));
        }
        match instance {
            Some(i) => {
                let call = order
                    .iter()
                    .map(|n| format!("{n} := {}", args[n]))
                    .collect::<Vec<_>>()
                    .join(", ");
                let on = if en {
                    format!("{i}({call}); {eno} := TRUE;")
                } else {
                    format!("{i}({call});")
                };
                let line = guard(on, format!("{eno} := FALSE;"));
                self.lines.push(line);
            }
            None => {
                if !self.read(id, None) {
                    // No one reads it: it does not run.
                    return Some(());
                }
                let out = outputs.iter().find(|p| p.name != "ENO")?;
                let f = format!("zz_f{id}");
                self.hidden.push((f.clone(), out.ty.name().into()));
                let expr = Self::function(ty, &args)?;
                let on = if en {
                    format!("{f} := {expr}; {eno} := TRUE;")
                } else {
                    format!("{f} := {expr};")
                };
                let off = format!("{f} := {}; {eno} := FALSE;", default(out.ty));
                let line = guard(on, off);
                self.lines.push(line);
            }
        }
        // Edges on outputs: a detector each, called after the block.
        for p in outputs {
            if p.edge != Edge::None && !p.negated && self.read(id, Some(&p.name)) {
                let raw = match (p.name.as_str(), instance) {
                    ("ENO", _) if en => eno.clone(),
                    ("ENO", _) => "TRUE".into(),
                    (n, Some(i)) => format!("{i}.{n}"),
                    (_, None) => format!("zz_f{id}"),
                };
                let d = format!("zz_o{id}_{}", p.name);
                let t = if p.edge == Edge::Rising {
                    "R_TRIG"
                } else {
                    "F_TRIG"
                };
                self.hidden.push((d.clone(), t.into()));
                self.lines.push(format!("{d}(CLK := {raw});"));
            }
        }
        Some(())
    }

    fn out_var(&mut self, id: u64) -> Option<()> {
        let Kind::OutVar {
            expr,
            negated,
            wires,
        } = &self.elem(id).kind
        else {
            return None;
        };
        let srcs = self.all_sources(wires);
        if srcs.is_empty() {
            return Some(());
        }
        // One wire, of any type; several only of power flow.
        let v = self.input(wires, Ty::Bool)?;
        let v = if *negated { format!("NOT {v}") } else { v };
        let mut s = format!("{expr} := {v};");
        // Fed by a block whose EN is wired: written only when the block ran (its
        // ENO itself is not guarded: it is the variable's value).
        if let [(b, pin)] = srcs.as_slice() {
            let from_eno = pin
                .as_deref()
                .is_some_and(|p| p.eq_ignore_ascii_case("ENO"));
            if self.en_wired(*b) && !from_eno {
                s = format!("IF zz_eno{b} THEN {s} END_IF;");
            }
        }
        self.lines.push(s);
        Some(())
    }

    fn eval(&mut self, id: u64) -> Option<()> {
        match &self.elem(id).kind {
            Kind::Contact { .. } => self.contact(id)?,
            Kind::Coil { .. } => self.coil(id)?,
            Kind::Block { .. } => self.block(id)?,
            Kind::OutVar { .. } => self.out_var(id)?,
            Kind::Jump { wires, .. } | Kind::Return { wires }
                if self.all_sources(wires).is_empty() => {}
            Kind::Jump { label, wires } => {
                let p = self.input(wires, Ty::Bool)?;
                self.lines.push(format!("IF {p} THEN JMP {label}; END_IF;"));
            }
            Kind::Return { wires } => {
                let p = self.input(wires, Ty::Bool)?;
                self.lines.push(format!("IF {p} THEN RETURN; END_IF;"));
            }
            Kind::Label { label } => self.lines.push(format!("{label}: ;")),
            _ => {}
        }
        Some(())
    }

    /// The order of the elements of a network; `None` where a loop's cut leaves a
    /// value the rules do not give.
    fn order(&self, members: &[u64]) -> Option<Vec<u64>> {
        let inside: BTreeSet<u64> = members.iter().copied().collect();
        let deps: BTreeMap<u64, Vec<u64>> = members
            .iter()
            .map(|&m| {
                let d = self.deps(m).into_iter().filter(|d| inside.contains(d));
                (m, d.collect())
            })
            .collect();
        let mut done: BTreeSet<u64> = BTreeSet::new();
        let mut out = Vec::new();
        while out.len() < members.len() {
            let rest: Vec<u64> = members
                .iter()
                .copied()
                .filter(|m| !done.contains(m))
                .collect();
            let ready = rest
                .iter()
                .copied()
                .filter(|m| deps[m].iter().all(|d| done.contains(d)))
                .min_by_key(|&m| self.key(m));
            let next = match ready {
                Some(m) => m,
                None => {
                    // A loop: cut at its first block, among the loops whose other
                    // inputs are computed (source components of what is left).
                    let reach = |b: u64| {
                        let mut seen = BTreeSet::new();
                        let mut todo = vec![b];
                        while let Some(x) = todo.pop() {
                            for &c in &rest {
                                if deps[&c].contains(&x) && seen.insert(c) {
                                    todo.push(c);
                                }
                            }
                        }
                        seen
                    };
                    let reaches: BTreeMap<u64, BTreeSet<u64>> =
                        rest.iter().map(|&x| (x, reach(x))).collect();
                    let component = |b: u64| -> BTreeSet<u64> {
                        let mut c: BTreeSet<u64> = rest
                            .iter()
                            .copied()
                            .filter(|y| reaches[&b].contains(y) && reaches[y].contains(&b))
                            .collect();
                        c.insert(b);
                        c
                    };
                    let candidate = |b: u64| {
                        if !matches!(self.elem(b).kind, Kind::Block { .. })
                            || !reaches[&b].contains(&b)
                        {
                            return false;
                        }
                        let comp = component(b);
                        comp.iter()
                            .all(|m| deps[m].iter().all(|d| done.contains(d) || comp.contains(d)))
                    };
                    let cut = rest
                        .iter()
                        .copied()
                        .filter(|&b| candidate(b))
                        .min_by_key(|&b| self.key(b))?;
                    // Known bug 7: plcc starts at the first block left.
                    let block = |b: &u64| matches!(self.elem(*b).kind, Kind::Block { .. });
                    let first = rest
                        .iter()
                        .copied()
                        .filter(block)
                        .min_by_key(|&b| self.key(b));
                    if self.avoid && first != Some(cut) {
                        return None;
                    }
                    // It reads the loop's values as they are: only blocks keep them.
                    let stored = deps[&cut].iter().all(|d| {
                        done.contains(d) || matches!(self.elem(*d).kind, Kind::Block { .. })
                    });
                    if !stored {
                        return None;
                    }
                    cut
                }
            };
            done.insert(next);
            out.push(next);
        }
        Some(out)
    }
}

/// A variable's declaration.
fn decl(v: &super::Var) -> String {
    let ty = match &v.ty {
        VarTy::Elem(t) => t.name().to_string(),
        VarTy::Fb(n) => n.clone(),
    };
    match &v.init {
        Some(i) => format!("    {} : {ty} := {i};\n", v.name),
        None => format!("    {} : {ty};\n", v.name),
    }
}

/// The twin of one POU, or `None`.
fn pou(p: &Pou, avoid: bool) -> Option<String> {
    let mut tw = Tw {
        avoid,
        p,
        at: p.elems.iter().enumerate().map(|(i, e)| (e.id, i)).collect(),
        hidden: Vec::new(),
        lines: Vec::new(),
        done: BTreeSet::new(),
        detectors: 0,
    };
    let mut nets = networks(p);
    nets.sort_by_key(|n| {
        let id = n
            .iter()
            .filter_map(|&id| tw.elem(id).order.filter(|&o| o > 0))
            .min()
            .unwrap_or(u32::MAX);
        let top = n
            .iter()
            .map(|&id| {
                let e = tw.elem(id);
                (e.pos.1, e.pos.0, tw.at[&id])
            })
            .min();
        (id, top)
    });
    for net in nets {
        tw.lines.push(String::new());
        for id in tw.order(&net)? {
            tw.eval(id)?;
            tw.done.insert(id);
        }
    }
    let mut o = String::new();
    let (head, tail) = if p.fb {
        ("FUNCTION_BLOCK", "END_FUNCTION_BLOCK")
    } else {
        ("PROGRAM", "END_PROGRAM")
    };
    let _ = writeln!(o, "{head} {}", p.name);
    for (class, kw) in [
        (super::Class::Input, "VAR_INPUT"),
        (super::Class::Output, "VAR_OUTPUT"),
        (super::Class::Local, "VAR"),
    ] {
        let vars: Vec<&super::Var> = p.vars.iter().filter(|v| v.class == class).collect();
        if !vars.is_empty() {
            let _ = writeln!(o, "{kw}");
            for v in vars {
                o.push_str(&decl(v));
            }
            o.push_str("END_VAR\n");
        }
    }
    if !tw.hidden.is_empty() {
        o.push_str("VAR\n");
        for (n, t) in &tw.hidden {
            let _ = writeln!(o, "    {n} : {t};");
        }
        o.push_str("END_VAR\n");
    }
    o.push_str("    ;\n");
    for l in &tw.lines {
        if !l.is_empty() {
            let _ = writeln!(o, "    {l}");
        }
    }
    let _ = writeln!(o, "{tail}\n");
    Some(o)
}

/// The twin of a program as ST, or `None` where the documented rules do not fix
/// its meaning (a loop cut where a value is read that nothing keeps, an edge on an
/// output read before its block runs). With `avoid`, `None` too for the programs
/// where plcc's lowering and its documentation are known to differ
/// ([`super::gen::KNOWN_BUGS`] 5 to 7).
pub fn twin(prog: &XmlProg, avoid: bool) -> Option<String> {
    if avoid && prog.pous.iter().any(|p| super::loops(p).1 || eno_back(p)) {
        return None;
    }
    let mut o = String::new();
    for p in &prog.pous {
        o.push_str(&pou(p, avoid)?);
    }
    Some(o)
}

/// True if an ENO is wired back into its own block (known bug 6).
fn eno_back(p: &Pou) -> bool {
    p.elems.iter().any(|e| match &e.kind {
        Kind::Block { inputs, .. } => inputs
            .iter()
            .flat_map(|i| &i.wires)
            .any(|w| w.from == e.id && w.pin.as_deref() == Some("ENO")),
        _ => false,
    })
}
