//! Watchdog checks on loop back edges.
//!
//! A PLC program that loops forever must not hang the tools that run it. This pass
//! puts a `stop_requested` check on every loop back edge; when the running machine's
//! watchdog fires, the check leaves the function at once (returning zero), every
//! enclosing loop leaves its function the same way, and the scan ends, so the machine
//! can report the overrun. It is for running code under the runner (`plcc run`,
//! `plcc test`); code for a real controller is built without it.
//!
//! A loop that cannot run long gets no check (a load and a branch an iteration, which
//! cost a tight loop up to half its time): one with no loop and no call inside, whose
//! header leaves it on a compare of a counter (a parameter of the header) that every
//! back edge steps up by at least one, where [`ranges`](super::ranges) bounds the
//! counter in the loop to an interval the steps cannot wrap back into: it runs at most
//! [`MAX_WORK`] instructions (iterations times its size). Whatever encloses it keeps
//! its checks.
//!
//! A loop of that shape whose steps or start are not known (the sieve's
//! `j := j + i`, from `j := i * i`) but whose bound is a constant gets a copy without
//! checks, entered when a test before the loop finds the steps at least one (and small
//! enough not to wrap) and the start high enough; otherwise the loop as it was runs,
//! checks and all (`guarded`).

mod guarded;

use crate::dominators::DomTree;
use crate::entities::{Block, Value};
use crate::function::Function;
use crate::inst::{BlockCall, InstData, Intrinsic};
use crate::module::Module;
use crate::types::Type;

/// The most instructions (iterations times the loop's size) a loop without a check
/// may run: a few milliseconds.
pub const MAX_WORK: i128 = 1 << 24;

/// Adds the checks to every function of the module; returns true if it added any.
pub fn run(module: &mut Module) -> bool {
    crate::parallel::each_mut(module.funcs.iter_mut().collect(), run_function)
}

/// Adds the checks to one function.
pub fn run_function(f: &mut Function) -> bool {
    if f.layout.is_empty() {
        return false;
    }
    let dom = DomTree::compute(f);
    let mut edges = dom.back_edges(f);
    // Loops that cannot run long keep no check.
    let mut headers: Vec<Block> = edges
        .iter()
        .map(|&(b, k)| f.inst(f.terminator(b).expect("terminator")).successors()[k].block)
        .collect();
    headers.sort_unstable();
    headers.dedup();
    let mut ranges = None;
    let mut short = Vec::new();
    let mut guards = Vec::new();
    for h in headers {
        let Some(c) = counted(f, &dom, h) else {
            continue;
        };
        if short_loop(f, &c, &mut ranges) {
            short.push(h);
        } else if let Some(g) = guarded::guard(f, c) {
            guards.push(g);
        }
    }
    drop(ranges);
    edges.retain(|&(b, k)| {
        let h = f.inst(f.terminator(b).expect("terminator")).successors()[k].block;
        !short.contains(&h)
    });
    if edges.is_empty() {
        return false;
    }
    // Room for what comes (a compacted function's arenas are full: one more
    // instruction would double them).
    let copies: usize = guards.iter().map(|g| g.added(f)).sum();
    f.reserve(copies + 2 * edges.len() + 2);
    // Copies without checks, made before the checks go in: the copies' back edges
    // are not in `edges`.
    guarded::copy_all(f, &dom, guards);
    // One exit block returning zero (or nothing).
    let bail = f.create_block();
    let ret = f.ret;
    let value = ret.map(|t| {
        let data = if t.is_float() {
            InstData::Fconst { ty: t, bits: 0 }
        } else {
            InstData::Iconst { ty: t, imm: 0 }
        };
        let i = f.create_inst(data, Some(t), None);
        f.blocks[bail.index()].insts.push(i);
        f.result(i).expect("constant")
    });
    let r = f.create_inst(InstData::Return { value }, None, None);
    f.blocks[bail.index()].insts.push(r);
    f.layout.push(bail);
    // Each back edge goes through a new block: check, then go on or leave.
    for (b, k) in edges {
        let t = f.terminator(b).expect("terminator");
        let check = f.create_block();
        let dest = {
            let mut dests = f.inst_mut(t).successors_mut();
            std::mem::replace(dests[k], BlockCall::new(check, Vec::new()))
        };
        let span = f.spans[t.index()];
        let stop = f.create_inst(
            InstData::Intrinsic {
                op: Intrinsic::StopRequested,
                args: Vec::new(),
            },
            Some(Type::I1),
            span,
        );
        let cond = f.result(stop).expect("flag");
        let br = f.create_inst(
            InstData::Brif {
                cond,
                then_dest: Box::new(BlockCall::new(bail, Vec::new())),
                else_dest: Box::new(dest),
            },
            None,
            span,
        );
        f.blocks[check.index()].insts = vec![stop, br];
        let at = f.layout.iter().position(|&x| x == b).expect("in layout");
        f.layout.insert(at + 1, check);
    }
    true
}

/// A loop of the shape the module doc describes: its header leaves on a compare of a
/// counter, every back edge steps the counter up by an `iadd`, and it holds no loop
/// and no call.
struct Counted {
    /// Its blocks, the header first.
    blocks: Vec<Block>,
    /// The counter: a parameter of the header, and its index there.
    counter: Value,
    pos: usize,
    /// Instructions in the loop (an iteration runs at most these).
    size: i128,
    /// The step of each back edge and the block it leaves.
    steps: Vec<(Value, Block)>,
}

/// The loop of header `h` if it has the shape of [`Counted`].
fn counted(f: &Function, dom: &DomTree, h: Block) -> Option<Counted> {
    // The header leaves on `icmp counter, bound`.
    let term = f.terminator(h)?;
    let InstData::Brif { cond, .. } = f.inst(term) else {
        return None;
    };
    let Some(InstData::Icmp { args, .. }) = super::util::def_inst(f, *cond) else {
        return None;
    };
    let params = &f.block(h).params;
    let &counter = args.iter().find(|a| params.contains(a))?;
    let pos = params
        .iter()
        .position(|&p| p == counter)
        .expect("a parameter");
    let ty = f.value_type(counter);
    if !ty.is_int() || ty == Type::I1 {
        return None;
    }
    let blocks = dom.natural_loop(h);
    // No loop and no call inside; the size of an iteration.
    let mut size: i128 = 0;
    for &b in &blocks {
        for &i in &f.block(b).insts {
            size += 1;
            match f.inst(i) {
                InstData::Call { .. } | InstData::CallTable { .. } | InstData::InlineC { .. } => {
                    return None
                }
                data => {
                    if data
                        .dests()
                        .any(|d| d.block != h && dom.dominates(d.block, b))
                    {
                        return None;
                    }
                }
            }
        }
    }
    // Every back edge steps the counter: `counter + s`.
    let mut steps = Vec::new();
    for &b in &blocks[1..] {
        let t = f.terminator(b).expect("terminator");
        for d in f.inst(t).dests().filter(|d| d.block == h) {
            let next = d.args[pos];
            let Some(InstData::Binary {
                op: crate::inst::BinaryOp::Iadd,
                args: [x, step],
            }) = super::util::def_inst(f, next)
            else {
                return None;
            };
            match (*x == counter, *step == counter) {
                (true, _) => steps.push((*step, b)),
                (_, true) => steps.push((*x, b)),
                _ => return None,
            }
        }
    }
    Some(Counted {
        blocks,
        counter,
        pos,
        size,
        steps,
    })
}

/// True if the loop `c` cannot run long (see the module doc).
fn short_loop<'f>(
    f: &'f Function,
    c: &Counted,
    ranges: &mut Option<super::ranges::ValueRanges<'f>>,
) -> bool {
    let Counted {
        blocks,
        counter,
        size,
        steps,
        ..
    } = c;
    let (counter, size) = (*counter, *size);
    let ty = f.value_type(counter);
    // By at least 1 (the ranges are worked out only for loops that got this far).
    let r = ranges.get_or_insert_with(|| super::ranges::ValueRanges::new(f));
    let (mut s_lo, mut s_hi) = (i128::MAX, i128::MIN);
    for &(step, b) in steps {
        let Some((lo, hi)) = r.at(step, b) else {
            return false;
        };
        s_lo = s_lo.min(lo);
        s_hi = s_hi.max(hi);
    }
    if s_lo < 1 {
        return false;
    }
    // The counter's range in the loop, where the header's test let it in.
    let inside = blocks[1..].iter().filter_map(|&b| r.at(counter, b)).fold(
        None,
        |acc: Option<(i128, i128)>, (lo, hi)| {
            Some(acc.map_or((lo, hi), |(a, z)| (a.min(lo), z.max(hi))))
        },
    );
    let Some((lo, hi)) = inside else {
        return false;
    };
    // A step that wraps lands below `lo` (out of the loop) unless it is this large.
    let width = 1i128 << ty.bits();
    if s_hi >= width - (hi - lo) {
        return false;
    }
    let trips = (hi - lo) / s_lo + 1;
    trips.saturating_mul(size) <= MAX_WORK
}
