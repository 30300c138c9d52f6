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
//! staged through common RAM first (see [`Emitter::reg_for`]).

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
            InstData::Unary { op, arg } => self.unary(inst, op, arg, res.unwrap()),
            InstData::Binary { op, args } => self.binary(inst, op, args, res.unwrap()),
            InstData::Icmp { cond, args } => {
                let r = res.unwrap();
                if matches!(self.frame.repr[r.index()], Repr::Flags) {
                    return; // the branch after it compares
                }
                let fc = self.compare(cond, args);
                if let Some(d) = self.home_bit(r) {
                    self.flag_to_bit(d, fc);
                }
            }
            InstData::Fcmp { .. } => self.unsupported(inst, "REAL comparison"),
            InstData::Convert { op, ty, arg } => self.convert(inst, op, ty, arg, res.unwrap()),
            InstData::Select {
                cond,
                if_true,
                if_false,
            } => self.select(cond, if_true, if_false, res.unwrap()),
            InstData::Load { ty, addr } => self.load(ty, addr, res.unwrap()),
            InstData::Store { value, addr } => self.store(value, addr),
            InstData::Call { func, args } => self.call(func, &args, res),
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

    // ---- arithmetic ----------------------------------------------------------------

    fn unary(&mut self, inst: plcc_ir::Inst, op: UnaryOp, a: Value, r: Value) {
        let t = self.ty(a);
        if t == Type::I1 {
            if matches!(self.frame.repr[r.index()], Repr::NotOf(_)) {
                return;
            }
            if let (UnaryOp::Bnot, Some(d)) = (op, self.home_bit(r)) {
                let s = self.bit(a);
                self.copy_bit(d, s, true);
            }
            return;
        }
        if !op.is_int_op() {
            self.unsupported(inst, "REAL arithmetic");
            return;
        }
        let Some(d) = self.home(r) else { return };
        let n = self.bytes(t);
        let la = self.loc(a);
        match op {
            UnaryOp::Bnot => {
                for i in 0..n {
                    match Self::byte(la, i) {
                        Src::Reg(x) => self.i(Inst::Comf(x, Dest::W)),
                        s => {
                            self.load_w(s);
                            self.i(Inst::Xorlw(0xFF));
                        }
                    }
                    self.i(Inst::Movwf(d + i));
                }
            }
            UnaryOp::Ineg => {
                self.copy_bytes(d, la, n);
                self.negate_in_place(d, n);
            }
            UnaryOp::Iabs => {
                self.copy_bytes(d, la, n);
                let done = self.new_label("abs");
                self.i(Inst::Btfss(d + n - 1, 7));
                self.goto(done);
                self.negate_in_place(d, n);
                self.label(done);
            }
            _ => unreachable!(),
        }
    }

    fn negate_in_place(&mut self, d: u16, n: u16) {
        for i in 0..n {
            self.i(Inst::Comf(d + i, Dest::F));
        }
        self.increment_in_place(d, n);
    }

    fn increment_in_place(&mut self, d: u16, n: u16) {
        if n == 1 {
            self.i(Inst::Incf(d, Dest::F));
            return;
        }
        if n == 2 {
            self.i(Inst::Incf(d, Dest::F));
            self.i(Inst::Btfsc(reg::STATUS, reg::Z));
            self.i(Inst::Incf(d + 1, Dest::F));
            return;
        }
        self.carry_chain(d, 0, n);
    }

    /// Adds one to bytes `from..n` of `d` as one number, stopping at the first byte
    /// that does not wrap to zero.
    fn carry_chain(&mut self, d: u16, from: u16, n: u16) {
        let done = self.new_label("inc");
        for i in from..n {
            if i + 1 == n {
                self.i(Inst::Incf(d + i, Dest::F));
            } else {
                self.i(Inst::Incfsz(d + i, Dest::F));
                self.goto(done);
            }
        }
        self.label(done);
    }

    /// `d += s` over `n` bytes, the carry chained.
    fn add_in_place(&mut self, d: u16, s: Loc, n: u16) {
        if let Loc::Lit(k) = s {
            let k = k & mask(n);
            if k == 0 {
                return;
            }
            if k == 1 {
                self.increment_in_place(d, n);
                return;
            }
            if k < 256 && n > 1 {
                // Only the low byte adds; the carry ripples up.
                self.i(Inst::Movlw(k as u8));
                self.i(Inst::Addwf(d, Dest::F));
                if n == 2 {
                    self.i(Inst::Btfsc(reg::STATUS, reg::C));
                    self.i(Inst::Incf(d + 1, Dest::F));
                    return;
                }
                let no_carry = self.new_label("cy");
                self.i(Inst::Btfss(reg::STATUS, reg::C));
                self.goto(no_carry);
                self.carry_chain(d, 1, n);
                self.label(no_carry);
                return;
            }
        }
        for i in 0..n {
            let src = Self::byte(s, i);
            if i == 0 {
                self.load_w(src);
                self.i(Inst::Addwf(d, Dest::F));
                continue;
            }
            match src {
                Src::Lit(0) if i + 1 == n => {
                    // The carry out of the top byte is not needed.
                    self.i(Inst::Btfsc(reg::STATUS, reg::C));
                    self.i(Inst::Incf(d + i, Dest::F));
                }
                Src::Lit(k) => {
                    if k == 0xFF {
                        self.i(Inst::Movlw(0xFF));
                        self.i(Inst::Btfss(reg::STATUS, reg::C));
                        self.i(Inst::Addwf(d + i, Dest::F));
                    } else {
                        self.i(Inst::Movlw(k));
                        self.i(Inst::Btfsc(reg::STATUS, reg::C));
                        self.i(Inst::Movlw(k + 1));
                        self.i(Inst::Addwf(d + i, Dest::F));
                    }
                }
                _ => {
                    let r = self.reg_for(src, SCRATCH[0], Some(d + i));
                    self.i(Inst::Movf(r, Dest::W));
                    self.i(Inst::Btfsc(reg::STATUS, reg::C));
                    self.i(Inst::Incfsz(r, Dest::W));
                    self.i(Inst::Addwf(d + i, Dest::F));
                }
            }
        }
    }

    /// `d -= s` over `n` bytes, the borrow chained (C = 1: no borrow).
    fn sub_in_place(&mut self, d: u16, s: Loc, n: u16) {
        if let Loc::Lit(k) = s {
            self.add_in_place(d, Loc::Lit(k.wrapping_neg()), n);
            return;
        }
        for i in 0..n {
            let src = Self::byte(s, i);
            if i == 0 {
                self.load_w(src);
                self.i(Inst::Subwf(d, Dest::F));
                continue;
            }
            let r = self.reg_for(src, SCRATCH[0], Some(d + i));
            self.i(Inst::Movf(r, Dest::W));
            self.i(Inst::Btfss(reg::STATUS, reg::C));
            self.i(Inst::Incfsz(r, Dest::W));
            self.i(Inst::Subwf(d + i, Dest::F));
        }
    }

    fn binary(&mut self, inst: plcc_ir::Inst, op: BinaryOp, args: [Value; 2], r: Value) {
        let t = self.ty(args[0]);
        if !op.is_int_op() {
            self.unsupported(inst, "REAL arithmetic");
            return;
        }
        if t == Type::I1 {
            self.binary_bits(op, args, r);
            return;
        }
        let n = self.bytes(t);
        let (a, b) = (self.loc(args[0]), self.loc(args[1]));
        let Some(d) = self.home(r) else {
            // A division whose result is unused still raises the fault on zero.
            if op.can_fault() {
                if let Loc::Lit(0) = b {
                    self.i(Inst::Bsf(self.p.rt.flags, crate::runtime::FAULT_BIT));
                } else if !matches!(b, Loc::Lit(_)) {
                    let ok = self.new_label("nz");
                    self.test_zero(b, n);
                    self.i(Inst::Btfss(reg::STATUS, reg::Z));
                    self.goto(ok);
                    self.i(Inst::Bsf(self.p.rt.flags, crate::runtime::FAULT_BIT));
                    self.label(ok);
                }
            }
            return;
        };
        match op {
            BinaryOp::Iadd => {
                // The second operand may be the destination itself (`v := k * w + v`,
                // with v used in place): adding into it leaves it unread by the copy.
                let (x, y) = if matches!(a, Loc::Lit(_)) || b == Loc::Mem(d) {
                    (b, a)
                } else {
                    (a, b)
                };
                self.copy_bytes(d, x, n);
                self.add_in_place(d, y, n);
            }
            BinaryOp::Isub => {
                self.copy_bytes(d, a, n);
                self.sub_in_place(d, b, n);
            }
            BinaryOp::Band | BinaryOp::Bor | BinaryOp::Bxor => {
                for i in 0..n {
                    let (x, y) = (Self::byte(a, i), Self::byte(b, i));
                    let (x, y) = if matches!(x, Src::Lit(_)) {
                        (y, x)
                    } else {
                        (x, y)
                    };
                    match (op, y) {
                        (BinaryOp::Band, Src::Lit(0)) => {
                            self.i(Inst::Clrf(d + i));
                            continue;
                        }
                        (BinaryOp::Band, Src::Lit(0xFF))
                        | (BinaryOp::Bor, Src::Lit(0))
                        | (BinaryOp::Bxor, Src::Lit(0)) => {
                            self.load_w(x);
                        }
                        (_, Src::Lit(k)) => {
                            self.load_w(x);
                            self.i(match op {
                                BinaryOp::Band => Inst::Andlw(k),
                                BinaryOp::Bor => Inst::Iorlw(k),
                                _ => Inst::Xorlw(k),
                            });
                        }
                        _ => {
                            let yr = self.reg_for(y, SCRATCH[0], None);
                            self.load_w(x);
                            self.i(match op {
                                BinaryOp::Band => Inst::Andwf(yr, Dest::W),
                                BinaryOp::Bor => Inst::Iorwf(yr, Dest::W),
                                _ => Inst::Xorwf(yr, Dest::W),
                            });
                        }
                    }
                    self.i(Inst::Movwf(d + i));
                }
            }
            BinaryOp::Imul => {
                if let Loc::Lit(k) = b {
                    let k = k & mask(n);
                    if k.is_power_of_two() {
                        self.shift_const(BinaryOp::Ishl, d, a, n, k.trailing_zeros());
                        return;
                    }
                }
                if let Loc::Lit(k) = a {
                    let k = k & mask(n);
                    if k.is_power_of_two() {
                        self.shift_const(BinaryOp::Ishl, d, b, n, k.trailing_zeros());
                        return;
                    }
                }
                self.helpers.mul = self.helpers.mul.max(n);
                let ws = self.p.ws;
                self.copy_bytes(ws.a, a, n);
                self.copy_bytes(ws.b, b, n);
                let l = self
                    .helpers
                    .label(self.labels, crate::helpers::Helper::Mul(n));
                self.items.push(Item::Op(Op::Call(l)));
                self.copy_bytes(d, Loc::Mem(ws.r), n);
            }
            BinaryOp::Udiv | BinaryOp::Urem | BinaryOp::Sdiv | BinaryOp::Srem => {
                self.divide(op, d, a, b, n)
            }
            BinaryOp::Ishl | BinaryOp::Ushr | BinaryOp::Sshr | BinaryOp::Rotl | BinaryOp::Rotr => {
                let bits = 8 * n as u32;
                match b {
                    Loc::Lit(k) => {
                        let nb = self.bytes(self.ty(args[1]));
                        let k = k & mask(nb);
                        let c = if matches!(op, BinaryOp::Rotl | BinaryOp::Rotr) {
                            (k % bits as u64) as u32
                        } else {
                            k.min(bits as u64) as u32
                        };
                        self.shift_const(op, d, a, n, c);
                    }
                    _ => {
                        let nb = self.bytes(self.ty(args[1]));
                        self.shift_var(op, d, a, b, n, nb);
                    }
                }
            }
            _ => unreachable!(),
        }
    }

    fn binary_bits(&mut self, op: BinaryOp, args: [Value; 2], r: Value) {
        let Some(d) = self.home_bit(r) else { return };
        let (a, b) = (self.bit(args[0]), self.bit(args[1]));
        let (a, b) = if matches!(a, BitLoc::Lit(_)) {
            (b, a)
        } else {
            (a, b)
        };
        match (op, b) {
            (BinaryOp::Band, BitLoc::Lit(false)) => self.i(Inst::Bcf(d.0, d.1)),
            (BinaryOp::Bor, BitLoc::Lit(true)) => self.i(Inst::Bsf(d.0, d.1)),
            (BinaryOp::Band, BitLoc::Lit(true))
            | (BinaryOp::Bor, BitLoc::Lit(false))
            | (BinaryOp::Bxor, BitLoc::Lit(false)) => self.copy_bit(d, a, false),
            (BinaryOp::Bxor, BitLoc::Lit(true)) => self.copy_bit(d, a, true),
            (_, b @ BitLoc::Bit(..)) => {
                let BitLoc::Bit(ab, an, aneg) = a else {
                    unreachable!()
                };
                let BitLoc::Bit(bb, bn, bneg) = b else {
                    unreachable!()
                };
                let is_d = |x: (u16, u8), n: bool| x == d && !n;
                let touches_d = (ab, an) == d || (bb, bn) == d;
                match op {
                    BinaryOp::Band if is_d((ab, an), aneg) => {
                        self.skip_then(b.skip_if_true(), Inst::Bcf(d.0, d.1))
                    }
                    BinaryOp::Band if is_d((bb, bn), bneg) => {
                        self.skip_then(a.skip_if_true(), Inst::Bcf(d.0, d.1))
                    }
                    BinaryOp::Bor if is_d((ab, an), aneg) => {
                        self.skip_then(b.skip_if_false(), Inst::Bsf(d.0, d.1))
                    }
                    BinaryOp::Bor if is_d((bb, bn), bneg) => {
                        self.skip_then(a.skip_if_false(), Inst::Bsf(d.0, d.1))
                    }
                    BinaryOp::Band if !touches_d => {
                        self.i(Inst::Bsf(d.0, d.1));
                        self.skip_then(a.skip_if_true(), Inst::Bcf(d.0, d.1));
                        self.skip_then(b.skip_if_true(), Inst::Bcf(d.0, d.1));
                    }
                    BinaryOp::Bor if !touches_d => {
                        self.i(Inst::Bcf(d.0, d.1));
                        self.skip_then(a.skip_if_false(), Inst::Bsf(d.0, d.1));
                        self.skip_then(b.skip_if_false(), Inst::Bsf(d.0, d.1));
                    }
                    _ => {
                        // Through W: W = the result (0 or 1), then Z.
                        match op {
                            BinaryOp::Band => {
                                self.i(Inst::Movlw(0));
                                self.i(a.skip_if_false());
                                self.i(Inst::Movlw(1));
                                self.i(b.skip_if_true());
                                self.i(Inst::Movlw(0));
                            }
                            BinaryOp::Bor => {
                                self.i(Inst::Movlw(0));
                                self.i(a.skip_if_false());
                                self.i(Inst::Movlw(1));
                                self.i(b.skip_if_false());
                                self.i(Inst::Movlw(1));
                            }
                            _ => {
                                self.i(Inst::Movlw((aneg != bneg) as u8));
                                self.i(Inst::Btfsc(ab, an));
                                self.i(Inst::Xorlw(1));
                                self.i(Inst::Btfsc(bb, bn));
                                self.i(Inst::Xorlw(1));
                            }
                        }
                        self.i(Inst::Andlw(1));
                        self.i(Inst::Bcf(d.0, d.1));
                        self.i(Inst::Btfss(reg::STATUS, reg::Z));
                        self.i(Inst::Bsf(d.0, d.1));
                    }
                }
            }
            _ => unreachable!(),
        }
    }

    fn test_zero(&mut self, s: Loc, n: u16) {
        for i in 0..n {
            let src = Self::byte(s, i);
            if i == 0 {
                self.load_w(src);
                if !matches!(src, Src::Reg(_)) {
                    self.i(Inst::Iorlw(0));
                }
            } else {
                let r = self.reg_for(src, SCRATCH[0], None);
                self.i(Inst::Iorwf(r, Dest::W));
            }
        }
    }

    fn divide(&mut self, op: BinaryOp, d: u16, a: Loc, b: Loc, n: u16) {
        let flags = self.p.rt.flags;
        let signed = matches!(op, BinaryOp::Sdiv | BinaryOp::Srem);
        let want_rem = matches!(op, BinaryOp::Urem | BinaryOp::Srem);
        if let Loc::Lit(k) = b {
            let k = k & mask(n);
            if k == 0 {
                self.i(Inst::Bsf(flags, crate::runtime::FAULT_BIT));
                for i in 0..n {
                    self.i(Inst::Clrf(d + i));
                }
                return;
            }
            if !signed && k.is_power_of_two() {
                if want_rem {
                    self.binary_const_and(d, a, n, k - 1);
                } else {
                    self.shift_const(BinaryOp::Ushr, d, a, n, k.trailing_zeros());
                }
                return;
            }
            let positive = k < 1u64 << (8 * n as u32 - 1);
            if signed && want_rem && positive && k.is_power_of_two() {
                // The remainder takes the dividend's sign: mask |a|, then restore it.
                self.copy_bytes(d, a, n);
                let pos = self.new_label("pos");
                let done = self.new_label("rem");
                self.i(Inst::Btfss(d + n - 1, 7));
                self.goto(pos);
                self.negate_in_place(d, n);
                self.binary_const_and(d, Loc::Mem(d), n, k - 1);
                self.negate_in_place(d, n);
                self.goto(done);
                self.label(pos);
                self.binary_const_and(d, Loc::Mem(d), n, k - 1);
                self.label(done);
                return;
            }
            if signed && !want_rem && positive && k.is_power_of_two() {
                // Toward zero: a negative dividend is biased by k - 1 before the
                // arithmetic shift.
                self.copy_bytes(d, a, n);
                if k > 1 {
                    let pos = self.new_label("pos");
                    self.i(Inst::Btfss(d + n - 1, 7));
                    self.goto(pos);
                    self.add_in_place(d, Loc::Lit(k - 1), n);
                    self.label(pos);
                    self.shift_const(BinaryOp::Sshr, d, Loc::Mem(d), n, k.trailing_zeros());
                }
                return;
            }
        }
        let done = self.new_label("div");
        if !matches!(b, Loc::Lit(_)) {
            let ok = self.new_label("nz");
            self.test_zero(b, n);
            self.i(Inst::Btfss(reg::STATUS, reg::Z));
            self.goto(ok);
            self.i(Inst::Bsf(flags, crate::runtime::FAULT_BIT));
            for i in 0..n {
                self.i(Inst::Clrf(d + i));
            }
            self.goto(done);
            self.label(ok);
        }
        let ws = self.p.ws;
        self.helpers.div = self.helpers.div.max(n);
        self.copy_bytes(ws.a, a, n);
        self.copy_bytes(ws.b, b, n);
        let sign = SCRATCH[5];
        if signed {
            // sign bit 0: result negative; |a|, |b| into the workspace.
            self.i(Inst::Clrf(sign));
            let pa = self.new_label("pa");
            self.i(Inst::Btfss(ws.a + n - 1, 7));
            self.goto(pa);
            self.negate_in_place(ws.a, n);
            self.i(Inst::Incf(sign, Dest::F));
            self.label(pa);
            let pb = self.new_label("pb");
            self.i(Inst::Btfss(ws.b + n - 1, 7));
            self.goto(pb);
            self.negate_in_place(ws.b, n);
            if !want_rem {
                self.i(Inst::Incf(sign, Dest::F));
            }
            self.label(pb);
        }
        let l = self
            .helpers
            .label(self.labels, crate::helpers::Helper::Div(n));
        self.items.push(Item::Op(Op::Call(l)));
        let res = if want_rem { ws.r } else { ws.a };
        self.copy_bytes(d, Loc::Mem(res), n);
        if signed {
            let pos = self.new_label("pos");
            self.i(Inst::Btfss(sign, 0));
            self.goto(pos);
            self.negate_in_place(d, n);
            self.label(pos);
        }
        self.label(done);
    }

    fn binary_const_and(&mut self, d: u16, a: Loc, n: u16, k: u64) {
        for i in 0..n {
            let kb = (k >> (8 * i)) as u8;
            if kb == 0 {
                self.i(Inst::Clrf(d + i));
            } else {
                self.load_w(Self::byte(a, i));
                if kb != 0xFF {
                    self.i(Inst::Andlw(kb));
                }
                self.i(Inst::Movwf(d + i));
            }
        }
    }

    /// One-bit shift or rotate of `d` in place.
    fn shift1(&mut self, op: BinaryOp, d: u16, n: u16) {
        let top = d + n - 1;
        match op {
            BinaryOp::Ishl => {
                self.i(Inst::Bcf(reg::STATUS, reg::C));
                for i in 0..n {
                    self.i(Inst::Rlf(d + i, Dest::F));
                }
            }
            BinaryOp::Rotl => {
                self.i(Inst::Rlf(top, Dest::W));
                for i in 0..n {
                    self.i(Inst::Rlf(d + i, Dest::F));
                }
            }
            BinaryOp::Ushr => {
                self.i(Inst::Bcf(reg::STATUS, reg::C));
                for i in (0..n).rev() {
                    self.i(Inst::Rrf(d + i, Dest::F));
                }
            }
            BinaryOp::Sshr => {
                self.i(Inst::Rlf(top, Dest::W));
                for i in (0..n).rev() {
                    self.i(Inst::Rrf(d + i, Dest::F));
                }
            }
            BinaryOp::Rotr => {
                self.i(Inst::Rrf(d, Dest::W));
                for i in (0..n).rev() {
                    self.i(Inst::Rrf(d + i, Dest::F));
                }
            }
            _ => unreachable!(),
        }
    }

    fn fill(&mut self, op: BinaryOp, d: u16, n: u16, sign_from: Src) {
        if op == BinaryOp::Sshr {
            let t = self.reg_for(sign_from, SCRATCH[1], None);
            self.i(Inst::Movlw(0));
            self.i(Inst::Btfsc(t, 7));
            self.i(Inst::Movlw(0xFF));
            for i in 0..n {
                self.i(Inst::Movwf(d + i));
            }
        } else {
            for i in 0..n {
                self.i(Inst::Clrf(d + i));
            }
        }
    }

    fn shift_const(&mut self, op: BinaryOp, d: u16, a: Loc, n: u16, c: u32) {
        let bits = 8 * n as u32;
        let top = Self::byte(a, n - 1);
        if c >= bits {
            self.fill(op, d, n, top);
            return;
        }
        let (q, r) = ((c / 8) as u16, c % 8);
        // Whole bytes first, straight from the operand.
        match op {
            BinaryOp::Ishl => {
                for i in (0..n).rev() {
                    if i >= q {
                        let s = Self::byte(a, i - q);
                        self.copy_src(d + i, s);
                    } else {
                        self.i(Inst::Clrf(d + i));
                    }
                }
            }
            BinaryOp::Ushr | BinaryOp::Sshr => {
                for i in 0..n {
                    if i + q < n {
                        let s = Self::byte(a, i + q);
                        self.copy_src(d + i, s);
                    }
                }
                if q > 0 {
                    self.fill(op, d + n - q, q, top);
                }
            }
            BinaryOp::Rotl | BinaryOp::Rotr => {
                for i in 0..n {
                    let from = if op == BinaryOp::Rotl {
                        (i + n - q) % n
                    } else {
                        (i + q) % n
                    };
                    let s = Self::byte(a, from);
                    self.copy_src(d + i, s);
                }
            }
            _ => unreachable!(),
        }
        for _ in 0..r {
            self.shift1(op, d, n);
        }
    }

    fn copy_src(&mut self, d: u16, s: Src) {
        match s {
            Src::Lit(0) => self.i(Inst::Clrf(d)),
            Src::Reg(r) if r == d => {}
            _ => {
                self.load_w(s);
                self.i(Inst::Movwf(d));
            }
        }
    }

    fn shift_var(&mut self, op: BinaryOp, d: u16, a: Loc, c: Loc, n: u16, nc: u16) {
        let bits = 8 * n as u8;
        let cnt = SCRATCH[2];
        let done = self.new_label("sh");
        let lp = self.new_label("shl");
        self.copy_bytes(d, a, n);
        self.load_w(Self::byte(c, 0));
        self.i(Inst::Movwf(cnt));
        if matches!(op, BinaryOp::Rotl | BinaryOp::Rotr) {
            self.i(Inst::Movlw(bits - 1));
            self.i(Inst::Andwf(cnt, Dest::F));
        } else {
            let big = self.new_label("big");
            for i in 1..nc {
                let r = self.reg_for(Self::byte(c, i), SCRATCH[0], None);
                self.i(Inst::Movf(r, Dest::W));
                self.i(Inst::Btfss(reg::STATUS, reg::Z));
                self.goto(big);
            }
            self.i(Inst::Movlw(bits));
            self.i(Inst::Subwf(cnt, Dest::W));
            let small = self.new_label("small");
            self.i(Inst::Btfss(reg::STATUS, reg::C));
            self.goto(small);
            self.label(big);
            self.fill(op, d, n, Src::Reg(d + n - 1));
            self.goto(done);
            self.label(small);
        }
        self.i(Inst::Movf(cnt, Dest::F));
        self.i(Inst::Btfsc(reg::STATUS, reg::Z));
        self.goto(done);
        self.label(lp);
        self.shift1(op, d, n);
        self.i(Inst::Decfsz(cnt, Dest::F));
        self.goto(lp);
        self.label(done);
    }

    // ---- compares --------------------------------------------------------------

    /// Sets the flags for `a cond b` and says which flag holds the answer.
    fn compare(&mut self, cond: IntCC, args: [Value; 2]) -> FlagCond {
        let t = self.ty(args[0]);
        if t == Type::I1 {
            let (a, b) = (self.bit(args[0]), self.bit(args[1]));
            let mut k = 0u8;
            for x in [a, b] {
                match x {
                    BitLoc::Lit(v) => k ^= v as u8,
                    BitLoc::Bit(_, _, n) => k ^= n as u8,
                }
            }
            self.i(Inst::Movlw(k));
            for x in [a, b] {
                if let BitLoc::Bit(r, bn, _) = x {
                    self.i(Inst::Btfsc(r, bn));
                    self.i(Inst::Xorlw(1));
                }
            }
            self.i(Inst::Andlw(1));
            return FlagCond {
                bit: reg::Z,
                when_set: cond == IntCC::Eq,
            };
        }
        let n = self.bytes(t);
        let (mut a, mut b) = (self.loc(args[0]), self.loc(args[1]));
        match cond {
            IntCC::Eq | IntCC::Ne => {
                if matches!(a, Loc::Lit(_)) {
                    std::mem::swap(&mut a, &mut b);
                }
                let join = self.new_label("eq");
                for i in 0..n {
                    let (x, y) = (Self::byte(a, i), Self::byte(b, i));
                    match y {
                        Src::Lit(0) => {
                            let r = self.reg_for(x, SCRATCH[0], None);
                            self.i(Inst::Movf(r, Dest::W));
                        }
                        Src::Lit(k) => {
                            self.load_w(x);
                            self.i(Inst::Xorlw(k));
                        }
                        _ => {
                            let yr = self.reg_for(y, SCRATCH[0], None);
                            self.load_w(x);
                            self.i(Inst::Xorwf(yr, Dest::W));
                        }
                    }
                    if i + 1 < n {
                        self.i(Inst::Btfss(reg::STATUS, reg::Z));
                        self.goto(join);
                    }
                }
                self.label(join);
                FlagCond {
                    bit: reg::Z,
                    when_set: cond == IntCC::Eq,
                }
            }
            _ => {
                // a < b or a >= b after swapping the others.
                let (cond, swap) = match cond {
                    IntCC::Sgt => (IntCC::Slt, true),
                    IntCC::Sle => (IntCC::Sge, true),
                    IntCC::Ugt => (IntCC::Ult, true),
                    IntCC::Ule => (IntCC::Uge, true),
                    c => (c, false),
                };
                if swap {
                    std::mem::swap(&mut a, &mut b);
                }
                let signed = matches!(cond, IntCC::Slt | IntCC::Sge);
                if signed && matches!(b, Loc::Lit(k) if k & mask(n) == 0) {
                    // The sign bit alone: C := it.
                    match Self::byte(a, n - 1) {
                        Src::Reg(r) => self.i(Inst::Rlf(r, Dest::W)),
                        s => {
                            let r = self.reg_for(s, SCRATCH[0], None);
                            self.i(Inst::Rlf(r, Dest::W));
                        }
                    }
                    return FlagCond {
                        bit: reg::C,
                        when_set: cond == IntCC::Slt,
                    };
                }
                let join = self.new_label("cmp");
                for i in (0..n).rev() {
                    let (mut x, mut y) = (Self::byte(a, i), Self::byte(b, i));
                    if signed && i == n - 1 && matches!((x, y), (Src::Lit(_), _) | (_, Src::Lit(_)))
                    {
                        // One side constant: flip the other's sign bit in W.
                        match (x, y) {
                            (_, Src::Lit(ky)) => {
                                let k = ky ^ 0x80;
                                self.load_w(x);
                                self.i(Inst::Xorlw(0x80));
                                if k == 0 {
                                    // x' >= 0 always; Z already says x' == 0.
                                    self.i(Inst::Bsf(reg::STATUS, reg::C));
                                } else {
                                    self.i(Inst::Addlw(k.wrapping_neg()));
                                }
                            }
                            (Src::Lit(kx), _) => {
                                self.load_w(y);
                                self.i(Inst::Xorlw(0x80));
                                self.i(Inst::Sublw(kx ^ 0x80));
                            }
                            _ => unreachable!(),
                        }
                        if i > 0 {
                            self.i(Inst::Btfss(reg::STATUS, reg::Z));
                            self.goto(join);
                        }
                        continue;
                    }
                    if signed && i == n - 1 {
                        // Flip the sign bits: signed order becomes unsigned order.
                        x = self.flip_sign(x, SCRATCH[0]);
                        y = self.flip_sign(y, SCRATCH[1]);
                    }
                    // W = x - y; C = x >= y; Z = x == y.
                    match (x, y) {
                        (_, Src::Lit(k)) => {
                            let xr = self.reg_for(x, SCRATCH[2], None);
                            self.i(Inst::Movlw(k));
                            self.i(Inst::Subwf(xr, Dest::W));
                        }
                        (Src::Lit(k), _) => {
                            self.load_w(y);
                            self.i(Inst::Sublw(k));
                        }
                        _ => {
                            let xr = self.reg_for(x, SCRATCH[2], None);
                            self.load_w(y);
                            self.i(Inst::Subwf(xr, Dest::W));
                        }
                    }
                    if i > 0 {
                        self.i(Inst::Btfss(reg::STATUS, reg::Z));
                        self.goto(join);
                    }
                }
                self.label(join);
                FlagCond {
                    bit: reg::C,
                    when_set: matches!(cond, IntCC::Sge | IntCC::Uge),
                }
            }
        }
    }

    fn flip_sign(&mut self, s: Src, t: u16) -> Src {
        match s {
            Src::Lit(k) => Src::Lit(k ^ 0x80),
            _ => {
                self.load_w(s);
                self.i(Inst::Xorlw(0x80));
                self.i(Inst::Movwf(t));
                Src::Reg(t)
            }
        }
    }

    fn flag_to_bit(&mut self, d: (u16, u8), fc: FlagCond) {
        self.i(Inst::Bcf(d.0, d.1));
        self.i(if fc.when_set {
            Inst::Btfsc(reg::STATUS, fc.bit)
        } else {
            Inst::Btfss(reg::STATUS, fc.bit)
        });
        self.i(Inst::Bsf(d.0, d.1));
    }

    // ---- conversions, select, memory -----------------------------------------------

    fn convert(&mut self, inst: plcc_ir::Inst, op: ConvOp, ty: Type, a: Value, r: Value) {
        let from = self.ty(a);
        if ty.is_float() || from.is_float() {
            if op == ConvOp::Bitcast {
                if let Some(d) = self.home(r) {
                    let l = self.loc(a);
                    self.copy_bytes(d, l, self.bytes(ty));
                }
                return;
            }
            self.unsupported(inst, "REAL conversion");
            return;
        }
        if ty == Type::I1 {
            // itrunc to i1 keeps bit 0.
            if let Some(d) = self.home_bit(r) {
                match Self::byte(self.loc(a), 0) {
                    Src::Lit(k) => self.copy_bit(d, BitLoc::Lit(k & 1 != 0), false),
                    s => {
                        let reg = self.reg_for(s, SCRATCH[0], Some(d.0));
                        self.copy_bit(d, BitLoc::Bit(reg, 0, false), false);
                    }
                }
            }
            return;
        }
        let Some(d) = self.home(r) else { return };
        let n = self.bytes(ty);
        if from == Type::I1 {
            for i in 1..n {
                self.i(Inst::Clrf(d + i));
            }
            match self.bit(a) {
                BitLoc::Lit(b) => {
                    self.i(Inst::Movlw(b as u8));
                    self.i(Inst::Movwf(d));
                }
                BitLoc::Bit(x, bn, neg) => {
                    self.i(Inst::Movlw(neg as u8));
                    self.i(Inst::Btfsc(x, bn));
                    self.i(Inst::Movlw(!neg as u8));
                    self.i(Inst::Movwf(d));
                }
            }
            return;
        }
        let m = self.bytes(from);
        let la = self.loc(a);
        match op {
            // REAL bits as DWORD and back, once REAL is an integer (see `softfloat`).
            ConvOp::Itrunc | ConvOp::Bitcast => self.copy_bytes(d, la, n),
            ConvOp::Uext | ConvOp::Sext => {
                self.copy_bytes(d, la, m);
                if op == ConvOp::Sext {
                    self.fill(BinaryOp::Sshr, d + m, n - m, Src::Reg(d + m - 1));
                } else {
                    for i in m..n {
                        self.i(Inst::Clrf(d + i));
                    }
                }
            }
            ConvOp::PtrToInt | ConvOp::IntToPtr => {
                self.unsupported(inst, "pointer arithmetic (CODESYS pointers as numbers)")
            }
            _ => self.unsupported(inst, "this conversion"),
        }
    }

    fn select(&mut self, c: Value, t: Value, e: Value, r: Value) {
        let cond = self.bit(c);
        let ty = self.ty(t);
        let emit_copy = |s: &mut Self, v: Value| {
            if ty == Type::I1 {
                if let Some(d) = s.home_bit(r) {
                    let b = s.bit(v);
                    s.copy_bit(d, b, false);
                }
            } else if let Some(d) = s.home(r) {
                let l = s.loc(v);
                s.copy_bytes(d, l, s.bytes(ty));
            }
        };
        match cond {
            BitLoc::Lit(true) => emit_copy(self, t),
            BitLoc::Lit(false) => emit_copy(self, e),
            c @ BitLoc::Bit(..) => {
                let else_l = self.new_label("sel");
                let end = self.new_label("sele");
                self.i(c.skip_if_true());
                self.goto(else_l);
                emit_copy(self, t);
                self.goto(end);
                self.label(else_l);
                emit_copy(self, e);
                self.label(end);
            }
        }
    }

    /// Points FSR (and IRP) at a dynamic pointer plus `add`.
    fn point_fsr(&mut self, p: Loc, add: u16) {
        let lo = Self::byte(p, 0);
        self.load_w(lo);
        let k = add as u8;
        if k != 0 {
            self.i(Inst::Addlw(k));
        }
        self.i(Inst::Movwf(reg::FSR));
        match Self::byte(p, 1) {
            Src::Lit(h) => self.items.push(Item::Op(Op::Irp(h & 1 != 0))),
            Src::Reg(r) | Src::Add(r, _) => {
                self.i(Inst::Bcf(reg::STATUS, reg::IRP));
                self.skip_then(Inst::Btfsc(r, 0), Inst::Bsf(reg::STATUS, reg::IRP));
            }
        }
    }

    /// The address form of a pointer operand: a fixed address with its bit, or a
    /// pointer in RAM plus a constant offset with the bit if it is known.
    fn addr_of(&self, p: Value) -> Result<(u16, u8), (Loc, u16, Option<u8>)> {
        match self.frame.repr[p.index()] {
            Repr::Ptr(Ptr::Known(s, o, b)) => {
                let v = self.p.ptr_value(s, o, b);
                Ok((v & 0x1FF, (v >> 9) as u8 & 7))
            }
            Repr::Ptr(Ptr::Derived(base, o, b)) => Err((self.loc(base), o, b)),
            _ => Err((self.loc(p), 0, None)),
        }
    }

    fn bitmask_from(&mut self, p: Loc) {
        // W := 1 << bit, the bit number from the pointer's high byte.
        self.load_w(Self::byte(p, 1));
        let l = self
            .helpers
            .label(self.labels, crate::helpers::Helper::BitMask);
        self.items.push(Item::Op(Op::Call(l)));
    }

    fn load(&mut self, ty: Type, addr: Value, r: Value) {
        match self.addr_of(addr) {
            Ok((a, bit)) => {
                if ty == Type::I1 {
                    if let Some(d) = self.home_bit(r) {
                        self.copy_bit(d, BitLoc::Bit(a, bit, false), false);
                    }
                } else if let Some(d) = self.home(r) {
                    self.copy_bytes(d, Loc::Mem(a), self.bytes(ty));
                }
            }
            Err((p, off, bit)) => {
                if ty == Type::I1 {
                    let Some(d) = self.home_bit(r) else { return };
                    match bit {
                        Some(b) => {
                            self.point_fsr(p, off);
                            self.copy_bit(d, BitLoc::Bit(reg::INDF, b, false), false);
                        }
                        None => {
                            self.bitmask_from(p);
                            self.i(Inst::Movwf(SCRATCH[3]));
                            self.point_fsr(p, off);
                            self.i(Inst::Movf(SCRATCH[3], Dest::W));
                            self.i(Inst::Andwf(reg::INDF, Dest::W));
                            self.i(Inst::Bcf(d.0, d.1));
                            self.i(Inst::Btfss(reg::STATUS, reg::Z));
                            self.i(Inst::Bsf(d.0, d.1));
                        }
                    }
                    return;
                }
                let Some(d) = self.home(r) else { return };
                self.point_fsr(p, off);
                let n = self.bytes(ty);
                for i in 0..n {
                    self.i(Inst::Movf(reg::INDF, Dest::W));
                    self.i(Inst::Movwf(d + i));
                    if i + 1 < n {
                        self.i(Inst::Incf(reg::FSR, Dest::F));
                    }
                }
            }
        }
    }

    fn store(&mut self, v: Value, addr: Value) {
        let ty = self.ty(v);
        match self.addr_of(addr) {
            Ok((a, bit)) => {
                if ty == Type::I1 {
                    let s = self.bit(v);
                    self.copy_bit((a, bit), s, false);
                } else {
                    let l = self.loc(v);
                    self.copy_bytes(a, l, self.bytes(ty));
                }
            }
            Err((p, off, bit)) => {
                if ty == Type::I1 {
                    let s = self.bit(v);
                    match bit {
                        Some(b) => {
                            self.point_fsr(p, off);
                            self.copy_bit((reg::INDF, b), s, false);
                        }
                        None => {
                            self.bitmask_from(p);
                            self.i(Inst::Movwf(SCRATCH[3]));
                            self.point_fsr(p, off);
                            self.i(Inst::Movf(SCRATCH[3], Dest::W));
                            match s {
                                BitLoc::Lit(true) => self.i(Inst::Iorwf(reg::INDF, Dest::F)),
                                BitLoc::Lit(false) => {
                                    self.i(Inst::Xorlw(0xFF));
                                    self.i(Inst::Andwf(reg::INDF, Dest::F));
                                }
                                x @ BitLoc::Bit(..) => {
                                    let set = self.new_label("bs");
                                    let end = self.new_label("be");
                                    self.i(x.skip_if_false());
                                    self.goto(set);
                                    self.i(Inst::Xorlw(0xFF));
                                    self.i(Inst::Andwf(reg::INDF, Dest::F));
                                    self.goto(end);
                                    self.label(set);
                                    self.i(Inst::Iorwf(reg::INDF, Dest::F));
                                    self.label(end);
                                }
                            }
                        }
                    }
                    return;
                }
                let l = self.loc(v);
                self.point_fsr(p, off);
                let n = self.bytes(ty);
                for i in 0..n {
                    self.load_w(Self::byte(l, i));
                    self.i(Inst::Movwf(reg::INDF));
                    if i + 1 < n {
                        self.i(Inst::Incf(reg::FSR, Dest::F));
                    }
                }
            }
        }
    }

    fn call(&mut self, func: FuncId, args: &[Value], res: Option<Value>) {
        let callee = &self.p.module.funcs[func.index()];
        let cframe = &self.p.frames[func.index()];
        let cbase = self.p.frame_base[func.index()];
        if let Some(entry) = callee.entry() {
            let params = callee.block(entry).params.clone();
            for (p, &a) in params.iter().zip(args) {
                match cframe.repr[p.index()] {
                    Repr::Bytes(o) => {
                        let l = self.loc(a);
                        let n = self.bytes(callee.value_type(*p));
                        self.copy_bytes(cbase + o, l, n);
                    }
                    Repr::Bit(o, b) => {
                        let s = self.bit(a);
                        self.copy_bit((cbase + o, b), s, false);
                    }
                    _ => {}
                }
            }
        }
        let l = self.p.func_label[func.index()];
        self.items.push(Item::Op(Op::Call(l)));
        if let Some(r) = res {
            let ret = cbase + cframe.ret_offset;
            let t = self.ty(r);
            if t == Type::I1 {
                if let Some(d) = self.home_bit(r) {
                    self.copy_bit(d, BitLoc::Bit(ret, 0, false), false);
                }
            } else if let Some(d) = self.home(r) {
                self.copy_bytes(d, Loc::Mem(ret), self.bytes(t));
            }
        }
    }

    // ---- control flow --------------------------------------------------------------

    /// Copies branch arguments into the destination's parameters (as one parallel
    /// copy: through the frame's copy area when a destination overlaps a source).
    fn edge_copies(&mut self, dest: &BlockCall) {
        let params = self.f.block(dest.block).params.clone();
        let mut moves: Vec<(Value, Value)> = Vec::new();
        for (p, a) in params.iter().zip(&dest.args) {
            if p != a && !matches!(self.frame.repr[p.index()], Repr::Unused) {
                moves.push((*p, *a));
            }
        }
        if moves.is_empty() {
            return;
        }
        let range = |s: &Self, mut v: Value| -> Option<(u32, u32)> {
            while let Repr::NotOf(x) = s.frame.repr[v.index()] {
                v = x;
            }
            // In bits, so BOOLs sharing a byte are told apart.
            let bytes = |a: u16, n: u16| Some((a as u32 * 8, (a + n) as u32 * 8));
            match s.frame.repr[v.index()] {
                Repr::Bytes(o) => bytes(s.base + o, s.bytes(s.ty(v))),
                Repr::Bit(o, b) => {
                    let at = (s.base + o) as u32 * 8 + b as u32;
                    Some((at, at + 1))
                }
                Repr::Ptr(Ptr::Derived(b, _, _)) => match s.frame.repr[b.index()] {
                    Repr::Bytes(o) => bytes(s.base + o, 2),
                    _ => None,
                },
                _ => None,
            }
        };
        let clash = |s: &Self, dst: Value, src: Value| match (range(s, dst), range(s, src)) {
            (Some((ps, pe)), Some((as_, ae))) => ps < ae && as_ < pe,
            _ => false,
        };
        // Sequentialise: a move may go once no other pending move still reads the
        // place it writes; a cycle (a swap) goes through the copy area.
        while !moves.is_empty() {
            let ready = (0..moves.len()).find(|&i| {
                moves
                    .iter()
                    .enumerate()
                    .all(|(j, &(_, a))| j == i || !clash(self, moves[i].0, a))
            });
            match ready {
                Some(i) => {
                    let (p, a) = moves.remove(i);
                    self.move_value(p, a);
                }
                None => break,
            }
        }
        if moves.is_empty() {
            return;
        }
        // Two phases through the copy area.
        let mut at = self.base + self.frame.copy_offset;
        let mut staged = Vec::new();
        for &(p, a) in &moves {
            let t = self.ty(p);
            if t == Type::I1 {
                let s = self.bit(a);
                self.i(Inst::Clrf(at));
                self.copy_bit((at, 0), s, false);
                staged.push((p, at));
                at += 1;
            } else {
                let n = self.bytes(t);
                let l = self.loc(a);
                self.copy_bytes(at, l, n);
                staged.push((p, at));
                at += n;
            }
        }
        for (p, from) in staged {
            let t = self.ty(p);
            if t == Type::I1 {
                if let Some(d) = self.home_bit(p) {
                    self.copy_bit(d, BitLoc::Bit(from, 0, false), false);
                }
            } else if let Some(d) = self.home(p) {
                self.copy_bytes(d, Loc::Mem(from), self.bytes(t));
            }
        }
    }

    fn move_value(&mut self, dst: Value, src: Value) {
        let t = self.ty(dst);
        if t == Type::I1 {
            if let Some(d) = self.home_bit(dst) {
                let s = self.bit(src);
                self.copy_bit(d, s, false);
            }
        } else if let Some(d) = self.home(dst) {
            let l = self.loc(src);
            self.copy_bytes(d, l, self.bytes(t));
        }
    }

    fn jump(&mut self, dest: &BlockCall, next: Option<Block>) {
        self.edge_copies(dest);
        if Some(dest.block) != next {
            let l = self.block_label(dest.block);
            self.goto(l);
        }
    }

    fn has_moves(&self, d: &BlockCall) -> bool {
        let params = &self.f.block(d.block).params;
        params
            .iter()
            .zip(&d.args)
            .any(|(p, a)| p != a && !matches!(self.frame.repr[p.index()], Repr::Unused))
    }

    fn brif(&mut self, cond: Value, t: &BlockCall, e: &BlockCall, next: Option<Block>) {
        // The test: a skip instruction that skips the next one when the condition is
        // true.
        let skip_if_true = match self.frame.repr[cond.index()] {
            Repr::Flags => {
                let (icmp_cond, args) = match self.f.inst(match self.f.value_def(cond) {
                    plcc_ir::function::ValueDef::Result(i) => i,
                    _ => unreachable!(),
                }) {
                    InstData::Icmp { cond, args } => (*cond, *args),
                    _ => unreachable!(),
                };
                let fc = self.compare(icmp_cond, args);
                if fc.when_set {
                    Inst::Btfss(reg::STATUS, fc.bit)
                } else {
                    Inst::Btfsc(reg::STATUS, fc.bit)
                }
            }
            _ => match self.bit(cond) {
                BitLoc::Lit(true) => return self.jump(t, next),
                BitLoc::Lit(false) => return self.jump(e, next),
                c @ BitLoc::Bit(..) => c.skip_if_true(),
            },
        };
        let (tm, em) = (self.has_moves(t), self.has_moves(e));
        if !em && !tm && Some(e.block) == next && Some(t.block) != next {
            // The false side follows: test the other way and jump only when true.
            let skip_if_false = match skip_if_true {
                Inst::Btfss(f, b) => Inst::Btfsc(f, b),
                Inst::Btfsc(f, b) => Inst::Btfss(f, b),
                other => unreachable!("a bit test, not {other:?}"),
            };
            self.i(skip_if_false);
            let l = self.block_label(t.block);
            self.goto(l);
            return;
        }
        let else_target = if em {
            self.new_label("else")
        } else {
            self.block_label(e.block)
        };
        // False falls into `goto else`; true skips it.
        self.i(skip_if_true);
        self.goto(else_target);
        self.jump(t, if em { None } else { next });
        if em {
            self.label(else_target);
            self.jump(e, next);
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
