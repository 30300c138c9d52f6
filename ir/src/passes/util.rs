//! Helpers shared by the passes: value substitution, CFG edges, block-parameter
//! removal.
//!
//! Everything here is linear in the size of the function and uses vectors indexed by
//! entity ids, because the passes run on every compile.

use crate::entities::{Block, Inst, Value};
use crate::function::{Function, ValueDef};
use crate::inst::{BlockCall, InstData};

/// A substitution of SSA values (`from -> to`), applied to every operand at the end of
/// a pass. Chains are followed, so passes may record `a -> b` and later `b -> c`.
pub(crate) struct ValueMap {
    /// `map[v]` is what `v` becomes; empty until the first substitution, because most
    /// runs of most passes substitute nothing.
    map: Vec<Value>,
    /// The number of values when the map was created (later values map to themselves).
    len: usize,
}

impl ValueMap {
    /// An empty substitution for the values of `func`.
    pub(crate) fn new(func: &Function) -> ValueMap {
        ValueMap {
            map: Vec::new(),
            len: func.values.len(),
        }
    }

    /// True if any substitution was recorded.
    pub(crate) fn is_empty(&self) -> bool {
        self.map.is_empty()
    }

    /// Records that every use of `from` must become `to`.
    pub(crate) fn set(&mut self, from: Value, to: Value) {
        if self.map.is_empty() {
            self.map = (0..self.len).map(Value::new).collect();
        }
        let to = self.resolve(to);
        if from != to && from.index() < self.len {
            self.map[from.index()] = to;
        }
    }

    /// What `v` finally becomes (with path compression).
    pub(crate) fn resolve(&mut self, v: Value) -> Value {
        if self.map.is_empty() || v.index() >= self.len {
            return v;
        }
        let mut root = v;
        while self.map[root.index()] != root {
            root = self.map[root.index()];
            if root.index() >= self.len {
                break;
            }
        }
        let mut cur = v;
        while cur != root && cur.index() < self.len {
            let next = self.map[cur.index()];
            self.map[cur.index()] = root;
            cur = next;
        }
        root
    }

    /// Rewrites the operands of every instruction in the layout. Returns true if an
    /// operand changed.
    pub(crate) fn apply(&mut self, func: &mut Function) -> bool {
        if self.map.is_empty() {
            return false;
        }
        let mut changed = false;
        for bi in 0..func.layout.len() {
            let b = func.layout[bi];
            for ii in 0..func.blocks[b.index()].insts.len() {
                let i = func.blocks[b.index()].insts[ii];
                func.insts[i.index()].map_args(|a| {
                    let r = self.resolve(a);
                    changed |= r != a;
                    r
                });
            }
        }
        changed
    }
}

/// Destination `which` of a terminator (numbered as by [`InstData::dest`]), for
/// rewriting.
#[inline]
pub(crate) fn dest_mut(data: &mut InstData, which: u32) -> &mut BlockCall {
    data.dest_mut(which as usize)
        .expect("an edge names a destination of its terminator")
}

/// Destination `which` of a terminator.
#[inline]
pub(crate) fn dest_ref(data: &InstData, which: u32) -> &BlockCall {
    data.dest(which as usize)
        .expect("an edge names a destination of its terminator")
}

/// One CFG edge: destination `which` of the terminator `inst` of block `from`.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub(crate) struct Edge {
    /// The predecessor block.
    pub from: Block,
    /// Its terminator.
    pub inst: Inst,
    /// Which destination of the terminator (see [`InstData::dest`]: 0 is `jump`'s,
    /// `brif`'s then or `br_table`'s default).
    pub which: u32,
}

/// The incoming edges of every block, from the terminators of the layout blocks
/// (compressed rows: one allocation for the whole function).
pub(crate) struct Incoming {
    start: Vec<u32>,
    edges: Vec<Edge>,
}

impl Incoming {
    /// Collects the edges of the layout.
    pub(crate) fn compute(func: &Function) -> Incoming {
        let n = func.blocks.len();
        let mut count = vec![0u32; n + 1];
        for &b in &func.layout {
            if let Some(t) = func.terminator(b) {
                for d in func.inst(t).dests() {
                    count[d.block.index() + 1] += 1;
                }
            }
        }
        for i in 0..n {
            count[i + 1] += count[i];
        }
        let mut fill = count.clone();
        let placeholder = Edge {
            from: Block(0),
            inst: Inst(0),
            which: 0,
        };
        let mut edges = vec![placeholder; count[n] as usize];
        for &b in &func.layout {
            if let Some(t) = func.terminator(b) {
                for (w, d) in func.inst(t).dests().enumerate() {
                    let slot = &mut fill[d.block.index()];
                    edges[*slot as usize] = Edge {
                        from: b,
                        inst: t,
                        which: w as u32,
                    };
                    *slot += 1;
                }
            }
        }
        Incoming {
            start: count,
            edges,
        }
    }

    /// The edges into `b`.
    #[inline]
    pub(crate) fn of(&self, b: Block) -> &[Edge] {
        let i = b.index();
        if i + 1 >= self.start.len() {
            return &[];
        }
        &self.edges[self.start[i] as usize..self.start[i + 1] as usize]
    }
}

/// Removes the parameters of `block` for which `keep` is false, and the matching
/// arguments of every incoming edge; renumbers the remaining parameters' definitions.
pub(crate) fn remove_block_params(
    func: &mut Function,
    block: Block,
    keep: &[bool],
    incoming: &[Edge],
) {
    debug_assert_eq!(keep.len(), func.blocks[block.index()].params.len());
    for e in incoming {
        let call = dest_mut(&mut func.insts[e.inst.index()], e.which);
        if call.block != block || call.args.len() != keep.len() {
            continue; // a stale edge (the caller rewrote it): nothing to do
        }
        let mut k = keep.iter();
        call.args
            .retain(|_| *k.next().expect("one flag per argument"));
    }
    let params = std::mem::take(&mut func.blocks[block.index()].params);
    let mut kept = Vec::with_capacity(params.len());
    for (p, &k) in params.into_iter().zip(keep) {
        if k {
            func.values[p.index()].def = ValueDef::Param(block, kept.len() as u32);
            kept.push(p);
        }
    }
    func.blocks[block.index()].params = kept;
}

/// The instruction defining `v`, if it is an instruction result.
#[inline]
pub(crate) fn def_inst(func: &Function, v: Value) -> Option<&InstData> {
    match func.value_def(v) {
        ValueDef::Result(i) => Some(func.inst(i)),
        ValueDef::Param(..) => None,
    }
}

/// The canonical integer constant `v` is defined as, if any.
#[inline]
pub(crate) fn int_const(func: &Function, v: Value) -> Option<i64> {
    match def_inst(func, v) {
        Some(InstData::Iconst { imm, .. }) => Some(*imm),
        _ => None,
    }
}
