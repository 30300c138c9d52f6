//! Promotion of instance variables to SSA values within one call.
//!
//! A PROGRAM or FUNCTION_BLOCK body reads and writes its variables in the instance
//! memory its first parameter points to. Inside one call nothing else can see that
//! memory unless the body hands an address out (to a call, a store, an array access).
//! So every scalar field reached from the instance by a chain of `field_addr` whose
//! address never escapes is loaded once at entry into a stack slot, used there, and
//! stored back before every return (only if it was written); `mem2reg` then turns the
//! slot into SSA values. A loop over program variables then runs in registers.
//!
//! An address escapes when it is used other than as the base of a `field_addr` or the
//! address of a load or store: then it and everything inside it stay in memory.

use crate::entities::{AggId, SlotId, Value};
use crate::function::{FuncKind, Function, ValueDef};
use crate::inst::InstData;
use crate::module::AggDef;
use crate::types::{MemType, Type};
use rustc_hash::FxHashMap;

/// A chain of field indexes from the instance pointer.
type Path = Vec<u32>;

/// Promotes the non-escaping scalar instance fields of `f`, if it is a PROGRAM or FB
/// body (`aggs`: the module's aggregates). Says whether it changed; run `mem2reg` on
/// it then.
pub fn run_function(aggs: &[AggDef], f: &mut Function) -> bool {
    matches!(f.kind, FuncKind::ProgramBody | FuncKind::FbBody) && promote_function(aggs, f)
}

/// What is known about one path.
struct PathInfo {
    /// The struct the last step indexes (for rebuilding the address).
    steps: Vec<(AggId, u32)>,
    /// The scalar type loaded and stored through it, if consistent.
    ty: Option<Type>,
    /// Some use other than field_addr/load/store, or loads/stores of mixed types.
    escapes: bool,
    /// Stored somewhere in the function.
    written: bool,
    /// Accessed by a load or store at all.
    accessed: bool,
    /// Accessed inside a loop.
    in_loop: bool,
    /// Distinct blocks with an access (counted up to a few).
    blocks: Vec<crate::entities::Block>,
}

fn promote_function(aggs: &[AggDef], f: &mut Function) -> bool {
    let Some(entry) = f.entry() else { return false };
    let Some(&this) = f.block(entry).params.first() else {
        return false;
    };
    // Map values that are paths from the instance pointer.
    let mut path_of: FxHashMap<Value, usize> = FxHashMap::default();
    let mut paths: Vec<PathInfo> = Vec::new();
    let mut index: FxHashMap<Path, usize> = FxHashMap::default();
    index.insert(Vec::new(), 0);
    paths.push(PathInfo {
        steps: Vec::new(),
        ty: None,
        escapes: false,
        written: false,
        accessed: false,
        in_loop: false,
        blocks: Vec::new(),
    });
    path_of.insert(this, 0);
    // Layout order visits definitions before uses within a block; a field_addr whose
    // base is defined in a later block is treated as an unknown pointer, which is
    // safe only if its base then escapes — so iterate until no new paths appear.
    let mut grew = true;
    while grew {
        grew = false;
        for (_, i) in f.inst_iter() {
            if let InstData::FieldAddr { base, agg, field } = f.inst(i) {
                let (Some(&bp), Some(r)) = (path_of.get(base), f.result(i)) else {
                    continue;
                };
                if path_of.contains_key(&r) {
                    continue;
                }
                let mut key: Path = paths_key(&paths[bp]);
                key.push(*field);
                let id = *index.entry(key).or_insert_with(|| {
                    let mut steps = paths[bp].steps.clone();
                    steps.push((*agg, *field));
                    paths.push(PathInfo {
                        steps,
                        ty: None,
                        escapes: false,
                        written: false,
                        accessed: false,
                        in_loop: false,
                        blocks: Vec::new(),
                    });
                    paths.len() - 1
                });
                path_of.insert(r, id);
                grew = true;
            }
        }
    }
    // Classify every use of a path value.
    let looped = loop_blocks(f);
    for (b, i) in f.inst_iter() {
        let data = f.inst(i);
        match data {
            InstData::FieldAddr { .. } => {
                // A base use: fine (the result is a path, or the base escapes below if
                // the result could not be mapped, which cannot happen here).
            }
            InstData::Load { ty, addr } => {
                if let Some(&p) = path_of.get(addr) {
                    note_access(&mut paths[p], *ty, false);
                    note_block(&mut paths[p], b, looped[b.index()]);
                }
            }
            InstData::Store { value, addr } => {
                if let Some(&p) = path_of.get(value) {
                    paths[p].escapes = true;
                }
                if let Some(&p) = path_of.get(addr) {
                    let ty = f.value_type(*value);
                    note_access(&mut paths[p], ty, true);
                    note_block(&mut paths[p], b, looped[b.index()]);
                }
            }
            other => other.for_each_arg(|v| {
                if let Some(&p) = path_of.get(&v) {
                    paths[p].escapes = true;
                }
            }),
        }
    }
    // A path is promotable if it is a scalar field, accessed, and neither it nor any
    // ancestor escapes. It is worth promoting when it is used in a loop or in several
    // blocks: within one block, load/store forwarding already keeps it in a register,
    // and promotion would only add the entry load and the exit store.
    let mut promote: Vec<usize> = Vec::new();
    for (id, p) in paths.iter().enumerate() {
        if id == 0 || p.escapes || !p.accessed || p.ty.is_none() {
            continue;
        }
        if !p.in_loop && p.blocks.len() < MIN_BLOCKS {
            continue;
        }
        if ancestor_escapes(&paths, &index, id) {
            continue;
        }
        let (agg, field) = *p.steps.last().expect("non-root path");
        let AggDef::Struct(s) = &aggs[agg.index()] else {
            continue;
        };
        match s.fields.get(field as usize).map(|fd| fd.ty) {
            Some(MemType::Scalar(t)) if Some(t) == p.ty => promote.push(id),
            _ => {}
        }
    }
    if promote.is_empty() {
        return false;
    }
    // One slot per promoted path; loads and stores go to it.
    let mut slot_of: FxHashMap<usize, SlotId> = FxHashMap::default();
    for &id in &promote {
        let t = paths[id].ty.expect("typed");
        slot_of.insert(
            id,
            f.create_slot(format!("promoted{id}"), MemType::Scalar(t)),
        );
    }
    let mut slot_addr_of: FxHashMap<usize, Value> = FxHashMap::default();
    // Prologue at the start of the entry block: slot_addr, field address, load, store.
    let mut prologue = Vec::new();
    for &id in &promote {
        let slot = slot_of[&id];
        let sa = f.create_inst(InstData::SlotAddr { slot }, Some(Type::Ptr), None);
        prologue.push(sa);
        let sav = f.result(sa).expect("address");
        slot_addr_of.insert(id, sav);
        let (addr, mut insts) = build_path(f, this, &paths[id].steps);
        prologue.append(&mut insts);
        let t = paths[id].ty.expect("typed");
        let ld = f.create_inst(InstData::Load { ty: t, addr }, Some(t), None);
        prologue.push(ld);
        let v = f.result(ld).expect("loaded");
        prologue.push(f.create_inst(
            InstData::Store {
                value: v,
                addr: sav,
            },
            None,
            None,
        ));
    }
    // Redirect accesses.
    let live: Vec<crate::entities::Inst> = f.inst_iter().map(|(_, i)| i).collect();
    for i in live {
        let new_addr = match f.inst(i) {
            InstData::Load { addr, .. } | InstData::Store { addr, .. } => {
                path_of.get(addr).and_then(|p| slot_addr_of.get(p)).copied()
            }
            _ => None,
        };
        if let Some(sa) = new_addr {
            match f.inst_mut(i) {
                InstData::Load { addr, .. } | InstData::Store { addr, .. } => *addr = sa,
                _ => {}
            }
        }
    }
    // Epilogue before every return: write back the fields that were written.
    let blocks: Vec<crate::entities::Block> = f.layout.clone();
    for b in blocks {
        let Some(term) = f.terminator(b) else {
            continue;
        };
        if !matches!(f.inst(term), InstData::Return { .. }) {
            continue;
        }
        let mut epilogue = Vec::new();
        for &id in &promote {
            if !paths[id].written {
                continue;
            }
            let t = paths[id].ty.expect("typed");
            let slot = slot_of[&id];
            let sa = f.create_inst(InstData::SlotAddr { slot }, Some(Type::Ptr), None);
            epilogue.push(sa);
            let sav = f.result(sa).expect("address");
            let ld = f.create_inst(InstData::Load { ty: t, addr: sav }, Some(t), None);
            epilogue.push(ld);
            let v = f.result(ld).expect("loaded");
            let (addr, mut insts) = build_path(f, this, &paths[id].steps);
            epilogue.append(&mut insts);
            epilogue.push(f.create_inst(InstData::Store { value: v, addr }, None, None));
        }
        let insts = &mut f.blocks[b.index()].insts;
        let at = insts.len() - 1;
        insts.splice(at..at, epilogue);
    }
    let entry_insts = &mut f.blocks[entry.index()].insts;
    entry_insts.splice(0..0, prologue);
    debug_assert!(matches!(f.value_def(this), ValueDef::Param(..)));
    true
}

/// A variable used in this many blocks (outside loops) is promoted.
const MIN_BLOCKS: usize = 3;

fn note_block(p: &mut PathInfo, b: crate::entities::Block, in_loop: bool) {
    p.in_loop |= in_loop;
    if p.blocks.len() < MIN_BLOCKS && !p.blocks.contains(&b) {
        p.blocks.push(b);
    }
}

/// Which blocks lie on a cycle: the natural loops of the headers that back edges (an
/// edge to a block that dominates its source) enter.
fn loop_blocks(f: &Function) -> Vec<bool> {
    let dom = crate::dominators::DomTree::compute(f);
    let mut in_loop = vec![false; f.blocks.len()];
    for &h in dom.rpo() {
        if dom.preds(h).iter().any(|&p| dom.dominates(h, p)) {
            for b in dom.natural_loop(h) {
                in_loop[b.index()] = true;
            }
        }
    }
    in_loop
}

fn paths_key(p: &PathInfo) -> Path {
    p.steps.iter().map(|&(_, f)| f).collect()
}

fn note_access(p: &mut PathInfo, ty: Type, write: bool) {
    p.accessed = true;
    p.written |= write;
    match p.ty {
        None => p.ty = Some(ty),
        Some(t) if t == ty => {}
        Some(_) => p.escapes = true,
    }
}

fn ancestor_escapes(paths: &[PathInfo], index: &FxHashMap<Path, usize>, id: usize) -> bool {
    let key = paths_key(&paths[id]);
    (0..key.len()).any(|n| index.get(&key[..n]).is_some_and(|&a| paths[a].escapes))
}

/// Instructions computing the address of a path from the instance pointer.
fn build_path(
    f: &mut Function,
    this: Value,
    steps: &[(AggId, u32)],
) -> (Value, Vec<crate::entities::Inst>) {
    let mut insts = Vec::new();
    let mut addr = this;
    for &(agg, field) in steps {
        let i = f.create_inst(
            InstData::FieldAddr {
                base: addr,
                agg,
                field,
            },
            Some(Type::Ptr),
            None,
        );
        insts.push(i);
        addr = f.result(i).expect("address");
    }
    (addr, insts)
}
