//! Tests of the passes: before/after tests in the text form (`unit`), folding checked
//! against the reference interpreter (`fold_oracle`), and random naive-lowering-style
//! functions run before and after every pass (`fuzz`).

mod fold_oracle;
mod fuzz;
mod shape;
mod unit;
mod watchdog;

use crate::function::Function;
use crate::module::Module;
use crate::text::{parse_module, print_function, PrintOptions};
use crate::verify::verify_function;

/// A pass as the tests drive it.
pub(super) type Pass = fn(&mut Function) -> bool;

/// Every pass by name, in driver order.
pub(super) const PASSES: [(&str, Pass); 6] = [
    ("simplify_cfg", super::simplify_cfg::run),
    ("mem2reg", super::mem2reg::run),
    ("const_fold", super::const_fold::run),
    ("copy_prop", super::copy_prop::run),
    ("load_store", super::load_store::run),
    ("dce", super::dce::run),
];

pub(super) fn parse(text: &str) -> Module {
    parse_module(text).unwrap_or_else(|e| panic!("parse error {e}\n{text}"))
}

/// The number of back edges of `f` (one per loop the passes made or kept).
pub(super) fn back_edges(f: &Function) -> usize {
    crate::dominators::DomTree::compute(f).back_edges(f).len()
}

/// Panics with the function's text if it does not verify.
pub(super) fn verify(m: &Module, f: &Function, what: &str) {
    if let Err(errs) = verify_function(m, f) {
        let list: Vec<String> = errs.iter().map(|e| e.to_string()).collect();
        panic!(
            "{what}: invalid IR:\n{}\n{}",
            list.join("\n"),
            print_function(m, f, &PrintOptions::default())
        );
    }
}

/// Prints every function of the module.
pub(super) fn print_funcs(m: &Module) -> String {
    m.funcs
        .iter()
        .map(|f| print_function(m, f, &PrintOptions::default()))
        .collect::<Vec<_>>()
        .join("\n")
}

/// Applies `f` to every function of `m` (with the module at hand for verification),
/// verifying before and after. Returns true if any function changed.
pub(super) fn apply(m: &mut Module, what: &str, f: impl Fn(&mut Function) -> bool) -> bool {
    let mut changed = false;
    for k in 0..m.funcs.len() {
        verify(m, &m.funcs[k], &format!("before {what}"));
        let mut func = m.funcs[k].clone();
        changed |= f(&mut func);
        m.funcs[k] = func;
        verify(m, &m.funcs[k], &format!("after {what}"));
    }
    changed
}

/// Parses `input`, runs `pass` on every function and compares the printed functions
/// with `expected` (both trimmed, trailing spaces ignored).
#[track_caller]
pub(super) fn check(input: &str, pass: Pass, expected: &str) {
    check_in_module(input, |f, _| pass(f), expected);
}

/// [`check`] for a pass that reads the module (its types) too.
#[track_caller]
pub(super) fn check_in_module(
    input: &str,
    pass: impl Fn(&mut Function, &Module) -> bool,
    expected: &str,
) {
    let mut m = parse(input);
    let types = m.clone();
    apply(&mut m, "pass", |f| pass(f, &types));
    let got = print_funcs(&m);
    let norm = |s: &str| {
        s.trim()
            .lines()
            .map(str::trim_end)
            .collect::<Vec<_>>()
            .join("\n")
    };
    if norm(&got) != norm(expected) {
        panic!(
            "unexpected result:\n{got}\n--- expected:\n{}",
            expected.trim()
        );
    }
    // A second run must find nothing more to do if the first reported a fixpoint.
    let mut again = m.clone();
    let before = print_funcs(&again);
    let changed = apply(&mut again, "second run", |f| pass(f, &types));
    assert!(
        changed || print_funcs(&again) == before,
        "a run that reports no change changed the function"
    );
}
