//! Shrinking a program that shows a mismatch: statements are removed or replaced by
//! their bodies, expressions by a plain literal or by a subexpression of their type,
//! an exact EXPT's operand by a literal, and the declared parts (the CONFIGURATION,
//! its instances, tasks, connections and globals, the parts reached through
//! run-time addresses, the object-oriented part or pieces of it) are dropped, for as
//! long as the mismatch stays. A step that
//! takes away what the program still uses makes a program the front end rejects,
//! which is no mismatch, so it is not taken.

use super::gen::{Expr, Operand, Prog, Stmt, FIXED, T};
use super::oo::Oo;

/// The simplest literal of a type.
fn plain(t: T) -> Expr {
    let text = match t {
        T::Bool => "FALSE".to_string(),
        T::Real | T::Lreal => format!("{}#1.0", t.name()),
        T::Time => "T#1ms".to_string(),
        T::Date => "D#1970-01-02".to_string(),
        T::Tod => "TOD#00:00:01".to_string(),
        T::Dt => "DT#1970-01-01-00:00:01".to_string(),
        _ => format!("{}#1", t.name()),
    };
    Expr::Lit(t, text)
}

/// Every statement list of the body, depth first, with a visitor that may edit one.
fn for_each_list(body: &mut Vec<Stmt>, f: &mut dyn FnMut(&mut Vec<Stmt>) -> bool) -> bool {
    if f(body) {
        return true;
    }
    body.iter_mut()
        .any(|s| s.bodies_mut().into_iter().any(|b| for_each_list(b, f)))
}

/// Every expression of the program (statements' and initial values'), depth first.
fn for_each_expr(p: &mut Prog, f: &mut dyn FnMut(&mut Expr) -> bool) -> bool {
    fn walk(e: &mut Expr, f: &mut dyn FnMut(&mut Expr) -> bool) -> bool {
        if f(e) {
            return true;
        }
        e.children_mut().into_iter().any(|c| walk(c, f))
    }
    fn stmts(body: &mut [Stmt], f: &mut dyn FnMut(&mut Expr) -> bool) -> bool {
        body.iter_mut().any(|s| {
            s.exprs_mut().into_iter().any(|e| walk(e, f))
                || s.bodies_mut().into_iter().any(|b| stmts(b, f))
        })
    }
    p.vars.iter_mut().any(|(_, _, e)| walk(e, f)) || stmts(&mut p.body, f)
}

/// The programs with one declared part less than `p`: the configuration, an
/// instance, a task, a connection, a global, an output, one of the parts reached
/// through run-time addresses.
fn fewer_parts(p: &Prog) -> Vec<Prog> {
    let mut out = Vec::new();
    let mut with = |f: &dyn Fn(&mut Prog)| {
        let mut q = p.clone();
        f(&mut q);
        out.push(q);
    };
    if let Some(c) = &p.config {
        with(&|q| q.config = None);
        for i in 0..c.instances.len() {
            if c.instances.len() > 1 {
                with(&|q| {
                    q.config.as_mut().expect("config").instances.remove(i);
                });
            }
            for k in 0..c.instances[i].conns.len() {
                with(&|q| {
                    q.config.as_mut().expect("config").instances[i]
                        .conns
                        .remove(k);
                });
            }
            if c.instances[i].task.is_some() {
                with(&|q| q.config.as_mut().expect("config").instances[i].task = None);
            }
        }
        for t in 0..c.tasks.len() {
            with(&|q| {
                let c = q.config.as_mut().expect("config");
                c.tasks.remove(t);
                for inst in &mut c.instances {
                    inst.task = match inst.task {
                        Some(x) if x == t => None,
                        Some(x) if x > t => Some(x - 1),
                        x => x,
                    };
                }
            });
        }
        for g in 0..c.globals.len() {
            with(&|q| {
                q.config.as_mut().expect("config").globals.remove(g);
            });
        }
        if c.resource {
            with(&|q| q.config.as_mut().expect("config").resource = false);
        }
    }
    if p.outputs > 0 {
        with(&|q| q.outputs = 0);
    }
    for i in 0..p.vars.len() {
        with(&|q| {
            q.vars.remove(i);
            if i < q.outputs {
                q.outputs -= 1;
            }
        });
    }
    for i in 0..p.inputs.len() {
        with(&|q| {
            q.inputs.remove(i);
        });
    }
    for d in FIXED {
        if !p.dropped.iter().any(|x| x == d) {
            with(&|q| q.dropped.push(d.to_string()));
        }
    }
    if p.recs.is_some() {
        with(&|q| q.recs = None);
    }
    if p.fbs.is_some() {
        with(&|q| q.fbs = None);
    }
    if p.inout {
        with(&|q| q.inout = false);
    }
    if p.refs {
        with(&|q| q.refs = false);
    }
    if let Some(oo) = &p.oo {
        oo_parts(oo, &mut with);
    }
    out
}

/// What makes a candidate from an edit of a copy of the program.
type With<'a> = dyn FnMut(&dyn Fn(&mut Prog)) + 'a;

/// The object-oriented part's simplifications: all of it (with its statements),
/// an FB's body or its `SUPER^();`, a method's statement, a property's SET body, a
/// property, a method, a field, one of `main`'s instances, interface variables,
/// arrays and references.
fn oo_parts(oo: &Oo, with: &mut With) {
    fn part(q: &mut Prog) -> &mut Oo {
        q.oo.as_mut().expect("an OO part")
    }
    with(&|q| super::oo::strip(q));
    for (c, class) in oo.classes.iter().enumerate() {
        if !class.body.is_empty() {
            with(&|q| part(q).classes[c].body.clear());
        }
        if class.super_body {
            with(&|q| part(q).classes[c].super_body = false);
        }
        for (m, method) in class.methods.iter().enumerate() {
            for i in 0..method.body.len() {
                with(&|q| {
                    part(q).classes[c].methods[m].body.remove(i);
                });
            }
        }
        for (k, prop) in class.props.iter().enumerate() {
            if !prop.set.is_empty() {
                with(&|q| part(q).classes[c].props[k].set.clear());
            }
            with(&|q| {
                part(q).classes[c].props.remove(k);
            });
        }
        // Declarations (a step leaving a use behind is rejected, so not taken).
        for m in 0..class.methods.len() {
            with(&|q| {
                part(q).classes[c].methods.remove(m);
            });
        }
        for i in 0..class.inputs.len() {
            with(&|q| {
                part(q).classes[c].inputs.remove(i);
            });
        }
        for i in 0..class.outputs.len() {
            with(&|q| {
                part(q).classes[c].outputs.remove(i);
            });
        }
        for i in 0..class.vars.len() {
            with(&|q| {
                part(q).classes[c].vars.remove(i);
            });
        }
    }
    for i in 0..oo.insts.len() {
        with(&|q| {
            part(q).insts.remove(i);
        });
    }
    for i in 0..oo.itf_vars.len() {
        with(&|q| {
            part(q).itf_vars.remove(i);
        });
    }
    for i in 0..oo.arrays.len() {
        with(&|q| {
            part(q).arrays.remove(i);
        });
    }
    for i in 0..oo.refs.len() {
        with(&|q| {
            part(q).refs.remove(i);
        });
    }
}

/// The `n`th one-step simplification of `p`, if there is one: removing a statement,
/// putting one of a compound statement's bodies in its place, dropping a declared
/// part, or simplifying an expression.
fn candidate(p: &Prog, n: usize) -> Option<Prog> {
    let mut q = p.clone();
    let mut k = 0;
    // Remove a statement, or put a compound statement's first body in its place.
    let done = for_each_list(&mut q.body, &mut |list| {
        for i in 0..list.len() {
            if k == n {
                list.remove(i);
                return true;
            }
            k += 1;
            let bodies: Vec<Vec<Stmt>> = list[i].bodies().into_iter().cloned().collect();
            for inner in bodies {
                if k == n {
                    list.splice(i..=i, inner);
                    return true;
                }
                k += 1;
            }
        }
        false
    });
    if done {
        return Some(q);
    }
    let parts = fewer_parts(p);
    if n - k < parts.len() {
        return parts.into_iter().nth(n - k);
    }
    k += parts.len();
    // Replace an expression by a plain literal, or by a subexpression of its type;
    // an operand of an exact EXPT by a literal.
    let done = for_each_expr(&mut q, &mut |e| {
        let t = e.ty();
        if !matches!(e, Expr::Lit(..)) {
            if k == n {
                *e = plain(t);
                return true;
            }
            k += 1;
        }
        if let Expr::Pow(pow) = e {
            for o in [&mut pow.base, &mut pow.exp] {
                let lit = match o {
                    Operand::Lit(..) => continue,
                    Operand::Clamp(t, _, hi, _) => Operand::Lit(*t, (*hi).min(2)),
                    Operand::Choice(t, vals, _) => Operand::Lit(*t, vals[0]),
                };
                if k == n {
                    *o = lit;
                    return true;
                }
                k += 1;
            }
        }
        let child = e
            .children_mut()
            .into_iter()
            .find(|c| c.ty() == t)
            .map(|c| c.clone());
        if let Some(c) = child {
            if k == n {
                *e = c;
                return true;
            }
            k += 1;
        }
        false
    });
    done.then_some(q)
}

/// Shrinks `p` while `fails` holds, trying at most `budget` candidates.
pub fn shrink(p: &Prog, fails: &mut dyn FnMut(&Prog) -> bool, budget: usize) -> Prog {
    let mut best = p.clone();
    let mut tries = 0;
    'outer: loop {
        let mut n = 0;
        while let Some(q) = candidate(&best, n) {
            tries += 1;
            if tries > budget {
                break 'outer;
            }
            if fails(&q) {
                best = q;
                continue 'outer;
            }
            n += 1;
        }
        break;
    }
    best
}
