//! The C backend's diagnostics: bad settings (E9201), no compiler (E9202), a
//! compiler that fails (E9203), a library that does not load (E9204), malformed IR
//! (E9206). Unchecked pointers (E9205) are in the root package's `tests/codesys.rs`.

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

/// The file set, its names in iec2c's order, and the headers.
#[test]
fn the_files_and_the_headers() {
    let arts = CBackend::new()
        .compile(&good(), &Options::default())
        .unwrap();
    let names: Vec<&str> = arts.files.iter().map(|f| f.kind.as_str()).collect();
    assert_eq!(
        names,
        ["POUS.c", "POUS.h", "Config0.c", "Config0.h", "Res0.c"]
    );
    let res = String::from_utf8(arts.files[4].bytes.clone()).unwrap();
    let lines: Vec<&str> = res.lines().collect();
    assert_eq!(lines[5], "#include \"iec_std_lib.h\"");
    assert_eq!(lines[6], "", "line 7 of Res0.c is blank");
    assert!(res.contains("MAIN RES0__MAIN;"));
    let config = String::from_utf8(arts.files[2].bytes.clone()).unwrap();
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
