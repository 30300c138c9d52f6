//! The JIT machine: the whole module compiled into this process's memory, run scan by
//! scan through [`plcc_ir::machine::Machine`].

use crate::codegen::{self, CodegenSettings, DataLayout};
use crate::codes;
use crate::runtime::{Runtime, MATH};
use crate::translate::Addressing;
use cranelift_jit::{JITBuilder, JITModule};
use cranelift_module::{default_libcall_names, Linkage};
use plcc_ir::diag::Diagnostic;
use plcc_ir::machine::{Machine, MachineError};
use plcc_ir::value::{host_size, PlcValue};
use plcc_ir::{Module, Type};

/// The byte cold start fills data memory with before the init functions run. Not zero,
/// so that a variable an init function forgets shows up as garbage in tests.
pub const GARBAGE: u8 = 0xA5;

type EntryFn = unsafe extern "C" fn(*mut u8);
type InitGlobalsFn = unsafe extern "C" fn();

/// A program instance: its body, its init and where its data is.
#[derive(Copy, Clone)]
struct Program {
    body: EntryFn,
    init: EntryFn,
    offset: u64,
}

/// Machine code compiled for one data block and runtime context: what scans run.
/// Dropping it frees the code.
struct Code {
    jit: Option<JITModule>,
    init_globals: Option<InitGlobalsFn>,
    programs: Vec<Program>,
    code_size: u64,
}

impl Code {
    /// Compiles every function of `module` for the data block at `data` and the
    /// runtime context at `rt`, laid out as `data_layout`.
    fn compile(
        module: &Module,
        data_layout: &DataLayout,
        data: u64,
        rt: u64,
        settings: &CodegenSettings,
    ) -> Result<Code, Vec<Diagnostic>> {
        check_entries(module)?;
        let isa = codegen::host_isa(settings)?;
        let mut builder = JITBuilder::with_isa(isa.clone(), default_libcall_names());
        for m in &MATH {
            builder.symbol(m.name, (m.addr)());
        }
        let mut cl = JITModule::new(builder);
        let compiled = codegen::compile_functions(
            &mut cl,
            module,
            data_layout,
            Addressing::Absolute { data, rt },
            Linkage::Local,
            settings,
            &isa,
        );
        let compiled = match compiled {
            Ok(c) => c,
            Err(e) => {
                // SAFETY: nothing of this module has run; its code is garbage now.
                unsafe { cl.free_memory() };
                return Err(e);
            }
        };
        if let Err(e) = cl.finalize_definitions() {
            // SAFETY: as above.
            unsafe { cl.free_memory() };
            return Err(vec![Diagnostic::error_nowhere(
                codes::E_EMIT,
                format!("cannot finalise the JIT code: {e}"),
            )]);
        }
        let addr = |f: plcc_ir::FuncId| cl.get_finalized_function(compiled.funcs[f.index()]);
        // SAFETY: the functions were checked to have these signatures
        // (`check_entries`), and Cranelift compiled them with the host's C convention.
        let (init_globals, programs) = unsafe {
            let init_globals = module
                .init_globals
                .map(|f| std::mem::transmute::<*const u8, InitGlobalsFn>(addr(f)));
            let programs = module
                .programs
                .iter()
                .map(|p| Program {
                    body: std::mem::transmute::<*const u8, EntryFn>(addr(p.body)),
                    init: std::mem::transmute::<*const u8, EntryFn>(addr(p.init)),
                    offset: data_layout.offsets[p.data.index()],
                })
                .collect();
            (init_globals, programs)
        };
        Ok(Code {
            jit: Some(cl),
            init_globals,
            programs,
            code_size: compiled.code_size,
        })
    }
}

impl Drop for Code {
    fn drop(&mut self) {
        if let Some(m) = self.jit.take() {
            // SAFETY: the function pointers die with `self`, and code runs only inside
            // the `&mut` methods of the `Jit` that owns it.
            unsafe { m.free_memory() };
        }
    }
}

/// A module compiled to machine code in this process, with its data memory and runtime
/// context: the `host` target's [`Machine`].
///
/// Data memory is one block, never moved after compilation, whose address is baked into
/// the code; so is the runtime context's. Dropping the machine frees its code.
///
/// Its code can be replaced between scans by code compiled for the same memory
/// ([`Upgrade`], [`Jit::install`]): the tiered JIT starts a large program on
/// quickly compiled code and swaps the optimised code in when it is ready
/// ([`crate::quick_jit`]). Nothing of
/// a scan's state lives outside data memory and the runtime context between scans, so
/// the swap is invisible but for speed.
pub struct Jit {
    code: Code,
    /// Data memory: `words` u64s (8-byte aligned), owned through a raw pointer because
    /// the compiled code writes it behind Rust's back.
    data: *mut u64,
    words: usize,
    rt: *mut Runtime,
    /// The module's types and data objects (no functions), to resolve paths.
    vars: Module,
    data_layout: DataLayout,
    /// Stops scans that run too long (dropped before the runtime it points into).
    watchdog: Option<plcc_ir::watchdog::Watchdog>,
}

/// What compiles a second version of a [`Jit`]'s module for its memory, on any
/// thread ([`crate::quick_jit`]). It holds the machine's memory addresses, not the
/// machine: what it compiles runs only once [`Jit::install`]ed in that machine.
pub struct Upgrade {
    data: u64,
    rt: u64,
    data_layout: DataLayout,
    /// Program instances of the running module.
    programs: usize,
    settings: CodegenSettings,
}

/// Code an [`Upgrade`] compiled, waiting to be [`Jit::install`]ed.
pub struct Tier {
    code: Code,
    data: u64,
}

// SAFETY: a `Tier`'s code runs only once installed in its `Jit` (checked by address),
// from that machine's `&mut` methods; `JITModule` is `Send` itself.
unsafe impl Send for Tier {}

impl Upgrade {
    /// Compiles `module`, another version of the machine's module (the same data
    /// objects and types, as the optimiser leaves them), with this upgrade's settings.
    /// A module whose data is laid out differently is refused.
    pub fn compile(&self, module: &Module) -> Result<Tier, Vec<Diagnostic>> {
        let layout = DataLayout::compute(module)?;
        if layout.offsets != self.data_layout.offsets
            || layout.size != self.data_layout.size
            || module.programs.len() != self.programs
        {
            return Err(vec![Diagnostic::error_nowhere(
                codes::E_MALFORMED_IR,
                "the module to upgrade to lays out its data differently from the running one",
            )]);
        }
        let code = Code::compile(module, &layout, self.data, self.rt, &self.settings)?;
        Ok(Tier {
            code,
            data: self.data,
        })
    }
}

impl Jit {
    /// Compiles `module` with the default settings.
    pub fn new(module: &Module) -> Result<Jit, Vec<Diagnostic>> {
        Jit::with_settings(module, &CodegenSettings::default())
    }

    pub(crate) fn with_settings(
        module: &Module,
        settings: &CodegenSettings,
    ) -> Result<Jit, Vec<Diagnostic>> {
        let data_layout = DataLayout::compute(module)?;
        let words = (data_layout.size.div_ceil(8) as usize).max(1);
        let data = Box::into_raw(vec![0u64; words].into_boxed_slice()) as *mut u64;
        let rt = Box::into_raw(Box::new(Runtime::default()));
        let code = match Code::compile(module, &data_layout, data as u64, rt as u64, settings) {
            Ok(c) => c,
            Err(e) => {
                // SAFETY: both came from `Box::into_raw` with these sizes, and no code
                // refers to them.
                unsafe {
                    drop(Box::from_raw(std::ptr::slice_from_raw_parts_mut(
                        data, words,
                    )));
                    drop(Box::from_raw(rt));
                }
                return Err(e);
            }
        };
        Ok(Jit {
            code,
            data,
            words,
            rt,
            vars: Module {
                aggs: module.aggs.clone(),
                data: module.data.clone(),
                ..Module::default()
            },
            data_layout,
            watchdog: None,
        })
    }

    /// What compiles another version of this machine's module for its memory, with
    /// the backend settings of `settings` (on another thread if wanted).
    pub(crate) fn upgrade_with(&self, settings: CodegenSettings) -> Upgrade {
        Upgrade {
            data: self.data as u64,
            rt: self.rt as u64,
            data_layout: self.data_layout.clone(),
            programs: self.code.programs.len(),
            settings,
        }
    }

    /// Replaces the machine's code by `tier`'s, from the next scan on. The old code is
    /// freed. A tier compiled for another machine is refused (and freed).
    pub fn install(&mut self, tier: Tier) -> Result<(), MachineError> {
        if tier.data != self.data as u64 {
            return Err(MachineError(
                "the code to install was compiled for another machine".into(),
            ));
        }
        self.code = tier.code;
        Ok(())
    }

    /// Bytes of machine code the module compiled to.
    pub fn code_size(&self) -> u64 {
        self.code.code_size
    }

    /// Bytes of data memory.
    pub fn data_size(&self) -> u64 {
        self.data_layout.size
    }

    /// The runtime context (clock and fault flag) as the code sees it.
    pub fn runtime(&self) -> Runtime {
        // SAFETY: `rt` is valid while `self` lives; no code runs during the read.
        unsafe { std::ptr::read(self.rt) }
    }

    /// Data memory, for inspection (only valid until the next scan).
    pub fn data(&self) -> &[u8] {
        // SAFETY: `data` holds `words * 8` initialised bytes; no code runs while the
        // borrow of `self` lasts.
        unsafe {
            std::slice::from_raw_parts(self.data as *const u8, self.data_layout.size as usize)
        }
    }

    fn data_ptr(&self) -> *mut u8 {
        self.data as *mut u8
    }

    /// Byte offset and size of a variable in data memory.
    fn locate(&self, path: &str) -> Result<(plcc_ir::vars::VarRef, usize, usize), MachineError> {
        let var = plcc_ir::vars::resolve(&self.vars, path)?;
        let off = self.data_layout.offsets[var.root.index()]
            + self.data_layout.layout.offset_of(&var.steps);
        let size = host_size(var.ty) as usize;
        if off + size as u64 > self.data_layout.size {
            return Err(MachineError(format!("`{path}` lies outside data memory")));
        }
        Ok((var, off as usize, size))
    }
}

/// Program bodies and inits take the instance; `init_globals` takes nothing.
fn check_entries(module: &Module) -> Result<(), Vec<Diagnostic>> {
    let bad = |name: &str, what: &str| {
        vec![Diagnostic::error_nowhere(
            codes::E_MALFORMED_IR,
            format!("function `{name}` cannot be {what}: wrong signature"),
        )]
    };
    let get = |id: plcc_ir::FuncId| module.funcs.get(id.index());
    for p in &module.programs {
        for (id, what) in [(p.body, "a program body"), (p.init, "a program init")] {
            match get(id) {
                Some(f) if f.params == [Type::Ptr] && f.ret.is_none() => {}
                Some(f) => return Err(bad(&f.name, what)),
                None => return Err(bad(&format!("{id}"), what)),
            }
        }
        if p.data.index() >= module.data.len() {
            return Err(bad(&p.name, "run: its data object is missing;"));
        }
    }
    if let Some(id) = module.init_globals {
        match get(id) {
            Some(f) if f.params.is_empty() && f.ret.is_none() => {}
            Some(f) => return Err(bad(&f.name, "init_globals")),
            None => return Err(bad(&format!("{id}"), "init_globals")),
        }
    }
    Ok(())
}

impl Drop for Jit {
    fn drop(&mut self) {
        // The watchdog thread points into the runtime context: stop it first. The
        // code is freed after this (a field), but nothing runs it any more.
        self.watchdog = None;
        // SAFETY: both came from `Box::into_raw` with these sizes.
        unsafe {
            drop(Box::from_raw(std::ptr::slice_from_raw_parts_mut(
                self.data, self.words,
            )));
            drop(Box::from_raw(self.rt));
        }
    }
}

impl Machine for Jit {
    fn target(&self) -> &str {
        "host"
    }

    fn vars_module(&self) -> &plcc_ir::Module {
        &self.vars
    }

    fn cold_start(&mut self) -> Result<(), MachineError> {
        // SAFETY: data and rt are valid and exclusively ours between scans (the
        // watchdog thread only writes the stop byte, atomically); the entry points were
        // compiled for exactly these arguments.
        unsafe {
            (*self.rt).clock_ms = 0;
            (*self.rt).clock_ns = 0;
            (*self.rt).fault = 0;
            std::ptr::write_bytes(self.data_ptr(), GARBAGE, self.words * 8);
            if let Some(f) = self.code.init_globals {
                f();
            }
            for p in &self.code.programs {
                (p.init)(self.data_ptr().add(p.offset as usize));
            }
        }
        Ok(())
    }

    fn set_clock_us(&mut self, us: i64) {
        // SAFETY: see `cold_start`.
        unsafe {
            (*self.rt).clock_ms = us.div_euclid(1000) as i32;
            (*self.rt).clock_ns = us.wrapping_mul(1000);
        }
    }

    fn scan(&mut self) -> Result<(), MachineError> {
        if let Some(w) = &self.watchdog {
            w.scan_begins();
        }
        // SAFETY: see `cold_start`.
        unsafe {
            for p in &self.code.programs {
                (p.body)(self.data_ptr().add(p.offset as usize));
            }
        }
        if let Some(w) = &self.watchdog {
            if w.scan_ends() {
                return Err(MachineError(format!(
                    "watchdog: a scan ran longer than {:?} and was stopped (an endless loop?)",
                    w.limit()
                )));
            }
        }
        Ok(())
    }

    fn set_watchdog(&mut self, limit: Option<std::time::Duration>) {
        self.watchdog = None;
        if let Some(limit) = limit {
            // SAFETY: `rt` lives until `self` is dropped, and the watchdog is dropped
            // first; the compiled code only reads the byte.
            let stop = unsafe { std::ptr::addr_of_mut!((*self.rt).stop) };
            self.watchdog = Some(unsafe { plcc_ir::watchdog::Watchdog::start(stop, limit) });
        }
    }

    fn read(&self, path: &str) -> Result<PlcValue, MachineError> {
        let (var, off, size) = self.locate(path)?;
        let mut buf = [0u8; 8];
        buf[..size].copy_from_slice(&self.data()[off..off + size]);
        Ok(PlcValue::from_bits(var.elem, u64::from_le_bytes(buf)))
    }

    fn write(&mut self, path: &str, value: PlcValue) -> Result<(), MachineError> {
        let (var, off, size) = self.locate(path)?;
        if value.ty != var.elem {
            return Err(MachineError(format!(
                "`{}` is {}, not {}",
                var.path,
                var.elem.name(),
                value.ty.name()
            )));
        }
        let bits = if var.ty == Type::I1 {
            (value.bits != 0) as u64
        } else {
            value.bits
        };
        let bytes = bits.to_le_bytes();
        // SAFETY: `locate` checked the range; no code runs during the write.
        unsafe {
            std::ptr::copy_nonoverlapping(bytes.as_ptr(), self.data_ptr().add(off), size);
        }
        Ok(())
    }

    fn fault(&self) -> bool {
        self.runtime().fault != 0
    }

    fn clear_fault(&mut self) {
        // SAFETY: see `cold_start`.
        unsafe { (*self.rt).fault = 0 };
    }
}
// SAFETY: the raw pointers are to memory the `Jit` alone owns (nothing else holds
// them but the compiled code, which runs only inside `&mut self` methods), the code has
// no thread affinity, and `JITModule` is `Send` itself (checked below). So a machine
// may move to another thread, as a test runner's thread pool needs.
unsafe impl Send for Jit {}

const _: () = {
    const fn is_send<T: Send>() {}
    is_send::<JITModule>();
};
