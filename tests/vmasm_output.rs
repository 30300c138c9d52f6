//! The vmasm target's files: `plcc --target vmasm prog.st -o prog.xcp` writes the
//! image and its description, the description says where every variable is and where
//! the task body starts, the listing matches the image, and `plcc disasm` reads it back.

use plcc::driver::{build_sources, BuildOptions};
use plcc_ir::backend::{Backend, Options};
use plcc_vmasm::dcp_read;
use std::path::{Path, PathBuf};

#[path = "common/cli.rs"]
#[allow(dead_code)]
mod cli;
use cli::plcc;

fn example() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/traffic_light.st")
}

fn scratch_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("plcc-vmasm-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

#[test]
fn writes_the_image_and_its_description() {
    let dir = scratch_dir("out");
    let xcp = dir.join("light.xcp");
    for mode in ["16", "32", "32a"] {
        let out = plcc(&[
            "--target",
            "vmasm",
            "-s",
            &format!("mode={mode}"),
            "-s",
            "cycle=50",
            example().to_str().unwrap(),
            "-o",
            xcp.to_str().unwrap(),
        ]);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        assert!(String::from_utf8_lossy(&out.stderr).contains("vmasm ("));
        let code = std::fs::read(&xcp).unwrap();
        let dcp = dcp_read::Dcp::read(&xcp.with_extension("dcp")).unwrap();
        assert_eq!(dcp.code_size, Some(code.len() as u32));
        assert_eq!(dcp.mode.map(|m| m.name()), Some(mode));
        assert_eq!(dcp.tasks.len(), 1);
        assert_eq!(dcp.tasks[0].cycle_ms, 50);
        let text = std::fs::read_to_string(xcp.with_extension("dcp")).unwrap();
        assert!(
            text.contains(">light.xcp</file>"),
            "the description names the image"
        );
        // The listing in the description is the image, byte for byte.
        let mut listed = Vec::new();
        for l in &dcp.listing {
            if !l.bytes.is_empty() {
                assert_eq!(l.addr as usize, listed.len(), "{l:?}");
                listed.extend_from_slice(&l.bytes);
            }
        }
        assert_eq!(listed, code, "mode {mode}");
        // The task body address is the TSKLOOP label's.
        let tskloop = dcp
            .labels()
            .into_iter()
            .find(|(_, n)| n.ends_with("TSKLOOP"))
            .expect("a TSKLOOP label")
            .0;
        assert_eq!(tskloop, dcp.tasks[0].body_addr);
    }
}

#[test]
fn the_data_map_gives_the_addresses_plcc_uses() {
    let texts = vec![(
        "traffic_light.st".to_string(),
        std::fs::read(example()).unwrap(),
    )];
    let module = build_sources(texts, &BuildOptions::default())
        .unwrap()
        .module
        .unwrap();
    let backend = plcc_vmasm::VmasmBackend::new();
    let arts = backend.compile(&module, &Options::default()).unwrap();
    let dcp_text = String::from_utf8(arts.files[1].bytes.clone()).unwrap();
    let dcp = dcp_read::parse(&dcp_text).unwrap();
    assert!(!arts.symbols.is_empty());
    for s in &arts.symbols {
        let v = dcp
            .find_var(&format!("plcc.TASK.{}", s.path))
            .unwrap_or_else(|| panic!("the data map has no {}", s.path));
        assert_eq!(v.addr as u64, s.address, "{}", s.path);
        assert_eq!(v.size, s.size, "{}", s.path);
    }
}

#[test]
fn emits_the_listing_and_disassembles_the_image() {
    let dir = scratch_dir("asm");
    let xcp = dir.join("t.xcp");
    let asm = plcc(&[
        "--target",
        "vmasm",
        "--emit",
        "asm",
        example().to_str().unwrap(),
        "-o",
        "-",
    ]);
    assert!(asm.status.success());
    let listing = String::from_utf8(asm.stdout).unwrap();
    assert!(listing.contains("$VMSYS.TRML :?plcc.TASK?TSKLOOP"));
    assert!(listing.contains("$VMSYS.CALB traffic_light, :?plcc.traffic_light?CODE"));
    let out = plcc(&[
        "--target",
        "vmasm",
        example().to_str().unwrap(),
        "-o",
        xcp.to_str().unwrap(),
    ]);
    assert!(out.status.success());
    let dis = plcc(&["disasm", xcp.to_str().unwrap()]);
    assert!(
        dis.status.success(),
        "{}",
        String::from_utf8_lossy(&dis.stderr)
    );
    let text = String::from_utf8(dis.stdout).unwrap();
    // Every instruction line of the listing comes back with the same bytes.
    let hex = |s: &str| -> Vec<(String, String)> {
        s.lines()
            .filter_map(|l| {
                let mut p = l.split('|');
                let addr = p.next()?.trim().to_string();
                let bytes = p.next()?.trim().to_string();
                (addr.starts_with(':') && !bytes.is_empty()).then_some((addr, bytes))
            })
            .collect()
    };
    assert_eq!(hex(&text), hex(&listing));
    assert!(
        text.contains(":?plcc.traffic_light?CODE"),
        "labels come from the dcp"
    );
}

#[test]
fn bad_settings_and_images_are_errors() {
    let out = plcc(&[
        "--target",
        "vmasm",
        "-s",
        "mode=8",
        example().to_str().unwrap(),
        "-o",
        "-",
    ]);
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("E9103"));
    let out = plcc(&[
        "--target",
        "vmasm",
        "-s",
        "speed=9",
        example().to_str().unwrap(),
        "-o",
        "-",
    ]);
    assert_eq!(out.status.code(), Some(1));
    let dir = scratch_dir("bad");
    let bad = dir.join("bad.xcp");
    std::fs::write(&bad, [0x1C, 0x15, 0x00]).unwrap();
    let out = plcc(&["disasm", bad.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("bad.xcp"));
    let out = plcc(&["disasm", dir.join("missing.xcp").to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
}

#[test]
fn data_beyond_16_bit_addresses_is_e9102_and_fits_in_32_bit_mode() {
    let dir = scratch_dir("big");
    let src = dir.join("big.st");
    std::fs::write(
        &src,
        "PROGRAM big\nVAR a : ARRAY[0..40000] OF DINT; i : DINT; END_VAR\n\
         FOR i := 0 TO 40000 DO a[i] := i; END_FOR;\nEND_PROGRAM\n",
    )
    .unwrap();
    let out_path = dir.join("big.xcp");
    let out = plcc(&[
        "--target",
        "vmasm",
        src.to_str().unwrap(),
        "-o",
        out_path.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("E9102") && err.contains("bytes of data memory"),
        "{err}"
    );
    assert!(!out_path.exists(), "no output from a failed build");
    let out = plcc(&[
        "--target",
        "vmasm",
        "-s",
        "mode=32",
        src.to_str().unwrap(),
        "-o",
        out_path.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let run = plcc(&[
        "run",
        "--target",
        "vmasm",
        "-s",
        "mode=32",
        src.to_str().unwrap(),
    ]);
    let text = String::from_utf8_lossy(&run.stdout);
    assert!(text.contains("a[40000] = 40000"), "{text}");
}

#[test]
fn an_operation_without_vm_instructions_is_e9101_at_its_source() {
    let text = r#"
file 0 "t.st"
struct %main program {
    var x: f32 REAL
}
data @main: %main program
func @main(ptr) program {
block0(v0: ptr):
    v1 = field_addr v0, %main.x
    v2 = load.f32 v1
    v3 = fatan2 v2, v2   !0:10..20
    store v3, v1
    return
}
func @main$init(ptr) init {
block0(v0: ptr):
    v1 = field_addr v0, %main.x
    v2 = fconst.f32 1.0
    store v2, v1
    return
}
program "main" data @main body @main init @main$init
"#;
    let module = plcc_ir::text::parse_module(text).expect("IR text");
    let err = plcc_vmasm::VmasmBackend::new()
        .compile(&module, &Options::default())
        .expect_err("no VM instruction for ATAN2");
    assert_eq!(err[0].code, "E9101");
    assert!(err[0].message.contains("ATAN2"));
    assert!(err[0].span.is_some(), "the error points at the operation");
}

/// `-s port=NAME`: an instruction the chosen CPDev VM port lacks is error E9105 at
/// the source that needs it (the ESP32 and AVR builds have no LREAL or 64-bit
/// integers; the 6502 and sdcc builds no REAL either); the default port, `full`,
/// takes everything, and an integer program builds for every port.
#[test]
fn what_a_port_lacks_is_e9105_at_its_source() {
    let dir = scratch_dir("port");
    let lreal = dir.join("lreal.st");
    std::fs::write(
        &lreal,
        "PROGRAM main\nVAR x : LREAL := 1.5; n : INT := 3; END_VAR\n    n := n * 2;\n    x := x * 2.0;\nEND_PROGRAM\n",
    )
    .unwrap();
    let ints = dir.join("ints.st");
    std::fs::write(
        &ints,
        "PROGRAM main\nVAR n : INT := 3; d : DINT; END_VAR\n    n := n * 2;\n    d := INT_TO_DINT(n) / 3;\nEND_PROGRAM\n",
    )
    .unwrap();
    let xcp = dir.join("out.xcp");
    let build = |port: &str, src: &Path| {
        plcc(&[
            "--target",
            "vmasm",
            "-s",
            &format!("port={port}"),
            src.to_str().unwrap(),
            "-o",
            xcp.to_str().unwrap(),
        ])
    };
    assert!(build("full", &lreal).status.success());
    for port in ["esp32", "avr", "6502", "sdcc"] {
        let out = build(port, &lreal);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{port}: {err}");
        assert!(err.contains("error[E9105]"), "{port}: {err}");
        assert!(err.contains(&format!("port `{port}`")), "{port}: {err}");
        assert!(err.contains("lreal.st:4:"), "{port}: the span: {err}");
        let ok = build(port, &ints);
        assert!(
            ok.status.success(),
            "{port}: {}",
            String::from_utf8_lossy(&ok.stderr)
        );
    }
    let err = String::from_utf8_lossy(&build("esp32", &lreal).stderr).to_string();
    assert!(err.contains("LREAL"), "{err}");
    let out = build("z80", &ints);
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("E9103"));
}

/// The DCP describes what a CPDev tool needs to show the variables: IEC type names
/// (never the IR's `i32`/`i1`), a configuration's globals once and without the task
/// state the front end adds, the fault word, an array's element type and every
/// dimension, the members of an array of STRUCTs, and DATE/TOD/DT by what they hold.
#[test]
fn the_description_names_types_as_iec_does() {
    let src = "TYPE pt : STRUCT x : INT; y : DINT; END_STRUCT; END_TYPE
PROGRAM p
VAR_INPUT inp : INT; END_VAR
VAR a : ARRAY[1..4] OF INT; m : ARRAY[1..2, 0..3] OF INT; s : ARRAY[0..2] OF pt;
 d : DATE := D#2024-03-15; str : STRING[10]; END_VAR
a[1] := inp;
END_PROGRAM
CONFIGURATION c
VAR_GLOBAL g : INT; END_VAR
RESOURCE r ON plc
TASK t (INTERVAL := T#20ms, PRIORITY := 1);
TASK t2 (INTERVAL := T#30ms, PRIORITY := 2);
PROGRAM i1 WITH t : p (inp := g);
PROGRAM i2 WITH t2 : p (inp := g);
END_RESOURCE
END_CONFIGURATION
";
    let module = build_sources(
        vec![("c.st".to_string(), src.as_bytes().to_vec())],
        &BuildOptions::default(),
    )
    .unwrap()
    .module
    .unwrap();
    for mode in ["16", "32a"] {
        let options = Options {
            settings: vec![("mode".into(), mode.into())],
            ..Default::default()
        };
        let arts = plcc_vmasm::VmasmBackend::new()
            .compile(&module, &options)
            .unwrap();
        let dcp = String::from_utf8(arts.files[1].bytes.clone()).unwrap();
        let global = &dcp[dcp.find("<GLOBAL>").unwrap()..dcp.find("</GLOBAL>").unwrap()];
        assert_eq!(global.matches("<VAR ").count(), 2, "{global}");
        assert!(global.contains("LName=\"g\"") && global.contains("Type=\"INT\""));
        assert!(global.contains("LName=\"PLCC_FAULT\"") && global.contains("Type=\"WORD\""));
        assert!(!dcp.contains("Type=\"i32\"") && !dcp.contains("Type=\"i1\""));
        assert!(!dcp.contains("LName=\"last\"") && !dcp.contains("LName=\"started\""));
        assert!(dcp.contains("ArrayBase=\"INT\""));
        assert!(dcp.contains("<LEVEL No=\"1\" LoBound=\"0\" UpBound=\"3\" />"));
        assert!(dcp.contains("ArrayBase=\"pt\""));
        assert!(dcp.contains("PName=\"plcc.TASK.i2.s[0].y\""));
        assert!(dcp.contains("Type=\"UDINT\" PType=\"$DEFAULT.UDINT\" TypeStatus=\"build-in type\" VFlags=\"00000000\" PlccType=\"DATE\""));
        assert!(dcp.contains("PlccType=\"STRING[10]\""));
        assert!(dcp.contains("TypeStatus=\"program\""));
        assert_eq!(dcp.contains("AddressSize=\"8\""), mode != "16");
        // The task cycle is the common tick of 20 and 30 ms, so each runs when due.
        assert!(dcp.contains("Cycle=\"10\""), "the task cycle");
        // plcc's own reader still finds every variable where plcc put it.
        let read = dcp_read::parse(&dcp).unwrap();
        // (Globals are at the top level; a task's hidden state is not listed.)
        // Elements are not listed: an array's address, bounds and ElementSize give
        // them (checked for one element below).
        let m = read.find_var("plcc.TASK.i2.m").expect("the array m");
        let m23 = arts
            .symbols
            .iter()
            .find(|s| s.path == "i2.m[2][3]")
            .unwrap();
        // m[2][3]: (2 - 1) rows of 4 INTs, then 3 INTs, from m[1][0].
        let (row, col) = (1u64, 3u64);
        assert_eq!(m.addr as u64 + (row * 4 + col) * 2, m23.address);
        for s in arts
            .symbols
            .iter()
            .filter(|s| !s.path.contains("$state") && !s.path.contains('['))
        {
            let path = match s.path.strip_prefix("$globals.") {
                Some(g) => format!("plcc.{g}"),
                None => format!("plcc.TASK.{}", s.path),
            };
            let v = read
                .find_var(&path)
                .unwrap_or_else(|| panic!("the data map has no {path}"));
            assert_eq!(v.addr as u64, s.address, "{}", s.path);
        }
    }
}
