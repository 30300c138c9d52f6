//! Which values are live at the entry and the exit of each block of a function.
//!
//! The classic backward data flow over the blocks (`live_in(b) = uses(b) ∪
//! (live_out(b) − defs(b))`, `live_out(b)` the union of the successors' `live_in`),
//! iterated to its fixed point in reverse layout order, on bit sets of value
//! numbers. A block's parameters and its instructions' results are its definitions;
//! the arguments of its instructions (those passed to a successor's parameters
//! included) are its uses.
//!
//! What counts as a use is the caller's: a backend may say that a use of a value is
//! a use of another (a derived pointer keeps its base alive), leave out values that
//! have no storage of their own, or add uses the IR does not show (a value read
//! after its instruction). [`Liveness::compute`] takes that as a function; the
//! answers are exact for whatever it says.

use crate::entities::{Block, Inst, Value};
use crate::function::Function;

/// The values live into and out of each block of one function.
#[derive(Clone, Debug)]
pub struct Liveness {
    words: usize,
    live_in: Vec<Vec<u64>>,
    live_out: Vec<Vec<u64>>,
}

fn bit(set: &[u64], v: usize) -> bool {
    set[v / 64] >> (v % 64) & 1 != 0
}

fn set_bit(set: &mut [u64], v: usize) {
    set[v / 64] |= 1 << (v % 64);
}

impl Liveness {
    /// The liveness of `f`'s values when instruction `i` reads the values
    /// `uses(i, push)` pushes (for the IR's own meaning: its arguments,
    /// [`Liveness::of_args`]).
    pub fn compute(f: &Function, mut uses: impl FnMut(Inst, &mut dyn FnMut(Value))) -> Liveness {
        let nb = f.blocks.len();
        let words = f.values.len().div_ceil(64);
        let mut uses_b = vec![vec![0u64; words]; nb];
        let mut defs_b = vec![vec![0u64; words]; nb];
        for &b in &f.layout {
            let bi = b.index();
            for &p in &f.block(b).params {
                set_bit(&mut defs_b[bi], p.index());
            }
            for &i in &f.block(b).insts {
                let (u, d) = (&mut uses_b[bi], &defs_b[bi]);
                uses(i, &mut |v| {
                    if !bit(d, v.index()) {
                        set_bit(u, v.index());
                    }
                });
                if let Some(r) = f.result(i) {
                    set_bit(&mut defs_b[bi], r.index());
                }
            }
        }
        let succs: Vec<Vec<Block>> = (0..nb).map(|i| f.successors(Block::new(i))).collect();
        let mut live_in = vec![vec![0u64; words]; nb];
        let mut live_out = vec![vec![0u64; words]; nb];
        let mut changed = true;
        while changed {
            changed = false;
            for &b in f.layout.iter().rev() {
                let bi = b.index();
                let mut out = vec![0u64; words];
                for s in &succs[bi] {
                    for (o, x) in out.iter_mut().zip(&live_in[s.index()]) {
                        *o |= x;
                    }
                }
                let mut inn = uses_b[bi].clone();
                for w in 0..words {
                    inn[w] |= out[w] & !defs_b[bi][w];
                }
                if out != live_out[bi] || inn != live_in[bi] {
                    live_out[bi] = out;
                    live_in[bi] = inn;
                    changed = true;
                }
            }
        }
        Liveness {
            words,
            live_in,
            live_out,
        }
    }

    /// The liveness of `f`'s values as the IR has it: an instruction reads its
    /// arguments.
    pub fn of_args(f: &Function) -> Liveness {
        Liveness::compute(f, |i, push| f.inst(i).for_each_arg(&mut *push))
    }

    /// Whether `v` is live on entry to `b`.
    pub fn is_live_in(&self, b: Block, v: Value) -> bool {
        bit(&self.live_in[b.index()], v.index())
    }

    /// Whether `v` is live on exit from `b` (live on entry to a successor).
    pub fn is_live_out(&self, b: Block, v: Value) -> bool {
        bit(&self.live_out[b.index()], v.index())
    }

    /// The values live on entry to `b`, in increasing number.
    pub fn live_in(&self, b: Block) -> impl Iterator<Item = Value> + '_ {
        self.members(&self.live_in[b.index()])
    }

    /// The values live on exit from `b`, in increasing number.
    pub fn live_out(&self, b: Block) -> impl Iterator<Item = Value> + '_ {
        self.members(&self.live_out[b.index()])
    }

    fn members<'a>(&'a self, set: &'a [u64]) -> impl Iterator<Item = Value> + 'a {
        (0..self.words * 64)
            .filter(move |&v| bit(set, v))
            .map(Value::new)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::text::parse_module;

    /// A counting loop: `v1` (the bound) lives through the loop, the counter is a
    /// block parameter, `v5` dies in the block that makes it.
    #[test]
    fn a_loop_keeps_its_bound_alive() {
        let m = parse_module(
            "func @f(i32) -> i32 function {
block0(v0: i32):
    v1 = iconst.i32 10
    jump block1(v0)
block1(v2: i32):
    v3 = icmp slt v2, v1
    brif v3, block2, block3
block2:
    v4 = iconst.i32 1
    v5 = iadd v2, v4
    jump block1(v5)
block3:
    return v2
}
",
        )
        .expect("parses");
        let f = &m.funcs[0];
        let l = Liveness::of_args(f);
        let (b0, b1, b2, b3) = (Block::new(0), Block::new(1), Block::new(2), Block::new(3));
        let v = Value::new;
        assert_eq!(l.live_in(b0).collect::<Vec<_>>(), []);
        assert_eq!(l.live_out(b0).collect::<Vec<_>>(), [v(1)]);
        assert_eq!(l.live_in(b1).collect::<Vec<_>>(), [v(1)]);
        assert_eq!(l.live_out(b1).collect::<Vec<_>>(), [v(1), v(2)]);
        assert_eq!(l.live_in(b2).collect::<Vec<_>>(), [v(1), v(2)]);
        assert_eq!(l.live_out(b2).collect::<Vec<_>>(), [v(1)]);
        assert_eq!(l.live_in(b3).collect::<Vec<_>>(), [v(2)]);
        assert!(l.is_live_out(b1, v(2)) && !l.is_live_in(b1, v(2)) && !l.is_live_out(b3, v(2)));
        // A caller's uses: reading v2 counts as reading v1 too.
        let l = Liveness::compute(f, |i, push| {
            f.inst(i).for_each_arg(|a| {
                push(a);
                if a == v(2) {
                    push(v(0));
                }
            })
        });
        assert!(l.is_live_in(b1, v(0)) && l.is_live_out(b0, v(0)));
    }
}
