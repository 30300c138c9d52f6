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
//! function's prologue fills with MCD. Operations the VM lacks are composed (the
//! arithmetic right shift, sign extension, float rounding, conversions); what its C
//! leaves undefined (division by zero, `MIN / -1`, shifts by the width or more, float
//! casts out of range) the build's `passes::legalize` has guarded in the IR.

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

mod coalesce;
mod compose;
mod fill;
mod in_place;
mod index;
mod portable;
mod power;

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
    /// Absolute address of the fault word (a WORD, 1 once a fault was raised).
    pub fault_addr: u32,
    /// The VM port the code is for.
    pub port: crate::port::Port,
    /// The functions whose constants the task loads once, at cold start (the bodies
    /// of the task's PROGRAMs that nothing else calls): their pool goes into a unit of
    /// its own ([`FuncCode::constants`]) instead of their prologue.
    pub constants_once: &'a [bool],
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
    /// For a function of [`Cx::constants_once`], the unit that fills its constant pool
    /// (run with DPTR at the instance, ending in RETURN), and its label.
    pub constants: Option<(LabelId, Unit)>,
}

const SCRATCH: u32 = 96;

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
    /// The span of the IR instruction being selected.
    cur_span: Option<Span>,
    /// The first opcode emitted that the port lacks, with the part it needs.
    port_error: Option<(crate::port::Part, Opcode, Option<Span>)>,
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
        cur_span: None,
        port_error: None,
    };
    fx.run()?;
    if let Some((part, opcode, span)) = fx.port_error {
        let port = cx.port.name();
        let msg = format!(
            "{} (opcode {opcode}) {} not available on the CPDev VM port `{port}`",
            part.describe(),
            if matches!(part, crate::port::Part::Pointers | crate::port::Part::Long) {
                "are"
            } else {
                "is"
            },
        );
        let note = format!(
            "the `{port}` VM is built without it and stops on this instruction; choose another port (`-s port=full`) or avoid it"
        );
        let d = match span {
            Some(s) => Diagnostic::error(crate::codes::E_PORT, msg, s),
            None => {
                Diagnostic::error_nowhere(crate::codes::E_PORT, format!("{msg} (in `{}`)", f.name))
            }
        };
        return Err(Box::new(d.with_note(note)));
    }
    let frame_size = fx.next - base;
    let mut items = vec![Item::Label(cx.entry_labels[id.index()])];
    let constants = if cx.constants_once[id.index()] {
        let label = fx.prog.label(format!("?plcc.{}?CONST", f.name));
        let mut pool = vec![Item::Label(label)];
        pool.append(&mut fx.prologue);
        pool.push(Item::Inst(VInst {
            opcode: op::RETURN,
            args: vec![],
        }));
        let unit = Unit {
            items: pool,
            rel_names: fx.names.clone(),
            abs_names: FxHashMap::default(),
        };
        Some((label, unit))
    } else {
        items.append(&mut fx.prologue);
        None
    };
    items.append(&mut fx.body);
    Ok(FuncCode {
        unit: Unit {
            items,
            rel_names: fx.names,
            abs_names: FxHashMap::default(),
        },
        frame_size,
        constants,
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
        if self.port_error.is_none() {
            if let Some(part) = self.cx.port.lacks(opcode) {
                self.port_error = Some((part, opcode, self.cur_span));
            }
        }
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
        let opcode = self.mode().mcd();
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

    /// Raises the fault flag: writes 1 to the program's fault word (a global the DCP
    /// lists as `PLCC_FAULT`). The status word's ARRAYBOUND bit is not used: every
    /// CPDev runtime stops the VM when CEAC sets it.
    fn raise_fault(&mut self) -> Res<()> {
        let one = self.konst(Type::I16, 1);
        let at = self.cx.fault_addr;
        self.emit(op::mmv(2, true), vec![Arg::Abs(at), Arg::Rel(one)]);
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
                InstData::CallTable { table, index, args } => {
                    // The first argument is an instance only if every entry takes one.
                    let entries = &self.cx.module.tables[table.index()].entries;
                    let inst_conv = entries.iter().any(Option::is_some)
                        && entries
                            .iter()
                            .flatten()
                            .all(|g| matches!(self.cx.convs[g.index()], Conv::Instance { .. }));
                    let mut push = |v: Value, kind: UseKind| self.uses[v.index()].push((k, kind));
                    push(*index, UseKind::Value);
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
                // A fill writes through its pointer as a store does (`isel/fill.rs`).
                InstData::Intrinsic {
                    op: Intrinsic::Fill,
                    args,
                } => {
                    push(args[0], UseKind::Addr);
                    args[1..].iter().for_each(|&v| push(v, UseKind::Value));
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
                    // The A?RD/A?WR index is an INT: longer arrays go through pointers.
                    let short = arr.len <= 1 << 15;
                    match bc {
                        PtrClass::Rel(b)
                            if elem_scalar && whole && short && [1, 2, 4, 8].contains(&stride) =>
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
    fn run(&mut self) -> Res<()> {
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
            for g in plcc_ir::analysis::inst_callees(self.cx.module, f.inst(i)) {
                if self.cx.convs[g.index()] == Conv::Area {
                    area = Some(area.unwrap_or(0).max(self.cx.frame_sizes[g.index()]));
                }
            }
        }
        if let Some(area) = area {
            self.call_area = Some(self.alloc(area, "?LCALL".into()));
        }
        self.record_uses();
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
                self.cur_span = f.spans[i.index()];
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

    /// DPRDL (`write` false) or DPWRL of `n` bytes between the frame offset `local`
    /// and the absolute address held at `ptr`. These exist in every mode (vmdef.h's
    /// DPRDL4A/DPWRL4A are executed by no VM). In the aligned mode they are 14 bytes
    /// long, so a no-op FPAT (count 0, 10 bytes) brings the next instruction back to a
    /// multiple of 4, as every instruction of CPDev's aligned code is.
    fn dp_move(&mut self, write: bool, local: u32, ptr: u32, n: u32) {
        let o = if write { op::DPWRL } else { op::DPRDL };
        self.emit(o, vec![Arg::Rel(local), Arg::Rel(ptr), Arg::Imm(n)]);
        if self.mode() == Mode::M32A {
            self.emit(op::FPAT, vec![Arg::Rel(local), Arg::Imm(0), Arg::Imm(0)]);
        }
    }

    fn load(&mut self, dst: u32, addr: Value, n: u32) -> Res<()> {
        match self.class_of(addr) {
            PtrClass::Rel(o) => self.copy(dst, o, n),
            PtrClass::Abs(a) => {
                self.emit(op::mmv(n as u8, false), vec![Arg::Rel(dst), Arg::Abs(a)])
            }
            PtrClass::Idx {
                base, index, len, ..
            } => {
                let l = self.lac(index, len)?;
                self.rrr(array_read_op(n), &[dst, base, l]);
            }
            PtrClass::Dyn => {
                let p = self.home(addr);
                self.dp_move(false, dst, p, n);
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
                self.dp_move(true, src, p, n);
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
            InstData::CallTable { table, index, args } => {
                self.call_table(table, index, &args, res)?
            }
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
                self.unary(uop, arg, v)?;
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
                if signed && t == Type::I64 {
                    self.cmp_lint(g, d, a, b)?;
                } else {
                    self.rrr(op::cmp(g, ty), &[d, a, b]);
                }
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
            InstData::Convert {
                op: ConvOp::PtrToInt | ConvOp::IntToPtr,
                ..
            } => {
                return Err(
                    self.unsupported("pointer arithmetic (CODESYS pointers as numbers)", span)
                );
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
            // `build` refuses these first (`reject_inline_c`).
            InstData::InlineC { .. } => return Err(self.unsupported("C code in a pragma", span)),
            // The build expands every table into compares first (`passes::br_table`).
            InstData::BrTable { .. } => {
                return Err(self.unsupported("a jump table left unexpanded", span))
            }
            // `build` answered every one with the layout (passes::sizes).
            InstData::SizeOf { .. } => {
                return Err(self.unsupported("a `sizeof` left after its resolution", span))
            }
            InstData::Intrinsic { op: iop, ref args } => match iop {
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
                Intrinsic::Fill => self.fill_elems(args)?,
                // plcc's VM stops a runaway scan itself; the program never asks, and
                // branches on the answer go straight on (see Brif).
                Intrinsic::StopRequested => {
                    let v = res.expect("result");
                    let zero = self.konst(Type::I1, 0);
                    self.homes[v.index()] = Some(zero);
                }
            },
            InstData::Jump { dest } => {
                self.edge(&dest)?;
                if Some(dest.block) != next {
                    self.jmp(self.block_labels[dest.block.index()]);
                }
            }
            InstData::Brif {
                else_dest, cond, ..
            } if self.is_stop_request(cond) => {
                self.edge(&else_dest)?;
                if Some(else_dest.block) != next {
                    self.jmp(self.block_labels[else_dest.block.index()]);
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

    /// True for the result of `stop_requested`, which is always FALSE here.
    fn is_stop_request(&self, v: Value) -> bool {
        matches!(
            self.f.value_def(v),
            ValueDef::Result(i) if matches!(
                self.f.inst(i),
                InstData::Intrinsic { op: Intrinsic::StopRequested, .. }
            )
        )
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
                    let (p, d, _, n) = pending[0];
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

    /// `call_table`: the VM calls only immediate code addresses (CALB, CALBR, CALF),
    /// so a compare chain on the index (EQ of the index's unsigned type against each
    /// entry's number) jumps to a direct call of the entry; past the chain (an empty
    /// entry or an index out of range) the fault word is set and the result zeroed.
    fn call_table(
        &mut self,
        table: plcc_ir::TableId,
        index: Value,
        args: &[Value],
        res: Option<Value>,
    ) -> Res<()> {
        let entries = self.cx.module.tables[table.index()].entries.clone();
        let it = self.vty(index);
        let reach = match it.bits() {
            64 => u64::MAX,
            b => (1u64 << b) - 1,
        };
        let ih = self.home(index);
        let c = self.scratch(self.size(Type::I1))?;
        let mut cases = Vec::new();
        for (k, e) in entries.iter().enumerate() {
            let Some(g) = *e else { continue };
            if k as u64 > reach {
                break;
            }
            let l = self.new_label("TC");
            let kc = self.konst(it, k as u64);
            self.rrr(op::cmp(op::group::EQ, int_ty(it, false)), &[c, ih, kc]);
            self.jnz(c, l);
            cases.push((l, g));
        }
        self.raise_fault()?;
        if let Some(v) = res {
            let n = self.size(self.vty(v));
            let h = self.home(v);
            self.fill(h, 0, n);
        }
        let end = self.new_label("TE");
        for (l, g) in cases {
            self.jmp(end);
            self.label(l);
            self.call(g, args, res)?;
        }
        self.label(end);
        Ok(())
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
                            self.dp_move(true, ah, q, n);
                        }
                        self.emit(op::CALBR, vec![Arg::Rel(p), Arg::Label(label)]);
                        if let (Some(v), Some(r)) = (res, ret) {
                            let n = self.size(self.vty(v));
                            let h = self.home(v);
                            let k = self.konst(pt, (temp_base + r) as u64);
                            self.rrr(op::add(self.ptr_ty(), 2), &[q, p, k]);
                            self.dp_move(false, h, q, n);
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
