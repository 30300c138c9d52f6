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
//!
//! That holds within the body; but an address can also get out in another function,
//! or in an earlier call: an init function that sets `pr := REF(r1)` leaves a pointer
//! in memory through which the body may read `r1.a` while it keeps `r1.a` in a
//! register. So a field whose address gets out anywhere in the module ([`Exposed`],
//! computed over every function first) is never promoted, nor is anything inside an
//! aggregate whose whole address gets out.

use crate::entities::{AggId, SlotId, Value};
use crate::function::{FuncKind, Function, ValueDef};
use crate::inst::InstData;
use crate::module::{AggDef, Module};
use crate::types::{MemType, Type};
use rustc_hash::{FxHashMap, FxHashSet};

/// A chain of field indexes from the instance pointer.
type Path = Vec<u32>;

/// Where promotion pays, which depends on where the target keeps SSA values
/// ([`crate::backend::TargetFacts::promotion`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Promotion {
    /// In loops, and for a variable used in several blocks: values live in registers
    /// (the JIT, C), so a variable read in three blocks is loaded once, not three
    /// times.
    #[default]
    Everywhere,
    /// In loops only: every value lives in memory anyway (plcc's VM), so outside a
    /// loop a promoted variable only gains the copies in and out; in a loop it lets
    /// the other passes work (induction variables, bounds checks).
    InLoops,
}

/// What the functions of a module let the address of out (store it, pass it to a
/// call, return it, compare it, ...): memory that a pointer read from memory may
/// reach, so that no body may keep it in a register.
#[derive(Debug, Default)]
pub struct Exposed {
    /// Fields (of a struct type, in every instance of it) whose address, or the
    /// address of something inside which, gets out.
    fields: FxHashSet<(AggId, u32)>,
    /// Aggregates the address of a whole instance of which gets out.
    whole: FxHashSet<AggId>,
    /// An address of an instance of unknown type gets out: nothing is promoted.
    all: bool,
}

impl Exposed {
    /// What the functions of `module` let out. A pointer passed to a call gets out
    /// only if the callee lets that parameter out (stores it, passes it on, ...), or
    /// if the call is bound at run time.
    pub fn of(module: &Module) -> Exposed {
        let params_out = crate::parallel::map(&module.funcs, params_let_out);
        let each = crate::parallel::map(&module.funcs, |f| exposed_by(module, &params_out, f));
        let mut all = Exposed::default();
        for e in each {
            all.fields.extend(e.fields);
            all.whole.extend(e.whole);
            all.all |= e.all;
        }
        all
    }

    /// Whether the path of `steps` from an instance may be reached through a pointer.
    fn reaches(&self, steps: &[(AggId, u32)]) -> bool {
        self.all
            || steps
                .first()
                .is_some_and(|(agg, _)| self.whole.contains(agg))
            || steps.iter().any(|s| self.fields.contains(s))
    }
}

/// Calls `use_` with every value `f` uses other than as the address of a load or
/// store or the base of an address computation (an element's index is no address),
/// and with whether the use is the `k`th argument of a direct call (`Some((callee,
/// k))`).
fn for_each_let_out(f: &Function, mut use_: impl FnMut(Value, Option<(usize, usize)>)) {
    for (_, i) in f.inst_iter() {
        match f.inst(i) {
            InstData::Load { .. } | InstData::FieldAddr { .. } | InstData::ElemAddr { .. } => {}
            InstData::Store { value, .. } => use_(*value, None),
            InstData::Call { func, args } => {
                for (k, &a) in args.iter().enumerate() {
                    use_(a, Some((func.index(), k)));
                }
            }
            other => other.for_each_arg(|v| use_(v, None)),
        }
    }
}

/// Which parameters of `f` (the entry block's) it lets out as they are, any use
/// counted, a call's argument included.
fn params_let_out(f: &Function) -> Vec<bool> {
    let params: &[Value] = match f.entry() {
        Some(e) => &f.block(e).params,
        None => &[],
    };
    let mut out = vec![false; params.len()];
    for_each_let_out(f, |v, _| {
        let mut v = v;
        while let ValueDef::Result(i) = f.value_def(v) {
            match f.inst(i) {
                InstData::ElemAddr { base, .. } => v = *base,
                _ => return,
            }
        }
        if let Some(k) = params.iter().position(|&p| p == v) {
            out[k] = true;
        }
    });
    out
}

/// What one function lets out: the fields (and data objects, and its own instance)
/// of the address computations each value it lets out comes from.
fn exposed_by(module: &Module, params_out: &[Vec<bool>], f: &Function) -> Exposed {
    let mut out = Exposed::default();
    // The instance's type: what a `field_addr` on the entry's first parameter names.
    let this = f
        .entry()
        .and_then(|e| f.block(e).params.first().copied())
        .filter(|_| matches!(f.kind, FuncKind::ProgramBody | FuncKind::FbBody));
    let this_agg = this.and_then(|t| {
        f.inst_iter().find_map(|(_, i)| match f.inst(i) {
            InstData::FieldAddr { base, agg, .. } if *base == t => Some(*agg),
            _ => None,
        })
    });
    for_each_let_out(f, |v, call| {
        if let Some((callee, k)) = call {
            if !params_out
                .get(callee)
                .and_then(|p| p.get(k))
                .copied()
                .unwrap_or(true)
            {
                return;
            }
        }
        let mut v = v;
        let mut field = false;
        loop {
            match f.value_def(v) {
                ValueDef::Result(i) => match f.inst(i) {
                    InstData::FieldAddr {
                        base,
                        agg,
                        field: k,
                    } => {
                        out.fields.insert((*agg, *k));
                        field = true;
                        v = *base;
                    }
                    InstData::ElemAddr { base, .. } => v = *base,
                    InstData::GlobalAddr { data } => {
                        if let (false, Some(MemType::Agg(agg))) =
                            (field, module.data.get(data.index()).map(|d| d.ty))
                        {
                            out.whole.insert(agg);
                        }
                        break;
                    }
                    _ => break,
                },
                ValueDef::Param(..) => {
                    if !field && Some(v) == this {
                        match this_agg {
                            Some(agg) => {
                                out.whole.insert(agg);
                            }
                            None => out.all = true,
                        }
                    }
                    break;
                }
            }
        }
    });
    out
}

/// Promotes the non-escaping scalar instance fields of `f`, if it is a PROGRAM or FB
/// body (`aggs`: the module's aggregates), leaving alone what `exposed` says other
/// code may reach. Says whether it changed; run `mem2reg` on it then.
pub fn run_function(
    aggs: &[AggDef],
    exposed: &Exposed,
    promotion: Promotion,
    f: &mut Function,
) -> bool {
    matches!(f.kind, FuncKind::ProgramBody | FuncKind::FbBody)
        && promote_function(aggs, exposed, promotion, f)
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

fn promote_function(
    aggs: &[AggDef],
    exposed: &Exposed,
    promotion: Promotion,
    f: &mut Function,
) -> bool {
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
        if !p.in_loop && (promotion == Promotion::InLoops || p.blocks.len() < MIN_BLOCKS) {
            continue;
        }
        if ancestor_escapes(&paths, &index, id) || exposed.reaches(&p.steps) {
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
