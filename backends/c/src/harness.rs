//! The machine's own translation unit, `plcc_machine.c`, built into its library
//! beside the generated files: it plays the runtime (it defines `__CURRENT_TIME` and
//! `__DEBUG`, counts ticks and calls `config_init__`/`config_run__`) and tells the
//! machine where every variable is, with tables the C compiler fills in (`offsetof`,
//! `sizeof`), so the machine never assumes a layout.
//!
//! Symbols (all `uint64_t` tables end with an unused 0, since C has no empty arrays):
//! - `plcc_data[]`, `plcc_data_size[]`: each data object's address and size, in the
//!   module's order (0 for the globals' object, whose fields are variables);
//!   `plcc_global[]`, `plcc_global_size[]`: each global's;
//! - the located variables' storage and pointers (from `LOCATED_VARIABLES.h`, as a
//!   runtime's glue defines them);
//! - `plcc_field_offset[]`: the offsets of every struct's fields, struct after struct;
//!   `plcc_field_located[]`: 1 for a located field (it holds a pointer to the value);
//!   `plcc_agg_first[]` (where each aggregate's start in it), `plcc_agg_size[]`,
//!   `plcc_agg_stride[]` (an array's element size; 0 for structs);
//! - `plcc_pointer_size`: `sizeof(void *)`;
//! - `plcc_cold_start(fill)`: fills every data object with `fill` (nobody zeroes
//!   memory in the IR's contract, so a variable no init writes shows as garbage), sets
//!   the clock to 0 and runs `config_init__`;
//! - `plcc_scan(sec, nsec)`: sets `__CURRENT_TIME` and runs `config_run__` with the
//!   next tick;
//! - `plcc_fault()`, `plcc_stop()`: the addresses of the fault flag and of the stop
//!   request.

use crate::names::Names;
use crate::repr::Repr;
use plcc_ir::module::AggDef;
use plcc_ir::Module;
use std::fmt::Write;

/// The file name of the harness.
pub const FILE: &str = "plcc_machine.c";

/// The harness for `module`, whose files were named `names`.
pub fn source(module: &Module, names: &Names) -> String {
    let mut s = String::new();
    s.push_str(
        "/* plcc_machine.c: the C machine's runtime and layout tables (written by plcc). */\n\n",
    );
    s.push_str("#include \"iec_std_lib.h\"\n#include \"POUS.h\"\n\n");
    s.push_str("TIME __CURRENT_TIME;\nBOOL __DEBUG;\n\n");
    s.push_str(
        "/* The located variables' storage and the pointers the program binds to, as a\n   runtime's glue defines them. */\n\
         #define __LOCATED_VAR(type, name, ...) type __##name;\n\
         #include \"LOCATED_VARIABLES.h\"\n#undef __LOCATED_VAR\n\
         #define __LOCATED_VAR(type, name, ...) type *name = &__##name;\n\
         #include \"LOCATED_VARIABLES.h\"\n#undef __LOCATED_VAR\n\n",
    );
    s.push_str("void config_init__(void);\nvoid config_run__(unsigned long tick);\n\n");
    s.push_str("static unsigned long plcc_tick;\n\n");

    let list = |items: Vec<String>| -> String {
        let mut t = String::new();
        for i in items {
            let _ = writeln!(t, "    {i},");
        }
        t.push_str("    0\n");
        t
    };
    // The globals' object is not a C object: each global is a variable.
    let addr = |n: &String| {
        if n.is_empty() {
            "(unsigned char *)0".to_string()
        } else {
            format!("(unsigned char *)&{n}")
        }
    };
    let size = |n: &String| {
        if n.is_empty() {
            "0".to_string()
        } else {
            format!("sizeof {n}")
        }
    };
    for (sym, items, ty) in [
        (
            "plcc_data",
            names.data.iter().map(addr).collect::<Vec<_>>(),
            "unsigned char *const",
        ),
        (
            "plcc_data_size",
            names.data.iter().map(size).collect(),
            "const uint64_t",
        ),
        (
            "plcc_global",
            names.globals.iter().map(addr).collect(),
            "unsigned char *const",
        ),
        (
            "plcc_global_size",
            names.globals.iter().map(size).collect(),
            "const uint64_t",
        ),
    ] {
        let _ = write!(s, "{ty} {sym}[] = {{\n{}}};\n", list(items));
    }
    let mut offsets = Vec::new();
    let mut located = Vec::new();
    let mut first = Vec::new();
    let mut size = Vec::new();
    let mut stride = Vec::new();
    for (k, a) in module.aggs.iter().enumerate() {
        let name = &names.aggs[k];
        first.push(offsets.len().to_string());
        size.push(format!("sizeof({name})"));
        match a {
            AggDef::Struct(_) => {
                for (i, f) in names.fields[k].iter().enumerate() {
                    offsets.push(format!("offsetof({name}, {f})"));
                    let at = matches!(names.repr.fields[k][i], Repr::Located(_));
                    located.push(if at { "1" } else { "0" }.to_string());
                }
                stride.push("0".to_string());
            }
            AggDef::Array(_) => stride.push(format!("sizeof(((const {name} *)0)->table[0])")),
        }
    }
    for (sym, items) in [
        ("plcc_field_offset", offsets),
        ("plcc_field_located", located),
        ("plcc_agg_first", first),
        ("plcc_agg_size", size),
        ("plcc_agg_stride", stride),
    ] {
        let _ = write!(s, "const uint64_t {sym}[] = {{\n{}}};\n", list(items));
    }
    s.push_str("const uint64_t plcc_pointer_size = sizeof(void *);\n\n");

    s.push_str("void plcc_cold_start(unsigned char fill) {\n");
    for n in names
        .data
        .iter()
        .chain(&names.globals)
        .filter(|n| !n.is_empty())
    {
        let _ = writeln!(s, "    memset(&{n}, fill, sizeof {n});");
    }
    for l in &names.repr.located {
        let _ = writeln!(s, "    memset(&__{0}, fill, sizeof __{0});", l.name());
    }
    s.push_str(
        "    __CURRENT_TIME.tv_sec = 0;\n    __CURRENT_TIME.tv_nsec = 0;\n    plcc_tick = 0;\n    config_init__();\n}\n\n",
    );
    s.push_str(
        "void plcc_scan(long sec, long nsec) {\n    __CURRENT_TIME.tv_sec = sec;\n    __CURRENT_TIME.tv_nsec = nsec;\n    config_run__(plcc_tick++);\n}\n\n",
    );
    s.push_str("unsigned char *plcc_fault(void) {\n    return &__plcc_rt.fault;\n}\n\n");
    s.push_str(
        "unsigned char *plcc_stop(void) {\n    return (unsigned char *)&__plcc_rt.stop;\n}\n",
    );
    s
}
