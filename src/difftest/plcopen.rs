//! Random PLCopen XML programs: a model of a TC6 2.01 project with LD and FBD bodies
//! (`plcopen/gen.rs` builds it at random, `plcopen/xml.rs` prints it), what a
//! program shows of the features of graphical bodies ([`features`]), and when the
//! editors' profiles must give it the standard's meaning ([`profiles_agree`]).
//!
//! A program is a PROGRAM `main` with BOOL, INT, DINT, sometimes REAL and TIME
//! variables (VAR_INPUTs the runner sets before each scan, VAR_OUTPUTs and VARs with
//! initial values) and an LD or an FBD body of random networks, and sometimes a
//! FUNCTION_BLOCK `helper` in the other language, instantiated in `main`'s diagram.
//! Everything generated is valid: power flow and BOOL pins carry BOOL, arithmetic
//! pins their function's one type, every function whose result type follows its
//! inputs has one input wired from something whose type is told (a variable, a typed
//! literal, a block output), and every loop goes through a block (wires go from an
//! element to a later one, except the feedback wires, which enter a block).

pub mod gen;
pub mod shrink;
mod sigs;
pub mod twin;
pub mod xml;

use super::gen::Rng;
use super::{Finding, Verdict};
use crate::driver::BuildOptions;
use plcc_frontend::plcopen::{Options, Profile};
use plcc_ir::Module;
use std::collections::{BTreeMap, BTreeSet};

/// The name of the FUNCTION_BLOCK with a graphical body that `main` may call.
pub const SUB_FB: &str = "helper";

/// The elementary types of the variables and wires.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Ty {
    /// BOOL
    Bool,
    /// INT
    Int,
    /// DINT
    Dint,
    /// REAL
    Real,
    /// TIME
    Time,
}

impl Ty {
    /// The IEC name.
    pub fn name(self) -> &'static str {
        match self {
            Ty::Bool => "BOOL",
            Ty::Int => "INT",
            Ty::Dint => "DINT",
            Ty::Real => "REAL",
            Ty::Time => "TIME",
        }
    }

    /// The ST generator's type, for random input values.
    pub fn t(self) -> super::gen::T {
        use super::gen::T;
        match self {
            Ty::Bool => T::Bool,
            Ty::Int => T::Int,
            Ty::Dint => T::Dint,
            Ty::Real => T::Real,
            Ty::Time => T::Time,
        }
    }
}

/// Where a variable is declared.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum Class {
    /// VAR_INPUT: set by the runner (in `main`) or by the caller (in `helper`).
    Input,
    /// VAR_OUTPUT.
    Output,
    /// VAR.
    Local,
}

/// The type of a variable: elementary, or a function block (an instance).
#[derive(Clone, Debug, PartialEq)]
pub enum VarTy {
    /// An elementary type.
    Elem(Ty),
    /// An instance of a function block (`TON`, `helper`).
    Fb(String),
}

/// A declared variable.
#[derive(Clone, Debug, PartialEq)]
pub struct Var {
    /// Its name.
    pub name: String,
    /// Its type.
    pub ty: VarTy,
    /// Its section.
    pub class: Class,
    /// Its initial value (IEC literal text).
    pub init: Option<String>,
}

/// An edge modifier.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum Edge {
    /// None.
    None,
    /// `edge="rising"`.
    Rising,
    /// `edge="falling"`.
    Falling,
}

/// A coil's storage.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum Storage {
    /// A plain coil.
    None,
    /// `storage="set"`.
    Set,
    /// `storage="reset"`.
    Reset,
}

/// A connection: the element it comes from and, for a block, its output.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Wire {
    /// The `localId` of the source.
    pub from: u64,
    /// The block output (`formalParameter`).
    pub pin: Option<String>,
}

/// A pin of a block, with its modifiers and, for an input, its connections.
#[derive(Clone, Debug, PartialEq)]
pub struct Pin {
    /// The formal parameter.
    pub name: String,
    /// Its type (the function's one type resolved).
    pub ty: Ty,
    /// `negated="true"`.
    pub negated: bool,
    /// The edge modifier.
    pub edge: Edge,
    /// The connections (inputs only; empty: unwired).
    pub wires: Vec<Wire>,
}

/// What an element is.
#[derive(Clone, Debug, PartialEq)]
pub enum Kind {
    /// A left power rail.
    LeftRail,
    /// A right power rail, with the coils it is connected to.
    RightRail {
        /// The connections.
        wires: Vec<Wire>,
    },
    /// A contact.
    Contact {
        /// The variable.
        var: String,
        /// Normally closed.
        negated: bool,
        /// Edge.
        edge: Edge,
        /// The connections on its left.
        wires: Vec<Wire>,
    },
    /// A coil.
    Coil {
        /// The variable.
        var: String,
        /// Negated coil.
        negated: bool,
        /// Set or reset.
        storage: Storage,
        /// Edge.
        edge: Edge,
        /// The connections on its left.
        wires: Vec<Wire>,
    },
    /// A function or function block.
    Block {
        /// The type.
        ty: String,
        /// The instance (function blocks).
        instance: Option<String>,
        /// The inputs, EN first when it has one.
        inputs: Vec<Pin>,
        /// The outputs, ENO first when it has one.
        outputs: Vec<Pin>,
    },
    /// An input variable (a variable or a literal).
    InVar {
        /// The expression.
        expr: String,
        /// Negated.
        negated: bool,
    },
    /// An output variable.
    OutVar {
        /// The variable.
        expr: String,
        /// Negated.
        negated: bool,
        /// The connection.
        wires: Vec<Wire>,
    },
    /// A connector.
    Connector {
        /// Its name.
        name: String,
        /// Its connection.
        wires: Vec<Wire>,
    },
    /// A continuation of the connector of the same name.
    Continuation {
        /// The name.
        name: String,
    },
    /// A jump.
    Jump {
        /// The label.
        label: String,
        /// The connections.
        wires: Vec<Wire>,
    },
    /// A label.
    Label {
        /// The label.
        label: String,
    },
    /// A return.
    Return {
        /// The connections.
        wires: Vec<Wire>,
    },
}

impl Kind {
    /// Every connection of the element.
    pub fn wires(&self) -> Vec<&Wire> {
        match self {
            Kind::RightRail { wires }
            | Kind::Contact { wires, .. }
            | Kind::Coil { wires, .. }
            | Kind::OutVar { wires, .. }
            | Kind::Connector { wires, .. }
            | Kind::Jump { wires, .. }
            | Kind::Return { wires } => wires.iter().collect(),
            Kind::Block { inputs, .. } => inputs.iter().flat_map(|p| &p.wires).collect(),
            _ => Vec::new(),
        }
    }

    /// Every list of connections of the element (a block: one per input).
    pub fn wire_lists_mut(&mut self) -> Vec<&mut Vec<Wire>> {
        match self {
            Kind::RightRail { wires }
            | Kind::Contact { wires, .. }
            | Kind::Coil { wires, .. }
            | Kind::OutVar { wires, .. }
            | Kind::Connector { wires, .. }
            | Kind::Jump { wires, .. }
            | Kind::Return { wires } => vec![wires],
            Kind::Block { inputs, .. } => inputs.iter_mut().map(|p| &mut p.wires).collect(),
            _ => Vec::new(),
        }
    }
}

/// An element of a body.
#[derive(Clone, Debug, PartialEq)]
pub struct Elem {
    /// Its `localId`.
    pub id: u64,
    /// What it is.
    pub kind: Kind,
    /// Its position (all zero in a body without positions).
    pub pos: (i64, i64),
    /// Its `executionOrderId`.
    pub order: Option<u32>,
}

/// A POU with a graphical body.
#[derive(Clone, Debug, PartialEq)]
pub struct Pou {
    /// Its name.
    pub name: String,
    /// A FUNCTION_BLOCK (else a PROGRAM).
    pub fb: bool,
    /// An LD body (else FBD).
    pub ld: bool,
    /// Its variables.
    pub vars: Vec<Var>,
    /// Its body, in document order.
    pub elems: Vec<Elem>,
    /// The body gives real positions (else every position is 0, 0: document order).
    pub positions: bool,
}

/// A generated project: the POUs, `main` last.
#[derive(Clone, Debug, PartialEq)]
pub struct XmlProg {
    /// The POUs: maybe the FUNCTION_BLOCK `helper`, then the PROGRAM `main`.
    pub pous: Vec<Pou>,
}

impl XmlProg {
    /// The PROGRAM.
    pub fn main(&self) -> &Pou {
        self.pous.last().expect("main")
    }

    /// The variables the runner sets before every scan: `main`'s VAR_INPUTs.
    pub fn input_paths(&self) -> Vec<(String, super::gen::T)> {
        self.main()
            .vars
            .iter()
            .filter(|v| v.class == Class::Input)
            .filter_map(|v| match v.ty {
                VarTy::Elem(t) => Some((format!("main.{}", v.name), t.t())),
                VarTy::Fb(_) => None,
            })
            .collect()
    }

    /// The project as PLCopen TC6 2.01 XML.
    pub fn to_xml(&self) -> String {
        xml::print(self)
    }
}

/// The first name of an expression (`ton0` of `ton0.Q`), upper-case; empty for a
/// literal.
fn root(expr: &str) -> String {
    let first = expr.split(['.', '[']).next().unwrap_or("").trim();
    let literal = first.is_empty()
        || first.contains('#')
        || first.as_bytes()[0].is_ascii_digit()
        || first.starts_with('-')
        || first.eq_ignore_ascii_case("TRUE")
        || first.eq_ignore_ascii_case("FALSE");
    if literal {
        String::new()
    } else {
        first.to_ascii_uppercase()
    }
}

/// The elements of a body by `localId`, and for each the elements wired from it.
struct Index<'a> {
    by_id: BTreeMap<u64, &'a Elem>,
    /// For each `localId`, the (consumer, connection) pairs reading it, a
    /// continuation standing for its connector.
    users: BTreeMap<u64, Vec<(u64, Option<String>)>>,
}

impl<'a> Index<'a> {
    fn new(p: &'a Pou) -> Index<'a> {
        let by_id: BTreeMap<u64, &Elem> = p.elems.iter().map(|e| (e.id, e)).collect();
        let mut users: BTreeMap<u64, Vec<(u64, Option<String>)>> = BTreeMap::new();
        for e in &p.elems {
            for w in e.kind.wires() {
                for src in resolve(p, w.from) {
                    users.entry(src).or_default().push((e.id, w.pin.clone()));
                }
            }
        }
        Index { by_id, users }
    }

    fn kind(&self, id: u64) -> Option<&'a Kind> {
        self.by_id.get(&id).map(|e| &e.kind)
    }
}

/// What a connection from `id` stands for: the element itself, or for a
/// continuation what is wired to its connector (through any chain of them).
fn resolve(p: &Pou, id: u64) -> Vec<u64> {
    fn walk(p: &Pou, id: u64, depth: u32, out: &mut Vec<u64>) {
        let Some(e) = p.elems.iter().find(|e| e.id == id) else {
            return;
        };
        match &e.kind {
            Kind::Continuation { name } if depth < 16 => {
                for c in &p.elems {
                    if let Kind::Connector { name: n, wires } = &c.kind {
                        if n == name {
                            for w in wires {
                                walk(p, w.from, depth + 1, out);
                            }
                        }
                    }
                }
            }
            Kind::Continuation { .. } => {}
            _ => out.push(id),
        }
    }
    let mut out = Vec::new();
    walk(p, id, 0, &mut out);
    out
}

/// The networks of a body as plcc finds them: the elements wired to each other (the
/// rails join nothing; a continuation joins its connector), by `localId`, in
/// document order.
pub fn networks(p: &Pou) -> Vec<Vec<u64>> {
    let n = p.elems.len();
    let mut parent: Vec<usize> = (0..n).collect();
    fn find(p: &mut [usize], mut x: usize) -> usize {
        while p[x] != x {
            p[x] = p[p[x]];
            x = p[x];
        }
        x
    }
    let rail = |k: &Kind| matches!(k, Kind::LeftRail | Kind::RightRail { .. });
    let at: BTreeMap<u64, usize> = p.elems.iter().enumerate().map(|(i, e)| (e.id, i)).collect();
    for (i, e) in p.elems.iter().enumerate() {
        if rail(&e.kind) {
            continue;
        }
        let mut joins: Vec<usize> = e
            .kind
            .wires()
            .iter()
            .filter_map(|w| at.get(&w.from).copied())
            .filter(|&j| !rail(&p.elems[j].kind))
            .collect();
        if let Kind::Continuation { name } = &e.kind {
            joins.extend(
                p.elems
                    .iter()
                    .enumerate()
                    .filter_map(|(j, c)| match &c.kind {
                        Kind::Connector { name: m, .. } if m == name => Some(j),
                        _ => None,
                    }),
            );
        }
        for j in joins {
            let (a, b) = (find(&mut parent, i), find(&mut parent, j));
            parent[a] = b;
        }
    }
    let mut groups: BTreeMap<usize, Vec<u64>> = BTreeMap::new();
    let mut first: Vec<usize> = Vec::new();
    for (i, e) in p.elems.iter().enumerate() {
        if rail(&e.kind) {
            continue;
        }
        let r = find(&mut parent, i);
        if !groups.contains_key(&r) {
            first.push(r);
        }
        groups.entry(r).or_default().push(e.id);
    }
    first
        .into_iter()
        .map(|r| groups.remove(&r).unwrap_or_default())
        .collect()
}

/// True if a loop of `p` goes through a block: an element reaches itself.
fn loops(p: &Pou) -> (bool, bool) {
    let ix = Index::new(p);
    let reach = |from: u64, to: u64| {
        let mut seen = BTreeSet::new();
        let mut todo = vec![from];
        while let Some(x) = todo.pop() {
            for (u, _) in ix.users.get(&x).into_iter().flatten() {
                if *u == to {
                    return true;
                }
                if seen.insert(*u) {
                    todo.push(*u);
                }
            }
        }
        false
    };
    let (mut own, mut through) = (false, false);
    for e in &p.elems {
        if let Kind::Block { inputs, .. } = &e.kind {
            for w in inputs.iter().flat_map(|p| &p.wires) {
                for src in resolve(p, w.from) {
                    if src == e.id {
                        own = true;
                    } else if reach(e.id, src) {
                        through = true;
                    }
                }
            }
        }
    }
    (own, through)
}

/// The features of graphical bodies a program shows, by name (the test of the
/// generator counts them over many seeds).
pub fn features(prog: &XmlProg) -> BTreeSet<String> {
    let mut f = BTreeSet::new();
    let mut add = |s: &str| {
        f.insert(s.to_string());
    };
    if prog.pous.len() > 1 {
        add("user FB with a graphical body");
    }
    for p in &prog.pous {
        let ix = Index::new(p);
        add(if p.ld { "LD body" } else { "FBD body" });
        if p.positions {
            add("positions");
        }
        if p.vars.iter().any(|v| v.ty == VarTy::Elem(Ty::Real)) {
            add("REAL variable");
        }
        let (own, through) = loops(p);
        if own {
            add("feedback into the same block");
        }
        if through {
            add("feedback through a later block");
        }
        let users = |id: u64| ix.users.get(&id).map_or(0, |u| u.len());
        let src_kind = |w: &Wire| resolve(p, w.from).into_iter().filter_map(|s| ix.kind(s));
        for e in &p.elems {
            if e.order.is_some() {
                add("executionOrderId");
            }
            let from_rail = e.kind.wires().len() == 1
                && e.kind
                    .wires()
                    .iter()
                    .all(|w| src_kind(w).all(|k| matches!(k, Kind::LeftRail)));
            match &e.kind {
                Kind::Contact {
                    negated,
                    edge,
                    wires,
                    ..
                } => {
                    add(match (negated, edge) {
                        (true, _) => "negated contact",
                        (_, Edge::Rising) => "rising contact",
                        (_, Edge::Falling) => "falling contact",
                        _ => "contact",
                    });
                    if wires.len() > 1 {
                        add("parallel branches joined");
                        if users(e.id) > 1 {
                            add("bridge: a contact with several sources and sinks");
                        }
                    }
                    if wires
                        .iter()
                        .any(|w| src_kind(w).any(|k| matches!(k, Kind::Contact { .. })))
                    {
                        add("contacts in series");
                    }
                    if users(e.id) > 1 {
                        add("a contact feeding several elements");
                    }
                }
                Kind::Coil {
                    negated,
                    storage,
                    edge,
                    wires,
                    ..
                } => {
                    add(match (negated, storage, edge) {
                        (true, _, _) => "negated coil",
                        (_, Storage::Set, _) => "set coil",
                        (_, Storage::Reset, _) => "reset coil",
                        (_, _, Edge::Rising) => "rising coil",
                        (_, _, Edge::Falling) => "falling coil",
                        _ => "coil",
                    });
                    if from_rail {
                        add("coil on the left rail");
                    }
                    if wires
                        .iter()
                        .any(|w| src_kind(w).any(|k| matches!(k, Kind::Coil { .. })))
                    {
                        add("coils in series");
                    }
                    if wires.len() > 1 {
                        add("coil with several wires");
                    }
                }
                Kind::Block {
                    ty,
                    instance,
                    inputs,
                    outputs,
                } => {
                    add(&format!("block {ty}"));
                    let en = inputs.first().filter(|p| p.name == "EN");
                    match en {
                        Some(p) if p.wires.is_empty() => add("EN unwired"),
                        Some(_) => add("EN wired"),
                        None => add("block without EN"),
                    }
                    if outputs.first().is_some_and(|p| p.name == "ENO")
                        && ix
                            .users
                            .get(&e.id)
                            .is_some_and(|u| u.iter().any(|(_, pin)| pin.as_deref() == Some("ENO")))
                    {
                        add("ENO wired");
                    }
                    if inputs.iter().any(|p| p.name == "IN3") {
                        add("extensible inputs");
                    }
                    for pin in inputs.iter().chain(outputs) {
                        if pin.negated {
                            add("negated pin");
                        }
                        if pin.edge != Edge::None {
                            add("edge pin");
                        }
                    }
                    if instance.is_none()
                        && inputs.iter().any(|p| p.name != "EN" && p.wires.is_empty())
                    {
                        add("unwired function input");
                    }
                    if instance.is_some() && inputs.iter().skip(1).any(|p| p.wires.is_empty()) {
                        add("unwired FB input");
                    }
                }
                Kind::InVar { negated, .. } | Kind::OutVar { negated, .. } if *negated => {
                    add("negated variable")
                }
                Kind::Connector { .. } => add("connector and continuation"),
                Kind::Jump { .. } => add("jump"),
                Kind::Label { .. } => add("label"),
                Kind::Return { .. } => add("return"),
                Kind::RightRail { .. } => add("right rail"),
                _ => {}
            }
        }
        let rails = p
            .elems
            .iter()
            .filter(|e| matches!(e.kind, Kind::LeftRail))
            .count();
        if rails > 1 {
            add("several left rails");
        }
    }
    f
}

/// True if every profile must give `prog` the same meaning (docs/plcopen.md, "The
/// editors' orders"): no jump, label or return; no negated variable; no
/// `executionOrderId`; no loop; no coil with several wires that feeds a later
/// element; no variable wired to an ENO; and no variable both read and written by the body, nor written twice
/// (an FB instance is written by its call), so that the order of the statements
/// and the number of times a contact's variable is read do not matter.
pub fn profiles_agree(prog: &XmlProg) -> bool {
    prog.pous.iter().all(|p| {
        let ix = Index::new(p);
        // Something but a right rail reads it.
        let fed = |id: u64| {
            ix.users.get(&id).is_some_and(|u| {
                u.iter()
                    .any(|(c, _)| !matches!(ix.kind(*c), Some(Kind::RightRail { .. })))
            })
        };
        let (own, through) = loops(p);
        if own || through {
            return false;
        }
        let mut reads = BTreeSet::new();
        let mut writes: Vec<String> = Vec::new();
        for e in &p.elems {
            if e.order.is_some() {
                return false;
            }
            match &e.kind {
                Kind::Jump { .. } | Kind::Label { .. } | Kind::Return { .. } => return false,
                Kind::InVar { negated: true, .. } | Kind::OutVar { negated: true, .. } => {
                    return false
                }
                Kind::Coil { wires, .. } if wires.len() > 1 && fed(e.id) => return false,
                // The editors write a variable on an ENO only when ENO is TRUE (the
                // ENO may come through a connector).
                Kind::OutVar { wires, .. } | Kind::Connector { wires, .. }
                    if wires.iter().any(|w| {
                        w.pin
                            .as_deref()
                            .is_some_and(|p| p.eq_ignore_ascii_case("ENO"))
                    }) =>
                {
                    return false
                }
                _ => {}
            }
            match &e.kind {
                Kind::Contact { var, .. } | Kind::InVar { expr: var, .. } => {
                    reads.insert(root(var));
                }
                Kind::Coil { var, .. } | Kind::OutVar { expr: var, .. } => {
                    writes.push(root(var));
                }
                Kind::Block {
                    instance: Some(i), ..
                } => writes.push(root(i)),
                _ => {}
            }
        }
        let distinct: BTreeSet<&String> = writes.iter().collect();
        distinct.len() == writes.len() && !writes.iter().any(|w| reads.contains(w))
    })
}

/// The PLCopen program of a seed (not the ST program of the same seed), steering
/// around the front-end bugs known so far ([`gen::KNOWN_BUGS`]).
pub fn program(seed: u64) -> XmlProg {
    program_with(seed, false)
}

/// The PLCopen program of a seed; `known_bugs`: also with the constructs of the
/// known front-end bugs.
pub fn program_with(seed: u64, known_bugs: bool) -> XmlProg {
    let mut rng = Rng::new(seed ^ 0x91C0_9E4D_1AD0_F8D1);
    gen::program(&mut rng, !known_bugs)
}

/// Compiles a program under a profile.
pub fn compile(p: &XmlProg, profile: Profile) -> Result<Module, String> {
    let opts = BuildOptions {
        plcopen: Options {
            profile,
            strict_rungs: false,
        },
        ..BuildOptions::default()
    };
    super::build_text("difftest.xml", &p.to_xml(), &opts)
}

/// Runs `p` (the standard's meaning, profile `iec`) on `machines` for `scans`
/// scans, as [`super::check`] runs an ST program.
pub fn check(p: &XmlProg, machines: &[&str], scans: u32, seed: u64) -> Verdict {
    match compile(p, Profile::Iec) {
        Ok(m) => super::check_module(&m, &p.input_paths(), machines, scans, seed),
        Err(e) => Verdict::Rejected(e),
    }
}

/// The profiles compared with `iec` when they must agree ([`profiles_agree`]).
pub const PROFILES: [Profile; 4] = [
    Profile::Xml2st,
    Profile::Openplc3,
    Profile::Beremiz,
    Profile::Legacy,
];

/// The paths of the variables the program declares (not the hidden ones the
/// lowering adds, which differ between profiles): `main.x0`, `main.ton1.ET`,
/// `main.helper0.i3`.
fn declared_paths(p: &XmlProg, module: &Module) -> Vec<String> {
    let declared = |pou: &Pou, name: &str| pou.vars.iter().find(|v| v.name == name).cloned();
    let sub = p.pous.iter().find(|q| q.fb);
    module
        .programs
        .iter()
        .flat_map(|e| plcc_ir::vars::variables(module, e.data))
        .map(|v| v.path)
        .filter(|path| {
            let seg: Vec<&str> = path.split('.').collect();
            match seg.get(1).and_then(|n| declared(p.main(), n)) {
                Some(Var {
                    ty: VarTy::Fb(t), ..
                }) if t == SUB_FB => sub
                    .zip(seg.get(2))
                    .is_some_and(|(s, n)| declared(s, n).is_some()),
                Some(_) => true,
                None => false,
            }
        })
        .collect()
}

/// Runs `p` under every profile side by side on `machine` (profile `iec` the
/// reference), comparing the variables it declares after every scan. Only
/// meaningful when [`profiles_agree`] holds.
pub fn check_profiles(p: &XmlProg, machine: &str, scans: u32, seed: u64) -> Verdict {
    let name = super::machine_for_seed(machine, seed);
    let mut ms = Vec::new();
    let mut vars = Vec::new();
    for profile in std::iter::once(Profile::Iec).chain(PROFILES) {
        let module = match compile(p, profile) {
            Ok(m) => m,
            Err(e) => return Verdict::Rejected(format!("profile {}: {e}", profile.name())),
        };
        if vars.is_empty() {
            vars = declared_paths(p, &module);
        }
        match super::machine(&name, &module) {
            Ok(Some(m)) => ms.push((format!("{name} ({})", profile.name()), m)),
            Ok(None) => return Verdict::Agree { machines: 0 },
            Err(e) => return Verdict::Mismatch(e),
        }
    }
    super::run(ms, &vars, &p.input_paths(), scans, seed)
}

/// Runs `p` and its twin ([`twin::twin`]: its diagrams written as ST by the
/// documented rules) side by side on `machine`, comparing the variables it declares
/// after every scan; `None` when the rules do not fix the program's meaning (or,
/// without `known_bugs`, where plcc is known to differ from them).
pub fn check_twin(
    p: &XmlProg,
    machine: &str,
    scans: u32,
    seed: u64,
    known_bugs: bool,
) -> Option<Verdict> {
    let st = twin::twin(p, !known_bugs)?;
    compare_twin(p, &st, machine, scans, seed)
}

/// Runs `p` beside the ST program `twin` on `machine` (see [`check_twin`]);
/// `None` if the machine cannot hold them.
pub fn compare_twin(
    p: &XmlProg,
    twin: &str,
    machine: &str,
    scans: u32,
    seed: u64,
) -> Option<Verdict> {
    let name = super::machine_for_seed(machine, seed);
    let xml = match compile(p, Profile::Iec) {
        Ok(m) => m,
        Err(e) => return Some(Verdict::Rejected(e)),
    };
    let tw = match super::build_text("twin.st", twin, &BuildOptions::default()) {
        Ok(m) => m,
        Err(e) => return Some(Verdict::Rejected(format!("the twin: {e}"))),
    };
    let vars = declared_paths(p, &xml);
    let mut ms = Vec::new();
    for (what, m) in [("xml", &xml), ("twin", &tw)] {
        match super::machine(&name, m) {
            Ok(Some(m)) => ms.push((format!("{name} ({what})"), m)),
            Ok(None) => return None,
            Err(e) => return Some(Verdict::Mismatch(e)),
        }
    }
    Some(super::run(ms, &vars, &p.input_paths(), scans, seed))
}

/// Which comparison showed a finding.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum Stage {
    /// The machines ([`check`]).
    Machines,
    /// The program and its twin ([`check_twin`]).
    Twin,
    /// The profiles ([`check_profiles`]).
    Profiles,
}

/// Every comparison of a program, in turn: the machines, the twin on the first
/// machine, the profiles on the first machine when they must agree; the first that
/// does not agree, or the machines' agreement.
pub fn check_all(
    p: &XmlProg,
    machines: &[&str],
    scans: u32,
    seed: u64,
    known_bugs: bool,
) -> (Verdict, Stage) {
    let agree = check(p, machines, scans, seed);
    if !matches!(agree, Verdict::Agree { .. }) {
        return (agree, Stage::Machines);
    }
    if let Some(v) = check_twin(p, machines[0], scans, seed, known_bugs) {
        if !matches!(v, Verdict::Agree { .. }) {
            return (v, Stage::Twin);
        }
    }
    if profiles_agree(p) {
        let v = check_profiles(p, machines[0], scans, seed);
        if !matches!(v, Verdict::Agree { .. }) {
            return (v, Stage::Profiles);
        }
    }
    (agree, Stage::Machines)
}

/// Checks the PLCopen program of seed `seed` ([`program_with`]) by every
/// comparison ([`check_all`]); on a finding, shrinks it ([`shrink::shrink`]) to a
/// reproducer in XML that the same comparison finds.
pub fn run_seed(seed: u64, machines: &[&str], scans: u32, known_bugs: bool) -> Option<Finding> {
    let p = program_with(seed, known_bugs);
    let both = |q: &XmlProg| check_all(q, machines, scans, seed, known_bugs);
    let (verdict, stage) = both(&p);
    if matches!(verdict, Verdict::Agree { .. }) {
        return None;
    }
    let want = super::codes(&verdict);
    let mismatch = matches!(verdict, Verdict::Mismatch(_));
    let small = shrink::shrink(
        &p,
        &mut |q| {
            let (v, st) = both(q);
            st == stage
                && if mismatch {
                    matches!(v, Verdict::Mismatch(_))
                } else {
                    matches!(v, Verdict::Rejected(_)) && super::codes(&v) == want
                }
        },
        1500,
    );
    let (verdict, _) = both(&small);
    let mut reproducer = small.to_xml();
    if stage == Stage::Twin {
        if let Some(t) = twin::twin(&small, !known_bugs) {
            reproducer.push_str(&format!(
                "<!-- {verdict:?}\n\nThe twin (the documented meaning, as ST):\n\n{}-->\n",
                t.replace("--", "- -")
            ));
        }
    }
    Some(Finding {
        seed,
        verdict,
        reproducer,
        ext: "xml",
    })
}
