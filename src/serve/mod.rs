//! `plcc serve`: runs a program in real time as a soft PLC, its located variables on
//! OpenPLC's Modbus map (`docs/serve.md`).
//!
//! The scan thread ([`scan`]) owns the machine; the I/O image ([`image`]) is shared
//! with the servers under one lock. SIGINT and SIGTERM end the loop after the scan
//! in progress, and the command exits 0.

pub mod image;
pub mod modbus;
pub mod scan;

use crate::commands::{self, How, Mode, PlcopenFlags, EXIT_FAIL, EXIT_USAGE};
use crate::{render, scenario, targets};
use image::Image;
use scan::Stats;
use std::path::PathBuf;
use std::sync::atomic::AtomicBool;
use std::sync::{Arc, Mutex, MutexGuard};
use std::time::Duration;

/// The arguments of `plcc serve`.
pub struct ServeArgs {
    /// Source files.
    pub files: Vec<PathBuf>,
    /// Library files (`--lib`).
    pub library: Vec<PathBuf>,
    /// `--lang`
    pub lang: Option<String>,
    /// `--dialect`
    pub dialect: Option<String>,
    /// `--plcopen-order`, `--strict-rungs`, `--sfc`.
    pub plcopen: PlcopenFlags,
    /// The target whose machine runs the program (`host`: the JIT).
    pub target: String,
    /// The PROGRAM to run (default: every instance).
    pub program: Option<String>,
    /// `--cycle-ms`, in microseconds.
    pub cycle_us: Option<u64>,
    /// Target settings (`-s KEY=VALUE`).
    pub settings: Vec<(String, String)>,
    /// `--modbus ADDR:PORT`, or `none` (default: [`DEFAULT_MODBUS`]).
    pub modbus: Option<String>,
}

/// Where the Modbus server listens unless told: loopback, port 5020 (OpenPLC's 502
/// needs privileges).
pub const DEFAULT_MODBUS: &str = "127.0.0.1:5020";

/// A server's address: `None` for `none`; an error for an address that is not
/// `IP:PORT`, or not a loopback one.
fn listen_addr(what: &str, text: &str) -> Result<Option<std::net::SocketAddr>, String> {
    if text.eq_ignore_ascii_case("none") {
        return Ok(None);
    }
    let addr: std::net::SocketAddr = text
        .parse()
        .map_err(|_| format!("--{what} `{text}` is not IP:PORT (e.g. 127.0.0.1:5020) or none"))?;
    if !addr.ip().is_loopback() {
        return Err(format!(
            "--{what} `{text}` is not a loopback address: plcc serve listens only on loopback (127.0.0.1, ::1)"
        ));
    }
    Ok(Some(addr))
}

/// What the scan thread and the servers share.
pub struct Shared {
    /// The Modbus tables.
    pub image: Mutex<Image>,
    /// The scan statistics.
    pub stats: Mutex<Stats>,
    /// Set by SIGINT or SIGTERM: the scan thread ends after the scan in progress.
    pub stop: Arc<AtomicBool>,
}

impl Shared {
    /// The image, locked (a thread that panicked while holding it left the tables
    /// whole: every write to them is a plain store).
    pub fn lock_image(&self) -> MutexGuard<'_, Image> {
        self.image.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// The statistics, locked.
    pub fn lock_stats(&self) -> MutexGuard<'_, Stats> {
        self.stats.lock().unwrap_or_else(|p| p.into_inner())
    }
}

/// `plcc serve FILE...`
pub fn serve(a: &ServeArgs) -> u8 {
    let target = match commands::runnable_target(&a.target) {
        Ok(t) => t,
        Err(s) => return s,
    };
    let stop = Arc::new(AtomicBool::new(false));
    for sig in [signal_hook::consts::SIGINT, signal_hook::consts::SIGTERM] {
        if let Err(e) = signal_hook::flag::register(sig, Arc::clone(&stop)) {
            eprintln!("error: cannot handle signal {sig}: {e}");
            return EXIT_USAGE;
        }
    }
    let modbus = match listen_addr("modbus", a.modbus.as_deref().unwrap_or(DEFAULT_MODBUS)) {
        Ok(m) => m,
        Err(e) => {
            eprintln!("error: {e}");
            return EXIT_USAGE;
        }
    };
    let (build, module) = match commands::build_and_report(
        &a.files,
        &a.library,
        a.lang.as_deref(),
        a.dialect.as_deref(),
        &a.plcopen,
        How {
            programs: a.program.iter().cloned().collect(),
            mode: Mode::Full,
            inline_c: targets::find(target).is_some_and(|t| t.inline_c),
        },
    ) {
        Ok(b) => b,
        Err(s) => return s,
    };
    if let Err(s) = commands::pick_programs(&module, a.program.as_deref()) {
        return s;
    }
    let cycle = scenario::Cycle::of(&module, a.cycle_us);
    eprintln!("{cycle}");
    let (binds, outside) = image::bindings(&module);
    for o in &outside {
        eprintln!("warning: {o}: not on Modbus, an ordinary variable");
    }
    let nbinds = binds.len();
    let shared = Arc::new(Shared {
        image: Mutex::new(Image::default()),
        stats: Mutex::new(Stats::default()),
        stop,
    });
    // The machine is made on the scan thread, which owns it (a JIT's code and data
    // stay with one thread).
    let (ready_tx, ready_rx) = std::sync::mpsc::channel();
    let settings = a.settings.clone();
    let scan_shared = Arc::clone(&shared);
    let scanner = std::thread::Builder::new()
        .name("plc-scan".into())
        .spawn(move || {
            let mut m = match targets::machine_owned(target, module, &settings) {
                Ok(m) => m,
                Err(diags) => {
                    let _ = ready_tx.send(Err(diags));
                    return;
                }
            };
            let _ = ready_tx.send(Ok(()));
            scan::run(
                m.as_mut(),
                &scan_shared,
                &binds,
                Duration::from_micros(cycle.us),
            );
        });
    let scanner = match scanner {
        Ok(s) => s,
        Err(e) => {
            eprintln!("error: cannot start the scan thread: {e}");
            return EXIT_USAGE;
        }
    };
    match ready_rx.recv() {
        Ok(Ok(())) => {}
        Ok(Err(diags)) => {
            render::to_stderr(&build.sources, &diags);
            let _ = scanner.join();
            return EXIT_FAIL;
        }
        Err(_) => {
            eprintln!("error: the scan thread ended before the machine was made");
            return EXIT_FAIL;
        }
    }
    if let Some(addr) = modbus {
        match modbus::start(addr, Arc::clone(&shared)) {
            Ok(bound) => eprintln!("modbus: listening on {bound}"),
            Err(e) => {
                eprintln!("error: modbus: cannot listen on {addr}: {e}");
                shared.stop.store(true, std::sync::atomic::Ordering::SeqCst);
                let _ = scanner.join();
                return EXIT_USAGE;
            }
        }
    }
    eprintln!("serving: {target}, {nbinds} located variable(s) on the I/O image");
    if scanner.join().is_err() {
        eprintln!("error: the scan thread panicked");
        return EXIT_FAIL;
    }
    let stats = shared.lock_stats().clone();
    eprintln!("{}", stats.line());
    match stats.error {
        Some(e) => {
            eprintln!("error: {e}");
            EXIT_FAIL
        }
        None => 0,
    }
}
