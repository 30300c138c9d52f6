//! The registry of targets: name to backend, and machines to run programs on.

use plcc_ir::backend::{Backend, Options};
use plcc_ir::diag::Diagnostic;
use plcc_ir::machine::Machine;
use plcc_ir::Module;

/// A target plcc knows.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct TargetInfo {
    /// Its name on the command line.
    pub name: &'static str,
    /// One line for `--help` and errors.
    pub about: &'static str,
    /// True if `plcc run`/`plcc test` can run programs on it here.
    pub runs: bool,
}

/// Every target, the default first.
pub const TARGETS: &[TargetInfo] = &[
    TargetInfo {
        name: "host",
        about: "this machine: Cranelift JIT for run/test, relocatable object files",
        runs: true,
    },
    TargetInfo {
        name: "pic16f876a",
        about: "the PIC16F876A: MPASM assembly (--emit hex: Intel HEX); run/test on plcc's simulator of the chip",
        runs: true,
    },
    TargetInfo {
        name: "vmasm",
        about: "the CPDev virtual machine: XCP code image and DCP description (--emit asm: the VMASM listing); run/test on plcc's VM",
        runs: true,
    },
    TargetInfo {
        name: "interp",
        about: "plcc's reference IR interpreter (run/test only)",
        runs: true,
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
        .filter(|t| t.runs || !runnable_only)
        .map(|t| t.name)
        .collect::<Vec<_>>()
        .join(", ")
}

/// The backend of a target that generates code.
pub fn backend(name: &str) -> Option<Box<dyn Backend>> {
    match name {
        "host" => Some(Box::new(plcc_native::NativeBackend::new())),
        "pic16f876a" => Some(Box::new(plcc_pic16::Pic16Backend::new())),
        "vmasm" => Some(Box::new(plcc_vmasm::VmasmBackend::new())),
        _ => None,
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
