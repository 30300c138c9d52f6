//! Dead code elimination: instructions whose results nobody needs and block
//! parameters nobody reads.
//!
//! Liveness is computed by marking from the instructions that must stay (side effects,
//! terminators) through operands; a block parameter is live only if something live
//! reads it, and only then are its incoming arguments live. So cycles of parameters
//! that only feed each other around a loop die too.

use crate::entities::{Block, Value};
use crate::function::{Function, ValueDef};
use crate::inst::{InstData, Intrinsic};
use crate::passes::util::{dest_ref, int_const, remove_block_params, Incoming};

/// True if `data` must stay even when its result is unused. Sharper than
/// [`InstData::has_side_effects`]: a division by a nonzero constant cannot fault, and
/// reading the clock has no effect.
pub fn must_keep(func: &Function, data: &InstData) -> bool {
    match data {
        InstData::Binary { op, args } if op.can_fault() => {
            !matches!(int_const(func, args[1]), Some(d) if d != 0)
        }
        InstData::Intrinsic {
            op: Intrinsic::ClockMs | Intrinsic::ClockNs,
            ..
        } => false,
        _ => data.has_side_effects(),
    }
}

/// Removes dead instructions and dead parameters of non-entry blocks (with their
/// branch arguments). Returns true if the function changed.
pub fn run(func: &mut Function) -> bool {
    let Some(entry) = func.entry() else {
        return false;
    };
    let incoming = Incoming::compute(func);
    let mut live_inst = vec![false; func.insts.len()];
    let mut live_val = vec![false; func.values.len()];
    let mut work: Vec<Value> = Vec::new();

    for &b in &func.layout {
        for &i in &func.blocks[b.index()].insts {
            let data = func.inst(i);
            if !must_keep(func, data) {
                continue;
            }
            live_inst[i.index()] = true;
            match data {
                // Branch arguments are live only if their parameter is.
                InstData::Jump { .. } => {}
                InstData::Brif { cond, .. } | InstData::BrTable { arg: cond, .. } => {
                    work.push(*cond)
                }
                _ => data.for_each_arg(|a| work.push(a)),
            }
        }
    }
    while let Some(v) = work.pop() {
        if live_val[v.index()] {
            continue;
        }
        live_val[v.index()] = true;
        match func.value_def(v) {
            ValueDef::Result(i) => {
                if !live_inst[i.index()] {
                    live_inst[i.index()] = true;
                    func.inst(i).for_each_arg(|a| work.push(a));
                }
            }
            ValueDef::Param(b, k) => {
                for e in incoming.of(b) {
                    if let Some(&a) = dest_ref(func.inst(e.inst), e.which).args.get(k as usize) {
                        work.push(a);
                    }
                }
            }
        }
    }

    let mut changed = false;
    let mut keep = Vec::new();
    for bi in 0..func.layout.len() {
        let b: Block = func.layout[bi];
        let before = func.blocks[b.index()].insts.len();
        func.blocks[b.index()]
            .insts
            .retain(|i| live_inst[i.index()]);
        changed |= func.blocks[b.index()].insts.len() != before;
        if b == entry {
            continue;
        }
        keep.clear();
        keep.extend(
            func.blocks[b.index()]
                .params
                .iter()
                .map(|p| live_val[p.index()]),
        );
        if keep.iter().any(|&k| !k) {
            remove_block_params(func, b, &keep, incoming.of(b));
            changed = true;
        }
    }
    changed
}
