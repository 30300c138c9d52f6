//! The `c` target's files in a runtime like OpenPLC v3's (`tests/c_openplc/`): the
//! runtime owns the located variables (their storage and pointers, defined from
//! `LOCATED_VARIABLES.h`), binds them into its I/O tables, and runs
//! `config_run__(tick++)` with virtual time advancing by `common_ticktime__`; the
//! program has multi-rate tasks, `%IX %QX %IW %QW %MW %MD %ML` variables, globals of
//! the configuration and of the resource, and a TON that counts `__CURRENT_TIME`.
//! Built as C99 and as C++ (gnu++11 and gnu++17) with `-Wall -Wextra -Werror`
//! against plcc's own headers (`--emit headers`). Also: the exact
//! `LOCATED_VARIABLES.h`, `VARIABLES.csv` and `Config0.h`, the C++ names of the
//! entry points, `POUS.c` compiled alone, and `plcc iec2c` writing the same files.

use plcc_c::cc::{run, TempDir, WARNINGS};
use std::path::{Path, PathBuf};
use std::process::Command;

fn here() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/c_openplc")
}

/// Runs plcc with `args` in `dir`; its standard output.
fn plcc(dir: &Path, args: &[&str]) -> String {
    let o = Command::new(env!("CARGO_BIN_EXE_plcc"))
        .current_dir(dir)
        .args(args)
        .output()
        .expect("plcc runs");
    assert!(
        o.status.success(),
        "plcc {args:?}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    String::from_utf8(o.stdout).unwrap()
}

const FILES: &str =
    "POUS.c\nPOUS.h\nLOCATED_VARIABLES.h\nVARIABLES.csv\nConfig0.c\nConfig0.h\nRes0.c\n";

/// The files of `plant.st` and plcc's headers in a new directory.
fn generate() -> TempDir {
    let dir = TempDir::new().unwrap();
    let st = here().join("plant.st");
    let st = st.to_str().unwrap();
    assert_eq!(plcc(dir.path(), &["--target", "c", st, "-o", "."]), FILES);
    plcc(
        dir.path(),
        &["--target", "c", "--emit", "headers", st, "-o", "."],
    );
    dir
}

/// Builds the configuration, the resource and the runtime with `compiler` and runs
/// the runtime, which prints `OK` when every check holds.
fn build_and_run(dir: &Path, compiler: &[&str], cxx: bool) {
    let runtime = here().join("runtime.c");
    for unit in ["Config0.c", "Res0.c"] {
        let mut cmd = Command::new(compiler[0]);
        cmd.current_dir(dir)
            .args(&compiler[1..])
            .args(WARNINGS)
            .args(["-I.", "-c", unit]);
        run(cmd).unwrap();
    }
    let mut cmd = Command::new(compiler[0]);
    cmd.current_dir(dir)
        .args(&compiler[1..])
        .args(WARNINGS)
        .arg("-I.");
    if cxx {
        cmd.args(["-x", "c++"]).arg(&runtime).args(["-x", "none"]);
    } else {
        cmd.arg(&runtime);
    }
    cmd.args(["Config0.o", "Res0.o", "-lm", "-o", "runtime"]);
    run(cmd).unwrap();
    let o = Command::new(dir.join("runtime")).output().unwrap();
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success() && out == "OK\n", "{compiler:?}:\n{out}");
}

#[test]
fn an_openplc_like_runtime_runs_the_c() {
    let dir = generate();
    build_and_run(dir.path(), &["cc", "-std=c99"], false);
    for std in ["-std=gnu++11", "-std=gnu++17"] {
        build_and_run(dir.path(), &["g++", std, "-x", "c++"], true);
        // As OpenPLC compiles them: C++ names for the entry points, plain names
        // for the variables the runtime links to.
        let nm = Command::new("nm")
            .current_dir(dir.path())
            .arg("Config0.o")
            .output()
            .unwrap();
        let nm = String::from_utf8_lossy(&nm.stdout);
        for sym in [
            " T _Z12config_run__m",
            " T _Z13config_init__v",
            " D common_ticktime__",
        ] {
            assert!(nm.contains(sym), "{sym} not in\n{nm}");
        }
    }
}

#[test]
fn the_runtimes_files() {
    let dir = generate();
    let read = |n: &str| std::fs::read_to_string(dir.path().join(n)).unwrap();
    // One line per address (%IX0.0 is declared twice), elementary types.
    assert_eq!(
        read("LOCATED_VARIABLES.h"),
        "__LOCATED_VAR(BOOL,__IX0_0,I,X,0,0)\n\
         __LOCATED_VAR(BOOL,__IX0_1,I,X,0,1)\n\
         __LOCATED_VAR(BOOL,__QX0_0,Q,X,0,0)\n\
         __LOCATED_VAR(BOOL,__QX0_1,Q,X,0,1)\n\
         __LOCATED_VAR(INT,__IW0,I,W,0)\n\
         __LOCATED_VAR(UINT,__QW1,Q,W,1)\n\
         __LOCATED_VAR(WORD,__MW2,M,W,2)\n\
         __LOCATED_VAR(DINT,__MD0,M,D,0)\n\
         __LOCATED_VAR(LINT,__ML1,M,L,1)\n\
         __LOCATED_VAR(INT,__QW7,Q,W,7)\n"
    );
    let csv = read("VARIABLES.csv");
    assert!(csv.starts_with(
        "// Programs\n0;CONFIG0.RES0.INSTANCE0;PROG0;\n1;CONFIG0.RES0.INST1;PROG1;\n\n// Variables\n\
         0;VAR;CONFIG0.G1;CONFIG0.G1;INT;INT;0;\n\
         1;OUT;CONFIG0.GQ;CONFIG0.GQ;INT;INT;0;\n\
         2;VAR;CONFIG0.RES0.RG;CONFIG0.RES0.RG;DINT;DINT;0;\n\
         3;FB;CONFIG0.RES0.INSTANCE0;CONFIG0.RES0.INSTANCE0;PROG0;;0;\n\
         4;IN;CONFIG0.RES0.INSTANCE0.START;CONFIG0.RES0.INSTANCE0.START;BOOL;BOOL;0;\n"
    ));
    for row in [
        ";MEM;CONFIG0.RES0.INSTANCE0.MEM;CONFIG0.RES0.INSTANCE0.MEM;WORD;WORD;0;\n",
        ";FB;CONFIG0.RES0.INSTANCE0.T1;CONFIG0.RES0.INSTANCE0.T1;TON;;0;\n",
        ";VAR;CONFIG0.RES0.INSTANCE0.T1.Q;CONFIG0.RES0.INSTANCE0.T1.Q;BOOL;BOOL;0;\n",
        ";VAR;CONFIG0.RES0.INSTANCE0.ET;CONFIG0.RES0.INSTANCE0.ET;DINT;TIME;0;\n",
        ";IN;CONFIG0.RES0.INST1.AGAIN;CONFIG0.RES0.INST1.AGAIN;BOOL;BOOL;0;\n",
    ] {
        assert!(csv.contains(row), "{row} not in\n{csv}");
    }
    assert!(csv.ends_with("\n\n// Ticktime\n10000000\n"), "{csv}");
    // Every row numbered from 0, each ending with `;`.
    let rows: Vec<&str> = csv
        .split("// Variables\n")
        .nth(1)
        .unwrap()
        .lines()
        .take_while(|l| !l.is_empty())
        .collect();
    for (k, r) in rows.iter().enumerate() {
        assert!(r.starts_with(&format!("{k};")) && r.ends_with(';'), "{r}");
        assert_eq!(r.split(';').count(), 8, "{r}");
    }
    assert_eq!(
        read("Config0.h"),
        "__DECLARE_GLOBAL_PROTOTYPE(INT, G1)\n__DECLARE_GLOBAL_PROTOTYPE(INT, GQ)\n"
    );
    let res = read("Res0.c");
    let lines: Vec<&str> = res.lines().collect();
    assert_eq!(lines[5], "#include \"iec_std_lib.h\"");
    assert_eq!(lines[6], "", "line 7 of Res0.c is blank");
    // POUS.c compiles alone with POUS.h before it (as the Arduino builder does).
    let pous = format!("#include \"POUS.h\"\n{}", read("POUS.c"));
    std::fs::write(dir.path().join("pous_alone.c"), pous).unwrap();
    let mut cmd = Command::new("cc");
    cmd.current_dir(dir.path())
        .args(["-std=c99", "-fsyntax-only", "-I."])
        .args(WARNINGS)
        .arg("pous_alone.c");
    run(cmd).unwrap();
}

/// Runs `exe` with `args` in `dir`: its status, stdout and stderr.
fn run_in(dir: &Path, exe: &Path, args: &[&str]) -> (i32, String, String) {
    let o = Command::new(exe)
        .current_dir(dir)
        .args(args)
        .output()
        .expect("runs");
    (
        o.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&o.stdout).into_owned(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

#[test]
fn plcc_as_iec2c() {
    let dir = TempDir::new().unwrap();
    let plcc = Path::new(env!("CARGO_BIN_EXE_plcc"));
    let st = here().join("plant.st");
    let st = st.to_str().unwrap();
    let reference = generate();
    let same_files = |d: &Path| {
        for name in FILES.lines() {
            let a = std::fs::read(d.join(name)).unwrap();
            let b = std::fs::read(reference.path().join(name)).unwrap();
            assert!(a == b, "{name} differs from --target c's");
        }
    };
    // OpenPLC's call, in the directory the files go to.
    let (status, out, err) = run_in(
        dir.path(),
        plcc,
        &["iec2c", "-f", "-l", "-p", "-r", "-R", "-a", st],
    );
    assert_eq!((status, out.as_str()), (0, FILES), "{err}");
    same_files(dir.path());
    // Beremiz's: -I and -T, options grouped, and plcc installed as `iec2c`.
    let iec2c = dir.path().join("iec2c");
    std::os::unix::fs::symlink(plcc, &iec2c).unwrap();
    let (status, out, err) = run_in(dir.path(), &iec2c, &["-flp", "-I", "lib", "-Tbuild", st]);
    assert_eq!((status, out.as_str()), (0, FILES), "{err}");
    same_files(&dir.path().join("build"));
    // The help names the options Beremiz looks for.
    let (status, out, _) = run_in(dir.path(), &iec2c, &["-h"]);
    assert_eq!(status, 0);
    for opt in [" -f : ", " -l : ", " -p : ", " -I : ", " -T : "] {
        assert!(out.contains(opt), "{opt} not in\n{out}");
    }
    let (status, out, _) = run_in(dir.path(), &iec2c, &["-v"]);
    assert!(status == 0 && out.contains("version"), "{out}");
    // Failures: status 1, as iec2c's.
    for (args, says) in [
        (&[][..], "Missing input file"),
        (&["-x", st][..], "Unrecognized option: -x"),
        (&[st, st][..], "Too many input files"),
        (&[st, "-T"][..], "Option -T requires an operand"),
    ] {
        let (status, out, err) = run_in(dir.path(), &iec2c, args);
        assert_eq!(status, 1, "{args:?}");
        assert!(err.contains(says), "{args:?}: {err}");
        assert!(out.contains("syntax:"), "{args:?}: the usage follows");
    }
    let bad = dir.path().join("bad.st");
    std::fs::write(&bad, "PROGRAM p VAR x : INT; END_VAR x := y; END_PROGRAM\n").unwrap();
    let (status, out, err) = run_in(
        dir.path(),
        &iec2c,
        &[bad.to_str().unwrap(), "-T", "nothing"],
    );
    assert_eq!((status, out.as_str()), (1, ""), "{err}");
    assert!(err.contains("E0201"), "{err}");
    assert!(!dir.path().join("nothing").exists());
}
