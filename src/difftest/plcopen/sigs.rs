//! The blocks the PLCopen generator uses: their pins and types.

use super::Ty;

/// The type of a pin: a fixed type, or the function's one type.
#[derive(Copy, Clone, Debug, PartialEq)]
pub(super) enum P {
    /// This type.
    T(Ty),
    /// The function's type.
    X,
}

/// A block type: its inputs and outputs, the types its `X` may be.
#[derive(Clone, Debug)]
pub(super) struct Sig {
    pub(super) name: String,
    pub(super) fb: bool,
    pub(super) ins: Vec<(String, P)>,
    pub(super) outs: Vec<(String, P)>,
    pub(super) types: Vec<Ty>,
    /// Inputs may be added (IN3...).
    pub(super) extensible: bool,
}

const B: P = P::T(Ty::Bool);
const NUM: &[Ty] = &[Ty::Int, Ty::Dint, Ty::Real];

fn sig(name: &str, fb: bool, ins: &[(&str, P)], outs: &[(&str, P)], types: &[Ty]) -> Sig {
    Sig {
        name: name.into(),
        fb,
        ins: ins.iter().map(|(n, p)| (n.to_string(), *p)).collect(),
        outs: outs.iter().map(|(n, p)| (n.to_string(), *p)).collect(),
        types: types.to_vec(),
        extensible: false,
    }
}

/// The standard blocks the generator uses.
pub(super) fn library() -> Vec<Sig> {
    let x2 = [("IN1", P::X), ("IN2", P::X)];
    let out = [("OUT", P::X)];
    let mut v = Vec::new();
    for f in ["ADD", "MUL", "MAX", "MIN"] {
        let mut s = sig(f, false, &x2, &out, NUM);
        s.extensible = true;
        v.push(s);
    }
    for f in ["SUB", "DIV"] {
        v.push(sig(f, false, &x2, &out, NUM));
    }
    v.push(sig("MOD", false, &x2, &out, &[Ty::Int, Ty::Dint]));
    for f in ["AND", "OR", "XOR"] {
        let mut s = sig(f, false, &x2, &out, &[Ty::Bool]);
        s.extensible = true;
        v.push(s);
    }
    v.push(sig("NOT", false, &[("IN", P::X)], &out, &[Ty::Bool]));
    for f in ["GT", "GE", "EQ", "NE", "LT", "LE"] {
        v.push(sig(f, false, &x2, &[("OUT", B)], NUM));
    }
    let all = [Ty::Bool, Ty::Int, Ty::Dint, Ty::Real];
    v.push(sig(
        "SEL",
        false,
        &[("G", B), ("IN0", P::X), ("IN1", P::X)],
        &out,
        &all,
    ));
    v.push(sig(
        "LIMIT",
        false,
        &[("MN", P::X), ("IN", P::X), ("MX", P::X)],
        &out,
        NUM,
    ));
    v.push(sig("MOVE", false, &[("IN", P::X)], &out, &all));
    v.push(sig("ABS", false, &[("IN", P::X)], &out, NUM));
    for (from, to) in [
        (Ty::Int, Ty::Dint),
        (Ty::Dint, Ty::Int),
        (Ty::Int, Ty::Real),
        (Ty::Real, Ty::Int),
        (Ty::Dint, Ty::Real),
        (Ty::Bool, Ty::Int),
        (Ty::Int, Ty::Bool),
        (Ty::Time, Ty::Dint),
        (Ty::Dint, Ty::Time),
    ] {
        let name = format!("{}_TO_{}", from.name(), to.name());
        v.push(sig(
            &name,
            false,
            &[("IN", P::T(from))],
            &[("OUT", P::T(to))],
            &[from],
        ));
    }
    let time = P::T(Ty::Time);
    let int = P::T(Ty::Int);
    for f in ["TON", "TOF", "TP"] {
        v.push(sig(
            f,
            true,
            &[("IN", B), ("PT", time)],
            &[("Q", B), ("ET", time)],
            &[Ty::Bool],
        ));
    }
    v.push(sig(
        "CTU",
        true,
        &[("CU", B), ("R", B), ("PV", int)],
        &[("Q", B), ("CV", int)],
        &[Ty::Bool],
    ));
    v.push(sig(
        "CTD",
        true,
        &[("CD", B), ("LD", B), ("PV", int)],
        &[("Q", B), ("CV", int)],
        &[Ty::Bool],
    ));
    v.push(sig(
        "CTUD",
        true,
        &[("CU", B), ("CD", B), ("R", B), ("LD", B), ("PV", int)],
        &[("QU", B), ("QD", B), ("CV", int)],
        &[Ty::Bool],
    ));
    for f in ["R_TRIG", "F_TRIG"] {
        v.push(sig(f, true, &[("CLK", B)], &[("Q", B)], &[Ty::Bool]));
    }
    v.push(sig(
        "SR",
        true,
        &[("S1", B), ("R", B)],
        &[("Q1", B)],
        &[Ty::Bool],
    ));
    v.push(sig(
        "RS",
        true,
        &[("S", B), ("R1", B)],
        &[("Q1", B)],
        &[Ty::Bool],
    ));
    v
}

/// The functions whose result has the type of their inputs: one input must be
/// wired from a source whose type plcc can tell.
pub(super) fn passes_type(s: &Sig) -> bool {
    !s.fb && s.outs.iter().any(|(_, p)| *p == P::X)
}
