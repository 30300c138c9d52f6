//! Global value numbering: an instruction that computes the same thing as one that
//! dominates it is replaced by that one's result.
//!
//! Front ends recompute freely (every mention of `t.Q` builds its address again, every
//! bounds check repeats its constants); this pass folds such repeats across blocks. It
//! walks the dominator tree with a scoped table of pure instructions. Pure here means
//! the result depends only on the operands: arithmetic, comparisons, conversions,
//! selects, constants and address computations, and the clock (constant within a
//! scan). Division is included although it can raise the fault flag: a repeat is only
//! removed when the first one dominates it, so the flag was raised already. Loads are
//! left to `load_store`, which knows about memory.

use crate::dominators::DomTree;
use crate::entities::{Block, Value};
use crate::function::Function;
use crate::inst::{InstData, Intrinsic};
use rustc_hash::FxHashMap;

/// Runs value numbering on `func`; returns true if any use was redirected.
pub fn run(func: &mut Function) -> bool {
    let Some(entry) = func.entry() else {
        return false;
    };
    let dom = DomTree::compute(func);
    let mut table: FxHashMap<InstData, Value> = FxHashMap::default();
    // Undo log: keys inserted in each open dominator-tree scope.
    let mut scopes: Vec<Vec<InstData>> = Vec::new();
    let mut replace: Vec<Option<Value>> = vec![None; func.values.len()];
    let mut changed = false;
    // Explicit DFS: (block, next child index).
    let mut stack: Vec<(Block, usize)> = vec![(entry, 0)];
    scopes.push(visit_block(
        func,
        entry,
        &mut table,
        &mut replace,
        &mut changed,
    ));
    while let Some(top) = stack.last_mut() {
        let (b, next) = *top;
        let children = dom.children(b);
        if next < children.len() {
            top.1 += 1;
            let c = children[next];
            scopes.push(visit_block(func, c, &mut table, &mut replace, &mut changed));
            stack.push((c, 0));
        } else {
            for key in scopes.pop().unwrap_or_default() {
                table.remove(&key);
            }
            stack.pop();
        }
    }
    if !changed {
        return false;
    }
    // A repeat whose result nothing uses changes nothing (a division, which may fault,
    // stays even when its result is unused): report only rewritten operands, so that
    // optimising again finds nothing to do.
    let resolve = |v: Value, r: &Vec<Option<Value>>| {
        let mut v = v;
        while let Some(Some(n)) = r.get(v.index()) {
            v = *n;
        }
        v
    };
    let mut rewritten = false;
    let live: Vec<_> = func.inst_iter().map(|(_, i)| i).collect();
    for i in live {
        func.inst_mut(i).map_args(|v| {
            let n = resolve(v, &replace);
            rewritten |= n != v;
            n
        });
    }
    rewritten
}

/// Numbers the instructions of one block; returns the keys it added to the table.
fn visit_block(
    func: &Function,
    b: Block,
    table: &mut FxHashMap<InstData, Value>,
    replace: &mut [Option<Value>],
    changed: &mut bool,
) -> Vec<InstData> {
    let mut added = Vec::new();
    for &i in &func.block(b).insts {
        let Some(result) = func.result(i) else {
            continue;
        };
        let Some(mut key) = pure_key(func.inst(i)) else {
            continue;
        };
        // Operands already known equal to earlier values make equal keys.
        key.map_args(|v| {
            let mut v = v;
            while let Some(Some(n)) = replace.get(v.index()) {
                v = *n;
            }
            v
        });
        canonicalise(&mut key);
        match table.get(&key) {
            Some(&earlier) if func.value_type(earlier) == func.value_type(result) => {
                replace[result.index()] = Some(earlier);
                *changed = true;
            }
            Some(_) => {}
            None => {
                table.insert(key.clone(), result);
                added.push(key);
            }
        }
    }
    added
}

/// The instruction as a table key if its result depends only on its operands.
fn pure_key(data: &InstData) -> Option<InstData> {
    match data {
        InstData::Iconst { .. }
        | InstData::Fconst { .. }
        | InstData::Unary { .. }
        | InstData::Binary { .. }
        | InstData::Icmp { .. }
        | InstData::Fcmp { .. }
        | InstData::Convert { .. }
        | InstData::Select { .. }
        | InstData::GlobalAddr { .. }
        | InstData::SlotAddr { .. }
        | InstData::FieldAddr { .. }
        | InstData::ElemAddr { .. } => Some(data.clone()),
        InstData::Intrinsic {
            op: Intrinsic::ClockMs | Intrinsic::ClockNs,
            ..
        } => Some(data.clone()),
        _ => None,
    }
}

/// Orders the operands of commutative operations so `a+b` and `b+a` meet.
fn canonicalise(key: &mut InstData) {
    match key {
        InstData::Binary { op, args } if op.is_commutative() && args[1] < args[0] => {
            args.swap(0, 1)
        }
        InstData::Icmp { cond, args } if args[1] < args[0] => {
            args.swap(0, 1);
            *cond = cond.swapped();
        }
        _ => {}
    }
}
