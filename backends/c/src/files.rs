//! The file set `iec2c` writes, with matiec's names and layouts: `POUS.h` (types,
//! variables, prototypes), `POUS.c` (every function, no `#include`: the first
//! resource's file includes it), `LOCATED_VARIABLES.h` (one line per located address,
//! see [`located`](crate::located)), `VARIABLES.csv` (the debuggers' list, see
//! [`variables`]), `<Config>.c` (the configuration's globals, their
//! accessors, `config_init__`, `config_run__`, `common_ticktime__`,
//! `greatest_tick_count__`, the runtime context), `<Config>.h` (the accessors'
//! prototypes) and one `<Res>.c` per resource (its globals, its program instances,
//! `<RES>_init__`, `<RES>_run__`). The names are the configuration's and resources'
//! as spelled (`Config0` and `Res0` when the source has no configuration).

use crate::body;
use crate::decls;
use crate::names::{ident, FuncForm, Names};
use crate::repr::Repr;
use crate::variables;
use plcc_ir::diag::Diagnostic;
use plcc_ir::module::{AggDef, DataKind};
use plcc_ir::passes::{inline, legalize, ranges};
use plcc_ir::types::MemType;
use plcc_ir::{FuncId, InstData, Module, Type};
use std::fmt::Write;

/// The generated files.
#[derive(Clone, Debug)]
pub struct Files {
    /// Every file, by name, in the order `iec2c` prints them: `POUS.c`, `POUS.h`,
    /// `LOCATED_VARIABLES.h`, `VARIABLES.csv`, `<Config>.c`, `<Config>.h`, then each
    /// `<Res>.c`.
    pub files: Vec<(String, String)>,
    /// The translation units a runtime compiles: `<Config>.c` and each `<Res>.c`.
    pub units: Vec<String>,
    /// The names everything got (the machine's harness needs them).
    pub names: Names,
}

impl Files {
    /// The files by name, in the order `iec2c` prints them.
    pub fn into_named(self) -> Vec<(String, String)> {
        self.files
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
    if let Some(g) = module.globals {
        match module.data.get(g.index()).map(|d| d.ty) {
            Some(MemType::Agg(a))
                if matches!(module.aggs.get(a.index()), Some(AggDef::Struct(_))) => {}
            _ => {
                return Err(bad(
                    "the globals' data object is missing or not a struct".into()
                ))
            }
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

/// Inlines every call that passes the globals' address (or a value that holds only
/// it): in C each global is a variable of its own, so the address is never a value,
/// and a callee's `field_addr`s on it must see where it comes from.
fn inline_globals_address(m: &mut Module, names: &Names) -> Result<(), Vec<Diagnostic>> {
    if names.globals_data.is_none() {
        return Ok(());
    }
    // Each inlining removes one call; the call graph is acyclic, so this ends.
    let mut budget = 10_000usize;
    for k in 0..m.funcs.len() {
        loop {
            let func = &m.funcs[k];
            let split = body::globals_values(names, func);
            let site = func.inst_iter().find_map(|(b, i)| match func.inst(i) {
                InstData::Call { func: callee, args } if args.iter().any(|a| split[a.index()]) => {
                    Some((b, i, *callee))
                }
                _ => None,
            });
            let Some((b, i, callee)) = site else { break };
            if callee.index() == k || budget == 0 {
                return Err(vec![Diagnostic::error_nowhere(
                    crate::codes::E_MALFORMED_IR,
                    format!(
                        "function `{}` passes the globals' address to a call that cannot be inlined",
                        m.funcs[k].name
                    ),
                )]);
            }
            budget -= 1;
            let callee = m.funcs[callee.index()].clone();
            inline::inline_call(&mut m.funcs[k], b, i, &callee);
        }
    }
    Ok(())
}

/// True if the program entries run resource after resource, in the resources'
/// order: then `config_run__` can run each resource's `<RES>_run__` in turn and keep
/// plcc's order (priority first, across resources).
fn grouped(names: &Names) -> bool {
    names.program_resource.windows(2).all(|w| w[0] <= w[1])
}

/// Writes the files for `module`. On a copy of the module, the checks that value
/// ranges show cannot fail go (`passes::ranges`: the bounds checks of loops whose
/// index stays in its array, which a C compiler cannot remove, not knowing that the
/// index's arithmetic does not wrap), and the module is legalized for C.
pub fn generate(module: &Module) -> Result<Files, Vec<Diagnostic>> {
    check_entries(module)?;
    // The verifier rejects recursion (IEC forbids it); the runtimes' C does not
    // expect it either.
    if let Some(cycle) = plcc_ir::analysis::find_recursion(module) {
        return Err(vec![Diagnostic::error_nowhere(
            crate::codes::E_MALFORMED_IR,
            format!(
                "recursion ({}, directly or through a table): the c target is given verified IR, which has none",
                plcc_ir::analysis::describe_cycle(module, &cycle)
            ),
        )]);
    }
    let mut m = module.clone();
    let names = Names::new(&m)?;
    inline_globals_address(&mut m, &names)?;
    ranges::run_module(&mut m);
    legalize::run(&mut m, &legalize::Defines::NONE);
    debug_assert!(
        plcc_ir::verify::verify_module(&m).is_ok(),
        "ranges and legalize left a module that does not verify: {:?}",
        plcc_ir::verify::verify_module(&m).err()
    );
    let module = &m;
    let pous_h = decls::pous_h(module, &names);
    let mut pous_c = String::from(
        "/* POUS.c: the program's functions (written by plcc; included by the resource's file). */\n\n",
    );
    for k in 0..module.funcs.len() {
        pous_c.push_str(&body::function(module, &names, FuncId::new(k))?);
        pous_c.push('\n');
    }
    let tick_us = module.task_tick_us().unwrap_or(10_000);
    let mut located_h = String::new();
    for l in &names.repr.located {
        located_h.push_str(&l.line());
        located_h.push('\n');
    }
    let config = &names.config;
    let mut files = vec![
        ("POUS.c".to_string(), pous_c),
        ("POUS.h".to_string(), pous_h),
        ("LOCATED_VARIABLES.h".to_string(), located_h),
        (
            "VARIABLES.csv".to_string(),
            variables::csv(module, &names, tick_us * 1000),
        ),
        (format!("{config}.c"), config_c(module, &names, tick_us)),
        (format!("{config}.h"), config_h(module, &names)),
    ];
    let mut units = vec![format!("{config}.c")];
    for r in 0..names.resources.len() {
        let file = format!("{}.c", names.resources[r].file);
        files.push((file.clone(), res_c(module, &names, r)));
        units.push(file);
    }
    Ok(Files {
        files,
        units,
        names,
    })
}

/// The C type a global's accessors take and give (`INT`, `TON`).
fn accessor_type(module: &Module, names: &Names, g: usize) -> String {
    let Some(AggDef::Struct(s)) = globals_struct(module, names) else {
        return String::new();
    };
    match (names.global_repr(module, g), s.fields[g].ty) {
        (Repr::Var(t), _) => t.to_string(),
        (Repr::Located(i), _) => names.repr.located[i].ty.to_string(),
        (_, t) => decls::mem_type(names, t),
    }
}

/// The struct of the globals.
fn globals_struct<'m>(module: &'m Module, names: &Names) -> Option<&'m AggDef> {
    match module.data[names.globals_data?.index()].ty {
        MemType::Agg(a) => Some(module.agg(a)),
        MemType::Scalar(_) => None,
    }
}

/// The definitions of the globals of a scope (`None`: the configuration's; else a
/// resource's), with matiec's accessors `__GET_GLOBAL_<G>`, `__IS_GLOBAL_<G>_FORCED`
/// and `__INIT_GLOBAL_<G>`.
fn globals(module: &Module, names: &Names, scope: Option<usize>) -> String {
    let mut s = String::new();
    let Some(AggDef::Struct(st)) = globals_struct(module, names) else {
        return s;
    };
    for (g, f) in st.fields.iter().enumerate() {
        if names.global_scope[g] != scope {
            continue;
        }
        let var = &names.globals[g];
        let repr = names.global_repr(module, g);
        let t = accessor_type(module, names, g);
        let short = ident(&f.name);
        let _ = writeln!(s, "{};", decls::member_decl(names, repr, f.ty, f.elem, var));
        let (get, init) = match repr {
            Repr::Var(_) | Repr::AggVar => (
                format!("&({var}.value)"),
                Some(format!("{var}.value = value;")),
            ),
            Repr::Located(_) => (
                format!("{var}.value"),
                Some(format!("*({var}.value) = value;")),
            ),
            Repr::Plain => (format!("&{var}"), None),
        };
        let forced = match repr {
            Repr::Plain => "0".to_string(),
            _ => format!("(IEC_BYTE)({var}.flags & __IEC_FORCE_FLAG)"),
        };
        let _ = writeln!(
            s,
            "{} __GET_GLOBAL_{short}(void) {{\n    return {get};\n}}",
            decls::declare(&format!("{t} *"), "")
        );
        let _ = writeln!(
            s,
            "IEC_BYTE __IS_GLOBAL_{short}_FORCED(void) {{\n    return {forced};\n}}"
        );
        if let Some(init) = init {
            let _ = writeln!(
                s,
                "void __INIT_GLOBAL_{short}({}) {{\n    {init}\n}}",
                decls::declare(&t, "value")
            );
        }
        s.push('\n');
    }
    s
}

/// `<Config>.c`.
fn config_c(module: &Module, names: &Names, tick_us: u64) -> String {
    let mut c = String::new();
    let _ = writeln!(
        c,
        "/* {}.c: the configuration (written by plcc). */\n",
        names.config
    );
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
    c.push_str(&globals(module, names, None));
    for (k, d) in module.data.iter().enumerate() {
        if d.kind != DataKind::Program && !names.is_globals(plcc_ir::DataId::new(k)) {
            let _ = writeln!(c, "{} {};", decls::mem_type(names, d.ty), names.data[k]);
        }
    }
    c.push('\n');
    for r in &names.resources {
        let _ = writeln!(
            c,
            "void {0}_init__(void);\nvoid {0}_run__(unsigned long tick);",
            r.c
        );
    }
    c.push_str("\nvoid config_init__(void) {\n");
    c.push_str(
        "    __plcc_rt.clock_ms = 0;\n    __plcc_rt.clock_ns = 0;\n    __plcc_rt.fault = 0;\n",
    );
    c.push_str(&preps(module, names));
    if let Some(g) = module.init_globals {
        let _ = writeln!(c, "    {}();", names.funcs[g.index()]);
    }
    for r in &names.resources {
        let _ = writeln!(c, "    {}_init__();", r.c);
    }
    c.push_str("}\n\n");
    c.push_str("void config_run__(unsigned long tick) {\n");
    c.push_str("    /* The clock, sampled once for the scan. */\n");
    c.push_str("    uint64_t sec = (uint64_t)__CURRENT_TIME.tv_sec;\n");
    c.push_str("    uint64_t nsec = (uint64_t)__CURRENT_TIME.tv_nsec;\n");
    c.push_str("    __plcc_rt.clock_ms = (int32_t)(uint32_t)(sec * 1000u + nsec / 1000000u);\n");
    c.push_str("    __plcc_rt.clock_ns = (int64_t)(sec * 1000000000u + nsec);\n");
    if grouped(names) {
        for r in &names.resources {
            let _ = writeln!(c, "    {}_run__(tick);", r.c);
        }
    } else {
        // The resources' programs interleave in plcc's order (priority first).
        c.push_str("    (void)tick;\n");
        for p in &module.programs {
            let _ = writeln!(
                c,
                "    {};",
                entry_call(names, p.body, &names.data[p.data.index()])
            );
        }
    }
    c.push_str("}\n");
    c
}

/// `<Config>.h`: the prototypes of the configuration's globals' accessors (a newline
/// when it has none).
fn config_h(module: &Module, names: &Names) -> String {
    let mut h = String::new();
    if let Some(AggDef::Struct(st)) = globals_struct(module, names) {
        for (g, f) in st.fields.iter().enumerate() {
            if names.global_scope[g].is_none() {
                let _ = writeln!(
                    h,
                    "__DECLARE_GLOBAL_PROTOTYPE({}, {})",
                    accessor_type(module, names, g),
                    ident(&f.name)
                );
            }
        }
    }
    if h.is_empty() {
        h.push('\n');
    }
    h
}

/// `<Res>.c` of resource `r`. Lines 1-4 are a comment, line 5 blank, line 6 includes
/// `iec_std_lib.h` and line 7 is blank (a runtime may put an `#include` there). The
/// first resource's file includes `POUS.c` (matiec includes it in each, which gives
/// duplicate definitions with two resources).
fn res_c(module: &Module, names: &Names, r: usize) -> String {
    let res = &names.resources[r];
    let rc = &res.c;
    let mut s = String::new();
    let _ = writeln!(
        s,
        "/* {}.c: resource {}: its program instances and their scan.",
        res.file, res.spelled
    );
    s.push_str(" * Written by plcc.\n");
    s.push_str(" * Tasks are scheduled by the programs' code from the clock.\n");
    s.push_str(" */\n\n");
    s.push_str("#include \"iec_std_lib.h\"\n\n");
    s.push_str("extern unsigned long long common_ticktime__;\n\n");
    let _ = writeln!(
        s,
        "#include \"accessor.h\"\n#include \"POUS.h\"\n\n#include \"{}.h\"\n",
        names.config
    );
    if r == 0 {
        s.push_str("#include \"POUS.c\"\n\n");
    }
    s.push_str(&globals(module, names, Some(r)));
    let mine: Vec<&plcc_ir::ProgramEntry> = module
        .programs
        .iter()
        .enumerate()
        .filter(|(p, _)| names.program_resource[*p] == r)
        .map(|(_, p)| p)
        .collect();
    for (k, d) in module.data.iter().enumerate() {
        let here = module
            .programs
            .iter()
            .position(|p| p.data.index() == k)
            .map_or(r == 0, |p| names.program_resource[p] == r);
        if d.kind == DataKind::Program && here {
            let _ = writeln!(s, "{} {};", decls::mem_type(names, d.ty), names.data[k]);
        }
    }
    let _ = writeln!(
        s,
        "\nvoid {rc}_init__(void) {{\n    BOOL retain = 0;\n    (void)retain;"
    );
    for p in &mine {
        let d = p.data.index();
        if let MemType::Agg(a) = module.data[d].ty {
            if names.repr.prep[a.index()] {
                let _ = writeln!(
                    s,
                    "    __plcc_prep_{}(&{});",
                    names.aggs[a.index()],
                    names.data[d]
                );
            }
        }
    }
    for p in &mine {
        let _ = writeln!(
            s,
            "    {};",
            entry_call(names, p.init, &names.data[p.data.index()])
        );
    }
    s.push_str("}\n\n");
    let _ = writeln!(s, "void {rc}_run__(unsigned long tick) {{\n    (void)tick;");
    for p in &mine {
        let _ = writeln!(
            s,
            "    {};",
            entry_call(names, p.body, &names.data[p.data.index()])
        );
    }
    s.push_str("}\n");
    s
}

/// The preparation of the globals and of the data objects other than program
/// instances (flags cleared, located variables bound).
fn preps(module: &Module, names: &Names) -> String {
    let mut s = String::new();
    if let Some(AggDef::Struct(st)) = globals_struct(module, names) {
        for (g, f) in st.fields.iter().enumerate() {
            s.push_str(&decls::prep_member(
                names,
                names.global_repr(module, g),
                f.ty,
                &names.globals[g],
            ));
        }
    }
    for (k, d) in module.data.iter().enumerate() {
        if let MemType::Agg(a) = d.ty {
            if d.kind != DataKind::Program
                && !names.is_globals(plcc_ir::DataId::new(k))
                && names.repr.prep[a.index()]
            {
                let _ = writeln!(
                    s,
                    "    __plcc_prep_{}(&{});",
                    names.aggs[a.index()],
                    names.data[k]
                );
            }
        }
    }
    s
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
