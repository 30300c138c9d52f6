//! The call graph of a module.
//!
//! A `call_table` calls every entry of its table as far as the call graph is
//! concerned: any of them may run, so recursion checks, stack depths and the
//! reachability of functions count them all.

use crate::entities::FuncId;
use crate::inst::InstData;
use crate::module::Module;

/// Function ids ordered so that every callee comes before its callers.
pub fn callees_first(module: &Module) -> Vec<FuncId> {
    let n = module.funcs.len();
    let mut state = vec![0u8; n];
    let mut order = Vec::with_capacity(n);
    for start in 0..n {
        if state[start] != 0 {
            continue;
        }
        // Iterative post-order DFS over call edges.
        let mut stack: Vec<(usize, Vec<usize>)> = vec![(start, callees(module, start))];
        state[start] = 1;
        while let Some((node, pending)) = stack.last_mut() {
            if let Some(next) = pending.pop() {
                if state[next] == 0 {
                    state[next] = 1;
                    let c = callees(module, next);
                    stack.push((next, c));
                }
            } else {
                state[*node] = 2;
                order.push(FuncId::new(*node));
                stack.pop();
            }
        }
    }
    order
}

/// The functions reachable from `roots` by calls, ordered so that every caller comes
/// before its callees (a reverse post-order of a depth-first walk from the roots in
/// their order, the callees of each function in index order). Functions no root
/// reaches are left out. With recursion (which the verifier rejects) the order within
/// a cycle is arbitrary.
pub fn callers_first_from(module: &Module, roots: &[FuncId]) -> Vec<FuncId> {
    let n = module.funcs.len();
    let mut state = vec![false; n];
    let mut post = Vec::with_capacity(n);
    for &root in roots {
        if root.index() >= n || state[root.index()] {
            continue;
        }
        // Iterative post-order DFS; each frame's pending callees in reverse so that
        // the lowest index is walked first.
        let pending = |f: usize| {
            let mut c = callees(module, f);
            c.reverse();
            c
        };
        let mut stack: Vec<(usize, Vec<usize>)> = vec![(root.index(), pending(root.index()))];
        state[root.index()] = true;
        while let Some((node, next)) = stack.last_mut() {
            match next.pop() {
                Some(g) if !state[g] => {
                    state[g] = true;
                    stack.push((g, pending(g)));
                }
                Some(_) => {}
                None => {
                    post.push(FuncId::new(*node));
                    stack.pop();
                }
            }
        }
    }
    post.reverse();
    post
}

/// The functions an instruction may call: the callee of a `call`, every entry of the
/// table of a `call_table` (ids out of range left out), none for other instructions.
pub fn inst_callees(module: &Module, data: &InstData) -> Vec<FuncId> {
    let n = module.funcs.len();
    match data {
        InstData::Call { func, .. } if func.index() < n => vec![*func],
        InstData::CallTable { table, .. } => module
            .tables
            .get(table.index())
            .map(|t| {
                t.entries
                    .iter()
                    .flatten()
                    .copied()
                    .filter(|f| f.index() < n)
                    .collect()
            })
            .unwrap_or_default(),
        _ => Vec::new(),
    }
}

/// The functions `f` calls (directly or through a table), each once.
pub fn callees(module: &Module, f: usize) -> Vec<usize> {
    let func = &module.funcs[f];
    let mut out: Vec<usize> = func
        .inst_iter()
        .flat_map(|(_, i)| inst_callees(module, func.inst(i)))
        .map(FuncId::index)
        .collect();
    out.sort_unstable();
    out.dedup();
    out
}

/// The longest chain of nested calls below each function (0 for one that calls
/// nothing), indexed by function. There is no recursion (the verifier rejects it).
pub fn call_depths(module: &Module) -> Vec<usize> {
    let mut depth = vec![0usize; module.funcs.len()];
    for f in callees_first(module) {
        depth[f.index()] = callees(module, f.index())
            .into_iter()
            .map(|c| depth[c] + 1)
            .max()
            .unwrap_or(0);
    }
    depth
}

/// A cycle of the call graph, if there is one: functions each of which calls the next
/// (the last calls the first), directly or through a table. The verifier rejects
/// such a module; a backend whose frames are static checks it too rather than trust
/// that the verifier ran.
pub fn find_recursion(module: &Module) -> Option<Vec<FuncId>> {
    let n = module.funcs.len();
    // 0 = not visited, 1 = on the current path, 2 = done.
    let mut state = vec![0u8; n];
    for start in 0..n {
        if state[start] != 0 {
            continue;
        }
        let mut path: Vec<(usize, Vec<usize>)> = vec![(start, callees(module, start))];
        state[start] = 1;
        while let Some((node, pending)) = path.last_mut() {
            let node = *node;
            match pending.pop() {
                Some(next) if state[next] == 1 => {
                    let at = path.iter().position(|(f, _)| *f == next).unwrap_or(0);
                    return Some(path[at..].iter().map(|(f, _)| FuncId::new(*f)).collect());
                }
                Some(next) if state[next] == 0 => {
                    state[next] = 1;
                    let c = callees(module, next);
                    path.push((next, c));
                }
                Some(_) => {}
                None => {
                    state[node] = 2;
                    path.pop();
                }
            }
        }
    }
    None
}

/// The names of a cycle of [`find_recursion`], `@a -> @b -> @a`.
pub fn describe_cycle(module: &Module, cycle: &[FuncId]) -> String {
    cycle
        .iter()
        .chain(cycle.first())
        .map(|f| format!("@{}", module.func(*f).name))
        .collect::<Vec<_>>()
        .join(" -> ")
}
