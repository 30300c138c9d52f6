//! `plcc --target c`: the file set written into the directory `-o` names, each name
//! printed on stdout as iec2c prints them; `--emit headers` writes plcc's headers; the
//! files build with them as C and as C++.

use std::path::Path;
use std::process::Command;

/// The file set in `out` (with plcc's headers there) compiles as C99 and as C++
/// (`g++ -std=gnu++11`, as OpenPLC builds it) with `-Wall -Wextra -Werror`.
fn builds_as_c_and_cpp(out: &Path) {
    for compiler in [
        &["cc", "-std=c99"][..],
        &["g++", "-std=gnu++11", "-x", "c++"][..],
    ] {
        for unit in ["Config0.c", "Res0.c"] {
            let mut cmd = Command::new(compiler[0]);
            cmd.current_dir(out)
                .args(&compiler[1..])
                .args(plcc_c::cc::WARNINGS)
                .args(["-I.", "-c", unit, "-o", "/dev/null"]);
            plcc_c::cc::run(cmd).unwrap();
        }
    }
}

#[test]
fn the_file_set_and_the_headers_build() {
    let prog = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/traffic_light.st");
    let dir = plcc_c::cc::TempDir::new().unwrap();
    let out = dir.path().join("out");
    let run = |extra: &[&str]| {
        let o = Command::new(env!("CARGO_BIN_EXE_plcc"))
            .args(["--target", "c"])
            .args(extra)
            .arg(&prog)
            .arg("-o")
            .arg(&out)
            .output()
            .expect("plcc runs");
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        String::from_utf8(o.stdout).unwrap()
    };
    assert_eq!(
        run(&[]),
        "POUS.c\nPOUS.h\nLOCATED_VARIABLES.h\nVARIABLES.csv\nConfig0.c\nConfig0.h\nRes0.c\n"
    );
    assert_eq!(
        run(&["--emit", "headers"]),
        "iec_types.h\niec_types_all.h\naccessor.h\niec_std_lib.h\n"
    );
    builds_as_c_and_cpp(&out);
}

/// C code in pragmas goes into the C where it stands (matiec's way, `data__` the
/// instance): the scenario passes on the c machine (under UBSan), the files build as
/// C and C++, and another target skips the pragmas with W0010.
#[test]
fn pragmas_holding_c_run_on_the_c_target_only() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/c_output");
    let prog = root.join("inline_c.st");
    let plcc = |args: &[&str]| {
        Command::new(env!("CARGO_BIN_EXE_plcc"))
            .args(args)
            .output()
            .expect("plcc runs")
    };
    let scenario = root.join("inline_c.expect");
    let (p, s) = (prog.to_str().unwrap(), scenario.to_str().unwrap());
    let on_c = plcc(&[
        "test",
        p,
        "--scenario",
        s,
        "--target",
        "c",
        "-s",
        "sanitize=undefined",
    ]);
    assert!(
        on_c.status.success(),
        "{}{}",
        String::from_utf8_lossy(&on_c.stdout),
        String::from_utf8_lossy(&on_c.stderr)
    );
    assert!(!String::from_utf8_lossy(&on_c.stderr).contains("W0010"));
    let on_host = plcc(&["test", p, "--scenario", s, "--target", "host"]);
    let err = String::from_utf8_lossy(&on_host.stderr);
    assert_eq!(err.matches("warning[W0010]").count(), 2, "{err}");
    assert!(err.contains("only the `c` target copies C code"), "{err}");
    assert!(
        !on_host.status.success(),
        "the C did not run, so the scenario fails"
    );

    let dir = plcc_c::cc::TempDir::new().unwrap();
    let out = dir.path().join("out");
    let o = out.to_str().unwrap();
    assert!(plcc(&["--target", "c", p, "-o", o]).status.success());
    assert!(plcc(&["--target", "c", "--emit", "headers", p, "-o", o])
        .status
        .success());
    let pous = std::fs::read_to_string(out.join("POUS.c")).unwrap();
    assert!(
        pous.contains("__SET_VAR(data__->,Y,,__GET_VAR(data__->X,) * 2);"),
        "{pous}"
    );
    assert!(pous.contains("{ if (__GET_VAR(data__->N,) >= 3)"), "{pous}");
    builds_as_c_and_cpp(&out);
}
