//! Loops guarded at entry ([`super`]'s module doc): a copy of the loop without checks,
//! and the test before it that chooses the copy or the loop with its checks.
//!
//! ```text
//! P:   jump H(x, ..)          P:   jump G(x, ..)
//!                             G(c, ..):
//!                                  ok = step >= 1 & step <= S & c >= L
//!                                  brif ok, H'(c, ..), H(c, ..)
//! H(c, ..): the loop          H(c, ..): the loop, checks on its back edges
//!                             H'(c, ..): the same loop without them
//! ```
//!
//! The loop goes on while `counter <= B` (or `<`; signed or unsigned; `B` a constant)
//! and every back edge adds a step to the counter ([`Counted`]). When every step is at
//! least 1 and at most `S` (the type's greatest value less the counter's greatest in
//! the loop), the counter only grows and never wraps, so the loop runs at most `B -
//! c + 1` times from a start `c`; `L` is the lowest start for which that is at most
//! [`MAX_WORK`] instructions. A step that is a constant is checked here, not at run
//! time, and a test that always holds is left out. The steps that are values must
//! not change in the loop (they are defined before it).
//!
//! Values of the loop used after it (other than through its exits' arguments) become
//! parameters of its exit block, passed by the loop's edges and by the copy's: this
//! needs one exit block, entered from the loop only, that dominates every such use;
//! a loop where that fails keeps its checks and gets no copy, as does a loop whose
//! header is the function's entry.

use super::{Counted, MAX_WORK};
use crate::dominators::DomTree;
use crate::entities::{Block, Value};
use crate::function::{Function, ValueDef};
use crate::inst::{BinaryOp, BlockCall, InstData, IntCC};
use crate::passes::util::{def_inst, int_const};
use crate::types::Type;
use rustc_hash::FxHashMap;

/// A loop to copy, and what its test tests.
pub(super) struct Guard {
    /// The loop's blocks, the header first.
    blocks: Vec<Block>,
    /// The counter's index among the header's parameters.
    pos: usize,
    /// Signed or unsigned compares.
    signed: bool,
    /// The steps known only at run time.
    steps: Vec<Value>,
    /// The greatest step that cannot wrap the counter, if some step could.
    max_step: Option<i128>,
    /// The lowest start that keeps the loop short, if some start would not.
    min_start: Option<i128>,
}

impl Guard {
    /// The most instructions the copy and its test add.
    pub(super) fn added(&self, f: &Function) -> usize {
        let copy: usize = self.blocks.iter().map(|&b| f.block(b).insts.len()).sum();
        copy + 4 * self.steps.len() + 4
    }
}

/// The guard of loop `c`, if it can have one (see the module doc).
pub(super) fn guard(f: &Function, c: Counted) -> Option<Guard> {
    let h = c.blocks[0];
    if f.entry() == Some(h) {
        return None;
    }
    let InstData::Brif {
        cond,
        then_dest,
        else_dest,
    } = f.inst(f.terminator(h)?)
    else {
        return None;
    };
    // The compare decides whether the loop goes on: one way leaves it.
    let stays = |d: &crate::inst::BlockCall| c.blocks.contains(&d.block);
    if stays(then_dest) == stays(else_dest) {
        return None;
    }
    let Some(InstData::Icmp { cond: cc, args }) = def_inst(f, *cond) else {
        return None;
    };
    let (mut cc, bound) = if args[0] == c.counter {
        (*cc, args[1])
    } else {
        (cc.swapped(), args[0])
    };
    if bound == c.counter {
        return None;
    }
    // The condition under which the loop goes on.
    if !stays(then_dest) {
        cc = cc.inverted();
    }
    let bits = f.value_type(c.counter).bits();
    let (signed, min, max) = match cc {
        IntCC::Slt | IntCC::Sle => (true, -(1i128 << (bits - 1)), (1i128 << (bits - 1)) - 1),
        IntCC::Ult | IntCC::Ule => (false, 0, (1i128 << bits) - 1),
        _ => return None,
    };
    // A constant in the compare's view (`int_const` is sign-extended).
    let view = |k: i64| {
        if signed {
            i128::from(k)
        } else {
            i128::from(k) & max
        }
    };
    let b = view(int_const(f, bound)?);
    // The counter's greatest value in the loop.
    let top = if matches!(cc, IntCC::Slt | IntCC::Ult) {
        b - 1
    } else {
        b
    };
    let max_step = max - top;
    if top < min || max_step < 1 {
        return None;
    }
    let mut steps = Vec::new();
    for &(s, _) in &c.steps {
        match int_const(f, s).map(view) {
            Some(k) if (1..=max_step).contains(&k) => {}
            Some(_) => return None,
            None if defined_in(f, s, &c.blocks) => return None,
            None if !steps.contains(&s) => steps.push(s),
            None => {}
        }
    }
    let lowest = top + 1 - MAX_WORK / c.size.max(1);
    let min_start = (lowest > min).then_some(lowest);
    if steps.is_empty() && min_start.is_none() {
        // Nothing to test: the ranges saw it short, or it is not (`short_loop`).
        return None;
    }
    Some(Guard {
        blocks: c.blocks,
        pos: c.pos,
        signed,
        max_step: (max_step < max).then_some(max_step),
        steps,
        min_start,
    })
}

/// True if `v` is defined in one of `blocks`.
fn defined_in(f: &Function, v: Value, blocks: &[Block]) -> bool {
    match f.value_def(v) {
        ValueDef::Param(b, _) => blocks.contains(&b),
        ValueDef::Result(i) => blocks.iter().any(|&b| f.block(b).insts.contains(&i)),
    }
}

/// Gives each loop of `guards` its copy and test, where its values used after it can
/// be merged (see [`exit_merge`]).
pub(super) fn copy_all(f: &mut Function, dom: &DomTree, guards: Vec<Guard>) {
    // The loop each block and each value of a guarded loop belongs to.
    let mut block_of: FxHashMap<Block, usize> = FxHashMap::default();
    let mut value_of: FxHashMap<Value, usize> = FxHashMap::default();
    for (k, g) in guards.iter().enumerate() {
        for &b in &g.blocks {
            block_of.insert(b, k);
            for &p in &f.block(b).params {
                value_of.insert(p, k);
            }
            for &i in &f.block(b).insts {
                if let Some(r) = f.result(i) {
                    value_of.insert(r, k);
                }
            }
        }
    }
    // The values of each loop used after it, and where.
    let mut used: Vec<Vec<(Value, Block)>> = vec![Vec::new(); guards.len()];
    for &b in &f.layout {
        let here = block_of.get(&b).copied();
        for &i in &f.block(b).insts {
            f.inst(i).for_each_arg(|v| {
                if let Some(&k) = value_of.get(&v) {
                    if here != Some(k) {
                        used[k].push((v, b));
                    }
                }
            });
        }
    }
    let plans: Vec<Option<Merge>> = guards
        .iter()
        .zip(used)
        .map(|(g, used)| exit_merge(f, dom, g, used))
        .collect();
    for (g, plan) in guards.iter().zip(plans) {
        if let Some(merge) = plan {
            copy(f, g, merge);
        }
    }
}

/// How the values of a loop used after it reach their uses once the loop has a copy:
/// as new parameters of its one exit block.
#[derive(Default)]
struct Merge {
    /// The exit block (none when nothing is used after the loop).
    exit: Option<Block>,
    /// The values, each once.
    values: Vec<Value>,
}

/// The [`Merge`] for loop `g` whose values `used` (with the blocks using them) are
/// used after it: `None` if they cannot be merged, which needs one exit block that
/// only the loop enters and that dominates every use.
fn exit_merge(
    f: &Function,
    dom: &DomTree,
    g: &Guard,
    mut used: Vec<(Value, Block)>,
) -> Option<Merge> {
    if used.is_empty() {
        return Some(Merge::default());
    }
    let mut exit = None;
    for &b in &g.blocks {
        for d in f.inst(f.terminator(b)?).dests() {
            if !g.blocks.contains(&d.block) && exit.replace(d.block).is_some_and(|x| x != d.block) {
                return None;
            }
        }
    }
    let exit = exit?;
    let only_from_loop = f.layout.iter().all(|&b| {
        g.blocks.contains(&b)
            || f.terminator(b)
                .is_none_or(|t| f.inst(t).dests().all(|d| d.block != exit))
    });
    if !only_from_loop || !used.iter().all(|&(_, b)| dom.dominates(exit, b)) {
        return None;
    }
    used.sort_unstable_by_key(|&(v, _)| v.index());
    let mut values: Vec<Value> = used.into_iter().map(|(v, _)| v).collect();
    values.dedup();
    Some(Merge {
        exit: Some(exit),
        values,
    })
}

/// Puts the copy of `g`'s loop and its test into `f`.
fn copy(f: &mut Function, g: &Guard, merge: Merge) {
    let (blocks, values) = clone_loop(f, &g.blocks);
    if let Some(exit) = merge.exit {
        merge_at_exit(f, g, exit, &merge.values, &blocks, &values);
    }
    let test = add_test(f, g, blocks[&g.blocks[0]]);
    // The test just before the loop, the copy just after it.
    let at = f
        .layout
        .iter()
        .position(|&b| b == g.blocks[0])
        .expect("in layout");
    f.layout.insert(at, test);
    let last = f
        .layout
        .iter()
        .rposition(|b| g.blocks.contains(b))
        .expect("in layout");
    let copies: Vec<Block> = f
        .layout
        .iter()
        .filter(|b| g.blocks.contains(b))
        .map(|b| blocks[b])
        .collect();
    f.layout.splice(last + 1..last + 1, copies);
}

/// A copy of `loop_blocks` (not yet in the layout): its blocks and parameters, its
/// instructions, then their operands and the destinations inside the loop renamed.
/// Returns the copy of each block and of each value defined in the loop.
fn clone_loop(
    f: &mut Function,
    loop_blocks: &[Block],
) -> (FxHashMap<Block, Block>, FxHashMap<Value, Value>) {
    let mut blocks: FxHashMap<Block, Block> = FxHashMap::default();
    let mut values: FxHashMap<Value, Value> = FxHashMap::default();
    for &b in loop_blocks {
        let nb = f.create_block();
        blocks.insert(b, nb);
        for p in f.block(b).params.clone() {
            let np = f.append_block_param(nb, f.value_type(p));
            values.insert(p, np);
        }
    }
    let mut made = Vec::new();
    for &b in loop_blocks {
        for i in f.block(b).insts.clone() {
            let ty = f.result(i).map(|r| f.value_type(r));
            let ni = f.create_inst(f.inst(i).clone(), ty, f.spans[i.index()]);
            if let (Some(r), Some(nr)) = (f.result(i), f.result(ni)) {
                values.insert(r, nr);
            }
            f.blocks[blocks[&b].index()].insts.push(ni);
            made.push(ni);
        }
    }
    for ni in made {
        let data = f.inst_mut(ni);
        data.map_args(|v| values.get(&v).copied().unwrap_or(v));
        for d in data.successors_mut() {
            if let Some(&nb) = blocks.get(&d.block) {
                d.block = nb;
            }
        }
    }
    (blocks, values)
}

/// The values of `g`'s loop used after it (`used`) become parameters of its exit
/// block, passed by the loop's edges and by its copy's (`blocks`, `values`); their
/// uses outside the loop read the parameters.
fn merge_at_exit(
    f: &mut Function,
    g: &Guard,
    exit: Block,
    used: &[Value],
    blocks: &FxHashMap<Block, Block>,
    values: &FxHashMap<Value, Value>,
) {
    let mut renamed: FxHashMap<Value, Value> = FxHashMap::default();
    for &v in used {
        renamed.insert(v, f.append_block_param(exit, f.value_type(v)));
    }
    let copies: Vec<Block> = g.blocks.iter().map(|b| blocks[b]).collect();
    for &b in g.blocks.iter().chain(&copies) {
        let t = f.terminator(b).expect("a terminator");
        let in_copy = copies.contains(&b);
        for d in f.inst_mut(t).successors_mut() {
            if d.block == exit {
                d.args.extend(used.iter().map(|v| match in_copy {
                    true => values[v],
                    false => *v,
                }));
            }
        }
    }
    for b in f.layout.clone() {
        if g.blocks.contains(&b) {
            continue;
        }
        for i in f.block(b).insts.clone() {
            f.inst_mut(i)
                .map_args(|v| renamed.get(&v).copied().unwrap_or(v));
        }
    }
}

/// The test block (not yet in the layout), entered instead of `g`'s header from
/// outside the loop: it goes to `copy` (the copy's header) when every test holds,
/// else to the loop.
fn add_test(f: &mut Function, g: &Guard, copy: Block) -> Block {
    let h = g.blocks[0];
    let test = f.create_block();
    let params: Vec<Value> = f
        .block(h)
        .params
        .clone()
        .into_iter()
        .map(|p| f.append_block_param(test, f.value_type(p)))
        .collect();
    for b in f.layout.clone() {
        if g.blocks.contains(&b) {
            continue;
        }
        let Some(t) = f.terminator(b) else { continue };
        for d in f.inst_mut(t).successors_mut() {
            if d.block == h {
                d.block = test;
            }
        }
    }
    let span = f.spans[f.terminator(h).expect("a brif").index()];
    let ty = f.value_type(params[g.pos]);
    let (ge, le) = if g.signed {
        (IntCC::Sge, IntCC::Sle)
    } else {
        (IntCC::Uge, IntCC::Ule)
    };
    let emit = |f: &mut Function, data: InstData, ty: Option<Type>| {
        let i = f.create_inst(data, ty, span);
        f.blocks[test.index()].insts.push(i);
        f.result(i)
    };
    let mut tests = Vec::new();
    let mut compare = |f: &mut Function, cc: IntCC, v: Value, k: i128| {
        let imm = ty.canon_int(k as i64);
        let k = emit(f, InstData::Iconst { ty, imm }, Some(ty)).expect("a constant");
        let args = [v, k];
        tests.push(emit(f, InstData::Icmp { cond: cc, args }, Some(Type::I1)).expect("a flag"));
    };
    for &s in &g.steps {
        compare(f, ge, s, 1);
        if let Some(m) = g.max_step {
            compare(f, le, s, m);
        }
    }
    if let Some(l) = g.min_start {
        compare(f, ge, params[g.pos], l);
    }
    let ok = tests
        .into_iter()
        .reduce(|a, b| {
            let data = InstData::Binary {
                op: BinaryOp::Band,
                args: [a, b],
            };
            emit(f, data, Some(Type::I1)).expect("a flag")
        })
        .expect("a test");
    let br = InstData::Brif {
        cond: ok,
        then_dest: Box::new(BlockCall::new(copy, params.clone())),
        else_dest: Box::new(BlockCall::new(h, params)),
    };
    emit(f, br, None);
    test
}
