//! The registry of targets: name to backend, and machines to run programs on.

use plcc_ir::backend::{Backend, Options};
use plcc_ir::diag::{CodeInfo, Diagnostic};
use plcc_ir::machine::Machine;
use plcc_ir::Module;

/// A target plcc knows: one line of [`TARGETS`] each.
#[derive(Copy, Clone)]
pub struct TargetInfo {
    /// Its name on the command line.
    pub name: &'static str,
    /// One line for `--help` and errors.
    pub about: &'static str,
    /// True if `plcc run`/`plcc test` can run programs on it here.
    pub can_run: fn() -> bool,
    /// Its backend, if it generates code (the interpreter does not).
    pub backend: Option<fn() -> Box<dyn Backend>>,
    /// What it writes, for the help of `--target` (empty: nothing).
    pub writes: &'static str,
    /// What runs programs on it, for the help of `run`/`test`.
    pub machine: &'static str,
    /// The setting (`KEY=VALUE`) the tests and `plcc difftest` run its machine
    /// with, the one that checks the most; empty for none.
    pub checked: &'static str,
    /// Its backend's diagnostic codes, for `plcc explain`.
    pub codes: &'static [CodeInfo],
    /// It copies the C code of pragmas into its output (matiec's way), so the front
    /// end keeps them (`inline_c` in the IR) instead of skipping them with W0010.
    pub inline_c: bool,
}

impl TargetInfo {
    /// True if `plcc run`/`plcc test` can run programs on it here.
    pub fn runs(&self) -> bool {
        (self.can_run)()
    }

    /// Its machine with its [`checked`](TargetInfo::checked) setting:
    /// `c:sanitize=undefined`.
    pub fn checked_machine(&self) -> String {
        if self.checked.is_empty() {
            self.name.to_string()
        } else {
            format!("{}:{}", self.name, self.checked)
        }
    }
}

impl std::fmt::Debug for TargetInfo {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("TargetInfo")
            .field("name", &self.name)
            .finish_non_exhaustive()
    }
}

impl PartialEq for TargetInfo {
    fn eq(&self, other: &Self) -> bool {
        self.name == other.name
    }
}

fn always() -> bool {
    true
}

/// Every target, the default first.
pub const TARGETS: &[TargetInfo] = &[
    TargetInfo {
        name: "host",
        about: "this machine: Cranelift JIT for run/test, relocatable object files",
        can_run: always,
        backend: Some(|| Box::new(plcc_native::NativeBackend::new())),
        writes: "object file",
        machine: "JIT",
        checked: "",
        codes: plcc_native::CODES,
        inline_c: false,
    },
    TargetInfo {
        name: "pic16f876a",
        about: "the PIC16F876A: MPASM assembly (--emit hex: Intel HEX); run/test on plcc's simulator of the chip",
        can_run: always,
        backend: Some(|| Box::new(plcc_pic16::Pic16Backend::new())),
        writes: "MPASM/HEX",
        machine: "simulator",
        checked: "",
        codes: plcc_pic16::CODES,
        inline_c: false,
    },
    TargetInfo {
        name: "vmasm",
        about: "the CPDev virtual machine: XCP code image and DCP description (--emit asm: the VMASM listing); run/test on plcc's VM",
        can_run: always,
        backend: Some(|| Box::new(plcc_vmasm::VmasmBackend::new())),
        writes: "CPDev XCP + DCP",
        machine: "plcc's VM",
        checked: "",
        codes: plcc_vmasm::CODES,
        inline_c: false,
    },
    TargetInfo {
        name: "c",
        about: "C against matiec's ABI (POUS.c, POUS.h, Config0.c, Config0.h, Res0.c; --emit headers: plcc's own headers); run/test built by the system's C compiler",
        can_run: plcc_c::can_run,
        backend: Some(|| Box::new(plcc_c::CBackend::new())),
        writes: "C files against matiec's ABI",
        machine: "the C built by the system's compiler",
        checked: "sanitize=undefined",
        codes: plcc_c::CODES,
        inline_c: true,
    },
    TargetInfo {
        name: "interp",
        about: "plcc's reference IR interpreter (run/test only)",
        can_run: always,
        backend: None,
        writes: "",
        machine: "the reference interpreter",
        checked: "",
        codes: &[],
        inline_c: false,
    },
];

/// Looks a target up by name.
pub fn find(name: &str) -> Option<&'static TargetInfo> {
    TARGETS.iter().find(|t| t.name.eq_ignore_ascii_case(name))
}

/// The names of the targets, for messages.
pub fn names(runnable_only: bool) -> String {
    TARGETS
        .iter()
        .filter(|t| !runnable_only || t.runs())
        .map(|t| t.name)
        .collect::<Vec<_>>()
        .join(", ")
}

/// The reference machine, which the others are compared with.
pub const REFERENCE: &str = "interp";

/// The machines the tests and `plcc difftest` compare programs on: every target
/// that can run programs here, the reference first, each with its [`checked`]
/// setting (`c:sanitize=undefined`).
///
/// [`checked`]: TargetInfo::checked
pub fn checked_machines() -> Vec<String> {
    in_order()
        .filter(|t| t.runs())
        .map(|t| t.checked_machine())
        .collect()
}

/// Every target, the reference first.
fn in_order() -> impl Iterator<Item = &'static TargetInfo> {
    let reference = TARGETS.iter().filter(|t| t.name == REFERENCE);
    reference.chain(TARGETS.iter().filter(|t| t.name != REFERENCE))
}

/// The targets that cannot run programs here (the C target without a compiler),
/// for the notices of tests that run on every machine.
pub fn not_running() -> Vec<&'static str> {
    TARGETS
        .iter()
        .filter(|t| !t.runs())
        .map(|t| t.name)
        .collect()
}

/// The help of `--target` for building: each target and what it writes.
pub fn build_help() -> String {
    let list: Vec<String> = TARGETS
        .iter()
        .map(|t| match t.writes {
            "" => t.name.to_string(),
            w => format!("{} ({w})", t.name),
        })
        .collect();
    format!("The target: {}", list.join(", "))
}

/// The help of `--target` for `run` and `test`: each target and its machine.
pub fn run_help() -> String {
    let list: Vec<String> = TARGETS
        .iter()
        .map(|t| format!("{} ({})", t.name, t.machine))
        .collect();
    format!("Where to run it: {}", list.join(", "))
}

/// The help of `plcc difftest --targets`.
pub fn difftest_help() -> String {
    let all: Vec<String> = in_order().map(|t| t.checked_machine()).collect();
    format!(
        "The machines, the reference first (a machine may carry settings: \
         vmasm:mode=32a; interp:ir=raw runs the unoptimised IR, the optimiser's \
         oracle; host:tier=quick and host:tier=swap-at-2 the JIT's tiers); default: \
         those of {} that run here",
        all.join(",")
    )
}

/// The backend of a target that generates code, behind the panic boundary
/// ([`Guarded`]).
pub fn backend(name: &str) -> Option<Box<dyn Backend>> {
    let t = TARGETS.iter().find(|t| t.name == name)?;
    let make = t.backend?;
    Some(Box::new(Guarded {
        target: t.name,
        inner: make(),
    }))
}

/// A backend whose panics become internal-error diagnostics (E9901) that name the
/// target and ask for a report, instead of taking the command (or `plcc serve`, or
/// the language server) down: the panic policy of ARCHITECTURE.md.
pub struct Guarded {
    target: &'static str,
    inner: Box<dyn Backend>,
}

impl Guarded {
    fn catch<T>(&self, what: &str, f: impl FnOnce() -> T) -> Result<T, Vec<Diagnostic>> {
        catch_panic(self.target, what, f)
    }
}

/// Runs `f`; a panic becomes the internal-error diagnostic (E9901) that names the
/// target and what it was doing, and asks for a report.
pub(crate) fn catch_panic<T>(
    target: &str,
    what: &str,
    f: impl FnOnce() -> T,
) -> Result<T, Vec<Diagnostic>> {
    std::panic::catch_unwind(std::panic::AssertUnwindSafe(f)).map_err(|payload| {
        let why = crate::driver::panic_message(payload.as_ref());
        vec![Diagnostic::error_nowhere(
            crate::driver::E_INTERNAL,
            format!(
                "internal error: the {target} backend panicked while {what}: {why} \
                 (a bug in plcc: please report it with the program)"
            ),
        )]
    })
}

impl Backend for Guarded {
    fn facts(&self) -> plcc_ir::backend::TargetFacts {
        self.inner.facts()
    }

    fn compile(
        &self,
        module: &Module,
        options: &Options,
    ) -> Result<plcc_ir::backend::Artifacts, Vec<Diagnostic>> {
        self.catch("compiling", || self.inner.compile(module, options))?
    }

    fn machine(
        &self,
        module: &Module,
        options: &Options,
    ) -> Option<Result<Box<dyn Machine>, Vec<Diagnostic>>> {
        match self.catch("setting up its machine", || {
            self.inner.machine(module, options)
        }) {
            Ok(m) => m,
            Err(d) => Some(Err(d)),
        }
    }
}

/// How long one scan may run under `plcc run`/`plcc test` before the watchdog stops it.
pub const WATCHDOG: std::time::Duration = std::time::Duration::from_secs(10);

/// A machine running `module` on the target, with the scan watchdog armed.
pub fn machine(name: &str, module: &Module) -> Result<Box<dyn Machine>, Vec<Diagnostic>> {
    machine_owned(name, module.clone(), &[])
}

/// Like [`machine`], with target settings (`-s KEY=VALUE`).
pub fn machine_with(
    name: &str,
    module: &Module,
    settings: &[(String, String)],
) -> Result<Box<dyn Machine>, Vec<Diagnostic>> {
    machine_owned(name, module.clone(), settings)
}

/// The machine of a name that may carry settings, as the tests and `plcc difftest`
/// write them: `c:sanitize=undefined`, `vmasm:mode=32a` (settings separated by
/// `,` after the colon).
pub fn machine_spec(spec: &str, module: &Module) -> Result<Box<dyn Machine>, Vec<Diagnostic>> {
    let (name, settings) = split_spec(spec);
    machine_with(name, module, &settings)
}

/// A machine's name and its settings: `vmasm:mode=32a` is `vmasm` with `mode=32a`.
pub fn split_spec(spec: &str) -> (&str, Vec<(String, String)>) {
    match spec.split_once(':') {
        Some((name, kvs)) => {
            let settings = kvs
                .split(',')
                .map(|kv| match kv.split_once('=') {
                    Some((k, v)) => (k.trim().to_string(), v.trim().to_string()),
                    None => (kv.trim().to_string(), String::new()),
                })
                .collect();
            (name, settings)
        }
        None => (spec, Vec::new()),
    }
}

/// Where promotion pays on the target `name` (its backend's
/// [`plcc_ir::backend::TargetFacts::promotion`]; the interpreter's is the default).
pub fn promotion(name: &str) -> plcc_ir::passes::promote::Promotion {
    backend(name).map_or(Default::default(), |b| b.facts().promotion)
}

/// The machine of a module built with [`crate::driver::BuildOptions::staged`] (each
/// function optimised, the whole-program passes not run), as `plcc run`, `plcc test`
/// and `plcc serve` build. The `host` target takes the `tier` setting
/// ([`crate::tiers::Tiers`]): a large program starts on quickly compiled code and the
/// whole-program passes run in the background (the tiered JIT). Otherwise they run
/// here, and the machine is [`machine_owned`]'s.
pub fn machine_staged(
    name: &str,
    mut module: Module,
    settings: &[(String, String)],
) -> Result<Box<dyn Machine>, Vec<Diagnostic>> {
    let (tiers, settings) = match name {
        "host" => crate::tiers::Tiers::take(settings)?,
        _ => (crate::tiers::Tiers::Full, settings.to_vec()),
    };
    let insts: usize = module.funcs.iter().map(|f| f.live_inst_count()).sum();
    if tiers.starts_quick(insts) {
        let t = std::time::Instant::now();
        let mut m = crate::tiers::machine(module, &settings, tiers)?;
        crate::driver::report_time(
            "quick code (the optimised code follows in the background)",
            t.elapsed(),
        );
        m.set_watchdog(Some(WATCHDOG));
        return Ok(m);
    }
    let t = std::time::Instant::now();
    plcc_ir::passes::optimize_whole_program(&mut module, promotion(name));
    crate::driver::check(&module, "optimisation")?;
    crate::driver::report_time("whole-program optimisation", t.elapsed());
    machine_owned(name, module, &settings)
}

/// Like [`machine_with`], taking the module (saves a copy of a large one).
pub fn machine_owned(
    name: &str,
    mut module: Module,
    settings: &[(String, String)],
) -> Result<Box<dyn Machine>, Vec<Diagnostic>> {
    // Loops check the watchdog, so an endless loop ends in an error, not a hang. The
    // interpreter's watchdog is its step limit: it runs the IR without the checks,
    // and so stays an oracle for the pass (its copies of loops, docs/ir.md).
    let t = std::time::Instant::now();
    if name != "interp" {
        plcc_ir::passes::watchdog::run(&mut module);
    }
    crate::driver::report_time("watchdog checks", t.elapsed());
    let mut m = match name {
        "interp" => plcc_ir::interp::Interp::new(&module)
            .map(|m| Box::new(m) as Box<dyn Machine>)
            .map_err(|e| {
                let code = match e {
                    plcc_ir::interp::SetupError::DataTooLarge { .. } => {
                        crate::driver::E_INTERP_DATA_TOO_LARGE
                    }
                    plcc_ir::interp::SetupError::Malformed(_) => crate::driver::E_INTERNAL,
                };
                vec![Diagnostic::error_nowhere(code, e.to_string())]
            })?,
        _ => match backend(name).and_then(|b| {
            let opts = Options {
                settings: settings.to_vec(),
                ..Options::default()
            };
            b.machine(&module, &opts)
        }) {
            Some(r) => r?,
            None => {
                return Err(vec![Diagnostic::error_nowhere(
                    crate::driver::E_CANNOT_RUN,
                    format!("target `{name}` cannot run programs here"),
                )])
            }
        },
    };
    m.set_watchdog(Some(WATCHDOG));
    // The machine holds what it runs; a large module is freed meanwhile.
    if module.funcs.iter().map(|f| f.insts.len()).sum::<usize>() >= plcc_ir::parallel::MIN_INSTS {
        crate::driver::drop_in_background(module);
    }
    Ok(m)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A backend that panics: the boundary's test subject.
    struct Panics;

    impl Backend for Panics {
        fn facts(&self) -> plcc_ir::backend::TargetFacts {
            panic!("facts are not the point")
        }
        fn compile(
            &self,
            _: &Module,
            _: &Options,
        ) -> Result<plcc_ir::backend::Artifacts, Vec<Diagnostic>> {
            panic!("index out of bounds: the len is 3 but the index is 7")
        }
        fn machine(
            &self,
            _: &Module,
            _: &Options,
        ) -> Option<Result<Box<dyn Machine>, Vec<Diagnostic>>> {
            let reason = String::from("no such register");
            panic!("{reason}")
        }
    }

    #[test]
    fn a_backend_panic_is_an_internal_error_diagnostic() {
        let g = Guarded {
            target: "test",
            inner: Box::new(Panics),
        };
        let m = Module::default();
        let e = g.compile(&m, &Options::default()).unwrap_err();
        assert_eq!(e[0].code, crate::driver::E_INTERNAL);
        assert!(
            e[0].message
                .contains("the test backend panicked while compiling: index out of bounds"),
            "{}",
            e[0].message
        );
        let Some(Err(e)) = g.machine(&m, &Options::default()) else {
            panic!("the machine's panic is an error")
        };
        assert!(
            e[0].message
                .contains("setting up its machine: no such register"),
            "{}",
            e[0].message
        );
        // Every target's backend is behind the boundary.
        for t in TARGETS.iter().filter(|t| t.backend.is_some()) {
            assert!(backend(t.name).is_some());
        }
    }
}
