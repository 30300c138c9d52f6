//! The editors' own translations as an oracle for plcc's reading of PLCopen XML.
//!
//! For some projects of `../shared/corpus/plcopen/`, the corpus also holds the ST
//! the editor (OpenPLC Editor v3) wrote for the project (`NAME.generated.st`): what
//! its diagrams mean to the editor. plcc builds both, the XML under the matching
//! profile (`--plcopen-order openplc3`), and runs them side by side on every machine
//! that can hold them for [`SCANS`] scans, with the same random values written to the
//! programs' variables before every scan; after every scan every variable the two
//! builds share must be equal. Hidden variables (the function results and edge
//! detectors both make) are compared too where both have them.
//!
//! A project that plcc cannot build from either form is listed with the reason, and
//! must be in [`NOT_BUILT`] (so that the list stays exact). Skipped, with a notice,
//! when `../shared` is absent.

#[path = "common/lockstep.rs"]
mod lockstep;
#[path = "common/rng.rs"]
#[allow(dead_code)]
mod rng;

use plcc::driver::{build_sources, BuildOptions};
use plcc_frontend::plcopen::{Options, Profile};
use plcc_ir::Module;
use std::path::{Path, PathBuf};

#[path = "common/skip.rs"]
mod skip;

/// Scans per project and machine.
const SCANS: u32 = 1000;

/// The profile of each project whose translation does not come from OpenPLC Editor
/// v3's generator (`openplc3`, the default here), with the evidence.
const PROFILES: &[(&str, Profile)] = &[
    // Generated in 2023 by an OpenPLC Editor of the Python-2 line: its coils are in
    // the order of their positions (stop_status, sys_run, RUN_STATUS, sys_run,
    // system_out), not of the document (system_out is the second coil there).
    ("sakunamary__Roaster_s7-200__openplc", Profile::Legacy),
];

/// Library files of the corpus a project needs (as `--lib`): the blocks its editor
/// takes from a library rather than from the project.
const LIBS: &[(&str, &str)] = &[(
    "gracesrm__OpenPLC_Sample_Programs__PT_Motor_PID_Wave",
    "beremiz__beremiz__plcopen_Additional_Function_Blocks.xml",
)];

/// Stubs of vendor blocks (`tests/plcopen_stubs/`, as the corpus test builds the
/// projects) that both builds of a project take, as `--lib`: the vendor's blocks are
/// the same stub on both sides, so the comparison is of the diagram's meaning.
const STUBS: &[(&str, &str)] = &[
    (
        "gracesrm__OpenPLC_Sample_Programs__RobotStudio_Estun",
        "openplc_robotstudio.st",
    ),
    ("sakunamary__Roaster_s7-200__I2C_test", "openplc_boards.st"),
];

/// Projects with an editor translation that plcc does not build, and why (none: the
/// last one, Roaster's I2C_test, reads an FB instance's ENO, which plcc now keeps).
const NOT_BUILT: &[(&str, &str)] = &[];

/// Projects whose editor translation is of another revision of the project: both
/// sides must build, and are not compared.
const OTHER_REVISION: &[(&str, &str)] = &[(
    "sakunamary__Roaster_s7-200__I2C_test",
    "the translation's get_temp initialises sck := 5 and sda := 4 and calls the block with \
     EN := TRUE under IF I2C_AHT200.ENO, where the XML has NODE_PIN_D5 and NODE_PIN_D4 \
     (the board's constants: 14 and 2) and no EN or ENO",
)];

fn corpus() -> Option<PathBuf> {
    let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/corpus/plcopen");
    p.is_dir().then_some(p)
}

fn build(path: &Path, libs: &[PathBuf], profile: Profile) -> Result<Module, String> {
    let mut files = Vec::new();
    for p in std::iter::once(path).chain(libs.iter().map(PathBuf::as_path)) {
        let bytes = std::fs::read(p).map_err(|e| e.to_string())?;
        files.push((p.display().to_string(), bytes));
    }
    let opts = BuildOptions {
        plcopen: Options {
            profile,
            strict_rungs: false,
        },
        ..Default::default()
    };
    build_sources(files, &opts).map_err(|e| e.0)?.into_module()
}

/// A variable the test writes: a variable of a program instance (`inst.x`) or a
/// global (`x`), not a member of a block instance, not one the translators make.
fn writable(path: &str) -> bool {
    path.split('.').count() <= 2 && !hidden(path)
}

fn hidden(path: &str) -> bool {
    let last = path.rsplit('.').next().unwrap_or("").to_ascii_uppercase();
    last.starts_with("_TMP_") || last.starts_with("R_TRIG") || last.starts_with("F_TRIG")
}

#[test]
fn xml_and_the_editors_st_agree_scan_by_scan() {
    let Some(dir) = corpus() else {
        skip::notice(
            "../shared/corpus/plcopen is absent: the editor-translation oracle is skipped",
        );
        return;
    };
    let mut pairs: Vec<PathBuf> = std::fs::read_dir(&dir)
        .expect("corpus directory")
        .filter_map(|e| {
            let p = e.ok()?.path();
            p.to_str()?.ends_with(".generated.st").then_some(p)
        })
        .collect();
    pairs.sort();
    assert!(
        pairs.len() >= 9,
        "expected the corpus's 9 editor translations, found {}",
        pairs.len()
    );
    let mut failures = Vec::new();
    let mut not_built = Vec::new();
    let mut report = Vec::new();
    // Every machine of the target registry that runs here (the C one under UBSan).
    let machines = plcc::targets::checked_machines();
    for st in &pairs {
        let stem = st
            .file_name()
            .unwrap()
            .to_str()
            .unwrap()
            .trim_end_matches(".generated.st")
            .to_string();
        let xml = dir.join(format!("{stem}.xml"));
        let profile = PROFILES
            .iter()
            .find(|(n, _)| *n == stem)
            .map_or(Profile::Openplc3, |(_, p)| *p);
        let libs: Vec<PathBuf> = LIBS
            .iter()
            .filter(|(n, _)| *n == stem)
            .map(|(_, l)| dir.join(l))
            .chain(STUBS.iter().filter(|(n, _)| *n == stem).map(|(_, l)| {
                Path::new(env!("CARGO_MANIFEST_DIR"))
                    .join("tests/plcopen_stubs")
                    .join(l)
            }))
            .collect();
        let (a, b) = match (build(&xml, &libs, profile), build(st, &libs, Profile::Iec)) {
            (Ok(a), Ok(b)) => (a, b),
            (a, b) => {
                let why = [a.err(), b.err()]
                    .into_iter()
                    .flatten()
                    .collect::<Vec<_>>()
                    .join(" / ");
                not_built.push((stem.clone(), why));
                continue;
            }
        };
        if let Some((_, why)) = OTHER_REVISION.iter().find(|(n, _)| *n == stem) {
            report.push(format!("{stem}: both build, not compared: {why}"));
            continue;
        }
        let cycle = a.task_tick_us().map_or(10, |us| us.div_ceil(1000) as u32);
        let mut ran = Vec::new();
        for target in &machines {
            let target = target.as_str();
            let seed = 0x9E37_79B9_7F4A_7C15 ^ stem.len() as u64;
            match lockstep::run(&a, &b, target, SCANS, cycle, seed, &writable, &|_| true) {
                Ok(Some(o)) => ran.push(format!(
                    "{target} ({} compared, {} written)",
                    o.compared, o.inputs
                )),
                Ok(None) => ran.push(format!("{target} (does not fit)")),
                Err(e) => failures.push(format!("{stem} on {target}: {e}")),
            }
        }
        report.push(format!("{stem} ({}): {}", profile.name(), ran.join(", ")));
    }
    for r in &report {
        eprintln!("{r}");
    }
    let listed: Vec<&str> = NOT_BUILT.iter().map(|(n, _)| *n).collect();
    for (n, why) in &not_built {
        eprintln!("not built: {n}: {why}");
        if !listed.contains(&n.as_str()) {
            failures.push(format!(
                "{n} is not built and not listed in NOT_BUILT: {why}"
            ));
        }
    }
    for n in &listed {
        if !not_built.iter().any(|(m, _)| m == n) {
            failures.push(format!(
                "{n} is listed in NOT_BUILT but builds: take it off the list"
            ));
        }
    }
    assert!(
        report.len() >= 6,
        "fewer than 6 projects compared: {report:#?}"
    );
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
