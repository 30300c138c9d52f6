//! The registry of targets: name to backend, and machines to run programs on.

use plcc_ir::backend::{Backend, Options};
use plcc_ir::diag::Diagnostic;
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
}

impl TargetInfo {
    /// True if `plcc run`/`plcc test` can run programs on it here.
    pub fn runs(&self) -> bool {
        (self.can_run)()
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
    },
    TargetInfo {
        name: "pic16f876a",
        about: "the PIC16F876A: MPASM assembly (--emit hex: Intel HEX); run/test on plcc's simulator of the chip",
        can_run: always,
        backend: Some(|| Box::new(plcc_pic16::Pic16Backend::new())),
    },
    TargetInfo {
        name: "vmasm",
        about: "the CPDev virtual machine: XCP code image and DCP description (--emit asm: the VMASM listing); run/test on plcc's VM",
        can_run: always,
        backend: Some(|| Box::new(plcc_vmasm::VmasmBackend::new())),
    },
    TargetInfo {
        name: "c",
        about: "C against matiec's ABI (POUS.c, POUS.h, Config0.c, Config0.h, Res0.c; --emit headers: plcc's own headers); run/test built by the system's C compiler",
        can_run: plcc_c::can_run,
        backend: Some(|| Box::new(plcc_c::CBackend::new())),
    },
    TargetInfo {
        name: "interp",
        about: "plcc's reference IR interpreter (run/test only)",
        can_run: always,
        backend: None,
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

/// The backend of a target that generates code.
pub fn backend(name: &str) -> Option<Box<dyn Backend>> {
    TARGETS
        .iter()
        .find(|t| t.name == name)
        .and_then(|t| t.backend)
        .map(|make| make())
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

/// Like [`machine_with`], taking the module (saves a copy of a large one).
pub fn machine_owned(
    name: &str,
    mut module: Module,
    settings: &[(String, String)],
) -> Result<Box<dyn Machine>, Vec<Diagnostic>> {
    // Loops check the watchdog, so an endless loop ends in an error, not a hang.
    let t = std::time::Instant::now();
    plcc_ir::passes::watchdog::run(&mut module);
    if std::env::var_os("PLCC_TIME_PASSES").is_some() {
        eprintln!(
            "time: {:>9.3} ms  watchdog checks",
            t.elapsed().as_secs_f64() * 1e3
        );
    }
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
    Ok(m)
}
