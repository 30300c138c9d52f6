//! The loop step superinstruction: `ADD`/`SUB` of a 16 or 32-bit integer, `JMP` to a
//! comparison of an integer of the same size and `JZ`/`JNZ` on its result. It is the
//! back edge of a counted loop and its test (`i := i + 1; JMP head; head: GT t, i, n;
//! JNZ t, exit`), four instructions that one entry runs when every operand is in data
//! memory (else the entry runs the `ADD` and `JMP` alone, and the comparison runs from
//! its own entry, where a fault names its PC).

use super::ops::{self, Op2, Rel, Val};
use super::{Core, Handler, Ins};
use crate::isa::op::group as g;

/// The arithmetic of a loop step.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub(super) enum StepOp {
    Add,
    Sub,
}

/// `a`, `b`, `c` the operation; `d` the comparison's entry; `e`, `g`, `h` the
/// comparison's dst, x and y; `j` the branch's target.
fn step_rel_j<TB: Val, O: Op2<TB>, TR: Val + PartialOrd, R: Rel, const Z: bool>(
    c: &mut Core,
    i: &Ins,
    k: usize,
) -> usize {
    match run::<TB, O, TR, R>(c, i) {
        Some(r) => {
            c.extra += 3;
            if r != Z {
                i.j as usize
            } else {
                i.d as usize + 2
            }
        }
        None => ops::bin_jmp::<TB, O>(c, i, k),
    }
}

/// The operation and the comparison, or `None` (and nothing done) when an operand is
/// outside data memory.
#[inline(always)]
fn run<TB: Val, O: Op2<TB>, TR: Val + PartialOrd, R: Rel>(c: &mut Core, i: &Ins) -> Option<bool> {
    let (a, b, y, e, p, q) = (
        c.at(i.a),
        c.at(i.b),
        c.at(i.c),
        c.at(i.e),
        c.at(i.g),
        c.at(i.h),
    );
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
pub(super) fn handler(op: StepOp, bt: u8, grp: u8, rt: u8, z: bool) -> Option<Handler> {
    macro_rules! rels {
        ($tb:ty, $o:ty, $tr:ty) => {
            match (grp, z) {
                (g::GT, true) => Some(step_rel_j::<$tb, $o, $tr, ops::Gt, true> as Handler),
                (g::GT, false) => Some(step_rel_j::<$tb, $o, $tr, ops::Gt, false>),
                (g::GE, true) => Some(step_rel_j::<$tb, $o, $tr, ops::Ge, true>),
                (g::GE, false) => Some(step_rel_j::<$tb, $o, $tr, ops::Ge, false>),
                (g::EQ, true) => Some(step_rel_j::<$tb, $o, $tr, ops::Eq, true>),
                (g::EQ, false) => Some(step_rel_j::<$tb, $o, $tr, ops::Eq, false>),
                (g::LE, true) => Some(step_rel_j::<$tb, $o, $tr, ops::Le, true>),
                (g::LE, false) => Some(step_rel_j::<$tb, $o, $tr, ops::Le, false>),
                (g::LT, true) => Some(step_rel_j::<$tb, $o, $tr, ops::Lt, true>),
                (g::LT, false) => Some(step_rel_j::<$tb, $o, $tr, ops::Lt, false>),
                (g::NE, true) => Some(step_rel_j::<$tb, $o, $tr, ops::Ne, true>),
                (g::NE, false) => Some(step_rel_j::<$tb, $o, $tr, ops::Ne, false>),
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
