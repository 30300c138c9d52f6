// Library crates never print (ARCHITECTURE.md, "Panics"): what they say is a Diagnostic.
#![cfg_attr(
    not(test),
    deny(clippy::print_stdout, clippy::print_stderr, clippy::unwrap_used)
)]
//! plcc's native backend: the IR translated to Cranelift IR, then either compiled into
//! this process (the [`Jit`], the `host` target's [`Machine`]) or into a relocatable
//! object for a target triple with a C header of its memory layout
//! ([`NativeBackend::compile`]).
//!
//! Memory model: every data object lives in one block laid out by
//! [`plcc_ir::layout::Layout`] with [`plcc_ir::layout::LayoutRules::HOST`] (objects one
//! after the other, each at its alignment). The clock and the fault flag live in a
//! small [`Runtime`] context. In the JIT both are at fixed addresses baked into the
//! code; in objects they are the symbols `plcc_data` and `plcc_rt`.
//!
//! Semantics: the IR contract (`docs/ir.md`) holds bit for bit, as the differential
//! tests against `plcc_ir::interp` check. Where Cranelift traps or masks, the code
//! checks: a zero divisor raises the fault and gives 0 (no signal), `MIN / -1` wraps,
//! shift counts at least the width give 0 or the sign, float-to-integer conversions
//! saturate at the destination width. Math functions call the C library's (`sinf`,
//! `pow`, ...): in the JIT through Rust's float methods, which the interpreter uses too.
//!
//! Compile speed: functions are translated and compiled on worker threads (largest
//! first) and placed in module order, so objects are reproducible. Field and data
//! offsets fold into the loads and stores, and divisions by constants skip their
//! checks (Cranelift turns them into multiplications).
//!
//! [`Machine`]: plcc_ir::machine::Machine

#![warn(missing_docs)]

mod codegen;
mod header;
mod jit;
mod object;
mod runtime;
mod translate;

pub use jit::{Jit, Tier, Upgrade, GARBAGE};
pub use runtime::{data_symbol, func_symbol, mangle, Runtime, DATA_SYMBOL, RT_SYMBOL};

use codegen::CodegenSettings;
use plcc_ir::backend::{Artifacts, Backend, Options, TargetFacts};
use plcc_ir::diag::{CodeInfo, Diagnostic};
use plcc_ir::machine::Machine;
use plcc_ir::{ElemType, Module};

/// The Cranelift IR the JIT would compile for every function of `module`, as text
/// (data at the made-up address 0x1000, the runtime context at 0x100).
pub fn clif(module: &Module) -> Result<String, Vec<Diagnostic>> {
    codegen::clif_text(module)
}

/// Diagnostic codes of the native backend.
pub mod codes {
    /// The target triple is not understood or Cranelift cannot generate code for it.
    pub const E_UNSUPPORTED_TARGET: &str = "E8001";
    /// A backend setting is unknown or has a bad value.
    pub const E_BAD_SETTING: &str = "E8002";
    /// The IR breaks a rule the verifier checks (a bug of the front end or a pass).
    pub const E_MALFORMED_IR: &str = "E8003";
    /// Cranelift failed on a function (a bug of this backend).
    pub const E_CODEGEN: &str = "E8004";
    /// The code could not be placed in memory or written as an object.
    pub const E_EMIT: &str = "E8005";
    /// The program's data does not fit the backend's limit.
    pub const E_DATA_TOO_LARGE: &str = "E8006";
    /// The program has unchecked pointers, which the JIT does not run.
    pub const E_UNCHECKED_POINTERS: &str = "E8007";
}

/// Every code the native backend reports, for `plcc explain`.
pub const CODES: &[CodeInfo] = &[
    CodeInfo {
        code: codes::E_UNSUPPORTED_TARGET,
        title: "unsupported native target",
        explanation: "The `triple` setting names a target the native backend cannot generate \
code for: it is not a valid target triple, Cranelift has no code generator for its \
architecture (it has x86_64, aarch64, riscv64 and s390x), or its pointers are not 64 bits \
wide. Example: `--target host -s triple=armv7-unknown-linux-gnueabihf` fails; use a \
64-bit triple such as `aarch64-unknown-linux-gnu`, or leave the setting out to compile \
for this machine.",
    },
    CodeInfo {
        code: codes::E_BAD_SETTING,
        title: "bad native backend setting",
        explanation: "A `key=value` setting given to the native backend is unknown or its \
value is invalid. The backend knows `triple` (a target triple, default: this machine), \
`opt_level` (`none`, `speed` or `speed_and_size`; default `speed`), `regalloc` \
(`backtracking` or `single_pass`; default `backtracking`) and `threads` (worker threads \
for compiling, 0 chooses; default 0); to run a program (`plcc run`, `test`, `serve`) \
also `tier`: `auto` (the default: a program of 20,000 IR instructions or more starts on \
quickly compiled code and the optimised code takes over between two scans once it is \
ready), `full` (the optimised code from the first scan), `quick` (the quick code only) \
or `swap-at-N` (the optimised code from scan N on). Example: `-s opt_level=fast` fails; \
write `-s opt_level=speed`.",
    },
    CodeInfo {
        code: codes::E_MALFORMED_IR,
        title: "malformed IR reached the native backend",
        explanation: "The IR module breaks a rule the IR verifier enforces (a value used \
where its definition does not dominate, a block without a terminator, an operation on \
the wrong type, a program body without the `(ptr)` signature, ...). This is a bug of \
plcc's front end or of an IR pass, not of the program: please report it with the \
source that triggers it. `plcc` can print the IR with its IR-emitting option to help. \
No correct program shows it, so there is no example.",
    },
    CodeInfo {
        code: codes::E_CODEGEN,
        title: "code generation failed",
        explanation: "Cranelift refused a function the native backend produced. The note \
shows Cranelift's account of the function. This is a bug of plcc's native backend: \
please report it with the source that triggers it. Other targets, or the IR \
interpreter, can run the program meanwhile. No correct program shows it, so there is no \
example.",
    },
    CodeInfo {
        code: codes::E_EMIT,
        title: "cannot place or write the machine code",
        explanation: "The compiled code could not be placed in executable memory (the JIT) \
or written as an object file: the system refused memory, or a symbol could not be \
declared. Check the memory limits of the process; if the problem persists, report it. \
It comes from the system, not from a program, so there is no example.",
    },
    CodeInfo {
        code: codes::E_DATA_TOO_LARGE,
        title: "program data too large",
        explanation: "The program's variables (all program instances and globals) take \
more than 1 GiB, the native backend's limit. Usually an array is declared far larger \
than meant, e.g. `ARRAY[0..999999999] OF LREAL`. Shrink the array bounds.",
    },
    CodeInfo {
        code: codes::E_UNCHECKED_POINTERS,
        title: "unchecked pointers on the host",
        explanation: "The program uses CODESYS pointers as numbers (`pt := pt + 1`, `dw := pt`, `pt := dw`), gives a pointer the address of another type, or keeps the address of a temporary (ADR of a FUNCTION's variable), so a pointer may hold any address. The JIT runs code natively in plcc's own process, where a wrong address would corrupt plcc instead of raising the fault flag, so `plcc run`/`test` on `host` refuse such a program (it still compiles to objects). Example: `pt := ADR(buf); pt := pt + 1; x := pt^;` in `--dialect codesys`. Run it with `--target interp`, which checks every access, or use IEC references (REF_TO, REF()).",
    },
];

/// The `host` target: Cranelift JIT for running here, objects for any 64-bit triple
/// Cranelift supports.
///
/// Settings (`Options::settings`): `triple` (objects only; default: this machine, with
/// the baseline CPU features of its architecture), `opt_level` (`none`, `speed`,
/// `speed_and_size`; default `speed`), `regalloc` (`backtracking`, `single_pass`;
/// default `backtracking`), `threads` (compile threads; 0, the default, picks by the
/// number of cores). Debug builds also run the IR verifier on every module.
#[derive(Clone, Debug, Default)]
pub struct NativeBackend;

impl NativeBackend {
    /// The backend.
    pub fn new() -> NativeBackend {
        NativeBackend
    }
}

/// Splits the options into the triple and the code generation settings.
fn parse_settings(options: &Options) -> Result<(Option<String>, CodegenSettings), Vec<Diagnostic>> {
    let mut triple = None;
    let mut s = CodegenSettings::default();
    let bad = |m: String| vec![Diagnostic::error_nowhere(codes::E_BAD_SETTING, m)];
    for (k, v) in &options.settings {
        match k.as_str() {
            "triple" => triple = Some(v.clone()),
            "opt_level" => match v.as_str() {
                "none" | "speed" | "speed_and_size" => s.opt_level = v.clone(),
                _ => {
                    return Err(bad(format!(
                        "`opt_level` is `none`, `speed` or `speed_and_size`, not `{v}`"
                    )))
                }
            },
            "regalloc" => match v.as_str() {
                "backtracking" | "single_pass" => s.regalloc = v.clone(),
                _ => {
                    return Err(bad(format!(
                        "`regalloc` is `backtracking` or `single_pass`, not `{v}`"
                    )))
                }
            },
            "threads" => {
                s.threads = v
                    .parse()
                    .map_err(|_| bad(format!("`threads` is a number, not `{v}`")))?
            }
            _ => {
                return Err(bad(format!(
                    "the native backend has no setting `{k}` (it has `triple`, `opt_level`, \
                     `regalloc` and `threads`)"
                )))
            }
        }
    }
    Ok((triple, s))
}

impl Backend for NativeBackend {
    fn facts(&self) -> TargetFacts {
        TargetFacts {
            name: "host",
            pointer_bits: 64,
            little_endian: cfg!(target_endian = "little"),
            elem_types: &ElemType::ALL,
            promotion: plcc_ir::passes::promote::Promotion::Everywhere,
        }
    }

    /// An object file (`o`) and its C header (`h`); symbol addresses are offsets in
    /// the data block `plcc_data`.
    fn compile(&self, module: &Module, options: &Options) -> Result<Artifacts, Vec<Diagnostic>> {
        let (triple, settings) = parse_settings(options)?;
        object::compile(module, triple.as_deref(), &settings)
    }

    /// The JIT (the `triple` setting does not apply: it always runs here).
    fn machine(
        &self,
        module: &Module,
        options: &Options,
    ) -> Option<Result<Box<dyn Machine>, Vec<Diagnostic>>> {
        if let Err(e) = runs_here(module) {
            return Some(Err(e));
        }
        Some(parse_settings(options).and_then(|(_, settings)| {
            Jit::with_settings(module, &settings).map(|j| Box::new(j) as Box<dyn Machine>)
        }))
    }
}

/// Refuses a module the JIT must not run.
fn runs_here(module: &Module) -> Result<(), Vec<Diagnostic>> {
    if module.unchecked_pointers {
        // Such a pointer may address the host process itself: a wrong one would
        // corrupt plcc rather than raise the fault flag.
        return Err(vec![Diagnostic::error_nowhere(
            codes::E_UNCHECKED_POINTERS,
            "this program's pointers are unchecked (CODESYS pointer arithmetic, a pointer given the address of another type, or the address of a temporary kept), which the host target does not run: run it with `--target interp`",
        )]);
    }
    Ok(())
}

/// The `host` machine in two tiers, for a large program (the tiered JIT,
/// ARCHITECTURE.md, "Tiers"): `module` compiled quickly (Cranelift's optimiser off,
/// its single-pass register allocator, none of the translator's optimisations) and
/// the [`Upgrade`] that compiles another version of it, the optimised one, for the
/// same memory with `options`' settings. The quick code computes exactly what the
/// optimised code does (both keep the IR contract); it runs slower.
///
/// Both add the watchdog checks ([`plcc_ir::passes::watchdog`]) to each function as
/// they translate it: the modules given have none, and are not changed.
pub fn quick_jit(module: &Module, options: &Options) -> Result<(Jit, Upgrade), Vec<Diagnostic>> {
    runs_here(module)?;
    let (_, settings) = parse_settings(options)?;
    let quick = CodegenSettings {
        opt_level: "none".to_string(),
        regalloc: "single_pass".to_string(),
        threads: settings.threads,
        watchdog: true,
        quick: true,
    };
    let jit = Jit::with_settings(module, &quick)?;
    let upgrade = jit.upgrade_with(CodegenSettings {
        watchdog: true,
        ..settings
    });
    Ok((jit, upgrade))
}
