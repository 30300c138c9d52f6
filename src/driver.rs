//! From files on disk to a verified, optimised IR module, with diagnostics.

use plcc_frontend::source::{SourceFile, SourceMap};
use plcc_frontend::{Lang, LowerOptions};
use plcc_ir::diag::{Diagnostic, FileId};
use plcc_ir::Module;
use std::path::Path;
use std::time::{Duration, Instant};

/// Code of the diagnostic for an internal compiler error (a bug in plcc).
pub const E_INTERNAL: &str = "E9901";
/// Code of the diagnostic for a target that cannot run programs on this machine.
pub const E_CANNOT_RUN: &str = "E9902";
/// Code of the diagnostic for a program whose data the IR interpreter cannot hold.
pub const E_INTERP_DATA_TOO_LARGE: &str = "E9903";

/// The driver's own diagnostic codes.
pub const CODES: &[plcc_ir::diag::CodeInfo] = &[
    plcc_ir::diag::CodeInfo {
        code: E_INTERNAL,
        title: "internal compiler error",
        explanation: "plcc produced invalid IR, a machine could not be set up for a valid module, or the front end or a backend panicked (the panic is caught and reported, the command goes on as for any error): a bug in plcc. Please report it with the program that shows it. No correct program shows it, so there is no example.",
    },
    plcc_ir::diag::CodeInfo {
        code: E_CANNOT_RUN,
        title: "target cannot run programs here",
        explanation: "`plcc run` and `plcc test` need a machine for the target: the JIT (`host`), the interpreter (`interp`), plcc's simulator of the PIC16F876A (`pic16f876a`), plcc's CPDev VM (`vmasm`) or the C built by the system's compiler (`c`, where one is found). A target without one only produces files. Every target of the command line has one, so only a program using plcc as a library meets this code:\n\n    plcc::targets::machine(\"plc5\", &module)   (* error: no machine for `plc5` *)",
    },
    plcc_ir::diag::CodeInfo {
        code: E_INTERP_DATA_TOO_LARGE,
        title: "program data too large for the interpreter",
        explanation: "The program's variables (all program instances and globals) take more than 1 GiB, the IR interpreter's limit (`--target interp`); the host's JIT has the same limit (E8006). Usually arrays are declared far larger than meant. Shrink the array bounds.\n\n    VAR a0, a1, a2, a3, a4, a5, a6, a7, a8, a9, a10, a11, a12, a13 : ARRAY[0..9999999] OF LREAL; END_VAR\n    (* error: 14 arrays of 80 MB take 1.12 GB *)",
    },
];

/// A failure that is not a diagnostic of the program: a file that cannot be read, a
/// language that cannot be told (exit status 2).
#[derive(Debug)]
pub struct UsageError(pub String);

impl std::fmt::Display for UsageError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

/// The outcome of a build: the sources (for rendering diagnostics), the module if
/// there was no error, and the diagnostics.
pub struct Build {
    /// Every source file, the standard library included.
    pub sources: SourceMap,
    /// The module, optimised unless asked otherwise; `None` after an error.
    pub module: Option<Module>,
    /// Errors and warnings.
    pub diagnostics: Vec<Diagnostic>,
    /// Wall time of each phase.
    pub timings: Vec<(&'static str, Duration)>,
    /// The syntax trees (see [`plcc_frontend::Compiled::syntax`]).
    pub syntax: Vec<plcc_frontend::ast::SourceUnit>,
    /// The PLCopen files and their views (see [`plcc_frontend::Compiled::ladder`]).
    pub ladder: Vec<plcc_frontend::plcopen::View>,
    /// The files with charts (see [`plcc_frontend::Compiled::charts`]).
    pub charts: Vec<plcc_frontend::sfc::View>,
    /// The files printed (see [`plcc_frontend::Compiled::printed`]).
    pub printed: Option<String>,
}

impl Build {
    /// The module, else the build's first three errors joined by `; ` (for tests
    /// and tools that report a failed build in one line).
    pub fn into_module(self) -> Result<Module, String> {
        self.module.ok_or_else(|| {
            self.diagnostics
                .iter()
                .filter(|d| d.is_error())
                .take(3)
                .map(|d| d.to_string())
                .collect::<Vec<_>>()
                .join("; ")
        })
    }

    /// Prints the phase timings to standard error when `PLCC_TIME_PASSES` is set.
    pub fn report_timings(&self, extra: &[(&'static str, Duration)]) {
        let mut total = Duration::ZERO;
        for (name, d) in self.timings.iter().chain(extra) {
            report_time(name, *d);
            total += *d;
        }
        report_time("total", total);
    }
    /// True if the build failed.
    pub fn failed(&self) -> bool {
        self.module.is_none()
    }
}

/// How to build.
#[derive(Clone, Debug, Default)]
pub struct BuildOptions {
    /// The language of every file (else from each file's extension).
    pub lang: Option<Lang>,
    /// PROGRAMs to instantiate (all when empty).
    pub programs: Vec<String>,
    /// The CODESYS dialect (`--dialect codesys`).
    pub codesys: bool,
    /// The dialect was given (`--dialect`): a PLCopen file's header does not change
    /// it (see [`plcc_frontend::LowerOptions::dialect_given`]).
    pub dialect_given: bool,
    /// How PLCopen XML files are read.
    pub plcopen: plcc_frontend::plcopen::Options,
    /// How sequential function charts evolve (`--sfc`).
    pub sfc: plcc_frontend::sfc::Profile,
    /// Skip the optimisation passes.
    pub no_opt: bool,
    /// Optimise each function only: the whole-program passes
    /// ([`plcc_ir::passes::optimize_whole_program`]) are left to the machine
    /// ([`crate::targets::machine_staged`]), which runs them in the background for a
    /// large program on the JIT (ARCHITECTURE.md, "Tiers").
    pub staged: bool,
    /// Only check: no verification or optimisation of the IR.
    pub check_only: bool,
    /// Keep the C code of pragmas for a target that copies it into its output
    /// ([`plcc_frontend::LowerOptions::inline_c`]).
    pub inline_c: bool,
    /// What to print of the files ([`Build::printed`]).
    pub print: plcc_frontend::PrintAs,
    /// The syntax trees are not wanted ([`Build::syntax`] comes back empty): they are
    /// freed on a thread of their own once the IR is made, so that the optimiser and
    /// the code generator reuse their memory.
    pub drop_syntax: bool,
    /// Where promotion pays on the target the build is for (the whole-program passes
    /// of a full build: [`plcc_ir::passes::optimize_program_for`]).
    pub promotion: plcc_ir::passes::promote::Promotion,
    /// When the POU bodies are lowered on two threads
    /// ([`plcc_frontend::LowerOptions::parallel_bodies`]; `difftest` compares).
    pub parallel_bodies: plcc_frontend::ParallelBodies,
}

/// Prints one phase's time to standard error when `PLCC_TIME_PASSES` is set.
pub fn report_time(phase: &str, took: Duration) {
    if std::env::var_os("PLCC_TIME_PASSES").is_some() {
        eprintln!("time: {:>9.3} ms  {phase}", took.as_secs_f64() * 1e3);
    }
}

/// Frees `value` on a thread of its own: the large structures of a build (its syntax
/// trees, a module once compiled) take tens of milliseconds to free, which the
/// calling thread need not wait for.
pub fn drop_in_background<T: Send + 'static>(value: T) {
    std::thread::spawn(move || drop(value));
}

/// Reads the files and the library files (`--lib`) and builds them together.
pub fn build_files<P: AsRef<Path>, L: AsRef<Path>>(
    files: &[P],
    library: &[L],
    opts: &BuildOptions,
) -> Result<Build, UsageError> {
    if files.is_empty() {
        return Err(UsageError("no input files".into()));
    }
    let read = |paths: &mut dyn Iterator<Item = &Path>| {
        let mut texts = Vec::new();
        for path in paths {
            let bytes = std::fs::read(path)
                .map_err(|e| UsageError(format!("cannot read {}: {e}", path.display())))?;
            texts.push((path.display().to_string(), bytes));
        }
        Ok::<_, UsageError>(texts)
    };
    let texts = read(&mut files.iter().map(|f| f.as_ref()))?;
    let library = read(&mut library.iter().map(|f| f.as_ref()))?;
    build_sources_with_library(texts, library, opts)
}

/// Builds sources given as (name, bytes); the language comes from the options or
/// each name's extension.
pub fn build_sources(
    texts: Vec<(String, Vec<u8>)>,
    opts: &BuildOptions,
) -> Result<Build, UsageError> {
    build_sources_with_library(texts, Vec::new(), opts)
}

/// Builds sources and library sources (`--lib`), both given as (name, bytes). A
/// library is compiled like any source, after them; it declares POUs and types for
/// the rest of the build, and its PROGRAMs run only when `programs` or a
/// configuration names them.
pub fn build_sources_with_library(
    texts: Vec<(String, Vec<u8>)>,
    library: Vec<(String, Vec<u8>)>,
    opts: &BuildOptions,
) -> Result<Build, UsageError> {
    let mut sources = SourceMap::new();
    let mut inputs: Vec<(FileId, Lang)> = Vec::new();
    let first_library = texts.len();
    for (name, bytes) in texts.into_iter().chain(library) {
        let lang = match opts.lang.or_else(|| Lang::from_path(&name)) {
            Some(l) => l,
            None => {
                return Err(UsageError(format!(
                    "cannot tell the language of {name}: use a .st, .il, .stl or .xml extension, or --lang"
                )))
            }
        };
        let id = sources.add(SourceFile::from_bytes(name, bytes));
        inputs.push((id, lang));
    }
    let lower_opts = LowerOptions {
        programs: opts.programs.clone(),
        codesys: opts.codesys,
        dialect_given: opts.dialect_given,
        plcopen: opts.plcopen.clone(),
        sfc: opts.sfc,
        library: inputs[first_library..].iter().map(|&(f, _)| f).collect(),
        inline_c: opts.inline_c,
        check_only: opts.check_only,
        print: opts.print,
        parallel_bodies: opts.parallel_bodies,
    };
    // The panic boundary of the front end (ARCHITECTURE.md, "Panics"): a panic is a
    // bug in plcc, reported as an internal error, not a crash of the command.
    let compiled = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        plcc_frontend::compile(&mut sources, &inputs, &lower_opts)
    }))
    .unwrap_or_else(|payload| plcc_frontend::Compiled {
        module: None,
        diagnostics: vec![Diagnostic::error_nowhere(
            E_INTERNAL,
            format!(
                "internal error: the front end panicked: {} \
                 (a bug in plcc: please report it with the program)",
                panic_message(payload.as_ref())
            ),
        )],
        timings: Vec::new(),
        syntax: Vec::new(),
        ladder: Vec::new(),
        charts: Vec::new(),
        printed: None,
    });
    let mut diagnostics = compiled.diagnostics;
    let mut timings = compiled.timings;
    let mut module = compiled.module;
    let mut syntax = compiled.syntax;
    if opts.drop_syntax {
        drop_in_background(std::mem::take(&mut syntax));
    }
    if let (Some(m), false) = (&mut module, opts.check_only) {
        let t = Instant::now();
        let mut ok = check(m, "the front end")
            .map_err(|e| diagnostics.extend(e))
            .is_ok();
        timings.push(("verify", t.elapsed()));
        if ok && !opts.no_opt {
            let t = Instant::now();
            if opts.staged {
                plcc_ir::passes::optimize_module(m);
            } else {
                plcc_ir::passes::optimize_program_for(m, opts.promotion);
            }
            timings.push(("optimise", t.elapsed()));
            if std::env::var_os("PLCC_TIME_PASSES").is_some() {
                let insts: usize = m.funcs.iter().map(|f| f.live_inst_count()).sum();
                eprintln!(
                    "optimised IR: {} functions, {insts} instructions",
                    m.funcs.len()
                );
            }
            // A staged module is verified once its optimisation is done: by
            // `machine_staged`, or by the JIT, which verifies what it compiles.
            if !opts.staged {
                let t = Instant::now();
                ok = check(m, "optimisation")
                    .map_err(|e| diagnostics.extend(e))
                    .is_ok();
                timings.push(("verify", t.elapsed()));
            }
        }
        if !ok {
            module = None;
        }
    }
    Ok(Build {
        sources,
        module,
        diagnostics,
        timings,
        syntax,
        ladder: compiled.ladder,
        charts: compiled.charts,
        printed: compiled.printed,
    })
}

/// The message of a panic's payload (`panic!("...")` gives a `&str` or a `String`).
pub fn panic_message(payload: &(dyn std::any::Any + Send)) -> String {
    payload
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "no message".into())
}

/// Verifies a module; failures are internal errors (bugs in plcc), reported as
/// diagnostics rather than panics.
pub(crate) fn check(m: &Module, stage: &str) -> Result<(), Vec<Diagnostic>> {
    plcc_ir::verify::verify_module(m).map_err(|errs| {
        errs.iter()
            .take(10)
            .map(|e| {
                Diagnostic::error_nowhere(
                    E_INTERNAL,
                    format!("internal error: invalid IR after {stage}: {e}"),
                )
                .with_note("this is a bug in plcc; please report it with the program")
            })
            .collect()
    })
}

/// The text of every file of `module`, for listings with source lines.
pub fn source_texts(sources: &SourceMap, module: &Module) -> Vec<Option<String>> {
    module
        .files
        .iter()
        .map(|name| {
            sources
                .iter()
                .find(|(_, f)| &f.name == name)
                .map(|(_, f)| f.text.to_string())
        })
        .collect()
}
