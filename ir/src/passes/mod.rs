//! Optimisation passes over the IR.
//!
//! The front ends lower naively (locals in stack slots, every statement reloading
//! what it reads, dead blocks after `RETURN`); these passes turn that into tight SSA
//! for every backend. Each pass is `run(&mut Function) -> bool` (true if it changed
//! the function), preserves the semantics of `docs/ir.md` exactly (the fault flag
//! included) and leaves valid SSA. All of them are linear or close to it in the size
//! of the function, since they run on every compile.
//!
//! [`optimize_module`] / [`optimize_function`] run them in a sensible order.

pub mod const_fold;
pub mod copy_prop;
pub mod dce;
pub mod domtree;
pub mod load_store;
pub mod mem2reg;
pub mod simplify_cfg;
mod util;

#[cfg(test)]
mod tests;

use crate::function::Function;
use crate::module::Module;

pub use domtree::{DomTree, DominanceFrontiers};

/// Rounds of the cleanup passes after which a function is left as it is (each round
/// is linear; real code settles in two or three).
const MAX_ROUNDS: usize = 8;

/// Optimises one function: CFG cleanup, promotion of stack slots, then constant
/// folding, copy propagation, load/store forwarding, dead code elimination and CFG
/// simplification until nothing changes (at most a few rounds). Returns true if the
/// function changed.
pub fn optimize_function(func: &mut Function) -> bool {
    if func.layout.is_empty() {
        return false;
    }
    // Dropping unreachable code first lets mem2reg promote slots only dead code
    // would otherwise have kept in memory.
    let mut changed = simplify_cfg::run(func);
    changed |= mem2reg::run(func);
    for _ in 0..MAX_ROUNDS {
        let mut round = const_fold::run(func);
        round |= copy_prop::run(func);
        round |= load_store::run(func);
        round |= dce::run(func);
        round |= simplify_cfg::run(func);
        changed |= round;
        if !round {
            break;
        }
    }
    changed
}

/// Optimises every function of `module` (see [`optimize_function`]).
pub fn optimize_module(module: &mut Module) {
    for func in &mut module.funcs {
        optimize_function(func);
    }
}
