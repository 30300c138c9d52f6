//! Charts under `--sfc matiec` against matiec itself: the textual SFC programs of
//! `../shared/reference/plcopen-semantics-samples/sfc_text_*.st` were run by matiec
//! (10 ms ticks from 0), and their `.trace.txt` files hold the state after every scan.
//! plcc's build of each program must give the same state after every scan on every
//! machine. Skipped, with a notice, when `../shared` is absent.

use plcc::driver::{build_sources, BuildOptions};
use plcc::targets;
use plcc_frontend::sfc::Profile;
use std::path::{Path, PathBuf};

#[path = "common/skip.rs"]
mod skip;

/// The codes of a program too large for the target.
const UNFIT: [&str; 4] = ["E9001", "E9002", "E9003", "E9004"];

/// Each trace's columns and the variables they show.
const TRACES: &[(&str, &[(&str, &str)])] = &[
    (
        "sfc_text_qualifiers",
        &[
            ("S0", "inst.S0.X"),
            ("S1", "inst.S1.X"),
            ("S2", "inst.S2.X"),
            ("T2", "inst.S2.T"),
            ("P", "inst.pcnt"),
            ("P0", "inst.p0cnt"),
            ("vN", "inst.vN"),
            ("N", "inst.ncnt"),
            ("L", "inst.lcnt"),
            ("D", "inst.dcnt"),
            ("S", "inst.scnt"),
            ("vS", "inst.vS"),
            ("vD", "inst.vD"),
        ],
    ),
    (
        "sfc_text_selfloop",
        &[
            ("S0", "inst.S0.X"),
            ("S1", "inst.S1.X"),
            ("T1", "inst.S1.T"),
            ("P", "inst.pc"),
            ("N", "inst.nc"),
            ("tInAction", "inst.t1"),
        ],
    ),
    (
        "sfc_text_stored_and_p_override",
        &[
            ("S0", "inst.S0.X"),
            ("S1", "inst.S1.X"),
            ("S2", "inst.S2.X"),
            ("S3", "inst.S3.X"),
            ("A", "inst.acnt"),
            ("SL", "inst.slcnt"),
            ("SD", "inst.sdcnt"),
            ("DS", "inst.dscnt"),
            ("S", "inst.scnt"),
        ],
    ),
    (
        "sfc_text_unprioritised_divergence",
        &[
            ("S0", "inst.S0.X"),
            ("S1", "inst.S1.X"),
            ("S2", "inst.S2.X"),
            ("cnt1", "inst.cnt1"),
            ("cnt2", "inst.cnt2"),
            ("pcnt", "inst.pcnt"),
        ],
    ),
];

fn samples() -> Option<PathBuf> {
    let p =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/reference/plcopen-semantics-samples");
    p.is_dir().then_some(p)
}

/// A value as the traces write it: `1`/`0` for BOOL, `10ms` for TIME.
fn trace_form(v: plcc_ir::value::PlcValue) -> String {
    let s = v.to_string();
    match s.as_str() {
        "TRUE" => "1".into(),
        "FALSE" => "0".into(),
        _ => s.strip_prefix("T#").map_or(s.clone(), str::to_string),
    }
}

#[test]
fn matiec_profile_matches_matiec_scan_by_scan() {
    let Some(dir) = samples() else {
        skip::notice("../shared/reference is absent: the matiec SFC traces are skipped");
        return;
    };
    let mut failures = Vec::new();
    let mut compared = 0;
    let mut unfit = 0;
    for (name, columns) in TRACES {
        let st = dir.join(format!("{name}.st"));
        let trace = std::fs::read_to_string(dir.join(format!("{name}.trace.txt")))
            .unwrap_or_else(|e| panic!("{name}.trace.txt: {e}"));
        let bytes = std::fs::read(&st).unwrap_or_else(|e| panic!("{name}.st: {e}"));
        let opts = BuildOptions {
            sfc: Profile::Matiec,
            ..Default::default()
        };
        let build = build_sources(vec![(st.display().to_string(), bytes)], &opts)
            .unwrap_or_else(|e| panic!("{name}: {}", e.0));
        let Some(module) = build.module else {
            let errs: Vec<String> = build.diagnostics.iter().map(|d| d.to_string()).collect();
            failures.push(format!("{name} does not compile: {}", errs.join("; ")));
            continue;
        };
        for target in targets::checked_machines().iter().map(String::as_str) {
            let mut m = match targets::machine_spec(target, &module) {
                Ok(m) => m,
                // The program does not fit the chip: counted, not a failure.
                Err(d) if UNFIT.contains(&d[0].code) => {
                    eprintln!("{name} does not fit {target}: {}", d[0]);
                    unfit += 1;
                    continue;
                }
                Err(d) => {
                    failures.push(format!("{name} on {target}: {}", d[0]));
                    continue;
                }
            };
            m.cold_start().expect("cold start");
            for (k, line) in trace.lines().enumerate() {
                m.set_clock_us(k as i64 * 10_000);
                m.scan().expect("scan");
                let want: Vec<(&str, &str)> = line
                    .split_once(':')
                    .map(|(_, rest)| rest)
                    .unwrap_or("")
                    .split_whitespace()
                    .filter_map(|kv| kv.split_once('='))
                    .collect();
                for (col, value) in want {
                    let path = columns
                        .iter()
                        .find(|(c, _)| *c == col)
                        .map(|(_, p)| *p)
                        .unwrap_or_else(|| panic!("{name}: no variable for column {col}"));
                    let got = trace_form(
                        m.read(path)
                            .unwrap_or_else(|e| panic!("{name} on {target}: {path}: {e}")),
                    );
                    compared += 1;
                    if got != value {
                        failures.push(format!(
                            "{name} on {target}, scan {k}: {col} ({path}) is {got}, matiec {value}"
                        ));
                    }
                }
            }
        }
    }
    eprintln!("{compared} values compared; {unfit} builds do not fit their target");
    assert!(
        unfit <= 1,
        "more programs than sfc_text_qualifiers on pic16f876a do not fit"
    );
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[path = "common/lockstep.rs"]
mod lockstep;
#[path = "common/rng.rs"]
#[allow(dead_code)]
mod rng;

/// The configuration the samples' XML files have, for the editor's ST of their
/// program (which holds the program only), so that both builds name the instance `i`.
const SAMPLE_CONFIG: &str = "\nCONFIGURATION C\n  RESOURCE R ON PLC\n    \
    TASK t(INTERVAL := T#20ms, PRIORITY := 0);\n    PROGRAM i WITH t : P;\n  \
    END_RESOURCE\nEND_CONFIGURATION\n";

/// A variable the comparison writes: one of the program's own, not one a translator
/// or plcc makes (edge detectors, temporaries, chart state).
fn writable(path: &str) -> bool {
    let last = path.rsplit('.').next().unwrap_or("").to_ascii_uppercase();
    path.split('.').count() == 2
        && !last.starts_with("R_TRIG")
        && !last.starts_with("F_TRIG")
        && !last.starts_with("_TMP_")
        && !last.starts_with("__")
}

/// The charts of the samples' XML, as plcc writes them into textual SFC, against the
/// textual SFC the editor (OpenPLC Editor v3) wrote for them: both built under
/// `--sfc matiec` (what the editor's runtime runs), 1,000 scans with random inputs on
/// every machine, equal on every variable both have after every scan.
#[test]
fn xml_charts_run_as_the_editors_text() {
    let Some(dir) = samples() else {
        skip::notice("../shared/reference is absent: the SFC sample comparison is skipped");
        return;
    };
    let build = |files: Vec<(String, Vec<u8>)>| {
        let opts = BuildOptions {
            sfc: Profile::Matiec,
            ..Default::default()
        };
        build_sources(files, &opts)
            .unwrap_or_else(|e| panic!("{}", e.0))
            .into_module()
            .unwrap_or_else(|e| panic!("{e}"))
    };
    let mut failures = Vec::new();
    let (mut compared, mut written) = (0, 0);
    for name in ["sfc_graphical", "sfc_named_transitions"] {
        let xml = dir.join(format!("{name}.xml"));
        let st = dir.join(format!("{name}.openplc-v3.st"));
        let a = build(vec![(
            xml.display().to_string(),
            std::fs::read(&xml).expect("the sample's XML"),
        )]);
        let mut text = std::fs::read(&st).expect("the editor's ST");
        text.extend_from_slice(SAMPLE_CONFIG.as_bytes());
        let b = build(vec![(st.display().to_string(), text)]);
        for target in targets::checked_machines().iter().map(String::as_str) {
            match lockstep::run(
                &a,
                &b,
                target,
                1000,
                20,
                0x5FC0 + name.len() as u64,
                &writable,
                &|_| true,
            ) {
                Ok(Some(o)) => {
                    compared += o.compared;
                    written += o.inputs;
                }
                Ok(None) => eprintln!("{name} does not fit {target}"),
                Err(e) => failures.push(format!("{name} on {target}: {e}")),
            }
        }
    }
    eprintln!("{compared} variables compared after each of 1,000 scans, {written} written");
    assert!(compared > 40, "too little compared: {compared}");
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// A graphical condition's blocks (here a rising edge, `c AND R_TRIG1.Q` in
/// `sfc_graphical.xml`) are computed when the condition is tested under `iec`, and
/// with the actions, after the tests, under `matiec`: there the transition fires one
/// scan late.
#[test]
fn graphical_condition_blocks_are_late_only_under_matiec() {
    let Some(dir) = samples() else {
        skip::notice("../shared/reference is absent: the graphical condition test is skipped");
        return;
    };
    let xml = dir.join("sfc_graphical.xml");
    for (profile, fires_at) in [(Profile::Iec, 3), (Profile::Matiec, 4)] {
        let opts = BuildOptions {
            sfc: profile,
            ..Default::default()
        };
        let bytes = std::fs::read(&xml).expect("the sample");
        let b = build_sources(vec![(xml.display().to_string(), bytes)], &opts)
            .unwrap_or_else(|e| panic!("{}", e.0));
        let module = b.module.expect("the sample compiles");
        for target in targets::checked_machines().iter().map(String::as_str) {
            let mut m = match targets::machine_spec(target, &module) {
                Ok(m) => m,
                Err(d) if UNFIT.contains(&d[0].code) => continue,
                Err(d) => panic!("{target}: {}", d[0]),
            };
            m.cold_start().expect("cold start");
            let set = |m: &mut Box<dyn plcc_ir::machine::Machine>, var: &str, on: bool| {
                let v = plcc_ir::value::PlcValue::parse(
                    plcc_ir::ElemType::Bool,
                    if on { "TRUE" } else { "FALSE" },
                )
                .expect("a BOOL");
                m.write(var, v).unwrap_or_else(|e| panic!("{var}: {e}"));
            };
            let mut fired = None;
            for k in 0..6u32 {
                // Scan 0 in S0 (matiec stores COMPUTE_FUNCTION_BLOCKS's S then:
                // had S0 been left in scan 0, never); scan 1: S0 -> S1. From
                // scan 2, c; d rises in scan 3.
                set(&mut m, "i.start", k == 1);
                set(&mut m, "i.c", k >= 2);
                set(&mut m, "i.d", k >= 3);
                m.set_clock_us(i64::from(k) * 20_000);
                m.scan().expect("scan");
                let s7 = m.read("i.S7.X").expect("S7.X").to_string() == "TRUE";
                if s7 && fired.is_none() {
                    fired = Some(k);
                }
            }
            assert_eq!(
                fired,
                Some(fires_at),
                "{} on {target}: S7 became active in scan {fired:?}",
                profile.name()
            );
        }
    }
}

/// `plcc --emit sfc-text` draws a chart and `--emit st` shows the ST it is written
/// as (a file of the repository: never skipped).
#[test]
fn the_cli_draws_a_chart_and_shows_its_st() {
    let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/programs/sfc/mixing_tank.st");
    let run = |emit: &str| {
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_plcc"))
            .args(["--emit", emit])
            .arg(&file)
            .output()
            .expect("plcc runs");
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        String::from_utf8(o.stdout).expect("UTF-8")
    };
    let drawing = run("sfc-text");
    assert!(
        drawing.starts_with("PROGRAM main: 7 steps, 6 transitions\n"),
        "{drawing}"
    );
    assert!(
        drawing.contains("[[Idle]]  (initial)\n  +--> #1 start  ==> (FillA, FillB)\n"),
        "{drawing}"
    );
    assert!(drawing.contains("  | L  stirrer (T#40ms)\n"), "{drawing}");
    let st = run("st");
    // Laid out by `plcc fmt` (the declarations' colons aligned): compared by words.
    let words = st.split_whitespace().collect::<Vec<_>>().join(" ");
    assert!(words.contains("Idle : __SFC_STEP := (X := TRUE);"), "{st}");
    assert!(st.contains("\n    Idle    "), "not formatted:\n{st}");
    assert!(st.contains("END_PROGRAM"), "{st}");
}
