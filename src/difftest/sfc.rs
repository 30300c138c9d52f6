//! Random sequential function charts (`plcc difftest --lang sfc`): PROGRAM `main`
//! (and sometimes a FUNCTION_BLOCK `SfcFb`, instantiated once or twice and called
//! from `main`'s actions) with a textual SFC body: steps, transitions between them
//! (selective and simultaneous divergence and convergence, self loops, jumps, some
//! with PRIORITY), actions whose bodies are random ST statements of the ST
//! generator ([`super::gen`]), associations with every qualifier, BOOL variables
//! as actions. The generator is `sfc/gen.rs`, the shrinker `sfc/shrink.rs`.
//!
//! Each program is built under each of the three SFC profiles (`--sfc iec`,
//! `matiec`, `codesys`) and every build runs on every machine, every variable
//! (the step and action variables among them) compared with the reference after
//! every scan, as [`super::check_module`] does.

pub mod gen;
pub mod shrink;

use super::gen::{Expr, Prog, Stmt, T};
use super::print::{expr_text, stmts_text};
use super::{build_text, check_module, Finding, Verdict};
use crate::driver::BuildOptions;
use plcc_frontend::sfc::Profile;
use std::fmt::Write;

/// The name of the FUNCTION_BLOCK with a chart that `main` may instantiate.
pub const FB: &str = "SfcFb";

/// The three profiles every program is built under, with their `--sfc` names.
pub const PROFILES: [(Profile, &str); 3] = [
    (Profile::Iec, "iec"),
    (Profile::Matiec, "matiec"),
    (Profile::Codesys, "codesys"),
];

/// The action qualifiers; the timed ones take a duration.
pub const QUALIFIERS: [&str; 11] = ["N", "R", "S", "L", "D", "P", "P1", "P0", "SD", "DS", "SL"];

/// CODESYS's step actions, as plcc writes them (pseudo-qualifiers of actions).
pub const STEP_ACTIONS: [&str; 3] = ["ENTRY", "ACTIVE", "EXIT"];

/// A qualifier that takes a duration (L, D, SD, DS, SL).
pub fn timed(q: &str) -> bool {
    matches!(q, "L" | "D" | "SD" | "DS" | "SL")
}

/// An association of a step with an action or a BOOL variable: `A(q[, T#..ms]);`.
#[derive(Clone, Debug, PartialEq)]
pub struct Assoc {
    /// The action or BOOL variable.
    pub target: String,
    /// The qualifier.
    pub qual: &'static str,
    /// The duration in ms (timed qualifiers only).
    pub ms: Option<u32>,
}

/// A step and its associations.
#[derive(Clone, Debug, PartialEq)]
pub struct Step {
    /// Its name.
    pub name: String,
    /// An INITIAL_STEP.
    pub initial: bool,
    /// Its associations, in text order.
    pub assocs: Vec<Assoc>,
}

/// `TRANSITION [(PRIORITY := p)] FROM from TO to := cond; END_TRANSITION`.
#[derive(Clone, Debug, PartialEq)]
pub struct Transition {
    /// The priority, if any.
    pub priority: Option<u32>,
    /// The steps it leaves (several: a simultaneous convergence).
    pub from: Vec<String>,
    /// The steps it activates (several: a simultaneous divergence).
    pub to: Vec<String>,
    /// The condition, a BOOL expression.
    pub cond: Expr,
}

/// `ACTION name: body END_ACTION`.
#[derive(Clone, Debug, PartialEq)]
pub struct Action {
    /// Its name.
    pub name: String,
    /// Its statements.
    pub body: Vec<Stmt>,
    /// An action written as a chart (its steps and transitions; its associations
    /// name actions of the POU's chart, its own `actions` are empty): written in
    /// place of `body`.
    pub chart: Option<Chart>,
}

/// A chart: the body of a POU.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Chart {
    /// The steps, in text order.
    pub steps: Vec<Step>,
    /// The transitions, in text order.
    pub transitions: Vec<Transition>,
    /// The actions.
    pub actions: Vec<Action>,
}

/// A POU with a chart: its declarations (a [`Prog`] whose body is not used;
/// `main`'s also gives the POUs and types every program has) and its chart.
#[derive(Clone, Debug, PartialEq)]
pub struct ChartPou {
    /// The declarations, as the ST generator's program has them.
    pub decl: Prog,
    /// More BOOL variables of the POU, used as actions (`b0`, `b1`).
    pub bools: Vec<String>,
    /// The chart.
    pub chart: Chart,
}

/// A generated SFC program.
#[derive(Clone, Debug, PartialEq)]
pub struct SfcProg {
    /// PROGRAM `main`.
    pub main: ChartPou,
    /// The FUNCTION_BLOCK [`FB`], if any, and the names of its instances in `main`.
    pub fb: Option<(ChartPou, Vec<String>)>,
}

fn print_chart(c: &Chart, o: &mut String) {
    for s in &c.steps {
        let kw = if s.initial { "INITIAL_STEP" } else { "STEP" };
        let _ = write!(o, "{kw} {}:", s.name);
        for a in &s.assocs {
            match a.ms {
                Some(ms) => {
                    let _ = write!(o, " {}({}, T#{ms}ms);", a.target, a.qual);
                }
                None => {
                    let _ = write!(o, " {}({});", a.target, a.qual);
                }
            }
        }
        o.push_str(" END_STEP\n");
    }
    let list = |v: &[String]| {
        if v.len() == 1 {
            v[0].clone()
        } else {
            format!("({})", v.join(", "))
        }
    };
    for t in &c.transitions {
        o.push_str("TRANSITION ");
        if let Some(p) = t.priority {
            let _ = write!(o, "(PRIORITY := {p}) ");
        }
        let _ = writeln!(
            o,
            "FROM {} TO {} := {}; END_TRANSITION",
            list(&t.from),
            list(&t.to),
            expr_text(&t.cond)
        );
    }
    for a in &c.actions {
        let _ = writeln!(o, "ACTION {}:", a.name);
        match &a.chart {
            Some(inner) => print_chart(inner, o),
            None => o.push_str(&stmts_text(&a.body, 1)),
        }
        o.push_str("END_ACTION\n");
    }
}

impl ChartPou {
    /// The POU's text from its header's next line to its END: declarations, chart.
    fn text(&self, extra: &str) -> String {
        let mut chart = String::new();
        print_chart(&self.chart, &mut chart);
        let mut extra = extra.to_string();
        if !self.bools.is_empty() {
            let _ = writeln!(extra, "    {} : BOOL;", self.bools.join(", "));
        }
        let mut o = self.decl.decls(&chart, &extra);
        o.push_str(&chart);
        o
    }
}

impl SfcProg {
    /// The ST text: the ST generator's POUs and types, the FB with a chart, `main`.
    pub fn to_st(&self) -> String {
        let mut o = self.main.decl.prelude();
        let mut extra = String::new();
        if let Some((fb, instances)) = &self.fb {
            let _ = writeln!(o, "FUNCTION_BLOCK {FB}");
            o.push_str(&fb.text(""));
            o.push_str("END_FUNCTION_BLOCK\n\n");
            if !instances.is_empty() {
                let _ = writeln!(extra, "    {} : {FB};", instances.join(", "));
            }
        }
        o.push_str("PROGRAM main\n");
        o.push_str(&self.main.text(&extra));
        o.push_str("END_PROGRAM\n");
        o
    }

    /// The variables the runner sets before every scan: `main`'s VAR_INPUTs.
    pub fn input_paths(&self) -> Vec<(String, T)> {
        self.main.decl.input_paths()
    }
}

/// The program of a seed; `avoid`: steer around the [`gen::KNOWN_BUGS`].
/// Three charts in four that come out unsafe (E0784 under iec and codesys) are made
/// safe by turning their simultaneous divergences into single transitions (the
/// first step of each), so that the standard's profiles run most charts; the
/// rest stay unsafe, for matiec and for the refusal itself.
pub fn program_with(seed: u64, avoid: bool) -> SfcProg {
    let mut rng = super::gen::Rng::new(seed);
    let mut p = gen::program(&mut rng, avoid);
    if rng.chance(75) && is_unsafe_under_matiec(&p) {
        let charts =
            std::iter::once(&mut p.main.chart).chain(p.fb.as_mut().map(|f| &mut f.0.chart));
        for c in charts {
            for t in &mut c.transitions {
                t.to.truncate(1);
            }
        }
    }
    p
}

/// The program of a seed, steering around the known bugs.
pub fn program(seed: u64) -> SfcProg {
    program_with(seed, true)
}

/// Builds `p` under one profile.
pub fn compile(p: &SfcProg, profile: Profile) -> Result<plcc_ir::Module, String> {
    let opts = BuildOptions {
        sfc: profile,
        ..Default::default()
    };
    build_text("difftest.st", &p.to_st(), &opts)
}

/// Builds `p` under each profile and runs each build on `machines` (the first is
/// the reference) for `scans` scans. `Agree` counts the machine runs of all three
/// builds (a machine the program does not fit is not run).
pub fn check(p: &SfcProg, machines: &[&str], scans: u32, seed: u64) -> Verdict {
    check_under(p, &PROFILES, machines, scans, seed)
}

/// The code of an unsafe chart under `iec` and `codesys`.
const UNSAFE: &str = "E0784";

/// True if `p`'s matiec build warns that the chart is unsafe (W0782): the same
/// token game as the refusal, so a refusal without it is a finding.
pub fn is_unsafe_under_matiec(p: &SfcProg) -> bool {
    let opts = BuildOptions {
        sfc: Profile::Matiec,
        check_only: true,
        ..Default::default()
    };
    let files = vec![("difftest.st".to_string(), p.to_st().into_bytes())];
    crate::driver::build_sources(files, &opts)
        .is_ok_and(|b| b.diagnostics.iter().any(|d| d.code == "W0782"))
}

/// [`check`] under some of the profiles only (of [`PROFILES`]).
pub fn check_under(
    p: &SfcProg,
    profiles: &[(Profile, &str)],
    machines: &[&str],
    scans: u32,
    seed: u64,
) -> Verdict {
    let inputs = p.input_paths();
    let mut ran = 0;
    for &(profile, name) in profiles {
        let module = match compile(p, profile) {
            Ok(m) => m,
            // An unsafe chart: the standard's profiles refuse it (E0784), matiec
            // runs it (W0782); only the refusal of a safe chart is a finding.
            Err(e)
                if profile != Profile::Matiec
                    && e.contains(UNSAFE)
                    && is_unsafe_under_matiec(p) =>
            {
                continue;
            }
            Err(e) => return Verdict::Rejected(format!("--sfc {name}: {e}")),
        };
        match check_module(&module, &inputs, machines, scans, seed) {
            Verdict::Agree { machines } => ran += machines,
            Verdict::Mismatch(e) => return Verdict::Mismatch(format!("--sfc {name}: {e}")),
            Verdict::Rejected(e) => return Verdict::Rejected(format!("--sfc {name}: {e}")),
        }
    }
    Verdict::Agree { machines: ran }
}

/// The profile a verdict names (`--sfc matiec: …`), to shrink a finding to one of
/// the same profile.
fn profile_of(v: &Verdict) -> &str {
    let text = match v {
        Verdict::Mismatch(e) | Verdict::Rejected(e) => e.as_str(),
        Verdict::Agree { .. } => return "",
    };
    text.split(':').next().unwrap_or("")
}

/// Checks seed `seed`: the machine runs (of the three builds) when every machine
/// agreed, else the finding, shrunk to a program that fails the same way under
/// the same profile.
pub fn run_seed(seed: u64, machines: &[&str], scans: u32, avoid: bool) -> Result<usize, Finding> {
    let p = program_with(seed, avoid);
    let verdict = check(&p, machines, scans, seed);
    if let Verdict::Agree { machines } = verdict {
        return Ok(machines);
    }
    // A rejection shrinks to a program rejected with the same first message.
    let first = |v: &Verdict| match v {
        Verdict::Rejected(e) => e.split("; ").next().unwrap_or("").to_string(),
        _ => String::new(),
    };
    let want = first(&verdict);
    let profile = profile_of(&verdict).to_string();
    let mismatch = matches!(verdict, Verdict::Mismatch(_));
    let small = shrink::shrink(
        &p,
        &mut |q| {
            let v = check(q, machines, scans, seed);
            profile_of(&v) == profile
                && if mismatch {
                    matches!(v, Verdict::Mismatch(_))
                } else {
                    matches!(v, Verdict::Rejected(_)) && first(&v) == want
                }
        },
        1500,
    );
    let verdict = check(&small, machines, scans, seed);
    Err(Finding {
        seed,
        verdict,
        reproducer: small.to_st(),
        ext: "st",
    })
}

/// What a program shows of the features of charts, by name (`qualifier SD`,
/// `simultaneous divergence`, …), for the test that the generator reaches each.
pub fn features(p: &SfcProg) -> std::collections::BTreeSet<String> {
    let mut f = std::collections::BTreeSet::new();
    let mut pous = vec![&p.main];
    if let Some((fb, instances)) = &p.fb {
        f.insert("FB with a chart".to_string());
        if instances.len() > 1 {
            f.insert("FB instantiated twice".into());
        }
        pous.push(fb);
    }
    for pou in pous {
        let c = &pou.chart;
        if c.steps.iter().filter(|s| s.initial).count() > 1 {
            f.insert("two initial steps".into());
        }
        if c.actions.iter().any(|a| a.chart.is_some()) {
            f.insert("action written as a chart".into());
        }
        for (flag, _) in pou.decl.inputs.iter().filter(|v| v.0.starts_with("SFC")) {
            f.insert(format!("SFC flag {flag}"));
        }
        let inner = c.actions.iter().filter_map(|a| a.chart.as_ref());
        for s in c.steps.iter().chain(inner.flat_map(|i| &i.steps)) {
            for a in &s.assocs {
                f.insert(format!("qualifier {}", a.qual));
                if pou.bools.contains(&a.target) {
                    f.insert("BOOL variable as action".into());
                } else if !c.actions.iter().any(|x| x.name == a.target) {
                    f.insert("declared BOOL variable as action".into());
                }
            }
        }
        let index = |n: &String| c.steps.iter().position(|s| &s.name == n);
        for t in &c.transitions {
            if t.priority.is_some() {
                f.insert("PRIORITY".into());
            }
            if t.to.len() > 1 {
                f.insert("simultaneous divergence".into());
            }
            if t.from.len() > 1 {
                f.insert("simultaneous convergence".into());
            }
            if t.from.iter().any(|s| t.to.contains(s)) {
                f.insert("self loop".into());
            }
            if let ([a], [b]) = (&t.from[..], &t.to[..]) {
                if let (Some(i), Some(j)) = (index(a), index(b)) {
                    if j != i && j != (i + 1) % c.steps.len() {
                        f.insert("jump".into());
                    }
                }
            }
            let cond = expr_text(&t.cond);
            if cond.contains(".T >= T#") {
                f.insert("S.T in a condition".into());
            }
            if cond.contains(".X") {
                f.insert("S.X in a condition".into());
            }
            if cond.contains(".Q") {
                f.insert("A.Q in a condition".into());
            }
        }
        for s in &c.steps {
            let leaving = c.transitions.iter().filter(|t| t.from.contains(&s.name));
            if leaving.count() > 1 {
                f.insert("selective divergence".into());
            }
            let entering = c.transitions.iter().filter(|t| t.to.contains(&s.name));
            if entering.count() > 1 {
                f.insert("selective convergence".into());
            }
        }
        let bodies = c
            .actions
            .iter()
            .map(|a| stmts_text(&a.body, 1))
            .collect::<String>();
        if bodies.contains(".Q") {
            f.insert("A.Q in an action".into());
        }
        if bodies.contains(".T") || bodies.contains(".X") {
            f.insert("step flag in an action".into());
        }
    }
    f
}
