//! Snapshots of the PIC16F876A assembly plcc generates for small programs
//! (`tests/pic16/*.st`): the code of the programs, FBs, functions and runtime helpers
//! (the vectors and the scan loop are left out: they differ only in whether the
//! program reads the clock, which one test below checks).
//!
//! Each snapshot was read and checked by hand: the arithmetic idioms, the bank
//! selects (only where the bank changes, never between a skip and what it skips) and
//! the BOOLs as bits. `tests/pic16_gpsim.rs` checks that gpasm and gpsim agree with
//! plcc about the same programs.

use plcc::driver::{build_sources, source_texts, BuildOptions};
use plcc_ir::backend::{Backend, Options};
use std::path::PathBuf;

fn listing(name: &str) -> String {
    let (asm, summary) = assembly(name);
    let mut out = String::new();
    for section in asm.split("\n; ---- ").skip(1) {
        let title = section.lines().next().unwrap_or("");
        if [
            "program", "fb", "function", "init", "helper", "Mul", "Div", "BitMask",
        ]
        .iter()
        .any(|k| title.starts_with(k))
        {
            out.push_str("; ---- ");
            out.push_str(section.trim_end().trim_end_matches("END").trim_end());
            out.push_str("\n\n");
        }
    }
    format!("; {summary}\n{out}")
}

/// The whole assembly of `tests/pic16/{name}` and the build's summary line.
fn assembly(name: &str) -> (String, String) {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/pic16")
        .join(name);
    let text = std::fs::read(&path).expect("program");
    let b = build_sources(
        vec![(format!("tests/pic16/{name}"), text)],
        &BuildOptions::default(),
    )
    .expect("build");
    let module = b
        .module
        .as_ref()
        .unwrap_or_else(|| panic!("{name} does not compile"));
    let opts = Options {
        sources: source_texts(&b.sources, module),
        ..Default::default()
    };
    let arts = plcc_pic16::Pic16Backend::new()
        .compile(module, &opts)
        .unwrap_or_else(|d| panic!("{name}: {d:?}"));
    let asm = String::from_utf8(arts.files[0].bytes.clone()).unwrap();
    (asm, arts.summary.unwrap_or_default())
}

/// The clock (Timer1, its interrupt, the sampling at scan start) is built only for a
/// program that reads it; its interrupt counts with an `incf` chain.
#[test]
fn the_clock_is_built_only_for_programs_that_read_it() {
    let (asm, summary) = assembly("ton_timer.st");
    for part in [
        "\tORG\t0x004",
        "\tincf\tplc_clock_ms+3,F",
        "\tretfie",
        "\tmovwf\tT1CON",
        "\tbsf\tINTCON,7",
        "\tmovwf\tplc_now_ms",
    ] {
        assert!(asm.contains(part), "TON: no {part:?} in\n{asm}");
    }
    assert!(summary.contains("stack 2/8"), "{summary}");
    let (asm, summary) = assembly("add16.st");
    let code: Vec<&str> = asm.lines().filter(|l| !l.contains("EQU")).collect();
    for part in ["ORG\t0x004", "retfie", "T1CON", "INTCON", "plc_now_ms"] {
        assert!(
            !code.iter().any(|l| l.contains(part)),
            "no clock read, yet {part:?} in\n{asm}"
        );
    }
    assert!(summary.contains("stack 1/8"), "{summary}");
}

macro_rules! snap {
    ($($name:ident),* $(,)?) => {
        $(
            #[test]
            fn $name() {
                insta::assert_snapshot!(listing(concat!(stringify!($name), ".st")));
            }
        )*

        #[test]
        fn every_program_has_a_snapshot_test() {
            let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/pic16");
            let mut files: Vec<String> = std::fs::read_dir(dir)
                .unwrap()
                .filter_map(|e| e.ok())
                .map(|e| e.file_name().to_string_lossy().into_owned())
                .filter(|n| n.ends_with(".st"))
                .collect();
            files.sort();
            let mut listed = vec![$(concat!(stringify!($name), ".st")),*];
            listed.sort();
            assert_eq!(files, listed);
            assert!(files.len() >= 15);
        }
    };
}

snap!(
    abs_neg,
    add16,
    array_index,
    bools,
    case_stmt,
    compare,
    counter_fb,
    function_call,
    if_else,
    io_pins,
    loop_sum,
    mul_div,
    select_max,
    shifts,
    sub32,
    ton_timer,
);

/// A program over one 2K page: units are placed so none crosses a page, calls between
/// pages set PCLATH, and the program computes what the host computes.
#[test]
fn programs_over_one_page_run() {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/pic16/paging/big.st");
    let b = build_sources(
        vec![("big.st".into(), std::fs::read(&path).unwrap())],
        &BuildOptions::default(),
    )
    .unwrap();
    let module = b.module.expect("compiles");
    let build = plcc_pic16::build(&module, &Options::default()).expect("fits the chip");
    assert!(
        build.image.words.len() > 2 * 2048,
        "the program spans three pages or more"
    );
    let asm = build.program.mpasm();
    assert!(asm.contains("ORG\t0x800") && asm.contains("ORG\t0x1000"));
    assert!(asm.contains("bsf\tPCLATH,3"), "calls into page 1 select it");
    let mut host = plcc::targets::machine("host", &module).unwrap();
    let mut pic = plcc::targets::machine("pic16f876a", &module).unwrap();
    host.cold_start().unwrap();
    pic.cold_start().unwrap();
    for scan in 1..=3 {
        host.scan().unwrap();
        pic.scan().unwrap();
        for v in ["main.x", "main.y", "main.acc"] {
            assert_eq!(
                host.read(v).unwrap(),
                pic.read(v).unwrap(),
                "{v} after scan {scan}"
            );
        }
    }
}

/// Located BOOLs drive and read pins: by default `%IX0.n` = RBn and `%QX0.n` = RCn;
/// a setting moves one. Inputs are latched at scan start, outputs written at its end.
#[test]
fn located_bools_are_pins() {
    use plcc_ir::machine::Machine;
    use plcc_ir::value::PlcValue;
    use plcc_pic16::sim::Port;
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/pic16/io_pins.st");
    let b = build_sources(
        vec![("io_pins.st".into(), std::fs::read(&path).unwrap())],
        &BuildOptions::default(),
    )
    .unwrap();
    let module = b.module.expect("compiles");
    let moved = Options {
        settings: vec![("pin.%QX0.0".into(), "RB7".into())],
        ..Default::default()
    };
    for (opts, out_port, out_bit) in [(Options::default(), Port::C, 0), (moved, Port::B, 7)] {
        let build = plcc_pic16::build(&module, &opts).expect("builds");
        let listing = build.program.mpasm();
        let pin = if out_port == Port::C { "RC0" } else { "RB7" };
        assert!(
            listing.contains(&format!("main.motor -> {pin}")),
            "{listing}"
        );
        let mut m = plcc_pic16::machine::PicMachine::new(&module, build);
        m.cold_start().unwrap();
        m.scan().unwrap();
        assert!(!m.sim().output(out_port, out_bit));
        // start is %IX0.0 = RB0: the write drives the pin, the next scan latches it.
        m.write("main.start", PlcValue::from_bool(true)).unwrap();
        assert_eq!(m.read("main.start").unwrap(), PlcValue::from_bool(false));
        m.scan().unwrap();
        assert_eq!(m.read("main.motor").unwrap(), PlcValue::from_bool(true));
        assert!(m.sim().output(out_port, out_bit), "motor drives {pin}");
        m.write("main.start", PlcValue::from_bool(false)).unwrap();
        m.write("main.stop", PlcValue::from_bool(true)).unwrap();
        m.scan().unwrap();
        assert!(!m.sim().output(out_port, out_bit), "stop releases {pin}");
    }
    let bad = Options {
        settings: vec![("pin.%QX0.0".into(), "RD1".into())],
        ..Default::default()
    };
    let Err(err) = plcc_pic16::build(&module, &bad) else {
        panic!("a bad pin is an error");
    };
    assert_eq!(err[0].code, "E9005");
}

fn pic16_errors(src: &str) -> Vec<plcc_ir::diag::Diagnostic> {
    let b = build_sources(
        vec![("gen.st".into(), src.as_bytes().to_vec())],
        &BuildOptions::default(),
    )
    .unwrap();
    let module = b.module.expect("compiles");
    match plcc_pic16::build(&module, &Options::default()) {
        Ok(_) => panic!("expected the chip to run out"),
        Err(d) => d,
    }
}

/// Running out of RAM, stack or program memory is an error that says which and by
/// how much, never a silent overflow.
#[test]
fn resources_that_run_out_are_errors() {
    let ram = "PROGRAM main
VAR a, b, c, d, e : ARRAY[0..39] OF INT; i : INT; END_VAR
a[i] := b[i] + c[i] + d[i] + e[i];
i := (i + 1) MOD 40;
END_PROGRAM";
    let d = pic16_errors(ram);
    assert_eq!(d[0].code, "E9003");
    assert!(
        d[0].message.contains("402 bytes") && d[0].message.contains("69 too many"),
        "{}",
        d[0].message
    );

    // Nine FUNCTIONs too big to inline, each calling the next: 9 levels, and the
    // scan loop's call (no interrupt: the program never reads the clock).
    let mut deep = String::new();
    for i in 0..9 {
        deep += &format!("FUNCTION f{i} : DINT\nVAR_INPUT a : DINT; END_VAR\nVAR t : DINT; END_VAR\nt := a * {};\n", i + 3);
        for j in 0..12 {
            deep += &format!("t := t XOR SHR(t, {}) + {j};\n", j + 1);
        }
        if i < 8 {
            deep += &format!("t := t + f{}(t) - f{}(a);\n", i + 1, i + 1);
        }
        deep += &format!("f{i} := t;\nEND_FUNCTION\n");
    }
    deep += "PROGRAM main\nVAR x : DINT := 1; END_VAR\nx := f0(x) + f0(x + 1);\nEND_PROGRAM\n";
    let d = pic16_errors(&deep);
    assert_eq!(d[0].code, "E9004");
    assert!(
        d[0].message.contains("11 levels") && d[0].message.contains("3 too many"),
        "{}",
        d[0].message
    );

    // Sixteen big FUNCTIONs, each called twice: more than 8K words.
    let mut big = String::new();
    for i in 0..16 {
        big += &format!("FUNCTION f{i} : DINT\nVAR_INPUT a : DINT; b : DINT; END_VAR\nVAR t : DINT; u : DINT; END_VAR\n");
        big += &format!(
            "t := a * {} + b;\nIF t > {} THEN t := t - a / {}; ELSE t := t + (b MOD {}); END_IF;\n",
            i + 3,
            i * 100,
            i + 2,
            i + 5
        );
        for j in 0..12 {
            big += &format!(
                "u := u + (t AND {}) - SHR(t, {}); t := t XOR u;\n",
                j * 7 + 1,
                j % 7 + 1
            );
        }
        big += &format!("f{i} := t;\nEND_FUNCTION\n");
    }
    big += "PROGRAM main\nVAR x : DINT := 7; y : DINT := 3; acc : DINT; END_VAR\n";
    for i in 0..16 {
        big += &format!("acc := acc + f{i}(x, y) - f{i}(y, x);\n");
    }
    big += "END_PROGRAM\n";
    let d = pic16_errors(&big);
    assert_eq!(d[0].code, "E9002");
    assert!(
        d[0].message.contains("of the chip's") || d[0].message.contains("the chip has 8192"),
        "{}",
        d[0].message
    );
    assert!(d[0].message.contains("too many"), "{}", d[0].message);
}

/// Regression: a result allowed to share RAM with its dying first operand was once
/// placed over part of it (not at its first byte) when the exact place was taken;
/// a byte-wise 64-bit shift then read bytes it had already written and a loop never
/// ended. Found by the soft-float math library's tests.
#[test]
fn results_never_overlap_part_of_an_operand() {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("backends/pic16/softfloat");
    let prog = "PROGRAM p
VAR a : DWORD := 16#3F7F_FFFF; b : DWORD := 16#4B3A_1C41; v : ULINT; q : INT; neg : BOOL; r : DWORD; END_VAR
    v := SM_LOGV(a := a, mode := 2, q => q, neg => neg);
    WHILE v >= 16#100_0000_0000_0000 DO v := SHR(v, 8); q := q - 8; END_WHILE;
    WHILE v >= 16#100_0000_0000 DO v := SHR(v, 1); q := q - 1; END_WHILE;
    WHILE v < 16#80_0000_0000 DO v := SHL(v, 1); q := q + 1; END_WHILE;
    r := SM_EXP2M(b, v, -q, neg);
END_PROGRAM";
    let mut sources = vec![("p.st".to_string(), prog.as_bytes().to_vec())];
    for f in ["softfloat.st", "softmath.st"] {
        sources.push((f.to_string(), std::fs::read(dir.join(f)).unwrap()));
    }
    let b = build_sources(sources, &BuildOptions::default()).unwrap();
    let module = b.module.expect("compiles");
    let mut host = plcc::targets::machine("host", &module).unwrap();
    let mut pic = plcc::targets::machine("pic16f876a", &module).unwrap();
    for m in [&mut host, &mut pic] {
        m.cold_start().unwrap();
        m.scan().unwrap();
    }
    for v in ["p.v", "p.q", "p.r"] {
        assert_eq!(host.read(v).unwrap(), pic.read(v).unwrap(), "{v}");
    }
}
