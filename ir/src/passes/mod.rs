//! Optimisation passes over the IR.
//!
//! The front ends lower naively (locals in stack slots, every statement reloading
//! what it reads, dead blocks after `RETURN`); these passes turn that into tight SSA
//! for every backend. Each pass is `run(&mut Function) -> bool` (true if it changed
//! the function), preserves the semantics of `docs/ir.md` exactly (the fault flag
//! included) and leaves valid SSA. All of them are linear or close to it in the size
//! of the function, since they run on every compile.
//!
//! [`optimize_program`] is the whole pipeline; [`optimize_module`] /
//! [`optimize_function`] run the per-function passes in a sensible order.

pub mod br_table;
pub mod const_fold;
pub mod copy_prop;
pub mod dce;
pub mod dispatch;
pub mod fill;
pub mod gvn;
pub mod if_convert;
pub mod inline;
pub mod legalize;
pub mod load_store;
pub mod mem2reg;
pub mod promote;
pub mod ranges;
pub mod rotate;
pub mod simplify_cfg;
pub mod sizes;
mod util;
pub mod watchdog;

#[cfg(test)]
mod tests;

use crate::function::Function;
use crate::module::Module;

pub use crate::dominators::{DomTree, DominanceFrontiers};

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
const ALL: u8 = CF | CP | LS | DCE | CFG;

/// Which passes a change by each cleanup pass can give new work to. A pass is only
/// rerun when one of these says so, which saves most of the confirmation runs of a
/// plain "repeat everything until nothing changes" loop:
/// - folding substitutes values and turns branches into jumps: everyone but itself
///   (it revisits rewritten instructions and follows its own substitutions);
/// - copy propagation and forwarding substitute values: the same;
/// - dead code elimination only removes things, which can only empty blocks
///   (simplify_cfg) and remove loads that kept stores alive (load_store);
/// - CFG simplification merges blocks (new constants, longer blocks), removes edges
///   (trivial parameters) and can create new forwarders: everyone.
const ENABLES: [u8; 5] = [
    CP | LS | DCE | CFG,
    CF | LS | DCE | CFG,
    CF | CP | DCE | CFG,
    LS | CFG,
    ALL,
];

/// Rounds of value numbering and cleanup after which a function is left as it is.
const MAX_GVN_ROUNDS: usize = 4;

/// Runs of cleanup passes after which a function is left as it is (each is linear;
/// real code settles after a dozen or so).
const MAX_RUNS: usize = 40;

/// Optimises one function: CFG cleanup, promotion of stack slots, then constant
/// folding, copy propagation, load/store forwarding, dead code elimination and CFG
/// simplification until none has anything left to do (with a bound on the work), then
/// global value numbering and, if it found repeats, the cleanup again.
/// Returns true if the function changed.
pub fn optimize_function(func: &mut Function) -> bool {
    if func.layout.is_empty() {
        return false;
    }
    // Dropping unreachable code first lets mem2reg promote slots only dead code
    // would otherwise have kept in memory.
    let mut changed = simplify_cfg::run(func);
    changed |= mem2reg::run(func);
    changed |= cleanup(func, ALL);
    // Value numbering is the costliest pass (a dominator tree and a hash table): it
    // runs once the cheap passes have settled, and again only while it finds repeats
    // (the cleanup after it can expose more).
    for _ in 0..MAX_GVN_ROUNDS {
        if !gvn::run(func) {
            break;
        }
        changed = true;
        cleanup(func, ALL);
    }
    changed
}

/// Runs the cleanup passes, starting with the `dirty` ones, until none has work left.
fn cleanup(func: &mut Function, mut dirty: u8) -> bool {
    let mut changed = false;
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

/// Optimises every function of `module` (see [`optimize_function`]), on several
/// threads when the machine has several cores (functions are independent here;
/// [`crate::parallel`]).
pub fn optimize_module(module: &mut Module) {
    crate::parallel::each_mut(module.funcs.iter_mut().collect(), optimize_function);
}

/// The whole-program pipeline the driver runs: every function on its own, then
/// inlining of small and single-use callees (callees first, each caller cleaned up
/// after), removal of functions nothing calls any more, and promotion of instance
/// variables to SSA values within each PROGRAM and FB body followed by a last cleanup
/// of the bodies it changed.
pub fn optimize_program(module: &mut Module) {
    optimize_program_for(module, promote::Promotion::Everywhere);
}

/// [`optimize_program`] for a target whose SSA values live where `promotion` says.
pub fn optimize_program_for(module: &mut Module, promotion: promote::Promotion) {
    optimize_module(module);
    optimize_whole_program(module, promotion);
}

/// The whole-program part of [`optimize_program`], for a module whose functions
/// [`optimize_module`] has already optimised: inlining, removal of functions nothing
/// calls, promotion of instance variables, and the cleanup of what they changed.
/// `optimize_module` then `optimize_whole_program` gives exactly what
/// `optimize_program_for` gives; the tiered JIT runs the second step in the background
/// (ARCHITECTURE.md, "Tiers").
pub fn optimize_whole_program(module: &mut Module, promotion: promote::Promotion) {
    inline::run(module, &|f| {
        optimize_function(f);
    });
    inline::remove_unreachable_functions(module);
    let exposed = promote::Exposed::of(module);
    let aggs = &module.aggs;
    crate::parallel::each_mut(module.funcs.iter_mut().collect(), |f| {
        let promoted = promote::run_function(aggs, &exposed, promotion, f);
        if promoted {
            optimize_function(f);
        }
        promoted
    });
    // The passes leave dead instructions in the arenas (more than half of them in
    // large programs); the backends and the runner's copy need only the live ones.
    for f in &mut module.funcs {
        f.compact();
    }
}
