//! Snapshots of the PIC16F876A assembly plcc generates for small programs
//! (`tests/pic16/*.st`): the code of the programs, FBs, functions and runtime helpers
//! (the vectors and the scan loop are the same for every program and left out).
//!
//! Each snapshot was read and checked by hand: the arithmetic idioms, the bank
//! selects (only where the bank changes, never between a skip and what it skips) and
//! the BOOLs as bits. `tests/pic16_gpsim.rs` checks that gpasm and gpsim agree with
//! plcc about the same programs.

use plcc::driver::{build_sources, source_texts, BuildOptions};
use plcc_ir::backend::{Backend, Options};
use std::path::PathBuf;

fn listing(name: &str) -> String {
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
    let summary = arts.summary.unwrap_or_default();
    format!("; {summary}\n{out}")
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
