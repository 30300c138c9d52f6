//! `--emit ld-text`: every ladder body drawn as ASCII ladder, rung by rung, for review
//! in a terminal and in diffs.
//!
//! ```text
//! (* PROGRAM motor *)
//! rung 1
//! |--[start]--+--[/stop]--(run)--|
//! |--[run]----+                  |
//! ```
//!
//! Contacts are `[x]` (normally closed `[/x]`, rising `[P x]`, falling `[N x]`), coils
//! `(x)` (negated `(/x)`, set `(S x)`, reset `(R x)`, edge `(P x)` `(N x)`), blocks
//! `[TYPE instance IN:=value OUT=>variable]` with the variables wired to their data
//! inputs and outputs, variables in the power flow `{x}` (read) and `{=x}` (written),
//! jumps `>>label`, returns `<RETURN>`. Parallel branches hang below their line
//! between `+` junctions; where a block has several inputs or outputs in the power
//! flow, the wires say which (`>R`, `CV>`). The drawing follows the rung's
//! series-parallel structure, not the positions in the file.
//!
//! What cannot be drawn so (a function block diagram, a rung that is not
//! series-parallel) is listed as a netlist, one element per line in the order it is
//! evaluated, each input with what is wired to it:
//!
//! ```text
//! network 1
//!   #2 [ADD] IN1 <- {a}, IN2 <- #2.OUT
//!   #3 {=x} <- #2.OUT
//! ```

use super::graph::{input_name, output_name, Graph, Net};
use super::xml::{Body, Edge, Element, Graphic, Kind, PouKind, Project, Storage};

/// Draws every ladder body of the project.
pub(crate) fn render(project: &Project, graphs: &[Option<Graph>]) -> String {
    let mut out = String::new();
    for (pou, g) in project.pous.iter().zip(graphs) {
        let Some(g) = g else {
            continue;
        };
        let kind = match pou.kind {
            PouKind::Program => "PROGRAM",
            PouKind::Function => "FUNCTION",
            PouKind::FunctionBlock => "FUNCTION_BLOCK",
        };
        if !out.is_empty() {
            out.push('\n');
        }
        out.push_str(&format!("(* {kind} {} *)\n", pou.name.value));
        if matches!(pou.body, Body::Graph(Graphic::Fbd, _)) {
            for rung in &g.rungs {
                out.push_str(&format!("network {}\n", rung.number));
                netlist(g, &rung.order, &mut out);
            }
            continue;
        }
        for rung in &g.rungs {
            if let [e] = rung.order.as_slice() {
                if let Kind::Label { label } = &g.elems[*e].kind {
                    out.push_str(&format!("rung {}\n{}:\n", rung.number, label.value));
                    continue;
                }
            }
            out.push_str(&format!("rung {}\n", rung.number));
            if rung.net.is_none() {
                netlist(g, &rung.order, &mut out);
                continue;
            }
            let mut drawn = Vec::new();
            if let Some(net) = &rung.net {
                collect(net, &mut drawn);
                if !drawn.is_empty() {
                    let b = draw(net, g, true, true);
                    for (r, row) in b.rows.iter().enumerate() {
                        let lead = if b.lw[r] { "--" } else { "  " };
                        let trail = if b.rw[r] { "--" } else { "  " };
                        out.push('|');
                        out.push_str(lead);
                        out.push_str(row);
                        out.push_str(trail);
                        out.push_str("|\n");
                    }
                }
            }
            // Blocks wired to variables only are not in the power flow: one line each.
            for &e in &rung.order {
                if !drawn.contains(&e) && matches!(g.elems[e].kind, Kind::Block { .. }) {
                    out.push_str(&format!("|  {}\n", glyph(g, e)));
                }
            }
        }
    }
    out
}

/// One line per element of `order`: the element and what is wired to its inputs.
fn netlist(g: &Graph, order: &[usize], out: &mut String) {
    let src = |s: super::graph::Src| -> String {
        let el = &g.elems[s.elem];
        match &el.kind {
            Kind::LeftRail => "|".to_string(),
            Kind::InVariable { expr, negated } => {
                let n = if *negated { "NOT " } else { "" };
                format!("{{{n}{}}}", expr.value)
            }
            Kind::InOutVariable { expr } => format!("{{{}}}", expr.value),
            Kind::Block { .. } => format!(
                "#{}.{}",
                el.id,
                output_name(&el.kind, s.port).unwrap_or("?")
            ),
            _ => format!("#{}", el.id),
        }
    };
    for &e in order {
        let el = &g.elems[e];
        let what = match &el.kind {
            Kind::InVariable { .. } | Kind::LeftRail | Kind::RightRail => continue,
            Kind::OutVariable { expr, negated } => {
                let n = if *negated { "NOT " } else { "" };
                format!("{{={n}{}}}", expr.value)
            }
            Kind::InOutVariable { expr } => format!("{{={}}}", expr.value),
            Kind::Block { ty, instance, .. } => match instance {
                Some(i) => format!("[{} {}]", ty.value, i.value),
                None => format!("[{}]", ty.value),
            },
            Kind::Connector { name } => format!(">{}>", name.value),
            Kind::Continuation { .. } => continue,
            _ => glyph(g, e),
        };
        let mut ins = Vec::new();
        for (port, srcs) in g.ins[e].iter().enumerate() {
            if srcs.is_empty() {
                continue;
            }
            let from: Vec<String> = srcs.iter().map(|&s| src(s)).collect();
            let from = from.join(" | ");
            match input_name(&el.kind, port) {
                Some(p) => ins.push(format!("{p} <- {from}")),
                None => ins.push(format!("<- {from}")),
            }
        }
        out.push_str(&format!("  #{} {what}", el.id));
        if !ins.is_empty() {
            out.push(' ');
            out.push_str(&ins.join(", "));
        }
        out.push('\n');
    }
}

/// The elements a net draws.
fn collect(n: &Net, out: &mut Vec<usize>) {
    match n {
        Net::Elem(e) => out.push(*e),
        Net::Series(v) | Net::Parallel(v) => v.iter().for_each(|x| collect(x, out)),
        Net::Wire { .. } => {}
    }
}

/// A drawing: rows of equal width (row 0 is the line through it) and which rows touch
/// the left and the right side with a wire.
struct Blk {
    rows: Vec<String>,
    lw: Vec<bool>,
    rw: Vec<bool>,
}

fn width(s: &str) -> usize {
    s.chars().count()
}

impl Blk {
    fn one(s: String) -> Blk {
        Blk {
            rows: vec![s],
            lw: vec![true],
            rw: vec![true],
        }
    }

    fn width(&self) -> usize {
        self.rows.first().map_or(0, |r| width(r))
    }

    fn is_empty(&self) -> bool {
        self.width() == 0
    }
}

/// The text of an element.
fn glyph(g: &Graph, e: usize) -> String {
    let el: &Element = &g.elems[e];
    match &el.kind {
        Kind::Contact {
            var, negated, edge, ..
        } => {
            let n = if *negated { "/" } else { "" };
            let ed = match edge {
                Edge::None => "",
                Edge::Rising => "P ",
                Edge::Falling => "N ",
            };
            format!("[{n}{ed}{}]", var.value)
        }
        Kind::Coil {
            var,
            negated,
            storage,
            edge,
        } => {
            let m = match (storage, edge) {
                (Storage::Set, _) => "S ",
                (Storage::Reset, _) => "R ",
                (_, Edge::Rising) => "P ",
                (_, Edge::Falling) => "N ",
                _ => "",
            };
            let n = if *negated { "/" } else { "" };
            format!("({n}{m}{})", var.value)
        }
        Kind::Block { ty, instance, .. } => {
            let mut s = format!("[{}", ty.value);
            if let Some(i) = instance {
                s.push(' ');
                s.push_str(&i.value);
            }
            for (port, srcs) in g.ins[e].iter().enumerate() {
                for src in srcs {
                    if let Kind::InVariable { expr, negated }
                    | Kind::OutVariable { expr, negated } = &g.elems[src.elem].kind
                    {
                        let not = if *negated { "NOT " } else { "" };
                        s.push_str(&format!(
                            " {}:={not}{}",
                            input_name(&el.kind, port).unwrap_or("?"),
                            expr.value
                        ));
                    } else if let Kind::InOutVariable { expr } = &g.elems[src.elem].kind {
                        s.push_str(&format!(
                            " {}:={}",
                            input_name(&el.kind, port).unwrap_or("?"),
                            expr.value
                        ));
                    }
                }
            }
            for (port, cons) in g.outs[e].iter().enumerate() {
                for &(c, _) in cons {
                    if let Kind::OutVariable { expr, .. } | Kind::InOutVariable { expr } =
                        &g.elems[c].kind
                    {
                        s.push_str(&format!(
                            " {}=>{}",
                            output_name(&el.kind, port).unwrap_or("?"),
                            expr.value
                        ));
                    }
                }
            }
            s.push(']');
            s
        }
        Kind::InVariable { expr, negated } => {
            format!("{{{}{}}}", if *negated { "NOT " } else { "" }, expr.value)
        }
        Kind::OutVariable { expr, negated } => {
            format!("{{={}{}}}", if *negated { "NOT " } else { "" }, expr.value)
        }
        Kind::InOutVariable { expr } => format!("{{{}}}", expr.value),
        Kind::Jump { label } => format!(">>{}", label.value),
        Kind::Return => "<RETURN>".into(),
        Kind::Label { label } => format!("{}:", label.value),
        other => other.describe(),
    }
}

/// Draws a net. `open_left`/`open_right`: it starts at the left rail or ends at the
/// right one, so that parallel branches there hang on the rail rather than on `+`.
fn draw(n: &Net, g: &Graph, open_left: bool, open_right: bool) -> Blk {
    match n {
        Net::Elem(e) => Blk::one(glyph(g, *e)),
        Net::Wire { from, to } => {
            let mut s = String::new();
            if let Some(f) = from {
                s.push_str(f);
                s.push('>');
            }
            if let Some(t) = to {
                s.push('>');
                s.push_str(t);
            }
            Blk::one(s)
        }
        Net::Series(items) => {
            let last = items.len().saturating_sub(1);
            let parts: Vec<Blk> = items
                .iter()
                .enumerate()
                .map(|(i, x)| draw(x, g, open_left && i == 0, open_right && i == last))
                .filter(|b| !b.is_empty())
                .collect();
            series(parts)
        }
        Net::Parallel(branches) => {
            let parts: Vec<Blk> = branches.iter().map(|b| draw(b, g, false, false)).collect();
            parallel(parts, open_left, open_right)
        }
    }
}

fn series(parts: Vec<Blk>) -> Blk {
    let Some(h) = parts.iter().map(|b| b.rows.len()).max() else {
        return Blk::one(String::new());
    };
    let mut rows = vec![String::new(); h];
    for (k, b) in parts.iter().enumerate() {
        let w = b.width();
        for (r, row) in rows.iter_mut().enumerate() {
            if k > 0 {
                row.push_str(if r == 0 { "--" } else { "  " });
            }
            match b.rows.get(r) {
                Some(s) => row.push_str(s),
                None => row.push_str(&" ".repeat(w)),
            }
        }
    }
    let first = &parts[0];
    let last = &parts[parts.len() - 1];
    let lw = (0..h)
        .map(|r| first.lw.get(r).copied().unwrap_or(false))
        .collect();
    let rw = (0..h)
        .map(|r| last.rw.get(r).copied().unwrap_or(false))
        .collect();
    Blk { rows, lw, rw }
}

fn parallel(parts: Vec<Blk>, open_left: bool, open_right: bool) -> Blk {
    let w = parts.iter().map(Blk::width).max().unwrap_or(0);
    let n = parts.len();
    let mut rows = Vec::new();
    let mut lw = Vec::new();
    let mut rw = Vec::new();
    for (i, b) in parts.iter().enumerate() {
        let more = i + 1 < n;
        for (r, row) in b.rows.iter().enumerate() {
            let wire = r == 0;
            let fill = if wire { '-' } else { ' ' };
            let mut s = String::new();
            if !open_left {
                s.push(if wire {
                    '+'
                } else if more {
                    '|'
                } else {
                    ' '
                });
                s.push_str(if wire { "--" } else { "  " });
            }
            s.push_str(row);
            s.extend(std::iter::repeat_n(fill, w - width(row)));
            if !open_right {
                s.push_str(if wire { "--" } else { "  " });
                s.push(if wire {
                    '+'
                } else if more {
                    '|'
                } else {
                    ' '
                });
            }
            rows.push(s);
            lw.push(if open_left {
                wire && b.lw[r]
            } else {
                i == 0 && wire
            });
            rw.push(if open_right {
                wire && b.rw[r]
            } else {
                i == 0 && wire
            });
        }
    }
    Blk { rows, lw, rw }
}
