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
use crate::inst::{InstData, Intrinsic};
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
    fn may_alias(&self, a: u32, b: u32) -> bool {
        if a == b {
            return true;
        }
        let (ra, rb) = (self.root[a as usize], self.root[b as usize]);
        if ra != rb {
            let known = |n: &Node| matches!(n, Node::Global(_) | Node::Slot(_));
            // Two different objects never overlap; an opaque pointer may point anywhere.
            return !(known(&self.nodes[ra as usize]) && known(&self.nodes[rb as usize]));
        }
        // Same root: relate the paths level by level. The first level from the root
        // that is decisive decides: different fields or constant elements are
        // disjoint, different aggregate types are unknown. Levels that may be the
        // same element pass the question down. Walking up from the bottom, the last
        // decisive level seen is that first one. (One path a prefix of the other, or
        // no decisive level: they may overlap.)
        let (mut x, mut y) = (a, b);
        while self.depth[x as usize] > self.depth[y as usize] {
            x = self.parent(x);
        }
        while self.depth[y as usize] > self.depth[x as usize] {
            y = self.parent(y);
        }
        let mut result = true;
        while x != y {
            match self.step(x, y) {
                Step::Disjoint => result = false,
                Step::Unknown => result = true,
                Step::Same | Step::SameOrDisjoint => {}
            }
            x = self.parent(x);
            y = self.parent(y);
        }
        result
    }

    /// The parent of a path node (itself for a root).
    fn parent(&self, a: u32) -> u32 {
        match self.nodes[a as usize] {
            Node::Field { parent, .. } | Node::Elem { parent, .. } => parent,
            _ => a,
        }
    }

    /// How the last steps of `x` and `y` relate, given that their parents are the same
    /// place (or may be the same array element: then "same" means same under that
    /// assumption).
    fn step(&self, x: u32, y: u32) -> Step {
        if x == y {
            return Step::Same;
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
                if f1 == f2 {
                    Step::Same
                } else {
                    Step::Disjoint
                }
            }
            (
                Node::Elem {
                    agg: g1, index: i1, ..
                },
                Node::Elem {
                    agg: g2, index: i2, ..
                },
            ) if g1 == g2 => match (i1, i2) {
                (Index::Const(c1), Index::Const(c2)) if c1 != c2 => Step::Disjoint,
                _ if i1 == i2 => Step::Same,
                // The same array element or disjoint ones: the rest of the paths
                // decides under the "same element" assumption.
                _ => Step::SameOrDisjoint,
            },
            // Different aggregate types at one address: no knowledge.
            _ => Step::Unknown,
        }
    }
}

/// How two steps of address paths from the same place relate.
#[derive(Copy, Clone, PartialEq, Eq, Debug)]
enum Step {
    /// The same step.
    Same,
    /// Provably different memory (different fields, different constant elements).
    Disjoint,
    /// Elements of one array at indexes that may or may not be equal.
    SameOrDisjoint,
    /// Nothing known (different aggregate types).
    Unknown,
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
                InstData::Call { .. }
                | InstData::CallTable { .. }
                | InstData::InlineC { .. }
                | InstData::Intrinsic {
                    op: Intrinsic::Fill,
                    ..
                } => {
                    // The callee (or C code) may read and write any memory it can
                    // reach; a fill writes elements from its address on, which the
                    // alias oracle does not describe (it knows single elements).
                    known.clear();
                    pending.clear();
                }
                ref data if data.has_side_effects() && !data.is_terminator() => {
                    // Faults (division, raise_fault) end nothing in the IR, but a
                    // runtime may stop the task on them, and a watchdog may end the
                    // scan where `stop_requested` is read: keep the stores before.
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::function::FuncKind;

    #[test]
    fn alias_oracle() {
        let f = Function::new("f", FuncKind::Function, vec![], None);
        let mut a = Addrs::new(&f);
        let (s, s2, t, arr) = (AggId(0), AggId(1), AggId(2), AggId(3));
        let r = a.intern(Node::Opaque(Value(0)));
        let r2 = a.intern(Node::Opaque(Value(9)));
        let g = a.intern(Node::Global(DataId(0)));
        let h = a.intern(Node::Global(DataId(1)));
        let sl = a.intern(Node::Slot(SlotId(0)));
        let field =
            |a: &mut Addrs, parent, agg, field| a.intern(Node::Field { parent, agg, field });
        let elem = |a: &mut Addrs, parent, index| {
            a.intern(Node::Elem {
                parent,
                agg: arr,
                index,
            })
        };
        let f0 = field(&mut a, r, s, 0);
        let f1 = field(&mut a, r, s, 1);
        let ei = elem(&mut a, f0, Index::Value(Value(1)));
        let ej = elem(&mut a, f0, Index::Value(Value(2)));
        let e0 = elem(&mut a, f0, Index::Const(0));
        let e1 = elem(&mut a, f0, Index::Const(1));
        let ei_x = field(&mut a, ei, t, 0);
        let ej_x = field(&mut a, ej, t, 0);
        let ej_y = field(&mut a, ej, t, 1);
        let e0_x = field(&mut a, e0, t, 0);
        let e1_x = field(&mut a, e1, t, 0);
        let pun = field(&mut a, r, s2, 1);
        let pun_y = field(&mut a, pun, t, 1);
        let f0_x = field(&mut a, f0, t, 0);
        let g0 = field(&mut a, g, s, 0);
        let cases = [
            (f0, f1, false),     // different fields
            (f0, f0, true),      // the same
            (ei, ej, true),      // unknown indexes
            (ei_x, ej_y, false), // same element or not, different fields
            (ei_x, ej_x, true),  // possibly the same element, same field
            (e0, e1, false),     // different constant elements
            (e0_x, e1_x, false), // inside different elements
            (e0_x, e1, false),   // different depths, different elements
            (ei_x, ej, true),    // inside a possibly equal element
            (f0, ei_x, true),    // a prefix
            (f0_x, pun_y, true), // different types at one address: no knowledge
            (f0, r2, true),      // another opaque pointer
            (g, h, false),       // different objects
            (g0, sl, false),     // a global and a slot
            (g0, f0, true),      // an opaque pointer may point into a global
            (g0, field(&mut a, g, s, 1), false),
        ];
        for (k, &(x, y, expect)) in cases.iter().enumerate() {
            assert_eq!(a.may_alias(x, y), expect, "case {k}");
            assert_eq!(a.may_alias(y, x), expect, "case {k} swapped");
        }
    }
}
