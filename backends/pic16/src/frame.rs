//! Per-function analysis before code is emitted: which values are constants or known
//! addresses (and need no RAM), which pointers are a base plus a constant offset,
//! and a home in the function's static frame for every other value, overlaid by
//! liveness.
//!
//! Addresses are symbolic here ([`Sym`]); they become numbers once every frame is
//! placed.

use crate::ram::{scalar_bytes, PicLayout};
use plcc_ir::analysis::Liveness;
use plcc_ir::function::{Function, ValueDef};
use plcc_ir::inst::{BinaryOp, InstData, Intrinsic};
use plcc_ir::{DataId, FuncId, SlotId, Type, Value};
use rustc_hash::{FxHashMap, FxHashSet};

/// A memory object whose address is fixed once RAM is laid out.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
pub enum Sym {
    /// A data object.
    Data(DataId),
    /// A stack slot of a function (static, in its frame).
    Slot(FuncId, SlotId),
}

/// What is known about a pointer value.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
pub enum Ptr {
    /// A fixed address: the object, the byte offset in it and the bit for a BOOL.
    Known(Sym, u16, u8),
    /// `base + offset` where `base` is a pointer value held in RAM; the bit if the
    /// pointee is a BOOL field (else the bit comes from the pointer at run time).
    Derived(Value, u16, Option<u8>),
}

/// How a value is represented.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum Repr {
    /// An integer constant (no RAM).
    Const(i64),
    /// A pointer with a known or derived address (no RAM of its own).
    Ptr(Ptr),
    /// A compare whose only use is the branch right after it: the flags carry it.
    Flags,
    /// Bytes in the frame at this offset.
    Bytes(u16),
    /// A bit in the frame: byte offset and bit.
    Bit(u16, u8),
    /// Defined but never used: no code.
    Unused,
    /// The value is a variable in memory, used in place: a load whose variable does
    /// not change before the value's last use, or a result computed straight into
    /// the variable it is stored to. Object, byte offset, bit.
    Mem(Sym, u16, u8),
    /// The negation of a BOOL value: tests read the other value with the opposite
    /// sense, so a `NOT` costs nothing.
    NotOf(Value),
}

/// The frame of one function: sizes and the representation of every value.
#[derive(Clone, Debug, Default)]
pub struct FrameInfo {
    /// One entry per value of the function.
    pub repr: Vec<Repr>,
    /// Bytes for values (overlaid by liveness) and bit bytes, then slots.
    pub size: u16,
    /// Offset of each stack slot.
    pub slot_offsets: Vec<u16>,
    /// Offset of the return value.
    pub ret_offset: u16,
    /// Offset of the scratch area for block-argument copies.
    pub copy_offset: u16,
    /// Functions this one calls.
    pub callees: Vec<FuncId>,
}

/// For every function, what its pointer parameters are known to be at every call
/// (the same address from every caller), computed callers first.
pub fn param_consensus(
    funcs: &[Function],
    order: &[FuncId],
    roots: &FxHashMap<FuncId, Vec<Option<Ptr>>>,
) -> Vec<Vec<Option<Ptr>>> {
    // None = no call seen yet; Some(None) = disagreement; Some(Some(p)) = agreed.
    let mut seen: Vec<Vec<Option<Option<Ptr>>>> =
        funcs.iter().map(|f| vec![None; f.params.len()]).collect();
    for (f, ps) in roots {
        for (i, p) in ps.iter().enumerate() {
            merge(&mut seen[f.index()][i], *p);
        }
    }
    let mut result: Vec<Vec<Option<Ptr>>> =
        funcs.iter().map(|f| vec![None; f.params.len()]).collect();
    for &fid in order {
        let f = &funcs[fid.index()];
        let params: Vec<Option<Ptr>> = seen[fid.index()].iter().map(|s| s.flatten()).collect();
        result[fid.index()] = params.clone();
        let ptrs = pointer_facts(f, fid, &params);
        for (_, inst) in f.inst_iter() {
            if let InstData::Call { func, args } = f.inst(inst) {
                for (i, a) in args.iter().enumerate() {
                    let p = match ptrs.get(a) {
                        Some(Ptr::Known(Sym::Data(d), o, b)) => {
                            Some(Ptr::Known(Sym::Data(*d), *o, *b))
                        }
                        Some(Ptr::Known(Sym::Slot(sf, s), o, b)) => {
                            Some(Ptr::Known(Sym::Slot(*sf, *s), *o, *b))
                        }
                        _ => None,
                    };
                    merge(&mut seen[func.index()][i], p);
                }
            }
        }
    }
    result
}

fn merge(slot: &mut Option<Option<Ptr>>, p: Option<Ptr>) {
    *slot = match *slot {
        None => Some(p),
        Some(prev) if prev == p => Some(prev),
        Some(_) => Some(None),
    };
}

/// The pointer facts of one function, given what its entry parameters are.
pub fn pointer_facts(f: &Function, fid: FuncId, params: &[Option<Ptr>]) -> FxHashMap<Value, Ptr> {
    let mut m: FxHashMap<Value, Ptr> = FxHashMap::default();
    if let Some(entry) = f.entry() {
        for (i, v) in f.block(entry).params.iter().enumerate() {
            if let Some(Some(p)) = params.get(i) {
                m.insert(*v, *p);
            }
        }
    }
    // Blocks in layout order; definitions dominate uses, and the layout starts with
    // the entry, but a use may come before its definition in layout: iterate twice.
    for _ in 0..2 {
        for &b in &f.layout {
            for &inst in &f.block(b).insts {
                let Some(res) = f.result(inst) else { continue };
                if m.contains_key(&res) {
                    continue;
                }
                let p = match f.inst(inst) {
                    InstData::GlobalAddr { data } => Some(Ptr::Known(Sym::Data(*data), 0, 0)),
                    InstData::SlotAddr { slot } => Some(Ptr::Known(Sym::Slot(fid, *slot), 0, 0)),
                    _ => None,
                };
                if let Some(p) = p {
                    m.insert(res, p);
                }
            }
        }
    }
    m
}

/// Adds field and constant-index element offsets to the facts (needs the layout).
pub fn derive_pointers(f: &Function, layout: &PicLayout, base: &mut FxHashMap<Value, Ptr>) {
    for _ in 0..3 {
        for &b in &f.layout {
            for &inst in &f.block(b).insts {
                let Some(res) = f.result(inst) else { continue };
                if base.contains_key(&res) {
                    continue;
                }
                let (bv, off, bit) = match f.inst(inst) {
                    InstData::FieldAddr {
                        base: bv,
                        agg,
                        field,
                    } => {
                        let p = layout.agg(*agg).fields[*field as usize];
                        (*bv, p.offset, Some(p.bit))
                    }
                    InstData::ElemAddr {
                        base: bv,
                        agg,
                        index,
                    } => {
                        let Some(k) = const_of(f, *index) else {
                            continue;
                        };
                        let stride = layout.agg(*agg).stride as i64;
                        let Ok(off) = u16::try_from(k * stride) else {
                            continue;
                        };
                        (*bv, off, Some(0))
                    }
                    _ => continue,
                };
                let p = match base.get(&bv) {
                    Some(Ptr::Known(s, o, _)) => Ptr::Known(*s, o + off, bit.unwrap_or(0)),
                    Some(Ptr::Derived(v, o, _)) => Ptr::Derived(*v, o + off, bit),
                    None => Ptr::Derived(bv, off, bit),
                };
                base.insert(res, p);
            }
        }
    }
}

/// The constant an `iconst` value holds.
pub fn const_of(f: &Function, v: Value) -> Option<i64> {
    match f.value_def(v) {
        ValueDef::Result(i) => match f.inst(i) {
            InstData::Iconst { imm, .. } => Some(*imm),
            _ => None,
        },
        _ => None,
    }
}

/// Computes the frame of `f`: representations, liveness-overlaid homes, slots.
pub fn build_frame(f: &Function, ptrs: &FxHashMap<Value, Ptr>, slot_sizes: &[u32]) -> FrameInfo {
    let nv = f.values.len();
    let mut uses = vec![0u32; nv];
    for (_, inst) in f.inst_iter() {
        f.inst(inst).for_each_arg(|a| uses[a.index()] += 1);
    }
    let mut repr = vec![Repr::Unused; nv];
    let mut needs_home = vec![false; nv];
    let mut callees = Vec::new();
    for &b in &f.layout {
        let insts = &f.block(b).insts;
        for &p in &f.block(b).params {
            needs_home[p.index()] = uses[p.index()] > 0;
        }
        for (k, &inst) in insts.iter().enumerate() {
            if let InstData::Call { func, .. } = f.inst(inst) {
                if !callees.contains(func) {
                    callees.push(*func);
                }
            }
            let Some(res) = f.result(inst) else { continue };
            if let Some(p) = ptrs.get(&res) {
                repr[res.index()] = Repr::Ptr(*p);
                continue;
            }
            match f.inst(inst) {
                InstData::Iconst { imm, .. } => repr[res.index()] = Repr::Const(*imm),
                // A REAL constant is its IEEE bits: copies and stores need no float code.
                InstData::Fconst { bits, .. } => repr[res.index()] = Repr::Const(*bits as i64),
                InstData::Intrinsic {
                    op: Intrinsic::StopRequested,
                    ..
                } => repr[res.index()] = Repr::Const(0),
                InstData::Icmp { .. }
                    if uses[res.index()] == 1
                        && k + 2 == insts.len()
                        && matches!(f.inst(insts[k + 1]), InstData::Brif { cond, then_dest, else_dest }
                            if *cond == res && !then_dest.args.contains(&res) && !else_dest.args.contains(&res)) =>
                {
                    repr[res.index()] = Repr::Flags
                }
                _ if uses[res.index()] == 0 && !f.inst(inst).has_side_effects() => {}
                _ => needs_home[res.index()] = true,
            }
        }
    }
    forward_memory(f, ptrs, &mut repr, &mut needs_home);
    // Entry parameters known from every caller need no home.
    if let Some(e) = f.entry() {
        for &p in &f.block(e).params {
            if let Some(ptr) = ptrs.get(&p) {
                repr[p.index()] = Repr::Ptr(*ptr);
                needs_home[p.index()] = false;
            }
        }
    }
    fold_negations(f, ptrs, &mut repr, &mut needs_home);
    // Base pointers of derived pointers, and the operands of folded negations, must
    // live as long as the values made from them: a use of one is a use of the other.
    let base_of = |mut v: Value| -> Value {
        loop {
            match repr[v.index()] {
                Repr::Ptr(Ptr::Derived(b, _, _)) => return b,
                Repr::NotOf(x) => v = x,
                _ => return v,
            }
        }
    };
    let homed = |v: Value| needs_home[v.index()];

    // Liveness (block granularity from `ir`, then per instruction): a use of a
    // derived value is a use of its base, and only values with a home count.
    let liveness = Liveness::compute(f, |inst, push| {
        f.inst(inst).for_each_arg(|a| {
            let a = base_of(a);
            if homed(a) {
                push(a);
            }
        })
    });
    // Interference.
    let mut adj: Vec<Vec<Value>> = vec![Vec::new(); nv];
    let mut hint: Vec<Option<Value>> = vec![None; nv];
    // A result and the dying first operand it may share RAM with: they do not
    // interfere, but may only overlap exactly (same first byte), never in part.
    let mut shared: Vec<Option<Value>> = vec![None; nv];
    // Block arguments prefer their parameter's place (and the other way round), so
    // that most edges copy nothing.
    for &b in &f.layout {
        let Some(t) = f.terminator(b) else { continue };
        for dest in f.inst(t).successors() {
            for (p, a) in f.block(dest.block).params.iter().zip(&dest.args) {
                let a = base_of(*a);
                if homed(*p) && homed(a) && f.values[p.index()].ty == f.values[a.index()].ty {
                    hint[p.index()].get_or_insert(a);
                    hint[a.index()].get_or_insert(*p);
                }
            }
        }
    }
    let add = |a: Value, b: Value, adj: &mut Vec<Vec<Value>>| {
        if a != b {
            adj[a.index()].push(b);
            adj[b.index()].push(a);
        }
    };
    for &b in &f.layout {
        let mut live: FxHashSet<Value> = liveness.live_out(b).collect();
        for &inst in f.block(b).insts.iter().rev() {
            let mut operands = Vec::new();
            f.inst(inst).for_each_arg(|a| {
                let a = base_of(a);
                if homed(a) {
                    operands.push(a);
                }
            });
            if let Some(r) = f.result(inst) {
                if homed(r) {
                    for &l in &live {
                        add(r, l, &mut adj);
                    }
                    // The result may take the place of a first operand that dies here
                    // (the code reads each byte of it before writing that byte).
                    let first = in_place_operand(f.inst(inst)).map(base_of);
                    let share = first.filter(|a| {
                        homed(*a)
                            && !live.contains(a)
                            && (f.values[a.index()].ty == Type::I1)
                                == (f.values[r.index()].ty == Type::I1)
                    });
                    if let Some(a) = share {
                        hint[r.index()] = Some(a);
                        shared[r.index()] = Some(a);
                    }
                    for &o in &operands {
                        if Some(o) != share {
                            add(r, o, &mut adj);
                        }
                    }
                }
                live.remove(&r);
            }
            live.extend(operands);
        }
        let params = &f.block(b).params;
        for &p in params {
            if !homed(p) {
                continue;
            }
            for &l in &live {
                add(p, l, &mut adj);
            }
            for &q in params {
                if homed(q) {
                    add(p, q, &mut adj);
                }
            }
        }
    }
    let mut sharers: Vec<Vec<Value>> = vec![Vec::new(); nv];
    for (r, a) in shared.iter().enumerate() {
        if let Some(a) = a {
            sharers[a.index()].push(Value::new(r));
        }
    }
    // Colouring: bytes first-fit, bits as colours packed eight to a byte.
    let mut byte_off: Vec<Option<(u16, u16)>> = vec![None; nv];
    let mut bit_color: Vec<Option<u32>> = vec![None; nv];
    let mut bytes_end = 0u16;
    let mut ncolors = 0u32;
    for v in 0..nv {
        if !needs_home[v] {
            continue;
        }
        let ty = f.values[v].ty;
        if ty == Type::I1 {
            let taken: FxHashSet<u32> =
                adj[v].iter().filter_map(|n| bit_color[n.index()]).collect();
            let hinted = hint[v]
                .and_then(|h| bit_color[h.index()])
                .filter(|c| !taken.contains(c));
            let c = hinted.unwrap_or_else(|| {
                (0..)
                    .find(|c| !taken.contains(c))
                    .expect("some colour is free")
            });
            bit_color[v] = Some(c);
            ncolors = ncolors.max(c + 1);
        } else {
            let size = scalar_bytes(ty) as u16;
            let mut busy: Vec<(u16, u16)> =
                adj[v].iter().filter_map(|n| byte_off[n.index()]).collect();
            // Values it may share with (see `shared`), already placed.
            let soft: Vec<(u16, u16)> = shared[v]
                .into_iter()
                .chain(sharers[v].iter().copied())
                .filter_map(|n| byte_off[n.index()])
                .collect();
            let free = |at: u16| {
                busy.iter().all(|&(s, e)| at + size <= s || at >= e)
                    && soft
                        .iter()
                        .all(|&(s, e)| at == s || at + size <= s || at >= e)
            };
            let hinted = hint[v]
                .and_then(|h| byte_off[h.index()])
                .map(|(s, _)| s)
                .filter(|&s| free(s));
            busy.extend(soft.iter().copied());
            busy.sort();
            let mut at = 0u16;
            for &(s, e) in &busy {
                if s >= at + size {
                    break;
                }
                at = at.max(e);
            }
            let at = hinted.unwrap_or(at);
            byte_off[v] = Some((at, at + size));
            bytes_end = bytes_end.max(at + size);
        }
    }
    let bits_at = bytes_end;
    for v in 0..nv {
        if let Some((s, _)) = byte_off[v] {
            repr[v] = Repr::Bytes(s);
        } else if let Some(c) = bit_color[v] {
            repr[v] = Repr::Bit(bits_at + (c / 8) as u16, (c % 8) as u8);
        }
    }
    let mut off = bits_at + ncolors.div_ceil(8) as u16;
    let mut slot_offsets = Vec::with_capacity(slot_sizes.len());
    for &s in slot_sizes {
        slot_offsets.push(off);
        off += s as u16;
    }
    let ret_offset = off;
    off += f.ret.map(|t| scalar_bytes(t) as u16).unwrap_or(0);
    let copy_offset = off;
    // Block-argument copies caught in a cycle (a parameter placed over another
    // one's argument) go through this area: room for every move that overlaps
    // another (`isel` stages only moves it cannot order).
    let bit_range = |v: Value| -> Option<(u32, u32)> {
        let mut v = v;
        while let Repr::NotOf(x) = repr[v.index()] {
            v = x;
        }
        match repr[v.index()] {
            Repr::Bytes(o) => Some((
                o as u32 * 8,
                (o as u32 + scalar_bytes(f.values[v.index()].ty)) * 8,
            )),
            Repr::Bit(o, b) => Some((o as u32 * 8 + b as u32, o as u32 * 8 + b as u32 + 1)),
            Repr::Ptr(Ptr::Derived(base, _, _)) => match repr[base.index()] {
                Repr::Bytes(o) => Some((o as u32 * 8, (o as u32 + 2) * 8)),
                _ => None,
            },
            _ => None,
        }
    };
    let mut copy_max = 0u32;
    for &b in &f.layout {
        let Some(t) = f.terminator(b) else { continue };
        for dest in f.inst(t).successors() {
            let moves: Vec<(Value, Value)> = f
                .block(dest.block)
                .params
                .iter()
                .zip(&dest.args)
                .filter(|(p, a)| p != a && !matches!(repr[p.index()], Repr::Unused))
                .map(|(p, a)| (*p, *a))
                .collect();
            let mut need = 0;
            for (i, (p, _)) in moves.iter().enumerate() {
                let clashes = moves.iter().enumerate().any(|(j, (_, a))| {
                    j != i
                        && matches!((bit_range(*p), bit_range(*a)),
                            (Some((ps, pe)), Some((as_, ae))) if ps < ae && as_ < pe)
                });
                if clashes {
                    need += scalar_bytes(f.values[p.index()].ty);
                }
            }
            copy_max = copy_max.max(need);
        }
    }
    off += copy_max as u16;
    FrameInfo {
        repr,
        size: off,
        slot_offsets,
        ret_offset,
        copy_offset,
        callees,
    }
}

/// Where a value is used: (block, instruction index in the block).
fn use_sites(f: &Function) -> Vec<Vec<(plcc_ir::Block, usize)>> {
    let mut u = vec![Vec::new(); f.values.len()];
    for &b in &f.layout {
        for (k, &inst) in f.block(b).insts.iter().enumerate() {
            f.inst(inst).for_each_arg(|a| u[a.index()].push((b, k)));
        }
    }
    u
}

/// The bits of memory a known pointer designates for a value of type `t` (in
/// bits, so that BOOLs packed into one byte are told apart).
fn range(p: Ptr, t: Type) -> Option<(Sym, u16, u16)> {
    match p {
        Ptr::Known(s, o, b) => Some(bit_range(s, o, b, t)),
        Ptr::Derived(..) => None,
    }
}

fn bit_range(s: Sym, o: u16, b: u8, t: Type) -> (Sym, u16, u16) {
    if t == Type::I1 {
        (s, o * 8 + b as u16, o * 8 + b as u16 + 1)
    } else {
        (s, o * 8, (o + scalar_bytes(t) as u16) * 8)
    }
}

fn overlaps(a: (Sym, u16, u16), b: (Sym, u16, u16)) -> bool {
    a.0 == b.0 && a.1 < b.2 && b.1 < a.2
}

/// Turns loads and stores of known variables into direct use of the variable (see
/// [`Repr::Mem`]), as a PLC compiler working on variables would.
fn forward_memory(
    f: &Function,
    ptrs: &FxHashMap<Value, Ptr>,
    repr: &mut [Repr],
    needs_home: &mut [bool],
) {
    let uses = use_sites(f);
    let mem_of = |repr: &[Repr], v: Value, t: Type| -> Option<(Sym, u16, u16)> {
        match repr[v.index()] {
            Repr::Mem(s, o, b) => Some(bit_range(s, o, b, t)),
            _ => None,
        }
    };
    // What the function writes: known ranges, or anything at all (calls, stores
    // through computed pointers).
    let mut written = Vec::new();
    let mut unknown_writes = false;
    for (_, inst) in f.inst_iter() {
        match f.inst(inst) {
            InstData::Call { .. } => unknown_writes = true,
            InstData::Store { value, addr } => {
                match ptrs.get(addr).and_then(|p| range(*p, f.value_type(*value))) {
                    Some(r) => written.push(r),
                    None => unknown_writes = true,
                }
            }
            _ => {}
        }
    }
    for &b in &f.layout {
        let insts = &f.block(b).insts;
        // Whether instruction k may change the memory `r`.
        let clobbers = |k: usize, r: (Sym, u16, u16)| match f.inst(insts[k]) {
            InstData::Call { .. } => true,
            InstData::Store { value, addr } => ptrs
                .get(addr)
                .and_then(|p| range(*p, f.value_type(*value)))
                .is_none_or(|w| overlaps(w, r)),
            _ => false,
        };
        // Loads used in place.
        for (k, &inst) in insts.iter().enumerate() {
            let InstData::Load { ty, addr } = f.inst(inst) else {
                continue;
            };
            let Some(r) = f.result(inst) else { continue };
            let Some(p @ Ptr::Known(s, o, bit)) = ptrs.get(addr).copied() else {
                continue;
            };
            if !unknown_writes
                && !written
                    .iter()
                    .any(|w| overlaps(*w, range(p, *ty).expect("a known place has a range")))
            {
                // Nothing in the function writes the variable: use it in place anywhere.
                repr[r.index()] = Repr::Mem(s, o, bit);
                needs_home[r.index()] = false;
                continue;
            }
            let us = &uses[r.index()];
            if us.is_empty() || us.iter().any(|&(ub, _)| ub != b) {
                continue;
            }
            let last = us
                .iter()
                .map(|&(_, i)| i)
                .max()
                .expect("a used value has uses");
            let r_range = range(p, *ty).expect("a known place has a range");
            if (k + 1..last).any(|j| clobbers(j, r_range)) {
                continue;
            }
            repr[r.index()] = Repr::Mem(s, o, bit);
            needs_home[r.index()] = false;
        }
        // Results computed straight into the variable they are stored to.
        for (sk, &inst) in insts.iter().enumerate() {
            let InstData::Store { value, addr } = f.inst(inst) else {
                continue;
            };
            let Some(dst @ Ptr::Known(s, o, bit)) = ptrs.get(addr).copied() else {
                continue;
            };
            let v = *value;
            if !needs_home[v.index()] || uses[v.index()].len() != 1 {
                continue;
            }
            let plcc_ir::function::ValueDef::Result(def) = f.value_def(v) else {
                continue;
            };
            let Some(dk) = insts.iter().position(|&i| i == def) else {
                continue;
            };
            if dk >= sk {
                continue;
            }
            let t = f.value_type(v);
            let drange = range(dst, t).expect("a known place has a range");
            let data = f.inst(def);
            let computes = matches!(
                data,
                InstData::Unary { .. }
                    | InstData::Binary { .. }
                    | InstData::Icmp { .. }
                    | InstData::Convert { .. }
                    | InstData::Select { .. }
                    | InstData::Load { .. }
                    | InstData::Call { .. }
                    | InstData::Intrinsic { .. }
            );
            if !computes {
                continue;
            }
            // Nothing between may read or write the variable.
            let mut clash = false;
            for &between in &insts[dk + 1..sk] {
                match f.inst(between) {
                    InstData::Call { .. } => clash = true,
                    InstData::Store { value, addr } => {
                        match ptrs.get(addr).and_then(|p| range(*p, f.value_type(*value))) {
                            Some(w) if !overlaps(w, drange) => {}
                            _ => clash = true,
                        }
                    }
                    InstData::Load { ty, addr } => {
                        match ptrs.get(addr).and_then(|p| range(*p, *ty)) {
                            Some(r) if !overlaps(r, drange) => {}
                            _ => clash = true,
                        }
                    }
                    _ => {}
                }
                // A value used in place that lives in the destination must be dead by
                // the time the destination is written: it is, unless used after.
            }
            if clash {
                continue;
            }
            // Operands that overlap the destination: only the first, exactly, and
            // only for operations that read it before writing (or work in place).
            let mut operands = Vec::new();
            data.for_each_arg(|a| operands.push(a));
            let first_ok = matches!(
                data,
                InstData::Binary { op, .. } if matches!(op,
                    BinaryOp::Iadd | BinaryOp::Isub | BinaryOp::Band | BinaryOp::Bor
                    | BinaryOp::Bxor | BinaryOp::Imul | BinaryOp::Sdiv | BinaryOp::Udiv
                    | BinaryOp::Srem | BinaryOp::Urem)
            ) || matches!(
                data,
                InstData::Unary { .. } | InstData::Convert { .. } | InstData::Icmp { .. }
            );
            let mut bad = false;
            for (i, &a) in operands.iter().enumerate() {
                let at = f.value_type(a);
                // In-place operands, and memory values still in use after the store.
                let arange = mem_of(repr, a, at);
                if let Some(ar) = arange {
                    if overlaps(ar, drange) {
                        let exact = ar == drange;
                        let commutes = matches!(data, InstData::Binary { op, .. } if op.is_commutative() && !op.can_fault());
                        if !(exact
                            && (i == 0 || commutes || matches!(data, InstData::Icmp { .. }))
                            && first_ok)
                        {
                            bad = true;
                        }
                    }
                }
            }
            // Values kept in the destination's memory and used after the store would
            // see the new value.
            // (The variable holds the new value from the definition on.)
            for &later in &insts[dk + 1..] {
                f.inst(later).for_each_arg(|a| {
                    if let Some(ar) = mem_of(repr, a, f.value_type(a)) {
                        if overlaps(ar, drange) {
                            bad = true;
                        }
                    }
                });
            }
            if bad {
                continue;
            }
            repr[v.index()] = Repr::Mem(s, o, bit);
            needs_home[v.index()] = false;
        }
    }
}

/// Makes `bnot` of a BOOL free where the operand keeps its value for as long as the
/// negation is used (an SSA value in the frame, a constant, or a variable that is not
/// written before the negation's last use).
fn fold_negations(
    f: &Function,
    ptrs: &FxHashMap<Value, Ptr>,
    repr: &mut [Repr],
    needs_home: &mut [bool],
) {
    let uses = use_sites(f);
    for &b in &f.layout {
        let insts = &f.block(b).insts;
        for (k, &inst) in insts.iter().enumerate() {
            let InstData::Unary {
                op: plcc_ir::inst::UnaryOp::Bnot,
                arg,
            } = f.inst(inst)
            else {
                continue;
            };
            let Some(r) = f.result(inst) else { continue };
            if f.value_type(r) != Type::I1 || !needs_home[r.index()] {
                continue;
            }
            let ok = match repr[arg.index()] {
                Repr::Mem(..) => {
                    let us = &uses[r.index()];
                    !us.is_empty() && us.iter().all(|&(ub, _)| ub == b) && {
                        let last = us
                            .iter()
                            .map(|&(_, i)| i)
                            .max()
                            .expect("a used value has uses");
                        let Repr::Mem(sym, o, bit) = repr[arg.index()] else {
                            unreachable!()
                        };
                        let mine = bit_range(sym, o, bit, Type::I1);
                        !(k + 1..last).any(|j| {
                            let writes_var = !matches!(f.inst(insts[j]), InstData::Load { .. })
                                && f.result(insts[j]).is_some_and(|x| match repr[x.index()] {
                                    Repr::Mem(s2, o2, b2) => {
                                        overlaps(bit_range(s2, o2, b2, f.value_type(x)), mine)
                                    }
                                    _ => false,
                                });
                            writes_var
                                || match f.inst(insts[j]) {
                                    InstData::Call { .. } => true,
                                    InstData::Store { value, addr } => ptrs
                                        .get(addr)
                                        .and_then(|p| range(*p, f.value_type(*value)))
                                        .is_none_or(|w| overlaps(w, mine)),
                                    _ => false,
                                }
                        })
                    }
                }
                Repr::Const(_) | Repr::NotOf(_) => true,
                _ => needs_home[arg.index()],
            };
            if ok {
                repr[r.index()] = Repr::NotOf(*arg);
                needs_home[r.index()] = false;
            }
        }
    }
}

/// The operand an instruction's result may share RAM with, if that operand dies at
/// the instruction: the code reads each byte (or the bit) of it before writing the
/// same byte of the result.
fn in_place_operand(data: &InstData) -> Option<Value> {
    match data {
        InstData::Unary { arg, .. } | InstData::Convert { arg, .. } => Some(*arg),
        InstData::Binary { op, args } => {
            (!matches!(op, BinaryOp::Rotl | BinaryOp::Rotr)).then_some(args[0])
        }
        InstData::Load { addr, .. } => Some(*addr),
        _ => None,
    }
}
