//! The file set `iec2c` writes, with matiec's names and layouts: `POUS.h` (types,
//! variables, prototypes), `POUS.c` (every function, no `#include`: `Res0.c` includes
//! it), `Config0.c` (the globals, `config_init__`, `config_run__`,
//! `common_ticktime__`, `greatest_tick_count__`, the runtime context), `Config0.h`
//! and `Res0.c` (the program instances, `RES0_init__`, `RES0_run__`).
//!
//! Not yet written: `LOCATED_VARIABLES.h` and `VARIABLES.csv`, and the `__IEC_<T>_t`
//! and `__IEC_<T>_p` wrappers of matiec's variables (fields hold plain values; located
//! variables are fields too, not pointers into the runtime's I/O). Without those two
//! files a runtime's build stops at once rather than running with its I/O unbound.

use crate::body;
use crate::decls;
use crate::names::{ident, FuncForm, Names, CONFIG, RESOURCE};
use plcc_ir::diag::Diagnostic;
use plcc_ir::module::DataKind;
use plcc_ir::passes::{legalize, ranges};
use plcc_ir::{FuncId, Module, Type};
use std::fmt::Write;

/// The generated files.
#[derive(Clone, Debug)]
pub struct Files {
    /// `POUS.h`.
    pub pous_h: String,
    /// `POUS.c`.
    pub pous_c: String,
    /// `Config0.c`.
    pub config_c: String,
    /// `Config0.h`.
    pub config_h: String,
    /// `Res0.c`.
    pub res_c: String,
    /// The names everything got (the machine's harness needs them).
    pub names: Names,
}

impl Files {
    /// The files by name, in the order `iec2c` prints them.
    pub fn into_named(self) -> Vec<(String, String)> {
        vec![
            ("POUS.c".into(), self.pous_c),
            ("POUS.h".into(), self.pous_h),
            (format!("{CONFIG}.c"), self.config_c),
            (format!("{CONFIG}.h"), self.config_h),
            (format!("{RESOURCE}.c"), self.res_c),
        ]
    }

    /// The file names, in that order.
    pub fn file_names() -> [String; 5] {
        [
            "POUS.c".into(),
            "POUS.h".into(),
            format!("{CONFIG}.c"),
            format!("{CONFIG}.h"),
            format!("{RESOURCE}.c"),
        ]
    }
}

/// Checks what the scan needs of the module: program bodies and inits take the
/// instance, `init_globals` takes nothing, and everything named exists.
fn check_entries(module: &Module) -> Result<(), Vec<Diagnostic>> {
    let bad = |what: String| {
        vec![Diagnostic::error_nowhere(
            crate::codes::E_MALFORMED_IR,
            what,
        )]
    };
    let nf = module.funcs.len();
    for p in &module.programs {
        if p.body.index() >= nf || p.init.index() >= nf || p.data.index() >= module.data.len() {
            return Err(bad(format!(
                "program `{}` names a missing function or data object",
                p.name
            )));
        }
        for id in [p.body, p.init] {
            let f = module.func(id);
            if f.params != [Type::Ptr] || f.ret.is_some() {
                return Err(bad(format!(
                    "function `{}` of program `{}` does not take just the instance",
                    f.name, p.name
                )));
            }
        }
    }
    if let Some(g) = module.init_globals {
        match module.funcs.get(g.index()) {
            Some(f) if f.params.is_empty() && f.ret.is_none() => {}
            _ => return Err(bad("`init_globals` is missing or takes arguments".into())),
        }
    }
    Ok(())
}

/// The greatest common divisor.
fn gcd(a: u64, b: u64) -> u64 {
    if b == 0 {
        a
    } else {
        gcd(b, a % b)
    }
}

/// `greatest_tick_count__`: the largest multiple of the least common multiple of the
/// task periods (in ticks) that fits 32 bits, or 0 when every task runs every tick
/// (matiec's rule, computed exactly).
fn greatest_tick_count(module: &Module, tick_us: u64) -> u64 {
    let mut lcm: u64 = 1;
    for p in module.programs.iter().filter_map(|p| p.interval_us) {
        if p == 0 {
            continue;
        }
        let k = p / tick_us;
        lcm = lcm / gcd(lcm, k) * k;
        if lcm > u32::MAX as u64 {
            return 0;
        }
    }
    if lcm <= 1 {
        0
    } else {
        (u32::MAX as u64 / lcm) * lcm
    }
}

/// Writes the files for `module`. On a copy of the module, the checks that value
/// ranges show cannot fail go (`passes::ranges`: the bounds checks of loops whose
/// index stays in its array, which a C compiler cannot remove, not knowing that the
/// index's arithmetic does not wrap), and the module is legalized for C.
pub fn generate(module: &Module) -> Result<Files, Vec<Diagnostic>> {
    check_entries(module)?;
    let mut m = module.clone();
    for f in &mut m.funcs {
        ranges::run(f);
    }
    legalize::run(&mut m, &legalize::Defines::NONE);
    debug_assert!(
        plcc_ir::verify::verify_module(&m).is_ok(),
        "ranges and legalize left a module that does not verify: {:?}",
        plcc_ir::verify::verify_module(&m).err()
    );
    let module = &m;
    let names = Names::new(module);
    let pous_h = decls::pous_h(module, &names);
    let mut pous_c = String::from(
        "/* POUS.c: the program's functions (written by plcc; included by the resource's file). */\n\n",
    );
    for k in 0..module.funcs.len() {
        pous_c.push_str(&body::function(module, &names, FuncId::new(k)));
        pous_c.push('\n');
    }
    let res = ident(RESOURCE);
    let tick_us = module.task_tick_us().unwrap_or(10_000);

    // Config0.c
    let mut c = String::new();
    c.push_str("/* Config0.c: the configuration (written by plcc). */\n\n");
    c.push_str("#include \"iec_std_lib.h\"\n#include \"accessor.h\"\n#include \"POUS.h\"\n\n");
    let _ = writeln!(
        c,
        "/* The common tick of the tasks, in ns. */\nunsigned long long common_ticktime__ = {}ULL * 1ULL;",
        tick_us * 1000
    );
    let _ = writeln!(
        c,
        "unsigned long greatest_tick_count__ = (unsigned long){}UL;\n",
        greatest_tick_count(module, tick_us)
    );
    c.push_str("__plcc_rt_t __plcc_rt;\n\n");
    for (k, d) in module.data.iter().enumerate() {
        if d.kind != DataKind::Program {
            let _ = writeln!(c, "{} {};", decls::mem_type(&names, d.ty), names.data[k]);
        }
    }
    let _ = writeln!(
        c,
        "\nvoid {res}_init__(void);\nvoid {res}_run__(unsigned long tick);\n"
    );
    c.push_str("void config_init__(void) {\n");
    c.push_str(
        "    __plcc_rt.clock_ms = 0;\n    __plcc_rt.clock_ns = 0;\n    __plcc_rt.fault = 0;\n",
    );
    if let Some(g) = module.init_globals {
        let _ = writeln!(c, "    {}();", names.funcs[g.index()]);
    }
    let _ = writeln!(c, "    {res}_init__();\n}}\n");
    c.push_str("void config_run__(unsigned long tick) {\n");
    c.push_str("    /* The clock, sampled once for the scan. */\n");
    c.push_str("    uint64_t sec = (uint64_t)__CURRENT_TIME.tv_sec;\n");
    c.push_str("    uint64_t nsec = (uint64_t)__CURRENT_TIME.tv_nsec;\n");
    c.push_str("    __plcc_rt.clock_ms = (int32_t)(uint32_t)(sec * 1000u + nsec / 1000000u);\n");
    c.push_str("    __plcc_rt.clock_ns = (int64_t)(sec * 1000000000u + nsec);\n");
    let _ = writeln!(c, "    {res}_run__(tick);\n}}");

    // Res0.c: line 7 stays blank (a runtime may put an #include there).
    let mut r = String::new();
    r.push_str("/* Res0.c: the resource: its program instances and their scan.\n");
    r.push_str(" * Written by plcc.\n");
    r.push_str(" * Tasks are scheduled by the programs' code from the clock.\n");
    r.push_str(" */\n\n");
    r.push_str("#include \"iec_std_lib.h\"\n\n");
    r.push_str("extern unsigned long long common_ticktime__;\n\n");
    let _ = writeln!(
        r,
        "#include \"accessor.h\"\n#include \"POUS.h\"\n\n#include \"{CONFIG}.h\"\n\n#include \"POUS.c\"\n"
    );
    for (k, d) in module.data.iter().enumerate() {
        if d.kind == DataKind::Program {
            let _ = writeln!(r, "{} {};", decls::mem_type(&names, d.ty), names.data[k]);
        }
    }
    let _ = writeln!(
        r,
        "\nvoid {res}_init__(void) {{\n    BOOL retain = 0;\n    (void)retain;"
    );
    for p in &module.programs {
        let _ = writeln!(
            r,
            "    {};",
            entry_call(&names, p.init, &names.data[p.data.index()])
        );
    }
    r.push_str("}\n\n");
    let _ = writeln!(
        r,
        "void {res}_run__(unsigned long tick) {{\n    (void)tick;"
    );
    for p in &module.programs {
        let _ = writeln!(
            r,
            "    {};",
            entry_call(&names, p.body, &names.data[p.data.index()])
        );
    }
    r.push_str("}\n");

    Ok(Files {
        pous_h,
        pous_c,
        config_c: c,
        config_h: "\n".into(),
        res_c: r,
        names,
    })
}

/// The call of a program's body or init on its instance `data`.
fn entry_call(names: &Names, f: FuncId, data: &str) -> String {
    let name = &names.funcs[f.index()];
    match names.forms[f.index()] {
        FuncForm::Body(_) => format!("{name}(&{data})"),
        FuncForm::Init(_) => format!("{name}(&{data}, retain)"),
        FuncForm::Plain => format!("{name}((unsigned char *)&{data})"),
    }
}
