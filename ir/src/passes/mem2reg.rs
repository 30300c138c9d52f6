//! Promotion of stack slots to SSA values (Cytron et al.: block parameters at the
//! iterated dominance frontier of the stores, then renaming along the dominator tree).
//!
//! A slot is promoted when it holds a scalar and every use of every `slot_addr` of it
//! is the address operand of a load or store of exactly that scalar type: then nothing
//! else can observe the memory, and each load reads the value of the last store on its
//! path. Parameters are only placed for slots that are live across blocks (loaded in
//! some block before being stored there: "semi-pruned" SSA); the dead ones that remain
//! are left to [`crate::passes::dce`].
//!
//! A load no store reaches reads an undefined value (front ends always initialise, so
//! this is only robustness): it becomes a zero constant of its type, or for a `ptr`,
//! which has no constant, the address of the slot itself (kept declared for that).
//!
//! Promoted slots (and slots no instruction refers to) are removed from the function
//! and the remaining ones renumbered, so that static frames (PIC16) shrink too.

use crate::dominators::DomTree;
use crate::entities::{Block, Inst, SlotId, Value};
use crate::function::Function;
use crate::inst::{BlockCall, InstData};
use crate::passes::util::{dest_mut, ValueMap};
use crate::types::{MemType, Type};

const NONE: u32 = u32::MAX;

/// Promotes the promotable scalar stack slots of `func` to SSA values. Unreachable
/// blocks are dropped from the layout first (they would otherwise keep loads of
/// removed slots). Returns true if the function changed.
pub fn run(func: &mut Function) -> bool {
    let nslots = func.slots.len();
    if nslots == 0 || func.layout.is_empty() {
        return false;
    }
    let slot_ty: Vec<Option<Type>> = func
        .slots
        .iter()
        .map(|s| match s.ty {
            MemType::Scalar(t) => Some(t),
            MemType::Agg(_) => None,
        })
        .collect();
    let mut changed = false;

    let mut dt = DomTree::compute(func);
    if dt.rpo().len() != func.layout.len() {
        func.layout.retain(|&b| dt.is_reachable(b));
        changed = true;
    }

    // Which values are addresses of which slot, and whether each slot is promotable.
    let mut addr_slot = vec![NONE; func.values.len()];
    let mut referenced = vec![false; nslots];
    let mut ok: Vec<bool> = slot_ty.iter().map(Option::is_some).collect();
    for (_, i) in func.inst_iter() {
        if let InstData::SlotAddr { slot } = func.inst(i) {
            referenced[slot.index()] = true;
            if let Some(r) = func.result(i) {
                addr_slot[r.index()] = slot.0;
            }
        }
    }
    let slot_of = |v: Value| addr_slot.get(v.index()).copied().unwrap_or(NONE);
    for (_, i) in func.inst_iter() {
        match func.inst(i) {
            InstData::Load { ty, addr } => {
                let s = slot_of(*addr);
                if s != NONE && slot_ty[s as usize] != Some(*ty) {
                    ok[s as usize] = false;
                }
            }
            InstData::Store { value, addr } => {
                let sv = slot_of(*value);
                if sv != NONE {
                    ok[sv as usize] = false; // the address escapes into memory
                }
                let s = slot_of(*addr);
                if s != NONE && slot_ty[s as usize] != Some(func.value_type(*value)) {
                    ok[s as usize] = false;
                }
            }
            data => data.for_each_arg(|a| {
                let s = slot_of(a);
                if s != NONE {
                    ok[s as usize] = false;
                }
            }),
        }
    }
    let mut remove: Vec<bool> = (0..nslots).map(|s| ok[s] || !referenced[s]).collect();
    if !remove.iter().any(|&r| r) {
        return changed;
    }
    changed = true;

    if ok.iter().zip(&referenced).any(|(&o, &r)| o && r) {
        let entry = func.layout[0];
        if !dt.preds(entry).is_empty() {
            // Block parameters cannot go on the entry (they are the function's): give
            // the function a fresh entry that jumps to the old one.
            split_entry(func);
            dt = DomTree::compute(func);
        }
        if let Some(kept) = promote(func, &dt, &slot_ty, &ok, &addr_slot) {
            remove[kept.index()] = false;
        }
    }
    renumber_slots(func, &remove);
    changed
}

/// Puts a new entry block, taking the function's parameters, in front of the old one.
fn split_entry(func: &mut Function) {
    let old = func.layout[0];
    let new = func.create_block();
    let tys: Vec<Type> = func.blocks[old.index()]
        .params
        .iter()
        .map(|&p| func.value_type(p))
        .collect();
    let args: Vec<Value> = tys
        .into_iter()
        .map(|ty| func.append_block_param(new, ty))
        .collect();
    let jump = func.create_inst(
        InstData::Jump {
            dest: BlockCall::new(old, args),
        },
        None,
        None,
    );
    func.blocks[new.index()].insts.push(jump);
    func.layout.insert(0, new);
}

/// Places block parameters and renames loads and stores of the slots with `ok` set.
/// Returns the slot whose address stands for an undefined pointer, if one was needed
/// (it must stay declared).
fn promote(
    func: &mut Function,
    dt: &DomTree,
    slot_ty: &[Option<Type>],
    ok: &[bool],
    addr_slot: &[u32],
) -> Option<SlotId> {
    let nslots = slot_ty.len();
    let nblocks = func.blocks.len();
    let promoted_slot = |v: Value| -> Option<usize> {
        let s = *addr_slot.get(v.index())?;
        (s != NONE && ok[s as usize]).then_some(s as usize)
    };

    // Blocks storing each slot, and slots read before written in some block (only
    // those can need parameters).
    let mut def_blocks: Vec<Vec<Block>> = vec![Vec::new(); nslots];
    let mut last_store_block = vec![NONE; nslots];
    let mut live_in = vec![false; nslots];
    for &b in dt.rpo() {
        for &i in &func.blocks[b.index()].insts {
            match func.inst(i) {
                InstData::Load { addr, .. } => {
                    if let Some(s) = promoted_slot(*addr) {
                        if last_store_block[s] != b.0 {
                            live_in[s] = true;
                        }
                    }
                }
                InstData::Store { addr, .. } => {
                    if let Some(s) = promoted_slot(*addr) {
                        if last_store_block[s] != b.0 {
                            last_store_block[s] = b.0;
                            def_blocks[s].push(b);
                        }
                    }
                }
                _ => {}
            }
        }
    }

    // Parameter placement at the iterated dominance frontier.
    let mut phis: Vec<Vec<(u32, Value)>> = vec![Vec::new(); nblocks];
    if (0..nslots).any(|s| live_in[s] && !def_blocks[s].is_empty()) {
        let df = dt.frontiers();
        let mut has_phi = vec![NONE; nblocks];
        let mut queued = vec![NONE; nblocks];
        let mut work: Vec<Block> = Vec::new();
        for s in 0..nslots {
            if !live_in[s] || def_blocks[s].is_empty() {
                continue;
            }
            let ty = slot_ty[s].expect("promoted slots are scalar");
            work.clear();
            for &b in &def_blocks[s] {
                queued[b.index()] = s as u32;
                work.push(b);
            }
            while let Some(b) = work.pop() {
                for &d in df.frontier(b) {
                    if has_phi[d.index()] == s as u32 {
                        continue;
                    }
                    has_phi[d.index()] = s as u32;
                    let p = func.append_block_param(d, ty);
                    phis[d.index()].push((s as u32, p));
                    if queued[d.index()] != s as u32 {
                        queued[d.index()] = s as u32;
                        work.push(d);
                    }
                }
            }
        }
    }

    // Renaming along the dominator tree, with an undo log instead of per-slot stacks.
    let mut cur: Vec<Option<Value>> = vec![None; nslots];
    let mut undo: Vec<(u32, Option<Value>)> = Vec::new();
    let mut dead = vec![false; func.insts.len()];
    let mut vmap = ValueMap::new(func);
    let mut zeros = Zeros::default();
    enum Step {
        Enter(Block),
        Exit(usize),
    }
    let mut stack = vec![Step::Enter(func.layout[0])];
    while let Some(step) = stack.pop() {
        let b = match step {
            Step::Exit(mark) => {
                while undo.len() > mark {
                    let (s, v) = undo.pop().expect("undo holds more than mark");
                    cur[s as usize] = v;
                }
                continue;
            }
            Step::Enter(b) => b,
        };
        stack.push(Step::Exit(undo.len()));
        for &(s, p) in &phis[b.index()] {
            undo.push((s, cur[s as usize]));
            cur[s as usize] = Some(p);
        }
        for k in 0..func.blocks[b.index()].insts.len() {
            let i = func.blocks[b.index()].insts[k];
            match *func.inst(i) {
                InstData::SlotAddr { slot } if ok[slot.index()] => dead[i.index()] = true,
                InstData::Load { ty, addr } => {
                    if let Some(s) = promoted_slot(addr) {
                        let v = match cur[s] {
                            Some(v) => v,
                            None => zeros.get(func, ty, SlotId::new(s)),
                        };
                        vmap.set(func.result(i).expect("load has a result"), v);
                        dead[i.index()] = true;
                    }
                }
                InstData::Store { value, addr } => {
                    if let Some(s) = promoted_slot(addr) {
                        undo.push((s as u32, cur[s]));
                        cur[s] = Some(value);
                        dead[i.index()] = true;
                    }
                }
                InstData::Jump { .. } | InstData::Brif { .. } | InstData::BrTable { .. } => {
                    for which in 0..func.inst(i).dest_count() as u32 {
                        let Some(d) = func.inst(i).dest(which as usize).map(|d| d.block) else {
                            continue;
                        };
                        if phis[d.index()].is_empty() {
                            continue;
                        }
                        let mut args = Vec::with_capacity(phis[d.index()].len());
                        for &(s, _) in &phis[d.index()] {
                            let s = s as usize;
                            args.push(match cur[s] {
                                Some(v) => v,
                                None => zeros.get(
                                    func,
                                    slot_ty[s].expect("a promoted slot has a type"),
                                    SlotId::new(s),
                                ),
                            });
                        }
                        dest_mut(func.inst_mut(i), which).args.extend(args);
                    }
                }
                _ => {}
            }
        }
        for &c in dt.children(b).iter().rev() {
            stack.push(Step::Enter(c));
        }
    }

    for &b in &func.layout {
        func.blocks[b.index()]
            .insts
            .retain(|i| !dead.get(i.index()).copied().unwrap_or(false));
    }
    if !zeros.insts.is_empty() {
        let entry = func.layout[0].index();
        let mut insts = std::mem::take(&mut zeros.insts);
        insts.append(&mut func.blocks[entry].insts);
        func.blocks[entry].insts = insts;
    }
    vmap.apply(func);
    zeros.ptr_slot
}

/// Zero constants for reads of never-stored slots, one per type, placed at the start
/// of the entry block (which dominates every use).
#[derive(Default)]
struct Zeros {
    by_type: [Option<Value>; 8],
    insts: Vec<Inst>,
    /// The slot whose address serves as the undefined pointer.
    ptr_slot: Option<SlotId>,
}

impl Zeros {
    /// The value read from the never-stored `slot` of type `ty`.
    fn get(&mut self, func: &mut Function, ty: Type, slot: SlotId) -> Value {
        let k = ty as usize;
        if let Some(v) = self.by_type[k] {
            return v;
        }
        let data = if ty.is_float() {
            InstData::Fconst { ty, bits: 0 }
        } else if ty == Type::Ptr {
            // There is no null pointer constant. Any valid address will do for a
            // pointer variable read before it is written (a front-end bug): use the
            // slot's own, and keep the slot declared.
            self.ptr_slot = Some(slot);
            InstData::SlotAddr { slot }
        } else {
            InstData::Iconst { ty, imm: 0 }
        };
        let i = func.create_inst(data, Some(ty), None);
        let v = func.result(i).expect("created with a result");
        self.insts.push(i);
        self.by_type[k] = Some(v);
        v
    }
}

/// Drops the slots marked in `remove` and renumbers the `slot_addr`s of the others.
fn renumber_slots(func: &mut Function, remove: &[bool]) {
    let mut new_id = vec![NONE; remove.len()];
    let old = std::mem::take(&mut func.slots);
    for (k, slot) in old.into_iter().enumerate() {
        if !remove[k] {
            new_id[k] = func.slots.len() as u32;
            func.slots.push(slot);
        }
    }
    for bi in 0..func.layout.len() {
        let b = func.layout[bi];
        for k in 0..func.blocks[b.index()].insts.len() {
            let i = func.blocks[b.index()].insts[k];
            if let InstData::SlotAddr { slot } = func.inst_mut(i) {
                debug_assert_ne!(new_id[slot.index()], NONE, "a removed slot is still used");
                *slot = SlotId(new_id[slot.index()]);
            }
        }
    }
}
