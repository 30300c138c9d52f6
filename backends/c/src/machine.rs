//! The `c` target's machine: the module's C built by the system's compiler into a
//! shared library (with the [`harness`]), loaded into this process,
//! run scan by scan.
//!
//! Variables are found through the layout tables the library exports (filled in by
//! the C compiler), and read and written in its memory between scans. The clock is
//! the runtime's `__CURRENT_TIME`, set before every scan. The watchdog is a thread
//! that sets the library's stop request (the module's loops check it).
//!
//! Every machine loads its own copy of the library (a file of its own), so two
//! machines of one module keep apart: a library's globals are the program's memory.
//! Builds are kept in memory for the process by the hash of their sources and flags,
//! so a module built again (by another test, another machine) is not compiled again.

use crate::cc::{self, TempDir};
use crate::{codes, files, harness, headers, Settings};
use plcc_ir::diag::Diagnostic;
use plcc_ir::machine::{Machine, MachineError};
use plcc_ir::value::PlcValue;
use plcc_ir::vars::{resolve, PathStep};
use plcc_ir::watchdog::Watchdog;
use plcc_ir::{Module, Type};
use std::collections::HashMap;
use std::hash::{Hash, Hasher};
use std::os::raw::c_long;
use std::sync::{Arc, Mutex, OnceLock};

/// The byte cold start fills the program's memory with before the init code runs
/// (as the JIT does): a variable nobody initialises shows up as garbage.
pub const GARBAGE: u8 = 0xA5;

/// The file name of the library in the machine's directory.
const LIBRARY: &str = "libplcc.so";

/// Built libraries kept for the process, by the hash of what they were built from.
/// Bounded: the oldest goes first.
struct Cache {
    libs: HashMap<u64, Arc<Vec<u8>>>,
    order: Vec<u64>,
    bytes: usize,
}

/// At most this many bytes of libraries are kept.
const CACHE_BYTES: usize = 256 << 20;

fn cache() -> &'static Mutex<Cache> {
    static CACHE: OnceLock<Mutex<Cache>> = OnceLock::new();
    CACHE.get_or_init(|| {
        Mutex::new(Cache {
            libs: HashMap::new(),
            order: Vec::new(),
            bytes: 0,
        })
    })
}

/// The layout tables of a loaded library.
struct Tables {
    data: Vec<*mut u8>,
    data_size: Vec<u64>,
    global: Vec<*mut u8>,
    global_size: Vec<u64>,
    /// The globals' data object (each of its fields a variable of its own).
    globals: Option<plcc_ir::DataId>,
    field_offset: Vec<u64>,
    field_located: Vec<u64>,
    agg_first: Vec<u64>,
    agg_stride: Vec<u64>,
}

/// A module's C, built and loaded here: the `c` target's [`Machine`].
pub struct CMachine {
    // Field order matters for drop: the watchdog (which points into the library),
    // then the library, then its directory.
    watchdog: Option<Watchdog>,
    lib: libloading::Library,
    _dir: TempDir,
    cold_start: unsafe extern "C" fn(u8),
    scan: unsafe extern "C" fn(c_long, c_long),
    fault: *mut u8,
    stop: *mut u8,
    tables: Tables,
    /// The module's types and data objects (no functions), to resolve paths.
    vars: Module,
    clock_us: i64,
}

// SAFETY: the library's memory is touched only through `&mut self` (and by the
// watchdog thread, atomically, on the stop byte); nothing in it is tied to a thread.
unsafe impl Send for CMachine {}

fn err(code: &'static str, m: impl Into<String>) -> Vec<Diagnostic> {
    vec![Diagnostic::error_nowhere(code, m.into())]
}

impl CMachine {
    /// Generates the C of `module`, builds and loads it.
    pub fn new(module: &Module, settings: &Settings) -> Result<CMachine, Vec<Diagnostic>> {
        if module.unchecked_pointers {
            return Err(err(
                codes::E_UNCHECKED_POINTERS,
                "this program's pointers are unchecked (CODESYS pointer arithmetic, a pointer given the address of another type, or the address of a temporary kept), which the c target does not run: run it with `--target interp`",
            ));
        }
        let compiler =
            cc::find(settings.cc.as_deref()).map_err(|m| err(codes::E_NO_COMPILER, m))?;
        let generated = files::generate(module)?;
        let harness = harness::source(module, &generated.names);
        let mut units = generated.units.clone();
        units.push(harness::FILE.to_string());
        let mut sources: Vec<(String, String)> = generated.into_named();
        sources.push((harness::FILE.to_string(), harness));
        for (n, t) in headers::all() {
            sources.push((n.to_string(), t.to_string()));
        }
        // No -g: the sanitizer's reports carry their source locations without it,
        // and debug information nearly doubles the time of a build.
        let extra = cc::sanitizer_flags(&settings.sanitize);
        let mut h = std::collections::hash_map::DefaultHasher::new();
        (&sources, &compiler, settings.opt, &extra).hash(&mut h);
        let key = h.finish();

        let dir = TempDir::new().map_err(|e| {
            err(
                codes::E_LOAD,
                format!("cannot make a temporary directory: {e}"),
            )
        })?;
        let lib_path = dir.path().join(LIBRARY);
        let cached = cache().lock().expect("cache").libs.get(&key).cloned();
        match cached {
            Some(bytes) => std::fs::write(&lib_path, &*bytes)
                .map_err(|e| err(codes::E_LOAD, format!("cannot write the library: {e}")))?,
            None => {
                for (name, text) in &sources {
                    std::fs::write(dir.path().join(name), text)
                        .map_err(|e| err(codes::E_LOAD, format!("cannot write {name}: {e}")))?;
                }
                let units: Vec<&str> = units.iter().map(String::as_str).collect();
                cc::shared_library(
                    &compiler,
                    dir.path(),
                    &units,
                    &lib_path,
                    settings.opt,
                    &extra,
                )
                .map_err(|m| err(codes::E_CC_FAILED, m))?;
                if let Ok(bytes) = std::fs::read(&lib_path) {
                    let mut c = cache().lock().expect("cache");
                    c.bytes += bytes.len();
                    c.libs.insert(key, Arc::new(bytes));
                    c.order.push(key);
                    while c.bytes > CACHE_BYTES && c.order.len() > 1 {
                        let old = c.order.remove(0);
                        if let Some(b) = c.libs.remove(&old) {
                            c.bytes -= b.len();
                        }
                    }
                }
            }
        }
        // SAFETY: the library is plcc's generated C and harness: its initialisers do
        // nothing but set up its globals.
        let lib = unsafe { libloading::Library::new(&lib_path) }
            .map_err(|e| err(codes::E_LOAD, format!("cannot load the built library: {e}")))?;
        Self::bind(lib, dir, module)
            .map_err(|e| err(codes::E_LOAD, format!("the built library lacks {e}")))
    }

    fn bind(lib: libloading::Library, dir: TempDir, module: &Module) -> Result<CMachine, String> {
        // SAFETY: the symbols are the harness's, with these types (see `harness`).
        unsafe {
            let table = |name: &str, n: usize| -> Result<Vec<u64>, String> {
                let p: libloading::Symbol<*const u64> = lib
                    .get(name.as_bytes())
                    .map_err(|e| format!("{name}: {e}"))?;
                Ok(std::slice::from_raw_parts(*p, n).to_vec())
            };
            let nd = module.data.len();
            let na = module.aggs.len();
            let nf: usize = module
                .aggs
                .iter()
                .map(|a| match a {
                    plcc_ir::AggDef::Struct(s) => s.fields.len(),
                    plcc_ir::AggDef::Array(_) => 0,
                })
                .sum();
            let data_ptrs: libloading::Symbol<*const *mut u8> = lib
                .get(b"plcc_data")
                .map_err(|e| format!("plcc_data: {e}"))?;
            let data = std::slice::from_raw_parts(*data_ptrs, nd).to_vec();
            let ng = module
                .globals
                .and_then(|g| match module.data.get(g.index()).map(|d| d.ty) {
                    Some(plcc_ir::MemType::Agg(a)) => match &module.aggs[a.index()] {
                        plcc_ir::AggDef::Struct(s) => Some(s.fields.len()),
                        plcc_ir::AggDef::Array(_) => None,
                    },
                    _ => None,
                })
                .unwrap_or(0);
            let global_ptrs: libloading::Symbol<*const *mut u8> = lib
                .get(b"plcc_global")
                .map_err(|e| format!("plcc_global: {e}"))?;
            let global = std::slice::from_raw_parts(*global_ptrs, ng).to_vec();
            let ptr_size = **lib
                .get::<*const u64>(b"plcc_pointer_size")
                .map_err(|e| format!("plcc_pointer_size: {e}"))?;
            if ptr_size != 8 {
                return Err(format!("64-bit pointers (it has {ptr_size}-byte ones)"));
            }
            let tables = Tables {
                data,
                data_size: table("plcc_data_size", nd)?,
                global,
                global_size: table("plcc_global_size", ng)?,
                globals: module.globals,
                field_offset: table("plcc_field_offset", nf)?,
                field_located: table("plcc_field_located", nf)?,
                agg_first: table("plcc_agg_first", na)?,
                agg_stride: table("plcc_agg_stride", na)?,
            };
            let cold_start = *lib
                .get::<unsafe extern "C" fn(u8)>(b"plcc_cold_start")
                .map_err(|e| format!("plcc_cold_start: {e}"))?;
            let scan = *lib
                .get::<unsafe extern "C" fn(c_long, c_long)>(b"plcc_scan")
                .map_err(|e| format!("plcc_scan: {e}"))?;
            let fault = (*lib
                .get::<unsafe extern "C" fn() -> *mut u8>(b"plcc_fault")
                .map_err(|e| format!("plcc_fault: {e}"))?)();
            let stop = (*lib
                .get::<unsafe extern "C" fn() -> *mut u8>(b"plcc_stop")
                .map_err(|e| format!("plcc_stop: {e}"))?)();
            Ok(CMachine {
                watchdog: None,
                lib,
                _dir: dir,
                cold_start,
                scan,
                fault,
                stop,
                tables,
                vars: Module {
                    aggs: module.aggs.clone(),
                    data: module.data.clone(),
                    ..Module::default()
                },
                clock_us: 0,
            })
        }
    }

    /// The address and types of a variable. A located field holds a pointer to the
    /// runtime's storage, which is where the variable is.
    fn locate(&self, path: &str) -> Result<(*mut u8, Type, plcc_ir::ElemType), MachineError> {
        let var = resolve(&self.vars, path)?;
        let t = &self.tables;
        let outside = || MachineError(format!("`{path}` lies outside its object"));
        let mut base = t.data[var.root.index()];
        let mut limit = t.data_size[var.root.index()];
        let mut off: u64 = 0;
        let size = scalar_size(var.ty);
        for (n, s) in var.steps.iter().enumerate() {
            match *s {
                PathStep::Field(agg, f) => {
                    let k = (t.agg_first[agg.index()] + f as u64) as usize;
                    if n == 0 && t.globals == Some(var.root) {
                        // A global: a variable of its own.
                        (base, limit) = (t.global[f as usize], t.global_size[f as usize]);
                    } else {
                        off += t.field_offset[k];
                    }
                    if t.field_located[k] != 0 {
                        if off + 8 > limit {
                            return Err(outside());
                        }
                        // SAFETY: within the object, checked above; the field is
                        // the pointer the library bound at cold start.
                        let p =
                            unsafe { (base.add(off as usize) as *const *mut u8).read_unaligned() };
                        if p.is_null() {
                            return Err(MachineError(format!("`{path}` is not bound")));
                        }
                        (base, off, limit) = (p, 0, size);
                    }
                }
                PathStep::Elem(agg, i) => off += t.agg_stride[agg.index()] * i as u64,
            }
        }
        if off + size > limit {
            return Err(outside());
        }
        // SAFETY: within the object, checked above.
        let p = unsafe { base.add(off as usize) };
        Ok((p, var.ty, var.elem))
    }

    /// The loaded library (for tests that look up more symbols).
    pub fn library(&self) -> &libloading::Library {
        &self.lib
    }
}

fn scalar_size(ty: Type) -> u64 {
    match ty {
        Type::I1 | Type::I8 => 1,
        Type::I16 => 2,
        Type::I32 | Type::F32 => 4,
        Type::I64 | Type::F64 | Type::Ptr => 8,
    }
}

impl Machine for CMachine {
    fn target(&self) -> &str {
        "c"
    }

    fn vars_module(&self) -> &plcc_ir::Module {
        &self.vars
    }

    fn cold_start(&mut self) -> Result<(), MachineError> {
        self.clock_us = 0;
        // SAFETY: the harness's entry point; no other code of the library runs.
        unsafe { (self.cold_start)(GARBAGE) };
        Ok(())
    }

    fn set_clock_us(&mut self, us: i64) {
        self.clock_us = us;
    }

    fn scan(&mut self) -> Result<(), MachineError> {
        let sec = self.clock_us.div_euclid(1_000_000);
        let nsec = self.clock_us.rem_euclid(1_000_000) * 1000;
        if let Some(w) = &self.watchdog {
            w.scan_begins();
        }
        // SAFETY: see `cold_start`.
        unsafe { (self.scan)(sec as c_long, nsec as c_long) };
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

    fn read(&self, path: &str) -> Result<PlcValue, MachineError> {
        let (p, ty, elem) = self.locate(path)?;
        // SAFETY: `locate` checked the range; no code of the library runs now.
        let bits = unsafe {
            match scalar_size(ty) {
                1 => p.read() as u64,
                2 => (p as *const u16).read_unaligned() as u64,
                4 => (p as *const u32).read_unaligned() as u64,
                _ => (p as *const u64).read_unaligned(),
            }
        };
        Ok(PlcValue::from_bits(elem, bits))
    }

    fn write(&mut self, path: &str, value: PlcValue) -> Result<(), MachineError> {
        let (p, ty, elem) = self.locate(path)?;
        if value.ty != elem {
            return Err(MachineError(format!(
                "`{path}` is {elem}, cannot write a {} value",
                value.ty
            )));
        }
        let bits = if ty == Type::I1 {
            (value.bits != 0) as u64
        } else {
            value.bits
        };
        // SAFETY: see `read`.
        unsafe {
            match scalar_size(ty) {
                1 => p.write(bits as u8),
                2 => (p as *mut u16).write_unaligned(bits as u16),
                4 => (p as *mut u32).write_unaligned(bits as u32),
                _ => (p as *mut u64).write_unaligned(bits),
            }
        }
        Ok(())
    }

    fn fault(&self) -> bool {
        // SAFETY: the library's fault flag; no code of it runs now.
        unsafe { self.fault.read() != 0 }
    }

    fn clear_fault(&mut self) {
        // SAFETY: see `fault`.
        unsafe { self.fault.write(0) }
    }

    fn set_watchdog(&mut self, limit: Option<std::time::Duration>) {
        self.watchdog = None;
        if let Some(limit) = limit {
            // SAFETY: the stop byte lives as long as the library, which outlives the
            // watchdog (dropped first); the code reads it atomically.
            self.watchdog = Some(unsafe { Watchdog::start(self.stop, limit) });
        }
    }
}
