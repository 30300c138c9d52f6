//! The loop step superinstruction: `ADD`/`SUB` of a 16 or 32-bit integer, `JMP` to a
//! comparison of an integer of the same size and `JZ`/`JNZ` on its result. It is the
//! back edge of a counted loop and its test (`i := i + 1; JMP head; head: GT t, i, n;
//! JNZ t, exit`), four instructions that one entry runs when every operand is in data
//! memory (else the entry runs the `ADD` and `JMP` alone, and the comparison runs from
//! its own entry, where a fault names its PC).
//!
//! The same step may follow an array write (`AxWR var, base, idx`: the last statement
//! of a loop body that sets an element), five instructions in one entry: the write
//! first (a fault there names the write), then the step as above, or, when one of its
//! operands is outside data memory, nothing more: the step's own entry runs next. Or
//! it may follow an AORD and the `JZ`/`JNZ` on the element read that jumps to it (an
//! `IF arr[i] THEN … END_IF` ending the body), six instructions ([`ReadSkip`]).
//!
//! A step that leads back to its own entry (a loop whose body is the write, or the
//! read and its branch) goes round again inside the handler ([`spin`]) as long as the
//! fuel that [`exec`](super::exec) sets aside from the budget lasts, saving a call and
//! a dispatch a round: the sieve's marking loop on plcc's VM runs 1.4× faster so.

use super::ops::{self, Access, Op2, Rel, Val, Wr};
use super::{Core, Exit, Handler, Ins, EXIT};
use crate::isa::op::group as g;

/// The arithmetic of a loop step.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub(super) enum StepOp {
    Add,
    Sub,
}

/// What runs before the step in the same entry.
pub(super) trait Prefix {
    /// Instructions it counts.
    const COUNT: u64;
    /// Runs it (a fault here is the first instruction's): `Some(next)` when the step
    /// is not to run (the prefix counted its own instructions beyond the first).
    fn run(c: &mut Core, i: &Ins, k: usize) -> Result<Option<usize>, Exit>;
    /// The operation's dst, x and y.
    fn operation(c: &Core, i: &Ins) -> [u32; 3];
    /// The comparison's dst, x and y.
    #[inline(always)]
    fn compare(_: &Core, i: &Ins) -> [u32; 3] {
        [i.e, i.g, i.h]
    }
    /// The target of the branch after the comparison.
    #[inline(always)]
    fn branch_target(_: &Core, i: &Ins) -> usize {
        i.j as usize
    }
    /// The comparison's entry.
    fn compare_entry(c: &Core, i: &Ins) -> usize;
    /// Where to go on when the step's operands are not all in data memory.
    fn fallback<TB: Val, O: Op2<TB>>(c: &mut Core, i: &Ins, k: usize) -> usize;
}

/// The step alone: `d` is the comparison's entry.
pub(super) struct Alone;
impl Prefix for Alone {
    const COUNT: u64 = 0;
    #[inline(always)]
    fn run(_: &mut Core, _: &Ins, _: usize) -> Result<Option<usize>, Exit> {
        Ok(None)
    }
    #[inline(always)]
    fn operation(_: &Core, i: &Ins) -> [u32; 3] {
        [i.a, i.b, i.c]
    }
    #[inline(always)]
    fn compare_entry(_: &Core, i: &Ins) -> usize {
        i.d as usize
    }
    #[inline(always)]
    fn fallback<TB: Val, O: Op2<TB>>(c: &mut Core, i: &Ins, k: usize) -> usize {
        ops::bin_jmp::<TB, O>(c, i, k)
    }
}

/// An array write of `T`s first: `a`, `b`, `c` are the write's var, base and idx (as
/// the entry's own handler reads them), and `d` indexes the operand pool, which holds
/// the operation's dst, x and y and the comparison's entry.
pub(super) struct Write<T>(std::marker::PhantomData<T>);
impl<T: Val> Prefix for Write<T> {
    const COUNT: u64 = 1;
    #[inline(always)]
    fn run(c: &mut Core, i: &Ins, _: usize) -> Result<Option<usize>, Exit> {
        let n: i16 = c.ld(i.c)?;
        Wr::f::<T>(c, i.a, ops::elem_addr::<T>(i.b, n))?;
        Ok(None)
    }
    #[inline(always)]
    fn operation(c: &Core, i: &Ins) -> [u32; 3] {
        let x = i.d as usize;
        [c.pool[x], c.pool[x + 1], c.pool[x + 2]]
    }
    #[inline(always)]
    fn compare_entry(c: &Core, i: &Ins) -> usize {
        c.pool[i.d as usize + 3] as usize
    }
    #[inline(always)]
    fn fallback<TB: Val, O: Op2<TB>>(_: &mut Core, _: &Ins, k: usize) -> usize {
        // The write ran (the loop counts this call as one instruction); the ADD's
        // entry runs next.
        k + 1
    }
}

/// A read of a BOOL or BYTE element and the branch on it (`AORD var, base, idx`,
/// `JZ var, L` when `ZJ`, else `JNZ`) first, where `L` is a loop step (an `IF arr[i]
/// THEN … END_IF` ending a loop body): `a`, `b`, `c` the read's (as the entry's own
/// handler reads them), `d` the branch's target `L`, `e` an index into the operand
/// pool, which holds the operation's dst, x and y, the comparison's entry and its dst,
/// x and y, and `g` the target of the branch after the comparison. When the branch
/// does not jump, the entry ends after it.
pub(super) struct ReadSkip<const ZJ: bool>;
impl<const ZJ: bool> Prefix for ReadSkip<ZJ> {
    const COUNT: u64 = 2;
    #[inline(always)]
    fn run(c: &mut Core, i: &Ins, k: usize) -> Result<Option<usize>, Exit> {
        let n: i16 = c.ld(i.c)?;
        let v: u8 = c.ld(ops::elem_addr::<u8>(i.b, n))?;
        c.st(i.a, v)?;
        if (v == 0) == ZJ {
            Ok(None)
        } else {
            c.extra += 1;
            Ok(Some(k + 2))
        }
    }
    #[inline(always)]
    fn operation(c: &Core, i: &Ins) -> [u32; 3] {
        let x = i.e as usize;
        [c.pool[x], c.pool[x + 1], c.pool[x + 2]]
    }
    #[inline(always)]
    fn compare(c: &Core, i: &Ins) -> [u32; 3] {
        let x = i.e as usize + 4;
        [c.pool[x], c.pool[x + 1], c.pool[x + 2]]
    }
    #[inline(always)]
    fn branch_target(_: &Core, i: &Ins) -> usize {
        i.g as usize
    }
    #[inline(always)]
    fn compare_entry(c: &Core, i: &Ins) -> usize {
        c.pool[i.e as usize + 3] as usize
    }
    #[inline(always)]
    fn fallback<TB: Val, O: Op2<TB>>(c: &mut Core, i: &Ins, _: usize) -> usize {
        // The read and the branch ran; the step's own entry runs next.
        c.extra += 1;
        i.d as usize
    }
}

/// `a`, `b`, `c` the operation; `e`, `g`, `h` the comparison's dst, x and y; `j` the
/// branch's target; `d` as the prefix says (or all as [`ReadSkip`] says).
///
/// When the step leads back to this entry (the loop's body is the prefix alone), the
/// entry goes round again ([`spin`]) instead of returning, while the fuel
/// [`exec`](super::exec) set aside lasts.
fn step_rel_j<P: Prefix, TB: Val, O: Op2<TB>, TR: Val + PartialOrd, R: Rel, const Z: bool>(
    c: &mut Core,
    i: &Ins,
    k: usize,
) -> usize {
    let next = once::<P, TB, O, TR, R, Z>(c, i, k, |c| Parts::of::<P>(c, i));
    if next == k && c.fuel >= 4 + P::COUNT {
        spin::<P, TB, O, TR, R, Z>(c, i, k)
    } else {
        next
    }
}

/// Runs the entry again and again while it leads back to itself and the fuel lasts.
/// Each round is what the caller's next call of the entry would be: the one
/// instruction the caller counts for a call goes into `extra` as the round starts,
/// so a fault in a round counts every instruction before it.
#[inline(never)]
fn spin<P: Prefix, TB: Val, O: Op2<TB>, TR: Val + PartialOrd, R: Rel, const Z: bool>(
    c: &mut Core,
    i: &Ins,
    k: usize,
) -> usize {
    let parts = Parts::of::<P>(c, i);
    loop {
        c.fuel -= 4 + P::COUNT;
        c.extra += 1;
        let next = once::<P, TB, O, TR, R, Z>(c, i, k, |_| parts);
        if next != k || c.fuel < 4 + P::COUNT {
            return next;
        }
    }
}

/// The operands and targets of the step after the prefix.
#[derive(Copy, Clone)]
struct Parts {
    op: [u32; 3],
    rel: [u32; 3],
    taken: usize,
    fallen: usize,
}

impl Parts {
    #[inline(always)]
    fn of<P: Prefix>(c: &Core, i: &Ins) -> Parts {
        Parts {
            op: P::operation(c, i),
            rel: P::compare(c, i),
            taken: P::branch_target(c, i),
            fallen: P::compare_entry(c, i) + 2,
        }
    }
}

/// One run of the entry, with the step's `parts` (read only when the prefix lets the
/// step run).
#[inline(always)]
fn once<P: Prefix, TB: Val, O: Op2<TB>, TR: Val + PartialOrd, R: Rel, const Z: bool>(
    c: &mut Core,
    i: &Ins,
    k: usize,
    parts: impl FnOnce(&Core) -> Parts,
) -> usize {
    match P::run(c, i, k) {
        Err(e) => {
            c.exit = e;
            return EXIT;
        }
        Ok(Some(next)) => return next,
        Ok(None) => {}
    }
    let p = parts(c);
    match run::<TB, O, TR, R>(c, p.op, p.rel) {
        Some(r) => {
            c.extra += 3 + P::COUNT;
            if r != Z {
                p.taken
            } else {
                p.fallen
            }
        }
        None => P::fallback::<TB, O>(c, i, k),
    }
}

/// The operation (`dst := x op y`, `op` = `[dst, x, y]`) and the comparison (`rel`,
/// the same), or `None` (and nothing done) when an operand is outside data memory.
#[inline(always)]
fn run<TB: Val, O: Op2<TB>, TR: Val + PartialOrd, R: Rel>(
    c: &mut Core,
    op: [u32; 3],
    rel: [u32; 3],
) -> Option<bool> {
    let (a, b, y) = (c.at(op[0]), c.at(op[1]), c.at(op[2]));
    let (e, p, q) = (c.at(rel[0]), c.at(rel[1]), c.at(rel[2]));
    let d = &mut c.data[..];
    let fits = |x: usize, n: usize| x + n <= d.len();
    let (sb, sr) = (std::mem::size_of::<TB>(), std::mem::size_of::<TR>());
    if !(fits(a, sb) && fits(e, 1) && fits(p, sr) && fits(q, sr)) {
        return None;
    }
    let v = O::f(TB::load(d, b)?, TB::load(d, y)?);
    v.store(d, a);
    let r = R::t(TR::load(d, p)?, TR::load(d, q)?);
    d[e] = r as u8;
    Some(r)
}

/// The step handler for `op` on the type code `bt` followed by the comparison `grp`
/// on the type code `rt` and JZ (`z`) or JNZ, or `None` when there is none (other
/// types, or sizes that differ).
pub(super) fn handler<P: Prefix>(op: StepOp, bt: u8, grp: u8, rt: u8, z: bool) -> Option<Handler> {
    macro_rules! rels {
        ($tb:ty, $o:ty, $tr:ty) => {
            match (grp, z) {
                (g::GT, true) => Some(step_rel_j::<P, $tb, $o, $tr, ops::Gt, true> as Handler),
                (g::GT, false) => Some(step_rel_j::<P, $tb, $o, $tr, ops::Gt, false>),
                (g::GE, true) => Some(step_rel_j::<P, $tb, $o, $tr, ops::Ge, true>),
                (g::GE, false) => Some(step_rel_j::<P, $tb, $o, $tr, ops::Ge, false>),
                (g::EQ, true) => Some(step_rel_j::<P, $tb, $o, $tr, ops::Eq, true>),
                (g::EQ, false) => Some(step_rel_j::<P, $tb, $o, $tr, ops::Eq, false>),
                (g::LE, true) => Some(step_rel_j::<P, $tb, $o, $tr, ops::Le, true>),
                (g::LE, false) => Some(step_rel_j::<P, $tb, $o, $tr, ops::Le, false>),
                (g::LT, true) => Some(step_rel_j::<P, $tb, $o, $tr, ops::Lt, true>),
                (g::LT, false) => Some(step_rel_j::<P, $tb, $o, $tr, ops::Lt, false>),
                (g::NE, true) => Some(step_rel_j::<P, $tb, $o, $tr, ops::Ne, true>),
                (g::NE, false) => Some(step_rel_j::<P, $tb, $o, $tr, ops::Ne, false>),
                _ => None,
            }
        };
    }
    macro_rules! ops {
        ($tb:ty, $tr:ty) => {
            match op {
                StepOp::Add => rels!($tb, ops::Add, $tr),
                StepOp::Sub => rels!($tb, ops::Sub, $tr),
            }
        };
    }
    // Wrapping addition and subtraction are the same on signed and unsigned types
    // (INT 2, DINT 3, WORD 6, DWORD 7); the comparison's type decides its sign.
    match (bt, rt) {
        (2 | 6, 2) => ops!(u16, i16),
        (2 | 6, 6) => ops!(u16, u16),
        (3 | 7, 3) => ops!(u32, i32),
        (3 | 7, 7) => ops!(u32, u32),
        _ => None,
    }
}

/// The step after an array write of `size`-byte elements (see [`handler`]).
pub(super) fn after_write(
    size: usize,
    op: StepOp,
    bt: u8,
    grp: u8,
    rt: u8,
    z: bool,
) -> Option<Handler> {
    match size {
        1 => handler::<Write<u8>>(op, bt, grp, rt, z),
        2 => handler::<Write<u16>>(op, bt, grp, rt, z),
        4 => handler::<Write<u32>>(op, bt, grp, rt, z),
        8 => handler::<Write<u64>>(op, bt, grp, rt, z),
        _ => None,
    }
}

/// The step after an AORD and the JZ (`jz`) or JNZ on it (see [`ReadSkip`]).
pub(super) fn after_read(
    jz: bool,
    op: StepOp,
    bt: u8,
    grp: u8,
    rt: u8,
    z: bool,
) -> Option<Handler> {
    if jz {
        handler::<ReadSkip<true>>(op, bt, grp, rt, z)
    } else {
        handler::<ReadSkip<false>>(op, bt, grp, rt, z)
    }
}
