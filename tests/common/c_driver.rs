//! Checks of the `c` target's files outside the C machine: as C++ (the way OpenPLC
//! compiles them), and as an executable of their own under the address sanitizer
//! (which cannot be loaded into a running process, so the machine cannot use it).

use plcc_c::names::Names;
use plcc_ir::interp::Interp;
use plcc_ir::machine::Machine;
use plcc_ir::value::PlcValue;
use plcc_ir::vars::{variables, VarRef};
use plcc_ir::{ElemType, Module};
use std::path::Path;
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

/// `<Config>.c` and every `<Res>.c` compile as C++ (`g++ -std=gnu++11`, as OpenPLC
/// builds them) with `-Wall -Wextra -Werror`.
pub fn compiles_as_cpp(module: &Module) -> Result<(), String> {
    let dir = plcc_c::cc::TempDir::new().map_err(|e| e.to_string())?;
    let (_, units) = write_files(module, dir.path())?;
    for unit in &units {
        let mut cmd = Command::new("g++");
        cmd.current_dir(dir.path())
            .args(["-std=gnu++11", "-x", "c++", "-fsyntax-only", "-I."])
            .args(plcc_c::cc::WARNINGS)
            .arg(unit);
        plcc_c::cc::run(cmd)?;
    }
    Ok(())
}

/// Every elementary variable of the programs and the globals.
fn all_vars(m: &Module) -> Vec<VarRef> {
    let mut v: Vec<VarRef> = m
        .programs
        .iter()
        .flat_map(|e| variables(m, e.data))
        .collect();
    if let Some(g) = m.data_by_name(plcc_frontend::GLOBALS_DATA) {
        v.extend(variables(m, g));
    }
    v
}

fn same(a: PlcValue, b: PlcValue) -> bool {
    match a.ty {
        ElemType::Real | ElemType::LReal if a.as_f64().is_nan() => b.as_f64().is_nan(),
        _ => a.ty == b.ty && a.bits == b.bits,
    }
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
    let vars = all_vars(module);
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
        .args(["-std=c99", "-O0", "-g", "-ffp-contract=off", "-I."])
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
            if path != v.path || !same(c, i) {
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
