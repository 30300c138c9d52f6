//! `plcc --target c`: the file set written into the directory `-o` names, each name
//! printed on stdout as iec2c prints them; `--emit headers` writes plcc's headers; the
//! files build with them as C and as C++.

use std::path::Path;
use std::process::Command;

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
    for compiler in [
        &["cc", "-std=c99"][..],
        &["g++", "-std=gnu++11", "-x", "c++"][..],
    ] {
        for unit in ["Config0.c", "Res0.c"] {
            let mut cmd = Command::new(compiler[0]);
            cmd.current_dir(&out)
                .args(&compiler[1..])
                .args(plcc_c::cc::WARNINGS)
                .args(["-I.", "-c", unit, "-o", "/dev/null"]);
            plcc_c::cc::run(cmd).unwrap();
        }
    }
}
