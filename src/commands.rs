//! The commands of the `plcc` binary. Each returns the process exit status: 0 on
//! success, 1 when the program has errors or a check fails, 2 for usage and I/O
//! errors.

use crate::driver::{self, Build, BuildOptions, UsageError};
use crate::{output, render, scenario, targets};
use plcc_frontend::Lang;
use plcc_ir::text::{print_module, PrintOptions};
use plcc_ir::Module;
use std::path::{Path, PathBuf};

/// Exit status for a program with errors or a failed check.
pub const EXIT_FAIL: u8 = 1;
/// Exit status for usage and I/O errors.
pub const EXIT_USAGE: u8 = 2;

fn usage(msg: impl std::fmt::Display) -> u8 {
    eprintln!("error: {msg}");
    EXIT_USAGE
}

fn parse_lang(lang: Option<&str>) -> Result<Option<Lang>, UsageError> {
    match lang {
        None => Ok(None),
        Some(l) => Lang::from_name(l)
            .map(Some)
            .ok_or_else(|| UsageError(format!("unknown language `{l}` (use st, il, stl or xml)"))),
    }
}

/// The source files of a build and how to read them: what every building command
/// takes.
#[derive(Clone, Debug, Default)]
pub struct Inputs {
    /// Source files.
    pub files: Vec<PathBuf>,
    /// Library files (`--lib`): declarations for the rest of the build.
    pub library: Vec<PathBuf>,
    /// `--lang`
    pub lang: Option<String>,
    /// `--dialect`
    pub dialect: Option<String>,
    /// `--plcopen-order`, `--strict-rungs`, `--sfc`.
    pub plcopen: PlcopenFlags,
}

/// `--plcopen-order`, `--strict-rungs` and `--sfc`, as given.
#[derive(Clone, Debug, Default)]
pub struct PlcopenFlags {
    /// The profile's name.
    pub order: Option<String>,
    /// The ladder editor's style rules are errors.
    pub strict_rungs: bool,
    /// The SFC profile's name.
    pub sfc: Option<String>,
}

impl PlcopenFlags {
    /// The flags from the command line.
    pub fn new(order: Option<String>, strict_rungs: bool) -> PlcopenFlags {
        PlcopenFlags {
            order,
            strict_rungs,
            sfc: None,
        }
    }

    /// With `--sfc`.
    pub fn with_sfc(mut self, sfc: Option<String>) -> PlcopenFlags {
        self.sfc = sfc;
        self
    }

    pub(crate) fn sfc_profile(&self) -> Result<plcc_frontend::sfc::Profile, u8> {
        match &self.sfc {
            None => Ok(plcc_frontend::sfc::Profile::Iec),
            Some(name) => plcc_frontend::sfc::Profile::from_name(name).ok_or_else(|| {
                eprintln!("error: unknown SFC profile `{name}`: use iec, matiec or codesys");
                EXIT_USAGE
            }),
        }
    }

    pub(crate) fn options(&self) -> Result<plcc_frontend::plcopen::Options, u8> {
        let profile = match &self.order {
            None => plcc_frontend::plcopen::Profile::Iec,
            Some(name) => match plcc_frontend::plcopen::Profile::from_name(name) {
                Some(p) => p,
                None => {
                    eprintln!(
                        "error: unknown PLCopen profile `{name}`: use iec, xml2st, openplc3, beremiz or legacy"
                    );
                    return Err(EXIT_USAGE);
                }
            },
        };
        Ok(plcc_frontend::plcopen::Options {
            profile,
            strict_rungs: self.strict_rungs,
        })
    }
}

/// Builds and prints the diagnostics; `Err(status)` when the build cannot go on.
/// The returned build's module has been taken out into the second value.
pub(crate) fn build_and_report(inputs: &Inputs, how: How) -> Result<(Build, Module), u8> {
    let Inputs {
        files,
        library,
        lang,
        dialect,
        plcopen,
    } = inputs;
    let (lang, dialect) = (lang.as_deref(), dialect.as_deref());
    let How {
        programs,
        mode,
        inline_c,
        keep_syntax,
    } = how;
    let sfc = plcopen.sfc_profile()?;
    let plcopen = plcopen.options()?;
    let lang = parse_lang(lang).map_err(usage)?;
    let codesys = match dialect.map(|d| d.to_ascii_lowercase()) {
        None => false,
        Some(d) if d == "iec" => false,
        Some(d) if d == "codesys" => true,
        Some(d) => {
            eprintln!("error: unknown dialect `{d}`: use iec or codesys");
            return Err(EXIT_USAGE);
        }
    };
    let opts = BuildOptions {
        lang,
        codesys,
        dialect_given: dialect.is_some(),
        plcopen,
        sfc,
        programs,
        no_opt: mode == Mode::Unoptimised,
        staged: mode == Mode::Staged,
        check_only: matches!(mode, Mode::Check | Mode::Print(_)),
        inline_c,
        print: match mode {
            Mode::Print(p) => p,
            _ => plcc_frontend::PrintAs::Nothing,
        },
        drop_syntax: !keep_syntax,
        parallel_bodies: Default::default(),
        promotion: match mode {
            Mode::Full(p) => p,
            _ => Default::default(),
        },
    };
    let mut build = driver::build_files(files, library, &opts).map_err(usage)?;
    render::to_stderr(&build.sources, &build.diagnostics);
    match build.module.take() {
        Some(m) => Ok((build, m)),
        None => {
            build.report_timings(&[]);
            let n = build.diagnostics.iter().filter(|d| d.is_error()).count();
            eprintln!("error: could not compile: {n} error(s)");
            Err(EXIT_FAIL)
        }
    }
}

/// What a build is for: the PROGRAMs to run, how far it goes, and whether its
/// target keeps C pragmas ([`targets::TargetInfo::inline_c`]).
pub(crate) struct How {
    pub(crate) programs: Vec<String>,
    pub(crate) mode: Mode,
    pub(crate) inline_c: bool,
    /// Keep the syntax trees in the build (`plcc serve` reads the RETAIN blocks).
    pub(crate) keep_syntax: bool,
}

/// How far a build goes.
#[derive(Copy, Clone, PartialEq, Eq)]
pub(crate) enum Mode {
    /// Diagnostics only.
    Check,
    /// Diagnostics and the files printed (as ST, or as a PLCopen project).
    Print(plcc_frontend::PrintAs),
    /// IR as the front end made it.
    Unoptimised,
    /// Optimised IR, for code generation on a target whose promotion is this
    /// ([`targets::promotion`]).
    Full(plcc_ir::passes::promote::Promotion),
    /// Each function optimised, the whole-program passes left to the machine
    /// ([`targets::machine_staged`]).
    Staged,
}

/// `plcc check FILE...`
pub fn check(inputs: &Inputs) -> u8 {
    match build_and_report(
        inputs,
        How {
            programs: Vec::new(),
            mode: Mode::Check,
            inline_c: false,
            // Kept, and left unfreed with the rest: the process ends here.
            keep_syntax: true,
        },
    ) {
        Ok((build, module)) => {
            build.report_timings(&[]);
            std::mem::forget(module);
            std::mem::forget(build);
            0
        }
        Err(s) => s,
    }
}

/// Every documented diagnostic code: the front end's, the backends' (of the target
/// registry), the driver's.
fn all_codes() -> impl Iterator<Item = &'static plcc_ir::diag::CodeInfo> {
    plcc_frontend::codes::ALL
        .iter()
        .chain(targets::TARGETS.iter().flat_map(|t| t.codes.iter()))
        .chain(driver::CODES.iter())
}

/// `plcc disasm IMAGE.xcp [--mode M] [--dcp FILE]`: the VMASM listing of a CPDev code
/// image. Names and the mode come from the description (`IMAGE.dcp` beside the image
/// unless `--dcp` says otherwise) when there is one.
pub fn disasm(xcp: &Path, mode: Option<&str>, dcp: Option<&Path>) -> u8 {
    use plcc_vmasm::{asm::Symbols, dcp_read, disasm, isa::Mode};
    let code = match std::fs::read(xcp) {
        Ok(c) => c,
        Err(e) => return usage(format!("cannot read {}: {e}", xcp.display())),
    };
    let beside = xcp.with_extension("dcp");
    let dcp_path = dcp
        .map(Path::to_path_buf)
        .or(beside.exists().then_some(beside));
    let desc = match &dcp_path {
        Some(p) => match std::fs::read_to_string(p) {
            Ok(t) => match dcp_read::parse(&t) {
                Ok(d) => Some(d),
                Err(e) => {
                    eprintln!("error: {}: {e}", p.display());
                    return EXIT_FAIL;
                }
            },
            Err(e) => return usage(format!("cannot read {}: {e}", p.display())),
        },
        None => None,
    };
    let mode = match mode {
        Some(m) => match Mode::parse(m) {
            Some(m) => m,
            None => return usage(format!("unknown mode `{m}` (modes: 16, 32, 32a)")),
        },
        None => desc.as_ref().and_then(|d| d.mode).unwrap_or(Mode::M16),
    };
    let syms = desc.as_ref().map(Symbols::from_dcp);
    let names = syms.as_ref().map(|s| s as &dyn disasm::Names);
    match disasm::disassemble(&code, mode, names) {
        Ok(text) => {
            print!("{text}");
            0
        }
        Err(e) => {
            eprintln!("error: {}: {e}", xcp.display());
            EXIT_FAIL
        }
    }
}

/// The arguments of `plcc difftest`.
pub struct DifftestArgs<'a> {
    /// The first seed.
    pub first: u64,
    /// How many seeds.
    pub count: u64,
    /// The machines, comma-separated, the reference first.
    pub machines: &'a str,
    /// Scans per program.
    pub scans: u32,
    /// Where to write the reproducers.
    pub out: Option<&'a Path>,
    /// Print every program and its verdict.
    pub show: bool,
    /// `st`, `xml` or `sfc`.
    pub lang: &'a str,
    /// PLCopen and SFC programs also with the constructs of the known front-end bugs.
    pub known_bugs: bool,
}

/// `plcc difftest`: random programs on every machine (see [`crate::difftest`]): ST
/// programs, or with `--lang xml` PLCopen projects with LD and FBD bodies
/// ([`crate::difftest::plcopen`]). Prints a line per finding and a summary; writes
/// each shrunk reproducer to `out` when given. Exit status 1 when anything disagreed
/// or was rejected.
pub fn difftest(a: &DifftestArgs) -> u8 {
    use crate::difftest::plcopen;
    let (first, count, scans, out) = (a.first, a.count, a.scans, a.out);
    let (xml, sfc) = match a.lang {
        "st" | "oo" => (false, false),
        "xml" => (true, false),
        "sfc" => (false, true),
        l => {
            return usage(format!(
                "`{l}` is not a language of difftest (st, oo, xml or sfc)"
            ))
        }
    };
    // `oo`: ST programs that all have an object-oriented part.
    let oo = a.lang == "oo";
    let machines: Vec<&str> = a.machines.split(',').map(str::trim).collect();
    for m in &machines {
        match targets::find(m.split(':').next().unwrap_or(m)) {
            Some(t) if t.runs() => {}
            _ => return usage(format!("`{m}` is not a target that runs programs")),
        }
    }
    if let Some(dir) = out {
        if let Err(e) = std::fs::create_dir_all(dir) {
            return usage(format!("cannot create {}: {e}", dir.display()));
        }
    }
    let started = std::time::Instant::now();
    let mut findings = 0;
    let (mut profiles, mut twins, mut runs) = (0, 0, 0u64);
    for seed in first..first.saturating_add(count) {
        if a.show && xml {
            let p = plcopen::program_with(seed, a.known_bugs);
            let v = plcopen::check(&p, &machines, scans, seed);
            let twin = plcopen::twin::twin(&p, !a.known_bugs)
                .map_or("no twin".to_string(), |t| t.replace("--", "- -"));
            println!(
                "{}<!-- seed {seed}: {v:?} -->\n<!-- the twin:\n{twin}-->",
                p.to_xml()
            );
        } else if a.show && sfc {
            let p = crate::difftest::sfc::program_with(seed, !a.known_bugs);
            let v = crate::difftest::sfc::check(&p, &machines, scans, seed);
            println!("(* seed {seed}: {v:?} *)\n{}", p.to_st());
        } else if a.show {
            let p = if oo {
                crate::difftest::program_oo(seed)
            } else {
                crate::difftest::program(seed)
            };
            let v = crate::difftest::check(&p, &machines, scans, seed);
            println!("(* seed {seed}: {v:?} *)\n{}", p.to_st());
        }
        let finding = if xml {
            let p = plcopen::program_with(seed, a.known_bugs);
            profiles += plcopen::profiles_agree(&p) as u64;
            twins += plcopen::twin::twin(&p, !a.known_bugs).is_some() as u64;
            plcopen::run_seed(seed, &machines, scans, a.known_bugs)
        } else if sfc {
            match crate::difftest::sfc::run_seed(seed, &machines, scans, !a.known_bugs) {
                Ok(n) => {
                    runs += n as u64;
                    None
                }
                Err(f) => Some(f),
            }
        } else if oo {
            crate::difftest::run_seed_oo(seed, &machines, scans)
        } else {
            crate::difftest::run_seed(seed, &machines, scans)
        };
        let Some(f) = finding else {
            continue;
        };
        findings += 1;
        println!("seed {seed}: {:?}", f.verdict);
        if let Some(dir) = out {
            let p = dir.join(format!("difftest_{seed}.{}", f.ext));
            if let Err(e) = output::write_atomic(&p, f.reproducer.as_bytes()) {
                return usage(format!("cannot write {}: {e}", p.display()));
            }
            println!("  reproducer: {}", p.display());
        } else {
            println!("{}", f.reproducer);
        }
    }
    let what = if xml {
        format!("PLCopen programs ({twins} beside their twin, {profiles} under every profile)")
    } else if sfc {
        format!(
            "charts (each under --sfc iec, matiec and codesys; {runs} machine runs of the \
             agreeing ones, of {} possible: the others did not fit the machine, or were the \
             builds of unsafe charts, which iec and codesys refuse, E0784)",
            3 * machines.len() as u64 * (count - findings)
        )
    } else {
        "programs".to_string()
    };
    println!(
        "{count} {what} from seed {first} on {}: {findings} findings ({:.1} s)",
        machines.join(", "),
        started.elapsed().as_secs_f64()
    );
    if findings == 0 {
        0
    } else {
        EXIT_FAIL
    }
}

/// The catalogue of every diagnostic code, as `docs/diagnostics.md` has it (the text
/// `plcc explain CODE` prints, in Markdown; `tests/diagnostics.rs` keeps the file
/// current).
pub fn diagnostics_markdown() -> String {
    let mut o = String::from(
        "# Diagnostics\n\nEvery code plcc reports, with what it means, how to fix it and an \
example. `plcc explain CODE` prints the same text; `plcc explain` lists the codes. \
Codes E0xxx and W0xxx come from the front ends, E80xx from the native backend, E90xx \
from the PIC16 backend, E91xx from the CPDev VM backend, E99xx from the driver. This \
file is generated from the code tables (`PLCC_BLESS=1 cargo test --test diagnostics \
diagnostics_catalogue` rewrites it).\n",
    );
    for c in all_codes() {
        o.push_str(&format!(
            "\n## {} {}\n\n{}\n",
            c.code, c.title, c.explanation
        ));
    }
    o
}

/// The title and explanation of a diagnostic code (any case), as `plcc explain` has them.
pub fn code_info(code: &str) -> Option<&'static plcc_ir::diag::CodeInfo> {
    all_codes().find(|c| c.code.eq_ignore_ascii_case(code))
}

/// `plcc explain CODE`, or the list of codes without one.
pub fn explain(code: Option<&str>) -> u8 {
    let Some(code) = code else {
        for c in all_codes() {
            println!("{}  {}", c.code, c.title);
        }
        return 0;
    };
    match code_info(code) {
        Some(c) => {
            println!("{}: {}\n\n{}", c.code, c.title, c.explanation);
            0
        }
        None => usage(format!(
            "no diagnostic code `{code}` (`plcc explain` lists them)"
        )),
    }
}

/// Arguments of `plcc run`.
pub struct RunArgs {
    /// The files and how to read them.
    pub inputs: Inputs,
    /// `--target`
    pub target: String,
    /// `--program`
    pub program: Option<String>,
    /// `--scans`
    pub scans: u64,
    /// `--cycle-ms` in microseconds; without it, the tasks' common tick, else 10 ms
    /// ([`scenario::Cycle::of`]).
    pub cycle_us: Option<u64>,
    /// `--timing`: report the time the scans took.
    pub timing: bool,
    /// `-s KEY=VALUE` target settings.
    pub settings: Vec<(String, String)>,
}

pub(crate) fn runnable_target(name: &str) -> Result<&'static str, u8> {
    match targets::find(name) {
        Some(t) if t.runs() => Ok(t.name),
        Some(t) => Err(usage(format!(
            "target `{}` cannot run programs here (targets that can: {})",
            t.name,
            targets::names(true)
        ))),
        None => Err(usage(format!(
            "unknown target `{name}` (known: {})",
            targets::names(false)
        ))),
    }
}

/// The program instances whose variables `run` prints: the one asked for, else all of
/// them (every instance runs in each scan, in declaration order).
pub(crate) fn pick_programs(m: &Module, asked: Option<&str>) -> Result<Vec<String>, u8> {
    match asked {
        Some(p) => match m.program_or_instance_of(p) {
            Some(e) => Ok(vec![e.name.clone()]),
            None => {
                eprintln!("error: no PROGRAM named `{p}`");
                Err(EXIT_FAIL)
            }
        },
        None if m.programs.is_empty() => {
            eprintln!("error: the files declare no PROGRAM to run");
            Err(EXIT_FAIL)
        }
        None => Ok(m.programs.iter().map(|p| p.name.clone()).collect()),
    }
}

/// The program instance a scenario's variables are relative to: the one it names,
/// else the only one; with several (a configuration's instances) and none named,
/// none: the scenario names variables by their whole paths (`fast.count`).
fn pick_program(m: &Module, asked: Option<&str>) -> Result<String, u8> {
    let all = pick_programs(m, asked)?;
    match all.as_slice() {
        [one] => Ok(one.clone()),
        _ => Ok(String::new()),
    }
}

/// `plcc run FILE...`
pub fn run(a: &RunArgs) -> u8 {
    let target = match runnable_target(&a.target) {
        Ok(t) => t,
        Err(s) => return s,
    };
    let programs: Vec<String> = a.program.iter().cloned().collect();
    let (build, module) = match build_and_report(
        &a.inputs,
        How {
            programs,
            mode: Mode::Staged,
            inline_c: targets::find(target).is_some_and(|t| t.inline_c),
            keep_syntax: false,
        },
    ) {
        Ok(b) => b,
        Err(s) => return s,
    };
    let programs = match pick_programs(&module, a.program.as_deref()) {
        Ok(p) => p,
        Err(s) => return s,
    };
    let cycle = scenario::Cycle::of(&module, a.cycle_us);
    eprintln!("{cycle}");
    // The machine takes the module; what prints the variables needs only its
    // declarations.
    let declared = module.clone_declarations();
    let t = std::time::Instant::now();
    let mut m = match targets::machine_staged(target, module, &a.settings) {
        Ok(m) => m,
        Err(diags) => {
            render::to_stderr(&build.sources, &diags);
            return EXIT_FAIL;
        }
    };
    build.report_timings(&[("code generation", t.elapsed())]);
    let mut scan_time = std::time::Duration::ZERO;
    let mut run = || -> Result<(), String> {
        m.cold_start().map_err(|e| e.to_string())?;
        let started = std::time::Instant::now();
        for k in 0..a.scans {
            m.set_clock_us((k * cycle.us) as i64);
            m.scan().map_err(|e| format!("scan {k}: {e}"))?;
        }
        scan_time = started.elapsed();
        Ok(())
    };
    if let Err(e) = run() {
        eprintln!("error: {e}");
        return EXIT_FAIL;
    }
    if a.timing {
        let per = scan_time.as_secs_f64() * 1e6 / a.scans.max(1) as f64;
        eprintln!(
            "timing: {} scans in {:.3} ms, {per:.3} us per scan [{target}]",
            a.scans,
            scan_time.as_secs_f64() * 1e3
        );
    }
    let several = programs.len() > 1;
    // One write for many lines, not one each (tens of thousands in a large program).
    let mut out = std::io::BufWriter::new(std::io::stdout().lock());
    for program in &programs {
        let entry = declared.program(program).expect("picked program");
        let prefix = format!("{}.", entry.name);
        let prefix = if several { String::new() } else { prefix };
        if let Err((status, e)) =
            print_variables(&mut out, m.as_ref(), &declared, entry.data, &prefix)
        {
            eprintln!("error: {e}");
            return status;
        }
    }
    // Globals after the programs' variables, by their plain names.
    if let Some(g) = declared.data_by_name(plcc_frontend::GLOBALS_DATA) {
        let prefix = format!("{}.", plcc_frontend::GLOBALS_DATA);
        if let Err((status, e)) = print_variables(&mut out, m.as_ref(), &declared, g, &prefix) {
            eprintln!("error: {e}");
            return status;
        }
    }
    if let Err(e) = std::io::Write::flush(&mut out) {
        eprintln!("error: cannot write the variables: {e}");
        return EXIT_USAGE;
    }
    drop(out);
    if m.fault() {
        eprintln!("warning: the runtime fault flag is set (a division by zero or an array index out of bounds happened)");
    }
    0
}

/// Prints every variable of data object `root` as `name = value` (STRING and
/// WSTRING variables as literals), each name without `prefix`, to `out`. An error
/// comes with its exit status: 1 for a variable the machine cannot read, 2 for
/// output that cannot be written.
fn print_variables(
    out: &mut impl std::io::Write,
    m: &dyn plcc_ir::machine::Machine,
    module: &plcc_ir::Module,
    root: plcc_ir::DataId,
    prefix: &str,
) -> Result<(), (u8, String)> {
    use plcc_ir::vars::Var;
    for var in plcc_ir::vars::variables_and_strings(module, root) {
        let (path, text) = match &var {
            Var::Scalar(v) => (&v.path, m.read(&v.path).map(|x| x.to_string())),
            Var::Str(s) => (
                &s.path,
                plcc_ir::machine::read_string(m, s)
                    .map(|c| plcc_ir::value::format_string_literal(&c, s.wide)),
            ),
        };
        let text = text.map_err(|e| (EXIT_FAIL, format!("reading {path}: {e}")))?;
        writeln!(
            out,
            "{} = {text}",
            path.strip_prefix(prefix).unwrap_or(path)
        )
        .map_err(|e| (EXIT_USAGE, format!("cannot write the variables: {e}")))?;
    }
    Ok(())
}

/// Arguments of `plcc test`.
pub struct TestArgs {
    /// The files and how to read them.
    pub inputs: Inputs,
    /// `--scenario`
    pub scenario: PathBuf,
    /// `--target`
    pub target: String,
    /// `--cycle-ms` in microseconds; without it, the tasks' common tick, else 10 ms
    /// ([`scenario::Cycle::of`]).
    pub cycle_us: Option<u64>,
    /// `-s KEY=VALUE` target settings.
    pub settings: Vec<(String, String)>,
}

/// `plcc test FILE... --scenario F.expect`
pub fn test(a: &TestArgs) -> u8 {
    let target = match runnable_target(&a.target) {
        Ok(t) => t,
        Err(s) => return s,
    };
    let text = match std::fs::read_to_string(&a.scenario) {
        Ok(t) => t,
        Err(e) => return usage(format!("cannot read {}: {e}", a.scenario.display())),
    };
    let scn = match scenario::parse(&text) {
        Ok(s) => s,
        Err(e) => return usage(format!("{}: {e}", a.scenario.display())),
    };
    if let Some(why) = &scn.unsupported {
        eprintln!("error: {}: not supported: {why}", a.scenario.display());
        return EXIT_FAIL;
    }
    let programs: Vec<String> = scn.program.iter().cloned().collect();
    let (build, module) = match build_and_report(
        &a.inputs,
        How {
            programs,
            mode: Mode::Staged,
            inline_c: targets::find(target).is_some_and(|t| t.inline_c),
            keep_syntax: false,
        },
    ) {
        Ok(b) => b,
        Err(s) => return s,
    };
    let program = match pick_program(&module, scn.program.as_deref()) {
        Ok(p) => p,
        Err(s) => return s,
    };
    let cycle = scenario::Cycle::of(&module, a.cycle_us);
    let mut m = match targets::machine_staged(target, module, &a.settings) {
        Ok(m) => m,
        Err(diags) => {
            render::to_stderr(&build.sources, &diags);
            return EXIT_FAIL;
        }
    };
    eprintln!("{cycle}");
    let out = scenario::run(&scn, m.as_mut(), &program, cycle.us);
    for c in &out.checks {
        if c.ok {
            println!("ok    line {}: {}", c.line, c.text);
        } else {
            println!("FAIL  line {}: {}: {}", c.line, c.text, c.detail);
        }
    }
    if let Some(e) = &out.error {
        println!("ERROR {e}");
    }
    let failed = out.checks.iter().filter(|c| !c.ok).count();
    println!(
        "{}: {} check(s), {} failed{} [{target}]",
        if out.passed() { "passed" } else { "FAILED" },
        out.checks.len(),
        failed,
        if out.fault { ", fault flag raised" } else { "" }
    );
    if out.passed() {
        0
    } else {
        EXIT_FAIL
    }
}

/// Arguments of a plain compilation.
pub struct CompileArgs {
    /// The files and how to read them.
    pub inputs: Inputs,
    /// `--target`
    pub target: String,
    /// `-o`
    pub output: Option<PathBuf>,
    /// `--emit`
    pub emit: Option<String>,
    /// `--program`
    pub programs: Vec<String>,
    /// `-s KEY=VALUE` target settings.
    pub settings: Vec<(String, String)>,
}

/// `plcc [--target T] [--emit KIND] FILE... [-o OUT]`
pub fn compile(a: &CompileArgs) -> u8 {
    if a.inputs.files.is_empty() {
        return usage("no input files (try `plcc --help`)");
    }
    let Some(target) = targets::find(&a.target) else {
        return usage(format!(
            "unknown target `{}` (known: {})",
            a.target,
            targets::names(false)
        ));
    };
    let emit = a.emit.as_deref();
    let mode = match emit {
        Some("ir-raw") => Mode::Unoptimised,
        // The views of ladder files need the front end's checks only.
        Some("il") | Some("ld-text") | Some("sfc-text") => Mode::Check,
        Some("st") => Mode::Print(plcc_frontend::PrintAs::St),
        Some("plcopen") => Mode::Print(plcc_frontend::PrintAs::Plcopen),
        _ => Mode::Full(targets::promotion(target.name)),
    };
    let (build, module) = match build_and_report(
        &a.inputs,
        How {
            programs: a.programs.clone(),
            mode,
            inline_c: target.inline_c,
            keep_syntax: false,
        },
    ) {
        Ok(b) => b,
        Err(s) => return s,
    };
    let (bytes, ext) = match emit {
        Some("ir") | Some("ir-raw") => (
            print_module(&module, &PrintOptions::default()).into_bytes(),
            "ir".to_string(),
        ),
        Some("sfc-text") => {
            if build.charts.is_empty() {
                return usage(
                    "`--emit sfc-text` draws sequential function charts: the files have none",
                );
            }
            let mut s = String::new();
            for v in &build.charts {
                if build.charts.len() > 1 {
                    s.push_str(&format!("(* {} *)\n", build.sources.get(v.file).name));
                }
                s.push_str(&v.drawing);
            }
            std::mem::forget(module);
            (s.into_bytes(), "sfc.txt".to_string())
        }
        Some("st") => {
            let Some(st) = build.printed.clone() else {
                return EXIT_FAIL;
            };
            std::mem::forget(module);
            (formatted_view(&st, false).into_bytes(), "st".to_string())
        }
        Some("plcopen") => {
            if !build.ladder.is_empty() {
                return usage(
                    "`--emit plcopen` writes ST, IL and STL files as a PLCopen project: the files are one already",
                );
            }
            let Some(xml) = build.printed.clone() else {
                eprintln!("error: the build cannot be written as PLCopen XML");
                return EXIT_FAIL;
            };
            std::mem::forget(module);
            (xml.into_bytes(), "xml".to_string())
        }
        Some(view @ ("il" | "ld-text")) => {
            if build.ladder.is_empty() {
                return usage(format!(
                    "`--emit {view}` shows what PLCopen diagrams (and sequential function charts) become: give a PLCopen XML file (.xml) or a file with a chart"
                ));
            }
            let mut s = String::new();
            for v in &build.ladder {
                if view != "ld-text" {
                    s.push_str(&formatted_view(&build.sources.get(v.il).text, true));
                } else {
                    if build.ladder.len() > 1 {
                        s.push_str(&format!("(* {} *)\n", build.sources.get(v.xml).name));
                    }
                    s.push_str(&v.ld_text);
                }
            }
            std::mem::forget(module);
            (s.into_bytes(), view.to_string())
        }
        _ => {
            let Some(backend) = targets::backend(target.name) else {
                return usage(format!(
                    "target `{}` produces no files; use `plcc run --target {}` or `--emit ir`",
                    target.name, target.name
                ));
            };
            let opts = plcc_ir::backend::Options {
                emit: a.emit.clone(),
                settings: a.settings.clone(),
                sources: driver::source_texts(&build.sources, &module),
                output_stem: a
                    .output
                    .as_deref()
                    .filter(|o| o.as_os_str() != "-")
                    .unwrap_or(&a.inputs.files[0])
                    .file_stem()
                    .map(|s| s.to_string_lossy().into_owned()),
            };
            match backend.compile(&module, &opts) {
                Ok(arts) => {
                    let Some(main) = arts.files.first() else {
                        return usage("the backend produced nothing");
                    };
                    if let Some(s) = &arts.summary {
                        eprintln!("{s}");
                    }
                    // A set of named files (the C target's, like iec2c's) goes into
                    // the directory `-o` names (default: here), each name printed.
                    if arts.files.iter().all(|f| f.kind.contains('.')) {
                        return write_file_set(a.output.as_deref(), &arts.files, &build);
                    }
                    // Secondary files (a C header, a description) go beside the main one.
                    let base = a
                        .output
                        .clone()
                        .unwrap_or_else(|| a.inputs.files[0].with_extension(&main.kind));
                    for extra in &arts.files[1..] {
                        if base.as_os_str() == "-" {
                            continue;
                        }
                        let p = base.with_extension(&extra.kind);
                        if let Err(e) = output::write_atomic(&p, &extra.bytes) {
                            return usage(format!("cannot write {}: {e}", p.display()));
                        }
                    }
                    (main.bytes.clone(), main.kind.clone())
                }
                Err(diags) => {
                    render::to_stderr(&build.sources, &diags);
                    return EXIT_FAIL;
                }
            }
        }
    };
    build.report_timings(&[]);
    let out = a.output.clone().unwrap_or_else(|| {
        let text = matches!(ext.as_str(), "ir" | "il" | "st" | "ld-text" | "sfc.txt");
        if (text || emit == Some("plcopen")) && a.output.is_none() {
            PathBuf::from("-")
        } else {
            a.inputs.files[0].with_extension(&ext)
        }
    });
    if out.as_os_str() == "-" {
        use std::io::Write;
        let _ = std::io::stdout().write_all(&bytes);
        return 0;
    }
    match output::write_atomic(&out, &bytes) {
        Ok(()) => 0,
        Err(e) => usage(format!("cannot write {}: {e}", out.display())),
    }
}

/// Writes a backend's named files into `dir` (created if need be; the current
/// directory when `None`) and prints each file's name on stdout as it is written, as
/// matiec's `iec2c` does.
fn write_file_set(dir: Option<&Path>, files: &[plcc_ir::backend::Artifact], build: &Build) -> u8 {
    let dir = dir.unwrap_or(Path::new("."));
    if dir.as_os_str() == "-" {
        return usage("this target writes several files: give a directory with -o");
    }
    if let Err(e) = std::fs::create_dir_all(dir) {
        return usage(format!("cannot create {}: {e}", dir.display()));
    }
    for f in files {
        let p = dir.join(&f.kind);
        if let Err(e) = output::write_atomic(&p, &f.bytes) {
            return usage(format!("cannot write {}: {e}", p.display()));
        }
        println!("{}", f.kind);
    }
    build.report_timings(&[]);
    0
}

/// The usage text of the `iec2c` mode, in the form matiec prints it (Beremiz looks
/// for the flags it passes in it).
fn iec2c_usage(cmd: &str) -> String {
    const OPTIONS: [(char, &str); 15] = [
        ('h', "show this help message"),
        ('v', "print version number"),
        (
            'f',
            "display full token location on error messages (plcc always does)",
        ),
        ('p', "allow use of forward references (plcc always does)"),
        (
            'l',
            "use a relaxed datatype equivalence model (accepted; plcc types as it does)",
        ),
        ('s', "allow use of safe datatypes (accepted, not read)"),
        ('n', "allow use of nested comments (accepted, not read)"),
        (
            'r',
            "allow use of references (REF_TO, REF, ^, NULL) (plcc always does)",
        ),
        (
            'R',
            "allow use of REF_TO ANY datatypes (accepted, not read)",
        ),
        ('a', "allow non-literal array bounds (accepted, not read)"),
        (
            'c',
            "create conversion functions for enumerated data types (accepted, not read)",
        ),
        ('e', "disable EN/ENO generation (accepted, not read)"),
        (
            'O',
            "options for output (code generation) stage (accepted, not read)",
        ),
        (
            'I',
            "the runtime's library directory (accepted; plcc compiles its own standard library)",
        ),
        (
            'T',
            "the directory the files are written into (default: the current directory)",
        ),
    ];
    let mut s = format!(
        "\nsyntax: {cmd} [<options>] [-O <output_options>] [-I <include_directory>] [-T <target_directory>] <input_file>\n"
    );
    for (c, what) in OPTIONS {
        s.push_str(&format!(" -{c} : {what}\n"));
    }
    s.push_str(&format!(
        "\nplcc {} in iec2c mode: writes matiec's files for the C target (see docs/c.md).\n",
        env!("CARGO_PKG_VERSION")
    ));
    s
}

/// `iec2c [options] [-I dir] [-T dir] file.st`, as matiec's compiler is called by
/// OpenPLC's and Beremiz's builds (`plcc iec2c ...`, or plcc installed under the name
/// `iec2c`): the file set of the C target written into `-T`'s directory (default:
/// here), each name printed on stdout. Options are read as `getopt` reads matiec's
/// (`-flp`, `-Tdir`, `-T dir`, options after the file); those that change matiec's
/// parsing are accepted and have no effect. Charts evolve as matiec's (`--sfc
/// matiec`). The exit status is 0 on success and 1 otherwise, as iec2c's (usage
/// errors print the usage).
pub fn iec2c(cmd: &str, args: &[String]) -> u8 {
    const FLAGS: &str = "nhvfplsrRcae";
    let fail = |msg: String| {
        if !msg.is_empty() {
            eprintln!("{msg}");
        }
        print!("{}", iec2c_usage(cmd));
        EXIT_FAIL
    };
    let mut out: Option<PathBuf> = None;
    let mut files: Vec<PathBuf> = Vec::new();
    let mut k = 0;
    let mut only_files = false;
    while k < args.len() {
        let a = &args[k];
        k += 1;
        if only_files || !a.starts_with('-') || a == "-" {
            files.push(PathBuf::from(a));
            continue;
        }
        if a == "--" {
            only_files = true;
            continue;
        }
        for (i, c) in a[1..].char_indices() {
            match c {
                'h' => {
                    print!("{}", iec2c_usage(cmd));
                    return 0;
                }
                'v' => {
                    println!("plcc version {} (iec2c mode)", env!("CARGO_PKG_VERSION"));
                    return 0;
                }
                'I' | 'T' | 'O' => {
                    let rest = &a[1 + i + 1..];
                    let operand = if !rest.is_empty() {
                        rest.to_string()
                    } else if k < args.len() {
                        k += 1;
                        args[k - 1].clone()
                    } else {
                        return fail(format!("Option -{c} requires an operand"));
                    };
                    if c == 'T' {
                        out = Some(PathBuf::from(operand.trim_end_matches('\\')));
                    }
                    break;
                }
                c if FLAGS.contains(c) => {}
                c => return fail(format!("Unrecognized option: -{c}")),
            }
        }
    }
    match files.len() {
        0 => return fail("Missing input file".into()),
        1 => {}
        _ => return fail("Too many input files".into()),
    }
    let status = compile(&CompileArgs {
        inputs: Inputs {
            files,
            library: Vec::new(),
            lang: None,
            dialect: None,
            plcopen: PlcopenFlags::default().with_sfc(Some("matiec".into())),
        },
        target: "c".into(),
        output: Some(out.unwrap_or_else(|| PathBuf::from("."))),
        emit: None,
        programs: Vec::new(),
        settings: Vec::new(),
    });
    if status == 0 {
        0
    } else {
        EXIT_FAIL
    }
}

/// A view of `--emit st` (`il`: it may hold IL bodies) laid out by `plcc fmt`; as it
/// was made, with a note on standard error, if the formatter refuses it.
fn formatted_view(text: &str, il: bool) -> String {
    let formatted = if il {
        plcc_frontend::fmt::format_il(text)
    } else {
        plcc_frontend::fmt::format_st(text)
    };
    formatted.unwrap_or_else(|e| {
        eprintln!("note: the view is shown as made, not formatted: {e}");
        text.to_string()
    })
}
