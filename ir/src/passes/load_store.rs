//! Redundant load elimination, store-to-load forwarding and dead store elimination
//! within basic blocks.
//!
//! Addresses are compared structurally: every address value is interned as a path of
//! `field_addr` / `elem_addr` steps from a root, which is a data object
//! (`global_addr`), a stack slot (`slot_addr`) or any other pointer value (a
//! parameter, a loaded pointer: "opaque"). Two addresses are provably distinct when
//! their roots are distinct objects, or when their paths from the same root part at
//! different fields of the same struct or at different constant elements of the same
//! array. Anything else may alias: an opaque root may point anywhere, a non-constant
//! index may equal any other, and one path being a prefix of the other overlaps.
//!
//! Within a block the pass tracks which value each address is known to hold (from a
//! store or an earlier load of the same type) and which stores nobody has read yet. A
//! store forgets what it may overwrite; a call forgets everything. A load of a known
//! value is replaced by it; a store of the value the address already holds is
//! dropped; a store overwritten by a store of the same type to the same address with
//! no possible read in between is dropped. The tables are capped so that huge blocks
//! stay linear.

use crate::entities::{AggId, DataId, Inst, SlotId, Value};
use crate::function::{Function, ValueDef};
use crate::inst::InstData;
use crate::passes::util::{int_const, ValueMap};
use crate::types::Type;
use rustc_hash::FxHashMap;

/// At most this many known values and pending stores are tracked at a time (the
/// oldest are forgotten first), which bounds the work per instruction.
const CAP: usize = 64;

/// One step of an address path, or its root.
#[derive(Copy, Clone, PartialEq, Eq, Hash, Debug)]
enum Node {
    Global(DataId),
    Slot(SlotId),
    Opaque(Value),
    Field {
        parent: u32,
        agg: AggId,
        field: u32,
    },
    Elem {
        parent: u32,
        agg: AggId,
        index: Index,
    },
}

/// An array index: a constant, or an SSA value (equal values are equal indices).
#[derive(Copy, Clone, PartialEq, Eq, Hash, Debug)]
enum Index {
    Const(i64),
    Value(Value),
}

/// Interned addresses: every distinct path gets an id; equal ids are equal addresses.
struct Addrs {
    nodes: Vec<Node>,
    depth: Vec<u32>,
    root: Vec<u32>,
    ids: FxHashMap<Node, u32>,
    /// The id of each value used as an address (`u32::MAX` until computed).
    of_value: Vec<u32>,
    /// Scratch paths for alias queries.
    pa: Vec<u32>,
    pb: Vec<u32>,
}

const UNSET: u32 = u32::MAX;

impl Addrs {
    fn new(func: &Function) -> Addrs {
        Addrs {
            nodes: Vec::new(),
            depth: Vec::new(),
            root: Vec::new(),
            ids: FxHashMap::default(),
            of_value: vec![UNSET; func.values.len()],
            pa: Vec::new(),
            pb: Vec::new(),
        }
    }

    fn intern(&mut self, node: Node) -> u32 {
        if let Some(&id) = self.ids.get(&node) {
            return id;
        }
        let id = self.nodes.len() as u32;
        let (depth, root) = match node {
            Node::Field { parent, .. } | Node::Elem { parent, .. } => {
                (self.depth[parent as usize] + 1, self.root[parent as usize])
            }
            _ => (0, id),
        };
        self.nodes.push(node);
        self.depth.push(depth);
        self.root.push(root);
        self.ids.insert(node, id);
        id
    }

    /// The interned address of the pointer value `v`.
    fn of(&mut self, func: &Function, vmap: &mut ValueMap, v: Value) -> u32 {
        if let Some(&id) = self.of_value.get(v.index()) {
            if id != UNSET {
                return id;
            }
        }
        let node = match func.value_def(v) {
            ValueDef::Result(i) => match *func.inst(i) {
                InstData::GlobalAddr { data } => Node::Global(data),
                InstData::SlotAddr { slot } => Node::Slot(slot),
                InstData::FieldAddr { base, agg, field } => Node::Field {
                    parent: {
                        let base = vmap.resolve(base);
                        self.of(func, vmap, base)
                    },
                    agg,
                    field,
                },
                InstData::ElemAddr { base, agg, index } => Node::Elem {
                    parent: {
                        let base = vmap.resolve(base);
                        self.of(func, vmap, base)
                    },
                    agg,
                    index: match int_const(func, vmap.resolve(index)) {
                        Some(k) => Index::Const(k),
                        None => Index::Value(vmap.resolve(index)),
                    },
                },
                _ => Node::Opaque(v),
            },
            ValueDef::Param(..) => Node::Opaque(v),
        };
        let id = self.intern(node);
        if let Some(slot) = self.of_value.get_mut(v.index()) {
            *slot = id;
        }
        id
    }

    /// True unless the addresses `a` and `b` provably do not overlap.
    fn may_alias(&mut self, a: u32, b: u32) -> bool {
        if a == b {
            return true;
        }
        let (ra, rb) = (self.root[a as usize], self.root[b as usize]);
        if ra != rb {
            let known = |n: &Node| matches!(n, Node::Global(_) | Node::Slot(_));
            // Two different objects never overlap; an opaque pointer may point anywhere.
            return !(known(&self.nodes[ra as usize]) && known(&self.nodes[rb as usize]));
        }
        // Same root: compare the paths step by step from the root.
        let mut pa = std::mem::take(&mut self.pa);
        let mut pb = std::mem::take(&mut self.pb);
        self.path(a, &mut pa);
        self.path(b, &mut pb);
        let mut result = true; // a prefix of the other overlaps it
        for (&x, &y) in pa.iter().zip(&pb) {
            if x == y {
                continue;
            }
            match (self.nodes[x as usize], self.nodes[y as usize]) {
                (
                    Node::Field {
                        agg: g1, field: f1, ..
                    },
                    Node::Field {
                        agg: g2, field: f2, ..
                    },
                ) if g1 == g2 => {
                    debug_assert_ne!(f1, f2);
                    result = false;
                    break;
                }
                (
                    Node::Elem {
                        agg: g1, index: i1, ..
                    },
                    Node::Elem {
                        agg: g2, index: i2, ..
                    },
                ) if g1 == g2 => {
                    if let (Index::Const(c1), Index::Const(c2)) = (i1, i2) {
                        if c1 != c2 {
                            result = false;
                            break;
                        }
                    }
                    // The same array element or disjoint ones: the rest of the paths
                    // decides under the "same element" assumption.
                }
                // Different aggregate types at one address: no knowledge.
                _ => break,
            }
        }
        self.pa = pa;
        self.pb = pb;
        result
    }

    /// The nodes from the root's child down to `a` (the root itself excluded).
    fn path(&self, mut a: u32, out: &mut Vec<u32>) {
        out.clear();
        while self.depth[a as usize] > 0 {
            out.push(a);
            a = match self.nodes[a as usize] {
                Node::Field { parent, .. } | Node::Elem { parent, .. } => parent,
                _ => unreachable!(),
            };
        }
        out.reverse();
    }
}

/// What an address is known to hold.
#[derive(Copy, Clone)]
struct Known {
    addr: u32,
    ty: Type,
    value: Value,
}

/// A store nothing has read yet.
#[derive(Copy, Clone)]
struct Pending {
    addr: u32,
    ty: Type,
    inst: Inst,
}

fn push_capped<T>(list: &mut Vec<T>, item: T) {
    if list.len() >= CAP {
        list.remove(0);
    }
    list.push(item);
}

/// Forwards stored and loaded values to later loads and removes redundant and dead
/// stores, block by block. Returns true if the function changed.
pub fn run(func: &mut Function) -> bool {
    let mut addrs = Addrs::new(func);
    let mut vmap = ValueMap::new(func);
    let mut dead: Vec<Inst> = Vec::new();
    let mut known: Vec<Known> = Vec::new();
    let mut pending: Vec<Pending> = Vec::new();
    let mut changed = false;

    for bi in 0..func.layout.len() {
        let b = func.layout[bi];
        known.clear();
        pending.clear();
        dead.clear();
        for k in 0..func.blocks[b.index()].insts.len() {
            let i = func.blocks[b.index()].insts[k];
            match *func.inst(i) {
                InstData::Load { ty, addr } => {
                    let addr = vmap.resolve(addr);
                    let a = addrs.of(func, &mut vmap, addr);
                    let result = func.result(i).expect("load has a result");
                    if let Some(e) = known.iter().rev().find(|e| e.addr == a && e.ty == ty) {
                        vmap.set(result, e.value);
                        dead.push(i);
                        continue;
                    }
                    // A real read: the stores it may see are no longer dead.
                    pending.retain(|p| !addrs.may_alias(p.addr, a));
                    push_capped(
                        &mut known,
                        Known {
                            addr: a,
                            ty,
                            value: result,
                        },
                    );
                }
                InstData::Store { value, addr } => {
                    let value = vmap.resolve(value);
                    let addr = vmap.resolve(addr);
                    let a = addrs.of(func, &mut vmap, addr);
                    let ty = func.value_type(value);
                    if known
                        .iter()
                        .rev()
                        .any(|e| e.addr == a && e.ty == ty && e.value == value)
                    {
                        // The memory already holds this value.
                        dead.push(i);
                        continue;
                    }
                    if let Some(pos) = pending.iter().position(|p| p.addr == a && p.ty == ty) {
                        dead.push(pending[pos].inst);
                        pending.remove(pos);
                    }
                    known.retain(|e| !addrs.may_alias(e.addr, a));
                    push_capped(&mut known, Known { addr: a, ty, value });
                    push_capped(
                        &mut pending,
                        Pending {
                            addr: a,
                            ty,
                            inst: i,
                        },
                    );
                }
                InstData::Call { .. } => {
                    // The callee may read and write any memory it can reach.
                    known.clear();
                    pending.clear();
                }
                ref data if data.has_side_effects() && !data.is_terminator() => {
                    // Faults (division, raise_fault) end nothing in the IR, but a
                    // runtime may stop the task on them: keep the stores before them.
                    pending.clear();
                }
                _ => {}
            }
        }
        if !dead.is_empty() {
            changed = true;
            dead.sort_unstable();
            func.blocks[b.index()]
                .insts
                .retain(|i| dead.binary_search(i).is_err());
        }
    }
    vmap.apply(func);
    changed
}
