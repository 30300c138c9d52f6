//! Per-function work spread over the machine's cores.
//!
//! Most passes and checks treat each function on its own; on a large program that
//! work is split among threads (at most eight), the largest functions first, each to
//! the least loaded thread. Small modules stay on the calling thread: starting
//! threads would cost more than it saves. Results come back in the functions' order,
//! so output never depends on the split.

use crate::function::Function;

/// Below this many instructions in all, the work stays on the calling thread (and,
/// elsewhere, a module is too small to be worth a thread of its own).
pub const MIN_INSTS: usize = 20_000;

/// The number of threads to use: the cores available, at most eight.
pub fn threads() -> usize {
    std::thread::available_parallelism()
        .map(|n| n.get())
        .unwrap_or(1)
        .min(8)
}

/// Runs `a` on the calling thread and `b` on another at the same time; returns both
/// results (a panic in `b` goes on here). For work split in two halves.
pub fn join<A, B: Send>(a: impl FnOnce() -> A, b: impl FnOnce() -> B + Send) -> (A, B) {
    std::thread::scope(|scope| {
        let other = scope.spawn(b);
        let a = a();
        let b = other
            .join()
            .unwrap_or_else(|p| std::panic::resume_unwind(p));
        (a, b)
    })
}

/// Groups the indexes of functions of the given sizes (instructions) into at most
/// [`threads`] loads of about equal size; `None` when it is not worth threads.
fn groups(sizes: &[usize]) -> Option<Vec<Vec<usize>>> {
    let threads = threads();
    if threads < 2 || sizes.iter().sum::<usize>() < MIN_INSTS {
        return None;
    }
    let mut order: Vec<usize> = (0..sizes.len()).collect();
    order.sort_by_key(|&i| std::cmp::Reverse(sizes[i]));
    let mut groups: Vec<(usize, Vec<usize>)> = (0..threads).map(|_| (0, Vec::new())).collect();
    for i in order {
        let g = groups
            .iter_mut()
            .min_by_key(|(load, _)| *load)
            .expect("at least one group");
        g.0 += sizes[i];
        g.1.push(i);
    }
    Some(groups.into_iter().map(|(_, g)| g).collect())
}

/// Runs `work` on each function; true if any call returned true.
pub fn each_mut(funcs: Vec<&mut Function>, work: impl Fn(&mut Function) -> bool + Sync) -> bool {
    each_mut_by(funcs, |f| f.insts.len(), work)
}

/// Runs `work` on each item, the items weighed by `size` (instructions: the loads
/// are balanced by it, and below [`MIN_INSTS`] in all everything stays on the
/// calling thread); true if any call returned true.
pub fn each_mut_by<T: Send>(
    items: Vec<&mut T>,
    size: impl Fn(&T) -> usize,
    work: impl Fn(&mut T) -> bool + Sync,
) -> bool {
    let sizes: Vec<usize> = items.iter().map(|t| size(t)).collect();
    let Some(groups) = groups(&sizes) else {
        return items.into_iter().fold(false, |any, t| work(t) | any);
    };
    let mut slots: Vec<Option<&mut T>> = items.into_iter().map(Some).collect();
    let parts: Vec<Vec<&mut T>> = groups
        .into_iter()
        .map(|g| g.into_iter().filter_map(|i| slots[i].take()).collect())
        .collect();
    let work = &work;
    std::thread::scope(|scope| {
        let handles: Vec<_> = parts
            .into_iter()
            .map(|part| scope.spawn(move || part.into_iter().fold(false, |any, f| work(f) | any)))
            .collect();
        handles
            .into_iter()
            .map(|h| h.join().unwrap_or_else(|p| std::panic::resume_unwind(p)))
            .fold(false, |a, b| a | b)
    })
}

/// `work` of each function, in the functions' order.
pub fn map<T: Send>(funcs: &[Function], work: impl Fn(&Function) -> T + Sync) -> Vec<T> {
    let sizes: Vec<usize> = funcs.iter().map(|f| f.insts.len()).collect();
    let Some(groups) = groups(&sizes) else {
        return funcs.iter().map(work).collect();
    };
    let work = &work;
    let done: Vec<Vec<(usize, T)>> = std::thread::scope(|scope| {
        let handles: Vec<_> = groups
            .into_iter()
            .map(|g| scope.spawn(move || g.into_iter().map(|i| (i, work(&funcs[i]))).collect()))
            .collect();
        handles
            .into_iter()
            .map(|h| h.join().unwrap_or_else(|p| std::panic::resume_unwind(p)))
            .collect()
    });
    let mut out: Vec<Option<T>> = funcs.iter().map(|_| None).collect();
    for (i, t) in done.into_iter().flatten() {
        out[i] = Some(t);
    }
    out.into_iter()
        .map(|t| t.expect("every function done"))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn join_returns_both_halves_and_passes_a_panic_on() {
        let (mut left, mut right) = (Vec::new(), Vec::new());
        let (a, b) = join(|| left.push(1), || right.push(2));
        assert_eq!((a, b, left, right), ((), (), vec![1], vec![2]));
        let caught = std::panic::catch_unwind(|| join(|| 1, || -> u8 { panic!("second half") }));
        assert!(caught.is_err());
    }
    use crate::builder::FuncBuilder;
    use crate::function::FuncKind;
    use crate::types::Type;

    /// Functions of different sizes, enough for threads.
    fn funcs() -> Vec<Function> {
        (0..40)
            .map(|k| {
                let mut f = Function::new(format!("f{k}"), FuncKind::Function, Vec::new(), None);
                let mut b = FuncBuilder::new(&mut f);
                for n in 0..(k * 37 % 1000 + 100) {
                    b.iconst(Type::I32, n as i64);
                }
                b.ret(None);
                f
            })
            .collect()
    }

    #[test]
    fn results_come_in_order_and_every_function_is_done_once() {
        let mut fs = funcs();
        assert!(fs.iter().map(|f| f.insts.len()).sum::<usize>() >= MIN_INSTS);
        let names = map(&fs, |f| f.name.clone());
        assert_eq!(names, fs.iter().map(|f| f.name.clone()).collect::<Vec<_>>());
        let any = each_mut(fs.iter_mut().collect(), |f| {
            f.name.push('!');
            f.name == "f7!"
        });
        assert!(any);
        assert!(fs
            .iter()
            .all(|f| f.name.ends_with('!') && !f.name.ends_with("!!")));
        assert!(!each_mut(fs.iter_mut().collect(), |_| false));
    }
}
