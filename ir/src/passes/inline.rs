//! Inlining of small functions and function block bodies into their callers.
//!
//! PLC code calls many tiny POUs (a TON per output, a helper per formula); a call
//! costs argument traffic through memory and blocks every optimisation across it.
//! Inlining a callee copies its blocks into the caller: the call's block is split, the
//! first half jumps to the copy of the callee's entry (passing the arguments as block
//! arguments), and every `return v` of the copy jumps to the second half, which takes
//! `v` as a block parameter. The call's result value keeps its number: it becomes that
//! parameter, so no use has to be rewritten.
//!
//! Callees are processed before callers (the call graph is acyclic: front ends reject
//! recursion), so inlined code is already optimised and itself inlined. A
//! `call_table` is never inlined (its callee is known only at run time); its entries
//! count as callees for the order and for reachability.

use crate::analysis::{callees, callees_first};
use crate::entities::{Block, FuncId, Inst, SlotId, Value};
use crate::function::{FuncKind, Function, ValueDef};
use crate::inst::{BlockCall, InstData};
use crate::module::Module;

/// Inline a callee with at most this many live instructions at every call site.
pub const SMALL_CALLEE: usize = 40;

/// Inline a callee called from one place only if it has at most this many live
/// instructions (inlining it adds no code, but very large bodies slow the backend's
/// register allocation down more than the call costs).
pub const SINGLE_SITE_CALLEE: usize = 40;

/// Stop growing a caller past this many live instructions.
pub const MAX_CALLER: usize = 2000;

/// Inlines small callees everywhere and single-call-site callees into their only
/// caller, callees first. Returns true if anything was inlined. `optimize` runs on
/// every function after its own callees were inlined into it, so that size estimates
/// are of optimised code.
///
/// Functions are processed level by level of the call graph (a function's level is
/// one more than its callees' highest): the functions of one level never call each
/// other, so they are inlined into and optimised on all cores at once.
pub fn run(module: &mut Module, optimize: &(dyn Fn(&mut Function) + Sync)) -> bool {
    let n = module.funcs.len();
    let mut sites = vec![0usize; n];
    for f in &module.funcs {
        for (_, i) in f.inst_iter() {
            if let InstData::Call { func, .. } = f.inst(i) {
                if func.index() < n {
                    sites[func.index()] += 1;
                }
            }
        }
    }
    let mut level = vec![0usize; n];
    for fid in callees_first(module) {
        let l = callees(module, fid.index())
            .into_iter()
            .filter(|&c| c != fid.index())
            .map(|c| level[c] + 1)
            .max()
            .unwrap_or(0);
        level[fid.index()] = l;
    }
    let top = level.iter().copied().max().unwrap_or(0);
    let mut changed = false;
    for l in 1..=top {
        // Take this level's functions out of the module; their callees stay in it.
        let placeholder = || Function::new("", FuncKind::Helper, Vec::new(), None);
        let mut batch: Vec<(usize, Function)> = (0..n)
            .filter(|&i| level[i] == l)
            .map(|i| (i, std::mem::replace(&mut module.funcs[i], placeholder())))
            .collect();
        let funcs = &module.funcs;
        let sites = &sites;
        // Weighed by the caller and the callees it may take in.
        let weight = |(_, f): &(usize, Function)| {
            f.insts.len()
                + f.inst_iter()
                    .filter_map(|(_, i)| match f.inst(i) {
                        InstData::Call { func, .. } => funcs.get(func.index()),
                        _ => None,
                    })
                    .map(|c| c.insts.len())
                    .sum::<usize>()
        };
        changed |= crate::parallel::each_mut_by(batch.iter_mut().collect(), weight, |(fid, f)| {
            inline_into(*fid, f, funcs, sites, optimize)
        });
        for (i, f) in batch {
            module.funcs[i] = f;
        }
    }
    changed
}

/// Inlines the chosen callees of one caller (`funcs` holds the callees, final by now)
/// and optimises it if anything was inlined.
fn inline_into(
    fid: usize,
    caller: &mut Function,
    funcs: &[Function],
    sites: &[usize],
    optimize: &(dyn Fn(&mut Function) + Sync),
) -> bool {
    let calls: Vec<(Block, Inst, FuncId)> = caller
        .inst_iter()
        .filter_map(|(b, i)| match caller.inst(i) {
            InstData::Call { func, .. } => Some((b, i, *func)),
            _ => None,
        })
        .collect();
    let mut did = false;
    // Last call first: splitting a block at a later call leaves the earlier calls in
    // the blocks recorded for them.
    for (block, inst, callee) in calls.into_iter().rev() {
        if callee.index() == fid || callee.index() >= funcs.len() {
            continue;
        }
        let callee_fn = &funcs[callee.index()];
        let size = callee_fn.live_inst_count();
        let small = size <= SMALL_CALLEE;
        let single = sites[callee.index()] == 1 && size <= SINGLE_SITE_CALLEE;
        if !(small || single) || caller.live_inst_count() + size > MAX_CALLER {
            continue;
        }
        if callee_fn.layout.is_empty() || !inlinable_kind(callee_fn.kind) {
            continue;
        }
        inline_call(caller, block, inst, callee_fn);
        did = true;
    }
    if did {
        optimize(caller);
    }
    did
}

/// Replaces the call `inst` in `block` of `caller` by a copy of `callee`'s body.
pub fn inline_call(caller: &mut Function, block: Block, inst: Inst, callee: &Function) {
    let InstData::Call { args, .. } = caller.inst(inst).clone() else {
        return;
    };
    let result = caller.result(inst);
    let call_span = caller.spans[inst.index()];

    // Split: the instructions after the call move to a continuation block.
    let pos = caller.blocks[block.index()]
        .insts
        .iter()
        .position(|&i| i == inst)
        .expect("call in its block");
    let rest: Vec<Inst> = caller.blocks[block.index()].insts.split_off(pos + 1);
    caller.blocks[block.index()].insts.pop(); // the call itself
    let cont = caller.create_block();
    caller.blocks[cont.index()].insts = rest;
    // The call's result becomes the continuation's parameter, keeping its number.
    if let Some(r) = result {
        caller.values[r.index()].def = ValueDef::Param(cont, 0);
        caller.blocks[cont.index()].params.push(r);
        caller.results[inst.index()] = None;
    }
    // Values defined by the moved instructions keep their definitions (an inst's
    // ValueDef names the inst, not the block), so nothing else changes.

    // Copy the callee's slots, blocks and values.
    let slot_map: Vec<SlotId> = callee
        .slots
        .iter()
        .map(|s| caller.create_slot(s.name.clone(), s.ty))
        .collect();
    let mut block_map: Vec<Option<Block>> = vec![None; callee.blocks.len()];
    for &b in &callee.layout {
        block_map[b.index()] = Some(caller.create_block());
    }
    let mut value_map: Vec<Option<Value>> = vec![None; callee.values.len()];
    for &b in &callee.layout {
        let nb = block_map[b.index()].expect("mapped");
        for &p in &callee.block(b).params {
            let ty = callee.value_type(p);
            value_map[p.index()] = Some(caller.append_block_param(nb, ty));
        }
    }
    // Create the instructions (results first, so forward uses resolve), then rewrite
    // their operands.
    let mut new_insts: Vec<(Block, Vec<(Inst, Inst)>)> = Vec::new();
    for &b in &callee.layout {
        let nb = block_map[b.index()].expect("mapped");
        let mut pairs = Vec::new();
        for &i in &callee.block(b).insts {
            let data = callee.inst(i).clone();
            let ty = callee.result(i).map(|v| callee.value_type(v));
            let span = callee.spans[i.index()].or(call_span);
            let ni = caller.create_inst(data, ty, span);
            if let (Some(old), Some(new)) = (callee.result(i), caller.result(ni)) {
                value_map[old.index()] = Some(new);
            }
            pairs.push((i, ni));
        }
        new_insts.push((nb, pairs));
    }
    let map_v =
        |v: Value, vm: &Vec<Option<Value>>| vm.get(v.index()).copied().flatten().unwrap_or(v);
    for (nb, pairs) in new_insts {
        for (_, ni) in pairs {
            let mut data = caller.insts[ni.index()].clone();
            data.map_args(|v| map_v(v, &value_map));
            if let InstData::SlotAddr { slot } = &mut data {
                *slot = slot_map[slot.index()];
            }
            for d in data.successors_mut() {
                d.block = block_map[d.block.index()].expect("destination in layout");
            }
            let data = match data {
                InstData::Return { value } => InstData::Jump {
                    dest: BlockCall::new(cont, value.into_iter().collect()),
                },
                d => d,
            };
            caller.insts[ni.index()] = data;
            caller.blocks[nb.index()].insts.push(ni);
        }
    }
    // Jump from the call site into the copy of the entry.
    let entry = block_map[callee.layout[0].index()].expect("entry mapped");
    let jump = caller.create_inst(
        InstData::Jump {
            dest: BlockCall::new(entry, args),
        },
        None,
        call_span,
    );
    caller.blocks[block.index()].insts.push(jump);
    // Layout: the copied blocks, then the continuation, right after the call block.
    let at = caller
        .layout
        .iter()
        .position(|&b| b == block)
        .expect("block in layout");
    let mut inserted: Vec<Block> = callee
        .layout
        .iter()
        .map(|b| block_map[b.index()].expect("mapped"))
        .collect();
    inserted.push(cont);
    caller.layout.splice(at + 1..at + 1, inserted);
}

/// Removes functions that nothing reachable calls: when the module has programs, only
/// program bodies, their init functions and `init_globals` (and what they call,
/// directly or through a table) stay.
/// Function ids are renumbered; returns true if any function was removed.
pub fn remove_unreachable_functions(module: &mut Module) -> bool {
    if module.programs.is_empty() {
        return false;
    }
    let n = module.funcs.len();
    let mut live = vec![false; n];
    let mut stack: Vec<usize> = Vec::new();
    for p in &module.programs {
        stack.push(p.body.index());
        stack.push(p.init.index());
    }
    if let Some(g) = module.init_globals {
        stack.push(g.index());
    }
    while let Some(f) = stack.pop() {
        if f >= n || live[f] {
            continue;
        }
        live[f] = true;
        stack.extend(callees(module, f));
    }
    if live.iter().all(|&l| l) {
        return false;
    }
    let mut new_id = vec![None; n];
    let mut funcs = Vec::new();
    for (i, f) in std::mem::take(&mut module.funcs).into_iter().enumerate() {
        if live[i] {
            new_id[i] = Some(FuncId::new(funcs.len()));
            funcs.push(f);
        }
    }
    for f in &mut funcs {
        for i in 0..f.insts.len() {
            if let InstData::Call { func, .. } = &mut f.insts[i] {
                if let Some(Some(nf)) = new_id.get(func.index()) {
                    *func = *nf;
                }
            }
        }
    }
    module.funcs = funcs;
    // A table no live function calls may name removed functions: those entries
    // become empty (nothing can reach them any more).
    for t in &mut module.tables {
        for e in &mut t.entries {
            *e = e.and_then(|f| new_id.get(f.index()).copied().flatten());
        }
    }
    let remap = |f: FuncId| new_id[f.index()].expect("live function");
    for p in &mut module.programs {
        p.body = remap(p.body);
        p.init = remap(p.init);
    }
    module.init_globals = module.init_globals.map(remap);
    true
}

/// True for the kinds of function the inliner may copy into callers.
pub fn inlinable_kind(k: FuncKind) -> bool {
    !matches!(k, FuncKind::ProgramBody)
}
