//! The order in which the elements of a graphical body run.
//!
//! Two kinds of order, one per way of lowering (see `body`):
//!
//! - [`network`]: the standard's. Within a network (a rung, a connected FBD network)
//!   an element runs once, after every element wired to its inputs; among the
//!   elements ready at the same time the one with the smaller `executionOrderId` goes
//!   first, then the topmost, then the leftmost, then the first in the document. A
//!   loop is cut at a block: when nothing is ready, the first block on a loop runs,
//!   reading what the loop gives it from the previous scan. A loop through contacts and coils
//!   alone has no meaning (no block to cut it at).
//! - [`sinks`]: the editors'. PLCGenerator (Beremiz, OpenPLC Editor) writes one
//!   statement per sink (variable, coil, block, connector) in an order of its own:
//!   the elements with an `executionOrderId` first, by id; then, in document order,
//!   every variable and coil, every block, every connector (`Order::Document`); or
//!   all of them sorted by position as CPython's `list.sort` sorts them with the
//!   generator's comparator (`Order::Position`); or each group sorted by position
//!   (`Order::PositionGrouped`, the Python-2 era).

use super::graph::Graph;
use super::xml::{Element, Kind};

/// The sort key of an element among those ready at the same time.
fn key(e: &Element, i: usize) -> (u32, f64, f64, usize) {
    let (x, y) = e.pos.unwrap_or((0.0, 0.0));
    (e.order.unwrap_or(0), y, x, i)
}

/// The standard's order of the elements `members` of one network: wired inputs
/// first, loops cut at blocks. `Err(e)` names an element of a loop that goes through
/// no block.
pub(crate) fn network(g: &Graph, members: &[usize]) -> Result<Vec<usize>, usize> {
    let n = g.elems.len();
    let mut inside = vec![false; n];
    for &e in members {
        inside[e] = true;
    }
    let mut waiting = vec![0usize; n];
    for &e in members {
        waiting[e] = g.ins[e].iter().flatten().filter(|s| inside[s.elem]).count();
    }
    let mut done = vec![false; n];
    let mut ready: Vec<usize> = members
        .iter()
        .copied()
        .filter(|&e| waiting[e] == 0)
        .collect();
    let mut order = Vec::with_capacity(members.len());
    while order.len() < members.len() {
        if ready.is_empty() {
            // A loop: its first block runs with what it has. (Only a block on a loop
            // among the elements left: one that merely waits for a loop must wait;
            // and first a block whose inputs still missing all come from its own
            // loops, so that a block fed by another loop waits for it.)
            let reach = |b: usize| {
                let mut seen = vec![false; n];
                let mut stack = vec![b];
                while let Some(x) = stack.pop() {
                    for port in &g.outs[x] {
                        for &(c, _) in port {
                            if inside[c] && !done[c] && !seen[c] {
                                seen[c] = true;
                                stack.push(c);
                            }
                        }
                    }
                }
                seen
            };
            let first = |list: &mut dyn Iterator<Item = usize>| {
                list.min_by(|&a, &b| {
                    key(&g.elems[a], a)
                        .partial_cmp(&key(&g.elems[b], b))
                        .unwrap_or(std::cmp::Ordering::Equal)
                })
            };
            let on_loop: Vec<(usize, bool)> = members
                .iter()
                .copied()
                .filter(|&e| !done[e] && matches!(g.elems[e].kind, Kind::Block { .. }))
                .filter_map(|e| {
                    let r = reach(e);
                    r[e].then(|| {
                        let closed = g.ins[e]
                            .iter()
                            .flatten()
                            .all(|s| !inside[s.elem] || done[s.elem] || r[s.elem]);
                        (e, closed)
                    })
                })
                .collect();
            let cut = first(&mut on_loop.iter().filter(|x| x.1).map(|x| x.0))
                .or_else(|| first(&mut on_loop.iter().map(|x| x.0)));
            match cut {
                Some(b) => ready.push(b),
                None => {
                    let stuck = members.iter().copied().find(|&e| !done[e]);
                    return Err(stuck.expect("some element is left"));
                }
            }
        }
        let (i, _) = ready
            .iter()
            .enumerate()
            .min_by(|(_, &a), (_, &b)| {
                key(&g.elems[a], a)
                    .partial_cmp(&key(&g.elems[b], b))
                    .unwrap_or(std::cmp::Ordering::Equal)
            })
            .expect("not empty");
        let e = ready.swap_remove(i);
        if done[e] {
            continue;
        }
        done[e] = true;
        order.push(e);
        for port in &g.outs[e] {
            for &(c, _) in port {
                if inside[c] && !done[c] {
                    waiting[c] = waiting[c].saturating_sub(1);
                    if waiting[c] == 0 && !ready.contains(&c) {
                        ready.push(c);
                    }
                }
            }
        }
    }
    Ok(order)
}

/// How the editors order the statements that have no `executionOrderId`.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub(crate) enum Order {
    /// Variables and coils, then blocks, then connectors, each in document order
    /// (Beremiz, OpenPLC Editor v3).
    Document,
    /// All of them sorted by position (OpenPLC Editor v4's xml2st).
    Position,
    /// Variables and coils sorted by position, then blocks sorted by position, then
    /// connectors (the Python-2 era of both editors).
    PositionGrouped,
}

/// The sinks of a body (the elements that give a statement in PLCGenerator), in the
/// order it writes them.
pub(crate) fn sinks(elems: &[Element], order: Order) -> Vec<usize> {
    let mut ordered: Vec<usize> = Vec::new();
    let (mut vars, mut blocks, mut conns) = (Vec::new(), Vec::new(), Vec::new());
    for (i, e) in elems.iter().enumerate() {
        let has_id = e.order.is_some();
        match &e.kind {
            Kind::OutVariable { .. } | Kind::InOutVariable { .. } | Kind::Block { .. }
                if has_id =>
            {
                ordered.push(i)
            }
            Kind::OutVariable { .. } | Kind::InOutVariable { .. } | Kind::Coil { .. } => {
                vars.push(i)
            }
            Kind::Block { .. } => blocks.push(i),
            Kind::Connector { .. } => conns.push(i),
            _ => {}
        }
    }
    // A stable sort by id.
    ordered.sort_by_key(|&i| elems[i].order.unwrap_or(0));
    match order {
        Order::Document => {
            ordered.extend(vars);
            ordered.extend(blocks);
            ordered.extend(conns);
        }
        Order::PositionGrouped => {
            let by_pos = |a: usize, b: usize| position_lt(&elems[a], &elems[b]);
            python_sort(&mut vars, by_pos);
            python_sort(&mut blocks, by_pos);
            ordered.extend(vars);
            ordered.extend(blocks);
            ordered.extend(conns);
        }
        Order::Position => {
            let mut rest: Vec<usize> = vars.into_iter().chain(blocks).chain(conns).collect();
            python_sort(&mut rest, |a, b| position_lt(&elems[a], &elems[b]));
            ordered.extend(rest);
        }
    }
    ordered
}

/// PLCGenerator's position comparator: within 10 units of height, left to right;
/// else top to bottom. Not transitive on staggered layouts.
fn position_lt(a: &Element, b: &Element) -> bool {
    let (ax, ay) = a.pos.unwrap_or((0.0, 0.0));
    let (bx, by) = b.pos.unwrap_or((0.0, 0.0));
    if (ay - by).abs() < 10.0 {
        ax < bx
    } else {
        ay < by
    }
}

/// Sorts as CPython's `list.sort` does with the comparison `lt`, so that a comparator
/// that is not a total order gives the same result: below 64 elements CPython takes
/// the initial run (non-descending, or strictly descending and then reversed) and
/// inserts the others one by one by binary search, to the right of equal ones. Longer
/// lists are merge-sorted, stably (CPython's timsort gives the same result for any
/// total order; for the generator's comparator on a long staggered list it may not).
pub(crate) fn python_sort(v: &mut [usize], lt: impl Fn(usize, usize) -> bool) {
    let n = v.len();
    if n < 2 {
        return;
    }
    if n >= 64 {
        v.sort_by(|&a, &b| {
            if lt(a, b) {
                std::cmp::Ordering::Less
            } else if lt(b, a) {
                std::cmp::Ordering::Greater
            } else {
                std::cmp::Ordering::Equal
            }
        });
        return;
    }
    // count_run
    let mut run = 2;
    if lt(v[1], v[0]) {
        while run < n && lt(v[run], v[run - 1]) {
            run += 1;
        }
        v[..run].reverse();
    } else {
        while run < n && !lt(v[run], v[run - 1]) {
            run += 1;
        }
    }
    // binary insertion
    for i in run..n {
        let pivot = v[i];
        let (mut lo, mut hi) = (0, i);
        while lo < hi {
            let mid = (lo + hi) / 2;
            if lt(pivot, v[mid]) {
                hi = mid;
            } else {
                lo = mid + 1;
            }
        }
        v[lo..=i].rotate_right(1);
    }
}

#[cfg(test)]
mod tests {
    use super::python_sort;

    #[test]
    fn sorts_like_cpython_for_a_total_order() {
        let mut v = vec![5, 3, 9, 1, 1, 7, 0, 2];
        python_sort(&mut v, |a, b| a < b);
        assert_eq!(v, vec![0, 1, 1, 2, 3, 5, 7, 9]);
    }

    #[test]
    fn keeps_equal_elements_in_order() {
        // Elements compare by tens only: 12 and 15 are equal.
        let mut v = vec![15, 12, 3, 19];
        python_sort(&mut v, |a, b| a / 10 < b / 10);
        assert_eq!(v, vec![3, 15, 12, 19]);
    }

    #[test]
    fn reverses_a_strictly_descending_run() {
        let mut v = vec![9, 7, 4, 8];
        python_sort(&mut v, |a, b| a < b);
        assert_eq!(v, vec![4, 7, 8, 9]);
    }
}
