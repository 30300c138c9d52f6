//! The execution loop and the semantics of every operation.
//!
//! Registers hold values in canonical form (see [`canon`]): integers sign-extended from
//! their width, `i1` as 0 or 1, `f32` as its encoding in the low 32 bits. Every
//! operation reads its operands at their width and writes a canonical result, so that
//! equality of registers is equality of values.
//!
//! Calls push an explicit frame instead of recursing in Rust, so a runaway call chain
//! in a malformed module ends in a `MachineError`, never in a host stack overflow.

use super::decode::{canon, DFunc, Op, FRAME_ALIGN, NONE};
use crate::inst::{BinaryOp, ConvOp, FloatCC, InstData, IntCC, UnaryOp};
use crate::machine::MachineError;
use crate::module::Module;
use crate::types::Type;
use std::fmt::Write as _;

/// The lowest valid address: nothing lives below it, so a null pointer always faults.
pub const DATA_BASE: u64 = 16;

/// The byte that fresh memory (data before cold start, stack slots at every call) is
/// filled with, so that reading something never written shows up deterministically.
pub const GARBAGE: u8 = 0xA5;

/// The deepest call chain allowed (the IR forbids recursion, so only a malformed
/// module gets there).
pub const MAX_CALL_DEPTH: usize = 256;

/// The most stack memory (slots of all live frames) a run may use.
pub const MAX_STACK_BYTES: u64 = 256 << 20;

/// A suspended caller.
#[derive(Copy, Clone, Debug)]
pub(super) struct Frame {
    func: u32,
    /// The operation after the call.
    pc: u32,
    /// First register of the caller's frame.
    base: u32,
    /// The caller's frame pointer (its slots).
    fp: u64,
    /// The stack top before the callee's frame was allocated.
    sp: u64,
    /// The caller's register receiving the result (`NONE` if unused).
    ret_dst: u32,
}

/// Everything a run changes: memory, registers, frames, the fault flag.
#[derive(Debug)]
pub(super) struct State {
    /// The byte arena: data objects from `DATA_BASE`, then the stack. Always at least
    /// as long as the current stack top, which bounds every access.
    pub mem: Vec<u8>,
    /// Registers of all live frames, each frame's at its base.
    pub regs: Vec<u64>,
    /// Suspended callers.
    pub frames: Vec<Frame>,
    /// Temporary for parallel copies of block arguments.
    pub scratch: Vec<u64>,
    /// The runtime fault flag.
    pub fault: bool,
    /// The clock as sampled at the start of the scan (ms, wrapping).
    pub clock_ms: i32,
    /// The same instant in ns.
    pub clock_ns: i64,
    /// Operations executed so far in this scan (or cold start, or call).
    pub steps: u64,
    /// The most operations a scan may execute.
    pub step_limit: u64,
}

/// The immutable program a run executes.
pub(super) struct Prog<'a> {
    /// Decoded functions, indexed like the module's.
    pub funcs: &'a [DFunc],
    /// The module (for error messages).
    pub module: &'a Module,
    /// Where the stack starts (all data lies below).
    pub stack_base: u64,
}

fn align_up(x: u64, a: u64) -> u64 {
    x.div_ceil(a) * a
}

/// The signed reading of a register of type `ty` (`i1` is a one-bit two's complement
/// number: 1 reads as -1).
#[inline(always)]
pub(super) fn sval(ty: Type, r: u64) -> i64 {
    if ty == Type::I1 {
        -((r & 1) as i64)
    } else {
        r as i64
    }
}

/// The unsigned reading of a register of type `ty`.
#[inline(always)]
pub(super) fn uval(ty: Type, r: u64) -> u64 {
    ty.zext_bits(r as i64)
}

/// `ineg`, `bnot`, `iabs`.
#[inline]
pub(super) fn int_unary(op: UnaryOp, ty: Type, a: u64) -> u64 {
    let r = match op {
        UnaryOp::Ineg => 0u64.wrapping_sub(a),
        UnaryOp::Bnot => !a,
        _ => sval(ty, a).wrapping_abs() as u64,
    };
    canon(ty, r)
}

/// An integer binary operation; division by zero sets `fault` and gives 0.
#[inline]
pub(super) fn int_binary(op: BinaryOp, ty: Type, a: u64, b: u64, fault: &mut bool) -> u64 {
    let w = ty.bits() as u64;
    let r = match op {
        BinaryOp::Iadd => a.wrapping_add(b),
        BinaryOp::Isub => a.wrapping_sub(b),
        BinaryOp::Imul => a.wrapping_mul(b),
        BinaryOp::Sdiv | BinaryOp::Srem => {
            let (x, y) = (sval(ty, a), sval(ty, b));
            if y == 0 {
                *fault = true;
                0
            } else if op == BinaryOp::Sdiv {
                // i64::MIN / -1 wraps to MIN; narrower MIN / -1 gives 2^(w-1), which
                // the canonicalisation below wraps to MIN as well.
                x.wrapping_div(y) as u64
            } else {
                x.wrapping_rem(y) as u64
            }
        }
        BinaryOp::Udiv | BinaryOp::Urem => {
            let (x, y) = (uval(ty, a), uval(ty, b));
            if y == 0 {
                *fault = true;
                0
            } else if op == BinaryOp::Udiv {
                x / y
            } else {
                x % y
            }
        }
        BinaryOp::Band => a & b,
        BinaryOp::Bor => a | b,
        BinaryOp::Bxor => a ^ b,
        BinaryOp::Ishl => {
            let c = uval(ty, b);
            if c >= w {
                0
            } else {
                a << c
            }
        }
        BinaryOp::Ushr => {
            let c = uval(ty, b);
            if c >= w {
                0
            } else {
                uval(ty, a) >> c
            }
        }
        BinaryOp::Sshr => {
            // The signed reading is sign-extended to 64 bits, so shifting it by
            // min(count, 63) gives the sign fill for every count >= the width.
            (sval(ty, a) >> uval(ty, b).min(63)) as u64
        }
        BinaryOp::Rotl | BinaryOp::Rotr => {
            let c = uval(ty, b) % w;
            let c = if op == BinaryOp::Rotl { c } else { (w - c) % w };
            let u = uval(ty, a);
            if c == 0 {
                u
            } else {
                (u << c) | (u >> (w - c))
            }
        }
        // Float operations never reach here (the decoder sends them elsewhere).
        _ => 0,
    };
    canon(ty, r)
}

/// `icmp`.
#[inline]
pub(super) fn int_cmp(cc: IntCC, ty: Type, a: u64, b: u64) -> bool {
    match cc {
        IntCC::Eq => a == b,
        IntCC::Ne => a != b,
        IntCC::Slt => sval(ty, a) < sval(ty, b),
        IntCC::Sle => sval(ty, a) <= sval(ty, b),
        IntCC::Sgt => sval(ty, a) > sval(ty, b),
        IntCC::Sge => sval(ty, a) >= sval(ty, b),
        IntCC::Ult => uval(ty, a) < uval(ty, b),
        IntCC::Ule => uval(ty, a) <= uval(ty, b),
        IntCC::Ugt => uval(ty, a) > uval(ty, b),
        IntCC::Uge => uval(ty, a) >= uval(ty, b),
    }
}

/// Float operations, written once for `f32` and `f64` so that each runs in its own
/// precision (an `f32` operation computed in `f64` would round differently).
macro_rules! float_ops {
    ($unary:ident, $binary:ident, $cmp:ident, $t:ty) => {
        /// A float unary operation.
        #[inline]
        pub(super) fn $unary(op: UnaryOp, a: $t) -> $t {
            match op {
                UnaryOp::Fneg => -a,
                UnaryOp::Fabs => a.abs(),
                UnaryOp::Fsqrt => a.sqrt(),
                UnaryOp::Fnearest => a.round_ties_even(),
                UnaryOp::Ftrunc => a.trunc(),
                UnaryOp::Ffloor => a.floor(),
                UnaryOp::Fceil => a.ceil(),
                UnaryOp::Sin => a.sin(),
                UnaryOp::Cos => a.cos(),
                UnaryOp::Tan => a.tan(),
                UnaryOp::Asin => a.asin(),
                UnaryOp::Acos => a.acos(),
                UnaryOp::Atan => a.atan(),
                UnaryOp::Ln => a.ln(),
                UnaryOp::Log10 => a.log10(),
                UnaryOp::Exp => a.exp(),
                // Integer operations never reach here.
                UnaryOp::Ineg | UnaryOp::Bnot | UnaryOp::Iabs => a,
            }
        }

        /// A float binary operation.
        #[inline]
        pub(super) fn $binary(op: BinaryOp, a: $t, b: $t) -> $t {
            match op {
                BinaryOp::Fadd => a + b,
                BinaryOp::Fsub => a - b,
                BinaryOp::Fmul => a * b,
                BinaryOp::Fdiv => a / b,
                BinaryOp::Fpow => a.powf(b),
                BinaryOp::Fatan2 => a.atan2(b),
                // Integer operations never reach here.
                _ => a,
            }
        }

        /// `fcmp`: Rust's comparisons are IEEE's (`!=` is the unordered one).
        #[inline]
        pub(super) fn $cmp(cc: FloatCC, a: $t, b: $t) -> bool {
            match cc {
                FloatCC::Eq => a == b,
                FloatCC::Ne => a != b,
                FloatCC::Lt => a < b,
                FloatCC::Le => a <= b,
                FloatCC::Gt => a > b,
                FloatCC::Ge => a >= b,
            }
        }
    };
}

float_ops!(f32_unary, f32_binary, f32_cmp, f32);
float_ops!(f64_unary, f64_binary, f64_cmp, f64);

fn reg_f32(r: u64) -> f32 {
    f32::from_bits(r as u32)
}

fn reg_f64(r: u64) -> f64 {
    f64::from_bits(r)
}

/// The value of a float register of type `ty`, widened exactly to `f64`.
fn float_value(ty: Type, r: u64) -> f64 {
    if ty == Type::F32 {
        reg_f32(r) as f64
    } else {
        reg_f64(r)
    }
}

/// A conversion of `a` (type `from`) to type `to`.
pub(super) fn convert(op: ConvOp, from: Type, to: Type, a: u64) -> u64 {
    match op {
        ConvOp::Sext => canon(to, sval(from, a) as u64),
        ConvOp::Uext => canon(to, uval(from, a)),
        ConvOp::Itrunc => canon(to, a),
        ConvOp::Fpromote => (reg_f32(a) as f64).to_bits(),
        ConvOp::Fdemote => (reg_f64(a) as f32).to_bits() as u64,
        // Rust's integer-to-float `as` rounds to nearest even, once.
        ConvOp::SiToF => match to {
            Type::F32 => (sval(from, a) as f32).to_bits() as u64,
            _ => (sval(from, a) as f64).to_bits(),
        },
        ConvOp::UiToF => match to {
            Type::F32 => (uval(from, a) as f32).to_bits() as u64,
            _ => (uval(from, a) as f64).to_bits(),
        },
        ConvOp::FToSi => {
            // `as i64` truncates toward zero, saturates at i64 and maps NaN to 0;
            // clamping the truncated value to the narrower range saturates there.
            let w = to.bits();
            let (lo, hi) = if w == 64 {
                (i64::MIN, i64::MAX)
            } else {
                (-(1i64 << (w - 1)), (1i64 << (w - 1)) - 1)
            };
            let v = (float_value(from, a) as i64).clamp(lo, hi);
            canon(to, v as u64)
        }
        ConvOp::FToUi => {
            // `as u64` also gives 0 for negatives and NaN.
            let w = to.bits();
            let hi = if w == 64 { u64::MAX } else { (1u64 << w) - 1 };
            canon(to, (float_value(from, a) as u64).min(hi))
        }
        ConvOp::Bitcast | ConvOp::PtrToInt | ConvOp::IntToPtr => canon(to, uval(from, a)),
    }
}

/// Bytes of a scalar in the arena (host layout: `i1` takes a byte, `ptr` 8).
#[inline(always)]
pub(super) fn scalar_size(ty: Type) -> u64 {
    match ty {
        Type::I1 | Type::I8 => 1,
        Type::I16 => 2,
        Type::I32 | Type::F32 => 4,
        Type::I64 | Type::F64 | Type::Ptr => 8,
    }
}

impl State {
    /// Reads a scalar at `addr`, which must lie in `DATA_BASE..limit` and be aligned.
    #[inline]
    pub fn load(&self, ty: Type, addr: u64, limit: u64) -> Result<u64, String> {
        let size = scalar_size(ty);
        if addr < DATA_BASE || addr > limit.saturating_sub(size) || addr & (size - 1) != 0 {
            return Err(bad_access("load", ty, addr, limit));
        }
        let a = addr as usize;
        let m = &self.mem;
        Ok(match ty {
            Type::I1 => {
                let b = m[a];
                if b > 1 {
                    return Err(format!(
                        "load.i1 at address {addr:#x} found {b:#04x}, not 0 or 1 (memory never written?)"
                    ));
                }
                b as u64
            }
            Type::I8 => m[a] as i8 as i64 as u64,
            Type::I16 => i16::from_le_bytes([m[a], m[a + 1]]) as i64 as u64,
            Type::I32 => {
                i32::from_le_bytes(m[a..a + 4].try_into().expect("a 4-byte slice")) as i64 as u64
            }
            Type::F32 => u32::from_le_bytes(m[a..a + 4].try_into().expect("a 4-byte slice")) as u64,
            Type::I64 | Type::F64 | Type::Ptr => {
                u64::from_le_bytes(m[a..a + 8].try_into().expect("an 8-byte slice"))
            }
        })
    }

    /// Writes a scalar (the low bytes of the register) at `addr`, checked like `load`.
    #[inline]
    pub fn store(&mut self, ty: Type, addr: u64, v: u64, limit: u64) -> Result<(), String> {
        let size = scalar_size(ty);
        if addr < DATA_BASE || addr > limit.saturating_sub(size) || addr & (size - 1) != 0 {
            return Err(bad_access("store", ty, addr, limit));
        }
        let a = addr as usize;
        let v = if ty == Type::I1 { v & 1 } else { v };
        self.mem[a..a + size as usize].copy_from_slice(&v.to_le_bytes()[..size as usize]);
        Ok(())
    }
}

#[cold]
fn bad_access(what: &str, ty: Type, addr: u64, limit: u64) -> String {
    let size = scalar_size(ty);
    if addr >= DATA_BASE && addr <= limit.saturating_sub(size) {
        format!("{what}.{ty} at misaligned address {addr:#x}")
    } else {
        format!("{what}.{ty} at address {addr:#x}, outside memory ({DATA_BASE:#x}..{limit:#x})")
    }
}

/// Allocates a frame of `size` bytes above `sp`, filled with garbage; returns the frame
/// pointer and the new stack top.
#[inline]
fn alloc_frame(st: &mut State, prog: &Prog, sp: u64, size: u64) -> Result<(u64, u64), String> {
    // A frame without slots takes no memory, so the callee's accessible memory ends
    // exactly where its caller's does (and stays within the arena).
    if size == 0 {
        return Ok((sp, sp));
    }
    let fp = align_up(sp, FRAME_ALIGN);
    let top = fp + size;
    if top - prog.stack_base > MAX_STACK_BYTES {
        return Err(format!(
            "stack overflow (more than {MAX_STACK_BYTES} bytes of stack slots)"
        ));
    }
    if (st.mem.len() as u64) < top {
        st.mem.resize(top as usize, GARBAGE);
    }
    st.mem[fp as usize..top as usize].fill(GARBAGE);
    Ok((fp, top))
}

/// A `MachineError` for operation `pc` of function `fi`: the message, the function and
/// the instruction in text form.
#[cold]
pub(super) fn fail(prog: &Prog, fi: usize, pc: usize, msg: &str) -> MachineError {
    let f = &prog.module.funcs[fi];
    let origin = prog.funcs[fi].origin.get(pc).copied().unwrap_or(NONE);
    if origin == NONE {
        return MachineError(format!("{msg} (in @{})", f.name));
    }
    let inst = crate::entities::Inst(origin);
    MachineError(format!(
        "{msg} (in @{}, {inst}: {})",
        f.name,
        inst_text(prog.module, f, inst)
    ))
}

/// A one-line text form of an instruction, close to the IR's text form, for errors.
pub(super) fn inst_text(
    m: &Module,
    f: &crate::function::Function,
    i: crate::entities::Inst,
) -> String {
    let mut s = String::new();
    let Some(d) = f.insts.get(i.index()) else {
        return format!("{i}");
    };
    if let Some(Some(r)) = f.results.get(i.index()) {
        let _ = write!(s, "{r} = ");
    }
    let list = |vs: &[crate::entities::Value]| {
        vs.iter()
            .map(|v| v.to_string())
            .collect::<Vec<_>>()
            .join(", ")
    };
    let call = |bc: &crate::inst::BlockCall| format!("{}({})", bc.block, list(&bc.args));
    let _ = match d {
        InstData::Iconst { ty, imm } => write!(s, "iconst.{ty} {imm}"),
        InstData::Fconst { ty, bits } => write!(s, "fconst.{ty} {bits:#x}"),
        InstData::SizeOf { ty, of } => write!(s, "sizeof.{ty} {of:?}"),
        InstData::Unary { op, arg } => write!(s, "{} {arg}", op.name()),
        InstData::Binary { op, args } => write!(s, "{} {}, {}", op.name(), args[0], args[1]),
        InstData::Icmp { cond, args } => write!(s, "icmp {} {}, {}", cond.name(), args[0], args[1]),
        InstData::Fcmp { cond, args } => write!(s, "fcmp {} {}, {}", cond.name(), args[0], args[1]),
        InstData::Convert { op, ty, arg } => write!(s, "{}.{ty} {arg}", op.name()),
        InstData::InlineC { data, .. } => write!(s, "inline_c {data}"),
        InstData::Select {
            cond,
            if_true,
            if_false,
        } => write!(s, "select {cond}, {if_true}, {if_false}"),
        InstData::GlobalAddr { data } => match m.data.get(data.index()) {
            Some(d) => write!(s, "global_addr @{}", d.name),
            None => write!(s, "global_addr {data}"),
        },
        InstData::SlotAddr { slot } => write!(s, "slot_addr {slot}"),
        InstData::FieldAddr { base, agg, field } => match m.aggs.get(agg.index()) {
            Some(crate::module::AggDef::Struct(st)) if (*field as usize) < st.fields.len() => {
                write!(
                    s,
                    "field_addr {base}, %{}.{}",
                    st.name, st.fields[*field as usize].name
                )
            }
            _ => write!(s, "field_addr {base}, {agg}.{field}"),
        },
        InstData::ElemAddr { base, agg, index } => match m.aggs.get(agg.index()) {
            Some(a) => write!(s, "elem_addr {base}, %{}, {index}", a.name()),
            None => write!(s, "elem_addr {base}, {agg}, {index}"),
        },
        InstData::Load { ty, addr } => write!(s, "load.{ty} {addr}"),
        InstData::Store { value, addr } => write!(s, "store {value}, {addr}"),
        InstData::Call { func, args } => match m.funcs.get(func.index()) {
            Some(c) => write!(s, "call @{}({})", c.name, list(args)),
            None => write!(s, "call {func}({})", list(args)),
        },
        InstData::CallTable { table, index, args } => {
            write!(s, "call_table {table}, {index}({})", list(args))
        }
        InstData::Intrinsic { op, .. } => write!(s, "{}", op.name()),
        InstData::Jump { dest } => write!(s, "jump {}", call(dest)),
        InstData::Brif {
            cond,
            then_dest,
            else_dest,
        } => write!(s, "brif {cond}, {}, {}", call(then_dest), call(else_dest)),
        InstData::BrTable {
            arg,
            default,
            table,
        } => {
            let t: Vec<String> = table.iter().map(&call).collect();
            write!(s, "br_table {arg}, {}, [{}]", call(default), t.join(", "))
        }
        InstData::Return { value: Some(v) } => write!(s, "return {v}"),
        InstData::Return { value: None } => write!(s, "return"),
    };
    if let Some(Some(sp)) = f.spans.get(i.index()) {
        let _ = write!(s, "   !{}:{}..{}", sp.file.0, sp.start, sp.end);
    }
    s
}

/// Runs function `func` with `args` (canonical registers) to completion, with an empty
/// stack, and returns its result.
pub(super) fn run(
    prog: &Prog,
    st: &mut State,
    func: usize,
    args: &[u64],
) -> Result<Option<u64>, MachineError> {
    let entry = &prog.funcs[func];
    let fname = || prog.module.funcs[func].name.clone();
    if args.len() != entry.param_types.len() {
        return Err(MachineError(format!(
            "@{} takes {} arguments, not {}",
            fname(),
            entry.param_types.len(),
            args.len()
        )));
    }
    st.frames.clear();
    st.regs.clear();
    st.regs.resize(entry.nregs as usize, 0);
    for ((&p, &a), &t) in entry.entry_params.iter().zip(args).zip(&entry.param_types) {
        st.regs[p as usize] = canon(t, a);
    }
    let (fp, sp) = alloc_frame(st, prog, prog.stack_base, entry.frame_size)
        .map_err(|m| MachineError(format!("{m} (calling @{})", fname())))?;
    let mut steps = st.steps;
    let r = exec(prog, st, func, fp, sp, &mut steps);
    st.steps = steps;
    st.frames.clear();
    st.regs.clear();
    r
}

/// The loop. `fp`/`sp` are the entry frame's; `steps` counts operations.
fn exec(
    prog: &Prog,
    st: &mut State,
    func: usize,
    mut fp: u64,
    mut sp: u64,
    steps: &mut u64,
) -> Result<Option<u64>, MachineError> {
    let limit = st.step_limit;
    let mut fi = func;
    let mut f = &prog.funcs[fi];
    let mut pc = 0usize;
    let mut base = 0usize;
    macro_rules! r {
        ($x:expr) => {
            st.regs[base + $x as usize]
        };
    }
    macro_rules! bail {
        ($msg:expr) => {
            return Err(fail(prog, fi, pc - 1, &$msg))
        };
    }
    // Enters function `callee` with the argument registers `args..args + nargs` of
    // `call_args`; its result goes to `dst` on return.
    macro_rules! call {
        ($callee:expr, $args:expr, $nargs:expr, $dst:expr) => {{
            let (callee, args, nargs, dst) = ($callee, $args, $nargs, $dst);
            if st.frames.len() + 1 >= MAX_CALL_DEPTH {
                bail!(format!(
                    "call depth limit exceeded ({MAX_CALL_DEPTH} frames)"
                ));
            }
            let g = &prog.funcs[callee as usize];
            let (nfp, nsp) = match alloc_frame(st, prog, sp, g.frame_size) {
                Ok(x) => x,
                Err(m) => bail!(m),
            };
            let nbase = st.regs.len();
            st.regs.resize(nbase + g.nregs as usize, 0);
            let a = &f.call_args[args as usize..(args + nargs) as usize];
            for (&p, &arg) in g.entry_params.iter().zip(a) {
                st.regs[nbase + p as usize] = st.regs[base + arg as usize];
            }
            st.frames.push(Frame {
                func: fi as u32,
                pc: pc as u32,
                base: base as u32,
                fp,
                sp,
                ret_dst: dst,
            });
            fi = callee as usize;
            f = g;
            pc = 0;
            base = nbase;
            fp = nfp;
            sp = nsp;
        }};
    }
    loop {
        *steps += 1;
        if *steps > limit {
            pc += 1;
            bail!(format!("step limit exceeded: the scan did not finish within {limit} operations (an endless loop?)"));
        }
        let op = f.code[pc];
        pc += 1;
        match op {
            Op::Const { dst, bits } => r!(dst) = bits,
            Op::IUnary { op, ty, dst, a } => r!(dst) = int_unary(op, ty, r!(a)),
            Op::F32Unary { op, dst, a } => r!(dst) = f32_unary(op, reg_f32(r!(a))).to_bits() as u64,
            Op::F64Unary { op, dst, a } => r!(dst) = f64_unary(op, reg_f64(r!(a))).to_bits(),
            Op::IBinary { op, ty, dst, a, b } => {
                let (x, y) = (r!(a), r!(b));
                r!(dst) = int_binary(op, ty, x, y, &mut st.fault);
            }
            Op::F32Binary { op, dst, a, b } => {
                r!(dst) = f32_binary(op, reg_f32(r!(a)), reg_f32(r!(b))).to_bits() as u64
            }
            Op::F64Binary { op, dst, a, b } => {
                r!(dst) = f64_binary(op, reg_f64(r!(a)), reg_f64(r!(b))).to_bits()
            }
            Op::Icmp { cc, ty, dst, a, b } => r!(dst) = int_cmp(cc, ty, r!(a), r!(b)) as u64,
            Op::F32Cmp { cc, dst, a, b } => {
                r!(dst) = f32_cmp(cc, reg_f32(r!(a)), reg_f32(r!(b))) as u64
            }
            Op::F64Cmp { cc, dst, a, b } => {
                r!(dst) = f64_cmp(cc, reg_f64(r!(a)), reg_f64(r!(b))) as u64
            }
            Op::Convert {
                op,
                from,
                to,
                dst,
                a,
            } => r!(dst) = convert(op, from, to, r!(a)),
            Op::Select { dst, c, t, f } => r!(dst) = if r!(c) != 0 { r!(t) } else { r!(f) },
            Op::SlotAddr { dst, off } => r!(dst) = fp + off as u64,
            Op::AddOffset { dst, base: b, off } => r!(dst) = r!(b).wrapping_add(off as u64),
            Op::ElemAddr {
                ty,
                dst,
                base: b,
                idx,
                stride,
                len,
            } => {
                let i = sval(ty, r!(idx));
                if i < 0 || i >= len as i64 {
                    bail!(format!("index {i} out of range 0..{len}"));
                }
                r!(dst) = r!(b).wrapping_add(i as u64 * stride as u64);
            }
            Op::Load { ty, dst, addr } => match st.load(ty, r!(addr), sp) {
                Ok(v) => r!(dst) = v,
                Err(m) => bail!(m),
            },
            Op::Store { ty, src, addr } => {
                let (v, a) = (r!(src), r!(addr));
                if let Err(m) = st.store(ty, a, v, sp) {
                    bail!(m);
                }
            }
            Op::CallTable {
                table,
                ty,
                idx,
                args,
                nargs,
                dst,
            } => {
                let entries = &f.tables[table as usize];
                let callee = usize::try_from(uval(ty, r!(idx)))
                    .ok()
                    .and_then(|i| entries.get(i).copied())
                    .unwrap_or(NONE);
                if callee == NONE {
                    st.fault = true;
                    if dst != NONE {
                        r!(dst) = 0;
                    }
                    continue;
                }
                call!(callee, args, nargs, dst);
            }
            Op::Call {
                func: callee,
                args,
                nargs,
                dst,
            } => call!(callee, args, nargs, dst),
            Op::ClockMs { dst } => r!(dst) = st.clock_ms as i64 as u64,
            Op::ClockNs { dst } => r!(dst) = st.clock_ns as u64,
            Op::RaiseFault => st.fault = true,
            Op::Fill { ty, ptr, src, n } => {
                let (a, v, n) = (r!(ptr), r!(src), r!(n) as i64);
                let size = scalar_size(ty);
                for k in 0..n.max(0) as u64 {
                    let at = a.wrapping_add(k.wrapping_mul(size));
                    if let Err(m) = st.store(ty, at, v, sp) {
                        bail!(m);
                    }
                }
            }
            Op::Jump { edge } => pc = take_edge(st, f, base, edge),
            Op::Brif {
                c,
                then_edge,
                else_edge,
            } => {
                let e = if r!(c) != 0 { then_edge } else { else_edge };
                pc = take_edge(st, f, base, e);
            }
            Op::BrTable {
                ty,
                idx,
                edges,
                len,
            } => {
                let k = uval(ty, r!(idx));
                let e = if k < len as u64 {
                    edges + 1 + k as u32
                } else {
                    edges
                };
                pc = take_edge(st, f, base, e);
            }
            Op::Return { val } => {
                let v = (val != NONE).then(|| r!(val));
                let Some(caller) = st.frames.pop() else {
                    return Ok(v);
                };
                st.regs.truncate(base);
                fi = caller.func as usize;
                f = &prog.funcs[fi];
                pc = caller.pc as usize;
                base = caller.base as usize;
                fp = caller.fp;
                sp = caller.sp;
                if caller.ret_dst != NONE {
                    // The decoder checked that a used result has a returned value.
                    r!(caller.ret_dst) = v.unwrap_or(0);
                }
            }
            Op::Trap { msg } => bail!(f.traps[msg as usize].clone()),
        }
    }
}

/// Follows a branch edge: assigns the block arguments as a parallel copy (all sources
/// are read before any parameter is written, so `jump b(v2, v1)` from a block whose
/// parameters are `v1, v2` swaps them) and returns the destination.
#[inline]
fn take_edge(st: &mut State, f: &DFunc, base: usize, edge: u32) -> usize {
    let e = f.edges[edge as usize];
    let moves = &f.moves[e.start as usize..(e.start + e.len) as usize];
    match moves {
        [] => {}
        [(d, s)] => st.regs[base + *d as usize] = st.regs[base + *s as usize],
        _ => {
            st.scratch.clear();
            st.scratch
                .extend(moves.iter().map(|&(_, s)| st.regs[base + s as usize]));
            for (&(d, _), &v) in moves.iter().zip(&st.scratch) {
                st.regs[base + d as usize] = v;
            }
        }
    }
    e.pc as usize
}
