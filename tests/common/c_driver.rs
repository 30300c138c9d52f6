//! Checks of the `c` target's files outside the C machine: under other compilers (as
//! C++, the way OpenPLC compiles them, and under clang), and as an executable of
//! their own under the address sanitizer (which cannot be loaded into a running
//! process, so the machine cannot use it).

use plcc_c::names::Names;
use plcc_ir::interp::Interp;
use plcc_ir::machine::Machine;
use plcc_ir::value::PlcValue;
use plcc_ir::Module;
use std::path::{Path, PathBuf};
use std::process::Command;

/// Writes the module's file set and plcc's headers into `dir`; the names used and the
/// translation units (`<Config>.c` and each `<Res>.c`).
fn write_files(module: &Module, dir: &Path) -> Result<(Names, Vec<String>), String> {
    let files = plcc_c::files::generate(module).map_err(|d| format!("{d:?}"))?;
    let names = files.names.clone();
    let units = files.units.clone();
    for (n, t) in files.into_named() {
        std::fs::write(dir.join(n), t).map_err(|e| e.to_string())?;
    }
    for (n, t) in plcc_c::headers::all() {
        std::fs::write(dir.join(n), t).map_err(|e| e.to_string())?;
    }
    Ok((names, units))
}

/// A compiler the C must pass clean with `-Wall -Wextra -Werror`: a name for
/// messages, the command, the language (`c` or `c++`) and its standard.
pub struct Compiler {
    pub name: &'static str,
    pub command: &'static str,
    pub lang: &'static str,
    pub std: &'static str,
}

/// C++ (`-std=gnu++11`, as OpenPLC builds the files) under gcc and clang, and C99
/// under clang (the C machine builds every program as C99 with gcc).
pub const COMPILERS: [Compiler; 3] = [
    Compiler {
        name: "g++ -std=gnu++11",
        command: "g++",
        lang: "c++",
        std: "gnu++11",
    },
    Compiler {
        name: "clang -std=c99",
        command: "clang",
        lang: "c",
        std: "c99",
    },
    Compiler {
        name: "clang++ -std=gnu++11",
        command: "clang++",
        lang: "c++",
        std: "gnu++11",
    },
];

/// The system headers the files include, precompiled once per compiler: in C++
/// `<math.h>` alone takes most of a unit's time.
const SYSTEM_HEADERS: &str =
    "#include <stddef.h>\n#include <stdint.h>\n#include <string.h>\n#include <math.h>\n";

/// A program's file set written by [`write_programs`]: its directory and its
/// translation units (`<Config>.c` and each `<Res>.c`, which includes `POUS.c`).
pub struct Program {
    pub dir: PathBuf,
    pub units: Vec<String>,
}

/// Writes each module's file set and plcc's headers into a directory of its own
/// under `root` (`0/`, `1/`, ...), the files' quoted includes finding the headers
/// beside them; the programs, in order.
pub fn write_programs(modules: &[&Module], root: &Path) -> Result<Vec<Program>, String> {
    let mut programs = Vec::new();
    for (k, m) in modules.iter().enumerate() {
        let dir = root.join(k.to_string());
        std::fs::create_dir_all(&dir).map_err(|e| e.to_string())?;
        let (_, units) = write_files(m, &dir)?;
        programs.push(Program { dir, units });
    }
    Ok(programs)
}

/// Compiles the programs in `dirs` (from [`write_programs`]) with `c` without
/// generating code (`-fsyntax-only`), the system headers precompiled first into
/// `work` and many programs to one compiler process; the indexes of the programs
/// that fail, each with the compiler's output (or an error of the precompiling).
pub fn compile_programs(
    c: &Compiler,
    work: &Path,
    dirs: &[Program],
) -> Result<Vec<(usize, String)>, String> {
    let header = work.join("system.h");
    std::fs::create_dir_all(work).map_err(|e| e.to_string())?;
    std::fs::write(&header, SYSTEM_HEADERS).map_err(|e| e.to_string())?;
    // gcc finds `system.h.gch` beside `system.h`; clang is given its file.
    let gcc = c.command.starts_with('g');
    let pch = if gcc {
        work.join("system.h.gch")
    } else {
        work.join("system.pch")
    };
    let mut cmd = Command::new(c.command);
    cmd.arg("-x")
        .arg(format!("{}-header", c.lang))
        .arg(format!("-std={}", c.std))
        .arg(&header)
        .arg("-o")
        .arg(&pch);
    plcc_c::cc::run(cmd)?;
    let run = |chunk: &[usize]| {
        let mut cmd = Command::new(c.command);
        cmd.args(["-x", c.lang])
            .arg(format!("-std={}", c.std))
            .arg("-fsyntax-only")
            .args(plcc_c::cc::WARNINGS);
        if gcc {
            cmd.args(["-Winvalid-pch", "-include"]).arg(&header);
        } else {
            cmd.arg("-include-pch").arg(&pch);
        }
        for &k in chunk {
            for u in &dirs[k].units {
                cmd.arg(dirs[k].dir.join(u));
            }
        }
        plcc_c::cc::run(cmd)
    };
    let all: Vec<usize> = (0..dirs.len()).collect();
    let mut failed = Vec::new();
    for chunk in all.chunks(32) {
        if run(chunk).is_err() {
            // Again one by one, to tell which programs fail.
            for &k in chunk {
                if let Err(e) = run(&[k]) {
                    failed.push((k, e));
                }
            }
        }
    }
    Ok(failed)
}

/// Builds the module with a `main` of its own under the address and
/// undefined-behaviour sanitizers, runs cold start and `scans` scans of `cycle_us`,
/// and compares every variable (after cold start and after the last scan) and the
/// fault flag with the interpreter's. Returns the number of values compared.
pub fn agrees_under_asan(module: &Module, scans: u32, cycle_us: u64) -> Result<usize, String> {
    let dir = plcc_c::cc::TempDir::new().map_err(|e| e.to_string())?;
    let (names, units) = write_files(module, dir.path())?;
    std::fs::write(
        dir.path().join(plcc_c::harness::FILE),
        plcc_c::harness::source(module, &names),
    )
    .map_err(|e| e.to_string())?;
    let vars = plcc::scenario::all_variables(module);
    let mut show = String::new();
    for v in &vars {
        let p = names.value_expr(v);
        show.push_str(&format!(
            "    show(\"{}\", &{p}, sizeof {p});\n",
            v.path.replace('\\', "\\\\").replace('"', "\\\"")
        ));
    }
    let main = format!(
        "#include <stdio.h>\n#include \"iec_std_lib.h\"\n#include \"POUS.h\"\n\
         void plcc_cold_start(unsigned char fill);\nvoid plcc_scan(long sec, long nsec);\n\
         unsigned char *plcc_fault(void);\n\
         static void show(const char *path, const void *p, size_t n) {{\n\
         \x20   uint64_t v = 0;\n    memcpy(&v, p, n);\n    printf(\"%s %llx\\n\", path, (unsigned long long)v);\n}}\n\
         static void all(void) {{\n{show}}}\n\
         int main(void) {{\n    long long k;\n    plcc_cold_start(0xA5);\n    all();\n\
         \x20   for (k = 0; k < {scans}; k++) {{\n        long long us = k * {cycle_us}LL;\n\
         \x20       plcc_scan((long)(us / 1000000), (long)(us % 1000000 * 1000));\n    }}\n\
         \x20   all();\n    printf(\"fault %d\\n\", *plcc_fault());\n    return 0;\n}}\n"
    );
    std::fs::write(dir.path().join("main.c"), main).map_err(|e| e.to_string())?;
    let mut cmd = Command::new("cc");
    cmd.current_dir(dir.path())
        // No -g: the sanitizers' reports name the function without it, and debug
        // information makes every build slower (add it back to debug a finding).
        .args(["-std=c99", "-O0", "-ffp-contract=off", "-I."])
        .args(plcc_c::cc::WARNINGS)
        .args([
            "-fsanitize=address,undefined,float-cast-overflow",
            "-fno-sanitize-recover=all",
        ])
        .args(&units)
        .args([plcc_c::harness::FILE, "main.c"])
        .args(["-lm", "-o", "prog"]);
    plcc_c::cc::run(cmd)?;
    let out = Command::new(dir.path().join("prog"))
        .env("ASAN_OPTIONS", "detect_leaks=0")
        .output()
        .map_err(|e| e.to_string())?;
    if !out.status.success() {
        return Err(format!(
            "the sanitized program failed ({}):\n{}",
            out.status,
            String::from_utf8_lossy(&out.stderr)
        ));
    }
    let text = String::from_utf8_lossy(&out.stdout).into_owned();
    let mut lines = text.lines();

    let mut interp = Interp::new(module).map_err(|e| e.to_string())?;
    interp.cold_start().map_err(|e| e.to_string())?;
    let mut compared = 0;
    for round in 0..2 {
        if round == 1 {
            for k in 0..scans as i64 {
                interp.set_clock_us(k * cycle_us as i64);
                interp.scan().map_err(|e| e.to_string())?;
            }
        }
        for v in &vars {
            let line = lines.next().ok_or("the program printed too little")?;
            let (path, hex) = line.rsplit_once(' ').ok_or("a bad line")?;
            let bits = u64::from_str_radix(hex, 16).map_err(|e| e.to_string())?;
            let c = PlcValue::from_bits(v.elem, bits);
            let i = interp.read(&v.path).map_err(|e| e.to_string())?;
            if path != v.path || !c.same(i) {
                return Err(format!(
                    "{} after {}: c {c}, interp {i}",
                    v.path,
                    if round == 0 {
                        "cold start"
                    } else {
                        "the scans"
                    }
                ));
            }
            compared += 1;
        }
    }
    let fault = lines.next().ok_or("no fault line")?;
    if fault != format!("fault {}", interp.fault() as u8) {
        return Err(format!("{fault}, the interpreter's {}", interp.fault()));
    }
    Ok(compared)
}

/// A `main` for the ATmega2560 (OpenPLC's Arduino Mega): the runtime's clock and
/// debug switch, cold start, then a scan every 10 ms of the clock, forever.
pub const AVR_MAIN: &str = "#include \"iec_std_lib.h\"\n\
TIME __CURRENT_TIME;\nBOOL __DEBUG;\n\
void config_init__(void);\nvoid config_run__(unsigned long tick);\n\
int main(void) {\n    unsigned long tick = 0;\n    config_init__();\n    for (;;) {\n\
\x20       __CURRENT_TIME.tv_nsec += 10000000;\n\
\x20       if (__CURRENT_TIME.tv_nsec >= 1000000000) {\n\
\x20           __CURRENT_TIME.tv_nsec -= 1000000000;\n\
\x20           __CURRENT_TIME.tv_sec += 1;\n        }\n\
\x20       config_run__(tick++);\n    }\n}\n";

/// The located variables' storage and the pointers to it, as a runtime defines them
/// from the program's `LOCATED_VARIABLES.h` (OpenPLC's glue does the same): a unit of
/// each AVR build.
const AVR_LOCATED: &str = "#include \"iec_std_lib.h\"\n\
#define __LOCATED_VAR(type, name, ...) type __##name;\n\
#include \"LOCATED_VARIABLES.h\"\n#undef __LOCATED_VAR\n\
#define __LOCATED_VAR(type, name, ...) type *name = &__##name;\n\
#include \"LOCATED_VARIABLES.h\"\n#undef __LOCATED_VAR\n\
typedef int avr_located_unit_is_never_empty;\n";

/// avr-gcc's flags: the Arduino Mega's chip, for size, unused sections dropped (as
/// the Arduino tools build), C99 with every warning an error.
pub const AVR_FLAGS: [&str; 9] = [
    "-mmcu=atmega2560",
    "-Os",
    "-std=c99",
    "-ffunction-sections",
    "-fdata-sections",
    "-Wl,--gc-sections",
    "-Wall",
    "-Wextra",
    "-Werror",
];

/// The ATmega2560's RAM and flash, in bytes.
const AVR_RAM: u64 = 8192;
const AVR_FLASH: u64 = 262_144;

/// What a program's C is on the ATmega2560.
#[derive(Debug)]
pub enum Avr {
    /// It builds: flash (`.text` + `.data`) and RAM (`.data` + `.bss`) in bytes.
    Fits { flash: u64, ram: u64 },
    /// It does not fit the chip, and why.
    DoesNotFit(String),
}

/// The `.text`, `.data` and `.bss` sizes of an ELF file (`avr-size -A`).
fn avr_sections(elf: &Path) -> Result<(u64, u64, u64), String> {
    let out = Command::new("avr-size")
        .arg("-A")
        .arg(elf)
        .output()
        .map_err(|e| format!("avr-size: {e}"))?;
    let text = String::from_utf8_lossy(&out.stdout);
    let size = |name: &str| {
        text.lines()
            .find_map(|l| {
                let mut w = l.split_whitespace();
                (w.next() == Some(name)).then(|| w.next()?.parse::<u64>().ok())?
            })
            .unwrap_or(0)
    };
    Ok((size(".text"), size(".data"), size(".bss")))
}

/// Builds the program in `dir` (from [`write_programs`]) for the ATmega2560 with
/// avr-gcc, linked with [`AVR_MAIN`] (already compiled: `main_o`). A program that
/// does not fit is one the linker refuses for the chip's 8 KB of RAM or 256 KB of
/// flash (measured again with room enough), or one with LREALs (avr-gcc's double
/// has 32 bits: plcc's C stops on it). Any other error is the compiler's output.
pub fn avr_build(program: &Program, main_o: &Path) -> Result<Avr, String> {
    let dir = &program.dir;
    let elf = dir.join("avr.elf");
    std::fs::write(dir.join("avr_located.c"), AVR_LOCATED).map_err(|e| e.to_string())?;
    let link = |extra: &[&str]| {
        let mut cmd = Command::new("avr-gcc");
        cmd.current_dir(dir)
            .args(AVR_FLAGS)
            .args(&program.units)
            .arg("avr_located.c")
            .arg(main_o)
            .arg("-o")
            .arg(&elf)
            .arg("-lm")
            .args(extra);
        plcc_c::cc::run(cmd)
    };
    let judge = |text: u64, data: u64, bss: u64| {
        let (flash, ram) = (text + data, data + bss);
        if ram > AVR_RAM {
            Avr::DoesNotFit(format!(
                "RAM: needs {ram} bytes (.data + .bss); the ATmega2560 has {AVR_RAM}"
            ))
        } else if flash > AVR_FLASH {
            Avr::DoesNotFit(format!(
                "flash: needs {flash} bytes; the ATmega2560 has {AVR_FLASH}"
            ))
        } else {
            Avr::Fits { flash, ram }
        }
    };
    match link(&[]) {
        Ok(()) => {
            let (text, data, bss) = avr_sections(&elf)?;
            Ok(judge(text, data, bss))
        }
        Err(e) if e.contains("__plcc_lreal_needs_a_64_bit_double") => Ok(Avr::DoesNotFit(
            "LREAL: avr-gcc's double has 32 bits".into(),
        )),
        Err(e) if e.contains("size of array") && e.contains("is too large") => Ok(Avr::DoesNotFit(
            "RAM: an array of more than 32767 bytes, avr-gcc's largest object".into(),
        )),
        Err(e) if e.contains("not within region `data'") || e.contains("region `text'") => {
            link(&[
                "-Wl,--defsym=__DATA_REGION_LENGTH__=0xfe00",
                "-Wl,--defsym=__TEXT_REGION_LENGTH__=0x1000000",
            ])
            .map_err(|e2| format!("{e}\n(measured with room enough: {e2})"))?;
            let (text, data, bss) = avr_sections(&elf)?;
            match judge(text, data, bss) {
                Avr::Fits { .. } => Err(format!("{e}\n(but it fits with room enough)")),
                unfit => Ok(unfit),
            }
        }
        Err(e) => Err(e),
    }
}

/// Compiles [`AVR_MAIN`] into `dir` with plcc's headers there (they do not depend on
/// the program); the object's path.
pub fn avr_main(dir: &Path) -> Result<PathBuf, String> {
    std::fs::create_dir_all(dir).map_err(|e| e.to_string())?;
    for (n, t) in plcc_c::headers::all() {
        std::fs::write(dir.join(n), t).map_err(|e| e.to_string())?;
    }
    std::fs::write(dir.join("avr_main.c"), AVR_MAIN).map_err(|e| e.to_string())?;
    let mut cmd = Command::new("avr-gcc");
    cmd.current_dir(dir)
        .args(AVR_FLAGS)
        .args(["-c", "avr_main.c", "-o", "avr_main.o"]);
    plcc_c::cc::run(cmd)?;
    Ok(dir.join("avr_main.o"))
}
