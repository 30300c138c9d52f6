//! Watchdog checks on loop back edges.
//!
//! A PLC program that loops forever must not hang the tools that run it. This pass
//! puts a `stop_requested` check on every loop back edge; when the running machine's
//! watchdog fires, the check leaves the function at once (returning zero), every
//! enclosing loop leaves its function the same way, and the scan ends, so the machine
//! can report the overrun. It is for running code under the runner (`plcc run`,
//! `plcc test`); code for a real controller is built without it.

use crate::dominators::DomTree;
use crate::entities::Block;
use crate::function::Function;
use crate::inst::{BlockCall, InstData, Intrinsic};
use crate::module::Module;
use crate::types::Type;

/// Adds the checks to every function of the module; returns true if it added any.
pub fn run(module: &mut Module) -> bool {
    let mut changed = false;
    for f in &mut module.funcs {
        changed |= run_function(f);
    }
    changed
}

/// Adds the checks to one function.
pub fn run_function(f: &mut Function) -> bool {
    if f.layout.is_empty() {
        return false;
    }
    let dom = DomTree::compute(f);
    // Back edges: a destination that dominates the source.
    let mut edges: Vec<(Block, usize)> = Vec::new();
    for &b in dom.rpo() {
        let Some(t) = f.terminator(b) else { continue };
        for (k, d) in f.inst(t).successors().into_iter().enumerate() {
            if dom.dominates(d.block, b) {
                edges.push((b, k));
            }
        }
    }
    if edges.is_empty() {
        return false;
    }
    // One exit block returning zero (or nothing).
    let bail = f.create_block();
    let ret = f.ret;
    let value = ret.map(|t| {
        let data = if t.is_float() {
            InstData::Fconst { ty: t, bits: 0 }
        } else {
            InstData::Iconst { ty: t, imm: 0 }
        };
        let i = f.create_inst(data, Some(t), None);
        f.blocks[bail.index()].insts.push(i);
        f.result(i).expect("constant")
    });
    let r = f.create_inst(InstData::Return { value }, None, None);
    f.blocks[bail.index()].insts.push(r);
    f.layout.push(bail);
    // Each back edge goes through a new block: check, then go on or leave.
    for (b, k) in edges {
        let t = f.terminator(b).expect("terminator");
        let check = f.create_block();
        let dest = {
            let mut dests = f.inst_mut(t).successors_mut();
            std::mem::replace(dests[k], BlockCall::new(check, Vec::new()))
        };
        let span = f.spans[t.index()];
        let stop = f.create_inst(
            InstData::Intrinsic {
                op: Intrinsic::StopRequested,
                args: Vec::new(),
            },
            Some(Type::I1),
            span,
        );
        let cond = f.result(stop).expect("flag");
        let br = f.create_inst(
            InstData::Brif {
                cond,
                then_dest: BlockCall::new(bail, Vec::new()),
                else_dest: dest,
            },
            None,
            span,
        );
        f.blocks[check.index()].insts = vec![stop, br];
        let at = f.layout.iter().position(|&x| x == b).expect("in layout");
        f.layout.insert(at + 1, check);
    }
    true
}
