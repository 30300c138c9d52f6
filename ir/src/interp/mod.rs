//! The reference interpreter of the IR: the oracle every backend is compared with.
//!
//! It implements `docs/ir.md` directly, independently of any code generator. Memory is
//! one flat byte arena laid out by [`Layout::compute`] with [`LayoutRules::HOST`]: data
//! objects from [`DATA_BASE`] up (so address 0 is never valid), then a stack of call
//! frames holding stack slots. `ptr` values are byte addresses in the arena.
//!
//! Nobody zeroes memory in the IR's contract, so the interpreter fills fresh memory
//! (all data before cold start, every frame's slots at every call) with [`GARBAGE`]:
//! a front end that reads something it never wrote then misbehaves the same way every
//! time, and a `load.i1` of such a byte is an error outright.
//!
//! Anything the contract leaves undefined or forbids (an access outside the arena or
//! misaligned, an index out of range at `elem_addr`, a call chain deeper than
//! [`MAX_CALL_DEPTH`], a malformed instruction that is executed, a scan longer than
//! the step limit) is a [`MachineError`] naming the function and the instruction,
//! never a panic.

mod decode;
mod exec;
#[cfg(test)]
mod tests;

use crate::entities::{AggId, DataId, FuncId};
use crate::inst::{BinaryOp, ConvOp, FloatCC, IntCC, UnaryOp};
use crate::layout::{Layout, LayoutRules};
use crate::machine::{Machine, MachineError};
use crate::module::{AggDef, Module};
use crate::types::{MemType, Type};
use crate::value::PlcValue;
use decode::{canon, mem_type_ok, DFunc, Op, FRAME_ALIGN};
use exec::{Prog, State};

pub use exec::{DATA_BASE, GARBAGE, MAX_CALL_DEPTH, MAX_STACK_BYTES};

/// The step limit a new interpreter starts with: operations per scan (or cold start,
/// or [`Interp::call`]). About minutes of work, so a runaway loop ends in an error
/// even when nobody set a limit.
pub const DEFAULT_STEP_LIMIT: u64 = 10_000_000_000;

/// The most data memory a module may declare (beyond it, `new` fails rather than
/// trying to allocate it).
pub const MAX_DATA_BYTES: u64 = 1 << 30;

/// Why [`Interp::new`] could not load a module.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum SetupError {
    /// The module breaks a rule of the IR (a bug of whoever built it).
    Malformed(String),
    /// The program's data needs more than [`MAX_DATA_BYTES`] (a property of the
    /// program, not a bug).
    DataTooLarge {
        /// The bytes the data objects need.
        bytes: u64,
    },
}

impl std::fmt::Display for SetupError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            SetupError::Malformed(m) => f.write_str(m),
            SetupError::DataTooLarge { bytes } => write!(
                f,
                "the program's data takes {bytes} bytes, more than the interpreter's \
                 limit of {MAX_DATA_BYTES}"
            ),
        }
    }
}

/// The canonical register form of a value of type `ty` given as raw bits: integers
/// sign-extended from their width, `i1` 0 or 1, `f32` its encoding in the low 32 bits,
/// `f64` and `ptr` unchanged. The `eval_*` functions take and give this form.
pub fn canonical(ty: Type, bits: u64) -> u64 {
    canon(ty, bits)
}

/// The interpreter's semantics of a unary operation on an operand of type `ty` (for
/// checking constant folding and other backends against the oracle). The operation
/// must suit the type, as the verifier requires; otherwise the result is meaningless.
pub fn eval_unary(op: UnaryOp, ty: Type, a: u64) -> u64 {
    let a = canon(ty, a);
    match ty {
        Type::F32 => exec::f32_unary(op, f32::from_bits(a as u32)).to_bits() as u64,
        Type::F64 => exec::f64_unary(op, f64::from_bits(a)).to_bits(),
        _ => exec::int_unary(op, ty, a),
    }
}

/// The interpreter's semantics of a binary operation on operands of type `ty`: the
/// result and whether it raises the fault flag (division by zero).
pub fn eval_binary(op: BinaryOp, ty: Type, a: u64, b: u64) -> (u64, bool) {
    let (a, b) = (canon(ty, a), canon(ty, b));
    match ty {
        Type::F32 => {
            let r = exec::f32_binary(op, f32::from_bits(a as u32), f32::from_bits(b as u32));
            (r.to_bits() as u64, false)
        }
        Type::F64 => {
            let r = exec::f64_binary(op, f64::from_bits(a), f64::from_bits(b));
            (r.to_bits(), false)
        }
        _ => {
            let mut fault = false;
            let r = exec::int_binary(op, ty, a, b, &mut fault);
            (r, fault)
        }
    }
}

/// The interpreter's `icmp` on operands of type `ty`.
pub fn eval_icmp(cc: IntCC, ty: Type, a: u64, b: u64) -> bool {
    exec::int_cmp(cc, ty, canon(ty, a), canon(ty, b))
}

/// The interpreter's `fcmp` on operands of type `ty` (`f32` or `f64`).
pub fn eval_fcmp(cc: FloatCC, ty: Type, a: u64, b: u64) -> bool {
    if ty == Type::F32 {
        exec::f32_cmp(cc, f32::from_bits(a as u32), f32::from_bits(b as u32))
    } else {
        exec::f64_cmp(cc, f64::from_bits(a), f64::from_bits(b))
    }
}

/// The interpreter's conversion `op` of an operand of type `from` to type `to`.
pub fn eval_convert(op: ConvOp, from: Type, to: Type, a: u64) -> u64 {
    exec::convert(op, from, to, canon(from, a))
}

/// The reference interpreter: a [`Machine`] (target name `interp`) that runs a module
/// by executing its IR.
#[derive(Debug)]
pub struct Interp {
    module: Module,
    layout: Layout,
    funcs: Vec<DFunc>,
    data_addr: Vec<u64>,
    /// End of the data objects, rounded up: the stack starts here.
    stack_base: u64,
    st: State,
    clock_us: i64,
}

fn align_up(x: u64, a: u64) -> u64 {
    x.div_ceil(a.max(1)) * a.max(1)
}

/// Fails if an aggregate refers to an aggregate that does not exist or contains
/// itself, which would make [`Layout::compute`] panic.
fn check_aggs(module: &Module) -> Result<(), MachineError> {
    let members = |id: usize| -> Vec<MemType> {
        match &module.aggs[id] {
            AggDef::Struct(s) => s.fields.iter().map(|f| f.ty).collect(),
            AggDef::Array(a) => vec![a.elem],
        }
    };
    for (i, a) in module.aggs.iter().enumerate() {
        if let Some(t) = members(i).into_iter().find(|t| !mem_type_ok(module, *t)) {
            return Err(MachineError(format!(
                "aggregate %{} refers to a missing aggregate ({t:?})",
                a.name()
            )));
        }
    }
    // Depth-first search with colours: 1 = on the current path, 2 = done.
    let mut state = vec![0u8; module.aggs.len()];
    for root in 0..module.aggs.len() {
        if state[root] != 0 {
            continue;
        }
        let mut stack = vec![(root, 0usize)];
        state[root] = 1;
        while let Some(&mut (id, ref mut next)) = stack.last_mut() {
            let ms = members(id);
            if let Some(t) = ms.get(*next) {
                *next += 1;
                if let MemType::Agg(c) = *t {
                    match state[c.index()] {
                        0 => {
                            state[c.index()] = 1;
                            stack.push((c.index(), 0));
                        }
                        1 => {
                            return Err(MachineError(format!(
                                "aggregate %{} contains itself",
                                module.aggs[c.index()].name()
                            )))
                        }
                        _ => {}
                    }
                }
            } else {
                state[id] = 2;
                stack.pop();
            }
        }
    }
    Ok(())
}

impl Interp {
    /// Prepares `module` to run: lays out memory and pre-decodes every function.
    ///
    /// Fails if the module's structure is broken (a missing or self-containing
    /// aggregate, a program naming a missing function or data object, too much data).
    /// A malformed instruction does not fail here: it fails when it is executed.
    pub fn new(module: &Module) -> Result<Interp, SetupError> {
        check_aggs(module).map_err(|e| SetupError::Malformed(e.0))?;
        for d in &module.data {
            if !mem_type_ok(module, d.ty) {
                return Err(SetupError::Malformed(format!(
                    "data @{} has a missing type",
                    d.name
                )));
            }
        }
        let nf = module.funcs.len();
        for p in &module.programs {
            if p.body.index() >= nf || p.init.index() >= nf || p.data.index() >= module.data.len() {
                return Err(SetupError::Malformed(format!(
                    "program {} refers to a missing function or data object",
                    p.name
                )));
            }
        }
        if module.init_globals.is_some_and(|g| g.index() >= nf) {
            return Err(SetupError::Malformed(
                "init_globals is a missing function".into(),
            ));
        }

        let layout = Layout::compute(module, LayoutRules::HOST);
        let mut data_addr = Vec::with_capacity(module.data.len());
        let mut end = DATA_BASE;
        for d in &module.data {
            let addr = align_up(end, layout.align_of(d.ty) as u64);
            data_addr.push(addr);
            end = addr + layout.size_of(d.ty) as u64;
        }
        if end > MAX_DATA_BYTES {
            return Err(SetupError::DataTooLarge { bytes: end });
        }
        let stack_base = align_up(end, FRAME_ALIGN);
        let funcs = (0..nf)
            .map(|i| decode::decode(module, &layout, &data_addr, FuncId::new(i)))
            .collect();
        Ok(Interp {
            module: module.clone(),
            layout,
            funcs,
            data_addr,
            stack_base,
            st: State {
                mem: vec![GARBAGE; stack_base as usize],
                regs: Vec::new(),
                frames: Vec::new(),
                scratch: Vec::new(),
                fault: false,
                clock_ms: 0,
                clock_ns: 0,
                steps: 0,
                step_limit: DEFAULT_STEP_LIMIT,
            },
            clock_us: 0,
        })
    }

    /// Sets the most operations one scan (or cold start, or [`Interp::call`]) may
    /// execute before it fails with "step limit exceeded"; `None` for no limit.
    pub fn set_step_limit(&mut self, limit: Option<u64>) {
        self.st.step_limit = limit.unwrap_or(u64::MAX);
    }

    /// The operations executed by the last scan, cold start or call.
    pub fn steps(&self) -> u64 {
        self.st.steps
    }

    /// The module being run.
    pub fn module(&self) -> &Module {
        &self.module
    }

    /// The memory layout of the module's aggregates.
    pub fn layout(&self) -> &Layout {
        &self.layout
    }

    /// The arena address of a data object.
    pub fn data_addr(&self, data: DataId) -> Option<u64> {
        self.data_addr.get(data.index()).copied()
    }

    /// The arena address of field `field` of struct `agg` at `base` (a convenience for
    /// tests and tools that poke memory).
    pub fn field_addr(&self, base: u64, agg: AggId, field: u32) -> u64 {
        base + self.layout.field_offset(agg, field) as u64
    }

    /// The malformed instructions found while decoding, one message each naming the
    /// function and the instruction. Each fails only if executed; a module the
    /// verifier accepts has none.
    pub fn problems(&self) -> Vec<String> {
        let prog = Prog {
            funcs: &self.funcs,
            module: &self.module,
            stack_base: self.stack_base,
        };
        let mut out = Vec::new();
        for (fi, d) in self.funcs.iter().enumerate() {
            for (pc, op) in d.code.iter().enumerate() {
                if let Op::Trap { msg } = *op {
                    out.push(exec::fail(&prog, fi, pc, &d.traps[msg as usize]).0);
                }
            }
        }
        out
    }

    /// Calls `func` directly with raw argument registers and returns its raw result.
    ///
    /// Registers are bits: integers two's complement (any extension; they are
    /// canonicalised), `i1` 0 or 1, `f32` its encoding in the low 32 bits, `f64` its
    /// encoding, `ptr` an arena address. A returned integer is sign-extended from its
    /// width (an `i1` is 0 or 1). The clock and the fault flag are those of the machine.
    pub fn call(&mut self, func: FuncId, args: &[u64]) -> Result<Option<u64>, MachineError> {
        if func.index() >= self.funcs.len() {
            return Err(MachineError(format!("{func} does not exist")));
        }
        self.st.steps = 0;
        self.run(func, args)
    }

    fn run(&mut self, func: FuncId, args: &[u64]) -> Result<Option<u64>, MachineError> {
        let prog = Prog {
            funcs: &self.funcs,
            module: &self.module,
            stack_base: self.stack_base,
        };
        exec::run(&prog, &mut self.st, func.index(), args)
    }

    /// Resolves a path to its address and types.
    fn locate(&self, path: &str) -> Result<(u64, Type, crate::types::ElemType), MachineError> {
        let v = crate::vars::resolve(&self.module, path)?;
        let addr = self.data_addr[v.root.index()] + self.layout.offset_of(&v.steps);
        Ok((addr, v.ty, v.elem))
    }
}

impl Machine for Interp {
    fn target(&self) -> &str {
        "interp"
    }

    fn vars_module(&self) -> &crate::Module {
        &self.module
    }

    fn cold_start(&mut self) -> Result<(), MachineError> {
        self.st.fault = false;
        self.clock_us = 0;
        self.st.clock_ms = 0;
        self.st.clock_ns = 0;
        self.st.steps = 0;
        self.st.mem.truncate(self.stack_base as usize);
        self.st.mem.fill(GARBAGE);
        if let Some(g) = self.module.init_globals {
            self.run(g, &[])?;
        }
        for i in 0..self.module.programs.len() {
            let p = &self.module.programs[i];
            let (init, addr) = (p.init, self.data_addr[p.data.index()]);
            self.run(init, &[addr])?;
        }
        Ok(())
    }

    fn set_clock_us(&mut self, us: i64) {
        self.clock_us = us;
    }

    fn scan(&mut self) -> Result<(), MachineError> {
        // TIME wraps after 2^31 ms, as an i32 counter of milliseconds does.
        self.st.clock_ms = self.clock_us.div_euclid(1000) as i32;
        self.st.clock_ns = self.clock_us.wrapping_mul(1000);
        self.st.steps = 0;
        for i in 0..self.module.programs.len() {
            let p = &self.module.programs[i];
            let (body, addr) = (p.body, self.data_addr[p.data.index()]);
            self.run(body, &[addr])?;
        }
        Ok(())
    }

    fn read(&self, path: &str) -> Result<PlcValue, MachineError> {
        let (addr, ty, elem) = self.locate(path)?;
        // Raw bytes rather than `load`: a BOOL never written reads as its low bit
        // instead of failing, so that tools can list every variable.
        let size = exec::scalar_size(ty) as usize;
        let a = addr as usize;
        let mut b = [0u8; 8];
        b[..size].copy_from_slice(&self.st.mem[a..a + size]);
        Ok(PlcValue::from_bits(elem, u64::from_le_bytes(b)))
    }

    fn write(&mut self, path: &str, value: PlcValue) -> Result<(), MachineError> {
        let (addr, ty, elem) = self.locate(path)?;
        if value.ty != elem {
            return Err(MachineError(format!(
                "`{path}` is {elem}, cannot write a {} value",
                value.ty
            )));
        }
        let bits = if ty == Type::I1 {
            (value.bits != 0) as u64
        } else {
            canon(ty, value.bits)
        };
        self.st
            .store(ty, addr, bits, self.stack_base)
            .map_err(|m| MachineError(format!("{m} (writing `{path}`)")))
    }

    fn fault(&self) -> bool {
        self.st.fault
    }

    fn clear_fault(&mut self) {
        self.st.fault = false;
    }

    /// The interpreter's watchdog is its step limit: 500 million IR instructions per
    /// second of `limit`, faster than the interpreter runs, so a stopped scan has run
    /// at least `limit` (and the limit does not depend on the machine's speed).
    fn set_watchdog(&mut self, limit: Option<std::time::Duration>) {
        let steps = limit.map(|d| (d.as_secs_f64() * 500e6) as u64);
        self.set_step_limit(steps.or(Some(DEFAULT_STEP_LIMIT)));
    }
}
