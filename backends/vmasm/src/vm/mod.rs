//! A fast interpreter of CPDev XCP code images, with the semantics of CPDev's C VM
//! (`reference/cpdev-vm.md` §1–3) in all three addressing modes ([`Mode`]).
//!
//! # Execution model
//!
//! The code image is loaded at code address 0. [`Vm::new`] pre-decodes every
//! instruction reachable from address 0 (following fall-through, jump, call and TRML
//! targets) into a compact array of handlers with plain integer operands; jump targets
//! become array indexes. Bytes that do not decode, and addresses outside the image,
//! are an error only when executed. [`Vm::run`] executes until `TRML` ends the scan
//! (the next run resumes at TRML's label), until the PC reaches `stop_at`, or until the
//! instruction budget is used up. [`Vm::new`] zero-fills data memory; the VM never
//! clears it afterwards ([`Vm::reset`] leaves it alone).
//!
//! Speed: each entry is a handler (a function pointer) with up to four operands; the
//! loop calls one handler per entry. Common sequences of the CPDev compiler and of plcc
//! run as one *superinstruction* (a comparison followed by `JZ` or `JNZ` on its
//! result; a comparison, a SEL on its result and `JZ` on it; SEL followed by `JZ`; ADD,
//! SUB or MUL followed by `JMP`; the array access `MEMCP lac, i, #2; CEAC lac, …;
//! AxRD/AxWR …, lac`, alone or followed by `JMP`; AORD followed by `JZ` or `JNZ` on
//! the element read; the loop step (`vm/step.rs`): ADD or SUB, `JMP` to a comparison and
//! the `JZ` or `JNZ` after it, alone, after an array write, or after an AORD and the
//! branch on it that jumps to the step) that does the same loads and stores in the
//! same order; instruction counts, budgets, `stop_at` and fault PCs are exactly
//! those of the single instructions (near the end of a budget and around a breakpoint
//! the loop runs them singly). With [`Vm::for_port`], only the instructions whose C
//! evaluation can go wrong on that port are checked, and the checks of DIV, MOD and the
//! signed ADD, SUB and MUL first try a fast path for the operands that cannot.
//!
//! Every data operand is relative to DPTR (`data[DPTR + addr]`, the sum wrapping in the
//! mode's address width), except MMV's absolute side and the targets of the pointer
//! instructions DPRDL/DPWRL/CALBR. An access outside data memory, a RETURN with an
//! empty stack, a call deeper than 128, executing bytes that do not decode, or a PC
//! outside the code image is a [`VmError`] naming the PC; the PC stays at the faulting
//! instruction.
//!
//! # Semantics where the C VM is undefined (plcc's choices)
//!
//! - Integer arithmetic wraps. DIV and MOD by zero give 0; `MIN / -1` gives MIN and
//!   `MIN MOD -1` gives 0; MOD has the sign of the dividend. REAL/LREAL are IEEE.
//! - NOT BOOL is logical (`dst := src == 0`); AND/OR/XOR (BOOL included) and NOT on
//!   BYTE..LWORD are bitwise. ABS of the most negative integer is itself.
//! - SHL/SHR by a count outside `0..width` give 0; ROL/ROR take the count modulo the
//!   width (Euclidean: -1 rotates by width - 1).
//! - EXPT `06 01..08` as every public C VM numbers and computes it
//!   (`reference/cpdev-vm-opcodes.md` §2.1): 01 SINT**SINT, 02 INT**SINT, 03
//!   DINT**SINT, each written as a DINT, by square-and-multiply with the running
//!   square held in the base's type (so it wraps: 2**8 is 0 in 01); a negative
//!   exponent gives 1. 04 REAL**SINT, 05 REAL**INT, 06 REAL**DINT, 07 REAL**REAL:
//!   `(float)exp(log((double)x) * y)`; 08 LREAL**LREAL: `exp(log(x) * y)` (NaN for a
//!   negative base, not correctly rounded).
//! - TRUNC, REAL_TO_INT, REAL_TO_TIME, REAL_TO_DWORD: toward zero, saturating, NaN
//!   gives 0 (Rust `as`). ROUND: to nearest, ties away from zero, saturating.
//! - BCD_TO_INT: nibbles above 9 count as their binary value. INT_TO_BCD: the low 2
//!   (BYTE) or 4 (WORD) decimal digits of the absolute value.
//! - INT_TO_BOOL tests only the low byte of the INT (the C VM's `((WM_BOOL)x) > 0`).
//! - LIMIT is `MIN(MAX(in, mn), mx)`. MAX/MIN/LIMIT/comparisons on REAL use IEEE
//!   comparisons (NE is true on NaN, the others false). MUX with K out of range leaves
//!   dst unchanged.
//! - AURD/AUWR with a negative size variable is an error. CEAC out of range sets
//!   [`status::ARRAYBOUND`] and stops the VM with an error, as `VMP_Debug(6)` stops
//!   every CPDev runtime but iOS's. Opcodes the public C VMs do not execute (vmdef.h's
//!   DPRDL4A/DPWRL4A among them) are errors too.
//! - Array element addresses are `base + idx * size`, wrapping in the address width,
//!   relative to DPTR like every operand.
//! - CUR_TIME returns the value set by [`Vm::set_clock_ms`] (constant within a scan);
//!   TASK_CYCLE the value set by [`Vm::set_task_cycle_ms`].
//! - [`Vm::run`]'s `stop_at` is checked before every instruction, the first included:
//!   a run that starts at `stop_at` returns at once (step past it with
//!   `run(None, 1)`). When the budget runs out just as the PC reaches `stop_at`, the
//!   outcome is [`End::Budget`].

mod ops;
mod step;
mod ub;

use std::collections::BTreeMap;
use std::fmt;

use rustc_hash::FxHashMap;

use crate::isa::{shape, Inst, Kind, Mode, Operand};

/// The status word bits (`vm.h`).
pub mod status {
    /// The scan took longer than the task cycle.
    pub const CYCLEOVERRUN: u16 = 0x0001;
    /// CEAC found an index out of bounds.
    pub const ARRAYBOUND: u16 = 0x0002;
    /// Cold restart.
    pub const COLDRESTART: u16 = 0x0004;
    /// First start.
    pub const FIRSTSTART: u16 = 0x0008;
    /// The program image is malformed.
    pub const BADFORMAT: u16 = 0x0010;
    /// The VM is paused.
    pub const PAUSED: u16 = 0x4000;
    /// The VM is stopped.
    pub const STOPPED: u16 = 0x8000;
}

/// What GET_VMACH_VERSION stores.
pub const VMACH_VERSION: u16 = 0x2900;

/// Entries of the call stack (and of the saved-DPTR stack).
pub const STACK_DEPTH: usize = 128;

/// A run-time error of the VM; the message names the PC.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct VmError(pub String);

impl fmt::Display for VmError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for VmError {}

/// Why [`Vm::run`] returned.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum End {
    /// TRML ended the scan; the PC is TRML's label.
    Trml,
    /// The PC reached `stop_at`; the instruction there has not run.
    StopAt,
    /// The budget of instructions ran out (not an error); the PC is the next
    /// instruction to run.
    Budget,
}

/// The result of [`Vm::run`].
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct Outcome {
    /// Why the run ended.
    pub end: End,
    /// Instructions executed by this run.
    pub executed: u64,
}

/// What ended a handler's normal flow.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
enum Exit {
    Trml,
    Stop,
    Fault,
}

/// A handler body's result: the index of the next instruction, or why to stop.
type Step = Result<usize, Exit>;

/// What a handler returns instead of an index to stop the loop (the reason is in
/// `Core::exit`).
const EXIT: usize = usize::MAX;

/// An instruction handler: gets its entry index, returns the next one or [`EXIT`].
type Handler = fn(&mut Core, &Ins, usize) -> usize;

/// A decoded instruction: its handler and up to four integer operands.
#[derive(Copy, Clone)]
struct Ins {
    f: Handler,
    a: u32,
    b: u32,
    c: u32,
    d: u32,
    /// Operands of superinstructions only.
    e: u32,
    g: u32,
    h: u32,
    j: u32,
}

impl Ins {
    fn new(f: Handler, [a, b, c, d]: [u32; 4]) -> Ins {
        Ins {
            f,
            a,
            b,
            c,
            d,
            e: 0,
            g: 0,
            h: 0,
            j: 0,
        }
    }
}

/// What the superinstruction pass needs to know of an entry.
#[derive(Copy, Clone)]
enum Tag {
    Other,
    /// A comparison, with its fused forms followed by JZ and by JNZ, and by SEL and JZ
    /// (a SEL of 2 and of 4 bytes) for the comparisons of 16 and 32-bit integers; its
    /// group and type code.
    Rel(Handler, Handler, Option<(Handler, Handler)>, (u8, u8)),
    Jz,
    Jnz,
    Jmp,
    /// A binary operation, with its fused form followed by JMP; for ADD and SUB, the
    /// operation and its type code (for [`step`]).
    Bin(Handler, Option<(step::StepOp, u8)>),
    /// SEL of a size, with its fused form followed by JZ.
    Sel(Handler, usize),
    /// MEMCP of 2 bytes.
    Mov2,
    Ceac,
    /// An array access, with the fused forms of the MEMCP-CEAC-access sequence, alone
    /// and followed by JMP; for AORD, its fused forms followed by JZ and by JNZ on the
    /// variable read; for the writes, the element's size (for [`step`]).
    Acc(Handler, Handler, Option<(Handler, Handler)>, Option<usize>),
}

/// The most instructions one entry runs (a superinstruction).
const MAX_WEIGHT: u64 = 6;

/// The machine state the handlers work on.
struct Core {
    data: Vec<u8>,
    dptr: u32,
    /// The address mask of the mode (0xFFFF or 0xFFFF_FFFF).
    mask: u32,
    status: u16,
    clock: u32,
    cycle: u32,
    sp: usize,
    ret_idx: [u32; STACK_DEPTH],
    ret_dptr: [u32; STACK_DEPTH],
    /// Where TRML says the next scan starts (an index).
    trml: usize,
    /// Why the last handler returned [`EXIT`].
    exit: Exit,
    /// The message of the last fault.
    fault: String,
    /// Variadic operand addresses.
    pool: Vec<u32>,
    /// MCD payloads.
    bytes: Vec<u8>,
    /// Messages of the invalid entries.
    msgs: Vec<String>,
    /// Instructions run beyond one per handler call (superinstructions add, `goto`
    /// subtracts; wrapping).
    extra: u64,
    /// Instructions a loop step may run beyond its entry's weight by going round its
    /// loop again without returning ([`step`]); [`exec`] sets it aside from the budget.
    fuel: u64,
    /// After a fault in a superinstruction: entries it completed before the faulting one.
    skip: usize,
    /// The port whose C semantics are checked ([`Vm::for_port`]), if any.
    checks: Option<ub::Checks>,
    /// The handler and opcode of each checked instruction (its `e` field indexes this).
    checked: Vec<(Handler, u16)>,
}

impl Core {
    /// The data-memory index of a local (DPTR-relative) address.
    #[inline(always)]
    fn at(&self, addr: u32) -> usize {
        (self.dptr.wrapping_add(addr) & self.mask) as usize
    }

    /// The data-memory index of an absolute address.
    #[inline(always)]
    fn abs(&self, addr: u32) -> usize {
        (addr & self.mask) as usize
    }

    #[inline(always)]
    fn ld<T: ops::Val>(&mut self, addr: u32) -> Result<T, Exit> {
        let a = self.at(addr);
        match T::load(&self.data, a) {
            Some(v) => Ok(v),
            None => Err(self.oob(a, T::SIZE)),
        }
    }

    #[inline(always)]
    fn st<T: ops::Val>(&mut self, addr: u32, v: T) -> Result<(), Exit> {
        let a = self.at(addr);
        if v.store(&mut self.data, a) {
            Ok(())
        } else {
            Err(self.oob(a, T::SIZE))
        }
    }

    /// The range `a..a + n` of data memory, checked.
    #[inline]
    fn range(&mut self, a: usize, n: usize) -> Result<std::ops::Range<usize>, Exit> {
        let len = self.data.len();
        if a <= len && n <= len - a {
            Ok(a..a + n)
        } else {
            Err(self.oob(a, n))
        }
    }

    /// memmove of `n` bytes between data-memory indexes.
    #[inline]
    fn copy(&mut self, dst: usize, src: usize, n: usize) -> Result<(), Exit> {
        let s = self.range(src, n)?;
        self.range(dst, n)?;
        self.data.copy_within(s, dst);
        Ok(())
    }

    #[inline]
    fn push(&mut self, ret: usize) -> Result<(), Exit> {
        if self.sp == STACK_DEPTH {
            return Err(self.fault(format!("call stack overflow (deeper than {STACK_DEPTH})")));
        }
        self.ret_idx[self.sp] = ret as u32;
        self.ret_dptr[self.sp] = self.dptr;
        self.sp += 1;
        Ok(())
    }

    #[inline]
    fn pop(&mut self) -> Step {
        if self.sp == 0 {
            return Err(self.fault("RETURN with an empty call stack".into()));
        }
        self.sp -= 1;
        self.dptr = self.ret_dptr[self.sp];
        Ok(self.ret_idx[self.sp] as usize)
    }

    #[cold]
    #[inline(never)]
    fn oob(&mut self, a: usize, n: usize) -> Exit {
        self.fault(format!(
            "data access of {n} byte(s) at {a:#06x} is outside data memory ({} bytes)",
            self.data.len()
        ))
    }

    /// CEAC out of range: ARRAYBOUND is set and the VM stops, as the CPDev runtimes do.
    #[cold]
    #[inline(never)]
    fn ceac_stop(&mut self, idx: i16) -> Exit {
        self.status |= status::ARRAYBOUND;
        self.fault(format!(
            "CEAC: array index {idx} out of bounds (ARRAYBOUND: a CPDev runtime stops here)"
        ))
    }

    #[cold]
    #[inline(never)]
    fn fault(&mut self, m: String) -> Exit {
        self.fault = m;
        Exit::Fault
    }
}

/// A CPDev virtual machine running one XCP code image.
pub struct Vm {
    core: Core,
    /// The entries, superinstructions in place of the first of their instructions.
    code: Vec<Ins>,
    /// The handler of each entry without superinstructions.
    plain: Vec<Handler>,
    /// The loop steps ([`step`]): each entry and the comparison's entry it jumps to.
    steps: Vec<(usize, usize)>,
    /// The code address of each entry of `code`.
    pcs: Vec<u32>,
    /// Entry index of each code address that starts an instruction.
    index: FxHashMap<u32, u32>,
    /// The next instruction to run.
    idx: usize,
    /// The entry of code address 0.
    start: usize,
    mode: Mode,
    executed: u64,
}

/// What exploration found at a code address.
enum Found {
    Inst(Inst, usize),
    Bad(String),
}

impl Vm {
    /// A VM for the code image `code` (loaded at address 0) with `data_size` bytes of
    /// data memory (zero-filled here; programs initialise what they use) in `mode`.
    /// Fails only when the code or data does not fit the mode's address space.
    pub fn new(code: &[u8], data_size: usize, mode: Mode) -> Result<Vm, VmError> {
        Vm::make(code, data_size, mode, None)
    }

    /// As [`Vm::new`], for the C VM of `port`: an instruction whose C evaluation would
    /// be undefined there (a signed overflow, a division by zero, a shift by the width,
    /// a float cast out of range) or whose LINT operand the port misreads stops the VM
    /// with an error, as a real VM would go wrong (`ub.rs`).
    pub fn for_port(
        code: &[u8],
        data_size: usize,
        mode: Mode,
        port: crate::port::Port,
    ) -> Result<Vm, VmError> {
        Vm::make(code, data_size, mode, Some(ub::Checks::for_port(port)))
    }

    fn make(
        code: &[u8],
        data_size: usize,
        mode: Mode,
        checks: Option<ub::Checks>,
    ) -> Result<Vm, VmError> {
        let space = mode.max_addr() + 1;
        if data_size as u64 > space {
            return Err(VmError(format!(
                "data memory of {data_size} bytes does not fit {}-bit addresses",
                8 * mode.addr_bytes()
            )));
        }
        if code.len() as u64 > space {
            return Err(VmError(format!(
                "a code image of {} bytes does not fit {}-bit addresses",
                code.len(),
                8 * mode.addr_bytes()
            )));
        }
        let mut core = Core {
            data: vec![0; data_size],
            dptr: 0,
            mask: mode.max_addr() as u32,
            status: 0,
            clock: 0,
            cycle: 0,
            sp: 0,
            ret_idx: [0; STACK_DEPTH],
            ret_dptr: [0; STACK_DEPTH],
            trml: 0,
            exit: Exit::Fault,
            fault: String::new(),
            pool: Vec::new(),
            bytes: Vec::new(),
            msgs: Vec::new(),
            extra: 0,
            fuel: 0,
            skip: 0,
            checks,
            checked: Vec::new(),
        };
        let found = explore(code, mode);

        // Lay out in address order; a fall-through that is not the next entry gets a
        // `goto` pseudo-instruction.
        let mut out: Vec<Ins> = Vec::with_capacity(found.len() + 1);
        let mut tags: Vec<Tag> = Vec::with_capacity(found.len() + 1);
        let mut pcs = Vec::with_capacity(found.len() + 1);
        let mut index = FxHashMap::default();
        // (entry, field, target code address)
        let mut fixups: Vec<(usize, usize, u32)> = Vec::new();
        let entries: Vec<(u32, Found)> = found.into_iter().collect();
        for (j, (pc, f)) in entries.iter().enumerate() {
            let pc = *pc;
            index.insert(pc, out.len() as u32);
            pcs.push(pc);
            match f {
                Found::Bad(m) => {
                    out.push(invalid(&mut core, m.clone()));
                    tags.push(Tag::Other);
                }
                Found::Inst(inst, len) => {
                    let e = out.len();
                    let lacked = core.checks.and_then(|k| {
                        k.port.lacks(inst.opcode).map(|p| {
                            format!(
                                "opcode {} needs {}, which port `{}` lacks",
                                inst.opcode,
                                p.describe(),
                                k.port.name()
                            )
                        })
                    });
                    match lacked.map_or_else(|| translate(inst, mode, &mut core), Err) {
                        Ok((mut ins, mut tag)) => {
                            if let Some(k) = core.checks.filter(|k| ub::watched(inst.opcode.0, k)) {
                                ins.e = core.checked.len() as u32;
                                core.checked.push((ins.f, inst.opcode.0));
                                ins.f = fast_check(inst.opcode.0, &k).unwrap_or(ops::checked);
                                tag = Tag::Other;
                            }
                            out.push(ins);
                            tags.push(tag);
                            let kinds = shape(inst.opcode, mode).map(|s| s.1).unwrap_or_default();
                            for (field, k) in kinds.iter().enumerate() {
                                if let (Kind::Code, Some(Operand::Code(t))) =
                                    (k, inst.operands.get(field))
                                {
                                    fixups.push((e, field, *t));
                                }
                            }
                        }
                        Err(m) => {
                            let m = format!("at code address {pc:04x}: {m}");
                            out.push(invalid(&mut core, m));
                            tags.push(Tag::Other);
                        }
                    }
                    if falls_through(inst) {
                        let next = next_pc(pc, *len, mode);
                        if entries.get(j + 1).map(|x| x.0) != Some(next) {
                            fixups.push((out.len(), 0, next));
                            out.push(Ins::new(ops::goto, [0; 4]));
                            tags.push(Tag::Other);
                            pcs.push(next);
                        }
                    }
                }
            }
        }
        for (e, field, t) in fixups {
            // Exploration decoded every target, so the lookup succeeds.
            let target = index.get(&t).copied().unwrap_or(u32::MAX);
            let ins = &mut out[e];
            match field {
                0 => ins.a = target,
                1 => ins.b = target,
                2 => ins.c = target,
                _ => ins.d = target,
            }
        }
        let plain = out.iter().map(|i| i.f).collect();
        let steps = fuse(&mut out, &tags, &mut core.pool);
        let start = index.get(&0).copied().unwrap_or(0) as usize;
        Ok(Vm {
            core,
            code: out,
            plain,
            steps,
            pcs,
            index,
            idx: start,
            start,
            mode,
            executed: 0,
        })
    }

    /// Data memory.
    pub fn data(&self) -> &[u8] {
        &self.core.data
    }

    /// Data memory, writable.
    pub fn data_mut(&mut self) -> &mut [u8] {
        &mut self.core.data
    }

    /// PC := 0, the stacks empty, DPTR := 0, the status word cleared; data memory is
    /// untouched.
    pub fn reset(&mut self) {
        self.idx = self.start;
        self.core.sp = 0;
        self.core.dptr = 0;
        self.core.status = 0;
    }

    /// Sets what CUR_TIME returns (milliseconds) until changed.
    pub fn set_clock_ms(&mut self, ms: u32) {
        self.core.clock = ms;
    }

    /// Sets what TASK_CYCLE returns (milliseconds).
    pub fn set_task_cycle_ms(&mut self, ms: u32) {
        self.core.cycle = ms;
    }

    /// The status word.
    pub fn status(&self) -> u16 {
        self.core.status
    }

    /// Sets the status word.
    pub fn set_status(&mut self, s: u16) {
        self.core.status = s;
    }

    /// The program counter: the code address of the next instruction to run.
    pub fn pc(&self) -> u32 {
        self.pcs[self.idx]
    }

    /// The data pointer (DPTR).
    pub fn dptr(&self) -> u32 {
        self.core.dptr
    }

    /// The number of active calls.
    pub fn call_depth(&self) -> usize {
        self.core.sp
    }

    /// The addressing mode.
    pub fn mode(&self) -> Mode {
        self.mode
    }

    /// True if `pc` is the address of an instruction reachable from address 0.
    pub fn is_instruction(&self, pc: u32) -> bool {
        self.index.contains_key(&pc)
    }

    /// The number of superinstructions.
    #[cfg(test)]
    fn superinstructions(&self) -> usize {
        self.code
            .iter()
            .zip(&self.plain)
            .filter(|(i, &p)| i.f as usize != p as usize)
            .count()
    }

    /// Total instructions executed since [`Vm::new`].
    pub fn executed(&self) -> u64 {
        self.executed
    }

    /// Runs until TRML (the scan ends; the next run starts at TRML's label), until the
    /// PC equals `stop_at` before the instruction there runs (checked before the first
    /// instruction too), or until `budget` instructions have run ([`End::Budget`], not
    /// an error). Returns why it stopped and the number of instructions executed. A
    /// fault is an error naming the PC, which stays at the faulting instruction.
    pub fn run(&mut self, stop_at: Option<u32>, budget: u64) -> Result<Outcome, VmError> {
        let stop = stop_at
            .and_then(|pc| self.index.get(&pc))
            .map(|&e| e as usize);
        // A breakpoint: the stop handler at `e` (in both tables), and no
        // superinstruction running over it.
        let mut saved = Vec::new();
        if let Some(e) = stop {
            let steps_over = self
                .steps
                .iter()
                .filter(|&&(_, t)| t == e || t + 1 == e)
                .map(|&(j, _)| j);
            for j in (e.saturating_sub(MAX_WEIGHT as usize - 1)..e).chain(steps_over) {
                saved.push((j, self.code[j].f));
                self.code[j].f = self.plain[j];
            }
            saved.push((e, self.code[e].f));
            self.code[e].f = ops::stop;
        }
        let plain_e = stop.map(|e| std::mem::replace(&mut self.plain[e], ops::stop));
        let (k, n, exit) = exec(&mut self.core, &self.code, &self.plain, self.idx, budget);
        if let (Some(e), Some(f)) = (stop, plain_e) {
            self.plain[e] = f;
        }
        for (j, f) in saved.into_iter().rev() {
            self.code[j].f = f;
        }
        self.executed += n;
        let end = match exit {
            None => {
                self.idx = k;
                End::Budget
            }
            Some(Exit::Trml) => {
                self.idx = self.core.trml;
                End::Trml
            }
            Some(Exit::Stop) => {
                self.idx = k;
                End::StopAt
            }
            Some(Exit::Fault) => {
                self.idx = k;
                let m = std::mem::take(&mut self.core.fault);
                return Err(VmError(format!("at PC {:04x}: {m}", self.pcs[k])));
            }
        };
        Ok(Outcome { end, executed: n })
    }

    /// Runs one scan: until TRML. Running out of `budget` instructions first is an
    /// error. Returns the instructions executed.
    pub fn run_cycle(&mut self, budget: u64) -> Result<u64, VmError> {
        let o = self.run(None, budget)?;
        match o.end {
            End::Trml => Ok(o.executed),
            _ => Err(VmError(format!(
                "at PC {:04x}: the scan did not end within {budget} instructions",
                self.pc()
            ))),
        }
    }
}

/// The interpreter loop from entry `k`. Returns the entry reached (the faulting
/// instruction after a fault), the number of instructions executed (the stop handler
/// and faulting instructions not counted), and the exit (None: the budget is used up).
#[inline(never)]
fn exec(
    c: &mut Core,
    code: &[Ins],
    plain: &[Handler],
    mut k: usize,
    budget: u64,
) -> (usize, u64, Option<Exit>) {
    // `n` counts handler calls, `n + c.extra` instructions, which never exceed the
    // budget: each chunk sets half its room aside as fuel for the loop steps that go
    // round their loops without returning, and makes only as many calls as cannot
    // overshoot the other half; the last few instructions run one at a time without
    // superinstructions.
    c.extra = 0;
    let mut n = 0u64;
    let exit = 'run: {
        loop {
            let room = budget - n.wrapping_add(c.extra);
            if room < 2 * MAX_WEIGHT {
                break;
            }
            c.fuel = room / 2;
            let end = n + (room - c.fuel) / MAX_WEIGHT;
            while n < end {
                let ins = &code[k];
                let next = (ins.f)(c, ins, k);
                if next == EXIT {
                    break 'run c.exit;
                }
                n += 1;
                k = next;
            }
        }
        while n.wrapping_add(c.extra) < budget {
            let next = plain[k](c, &code[k], k);
            if next == EXIT {
                break 'run c.exit;
            }
            n += 1;
            k = next;
        }
        return (k, n.wrapping_add(c.extra), None);
    };
    let done = n.wrapping_add(c.extra);
    match exit {
        Exit::Trml => (k, done + 1, Some(exit)),
        Exit::Stop => (k, done, Some(exit)),
        Exit::Fault => (k + std::mem::take(&mut c.skip), done, Some(exit)),
    }
}

/// Puts superinstructions in place of the first entry of the sequences they run: a
/// comparison followed by JZ or JNZ on its result, a binary operation followed by JMP,
/// SEL followed by JZ, a comparison followed by a SEL on its result and JZ on it, and
/// the array access `MEMCP lac, i, #2; CEAC lac, …; AxRD/AxWR …, lac`, alone and
/// followed by JMP; and the loop step ([`step`]: ADD or SUB, JMP to a comparison and
/// JZ or JNZ); AORD followed by JZ or JNZ on the variable read. The entries stay in place for jumps into the sequence; the operands of
/// the later entries are copied into the first. Returns the loop steps (each entry and
/// the comparison's entry).
fn fuse(code: &mut [Ins], tags: &[Tag], pool: &mut Vec<u32>) -> Vec<(usize, usize)> {
    let mut steps = Vec::new();
    for k in 0..code.len() {
        let at = |j: usize| tags.get(k + j).copied().unwrap_or(Tag::Other);
        match (tags[k], at(1), at(2), at(3)) {
            (Tag::Acc(_, _, _, Some(size)), Tag::Bin(_, Some((sop, bt))), Tag::Jmp, _)
                if step_target(code, tags, k + 1)
                    .and_then(|(_, grp, rt, z)| step::after_write(size, sop, bt, grp, rt, z))
                    .is_some() =>
            {
                let (t, grp, rt, z) = step_target(code, tags, k + 1).expect("checked");
                let h = step::after_write(size, sop, bt, grp, rt, z).expect("checked");
                let (bin, rel, br) = (code[k + 1], code[t], code[t + 1]);
                let d = pool.len() as u32;
                pool.extend_from_slice(&[bin.a, bin.b, bin.c, t as u32]);
                let i = &mut code[k];
                i.d = d;
                (i.e, i.g, i.h, i.j) = (rel.a, rel.b, rel.c, br.b);
                i.f = h;
                steps.push((k, t));
            }
            (Tag::Rel(_, _, Some((h2, h4)), _), Tag::Sel(_, n @ (2 | 4)), Tag::Jz, _)
                if code[k + 1].b == code[k].a && code[k + 2].a == code[k].a =>
            {
                let (sel, jz) = (code[k + 1], code[k + 2]);
                let i = &mut code[k];
                (i.d, i.e, i.g, i.h) = (sel.a, sel.c, sel.d, jz.b);
                i.f = if n == 2 { h2 } else { h4 };
            }
            (Tag::Mov2, Tag::Ceac, Tag::Acc(_, h, _, _), Tag::Jmp)
                if code[k + 1].a == code[k].a && code[k + 2].c == code[k].a =>
            {
                let (ceac, acc, jmp) = (code[k + 1], code[k + 2], code[k + 3]);
                let i = &mut code[k];
                (i.c, i.d, i.e, i.g, i.h) = (ceac.b, ceac.c, acc.a, acc.b, jmp.a);
                i.f = h;
            }
            (Tag::Rel(h, _, _, _), Tag::Jz, _, _) | (Tag::Rel(_, h, _, _), Tag::Jnz, _, _)
                if code[k + 1].a == code[k].a =>
            {
                code[k].d = code[k + 1].b;
                code[k].f = h;
            }
            (Tag::Bin(_, Some((sop, bt))), Tag::Jmp, _, _)
                if step_target(code, tags, k)
                    .and_then(|(_, grp, rt, z)| step::handler::<step::Alone>(sop, bt, grp, rt, z))
                    .is_some() =>
            {
                let (t, grp, rt, z) = step_target(code, tags, k).expect("checked");
                let h = step::handler::<step::Alone>(sop, bt, grp, rt, z).expect("checked");
                let (rel, br) = (code[t], code[t + 1]);
                let i = &mut code[k];
                (i.d, i.e, i.g, i.h, i.j) = (t as u32, rel.a, rel.b, rel.c, br.b);
                i.f = h;
                steps.push((k, t));
            }
            (Tag::Acc(_, _, Some(_), _), br @ (Tag::Jz | Tag::Jnz), _, _)
                if code[k + 1].a == code[k].a && read_skip(code, tags, k, br).is_some() =>
            {
                let (h, d, t) = read_skip(code, tags, k, br).expect("checked");
                let (bin, rel, back) = (code[d], code[t], code[t + 1]);
                let x = pool.len() as u32;
                pool.extend_from_slice(&[bin.a, bin.b, bin.c, t as u32, rel.a, rel.b, rel.c]);
                let i = &mut code[k];
                (i.d, i.e, i.g) = (d as u32, x, back.b);
                i.f = h;
                steps.push((k, d));
                steps.push((k, t));
            }
            (Tag::Acc(_, _, Some((h, _)), _), Tag::Jz, _, _)
            | (Tag::Acc(_, _, Some((_, h)), _), Tag::Jnz, _, _)
                if code[k + 1].a == code[k].a =>
            {
                code[k].d = code[k + 1].b;
                code[k].f = h;
            }
            (Tag::Bin(h, _), Tag::Jmp, _, _) => {
                code[k].d = code[k + 1].a;
                code[k].f = h;
            }
            (Tag::Sel(h, _), Tag::Jz, _, _) => {
                (code[k].e, code[k].g) = (code[k + 1].a, code[k + 1].b);
                code[k].f = h;
            }
            (Tag::Mov2, Tag::Ceac, Tag::Acc(h, _, _, _), _)
                if code[k + 1].a == code[k].a && code[k + 2].c == code[k].a =>
            {
                let (ceac, acc) = (code[k + 1], code[k + 2]);
                let i = &mut code[k];
                (i.c, i.d, i.e, i.g) = (ceac.b, ceac.c, acc.a, acc.b);
                i.f = h;
            }
            _ => {}
        }
    }
    steps
}

/// For the ADD or SUB at entry `k` (followed by a JMP): the entry of the comparison
/// the JMP goes to, its group and type code, and whether JZ (else JNZ) follows it on
/// its result; `None` if something else is there.
fn step_target(code: &[Ins], tags: &[Tag], k: usize) -> Option<(usize, u8, u8, bool)> {
    let t = code.get(k + 1)?.a as usize;
    let Tag::Rel(_, _, _, (grp, rt)) = *tags.get(t)? else {
        return None;
    };
    let z = match tags.get(t + 1)? {
        Tag::Jz => true,
        Tag::Jnz => false,
        _ => return None,
    };
    if code[t + 1].a != code[t].a {
        return None;
    }
    Some((t, grp, rt, z))
}

/// For the AORD at entry `k` followed by the branch `br` (JZ or JNZ) on its result:
/// the handler that also runs the loop step at the branch's target (see
/// `step::ReadSkip`), the step's entry and its comparison's entry; `None` if no loop
/// step is there.
fn read_skip(code: &[Ins], tags: &[Tag], k: usize, br: Tag) -> Option<(Handler, usize, usize)> {
    let d = code[k + 1].b as usize;
    let Tag::Bin(_, Some((sop, bt))) = *tags.get(d)? else {
        return None;
    };
    if !matches!(tags.get(d + 1)?, Tag::Jmp) {
        return None;
    }
    let (t, grp, rt, z) = step_target(code, tags, d)?;
    let h = step::after_read(matches!(br, Tag::Jz), sop, bt, grp, rt, z)?;
    Some((h, d, t))
}

/// An entry that fails with `m` when executed.
fn invalid(core: &mut Core, m: String) -> Ins {
    core.msgs.push(m);
    Ins::new(ops::invalid, [core.msgs.len() as u32 - 1, 0, 0, 0])
}

/// The address after an instruction (the PC wraps in the address width).
fn next_pc(pc: u32, len: usize, mode: Mode) -> u32 {
    ((pc as u64 + len as u64) & mode.max_addr()) as u32
}

/// False for the instructions after which execution never continues at the next address.
fn falls_through(inst: &Inst) -> bool {
    !matches!(inst.opcode.0, 0x1C00 | 0x1C13 | 0x1C18 | 0x1C1D)
}

/// Decodes everything reachable from address 0.
fn explore(code: &[u8], mode: Mode) -> BTreeMap<u32, Found> {
    let mut found = BTreeMap::new();
    let mut work = vec![0u32];
    while let Some(pc) = work.pop() {
        if found.contains_key(&pc) {
            continue;
        }
        let f = if pc as usize >= code.len() {
            Found::Bad(format!("PC outside the code image ({} bytes)", code.len()))
        } else {
            match Inst::decode(code, pc, mode) {
                Ok((inst, len)) => {
                    for o in &inst.operands {
                        if let Operand::Code(t) = o {
                            work.push(*t);
                        }
                    }
                    if falls_through(&inst) {
                        work.push(next_pc(pc, len, mode));
                    }
                    Found::Inst(inst, len)
                }
                Err(e) => Found::Bad(e.to_string()),
            }
        };
        found.insert(pc, f);
    }
    found
}

/// The handler for a type code over every numeric type.
macro_rules! num {
    ($t:expr, $h:ident $(, $o:ty)* $(; $z:expr)?) => {
        match $t {
            0 | 5 => Some(ops::$h::<u8 $(, $o)* $(, $z)?> as Handler),
            1 => Some(ops::$h::<i8 $(, $o)* $(, $z)?> as Handler),
            2 => Some(ops::$h::<i16 $(, $o)* $(, $z)?> as Handler),
            3 => Some(ops::$h::<i32 $(, $o)* $(, $z)?> as Handler),
            4 => Some(ops::$h::<i64 $(, $o)* $(, $z)?> as Handler),
            6 => Some(ops::$h::<u16 $(, $o)* $(, $z)?> as Handler),
            7 | 0xB | 0xC | 0xD => Some(ops::$h::<u32 $(, $o)* $(, $z)?> as Handler),
            8 | 0xE => Some(ops::$h::<u64 $(, $o)* $(, $z)?> as Handler),
            9 => Some(ops::$h::<f32 $(, $o)* $(, $z)?> as Handler),
            0xA => Some(ops::$h::<f64 $(, $o)* $(, $z)?> as Handler),
            _ => None,
        }
    };
}

/// The handler for an integer type code (BOOL excluded, as [`ub::check`] reads it).
macro_rules! int {
    ($t:expr, $h:ident $(, $o:ty)*) => {
        match $t {
            1 => Some(ops::$h::<i8 $(, $o)*> as Handler),
            2 => Some(ops::$h::<i16 $(, $o)*> as Handler),
            3 => Some(ops::$h::<i32 $(, $o)*> as Handler),
            4 => Some(ops::$h::<i64 $(, $o)*> as Handler),
            5 => Some(ops::$h::<u8 $(, $o)*> as Handler),
            6 => Some(ops::$h::<u16 $(, $o)*> as Handler),
            7 => Some(ops::$h::<u32 $(, $o)*> as Handler),
            8 => Some(ops::$h::<u64 $(, $o)*> as Handler),
            _ => None,
        }
    };
}

/// A checked handler with a fast path for the common operands of a watched `op`
/// (DIV and MOD; the two-operand ADD, SUB and MUL of up to 32 bits), or `None` for
/// [`ops::checked`] alone.
fn fast_check(op: u16, k: &ub::Checks) -> Option<Handler> {
    let (g, f) = ((op >> 8) as u8, op as u8);
    let t = f & 0xF;
    let lint = t == 4 && k.lint_read_bug;
    match g {
        0x04 if !lint && f < 0x10 => int!(t, checked_div, ops::Div),
        0x04 if !lint && f >> 4 == 1 => int!(t, checked_div, ops::Rem),
        0x01 if t != 4 && f >> 4 == 2 => int!(t, checked_arith, ops::Add),
        0x02 if t != 4 => int!(t, checked_arith, ops::Sub),
        0x03 if t != 4 && f >> 4 == 2 => int!(t, checked_arith, ops::Mul),
        _ => None,
    }
    .filter(|_| matches!(t, 1..=3 | 5 | 6) || (g == 0x04 && matches!(t, 4 | 7 | 8)))
}

/// The handler for a value size in bytes (1, 2, 4, 8).
macro_rules! sized {
    ($n:expr, $h:ident $(, $o:ty)* $(; $z:expr)?) => {
        match $n {
            1 => Some(ops::$h::<u8 $(, $o)* $(, $z)?> as Handler),
            2 => Some(ops::$h::<u16 $(, $o)* $(, $z)?> as Handler),
            4 => Some(ops::$h::<u32 $(, $o)* $(, $z)?> as Handler),
            8 => Some(ops::$h::<u64 $(, $o)* $(, $z)?> as Handler),
            _ => None,
        }
    };
}

/// The handler for a float function byte (even: REAL, odd: LREAL).
macro_rules! float {
    ($f:expr, $o:ty) => {
        Some(if $f & 1 == 0 {
            ops::un1::<f32, $o> as Handler
        } else {
            ops::un1::<f64, $o> as Handler
        })
    };
}

/// Bytes of a value of type code `t` (STRING: 0).
fn ty_size(t: u8) -> usize {
    crate::isa::Ty::from_code(t).map_or(0, |t| t.size())
}

/// The fused forms of a comparison followed by JZ and by JNZ.
macro_rules! rel_j {
    ($t:expr, $r:ident) => {
        (
            num!($t, rel_j, ops::$r; true),
            num!($t, rel_j, ops::$r; false),
        )
    };
}

/// The fused forms of a comparison of 16 or 32-bit integers followed by a SEL of 2 and
/// of 4 bytes and JZ.
macro_rules! rel_sel_jz {
    ($t:expr, $r:ident) => {{
        macro_rules! both {
            ($ty:ty) => {
                Some((
                    ops::rel_sel_jz::<$ty, ops::$r, u16> as Handler,
                    ops::rel_sel_jz::<$ty, ops::$r, u32> as Handler,
                ))
            };
        }
        match $t {
            2 => both!(i16),
            3 => both!(i32),
            6 => both!(u16),
            7 => both!(u32),
            _ => None,
        }
    }};
}

/// Translates a decoded instruction. Operand fields are in encoding order, except for
/// the variadic groups, MUX and MCD (see the handlers).
fn translate(inst: &Inst, mode: Mode, core: &mut Core) -> Result<(Ins, Tag), String> {
    use crate::isa::op::group as g;
    let (grp, f) = (inst.opcode.group(), inst.opcode.func());
    let n = (f >> 4) as usize;
    let t = f & 0xF;
    let mut v = [0u32; 4];
    let mut bytes: Option<&[u8]> = None;
    let mut rest: Vec<u32> = Vec::new();
    for (j, o) in inst.operands.iter().enumerate() {
        let x = match o {
            Operand::Data(x) | Operand::Code(x) | Operand::Imm(x) => *x,
            Operand::Bytes(b) => {
                bytes = Some(b);
                continue;
            }
        };
        if j < 4 {
            v[j] = x;
        }
        rest.push(x);
    }
    let mut ins = Ins::new(ops::nop, v);
    let mut tag = Tag::Other;
    // The fused form of a two-operand ADD, SUB or MUL followed by JMP.
    let mut jmp_form: Option<Handler> = None;
    let m16 = mode == Mode::M16;
    // A variadic group: 2 sources inline, more through the operand pool.
    let mut variadic = |two: Option<Handler>, many: Option<Handler>| {
        if n == 2 {
            two
        } else {
            ins.b = core.pool.len() as u32;
            ins.c = (rest.len() - 1) as u32;
            core.pool.extend_from_slice(&rest[1..]);
            many
        }
    };
    let h: Option<Handler> = match grp {
        0x00 if f == 0 => Some(ops::nop),
        g::ADD => {
            jmp_form = num!(t, bin_jmp, ops::Add);
            variadic(num!(t, bin, ops::Add), num!(t, fold, ops::Add))
        }
        g::MUL => {
            jmp_form = num!(t, bin_jmp, ops::Mul);
            variadic(num!(t, bin, ops::Mul), num!(t, fold, ops::Mul))
        }
        g::SUB => {
            jmp_form = num!(t, bin_jmp, ops::Sub);
            num!(t, bin, ops::Sub)
        }
        g::DIV if f < 0x10 => num!(t, bin, ops::Div),
        g::DIV => num!(t, bin, ops::Rem),
        g::NEG => match f {
            0x01..=0x04 | 0x07 | 0x09 => num!(
                match f {
                    7 => 9,
                    9 => 0xA,
                    x => x,
                },
                un1,
                ops::Neg
            ),
            0x10 => Some(ops::un1::<u8, ops::NotBool>),
            0x11..=0x14 => sized!(1usize << (f - 0x11), un1, ops::Not),
            _ => None,
        },
        g::MATH => match f {
            0x01 => Some(ops::expt_ss),
            0x02 => Some(ops::expt_is),
            0x03 => Some(ops::expt_ds),
            0x04 => Some(ops::expt_rs),
            0x05 => Some(ops::expt_ri),
            0x06 => Some(ops::expt_rd),
            0x07 => Some(ops::expt_rr),
            0x08 => Some(ops::expt_ll),
            0x11..=0x1A => num!(t, un1, ops::Abs),
            0x20 | 0x21 => float!(f, ops::Sqrt),
            0x22 | 0x23 => float!(f, ops::Ln),
            0x24 | 0x25 => float!(f, ops::Log),
            0x26 | 0x27 => float!(f, ops::Exp),
            0x28 | 0x29 => float!(f, ops::Sin),
            0x2A | 0x2B => float!(f, ops::Cos),
            0x2C | 0x2D => float!(f, ops::Tan),
            0x2E | 0x2F => float!(f, ops::Asin),
            0x30 | 0x31 => float!(f, ops::Acos),
            0x32 | 0x33 => float!(f, ops::Atan),
            0x34 => Some(ops::un::<f32, i32, ops::Trunc>),
            0x35 => Some(ops::un::<f64, i64, ops::Trunc>),
            0x36 => Some(ops::un::<f32, i32, ops::Round>),
            0x37 => Some(ops::un::<f64, i64, ops::Round>),
            _ => None,
        },
        g::MMV => {
            ins.c = (f & 0x7F) as u32;
            Some(if f & 0x80 == 0 {
                ops::mmv_in
            } else {
                ops::mmv_out
            })
        }
        g::AND | g::OR | g::XOR => {
            // AND/OR: BOOL 0, BYTE 1, WORD 2, DWORD 3, LWORD 4; XOR: …, DWORD 4, LWORD 5.
            let size = match (grp, t) {
                (_, 0 | 1) => 1,
                (_, 2) => 2,
                (g::XOR, 4) | (g::AND | g::OR, 3) => 4,
                (g::XOR, 5) | (g::AND | g::OR, 4) => 8,
                _ => 0,
            };
            match grp {
                g::AND => variadic(sized!(size, bin, ops::And), sized!(size, fold, ops::And)),
                g::OR => variadic(sized!(size, bin, ops::Or), sized!(size, fold, ops::Or)),
                _ => variadic(sized!(size, bin, ops::Xor), sized!(size, fold, ops::Xor)),
            }
        }
        g::SHIFT if (1..=4).contains(&t) => {
            let size = 1usize << (t - 1);
            match n {
                0 => sized!(size, shift, ops::Shl),
                1 => sized!(size, shift, ops::Shr),
                2 => sized!(size, shift, ops::Rol),
                3 => sized!(size, shift, ops::Ror),
                _ => None,
            }
        }
        g::SEL if f <= 0xE => {
            if let Some(x) = sized!(ty_size(t), sel_jz) {
                tag = Tag::Sel(x, ty_size(t));
            }
            sized!(ty_size(t), sel)
        }
        g::LIMIT if f <= 0xE => num!(t, limit),
        g::MAX => variadic(num!(t, bin, ops::Max), num!(t, fold, ops::Max)),
        g::MIN => variadic(num!(t, bin, ops::Min), num!(t, fold, ops::Min)),
        g::GT..=g::NE if f <= 0xE => {
            let (h, fused) = match grp {
                g::GT => (num!(t, rel, ops::Gt), rel_j!(t, Gt)),
                g::GE => (num!(t, rel, ops::Ge), rel_j!(t, Ge)),
                g::EQ => (num!(t, rel, ops::Eq), rel_j!(t, Eq)),
                g::LE => (num!(t, rel, ops::Le), rel_j!(t, Le)),
                g::LT => (num!(t, rel, ops::Lt), rel_j!(t, Lt)),
                _ => (num!(t, rel, ops::Ne), rel_j!(t, Ne)),
            };
            if let (Some(z), Some(nz)) = fused {
                let three = match grp {
                    g::GT => rel_sel_jz!(t, Gt),
                    g::GE => rel_sel_jz!(t, Ge),
                    g::EQ => rel_sel_jz!(t, Eq),
                    g::LE => rel_sel_jz!(t, Le),
                    g::LT => rel_sel_jz!(t, Lt),
                    _ => rel_sel_jz!(t, Ne),
                };
                tag = Tag::Rel(z, nz, three, (grp, t));
            }
            h
        }
        g::MUX => {
            // dst, K, in0..: the inputs through the pool.
            ins.c = core.pool.len() as u32;
            ins.d = rest.len().saturating_sub(2) as u32;
            core.pool.extend_from_slice(rest.get(2..).unwrap_or(&[]));
            sized!(ty_size(t), mux)
        }
        g::CONV => match f {
            0x00 => Some(ops::un::<i16, f32, ops::IntToReal> as Handler),
            0x01 => Some(ops::un::<i32, f32, ops::DintToReal>),
            0x02 | 0x03 => Some(ops::un::<u32, u32, ops::Bits32>),
            0x04 => Some(ops::un::<u32, f32, ops::TimeToReal>),
            0x05 => Some(ops::un::<f32, u32, ops::RealToTime>),
            0x06 => Some(ops::un::<u8, i16, ops::BcdByteToInt>),
            0x07 => Some(ops::un::<u16, i16, ops::BcdWordToInt>),
            0x08 => Some(ops::un::<i16, u8, ops::IntToBcdByte>),
            0x09 => Some(ops::un::<i16, u16, ops::IntToBcdWord>),
            0x0A => Some(ops::un::<f32, i16, ops::RealToInt>),
            0x0B => Some(ops::un::<i16, u8, ops::IntToBool>),
            0x0C => Some(ops::un::<i16, i32, ops::IntToDint>),
            0x0D => Some(ops::un::<f32, f64, ops::RealToLreal>),
            0x0E => Some(ops::un::<f64, f32, ops::LrealToReal>),
            0x0F => Some(ops::un::<i64, f64, ops::LintToLreal>),
            0x10 => Some(ops::un::<u32, f32, ops::DwordToReal>),
            0x11 => Some(ops::un::<f32, u32, ops::RealToDword>),
            _ => None,
        },
        g::SYS => match f {
            0x00 => {
                tag = Tag::Jmp;
                Some(ops::jmp as Handler)
            }
            0x01 => {
                tag = Tag::Jnz;
                Some(ops::jnz)
            }
            0x02 => {
                tag = Tag::Jz;
                Some(ops::jz)
            }
            0x10 | 0x16 => Some(ops::call),
            0x13 | 0x18 => Some(ops::ret),
            0x15 | 0x37 => {
                let b = bytes.unwrap_or(&[]);
                if matches!(b.len(), 1 | 2 | 4 | 8) {
                    let mut x = [0u8; 8];
                    x[..b.len()].copy_from_slice(b);
                    let x = u64::from_le_bytes(x);
                    ins.b = x as u32;
                    ins.c = (x >> 32) as u32;
                    sized!(b.len(), imm)
                } else {
                    ins.b = core.bytes.len() as u32;
                    ins.c = b.len() as u32;
                    core.bytes.extend_from_slice(b);
                    Some(ops::mcd)
                }
            }
            0x17 => Some(ops::cur_time),
            0x1D => Some(ops::trml),
            0x1F | 0x39 => {
                if v[2] == 2 {
                    tag = Tag::Mov2;
                }
                sized!(v[2], mov).or(Some(ops::memcp))
            }
            0x23 | 0x38 => Some(ops::fpat),
            0x24 => Some(ops::aurd),
            0x25 => Some(ops::auwr),
            0x26..=0x2D => {
                // AORD AOWR ATRD ATWR AFRD AFWR AQRD AQWR: 1, 2, 4, 8-byte elements.
                let size = 1usize << ((f - 0x26) / 2);
                let (h, fused, jmp) = if f & 1 == 0 {
                    (
                        sized!(size, acc, ops::Rd),
                        sized!(size, arr, ops::Rd; false),
                        sized!(size, arr, ops::Rd; true),
                    )
                } else {
                    (
                        sized!(size, acc, ops::Wr),
                        sized!(size, arr, ops::Wr; false),
                        sized!(size, arr, ops::Wr; true),
                    )
                };
                let branch = (f == 0x26).then_some((
                    ops::acc_j::<true> as Handler,
                    ops::acc_j::<false> as Handler,
                ));
                let write = (f & 1 == 1).then_some(size);
                if let (Some(x), Some(y)) = (fused, jmp) {
                    tag = Tag::Acc(x, y, branch, write);
                }
                h
            }
            0x2E => {
                tag = Tag::Ceac;
                Some(ops::ceac)
            }
            0x2F => Some(ops::status_word),
            0x31 => Some(ops::task_cycle),
            0x32 => Some(ops::version),
            _ => None,
        },
        g::PTR => match (f, m16) {
            (0x00, true) => Some(ops::dpsto::<u16> as Handler),
            (0x00, false) => Some(ops::dpsto::<u32>),
            (0x01, true) => Some(ops::dprdl::<u16>),
            (0x01, false) => Some(ops::dprdl::<u32>),
            (0x02, true) => Some(ops::dpwrl::<u16>),
            (0x02, false) => Some(ops::dpwrl::<u32>),
            (0x03, true) => Some(ops::calbr::<u16>),
            (0x03, false) => Some(ops::calbr::<u32>),
            _ => None,
        },
        _ => None,
    };
    if let (Tag::Other, Some(x), 2) = (tag, jmp_form, n) {
        let op = match grp {
            g::ADD => Some(step::StepOp::Add),
            g::SUB => Some(step::StepOp::Sub),
            _ => None,
        };
        tag = Tag::Bin(x, op.map(|o| (o, t)));
    }
    match h {
        Some(f) => Ok((Ins { f, ..ins }, tag)),
        None => Err(format!(
            "opcode {} is not implemented by the VM",
            inst.opcode
        )),
    }
}

#[cfg(test)]
mod tests;
