//! Instruction selection: one IR function to PIC16 code.
//!
//! Every value lives in RAM (its home in the function's static frame) or is a
//! constant or a known address; W and the STATUS flags carry values only inside the
//! code of one IR instruction (and from a compare to the branch right after it).
//! Multi-byte arithmetic is expanded inline, little-endian, with the carry idioms of
//! the mid-range core; multiply and divide call the runtime helpers.
//!
//! Bank rule: the instruction a skip may skip either touches no banked register or
//! the same bank as the skip. Where two operands could sit in different banks, one is
//! staged through common RAM first (see `Emitter::reg_for`).
//!
//! This module holds the emitter, the places of values and the copies; the code of
//! the instructions is in `arith`, `compare` (with conversions and selects),
//! `memory` (loads and stores) and `flow` (calls, edge copies, branches).

mod arith;
mod compare;
mod flow;
mod memory;

use crate::asm::{Item, Label, Op};
use crate::frame::{FrameInfo, Ptr, Repr, Sym};
use crate::helpers::{HelperSet, Workspace};
use crate::isa::{bank_of, reg, Dest, Inst};
use crate::ram::{scalar_bytes, PicLayout};
use crate::runtime::Rt;
use plcc_ir::diag::Diagnostic;
use plcc_ir::function::Function;
use plcc_ir::inst::{BinaryOp, BlockCall, ConvOp, InstData, IntCC, Intrinsic, UnaryOp};
use plcc_ir::{Block, FuncId, Module, Type, Value};

/// The verifier gives every value-producing instruction a result.
const HAS_RESULT: &str = "the instruction has a result";

/// Addresses of everything placed in RAM, for turning symbols into numbers.
pub struct Placement<'a> {
    /// The module.
    pub module: &'a Module,
    /// Layout of aggregates.
    pub layout: &'a PicLayout,
    /// Where each data object is.
    pub data: crate::ram::DataMap,
    /// Base address of each function's frame.
    pub frame_base: Vec<u16>,
    /// Each function's frame.
    pub frames: &'a [FrameInfo],
    /// Entry label of each function.
    pub func_label: Vec<Label>,
    /// Runtime addresses.
    pub rt: Rt,
    /// The helpers' workspace.
    pub ws: Workspace,
}

impl Placement<'_> {
    /// The numeric value of a known pointer: address, plus the bit number in bits
    /// 9–11 (the PIC16 pointer format).
    pub fn ptr_value(&self, s: Sym, off: u16, bit: u8) -> u16 {
        let a = match s {
            Sym::Data(d) => self.data.addr(d, off),
            Sym::Slot(f, slot) => {
                self.frame_base[f.index()] + self.frames[f.index()].slot_offsets[slot.index()] + off
            }
        };
        a | (bit as u16) << 9
    }
}

/// A multi-byte operand.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
enum Loc {
    /// A constant (the bytes of its two's complement).
    Lit(u64),
    /// Bytes in RAM from this address.
    Mem(u16),
    /// A pointer `base + add`, where `base` is a pointer in RAM.
    Derived(u16, u16),
}

/// A one-bit operand: a constant, or a bit in RAM that holds the value (or, when
/// the flag is set, its negation).
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
enum BitLoc {
    Lit(bool),
    Bit(u16, u8, bool),
}

impl BitLoc {
    /// The skip that skips the next instruction when the operand is TRUE.
    fn skip_if_true(self) -> Inst {
        match self {
            BitLoc::Bit(a, b, false) => Inst::Btfss(a, b),
            BitLoc::Bit(a, b, true) => Inst::Btfsc(a, b),
            BitLoc::Lit(_) => unreachable!("constants need no test"),
        }
    }

    /// The skip that skips the next instruction when the operand is FALSE.
    fn skip_if_false(self) -> Inst {
        match self {
            BitLoc::Bit(a, b, false) => Inst::Btfsc(a, b),
            BitLoc::Bit(a, b, true) => Inst::Btfss(a, b),
            BitLoc::Lit(_) => unreachable!("constants need no test"),
        }
    }

    fn not(self) -> BitLoc {
        match self {
            BitLoc::Lit(b) => BitLoc::Lit(!b),
            BitLoc::Bit(a, b, n) => BitLoc::Bit(a, b, !n),
        }
    }
}

/// One byte of an operand.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
enum Src {
    Lit(u8),
    Reg(u16),
    /// `register + constant` (a byte of a derived pointer).
    Add(u16, u8),
}

/// Which STATUS bit holds a condition, and its sense.
#[derive(Copy, Clone, Debug)]
struct FlagCond {
    bit: u8,
    /// The condition is true when the bit is set.
    when_set: bool,
}

/// Common-RAM scratch bytes instruction selection may use within one IR instruction.
pub const SCRATCH: [u16; 6] = [0x71, 0x72, 0x73, 0x74, 0x75, 0x76];

/// Emits the code of one function.
pub struct Emitter<'a> {
    p: &'a Placement<'a>,
    f: &'a Function,
    frame: &'a FrameInfo,
    base: u16,
    /// The code so far.
    pub items: Vec<Item>,
    /// Labels created (name, id); the caller registers them.
    pub labels: &'a mut Vec<String>,
    block_labels: Vec<Option<Label>>,
    /// Helpers this function uses.
    pub helpers: &'a mut HelperSet,
    /// Errors found (unsupported operations).
    pub diags: Vec<Diagnostic>,
    prefix: String,
    last_line: Option<(u32, u32)>,
    sources: &'a [Option<String>],
}

impl<'a> Emitter<'a> {
    /// An emitter for `fid`, whose labels start with `prefix`.
    pub fn new(
        p: &'a Placement<'a>,
        fid: FuncId,
        labels: &'a mut Vec<String>,
        helpers: &'a mut HelperSet,
        prefix: String,
        sources: &'a [Option<String>],
    ) -> Emitter<'a> {
        let f = &p.module.funcs[fid.index()];
        Emitter {
            p,
            f,
            frame: &p.frames[fid.index()],
            base: p.frame_base[fid.index()],
            items: Vec::new(),
            labels,
            block_labels: vec![None; f.blocks.len()],
            helpers,
            diags: Vec::new(),
            prefix,
            last_line: None,
            sources,
        }
    }

    fn new_label(&mut self, hint: &str) -> Label {
        self.labels
            .push(format!("{}_{}{}", self.prefix, hint, self.labels.len()));
        Label(self.labels.len() as u32 - 1)
    }

    fn block_label(&mut self, b: Block) -> Label {
        if let Some(l) = self.block_labels[b.index()] {
            return l;
        }
        self.labels.push(format!("{}_b{}", self.prefix, b.index()));
        let l = Label(self.labels.len() as u32 - 1);
        self.block_labels[b.index()] = Some(l);
        l
    }

    fn i(&mut self, inst: Inst) {
        self.items.push(Item::Op(Op::I(inst)));
    }

    fn goto(&mut self, l: Label) {
        self.items.push(Item::Op(Op::Goto(l)));
    }

    fn label(&mut self, l: Label) {
        self.items.push(Item::Label(l));
    }

    /// Emits the whole function.
    pub fn run(mut self, entry: Label) -> (Vec<Item>, Vec<Diagnostic>) {
        self.label(entry);
        let layout = self.f.layout.clone();
        for (bi, &b) in layout.iter().enumerate() {
            let l = self.block_label(b);
            self.label(l);
            let next = layout.get(bi + 1).copied();
            for &inst in &self.f.block(b).insts {
                self.source_comment(inst);
                self.inst(inst, next);
            }
        }
        (self.items, self.diags)
    }

    fn source_comment(&mut self, inst: plcc_ir::Inst) {
        let Some(span) = self.f.spans.get(inst.index()).copied().flatten() else {
            return;
        };
        let Some(Some(src)) = self.sources.get(span.file.0 as usize) else {
            return;
        };
        let start = (span.start as usize).min(src.len());
        let line_no = src[..start].matches('\n').count() as u32 + 1;
        if self.last_line == Some((span.file.0 as usize as u32, line_no)) {
            return;
        }
        self.last_line = Some((span.file.0 as usize as u32, line_no));
        let ls = src[..start].rfind('\n').map(|i| i + 1).unwrap_or(0);
        let le = src[start..]
            .find('\n')
            .map(|i| start + i)
            .unwrap_or(src.len());
        let text = src[ls..le].trim();
        if !text.is_empty() {
            self.items.push(Item::Comment(format!("{line_no}: {text}")));
        }
    }

    fn unsupported(&mut self, inst: plcc_ir::Inst, what: &str) {
        let msg = format!("{what} is not supported on pic16f876a");
        let d = match self.f.spans.get(inst.index()).copied().flatten() {
            Some(s) => Diagnostic::error(crate::codes::E_UNSUPPORTED, msg, s),
            None => Diagnostic::error_nowhere(crate::codes::E_UNSUPPORTED, msg),
        };
        self.diags.push(d);
    }

    // ---- operands -------------------------------------------------------------

    fn ty(&self, v: Value) -> Type {
        self.f.value_type(v)
    }

    fn loc(&self, v: Value) -> Loc {
        match self.frame.repr[v.index()] {
            Repr::Const(k) => Loc::Lit(k as u64),
            Repr::Ptr(Ptr::Known(s, o, b)) => Loc::Lit(self.p.ptr_value(s, o, b) as u64),
            Repr::Ptr(Ptr::Derived(base, o, b)) => {
                let Loc::Mem(a) = self.loc(base) else {
                    // A derived pointer from a constant base is itself known.
                    unreachable!("derived pointer without a RAM base")
                };
                Loc::Derived(a, o | (b.unwrap_or(0) as u16) << 9)
            }
            Repr::Bytes(o) => Loc::Mem(self.base + o),
            Repr::Mem(s, o, _) => Loc::Mem(self.p.ptr_value(s, o, 0)),
            Repr::Bit(..) | Repr::Flags | Repr::Unused | Repr::NotOf(_) => Loc::Mem(self.base),
        }
    }

    fn bit(&self, v: Value) -> BitLoc {
        match self.frame.repr[v.index()] {
            Repr::Const(k) => BitLoc::Lit(k & 1 != 0),
            Repr::Bit(o, b) => BitLoc::Bit(self.base + o, b, false),
            Repr::Mem(s, o, b) => BitLoc::Bit(self.p.ptr_value(s, o, 0), b, false),
            Repr::NotOf(x) => self.bit(x).not(),
            _ => BitLoc::Lit(false),
        }
    }

    fn home(&self, v: Value) -> Option<u16> {
        match self.frame.repr[v.index()] {
            Repr::Bytes(o) => Some(self.base + o),
            Repr::Mem(s, o, _) => Some(self.p.ptr_value(s, o, 0)),
            _ => None,
        }
    }

    fn home_bit(&self, v: Value) -> Option<(u16, u8)> {
        match self.frame.repr[v.index()] {
            Repr::Bit(o, b) => Some((self.base + o, b)),
            Repr::Mem(s, o, b) => Some((self.p.ptr_value(s, o, 0), b)),
            _ => None,
        }
    }

    fn byte(loc: Loc, i: u16) -> Src {
        match loc {
            Loc::Lit(k) => Src::Lit((k >> (8 * i)) as u8),
            Loc::Mem(a) => Src::Reg(a + i),
            Loc::Derived(a, add) => Src::Add(a + i, (add >> (8 * i)) as u8),
        }
    }

    fn load_w(&mut self, s: Src) {
        match s {
            Src::Lit(k) => self.i(Inst::Movlw(k)),
            Src::Reg(r) => self.i(Inst::Movf(r, Dest::W)),
            Src::Add(r, k) => {
                self.i(Inst::Movf(r, Dest::W));
                if k != 0 {
                    self.i(Inst::Addlw(k));
                }
            }
        }
    }

    /// A register holding `s`: `s` itself, or scratch `t` loaded with it. If `near`
    /// is given, the register must be bank-compatible with it (for skip pairs).
    fn reg_for(&mut self, s: Src, t: u16, near: Option<u16>) -> u16 {
        if let Src::Reg(r) = s {
            let ok = match (near.and_then(bank_of), bank_of(r)) {
                (Some(a), Some(b)) => a == b,
                _ => true,
            };
            if ok {
                return r;
            }
        }
        self.load_w(s);
        self.i(Inst::Movwf(t));
        t
    }

    fn copy_bytes(&mut self, dst: u16, src: Loc, n: u16) {
        // Overlapping ranges (a block parameter placed over part of its argument)
        // copy from the end that is not overwritten first.
        let downward = matches!(src, Loc::Mem(a) | Loc::Derived(a, _) if dst > a && dst < a + n);
        let order: Vec<u16> = if downward {
            (0..n).rev().collect()
        } else {
            (0..n).collect()
        };
        for i in order {
            let s = Self::byte(src, i);
            if s == Src::Reg(dst + i) {
                continue;
            }
            match s {
                Src::Lit(0) => self.i(Inst::Clrf(dst + i)),
                _ => {
                    self.load_w(s);
                    self.i(Inst::Movwf(dst + i));
                }
            }
        }
    }

    /// `dst := src` (or its negation) for bits.
    fn copy_bit(&mut self, dst: (u16, u8), src: BitLoc, invert: bool) {
        match src {
            BitLoc::Lit(b) => {
                if b != invert {
                    self.i(Inst::Bsf(dst.0, dst.1))
                } else {
                    self.i(Inst::Bcf(dst.0, dst.1))
                }
            }
            BitLoc::Bit(a, b, neg) => {
                let invert = invert != neg;
                if (a, b) == dst && !invert {
                    return;
                }
                let test = if invert {
                    Inst::Btfss(a, b)
                } else {
                    Inst::Btfsc(a, b)
                };
                if (a, b) == dst {
                    // Invert in place.
                    self.i(Inst::Movlw(1 << b));
                    self.i(Inst::Xorwf(a, Dest::F));
                    return;
                }
                if dst.0 == reg::INDF || a == reg::INDF {
                    // Through a pointer the two may be the same bit (`p^ := r` with
                    // `p = REF(r)`): the source is read before the destination
                    // changes.
                    if invert {
                        self.i(Inst::Movlw(0));
                        self.skip_then(Inst::Btfss(a, b), Inst::Movlw(1));
                        self.i(Inst::Bcf(dst.0, dst.1));
                        self.i(Inst::Iorlw(0));
                        self.skip_then(Inst::Btfss(reg::STATUS, reg::Z), Inst::Bsf(dst.0, dst.1));
                    } else {
                        self.skip_then(Inst::Btfsc(a, b), Inst::Bsf(dst.0, dst.1));
                        self.skip_then(Inst::Btfss(a, b), Inst::Bcf(dst.0, dst.1));
                    }
                    return;
                }
                self.i(Inst::Bcf(dst.0, dst.1));
                self.skip_then(test, Inst::Bsf(dst.0, dst.1));
            }
        }
    }

    /// Emits `skip; then`, moving the test to the Z flag when the two would need
    /// different banks. `then` must not read W.
    fn skip_then(&mut self, skip: Inst, then: Inst) {
        let conflict = match (skip.file().and_then(bank_of), then.file().and_then(bank_of)) {
            (Some(a), Some(b)) => a != b,
            _ => false,
        };
        if !conflict {
            self.i(skip);
            self.i(then);
            return;
        }
        match skip {
            Inst::Btfsc(f, b) | Inst::Btfss(f, b) => {
                self.i(Inst::Movf(f, Dest::W));
                self.i(Inst::Andlw(1 << b));
                // Z is set when the bit is clear.
                if matches!(skip, Inst::Btfsc(..)) {
                    self.i(Inst::Btfss(reg::STATUS, reg::Z));
                } else {
                    self.i(Inst::Btfsc(reg::STATUS, reg::Z));
                }
                self.i(then);
            }
            _ => unreachable!("only bit tests are staged"),
        }
    }

    fn bytes(&self, t: Type) -> u16 {
        scalar_bytes(t) as u16
    }

    // ---- instructions ------------------------------------------------------------

    fn inst(&mut self, inst: plcc_ir::Inst, next: Option<Block>) {
        let data = self.f.inst(inst).clone();
        let res = self.f.result(inst);
        if let Some(r) = res {
            if matches!(self.frame.repr[r.index()], Repr::Unused) && !data.has_side_effects() {
                return;
            }
        }
        match data {
            InstData::CallTable { .. } => {
                // `build` lowered every one to direct calls (passes::dispatch).
                self.unsupported(inst, "a call bound at run time left after its lowering")
            }
            InstData::Iconst { .. }
            | InstData::GlobalAddr { .. }
            | InstData::SlotAddr { .. }
            | InstData::Fconst { .. } => {}
            InstData::FieldAddr { base, agg, field } => {
                if let Some(d) = res.and_then(|r| self.home(r)) {
                    // Only when the result needed a home (a derived pointer used as a value).
                    let p = self.p.layout.agg(agg).fields[field as usize];
                    self.add_ptr(d, self.loc(base), p.offset | (p.bit as u16) << 9);
                }
            }
            InstData::ElemAddr { base, agg, index } => {
                if let Some(d) = res.and_then(|r| self.home(r)) {
                    let stride = self.p.layout.agg(agg).stride;
                    self.elem_addr(d, self.loc(base), self.loc(index), stride);
                }
            }
            InstData::Unary { op, arg } => self.unary(inst, op, arg, res.expect(HAS_RESULT)),
            InstData::Binary { op, args } => self.binary(inst, op, args, res.expect(HAS_RESULT)),
            InstData::Icmp { cond, args } => {
                let r = res.expect(HAS_RESULT);
                if matches!(self.frame.repr[r.index()], Repr::Flags) {
                    return; // the branch after it compares
                }
                let fc = self.compare(cond, args);
                if let Some(d) = self.home_bit(r) {
                    self.flag_to_bit(d, fc);
                }
            }
            InstData::Fcmp { .. } => self.unsupported(inst, "REAL comparison"),
            InstData::Convert { op, ty, arg } => {
                self.convert(inst, op, ty, arg, res.expect(HAS_RESULT))
            }
            InstData::Select {
                cond,
                if_true,
                if_false,
            } => self.select(cond, if_true, if_false, res.expect(HAS_RESULT)),
            InstData::Load { ty, addr } => self.load(ty, addr, res.expect(HAS_RESULT)),
            InstData::Store { value, addr } => self.store(value, addr),
            InstData::Call { func, args } => self.call(func, &args, res),
            // `build` refuses these first (`reject_inline_c`).
            InstData::InlineC { .. } => self.unsupported(inst, "C code in a pragma"),
            // The build expands the small tables into compares (`passes::br_table`).
            InstData::BrTable {
                arg,
                default,
                table,
            } => self.br_table(arg, &default, &table, next),
            // `build` answered every one with the layout (passes::sizes).
            InstData::SizeOf { .. } => {
                self.unsupported(inst, "a `sizeof` left after its resolution")
            }
            InstData::Intrinsic { op, .. } => match op {
                Intrinsic::ClockMs => {
                    if let Some(d) = res.and_then(|r| self.home(r)) {
                        self.copy_bytes(d, Loc::Mem(self.p.rt.now_ms), 4);
                    }
                }
                Intrinsic::ClockNs => {
                    if let Some(d) = res.and_then(|r| self.home(r)) {
                        self.copy_bytes(d, Loc::Mem(self.p.rt.now_ns), 8);
                    }
                }
                Intrinsic::RaiseFault => {
                    self.i(Inst::Bsf(self.p.rt.flags, crate::runtime::FAULT_BIT))
                }
                Intrinsic::StopRequested => {}
                // Only the JIT's pipeline makes fills (`passes::fill`).
                Intrinsic::Fill => self.unsupported(inst, "a `fill` of array elements"),
            },
            InstData::Jump { dest } => self.jump(&dest, next),
            InstData::Brif {
                cond,
                then_dest,
                else_dest,
            } => self.brif(cond, &then_dest, &else_dest, next),
            InstData::Return { value } => {
                if let Some(v) = value {
                    let ret = self.base + self.frame.ret_offset;
                    let t = self.ty(v);
                    if t == Type::I1 {
                        self.i(Inst::Clrf(ret));
                        let b = self.bit(v);
                        self.copy_bit((ret, 0), b, false);
                    } else {
                        let n = self.bytes(t);
                        let l = self.loc(v);
                        self.copy_bytes(ret, l, n);
                    }
                }
                self.i(Inst::Return);
            }
        }
    }

    /// `d := p + add` for a pointer (the low byte never carries: objects do not
    /// cross a bank, and the high byte holds bank and bit bits).
    fn add_ptr(&mut self, d: u16, p: Loc, add: u16) {
        for i in 0..2u16 {
            let k = (add >> (8 * i)) as u8;
            match Self::byte(p, i) {
                Src::Lit(x) => {
                    self.i(Inst::Movlw(x.wrapping_add(k)));
                }
                Src::Reg(r) => {
                    self.i(Inst::Movf(r, Dest::W));
                    if k != 0 {
                        self.i(Inst::Addlw(k));
                    }
                }
                Src::Add(r, x) => {
                    self.i(Inst::Movf(r, Dest::W));
                    if x.wrapping_add(k) != 0 {
                        self.i(Inst::Addlw(x.wrapping_add(k)));
                    }
                }
            }
            self.i(Inst::Movwf(d + i));
        }
    }

    fn elem_addr(&mut self, d: u16, base: Loc, index: Loc, stride: u32) {
        // index * stride fits a byte: the array lies in one bank.
        let t0 = SCRATCH[0];
        let t1 = SCRATCH[1];
        match Self::byte(index, 0) {
            Src::Lit(k) => {
                self.i(Inst::Movlw((k as u32 * stride) as u8));
                self.i(Inst::Movwf(t1));
            }
            s => {
                self.load_w(s);
                if stride == 1 {
                    self.i(Inst::Movwf(t1));
                } else if stride.is_power_of_two() {
                    self.i(Inst::Movwf(t1));
                    self.i(Inst::Bcf(reg::STATUS, reg::C));
                    for _ in 0..stride.trailing_zeros() {
                        self.i(Inst::Rlf(t1, Dest::F));
                    }
                } else {
                    self.i(Inst::Movwf(t0));
                    self.i(Inst::Clrf(t1));
                    let top = 32 - stride.leading_zeros();
                    for j in 0..top {
                        if stride >> j & 1 != 0 {
                            self.i(Inst::Movf(t0, Dest::W));
                            self.i(Inst::Addwf(t1, Dest::F));
                        }
                        if j + 1 < top {
                            self.i(Inst::Bcf(reg::STATUS, reg::C));
                            self.i(Inst::Rlf(t0, Dest::F));
                        }
                    }
                }
            }
        }
        self.load_w(Self::byte(base, 0));
        self.i(Inst::Addwf(t1, Dest::W));
        self.i(Inst::Movwf(d));
        let hi = Self::byte(base, 1);
        match hi {
            Src::Lit(0) => self.i(Inst::Clrf(d + 1)),
            _ => {
                self.load_w(hi);
                self.i(Inst::Movwf(d + 1));
            }
        }
    }
}

fn mask(n: u16) -> u64 {
    if n >= 8 {
        u64::MAX
    } else {
        (1u64 << (8 * n)) - 1
    }
}
