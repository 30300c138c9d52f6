//! Loop idiom: a counted loop whose only effect is to store one loop-invariant value
//! into consecutive elements of an array becomes one `fill` intrinsic
//! ([`Intrinsic::Fill`]), which a backend can turn into `memset`.
//!
//! ```text
//! H(i):  c = icmp sgt i, X            H(i):  ...  n = X - i + 1 (i64)
//!        brif c, E(i), B                     fill (elem_addr A, %arr, n > 0 ? i : 0), V, max(n, 0)
//! B:     p = elem_addr A, %arr, i            jump E(n > 0 ? X + 1 : i)
//!        store V, p                    B:    (unreachable, removed)
//!        i2 = iadd i, 1
//!        jump H(i2)
//! ```
//!
//! The loop must be exactly that:
//! - a header `H` with one parameter `i` (the counter), entered from one block outside
//!   the loop and from one latch, ending in a `brif` on `icmp i, X` that leaves to an
//!   exit block and otherwise runs the body; `X` is defined outside the loop (or is a
//!   constant in `H`), and the loop goes on while `i < X` or `i <= X` (signed or
//!   unsigned); nothing else in `H` reads `i`, and nothing in `H` has an effect;
//! - a body block `B` (entered only from `H`) whose instructions have no effect but one
//!   `store V, elem_addr A, %arr, i + k` (`V` and `A` not depending on the loop, the
//!   array's elements of `V`'s type) and `i + 1`, which goes back to `H`; either
//!   directly or through the watchdog's check block (`stop_requested`, `brif` to a bail
//!   block or back), which the fill does not need: it always ends.
//!
//! No bounds check remains in such a body (the front ends put one there unless
//! [`crate::passes::ranges`] proved every index in range), so the elements `i + k` for
//! `i` from the first value to the last are all in the array: the fill writes exactly
//! what the loop wrote. Since the counter goes up by one through all of them without
//! wrapping (the array is shorter than the counter's type's range), the loop ends.
//!
//! The counter's value after the loop (a FOR loop's variable is stored after it) is
//! `X + 1` (or `X` for `<`) when the loop ran, else its first value.
//!
//! Like [`crate::passes::rotate`], the pass is a backend's choice, not part of
//! [`crate::passes::optimize_function`]: only a backend with a fast fill gains.

use crate::builder::FuncBuilder;
use crate::dominators::DomTree;
use crate::entities::{AggId, Block, Inst, Value};
use crate::function::{Function, ValueDef};
use crate::inst::{BinaryOp, ConvOp, InstData, IntCC, Intrinsic};
use crate::module::{AggDef, Module};
use crate::types::{MemType, Type};

use super::util::int_const;

/// A loop that [`run`] replaces.
struct FillLoop {
    header: Block,
    /// The loop's other blocks (body, and the watchdog's check block if any).
    body: Vec<Block>,
    counter: Value,
    /// The bound and the comparison that keeps the loop going (`counter cc bound`).
    bound: Value,
    cc: IntCC,
    /// The stored value.
    value: Value,
    /// The array's address and type.
    base: Value,
    agg: AggId,
    /// The element's index (`counter + k`, perhaps widened): on entry to the header,
    /// the first element's.
    index: Value,
    /// The body's instructions but the address and the store (the index, constants,
    /// addresses): they have no effect, and move to the header, where the fill reads
    /// them.
    moved: Vec<Inst>,
}

/// The byte every byte of `value` is, when `value` is an integer or float constant of
/// `size` bytes whose bytes are all the same (0, -1, a BOOL, 0.0): a backend fills
/// such a value with a byte fill (`memset`, the VM's FPAT). `None` otherwise.
pub fn repeated_byte(func: &Function, value: Value, size: u32) -> Option<u8> {
    let bits = match super::util::def_inst(func, value)? {
        InstData::Iconst { imm, .. } => *imm as u64,
        InstData::Fconst { bits, .. } => *bits,
        _ => return None,
    };
    let b = bits as u8;
    (0..size.min(8))
        .all(|j| (bits >> (8 * j)) as u8 == b)
        .then_some(b)
}

/// Replaces each fill loop of `func` (see the module doc). Returns true if the
/// function changed.
pub fn run(func: &mut Function, module: &Module) -> bool {
    let Some(entry) = func.entry() else {
        return false;
    };
    let dt = DomTree::compute(func);
    let preds = func.predecessors();
    let found: Vec<FillLoop> = dt
        .rpo()
        .iter()
        .filter(|&&h| h != entry)
        .filter_map(|&h| matches(func, module, &dt, &preds, h))
        .collect();
    if found.is_empty() {
        return false;
    }
    for l in &found {
        rewrite(func, l);
    }
    super::cleanup(func, super::ALL);
    true
}

/// The block defining `v`.
fn def_block(func: &Function, v: Value) -> Option<Block> {
    match func.value_def(v) {
        ValueDef::Param(b, _) => Some(b),
        ValueDef::Result(i) => func
            .layout
            .iter()
            .copied()
            .find(|&b| func.block(b).insts.contains(&i)),
    }
}

/// The watchdog's check ending block `b`: `s = stop_requested` in `b`, then
/// `brif s, bail, h(args)` with `bail` outside the loop; the check and the arguments.
fn check_of(func: &Function, b: Block, h: Block, body: &[Block]) -> Option<(Inst, Vec<Value>)> {
    let insts = &func.block(b).insts;
    let InstData::Brif {
        cond,
        then_dest,
        else_dest,
    } = func.inst(*insts.last()?)
    else {
        return None;
    };
    let stop = def_inst(func, *cond)?;
    let bail = then_dest.block;
    if !insts.contains(&stop) || else_dest.block != h || bail == h || body.contains(&bail) {
        return None;
    }
    match func.inst(stop) {
        InstData::Intrinsic {
            op: Intrinsic::StopRequested,
            ..
        } => Some((stop, else_dest.args.clone())),
        _ => None,
    }
}

/// The loop's blocks after the header (the body, then the watchdog's check block if
/// the back edge has one of its own), the arguments of the back edge and the
/// watchdog's check in the body (to be ignored); `None` unless the loop is one block
/// (plus the check) entered from `h` alone.
fn body_of(
    func: &Function,
    preds: &[Vec<Block>],
    h: Block,
    b0: Block,
    latch: Block,
) -> Option<(Vec<Block>, Vec<Value>, Option<Inst>)> {
    if preds[b0.index()].len() != 1 || !func.block(b0).params.is_empty() {
        return None;
    }
    match func.inst(func.terminator(b0)?) {
        InstData::Jump { dest } if dest.block == h && b0 == latch => {
            Some((vec![b0], dest.args.clone(), None))
        }
        // The watchdog's check in a block of its own.
        InstData::Jump { dest } if dest.block == latch && dest.args.is_empty() => {
            let c = latch;
            if preds[c.index()].len() != 1 || func.block(c).insts.len() != 2 {
                return None;
            }
            let (_, args) = check_of(func, c, h, &[b0, c])?;
            Some((vec![b0, c], args, None))
        }
        // The check merged into the body.
        InstData::Brif { .. } if b0 == latch => {
            let (stop, args) = check_of(func, b0, h, &[b0])?;
            Some((vec![b0], args, Some(stop)))
        }
        _ => None,
    }
}

/// `h` as the header of a fill loop, if it is one.
fn matches(
    func: &Function,
    module: &Module,
    dt: &DomTree,
    preds: &[Vec<Block>],
    h: Block,
) -> Option<FillLoop> {
    let hp = &preds[h.index()];
    if hp.len() != 2 || func.block(h).params.len() != 1 {
        return None;
    }
    let latch = *hp.iter().find(|&&p| dt.dominates(h, p))?;
    if hp.iter().all(|&p| dt.dominates(h, p)) {
        return None;
    }
    let counter = func.block(h).params[0];
    let cty = func.value_type(counter);
    if !cty.is_int() || cty == Type::I1 {
        return None;
    }
    // The header's branch: on `icmp counter, bound` to the body or out.
    let term = func.terminator(h)?;
    let InstData::Brif {
        cond,
        then_dest,
        else_dest,
    } = func.inst(term)
    else {
        return None;
    };
    let ci = def_inst(func, *cond)?;
    let InstData::Icmp { cond: cc, args } = func.inst(ci) else {
        return None;
    };
    let (cc, bound) = if args[0] == counter {
        (*cc, args[1])
    } else if args[1] == counter {
        (cc.swapped(), args[0])
    } else {
        return None;
    };
    let (b0, exit, cc) = if dt.dominates(then_dest.block, latch) {
        (then_dest, else_dest, cc)
    } else {
        (else_dest, then_dest, cc.inverted())
    };
    if !matches!(cc, IntCC::Slt | IntCC::Sle | IntCC::Ult | IntCC::Ule) || !b0.args.is_empty() {
        return None;
    }
    let (body, back, check) = body_of(func, preds, h, b0.block, latch)?;
    let in_loop = |b: Option<Block>| b.is_some_and(|b| b == h || body.contains(&b));
    if in_loop(Some(exit.block)) {
        return None;
    }
    // The bound comes from outside the loop, or is a constant in the header.
    let bound_block = def_block(func, bound);
    if in_loop(bound_block) && !(bound_block == Some(h) && int_const(func, bound).is_some()) {
        return None;
    }
    // Nothing else in the header reads the counter or has an effect.
    for &i in &func.block(h).insts {
        if i == ci || i == term {
            continue;
        }
        let data = func.inst(i);
        let mut reads = false;
        data.for_each_arg(|a| reads |= a == counter || Some(a) == func.result(ci));
        if reads || data.has_side_effects() || matches!(data, InstData::Load { .. }) {
            return None;
        }
    }
    // The body: the counter plus or minus constants, widened as the comparison reads
    // it (the step among them), the element's address, the store, and values that
    // do not depend on the counter.
    let signed = matches!(cc, IntCC::Slt | IntCC::Sle);
    let mut affine: Vec<(Value, i64)> = vec![(counter, 0)];
    let mut store = None;
    let mut addr: Option<(Value, Value, AggId, Value)> = None;
    let mut moved = Vec::new();
    let insts = &func.block(b0.block).insts;
    for &i in &insts[..insts.len() - 1] {
        if Some(i) == check {
            continue;
        }
        let data = func.inst(i);
        let res = func.result(i);
        let varying = |v: Value| affine.iter().any(|a| a.0 == v) || addr.is_some_and(|a| a.0 == v);
        let mut reads_varying = false;
        data.for_each_arg(|a| reads_varying |= varying(a));
        let affine_of = |v: Value| affine.iter().find(|a| a.0 == v).map(|a| a.1);
        match data {
            InstData::Store { value, addr: a } if store.is_none() && !varying(*value) => {
                store = Some((*value, *a));
                continue;
            }
            _ if data.has_side_effects() || matches!(data, InstData::Load { .. }) => return None,
            _ if !reads_varying => {}
            InstData::Binary { op, args } if affine_of(args[0]).is_some() => {
                let k = int_const(func, args[1])?;
                let k = match op {
                    BinaryOp::Iadd => k,
                    BinaryOp::Isub => k.checked_neg()?,
                    _ => return None,
                };
                affine.push((res?, affine_of(args[0])?.checked_add(k)?));
            }
            InstData::Binary {
                op: BinaryOp::Iadd,
                args,
            } if affine_of(args[1]).is_some() => {
                let k = int_const(func, args[0])?;
                affine.push((res?, affine_of(args[1])?.checked_add(k)?));
            }
            InstData::Convert { op, arg, .. }
                if affine_of(*arg).is_some()
                    && (*op == ConvOp::Sext && signed || *op == ConvOp::Uext && !signed) =>
            {
                affine.push((res?, affine_of(*arg)?));
            }
            InstData::ElemAddr { base, agg, index } if addr.is_none() && !varying(*base) => {
                affine_of(*index)?;
                addr = Some((res?, *base, *agg, *index));
                continue;
            }
            _ => return None,
        }
        moved.push(i);
    }
    let (value, store_addr) = store?;
    let (addr, base, agg, index) = addr?;
    if store_addr != addr || back.len() != 1 || !affine.contains(&(back[0], 1)) {
        return None;
    }
    // An array of the stored value's type, shorter than the counter's range (so the
    // counter cannot wrap while it indexes it).
    let Some(AggDef::Array(a)) = module.aggs.get(agg.index()) else {
        return None;
    };
    if a.elem != MemType::Scalar(func.value_type(value))
        || u128::from(a.len) >= (1u128 << cty.bits().min(64)) - 1
    {
        return None;
    }
    // No value of the loop's blocks is used outside them.
    let loop_defs: Vec<Value> = body
        .iter()
        .flat_map(|&b| func.block(b).insts.iter().filter_map(|&i| func.result(i)))
        .collect();
    for &b in &func.layout {
        if in_loop(Some(b)) {
            continue;
        }
        for &i in &func.block(b).insts {
            let mut uses = false;
            func.inst(i)
                .for_each_arg(|a| uses |= loop_defs.contains(&a));
            if uses {
                return None;
            }
        }
    }
    Some(FillLoop {
        header: h,
        body,
        counter,
        bound,
        cc,
        value,
        base,
        agg,
        index,
        moved,
    })
}

fn def_inst(func: &Function, v: Value) -> Option<Inst> {
    match func.value_def(v) {
        ValueDef::Result(i) => Some(i),
        ValueDef::Param(..) => None,
    }
}

/// `v` as an `i64` (sign- or zero-extended).
fn widen(b: &mut FuncBuilder, v: Value, signed: bool) -> Value {
    if b.func.value_type(v) == Type::I64 {
        return v;
    }
    let op = if signed { ConvOp::Sext } else { ConvOp::Uext };
    b.convert(op, Type::I64, v)
}

/// Replaces the loop by a fill in its header (see the module doc).
fn rewrite(func: &mut Function, l: &FillLoop) {
    let h = l.header;
    // The header's branch goes; the header gets the body's moved instructions, the
    // fill, and a jump out.
    let term = func.blocks[h.index()].insts.pop().expect("header branch");
    let span = func.spans[term.index()];
    let InstData::Brif {
        then_dest,
        else_dest,
        ..
    } = func.inst(term).clone()
    else {
        unreachable!("matched a brif");
    };
    let b0 = l.body[0];
    func.blocks[b0.index()]
        .insts
        .retain(|i| !l.moved.contains(i));
    func.blocks[h.index()].insts.extend(&l.moved);
    let cty = func.value_type(l.counter);
    let inclusive = matches!(l.cc, IntCC::Sle | IntCC::Ule);
    let signed = matches!(l.cc, IntCC::Slt | IntCC::Sle);
    let mut b = FuncBuilder::new(func);
    b.set_span(span);
    b.switch_to(h);
    // The number of elements: bound - first (+ 1 for `<=`), in 64 bits.
    let first = widen(&mut b, l.counter, signed);
    let bound = widen(&mut b, l.bound, signed);
    let mut n = b.binary(BinaryOp::Isub, bound, first);
    if inclusive {
        let one = b.iconst(Type::I64, 1);
        n = b.binary(BinaryOp::Iadd, n, one);
    }
    let zero64 = b.iconst(Type::I64, 0);
    let ran = b.icmp(IntCC::Sgt, n, zero64);
    let count = b.select(ran, n, zero64);
    // The first element (element 0 when the loop does not run: any valid address).
    let ity = b.func.value_type(l.index);
    let zero = b.iconst(ity, 0);
    let ix = b.select(ran, l.index, zero);
    let at = b.elem_addr(l.base, l.agg, ix);
    b.intrinsic(Intrinsic::Fill, vec![at, l.value, count]);
    // The counter after the loop.
    let mut end = l.bound;
    if inclusive {
        let one = b.iconst(cty, 1);
        end = b.binary(BinaryOp::Iadd, end, one);
    }
    let after = b.select(ran, end, l.counter);
    // The header now runs once and goes out.
    let mut exit = if l.body.contains(&then_dest.block) {
        else_dest
    } else {
        then_dest
    };
    for a in &mut exit.args {
        if *a == l.counter {
            *a = after;
        }
    }
    b.jump(exit.block, exit.args);
    // Uses of the counter after the loop see its final value.
    for blk in func.layout.clone() {
        if blk == h || l.body.contains(&blk) {
            continue;
        }
        for ii in 0..func.blocks[blk.index()].insts.len() {
            let i = func.blocks[blk.index()].insts[ii];
            func.insts[i.index()].map_args(|a| if a == l.counter { after } else { a });
        }
    }
}
