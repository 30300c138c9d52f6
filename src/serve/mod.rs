//! `plcc serve`: runs a program in real time as a soft PLC, its located variables on
//! OpenPLC's Modbus map (`docs/serve.md`).
//!
//! The scan thread ([`scan`]) owns the machine; the I/O image ([`image`]) is shared
//! with the servers under one lock. SIGINT and SIGTERM end the loop after the scan
//! in progress, and the command exits 0.

pub mod http;
pub mod image;
pub mod modbus;
pub mod project;
pub mod retain;
pub mod scan;

use crate::commands::{self, How, Inputs, Mode, EXIT_FAIL, EXIT_USAGE};
use crate::{render, scenario, targets};
use image::Image;
use scan::Stats;
use std::collections::HashMap;
use std::path::PathBuf;
use std::sync::atomic::AtomicBool;
use std::sync::{Arc, Mutex, MutexGuard};
use std::time::Duration;

/// The arguments of `plcc serve`.
pub struct ServeArgs {
    /// The files and how to read them.
    pub inputs: Inputs,
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
    /// `--http ADDR:PORT`, or `none` (default: [`DEFAULT_HTTP`]).
    pub http: Option<String>,
    /// `--token-file F`: the bearer token of writes, forces and control calls.
    pub token_file: Option<PathBuf>,
    /// `--retain FILE`: where the RETAIN variables are kept between runs.
    pub retain: Option<PathBuf>,
    /// `--retain-every`: how often the retained values are saved while the PLC runs
    /// (default [`retain::DEFAULT_EVERY`]; zero: only at the end).
    pub retain_every: Option<Duration>,
}

/// Where the HTTP API listens unless told.
pub const DEFAULT_HTTP: &str = "127.0.0.1:8021";

/// Where the Modbus server listens unless told: loopback, port 5020 (OpenPLC's 502
/// needs privileges).
pub const DEFAULT_MODBUS: &str = "127.0.0.1:5020";

/// A server's address: `None` for `none`; an error for an address that is not
/// `IP:PORT`, or not a loopback one when there is no token.
fn listen_addr(
    what: &str,
    text: &str,
    token: bool,
) -> Result<Option<std::net::SocketAddr>, String> {
    if text.eq_ignore_ascii_case("none") {
        return Ok(None);
    }
    let addr: std::net::SocketAddr = text
        .parse()
        .map_err(|_| format!("--{what} `{text}` is not IP:PORT (e.g. 127.0.0.1:5020) or none"))?;
    if !addr.ip().is_loopback() && !token {
        return Err(format!(
            "--{what} `{text}` is not a loopback address: listening elsewhere needs --token-file"
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

/// Builds the programs of online changes (`POST /api/program`) as the command line
/// built the first one: the same libraries, dialect, profiles, target.
pub struct Loader {
    library: Vec<(String, Vec<u8>)>,
    opts: crate::driver::BuildOptions,
    target: &'static str,
    settings: Vec<(String, String)>,
}

impl Loader {
    fn new(a: &ServeArgs, target: &'static str) -> Result<Loader, u8> {
        let mut library = Vec::new();
        for f in &a.inputs.library {
            match std::fs::read(f) {
                Ok(b) => library.push((f.display().to_string(), b)),
                Err(e) => {
                    eprintln!("error: cannot read {}: {e}", f.display());
                    return Err(EXIT_USAGE);
                }
            }
        }
        let opts = crate::driver::BuildOptions {
            lang: None,
            programs: a.program.iter().cloned().collect(),
            codesys: a
                .inputs
                .dialect
                .as_deref()
                .is_some_and(|d| d.eq_ignore_ascii_case("codesys")),
            dialect_given: a.inputs.dialect.is_some(),
            plcopen: a.inputs.plcopen.options()?,
            sfc: a.inputs.plcopen.sfc_profile()?,
            no_opt: false,
            // The machine runs the whole-program passes (the tiered JIT).
            staged: true,
            check_only: false,
            inline_c: targets::find(target).is_some_and(|t| t.inline_c),
            print: plcc_frontend::PrintAs::Nothing,
            // The RETAIN blocks and the workbench read the syntax trees.
            drop_syntax: false,
            parallel_bodies: Default::default(),
            promotion: Default::default(),
        };
        Ok(Loader {
            library,
            opts,
            target,
            settings: a.settings.clone(),
        })
    }

    /// Builds a program's source (`lang`: its extension): what the API and the
    /// scan thread need to run it; the diagnostics when it has errors.
    pub fn compile(
        &self,
        text: Vec<u8>,
        lang: &str,
    ) -> Result<(http::Catalog, scan::Loaded), String> {
        let files = vec![(format!("program.{lang}"), text)];
        self.compile_files(files).map(|(c, l, _)| (c, l))
    }

    /// [`Loader::compile`] of several files (each language by its name's
    /// extension), with the build (for the workbench's view of the project).
    pub fn compile_files(
        &self,
        files: Vec<(String, Vec<u8>)>,
    ) -> Result<(http::Catalog, scan::Loaded, crate::driver::Build), String> {
        let build =
            crate::driver::build_sources_with_library(files, self.library.clone(), &self.opts)
                .map_err(|e| e.0)?;
        let Some(module) = build.module.clone() else {
            return Err(render::render(&build.sources, &build.diagnostics));
        };
        if module.programs.is_empty() {
            return Err("the program declares no PROGRAM to run".into());
        }
        let (binds, _) = image::bindings(&module);
        let (vars, listing) = api_vars(&module, &binds);
        let retained = retain::retained(&build, &module, &vars);
        let scan_vars = listing.iter().map(|(p, _)| vars[p].clone()).collect();
        Ok((
            http::Catalog {
                vars,
                listing,
                module: module.clone(),
            },
            scan::Loaded {
                module,
                target: self.target,
                settings: self.settings.clone(),
                binds,
                vars: scan_vars,
                retained,
            },
            build,
        ))
    }
}

/// The variables the API names, by canonical path, and their listing (path and
/// type, in declaration order): every variable of the programs, then the globals'.
fn api_vars(
    module: &plcc_ir::Module,
    binds: &[image::Binding],
) -> (HashMap<String, scan::Var>, Vec<(String, String)>) {
    use plcc_ir::vars::{variables_and_strings, Var as V};
    let by_path: HashMap<&str, usize> = binds
        .iter()
        .enumerate()
        .map(|(i, b)| (b.path.as_str(), i))
        .collect();
    let mut roots: Vec<plcc_ir::DataId> = module.programs.iter().map(|e| e.data).collect();
    roots.extend(module.data_by_name(plcc_frontend::GLOBALS_DATA));
    let mut vars = HashMap::new();
    let mut listing = Vec::new();
    for root in roots {
        for v in variables_and_strings(module, root) {
            let var = match v {
                V::Scalar(r) => scan::Var::Scalar {
                    bind: by_path.get(r.path.as_str()).copied(),
                    path: r.path,
                    elem: r.elem,
                },
                V::Str(s) => scan::Var::Str(s),
            };
            if vars.contains_key(var.path()) {
                continue;
            }
            listing.push((var.path().to_string(), http::type_name(&var)));
            vars.insert(var.path().to_string(), var);
        }
    }
    (vars, listing)
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
    let token = match &a.token_file {
        None => None,
        Some(f) => match std::fs::read_to_string(f) {
            Ok(t) if !t.trim().is_empty() && !t.trim().contains(char::is_whitespace) => {
                Some(t.trim().to_string())
            }
            Ok(_) => {
                eprintln!(
                    "error: {}: the token file must hold one token, without spaces",
                    f.display()
                );
                return EXIT_USAGE;
            }
            Err(e) => {
                eprintln!("error: cannot read {}: {e}", f.display());
                return EXIT_USAGE;
            }
        },
    };
    let addrs = listen_addr(
        "modbus",
        a.modbus.as_deref().unwrap_or(DEFAULT_MODBUS),
        token.is_some(),
    )
    .and_then(|m| {
        listen_addr(
            "http",
            a.http.as_deref().unwrap_or(DEFAULT_HTTP),
            token.is_some(),
        )
        .map(|h| (m, h))
    });
    let (modbus, http) = match addrs {
        Ok(a) => a,
        Err(e) => {
            eprintln!("error: {e}");
            return EXIT_USAGE;
        }
    };
    let (build, module) = match commands::build_and_report(
        &a.inputs,
        How {
            programs: a.program.iter().cloned().collect(),
            mode: Mode::Staged,
            inline_c: targets::find(target).is_some_and(|t| t.inline_c),
            keep_syntax: true,
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
    let (vars, listing) = api_vars(&module, &binds);
    let retained = retain::retained(&build, &module, &vars);
    let scan_vars: Vec<scan::Var> = listing.iter().map(|(p, _)| vars[p].clone()).collect();
    let saved = match &a.retain {
        Some(f) => match retain::load(f) {
            Ok(values) => values,
            Err((status, e)) => {
                eprintln!("error: {e}");
                return status;
            }
        },
        None => serde_json::Map::new(),
    };
    let every = a.retain_every.unwrap_or(retain::DEFAULT_EVERY);
    // The thread that saves the retained values while the PLC runs; dropped (ended)
    // on every way out of this function.
    let mut writer = None;
    let mut periodic = None;
    if let Some(f) = &a.retain {
        let when = if every.is_zero() {
            "at the end".to_string()
        } else {
            format!("every {} s and at the end", every.as_secs_f64())
        };
        eprintln!(
            "retain: {} variable(s), kept in {}, saved {when}",
            retained.len(),
            f.display()
        );
        if !every.is_zero() {
            match retain::Writer::start(f.clone(), Some(saved.clone())) {
                Ok((w, outbox)) => {
                    writer = Some(w);
                    periodic = Some(scan::Periodic {
                        every,
                        next: std::time::Instant::now().checked_add(every),
                        outbox,
                    });
                }
                Err(e) => {
                    eprintln!("error: cannot start the retain thread: {e}");
                    return EXIT_USAGE;
                }
            }
        }
    }
    let module_copy = module.clone();
    let project = project::Project::new(&build, &a.inputs.files, &module);
    let loader = match Loader::new(a, target) {
        Ok(l) => l,
        Err(s) => return s,
    };
    let (requests_tx, requests_rx) = std::sync::mpsc::channel();
    let requests_rx = http.map(|_| requests_rx);
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
            let m = match targets::machine_staged(target, module, &settings) {
                Ok(m) => m,
                Err(diags) => {
                    let _ = ready_tx.send(Err(diags));
                    return Ok(serde_json::Map::new());
                }
            };
            let _ = ready_tx.send(Ok(()));
            scan::run(
                m,
                &scan_shared,
                scan::Setup {
                    binds,
                    vars: scan_vars,
                    cycle: Duration::from_micros(cycle.us),
                    requests: requests_rx,
                    retained,
                    saved,
                    periodic,
                },
            )
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
    if let Some(addr) = http {
        let api = http::Api {
            shared: Arc::clone(&shared),
            catalog: Mutex::new(http::Catalog {
                vars,
                listing,
                module: module_copy,
            }),
            loader,
            token,
            requests: requests_tx,
            target: target.to_string(),
            cycle_us: cycle.us,
            streams: Arc::default(),
            project: std::sync::RwLock::new(project),
        };
        match http::start(addr, api) {
            Ok(bound) => eprintln!("http: listening on {bound}"),
            Err(e) => {
                eprintln!("error: http: cannot listen on {addr}: {e}");
                shared.stop.store(true, std::sync::atomic::Ordering::SeqCst);
                let _ = scanner.join();
                return EXIT_USAGE;
            }
        }
    }
    eprintln!("serving: {target}, {nbinds} located variable(s) on the I/O image");
    let kept = match scanner.join() {
        Ok(k) => k,
        Err(_) => {
            eprintln!("error: the scan thread panicked");
            return EXIT_FAIL;
        }
    };
    let stats = shared.lock_stats().clone();
    eprintln!("{}", stats.line());
    // The periodic writer ends (after the write in progress) before the last save.
    drop(writer);
    if let Some(f) = &a.retain {
        match kept.and_then(|values| retain::save(f, &values)) {
            Ok(()) => eprintln!("retain: saved to {}", f.display()),
            Err(e) => {
                eprintln!("error: retain: {e}");
                return EXIT_USAGE;
            }
        }
    }
    match stats.error {
        Some(e) => {
            eprintln!("error: {e}");
            EXIT_FAIL
        }
        None => 0,
    }
}
