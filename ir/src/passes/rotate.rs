//! Loop rotation: the test at the top of a loop is copied to the end of each block
//! that jumps back to it, so that an iteration ends in one conditional branch back to
//! the body instead of a jump to the test and a branch from there.
//!
//! ```text
//! H(p):  c = test p              H(p):  c = test p
//!        brif c, B, X                   brif c, B(p), X
//! B:     ... p ...         =>    B(q):  ... q ...
//! L:     jump H(n)               L:     c2 = test n
//!                                       brif c2, B(n), X
//! ```
//!
//! A header `H` is rotated when it is the target of at most [`MAX_LATCHES`] back
//! edges (edges from blocks it dominates), ends in a `brif` and holds at most
//! [`MAX_TEST`] other instructions, none with an effect (so running the copy at the
//! end of the latch `L` is running `H` at the same moment, as the edge would have).
//! The copy replaces `L`'s `jump`, or, when `L` ends in a `brif` (the watchdog's
//! checks on back edges do), sits in a new block on that edge. `H` stays where it is
//! and runs once, on entry.
//!
//! The values `H` defines (its parameters and results) are used in the loop: after the
//! rotation those uses are reached from `H` and from each `L`, so they become
//! parameters of the successor of `H` whose region holds them, passed explicitly by
//! `H`'s branch and by each copy. This needs every such use to lie in a block
//! dominated by a successor of `H` that only `H` reaches; a loop where that fails (a
//! use after an `EXIT`'s join, say) is left alone.
//!
//! The dominator tree does not change (the new edges leave blocks the loop header
//! already dominates, and enter successors whose immediate dominator stays `H`), so
//! one tree serves the whole pass.
//!
//! Like [`crate::passes::if_convert`], the pass is a backend's choice, not part of
//! [`crate::passes::optimize_function`]: it trades code size (the copies) for speed.

use crate::dominators::DomTree;
use crate::entities::{Block, Inst, Value};
use crate::function::{Function, ValueDef};
use crate::inst::{BlockCall, InstData};

/// The most instructions (besides the `brif`) a header may hold to be copied.
pub const MAX_TEST: usize = 6;
/// The most back edges of one header that receive a copy.
pub const MAX_LATCHES: usize = 2;

/// Rotates the loops of `func` (see the module doc). Returns true if the function
/// changed.
pub fn run(func: &mut Function) -> bool {
    let Some(entry) = func.entry() else {
        return false;
    };
    let dt = DomTree::compute(func);
    let mut tree = Tree::new(dt, func.blocks.len());
    let dt = &tree.dt;
    // The predecessors of each block, kept up to date as edges change.
    let mut preds = func.predecessors();
    // Back edges by header: (latch, which destination of its terminator) for the
    // edges into a block that dominates the latch.
    let mut latches: Vec<Vec<(Block, usize)>> = vec![Vec::new(); func.blocks.len()];
    for (b, k) in dt.back_edges(func) {
        let h = func
            .inst(func.terminator(b).expect("a terminator"))
            .dests()
            .nth(k);
        latches[h.expect("a destination").block.index()].push((b, k));
    }
    let mut changed = false;
    let headers: Vec<Block> = dt
        .rpo()
        .iter()
        .copied()
        .filter(|h| !latches[h.index()].is_empty() && *h != entry)
        .collect();
    for h in headers {
        let ls = std::mem::take(&mut latches[h.index()]);
        if ls.len() > MAX_LATCHES || !rotatable(func, h) {
            continue;
        }
        if !isolate(func, &mut tree, &mut preds, h) {
            continue;
        }
        for &(l, k) in &ls {
            let at = copy_test(func, h, l, k);
            if at != l {
                preds.push(vec![l]);
                tree.add(at, l);
            }
            for d in func.successors(h) {
                preds[d.index()].push(at);
            }
        }
        preds[h.index()].retain(|p| !ls.iter().any(|(l, _)| l == p));
        changed = true;
    }
    changed
}

/// True if `h` ends in a `brif` to two different blocks (neither `h`) after at most
/// [`MAX_TEST`] instructions without effects.
fn rotatable(func: &Function, h: Block) -> bool {
    let insts = &func.block(h).insts;
    let Some((&last, body)) = insts.split_last() else {
        return false;
    };
    let InstData::Brif {
        then_dest,
        else_dest,
        ..
    } = func.inst(last)
    else {
        return false;
    };
    then_dest.block != else_dest.block
        && then_dest.block != h
        && else_dest.block != h
        && body.len() <= MAX_TEST
        && body.iter().all(|&i| !func.inst(i).has_side_effects())
}

/// Makes the values `h` defines unused outside `h` except through its branch's
/// arguments: each use moves to a new parameter of the successor whose dominator
/// subtree holds it. A successor with other predecessors, each of which it dominates
/// (the header of a following loop), first gets a block of its own on the edge from
/// `h` to take the parameters. Returns false, changing nothing, when a use lies
/// outside both successors' subtrees or a successor that needs parameters has a
/// predecessor it does not dominate.
fn isolate(func: &mut Function, tree: &mut Tree, preds: &mut Vec<Vec<Block>>, h: Block) -> bool {
    let term = func
        .terminator(h)
        .expect("a rotatable header ends in a brif");
    let succ: Vec<Block> = func
        .inst(term)
        .successors()
        .iter()
        .map(|d| d.block)
        .collect();
    let defined_here = |func: &Function, v: Value| match func.value_def(v) {
        ValueDef::Param(b, _) => b == h,
        ValueDef::Result(i) => func.block(h).insts.contains(&i),
    };
    // The blocks of each successor's subtree, and what each needs from `h`.
    let mut regions: Vec<Vec<Block>> = Vec::with_capacity(2);
    let mut needs: Vec<Vec<Value>> = vec![Vec::new(), Vec::new()];
    let mut in_region = vec![false; func.blocks.len()];
    for (k, &s) in succ.iter().enumerate() {
        let blocks = if tree.dt.idom(s) == Some(h) {
            tree.subtree(s)
        } else {
            Vec::new()
        };
        for &b in &blocks {
            in_region[b.index()] = true;
            for &i in &func.block(b).insts {
                func.inst(i).for_each_arg(|a| {
                    if defined_here(func, a) && !needs[k].contains(&a) {
                        needs[k].push(a);
                    }
                });
            }
        }
        if !needs[k].is_empty() {
            let ps = &preds[s.index()];
            let from_h = ps.iter().filter(|&&p| p == h).count();
            if from_h != 1 || ps.iter().any(|&p| p != h && !tree.dominates(s, p)) {
                return false;
            }
        }
        regions.push(blocks);
    }
    // Any other use (a block `h` dominates outside both subtrees) stops the rotation.
    for b in tree.subtree(h) {
        if b == h || in_region[b.index()] {
            continue;
        }
        let mut outside = false;
        for &i in &func.block(b).insts {
            func.inst(i)
                .for_each_arg(|a| outside |= defined_here(func, a));
        }
        if outside {
            return false;
        }
    }
    for (k, &s) in succ.iter().enumerate() {
        if needs[k].is_empty() {
            continue;
        }
        // A successor others reach too gets its own entry block from `h`, which
        // dominates it and takes the parameters.
        let target = if preds[s.index()].len() == 1 {
            s
        } else {
            let e = split_edge(func, term, k);
            preds.push(vec![h]);
            tree.add(e, h);
            for p in preds[s.index()].iter_mut().filter(|p| **p == h) {
                *p = e;
            }
            e
        };
        let mut map: Vec<(Value, Value)> = Vec::with_capacity(needs[k].len());
        for &v in &needs[k] {
            let ty = func.value_type(v);
            map.push((v, func.append_block_param(target, ty)));
        }
        for &b in &regions[k] {
            for ii in 0..func.blocks[b.index()].insts.len() {
                let i = func.blocks[b.index()].insts[ii];
                func.insts[i.index()].map_args(|a| renamed(&map, a));
            }
        }
        if let Some(dest) = func.inst_mut(term).dest_mut(k) {
            dest.args.extend(needs[k].iter().copied());
        }
    }
    true
}

/// Sends destination `k` of the branch `term` through a new block that takes the
/// destination's arguments as parameters and jumps on with them; returns the block
/// (placed in the layout before the destination).
fn split_edge(func: &mut Function, term: Inst, k: usize) -> Block {
    let dest = func
        .inst(term)
        .dest(k)
        .cloned()
        .expect("a brif has two destinations");
    let e = func.create_block();
    let params: Vec<Value> = dest
        .args
        .iter()
        .map(|&a| {
            let ty = func.value_type(a);
            func.append_block_param(e, ty)
        })
        .collect();
    let span = func.spans[term.index()];
    let jump = func.create_inst(
        InstData::Jump {
            dest: BlockCall::new(dest.block, params),
        },
        None,
        span,
    );
    func.blocks[e.index()].insts.push(jump);
    place(func, e, dest.block, 0);
    if let Some(d) = func.inst_mut(term).dest_mut(k) {
        d.block = e;
    }
    e
}

/// Puts the new block `b` into the layout `offset` places after `at` (0: just before
/// it; 1: just after it).
fn place(func: &mut Function, b: Block, at: Block, offset: usize) {
    let i = func
        .layout
        .iter()
        .position(|&x| x == at)
        .map_or(func.layout.len(), |p| p + offset);
    func.layout.insert(i, b);
}

/// The dominator tree of the function as the pass found it, with the blocks the pass
/// adds hung under their immediate dominators (a block on an edge is dominated by
/// the edge's source; the old blocks keep their dominators, see the module doc).
struct Tree {
    dt: DomTree,
    /// The number of blocks `dt` knows.
    known: usize,
    /// The added blocks each block immediately dominates.
    extra: Vec<Vec<Block>>,
    /// The immediate dominator of each added block (indexed from `known`).
    up: Vec<Block>,
}

impl Tree {
    fn new(dt: DomTree, known: usize) -> Tree {
        Tree {
            dt,
            known,
            extra: vec![Vec::new(); known],
            up: Vec::new(),
        }
    }

    /// Records that the new block `b` is immediately dominated by `parent`.
    fn add(&mut self, b: Block, parent: Block) {
        debug_assert_eq!(
            b.index(),
            self.known + self.up.len(),
            "blocks come in order"
        );
        self.up.push(parent);
        self.extra.resize(b.index() + 1, Vec::new());
        self.extra[parent.index()].push(b);
    }

    /// True if `a` dominates `b`. An added `a` is only known to dominate the added
    /// blocks below it (false otherwise, which only makes the pass more careful).
    fn dominates(&self, a: Block, mut b: Block) -> bool {
        while b.index() >= self.known {
            if a == b {
                return true;
            }
            b = self.up[b.index() - self.known];
        }
        a.index() < self.known && self.dt.dominates(a, b)
    }

    /// The blocks of the dominator subtree rooted at `root`, `root` first.
    fn subtree(&self, root: Block) -> Vec<Block> {
        let mut out = vec![root];
        let mut k = 0;
        while k < out.len() {
            let b = out[k];
            if b.index() < self.known {
                out.extend_from_slice(self.dt.children(b));
            }
            out.extend_from_slice(&self.extra[b.index()]);
            k += 1;
        }
        out
    }
}

/// Gives the back edge `k` of `l`'s terminator a copy of `h`'s instructions and
/// branch, with `h`'s parameters replaced by the edge's arguments: in place of `l`'s
/// `jump`, or in a new block on the edge when `l` ends in a `brif` (as the watchdog's
/// checks on back edges do). Returns the block that holds the copy.
fn copy_test(func: &mut Function, h: Block, l: Block, k: usize) -> Block {
    let term = func.terminator(l).expect("a latch ends in a branch");
    let dest = func
        .inst(term)
        .dest(k)
        .cloned()
        .expect("the back edge is a destination of the latch");
    let mut map: Vec<(Value, Value)> = func
        .block(h)
        .params
        .iter()
        .copied()
        .zip(dest.args.iter().copied())
        .collect();
    let span = func.spans[term.index()];
    let mut copies: Vec<Inst> = Vec::new();
    for &i in &func.block(h).insts.clone() {
        let mut data = func.inst(i).clone();
        data.map_args(|a| renamed(&map, a));
        let ty = func.result(i).map(|r| func.value_type(r));
        let c = func.create_inst(data, ty, func.spans[i.index()].or(span));
        if let (Some(old), Some(new)) = (func.result(i), func.result(c)) {
            map.push((old, new));
        }
        copies.push(c);
    }
    if matches!(func.inst(term), InstData::Jump { .. }) {
        let insts = &mut func.blocks[l.index()].insts;
        insts.pop();
        insts.extend(copies);
        return l;
    }
    let t = func.create_block();
    func.blocks[t.index()].insts = copies;
    place(func, t, l, 1);
    if let Some(d) = func.inst_mut(term).dest_mut(k) {
        *d = BlockCall::new(t, Vec::new());
    }
    t
}

/// What `v` became under `map` (pairs of old and new values), or `v` itself.
fn renamed(map: &[(Value, Value)], v: Value) -> Value {
    map.iter().find(|(from, _)| *from == v).map_or(v, |m| m.1)
}
