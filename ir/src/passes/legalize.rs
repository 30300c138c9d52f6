//! Legalization: guards around the operations whose IR meaning a target's own
//! arithmetic does not give.
//!
//! The IR defines every operation for every operand (`docs/ir.md`): division by zero
//! gives 0 and raises the fault flag, `MIN / -1` wraps, shifts by the width or more give
//! 0 (or the sign fill), float-to-integer conversions saturate and take NaN to 0. A
//! target whose instructions (or whose language, for C) leave some of these undefined
//! says so in a [`Defines`], and this pass rewrites the module so that each such
//! operation only ever sees operands the target defines, with compares and selects
//! (and, for the fault flag, a branch) that produce exactly the IR's result around it.
//!
//! After the pass, in a function it has run on:
//! - every `sdiv`/`srem`/`udiv`/`urem` has a divisor that is not zero (if
//!   `div_by_zero` is not defined) and no `sdiv`/`srem` sees `MIN, -1` (at the widths
//!   `min_div_neg1` does not hold);
//! - every `ishl`/`ushr`/`sshr` has a count below the width (if `shift_ge_width` is
//!   not defined);
//! - every `ftosi`/`ftoui` has an operand whose truncation fits the result type (if
//!   `float_to_int_saturates` is not defined).
//!
//! The operations stay the same instructions, so a backend emits them plainly. What
//! the rewrites leave unused (the operands of a division by a constant zero, a
//! guarded division whose value nobody reads) is removed ([`dce`](super::dce)). The
//! pass is not idempotent (a second run guards the guarded operations again); run it
//! once, last, on the module a backend translates.

use crate::entities::{Block, Inst, Value};
use crate::function::{Function, ValueDef};
use crate::inst::{BinaryOp, BlockCall, ConvOp, FloatCC, InstData, IntCC, Intrinsic, UnaryOp};
use crate::module::Module;
use crate::types::Type;

/// A set of integer widths: 8, 16, 32 and 64 bits.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct Widths(u8);

impl Widths {
    /// No width.
    pub const NONE: Widths = Widths(0);
    /// Every width.
    pub const ALL: Widths = Widths(0b1111);

    /// The widths listed (each 8, 16, 32 or 64).
    pub const fn of(bits: &[u32]) -> Widths {
        let mut set = 0;
        let mut k = 0;
        while k < bits.len() {
            set |= Widths::bit(bits[k]);
            k += 1;
        }
        Widths(set)
    }

    const fn bit(bits: u32) -> u8 {
        match bits {
            8 => 1,
            16 => 2,
            32 => 4,
            64 => 8,
            _ => 0,
        }
    }

    /// True if `bits` is in the set.
    pub const fn contains(self, bits: u32) -> bool {
        self.0 & Widths::bit(bits) != 0
    }
}

/// What a target's own arithmetic defines as the IR does. `true` means the target's
/// operation already gives the IR's result (no guard); `false` asks for a guard.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct Defines {
    /// Division and remainder by zero give 0 and raise the fault flag.
    pub div_by_zero: bool,
    /// The widths at which signed `MIN / -1` gives `MIN` and `MIN % -1` gives 0 (a
    /// C-like target defines it where the type is promoted to a wider `int`).
    pub min_div_neg1: Widths,
    /// Shifts by a count of at least the width give 0 (`sshr`: the sign fill).
    pub shift_ge_width: bool,
    /// Float-to-integer conversions saturate at the result type's range and give 0
    /// for NaN.
    pub float_to_int_saturates: bool,
}

impl Defines {
    /// A target that defines everything as the IR does: the pass changes nothing.
    pub const ALL: Defines = Defines {
        div_by_zero: true,
        min_div_neg1: Widths::ALL,
        shift_ge_width: true,
        float_to_int_saturates: true,
    };

    /// A target that defines none of it (C: each is undefined behaviour there).
    pub const NONE: Defines = Defines {
        div_by_zero: false,
        min_div_neg1: Widths::NONE,
        shift_ge_width: false,
        float_to_int_saturates: false,
    };
}

/// Legalizes every function of the module; true if anything changed.
pub fn run(module: &mut Module, defines: &Defines) -> bool {
    let mut changed = false;
    for f in &mut module.funcs {
        changed |= run_function(f, defines);
    }
    changed
}

/// Legalizes one function; true if anything changed.
pub fn run_function(f: &mut Function, defines: &Defines) -> bool {
    if *defines == Defines::ALL {
        return false;
    }
    let mut changed = false;
    // Blocks split off while working are pushed and visited too.
    let mut work: Vec<Block> = f.layout.clone();
    work.reverse();
    while let Some(b) = work.pop() {
        let mut k = 0;
        while k < f.blocks[b.index()].insts.len() {
            let inst = f.blocks[b.index()].insts[k];
            match *f.inst(inst) {
                InstData::Binary { op, args } if op.can_fault() => {
                    match guard_division(f, b, k, op, args, defines) {
                        Guarded::Split(join) => {
                            changed = true;
                            work.push(join);
                            break;
                        }
                        Guarded::InPlace => changed = true,
                        Guarded::Unchanged => {}
                    }
                }
                InstData::Binary {
                    op: op @ (BinaryOp::Ishl | BinaryOp::Ushr | BinaryOp::Sshr),
                    args,
                } if !defines.shift_ge_width => {
                    changed |= guard_shift(f, b, k, op, args);
                }
                InstData::Convert {
                    op: op @ (ConvOp::FToSi | ConvOp::FToUi),
                    ty,
                    arg,
                } if !defines.float_to_int_saturates => {
                    guard_float_to_int(f, b, k, op, ty, arg);
                    changed = true;
                }
                _ => {}
            }
            // Guards go in before the instruction: find it again.
            k = f.blocks[b.index()]
                .insts
                .iter()
                .position(|&i| i == inst)
                .map_or(usize::MAX - 1, |p| p)
                + 1;
        }
    }
    if changed {
        super::dce::run(f);
    }
    changed
}

/// Inserts instructions before position `at` of block `b`.
struct Cursor<'a> {
    f: &'a mut Function,
    b: Block,
    at: usize,
    span: Option<crate::diag::Span>,
}

impl Cursor<'_> {
    fn ins(&mut self, data: InstData, ty: Option<Type>) -> Option<Value> {
        let i = self.f.create_inst(data, ty, self.span);
        self.f.blocks[self.b.index()].insts.insert(self.at, i);
        self.at += 1;
        self.f.result(i)
    }

    fn val(&mut self, data: InstData, ty: Type) -> Value {
        self.ins(data, Some(ty)).expect("a result")
    }

    fn iconst(&mut self, ty: Type, imm: i64) -> Value {
        let imm = ty.canon_int(imm);
        self.val(InstData::Iconst { ty, imm }, ty)
    }

    fn fconst(&mut self, ty: Type, x: f64) -> Value {
        let bits = if ty == Type::F32 {
            (x as f32).to_bits() as u64
        } else {
            x.to_bits()
        };
        self.val(InstData::Fconst { ty, bits }, ty)
    }

    fn icmp(&mut self, cond: IntCC, a: Value, b: Value) -> Value {
        self.val(InstData::Icmp { cond, args: [a, b] }, Type::I1)
    }

    fn fcmp(&mut self, cond: FloatCC, a: Value, b: Value) -> Value {
        self.val(InstData::Fcmp { cond, args: [a, b] }, Type::I1)
    }

    fn select(&mut self, cond: Value, if_true: Value, if_false: Value) -> Value {
        let ty = self.f.value_type(if_true);
        self.val(
            InstData::Select {
                cond,
                if_true,
                if_false,
            },
            ty,
        )
    }
}

/// The constant an integer value is, if it is one.
fn const_of(f: &Function, v: Value) -> Option<i64> {
    match f.value_def(v) {
        ValueDef::Result(i) => match *f.inst(i) {
            InstData::Iconst { imm, .. } => Some(imm),
            _ => None,
        },
        ValueDef::Param(..) => None,
    }
}

/// What [`guard_division`] did.
enum Guarded {
    /// Nothing: the target defines the division for every operand it can see.
    Unchanged,
    /// Rewrote it within its block.
    InPlace,
    /// Split the block: the rest of it went to this block (the caller goes on there).
    Split(Block),
}

/// Guards the division at position `k` of block `b`.
fn guard_division(
    f: &mut Function,
    b: Block,
    k: usize,
    op: BinaryOp,
    [x, d]: [Value; 2],
    defines: &Defines,
) -> Guarded {
    let inst = f.blocks[b.index()].insts[k];
    let ty = f.value_type(x);
    let signed = matches!(op, BinaryOp::Sdiv | BinaryOp::Srem);
    // Signed `MIN / -1` needs a guard at this width.
    let min_guard = signed && !defines.min_div_neg1.contains(ty.bits());
    let span = f.spans[inst.index()];
    let divisor = const_of(f, d);
    let mut cur = Cursor { f, b, at: k, span };
    match divisor {
        Some(0) if !defines.div_by_zero => {
            // Always a fault: raise it and give 0.
            cur.ins(
                InstData::Intrinsic {
                    op: Intrinsic::RaiseFault,
                    args: Vec::new(),
                },
                None,
            );
            *cur.f.inst_mut(inst) = InstData::Iconst { ty, imm: 0 };
            return Guarded::InPlace;
        }
        Some(-1) if min_guard => {
            // x / -1 = -x (wrapping), x % -1 = 0.
            *cur.f.inst_mut(inst) = if op == BinaryOp::Sdiv {
                InstData::Unary {
                    op: UnaryOp::Ineg,
                    arg: x,
                }
            } else {
                InstData::Iconst { ty, imm: 0 }
            };
            return Guarded::InPlace;
        }
        Some(_) => return Guarded::Unchanged,
        None => {}
    }
    if defines.div_by_zero {
        if min_guard {
            guard_min_div(&mut cur, inst, op, x, d);
            return Guarded::InPlace;
        }
        return Guarded::Unchanged;
    }

    // b: ...; z = icmp eq d, 0; brif z, fault, ok
    // fault: raise_fault; jump join(0)
    // ok: [MIN / -1 guard]; r' = op x, d; jump join(r')
    // join(r): the rest of b
    let f = cur.f;
    let r = f.result(inst).expect("a division has a result");
    let tail: Vec<Inst> = f.blocks[b.index()].insts.split_off(k + 1);
    f.blocks[b.index()].insts.pop(); // the division itself moves to `ok`
    let fault = f.create_block();
    let ok = f.create_block();
    let join = f.create_block();
    let mut cur = Cursor { f, b, at: k, span };
    let zero = cur.iconst(ty, 0);
    let z = cur.icmp(IntCC::Eq, d, zero);
    cur.ins(
        InstData::Brif {
            cond: z,
            then_dest: Box::new(BlockCall::new(fault, Vec::new())),
            else_dest: Box::new(BlockCall::new(ok, Vec::new())),
        },
        None,
    );
    let mut cur = Cursor {
        f: cur.f,
        b: fault,
        at: 0,
        span,
    };
    cur.ins(
        InstData::Intrinsic {
            op: Intrinsic::RaiseFault,
            args: Vec::new(),
        },
        None,
    );
    let zero = cur.iconst(ty, 0);
    cur.ins(
        InstData::Jump {
            dest: BlockCall::new(join, vec![zero]),
        },
        None,
    );
    // The division gets a new result in `ok`; its old value becomes `join`'s parameter,
    // so every use of it stays as it is.
    let mut cur = Cursor {
        f: cur.f,
        b: ok,
        at: 0,
        span,
    };
    let out = if min_guard {
        let (m, special, q) = min_div_parts(&mut cur, op, x, d);
        cur.select(m, special, q)
    } else {
        cur.val(InstData::Binary { op, args: [x, d] }, ty)
    };
    let f = cur.f;
    let j = f.create_inst(
        InstData::Jump {
            dest: BlockCall::new(join, vec![out]),
        },
        None,
        span,
    );
    f.blocks[ok.index()].insts.push(j);
    f.values[r.index()].def = ValueDef::Param(join, 0);
    f.blocks[join.index()].params.push(r);
    f.results[inst.index()] = None;
    f.blocks[join.index()].insts = tail;
    let at = f.layout.iter().position(|&x| x == b).expect("in layout");
    f.layout.splice(at + 1..at + 1, [fault, ok, join]);
    Guarded::Split(join)
}

/// Rewrites the instruction `inst` (in the cursor's block, at the cursor) into
/// `sdiv`/`srem` of `x` by `d` guarded against `MIN / -1`.
fn guard_min_div(cur: &mut Cursor, inst: Inst, op: BinaryOp, x: Value, d: Value) {
    let (m, special, q) = min_div_parts(cur, op, x, d);
    *cur.f.inst_mut(inst) = InstData::Select {
        cond: m,
        if_true: special,
        if_false: q,
    };
}

/// `m = d == -1; q = op x, (m ? 1 : d)`; the result is `m ? special : q` with
/// `special` `-x` for `sdiv` and 0 for `srem`. Returns `(m, special, q)`.
fn min_div_parts(cur: &mut Cursor, op: BinaryOp, x: Value, d: Value) -> (Value, Value, Value) {
    let ty = cur.f.value_type(x);
    let m1 = cur.iconst(ty, -1);
    let m = cur.icmp(IntCC::Eq, d, m1);
    let one = cur.iconst(ty, 1);
    let safe = cur.select(m, one, d);
    let q = cur.val(
        InstData::Binary {
            op,
            args: [x, safe],
        },
        ty,
    );
    let special = if op == BinaryOp::Sdiv {
        cur.val(
            InstData::Unary {
                op: UnaryOp::Ineg,
                arg: x,
            },
            ty,
        )
    } else {
        cur.iconst(ty, 0)
    };
    (m, special, q)
}

/// Guards the shift at position `k` of block `b`; true if it changed anything.
fn guard_shift(f: &mut Function, b: Block, k: usize, op: BinaryOp, [x, c]: [Value; 2]) -> bool {
    let inst = f.blocks[b.index()].insts[k];
    let ty = f.value_type(x);
    let w = ty.bits() as u64;
    let span = f.spans[inst.index()];
    if let Some(n) = const_of(f, c) {
        if ty.zext_bits(n) < w {
            return false;
        }
        let mut cur = Cursor { f, b, at: k, span };
        *cur.f.inst_mut(inst) = if op == BinaryOp::Sshr {
            let c2 = cur.iconst(ty, w as i64 - 1);
            InstData::Binary { op, args: [x, c2] }
        } else {
            InstData::Iconst { ty, imm: 0 }
        };
        return true;
    }
    let mut cur = Cursor { f, b, at: k, span };
    let wv = cur.iconst(ty, w as i64);
    let ge = cur.icmp(IntCC::Uge, c, wv);
    if op == BinaryOp::Sshr {
        // sshr x, (c >= w ? w - 1 : c)
        let last = cur.iconst(ty, w as i64 - 1);
        let c2 = cur.select(ge, last, c);
        *cur.f.inst_mut(inst) = InstData::Binary { op, args: [x, c2] };
    } else {
        // c >= w ? 0 : (x op (c >= w ? 0 : c))
        let zero = cur.iconst(ty, 0);
        let c2 = cur.select(ge, zero, c);
        let s = cur.val(InstData::Binary { op, args: [x, c2] }, ty);
        *cur.f.inst_mut(inst) = InstData::Select {
            cond: ge,
            if_true: zero,
            if_false: s,
        };
    }
    true
}

/// Guards the conversion at position `k` of block `b`: the conversion only sees an
/// operand whose truncation fits `ty`; out of range (and NaN) the result is selected.
fn guard_float_to_int(f: &mut Function, b: Block, k: usize, op: ConvOp, ty: Type, x: Value) {
    let inst = f.blocks[b.index()].insts[k];
    let fty = f.value_type(x);
    let span = f.spans[inst.index()];
    let w = ty.bits() as i32;
    let mut cur = Cursor { f, b, at: k, span };
    // The operand is in range when lo (<= or <) x < hi; both bounds are powers of two
    // (or -1), exact in both float types.
    let (lo, lo_cc, hi) = if op == ConvOp::FToSi {
        (-(2f64.powi(w - 1)), FloatCC::Ge, 2f64.powi(w - 1))
    } else {
        (-1.0, FloatCC::Gt, 2f64.powi(w))
    };
    let lo_v = cur.fconst(fty, lo);
    let hi_v = cur.fconst(fty, hi);
    let above_lo = cur.fcmp(lo_cc, x, lo_v);
    let below_hi = cur.fcmp(FloatCC::Lt, x, hi_v);
    let ok = cur.val(
        InstData::Binary {
            op: BinaryOp::Band,
            args: [above_lo, below_hi],
        },
        Type::I1,
    );
    let zero = cur.fconst(fty, 0.0);
    let safe = cur.select(ok, x, zero);
    let t = cur.val(InstData::Convert { op, ty, arg: safe }, ty);
    let big = cur.fcmp(FloatCC::Ge, x, hi_v);
    let (max, min) = if op == ConvOp::FToSi {
        (
            (1i64 << (w - 1)).wrapping_sub(1),
            Some(if w == 64 {
                i64::MIN
            } else {
                -(1i64 << (w - 1))
            }),
        )
    } else {
        (-1, None) // all ones
    };
    let max_v = cur.iconst(ty, max);
    match min {
        Some(min) => {
            let r1 = cur.select(big, max_v, t);
            let small = cur.fcmp(FloatCC::Lt, x, lo_v);
            let min_v = cur.iconst(ty, min);
            *cur.f.inst_mut(inst) = InstData::Select {
                cond: small,
                if_true: min_v,
                if_false: r1,
            };
        }
        None => {
            *cur.f.inst_mut(inst) = InstData::Select {
                cond: big,
                if_true: max_v,
                if_false: t,
            };
        }
    }
}

#[cfg(test)]
mod tests;
