//! The generator of random charts ([`super::SfcProg`]): `main`'s declarations come
//! from the ST generator (without a CONFIGURATION), the statements of the actions
//! too, with the chart's step flags (`S1.X`, `S1.T`) and action flags (`A0.Q`)
//! readable in every expression; the FB with a chart has slim declarations of its
//! own.

use super::{Action, Assoc, Chart, ChartPou, SfcProg, Step, Transition, QUALIFIERS, STEP_ACTIONS};
use crate::difftest::gen::{lit, Expr, Gen, Prog, Rng, Stmt, ALL, T};
use crate::difftest::print::expr_text;

/// Front-end bugs the SFC campaigns found and that are still open (TESTING.md),
/// which the generator steers around unless told otherwise (`plcc difftest --lang
/// sfc --known-bugs`), so that campaigns look for new ones. None is open: bug 1
/// (the flag `A.Q` of an ACTION no step associates rejected as undeclared, E0201)
/// is fixed, and the generator reads every action's flag.
pub const KNOWN_BUGS: [&str; 0] = [];

/// Durations of the timed qualifiers and of the step-time conditions: a few
/// 10 ms cycles.
const MS: [u32; 6] = [10, 20, 30, 40, 50, 70];

/// Generates a program; `avoid`: steer around the [`KNOWN_BUGS`].
pub fn program(rng: &mut Rng, avoid: bool) -> SfcProg {
    // `main`'s declarations: the ST generator's, without its CONFIGURATION and
    // body, with a BOOL input at least (for the conditions).
    let mut decl = Gen::new(rng).program();
    decl.config = None;
    decl.body.clear();
    if !decl.inputs.iter().any(|(_, t)| *t == T::Bool) {
        let n = decl.inputs.len();
        decl.inputs.push((format!("in{n}"), T::Bool));
    }
    // CODESYS's SFC flags, as inputs (written at random between scans).
    if rng.chance(20) {
        let flag = *rng.pick(&["SFCInit", "SFCReset", "SFCPause"]);
        decl.inputs.push((flag.to_string(), T::Bool));
    }
    let fb = rng.chance(30).then(|| {
        let decl = fb_decl(rng);
        let n = 2 + rng.below(4) as usize;
        let (chart, bools) = chart(rng, &decl, n, avoid);
        let n = 1 + rng.below(2) as usize;
        let instances: Vec<String> = (1..=n).map(|i| format!("c{i}")).collect();
        (ChartPou { decl, bools, chart }, instances)
    });
    let n = 2 + rng.below(7) as usize;
    let (mut chart, bools) = chart(rng, &decl, n, avoid);
    // The FB's instances are called from `main`'s actions (each instance evolves
    // when it is called), their outputs read into `main`'s variables.
    if let Some((f, instances)) = &fb {
        let mut g = Gen::over(rng, decl.clone());
        for inst in instances {
            for _ in 0..1 + g.rng().below(2) {
                let args: Vec<String> = f
                    .decl
                    .inputs
                    .iter()
                    .map(|(n, t)| format!("{n} := {}", expr_text(&g.expr(*t))))
                    .collect();
                let mut stmts = vec![Stmt::Raw(format!("{inst}({});", args.join(", ")))];
                for (n, t, _) in &f.decl.vars[..f.decl.outputs] {
                    let targets: Vec<String> = g
                        .prog()
                        .vars
                        .iter()
                        .filter(|v| v.1 == *t)
                        .map(|v| v.0.clone())
                        .collect();
                    if !targets.is_empty() && g.rng().chance(70) {
                        let target = g.rng().pick(&targets).clone();
                        stmts.push(Stmt::Assign(target, Expr::Var(*t, format!("{inst}.{n}"))));
                    }
                }
                let a = g.rng().below(chart.actions.len() as u64) as usize;
                let body = &mut chart.actions[a].body;
                let at = g.rng().below(body.len() as u64 + 1) as usize;
                body.splice(at..at, stmts);
            }
        }
    }
    SfcProg {
        main: ChartPou { decl, bools, chart },
        fb,
    }
}

/// The FB's declarations: a BOOL input and perhaps another, one to three
/// variables of at most 32 bits (the first one or two outputs), a short array.
fn fb_decl(rng: &mut Rng) -> Prog {
    let narrow: Vec<T> = ALL.iter().copied().filter(|t| t.bits() <= 32).collect();
    let mut inputs = vec![("in0".to_string(), T::Bool)];
    if rng.chance(50) {
        inputs.push(("in1".into(), *rng.pick(&narrow)));
    }
    let n = 1 + rng.below(3) as usize;
    let vars = (0..n)
        .map(|i| {
            let t = *rng.pick(&narrow);
            (format!("v{i}"), t, lit(rng, t))
        })
        .collect();
    let et = *rng.pick(&[T::Int, T::Byte, T::Bool]);
    Prog {
        vars,
        outputs: 1 + rng.below(2).min(n as u64 - 1) as usize,
        inputs,
        array: (et, 0, 1 + rng.below(2) as i64),
        recs: None,
        fbs: None,
        inout: false,
        refs: false,
        body: Vec::new(),
        config: None,
        dropped: Vec::new(),
        oo: None,
    }
}

/// A chart of `n` steps over the declarations `decl`, and the BOOL variables it
/// adds to them (used as actions).
fn chart(rng: &mut Rng, decl: &Prog, n: usize, _avoid: bool) -> (Chart, Vec<String>) {
    let names: Vec<String> = (0..n).map(|i| format!("S{i}")).collect();
    let nactions = 1 + rng.below(4) as usize;
    let actions: Vec<String> = (0..nactions).map(|i| format!("A{i}")).collect();
    let bools: Vec<String> = (0..rng.below(3)).map(|i| format!("b{i}")).collect();
    let mut g = Gen::over(rng, decl.clone());
    for s in &names {
        g.extra.push((format!("{s}.X"), T::Bool));
        g.extra.push((format!("{s}.T"), T::Time));
    }
    // Targets of associations: the actions, the added BOOLs, and sometimes a BOOL
    // variable the statements also write.
    let mut targets = actions.clone();
    targets.extend(bools.iter().cloned());
    let declared: Vec<String> = decl
        .vars
        .iter()
        .filter(|v| v.1 == T::Bool)
        .map(|v| v.0.clone())
        .collect();
    if !declared.is_empty() && g.rng().chance(30) {
        targets.push(g.rng().pick(&declared).clone());
    }
    // A second initial step in some charts.
    let second = (n > 2 && g.rng().chance(15)).then(|| 1 + g.rng().below(n as u64 - 1) as usize);
    let mut steps: Vec<Step> = names
        .iter()
        .enumerate()
        .map(|(i, name)| Step {
            name: name.clone(),
            initial: i == 0 || Some(i) == second,
            assocs: Vec::new(),
        })
        .collect();
    for s in &mut steps {
        let mut pool = targets.clone();
        for _ in 0..g.rng().below(4) {
            if pool.is_empty() {
                break;
            }
            let target = pool.remove(g.rng().below(pool.len() as u64) as usize);
            let qual = if g.rng().chance(25) {
                "N"
            } else {
                *g.rng().pick(&QUALIFIERS)
            };
            let ms = super::timed(qual).then(|| *g.rng().pick(&MS));
            s.assocs.push(Assoc { target, qual, ms });
        }
    }
    // CODESYS's step actions on some steps.
    for s in &mut steps {
        if g.rng().chance(20) {
            let target = g.rng().pick(&actions).clone();
            let qual = *g.rng().pick(&STEP_ACTIONS);
            s.assocs.push(Assoc {
                target,
                qual,
                ms: None,
            });
        }
    }
    // Every action is associated somewhere (most of the time).
    for a in &actions {
        let used = steps
            .iter()
            .any(|s| s.assocs.iter().any(|x| &x.target == a));
        if !used && g.rng().chance(85) {
            let k = g.rng().below(n as u64) as usize;
            steps[k].assocs.push(Assoc {
                target: a.clone(),
                qual: "N",
                ms: None,
            });
        }
    }
    // The actions' flags, readable in conditions and statements (also those of the
    // actions no step associates: FALSE).
    for a in &actions {
        g.extra.push((format!("{a}.Q"), T::Bool));
    }
    // Transitions: one leaving each step (to the next one most of the time, else
    // anywhere: a jump or a self loop), then more of every shape.
    let mut transitions = Vec::new();
    for i in 0..n {
        let to = if g.rng().chance(60) {
            (i + 1) % n
        } else {
            g.rng().below(n as u64) as usize
        };
        let t = transition(&mut g, &names, vec![i], vec![to]);
        transitions.push(t);
    }
    for _ in 0..g.rng().below(n as u64 + 1) {
        let pick = |g: &mut Gen, k: usize| -> Vec<usize> {
            let mut all: Vec<usize> = (0..n).collect();
            let mut out = Vec::new();
            for _ in 0..k.min(n) {
                out.push(all.remove(g.rng().below(all.len() as u64) as usize));
            }
            out
        };
        let (nf, nt) = match g.rng().below(10) {
            0..=4 => (1, 1),
            5..=6 => (1, 2 + g.rng().below(2) as usize),
            7..=8 => (2 + g.rng().below(2) as usize, 1),
            _ => (2, 2),
        };
        let from = pick(&mut g, nf);
        let to = pick(&mut g, nt);
        let t = transition(&mut g, &names, from, to);
        let at = g.rng().below(transitions.len() as u64 + 1) as usize;
        transitions.insert(at, t);
    }
    // The actions' bodies: statements of the ST generator, some wrapped in a
    // test of the action's own Q (the final execution runs the ELSE part).
    let mut acts = Vec::new();
    for a in &actions {
        let mut body: Vec<Stmt> = (0..1 + g.rng().below(4)).map(|_| g.stmt()).collect();
        let flag = g.extra.iter().any(|(n, _)| *n == format!("{a}.Q"));
        if flag && g.rng().chance(30) {
            let other = (0..g.rng().below(2)).map(|_| g.stmt()).collect();
            body = vec![Stmt::If(Expr::Var(T::Bool, format!("{a}.Q")), body, other)];
        }
        acts.push(Action {
            name: a.clone(),
            body,
            chart: None,
        });
    }
    // Sometimes the first action is a chart of two steps, driving the others.
    if acts.len() > 1 && g.rng().chance(25) {
        let a = acts[0].name.clone();
        let inner: Vec<String> = (0..2).map(|i| format!("{a}_S{i}")).collect();
        let mut steps: Vec<Step> = inner
            .iter()
            .enumerate()
            .map(|(i, name)| Step {
                name: name.clone(),
                initial: i == 0,
                assocs: Vec::new(),
            })
            .collect();
        for s in &mut steps {
            if g.rng().chance(80) {
                let target = acts[1 + g.rng().below(acts.len() as u64 - 1) as usize]
                    .name
                    .clone();
                let qual = if g.rng().chance(50) {
                    "N"
                } else {
                    *g.rng().pick(&QUALIFIERS)
                };
                let ms = super::timed(qual).then(|| *g.rng().pick(&MS));
                s.assocs.push(Assoc { target, qual, ms });
            }
        }
        let transitions = vec![
            transition(&mut g, &inner, vec![0], vec![1]),
            transition(&mut g, &inner, vec![1], vec![0]),
        ];
        acts[0].chart = Some(Chart {
            steps,
            transitions,
            actions: Vec::new(),
        });
        acts[0].body.clear();
    }
    (
        Chart {
            steps,
            transitions,
            actions: acts,
        },
        bools,
    )
}

/// A transition between steps (by index) with a random priority and condition.
fn transition(g: &mut Gen, names: &[String], from: Vec<usize>, to: Vec<usize>) -> Transition {
    let priority = g.rng().chance(25).then(|| g.rng().below(5) as u32);
    let cond = condition(g, names);
    Transition {
        priority,
        from: from.into_iter().map(|i| names[i].clone()).collect(),
        to: to.into_iter().map(|i| names[i].clone()).collect(),
        cond,
    }
}

/// A BOOL condition: TRUE, an input, a step's time or activity, their
/// combinations, or any BOOL expression of the ST generator.
fn condition(g: &mut Gen, names: &[String]) -> Expr {
    let b = Box::new;
    let bools: Vec<String> = g
        .prog()
        .inputs
        .iter()
        .filter(|v| v.1 == T::Bool)
        .map(|v| v.0.clone())
        .collect();
    let input = |g: &mut Gen| {
        let v = Expr::Var(T::Bool, g.rng().pick(&bools).clone());
        if g.rng().chance(30) {
            Expr::Un(T::Bool, "NOT", b(v))
        } else {
            v
        }
    };
    let step_time = |g: &mut Gen| {
        let s = g.rng().pick(names).clone();
        let ms = *g.rng().pick(&MS);
        Expr::Bin(
            T::Bool,
            ">=",
            b(Expr::Var(T::Time, format!("{s}.T"))),
            b(Expr::Lit(T::Time, format!("T#{ms}ms"))),
        )
    };
    match g.rng().below(100) {
        0..=11 => Expr::Lit(T::Bool, "TRUE".into()),
        12..=36 => input(g),
        37..=51 => step_time(g),
        52..=59 => {
            let t = step_time(g);
            let op = *g.rng().pick(&["AND", "OR"]);
            Expr::Bin(T::Bool, op, b(t), b(input(g)))
        }
        60..=71 => {
            let s = g.rng().pick(names).clone();
            let x = Expr::Var(T::Bool, format!("{s}.X"));
            let x = if g.rng().chance(50) {
                Expr::Un(T::Bool, "NOT", b(x))
            } else {
                x
            };
            let op = *g.rng().pick(&["AND", "OR", "XOR"]);
            Expr::Bin(T::Bool, op, b(x), b(input(g)))
        }
        _ => g.expr(T::Bool),
    }
}
