//! `plcc`: compile PLC programs, run them, test them.

use clap::{Args, Parser, Subcommand};
use plcc::commands;
use std::path::PathBuf;
use std::process::ExitCode;

// A compiler allocates many small objects and frees them in bulk; mimalloc does that
// markedly faster than the system allocator (see BENCHMARKS.md).
#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

/// mimalloc's `mi_option_purge_delay`: its place in `mi_option_t` (mimalloc 3,
/// `include/mimalloc.h`), which the Rust bindings do not name.
const MI_OPTION_PURGE_DELAY: libmimalloc_sys::mi_option_t = 15;

/// mimalloc's default purge delay, in milliseconds (`src/options.c`).
const MI_DEFAULT_PURGE_DELAY: std::os::raw::c_long = 1000;

/// Keeps mimalloc from giving memory back to the OS as the process ends (it does so
/// for every freed page at exit, and the OS takes it all anyway). On `plcc check` of
/// a 117k-line program that was 270 `madvise` calls in its last 25 ms, about 6% of
/// its time (BENCHMARKS.md). While a command runs, freed pages go back after
/// mimalloc's delay as usual, which keeps the peak of long builds down. A delay set
/// with `MIMALLOC_PURGE_DELAY` is left as it is (unless it is the default, 1000).
fn skip_purge_at_exit() {
    // SAFETY: reading and setting an option of the allocator; both are plain loads
    // and stores of an integer, safe at any time.
    unsafe {
        if libmimalloc_sys::mi_option_get(MI_OPTION_PURGE_DELAY) == MI_DEFAULT_PURGE_DELAY {
            libmimalloc_sys::mi_option_set(MI_OPTION_PURGE_DELAY, -1);
        }
    }
}

#[derive(Parser)]
#[command(
    name = "plcc",
    version,
    about = "A compiler for PLC programs: IEC 61131-3 Structured Text, Instruction List and ladder diagrams (PLCopen XML), PLC-UD STL",
    args_conflicts_with_subcommands = true,
    after_help = "Examples:\n  plcc run examples/traffic_light.st --scans 100 --cycle-ms 100\n  plcc test prog.st --scenario prog.expect --target interp\n  plcc --emit ir prog.st\n  plcc --emit il motor.xml      (the IL of a ladder diagram; --emit ld-text draws it)\n  plcc --target host prog.st -o prog.o\n  plcc iec2c -f -l -p prog.st   (matiec's iec2c: the C target's files here; docs/c.md)"
)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
    #[command(flatten)]
    build: BuildArgs,
}

/// Shared options of every command that compiles.
#[derive(Args, Clone)]
struct Common {
    /// Source files (.st, .il, .stl, .xml; the language comes from the extension or --lang)
    files: Vec<PathBuf>,
    /// A library file, in any language plcc reads: its POUs and types are declared
    /// for the other files (e.g. stubs of a vendor's blocks); its PROGRAMs run only
    /// when named by --program or a configuration. Repeatable.
    #[arg(long = "lib", value_name = "FILE")]
    lib: Vec<PathBuf>,
    /// The language of all files: st, il, stl, xml
    #[arg(long)]
    lang: Option<String>,
    /// The dialect: iec (default) or codesys (POINTER TO, ADR and pointer
    /// arithmetic, VAR_INPUT CONSTANT, implicit conversions between bit strings and
    /// numbers)
    #[arg(long)]
    dialect: Option<String>,
    /// PLCopen XML: whose meaning diagrams get where the standard and the editors
    /// differ: iec (default), xml2st (OpenPLC Editor v4), openplc3, beremiz
    #[arg(long = "plcopen-order")]
    plcopen_order: Option<String>,
    /// PLCopen XML: the ladder editor's style rules (open and short circuits, upper
    /// parallel branches, bridges, coils on the left rail) are errors, not warnings
    #[arg(long = "strict-rungs")]
    strict_rungs: bool,
    /// Sequential function charts: how they evolve: iec (default), matiec (OpenPLC,
    /// Beremiz), codesys
    #[arg(long)]
    sfc: Option<String>,
}

impl Common {
    /// The files and how to read them, as the commands take them.
    fn inputs(self) -> commands::Inputs {
        commands::Inputs {
            files: self.files,
            library: self.lib,
            lang: self.lang,
            dialect: self.dialect,
            plcopen: commands::PlcopenFlags::new(self.plcopen_order, self.strict_rungs)
                .with_sfc(self.sfc),
        }
    }
}

#[derive(Args)]
struct BuildArgs {
    #[command(flatten)]
    common: Common,
    #[arg(long, default_value = "host", help = plcc::targets::build_help())]
    target: String,
    /// Output file (default: the first input with the target's extension; `-` for
    /// standard output)
    #[arg(short, long)]
    output: Option<PathBuf>,
    /// What to produce: ir (optimised IR), ir-raw (unoptimised), st (any build printed
    /// as Structured Text: IL, STL, PLCopen diagrams, charts), plcopen (ST and IL
    /// files as one PLCopen XML project), il (a PLCopen file's view, IL bodies kept),
    /// ld-text (the diagrams drawn in ASCII), sfc-text (sequential function
    /// charts drawn as text), or a target output (host: obj,
    /// header; pic16f876a: asm, hex; vmasm: xcp, asm; c: c, headers)
    #[arg(long)]
    emit: Option<String>,
    /// PROGRAMs to instantiate (default: all)
    #[arg(long)]
    program: Vec<String>,
    /// A target setting KEY=VALUE (pic16f876a: pin.%IX0.0=RA2; vmasm: mode=16|32|32a,
    /// cycle=MS; host: triple=...; c: cc=PATH)
    #[arg(short = 's', long = "set", value_parser = parse_setting)]
    set: Vec<(String, String)>,
}

fn parse_setting(s: &str) -> Result<(String, String), String> {
    s.split_once('=')
        .map(|(k, v)| (k.trim().to_string(), v.trim().to_string()))
        .ok_or_else(|| format!("`{s}` is not KEY=VALUE"))
}

#[derive(Subcommand)]
enum Command {
    /// Run a program scan by scan and print its variables
    Run {
        #[command(flatten)]
        common: Common,
        #[arg(long, default_value = "host", help = plcc::targets::run_help())]
        target: String,
        /// The PROGRAM to run (needed when the files have several)
        #[arg(long)]
        program: Option<String>,
        /// Number of scans
        #[arg(long, default_value_t = 1)]
        scans: u64,
        /// Cycle time in milliseconds, e.g. 10 or 0.5 (scan k, from 0, runs with the
        /// clock at k * cycle); default: the greatest common divisor of the
        /// configuration's task intervals, else 10
        #[arg(long, value_parser = plcc::scenario::parse_ms)]
        cycle_ms: Option<u64>,
        /// Print the time the scans took (cold start and compilation excluded)
        #[arg(long)]
        timing: bool,
        /// A target setting KEY=VALUE (host: tier=auto|full|quick|swap-at-N, opt_level,
        /// regalloc, threads; vmasm: mode=16|32|32a; pic16f876a: pin.%IX0.0=RA2;
        /// c: sanitize=undefined, opt=0..3, cc=PATH)
        #[arg(short = 's', long = "set", value_parser = parse_setting)]
        set: Vec<(String, String)>,
    },
    /// Run a scenario (corpus-expect v1) and check its expectations
    Test {
        #[command(flatten)]
        common: Common,
        /// The scenario file
        #[arg(long)]
        scenario: PathBuf,
        #[arg(long, default_value = "host", help = plcc::targets::run_help())]
        target: String,
        /// Clock step of `run N` in milliseconds, e.g. 10 or 0.5; default: the greatest
        /// common divisor of the configuration's task intervals, else 10
        #[arg(long, value_parser = plcc::scenario::parse_ms)]
        cycle_ms: Option<u64>,
        /// A target setting KEY=VALUE (host: tier=auto|full|quick|swap-at-N, opt_level,
        /// regalloc, threads; vmasm: mode=16|32|32a; pic16f876a: pin.%IX0.0=RA2;
        /// c: sanitize=undefined, opt=0..3, cc=PATH)
        #[arg(short = 's', long = "set", value_parser = parse_setting)]
        set: Vec<(String, String)>,
    },
    /// Run a program in real time as a soft PLC: its tasks (or every PROGRAM) scanned
    /// every cycle on a thread of its own, with absolute deadlines and the real clock
    /// (docs/serve.md). SIGINT or SIGTERM ends it after the scan in progress.
    Serve {
        #[command(flatten)]
        common: Common,
        #[arg(long, default_value = "host", help = plcc::targets::run_help())]
        target: String,
        /// The PROGRAM to run (default: every instance)
        #[arg(long)]
        program: Option<String>,
        /// Cycle time in milliseconds, e.g. 10 or 0.5; default: the greatest common
        /// divisor of the configuration's task intervals, else 10
        #[arg(long, value_parser = plcc::scenario::parse_ms)]
        cycle_ms: Option<u64>,
        /// A target setting KEY=VALUE
        #[arg(short = 's', long = "set", value_parser = parse_setting)]
        set: Vec<(String, String)>,
        /// Where the Modbus TCP server listens, IP:PORT (port 0: any free port), or
        /// none; default 127.0.0.1:5020
        #[arg(long, value_name = "ADDR:PORT")]
        modbus: Option<String>,
        /// Where the HTTP/JSON API listens, IP:PORT (port 0: any free port), or none;
        /// default 127.0.0.1:8021
        #[arg(long, value_name = "ADDR:PORT")]
        http: Option<String>,
        /// A file holding the bearer token that writes, forces and control calls of
        /// the API need; required to listen on an address other than loopback
        #[arg(long, value_name = "FILE")]
        token_file: Option<PathBuf>,
        /// Where the RETAIN and PERSISTENT variables are kept: read at start (if it
        /// exists), written atomically every --retain-every seconds while the PLC
        /// runs (when they changed) and at the end
        #[arg(long, value_name = "FILE")]
        retain: Option<PathBuf>,
        /// How often the RETAIN variables are saved to the --retain file while the
        /// PLC runs, in seconds (e.g. 10 or 0.5; 0: only at the end); default 10
        #[arg(long, value_name = "SECONDS", value_parser = plcc::serve::retain::parse_seconds, requires = "retain")]
        retain_every: Option<std::time::Duration>,
    },
    /// Check programs and print diagnostics only
    Check {
        #[command(flatten)]
        common: Common,
    },
    /// Run random programs on several machines and compare every variable after every scan
    Difftest {
        /// The first seed
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// How many programs (seeds seed, seed+1, ...)
        #[arg(long, default_value_t = 100)]
        count: u64,
        #[arg(long, help = plcc::targets::difftest_help())]
        targets: Option<String>,
        /// Scans per program (default 5; 10 with --lang sfc)
        #[arg(long)]
        scans: Option<u32>,
        /// Where to write the shrunk reproducers
        #[arg(long)]
        out: Option<PathBuf>,
        /// Print every program and its verdict
        #[arg(long)]
        show: bool,
        /// The language of the programs: st (random ST programs), oo (random ST
        /// programs that all have an object-oriented part: interfaces, function
        /// blocks with methods, inheritance), xml (random PLCopen projects with LD
        /// and FBD bodies) or sfc (random sequential function charts, each under the
        /// three --sfc profiles)
        #[arg(long, default_value = "st")]
        lang: String,
        /// With --lang xml or sfc: also generate the constructs of the front-end bugs known
        /// so far, which the generator otherwise steers around (TESTING.md)
        #[arg(long)]
        known_bugs: bool,
    },
    /// Print the VMASM listing of a CPDev code image (.xcp)
    Disasm {
        /// The code image
        xcp: PathBuf,
        /// Addressing mode: 16, 32 or 32a (default: from the .dcp beside the image, else 16)
        #[arg(long)]
        mode: Option<String>,
        /// The project description giving names (default: the .dcp beside the image)
        #[arg(long)]
        dcp: Option<PathBuf>,
    },
    /// Format Structured Text, Instruction List and STL: keywords and IL operators in
    /// upper case, blocks indented, the `:` of declarations aligned, comments and
    /// literals kept as written (docs/editors.md)
    Fmt {
        /// Files to format (`-` or none: standard input); the formatted text is
        /// printed unless --check or --write
        files: Vec<PathBuf>,
        /// Change nothing: name each file that would change, and exit with 1 if any
        #[arg(long, conflicts_with = "write")]
        check: bool,
        /// Rewrite the files that change, in place (atomically)
        #[arg(long)]
        write: bool,
        /// The language of all files: st, il or stl (default: from the extension,
        /// `.il` and `.stl`; standard input is ST)
        #[arg(long, value_parser = ["st", "il", "stl"])]
        lang: Option<String>,
    },
    /// Run a language server over standard input and output (LSP: diagnostics,
    /// outline, hover, go to definition, references, completion; docs/editors.md)
    Lsp,
    /// Explain a diagnostic code (e.g. E0301); without one, list every code
    Explain {
        /// The code
        code: Option<String>,
    },
}

fn main() -> ExitCode {
    // Output piped into `head` and the like ends when the reader has had enough, as
    // for other command-line tools: Rust ignores SIGPIPE, and a print to a closed
    // pipe would panic.
    #[cfg(unix)]
    // SAFETY: setting a signal's disposition to its default before any thread starts.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
    // matiec's command line: `plcc iec2c ...`, or plcc installed as `iec2c`.
    let args: Vec<String> = std::env::args_os()
        .map(|a| a.to_string_lossy().into_owned())
        .collect();
    let invoked = args.first().map(std::path::Path::new);
    if invoked
        .and_then(|p| p.file_stem())
        .is_some_and(|s| s == "iec2c")
    {
        return ExitCode::from(commands::iec2c(&args[0], &args[1..]));
    }
    if args.get(1).is_some_and(|a| a == "iec2c") {
        return ExitCode::from(commands::iec2c("plcc iec2c", &args[2..]));
    }
    let cli = Cli::parse();
    let status = match cli.command {
        Some(Command::Run {
            common,
            target,
            program,
            scans,
            cycle_ms,
            timing,
            set,
        }) => commands::run(&commands::RunArgs {
            inputs: common.inputs(),
            target,
            program,
            scans,
            cycle_us: cycle_ms,
            timing,
            settings: set,
        }),
        Some(Command::Test {
            common,
            scenario,
            target,
            cycle_ms,
            set,
        }) => commands::test(&commands::TestArgs {
            inputs: common.inputs(),
            scenario,
            target,
            cycle_us: cycle_ms,
            settings: set,
        }),
        Some(Command::Serve {
            common,
            target,
            program,
            cycle_ms,
            set,
            modbus,
            http,
            token_file,
            retain,
            retain_every,
        }) => plcc::serve::serve(&plcc::serve::ServeArgs {
            inputs: common.inputs(),
            target,
            program,
            cycle_us: cycle_ms,
            settings: set,
            modbus,
            http,
            token_file,
            retain,
            retain_every,
        }),
        Some(Command::Check { common }) => commands::check(&common.inputs()),
        Some(Command::Fmt {
            files,
            check,
            write,
            lang,
        }) => plcc::format::fmt(
            &files,
            lang.as_deref(),
            if check {
                plcc::format::FmtMode::Check
            } else if write {
                plcc::format::FmtMode::Write
            } else {
                plcc::format::FmtMode::Print
            },
        ),
        Some(Command::Lsp) => plcc::lsp::run(),
        Some(Command::Explain { code }) => commands::explain(code.as_deref()),
        Some(Command::Difftest {
            seed,
            count,
            targets,
            scans,
            out,
            show,
            lang,
            known_bugs,
        }) => commands::difftest(&commands::DifftestArgs {
            first: seed,
            count,
            machines: &targets.unwrap_or_else(|| plcc::targets::checked_machines().join(",")),
            scans: scans.unwrap_or(if lang == "sfc" { 10 } else { 5 }),
            out: out.as_deref(),
            show,
            lang: &lang,
            known_bugs,
        }),
        Some(Command::Disasm { xcp, mode, dcp }) => {
            commands::disasm(&xcp, mode.as_deref(), dcp.as_deref())
        }
        None => commands::compile(&commands::CompileArgs {
            inputs: cli.build.common.inputs(),
            target: cli.build.target,
            output: cli.build.output,
            emit: cli.build.emit,
            programs: cli.build.program,
            settings: cli.build.set,
        }),
    };
    skip_purge_at_exit();
    ExitCode::from(status)
}
