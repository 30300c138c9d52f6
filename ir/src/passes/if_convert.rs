//! If-conversion: a branch around a few cheap instructions becomes straight-line code
//! with `select`s, for targets whose branches cost more than the instructions saved
//! (the JIT: a mispredicted branch costs some fifteen cycles, a `select` is a `cmov`).
//!
//! Two shapes are converted, where `T` and `F` have the branch as their only
//! predecessor, hold at most [`MAX_HOISTED`] instructions together, each of which
//! cannot fault, has no effect and is cheap ([`speculatable`]), and end in a `jump` to
//! the same block `J`:
//!
//! - the triangle `brif c, T(a), J(x)` with `T: ...; jump J(y)` (or the mirror,
//!   `brif c, J(x), F(a)`);
//! - the diamond `brif c, T(a), F(b)` with `T: ...; jump J(y)` and `F: ...; jump J(x)`.
//!
//! The instructions of `T` (and `F`) move in front of the branch, with their block
//! parameters replaced by the branch's arguments, and the branch becomes
//! `jump J(s)` where `s[k]` is `y[k]` if it equals `x[k]`, else `select c, y[k], x[k]`
//! (at most [`MAX_SELECTS`] of them). `T` and `F` leave the layout.
//!
//! Nothing here changes what a function computes: the moved instructions have no
//! effect and cannot fault, so running them on the other path too only costs their
//! time. The pass is not part of [`crate::passes::optimize_function`]: a backend runs
//! it when its target wants it (the interpreter runs the IR as the front end wrote it,
//! so the differential tests compare the converted code with the original).

use crate::entities::{Block, Inst, Value};
use crate::function::Function;
use crate::inst::{BinaryOp, BlockCall, ConvOp, InstData, UnaryOp};

/// At most this many instructions move in front of one branch.
pub const MAX_HOISTED: usize = 4;
/// At most this many `select`s replace one branch.
pub const MAX_SELECTS: usize = 3;

/// Converts the triangles and diamonds of `func` (see the module doc). Returns true
/// if the function changed.
pub fn run(func: &mut Function) -> bool {
    if func.layout.is_empty() {
        return false;
    }
    let mut preds = pred_counts(func);
    let mut changed = false;
    let mut removed = vec![false; func.blocks.len()];
    for bi in 0..func.layout.len() {
        let b = func.layout[bi];
        if removed[b.index()] {
            continue;
        }
        if let Some((gone, join)) = convert(func, b, &preds) {
            for g in gone.into_iter().flatten() {
                removed[g.index()] = true;
                preds[g.index()] = 0;
            }
            // The join lost an edge: a triangle's side and the branch (or a diamond's
            // two sides) became the one jump.
            preds[join.index()] -= 1;
            changed = true;
        }
    }
    if changed {
        func.layout.retain(|b| !removed[b.index()]);
    }
    changed
}

/// The number of incoming edges of each block (an edge per branch destination).
fn pred_counts(func: &Function) -> Vec<u32> {
    let mut n = vec![0u32; func.blocks.len()];
    for &b in &func.layout {
        if let Some(t) = func.terminator(b) {
            for d in func.inst(t).successors() {
                n[d.block.index()] += 1;
            }
        }
    }
    n
}

/// True for the instructions that may run on a path that did not ask for them: no
/// effect, no fault, and cheap (no division, no library math).
pub fn speculatable(data: &InstData) -> bool {
    match data {
        InstData::Iconst { .. }
        | InstData::Fconst { .. }
        | InstData::Icmp { .. }
        | InstData::Fcmp { .. }
        | InstData::Select { .. } => true,
        InstData::Binary { op, .. } => matches!(
            op,
            BinaryOp::Iadd
                | BinaryOp::Isub
                | BinaryOp::Imul
                | BinaryOp::Band
                | BinaryOp::Bor
                | BinaryOp::Bxor
                | BinaryOp::Ishl
                | BinaryOp::Ushr
                | BinaryOp::Sshr
                | BinaryOp::Rotl
                | BinaryOp::Rotr
                | BinaryOp::Fadd
                | BinaryOp::Fsub
                | BinaryOp::Fmul
        ),
        InstData::Unary { op, .. } => matches!(
            op,
            UnaryOp::Ineg | UnaryOp::Bnot | UnaryOp::Iabs | UnaryOp::Fneg | UnaryOp::Fabs
        ),
        InstData::Convert { op, .. } => matches!(
            op,
            ConvOp::Sext | ConvOp::Uext | ConvOp::Itrunc | ConvOp::Bitcast
        ),
        _ => false,
    }
}

/// A side block of a triangle or diamond: its instructions (terminator excluded) and
/// the arguments it passes to the join.
struct Side {
    block: Block,
    insts: Vec<Inst>,
    join: BlockCall,
}

/// `b`'s arm `dest`, if it is a block only `b` reaches, holding nothing but cheap
/// instructions and ending in a `jump`.
fn side(func: &Function, preds: &[u32], b: Block, dest: &BlockCall) -> Option<Side> {
    let s = dest.block;
    if s == b || preds[s.index()] != 1 {
        return None;
    }
    let insts = &func.block(s).insts;
    let (&last, body) = insts.split_last()?;
    let InstData::Jump { dest: join } = func.inst(last) else {
        return None;
    };
    if body.len() > MAX_HOISTED || !body.iter().all(|&i| speculatable(func.inst(i))) {
        return None;
    }
    Some(Side {
        block: s,
        insts: body.to_vec(),
        join: join.clone(),
    })
}

/// Converts the branch ending `b` if it heads a triangle or a diamond; returns the
/// blocks that left the layout and the join.
fn convert(func: &mut Function, b: Block, preds: &[u32]) -> Option<([Option<Block>; 2], Block)> {
    let term = func.terminator(b)?;
    let InstData::Brif {
        cond,
        then_dest,
        else_dest,
    } = func.inst(term).clone()
    else {
        return None;
    };
    if then_dest.block == else_dest.block {
        return None;
    }
    let t = side(func, preds, b, &then_dest);
    let f = side(func, preds, b, &else_dest);
    // The arguments each path brings to the join, and the blocks hoisted.
    let (join, on_true, on_false) = match (t, f) {
        (Some(t), Some(f)) if t.join.block == f.join.block && t.join.block != b => {
            let n = t.insts.len() + f.insts.len();
            if n > MAX_HOISTED {
                return None;
            }
            let join = t.join.block;
            (
                join,
                Some((t, then_dest.clone())),
                Some((f, else_dest.clone())),
            )
        }
        // A triangle; one whose join is the branch's own block is a loop, left alone.
        (Some(t), _) if t.join.block == else_dest.block && else_dest.block != b => {
            (else_dest.block, Some((t, then_dest.clone())), None)
        }
        (_, Some(f)) if f.join.block == then_dest.block && then_dest.block != b => {
            (then_dest.block, None, Some((f, else_dest.clone())))
        }
        _ => return None,
    };
    // What the join receives on each path, once the side's parameters are replaced.
    let args = |func: &Function, arm: &Option<(Side, Box<BlockCall>)>, direct: &BlockCall| match arm
    {
        Some((s, call)) => {
            let params = &func.block(s.block).params;
            s.join
                .args
                .iter()
                .map(|&a| subst(params, &call.args, a))
                .collect::<Vec<Value>>()
        }
        None => direct.args.clone(),
    };
    let yes = args(func, &on_true, &then_dest);
    let no = args(func, &on_false, &else_dest);
    let selects = yes.iter().zip(&no).filter(|(a, b)| a != b).count();
    if selects > MAX_SELECTS {
        return None;
    }

    // Hoist: each side's instructions, with its parameters replaced, go before the
    // branch (which is removed and replaced by the selects and the jump).
    let mut out = func.blocks[b.index()].insts.clone();
    out.pop();
    let mut gone = [None, None];
    for (k, arm) in [on_true, on_false].into_iter().enumerate() {
        let Some((s, call)) = arm else { continue };
        let params = func.block(s.block).params.clone();
        for &i in &s.insts {
            func.insts[i.index()].map_args(|a| subst(&params, &call.args, a));
            out.push(i);
        }
        gone[k] = Some(s.block);
    }
    let mut join_args = Vec::with_capacity(yes.len());
    for (a, z) in yes.into_iter().zip(no) {
        if a == z {
            join_args.push(a);
            continue;
        }
        let ty = func.value_type(a);
        let span = func.spans[term.index()];
        let sel = func.create_inst(
            InstData::Select {
                cond,
                if_true: a,
                if_false: z,
            },
            Some(ty),
            span,
        );
        out.push(sel);
        join_args.push(func.result(sel).expect("a select has a result"));
    }
    let jump = func.create_inst(
        InstData::Jump {
            dest: BlockCall::new(join, join_args),
        },
        None,
        func.spans[term.index()],
    );
    out.push(jump);
    func.blocks[b.index()].insts = out;
    for g in gone.iter().flatten() {
        func.blocks[g.index()].insts.clear();
    }
    Some((gone, join))
}

/// `v` with block parameter `params[k]` replaced by `args[k]`.
fn subst(params: &[Value], args: &[Value], v: Value) -> Value {
    params.iter().position(|&p| p == v).map_or(v, |k| args[k])
}
