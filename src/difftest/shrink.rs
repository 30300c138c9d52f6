//! Shrinking a program that shows a mismatch: statements are removed or replaced by
//! their bodies and expressions by a plain literal or by a subexpression of their
//! type, for as long as the mismatch stays.

use super::gen::{Expr, Prog, Stmt, T};

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
    for s in body.iter_mut() {
        let done = match s {
            Stmt::If(_, a, b) => for_each_list(a, f) || for_each_list(b, f),
            Stmt::For(_, _, _, b) | Stmt::While(_, b) => for_each_list(b, f),
            Stmt::Case(_, arms, other) => {
                arms.iter_mut().any(|(_, b)| for_each_list(b, f)) || for_each_list(other, f)
            }
            _ => false,
        };
        if done {
            return true;
        }
    }
    false
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
        body.iter_mut().any(|s| match s {
            Stmt::Assign(_, e) => walk(e, f),
            Stmt::AssignElem(i, e) => walk(i, f) || walk(e, f),
            Stmt::If(c, a, b) => walk(c, f) || stmts(a, f) || stmts(b, f),
            Stmt::For(_, _, _, b) | Stmt::While(_, b) => stmts(b, f),
            Stmt::Case(c, arms, other) => {
                walk(c, f) || arms.iter_mut().any(|(_, b)| stmts(b, f)) || stmts(other, f)
            }
            Stmt::CallFb(a, b, _) => walk(a, f) || walk(b, f),
            Stmt::Raw(_) => false,
        })
    }
    p.vars.iter_mut().any(|(_, _, e)| walk(e, f)) || stmts(&mut p.body, f)
}

/// The `n`th one-step simplification of `p`, if there is one: removing a statement,
/// putting one of a compound statement's bodies in its place, or simplifying an
/// expression.
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
            let bodies: Vec<Vec<Stmt>> = match &list[i] {
                Stmt::If(_, a, b) => vec![a.clone(), b.clone()],
                Stmt::For(_, _, _, b) | Stmt::While(_, b) => vec![b.clone()],
                Stmt::Case(_, arms, other) => arms
                    .iter()
                    .map(|a| a.1.clone())
                    .chain([other.clone()])
                    .collect(),
                _ => Vec::new(),
            };
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
    // Replace an expression by a plain literal, or by a subexpression of its type.
    let done = for_each_expr(&mut q, &mut |e| {
        let t = e.ty();
        if !matches!(e, Expr::Lit(..)) {
            if k == n {
                *e = plain(t);
                return true;
            }
            k += 1;
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
