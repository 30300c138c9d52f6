//! Snapshots of the optimised IR of programs from `tests/programs/st/`, chosen to cover
//! different constructs: calls and parameter passing, FB instances, VAR_TEMP, initial
//! values, constant folding, integer division and comparisons (signed, unsigned),
//! TIME scaling, CASE (a compare chain; dense ones as jump tables), FOR, loops with
//! EXIT/CONTINUE, short-circuit operators, integer power, shifts and rotations,
//! selection functions, REAL to integer conversions, the standard timers and
//! counters, array bounds checks, 2-D arrays, bit access, REAL arithmetic and arrays
//! passed by reference.
//!
//! Review a change with `cargo insta review` (or `INSTA_UPDATE=always cargo test
//! --test ir_snapshots`, then read the `.snap` files): check that the IR is correct
//! and that the passes left nothing obviously foldable behind.

use plcc::driver::{build_sources, BuildOptions};
use plcc_ir::text::{print_module, PrintOptions};

/// The optimised IR of `tests/programs/st/<rel>` in the text form.
fn optimised_ir(rel: &str) -> String {
    let name = format!("tests/programs/st/{rel}");
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(&name);
    let bytes = std::fs::read(&path).unwrap_or_else(|e| panic!("cannot read {name}: {e}"));
    let build = build_sources(vec![(name.clone(), bytes)], &BuildOptions::default())
        .unwrap_or_else(|e| panic!("{name}: {}", e.0));
    let Some(module) = build.module else {
        let errors: Vec<String> = build.diagnostics.iter().map(|d| d.to_string()).collect();
        panic!("{name} does not compile:\n{}", errors.join("\n"));
    };
    print_module(&module, &PrintOptions::default())
}

macro_rules! snapshot {
    ($($test:ident => $rel:literal,)*) => {
        $(
            #[test]
            fn $test() {
                insta::assert_snapshot!(stringify!($test), optimised_ir($rel), $rel);
            }
        )*
    };
}

snapshot! {
    function_basic => "pou/function_basic.st",
    function_outputs => "pou/function_outputs.st",
    function_inout_swap => "pou/function_inout_swap.st",
    fb_call_forms => "pou/fb_call_forms.st",
    var_temp => "pou/var_temp.st",
    initial_values => "pou/initial_values.st",
    var_constant => "pou/var_constant.st",
    signed_div_mod => "types/signed_div_mod.st",
    unsigned_compare_div => "types/unsigned_compare_div.st",
    time_arith => "types/time_arith.st",
    case_basic => "stmt/case_basic.st",
    case_dense => "stmt/case_dense.st",
    for_steps => "stmt/for_steps.st",
    exit_continue => "stmt/exit_continue.st",
    short_circuit => "ops/short_circuit.st",
    precedence => "ops/precedence.st",
    power => "ops/power.st",
    shift_byte_word => "stdfn/shift_byte_word.st",
    selection => "stdfn/selection.st",
    mux => "stdfn/mux.st",
    conv_real_to_int => "stdfn/conv_real_to_int.st",
    ton => "stdfb/ton.st",
    ctud => "stdfb/ctud.st",
    array_oob => "arrays/array_oob.st",
    array_2d => "arrays/array_2d.st",
    bit_access => "bits/bit_access.st",
    pi_control => "apps/pi_control.st",
    sort_readings => "apps/sort_readings.st",
}
