//! Pre-decoding: every function becomes a flat array of compact operations whose
//! operands are register numbers (the SSA value indices), so that the execution loop
//! never looks at `InstData`, types or the layout again.
//!
//! Malformed instructions (wrong operand types, unknown entities, a block without a
//! terminator) do not make the module fail to load: each becomes a `Trap` that reports
//! the problem if, and only if, it is executed. Front ends leave unreachable junk
//! (code after `RETURN`) that later passes remove, and the oracle must not reject a
//! module for code that never runs.

use crate::entities::{Block, FuncId, Inst, Value};
use crate::function::Function;
use crate::inst::{BinaryOp, ConvOp, FloatCC, InstData, IntCC, Intrinsic, UnaryOp};
use crate::layout::Layout;
use crate::module::{AggDef, Module};
use crate::types::{MemType, Type};

/// "No register" / "no instruction": a call whose result is unused, a bare `return`.
pub(super) const NONE: u32 = u32::MAX;

/// Stack frames start at this alignment (the largest scalar alignment, rounded up).
pub(super) const FRAME_ALIGN: u64 = 16;

/// One pre-decoded operation. Register operands index the current frame's registers.
#[derive(Copy, Clone, Debug)]
pub(super) enum Op {
    /// `dst = bits` (integer constants canonical, `global_addr` resolved).
    Const { dst: u32, bits: u64 },
    /// `ineg`, `bnot`, `iabs` at the width of `ty`.
    IUnary {
        op: UnaryOp,
        ty: Type,
        dst: u32,
        a: u32,
    },
    /// A float unary operation on binary32.
    F32Unary { op: UnaryOp, dst: u32, a: u32 },
    /// A float unary operation on binary64.
    F64Unary { op: UnaryOp, dst: u32, a: u32 },
    /// An integer binary operation at the width of `ty`.
    IBinary {
        op: BinaryOp,
        ty: Type,
        dst: u32,
        a: u32,
        b: u32,
    },
    /// A float binary operation on binary32.
    F32Binary {
        op: BinaryOp,
        dst: u32,
        a: u32,
        b: u32,
    },
    /// A float binary operation on binary64.
    F64Binary {
        op: BinaryOp,
        dst: u32,
        a: u32,
        b: u32,
    },
    /// `icmp` at the width of `ty`.
    Icmp {
        cc: IntCC,
        ty: Type,
        dst: u32,
        a: u32,
        b: u32,
    },
    /// `fcmp` on binary32.
    F32Cmp {
        cc: FloatCC,
        dst: u32,
        a: u32,
        b: u32,
    },
    /// `fcmp` on binary64.
    F64Cmp {
        cc: FloatCC,
        dst: u32,
        a: u32,
        b: u32,
    },
    /// A conversion from `from` to `to`.
    Convert {
        op: ConvOp,
        from: Type,
        to: Type,
        dst: u32,
        a: u32,
    },
    /// `dst = c ? t : f`
    Select { dst: u32, c: u32, t: u32, f: u32 },
    /// `dst = frame pointer + off`
    SlotAddr { dst: u32, off: u32 },
    /// `dst = base + off` (`field_addr`)
    AddOffset { dst: u32, base: u32, off: u32 },
    /// `dst = base + index * stride`, index (of type `ty`, signed) checked against `len`.
    ElemAddr {
        ty: Type,
        dst: u32,
        base: u32,
        idx: u32,
        stride: u32,
        len: u32,
    },
    /// `dst = load.ty [addr]`
    Load { ty: Type, dst: u32, addr: u32 },
    /// `store.ty src, [addr]`
    Store { ty: Type, src: u32, addr: u32 },
    /// `fill ptr, src, n`: `n` stores of `src` (type `ty`) at consecutive elements.
    Fill {
        ty: Type,
        ptr: u32,
        src: u32,
        n: u32,
    },
    /// Call `func` with the `nargs` registers listed at `args` in `call_args`.
    Call {
        func: u32,
        args: u32,
        nargs: u32,
        dst: u32,
    },
    /// Call entry `idx` (a register of type `ty`, read unsigned) of the call table
    /// `table` of `DFunc::tables` with the `nargs` registers at `args` in `call_args`;
    /// out of range or empty: raise the fault flag and set `dst` to 0.
    CallTable {
        table: u32,
        ty: Type,
        idx: u32,
        args: u32,
        nargs: u32,
        dst: u32,
    },
    /// `dst = clock_ms`
    ClockMs { dst: u32 },
    /// `dst = clock_ns`
    ClockNs { dst: u32 },
    /// Sets the fault flag.
    RaiseFault,
    /// Follows edge `edge`.
    Jump { edge: u32 },
    /// Follows `then_edge` if `c` is 1, else `else_edge`.
    Brif {
        c: u32,
        then_edge: u32,
        else_edge: u32,
    },
    /// Follows edge `edges + 1 + idx` if `idx` (a register of type `ty`, read
    /// unsigned) is below `len`, else edge `edges` (the default): the table's edges are
    /// consecutive, the default's first.
    BrTable {
        ty: Type,
        idx: u32,
        edges: u32,
        len: u32,
    },
    /// Returns `val` (or nothing when `NONE`).
    Return { val: u32 },
    /// Fails with message `msg` of `traps`.
    Trap { msg: u32 },
}

/// A branch edge: where it goes and which parallel copies it does.
#[derive(Copy, Clone, Debug)]
pub(super) struct Edge {
    /// The first operation of the destination block.
    pub pc: u32,
    /// First `(dst, src)` pair in `moves`.
    pub start: u32,
    /// Number of pairs.
    pub len: u32,
}

/// A function ready to run.
#[derive(Debug)]
pub(super) struct DFunc {
    /// The operations; execution starts at 0 (the entry block).
    pub code: Vec<Op>,
    /// The IR instruction each operation came from (`NONE` for synthesised traps), for
    /// error messages.
    pub origin: Vec<u32>,
    /// Registers of a frame: one per SSA value, plus a discard register.
    pub nregs: u32,
    /// The registers of the entry block's parameters.
    pub entry_params: Vec<u32>,
    /// The signature's parameter types (arguments are checked against them).
    pub param_types: Vec<Type>,
    /// Bytes of stack slots per call.
    pub frame_size: u64,
    /// Argument registers of every call, concatenated.
    pub call_args: Vec<u32>,
    /// The entries of the tables `call_table` operations call: function indexes,
    /// `NONE` for an empty entry.
    pub tables: Vec<Vec<u32>>,
    /// Branch edges.
    pub edges: Vec<Edge>,
    /// `(dst, src)` register pairs of the edges, concatenated.
    pub moves: Vec<(u32, u32)>,
    /// Messages of `Trap` operations.
    pub traps: Vec<String>,
}

/// True if `t` names only aggregates that exist.
pub(super) fn mem_type_ok(module: &Module, t: MemType) -> bool {
    match t {
        MemType::Scalar(_) => true,
        MemType::Agg(a) => a.index() < module.aggs.len(),
    }
}

fn align_up(x: u64, a: u64) -> u64 {
    x.div_ceil(a.max(1)) * a.max(1)
}

/// The register form of `bits` as a value of type `ty` (the canonical form registers
/// always hold: integers sign-extended from their width, `i1` 0 or 1, `f32` in the low
/// 32 bits).
pub(super) fn canon(ty: Type, bits: u64) -> u64 {
    match ty {
        Type::F32 => bits & 0xFFFF_FFFF,
        Type::F64 | Type::Ptr => bits,
        _ => ty.canon_int(bits as i64) as u64,
    }
}

/// Decodes function `fid` of `module`.
pub(super) fn decode(module: &Module, layout: &Layout, data_addr: &[u64], fid: FuncId) -> DFunc {
    let f = module.func(fid);
    let mut d = DFunc {
        code: Vec::new(),
        origin: Vec::new(),
        nregs: f.values.len() as u32 + 1,
        entry_params: Vec::new(),
        param_types: f.params.clone(),
        frame_size: 0,
        call_args: Vec::new(),
        tables: Vec::new(),
        edges: Vec::new(),
        moves: Vec::new(),
        traps: Vec::new(),
    };

    // Stack slots: offsets within the frame, natural alignment.
    let mut slot_off = Vec::with_capacity(f.slots.len());
    let mut off = 0u64;
    for s in &f.slots {
        if mem_type_ok(module, s.ty) {
            off = align_up(off, layout.align_of(s.ty) as u64);
            slot_off.push(Some(off));
            off += layout.size_of(s.ty) as u64;
        } else {
            slot_off.push(None);
        }
    }
    d.frame_size = off;

    let Some(entry) = f.entry() else {
        trap(&mut d, NONE, format!("function @{} has no body", f.name));
        return d;
    };
    let entry_ok = entry.index() < f.blocks.len() && {
        let params = &f.blocks[entry.index()].params;
        params.len() == f.params.len()
            && params
                .iter()
                .zip(&f.params)
                .all(|(v, t)| v.index() < f.values.len() && f.value_type(*v) == *t)
    };
    if !entry_ok {
        trap(
            &mut d,
            NONE,
            format!(
                "the entry block of @{} does not match its signature",
                f.name
            ),
        );
        return d;
    }
    d.entry_params = f.blocks[entry.index()].params.iter().map(|v| v.0).collect();

    // First pass: where every block of the layout starts. A block listed twice is
    // emitted once; a block whose last instruction is not a terminator gets a trap.
    let mut block_pc = vec![NONE; f.blocks.len()];
    let mut order = Vec::with_capacity(f.layout.len());
    let mut pc = 0u32;
    for &b in &f.layout {
        if b.index() >= f.blocks.len() || block_pc[b.index()] != NONE {
            continue;
        }
        block_pc[b.index()] = pc;
        order.push(b);
        pc += f.blocks[b.index()].insts.len() as u32;
        if !ends_in_terminator(f, b) {
            pc += 1;
        }
    }

    let mut dec = Decoder {
        module,
        layout,
        data_addr,
        f,
        block_pc: &block_pc,
        slot_off: &slot_off,
        d: &mut d,
    };
    for b in order {
        for &i in &f.blocks[b.index()].insts {
            let op = if i.index() < f.insts.len() {
                dec.inst(i)
            } else {
                Err(format!("{i} does not exist"))
            };
            match op {
                Ok(op) => {
                    dec.d.code.push(op);
                    dec.d.origin.push(i.0);
                }
                Err(msg) => trap(dec.d, i.0, msg),
            }
        }
        if !ends_in_terminator(f, b) {
            let origin = f.blocks[b.index()].insts.last().map_or(NONE, |i| i.0);
            trap(dec.d, origin, format!("{b} ends without a terminator"));
        }
    }
    debug_assert_eq!(d.code.len() as u32, pc);
    d
}

fn ends_in_terminator(f: &Function, b: Block) -> bool {
    f.blocks[b.index()]
        .insts
        .last()
        .and_then(|i| f.insts.get(i.index()))
        .is_some_and(InstData::is_terminator)
}

fn trap(d: &mut DFunc, origin: u32, msg: String) {
    d.traps.push(msg);
    d.code.push(Op::Trap {
        msg: d.traps.len() as u32 - 1,
    });
    d.origin.push(origin);
}

struct Decoder<'a> {
    module: &'a Module,
    layout: &'a Layout,
    data_addr: &'a [u64],
    f: &'a Function,
    block_pc: &'a [u32],
    slot_off: &'a [Option<u64>],
    d: &'a mut DFunc,
}

type R<T> = Result<T, String>;

impl Decoder<'_> {
    fn ty(&self, v: Value) -> Type {
        self.f.value_type(v)
    }

    /// Fails unless the values have the types of one class (`what` names it).
    fn want(&self, ok: bool, what: &str) -> R<()> {
        if ok {
            Ok(())
        } else {
            Err(format!("operands must be {what}"))
        }
    }

    fn inst(&mut self, i: Inst) -> R<Op> {
        let f = self.f;
        let data = &f.insts[i.index()];
        let mut bad = None;
        data.for_each_arg(|v| {
            if v.index() >= f.values.len() && bad.is_none() {
                bad = Some(v);
            }
        });
        if let Some(v) = bad {
            return Err(format!("{v} is not a value of @{}", f.name));
        }
        // The declared result must be what the instruction produces.
        let expected = f.result_type_of(self.module, data);
        let res = f.results.get(i.index()).copied().flatten();
        let dst = match (res, expected) {
            (Some(v), Some(t)) => {
                if v.index() >= f.values.len() {
                    return Err(format!("{v} is not a value of @{}", f.name));
                }
                if self.ty(v) != t {
                    return Err(format!(
                        "result {v} is {} but the instruction gives {t}",
                        self.ty(v)
                    ));
                }
                v.0
            }
            (Some(v), None) => return Err(format!("result {v} of an instruction that gives none")),
            (None, Some(_)) => self.d.nregs - 1,
            (None, None) => NONE,
        };
        Ok(match *data {
            InstData::Iconst { ty, imm } => {
                self.want(
                    ty.is_int() || (ty == Type::Ptr && imm == 0),
                    "an integer type for iconst (or 0 of ptr)",
                )?;
                Op::Const {
                    dst,
                    bits: canon(ty, imm as u64),
                }
            }
            InstData::SizeOf { ty, of } => {
                self.want(ty.is_int() && ty != Type::I1, "an integer type for sizeof")?;
                if let MemType::Agg(a) = of {
                    self.want(
                        a.index() < self.module.aggs.len(),
                        "an aggregate that exists",
                    )?;
                }
                Op::Const {
                    dst,
                    bits: canon(ty, self.layout.size_of(of) as u64),
                }
            }
            InstData::Fconst { ty, bits } => {
                self.want(ty.is_float(), "a float type for fconst")?;
                Op::Const {
                    dst,
                    bits: canon(ty, bits),
                }
            }
            InstData::Unary { op, arg } => {
                let ty = self.ty(arg);
                if op.is_int_op() {
                    self.want(ty.is_int(), "integers")?;
                    Op::IUnary {
                        op,
                        ty,
                        dst,
                        a: arg.0,
                    }
                } else {
                    match ty {
                        Type::F32 => Op::F32Unary { op, dst, a: arg.0 },
                        Type::F64 => Op::F64Unary { op, dst, a: arg.0 },
                        _ => return Err("operand must be a float".into()),
                    }
                }
            }
            InstData::Binary { op, args: [a, b] } => {
                let ty = self.ty(a);
                self.want(self.ty(b) == ty, "of one type")?;
                if op.is_int_op() {
                    self.want(ty.is_int() || ty == Type::Ptr, "integers")?;
                    Op::IBinary {
                        op,
                        ty,
                        dst,
                        a: a.0,
                        b: b.0,
                    }
                } else {
                    match ty {
                        Type::F32 => Op::F32Binary {
                            op,
                            dst,
                            a: a.0,
                            b: b.0,
                        },
                        Type::F64 => Op::F64Binary {
                            op,
                            dst,
                            a: a.0,
                            b: b.0,
                        },
                        _ => return Err("operands must be floats".into()),
                    }
                }
            }
            InstData::Icmp { cond, args: [a, b] } => {
                let ty = self.ty(a);
                self.want(
                    self.ty(b) == ty && (ty.is_int() || ty == Type::Ptr),
                    "integers or pointers of one type",
                )?;
                Op::Icmp {
                    cc: cond,
                    ty,
                    dst,
                    a: a.0,
                    b: b.0,
                }
            }
            InstData::Fcmp { cond, args: [a, b] } => {
                let ty = self.ty(a);
                self.want(self.ty(b) == ty, "of one type")?;
                match ty {
                    Type::F32 => Op::F32Cmp {
                        cc: cond,
                        dst,
                        a: a.0,
                        b: b.0,
                    },
                    Type::F64 => Op::F64Cmp {
                        cc: cond,
                        dst,
                        a: a.0,
                        b: b.0,
                    },
                    _ => return Err("operands must be floats".into()),
                }
            }
            InstData::Convert { op, ty, arg } => {
                let from = self.ty(arg);
                let ok = match op {
                    ConvOp::Sext | ConvOp::Uext => {
                        from.is_int() && ty.is_int() && ty.bits() >= from.bits()
                    }
                    ConvOp::Itrunc => from.is_int() && ty.is_int() && ty.bits() <= from.bits(),
                    ConvOp::Fpromote => from == Type::F32 && ty == Type::F64,
                    ConvOp::Fdemote => from == Type::F64 && ty == Type::F32,
                    ConvOp::SiToF | ConvOp::UiToF => from.is_int() && ty.is_float(),
                    ConvOp::FToSi | ConvOp::FToUi => from.is_float() && ty.is_int(),
                    ConvOp::Bitcast => from.bits() == ty.bits() && from != Type::I1,
                    ConvOp::PtrToInt => from == Type::Ptr && ty.is_int() && ty != Type::I1,
                    ConvOp::IntToPtr => from.is_int() && from != Type::I1 && ty == Type::Ptr,
                };
                if !ok {
                    return Err(format!("cannot {} {from} to {ty}", op.name()));
                }
                Op::Convert {
                    op,
                    from,
                    to: ty,
                    dst,
                    a: arg.0,
                }
            }
            InstData::Select {
                cond,
                if_true,
                if_false,
            } => {
                self.want(self.ty(cond) == Type::I1, "an i1 condition")?;
                self.want(self.ty(if_true) == self.ty(if_false), "of one type")?;
                Op::Select {
                    dst,
                    c: cond.0,
                    t: if_true.0,
                    f: if_false.0,
                }
            }
            InstData::GlobalAddr { data } => match self.data_addr.get(data.index()) {
                Some(&a) => Op::Const { dst, bits: a },
                None => return Err(format!("{data} does not exist")),
            },
            InstData::SlotAddr { slot } => match self.slot_off.get(slot.index()) {
                Some(Some(off)) => Op::SlotAddr {
                    dst,
                    off: u32::try_from(*off).map_err(|_| "the frame is too large".to_string())?,
                },
                Some(None) => return Err(format!("{slot} has an unknown type")),
                None => return Err(format!("{slot} does not exist")),
            },
            InstData::FieldAddr { base, agg, field } => {
                self.want(self.ty(base) == Type::Ptr, "a pointer base")?;
                match self.module.aggs.get(agg.index()) {
                    Some(AggDef::Struct(s)) if (field as usize) < s.fields.len() => Op::AddOffset {
                        dst,
                        base: base.0,
                        off: self.layout.field_offset(agg, field),
                    },
                    Some(AggDef::Struct(_)) => return Err(format!("{agg} has no field {field}")),
                    _ => return Err(format!("{agg} is not a struct")),
                }
            }
            InstData::ElemAddr { base, agg, index } => {
                self.want(self.ty(base) == Type::Ptr, "a pointer base")?;
                self.want(self.ty(index).is_int(), "an integer index")?;
                match self.module.aggs.get(agg.index()) {
                    Some(AggDef::Array(a)) => Op::ElemAddr {
                        ty: self.ty(index),
                        dst,
                        base: base.0,
                        idx: index.0,
                        stride: self.layout.stride(agg),
                        len: a.len,
                    },
                    _ => return Err(format!("{agg} is not an array")),
                }
            }
            InstData::Load { ty, addr } => {
                self.want(self.ty(addr) == Type::Ptr, "a pointer address")?;
                Op::Load {
                    ty,
                    dst,
                    addr: addr.0,
                }
            }
            InstData::Store { value, addr } => {
                self.want(self.ty(addr) == Type::Ptr, "a pointer address")?;
                Op::Store {
                    ty: self.ty(value),
                    src: value.0,
                    addr: addr.0,
                }
            }
            InstData::Call { func, ref args } => {
                let Some(callee) = self.module.funcs.get(func.index()) else {
                    return Err(format!("{func} does not exist"));
                };
                if args.len() != callee.params.len()
                    || args
                        .iter()
                        .zip(&callee.params)
                        .any(|(v, t)| self.ty(*v) != *t)
                {
                    return Err(format!(
                        "arguments do not match the signature of @{}",
                        callee.name
                    ));
                }
                let start = self.d.call_args.len() as u32;
                self.d.call_args.extend(args.iter().map(|v| v.0));
                Op::Call {
                    func: func.0,
                    args: start,
                    nargs: args.len() as u32,
                    dst,
                }
            }
            InstData::InlineC { .. } => {
                return Err(
                    "inline C code (a pragma kept for the c target) cannot run on the interpreter"
                        .to_string(),
                )
            }
            InstData::CallTable {
                table,
                index,
                ref args,
            } => {
                let Some(tab) = self.module.tables.get(table.index()) else {
                    return Err(format!("{table} does not exist"));
                };
                let ty = self.ty(index);
                self.want(ty.is_int() && ty != Type::I1, "an integer index")?;
                if args.len() != tab.params.len()
                    || args.iter().zip(&tab.params).any(|(v, t)| self.ty(*v) != *t)
                {
                    return Err(format!("arguments do not match the signature of {table}"));
                }
                let mut entries = Vec::with_capacity(tab.entries.len());
                for e in &tab.entries {
                    match *e {
                        None => entries.push(NONE),
                        Some(fid) => match self.module.funcs.get(fid.index()) {
                            Some(g) if g.params == tab.params && g.ret == tab.result => {
                                entries.push(fid.0)
                            }
                            Some(g) => {
                                return Err(format!(
                                    "@{} does not have the signature of {table}",
                                    g.name
                                ))
                            }
                            None => return Err(format!("{fid} of {table} does not exist")),
                        },
                    }
                }
                self.d.tables.push(entries);
                let start = self.d.call_args.len() as u32;
                self.d.call_args.extend(args.iter().map(|v| v.0));
                Op::CallTable {
                    table: self.d.tables.len() as u32 - 1,
                    ty,
                    idx: index.0,
                    args: start,
                    nargs: args.len() as u32,
                    dst,
                }
            }
            InstData::Intrinsic { op, ref args } => {
                if args.len() != op.operands() {
                    return Err(format!("{} takes {} operands", op.name(), op.operands()));
                }
                match op {
                    Intrinsic::Fill => {
                        self.want(self.ty(args[0]) == Type::Ptr, "a pointer address")?;
                        self.want(self.ty(args[2]) == Type::I64, "an i64 count")?;
                        Op::Fill {
                            ty: self.ty(args[1]),
                            ptr: args[0].0,
                            src: args[1].0,
                            n: args[2].0,
                        }
                    }
                    Intrinsic::ClockMs => Op::ClockMs { dst },
                    Intrinsic::ClockNs => Op::ClockNs { dst },
                    Intrinsic::RaiseFault => Op::RaiseFault,
                    // The interpreter's watchdog is its step limit, which stops a
                    // scan wherever it is; loops never need to be asked.
                    Intrinsic::StopRequested => Op::Const { dst, bits: 0 },
                }
            }
            InstData::Jump { ref dest } => Op::Jump {
                edge: self.edge(&dest.block, &dest.args)?,
            },
            InstData::Brif {
                cond,
                ref then_dest,
                ref else_dest,
            } => {
                self.want(self.ty(cond) == Type::I1, "an i1 condition")?;
                Op::Brif {
                    c: cond.0,
                    then_edge: self.edge(&then_dest.block, &then_dest.args)?,
                    else_edge: self.edge(&else_dest.block, &else_dest.args)?,
                }
            }
            InstData::BrTable {
                arg,
                ref default,
                ref table,
            } => {
                let ty = self.ty(arg);
                self.want(
                    matches!(ty, Type::I8 | Type::I16 | Type::I32 | Type::I64),
                    "an integer index (i8..i64)",
                )?;
                let len =
                    u32::try_from(table.len()).map_err(|_| "a jump table too long".to_string())?;
                // `edge` pushes one edge each, so the table's follow the default's.
                let edges = self.edge(&default.block, &default.args)?;
                for d in table {
                    self.edge(&d.block, &d.args)?;
                }
                Op::BrTable {
                    ty,
                    idx: arg.0,
                    edges,
                    len,
                }
            }
            InstData::Return { value } => match (value, f.ret) {
                (None, None) => Op::Return { val: NONE },
                (Some(v), Some(t)) if self.ty(v) == t => Op::Return { val: v.0 },
                _ => {
                    return Err(format!(
                        "the returned value does not match the signature of @{}",
                        f.name
                    ))
                }
            },
        })
    }

    fn edge(&mut self, block: &Block, args: &[Value]) -> R<u32> {
        let pc = self.block_pc.get(block.index()).copied().unwrap_or(NONE);
        if pc == NONE {
            return Err(format!("{block} is not in the layout"));
        }
        let params = &self.f.blocks[block.index()].params;
        if params.len() != args.len()
            || params
                .iter()
                .zip(args)
                .any(|(p, a)| p.index() >= self.f.values.len() || self.ty(*p) != self.ty(*a))
        {
            return Err(format!(
                "the arguments do not match the parameters of {block}"
            ));
        }
        let start = self.d.moves.len() as u32;
        self.d
            .moves
            .extend(params.iter().zip(args).map(|(p, a)| (p.0, a.0)));
        self.d.edges.push(Edge {
            pc,
            start,
            len: args.len() as u32,
        });
        Ok(self.d.edges.len() as u32 - 1)
    }
}
