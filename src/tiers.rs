//! The tiered JIT: a large program starts on quickly compiled code while the
//! whole-program optimiser and Cranelift's optimising compiler work on a thread of
//! their own, at a lower priority; the optimised code takes over between two scans.
//!
//! Both tiers compile versions of one module for one data block and runtime context
//! ([`plcc_native::quick_jit`]): the quick tier the module with each function
//! optimised ([`plcc_ir::passes::optimize_module`]), the full tier the same module
//! after the whole-program passes ([`plcc_ir::passes::optimize_whole_program`]).
//! Neither changes data objects, and nothing of a scan's state lives outside data
//! memory and the runtime context between scans, so the swap changes speed only.
//! The differential tests run both tiers and the swap (`host:tier=quick`,
//! `host:tier=swap-at-2`).

use crate::driver;
use plcc_ir::diag::Diagnostic;
use plcc_ir::machine::{Machine, MachineError};
use plcc_ir::value::PlcValue;
use plcc_ir::Module;
use plcc_native::{Jit, Tier};
use std::sync::mpsc::{Receiver, TryRecvError};

/// Instructions (each function optimised) from which `tier=auto` starts a program on
/// quick code: below it, the optimised code takes under about 0.1 s to make.
pub const TIER_MIN_INSTS: usize = 20_000;

/// Diagnostic code of a bad `tier` setting (the native backend's code for settings).
const E_BAD_SETTING: &str = plcc_native::codes::E_BAD_SETTING;

/// Target settings, `KEY=VALUE` pairs.
type Settings = Vec<(String, String)>;

/// When the `host` machine runs the optimised code: its `tier` setting.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Tiers {
    /// Quick code first for a program of [`TIER_MIN_INSTS`] instructions or more,
    /// the optimised code from the first scan after it is ready (the default).
    Auto,
    /// The optimised code from the first scan (`tier=full`).
    Full,
    /// The quick code only, never replaced (`tier=quick`): the quick tier's own
    /// results, for the tests.
    Quick,
    /// Quick code first, the optimised code from scan N on (counted from 0 after the
    /// cold start), waiting for it (`tier=swap-at-N`): a swap at a known scan, for the
    /// tests.
    SwapAt(u64),
}

impl Tiers {
    /// The `tier` setting out of a host machine's settings; the others are returned.
    pub fn take(settings: &[(String, String)]) -> Result<(Tiers, Settings), Vec<Diagnostic>> {
        let mut tiers = Tiers::Auto;
        let mut rest = Vec::new();
        for (k, v) in settings {
            if k != "tier" {
                rest.push((k.clone(), v.clone()));
                continue;
            }
            tiers = match v.as_str() {
                "auto" => Tiers::Auto,
                "full" => Tiers::Full,
                "quick" => Tiers::Quick,
                _ => match v.strip_prefix("swap-at-").and_then(|n| n.parse().ok()) {
                    Some(n) => Tiers::SwapAt(n),
                    None => {
                        return Err(vec![Diagnostic::error_nowhere(
                            E_BAD_SETTING,
                            format!(
                                "`tier` is `auto`, `full`, `quick` or `swap-at-N` (N a scan number), not `{v}`"
                            ),
                        )])
                    }
                },
            };
        }
        Ok((tiers, rest))
    }

    /// Whether a module of `insts` instructions starts on quick code.
    pub fn starts_quick(self, insts: usize) -> bool {
        match self {
            Tiers::Auto => insts >= TIER_MIN_INSTS,
            Tiers::Full => false,
            Tiers::Quick | Tiers::SwapAt(_) => true,
        }
    }
}

/// The `host` machine of a module whose functions are optimised but whose
/// whole-program passes have not run: quick code now (the watchdog checks added as
/// each function is translated), the optimised code made on a thread of its own and
/// swapped in as `tiers` says.
pub fn machine(
    module: Module,
    settings: &[(String, String)],
    tiers: Tiers,
) -> Result<Box<dyn Machine>, Vec<Diagnostic>> {
    let opts = plcc_ir::backend::Options {
        settings: settings.to_vec(),
        ..Default::default()
    };
    let (jit, upgrade) = crate::targets::catch_panic("host", "compiling the quick code", || {
        plcc_native::quick_jit(&module, &opts)
    })??;
    if tiers == Tiers::Quick {
        driver::drop_in_background(module);
        return Ok(Box::new(Tiered {
            jit,
            pending: None,
            swap_at: None,
            scans: 0,
        }));
    }
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        lower_priority();
        let mut module = module;
        let tier = crate::targets::catch_panic("host", "making the optimised code", || {
            plcc_ir::passes::optimize_whole_program(&mut module, crate::targets::promotion("host"));
            driver::check(&module, "optimisation")?;
            upgrade.compile(&module)
        })
        .and_then(|t| t);
        // The machine may be gone (a run of no scans): then the tier is freed here.
        let _ = tx.send(tier);
    });
    Ok(Box::new(Tiered {
        jit,
        pending: Some(rx),
        swap_at: match tiers {
            Tiers::SwapAt(n) => Some(n),
            _ => None,
        },
        scans: 0,
    }))
}

/// Makes the calling thread (and the threads it starts) yield the cores to the
/// scans: the optimised code is worth having, not worth a late scan.
fn lower_priority() {
    #[cfg(target_os = "linux")]
    // SAFETY: plain system calls on the calling thread's own id.
    unsafe {
        let tid = libc::syscall(libc::SYS_gettid) as libc::id_t;
        libc::setpriority(libc::PRIO_PROCESS, tid, 10);
    }
}

/// The JIT with the optimised code on its way.
struct Tiered {
    jit: Jit,
    /// The optimised code, once made; `None` once installed (or never coming).
    pending: Option<Receiver<Result<Tier, Vec<Diagnostic>>>>,
    /// The scan before which the optimised code must be in (waiting for it).
    swap_at: Option<u64>,
    /// Scans since the cold start.
    scans: u64,
}

impl Tiered {
    /// Installs the optimised code if it is ready (or waits for it, at `swap_at`).
    fn poll(&mut self) {
        let Some(rx) = &self.pending else { return };
        let got = if self.swap_at.is_some_and(|n| self.scans >= n) {
            rx.recv().map_err(|_| TryRecvError::Disconnected)
        } else {
            rx.try_recv()
        };
        let failed = match got {
            Err(TryRecvError::Empty) => return,
            Ok(Ok(tier)) => self.jit.install(tier).err().map(|e| e.0),
            Ok(Err(diags)) => Some(
                diags
                    .iter()
                    .map(|d| format!("{}: {}", d.code, d.message))
                    .collect::<Vec<_>>()
                    .join("; "),
            ),
            Err(TryRecvError::Disconnected) => Some("its thread ended without it".to_string()),
        };
        self.pending = None;
        if let Some(why) = failed {
            // A bug of plcc, not of the program: the quick code computes the same.
            eprintln!(
                "internal error: the optimised code could not be made ({why}); the \
                 program goes on running on the quickly compiled code (a bug in plcc: \
                 please report it with the program)"
            );
        }
    }
}

impl Machine for Tiered {
    fn target(&self) -> &str {
        self.jit.target()
    }

    fn cold_start(&mut self) -> Result<(), MachineError> {
        self.scans = 0;
        self.poll();
        self.jit.cold_start()
    }

    fn set_clock_us(&mut self, us: i64) {
        self.jit.set_clock_us(us)
    }

    fn scan(&mut self) -> Result<(), MachineError> {
        self.poll();
        self.scans += 1;
        self.jit.scan()
    }

    fn vars_module(&self) -> &Module {
        self.jit.vars_module()
    }

    fn string_var(&self, path: &str) -> Result<plcc_ir::vars::StrRef, MachineError> {
        self.jit.string_var(path)
    }

    fn read(&self, path: &str) -> Result<PlcValue, MachineError> {
        self.jit.read(path)
    }

    fn write(&mut self, path: &str, value: PlcValue) -> Result<(), MachineError> {
        self.jit.write(path, value)
    }

    fn fault(&self) -> bool {
        self.jit.fault()
    }

    fn clear_fault(&mut self) {
        self.jit.clear_fault()
    }

    fn set_watchdog(&mut self, limit: Option<std::time::Duration>) {
        self.jit.set_watchdog(limit)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn kv(k: &str, v: &str) -> (String, String) {
        (k.to_string(), v.to_string())
    }

    #[test]
    fn the_tier_setting_is_read_and_the_others_are_passed_on() {
        let (t, rest) = Tiers::take(&[kv("threads", "2"), kv("tier", "swap-at-7")]).unwrap();
        assert_eq!(t, Tiers::SwapAt(7));
        assert_eq!(rest, vec![kv("threads", "2")]);
        for (v, want) in [
            ("auto", Tiers::Auto),
            ("full", Tiers::Full),
            ("quick", Tiers::Quick),
        ] {
            assert_eq!(Tiers::take(&[kv("tier", v)]).unwrap().0, want);
        }
        assert_eq!(Tiers::take(&[]).unwrap().0, Tiers::Auto);
        for bad in ["", "fast", "swap-at-", "swap-at--1", "swap-at-1x"] {
            let e = Tiers::take(&[kv("tier", bad)]).unwrap_err();
            assert_eq!(e[0].code, E_BAD_SETTING, "{bad}");
        }
    }

    #[test]
    fn only_auto_looks_at_the_size() {
        assert!(!Tiers::Auto.starts_quick(TIER_MIN_INSTS - 1));
        assert!(Tiers::Auto.starts_quick(TIER_MIN_INSTS));
        assert!(!Tiers::Full.starts_quick(usize::MAX));
        assert!(Tiers::Quick.starts_quick(0));
        assert!(Tiers::SwapAt(3).starts_quick(0));
    }
}
