//! The C backend's diagnostics: bad settings (E9201), no compiler (E9202), a
//! compiler that fails (E9203), a library that does not load (E9204), malformed IR
//! (E9206), located variables the runtime cannot bind (E9207, E9208). Unchecked
//! pointers (E9205) are in the root package's `tests/codesys.rs`.

use plcc_c::{codes, CBackend, CMachine, Settings};
use plcc_ir::backend::{Backend, Options};
use plcc_ir::text::parse_module;
use plcc_ir::Module;

const GOOD: &str =
    "struct %main program {\n    var x: i32 DINT\n}\n\ndata @main: %main program\n\n\
func @main(ptr) program {\nblock0(v0: ptr):\n    return\n}\n\n\
func @main$init(ptr) init {\nblock0(v0: ptr):\n    return\n}\n\n\
program \"main\" data @main body @main init @main$init\n";

fn good() -> Module {
    parse_module(GOOD).unwrap()
}

fn code_of<T>(r: Result<T, Vec<plcc_ir::diag::Diagnostic>>) -> &'static str {
    match r {
        Ok(_) => panic!("no error"),
        Err(d) => d[0].code,
    }
}

#[test]
fn bad_settings_and_emits() {
    let b = CBackend::new();
    for (k, v) in [("sanitize", "thread"), ("opt", "7"), ("colour", "blue")] {
        let o = Options {
            settings: vec![(k.into(), v.into())],
            ..Options::default()
        };
        assert_eq!(
            code_of(b.compile(&good(), &o)),
            codes::E_BAD_SETTING,
            "{k}={v}"
        );
    }
    let o = Options {
        emit: Some("asm".into()),
        ..Options::default()
    };
    assert_eq!(code_of(b.compile(&good(), &o)), codes::E_BAD_SETTING);
}

#[test]
fn no_compiler() {
    let s = Settings {
        cc: Some("/nonexistent/plcc-no-cc".into()),
        ..Settings::default()
    };
    assert_eq!(code_of(CMachine::new(&good(), &s)), codes::E_NO_COMPILER);
}

/// A "compiler" that runs (`--version` succeeds) and then fails, or writes a file
/// that is no library.
fn fake_compiler(dir: &std::path::Path, name: &str, action: &str) -> String {
    let path = dir.join(name);
    std::fs::write(
        &path,
        format!(
            "#!/bin/sh\nif [ \"$1\" = --version ]; then echo fake; exit 0; fi\n\
             out=\nwhile [ $# -gt 0 ]; do if [ \"$1\" = -o ]; then out=$2; fi; shift; done\n{action}\n"
        ),
    )
    .unwrap();
    use std::os::unix::fs::PermissionsExt;
    std::fs::set_permissions(&path, std::fs::Permissions::from_mode(0o755)).unwrap();
    path.to_string_lossy().into_owned()
}

#[test]
fn a_failing_compiler_and_a_bad_library() {
    let dir = plcc_c::cc::TempDir::new().unwrap();
    let failing = fake_compiler(dir.path(), "failing", "echo 'error: no' >&2; exit 1");
    let s = Settings {
        cc: Some(failing),
        ..Settings::default()
    };
    assert_eq!(code_of(CMachine::new(&good(), &s)), codes::E_CC_FAILED);
    let garbage = fake_compiler(dir.path(), "garbage", "echo 'not a library' > \"$out\"");
    let s = Settings {
        cc: Some(garbage),
        ..Settings::default()
    };
    assert_eq!(code_of(CMachine::new(&good(), &s)), codes::E_LOAD);
}

#[test]
fn a_program_body_with_the_wrong_signature() {
    let text = GOOD.replace(
        "func @main(ptr) program {\nblock0(v0: ptr):",
        "func @main() program {\nblock0:",
    );
    let m = parse_module(&text).unwrap();
    assert_eq!(
        code_of(CBackend::new().compile(&m, &Options::default())),
        codes::E_MALFORMED_IR
    );
}

/// A module whose program has the fields `fields` (IR text), and an array type `%a`.
fn with_fields(fields: &str) -> Module {
    let text = GOOD.replace("    var x: i32 DINT\n", fields);
    parse_module(&format!("array %a = [2 x i16 INT] lower 0\n{text}")).unwrap()
}

#[test]
fn located_variables_the_runtime_cannot_bind() {
    let c =
        |fields: &str| code_of(CBackend::new().compile(&with_fields(fields), &Options::default()));
    for bad in [
        "    var x: i16 INT at \"%IX0.0\"\n",
        "    var x: i16 INT at \"%I0\"\n",
        "    var x: i32 DINT at \"%MW2\"\n",
        "    var x: i1 BOOL at \"%KX0.0\"\n",
        "    var x: i1 BOOL at \"%IY0\"\n",
        "    var x: %a at \"%IW0\"\n",
    ] {
        assert_eq!(c(bad), "E9207", "{bad}");
    }
    assert_eq!(
        c("    var x: i16 INT at \"%MW2\"\n    var y: i16 WORD at \"%MW2\"\n"),
        "E9208"
    );
    // Accepted: one address twice with one type, a BOOL without a size letter
    // (taken as X), a partly specified address (an ordinary variable).
    let ok = with_fields(
        "    var x: i1 BOOL at \"%IX0.0\"\n    var y: i1 BOOL at \"%IX0.0\"\n    var z: i1 BOOL at \"%I0.1\"\n    var w: i16 INT at \"%Q*\"\n",
    );
    let arts = CBackend::new().compile(&ok, &Options::default()).unwrap();
    let located = arts
        .files
        .iter()
        .find(|f| f.kind == "LOCATED_VARIABLES.h")
        .unwrap();
    assert_eq!(
        String::from_utf8(located.bytes.clone()).unwrap(),
        "__LOCATED_VAR(BOOL,__IX0_0,I,X,0,0)\n__LOCATED_VAR(BOOL,__IX0_1,I,X,0,1)\n"
    );
}

#[test]
fn the_globals_address_is_no_value() {
    // A program keeps the address of the globals' object (not of one global).
    let text = GOOD
        .replace(
            "struct %main program {\n    var x: i32 DINT\n}\n",
            "struct %main program {\n    var x: i32 DINT\n    var p: ptr\n}\nstruct %G program {\n    var g: i32 DINT\n}\n",
        )
        .replace(
            "data @main: %main program\n",
            "data @main: %main program\ndata @g: %G global\n",
        )
        .replace(
            "func @main(ptr) program {\nblock0(v0: ptr):\n",
            "func @main(ptr) program {\nblock0(v0: ptr):\n    v1 = global_addr @g\n    v2 = field_addr v0, %main.p\n    store v1, v2\n",
        )
        + "globals @g\n";
    let m = parse_module(&text).unwrap();
    assert_eq!(
        code_of(CBackend::new().compile(&m, &Options::default())),
        codes::E_MALFORMED_IR
    );
    // Reaching a global through it is what it is for.
    let fine = text.replace(
        "    store v1, v2\n",
        "    v3 = field_addr v1, %G.g\n    v4 = load.i32 v3\n    store v4, v3\n",
    );
    CBackend::new()
        .compile(&parse_module(&fine).unwrap(), &Options::default())
        .unwrap();
}

/// The file set, its names in iec2c's order, and the headers.
#[test]
fn the_files_and_the_headers() {
    let arts = CBackend::new()
        .compile(&good(), &Options::default())
        .unwrap();
    let names: Vec<&str> = arts.files.iter().map(|f| f.kind.as_str()).collect();
    assert_eq!(
        names,
        [
            "POUS.c",
            "POUS.h",
            "LOCATED_VARIABLES.h",
            "VARIABLES.csv",
            "Config0.c",
            "Config0.h",
            "Res0.c"
        ]
    );
    let file = |n: &str| {
        let f = arts.files.iter().find(|f| f.kind == n).unwrap();
        String::from_utf8(f.bytes.clone()).unwrap()
    };
    assert_eq!(file("LOCATED_VARIABLES.h"), "", "nothing is located");
    let res = file("Res0.c");
    let lines: Vec<&str> = res.lines().collect();
    assert_eq!(lines[5], "#include \"iec_std_lib.h\"");
    assert_eq!(lines[6], "", "line 7 of Res0.c is blank");
    assert!(res.contains("MAIN RES0__MAIN;"));
    let config = file("Config0.c");
    assert!(config.contains("unsigned long long common_ticktime__ = 10000000ULL * 1ULL;"));
    assert!(config.contains("void config_run__(unsigned long tick)"));
    let o = Options {
        emit: Some("headers".into()),
        ..Options::default()
    };
    let h = CBackend::new().compile(&good(), &o).unwrap();
    let names: Vec<&str> = h.files.iter().map(|f| f.kind.as_str()).collect();
    assert_eq!(
        names,
        [
            "iec_types.h",
            "iec_types_all.h",
            "accessor.h",
            "iec_std_lib.h"
        ]
    );
}
