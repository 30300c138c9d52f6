//! Dominator tree (Cooper, Harvey & Kennedy, "A Simple, Fast Dominance Algorithm") and
//! dominance frontiers.
//!
//! Only blocks of the layout reachable from the entry take part; unreachable blocks
//! have no immediate dominator and dominate nothing but themselves. Branches to blocks
//! that do not exist or are not in the layout are ignored, so the tree can be computed
//! for any function, valid or not (the verifier uses it too). Side tables are vectors
//! indexed by block id.

use crate::entities::Block;
use crate::function::Function;
use crate::inst::InstData;

const NONE: u32 = u32::MAX;

/// The terminator of `b`, if it has one. Tolerates malformed functions.
fn terminator(func: &Function, b: Block) -> Option<&InstData> {
    func.blocks
        .get(b.index())
        .and_then(|bd| bd.insts.last())
        .and_then(|i| func.insts.get(i.index()))
}

/// Destination `k` of `b`'s terminator if it exists and is in the layout (`in_layout`
/// indexed by block), `Some(None)` if it does not; `None` past the last destination.
/// Tolerates malformed functions.
fn successor(func: &Function, in_layout: &[bool], b: Block, k: usize) -> Option<Option<Block>> {
    let d = terminator(func, b)?.dest(k)?;
    Some(
        in_layout
            .get(d.block.index())
            .copied()
            .unwrap_or(false)
            .then_some(d.block),
    )
}

/// The destinations of `b`'s terminator that exist and are in the layout, one per
/// edge. Tolerates malformed functions.
fn successors<'f>(
    func: &'f Function,
    in_layout: &'f [bool],
    b: Block,
) -> impl Iterator<Item = Block> + 'f {
    terminator(func, b)
        .into_iter()
        .flat_map(|t| t.dests())
        .map(|d| d.block)
        .filter(|d| in_layout.get(d.index()).copied().unwrap_or(false))
}

fn layout_mask(func: &Function) -> Vec<bool> {
    let mut in_layout = vec![false; func.blocks.len()];
    for &b in &func.layout {
        if let Some(x) = in_layout.get_mut(b.index()) {
            *x = true;
        }
    }
    in_layout
}

/// Blocks reachable from the entry, in reverse postorder (the entry first; every block
/// comes after its dominators). Follows the terminators of the blocks, so it is correct
/// for any layout order.
pub fn reverse_postorder(func: &Function) -> Vec<Block> {
    rpo_with(func, &layout_mask(func))
}

fn rpo_with(func: &Function, in_layout: &[bool]) -> Vec<Block> {
    let Some(entry) = func
        .entry()
        .filter(|e| in_layout.get(e.index()) == Some(&true))
    else {
        return Vec::new();
    };
    let mut visited = vec![false; func.blocks.len()];
    let mut post = Vec::with_capacity(func.layout.len());
    // Explicit stack of (block, next successor index): deep CFGs must not overflow.
    let mut stack: Vec<(Block, usize)> = vec![(entry, 0)];
    visited[entry.index()] = true;
    while let Some(top) = stack.last_mut() {
        let (b, next) = *top;
        if let Some(succ) = successor(func, in_layout, b, next) {
            top.1 += 1;
            if let Some(s) = succ {
                if !visited[s.index()] {
                    visited[s.index()] = true;
                    stack.push((s, 0));
                }
            }
        } else {
            post.push(b);
            stack.pop();
        }
    }
    post.reverse();
    post
}

/// The dominator tree of a function's reachable blocks.
#[derive(Clone, Debug)]
pub struct DomTree {
    rpo: Vec<Block>,
    /// Position of each block in `rpo`, `NONE` if unreachable.
    rpo_num: Vec<u32>,
    /// Immediate dominator of each block (by index), `NONE` for the entry and for
    /// unreachable blocks.
    idom: Vec<u32>,
    /// Reachable predecessors (one per edge), in compressed rows.
    pred_start: Vec<u32>,
    preds: Vec<Block>,
    /// Dominator-tree children, in compressed rows.
    child_start: Vec<u32>,
    children: Vec<Block>,
    /// Preorder / postorder numbers in the dominator tree, for O(1) dominance queries.
    pre: Vec<u32>,
    post: Vec<u32>,
}

impl DomTree {
    /// Computes the dominator tree of `func` (blocks reachable from the entry).
    pub fn compute(func: &Function) -> DomTree {
        let n = func.blocks.len();
        let in_layout = layout_mask(func);
        let rpo = rpo_with(func, &in_layout);
        let mut rpo_num = vec![NONE; n];
        for (k, b) in rpo.iter().enumerate() {
            rpo_num[b.index()] = k as u32;
        }

        // Predecessors among reachable blocks (compressed rows).
        let mut pred_start = vec![0u32; n + 1];
        for &b in &rpo {
            for d in successors(func, &in_layout, b) {
                pred_start[d.index() + 1] += 1;
            }
        }
        for i in 0..n {
            pred_start[i + 1] += pred_start[i];
        }
        let mut fill = pred_start.clone();
        let mut preds = vec![Block(0); pred_start[n] as usize];
        for &b in &rpo {
            for d in successors(func, &in_layout, b) {
                let s = &mut fill[d.index()];
                preds[*s as usize] = b;
                *s += 1;
            }
        }

        // Cooper-Harvey-Kennedy: iterate idoms over RPO until stable. `idom` holds rpo
        // numbers during the iteration (the entry is its own idom).
        let m = rpo.len();
        let mut idom_rpo = vec![NONE; m];
        if m > 0 {
            idom_rpo[0] = 0;
        }
        let mut changed = true;
        while changed {
            changed = false;
            for k in 1..m {
                let b = rpo[k];
                let mut new_idom = NONE;
                for &p in &preds[pred_start[b.index()] as usize..pred_start[b.index() + 1] as usize]
                {
                    let pn = rpo_num[p.index()];
                    if idom_rpo[pn as usize] == NONE {
                        continue; // not processed yet
                    }
                    new_idom = if new_idom == NONE {
                        pn
                    } else {
                        intersect(&idom_rpo, pn, new_idom)
                    };
                }
                if new_idom != idom_rpo[k] {
                    idom_rpo[k] = new_idom;
                    changed = true;
                }
            }
        }
        let mut idom = vec![NONE; n];
        for k in 1..m {
            idom[rpo[k].index()] = rpo[idom_rpo[k] as usize].0;
        }

        // Children in compressed rows (in RPO order, which keeps traversals stable).
        let mut child_start = vec![0u32; n + 1];
        for &b in rpo.iter().skip(1) {
            child_start[idom[b.index()] as usize + 1] += 1;
        }
        for i in 0..n {
            child_start[i + 1] += child_start[i];
        }
        let mut fill = child_start.clone();
        let mut children = vec![Block(0); m.saturating_sub(1)];
        for &b in rpo.iter().skip(1) {
            let s = &mut fill[idom[b.index()] as usize];
            children[*s as usize] = b;
            *s += 1;
        }

        let mut tree = DomTree {
            rpo,
            rpo_num,
            idom,
            pred_start,
            preds,
            child_start,
            children,
            pre: vec![NONE; n],
            post: vec![NONE; n],
        };
        tree.number();
        tree
    }

    /// Pre/postorder numbering of the tree.
    fn number(&mut self) {
        let Some(&entry) = self.rpo.first() else {
            return;
        };
        let (mut pre, mut post) = (0u32, 0u32);
        let mut stack: Vec<(Block, u32)> = vec![(entry, 0)];
        self.pre[entry.index()] = pre;
        pre += 1;
        while let Some(top) = stack.last_mut() {
            let (b, k) = *top;
            let kids = self.children(b);
            if (k as usize) < kids.len() {
                let c = kids[k as usize];
                top.1 += 1;
                self.pre[c.index()] = pre;
                pre += 1;
                stack.push((c, 0));
            } else {
                self.post[b.index()] = post;
                post += 1;
                stack.pop();
            }
        }
    }

    /// Reachable blocks in reverse postorder (entry first).
    pub fn rpo(&self) -> &[Block] {
        &self.rpo
    }

    /// True if `b` is reachable from the entry.
    #[inline]
    pub fn is_reachable(&self, b: Block) -> bool {
        self.rpo_num.get(b.index()).is_some_and(|&n| n != NONE)
    }

    /// The position of `b` in reverse postorder, if reachable.
    pub fn rpo_number(&self, b: Block) -> Option<u32> {
        self.rpo_num.get(b.index()).copied().filter(|&n| n != NONE)
    }

    /// The immediate dominator of `b` (`None` for the entry and unreachable blocks).
    #[inline]
    pub fn idom(&self, b: Block) -> Option<Block> {
        let d = *self.idom.get(b.index())?;
        (d != NONE).then_some(Block(d))
    }

    /// Reachable predecessors of `b`, one per edge (a `brif` with both destinations
    /// `b` appears twice).
    pub fn preds(&self, b: Block) -> &[Block] {
        let i = b.index();
        &self.preds[self.pred_start[i] as usize..self.pred_start[i + 1] as usize]
    }

    /// The blocks of the natural loop of `h`, `h` first: every reachable block from
    /// which a back edge into `h` (an edge from a block `h` dominates) is reached
    /// without passing `h`. Just `[h]` when no back edge enters `h`.
    pub fn natural_loop(&self, h: Block) -> Vec<Block> {
        let mut blocks = vec![h];
        let mut seen = vec![false; self.rpo_num.len()];
        seen[h.index()] = true;
        let mut work: Vec<Block> = self
            .preds(h)
            .iter()
            .copied()
            .filter(|&p| self.dominates(h, p))
            .collect();
        while let Some(b) = work.pop() {
            if seen[b.index()] {
                continue;
            }
            seen[b.index()] = true;
            blocks.push(b);
            work.extend(self.preds(b).iter().copied());
        }
        blocks
    }

    /// The back edges of `func` (this tree's function): each edge into a block that
    /// dominates its source, as (source, index of the destination in its
    /// terminator), sources in reverse postorder.
    pub fn back_edges(&self, func: &Function) -> Vec<(Block, usize)> {
        let mut edges = Vec::new();
        for &b in self.rpo() {
            let Some(t) = func.terminator(b) else {
                continue;
            };
            for (k, d) in func.inst(t).dests().enumerate() {
                if self.dominates(d.block, b) {
                    edges.push((b, k));
                }
            }
        }
        edges
    }

    /// The blocks `b` immediately dominates.
    pub fn children(&self, b: Block) -> &[Block] {
        let i = b.index();
        &self.children[self.child_start[i] as usize..self.child_start[i + 1] as usize]
    }

    /// True if every path from the entry to `b` goes through `a`. Every block
    /// dominates itself; otherwise unreachable blocks dominate nothing and are
    /// dominated by nothing. Constant time.
    #[inline]
    pub fn dominates(&self, a: Block, b: Block) -> bool {
        if a == b {
            return true;
        }
        if !self.is_reachable(a) || !self.is_reachable(b) {
            return false;
        }
        self.pre[a.index()] <= self.pre[b.index()] && self.post[a.index()] >= self.post[b.index()]
    }

    /// True if `a` strictly dominates `b`.
    pub fn strictly_dominates(&self, a: Block, b: Block) -> bool {
        a != b && self.dominates(a, b)
    }

    /// The dominance frontier of every reachable block.
    pub fn frontiers(&self) -> DominanceFrontiers {
        let n = self.rpo_num.len();
        let mut df: Vec<Vec<Block>> = vec![Vec::new(); n];
        for &b in &self.rpo {
            let preds = self.preds(b);
            // A join point: two or more predecessors, or the entry with any (the
            // function's start is an implicit extra one).
            let join = preds.len() >= 2 || (b == self.rpo[0] && !preds.is_empty());
            if !join {
                continue;
            }
            let stop = self.idom[b.index()];
            for &p in preds {
                let mut runner = p.0;
                while runner != stop {
                    let list = &mut df[runner as usize];
                    if list.last() != Some(&b) {
                        list.push(b);
                    }
                    runner = self.idom[runner as usize];
                    if runner == NONE {
                        break; // walked past the entry (b is the entry)
                    }
                }
            }
        }
        DominanceFrontiers { df }
    }
}

fn intersect(idom: &[u32], mut a: u32, mut b: u32) -> u32 {
    while a != b {
        while a > b {
            a = idom[a as usize];
        }
        while b > a {
            b = idom[b as usize];
        }
    }
    a
}

/// Dominance frontiers: `DF(b)` is the set of blocks where `b`'s dominance ends (where
/// SSA needs block parameters for values defined in `b`).
#[derive(Clone, Debug)]
pub struct DominanceFrontiers {
    df: Vec<Vec<Block>>,
}

impl DominanceFrontiers {
    /// The dominance frontier of `b` (empty for unreachable blocks).
    pub fn frontier(&self, b: Block) -> &[Block] {
        self.df.get(b.index()).map_or(&[], |v| v.as_slice())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::text::parse_module;

    #[test]
    fn diamond_in_a_loop() {
        // 0 -> 1; 1 -> 2 | 3; 2 -> 4; 3 -> 4; 4 -> 1 | 5; 6 unreachable.
        let m = parse_module(
            r#"
func @f(i1) function {
block0(v0: i1):
    jump block1
block1:
    brif v0, block2, block3
block2:
    jump block4
block3:
    jump block4
block4:
    brif v0, block1, block5
block5:
    return
block6:
    jump block5
}
"#,
        )
        .unwrap();
        let f = &m.funcs[0];
        let dt = DomTree::compute(f);
        let b = Block;
        assert_eq!(dt.rpo()[0], b(0));
        assert_eq!(dt.rpo().len(), 6);
        assert!(!dt.is_reachable(b(6)));
        assert_eq!(dt.idom(b(0)), None);
        assert_eq!(dt.idom(b(1)), Some(b(0)));
        assert_eq!(dt.idom(b(2)), Some(b(1)));
        assert_eq!(dt.idom(b(4)), Some(b(1)));
        assert_eq!(dt.idom(b(5)), Some(b(4)));
        assert!(dt.dominates(b(1), b(5)));
        assert!(!dt.dominates(b(2), b(4)));
        assert!(dt.dominates(b(4), b(4)));
        assert!(!dt.strictly_dominates(b(4), b(4)));
        assert!(!dt.dominates(b(0), b(6)));
        let mut preds = dt.preds(b(4)).to_vec();
        preds.sort();
        assert_eq!(preds, vec![b(2), b(3)]);
        let mut l = dt.natural_loop(b(1));
        l[1..].sort();
        assert_eq!(l, [b(1), b(2), b(3), b(4)]);
        assert_eq!(dt.natural_loop(b(4)), [b(4)]);
        assert_eq!(dt.back_edges(f), [(b(4), 0)]);
        let df = dt.frontiers();
        assert_eq!(df.frontier(b(2)), &[b(4)][..]);
        assert_eq!(df.frontier(b(3)), &[b(4)][..]);
        assert_eq!(df.frontier(b(4)), &[b(1)][..]);
        assert_eq!(df.frontier(b(1)), &[b(1)][..]);
        assert!(df.frontier(b(0)).is_empty());
        assert!(df.frontier(b(5)).is_empty());
    }
}
