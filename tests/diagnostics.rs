//! Malformed programs and their diagnostics.
//!
//! Every file in `tests/bad/` is a malformed program in one of four languages, told by
//! its extension (as `plcc` tells it): `NAME.st` Structured Text, `il_NAME.il`
//! Instruction List, `stl_NAME.stl` PLC-UD STL, `ld_NAME.xml` a ladder diagram in
//! PLCopen XML. The `il_`, `stl_` and `ld_` prefixes are required, so that a test's
//! name (the file's stem) says which file it builds and no two files share a snapshot.
//! Every file starts with a comment (`(* *)`, or `<!-- -->` in XML) saying what is
//! wrong and which diagnostic codes it must produce:
//!
//! ```text
//! (* expect: E0102 x1, E0101 x2 — what is wrong *)
//! (* with: other.st *)              (optional: files built together with this one)
//! <!-- expect: E0744 x2 — what is wrong -->
//! ```
//!
//! The codes before the `—` must be exactly the set of codes the build reports
//! (errors and warnings); `xN` after a code says it is reported exactly N times. A
//! file whose codes are all warnings must still compile. The rendered diagnostics are
//! snapshotted as `snapshots/diagnostics__STEM.snap`, with the files named
//! `tests/bad/STEM.EXT` so that the snapshots are the same on every machine.
//!
//! Every code of the IL, STL and ladder front ends (`E070x`–`E071x`, `E072x`–`E073x`,
//! `E074x`–`E075x`, `W070x`) must be expected by at least one file, except those
//! listed in [`UNTRIGGERABLE`]. A ladder file's rung errors must name the POU, the rung
//! and the element's localId.
//!
//! Review a change with `cargo insta review` (or `INSTA_UPDATE=always cargo test --test
//! diagnostics`, then read the `.snap` files): each message must say what is wrong,
//! each caret must point at the culprit, and no error may be a consequence of another.
//!
//! The last tests run the `plcc` binary and check its exit statuses: 0 when there are
//! only warnings, 1 when the program has errors, 2 for usage errors.

use plcc::driver::{build_sources, BuildOptions};
use plcc_ir::diag::Severity;
use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use std::process::Output;

#[path = "common/cli.rs"]
#[allow(dead_code)]
mod cli;
use cli::{plcc, stderr};

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// What a file's `expect:` comment asks for.
#[derive(Debug)]
struct Expect {
    /// The first line, shown in the snapshot.
    header: String,
    /// Every expected code with its count, if the comment gives one.
    codes: BTreeMap<String, Option<usize>>,
    /// Files built together with this one (`with:`).
    with: Vec<String>,
}

fn is_code(s: &str) -> bool {
    let b = s.as_bytes();
    b.len() == 5 && (b[0] == b'E' || b[0] == b'W') && b[1..].iter().all(u8::is_ascii_digit)
}

/// Parses the `expect:` line (the first) and the optional `with:` line (the second).
fn parse_expect(name: &str, text: &str) -> Expect {
    let mut lines = text.lines();
    let header = lines.next().unwrap_or("").trim().to_string();
    let spec = header
        .strip_prefix("(* expect:")
        .or_else(|| header.strip_prefix("<!-- expect:"))
        .unwrap_or_else(|| {
            panic!("{name}: the first line must be `(* expect: CODES — what is wrong *)`")
        });
    let spec = spec
        .split_once('—')
        .unwrap_or_else(|| {
            panic!("{name}: the expect line needs `—` between the codes and the description")
        })
        .0;
    let mut codes = BTreeMap::new();
    let mut last: Option<String> = None;
    for tok in spec.split([' ', ',']).filter(|t| !t.is_empty()) {
        if is_code(tok) {
            assert!(
                codes.insert(tok.to_string(), None).is_none(),
                "{name}: {tok} is listed twice"
            );
            last = Some(tok.to_string());
        } else if let Some(n) = tok.strip_prefix('x').and_then(|n| n.parse::<usize>().ok()) {
            let code = last
                .take()
                .unwrap_or_else(|| panic!("{name}: `{tok}` does not follow a code"));
            codes.insert(code, Some(n));
        } else {
            panic!("{name}: `{tok}` in the expect line is neither a code nor a count `xN`");
        }
    }
    assert!(!codes.is_empty(), "{name}: the expect line lists no code");
    let with = match lines.next().map(str::trim).and_then(|l| {
        l.strip_prefix("(* with:")
            .or_else(|| l.strip_prefix("<!-- with:"))
    }) {
        Some(rest) => rest
            .trim_end_matches("*)")
            .trim_end_matches("-->")
            .split([' ', ','])
            .filter(|t| !t.is_empty())
            .map(str::to_string)
            .collect(),
        None => Vec::new(),
    };
    Expect {
        header,
        codes,
        with,
    }
}

/// The file of the test `name`: `il_*` is Instruction List, `stl_*` PLC-UD STL,
/// `ld_*` a ladder diagram in PLCopen XML, anything else Structured Text.
fn bad_file(name: &str) -> String {
    let ext = if name.starts_with("il_") {
        "il"
    } else if name.starts_with("stl_") {
        "stl"
    } else if name.starts_with("ld_") {
        "xml"
    } else {
        "st"
    };
    format!("{name}.{ext}")
}

/// The extensions of the files in `tests/bad/`, one per language.
const EXTENSIONS: &[&str] = &["st", "il", "stl", "xml"];

/// The codes of the rung checks, whose messages must name the POU, the rung and the
/// element (`in rung 2 of `main``, `(localId 7)`).
const RUNG_CODES: &[&str] = &[
    "E0743", "E0744", "E0745", "E0746", "E0747", "E0748", "E0749", "E0750",
];

/// The ladder files that break the ladder editor's style rules: warnings by default,
/// built here with `--strict-rungs`, which makes them errors
/// ([`style_rules_are_warnings_by_default`] builds them without).
const STRICT_RUNGS: &[&str] = &[
    "ld_bridge",
    "ld_open_circuit",
    "ld_short_circuit",
    "ld_upper_parallel",
    "ld_coil_on_rail",
    "ld_block_input",
];

/// Ladder files built under the OpenPLC Editor v3 profile (`--plcopen-order openplc3`).
const OPENPLC3: &[&str] = &["ld_jump_ignored"];

/// Files built in the CODESYS dialect (`--dialect codesys`).
const CODESYS: &[&str] = &["codesys_write_internal", "codesys_program_instances"];

fn read_bad(file: &str) -> (String, Vec<u8>) {
    let rel = format!("tests/bad/{file}");
    let bytes =
        std::fs::read(root().join(&rel)).unwrap_or_else(|e| panic!("cannot read {rel}: {e}"));
    (rel, bytes)
}

/// Builds the file of the test `name` (with its companions) and checks it against its
/// `expect:` comment and its snapshot.
fn check_bad(name: &str) {
    let (rel, bytes) = read_bad(&bad_file(name));
    let text = String::from_utf8_lossy(&bytes).into_owned();
    let expect = parse_expect(&rel, &text);
    let mut inputs = vec![(rel.clone(), bytes)];
    inputs.extend(expect.with.iter().map(|f| read_bad(f)));

    let mut opts = BuildOptions::default();
    opts.plcopen.strict_rungs = STRICT_RUNGS.contains(&name);
    if OPENPLC3.contains(&name) {
        opts.plcopen.profile = plcc_frontend::plcopen::Profile::Openplc3;
    }
    opts.codesys = CODESYS.contains(&name);
    let build = std::panic::catch_unwind(|| build_sources(inputs, &opts))
        .unwrap_or_else(|_| panic!("{rel}: plcc panicked"))
        .unwrap_or_else(|e| panic!("{rel}: {e}"));
    let rendered = plcc::render::render(&build.sources, &build.diagnostics);

    let mut got: BTreeMap<String, usize> = BTreeMap::new();
    for d in &build.diagnostics {
        *got.entry(d.code.to_string()).or_default() += 1;
    }
    let want: BTreeSet<&String> = expect.codes.keys().collect();
    let have: BTreeSet<&String> = got.keys().collect();
    assert_eq!(
        have, want,
        "{rel}: the codes reported differ from the expect line; the diagnostics:\n{rendered}"
    );
    for (code, count) in &expect.codes {
        if let Some(n) = count {
            assert_eq!(
                got[code], *n,
                "{rel}: {code} reported {} time(s), expected {n}:\n{rendered}",
                got[code]
            );
        }
    }
    for d in &build.diagnostics {
        if RUNG_CODES.contains(&d.code) {
            let named = d.message.contains("rung ")
                && d.message.contains("(localId ")
                && d.message.contains(" of `");
            assert!(
                named,
                "{rel}: a rung error must name the POU, the rung and the localId: {}",
                d.message
            );
            let in_xml = d
                .span
                .is_some_and(|sp| build.sources.get(sp.file).name == rel);
            assert!(in_xml, "{rel}: a rung error must point into the XML: {d:?}");
        }
    }
    let errors = build
        .diagnostics
        .iter()
        .any(|d| d.severity == Severity::Error);
    assert_eq!(
        build.failed(),
        errors,
        "{rel}: the build must fail exactly when there are errors:\n{rendered}"
    );

    insta::with_settings!({ description => expect.header.as_str(), omit_expression => true }, {
        insta::assert_snapshot!(name, rendered);
    });
}

/// Without `--strict-rungs`, a rung that breaks a style rule compiles, with the same
/// codes as warnings: the editors accept and run such rungs.
#[test]
fn style_rules_are_warnings_by_default() {
    for name in STRICT_RUNGS {
        let (rel, bytes) = read_bad(&bad_file(name));
        let build = build_sources(vec![(rel.clone(), bytes)], &BuildOptions::default())
            .unwrap_or_else(|e| panic!("{rel}: {e}"));
        let rendered = plcc::render::render(&build.sources, &build.diagnostics);
        assert!(!build.failed(), "{rel} must compile:\n{rendered}");
        assert!(
            !build.diagnostics.is_empty()
                && build
                    .diagnostics
                    .iter()
                    .all(|d| d.severity == Severity::Warning && RUNG_CODES.contains(&d.code)),
            "{rel}: expected rung warnings only:\n{rendered}"
        );
    }
}

macro_rules! bad {
    ($($name:ident,)*) => {
        $(
            #[test]
            fn $name() {
                check_bad(stringify!($name));
            }
        )*
        /// The names of all the tests above.
        const ALL_BAD: &[&str] = &[$(stringify!($name)),*];
    };
}

bad! {
    // sequential function charts
    sfc_errors,
    // lexical
    lex_bad_char,
    lex_unterminated_comment,
    lex_c_pragma,
    lex_unterminated_c_pragma,
    lex_unterminated_string,
    lex_bad_based_number,
    lex_bad_duration,
    lex_bad_escape,
    lex_bad_date,
    lex_bad_typed_literal,
    lex_bad_address,
    // a file that declares nothing
    nothing_to_compile,
    // declarations
    decl_anonymous_location,
    decl_reversed_bounds,
    decl_edge_misuse,
    decl_array_bounds_overflow,
    decl_constant_from_variable,
    lex_int_too_large,
    lex_several_errors,
    // syntax
    syn_missing_semicolon,
    syn_missing_end_if,
    syn_missing_end_while,
    syn_missing_end_var,
    syn_missing_end_program,
    syn_equals_for_assign,
    syn_stray_end_for,
    syn_garbage_expression,
    syn_missing_then,
    syn_missing_do,
    syn_unbalanced_parens,
    syn_call_missing_paren,
    syn_extra_paren,
    syn_else_if,
    syn_keyword_as_name,
    syn_several_errors,
    syn_too_deep,
    // names and declarations
    name_undeclared_variable,
    name_undeclared_function,
    name_duplicate_variable,
    name_duplicate_pou_a,
    name_duplicate_pou_b,
    name_unknown_type,
    name_unknown_blocks,
    name_unknown_library_type,
    name_external_without_global,
    type_external_mismatch,
    name_fb_contains_itself,
    name_program_as_type,
    name_fb_type_called,
    name_unknown_fb_member,
    name_fb_internal_var,
    name_program_variable,
    name_unknown_parameter,
    name_assign_to_function,
    name_struct_no_field,
    name_type_contains_itself,
    name_type_duplicate,
    name_enum_unknown_value,
    // types
    type_int_from_dint,
    type_bool_arithmetic,
    type_int_literal_to_bool,
    type_real_literal_to_int,
    type_literal_out_of_range,
    type_time_vs_int,
    type_if_on_int,
    type_case_on_real,
    type_case_overlap,
    type_for_real_var,
    type_for_bool_var,
    type_array_real_index,
    type_array_index_count,
    type_sqrt_int,
    type_real_function_of_literal_to_int,
    type_cur_time_to_dint,
    type_several_errors,
    type_for_bad_header_body,
    type_scalar_to_array,
    type_int_literal_to_time,
    type_struct_compare,
    type_string_compare_function,
    type_struct_mismatch,
    type_enum_mismatch,
    type_enum_ambiguous,
    type_enum_shadowed_value,
    type_enum_case_label,
    type_enum_value_out_of_range,
    type_subrange_out_of_range,
    // calls
    call_limit_too_many,
    call_limit_too_few,
    call_mixed_positional_named,
    call_output_arrow_on_input,
    call_assign_on_output,
    call_missing_in_out,
    call_expression_to_in_out,
    call_fb_call_as_value,
    call_no_result_as_value,
    call_action_arguments,
    // writing, loops, recursion
    write_constant,
    write_fb_output,
    write_fb_output_instance,
    write_exit_outside_loop,
    write_for_step_zero,
    write_recursion_direct,
    write_recursion_mutual,
    write_recursion_action,
    // the CODESYS dialect
    codesys_write_internal,
    codesys_program_instances,
    // object orientation
    oo_declarations,
    oo_abstract,
    oo_final,
    oo_access,
    oo_recursion,
    oo_abstract_instance,
    oo_abstract_unimplemented,
    oo_extends_final,
    oo_interface_unimplemented,
    oo_not_implementing,
    oo_override_final,
    oo_private_call,
    oo_class,
    oo_protected_access,
    oo_super_without_base,
    oo_unknown_method,
    // not supported yet
    string_width_mismatch,
    string_selection_mismatch,
    string_capacity_range,
    string_inout_too_short,
    string_number_mix,
    ref_of_temporary,
    ref_type_mismatch,
    partial_access_range,
    date_arith_mismatch,
    time_function_mismatch,
    bcd_mismatch,
    unsup_struct_copy_fb,
    unsup_var_global_in_pou,
    config_errors,
    prototypes,
    cascade_unknown_type,
    cascade_broken_statement,
    cascade_undeclared_uses,
    cascade_missing_end_if,
    cascade_unknown_fb_instance,
    il_cascade_undeclared,
    stl_cascade_undeclared,
    // warnings
    warn_write_own_input,
    warn_std_fb_redeclared,
    // Instruction List: instructions and their operands
    il_malformed,
    il_missing_operand,
    il_operand_not_allowed,
    il_not_with_operand,
    il_c_pragma,
    il_bad_modifier,
    il_bad_operand,
    il_unknown_operator,
    // Instruction List: deferred operations `op(` ... `)`
    il_unmatched_close,
    il_unclosed_paren,
    il_not_in_parens,
    il_too_deep,
    // Instruction List: the current result
    il_and_on_int,
    il_add_on_bool,
    il_cr_undefined,
    il_function_result_not_set,
    // Instruction List: labels, names, calls, stores
    il_unknown_label,
    il_duplicate_label,
    il_undeclared_variable,
    il_cal_not_instance,
    il_wrong_parameter_name,
    il_test_not_bool,
    il_set_not_bool,
    il_cal_function,
    il_void_result_read,
    il_result_after_label,
    il_store_to_constant,
    il_store_to_input,
    il_store_to_fb_output,
    il_several_errors,
    il_several_type_errors,
    // PLC-UD STL: lexical
    stl_lexical,
    stl_unterminated_comment,
    // PLC-UD STL: syntax
    stl_missing_semicolon,
    stl_equals_for_assign,
    stl_missing_then,
    stl_chained_comparison,
    stl_missing_begin,
    stl_missing_end_dot,
    stl_unclosed_block,
    stl_text_after_end,
    stl_too_deep,
    stl_several_errors,
    // PLC-UD STL: declarations
    stl_constant_before_var,
    stl_var_after_statement,
    stl_subprogram_after_begin,
    stl_constant_without_value,
    stl_result_type,
    stl_unknown_type,
    // PLC-UD STL: names, types, calls
    stl_undeclared_variable,
    stl_bool_to_int,
    stl_wrong_arg_count,
    stl_procedure_in_expression,
    stl_too_few_arguments,
    call_too_few_positional,
    stl_procedure_as_value,
    stl_several_type_errors,
    // Ladder diagrams (PLCopen XML): the file
    ld_malformed_xml,
    ld_not_plcopen,
    ld_sfc_body,
    ld_jump_ignored,
    ld_pous_in_add_data,
    ld_var_list,
    ld_sfc_action,
    ld_sfc_transition,
    ld_action_of_function,
    ld_bad_element,
    ld_duplicate_id,
    ld_edge_in_function,
    // Ladder diagrams: the rung checks
    ld_dangling,
    ld_open_circuit,
    ld_short_circuit,
    ld_upper_parallel,
    ld_bridge,
    ld_coil_on_rail,
    ld_block_input,
    ld_loop,
    // Ladder diagrams: the conversion, and errors of the IL made from a ladder
    ld_output_type,
    ld_undeclared,
    ld_unknown_blocks,
}

/// Every file in `tests/bad/` has its test above, and every test its file.
#[test]
fn every_bad_file_is_tested() {
    let mut files: Vec<String> = Vec::new();
    for e in std::fs::read_dir(root().join("tests/bad")).expect("tests/bad") {
        let path = e.expect("directory entry").path();
        let Some(ext) = path.extension().and_then(|x| x.to_str()) else {
            continue;
        };
        if !EXTENSIONS.contains(&ext) {
            continue;
        }
        let stem = path.file_stem().unwrap().to_string_lossy().into_owned();
        // The stem tells the language: `il_` for .il, `stl_` for .stl, neither for
        // .st. So no two files share a stem, hence a test or a snapshot.
        assert_eq!(
            bad_file(&stem),
            format!("{stem}.{ext}"),
            "tests/bad/{stem}.{ext}: .il files are named il_*, .stl files stl_*, .xml \
             files ld_*, and .st files none of these"
        );
        files.push(stem);
    }
    files.sort();
    let mut listed: Vec<String> = ALL_BAD.iter().map(|s| s.to_string()).collect();
    listed.sort();
    assert_eq!(
        files, listed,
        "tests/bad/*.{{st,il,stl,xml}} and the list in tests/diagnostics.rs differ"
    );
    // No snapshot outlives its file.
    for e in std::fs::read_dir(root().join("tests/snapshots")).expect("tests/snapshots") {
        let name = e
            .expect("directory entry")
            .file_name()
            .to_string_lossy()
            .into_owned();
        if let Some(stem) = name
            .strip_prefix("diagnostics__")
            .and_then(|n| n.strip_suffix(".snap"))
        {
            assert!(
                listed.iter().any(|l| l == stem),
                "tests/snapshots/{name} has no tests/bad/{}",
                bad_file(stem)
            );
        }
    }
}

/// Codes of the IL, STL and ladder front ends that no program can trigger (none
/// today).
const UNTRIGGERABLE: &[&str] = &[];

/// True for a code of the IL front end (`E070x`, `E071x`, `W070x`), of the STL front
/// end (`E072x`, `E073x`) or of the ladder front end (`E074x`, `E075x`, and E0602, a
/// body language it does not compile).
fn is_il_or_stl_code(code: &str) -> bool {
    [
        "E070", "E071", "E072", "E073", "E074", "E075", "W070", "E0602",
    ]
    .iter()
    .any(|p| code.starts_with(p))
}

/// Every code of the IL, STL and ladder front ends is expected by some file of
/// `tests/bad/`.
#[test]
fn every_il_and_stl_code_is_covered() {
    let mut expected = BTreeSet::new();
    for name in ALL_BAD {
        let (rel, bytes) = read_bad(&bad_file(name));
        expected.extend(
            parse_expect(&rel, &String::from_utf8_lossy(&bytes))
                .codes
                .into_keys(),
        );
    }
    let missing: Vec<&str> = plcc_frontend::codes::ALL
        .iter()
        .map(|c| c.code)
        .filter(|c| is_il_or_stl_code(c) && !UNTRIGGERABLE.contains(c))
        .filter(|c| !expected.contains(*c))
        .collect();
    assert!(
        missing.is_empty(),
        "no file in tests/bad/ expects {missing:?}: add one, or list the code in UNTRIGGERABLE"
    );
}

/// Every code a file expects is a code `plcc explain` knows.
#[test]
fn expected_codes_exist() {
    for name in ALL_BAD {
        let (rel, bytes) = read_bad(&bad_file(name));
        let expect = parse_expect(&rel, &String::from_utf8_lossy(&bytes));
        for code in expect.codes.keys() {
            assert!(
                plcc_frontend::codes::lookup(code).is_some(),
                "{rel}: no code {code} in the catalogue"
            );
        }
    }
}

// ---------------------------------------------------------------- the binary

/// Runs `plcc` in the crate's root, so that `tests/bad/...` paths work.
fn status(o: &Output) -> i32 {
    o.status.code().expect("plcc was killed by a signal")
}

/// A fresh directory for one test's files.
fn scratch(test: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("diagnostics-{test}"));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("cannot create a scratch directory");
    dir
}

const BAD: &str = "tests/bad/type_int_from_dint.st";
const WARN_ONLY: &str = "tests/bad/warn_write_own_input.st";

#[test]
fn exit_1_on_errors() {
    for args in [
        &["check", BAD][..],
        &["run", BAD, "--target", "interp"],
        &["run", BAD],
        &["--emit", "ir", BAD],
        &["--target", "interp", BAD],
        &[BAD, "-o", "-"],
    ] {
        let o = plcc(args);
        let err = stderr(&o);
        assert_eq!(status(&o), 1, "plcc {args:?}: stderr:\n{err}");
        assert!(
            err.contains("error[E0301]"),
            "plcc {args:?}: stderr:\n{err}"
        );
        assert!(
            err.contains("could not compile: 1 error(s)"),
            "plcc {args:?}: stderr:\n{err}"
        );
        assert!(o.stdout.is_empty(), "plcc {args:?} printed to stdout");
    }
}

#[test]
fn exit_1_on_errors_in_test() {
    let dir = scratch("exit_1_on_errors_in_test");
    let scenario = dir.join("s.expect");
    std::fs::write(&scenario, "# corpus-expect v1\nrun 1\n").unwrap();
    let o = plcc(&[
        "test",
        BAD,
        "--scenario",
        scenario.to_str().unwrap(),
        "--target",
        "interp",
    ]);
    assert_eq!(status(&o), 1, "stderr:\n{}", stderr(&o));
    assert!(
        stderr(&o).contains("error[E0301]"),
        "stderr:\n{}",
        stderr(&o)
    );
}

#[test]
fn exit_0_with_only_warnings() {
    for args in [
        &["check", WARN_ONLY][..],
        &["run", WARN_ONLY, "--target", "interp"],
        &["run", WARN_ONLY],
    ] {
        let o = plcc(args);
        let err = stderr(&o);
        assert_eq!(status(&o), 0, "plcc {args:?}: stderr:\n{err}");
        assert!(
            err.contains("warning[W0502]"),
            "plcc {args:?}: stderr:\n{err}"
        );
        assert!(!err.contains("error"), "plcc {args:?}: stderr:\n{err}");
    }
    // The program ran: the instance clamps -5 to 0, the function -7 to 0.
    let o = plcc(&["run", WARN_ONLY, "--target", "interp"]);
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(out.lines().any(|l| l == "r = 0"), "{out}");
    assert!(out.lines().any(|l| l == "s = 0"), "{out}");
}

/// The binary tells IL, STL, CPDev ST and ladder files by their extension and exits as
/// for ST.
#[test]
fn exit_statuses_of_il_and_stl() {
    for (file, status_want, code) in [
        ("tests/bad/il_and_on_int.il", 1, "error[E0301]"),
        ("tests/bad/stl_missing_semicolon.stl", 1, "error[E0724]"),
        ("tests/bad/ld_bridge.xml", 1, "error[E0747]"),
        ("tests/bad/ld_malformed_xml.xml", 1, "error[E0740]"),
        ("tests/programs/ld/motor_start_stop.xml", 0, ""),
        ("tests/bad/il_not_with_operand.il", 0, "warning[W0703]"),
        ("tests/programs/st/cpdev/dialect.cst", 0, "warning[W0208]"),
    ] {
        let o = plcc(&["check", "--strict-rungs", file]);
        let err = stderr(&o);
        assert_eq!(status(&o), status_want, "plcc check {file}: stderr:\n{err}");
        assert!(err.contains(code), "plcc check {file}: stderr:\n{err}");
    }
}

#[test]
fn exit_2_on_usage_errors() {
    let cases: &[(&[&str], &str)] = &[
        (
            &["check", "tests/bad/no_such_file.st"],
            "cannot read tests/bad/no_such_file.st",
        ),
        (&["tests/bad/no_such_file.st"], "cannot read"),
        (&["run", "tests/bad/no_such_file.st"], "cannot read"),
        (&["check", "--no-such-option", BAD], "--no-such-option"),
        (&["--no-such-option", BAD], "--no-such-option"),
        (
            &["check", "--lang", "cobol", BAD],
            "unknown language `cobol`",
        ),
        (&["--lang", "cobol", BAD], "unknown language `cobol`"),
        (&["check"], "no input files"),
        (&["explain", "E9999"], "no diagnostic code `E9999`"),
    ];
    for (args, msg) in cases {
        let o = plcc(args);
        let err = stderr(&o);
        assert_eq!(status(&o), 2, "plcc {args:?}: stderr:\n{err}");
        assert!(
            err.contains(msg),
            "plcc {args:?}: expected `{msg}` in stderr:\n{err}"
        );
    }
    // A file whose language cannot be told from its extension.
    let dir = scratch("exit_2_on_usage_errors");
    let txt = dir.join("prog.txt");
    std::fs::copy(root().join(BAD), &txt).unwrap();
    let o = plcc(&["check", txt.to_str().unwrap()]);
    assert_eq!(status(&o), 2, "stderr:\n{}", stderr(&o));
    assert!(
        stderr(&o).contains("cannot tell the language"),
        "stderr:\n{}",
        stderr(&o)
    );
    // ... unless --lang tells it: then the file's errors give 1.
    let o = plcc(&["check", "--lang", "st", txt.to_str().unwrap()]);
    assert_eq!(status(&o), 1, "stderr:\n{}", stderr(&o));
}

#[test]
fn explain_prints_the_explanation() {
    let o = plcc(&["explain", "E0301"]);
    assert_eq!(status(&o), 0, "stderr:\n{}", stderr(&o));
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(out.starts_with("E0301: type mismatch\n"), "stdout:\n{out}");
    assert!(out.contains("DINT_TO_INT"), "stdout:\n{out}");
    // Codes ignore case.
    let o = plcc(&["explain", "w0502"]);
    assert_eq!(status(&o), 0);
    assert!(String::from_utf8_lossy(&o.stdout).starts_with("W0502: assignment to an input"));
}

/// Every code that a bad file expects can be explained by the binary.
#[test]
fn explain_knows_every_expected_code() {
    let mut all = BTreeSet::new();
    for name in ALL_BAD {
        let (rel, bytes) = read_bad(&bad_file(name));
        all.extend(
            parse_expect(&rel, &String::from_utf8_lossy(&bytes))
                .codes
                .into_keys(),
        );
    }
    for code in all {
        let o = plcc(&["explain", &code]);
        assert_eq!(status(&o), 0, "plcc explain {code}");
        assert!(String::from_utf8_lossy(&o.stdout).starts_with(&format!("{code}: ")));
    }
}

/// A failed build writes nothing: an existing output file keeps its contents.
#[test]
fn failed_build_leaves_output_untouched() {
    let dir = scratch("failed_build_leaves_output_untouched");
    let before = b"previous contents\n";
    for (emit, name) in [
        (Some("ir"), "out.ir"),
        (Some("ir-raw"), "raw.ir"),
        (None, "out.o"),
    ] {
        let out = dir.join(name);
        std::fs::write(&out, before).unwrap();
        let mut args = Vec::new();
        if let Some(e) = emit {
            args.extend(["--emit", e]);
        }
        args.extend([BAD, "-o", out.to_str().unwrap()]);
        let o = plcc(&args);
        assert_eq!(status(&o), 1, "plcc {args:?}: stderr:\n{}", stderr(&o));
        assert_eq!(
            std::fs::read(&out).unwrap(),
            before,
            "plcc {args:?} changed {name}"
        );
    }
    // No temporary file is left behind either.
    let names: BTreeSet<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(
        names,
        ["out.ir", "out.o", "raw.ir"].map(String::from).into()
    );
    // The same command on a good program does write the file.
    let good = dir.join("good.st");
    std::fs::write(
        &good,
        "PROGRAM main VAR n : INT; END_VAR n := n + 1; END_PROGRAM\n",
    )
    .unwrap();
    let out = dir.join("out.ir");
    let o = plcc(&[
        "--emit",
        "ir",
        good.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(status(&o), 0, "stderr:\n{}", stderr(&o));
    assert_ne!(std::fs::read(&out).unwrap(), before);
}

/// Files built together: the duplicate is reported once, in whichever order they come.
#[test]
fn binary_reports_duplicate_across_files() {
    for files in [
        [
            "tests/bad/name_duplicate_pou_a.st",
            "tests/bad/name_duplicate_pou_b.st",
        ],
        [
            "tests/bad/name_duplicate_pou_b.st",
            "tests/bad/name_duplicate_pou_a.st",
        ],
    ] {
        let o = plcc(&["check", files[0], files[1]]);
        let err = stderr(&o);
        assert_eq!(status(&o), 1, "stderr:\n{err}");
        assert_eq!(err.matches("error[E0202]").count(), 1, "stderr:\n{err}");
        // Each file alone is fine.
        assert_eq!(status(&plcc(&["check", files[0]])), 0);
    }
}

/// Output piped into a reader that stops early (`plcc run big.st | head -1`) ends
/// the program quietly, with no panic about a broken pipe.
#[test]
fn a_closed_output_pipe_is_no_panic() {
    use std::io::Read;
    use std::process::{Command, Stdio};
    let dir = std::env::temp_dir().join(format!("plcc-pipe-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let src = dir.join("big.st");
    // 20,001 lines of output: more than a pipe holds.
    std::fs::write(
        &src,
        "PROGRAM big\nVAR a : ARRAY[0..20000] OF INT; END_VAR\n    a[0] := 1;\nEND_PROGRAM\n",
    )
    .unwrap();
    let mut child = Command::new(env!("CARGO_BIN_EXE_plcc"))
        .args(["run", src.to_str().unwrap()])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("plcc runs");
    let mut first = [0u8; 8];
    child
        .stdout
        .take()
        .expect("stdout")
        .read_exact(&mut first)
        .expect("some output");
    // The read end is closed here, long before plcc has written everything.
    let out = child.wait_with_output().expect("plcc ends");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!err.contains("panicked"), "{err}");
    assert_eq!(&first, b"a[0] = 1");
}

/// `docs/diagnostics.md` is the catalogue of every code, generated from the code
/// tables; `PLCC_BLESS=1` rewrites it. Every code is listed once.
#[test]
fn diagnostics_catalogue() {
    let want = plcc::commands::diagnostics_markdown();
    let path = root().join("docs/diagnostics.md");
    if std::env::var_os("PLCC_BLESS").is_some() {
        std::fs::write(&path, &want).unwrap();
    }
    let have = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        have == want,
        "docs/diagnostics.md is not current: run PLCC_BLESS=1 cargo test --test diagnostics diagnostics_catalogue"
    );
    let mut codes: Vec<&str> = want
        .lines()
        .filter_map(|l| l.strip_prefix("## "))
        .map(|l| l.split(' ').next().unwrap())
        .collect();
    let n = codes.len();
    codes.sort();
    codes.dedup();
    assert_eq!(codes.len(), n, "a code is used twice");
    assert!(n > 90, "{n} codes");
    // Each entry shows an example (an indented snippet, or one in the text), or says
    // why it has none.
    let without: Vec<&str> = want
        .split("\n## ")
        .skip(1)
        .filter(|e| !(e.contains("\n    ") || e.contains("xample") || e.contains("e.g.")))
        .map(|e| e.split(' ').next().unwrap())
        .collect();
    assert!(without.is_empty(), "codes without an example: {without:?}");
}

/// Codes the command line gives rather than a file: a PROGRAM that is not declared
/// (E0208), and a file read in a language it is not written in (an ST file as
/// PLCopen XML: E0740), both exit status 1.
#[test]
fn command_line_codes() {
    let o = plcc(&[
        "--emit",
        "ir",
        "--program",
        "nope",
        "examples/traffic_light.st",
    ]);
    assert_eq!(status(&o), 1);
    assert!(stderr(&o).contains("error[E0208]: there is no PROGRAM named `nope`"));
    let o = plcc(&["check", "--lang", "xml", "examples/traffic_light.st"]);
    assert_eq!(status(&o), 1);
    assert!(stderr(&o).contains("error[E0740]"), "{}", stderr(&o));
    // An unknown dialect is a usage error.
    let o = plcc(&["check", "--dialect", "turbo", "examples/traffic_light.st"]);
    assert_eq!(status(&o), 2);
    assert!(
        stderr(&o).contains("unknown dialect `turbo`"),
        "{}",
        stderr(&o)
    );
    let o = plcc(&["check", "--dialect", "codesys", "examples/traffic_light.st"]);
    assert_eq!(status(&o), 0, "{}", stderr(&o));
}

/// Data over the 1 GiB the host's JIT and the interpreter hold is a diagnostic of the
/// program (E8006 on the host, E9903 on the interpreter), found before anything is
/// allocated, not an internal error.
#[test]
fn data_too_large_to_run() {
    let dir = std::env::temp_dir().join(format!("plcc-big-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let src = dir.join("big.st");
    // Fourteen arrays of 10 million LREALs: 1.12 GB.
    let decls: String = (0..14)
        .map(|i| format!("a{i} : ARRAY[0..9999999] OF LREAL; "))
        .collect();
    std::fs::write(
        &src,
        format!("PROGRAM big\nVAR {decls}END_VAR\n    a0[1] := 2.0;\nEND_PROGRAM\n"),
    )
    .unwrap();
    for (target, code) in [("host", "E8006"), ("interp", "E9903")] {
        let o = plcc(&["run", "--target", target, src.to_str().unwrap()]);
        assert_eq!(status(&o), 1, "{target}: {}", stderr(&o));
        assert!(
            stderr(&o).contains(&format!("error[{code}]: the program's data takes 1120")),
            "{target}: {}",
            stderr(&o)
        );
    }
}

/// A machine for a target that has none is E9902; a module the interpreter cannot
/// load (a STRUCT containing itself, which no front end makes) is an internal error,
/// E9901.
#[test]
fn machine_setup_codes() {
    let m = plcc_ir::text::parse_module(
        "struct %p program {
    var x: i16 INT
}

data @p: %p program

func @p(ptr) program {
block0(v0: ptr):
    return
}

func @p$init(ptr) init {
block0(v0: ptr):
    return
}

program \"p\" data @p body @p init @p$init
",
    )
    .expect("parses");
    assert!(plcc::targets::machine("interp", &m).is_ok());
    let Err(ds) = plcc::targets::machine("plc5", &m) else {
        panic!("a machine for an unknown target")
    };
    assert_eq!(ds[0].code, "E9902");
    assert_eq!(ds[0].message, "target `plc5` cannot run programs here");
    let mut broken = m.clone();
    broken.aggs[0] = plcc_ir::AggDef::Struct(plcc_ir::StructDef {
        name: "p".into(),
        kind: plcc_ir::StructKind::Program,
        fields: vec![plcc_ir::Field {
            name: "me".into(),
            ty: plcc_ir::MemType::Agg(plcc_ir::AggId::new(0)),
            elem: None,
            role: plcc_ir::FieldRole::Var,
            location: None,
        }],
    });
    let Err(ds) = plcc::targets::machine("interp", &broken) else {
        panic!("a self-containing struct was loaded")
    };
    assert_eq!(ds[0].code, "E9901");
    assert!(
        ds[0].message.contains("contains itself"),
        "{}",
        ds[0].message
    );
}

/// Every code of the catalogue is exercised by some test: it appears, written out, in
/// a test's material (a bad program's expectation, a snapshot, an assertion in a
/// `tests` directory or a `#[cfg(test)]` module). Tests that name a code only through
/// its constant do not count, so that a renumbered code shows here.
#[test]
fn every_code_has_a_test() {
    fn walk(dir: &Path, out: &mut String) {
        let Ok(entries) = std::fs::read_dir(dir) else {
            return;
        };
        for e in entries.flatten() {
            let p = e.path();
            let name = p.file_name().unwrap().to_string_lossy().to_string();
            if p.is_dir() {
                if name != "target" && !name.starts_with('.') {
                    walk(&p, out);
                }
                continue;
            }
            let Ok(text) = std::fs::read_to_string(&p) else {
                continue;
            };
            let in_tests = p.components().any(|c| c.as_os_str() == "tests");
            if in_tests || name == "tests.rs" {
                out.push_str(&text);
            } else if name.ends_with(".rs") {
                if let Some(i) = text.find("#[cfg(test)]") {
                    out.push_str(&text[i..]);
                }
            }
        }
    }
    let mut material = String::new();
    for dir in ["tests", "src", "frontend", "ir", "backends"] {
        walk(&root().join(dir), &mut material);
    }
    let catalogue = plcc::commands::diagnostics_markdown();
    let untested: Vec<&str> = catalogue
        .lines()
        .filter_map(|l| l.strip_prefix("## "))
        .map(|l| l.split(' ').next().unwrap())
        .filter(|code| !material.contains(code))
        .collect();
    assert!(untested.is_empty(), "codes without a test: {untested:?}");
}
