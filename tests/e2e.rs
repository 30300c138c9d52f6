//! End-to-end tests of plcc's own programs, in every language: `tests/programs/st/`
//! (Structured Text, the checklist below), `il/` (Instruction List), `stl/` (PLC-UD
//! STL), `ld/` (ladder diagrams in PLCopen XML, each with an IL twin sharing its
//! scenario; `tests/ld_equivalence.rs` compares their IR), `plcopen/` (PLCopen XML
//! with LD and FBD bodies and multi-task configurations, no twins), `equiv/` (the same
//! logic in ST, IL and STL; `tests/equivalence.rs` compares their IR), mixed-language
//! builds among them (`# with:`).
//!
//! Every `tests/programs/**/*.{st,il,stl,xml}` has a scenario beside it (`NAME.expect`, the
//! `corpus-expect v1` format of `../shared/corpus/README.md`) whose expected values were
//! computed by hand from IEC 61131-3 and `DESIGN.md`, not copied from plcc's output.
//! Every example (`examples/**`, any language) with an `.expect` runs too. `run N` is
//! N scans of the cycle `plcc test` uses by default: the common tick of the
//! configuration's tasks (`config/common_tick`, `config/task_order`), else 10 ms.
//!
//! - `programs_on_host`, `programs_on_interp`: every scenario passes on that machine.
//! - `host_and_interp_agree`: the JIT and the IR interpreter hold the same value in
//!   every variable (and the same fault flag) after every scan of every scenario;
//!   `interp_and_vmasm_agree` (16-bit and aligned 32-bit modes) and
//!   `interp_and_pic16_agree` compare the VM and the chip with the interpreter;
//!   `programs_on_c` and `interp_and_c_agree` run the `c` target (its C built with the
//!   undefined-behaviour sanitizer) as a fifth machine.
//! - `vmasm_emits_only_what_the_c_vms_execute`: every instruction of every image is
//!   in the reference's table of what the C VMs execute.
//!
//! These tests never skip: a program without a scenario, a scenario without checks,
//! a program that does not compile, or a panic is a failure. Failures are collected
//! and reported together at the end.
//!
//! # Coverage checklist
//!
//! Construct → programs that cover it (paths under `tests/programs/st/`).
//!
//! POUs
//! - PROGRAM: every file; VAR_INPUT/VAR_OUTPUT of a PROGRAM: apps/motor_starter,
//!   apps/batching, apps/wash_cycle, apps/pump_alternation, stmt/if_elsif
//! - FUNCTION: pou/function_basic, pou/function_outputs, pou/function_chain,
//!   pou/function_types, pou/function_return, stmt/while_loop, stmt/repeat_loop
//! - FUNCTION without a result type, called as a statement: pou/function_outputs
//! - FUNCTION_BLOCK instances: pou/fb_instances, pou/fb_call_forms, apps/filters,
//!   apps/pi_control, apps/alarm_handler
//! - several instances of one FB, independent state: pou/fb_instances,
//!   pou/fb_nested (left/right), arrays/array_of_fbs, apps/alarm_handler
//! - FB instances nested in FBs (two levels): pou/fb_nested, pou/nested_initialisers,
//!   apps/alarm_handler, apps/pump_alternation, apps/ramp_generator
//! - formal calls: pou/function_basic, pou/fb_call_forms, stdfb/ton; positional
//!   calls: pou/function_basic, pou/fb_call_forms (`w2(4, 0, 10)`),
//!   pou/function_inout_swap, pou/call_binding (positional inputs and in-outs
//!   across interleaved VAR_INPUT/VAR_OUTPUT blocks, case-insensitive names)
//! - `=>` outputs: pou/function_outputs, pou/fb_call_forms, stdfb/ton,
//!   stdfb/bistables, pou/function_types, pou/call_binding (into bits and array
//!   elements); `NOT q => x`: pou/function_outputs, pou/fb_call_forms,
//!   pou/call_binding
//! - reading `inst.Q` in expressions: pou/fb_call_forms, pou/fb_instances,
//!   apps/motor_starter, apps/batching, stdfb/timers_one_clock (`NOT t.Q` as its own input)
//! - `inst.IN := x;` then `inst();`: pou/fb_call_forms (`w3.x := -8; w3();`),
//!   pou/nested_initialisers (`s1();`)
//! - FB instances as VAR_IN_OUT (of an FB and a FUNCTION), VAR_INPUT (copied, state
//!   included) and VAR_OUTPUT (read from outside, copied out with `=>`, a TON output
//!   with an initialiser): pou/fb_instance_params
//! - FB inputs keep their value between calls, FUNCTION inputs take their default:
//!   pou/fb_input_retention, pou/fb_inout
//! - VAR: every file; VAR_INPUT / VAR_OUTPUT: pou/function_outputs, pou/fb_call_forms
//! - VAR_IN_OUT in FUNCTIONs: pou/function_inout_swap, pou/function_chain,
//!   ops/short_circuit, bits/status_word, apps/sort_readings, apps/crc8,
//!   arrays/array_inout; in FBs: pou/fb_inout, arrays/array_inout, apps/seven_segment
//! - VAR_TEMP re-initialised at every call (FB and PROGRAM): pou/var_temp
//! - VAR_GLOBAL (scalars, arrays, an FB instance, CONSTANTs as array bounds), used
//!   directly from a FUNCTION and through VAR_EXTERNAL from a PROGRAM: pou/globals
//! - FUNCTION locals re-initialised at every call: pou/function_basic,
//!   pou/function_outputs (outputs restart at 0), pou/function_locals_reset
//!   (outputs with initial values, local arrays, a local FB instance)
//! - VAR CONSTANT (expressions, array bounds, CASE labels, FOR limits, NOT of a
//!   constant): pou/var_constant, apps/wash_cycle, apps/recipe_steps,
//!   apps/parking_garage, apps/frequency_meter
//! - initial values of every elementary type: pou/initial_values; FB instance
//!   initialisers `t : TON := (PT := T#2s)`: pou/initial_values, stdfb/tof,
//!   pou/nested_initialisers, pou/located_io (two levels deep),
//!   arrays/array_of_fbs (array of initialised TONs)
//! - located variables AT %I/%Q/%M: pou/located_io
//! - RETURN in FUNCTIONs: pou/function_return, pou/function_outputs; in FBs and
//!   PROGRAMs (also from inside a loop): pou/return_program_fb, apps/seven_segment
//!
//! Elementary types
//! - BOOL: types/bool_ops, literals/bool_literals, stdfn/conv_bool
//! - SINT INT DINT LINT (wrap-around at each width): types/signed_wrap,
//!   types/int_limits; USINT UINT UDINT ULINT: types/unsigned_wrap
//! - unsigned compare and divide: types/unsigned_compare_div, stmt/case_unsigned
//! - signed `/` toward zero, MOD with the sign of the dividend, MIN / -1:
//!   types/signed_div_mod, ops/arith_functions
//! - division and MOD by zero give 0 (no crash): types/div_by_zero
//! - BYTE WORD DWORD LWORD: types/bitstrings, ops/bitwise, stdfn/shift_byte_word,
//!   stdfn/shift_dword_lword, bits/bit_access
//! - REAL: types/real_arith, stdfn/math_real, apps/pi_control, apps/filters;
//!   LREAL: types/lreal_arith, stdfn/math_lreal, apps/ramp_generator
//! - TIME (arithmetic, comparison, wrap): types/time_arith, literals/time_literals;
//!   LTIME: types/ltime_arith, literals/time_literals
//! - implicit widening of mixed operands: types/implicit_widening
//!
//! Statements
//! - assignment: every file; IF/ELSIF/ELSE: stmt/if_elsif
//! - CASE with lists, ranges, ELSE, no match: stmt/case_basic; unsigned and
//!   bit-string selectors: stmt/case_unsigned; SINT/LINT/ULINT selectors:
//!   stmt/case_wide; CASE with constant labels: pou/var_constant, apps/wash_cycle;
//!   dense CASEs as jump tables (`br_table`) on every machine, INT, SINT and DINT
//!   selectors, negative labels, overlaps, a wrapping selector: the test
//!   `dense_case_is_a_jump_table_on_every_machine`
//! - FOR with BY (positive, negative, non-1, from a variable), the variable after
//!   the loop, empty ranges: stmt/for_steps; FOR up to the type's maximum or
//!   minimum terminates: stmt/for_type_max
//! - WHILE: stmt/while_loop; REPEAT: stmt/repeat_loop
//! - EXIT, CONTINUE (FOR, WHILE, REPEAT, nested): stmt/exit_continue,
//!   stmt/nested_control, apps/sort_readings
//! - nested control statements: stmt/nested_control
//!
//! Operators
//! - IEC ed. 3 precedence (unary minus tighter than `**`, `**` left-associative,
//!   NOT tightest, AND before XOR before OR, comparisons): ops/precedence
//! - AND_THEN / OR_ELSE short-circuit, AND / OR evaluate both (a FUNCTION with a
//!   side effect through VAR_IN_OUT): ops/short_circuit
//! - comparisons (also NaN, TIME, extensible GT/EQ/LE): ops/comparisons
//! - bitwise AND OR XOR NOT: ops/bitwise; unary + and -: ops/unary_ops
//! - `**` on REAL and integers, EXPT: ops/power, ops/precedence
//! - ADD MUL SUB DIV MOD MOVE as functions: ops/arith_functions
//!
//! Literals
//! - `16#FF`, `2#1010_0101`, `8#17`, `INT#-5`, typed based literals: literals/int_literals
//! - `T#1h2m3s4ms`, `T#1.5s`, `LT#…`, negative durations: literals/time_literals
//! - `1.5E3`, REAL#/LREAL#, `_` in reals: literals/real_literals
//! - `TRUE`, `BOOL#1`, `BOOL#0`, `BOOL#TRUE`: literals/bool_literals
//! - pragmas holding C code (`{...}`, `{{...}}` with `}` inside) skipped, never
//!   run as ST: pou/c_pragmas
//! - plain 0 and 1 as BOOLs (assigned, as inputs, beside a BOOL in logic and
//!   comparisons, in SEL/AND/EQ, in a CONSTANT): literals/bool_digits (and
//!   `il/bool_digits.il`)
//!
//! Standard functions
//! - ABS SQRT LN LOG EXP SIN COS TAN ASIN ACOS ATAN: stdfn/math_real,
//!   stdfn/math_lreal; ABS on integers: types/int_limits
//! - EXPT and `**`: ops/power
//! - SHL SHR ROL ROR on BYTE/WORD/DWORD/LWORD (shift >= width gives 0, rotate
//!   modulo the width): stdfn/shift_byte_word, stdfn/shift_dword_lword
//! - SEL MAX MIN LIMIT (also named arguments): stdfn/selection; MUX: stdfn/mux
//! - REAL→integer rounds half to even and saturates, NaN → 0: stdfn/conv_real_to_int
//! - narrowing integer conversions wrap, widening extends: stdfn/conv_int_narrow
//! - BOOL ↔ numbers: stdfn/conv_bool; TIME ↔ integers in ms: stdfn/conv_time,
//!   types/ltime_arith; REAL ↔ LREAL and integers → reals: stdfn/conv_real_lreal
//! - TO_* conversions: stdfn/conv_generic; TRUNC, *_TRUNC_*: stdfn/trunc
//! - BCD conversions both ways, every width, the overloaded and edition 2 names,
//!   ENO FALSE on an invalid BCD, a negative number or too many digits, EN FALSE:
//!   stdfn/bcd
//! - EQ NE LT LE GT GE on strings (extensible, capacities differ):
//!   strings/compare_functions; SEL MUX MOVE on strings (capacities differ,
//!   literals, cut on assignment, nested in LEN, CONCAT and `=`): strings/selection;
//!   MAX MIN LIMIT on STRING and WSTRING: strings/min_max
//! - ADD SUB MUL DIV on TIME, LTIME, TOD, DT and DATE (TOD wrapping, negative
//!   TIMEs, named arguments, nested): dates/time_functions; ADD_TIME … SUB_DT_DT,
//!   MULTIME, DIVTIME, MUL_TIME, DIV_TIME, CONCAT_DATE_TOD and the LTIME forms:
//!   dates/time_named_functions, dates/arithmetic
//!
//! Standard function blocks
//! - TON: stdfb/ton (IN dropping early), stdfb/timer_pt_zero (PT = 0),
//!   stdfb/timers_one_clock (one clock per scan), stdfb/timer_clock_wrap (the
//!   32-bit ms clock wrapping, also TOF and TP), apps/*
//! - TOF: stdfb/tof, stdfb/timer_pt_zero; TP: stdfb/tp (no retrigger, IN dropping
//!   early), stdfb/timer_pt_zero
//! - CTU (at PV, past PV, reset wins): stdfb/ctu, apps/batching; CTD (at the INT
//!   minimum): stdfb/ctd; CTUD (both edges, R over LD, INT maximum): stdfb/ctud,
//!   apps/parking_garage; typed variants: stdfb/counters_typed
//! - R_TRIG F_TRIG: stdfb/edge_triggers; SR RS (set vs reset dominance): stdfb/bistables
//!
//! Arrays
//! - 1-D: arrays/array_1d; 2-D: arrays/array_2d, arrays/array_inout; negative
//!   lower bounds: arrays/array_bounds, arrays/array_index_types; arrays of FB
//!   instances: arrays/array_of_fbs, apps/alarm_handler, apps/pump_alternation;
//!   initialisers `[1, 2, 3(0)]`: arrays/array_init, apps/crc8, apps/recipe_steps;
//!   out-of-bounds (read 0, write dropped, FB call skipped): arrays/array_oob,
//!   arrays/array_oob_inout (an element out of bounds passed to VAR_IN_OUT);
//!   ARRAY OF ARRAY (`a[i][j]`, nested initialisers): arrays/array_of_arrays;
//!   index types: arrays/array_index_types; arrays as VAR_IN_OUT: arrays/array_inout,
//!   apps/sort_readings, apps/crc8, apps/seven_segment
//!
//! User types (TYPE ... END_TYPE)
//! - STRUCT: field initial values, variable initialisers (partial, nested), member
//!   chains, a STRUCT written in place, a type declared after its use:
//!   types/struct_basic; arrays of STRUCTs and STRUCTs of arrays, their initialisers,
//!   `a.b[i].c`, out of bounds: types/struct_arrays; whole STRUCT and array
//!   assignment: types/struct_assign; STRUCTs and arrays as FUNCTION inputs (copied,
//!   defaults), outputs, in-outs and results: types/struct_function; in FBs (inputs,
//!   outputs, in-outs) and STRUCTs holding FB instances: types/struct_fb; global
//!   STRUCTs, enumerations and subranges, VAR_EXTERNAL: types/struct_global
//! - enumerations: defaults, explicit values, qualified and unqualified values, one
//!   name in two enumerations, `=` and `<>`, constants, FUNCTION input and result:
//!   types/enum_basic; CASE over them (lists, ranges, ELSE), a state machine in an
//!   FB: types/enum_case; typed enumerations (DINT, BYTE, INT), SEL, MOVE, EQ, NE:
//!   types/enum_typed
//! - aliases with initial values, aliases of aliases, typed literals of an alias,
//!   arrays of an alias, subranges, a named array type: types/alias_subrange
//! - in IL: member chains, enumeration values as operands, a whole STRUCT by LD/ST:
//!   ../il/tank_states
//!
//! Bit access `w.3`: bits/bit_access, bits/status_word, apps/crc8 (`c.7`),
//! apps/reject_tracking
//!
//! CPDev's ST (the `.cst` files its compiler consumed)
//! - `CUR_TIME()`, the timers' clock (also in a FUNCTION_BLOCK): cpdev/cur_time
//! - FOR over BYTE, WORD, DWORD, LWORD (unsigned, down with `BY -1`, to the type's
//!   maximum, a step variable, as an array index): cpdev/for_bitstring
//! - library-qualified types `IEC_61131.TON`, `Basic_blocks.TFF` (scalars, array
//!   elements, with an initialiser): cpdev/library_types
//! - generic functions of untyped literals typed by their context (`SQRT(2.0) * r`,
//!   `4.0 * ATAN(1.0)` in REAL, `ABS(-5) * x`, `TRUNC(2.7) * x` in INT, EXPT):
//!   cpdev/generic_literals, cpdev/generic_literals_expt
//!
//! Real-world style programs (apps/): motor_starter (star-delta), batching
//! (counter), pi_control (PI loop in REAL), sort_readings (sort via VAR_IN_OUT),
//! filters (moving average, low-pass, rate limit), wash_cycle (state machine),
//! alarm_handler, pump_alternation, analog_scaling, blinker, recipe_steps, crc8,
//! seven_segment, parking_garage, frequency_meter, reject_tracking, ramp_generator.
//!
//! Ladder diagrams (paths under `tests/programs/ld/`; PLCopen TC6 2.01 and 1.0 files)
//! - contacts normally open and closed: every file; rising and falling:
//!   edge_contacts, counter_reset, alarm_ack
//! - coils: normal and negated (set_reset, coil_chain), set and reset (set_reset,
//!   traffic_light, alarm_ack, tank_fill), several on one rung (output_tree,
//!   traffic_light), in series with contacts after them (coil_chain)
//! - series and parallel, nested: nested_parallel, motor_start_stop, alarm_ack
//! - a rung that writes what it reads: rung_order
//! - function blocks: TON (traffic_light, star_delta, blinker), TOF and TP
//!   (timers_tof_tp), CTU (counter_reset, conveyor), CTUD with four networks on its
//!   inputs (updown_counter), SR and RS (bistables), user FBs in ladder (fb_ld) and IL
//!   (mixed_bodies)
//! - functions with EN/ENO: counter_reset, edge_contacts, enable_chain (ENO to EN),
//!   jumps; enabled from the rail: compare_blocks, counter_reset; user functions in
//!   ladder (function_ld, return_function) and ST (mixed_bodies)
//! - jumps and labels: jumps; RETURN: return_function
//! - located I/O: motor_start_stop, conveyor; data types and globals of the
//!   configuration: mixed_bodies
//!
//! PLCopen XML (paths under `tests/programs/plcopen/`, the lowering of graphical
//! bodies; `scripts/plcopen_programs.py` writes the XML)
//! - LD: bridges (ld_bridge), coils on the left rail (ld_rail_coils), chained coils
//!   with one and several wires (ld_coil_chain, ld_coil_chain_or), contacts with no
//!   input (ld_unconnected_contact), edge contacts feeding two coils
//!   (ld_edge_two_coils), coil modifiers (ld_coil_modifiers), TON, CTU with EN and ADD
//!   with EN in rungs (ld_ton_rung, ld_ctu_en, ld_add_en), feedback through SR and
//!   ADD (ld_block_feedback), jumps and RETURN (ld_jump, ld_return), connectors
//!   (ld_connectors), rung order by position (ld_rung_order, ld_ton_contact),
//!   executionOrderId (ld_exec_order)
//! - FBD: standard functions (fbd_arith, fbd_select, fbd_logic, fbd_convert), timers,
//!   counters, bistables (fbd_timers, fbd_counters, fbd_bistables), negated and edge
//!   pins (fbd_pins, fbd_counters), connectors (fbd_connectors), unwired function
//!   inputs (fbd_unwired_input), EN/ENO (fbd_en_eno), feedback (fbd_feedback,
//!   fbd_inout_var), executionOrderId (fbd_exec_order), user FUNCTIONs and
//!   FUNCTION_BLOCKs in FBD (fbd_user_function, fbd_user_fb)
//! - configurations: tasks of 10 and 30 ms (cfg_two_tasks), globals and an instance
//!   with no task (cfg_globals), the TC6 1.0 format (cfg_old_namespace)
//! - a loop cut where executionOrderId says (fbd_loop_order), ids across networks
//!   (fbd_exec_order_networks), a variable on ENO (fbd_eno_variable)

#[path = "common/c_driver.rs"]
mod c_driver;
#[path = "common/cpdev_opcodes.rs"]
mod cpdev_opcodes;

use plcc::driver::{build_sources, BuildOptions};
use plcc::scenario::{self, Scenario, Step};
use plcc::targets;
use plcc_ir::backend::Backend;
use plcc_ir::machine::Machine;
use plcc_ir::value::PlcValue;
use plcc_ir::{ElemType, Module};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};

#[path = "common/skip.rs"]
mod skip;

/// The clock step of `run N` for a compiled case: the rule `plcc test` follows
/// without `--cycle-ms` (the common tick of the configuration's tasks, else 10 ms).
fn cycle_us(module: &Module) -> u64 {
    scenario::Cycle::of(module, None).us
}

/// Fewer programs than this means the discovery is broken.
const MIN_PROGRAMS: usize = 90;

/// The fewest programs (with their scenarios) each language other than ST must have.
const MIN_PER_LANGUAGE: [(&str, usize); 3] = [("il", 30), ("stl", 20), ("xml", 20)];

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The source languages the suite covers, by extension (`.cst`: ST in the CPDev
/// dialect; `.xml`: ladder diagrams in PLCopen XML).
const SOURCE_EXTENSIONS: [&str; 5] = ["st", "il", "stl", "cst", "xml"];

/// Every source file (ST, IL, STL, ladder) under `dir`, recursively.
fn source_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for e in entries {
        let p = e.expect("directory entry").path();
        if p.is_dir() {
            source_files(&p, out);
        } else if p
            .extension()
            .is_some_and(|x| SOURCE_EXTENSIONS.iter().any(|e| x == *e))
        {
            out.push(p);
        }
    }
}

/// A program and its scenario, named by its path relative to the crate. A scenario
/// may name more source files to build with the program, in a comment line
/// `# with: lib.st other.il` (paths relative to the scenario): that is how the
/// mixed-language cases are written. A line `# rejected-by: vmasm E9101` says that
/// a target refuses the program with that code (a feature it cannot have): the tests
/// then check that it does, instead of running the scenario there.
struct Case {
    name: String,
    sources: Vec<PathBuf>,
    expect: PathBuf,
}

impl Case {
    /// The code `target` (`vmasm`, `vmasm:mode=32`, …) must refuse the program with.
    fn rejected_by(&self, target: &str) -> Option<String> {
        let base = target.split(':').next().unwrap_or(target);
        let text = std::fs::read_to_string(&self.expect).unwrap_or_default();
        text.lines()
            .filter_map(|l| l.trim().strip_prefix("# rejected-by:"))
            .find_map(|rest| {
                let mut w = rest.split_whitespace();
                (w.next() == Some(base)).then(|| w.next().unwrap_or("").to_string())
            })
    }

    /// `Ok(true)` when `target` refused the program as its scenario says it must
    /// (`made` is what building the machine gave), `Ok(false)` when the scenario
    /// lists no refusal by `target` (the caller handles `made`), an error when the
    /// target did not refuse as listed.
    fn refusal<T>(&self, target: &str, made: &Result<T, String>) -> Result<bool, String> {
        match (self.rejected_by(target), made) {
            (Some(code), Err(e)) if e.contains(&code) => Ok(true),
            (Some(code), Ok(_)) => Err(format!(
                "{target} was to refuse it with {code}, and did not"
            )),
            (Some(code), Err(e)) => Err(format!("{target} was to refuse it with {code}: {e}")),
            (None, _) => Ok(false),
        }
    }
}

/// The files a scenario's `# with:` lines add, resolved beside the scenario.
fn with_files(expect: &Path) -> Vec<PathBuf> {
    let text = std::fs::read_to_string(expect).unwrap_or_default();
    let dir = expect.parent().map(Path::to_path_buf).unwrap_or_default();
    text.lines()
        .filter_map(|l| l.trim().strip_prefix("# with:"))
        .flat_map(|rest| {
            rest.split_whitespace()
                .map(|f| dir.join(f))
                .collect::<Vec<_>>()
        })
        .collect()
}

/// Every test program (each must have a scenario) and every example with one.
fn cases() -> (Vec<Case>, Vec<String>) {
    let root = root();
    let mut problems = Vec::new();
    let mut programs = Vec::new();
    source_files(&root.join("tests/programs"), &mut programs);
    programs.sort();
    // Files a scenario builds together with its program are not cases of their own.
    let helpers: Vec<PathBuf> = programs
        .iter()
        .filter_map(|p| {
            let e = p.with_extension("expect");
            e.exists().then(|| with_files(&e))
        })
        .flatten()
        .collect();
    let mut out = Vec::new();
    for src in programs {
        if helpers.contains(&src) {
            continue;
        }
        let expect = src.with_extension("expect");
        let name = rel(&src);
        if expect.exists() {
            let mut sources = vec![src];
            sources.extend(with_files(&expect));
            out.push(Case {
                name,
                sources,
                expect,
            });
        } else {
            problems.push(format!("{name}: no scenario (.expect) beside it"));
        }
    }
    if out.len() < MIN_PROGRAMS {
        problems.push(format!(
            "only {} programs found under tests/programs (expected at least {MIN_PROGRAMS})",
            out.len()
        ));
    }
    for (ext, min) in MIN_PER_LANGUAGE {
        let n = out
            .iter()
            .filter(|c| c.sources[0].extension().is_some_and(|x| x == ext))
            .count();
        if n < min {
            problems.push(format!(
                "only {n} .{ext} programs under tests/programs (expected at least {min})"
            ));
        }
    }
    let mut examples = Vec::new();
    source_files(&root.join("examples"), &mut examples);
    examples.sort();
    for src in examples {
        let expect = src.with_extension("expect");
        if expect.exists() {
            let mut sources = vec![src.clone()];
            sources.extend(with_files(&expect));
            out.push(Case {
                name: rel(&src),
                sources,
                expect,
            });
        }
    }
    (out, problems)
}

fn rel(p: &Path) -> String {
    p.strip_prefix(root())
        .unwrap_or(p)
        .to_string_lossy()
        .replace('\\', "/")
}

/// A compiled case: its scenario, module and the program the scenario runs.
struct Built {
    scn: Scenario,
    module: Module,
    program: String,
}

fn build(case: &Case) -> Result<Built, String> {
    let text = std::fs::read_to_string(&case.expect)
        .map_err(|e| format!("cannot read the scenario: {e}"))?;
    let scn = scenario::parse(&text).map_err(|e| format!("scenario: {e}"))?;
    if let Some(why) = &scn.unsupported {
        return Err(format!("scenario not supported: {why}"));
    }
    if !scn
        .steps
        .iter()
        .any(|(_, s)| matches!(s, Step::Expect { .. }))
    {
        return Err("the scenario checks nothing".into());
    }
    let mut texts = Vec::new();
    for src in &case.sources {
        let bytes =
            std::fs::read(src).map_err(|e| format!("cannot read {}: {e}", src.display()))?;
        texts.push((rel(src), bytes));
    }
    // Programs under a `codesys` directory are in the CODESYS dialect.
    let codesys = case
        .sources
        .iter()
        .any(|s| s.components().any(|c| c.as_os_str() == "codesys"));
    // A scenario line `# sfc: matiec` chooses how charts evolve.
    let sfc = std::fs::read_to_string(&case.expect)
        .unwrap_or_default()
        .lines()
        .find_map(|l| {
            l.trim()
                .strip_prefix("# sfc:")
                .map(|p| p.trim().to_string())
        });
    let sfc = match sfc {
        None => plcc_frontend::sfc::Profile::Iec,
        Some(p) => plcc_frontend::sfc::Profile::from_name(&p)
            .ok_or_else(|| format!("unknown SFC profile `{p}`"))?,
    };
    let opts = BuildOptions {
        programs: scn.program.iter().cloned().collect(),
        codesys,
        sfc,
        ..Default::default()
    };
    let b = build_sources(texts, &opts).map_err(|e| e.0)?;
    let Some(module) = b.module else {
        let errors: Vec<String> = b
            .diagnostics
            .iter()
            .filter(|d| d.is_error())
            .take(5)
            .map(|d| d.to_string())
            .collect();
        return Err(format!("does not compile: {}", errors.join("; ")));
    };
    let program = match &scn.program {
        // A configuration's instance may be named by its PROGRAM type.
        Some(p) => module
            .program_or_instance_of(p)
            .map_or_else(|| p.clone(), |e| e.name.clone()),
        // Several (a configuration's instances): whole paths in the scenario.
        None => match module.programs.as_slice() {
            [one] => one.name.clone(),
            [] => return Err("the files declare no PROGRAM".into()),
            _ => String::new(),
        },
    };
    Ok(Built {
        scn,
        module,
        program,
    })
}

/// A machine of `target`, which may carry settings: `vmasm:mode=32a`.
fn machine(target: &str, module: &Module) -> Result<Box<dyn Machine>, String> {
    targets::machine_spec(target, module).map_err(|d| {
        let msgs: Vec<String> = d.iter().map(|x| x.to_string()).collect();
        format!("no {target} machine: {}", msgs.join("; "))
    })
}

fn panic_text(p: Box<dyn std::any::Any + Send>) -> String {
    p.downcast_ref::<String>()
        .cloned()
        .or_else(|| p.downcast_ref::<&str>().map(|s| s.to_string()))
        .unwrap_or_else(|| "(no message)".into())
}

/// Runs one case's scenario on one target; the failures as text.
fn run_case(case: &Case, target: &str) -> Result<usize, String> {
    let built = build(case)?;
    let made = machine(target, &built.module);
    if case.refusal(target, &made)? {
        return Ok(0);
    }
    let mut m = made?;
    checked(scenario::run(
        &built.scn,
        m.as_mut(),
        &built.program,
        cycle_us(&built.module),
    ))
}

/// The number of checks of a scenario that passed, or its failed checks as text.
fn checked(out: scenario::Outcome) -> Result<usize, String> {
    if out.passed() {
        return Ok(out.checks.len());
    }
    let mut why: Vec<String> = out
        .checks
        .iter()
        .filter(|c| !c.ok)
        .map(|c| format!("line {}: {}: {}", c.line, c.text, c.detail))
        .collect();
    why.extend(out.error.clone());
    Err(why.join("\n    "))
}

fn run_all(target: &str) {
    let (cases, mut failures) = cases();
    let mut checks = 0;
    for case in &cases {
        match catch_unwind(AssertUnwindSafe(|| run_case(case, target))) {
            Ok(Ok(n)) => checks += n,
            Ok(Err(e)) => failures.push(format!("{}:\n    {e}", case.name)),
            Err(p) => failures.push(format!("{}: PANIC: {}", case.name, panic_text(p))),
        }
    }
    println!("{} programs, {checks} checks on {target}", cases.len());
    assert!(
        failures.is_empty(),
        "{} of {} programs failed on {target}:\n{}",
        failures.len(),
        cases.len(),
        failures.join("\n")
    );
}

#[test]
fn programs_on_host() {
    run_all("host");
}

#[test]
fn programs_on_interp() {
    run_all("interp");
}

/// The C machine with the registry's checked setting: its library built with the
/// undefined-behaviour sanitizer (which stops the process at the first undefined
/// operation).
#[test]
fn programs_on_c() {
    run_all(&checked_machine("c"));
}

/// A target's machine with the setting the target registry checks it with
/// (`c:sanitize=undefined`).
fn checked_machine(name: &str) -> String {
    targets::find(name)
        .unwrap_or_else(|| panic!("`{name}` is not in the target registry"))
        .checked_machine()
}

/// The targets whose machines have their own tests here: every scenario
/// (`programs_on_*`) and every scan against the interpreter (`*_agree`).
const MACHINES_TESTED: [&str; 5] = ["host", "interp", "vmasm", "pic16f876a", "c"];

/// Every target of the registry that runs programs has its tests here.
#[test]
fn every_machine_of_the_registry_is_tested() {
    let missing: Vec<&str> = targets::TARGETS
        .iter()
        .map(|t| t.name)
        .filter(|n| !MACHINES_TESTED.contains(n))
        .collect();
    assert!(
        missing.is_empty(),
        "targets of src/targets.rs without programs_on_* and *_agree tests: {missing:?}"
    );
    for t in targets::not_running() {
        skip::notice(&format!("target `{t}` cannot run programs here"));
    }
}

#[test]
fn programs_on_vmasm() {
    run_all("vmasm");
}

/// The other addressing modes of the VM: 32-bit, and 32-bit with 4-byte alignment.
#[test]
fn programs_on_vmasm_32_bit_modes() {
    run_all("vmasm:mode=32");
    run_all("vmasm:mode=32a");
}

/// The VM ports with a 16-bit C `int` and no 64-bit types: every program the port
/// holds (the others are E9105, and counted) passes there, with the VM checking that
/// no instruction would overflow a 16-bit `int` or use what the port lacks.
#[test]
fn programs_on_vmasm_small_ports() {
    for port in ["avr", "sdcc"] {
        let target = format!("vmasm:port={port}");
        let (cases, mut failures) = cases();
        let (mut ran, mut lacked) = (0, 0);
        for case in &cases {
            match catch_unwind(AssertUnwindSafe(|| run_case(case, &target))) {
                Ok(Ok(_)) => ran += 1,
                Ok(Err(e)) if e.contains("E9105") => lacked += 1,
                Ok(Err(e)) => failures.push(format!("{}:\n    {e}", case.name)),
                Err(p) => failures.push(format!("{}: PANIC: {}", case.name, panic_text(p))),
            }
        }
        println!("{target}: {ran} programs ran, {lacked} need what the port lacks");
        assert!(failures.is_empty(), "{target}:\n{}", failures.join("\n"));
        assert!(ran > 100, "{target}: only {ran} programs ran");
    }
}

/// Like [`same`], but REAL values may differ by a relative 1e-5: the transcendental
/// functions (SIN, LN, EXPT, ...) are not correctly rounded, so a target with its own
/// library (the PIC16's soft float) may give a neighbouring float.
fn close(a: PlcValue, b: PlcValue) -> bool {
    if a.same(b) {
        return true;
    }
    if a.ty != ElemType::Real || b.ty != ElemType::Real {
        return false;
    }
    let (x, y) = (a.as_f64(), b.as_f64());
    (x - y).abs() <= 1e-5 * x.abs().max(y.abs())
}

/// True if the module calls a transcendental function of REAL or LREAL.
fn uses_transcendentals(m: &Module) -> bool {
    use plcc_ir::inst::{BinaryOp, InstData, UnaryOp};
    m.funcs.iter().any(|f| {
        f.inst_iter().any(|(_, i)| match f.inst(i) {
            InstData::Unary { op, .. } => matches!(
                op,
                UnaryOp::Sin
                    | UnaryOp::Cos
                    | UnaryOp::Tan
                    | UnaryOp::Asin
                    | UnaryOp::Acos
                    | UnaryOp::Atan
                    | UnaryOp::Ln
                    | UnaryOp::Log10
                    | UnaryOp::Exp
            ),
            InstData::Binary { op, .. } => matches!(op, BinaryOp::Fpow | BinaryOp::Fatan2),
            _ => false,
        })
    })
}

/// Runs the scenario's scans and writes on both machines, comparing every variable
/// of the program and the fault flag after every scan (and after cold start).
fn differential(case: &Case, first: &str, second: &str) -> Result<usize, String> {
    let built = build(case)?;
    // Every variable of every program instance (a configuration has several).
    let vars: Vec<plcc_ir::vars::VarRef> = built
        .module
        .programs
        .iter()
        .flat_map(|p| plcc_ir::vars::variables(&built.module, p.data))
        .collect();
    if vars.is_empty() {
        return Err("the program has no variables to compare".into());
    }
    // Two machines with the same math library must agree bit for bit.
    let approx = second == "pic16f876a" && uses_transcendentals(&built.module);
    let mut host = machine(first, &built.module)?;
    let made = machine(second, &built.module);
    if case.refusal(second, &made)? {
        return Ok(0);
    }
    let mut interp = match made {
        Ok(m) => m,
        Err(e) if does_not_fit(&e) => return Ok(0),
        Err(e) => return Err(e),
    };
    let mut scans = 0usize;
    let compare = |host: &dyn Machine, interp: &dyn Machine, when: &str| -> Result<(), String> {
        let mut diffs = Vec::new();
        for v in &vars {
            let a = host
                .read(&v.path)
                .map_err(|e| format!("{first}: {}: {e}", v.path))?;
            let b = interp
                .read(&v.path)
                .map_err(|e| format!("{second}: {}: {e}", v.path))?;
            let equal = if approx { close(a, b) } else { a.same(b) };
            if !equal {
                diffs.push(format!("{} {first} {a} {second} {b}", v.path));
            }
        }
        if host.fault() != interp.fault() {
            diffs.push(format!(
                "fault flag {first} {} {second} {}",
                host.fault(),
                interp.fault()
            ));
        }
        if diffs.is_empty() {
            Ok(())
        } else {
            diffs.truncate(5);
            Err(format!("{when}: {}", diffs.join(", ")))
        }
    };
    host.cold_start()
        .map_err(|e| format!("{first} cold start: {e}"))?;
    interp
        .cold_start()
        .map_err(|e| format!("{second} cold start: {e}"))?;
    compare(host.as_ref(), interp.as_ref(), "after cold start")?;
    // The clock as `scenario::run` keeps it: `run` scans at the next cycle's time and
    // steps it; `run_at_us T` scans at T and goes on from T + cycle.
    let cycle_us = cycle_us(&built.module) as i64;
    let mut next_us: i64 = 0;
    let mut scan_at = |host: &mut dyn Machine, interp: &mut dyn Machine, t: i64, line: usize| {
        scans += 1;
        host.set_clock_us(t);
        host.scan()
            .map_err(|e| format!("line {line}: {first} scan failed: {e}"))?;
        interp.set_clock_us(t);
        interp
            .scan()
            .map_err(|e| format!("line {line}: {second} scan failed: {e}"))?;
        compare(
            host,
            interp,
            &format!("line {line}, scan {scans} (t = {t} us)"),
        )
    };
    for (line, step) in &built.scn.steps {
        match step {
            Step::Run(n) => {
                for _ in 0..*n {
                    let t = next_us;
                    next_us += cycle_us;
                    scan_at(host.as_mut(), interp.as_mut(), t, *line)?;
                }
            }
            Step::Duration(secs) => {
                let n = ((secs * 1e6) / cycle_us.max(1) as f64).ceil().max(1.0) as u64;
                for _ in 0..n {
                    let t = next_us;
                    next_us += cycle_us;
                    scan_at(host.as_mut(), interp.as_mut(), t, *line)?;
                }
            }
            Step::RunAt(t) => {
                next_us = *t + cycle_us;
                scan_at(host.as_mut(), interp.as_mut(), *t, *line)?;
            }
            Step::Set { var, value } => {
                for m in [&mut host, &mut interp] {
                    let path = scenario::path_of(m.as_ref(), &built.program, var);
                    scenario::set(m.as_mut(), &path, value)
                        .map_err(|e| format!("line {line}: {e}"))?;
                }
            }
            Step::Expect { .. } => {}
        }
    }
    Ok(scans)
}

fn agree(first: &str, second: &str) {
    let (cases, mut failures) = cases();
    let mut scans = 0;
    for case in &cases {
        match catch_unwind(AssertUnwindSafe(|| differential(case, first, second))) {
            Ok(Ok(n)) => scans += n,
            Ok(Err(e)) => failures.push(format!("{}: {e}", case.name)),
            Err(p) => failures.push(format!("{}: PANIC: {}", case.name, panic_text(p))),
        }
    }
    println!("{} programs, {scans} scans compared", cases.len());
    assert!(
        failures.is_empty(),
        "{first} and {second} disagree on {} of {} programs:\n{}",
        failures.len(),
        cases.len(),
        failures.join("\n")
    );
}

#[test]
fn host_and_interp_agree() {
    agree("host", "interp");
}

/// The VM and the chip simulator are compared with the interpreter, the independent
/// oracle, not with the JIT: a backend's own machine shares its mistakes.
#[test]
fn interp_and_vmasm_agree() {
    agree("interp", "vmasm");
}

#[test]
fn interp_and_vmasm_32a_agree() {
    agree("interp", "vmasm:mode=32a");
}

/// The C machine (built with the undefined-behaviour sanitizer) against the
/// interpreter.
#[test]
fn interp_and_c_agree() {
    agree("interp", &checked_machine("c"));
}

/// Every program's C compiles as C++ (`-std=gnu++11`, as OpenPLC builds it) under
/// g++ and clang++, and as C99 under clang, with `-Wall -Wextra -Werror`: checked
/// without code generation, with the system headers precompiled. (As C99 under gcc,
/// at -O1 with the same warnings, the C machine builds every program in
/// `programs_on_c`, `interp_and_c_agree` and `c_under_address_sanitizer`.)
#[test]
fn c_files_compile_under_gcc_and_clang() {
    let (cases, mut failures) = cases();
    let mut built = Vec::new();
    for case in &cases {
        match build(case) {
            Ok(b) => built.push((case.name.clone(), b.module)),
            Err(e) => failures.push(format!("{}: {e}", case.name)),
        }
    }
    let dir = plcc_c::cc::TempDir::new().expect("a temporary directory");
    let modules: Vec<&Module> = built.iter().map(|(_, m)| m).collect();
    let dirs = c_driver::write_programs(&modules, &dir.path().join("programs")).expect("the files");
    let results: Vec<_> = std::thread::scope(|s| {
        let jobs: Vec<_> = c_driver::COMPILERS
            .iter()
            .enumerate()
            .map(|(k, c)| {
                let work = dir.path().join(format!("pch{k}"));
                let dirs = &dirs;
                s.spawn(move || c_driver::compile_programs(c, &work, dirs))
            })
            .collect();
        jobs.into_iter()
            .map(|j| j.join().expect("a compiler job"))
            .collect()
    });
    for (c, r) in c_driver::COMPILERS.iter().zip(results) {
        match r {
            Ok(failed) => {
                for (k, e) in failed {
                    failures.push(format!("{} under {}: {e}", built[k].0, c.name));
                }
            }
            Err(e) => failures.push(format!("{}: {e}", c.name)),
        }
    }
    println!(
        "{} programs' C checked under {}",
        built.len(),
        c_driver::COMPILERS.map(|c| c.name).join(", ")
    );
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// Programs whose C does not fit the ATmega2560, and why, one per line (`NAME:
/// reason`); `c_builds_for_avr` checks that this list is exactly what avr-gcc says.
const AVR_UNFIT: &str = include_str!("avr_unfit.txt");

/// Every program's C builds with avr-gcc for the ATmega2560 (`-mmcu=atmega2560 -Os`,
/// OpenPLC's Arduino Mega target), with plcc's own headers and a `main` of its own,
/// under `-Wall -Wextra -Werror`; what does not fit the chip (its 8 KB of RAM, or
/// LREALs, which avr-gcc's 32-bit double cannot hold) is `tests/avr_unfit.txt`.
#[test]
fn c_builds_for_avr() {
    if std::process::Command::new("avr-gcc")
        .arg("--version")
        .output()
        .is_err()
    {
        skip::notice("avr-gcc is not installed (.ci/run installs gcc-avr and avr-libc); skipping the AVR builds");
        return;
    }
    let (cases, mut failures) = cases();
    let mut built = Vec::new();
    for case in &cases {
        match build(case) {
            Ok(b) => built.push((case.name.clone(), b.module)),
            Err(e) => failures.push(format!("{}: {e}", case.name)),
        }
    }
    let dir = plcc_c::cc::TempDir::new().expect("a temporary directory");
    let main_o = c_driver::avr_main(&dir.path().join("main")).expect("the AVR main");
    let modules: Vec<&Module> = built.iter().map(|(_, m)| m).collect();
    let dirs = c_driver::write_programs(&modules, &dir.path().join("programs")).expect("the files");
    // Two at a time (the machine's cores).
    let results: Vec<Result<c_driver::Avr, String>> = std::thread::scope(|s| {
        let half = dirs.len().div_ceil(2);
        let jobs: Vec<_> = dirs
            .chunks(half.max(1))
            .map(|chunk| {
                let main_o = &main_o;
                s.spawn(move || {
                    chunk
                        .iter()
                        .map(|d| c_driver::avr_build(d, main_o))
                        .collect::<Vec<_>>()
                })
            })
            .collect();
        jobs.into_iter()
            .flat_map(|j| j.join().expect("an AVR job"))
            .collect()
    });
    let (mut fits, mut flash, mut ram) = (0, 0u64, 0u64);
    let mut unfit = Vec::new();
    for ((name, _), r) in built.iter().zip(results) {
        match r {
            Ok(c_driver::Avr::Fits { flash: f, ram: r }) => {
                fits += 1;
                flash = flash.max(f);
                ram = ram.max(r);
            }
            Ok(c_driver::Avr::DoesNotFit(why)) => unfit.push(format!("{name}: {why}")),
            Err(e) => failures.push(format!("{name}: {e}")),
        }
    }
    println!(
        "{fits} of {} programs build for the ATmega2560 (at most {flash} bytes of flash, {ram} of RAM); {} do not fit:",
        built.len(),
        unfit.len()
    );
    for u in &unfit {
        println!("  {u}");
    }
    let listed: Vec<&str> = AVR_UNFIT
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty() && !l.starts_with('#'))
        .collect();
    for u in &unfit {
        if !listed.contains(&u.as_str()) {
            failures.push(format!(
                "does not fit, but tests/avr_unfit.txt does not say so: {u}"
            ));
        }
    }
    for l in &listed {
        if !unfit.iter().any(|u| u == l) {
            failures.push(format!(
                "tests/avr_unfit.txt lists what no longer happens: {l}"
            ));
        }
    }
    assert!(fits > 300, "only {fits} programs build for the ATmega2560");
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// Every program, built with a `main` of its own under the address and
/// undefined-behaviour sanitizers (the address sanitizer cannot be loaded into the
/// running test, so the C machine cannot use it), runs cold start and 20 scans with no
/// inputs and ends with every variable and the fault flag as the interpreter has them.
#[test]
fn c_under_address_sanitizer() {
    let (cases, mut failures) = cases();
    let mut compared = 0;
    for case in &cases {
        let r = build(case)
            .and_then(|b| c_driver::agrees_under_asan(&b.module, 20, cycle_us(&b.module)));
        match r {
            Ok(n) => compared += n,
            Err(e) => failures.push(format!("{}: {e}", case.name)),
        }
    }
    println!("{} programs, {compared} values compared", cases.len());
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn interp_and_pic16_agree() {
    agree("interp", "pic16f876a");
}

/// Every instruction of every program's vmasm image, in every mode, is one the public
/// CPDev C VMs execute, with the operand sizes the reference gives (its own table in
/// `common/cpdev_opcodes.rs`, not the backend's): walking the image with the
/// reference's forms lands exactly on its end. In the aligned mode every instruction
/// starts at a multiple of 4, as in CPDev's own images (but the no-op that realigns
/// after a 14-byte DPRDL/DPWRL).
#[test]
fn vmasm_emits_only_what_the_c_vms_execute() {
    let (cases, mut failures) = cases();
    let mut insts = 0;
    let mut opcodes = std::collections::BTreeSet::new();
    for case in &cases {
        let built = match build(case) {
            Ok(b) => b,
            Err(e) => {
                failures.push(format!("{}: {e}", case.name));
                continue;
            }
        };
        for mode in ["16", "32", "32a"] {
            let options = plcc_ir::backend::Options {
                settings: vec![("mode".into(), mode.into())],
                ..Default::default()
            };
            let made = plcc_vmasm::VmasmBackend::new()
                .compile(&built.module, &options)
                .map_err(|d| d[0].to_string());
            let arts = match (case.refusal("vmasm", &made), made) {
                (Ok(true), _) => continue,
                (Ok(false), Ok(a)) => a,
                (Err(e), _) | (Ok(false), Err(e)) => {
                    failures.push(format!("{} (mode {mode}): {e}", case.name));
                    continue;
                }
            };
            let code = &arts.files[0].bytes;
            match cpdev_opcodes::walk(code, mode) {
                Ok(list) => {
                    insts += list.len();
                    for (k, &(at, op)) in list.iter().enumerate() {
                        opcodes.insert(op);
                        // DPRDL/DPWRL are 14 bytes in 32A: the no-op FPAT after
                        // them realigns the next instruction.
                        let pad = k > 0 && matches!(list[k - 1].1, 0x1E01 | 0x1E02);
                        if mode == "32a" && at % 4 != 0 && !pad {
                            failures.push(format!(
                                "{} (mode 32a): {op:04X} at {at:#x} is not 4-byte aligned",
                                case.name
                            ));
                            break;
                        }
                    }
                }
                Err(e) => failures.push(format!("{} (mode {mode}): {e}", case.name)),
            }
        }
    }
    println!(
        "{} programs, {insts} instructions, {} distinct opcodes: {:04X?}",
        cases.len(),
        opcodes.len(),
        opcodes
    );
    assert!(
        opcodes.len() > 60,
        "too few opcodes seen: {}",
        opcodes.len()
    );
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// The backend codes that mean "the program does not fit the target" rather than a bug.
const UNFIT_CODES: [&str; 4] = ["E9001", "E9002", "E9003", "E9004"];

fn does_not_fit(message: &str) -> bool {
    UNFIT_CODES.iter().any(|c| message.contains(c))
}

/// Programs that do not fit the PIC16F876A and why, one per line (`NAME: reason`);
/// `programs_on_pic16` checks that this list is exactly what the backend reports.
const PIC16_UNFIT: &str = include_str!("pic16_unfit.txt");

#[test]
fn programs_on_pic16() {
    let (cases, mut failures) = cases();
    let mut checks = 0;
    let mut unfit: Vec<String> = Vec::new();
    let mut ran = 0;
    for case in &cases {
        let r = catch_unwind(AssertUnwindSafe(|| -> Result<Option<usize>, String> {
            let built = build(case)?;
            let mut m = match targets::machine("pic16f876a", &built.module) {
                Ok(m) => m,
                Err(d) => {
                    let first = d.iter().find(|x| x.is_error());
                    return match first {
                        Some(x) if UNFIT_CODES.contains(&x.code) => {
                            Err(format!("UNFIT {} {}", x.code, x.message))
                        }
                        _ => Err(format!(
                            "no pic16f876a machine: {}",
                            d.iter()
                                .map(|x| x.to_string())
                                .collect::<Vec<_>>()
                                .join("; ")
                        )),
                    };
                }
            };
            checked(scenario::run(
                &built.scn,
                m.as_mut(),
                &built.program,
                cycle_us(&built.module),
            ))
            .map(Some)
        }));
        match r {
            Ok(Ok(Some(n))) => {
                checks += n;
                ran += 1;
            }
            Ok(Ok(None)) => {}
            Ok(Err(e)) if e.starts_with("UNFIT ") => {
                unfit.push(format!("{}: {}", case.name, &e["UNFIT ".len()..]))
            }
            Ok(Err(e)) => failures.push(format!("{}:\n    {e}", case.name)),
            Err(p) => failures.push(format!("{}: PANIC: {}", case.name, panic_text(p))),
        }
    }
    println!(
        "{ran} of {} programs ran on pic16f876a with {checks} checks; {} do not fit:",
        cases.len(),
        unfit.len()
    );
    for u in &unfit {
        println!("  {u}");
    }
    let listed: Vec<&str> = PIC16_UNFIT
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty() && !l.starts_with('#'))
        .collect();
    let now: Vec<&str> = unfit.iter().map(String::as_str).collect();
    for u in &now {
        if !listed.contains(u) {
            failures.push(format!(
                "does not fit, but tests/pic16_unfit.txt does not say so: {u}"
            ));
        }
    }
    for l in &listed {
        if !now.contains(l) {
            failures.push(format!(
                "tests/pic16_unfit.txt lists what no longer happens: {l}"
            ));
        }
    }
    assert!(
        failures.is_empty(),
        "{} problems on pic16f876a:\n{}",
        failures.len(),
        failures.join("\n")
    );
}

/// SIZEOF is the size on the machine that runs the code, not one front-end number:
/// natural alignment on the host (interpreter, JIT, C on this machine), packed in
/// the VM's 16- and 32-bit modes and aligned to 4 in its mode 32a, and BOOL fields
/// eight to a byte on the PIC16 (docs/ir.md, `sizeof`).
#[test]
fn sizeof_is_each_targets_layout() {
    let src = "TYPE pair : STRUCT a : BOOL; c : BOOL; b : DINT; w : INT; END_STRUCT; END_TYPE\n\
               PROGRAM main\n\
               VAR x : pair; xs : ARRAY[1..3] OF pair; one, three : DINT; small : USINT; END_VAR\n\
               one := SIZEOF(x); three := SIZEOF(xs); small := SIZEOF(pair);\n\
               END_PROGRAM\n";
    let b = build_sources(
        vec![("sizeof.st".into(), src.as_bytes().to_vec())],
        &BuildOptions::default(),
    )
    .expect("builds");
    let module = b.module.expect("compiles");
    // (machine, SIZEOF(pair), SIZEOF(ARRAY[1..3] OF pair))
    let expected = [
        ("interp", 12, 36),
        ("host", 12, 36),
        ("c", 12, 36),
        ("vmasm", 8, 24),
        ("vmasm:mode=32", 8, 24),
        ("vmasm:mode=32a", 12, 36),
        ("pic16f876a", 7, 21),
    ];
    let mut failures = Vec::new();
    for (target, one, three) in expected {
        if targets::not_running().iter().any(|t| target.starts_with(t)) {
            skip::notice(&format!(
                "SIZEOF on `{target}`: it cannot run programs here"
            ));
            continue;
        }
        let mut m = machine(target, &module).unwrap_or_else(|e| panic!("{e}"));
        m.cold_start().expect("cold start");
        m.scan().expect("a scan");
        let got = ["main.one", "main.three", "main.small"]
            .map(|p| m.read(p).map_or_else(|e| e.to_string(), |v| v.to_string()));
        let want = [one, three, one].map(|n: u32| n.to_string());
        if got != want {
            failures.push(format!(
                "{target}: SIZEOF(x), SIZEOF(xs), SIZEOF(pair) are {got:?}, expected {want:?}"
            ));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// The dense CASEs of [`dense_case_is_a_jump_table_on_every_machine`]: an INT selector
/// with lists, a range, gaps and ELSE, an empty arm (its entries go straight to the
/// join, with the value before the CASE as a block argument); a SINT selector with
/// negative labels and no ELSE; a DINT one around a million with an overlap (the
/// first arm wins) and ELSE; a SINT whose `sel - min` wraps (-128 - 100 is 28, past
/// the table).
const DENSE_CASES: &str = "\
PROGRAM main
VAR_INPUT si : INT; ss : SINT; sd : DINT; END_VAR
VAR r_int : INT; r_sint : SINT; r_dint : DINT; r_wrap : SINT; END_VAR
r_int := si;
CASE si OF
    0: r_int := 10;
    1: r_int := 11;
    2, 3: r_int := 12;
    4..6: r_int := 13;
    10: ;
    9: r_int := 19;
ELSE
    r_int := -1;
END_CASE;
r_sint := 99;
CASE ss OF
    -5..-3: r_sint := 1;
    -2: r_sint := 2;
    -1, 1: r_sint := 3;
    0: r_sint := 4;
    3..4: r_sint := 5;
END_CASE;
CASE sd OF
    1000000..1000004: r_dint := 1;
    1000002: r_dint := 2;
    1000005, 1000007: r_dint := 3;
    999999: r_dint := 4;
ELSE
    r_dint := sd / 1000;
END_CASE;
CASE ss OF
    100..103: r_wrap := 1;
    110: r_wrap := 2;
    120..127: r_wrap := 3;
    104: r_wrap := 4;
ELSE
    r_wrap := -7;
END_CASE;
END_PROGRAM
";

/// What [`DENSE_CASES`] computes, by IEC 61131-3: `(r_int, r_sint, r_dint, r_wrap)`.
fn dense_cases_expected(si: i64, ss: i64, sd: i64) -> [i64; 4] {
    let r_int = match si {
        0 => 10,
        1 => 11,
        2 | 3 => 12,
        4..=6 => 13,
        10 => 10,
        9 => 19,
        _ => -1,
    };
    let r_sint = match ss {
        -5..=-3 => 1,
        -2 => 2,
        -1 | 1 => 3,
        0 => 4,
        3..=4 => 5,
        _ => 99,
    };
    let r_dint = match sd {
        1_000_000..=1_000_004 => 1,
        1_000_005 | 1_000_007 => 3,
        999_999 => 4,
        _ => sd / 1000, // truncates toward zero, as DIV does
    };
    let r_wrap = match ss {
        100..=103 => 1,
        110 => 2,
        120..=127 => 3,
        104 => 4,
        _ => -7,
    };
    [r_int, r_sint, r_dint, r_wrap]
}

/// Dense CASEs become jump tables (`br_table` in the IR; a Cranelift jump table on
/// the host, a `switch` in C, a binary search of compares on the VM and the PIC16)
/// and every machine gives every selector value the arm IEC 61131-3 says: all 256
/// SINTs, the INTs and DINTs around the labels and at the ends of their types.
#[test]
fn dense_case_is_a_jump_table_on_every_machine() {
    let b = build_sources(
        vec![("dense_case.st".into(), DENSE_CASES.as_bytes().to_vec())],
        &BuildOptions::default(),
    )
    .expect("builds");
    let module = b.module.expect("compiles");
    let ir = plcc_ir::text::print_module(&module, &plcc_ir::text::PrintOptions::default());
    assert_eq!(ir.matches("br_table").count(), 4, "{ir}");
    let ints = [-32768, -1, 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 32767];
    let dints = [
        i32::MIN as i64,
        -1_000_000,
        -1,
        0,
        999_998,
        999_999,
        1_000_000,
        1_000_002,
        1_000_004,
        1_000_005,
        1_000_006,
        1_000_007,
        1_000_008,
        1_000_255,
        i32::MAX as i64,
    ];
    let inputs: Vec<(i64, i64, i64)> = (0..256)
        .map(|k| (ints[k % ints.len()], k as i64 - 128, dints[k % dints.len()]))
        .collect();
    let mut failures = Vec::new();
    for target in [
        "interp",
        "host",
        "c",
        "vmasm:mode=16",
        "vmasm:mode=32",
        "vmasm:mode=32a",
        "pic16f876a",
    ] {
        if targets::not_running().iter().any(|t| target.starts_with(t)) {
            skip::notice(&format!(
                "dense CASE on `{target}`: it cannot run programs here"
            ));
            continue;
        }
        let mut m = machine(target, &module).unwrap_or_else(|e| panic!("{e}"));
        m.cold_start().expect("cold start");
        for &(si, ss, sd) in &inputs {
            m.write("main.si", PlcValue::from_i64(ElemType::Int, si))
                .unwrap();
            m.write("main.ss", PlcValue::from_i64(ElemType::SInt, ss))
                .unwrap();
            m.write("main.sd", PlcValue::from_i64(ElemType::DInt, sd))
                .unwrap();
            m.scan().expect("a scan");
            let got = ["main.r_int", "main.r_sint", "main.r_dint", "main.r_wrap"]
                .map(|p| m.read(p).expect("a variable").as_i64());
            let want = dense_cases_expected(si, ss, sd);
            if got != want {
                failures.push(format!(
                    "{target}: si = {si}, ss = {ss}, sd = {sd}: (r_int, r_sint, r_dint, r_wrap) are {got:?}, expected {want:?}"
                ));
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
