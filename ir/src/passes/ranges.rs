//! Value ranges: integer comparisons decided by what is known of their operands, so
//! that the bounds checks of array accesses inside loops go where the index cannot
//! leave the array.
//!
//! Two steps, then the usual cleanup (constant folding, CFG simplification, DCE):
//! 1. **Branches on a constant argument are threaded**: a block whose only
//!    instruction is `brif p` on its own parameter `p`, and whose parameters nothing
//!    else reads, reached by an edge passing a constant for `p`, is bypassed on that
//!    edge (the edge goes straight to the destination the constant picks). The fault path of a checked read (`0` for
//!    the value read) no longer joins the code after a successful read.
//! 2. **Ranges** (signed intervals in the width of each integer value) are computed
//!    from constants, arithmetic that cannot wrap, selects, extensions, and the
//!    conditions of branches: on the edge into a block that has no other
//!    predecessor, `x <s y` (and the other compares) bound `x` by `y`'s range, in
//!    that block and every block it dominates (the operands are SSA values, so the
//!    fact holds there; `x <u N` gives `0 <= x < N`). A value's range at a block is
//!    worked out from its operands' ranges at that block, so a product computed
//!    before a check of its factors is bounded after it. Block parameters take the
//!    union of their incoming arguments, iterated to a fixed point; a bound that
//!    keeps moving goes to its end of the type (so loops end, and a counter counting
//!    up keeps its start). A compare whose operands' ranges decide it becomes a
//!    constant.
//!
//! Everything is sound for the IR's wrapping arithmetic: an operation whose exact
//! result could leave its type's range gives the whole range; `i1` values are not
//! read as signed numbers (the contract leaves that open).

use crate::dominators::DomTree;
use crate::entities::{Block, Inst, Value};
use crate::function::{Function, ValueDef};
use crate::inst::{BinaryOp, BlockCall, ConvOp, InstData, IntCC, UnaryOp};
use crate::types::Type;

/// An inclusive interval in the signed domain of a value's width; `None` is empty
/// (no value reaches: unreachable so far).
type R = Option<(i128, i128)>;

/// How deep a value's range is worked out from its operands at one block.
const DEPTH: u32 = 6;

/// Times a bound of a block parameter's range may move before it goes to its end of
/// the type.
const WIDEN_AFTER: u32 = 3;

/// Rounds of the fixed point at most (each after the first widens something or
/// stops).
const MAX_ROUNDS: usize = 64;

/// Runs both steps and the cleanup on `func`; true if it changed.
pub fn run(func: &mut Function) -> bool {
    if func.layout.is_empty() {
        return false;
    }
    let mut changed = thread_constant_branches(func);
    let decided = Ranges::new(func).decide();
    for (i, truth) in &decided {
        *func.inst_mut(*i) = InstData::Iconst {
            ty: Type::I1,
            imm: *truth as i64,
        };
    }
    changed |= !decided.is_empty();
    if changed {
        super::cleanup(func, super::ALL);
    }
    changed
}

/// [`run`] on every function of `module` (what the compiling targets do before
/// translating it). True if a function changed.
pub fn run_module(module: &mut crate::module::Module) -> bool {
    module
        .funcs
        .iter_mut()
        .fold(false, |changed, f| run(f) | changed)
}

/// Step 1: edges passing a constant to a block that only branches on it go straight
/// to the chosen destination. True if an edge moved.
fn thread_constant_branches(func: &mut Function) -> bool {
    // The values something reads, but for the branch that is all of its block reading
    // that block's parameters: past such a block, the parameters have no value.
    let mut read = vec![false; func.values.len()];
    for &b in &func.layout {
        let insts = &func.block(b).insts;
        let params = &func.block(b).params;
        let lone = insts.len() == 1;
        for &i in insts {
            func.inst(i).for_each_arg(|a| {
                if !(lone && params.contains(&a)) {
                    read[a.index()] = true;
                }
            });
        }
    }
    let mut changed = false;
    let blocks = func.layout.clone();
    for &p in &blocks {
        let Some(&term) = func.blocks[p.index()].insts.last() else {
            continue;
        };
        let mut data = func.inst(term).clone();
        let mut moved = false;
        for dest in data.successors_mut() {
            moved |= thread(func, dest, &mut read);
        }
        if moved {
            *func.inst_mut(term) = data;
            changed = true;
        }
    }
    changed
}

/// Redirects `call` past its destination if that block only branches on one of its
/// parameters, nothing else reads them (`read`), and `call` passes a constant for the
/// condition. True if it did.
fn thread(func: &Function, call: &mut BlockCall, read: &mut [bool]) -> bool {
    let b = call.block;
    let insts = &func.block(b).insts;
    let [only] = insts.as_slice() else {
        return false;
    };
    let InstData::Brif {
        cond,
        then_dest,
        else_dest,
    } = func.inst(*only)
    else {
        return false;
    };
    let params = &func.block(b).params;
    let Some(k) = params.iter().position(|p| p == cond) else {
        return false;
    };
    if params.iter().any(|p| read[p.index()]) {
        return false;
    }
    let Some(c) = int_const(func, call.args[k]) else {
        return false;
    };
    let dest = if c & 1 != 0 { then_dest } else { else_dest };
    if dest.block == b {
        return false;
    }
    // The destination's arguments, with `b`'s parameters replaced by what this edge
    // passes (any other value is defined above `b`, so above this edge too).
    let args: Vec<Value> = dest
        .args
        .iter()
        .map(|a| match params.iter().position(|p| p == a) {
            Some(j) => call.args[j],
            None => *a,
        })
        .collect();
    for a in &args {
        read[a.index()] = true;
    }
    *call = BlockCall::new(dest.block, args);
    true
}

/// The integer constant `v` is, if it is one.
fn int_const(func: &Function, v: Value) -> Option<i64> {
    match func.value_def(v) {
        ValueDef::Result(i) => match *func.inst(i) {
            InstData::Iconst { imm, .. } => Some(imm),
            _ => None,
        },
        ValueDef::Param(..) => None,
    }
}

/// The whole range of an integer type.
fn full(ty: Type) -> (i128, i128) {
    match ty {
        Type::I1 => (0, 1),
        _ => {
            let w = ty.bits();
            (-(1i128 << (w - 1)), (1i128 << (w - 1)) - 1)
        }
    }
}

fn union(a: R, b: R) -> R {
    match (a, b) {
        (None, x) | (x, None) => x,
        (Some((a0, a1)), Some((b0, b1))) => Some((a0.min(b0), a1.max(b1))),
    }
}

fn meet(a: R, b: (i128, i128)) -> R {
    let (a0, a1) = a?;
    let (lo, hi) = (a0.max(b.0), a1.min(b.1));
    (lo <= hi).then_some((lo, hi))
}

/// `r` if it fits `ty`, else the whole type (the exact result may have wrapped).
fn fit(ty: Type, lo: i128, hi: i128) -> R {
    let (min, max) = full(ty);
    Some(if lo >= min && hi <= max {
        (lo, hi)
    } else {
        (min, max)
    })
}

/// The negation of a condition (`!(x < y)` is `x >= y`).
fn negate(cc: IntCC) -> IntCC {
    match cc {
        IntCC::Eq => IntCC::Ne,
        IntCC::Ne => IntCC::Eq,
        IntCC::Slt => IntCC::Sge,
        IntCC::Sle => IntCC::Sgt,
        IntCC::Sgt => IntCC::Sle,
        IntCC::Sge => IntCC::Slt,
        IntCC::Ult => IntCC::Uge,
        IntCC::Ule => IntCC::Ugt,
        IntCC::Ugt => IntCC::Ule,
        IntCC::Uge => IntCC::Ult,
    }
}

/// The condition with its operands swapped (`x < y` is `y > x`).
fn swap(cc: IntCC) -> IntCC {
    match cc {
        IntCC::Eq | IntCC::Ne => cc,
        IntCC::Slt => IntCC::Sgt,
        IntCC::Sle => IntCC::Sge,
        IntCC::Sgt => IntCC::Slt,
        IntCC::Sge => IntCC::Sle,
        IntCC::Ult => IntCC::Ugt,
        IntCC::Ule => IntCC::Uge,
        IntCC::Ugt => IntCC::Ult,
        IntCC::Uge => IntCC::Ule,
    }
}

/// What `x cc y` being true says of `x`, given `y`'s range, in `x`'s type.
fn bound(cc: IntCC, ty: Type, (y0, y1): (i128, i128)) -> Option<(i128, i128)> {
    let (min, max) = full(ty);
    let r = match cc {
        IntCC::Eq => (y0, y1),
        IntCC::Slt => (min, y1 - 1),
        IntCC::Sle => (min, y1),
        IntCC::Sgt => (y0 + 1, max),
        IntCC::Sge => (y0, max),
        // Unsigned: only where y is not negative, so its unsigned value is y1 at most.
        IntCC::Ult if y0 >= 0 => (0, y1 - 1),
        IntCC::Ule if y0 >= 0 => (0, y1),
        _ => return None,
    };
    Some(r)
}

/// The unsigned interval of a signed one that does not cross zero.
fn unsigned(ty: Type, (lo, hi): (i128, i128)) -> Option<(i128, i128)> {
    let m = 1i128 << ty.bits();
    if lo >= 0 {
        Some((lo, hi))
    } else if hi < 0 {
        Some((lo + m, hi + m))
    } else {
        None
    }
}

/// The value of `a cc b` when the ranges decide it.
fn decide_cc(cc: IntCC, ty: Type, a: (i128, i128), b: (i128, i128)) -> Option<bool> {
    let (a, b) = match cc {
        IntCC::Ult | IntCC::Ule | IntCC::Ugt | IntCC::Uge => (unsigned(ty, a)?, unsigned(ty, b)?),
        _ => (a, b),
    };
    let lt = a.1 < b.0; // every a < every b
    let ge = a.0 >= b.1;
    let le = a.1 <= b.0;
    let gt = a.0 > b.1;
    match cc {
        IntCC::Slt | IntCC::Ult => decided(lt, ge),
        IntCC::Sle | IntCC::Ule => decided(le, gt),
        IntCC::Sgt | IntCC::Ugt => decided(gt, le),
        IntCC::Sge | IntCC::Uge => decided(ge, lt),
        IntCC::Eq => decided(a.0 == a.1 && a == b, lt || gt),
        IntCC::Ne => decided(lt || gt, a.0 == a.1 && a == b),
    }
}

fn decided(yes: bool, no: bool) -> Option<bool> {
    if yes {
        Some(true)
    } else if no {
        Some(false)
    } else {
        None
    }
}

/// The ranges this pass works out, for other passes (the watchdog's bounded loops).
pub struct ValueRanges<'a>(Ranges<'a>);

impl<'a> ValueRanges<'a> {
    /// Works out the ranges of `f`'s integer values.
    pub fn new(f: &'a Function) -> ValueRanges<'a> {
        ValueRanges(Ranges::new(f))
    }

    /// The signed range (in its width) of integer value `v` where block `at` runs;
    /// `None` if no value reaches there.
    pub fn at(&self, v: Value, at: Block) -> Option<(i128, i128)> {
        self.0.at(v, at, DEPTH)
    }
}

struct Ranges<'a> {
    f: &'a Function,
    dom: DomTree,
    /// Per value: the blocks where a branch condition bounds it, and the bound.
    facts: Vec<Vec<(Block, (i128, i128))>>,
    /// Per value: the range of a block parameter (the fixed point so far).
    params: Vec<R>,
}

impl<'a> Ranges<'a> {
    fn new(f: &'a Function) -> Ranges<'a> {
        let dom = DomTree::compute(f);
        let mut r = Ranges {
            f,
            dom,
            facts: vec![Vec::new(); f.values.len()],
            params: vec![None; f.values.len()],
        };
        r.solve();
        r
    }

    fn int(&self, v: Value) -> Option<Type> {
        let ty = self.f.value_type(v);
        (ty.is_int() && ty != Type::I1).then_some(ty)
    }

    /// The range of `v` where `at` runs.
    fn at(&self, v: Value, at: Block, depth: u32) -> R {
        let ty = self.f.value_type(v);
        if !ty.is_int() {
            return Some((0, 0));
        }
        let mut r = match self.f.value_def(v) {
            ValueDef::Param(b, _) if Some(b) == self.f.entry() => Some(full(ty)),
            ValueDef::Param(..) => self.params[v.index()],
            ValueDef::Result(i) if depth == 0 => match *self.f.inst(i) {
                InstData::Iconst { imm, .. } => Some((imm as i128, imm as i128)),
                _ => Some(full(ty)),
            },
            ValueDef::Result(i) => self.compute(i, ty, at, depth - 1),
        };
        if ty == Type::I1 {
            return r.map(|_| (0, 1));
        }
        for &(b, bound) in &self.facts[v.index()] {
            if self.dom.dominates(b, at) {
                r = meet(r, bound);
            }
        }
        r
    }

    fn compute(&self, i: Inst, ty: Type, at: Block, depth: u32) -> R {
        let whole = Some(full(ty));
        let get = |v: Value| self.at(v, at, depth);
        match *self.f.inst(i) {
            InstData::Iconst { imm, .. } => Some((imm as i128, imm as i128)),
            InstData::Binary { op, args: [x, y] } => {
                let (a, b) = (get(x)?, get(y)?);
                match op {
                    BinaryOp::Iadd => fit(ty, a.0 + b.0, a.1 + b.1),
                    BinaryOp::Isub => fit(ty, a.0 - b.1, a.1 - b.0),
                    BinaryOp::Imul => {
                        let c = [a.0 * b.0, a.0 * b.1, a.1 * b.0, a.1 * b.1];
                        let lo = c.iter().copied().min().unwrap_or(0);
                        let hi = c.iter().copied().max().unwrap_or(0);
                        fit(ty, lo, hi)
                    }
                    BinaryOp::Band if a.0 >= 0 || b.0 >= 0 => {
                        let hi = match (a.0 >= 0, b.0 >= 0) {
                            (true, true) => a.1.min(b.1),
                            (true, false) => a.1,
                            _ => b.1,
                        };
                        Some((0, hi))
                    }
                    // A remainder is smaller than the divisor (0 when it is 0).
                    BinaryOp::Urem if b.0 >= 0 => Some((0, (b.1 - 1).max(0))),
                    BinaryOp::Srem => {
                        let m = b.0.abs().max(b.1.abs());
                        let m = (m - 1).max(0);
                        Some((if a.0 >= 0 { 0 } else { -m }, if a.1 <= 0 { 0 } else { m }))
                    }
                    // Division by a positive divisor is monotonic (toward zero; by
                    // zero gives 0, which the range holds).
                    BinaryOp::Sdiv if b.0 > 0 => {
                        let c = [a.0 / b.0, a.0 / b.1, a.1 / b.0, a.1 / b.1, 0];
                        let lo = c.iter().copied().min().unwrap_or(0);
                        let hi = c.iter().copied().max().unwrap_or(0);
                        fit(ty, lo, hi)
                    }
                    BinaryOp::Ushr | BinaryOp::Sshr if b.0 == b.1 && b.0 >= 0 => {
                        let k = b.0 as u32;
                        if k >= ty.bits() {
                            whole
                        } else if a.0 >= 0 || op == BinaryOp::Sshr {
                            Some((a.0 >> k, a.1 >> k))
                        } else if k > 0 {
                            let m = (1i128 << ty.bits()) - 1;
                            Some((0, m >> k))
                        } else {
                            Some(a)
                        }
                    }
                    _ => whole,
                }
            }
            InstData::Unary { op, arg } => {
                let a = get(arg)?;
                let (min, _) = full(ty);
                match op {
                    UnaryOp::Ineg if a.0 > min => Some((-a.1, -a.0)),
                    UnaryOp::Iabs if a.0 > min => {
                        if a.0 >= 0 {
                            Some(a)
                        } else {
                            Some((0.max(a.0.max(-a.1)), a.1.max(-a.0)))
                        }
                    }
                    _ => whole,
                }
            }
            InstData::Select {
                if_true, if_false, ..
            } => union(get(if_true), get(if_false)),
            InstData::Convert { op, arg, .. } => {
                let from = self.f.value_type(arg);
                if !from.is_int() {
                    return whole;
                }
                let a = get(arg)?;
                match op {
                    ConvOp::Sext if from != Type::I1 => Some(a),
                    ConvOp::Uext if a.0 >= 0 => Some(a),
                    ConvOp::Uext => Some((0, (1i128 << from.bits()) - 1)),
                    ConvOp::Itrunc if ty != Type::I1 => fit(ty, a.0, a.1),
                    _ => whole,
                }
            }
            _ => whole,
        }
    }

    /// The facts of the branches, then the block parameters' fixed point.
    fn solve(&mut self) {
        let f = self.f;
        // Facts: on the edge into a block with no other predecessor.
        for &b in self.dom.rpo() {
            let [p] = self.dom.preds(b) else {
                continue;
            };
            let Some(&term) = f.block(*p).insts.last() else {
                continue;
            };
            let InstData::Brif {
                cond,
                then_dest,
                else_dest,
            } = f.inst(term)
            else {
                continue;
            };
            if then_dest.block == else_dest.block {
                continue;
            }
            let ValueDef::Result(c) = f.value_def(*cond) else {
                continue;
            };
            let InstData::Icmp { cond: cc, args } = *f.inst(c) else {
                continue;
            };
            let cc = if then_dest.block == b { cc } else { negate(cc) };
            let [x, y] = args;
            let Some(ty) = self.int(x) else {
                continue;
            };
            for (v, w, cc) in [(x, y, cc), (y, x, swap(cc))] {
                if let Some(rw) = self.at(w, *p, DEPTH) {
                    if let Some(r) = bound(cc, ty, rw) {
                        self.facts[v.index()].push((b, r));
                    }
                }
            }
        }
        // Incoming edges of every block with parameters: (from, to, args).
        let mut edges: Vec<(Block, Block, Vec<Value>)> = Vec::new();
        for &b in self.dom.rpo() {
            let Some(&term) = f.block(b).insts.last() else {
                continue;
            };
            for d in f.inst(term).dests() {
                if !d.args.is_empty() {
                    edges.push((b, d.block, d.args.clone()));
                }
            }
        }
        // How often each parameter's lower and upper bound moved.
        let mut moved = vec![(0u32, 0u32); f.values.len()];
        for _ in 0..MAX_ROUNDS {
            let mut next: Vec<R> = vec![None; f.values.len()];
            for (from, to, args) in &edges {
                // Facts of the destination hold on the edge when it is the only one.
                let at = if self.dom.preds(*to).len() == 1 {
                    *to
                } else {
                    *from
                };
                for (p, a) in f.block(*to).params.iter().zip(args) {
                    next[p.index()] = union(next[p.index()], self.at(*a, at, DEPTH));
                }
            }
            let mut changed = false;
            for (v, r) in next.into_iter().enumerate() {
                let Some(r) = r else { continue };
                let old = self.params[v];
                let Some((mut lo, mut hi)) = union(old, Some(r)) else {
                    continue;
                };
                if Some((lo, hi)) == old {
                    continue;
                }
                // A bound that keeps moving goes to its end of the type (the other
                // one may still settle: a loop counting up keeps its start).
                let (min, max) = full(f.values[v].ty);
                if let Some((l0, h0)) = old {
                    if lo < l0 {
                        moved[v].0 += 1;
                        if moved[v].0 > WIDEN_AFTER {
                            lo = min;
                        }
                    }
                    if hi > h0 {
                        moved[v].1 += 1;
                        if moved[v].1 > WIDEN_AFTER {
                            hi = max;
                        }
                    }
                }
                self.params[v] = Some((lo, hi));
                changed = true;
            }
            if !changed {
                return;
            }
        }
        // No fixed point within the bound: nothing is known of any parameter.
        for (v, r) in self.params.iter_mut().enumerate() {
            if r.is_some() && f.values[v].ty.is_int() {
                *r = Some(full(f.values[v].ty));
            }
        }
    }

    /// The compares whose operands' ranges decide them, with their values.
    fn decide(&self) -> Vec<(Inst, bool)> {
        let mut out = Vec::new();
        for &b in self.dom.rpo() {
            for &i in &self.f.block(b).insts {
                let InstData::Icmp { cond, args: [x, y] } = *self.f.inst(i) else {
                    continue;
                };
                let Some(ty) = self.int(x) else { continue };
                let (Some(a), Some(c)) = (self.at(x, b, DEPTH), self.at(y, b, DEPTH)) else {
                    continue;
                };
                if let Some(t) = decide_cc(cond, ty, a, c) {
                    out.push((i, t));
                }
            }
        }
        out
    }
}

#[cfg(test)]
mod tests;
