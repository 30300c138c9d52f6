//! IR to Cranelift IR, one function at a time.
//!
//! Values map one to one: `i1` becomes an `I8` holding 0 or 1 (what `icmp` yields),
//! `ptr` an `I64`. IR blocks become Cranelift blocks with the same parameters, so no
//! SSA reconstruction is needed; blocks are translated in reverse postorder, which puts
//! every definition before its uses whatever the IR's layout order. Only reachable
//! blocks are translated (an unreachable block can define nothing a reachable one uses).
//!
//! The IR's total semantics cost a few instructions where Cranelift traps or masks:
//! division checks its divisor, shifts compare their count with the width, and
//! float-to-integer conversions saturate at the destination width.

use crate::runtime::{self, MATH, RT_CLOCK_MS, RT_CLOCK_NS, RT_FAULT, RT_STOP};
use cranelift_codegen::entity::packed_option::ReservedValue;
use cranelift_codegen::ir::{
    self, condcodes, types, AbiParam, BlockArg, InstBuilder, MemFlagsData, Signature,
    StackSlotData, StackSlotKind, UserExternalName, UserFuncName,
};
use cranelift_codegen::isa::{CallConv, TargetFrontendConfig};
use cranelift_frontend::{FunctionBuilder, FunctionBuilderContext};
use cranelift_module::{DataId as ClDataId, FuncId as ClFuncId};
use plcc_ir::layout::Layout;
use plcc_ir::{
    BinaryOp, Block, ConvOp, FloatCC, FuncId, Function, InstData, IntCC, Intrinsic, Module, Type,
    UnaryOp, Value,
};

/// How code finds data memory and the runtime context.
#[derive(Copy, Clone, Debug)]
pub(crate) enum Addressing {
    /// The JIT: both live at fixed addresses, baked into the code as constants.
    Absolute {
        /// Address of the data block (data objects at their offsets from it).
        data: u64,
        /// Address of the [`runtime::Runtime`].
        rt: u64,
    },
    /// Objects: relocations against the data block and runtime context symbols.
    Symbols {
        /// The data block.
        data: ClDataId,
        /// The runtime context.
        rt: ClDataId,
    },
}

/// Everything about the module that translating one function needs; shared (read
/// only) by every function and thread.
pub(crate) struct Env<'a> {
    pub module: &'a Module,
    pub layout: &'a Layout,
    /// Offset of every data object in the data block.
    pub data_offsets: &'a [u64],
    pub addressing: Addressing,
    /// The Cranelift id of every IR function.
    pub funcs: &'a [ClFuncId],
    /// The signature of every IR function.
    pub sigs: &'a [Signature],
    /// The Cranelift id of every [`MATH`] function.
    pub math: &'a [ClFuncId],
    pub call_conv: CallConv,
    /// Add the watchdog checks to each function first
    /// ([`crate::codegen::CodegenSettings::watchdog`]).
    pub watchdog: bool,
    /// Leave out the translator's own optimisations
    /// ([`crate::codegen::CodegenSettings::quick`]).
    pub quick: bool,
}

/// The Cranelift type that holds an IR type.
pub(crate) fn cl_type(t: Type) -> types::Type {
    match t {
        Type::I1 | Type::I8 => types::I8,
        Type::I16 => types::I16,
        Type::I32 => types::I32,
        Type::I64 | Type::Ptr => types::I64,
        Type::F32 => types::F32,
        Type::F64 => types::F64,
    }
}

fn abi_param(t: Type) -> AbiParam {
    let p = AbiParam::new(cl_type(t));
    // Narrow integers are extended to a register at calls as C does, so the code
    // follows the platform ABI (required by Apple's arm64 ABI).
    match t {
        Type::I1 => p.uext(),
        Type::I8 | Type::I16 => p.sext(),
        _ => p,
    }
}

/// The Cranelift signature of an IR function.
pub(crate) fn signature(f: &Function, call_conv: CallConv) -> Signature {
    let mut sig = Signature::new(call_conv);
    sig.params.extend(f.params.iter().map(|&t| abi_param(t)));
    sig.returns.extend(f.ret.map(abi_param));
    sig
}

/// The signature of a [`MATH`] function.
pub(crate) fn math_signature(m: &runtime::MathFn, call_conv: CallConv) -> Signature {
    let mut sig = Signature::new(call_conv);
    for _ in 0..m.arity {
        sig.params.push(AbiParam::new(m.ty));
    }
    sig.returns.push(AbiParam::new(m.ty));
    sig
}

/// Buffers reused from one function to the next (translation allocates nothing per
/// instruction once they have grown).
#[derive(Default)]
struct State {
    values: Vec<ir::Value>,
    /// For pointers: a constant offset still to be added to `values` (field and data
    /// offsets are folded into the loads and stores that use them, not computed).
    offs: Vec<i64>,
    blocks: Vec<ir::Block>,
    slots: Vec<ir::StackSlot>,
    order: Vec<Block>,
    mark: Vec<bool>,
    stack: Vec<(Block, u32)>,
    func_refs: Vec<Option<ir::FuncRef>>,
    touched: Vec<usize>,
    math_refs: [Option<ir::FuncRef>; 22],
    data_gv: Option<ir::GlobalValue>,
    rt_gv: Option<ir::GlobalValue>,
    bargs: Vec<BlockArg>,
    bargs2: Vec<BlockArg>,
    cargs: Vec<ir::Value>,
    entry_is_target: bool,
}

/// Translates functions; keep one per thread and reuse it.
#[derive(Default)]
pub(crate) struct Translator {
    fctx: FunctionBuilderContext,
    st: State,
}

/// Why a function could not be translated (malformed IR the verifier should have
/// caught).
pub(crate) type TransError = String;

impl Translator {
    /// Translates IR function `fid` into `func` (which must be empty).
    pub fn translate(
        &mut self,
        env: &Env,
        fid: FuncId,
        func: &mut ir::Function,
        frontend: TargetFrontendConfig,
    ) -> Result<(), TransError> {
        // Compares that value ranges decide (the bounds checks of indexes a loop
        // keeps in the array) go before translation, as in the `c` target; then
        // small branches become selects (cmov) and loop tests move to the loops'
        // ends (one branch an iteration), which Cranelift does not do itself; loops
        // that only set an array's elements to one value become `memset`.
        let mut narrowed = env.module.func(fid).clone();
        if env.watchdog {
            plcc_ir::passes::watchdog::run_function(&mut narrowed);
        }
        if !env.quick {
            plcc_ir::passes::ranges::run(&mut narrowed);
            plcc_ir::passes::fill::run(&mut narrowed, env.module);
            plcc_ir::passes::if_convert::run(&mut narrowed);
            plcc_ir::passes::rotate::run(&mut narrowed);
        }
        let f = &narrowed;
        func.signature = env.sigs[fid.index()].clone();
        func.name = UserFuncName::user(0, env.funcs[fid.index()].as_u32());
        let st = &mut self.st;
        st.reset(env, f)?;
        let b = FunctionBuilder::new(func, &mut self.fctx);
        let mut cx = Cx {
            env,
            f,
            b,
            st,
            frontend,
        };
        let r = cx.run();
        cx.b.seal_all_blocks();
        cx.b.finalize(frontend);
        r
    }
}

impl State {
    fn reset(&mut self, env: &Env, f: &Function) -> Result<(), TransError> {
        self.values.clear();
        self.values
            .resize(f.values.len(), ir::Value::reserved_value());
        self.offs.clear();
        self.offs.resize(f.values.len(), 0);
        self.blocks.clear();
        self.blocks
            .resize(f.blocks.len(), ir::Block::reserved_value());
        self.slots.clear();
        for &i in &self.touched {
            self.func_refs[i] = None;
        }
        self.touched.clear();
        if self.func_refs.len() != env.module.funcs.len() {
            self.func_refs.clear();
            self.func_refs.resize(env.module.funcs.len(), None);
        }
        self.math_refs = [None; 22];
        self.data_gv = None;
        self.rt_gv = None;
        self.compute_order(f)
    }

    /// Reverse postorder of the reachable blocks.
    fn compute_order(&mut self, f: &Function) -> Result<(), TransError> {
        self.order.clear();
        self.mark.clear();
        self.mark.resize(f.blocks.len(), false);
        self.entry_is_target = false;
        let Some(entry) = f.entry() else {
            return Err(format!("function `{}` has no blocks", f.name));
        };
        self.stack.clear();
        self.stack.push((entry, 0));
        self.mark[entry.index()] = true;
        while let Some(&mut (b, ref mut next)) = self.stack.last_mut() {
            let Some(term) = f.terminator(b) else {
                return Err(format!("{b} of `{}` has no terminator", f.name));
            };
            let succ = f.inst(term).dest(*next as usize).map(|d| d.block);
            match succ {
                Some(s) => {
                    *next += 1;
                    if s == entry {
                        self.entry_is_target = true;
                    }
                    if s.index() >= f.blocks.len() {
                        return Err(format!("branch to missing {s} in `{}`", f.name));
                    }
                    if !self.mark[s.index()] {
                        self.mark[s.index()] = true;
                        self.stack.push((s, 0));
                    }
                }
                None => {
                    self.order.push(b);
                    self.stack.pop();
                }
            }
        }
        self.order.reverse();
        Ok(())
    }
}

struct Cx<'e, 'f, 's> {
    env: &'e Env<'e>,
    f: &'e Function,
    b: FunctionBuilder<'f>,
    st: &'s mut State,
    frontend: TargetFrontendConfig,
}

fn trusted() -> MemFlagsData {
    MemFlagsData::trusted()
}

fn int_cc(c: IntCC) -> condcodes::IntCC {
    use condcodes::IntCC as C;
    match c {
        IntCC::Eq => C::Equal,
        IntCC::Ne => C::NotEqual,
        IntCC::Slt => C::SignedLessThan,
        IntCC::Sle => C::SignedLessThanOrEqual,
        IntCC::Sgt => C::SignedGreaterThan,
        IntCC::Sge => C::SignedGreaterThanOrEqual,
        IntCC::Ult => C::UnsignedLessThan,
        IntCC::Ule => C::UnsignedLessThanOrEqual,
        IntCC::Ugt => C::UnsignedGreaterThan,
        IntCC::Uge => C::UnsignedGreaterThanOrEqual,
    }
}

fn float_cc(c: FloatCC) -> condcodes::FloatCC {
    use condcodes::FloatCC as C;
    match c {
        FloatCC::Eq => C::Equal,
        // Cranelift's `ne` is "unordered or not equal", as the IR's.
        FloatCC::Ne => C::NotEqual,
        FloatCC::Lt => C::LessThan,
        FloatCC::Le => C::LessThanOrEqual,
        FloatCC::Gt => C::GreaterThan,
        FloatCC::Ge => C::GreaterThanOrEqual,
    }
}

/// An immediate as Cranelift wants it for a type: zero-extended from its width.
fn imm_for(ty: types::Type, v: i64) -> i64 {
    match ty.bits() {
        8 => v & 0xff,
        16 => v & 0xffff,
        32 => v & 0xffff_ffff,
        _ => v,
    }
}

impl Cx<'_, '_, '_> {
    fn run(&mut self) -> Result<(), TransError> {
        let f = self.f;
        // Stack slots, sized and aligned as the data layout says.
        for slot in &f.slots {
            let size = self.env.layout.size_of(slot.ty);
            let align = self.env.layout.align_of(slot.ty).max(1);
            let shift = align.trailing_zeros() as u8;
            let ss = self.b.create_sized_stack_slot(StackSlotData::new(
                StackSlotKind::ExplicitSlot,
                size,
                shift,
            ));
            self.st.slots.push(ss);
        }
        // Blocks and their parameters first, so branches can target any of them.
        for i in 0..self.st.order.len() {
            let ib = self.st.order[i];
            let cb = self.b.create_block();
            self.st.blocks[ib.index()] = cb;
            // Small blocks that raise the fault flag are the out-of-bounds and error
            // paths: lay them out of line (never the entry, which Cranelift keeps
            // first, nor a block doing real work besides).
            let insts = &f.block(ib).insts;
            let raises = i > 0
                && insts.len() <= 4
                && insts.iter().any(|&i| {
                    matches!(
                        f.inst(i),
                        InstData::Intrinsic {
                            op: Intrinsic::RaiseFault,
                            ..
                        }
                    )
                });
            if raises {
                self.b.set_cold_block(cb);
            }
            for &p in &f.block(ib).params {
                let v = self.b.append_block_param(cb, cl_type(f.value_type(p)));
                self.st.values[p.index()] = v;
            }
        }
        let entry = self.st.order[0];
        let entry_cb = self.st.blocks[entry.index()];
        if self.st.entry_is_target {
            // Cranelift's entry block cannot be a branch target: enter through a
            // fresh block that passes the function's parameters on.
            let pre = self.b.create_block();
            self.b.append_block_params_for_function_params(pre);
            self.b.switch_to_block(pre);
            self.st.bargs.clear();
            let n = self.b.block_params(pre).len();
            for i in 0..n {
                let v = self.b.block_params(pre)[i];
                self.st.bargs.push(BlockArg::Value(v));
            }
            let args = std::mem::take(&mut self.st.bargs);
            self.b.ins().jump(entry_cb, &args);
            self.st.bargs = args;
        } else {
            let sig_n = self.b.func.signature.params.len();
            if self.b.func.dfg.num_block_params(entry_cb) != sig_n {
                return Err(format!(
                    "the entry block of `{}` does not take the function's parameters",
                    f.name
                ));
            }
        }
        for i in 0..self.st.order.len() {
            let ib = self.st.order[i];
            self.b.switch_to_block(self.st.blocks[ib.index()]);
            for &inst in &f.block(ib).insts {
                self.inst(inst)?;
            }
        }
        Ok(())
    }

    /// A value as a Cranelift value (a pointer with a pending offset gets it added).
    fn val(&mut self, v: Value) -> Result<ir::Value, TransError> {
        let (base, off) = self.addr(v)?;
        Ok(if off == 0 {
            base
        } else {
            self.b.ins().iadd_imm_s(base, off)
        })
    }

    /// A value as a base and a constant offset (only pointers have offsets).
    fn addr(&self, v: Value) -> Result<(ir::Value, i64), TransError> {
        match self.st.values.get(v.index()) {
            Some(&x) if x != ir::Value::reserved_value() => Ok((x, self.st.offs[v.index()])),
            _ => Err(format!(
                "{v} is used in `{}` where its definition does not dominate",
                self.f.name
            )),
        }
    }

    /// Defines a pointer result as `base + off`; an offset that would not fit a load's
    /// immediate is added right away.
    fn set_addr(&mut self, inst: plcc_ir::Inst, base: ir::Value, off: i64) {
        let (base, off) = if (i32::MIN as i64..=i32::MAX as i64).contains(&off) {
            (base, off)
        } else {
            (self.b.ins().iadd_imm_s(base, off), 0)
        };
        if let Some(r) = self.f.result(inst) {
            self.st.values[r.index()] = base;
            self.st.offs[r.index()] = off;
        }
    }

    fn ty(&self, v: Value) -> Type {
        self.f.value_type(v)
    }

    fn iconst(&mut self, ty: types::Type, v: i64) -> ir::Value {
        self.b.ins().iconst(ty, imm_for(ty, v))
    }

    /// The data block's address (data objects are at offsets from it).
    fn data_base(&mut self) -> ir::Value {
        match self.env.addressing {
            Addressing::Absolute { data, .. } => self.b.ins().iconst(types::I64, data as i64),
            Addressing::Symbols { data, .. } => {
                let gv = match self.st.data_gv {
                    Some(gv) => gv,
                    None => {
                        let gv = self.symbol_gv(data);
                        self.st.data_gv = Some(gv);
                        gv
                    }
                };
                self.b.ins().symbol_value(types::I64, gv)
            }
        }
    }

    fn rt_addr(&mut self) -> ir::Value {
        match self.env.addressing {
            Addressing::Absolute { rt, .. } => self.b.ins().iconst(types::I64, rt as i64),
            Addressing::Symbols { rt, .. } => {
                let gv = match self.st.rt_gv {
                    Some(gv) => gv,
                    None => {
                        let gv = self.symbol_gv(rt);
                        self.st.rt_gv = Some(gv);
                        gv
                    }
                };
                self.b.ins().symbol_value(types::I64, gv)
            }
        }
    }

    /// What `Module::declare_data_in_func` does, without needing the module (so that
    /// worker threads can translate).
    fn symbol_gv(&mut self, data: ClDataId) -> ir::GlobalValue {
        let name = self
            .b
            .func
            .declare_imported_user_function(UserExternalName {
                namespace: 1,
                index: data.as_u32(),
            });
        self.b.create_global_value(ir::GlobalValueData::Symbol {
            name: ir::ExternalName::user(name),
            offset: ir::immediates::Imm64::new(0),
            colocated: true,
            tls: false,
        })
    }

    fn import(&mut self, id: ClFuncId, sig: Signature, colocated: bool) -> ir::FuncRef {
        let sigref = self.b.import_signature(sig);
        let name = self
            .b
            .func
            .declare_imported_user_function(UserExternalName {
                namespace: 0,
                index: id.as_u32(),
            });
        self.b.import_function(ir::ExtFuncData {
            name: ir::ExternalName::user(name),
            signature: sigref,
            colocated,
            patchable: false,
        })
    }

    fn func_ref(&mut self, callee: FuncId) -> Result<ir::FuncRef, TransError> {
        let i = callee.index();
        if i >= self.env.funcs.len() {
            return Err(format!(
                "call to missing function {callee} in `{}`",
                self.f.name
            ));
        }
        if let Some(r) = self.st.func_refs[i] {
            return Ok(r);
        }
        let r = self.import(self.env.funcs[i], self.env.sigs[i].clone(), true);
        self.st.func_refs[i] = Some(r);
        self.st.touched.push(i);
        Ok(r)
    }

    fn math_call(&mut self, index: usize, args: &[ir::Value]) -> ir::Value {
        let r = match self.st.math_refs[index] {
            Some(r) => r,
            None => {
                let sig = math_signature(&MATH[index], self.env.call_conv);
                // Not colocated: the helper lives anywhere in the process.
                let r = self.import(self.env.math[index], sig, false);
                self.st.math_refs[index] = Some(r);
                r
            }
        };
        let call = self.b.ins().call(r, args);
        self.b.inst_results(call)[0]
    }

    fn set(&mut self, inst: plcc_ir::Inst, v: ir::Value) {
        if let Some(r) = self.f.result(inst) {
            self.st.values[r.index()] = v;
        }
    }

    /// Keeps only bit 0 of an `i1` computed with 8-bit arithmetic.
    fn canon(&mut self, ty: Type, v: ir::Value) -> ir::Value {
        if ty == Type::I1 {
            self.b.ins().band_imm_u(v, 1)
        } else {
            v
        }
    }

    /// An `i1` read as a signed 1-bit number (0 or -1), else the value itself.
    fn signed_view(&mut self, ty: Type, v: ir::Value) -> ir::Value {
        if ty == Type::I1 {
            self.b.ins().ineg(v)
        } else {
            v
        }
    }

    /// `fill at, value, n` ([`Intrinsic::Fill`]): a call of `memset` when every byte of
    /// the element is the same (a one-byte value, or a constant such as 0), else a
    /// loop of stores. Nothing when `n <= 0`.
    fn fill(&mut self, at: Value, value: Value, n: Value) -> Result<(), TransError> {
        let ty = self.ty(value);
        let size = i64::from(self.env.layout.scalar_size(ty));
        let (p, off) = self.addr(at)?;
        let p = if off == 0 {
            p
        } else {
            self.b.ins().iadd_imm_s(p, off)
        };
        let n = self.val(n)?;
        let zero = self.b.ins().iconst(types::I64, 0);
        let positive = self
            .b
            .ins()
            .icmp(condcodes::IntCC::SignedGreaterThan, n, zero);
        let n = self.b.ins().select(positive, n, zero);
        let bytes = if size == 1 {
            n
        } else {
            self.b.ins().imul_imm_s(n, size)
        };
        let byte = match plcc_ir::passes::fill::repeated_byte(self.f, value, size as u32) {
            Some(b) => Some(self.b.ins().iconst(types::I8, i64::from(b))),
            None if size == 1 => Some(self.val(value)?),
            None => None,
        };
        if let Some(byte) = byte {
            self.b.call_memset(self.frontend, p, byte, bytes);
            return Ok(());
        }
        let v = self.val(value)?;
        let end = self.b.ins().iadd(p, bytes);
        let head = self.b.create_block();
        let at = self.b.append_block_param(head, types::I64);
        let body = self.b.create_block();
        let done = self.b.create_block();
        self.b.ins().jump(head, &[BlockArg::Value(p)]);
        self.b.switch_to_block(head);
        let more = self
            .b
            .ins()
            .icmp(condcodes::IntCC::UnsignedLessThan, at, end);
        self.b.ins().brif(more, body, &[], done, &[]);
        self.b.switch_to_block(body);
        self.b.ins().store(trusted(), v, at, 0);
        let next = self.b.ins().iadd_imm_s(at, size);
        self.b.ins().jump(head, &[BlockArg::Value(next)]);
        self.b.switch_to_block(done);
        Ok(())
    }

    fn raise_fault(&mut self) {
        let rt = self.rt_addr();
        let one = self.b.ins().iconst(types::I8, 1);
        self.b.ins().store(trusted(), one, rt, RT_FAULT);
    }

    fn inst(&mut self, inst: plcc_ir::Inst) -> Result<(), TransError> {
        let f = self.f;
        match f.inst(inst) {
            &InstData::Iconst { ty, imm } => {
                let imm = if ty == Type::I1 { imm & 1 } else { imm };
                let v = self.iconst(cl_type(ty), imm);
                self.set(inst, v);
            }
            &InstData::SizeOf { ty, of } => {
                let v = self.iconst(
                    cl_type(ty),
                    ty.canon_int(self.env.layout.size_of(of) as i64),
                );
                self.set(inst, v);
            }
            &InstData::Fconst { ty, bits } => {
                let v = match ty {
                    Type::F32 => self
                        .b
                        .ins()
                        .f32const(ir::immediates::Ieee32::with_bits(bits as u32)),
                    Type::F64 => self
                        .b
                        .ins()
                        .f64const(ir::immediates::Ieee64::with_bits(bits)),
                    _ => return Err(format!("fconst of type {ty} in `{}`", f.name)),
                };
                self.set(inst, v);
            }
            &InstData::Unary { op, arg } => {
                let ty = self.ty(arg);
                let a = self.val(arg)?;
                let v = self.unary(op, ty, a)?;
                self.set(inst, v);
            }
            &InstData::Binary { op, args } => {
                let ty = self.ty(args[0]);
                let a = self.val(args[0])?;
                let v = match self.const_of(args[1]) {
                    Some(c) if op.can_fault() && ty != Type::I1 => {
                        self.const_division(op, ty, a, c)
                    }
                    _ => {
                        let b = self.val(args[1])?;
                        self.binary(op, ty, a, b)?
                    }
                };
                self.set(inst, v);
            }
            &InstData::Icmp { cond, args } => {
                let ty = self.ty(args[0]);
                let mut a = self.val(args[0])?;
                let mut b = self.val(args[1])?;
                if matches!(cond, IntCC::Slt | IntCC::Sle | IntCC::Sgt | IntCC::Sge) {
                    a = self.signed_view(ty, a);
                    b = self.signed_view(ty, b);
                }
                let v = self.b.ins().icmp(int_cc(cond), a, b);
                self.set(inst, v);
            }
            &InstData::Fcmp { cond, args } => {
                let a = self.val(args[0])?;
                let b = self.val(args[1])?;
                let v = self.b.ins().fcmp(float_cc(cond), a, b);
                self.set(inst, v);
            }
            &InstData::Convert { op, ty, arg } => {
                let from = self.ty(arg);
                let a = self.val(arg)?;
                let v = self.convert(op, from, ty, a)?;
                self.set(inst, v);
            }
            &InstData::Select {
                cond,
                if_true,
                if_false,
            } => {
                let c = self.val(cond)?;
                let a = self.val(if_true)?;
                let b = self.val(if_false)?;
                let v = self.b.ins().select(c, a, b);
                self.set(inst, v);
            }
            &InstData::GlobalAddr { data } => {
                let Some(&off) = self.env.data_offsets.get(data.index()) else {
                    return Err(format!("missing data object {data} in `{}`", f.name));
                };
                let base = self.data_base();
                self.set_addr(inst, base, off as i64);
            }
            &InstData::SlotAddr { slot } => {
                let Some(&ss) = self.st.slots.get(slot.index()) else {
                    return Err(format!("missing slot {slot} in `{}`", f.name));
                };
                let v = self.b.ins().stack_addr(types::I64, ss, 0);
                self.set(inst, v);
            }
            &InstData::FieldAddr { base, agg, field } => {
                let (p, off) = self.addr(base)?;
                let off = off + self.env.layout.field_offset(agg, field) as i64;
                self.set_addr(inst, p, off);
            }
            &InstData::ElemAddr { base, agg, index } => {
                let (p, off) = self.addr(base)?;
                let ity = self.ty(index);
                let i = self.val(index)?;
                let stride = self.env.layout.stride(agg) as i64;
                let i64v = match ity {
                    Type::I64 | Type::Ptr => i,
                    Type::I1 => self.b.ins().uextend(types::I64, i),
                    _ => self.b.ins().sextend(types::I64, i),
                };
                let v = match stride {
                    0 => p,
                    1 => self.b.ins().iadd(p, i64v),
                    _ => {
                        let scaled = self.b.ins().imul_imm_s(i64v, stride);
                        self.b.ins().iadd(p, scaled)
                    }
                };
                self.set_addr(inst, v, off);
            }
            &InstData::Load { ty, addr } => {
                let (p, off) = self.addr(addr)?;
                let v = self.b.ins().load(cl_type(ty), trusted(), p, off as i32);
                self.set(inst, v);
            }
            &InstData::Store { value, addr } => {
                let v = self.val(value)?;
                let (p, off) = self.addr(addr)?;
                self.b.ins().store(trusted(), v, p, off as i32);
            }
            InstData::Call { func, args } => {
                let r = self.func_ref(*func)?;
                let mut cargs = std::mem::take(&mut self.st.cargs);
                cargs.clear();
                for &a in args {
                    cargs.push(self.val(a)?);
                }
                let call = self.b.ins().call(r, &cargs);
                self.st.cargs = cargs;
                if let Some(&res) = self.b.inst_results(call).first() {
                    self.set(inst, res);
                }
            }
            // `compile_functions` refuses these first (`reject_inline_c`).
            InstData::InlineC { .. } => {
                return Err("C code in a pragma cannot run on the host target".into())
            }
            InstData::CallTable { table, index, args } => {
                self.call_table(inst, *table, *index, args)?
            }
            InstData::Intrinsic { op, args } => match op {
                Intrinsic::Fill => self.fill(args[0], args[1], args[2])?,
                Intrinsic::ClockMs => {
                    let rt = self.rt_addr();
                    let v = self.b.ins().load(types::I32, trusted(), rt, RT_CLOCK_MS);
                    self.set(inst, v);
                }
                Intrinsic::ClockNs => {
                    let rt = self.rt_addr();
                    let v = self.b.ins().load(types::I64, trusted(), rt, RT_CLOCK_NS);
                    self.set(inst, v);
                }
                Intrinsic::RaiseFault => self.raise_fault(),
                Intrinsic::StopRequested => {
                    // Another thread writes the flag: an atomic load, so that no
                    // optimisation keeps an old value in a register.
                    let rt = self.rt_addr();
                    let at = self.b.ins().iadd_imm_s(rt, RT_STOP as i64);
                    let v = self.b.ins().atomic_load(types::I8, trusted(), at);
                    self.set(inst, v);
                }
            },
            InstData::Jump { dest } => {
                let target = self.block_args(dest, false)?;
                let args = std::mem::take(&mut self.st.bargs);
                self.b.ins().jump(target, &args);
                self.st.bargs = args;
            }
            InstData::Brif {
                cond,
                then_dest,
                else_dest,
            } => {
                let c = self.val(*cond)?;
                let t = self.block_args(then_dest, false)?;
                let e = self.block_args(else_dest, true)?;
                let targs = std::mem::take(&mut self.st.bargs);
                let eargs = std::mem::take(&mut self.st.bargs2);
                self.b.ins().brif(c, t, &targs, e, &eargs);
                self.st.bargs = targs;
                self.st.bargs2 = eargs;
            }
            InstData::BrTable {
                arg,
                default,
                table,
            } => {
                let idx = self.table_index(*arg, "br_table")?;
                let def = self.jump_table_call(default)?;
                let mut targets = Vec::with_capacity(table.len());
                for d in table {
                    targets.push(self.jump_table_call(d)?);
                }
                let jt = self
                    .b
                    .create_jump_table(ir::JumpTableData::new(def, &targets));
                self.b.ins().br_table(idx, jt);
            }
            InstData::Return { value } => match value {
                Some(v) => {
                    let x = self.val(*v)?;
                    self.b.ins().return_(&[x]);
                }
                None => {
                    self.b.ins().return_(&[]);
                }
            },
        }
        Ok(())
    }

    /// Fills `bargs` (or `bargs2`) with a branch's arguments; returns its target.
    fn block_args(
        &mut self,
        dest: &plcc_ir::BlockCall,
        second: bool,
    ) -> Result<ir::Block, TransError> {
        let mut buf = std::mem::take(if second {
            &mut self.st.bargs2
        } else {
            &mut self.st.bargs
        });
        buf.clear();
        for &a in &dest.args {
            buf.push(BlockArg::Value(self.val(a)?));
        }
        if second {
            self.st.bargs2 = buf;
        } else {
            self.st.bargs = buf;
        }
        Ok(self.st.blocks[dest.block.index()])
    }

    /// A branch's destination with its arguments as an entry of a jump table.
    fn jump_table_call(&mut self, dest: &plcc_ir::BlockCall) -> Result<ir::BlockCall, TransError> {
        let target = self.block_args(dest, false)?;
        let args = std::mem::take(&mut self.st.bargs);
        let call = self.b.func.dfg.block_call(target, &args);
        self.st.bargs = args;
        Ok(call)
    }

    /// The index of a `br_table` (the IR's index read unsigned, as Cranelift's must be
    /// an `i32`): narrower ones zero-extended, a 64-bit one cut to 32 bits, or to
    /// `u32::MAX` when it is larger (beyond 32 bits every index is past the table:
    /// `u32::MAX` is too).
    fn table_index(&mut self, index: Value, what: &str) -> Result<ir::Value, TransError> {
        let idx = self.val(index)?;
        Ok(match self.f.value_type(index) {
            Type::I8 | Type::I16 => self.b.ins().uextend(types::I32, idx),
            Type::I32 => idx,
            Type::I64 => {
                let big = self.b.ins().icmp_imm_u(
                    condcodes::IntCC::UnsignedGreaterThan,
                    idx,
                    u32::MAX as i64,
                );
                let low = self.b.ins().ireduce(types::I32, idx);
                let out = self.iconst(types::I32, -1);
                self.b.ins().select(big, out, low)
            }
            t => return Err(format!("{what} index of type {t} in `{}`", self.f.name)),
        })
    }

    fn unary(&mut self, op: UnaryOp, ty: Type, a: ir::Value) -> Result<ir::Value, TransError> {
        let ins = self.b.ins();
        Ok(match op {
            UnaryOp::Ineg => {
                let v = ins.ineg(a);
                self.canon(ty, v)
            }
            UnaryOp::Bnot if ty == Type::I1 => ins.bxor_imm_u(a, 1),
            UnaryOp::Bnot => ins.bnot(a),
            UnaryOp::Iabs => {
                // abs of the signed reading, wrapping (`abs(MIN) = MIN`); an `i1`
                // 1 reads as -1, whose absolute value 1 is itself.
                if ty == Type::I1 {
                    a
                } else {
                    let neg = ins.ineg(a);
                    let zero = self.iconst(cl_type(ty), 0);
                    let is_neg = self.b.ins().icmp(condcodes::IntCC::SignedLessThan, a, zero);
                    self.b.ins().select(is_neg, neg, a)
                }
            }
            UnaryOp::Fneg => ins.fneg(a),
            UnaryOp::Fabs => ins.fabs(a),
            UnaryOp::Fsqrt => ins.sqrt(a),
            UnaryOp::Fnearest => ins.nearest(a),
            UnaryOp::Ftrunc => ins.trunc(a),
            UnaryOp::Ffloor => ins.floor(a),
            UnaryOp::Fceil => ins.ceil(a),
            _ => {
                let Some(i) = runtime::math_unary_index(op) else {
                    unreachable!("every unary operation is handled")
                };
                let i = match ty {
                    Type::F32 => i,
                    Type::F64 => i + 1,
                    _ => return Err(format!("{} of {ty} in `{}`", op.name(), self.f.name)),
                };
                self.math_call(i, &[a])
            }
        })
    }

    fn binary(
        &mut self,
        op: BinaryOp,
        ty: Type,
        a: ir::Value,
        b: ir::Value,
    ) -> Result<ir::Value, TransError> {
        let ct = cl_type(ty);
        let bits = if ty == Type::I1 { 1 } else { ct.bits() as i64 };
        Ok(match op {
            BinaryOp::Iadd => {
                let v = self.b.ins().iadd(a, b);
                self.canon(ty, v)
            }
            BinaryOp::Isub => {
                let v = self.b.ins().isub(a, b);
                self.canon(ty, v)
            }
            BinaryOp::Imul => self.b.ins().imul(a, b),
            BinaryOp::Band => self.b.ins().band(a, b),
            BinaryOp::Bor => self.b.ins().bor(a, b),
            BinaryOp::Bxor => self.b.ins().bxor(a, b),
            BinaryOp::Sdiv | BinaryOp::Udiv | BinaryOp::Srem | BinaryOp::Urem => {
                self.division(op, ty, a, b)
            }
            BinaryOp::Ishl | BinaryOp::Ushr => {
                // Cranelift takes the count modulo the width; the IR wants 0 for a
                // count (unsigned) of at least the width.
                let w = self.iconst(ct, bits);
                let big = self
                    .b
                    .ins()
                    .icmp(condcodes::IntCC::UnsignedGreaterThanOrEqual, b, w);
                let shifted = if op == BinaryOp::Ishl {
                    self.b.ins().ishl(a, b)
                } else {
                    self.b.ins().ushr(a, b)
                };
                let zero = self.iconst(ct, 0);
                self.b.ins().select(big, zero, shifted)
            }
            BinaryOp::Sshr => {
                // A count past the width fills with the sign, as a count of width-1.
                let a = self.signed_view(ty, a);
                let max = self.iconst(ct, bits - 1);
                let n = self.b.ins().umin(b, max);
                let v = self.b.ins().sshr(a, n);
                self.canon(ty, v)
            }
            BinaryOp::Rotl | BinaryOp::Rotr if ty == Type::I1 => a,
            BinaryOp::Rotl => self.b.ins().rotl(a, b),
            BinaryOp::Rotr => self.b.ins().rotr(a, b),
            BinaryOp::Fadd => self.b.ins().fadd(a, b),
            BinaryOp::Fsub => self.b.ins().fsub(a, b),
            BinaryOp::Fmul => self.b.ins().fmul(a, b),
            BinaryOp::Fdiv => self.b.ins().fdiv(a, b),
            BinaryOp::Fpow | BinaryOp::Fatan2 => {
                let Some(i) = runtime::math_binary_index(op) else {
                    unreachable!()
                };
                let i = match ty {
                    Type::F32 => i,
                    Type::F64 => i + 1,
                    _ => return Err(format!("{} of {ty} in `{}`", op.name(), self.f.name)),
                };
                self.math_call(i, &[a, b])
            }
        })
    }

    /// The value of an IR integer constant.
    fn const_of(&self, v: Value) -> Option<i64> {
        match self.f.value_def(v) {
            plcc_ir::function::ValueDef::Result(i) => match self.f.inst(i) {
                InstData::Iconst { imm, .. } => Some(*imm),
                _ => None,
            },
            _ => None,
        }
    }

    /// Division by a constant (most divisions in PLC code): no checks where the
    /// divisor is known, so Cranelift can turn the division into a multiplication and
    /// the function keeps its blocks.
    fn const_division(&mut self, op: BinaryOp, ty: Type, a: ir::Value, c: i64) -> ir::Value {
        let ct = cl_type(ty);
        let signed = matches!(op, BinaryOp::Sdiv | BinaryOp::Srem);
        let c = ty.canon_int(c);
        if c == 0 {
            self.raise_fault();
            return self.iconst(ct, 0);
        }
        if signed && c == -1 {
            // MIN / -1 wraps to MIN; x % -1 is 0.
            return if op == BinaryOp::Sdiv {
                self.b.ins().ineg(a)
            } else {
                self.iconst(ct, 0)
            };
        }
        let (x, d) = if ct.bits() < 32 {
            // As in `division`: narrow operations in 32 bits.
            if signed {
                (
                    self.b.ins().sextend(types::I32, a),
                    self.iconst(types::I32, c),
                )
            } else {
                let d = ty.zext_bits(c) as i64;
                (
                    self.b.ins().uextend(types::I32, a),
                    self.iconst(types::I32, d),
                )
            }
        } else {
            (a, self.iconst(ct, c))
        };
        let r = match op {
            BinaryOp::Sdiv => self.b.ins().sdiv(x, d),
            BinaryOp::Udiv => self.b.ins().udiv(x, d),
            BinaryOp::Srem => self.b.ins().srem(x, d),
            _ => self.b.ins().urem(x, d),
        };
        if ct.bits() < 32 {
            self.b.ins().ireduce(ct, r)
        } else {
            r
        }
    }

    /// `call_table`: a `br_table` on the index, read unsigned, to one block per entry
    /// that calls it directly; empty entries and indexes out of range go to a cold
    /// block that raises the fault and gives 0. All of them join in one block whose
    /// parameter is the result.
    fn call_table(
        &mut self,
        inst: plcc_ir::Inst,
        table: plcc_ir::TableId,
        index: Value,
        args: &[Value],
    ) -> Result<(), TransError> {
        let module = self.env.module;
        let Some(tab) = module.tables.get(table.index()) else {
            return Err(format!("call through missing {table} in `{}`", self.f.name));
        };
        let idx = self.table_index(index, "call_table")?;
        let mut cargs = Vec::with_capacity(args.len());
        for &a in args {
            cargs.push(self.val(a)?);
        }
        let join = self.b.create_block();
        let res = tab
            .result
            .map(|t| self.b.append_block_param(join, cl_type(t)));
        let fault = self.b.create_block();
        self.b.set_cold_block(fault);
        let mut calls = Vec::new();
        let mut targets = Vec::with_capacity(tab.entries.len());
        for e in &tab.entries {
            let blk = match e {
                Some(fid) => {
                    let blk = self.b.create_block();
                    calls.push((blk, *fid));
                    blk
                }
                None => fault,
            };
            targets.push(self.b.func.dfg.block_call(blk, &[]));
        }
        let def = self.b.func.dfg.block_call(fault, &[]);
        let jt = self
            .b
            .create_jump_table(ir::JumpTableData::new(def, &targets));
        self.b.ins().br_table(idx, jt);

        for (blk, fid) in calls {
            self.b.switch_to_block(blk);
            let r = self.func_ref(fid)?;
            let call = self.b.ins().call(r, &cargs);
            let out: Vec<BlockArg> = self
                .b
                .inst_results(call)
                .iter()
                .map(|&v| BlockArg::Value(v))
                .collect();
            self.b.ins().jump(join, &out);
        }

        self.b.switch_to_block(fault);
        self.raise_fault();
        let zero: Vec<BlockArg> = match tab.result {
            Some(Type::F32) => vec![BlockArg::Value(self.b.ins().f32const(0.0))],
            Some(Type::F64) => vec![BlockArg::Value(self.b.ins().f64const(0.0))],
            Some(t) => vec![BlockArg::Value(self.iconst(cl_type(t), 0))],
            None => Vec::new(),
        };
        self.b.ins().jump(join, &zero);

        self.b.switch_to_block(join);
        if let Some(v) = res {
            self.set(inst, v);
        }
        Ok(())
    }

    /// Division and remainder that never trap: a zero divisor branches to a cold block
    /// that raises the fault and yields 0; a divisor of -1 never reaches the hardware
    /// (`MIN / -1` traps on x86).
    fn division(&mut self, op: BinaryOp, ty: Type, a: ir::Value, b: ir::Value) -> ir::Value {
        let ct = cl_type(ty);
        let zero_blk = self.b.create_block();
        let ok_blk = self.b.create_block();
        let join = self.b.create_block();
        self.b.set_cold_block(zero_blk);
        let res = self.b.append_block_param(join, ct);
        self.b.ins().brif(b, ok_blk, &[], zero_blk, &[]);

        self.b.switch_to_block(zero_blk);
        self.raise_fault();
        let z = self.iconst(ct, 0);
        self.b.ins().jump(join, &[BlockArg::Value(z)]);

        self.b.switch_to_block(ok_blk);
        let signed = matches!(op, BinaryOp::Sdiv | BinaryOp::Srem);
        let r = if ct.bits() <= 16 {
            // In 32 bits no narrow quotient overflows; narrowing wraps MIN/-1 to MIN.
            let (a32, b32) = if signed {
                let a = self.signed_view(ty, a);
                let b = self.signed_view(ty, b);
                (
                    self.b.ins().sextend(types::I32, a),
                    self.b.ins().sextend(types::I32, b),
                )
            } else {
                (
                    self.b.ins().uextend(types::I32, a),
                    self.b.ins().uextend(types::I32, b),
                )
            };
            let r = match op {
                BinaryOp::Sdiv => self.b.ins().sdiv(a32, b32),
                BinaryOp::Udiv => self.b.ins().udiv(a32, b32),
                BinaryOp::Srem => self.b.ins().srem(a32, b32),
                _ => self.b.ins().urem(a32, b32),
            };
            let r = self.b.ins().ireduce(ct, r);
            self.canon(ty, r)
        } else if signed {
            let m1 = self.iconst(ct, -1);
            let is_m1 = self.b.ins().icmp(condcodes::IntCC::Equal, b, m1);
            let one = self.iconst(ct, 1);
            let d = self.b.ins().select(is_m1, one, b);
            if op == BinaryOp::Sdiv {
                let q = self.b.ins().sdiv(a, d);
                let neg = self.b.ins().ineg(a);
                self.b.ins().select(is_m1, neg, q)
            } else {
                // x srem 1 = 0 = x srem -1.
                self.b.ins().srem(a, d)
            }
        } else if op == BinaryOp::Udiv {
            self.b.ins().udiv(a, b)
        } else {
            self.b.ins().urem(a, b)
        };
        self.b.ins().jump(join, &[BlockArg::Value(r)]);

        self.b.switch_to_block(join);
        res
    }

    fn convert(
        &mut self,
        op: ConvOp,
        from: Type,
        to: Type,
        a: ir::Value,
    ) -> Result<ir::Value, TransError> {
        let (cf, ctt) = (cl_type(from), cl_type(to));
        let bad = || Err(format!("{}.{to} of {from} in `{}`", op.name(), self.f.name));
        let ok = match op {
            ConvOp::Fpromote => from == Type::F32 && to == Type::F64,
            ConvOp::Fdemote => from == Type::F64 && to == Type::F32,
            ConvOp::SiToF | ConvOp::UiToF => from.is_int() && to.is_float(),
            ConvOp::FToSi | ConvOp::FToUi => from.is_float() && to.is_int(),
            _ => true,
        };
        if !ok {
            return bad();
        }
        Ok(match op {
            ConvOp::Sext => {
                if !from.is_int() || !to.is_int() {
                    return bad();
                }
                let a = self.signed_view(from, a);
                if cf == ctt {
                    self.canon(to, a)
                } else if ctt.bits() < cf.bits() {
                    return bad();
                } else {
                    self.b.ins().sextend(ctt, a)
                }
            }
            ConvOp::Uext => {
                if cf == ctt {
                    a
                } else if !from.is_int()
                    || !(to.is_int() || to == Type::Ptr)
                    || ctt.bits() < cf.bits()
                {
                    return bad();
                } else {
                    self.b.ins().uextend(ctt, a)
                }
            }
            ConvOp::Itrunc => {
                if !(from.is_int() || from == Type::Ptr) || !to.is_int() || ctt.bits() > cf.bits() {
                    return bad();
                }
                let v = if cf == ctt {
                    a
                } else {
                    self.b.ins().ireduce(ctt, a)
                };
                self.canon(to, v)
            }
            ConvOp::Fpromote => self.b.ins().fpromote(types::F64, a),
            ConvOp::Fdemote => self.b.ins().fdemote(types::F32, a),
            ConvOp::SiToF => {
                let a = self.signed_view(from, a);
                let a = if cf.bits() < 32 {
                    self.b.ins().sextend(types::I32, a)
                } else {
                    a
                };
                self.b.ins().fcvt_from_sint(ctt, a)
            }
            ConvOp::UiToF => {
                let a = if cf.bits() < 32 {
                    self.b.ins().uextend(types::I32, a)
                } else {
                    a
                };
                self.b.ins().fcvt_from_uint(ctt, a)
            }
            ConvOp::FToSi => {
                if ctt.bits() >= 32 {
                    self.b.ins().fcvt_to_sint_sat(ctt, a)
                } else {
                    // Saturate in 32 bits, then clamp to the narrow range.
                    let (lo, hi) = match to {
                        Type::I1 => (-1, 0),
                        Type::I8 => (i8::MIN as i64, i8::MAX as i64),
                        _ => (i16::MIN as i64, i16::MAX as i64),
                    };
                    let v = self.b.ins().fcvt_to_sint_sat(types::I32, a);
                    let hi = self.iconst(types::I32, hi);
                    let v = self.b.ins().smin(v, hi);
                    let lo = self.iconst(types::I32, lo);
                    let v = self.b.ins().smax(v, lo);
                    let v = self.b.ins().ireduce(ctt, v);
                    self.canon(to, v)
                }
            }
            ConvOp::FToUi => {
                if ctt.bits() >= 32 {
                    self.b.ins().fcvt_to_uint_sat(ctt, a)
                } else {
                    let hi = match to {
                        Type::I1 => 1,
                        Type::I8 => u8::MAX as i64,
                        _ => u16::MAX as i64,
                    };
                    let v = self.b.ins().fcvt_to_uint_sat(types::I32, a);
                    let hi = self.iconst(types::I32, hi);
                    let v = self.b.ins().umin(v, hi);
                    self.b.ins().ireduce(ctt, v)
                }
            }
            ConvOp::Bitcast => {
                if cf == ctt {
                    a
                } else if cf.bits() != ctt.bits() {
                    return bad();
                } else {
                    self.b.ins().bitcast(ctt, MemFlagsData::new(), a)
                }
            }
            ConvOp::PtrToInt | ConvOp::IntToPtr => {
                // Addresses are i64 here: cut or zero-extend.
                let a = if from == Type::I1 { return bad() } else { a };
                if cf == ctt {
                    a
                } else if ctt.bits() < cf.bits() {
                    self.b.ins().ireduce(ctt, a)
                } else {
                    self.b.ins().uextend(ctt, a)
                }
            }
        })
    }
}
