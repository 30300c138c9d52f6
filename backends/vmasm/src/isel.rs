//! Instruction selection: one IR function to VM instructions.
//!
//! Every function runs with DPTR at the start of its *frame* and names all its data
//! relative to it, as CPDev code does:
//! - a function with an instance ([`Conv::Instance`]: FB and PROGRAM bodies and their
//!   initialisers) runs on the instance: its fields are at their layout offsets, its
//!   parameters, result and SSA values in the instance's temporary area
//!   (`plcc_ir::layout::Layout::compute_with_tails`); callers use `CALB inst, code` (or `CALBR ptr, code` when the
//!   instance's address is only known at run time);
//! - any other function ([`Conv::Area`]) runs on a *call area* in its caller's frame
//!   (`CALF area, code`): parameters first, then the result, then its values.
//!
//! Pointers are classified statically where possible: frame-relative
//! ([`PtrClass::Rel`]: fields, slots), absolute ([`PtrClass::Abs`]: globals, reached
//! with MMV), an array element at a run-time index (copied index, CEAC, then the
//! A?RD/A?WR instructions), or a run-time absolute address held in a variable (DPSTO to
//! form it, DPRDL/DPWRL to use it). Constants live in a per-frame pool that the
//! function's prologue fills with MCD. Operations the VM lacks or leaves undefined are
//! composed: division guards, shifts by the width, sign extension, float rounding and
//! saturating float-to-integer conversions.

use crate::code::{Arg, Item, LabelId, Program, Unit, VInst};
use crate::isa::{op, Mode, Opcode, Ty};
use plcc_ir::diag::{Diagnostic, Span};
use plcc_ir::entities::{AggId, Block, FuncId, Value};
use plcc_ir::function::{Function, ValueDef};
use plcc_ir::inst::{BinaryOp, BlockCall, ConvOp, FloatCC, InstData, IntCC, Intrinsic, UnaryOp};
use plcc_ir::layout::Layout as VmLayout;
use plcc_ir::module::{AggDef, Module};
use plcc_ir::types::{MemType, Type};
use rustc_hash::FxHashMap;

/// How a function is called and where its frame is.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum Conv {
    /// It runs on the instance its first parameter points to; its temporaries start
    /// `temp_base` bytes into the instance.
    Instance {
        /// The instance's struct.
        agg: AggId,
        /// Offset of its temporaries in the instance.
        temp_base: u32,
    },
    /// It runs on a call area of its caller.
    Area,
}

/// What the code generator of one function needs to know about the whole program.
pub struct Cx<'a> {
    /// The module.
    pub module: &'a Module,
    /// Aggregate layout.
    pub layout: &'a VmLayout,
    /// The addressing mode.
    pub mode: Mode,
    /// Calling convention of every function.
    pub convs: &'a [Conv],
    /// Frame size of every function (from the previous round; see `lib.rs`).
    pub frame_sizes: &'a [u32],
    /// Absolute address of every data object.
    pub data_addrs: &'a [u32],
    /// The entry label of every function.
    pub entry_labels: &'a [LabelId],
    /// Source texts for the listing.
    pub sources: &'a [Option<String>],
}

/// Where a pointer value points, as far as is known statically.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum PtrClass {
    /// `DPTR + offset`.
    Rel(u32),
    /// An absolute data address.
    Abs(u32),
    /// Element `index` of an array at `DPTR + base`, accessed whole.
    Idx {
        /// Offset of the array.
        base: u32,
        /// The zero-based index value.
        index: Value,
        /// Bytes per element (1, 2, 4 or 8).
        size: u32,
        /// Number of elements.
        len: u32,
    },
    /// Known only at run time: an absolute address held in the value's home.
    Dyn,
}

/// The frame layout of a function's parameters and result: offsets from its frame
/// start (`None` for an instance parameter), the result's offset, and the end.
pub fn signature(
    layout: &VmLayout,
    f: &Function,
    conv: Conv,
    mode: Mode,
) -> (Vec<Option<u32>>, Option<u32>, u32) {
    let mut at = 0u32;
    let align = |at: u32, size: u32| {
        let a = if mode == Mode::M32A {
            size.clamp(1, 4)
        } else {
            1
        };
        at.div_ceil(a) * a
    };
    let mut params = Vec::new();
    for (i, &t) in f.params.iter().enumerate() {
        if i == 0 && matches!(conv, Conv::Instance { .. }) {
            params.push(None);
            continue;
        }
        let s = layout.scalar_size(t);
        at = align(at, s);
        params.push(Some(at));
        at += s;
    }
    let ret = f.ret.map(|t| {
        let s = layout.scalar_size(t);
        at = align(at, s);
        let r = at;
        at += s;
        r
    });
    (params, ret, at)
}

/// The code of one function.
pub struct FuncCode {
    /// Its unit.
    pub unit: Unit,
    /// Bytes its frame takes beyond its start.
    pub frame_size: u32,
}

const SCRATCH: u32 = 64;

/// Results of code generation; the error is boxed because diagnostics are large.
pub type Res<T> = Result<T, Box<Diagnostic>>;

struct Fx<'a, 'p> {
    cx: &'a Cx<'a>,
    f: &'a Function,
    conv: Conv,
    prog: &'p mut Program,
    next: u32,
    body: Vec<Item>,
    homes: Vec<Option<u32>>,
    class: Vec<Option<PtrClass>>,
    needs_value: Vec<bool>,
    pool: FxHashMap<(Type, u64), u32>,
    prologue: Vec<Item>,
    shadows: FxHashMap<Value, u32>,
    scratch: Option<u32>,
    scratch_used: u32,
    block_labels: Vec<LabelId>,
    call_area: Option<u32>,
    names: FxHashMap<u32, String>,
    uses: Vec<Vec<(usize, UseKind)>>,
    last_line: Option<(u32, usize)>,
    fname: String,
    slot_offsets: Vec<u32>,
    ret_home: Option<u32>,
    /// Array indexes `sext(i) - low` (with `i` an INT) that CEAC computes itself.
    folded_index: FxHashMap<Value, (Value, i64)>,
    /// Values whose only uses were folded into CEAC: not computed at all.
    skip: Vec<bool>,
    /// The index an array access at a run-time index reads when it happens.
    late_use: FxHashMap<plcc_ir::entities::Inst, Value>,
}

#[derive(Copy, Clone, Debug, PartialEq, Eq)]
enum UseKind {
    /// The address operand of a load or store.
    Addr,
    /// The base of a field or element address.
    Base,
    /// The first argument of a call of a function with an instance.
    Instance,
    /// Anything else: the value itself is needed.
    Value,
    /// Read by an array access at a run-time index, where the access is (the index,
    /// or the INT it was widened from when CEAC subtracts the low bound).
    Late,
}

/// Generates the code of function `id`.
pub fn gen_function(cx: &Cx<'_>, prog: &mut Program, id: FuncId) -> Res<FuncCode> {
    let f = cx.module.func(id);
    let conv = cx.convs[id.index()];
    let base = match conv {
        Conv::Instance { temp_base, .. } => temp_base,
        Conv::Area => 0,
    };
    let nblocks = f.blocks.len();
    let block_labels = (0..nblocks)
        .map(|b| prog.label(format!("?{}?B{b}", f.name)))
        .collect();
    let mut fx = Fx {
        cx,
        f,
        conv,
        prog,
        next: base,
        body: Vec::new(),
        homes: vec![None; f.values.len()],
        class: vec![None; f.values.len()],
        needs_value: vec![false; f.values.len()],
        pool: FxHashMap::default(),
        prologue: Vec::new(),
        shadows: FxHashMap::default(),
        scratch: None,
        scratch_used: 0,
        block_labels,
        call_area: None,
        names: FxHashMap::default(),
        uses: vec![Vec::new(); f.values.len()],
        last_line: None,
        fname: f.name.clone(),
        slot_offsets: Vec::new(),
        ret_home: None,
        folded_index: FxHashMap::default(),
        skip: vec![false; f.values.len()],
        late_use: FxHashMap::default(),
    };
    fx.run(id)?;
    let frame_size = fx.next - base;
    let mut items = vec![Item::Label(cx.entry_labels[id.index()])];
    items.append(&mut fx.prologue);
    items.append(&mut fx.body);
    Ok(FuncCode {
        unit: Unit {
            items,
            rel_names: fx.names,
            abs_names: FxHashMap::default(),
        },
        frame_size,
    })
}

fn int_ty(t: Type, signed: bool) -> Ty {
    match (t, signed) {
        (Type::I1, _) => Ty::Bool,
        (Type::I8, true) => Ty::Sint,
        (Type::I8, false) => Ty::Byte,
        (Type::I16, true) => Ty::Int,
        (Type::I16, false) => Ty::Word,
        (Type::I32, true) => Ty::Dint,
        (Type::I32, false) | (Type::F32, _) => Ty::Dword,
        (Type::I64, true) => Ty::Lint,
        (Type::I64, false) | (Type::F64, _) => Ty::Lword,
        (Type::Ptr, _) => Ty::Word,
    }
}

/// The code of a type in the AND/OR/NOT numbering (BOOL 0, BYTE 1, … LWORD 4).
fn logic_code(size: u32, is_bool: bool) -> u8 {
    if is_bool {
        return 0;
    }
    match size {
        1 => 1,
        2 => 2,
        4 => 3,
        _ => 4,
    }
}

impl<'a, 'p> Fx<'a, 'p> {
    fn mode(&self) -> Mode {
        self.cx.mode
    }

    fn size(&self, t: Type) -> u32 {
        self.cx.layout.scalar_size(t)
    }

    fn vty(&self, v: Value) -> Type {
        self.f.value_type(v)
    }

    fn ptr_ty(&self) -> Ty {
        if self.mode() == Mode::M16 {
            Ty::Word
        } else {
            Ty::Dword
        }
    }

    fn ptr_type(&self) -> Type {
        if self.mode() == Mode::M16 {
            Type::I16
        } else {
            Type::I32
        }
    }

    fn internal(&self, msg: impl Into<String>) -> Box<Diagnostic> {
        Box::new(Diagnostic::error_nowhere(
            crate::codes::E_INTERNAL,
            format!("vmasm: {} (in `{}`)", msg.into(), self.fname),
        ))
    }

    /// A new frame variable.
    fn alloc(&mut self, size: u32, name: String) -> u32 {
        let a = if self.mode() == Mode::M32A {
            size.clamp(1, 4)
        } else {
            1
        };
        self.next = self.next.div_ceil(a) * a;
        let at = self.next;
        self.next += size.max(1);
        self.names.entry(at).or_insert(name);
        at
    }

    /// Scratch memory for the duration of one IR instruction.
    fn scratch(&mut self, size: u32) -> Res<u32> {
        let base = match self.scratch {
            Some(b) => b,
            None => {
                let b = self.alloc(SCRATCH, "?TMP".into());
                self.scratch = Some(b);
                b
            }
        };
        let at = self.scratch_used.next_multiple_of(size.clamp(1, 4));
        if at + size > SCRATCH {
            return Err(self.internal("scratch area exhausted"));
        }
        self.scratch_used = at + size;
        Ok(base + at)
    }

    fn emit(&mut self, opcode: Opcode, args: Vec<Arg>) {
        self.body.push(Item::Inst(VInst { opcode, args }));
    }

    fn label(&mut self, l: LabelId) {
        self.body.push(Item::Label(l));
    }

    fn new_label(&mut self, what: &str) -> LabelId {
        let n = self.prog.labels.len();
        self.prog.label(format!("?{}?{what}{n}", self.fname))
    }

    /// A constant of type `t` with raw bits `bits`, from the frame's pool.
    fn konst(&mut self, t: Type, bits: u64) -> u32 {
        let size = self.size(t);
        let bits = if size >= 8 {
            bits
        } else {
            bits & ((1u64 << (size * 8)) - 1)
        };
        let key = (if t == Type::Ptr { self.ptr_type() } else { t }, bits);
        if let Some(&at) = self.pool.get(&key) {
            return at;
        }
        let at = self.alloc(size, format!("?L?CST{:04X}", self.pool.len()));
        let bytes = bits.to_le_bytes()[..size as usize].to_vec();
        let mcd = self.mcd_inst(Arg::Rel(at), bytes);
        self.prologue.push(Item::Inst(mcd));
        self.pool.insert(key, at);
        at
    }

    fn mcd_inst(&self, dst: Arg, bytes: Vec<u8>) -> VInst {
        let opcode = if self.mode() == Mode::M32A {
            op::MCD4A
        } else {
            op::MCD
        };
        VInst {
            opcode,
            args: vec![dst, Arg::Bytes(bytes)],
        }
    }

    fn mcd(&mut self, dst: u32, bytes: Vec<u8>) {
        let i = self.mcd_inst(Arg::Rel(dst), bytes);
        self.body.push(Item::Inst(i));
    }

    fn copy(&mut self, dst: u32, src: u32, n: u32) {
        if dst == src || n == 0 {
            return;
        }
        if self.mode() == Mode::M32A {
            self.emit(op::MEMCP4A, vec![Arg::Rel(dst), Arg::Rel(src), Arg::Imm(n)]);
        } else {
            self.emit(op::MEMCP, vec![Arg::Rel(dst), Arg::Rel(src), Arg::Imm(n)]);
        }
    }

    fn fill(&mut self, dst: u32, byte: u8, n: u32) {
        if self.mode() == Mode::M32A {
            self.emit(
                op::FPAT4A,
                vec![Arg::Rel(dst), Arg::Imm(byte as u32), Arg::Imm(n)],
            );
        } else {
            self.emit(
                op::FPAT,
                vec![Arg::Rel(dst), Arg::Imm(byte as u32), Arg::Imm(n)],
            );
        }
    }

    fn rrr(&mut self, opcode: Opcode, regs: &[u32]) {
        self.emit(opcode, regs.iter().map(|&r| Arg::Rel(r)).collect());
    }

    fn jz(&mut self, cond: u32, l: LabelId) {
        self.emit(op::JZ, vec![Arg::Rel(cond), Arg::Label(l)]);
    }

    fn jnz(&mut self, cond: u32, l: LabelId) {
        self.emit(op::JNZ, vec![Arg::Rel(cond), Arg::Label(l)]);
    }

    fn jmp(&mut self, l: LabelId) {
        self.emit(op::JMP, vec![Arg::Label(l)]);
    }

    /// Raises the fault flag: CEAC on an index below its range sets ARRAYBOUND.
    fn raise_fault(&mut self) -> Res<()> {
        let zero = self.konst(Type::I16, 0);
        let t = self.scratch(2)?;
        self.mcd(t, vec![0xFF, 0xFF]);
        self.rrr(op::CEAC, &[t, zero, zero]);
        Ok(())
    }

    // ---- analysis ------------------------------------------------------------------

    fn record_uses(&mut self) {
        let f = self.f;
        for (k, (_, inst)) in f.inst_iter().enumerate() {
            let data = f.inst(inst);
            let mut push = |v: Value, kind: UseKind| self.uses[v.index()].push((k, kind));
            match data {
                InstData::Load { addr, .. } => push(*addr, UseKind::Addr),
                InstData::Store { value, addr } => {
                    push(*value, UseKind::Value);
                    push(*addr, UseKind::Addr);
                }
                InstData::FieldAddr { base, .. } => push(*base, UseKind::Base),
                InstData::ElemAddr { base, index, .. } => {
                    push(*base, UseKind::Base);
                    push(*index, UseKind::Value);
                }
                InstData::Call { func, args } => {
                    let inst_conv = matches!(self.cx.convs[func.index()], Conv::Instance { .. });
                    for (i, a) in args.iter().enumerate() {
                        push(
                            *a,
                            if i == 0 && inst_conv {
                                UseKind::Instance
                            } else {
                                UseKind::Value
                            },
                        );
                    }
                }
                other => other.for_each_arg(|v| push(v, UseKind::Value)),
            }
        }
    }

    /// The static class of a pointer value.
    fn class_of(&mut self, v: Value) -> PtrClass {
        if let Some(c) = self.class[v.index()] {
            return c;
        }
        // Guards against cycles through block parameters (they are Dyn anyway).
        self.class[v.index()] = Some(PtrClass::Dyn);
        let c = self.compute_class(v);
        self.class[v.index()] = Some(c);
        c
    }

    fn compute_class(&mut self, v: Value) -> PtrClass {
        let f = self.f;
        match f.value_def(v) {
            ValueDef::Param(b, 0)
                if Some(b) == f.entry() && matches!(self.conv, Conv::Instance { .. }) =>
            {
                PtrClass::Rel(0)
            }
            ValueDef::Param(..) => PtrClass::Dyn,
            ValueDef::Result(i) => match f.inst(i) {
                InstData::GlobalAddr { data } => PtrClass::Abs(self.cx.data_addrs[data.index()]),
                InstData::SlotAddr { slot } => PtrClass::Rel(self.slot_offsets[slot.index()]),
                InstData::FieldAddr { base, agg, field } => {
                    let off = self.cx.layout.field_offset(*agg, *field);
                    match self.class_of(*base) {
                        PtrClass::Rel(b) => PtrClass::Rel(b + off),
                        PtrClass::Abs(b) => PtrClass::Abs(b + off),
                        _ => PtrClass::Dyn,
                    }
                }
                InstData::ElemAddr { base, agg, index } => {
                    let stride = self.cx.layout.stride(*agg);
                    let bc = self.class_of(*base);
                    if let Some(k) = self.iconst(*index) {
                        let off = (k * stride as i64) as u32;
                        return match bc {
                            PtrClass::Rel(b) => PtrClass::Rel(b.wrapping_add(off)),
                            PtrClass::Abs(b) => PtrClass::Abs(b.wrapping_add(off)),
                            _ => PtrClass::Dyn,
                        };
                    }
                    let AggDef::Array(arr) = self.cx.module.agg(*agg) else {
                        return PtrClass::Dyn;
                    };
                    let elem_scalar = matches!(arr.elem, MemType::Scalar(_));
                    let whole = self.uses[v.index()]
                        .iter()
                        .all(|&(_, k)| k == UseKind::Addr);
                    match bc {
                        PtrClass::Rel(b)
                            if elem_scalar && whole && [1, 2, 4, 8].contains(&stride) =>
                        {
                            PtrClass::Idx {
                                base: b,
                                index: *index,
                                size: stride,
                                len: arr.len,
                            }
                        }
                        _ => PtrClass::Dyn,
                    }
                }
                _ => PtrClass::Dyn,
            },
        }
    }

    fn iconst(&self, v: Value) -> Option<i64> {
        match self.f.value_def(v) {
            ValueDef::Result(i) => match self.f.inst(i) {
                InstData::Iconst { imm, .. } => Some(*imm),
                _ => None,
            },
            _ => None,
        }
    }

    /// The home of a value (allocating it on first use).
    fn home(&mut self, v: Value) -> u32 {
        if let Some(h) = self.homes[v.index()] {
            return h;
        }
        let f = self.f;
        if let ValueDef::Result(i) = f.value_def(v) {
            match f.inst(i) {
                InstData::Iconst { ty, imm } => {
                    let h = self.konst(*ty, *imm as u64);
                    self.homes[v.index()] = Some(h);
                    return h;
                }
                InstData::Fconst { ty, bits } => {
                    let h = self.konst(*ty, *bits);
                    self.homes[v.index()] = Some(h);
                    return h;
                }
                _ => {}
            }
        }
        let s = self.size(self.vty(v));
        let h = self.alloc(s, format!("?V{}", v.0));
        self.homes[v.index()] = Some(h);
        h
    }
}

/// Opcodes of the A?RD family by element size (the write form is the next opcode).
fn array_read_op(size: u32) -> Opcode {
    match size {
        1 => op::AORD,
        2 => op::ATRD,
        4 => op::AFRD,
        _ => op::AQRD,
    }
}

fn float_ty(t: Type) -> Ty {
    if t == Type::F64 {
        Ty::Lreal
    } else {
        Ty::Real
    }
}

fn bits_of(t: Type) -> u32 {
    match t {
        Type::I1 => 1,
        Type::I8 => 8,
        Type::I16 => 16,
        Type::I32 | Type::F32 => 32,
        _ => 64,
    }
}

/// The raw bits of `x` as a float of type `t`.
fn fbits(t: Type, x: f64) -> u64 {
    if t == Type::F64 {
        x.to_bits()
    } else {
        (x as f32).to_bits() as u64
    }
}

impl Fx<'_, '_> {
    fn run(&mut self, id: FuncId) -> Res<()> {
        let f = self.f;
        let Some(entry) = f.entry() else {
            return Err(self.internal("function without blocks"));
        };
        let base = self.next;
        let (params, ret, end) = signature(self.cx.layout, f, self.conv, self.mode());
        let entry_params = f.block(entry).params.clone();
        for (i, p) in params.iter().enumerate() {
            if let Some(off) = p {
                self.homes[entry_params[i].index()] = Some(base + off);
                self.names.insert(base + off, format!("?P{i}"));
            }
        }
        self.ret_home = ret.map(|r| base + r);
        if let Some(r) = self.ret_home {
            self.names.insert(r, format!("?R?{}", f.name));
        }
        self.next = base + end;
        let slots: Vec<u32> = f
            .slots
            .iter()
            .map(|s| {
                let size = self.cx.layout.size_of(s.ty);
                self.alloc(size, s.name.clone())
            })
            .collect();
        self.slot_offsets = slots;
        if let Conv::Instance { agg, .. } = self.conv {
            self.name_fields(agg, 0, "");
        }
        // The largest call area any callee without an instance needs.
        let mut area = None;
        for (_, i) in f.inst_iter() {
            if let InstData::Call { func, .. } = f.inst(i) {
                if self.cx.convs[func.index()] == Conv::Area {
                    area = Some(area.unwrap_or(0).max(self.cx.frame_sizes[func.index()]));
                }
            }
        }
        if let Some(area) = area {
            self.call_area = Some(self.alloc(area, "?LCALL".into()));
        }
        self.record_uses();
        let _ = id;
        self.fold_indexes();
        self.record_late_uses();
        self.plan_in_place();
        self.coalesce_block_params();
        // The instance pointer itself, where it is needed as a value.
        if matches!(self.conv, Conv::Instance { .. }) {
            let p = entry_params[0];
            if self.class_of(p) == PtrClass::Rel(0) && self.needs_value(p) {
                let h = self.home(p);
                self.materialize(h, PtrClass::Rel(0));
            }
        }
        let layout = f.layout.clone();
        for (bi, &b) in layout.iter().enumerate() {
            let next = layout.get(bi + 1).copied();
            self.label(self.block_labels[b.index()]);
            for &i in &f.block(b).insts {
                self.scratch_used = 0;
                self.source_line(f.spans[i.index()]);
                self.inst(i, next)?;
            }
        }
        Ok(())
    }

    fn name_fields(&mut self, agg: AggId, base: u32, prefix: &str) {
        let module = self.cx.module;
        if let AggDef::Struct(s) = module.agg(agg) {
            for (i, fld) in s.fields.iter().enumerate() {
                let off = base + self.cx.layout.field_offset(agg, i as u32);
                let name = format!("{prefix}{}", fld.name);
                if let MemType::Agg(a) = fld.ty {
                    if matches!(module.agg(a), AggDef::Struct(_)) {
                        self.name_fields(a, off, &format!("{name}."));
                    }
                }
                self.names.entry(off).or_insert(name);
            }
        }
    }

    fn source_line(&mut self, span: Option<Span>) {
        let Some(span) = span else { return };
        let Some(Some(text)) = self.cx.sources.get(span.file.0 as usize) else {
            return;
        };
        let start = (span.start as usize).min(text.len());
        let line = text[..start].bytes().filter(|&b| b == b'\n').count();
        if self.last_line == Some((span.file.0, line)) {
            return;
        }
        self.last_line = Some((span.file.0, line));
        if let Some(l) = text.lines().nth(line) {
            self.body.push(Item::Source(l.trim_end().to_string()));
        }
    }

    /// True if the pointer value `v` is needed as a number (not only to address memory
    /// statically).
    fn needs_value(&mut self, v: Value) -> bool {
        if let Some(&b) = self.needs_value.get(v.index()) {
            if b {
                return true;
            }
        }
        let uses = self.uses[v.index()].clone();
        let f = self.f;
        let insts: Vec<_> = f.inst_iter().map(|(_, i)| i).collect();
        let class = self.class_of(v);
        let mut need = false;
        for (k, kind) in uses {
            match kind {
                UseKind::Value => need = true,
                UseKind::Addr | UseKind::Late => {}
                UseKind::Instance => need |= !matches!(class, PtrClass::Rel(_)),
                UseKind::Base => {
                    if let Some(u) = f.result(insts[k]) {
                        need |= self.class_of(u) == PtrClass::Dyn;
                    }
                }
            }
        }
        self.needs_value[v.index()] = need;
        need
    }

    /// Puts the absolute address a static class stands for into `h`.
    fn materialize(&mut self, h: u32, c: PtrClass) {
        let pt = self.ptr_type();
        match c {
            PtrClass::Rel(off) => {
                self.emit(op::DPSTO, vec![Arg::Rel(h)]);
                if off != 0 {
                    let k = self.konst(pt, off as u64);
                    self.rrr(op::add(self.ptr_ty(), 2), &[h, h, k]);
                }
            }
            PtrClass::Abs(a) => {
                let n = self.mode().addr_bytes();
                self.mcd(h, a.to_le_bytes()[..n].to_vec());
            }
            PtrClass::Idx { .. } | PtrClass::Dyn => {}
        }
    }

    /// Copies an integer of `src_size` bytes at `src` to `dst_size` bytes at `dst`,
    /// keeping the low bytes or adding zero bytes.
    fn resize(&mut self, dst: u32, dst_size: u32, src: u32, src_size: u32) {
        if src_size >= dst_size {
            self.copy(dst, src, dst_size);
        } else {
            self.fill(dst, 0, dst_size);
            self.copy(dst, src, src_size);
        }
    }

    /// The copied, checked index for an A?RD/A?WR access.
    fn lac(&mut self, index: Value, len: u32) -> Res<u32> {
        let s = self.scratch(2)?;
        let (src, low) = self.folded_index.get(&index).copied().unwrap_or((index, 0));
        let ih = self.home(src);
        let isz = self.size(self.vty(src));
        self.resize(s, 2, ih, isz);
        let low = self.konst(Type::I16, low as u64);
        let span = self.konst(Type::I16, len.saturating_sub(1) as u64);
        self.rrr(op::CEAC, &[s, low, span]);
        Ok(s)
    }

    /// Records where array accesses at run-time indexes read their index (see
    /// [`UseKind::Late`]): the in-place and coalescing decisions must see those reads.
    fn record_late_uses(&mut self) {
        let f = self.f;
        for (k, (_, i)) in f.inst_iter().enumerate() {
            if let InstData::Load { addr, .. } | InstData::Store { addr, .. } = f.inst(i) {
                if let PtrClass::Idx { index, .. } = self.class_of(*addr) {
                    let src = self.folded_index.get(&index).map_or(index, |&(y, _)| y);
                    self.late_use.insert(i, src);
                    self.uses[src.index()].push((k, UseKind::Late));
                }
            }
        }
    }

    /// Finds the array indexes of the form `sext(i) - low` or `sext(i)` with `i` an
    /// INT: the copied index is then `i` and CEAC subtracts `low` (the CPDev shape), and
    /// the widening and subtraction are not computed when nothing else uses them.
    fn fold_indexes(&mut self) {
        let f = self.f;
        let def_of = |v: Value| match f.value_def(v) {
            ValueDef::Result(i) => Some(f.inst(i).clone()),
            _ => None,
        };
        let mut idx_values = Vec::new();
        for (_, i) in f.inst_iter() {
            if let (InstData::ElemAddr { .. }, Some(v)) = (f.inst(i), f.result(i)) {
                if let PtrClass::Idx { index, len, .. } = self.class_of(v) {
                    idx_values.push((index, len));
                }
            }
        }
        for (index, len) in idx_values {
            if self.folded_index.contains_key(&index) {
                continue;
            }
            let (x, low) = match def_of(index) {
                Some(InstData::Binary {
                    op: BinaryOp::Isub,
                    args,
                }) => match self.iconst(args[1]) {
                    Some(l) => (args[0], l),
                    None => continue,
                },
                _ => (index, 0),
            };
            let Some(InstData::Convert {
                op: ConvOp::Sext,
                arg: y,
                ..
            }) = def_of(x)
            else {
                continue;
            };
            let hi = low + len as i64 - 1;
            if self.vty(y) != Type::I16 || low < i16::MIN as i64 || hi > i16::MAX as i64 {
                continue;
            }
            self.folded_index.insert(index, (y, low));
        }
        // A folded index (and its widening) is computed only if something else uses it.
        let folded: Vec<Value> = self.folded_index.keys().copied().collect();
        for index in folded {
            let only_arrays = self.uses[index.index()].iter().all(|&(k, _)| {
                let i = f.inst_iter().nth(k).map(|(_, i)| i);
                i.and_then(|i| f.result(i))
                    .is_some_and(|r| matches!(self.class[r.index()], Some(PtrClass::Idx { .. })))
            });
            if !only_arrays {
                continue;
            }
            self.skip[index.index()] = true;
            if let Some(InstData::Binary {
                op: BinaryOp::Isub,
                args,
            }) = def_of(index)
            {
                if self.uses[args[0].index()].len() == 1 {
                    self.skip[args[0].index()] = true;
                }
            }
        }
    }

    fn dp_op(&self, write: bool) -> Opcode {
        match (self.mode() == Mode::M32A, write) {
            (false, false) => op::DPRDL,
            (false, true) => op::DPWRL,
            (true, false) => op::DPRDL4A,
            (true, true) => op::DPWRL4A,
        }
    }

    fn load(&mut self, dst: u32, addr: Value, n: u32) -> Res<()> {
        match self.class_of(addr) {
            PtrClass::Rel(o) => self.copy(dst, o, n),
            PtrClass::Abs(a) => {
                self.emit(op::mmv(n as u8, false), vec![Arg::Rel(dst), Arg::Abs(a)])
            }
            PtrClass::Idx {
                base,
                index,
                size,
                len,
            } => {
                let l = self.lac(index, len)?;
                let _ = size;
                self.rrr(array_read_op(n), &[dst, base, l]);
            }
            PtrClass::Dyn => {
                let p = self.home(addr);
                let o = self.dp_op(false);
                self.emit(o, vec![Arg::Rel(dst), Arg::Rel(p), Arg::Imm(n)]);
            }
        }
        Ok(())
    }

    fn store(&mut self, src: u32, addr: Value, n: u32) -> Res<()> {
        match self.class_of(addr) {
            PtrClass::Rel(o) => self.copy(o, src, n),
            PtrClass::Abs(a) => self.emit(op::mmv(n as u8, true), vec![Arg::Abs(a), Arg::Rel(src)]),
            PtrClass::Idx {
                base, index, len, ..
            } => {
                let l = self.lac(index, len)?;
                let w = Opcode(array_read_op(n).0 + 1);
                self.rrr(w, &[src, base, l]);
            }
            PtrClass::Dyn => {
                let p = self.home(addr);
                let o = self.dp_op(true);
                self.emit(o, vec![Arg::Rel(src), Arg::Rel(p), Arg::Imm(n)]);
            }
        }
        Ok(())
    }

    fn inst(&mut self, i: plcc_ir::entities::Inst, next: Option<Block>) -> Res<()> {
        let f = self.f;
        let data = f.inst(i).clone();
        let res = f.result(i);
        let span = f.spans[i.index()];
        if res.is_some_and(|v| self.skip[v.index()]) {
            return Ok(());
        }
        match data {
            InstData::Iconst { .. } | InstData::Fconst { .. } => {
                if let Some(v) = res {
                    self.home(v);
                }
            }
            InstData::GlobalAddr { .. }
            | InstData::SlotAddr { .. }
            | InstData::FieldAddr { .. }
            | InstData::ElemAddr { .. } => {
                let v = res.expect("address result");
                let c = self.class_of(v);
                match c {
                    PtrClass::Rel(_) | PtrClass::Abs(_) => {
                        if self.needs_value(v) {
                            let h = self.home(v);
                            self.materialize(h, c);
                        }
                    }
                    PtrClass::Idx { .. } => {}
                    PtrClass::Dyn => self.dyn_addr(v, &data)?,
                }
            }
            InstData::Load { ty, addr } => {
                let h = self.home(res.expect("load result"));
                let n = self.size(ty);
                self.load(h, addr, n)?;
            }
            InstData::Store { value, addr } => {
                let n = self.size(self.vty(value));
                let s = self.home(value);
                self.store(s, addr, n)?;
            }
            InstData::Unary { op: uop, arg } => {
                let v = res.expect("result");
                self.unary(uop, arg, v, span)?;
            }
            InstData::Binary { op: bop, args } => {
                let v = res.expect("result");
                self.binary(bop, args[0], args[1], v, span)?;
            }
            InstData::Icmp { cond, args } => {
                let t = self.vty(args[0]);
                let signed = matches!(cond, IntCC::Slt | IntCC::Sle | IntCC::Sgt | IntCC::Sge);
                let ty = int_ty(if t == Type::Ptr { self.ptr_type() } else { t }, signed);
                let g = match cond {
                    IntCC::Eq => op::group::EQ,
                    IntCC::Ne => op::group::NE,
                    IntCC::Slt | IntCC::Ult => op::group::LT,
                    IntCC::Sle | IntCC::Ule => op::group::LE,
                    IntCC::Sgt | IntCC::Ugt => op::group::GT,
                    IntCC::Sge | IntCC::Uge => op::group::GE,
                };
                let d = self.home(res.expect("result"));
                let a = self.home(args[0]);
                let b = self.home(args[1]);
                self.rrr(op::cmp(g, ty), &[d, a, b]);
            }
            InstData::Fcmp { cond, args } => {
                let ty = float_ty(self.vty(args[0]));
                let g = match cond {
                    FloatCC::Eq => op::group::EQ,
                    FloatCC::Ne => op::group::NE,
                    FloatCC::Lt => op::group::LT,
                    FloatCC::Le => op::group::LE,
                    FloatCC::Gt => op::group::GT,
                    FloatCC::Ge => op::group::GE,
                };
                let d = self.home(res.expect("result"));
                let a = self.home(args[0]);
                let b = self.home(args[1]);
                self.rrr(op::cmp(g, ty), &[d, a, b]);
            }
            InstData::Convert { op: cop, ty, arg } => {
                let v = res.expect("result");
                self.convert(cop, ty, arg, v)?;
            }
            InstData::Select {
                cond,
                if_true,
                if_false,
            } => {
                let t = self.vty(if_true);
                let ty = match t {
                    Type::F32 | Type::F64 => float_ty(t),
                    Type::Ptr => self.ptr_ty(),
                    _ => int_ty(t, false),
                };
                let d = self.home(res.expect("result"));
                let c = self.home(cond);
                let a = self.home(if_true);
                let b = self.home(if_false);
                self.rrr(op::sel(ty), &[d, c, b, a]);
            }
            InstData::Call { func, args } => self.call(func, &args, res)?,
            InstData::Intrinsic { op: iop, .. } => match iop {
                Intrinsic::ClockMs => {
                    let d = self.home(res.expect("result"));
                    self.emit(op::CUR_TIME, vec![Arg::Rel(d)]);
                }
                Intrinsic::ClockNs => {
                    let d = self.home(res.expect("result"));
                    let t = self.scratch(8)?;
                    self.fill(t, 0, 8);
                    self.emit(op::CUR_TIME, vec![Arg::Rel(t)]);
                    let k = self.konst(Type::I64, 1_000_000);
                    self.rrr(op::mul(Ty::Lword, 2), &[d, t, k]);
                }
                Intrinsic::RaiseFault => self.raise_fault()?,
                Intrinsic::StopRequested => {
                    // plcc's VM stops a runaway scan itself; the program never asks.
                    let d = self.home(res.expect("result"));
                    self.mcd(d, vec![0]);
                }
            },
            InstData::Jump { dest } => {
                self.edge(&dest)?;
                if Some(dest.block) != next {
                    self.jmp(self.block_labels[dest.block.index()]);
                }
            }
            InstData::Brif {
                cond,
                then_dest,
                else_dest,
            } => {
                let c = self.home(cond);
                let tl = self.block_labels[then_dest.block.index()];
                let el = self.block_labels[else_dest.block.index()];
                let t_copies = self.has_copies(&then_dest);
                let e_copies = self.has_copies(&else_dest);
                if !t_copies && !e_copies {
                    if Some(then_dest.block) == next {
                        self.jz(c, el);
                    } else {
                        self.jnz(c, tl);
                        if Some(else_dest.block) != next {
                            self.jmp(el);
                        }
                    }
                } else if !t_copies {
                    self.jnz(c, tl);
                    self.edge(&else_dest)?;
                    if Some(else_dest.block) != next {
                        self.jmp(el);
                    }
                } else if !e_copies {
                    self.jz(c, el);
                    self.edge(&then_dest)?;
                    if Some(then_dest.block) != next {
                        self.jmp(tl);
                    }
                } else {
                    let le = self.new_label("E");
                    self.jz(c, le);
                    self.edge(&then_dest)?;
                    self.jmp(tl);
                    self.label(le);
                    self.edge(&else_dest)?;
                    if Some(else_dest.block) != next {
                        self.jmp(el);
                    }
                }
            }
            InstData::Return { value } => {
                if let (Some(v), Some(r)) = (value, self.ret_home) {
                    let n = self.size(self.vty(v));
                    let h = self.home(v);
                    self.copy(r, h, n);
                }
                self.emit(op::RETURN, vec![]);
            }
        }
        Ok(())
    }

    fn has_copies(&mut self, bc: &BlockCall) -> bool {
        let params = self.f.block(bc.block).params.clone();
        params.iter().zip(&bc.args).any(|(p, a)| {
            let ph = self.home(*p);
            let ah = self.home(*a);
            ph != ah
        })
    }

    /// The copies of a branch's arguments into the destination's parameters, as one
    /// parallel copy.
    fn edge(&mut self, bc: &BlockCall) -> Res<()> {
        let params = self.f.block(bc.block).params.clone();
        let mut moves = Vec::new();
        for (p, a) in params.iter().zip(&bc.args) {
            let n = self.size(self.vty(*p));
            let ph = self.home(*p);
            let ah = self.home(*a);
            if ph != ah {
                moves.push((*p, ph, ah, n));
            }
        }
        // A parallel copy in sequence: a move goes once no pending move still reads
        // its destination; a cycle is broken through the first move's shadow.
        let mut pending: Vec<(Value, u32, u32, u32)> = moves;
        while !pending.is_empty() {
            let ready = pending.iter().position(|&(_, d, _, n)| {
                !pending
                    .iter()
                    .any(|&(_, d2, s, n2)| d2 != d && Self::overlaps((s, n2), (d, n)))
            });
            match ready {
                Some(k) => {
                    let (_, d, src, n) = pending.remove(k);
                    self.copy(d, src, n);
                }
                None => {
                    let (p, d, src, n) = pending[0];
                    let sh = match self.shadows.get(&p) {
                        Some(&sh) => sh,
                        None => {
                            let sh = self.alloc(n, format!("?S{}", p.0));
                            self.shadows.insert(p, sh);
                            sh
                        }
                    };
                    // Whoever reads `d` reads the shadow instead.
                    self.copy(sh, d, n);
                    for m in pending.iter_mut() {
                        if m.2 == d {
                            m.2 = sh;
                        }
                    }
                    let _ = src;
                }
            }
        }
        Ok(())
    }

    fn dyn_addr(&mut self, v: Value, data: &InstData) -> Res<()> {
        let pt = self.ptr_type();
        let pty = self.ptr_ty();
        let h = self.home(v);
        match *data {
            InstData::FieldAddr { base, agg, field } => {
                let off = self.cx.layout.field_offset(agg, field);
                let b = self.ptr_value(base);
                if off == 0 {
                    let n = self.size(pt);
                    self.copy(h, b, n);
                } else {
                    let k = self.konst(pt, off as u64);
                    self.rrr(op::add(pty, 2), &[h, b, k]);
                }
            }
            InstData::ElemAddr { base, agg, index } => {
                let stride = self.cx.layout.stride(agg);
                let b = self.ptr_value(base);
                let n = self.size(pt);
                let s = self.scratch(n)?;
                let ih = self.home(index);
                let isz = self.size(self.vty(index));
                self.resize(s, n, ih, isz);
                if stride != 1 {
                    let k = self.konst(pt, stride as u64);
                    self.rrr(op::mul(pty, 2), &[s, s, k]);
                }
                self.rrr(op::add(pty, 2), &[h, b, s]);
            }
            // Pointers from loads, calls, parameters and block parameters already
            // have their value in their home.
            _ => {}
        }
        Ok(())
    }

    /// The home of a pointer value, which holds its absolute address.
    fn ptr_value(&mut self, v: Value) -> u32 {
        self.home(v)
    }

    fn call(&mut self, g: FuncId, args: &[Value], res: Option<Value>) -> Res<()> {
        let callee = self.cx.module.func(g);
        let conv = self.cx.convs[g.index()];
        let (params, ret, _) = signature(self.cx.layout, callee, conv, self.mode());
        let label = self.cx.entry_labels[g.index()];
        match conv {
            Conv::Instance { temp_base, .. } => {
                let inst = args[0];
                match self.class_of(inst) {
                    PtrClass::Rel(off) => {
                        for (i, a) in args.iter().enumerate().skip(1) {
                            let n = self.size(self.vty(*a));
                            let ah = self.home(*a);
                            let p = params[i].expect("parameter offset");
                            self.copy(off + temp_base + p, ah, n);
                        }
                        self.emit(op::CALB, vec![Arg::Rel(off), Arg::Label(label)]);
                        if let (Some(v), Some(r)) = (res, ret) {
                            let n = self.size(self.vty(v));
                            let h = self.home(v);
                            self.copy(h, off + temp_base + r, n);
                        }
                    }
                    _ => {
                        let p = self.ptr_value(inst);
                        let pt = self.ptr_type();
                        let pn = self.size(pt);
                        let q = self.scratch(pn)?;
                        for (i, a) in args.iter().enumerate().skip(1) {
                            let n = self.size(self.vty(*a));
                            let ah = self.home(*a);
                            let k = self.konst(pt, (temp_base + params[i].expect("offset")) as u64);
                            self.rrr(op::add(self.ptr_ty(), 2), &[q, p, k]);
                            let o = self.dp_op(true);
                            self.emit(o, vec![Arg::Rel(ah), Arg::Rel(q), Arg::Imm(n)]);
                        }
                        self.emit(op::CALBR, vec![Arg::Rel(p), Arg::Label(label)]);
                        if let (Some(v), Some(r)) = (res, ret) {
                            let n = self.size(self.vty(v));
                            let h = self.home(v);
                            let k = self.konst(pt, (temp_base + r) as u64);
                            self.rrr(op::add(self.ptr_ty(), 2), &[q, p, k]);
                            let o = self.dp_op(false);
                            self.emit(o, vec![Arg::Rel(h), Arg::Rel(q), Arg::Imm(n)]);
                        }
                    }
                }
            }
            Conv::Area => {
                let area = self
                    .call_area
                    .ok_or_else(|| self.internal("call area missing"))?;
                for (i, a) in args.iter().enumerate() {
                    let n = self.size(self.vty(*a));
                    let ah = self.home(*a);
                    let p = params[i].expect("parameter offset");
                    self.copy(area + p, ah, n);
                }
                self.emit(op::CALF, vec![Arg::Rel(area), Arg::Label(label)]);
                if let (Some(v), Some(r)) = (res, ret) {
                    let n = self.size(self.vty(v));
                    let h = self.home(v);
                    self.copy(h, area + r, n);
                }
            }
        }
        Ok(())
    }
}

impl Fx<'_, '_> {
    fn unsupported(&self, what: &str, span: Option<Span>) -> Box<Diagnostic> {
        let msg = format!("{what} is not supported on the vmasm target");
        Box::new(match span {
            Some(s) => Diagnostic::error(crate::codes::E_UNSUPPORTED, msg, s),
            None => Diagnostic::error_nowhere(crate::codes::E_UNSUPPORTED, msg),
        })
    }

    fn unary(&mut self, uop: UnaryOp, arg: Value, v: Value, span: Option<Span>) -> Res<()> {
        let t = self.vty(arg);
        let d = self.home(v);
        let a = self.home(arg);
        let n = self.size(t);
        let lreal = t == Type::F64;
        let math = |base: u8| Opcode::new(op::group::MATH, base + lreal as u8);
        let opcode = match uop {
            UnaryOp::Ineg => Opcode::new(op::group::NEG, int_ty(t, true) as u8),
            UnaryOp::Bnot => Opcode::new(op::group::NEG, 0x10 | logic_code(n, t == Type::I1)),
            UnaryOp::Iabs => Opcode::new(op::group::MATH, 0x10 | int_ty(t, true) as u8),
            UnaryOp::Fneg => Opcode::new(op::group::NEG, if lreal { 9 } else { 7 }),
            UnaryOp::Fabs => Opcode::new(op::group::MATH, 0x10 | float_ty(t) as u8),
            UnaryOp::Fsqrt => math(0x20),
            UnaryOp::Ln => math(0x22),
            UnaryOp::Log10 => math(0x24),
            UnaryOp::Exp => math(0x26),
            UnaryOp::Sin => math(0x28),
            UnaryOp::Cos => math(0x2A),
            UnaryOp::Tan => math(0x2C),
            UnaryOp::Asin => math(0x2E),
            UnaryOp::Acos => math(0x30),
            UnaryOp::Atan => math(0x32),
            UnaryOp::Fnearest | UnaryOp::Ftrunc | UnaryOp::Ffloor | UnaryOp::Fceil => {
                return self.round(uop, t, a, d);
            }
        };
        let _ = span;
        self.rrr(opcode, &[d, a]);
        Ok(())
    }

    /// Float rounding to an integral float: through TRUNC where the value has a
    /// fraction, keeping the sign of zero.
    fn round(&mut self, uop: UnaryOp, t: Type, x: u32, d: u32) -> Res<()> {
        let ft = float_ty(t);
        let n = self.size(t);
        let it = if t == Type::F64 { Type::I64 } else { Type::I32 };
        let uty = int_ty(it, false);
        let lend = self.new_label("R");
        let lcopy = self.new_label("R");
        let a = self.scratch(n)?;
        let c = self.scratch(1)?;
        self.rrr(Opcode::new(op::group::MATH, 0x10 | ft as u8), &[a, x]);
        let big = self.konst(
            t,
            fbits(
                t,
                if t == Type::F64 {
                    4503599627370496.0
                } else {
                    8388608.0
                },
            ),
        );
        self.rrr(op::cmp(op::group::LT, ft), &[c, a, big]);
        self.jz(c, lcopy);
        let ti = self.scratch(n)?;
        let lr = t == Type::F64;
        self.rrr(Opcode::new(op::group::MATH, 0x34 + lr as u8), &[ti, x]);
        self.rrr(
            Opcode::new(op::group::CONV, if lr { 0x0F } else { 0x01 }),
            &[d, ti],
        );
        let sign = self.konst(it, 1u64 << (bits_of(t) - 1));
        let s = self.scratch(n)?;
        let code = logic_code(n, false);
        self.rrr(Opcode::new(op::group::AND, 0x20 | code), &[s, x, sign]);
        self.rrr(Opcode::new(op::group::OR, 0x20 | code), &[d, d, s]);
        let _ = uty;
        let one = self.konst(t, fbits(t, 1.0));
        match uop {
            UnaryOp::Ftrunc => {}
            UnaryOp::Ffloor => {
                self.rrr(op::cmp(op::group::GT, ft), &[c, d, x]);
                self.jz(c, lend);
                self.rrr(op::sub(ft), &[d, d, one]);
            }
            UnaryOp::Fceil => {
                self.rrr(op::cmp(op::group::LT, ft), &[c, d, x]);
                self.jz(c, lend);
                self.rrr(op::add(ft, 2), &[d, d, one]);
            }
            _ => {
                // Ties to even: the fraction decides, and at exactly one half the
                // parity of the truncated integer.
                let half = self.konst(t, fbits(t, 0.5));
                let mhalf = self.konst(t, fbits(t, -0.5));
                let fr = self.scratch(n)?;
                let odd = self.scratch(1)?;
                let one8 = self.konst(Type::I8, 1);
                let (lup, ldown, lneg) = (
                    self.new_label("R"),
                    self.new_label("R"),
                    self.new_label("R"),
                );
                self.rrr(op::sub(ft), &[fr, x, d]);
                self.rrr(Opcode::new(op::group::AND, 0x21), &[odd, ti, one8]);
                self.rrr(op::cmp(op::group::GT, ft), &[c, fr, half]);
                self.jnz(c, lup);
                self.rrr(op::cmp(op::group::LT, ft), &[c, fr, mhalf]);
                self.jnz(c, ldown);
                self.rrr(op::cmp(op::group::EQ, ft), &[c, fr, half]);
                self.jz(c, lneg);
                self.jnz(odd, lup);
                self.jmp(lend);
                self.label(lneg);
                self.rrr(op::cmp(op::group::EQ, ft), &[c, fr, mhalf]);
                self.jz(c, lend);
                self.jz(odd, lend);
                self.label(ldown);
                self.rrr(op::sub(ft), &[d, d, one]);
                self.jmp(lend);
                self.label(lup);
                self.rrr(op::add(ft, 2), &[d, d, one]);
            }
        }
        self.jmp(lend);
        self.label(lcopy);
        self.copy(d, x, n);
        self.label(lend);
        Ok(())
    }

    fn binary(
        &mut self,
        bop: BinaryOp,
        av: Value,
        bv: Value,
        v: Value,
        span: Option<Span>,
    ) -> Res<()> {
        let t = self.vty(av);
        let d = self.home(v);
        let a = self.home(av);
        let b = self.home(bv);
        let n = self.size(t);
        let u = int_ty(t, false);
        let is_bool = t == Type::I1;
        let logic = |g: u8, xor: bool| {
            let code = logic_code(n, is_bool);
            let code = if xor && code >= 3 { code + 1 } else { code };
            Opcode::new(g, 0x20 | code)
        };
        let opcode = match bop {
            BinaryOp::Iadd => op::add(u, 2),
            BinaryOp::Isub => op::sub(u),
            BinaryOp::Imul => op::mul(u, 2),
            BinaryOp::Band => logic(op::group::AND, false),
            BinaryOp::Bor => logic(op::group::OR, false),
            BinaryOp::Bxor => logic(op::group::XOR, true),
            BinaryOp::Fadd => op::add(float_ty(t), 2),
            BinaryOp::Fsub => op::sub(float_ty(t)),
            BinaryOp::Fmul => op::mul(float_ty(t), 2),
            BinaryOp::Fdiv => op::div(float_ty(t)),
            BinaryOp::Fpow => Opcode::new(op::group::MATH, if t == Type::F64 { 2 } else { 1 }),
            BinaryOp::Fatan2 => return Err(self.unsupported("ATAN2", span)),
            BinaryOp::Sdiv | BinaryOp::Srem | BinaryOp::Udiv | BinaryOp::Urem => {
                return self.divide(bop, t, d, a, b, bv);
            }
            BinaryOp::Ishl | BinaryOp::Ushr | BinaryOp::Sshr | BinaryOp::Rotl | BinaryOp::Rotr => {
                return self.shift(bop, t, d, a, b, bv);
            }
        };
        self.rrr(opcode, &[d, a, b]);
        Ok(())
    }

    /// Division and remainder with the IR's guards: by zero gives 0 and the fault
    /// flag; `MIN / -1` wraps (the C VM would trap on both).
    fn divide(&mut self, bop: BinaryOp, t: Type, d: u32, a: u32, b: u32, bv: Value) -> Res<()> {
        let signed = matches!(bop, BinaryOp::Sdiv | BinaryOp::Srem);
        let rem = matches!(bop, BinaryOp::Srem | BinaryOp::Urem);
        let ty = int_ty(t, signed);
        let u = int_ty(t, false);
        let n = self.size(t);
        let opc = if rem { op::modulo(ty) } else { op::div(ty) };
        let k = self.iconst(bv);
        let wide = n >= 4 && signed;
        if k == Some(0) {
            self.fill(d, 0, n);
            return self.raise_fault();
        }
        if let Some(k) = k {
            if !(wide && k == -1) {
                self.rrr(opc, &[d, a, b]);
                return Ok(());
            }
        }
        let lend = self.new_label("D");
        let c = self.scratch(1)?;
        let zero = self.konst(t, 0);
        if k.is_none() {
            let lok = self.new_label("D");
            self.rrr(op::cmp(op::group::NE, u), &[c, b, zero]);
            self.jnz(c, lok);
            self.fill(d, 0, n);
            self.raise_fault()?;
            self.jmp(lend);
            self.label(lok);
        }
        if wide {
            let ldiv = self.new_label("D");
            let m1 = self.konst(t, u64::MAX);
            self.rrr(op::cmp(op::group::EQ, u), &[c, b, m1]);
            self.jz(c, ldiv);
            if rem {
                self.fill(d, 0, n);
            } else {
                self.rrr(op::sub(u), &[d, zero, a]);
            }
            self.jmp(lend);
            self.label(ldiv);
        }
        self.rrr(opc, &[d, a, b]);
        self.label(lend);
        Ok(())
    }

    /// Shifts and rotates with the IR's rules for counts of at least the width, and
    /// the arithmetic right shift the VM lacks (through XOR with the sign mask).
    fn shift(&mut self, bop: BinaryOp, t: Type, d: u32, a: u32, cnt: u32, cv: Value) -> Res<()> {
        let n = self.size(t);
        let w = bits_of(t) as u64;
        let code = logic_code(n, false);
        let u = int_ty(t, false);
        let kind = match bop {
            BinaryOp::Ishl => 0x00,
            BinaryOp::Ushr | BinaryOp::Sshr => 0x10,
            BinaryOp::Rotl => 0x20,
            _ => 0x30,
        };
        let opc = Opcode::new(op::group::SHIFT, kind | code);
        let mask = if n >= 8 {
            u64::MAX
        } else {
            (1u64 << (n * 8)) - 1
        };
        let k = self.iconst(cv).map(|k| k as u64 & mask);
        match bop {
            BinaryOp::Rotl | BinaryOp::Rotr => {
                let c16 = match k {
                    Some(k) => self.konst(Type::I16, k % w),
                    None => {
                        let m = self.scratch(n)?;
                        let wm1 = self.konst(t, w - 1);
                        self.rrr(Opcode::new(op::group::AND, 0x20 | code), &[m, cnt, wm1]);
                        let c16 = self.scratch(2)?;
                        self.resize(c16, 2, m, n);
                        c16
                    }
                };
                self.rrr(opc, &[d, a, c16]);
            }
            BinaryOp::Ishl | BinaryOp::Ushr => match k {
                Some(k) if k < w => {
                    let c16 = self.konst(Type::I16, k);
                    self.rrr(opc, &[d, a, c16]);
                }
                Some(_) => self.fill(d, 0, n),
                None => {
                    let c = self.scratch(1)?;
                    let wk = self.konst(t, w);
                    let (lz, lend) = (self.new_label("S"), self.new_label("S"));
                    self.rrr(op::cmp(op::group::LT, u), &[c, cnt, wk]);
                    self.jz(c, lz);
                    let c16 = self.scratch(2)?;
                    self.resize(c16, 2, cnt, n);
                    self.rrr(opc, &[d, a, c16]);
                    self.jmp(lend);
                    self.label(lz);
                    self.fill(d, 0, n);
                    self.label(lend);
                }
            },
            _ => {
                // sshr: x XOR s, shifted logically, XOR s again (s = all sign bits).
                let s = self.scratch(n)?;
                let neg = self.scratch(1)?;
                let zero = self.konst(t, 0);
                let ones = self.konst(t, u64::MAX);
                self.rrr(op::cmp(op::group::LT, int_ty(t, true)), &[neg, a, zero]);
                self.rrr(op::sel(u), &[s, neg, zero, ones]);
                let c16 = match k {
                    Some(k) => self.konst(Type::I16, k.min(w - 1)),
                    None => {
                        let c = self.scratch(1)?;
                        let wk = self.konst(t, w);
                        self.rrr(op::cmp(op::group::LT, u), &[c, cnt, wk]);
                        let c16 = self.scratch(2)?;
                        self.resize(c16, 2, cnt, n);
                        let wm1 = self.konst(Type::I16, w - 1);
                        self.rrr(op::sel(Ty::Int), &[c16, c, wm1, c16]);
                        c16
                    }
                };
                let x = self.scratch(n)?;
                let xor = Opcode::new(
                    op::group::XOR,
                    0x20 | if code >= 3 { code + 1 } else { code },
                );
                self.rrr(xor, &[x, a, s]);
                self.rrr(opc, &[x, x, c16]);
                self.rrr(xor, &[d, x, s]);
            }
        }
        Ok(())
    }

    /// Sign-extends `src` (type `from`) into `dst` (type `to`).
    fn sext(&mut self, dst: u32, to: Type, src: u32, from: Type) {
        if from == Type::I16 && to == Type::I32 {
            self.rrr(Opcode::new(op::group::CONV, 0x0C), &[dst, src]);
            return;
        }
        let (dn, sn) = (self.size(to), self.size(from));
        self.resize(dst, dn, src, sn);
        let m = self.konst(to, 1u64 << (bits_of(from) - 1));
        let u = int_ty(to, false);
        let code = logic_code(dn, false);
        let xor = Opcode::new(
            op::group::XOR,
            0x20 | if code >= 3 { code + 1 } else { code },
        );
        self.rrr(xor, &[dst, dst, m]);
        self.rrr(op::sub(u), &[dst, dst, m]);
    }

    fn convert(&mut self, cop: ConvOp, to: Type, arg: Value, v: Value) -> Res<()> {
        let from = self.vty(arg);
        let d = self.home(v);
        let a = self.home(arg);
        let (dn, sn) = (self.size(to), self.size(from));
        let conv = |f: u8| Opcode::new(op::group::CONV, f);
        match cop {
            ConvOp::Sext => self.sext(d, to, a, from),
            ConvOp::Uext => self.resize(d, dn, a, sn),
            ConvOp::Itrunc if to == Type::I1 => {
                let one = self.konst(Type::I8, 1);
                self.rrr(Opcode::new(op::group::AND, 0x21), &[d, a, one]);
            }
            ConvOp::Itrunc | ConvOp::Bitcast => self.copy(d, a, dn),
            ConvOp::Fpromote => self.rrr(conv(0x0D), &[d, a]),
            ConvOp::Fdemote => self.rrr(conv(0x0E), &[d, a]),
            ConvOp::SiToF | ConvOp::UiToF => {
                let signed = cop == ConvOp::SiToF;
                let wide = self.int_to_f64_or_direct(d, to, a, from, signed)?;
                if let Some(t) = wide {
                    // Only LINT_TO_LREAL takes 64 bits: a REAL result rounds twice.
                    self.rrr(conv(0x0E), &[d, t]);
                }
            }
            ConvOp::FToSi | ConvOp::FToUi => {
                self.float_to_int(d, to, a, from, cop == ConvOp::FToSi)?
            }
        }
        Ok(())
    }

    /// Integer to float. Writes `d` directly, or returns a scratch LREAL that still
    /// has to be narrowed to REAL.
    fn int_to_f64_or_direct(
        &mut self,
        d: u32,
        to: Type,
        a: u32,
        from: Type,
        signed: bool,
    ) -> Res<Option<u32>> {
        let conv = |f: u8| Opcode::new(op::group::CONV, f);
        let sn = self.size(from);
        if to == Type::F32 {
            match (from, signed) {
                (Type::I16, true) => {
                    self.rrr(conv(0x00), &[d, a]);
                    return Ok(None);
                }
                (Type::I8, true) => {
                    let t = self.scratch(2)?;
                    self.sext(t, Type::I16, a, from);
                    self.rrr(conv(0x00), &[d, t]);
                    return Ok(None);
                }
                (Type::I32, true) => {
                    self.rrr(conv(0x01), &[d, a]);
                    return Ok(None);
                }
                (Type::I32, false) => {
                    self.rrr(conv(0x10), &[d, a]);
                    return Ok(None);
                }
                (Type::I8 | Type::I16, false) => {
                    let t = self.scratch(4)?;
                    self.resize(t, 4, a, sn);
                    self.rrr(conv(0x01), &[d, t]);
                    return Ok(None);
                }
                _ => {}
            }
        }
        let target = if to == Type::F32 { self.scratch(8)? } else { d };
        let l = if from == Type::I64 && to == Type::F32 {
            self.sticky_low_bits(a, signed)?
        } else if from == Type::I64 {
            a
        } else {
            let t = self.scratch(8)?;
            if signed {
                self.sext(t, Type::I64, a, from);
            } else {
                self.resize(t, 8, a, sn);
            }
            t
        };
        if signed || from != Type::I64 {
            self.rrr(conv(0x0F), &[target, l]);
        } else {
            // ULINT: halve (keeping the low bit for rounding) when the top bit is set.
            let c = self.scratch(1)?;
            let zero = self.konst(Type::I64, 0);
            let (lbig, lend) = (self.new_label("U"), self.new_label("U"));
            self.rrr(op::cmp(op::group::LT, Ty::Lint), &[c, l, zero]);
            self.jnz(c, lbig);
            self.rrr(conv(0x0F), &[target, l]);
            self.jmp(lend);
            self.label(lbig);
            let h = self.scratch(8)?;
            let b = self.scratch(8)?;
            let one16 = self.konst(Type::I16, 1);
            let one = self.konst(Type::I64, 1);
            self.rrr(Opcode::new(op::group::SHIFT, 0x14), &[h, l, one16]);
            self.rrr(Opcode::new(op::group::AND, 0x24), &[b, l, one]);
            self.rrr(Opcode::new(op::group::OR, 0x24), &[h, h, b]);
            self.rrr(conv(0x0F), &[target, h]);
            self.rrr(op::add(Ty::Lreal, 2), &[target, target, target]);
            self.label(lend);
        }
        Ok(if to == Type::F32 { Some(target) } else { None })
    }

    /// For a 64-bit integer going to REAL through LREAL: where it has more than 53
    /// significant bits, replaces its low 12 bits by one marker bit, so that the
    /// LREAL is exact and the one rounding to REAL is the correct one.
    fn sticky_low_bits(&mut self, a: u32, signed: bool) -> Res<u32> {
        let x = self.scratch(8)?;
        self.copy(x, a, 8);
        let c = self.scratch(1)?;
        let (lbig, lend) = (self.new_label("K"), self.new_label("K"));
        let t = if signed { Ty::Lint } else { Ty::Lword };
        let hi = self.konst(Type::I64, 1u64 << 53);
        self.rrr(op::cmp(op::group::GE, t), &[c, x, hi]);
        self.jnz(c, lbig);
        if signed {
            let lo = self.konst(Type::I64, (-(1i64 << 53)) as u64);
            self.rrr(op::cmp(op::group::LE, t), &[c, x, lo]);
            self.jnz(c, lbig);
        }
        self.jmp(lend);
        self.label(lbig);
        let low = self.scratch(8)?;
        let m = self.konst(Type::I64, 0xFFF);
        let keep = self.konst(Type::I64, !0xFFFu64);
        let zero = self.konst(Type::I64, 0);
        let marker = self.konst(Type::I64, 0x800);
        self.rrr(Opcode::new(op::group::AND, 0x24), &[low, x, m]);
        self.rrr(Opcode::new(op::group::AND, 0x24), &[x, x, keep]);
        self.rrr(op::cmp(op::group::NE, Ty::Lword), &[c, low, zero]);
        self.jz(c, lend);
        self.rrr(Opcode::new(op::group::OR, 0x24), &[x, x, marker]);
        self.label(lend);
        Ok(x)
    }

    /// Float to integer: toward zero, saturating, NaN gives 0 (the VM's conversions
    /// are C casts, undefined out of range, so the range is checked first).
    fn float_to_int(&mut self, d: u32, to: Type, x: u32, from: Type, signed: bool) -> Res<()> {
        let ft = float_ty(from);
        let dn = self.size(to);
        let w = bits_of(to);
        let (lo, hi) = if signed {
            (-(2f64.powi(w as i32 - 1)), 2f64.powi(w as i32 - 1))
        } else {
            (0.0, 2f64.powi(w as i32))
        };
        let (min, max): (u64, u64) = if signed {
            (1u64 << (w - 1), (1u64 << (w - 1)) - 1)
        } else {
            (0, if w == 64 { u64::MAX } else { (1u64 << w) - 1 })
        };
        let c = self.scratch(1)?;
        let (lzero, lmax, lmin, lend) = (
            self.new_label("F"),
            self.new_label("F"),
            self.new_label("F"),
            self.new_label("F"),
        );
        self.rrr(op::cmp(op::group::NE, ft), &[c, x, x]);
        self.jnz(c, lzero);
        let hk = self.konst(from, fbits(from, hi));
        self.rrr(op::cmp(op::group::GE, ft), &[c, x, hk]);
        self.jnz(c, lmax);
        let lk = self.konst(from, fbits(from, lo));
        self.rrr(op::cmp(op::group::LE, ft), &[c, x, lk]);
        self.jnz(c, lmin);
        // In range: truncate.
        let trunc_real = Opcode::new(op::group::MATH, 0x34);
        let trunc_lreal = Opcode::new(op::group::MATH, 0x35);
        if from == Type::F32 && w <= 32 && (signed || w < 32) {
            let t = self.scratch(4)?;
            self.rrr(trunc_real, &[t, x]);
            self.copy(d, t, dn);
        } else if from == Type::F32 && w == 32 {
            self.rrr(Opcode::new(op::group::CONV, 0x11), &[d, x]);
        } else {
            let xl = if from == Type::F32 {
                let xl = self.scratch(8)?;
                self.rrr(Opcode::new(op::group::CONV, 0x0D), &[xl, x]);
                xl
            } else {
                x
            };
            let t = self.scratch(8)?;
            if !signed && w == 64 {
                // At or above 2^63: subtract it, truncate, and put the top bit back.
                let (lsmall, ldone) = (self.new_label("F"), self.new_label("F"));
                let two63 = self.konst(Type::F64, fbits(Type::F64, 9223372036854775808.0));
                self.rrr(op::cmp(op::group::LT, Ty::Lreal), &[c, xl, two63]);
                self.jnz(c, lsmall);
                let y = self.scratch(8)?;
                self.rrr(op::sub(Ty::Lreal), &[y, xl, two63]);
                self.rrr(trunc_lreal, &[t, y]);
                let top = self.konst(Type::I64, 1u64 << 63);
                self.rrr(op::add(Ty::Lword, 2), &[t, t, top]);
                self.jmp(ldone);
                self.label(lsmall);
                self.rrr(trunc_lreal, &[t, xl]);
                self.label(ldone);
            } else {
                self.rrr(trunc_lreal, &[t, xl]);
            }
            self.copy(d, t, dn);
        }
        self.jmp(lend);
        self.label(lmax);
        self.mcd(d, max.to_le_bytes()[..dn as usize].to_vec());
        self.jmp(lend);
        self.label(lmin);
        self.mcd(d, min.to_le_bytes()[..dn as usize].to_vec());
        self.jmp(lend);
        self.label(lzero);
        self.fill(d, 0, dn);
        self.label(lend);
        Ok(())
    }
}

/// Variables used in place: a load whose value is used only in its block before
/// anything may write the variable reads the variable itself (no copy), and a value
/// computed by one VM instruction and then only stored to a variable is computed
/// straight into it. This is what makes `x := x + 1` one `ADD x, x, ?L?CST`.
impl Fx<'_, '_> {
    /// Where an instruction may write memory other than its result's home.
    fn writes(&mut self, data: &InstData) -> Option<Option<(u32, u32)>> {
        match data {
            InstData::Store { value, addr } => {
                let n = self.size(self.vty(*value));
                match self.class_of(*addr) {
                    PtrClass::Rel(o) => Some(Some((o, n))),
                    _ => Some(None),
                }
            }
            InstData::Call { .. } => Some(None),
            _ => None,
        }
    }

    fn overlaps(a: (u32, u32), b: (u32, u32)) -> bool {
        a.0 < b.0 + b.1 && b.0 < a.0 + a.1
    }

    fn single_vm_inst(&self, data: &InstData) -> bool {
        match data {
            InstData::Binary { op, .. } => matches!(
                op,
                BinaryOp::Iadd
                    | BinaryOp::Isub
                    | BinaryOp::Imul
                    | BinaryOp::Band
                    | BinaryOp::Bor
                    | BinaryOp::Bxor
                    | BinaryOp::Fadd
                    | BinaryOp::Fsub
                    | BinaryOp::Fmul
                    | BinaryOp::Fdiv
                    | BinaryOp::Fpow
            ),
            InstData::Unary { op, .. } => !matches!(
                op,
                UnaryOp::Fnearest | UnaryOp::Ftrunc | UnaryOp::Ffloor | UnaryOp::Fceil
            ),
            InstData::Icmp { .. } | InstData::Fcmp { .. } | InstData::Select { .. } => true,
            InstData::Load { .. } => true,
            InstData::Convert { op, .. } => matches!(
                op,
                ConvOp::Itrunc | ConvOp::Bitcast | ConvOp::Fpromote | ConvOp::Fdemote
            ),
            _ => false,
        }
    }

    fn plan_in_place(&mut self) {
        let f = self.f;
        let layout = f.layout.clone();
        for b in layout {
            let insts = f.block(b).insts.clone();
            let pos_of = |v: Value| -> Option<usize> {
                match f.value_def(v) {
                    ValueDef::Result(i) => insts.iter().position(|&x| x == i),
                    _ => None,
                }
            };
            let _ = pos_of;
            // Uses of each value within this block, by position.
            let mut local_uses: FxHashMap<Value, Vec<usize>> = FxHashMap::default();
            let mut all_uses: FxHashMap<Value, usize> = FxHashMap::default();
            for (p, &i) in insts.iter().enumerate() {
                f.inst(i)
                    .for_each_arg(|v| local_uses.entry(v).or_default().push(p));
                if let Some(&v) = self.late_use.get(&i) {
                    local_uses.entry(v).or_default().push(p);
                }
            }
            for (v, us) in &local_uses {
                all_uses.insert(*v, us.len());
            }
            // Loads read in place.
            for (p, &i) in insts.iter().enumerate() {
                let InstData::Load { ty, addr } = f.inst(i) else {
                    continue;
                };
                let Some(v) = f.result(i) else { continue };
                let PtrClass::Rel(o) = self.class_of(*addr) else {
                    continue;
                };
                let n = self.size(*ty);
                let total = self.uses[v.index()].len();
                let Some(local) = local_uses.get(&v) else {
                    continue;
                };
                if local.len() != total || total == 0 {
                    continue;
                }
                let last = *local.iter().max().expect("a use");
                let mut ok = true;
                for &j in &insts[p + 1..last] {
                    let d = f.inst(j).clone();
                    match self.writes(&d) {
                        Some(Some(w)) if Self::overlaps(w, (o, n)) => ok = false,
                        Some(None) => ok = false,
                        _ => {}
                    }
                    if !ok {
                        break;
                    }
                }
                if ok {
                    self.homes[v.index()] = Some(o);
                }
            }
            // Values computed straight into the variable they are stored to.
            for (p, &i) in insts.iter().enumerate() {
                let InstData::Store { value, addr } = f.inst(i).clone() else {
                    continue;
                };
                let PtrClass::Rel(o) = self.class_of(addr) else {
                    continue;
                };
                if self.homes[value.index()].is_some() || self.uses[value.index()].len() != 1 {
                    continue;
                }
                let ValueDef::Result(def) = f.value_def(value) else {
                    continue;
                };
                let Some(dp) = insts.iter().position(|&x| x == def) else {
                    continue;
                };
                let data = f.inst(def).clone();
                if !self.single_vm_inst(&data) {
                    continue;
                }
                let n = self.size(self.vty(value));
                let mut ok = true;
                for &j in &insts[dp + 1..p] {
                    let d = f.inst(j).clone();
                    match self.writes(&d) {
                        Some(Some(w)) if Self::overlaps(w, (o, n)) => ok = false,
                        Some(None) => ok = false,
                        _ => {}
                    }
                    if let InstData::Load { addr, ty } = &d {
                        match self.class_of(*addr) {
                            PtrClass::Rel(q) if Self::overlaps((q, self.size(*ty)), (o, n)) => {
                                ok = false
                            }
                            PtrClass::Rel(_) | PtrClass::Abs(_) => {}
                            _ => ok = false,
                        }
                    }
                    let homes = &self.homes;
                    let size = |t: Type| self.cx.layout.scalar_size(t);
                    d.for_each_arg(|u| {
                        if let Some(h) = homes[u.index()] {
                            if Self::overlaps((h, size(f.value_type(u))), (o, n)) {
                                ok = false;
                            }
                        }
                    });
                    if !ok {
                        break;
                    }
                }
                if ok {
                    self.homes[value.index()] = Some(o);
                }
            }
        }
    }
}

/// Block parameters share a home with the arguments that flow into them when the two
/// are never live at once, so the copies on the edges disappear (SSA's phi copies,
/// coalesced by liveness).
impl Fx<'_, '_> {
    fn coalesce_block_params(&mut self) {
        let f = self.f;
        let nv = f.values.len();
        let words = nv.div_ceil(64);
        let layout = f.layout.clone();
        let nb = f.blocks.len();
        let bit = |set: &[u64], v: usize| set[v / 64] >> (v % 64) & 1 != 0;
        let set_bit = |set: &mut Vec<u64>, v: usize| set[v / 64] |= 1 << (v % 64);
        let late_use = self.late_use.clone();
        let inst_uses = |i: plcc_ir::entities::Inst| -> Vec<Value> {
            let mut used = Vec::new();
            f.inst(i).for_each_arg(|v| used.push(v));
            used.extend(late_use.get(&i).copied());
            used
        };
        // Where each value is defined: block and position (-1 for parameters).
        let mut def_at: Vec<Option<(usize, i64)>> = vec![None; nv];
        let mut uses_b = vec![vec![0u64; words]; nb];
        let mut defs_b = vec![vec![0u64; words]; nb];
        for &b in &layout {
            let bi = b.index();
            for &p in &f.block(b).params {
                def_at[p.index()] = Some((bi, -1));
                set_bit(&mut defs_b[bi], p.index());
            }
            for (k, &i) in f.block(b).insts.iter().enumerate() {
                for v in inst_uses(i) {
                    if !bit(&defs_b[bi], v.index()) {
                        set_bit(&mut uses_b[bi], v.index());
                    }
                }
                if let Some(r) = f.result(i) {
                    def_at[r.index()] = Some((bi, k as i64));
                    set_bit(&mut defs_b[bi], r.index());
                }
            }
        }
        let mut live_in = vec![vec![0u64; words]; nb];
        let mut live_out = vec![vec![0u64; words]; nb];
        let mut changed = true;
        while changed {
            changed = false;
            for &b in layout.iter().rev() {
                let bi = b.index();
                let mut out = vec![0u64; words];
                for sb in f.successors(b) {
                    for (o, x) in out.iter_mut().zip(&live_in[sb.index()]) {
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
        // Is `v` live just after position `k` of block `bi`?
        let live_after = |v: Value, bi: usize, k: i64| -> bool {
            let vi = v.index();
            let defined_before = match def_at[vi] {
                Some((db, dk)) if db == bi => dk <= k,
                _ => bit(&live_in[bi], vi),
            };
            if !defined_before {
                return false;
            }
            if bit(&live_out[bi], vi) {
                return true;
            }
            let insts = &f.block(Block::new(bi)).insts;
            insts
                .iter()
                .skip((k + 1).max(0) as usize)
                .any(|&i| inst_uses(i).contains(&v))
        };
        let operands_of = |v: Value| -> Vec<Value> {
            let mut ops = Vec::new();
            if let ValueDef::Result(i) = f.value_def(v) {
                f.inst(i).for_each_arg(|x| ops.push(x));
            }
            ops
        };
        let atomic = |v: Value| -> bool {
            match f.value_def(v) {
                ValueDef::Result(i) => self.single_vm_inst(f.inst(i)),
                ValueDef::Param(..) => true,
            }
        };
        let interfere = |x: Value, y: Value| -> bool {
            let live_at_def = |a: Value, b: Value| match def_at[b.index()] {
                Some((bi, k)) => live_after(a, bi, k),
                None => true,
            };
            if live_at_def(x, y) || live_at_def(y, x) {
                return true;
            }
            // A definition made of several VM instructions may write its home before
            // it has read all its operands.
            (!atomic(x) && operands_of(x).contains(&y))
                || (!atomic(y) && operands_of(y).contains(&x))
        };
        let is_const = |v: Value| {
            matches!(
                f.value_def(v),
                ValueDef::Result(i) if matches!(f.inst(i), InstData::Iconst { .. } | InstData::Fconst { .. })
            )
        };
        // Classes of values that share a home.
        let mut class_of: FxHashMap<Value, usize> = FxHashMap::default();
        let mut classes: Vec<Vec<Value>> = Vec::new();
        for &b in &layout {
            let Some(term) = f.terminator(b) else {
                continue;
            };
            for bc in f.inst(term).successors() {
                let params = f.block(bc.block).params.clone();
                for (&p, &a) in params.iter().zip(&bc.args) {
                    if p == a
                        || is_const(a)
                        || self.homes[a.index()].is_some()
                        || self.homes[p.index()].is_some()
                        || self.skip[a.index()]
                        || self.size(self.vty(a)) != self.size(self.vty(p))
                    {
                        continue;
                    }
                    let ca = class_of.get(&a).copied();
                    let cp = class_of.get(&p).copied();
                    if ca.is_some() && ca == cp {
                        continue;
                    }
                    let ma = ca.map(|c| classes[c].clone()).unwrap_or_else(|| vec![a]);
                    let mp = cp.map(|c| classes[c].clone()).unwrap_or_else(|| vec![p]);
                    if ma.iter().any(|&x| mp.iter().any(|&y| interfere(x, y))) {
                        continue;
                    }
                    let target = match (ca, cp) {
                        (Some(c), _) | (None, Some(c)) => c,
                        (None, None) => {
                            classes.push(Vec::new());
                            classes.len() - 1
                        }
                    };
                    for v in ma.into_iter().chain(mp) {
                        if let Some(&old) = class_of.get(&v) {
                            if old != target {
                                classes[old].retain(|&x| x != v);
                            }
                        }
                        if !classes[target].contains(&v) {
                            classes[target].push(v);
                        }
                        class_of.insert(v, target);
                    }
                }
            }
        }
        for c in classes {
            if c.len() < 2 {
                continue;
            }
            let size = self.size(self.vty(c[0]));
            let h = self.alloc(size, format!("?V{}", c[0].0));
            for v in c {
                self.homes[v.index()] = Some(h);
            }
        }
    }
}
