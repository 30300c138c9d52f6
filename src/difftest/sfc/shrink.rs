//! Shrinking a chart that shows a mismatch or a rejection: first the chart itself
//! (the FB and its instances, steps, transitions, associations, actions, the BOOL
//! variables used as actions, priorities, the steps of a divergence or
//! convergence, conditions made TRUE, FALSE or a BOOL part of themselves,
//! qualifiers made N, statements of the actions), then each action's statements
//! and the declarations with the ST shrinker ([`crate::difftest::shrink`]), for as
//! long as the program fails the same way.

use super::{ChartPou, SfcProg};
use crate::difftest::gen::{Expr, Stmt, T};
use crate::difftest::print::stmts_text;
use crate::difftest::shrink;

/// Removes the top-level statements of `main`'s actions that mention an instance.
fn forget(p: &mut SfcProg, inst: &str) {
    let call = format!("{inst}(");
    let field = format!("{inst}.");
    for a in &mut p.main.chart.actions {
        a.body.retain(|s| {
            let t = stmts_text(std::slice::from_ref(s), 0);
            !t.contains(&call) && !t.contains(&field)
        });
    }
}

/// The one-step simplifications of a POU's chart.
fn chart_steps(pou: &ChartPou) -> Vec<ChartPou> {
    let mut out = Vec::new();
    let mut with = |f: &dyn Fn(&mut ChartPou)| {
        let mut q = pou.clone();
        f(&mut q);
        if q != *pou {
            out.push(q);
        }
    };
    let c = &pou.chart;
    // A step or an action is taken away only when nothing reads its flags (else a
    // rejected program could shrink to one that reads a flag it does not declare).
    let text = |q: &ChartPou| {
        let mut t = String::new();
        super::print_chart(&q.chart, &mut t);
        t
    };
    let unread = |name: &str| !text(pou).contains(&format!("{name}."));
    for i in 0..c.steps.len() {
        if !unread(&c.steps[i].name) {
            continue;
        }
        with(&|q| {
            let name = q.chart.steps.remove(i).name;
            q.chart
                .transitions
                .retain(|t| !t.from.contains(&name) && !t.to.contains(&name));
        });
    }
    for i in 0..c.transitions.len() {
        with(&|q| {
            q.chart.transitions.remove(i);
        });
    }
    for i in 0..c.actions.len() {
        if !unread(&c.actions[i].name) {
            continue;
        }
        with(&|q| {
            let name = q.chart.actions.remove(i).name;
            let inner = q.chart.actions.iter_mut().filter_map(|a| a.chart.as_mut());
            for s in inner.flat_map(|c| c.steps.iter_mut()) {
                s.assocs.retain(|a| a.target != name);
            }
            for s in &mut q.chart.steps {
                s.assocs.retain(|a| a.target != name);
            }
        });
    }
    for i in 0..pou.bools.len() {
        with(&|q| {
            let name = q.bools.remove(i);
            for s in &mut q.chart.steps {
                s.assocs.retain(|a| a.target != name);
            }
        });
    }
    for (i, s) in c.steps.iter().enumerate() {
        for k in 0..s.assocs.len() {
            with(&|q| {
                q.chart.steps[i].assocs.remove(k);
            });
            with(&|q| {
                let a = &mut q.chart.steps[i].assocs[k];
                a.qual = "N";
                a.ms = None;
            });
        }
    }
    for (i, t) in c.transitions.iter().enumerate() {
        with(&|q| q.chart.transitions[i].priority = None);
        for k in 0..t.from.len() {
            if t.from.len() > 1 {
                with(&|q| {
                    q.chart.transitions[i].from.remove(k);
                });
            }
        }
        for k in 0..t.to.len() {
            if t.to.len() > 1 {
                with(&|q| {
                    q.chart.transitions[i].to.remove(k);
                });
            }
        }
        for v in ["TRUE", "FALSE"] {
            with(&|q| q.chart.transitions[i].cond = Expr::Lit(T::Bool, v.into()));
        }
        let parts: Vec<Expr> = t
            .cond
            .children()
            .into_iter()
            .filter(|e| e.ty() == T::Bool)
            .cloned()
            .collect();
        for e in parts {
            with(&|q| q.chart.transitions[i].cond = e.clone());
        }
    }
    for (i, a) in c.actions.iter().enumerate() {
        for k in 0..a.body.len() {
            with(&|q| {
                q.chart.actions[i].body.remove(k);
            });
            let bodies: Vec<Vec<Stmt>> = a.body[k].bodies().into_iter().cloned().collect();
            for inner in bodies {
                with(&|q| {
                    q.chart.actions[i].body.splice(k..=k, inner.clone());
                });
            }
        }
    }
    out
}

/// The one-step simplifications of the chart parts of `p`.
fn candidates(p: &SfcProg) -> Vec<SfcProg> {
    let mut out = Vec::new();
    if let Some((fb, instances)) = &p.fb {
        let mut q = p.clone();
        for inst in instances {
            forget(&mut q, inst);
        }
        q.fb = None;
        out.push(q);
        if instances.len() > 1 {
            let mut q = p.clone();
            let last = instances[instances.len() - 1].clone();
            forget(&mut q, &last);
            q.fb.as_mut().expect("fb").1.pop();
            out.push(q);
        }
        for f in chart_steps(fb) {
            let mut q = p.clone();
            q.fb.as_mut().expect("fb").0 = f;
            out.push(q);
        }
    }
    for m in chart_steps(&p.main) {
        let mut q = p.clone();
        q.main = m;
        out.push(q);
    }
    out
}

/// `main` (0) or the FB (1).
fn pou_mut(pou: usize, s: &mut SfcProg) -> &mut ChartPou {
    if pou == 0 {
        &mut s.main
    } else {
        &mut s.fb.as_mut().expect("fb").0
    }
}

/// Shrinks `p` while `fails` holds, trying at most `budget` candidates.
pub fn shrink(p: &SfcProg, fails: &mut dyn FnMut(&SfcProg) -> bool, budget: usize) -> SfcProg {
    let mut best = p.clone();
    let mut tries = 0;
    'outer: loop {
        for q in candidates(&best) {
            tries += 1;
            if tries > budget {
                return best;
            }
            if fails(&q) {
                best = q;
                continue 'outer;
            }
        }
        break;
    }
    // Each action's statements and expressions, and the declarations of its POU,
    // with the ST shrinker (the POU's declarations seen as a program whose body is
    // the action).
    let left = budget.saturating_sub(tries);
    let pous = 1 + best.fb.is_some() as usize;
    for pou in 0..pous {
        let count = if pou == 0 {
            best.main.chart.actions.len()
        } else {
            best.fb.as_ref().map_or(0, |f| f.0.chart.actions.len())
        };
        for a in 0..count {
            let mut base = best.clone();
            let view = {
                let c = pou_mut(pou, &mut base);
                let mut v = c.decl.clone();
                v.body = c.chart.actions[a].body.clone();
                v
            };
            let small = shrink::shrink(
                &view,
                &mut |v| {
                    let mut s = base.clone();
                    let c = pou_mut(pou, &mut s);
                    c.decl = v.clone();
                    c.decl.body.clear();
                    c.chart.actions[a].body = v.body.clone();
                    fails(&s)
                },
                left / (count * pous).max(1),
            );
            let c = pou_mut(pou, &mut best);
            c.chart.actions[a].body = small.body.clone();
            c.decl = small;
            c.decl.body.clear();
        }
    }
    best
}
