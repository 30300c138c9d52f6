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
pub mod gvn;
pub mod inline;
pub mod load_store;
pub mod mem2reg;
pub mod promote;
pub mod simplify_cfg;
mod util;
pub mod watchdog;

#[cfg(test)]
mod tests;

use crate::function::Function;
use crate::module::Module;

pub use domtree::{DomTree, DominanceFrontiers};

/// The cleanup passes the driver repeats, in the order it runs them.
const CLEANUP: [fn(&mut Function) -> bool; 5] = [
    const_fold::run,
    copy_prop::run,
    load_store::run,
    dce::run,
    simplify_cfg::run,
];

const CF: u8 = 1;
const CP: u8 = 2;
const LS: u8 = 4;
const DCE: u8 = 8;
const CFG: u8 = 16;

/// Which passes a change by each cleanup pass can give new work to. A pass is only
/// rerun when one of these says so, which saves most of the confirmation runs of a
/// plain "repeat everything until nothing changes" loop:
/// - folding substitutes values and turns branches into jumps: everyone but itself
///   (it revisits rewritten instructions and follows its own substitutions);
/// - copy propagation substitutes values: the same;
/// - forwarding substitutes values and removes memory operations: the same;
/// - dead code elimination only removes things, which can only empty blocks
///   (simplify_cfg) and remove loads that kept stores alive (load_store);
/// - CFG simplification merges blocks (new constants, longer blocks), removes edges
///   (trivial parameters) and can create new forwarders: everyone.
const ENABLES: [u8; 5] = [
    CP | LS | DCE | CFG,
    CF | LS | DCE | CFG,
    CF | CP | DCE | CFG,
    LS | CFG,
    CF | CP | LS | DCE | CFG,
];

/// Runs of cleanup passes after which a function is left as it is (each is linear;
/// real code settles after a dozen or so).
const MAX_RUNS: usize = 40;

/// Optimises one function: CFG cleanup, promotion of stack slots, then constant
/// folding, copy propagation, load/store forwarding, dead code elimination and CFG
/// simplification until none has anything left to do (with a bound on the work).
/// Returns true if the function changed.
pub fn optimize_function(func: &mut Function) -> bool {
    if func.layout.is_empty() {
        return false;
    }
    // Dropping unreachable code first lets mem2reg promote slots only dead code
    // would otherwise have kept in memory.
    let mut changed = simplify_cfg::run(func);
    changed |= mem2reg::run(func);
    let mut dirty: u8 = CF | CP | LS | DCE | CFG;
    let mut runs = 0;
    while dirty != 0 && runs < MAX_RUNS {
        for (k, pass) in CLEANUP.iter().enumerate() {
            let bit = 1u8 << k;
            if dirty & bit == 0 {
                continue;
            }
            dirty &= !bit;
            runs += 1;
            if pass(func) {
                changed = true;
                dirty |= ENABLES[k];
            }
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
