//! Control-flow graph simplification.
//!
//! - `brif` or `br_table` on a constant, or whose destinations are all the same,
//!   becomes a `jump`;
//! - an edge into a block that only jumps on (an empty forwarder, whose parameters
//!   nothing but that jump reads) goes straight to the forwarder's destination, with
//!   the forwarder's arguments (its own parameters replaced by the edge's arguments).
//!   The forwarder's other arguments are defined in its strict dominators, which
//!   dominate all its predecessors, so they stay valid at the new use;
//! - blocks unreachable from the entry leave the layout;
//! - a block whose only predecessor ends in a `jump` to it is appended to that
//!   predecessor, its parameters replaced by the jump's arguments.
//!
//! The entry block stays first and is never merged into another block.

use crate::dominators::reverse_postorder;
use crate::entities::{Block, Value};
use crate::function::Function;
use crate::inst::{BlockCall, InstData};
use crate::passes::util::{dest_mut, int_const, ValueMap};

/// How many forwarders one edge is threaded through per run (cycles of empty blocks
/// must not loop forever; longer chains finish in the next run).
const MAX_THREAD: usize = 8;

/// Simplifies the CFG of `func`. Returns true if the function changed.
pub fn run(func: &mut Function) -> bool {
    let Some(entry) = func.entry() else {
        return false;
    };
    let mut changed = fold_branches(func);
    changed |= thread_jumps(func, entry);
    changed |= remove_unreachable(func);
    changed |= merge_blocks(func, entry);
    changed
}

/// `brif` and `br_table` with a constant operand or identical destinations become
/// `jump`s.
fn fold_branches(func: &mut Function) -> bool {
    let mut changed = false;
    for bi in 0..func.layout.len() {
        let b = func.layout[bi];
        let Some(t) = func.terminator(b) else {
            continue;
        };
        let dest = match func.inst(t) {
            InstData::Brif {
                cond,
                then_dest,
                else_dest,
            } => match int_const(func, *cond) {
                Some(c) if c & 1 != 0 => (**then_dest).clone(),
                Some(_) => (**else_dest).clone(),
                None if then_dest == else_dest => (**then_dest).clone(),
                None => continue,
            },
            InstData::BrTable {
                arg,
                default,
                table,
            } => match int_const(func, *arg) {
                Some(c) => {
                    let u = func.value_type(*arg).zext_bits(c);
                    let k = usize::try_from(u).ok().filter(|&k| k < table.len());
                    k.map_or(&**default, |k| &table[k]).clone()
                }
                None if table.iter().all(|d| d == &**default) => (**default).clone(),
                None => continue,
            },
            _ => continue,
        };
        *func.inst_mut(t) = InstData::Jump { dest };
        changed = true;
    }
    changed
}

/// If `b` is an empty forwarder (`jump` only, not to itself) whose parameters only
/// its own jump reads, its destination. (A parameter used further on, in a block `b`
/// dominates, must keep being defined by `b`.)
fn forwarder<'f>(
    func: &'f Function,
    b: Block,
    entry: Block,
    uses: &[u32],
) -> Option<&'f BlockCall> {
    if b == entry {
        return None;
    }
    let insts = &func.blocks[b.index()].insts;
    if insts.len() != 1 {
        return None;
    }
    match func.inst(insts[0]) {
        InstData::Jump { dest } if dest.block != b => {
            let params = &func.blocks[b.index()].params;
            let local_only = params.iter().all(|&p| {
                let in_jump = dest.args.iter().filter(|&&a| a == p).count();
                uses.get(p.index()).is_some_and(|&n| n as usize == in_jump)
            });
            local_only.then_some(dest)
        }
        _ => None,
    }
}

/// The number of uses of every value by the instructions of the layout.
fn use_counts(func: &Function) -> Vec<u32> {
    let mut uses = vec![0u32; func.values.len()];
    for (_, i) in func.inst_iter() {
        func.inst(i).for_each_arg(|a| uses[a.index()] += 1);
    }
    uses
}

/// Redirects every edge that enters an empty forwarder to the forwarder's destination.
fn thread_jumps(func: &mut Function, entry: Block) -> bool {
    let mut changed = false;
    let mut visited: Vec<Block> = Vec::with_capacity(MAX_THREAD);
    // Use counts are only needed when some forwarder has parameters.
    let any_params = func.layout.iter().any(|&b| {
        !func.blocks[b.index()].params.is_empty() && func.blocks[b.index()].insts.len() == 1
    });
    let uses = if any_params {
        use_counts(func)
    } else {
        Vec::new()
    };
    for bi in 0..func.layout.len() {
        let b = func.layout[bi];
        let Some(t) = func.terminator(b) else {
            continue;
        };
        for which in 0..func.inst(t).dest_count() as u32 {
            let Some(mut call) = func.inst(t).dest(which as usize).cloned() else {
                continue;
            };
            visited.clear();
            let mut cycle = false;
            while visited.len() < MAX_THREAD {
                let Some(next) = forwarder(func, call.block, entry, &uses) else {
                    break;
                };
                let params = &func.blocks[call.block.index()].params;
                if params.len() != call.args.len() {
                    break; // malformed: leave it to the verifier
                }
                visited.push(call.block);
                if visited.contains(&next.block) {
                    // An endless loop of empty blocks: leave the edge as it is rather
                    // than rotating it around the loop on every run.
                    cycle = true;
                    break;
                }
                let args: Vec<Value> = next
                    .args
                    .iter()
                    .map(|&a| match params.iter().position(|&p| p == a) {
                        Some(k) => call.args[k],
                        None => a,
                    })
                    .collect();
                call = BlockCall::new(next.block, args);
            }
            if !cycle && !visited.is_empty() {
                *dest_mut(func.inst_mut(t), which) = call;
                changed = true;
            }
        }
    }
    changed
}

/// Drops blocks unreachable from the entry from the layout.
fn remove_unreachable(func: &mut Function) -> bool {
    let reachable = reverse_postorder(func);
    if reachable.len() == func.layout.len() {
        return false;
    }
    let mut keep = vec![false; func.blocks.len()];
    for b in reachable {
        keep[b.index()] = true;
    }
    func.layout.retain(|b| keep[b.index()]);
    true
}

/// Appends each block to its single predecessor when that predecessor jumps to it.
fn merge_blocks(func: &mut Function, entry: Block) -> bool {
    let n = func.blocks.len();
    let mut npreds = vec![0u32; n];
    for &b in &func.layout {
        if let Some(t) = func.terminator(b) {
            for d in func.inst(t).dests() {
                npreds[d.block.index()] += 1;
            }
        }
    }
    let mut removed = vec![false; n];
    let mut vmap = ValueMap::new(func);
    let mut changed = false;
    for bi in 0..func.layout.len() {
        let p = func.layout[bi];
        if removed[p.index()] {
            continue;
        }
        while let Some(t) = func.terminator(p) {
            let InstData::Jump { dest } = func.inst(t) else {
                break;
            };
            let s = dest.block;
            if s == p || s == entry || npreds[s.index()] != 1 || removed[s.index()] {
                break;
            }
            let args = dest.args.clone();
            let params = std::mem::take(&mut func.blocks[s.index()].params);
            if params.len() != args.len() {
                func.blocks[s.index()].params = params;
                break; // malformed: leave it to the verifier
            }
            for (&param, &arg) in params.iter().zip(&args) {
                vmap.set(param, arg);
            }
            let mut moved = std::mem::take(&mut func.blocks[s.index()].insts);
            let pinsts = &mut func.blocks[p.index()].insts;
            pinsts.pop();
            pinsts.append(&mut moved);
            removed[s.index()] = true;
            changed = true;
        }
    }
    if changed {
        func.layout.retain(|b| !removed[b.index()]);
        vmap.apply(func);
    }
    changed
}
