//! Every real PLCopen project of `../shared/corpus/plcopen/`, compiled as a user would
//! compile it, with its outcome.
//!
//! Each file is built with the libraries its editor builds it with (Beremiz's
//! `py_ext`, `NativeLib`, `Additional_Function_Blocks` and `svgui` libraries, which
//! are files of the corpus too) and, for the blocks, types and globals that a runtime
//! or an editor extension provides in C, a user's stubs of them
//! (`tests/plcopen_stubs/`, passed as `--lib` would pass them). [`CASES`] lists every
//! file with what it needs and how it must come out: it compiles, or it fails, for a
//! reason written down; [`SFC_FILES`] names the 11 with SFC bodies (counted apart). The list must be exact: a file
//! missing from it, a file that does better or worse than listed, fails the test, so
//! the table below is the record of what plcc does with the corpus.
//!
//! Skipped, with a notice, when `../shared` is absent.

use plcc::driver::{build_sources_with_library, BuildOptions};
use std::path::{Path, PathBuf};

/// How a file must come out.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Expect {
    /// It compiles.
    Compiles,
    /// It does not compile, for the reason given; its errors carry these codes only.
    Fails(&'static str, &'static [&'static str]),
}
use Expect::*;

#[path = "common/skip.rs"]
mod skip;

/// One file: its name (without `.xml`), the corpus libraries and the stubs it is
/// built with, and its outcome.
struct Case {
    file: &'static str,
    libs: &'static [&'static str],
    stubs: &'static [&'static str],
    expect: Expect,
}

/// The files with SFC bodies (IEC 61131-3's charts), counted apart.
const SFC_FILES: [&str; 11] = [
    "Fantazzj__CodeSys-SFC-to-Cpp-converter__test",
    "MichielVanwelsenaere__HomeAutomation.CoDeSys3__src_Exports_PLCopen",
    "MichielVanwelsenaere__HomeAutomation.CoDeSys3__src_PLCopen_HomeAutomation",
    "VerifAPS__verifaps-lib__share_PPU_Scenario0_Final",
    "VerifAPS__verifaps-lib__share_PPU_Scenario9_Final",
    "VerifAPS__verifaps-lib__share_xPPU_PLCOpenXML_Scenario_1",
    "VerifAPS__verifaps-lib__xml_src_test_resources_test_st_in_main_and_nested_sfc",
    "beremiz__matiec__tests_SFC_TEST",
    "elian15122000__TINF19C-PLCOpen-Editor__SOURCE_src_assets",
    "jubnzv__iec-checker__test_plcopen_example",
    "tan-wei-xin-alez__codesys_plcopenxml_for_git__test_example_project",
];

const PY_EXT: &str = "beremiz__beremiz__py_ext_pous";
const NATIVE: &str = "beremiz__beremiz__NativeLib";
const ADDITIONAL: &str = "beremiz__beremiz__plcopen_Additional_Function_Blocks";
const SVGUI: &str = "beremiz__beremiz__svgui_pous";

const fn case(file: &'static str, expect: Expect) -> Case {
    Case {
        file,
        libs: &[],
        stubs: &[],
        expect,
    }
}

const fn with(
    file: &'static str,
    libs: &'static [&'static str],
    stubs: &'static [&'static str],
    expect: Expect,
) -> Case {
    Case {
        file,
        libs,
        stubs,
        expect,
    }
}

/// Every file of the corpus.
const CASES: &[Case] = &[
    case("AandIF__e-COCKPIT_python_scripting", Compiles),
    case("Fantazzj__CodeSys-SFC-to-Cpp-converter__test", Fails("a converter's test chart: an INT variable (`outDS`) associated as an action, which CODESYS and IEC allow only for BOOL variables", &["E0783"])),
    case("FelipeWoo__smart-factory-integration__openplc", Compiles),
    // Their methods, properties, inheritance and interfaces are read (issue 20), the
    // commas before a call's `)` and the `COVER_STATES.Idle` enumeration values are
    // accepted. What remains is mostly CODESYS's libraries, which plcc does not have:
    // MQTT, OSCAT_BASIC, OSCAT_BUILDING, WagoAppPlcModbus, Util, SysMem/SysSock
    // (E0201, E0203, an interface of the MQTT library E0800, and their types' uses,
    // E0301); besides, positional arguments after named ones (E0402), `ADR('TRUE')`
    // of a string literal (E0504) and, in the Exports file, two configurations (one
    // per device: E0202), pointers indexed as arrays (`pt[i]`, E0303) and array
    // bounds given by a library's constant (E0206).
    case(
        "MichielVanwelsenaere__HomeAutomation.CoDeSys3__src_Exports_PLCopen",
        Fails(
            "CODESYS libraries plcc does not have (MQTT, OSCAT, WAGO), two devices' \
             configurations, pointer indexing, arguments positional after named ones",
            &[
                "E0201", "E0202", "E0203", "E0206", "E0301", "E0303", "E0402", "E0504",
                "E0800",
            ],
        ),
    ),
    case(
        "MichielVanwelsenaere__HomeAutomation.CoDeSys3__src_PLCopen_HomeAutomation",
        Fails(
            "CODESYS libraries plcc does not have (MQTT, OSCAT, WAGO), arguments \
             positional after named ones, ADR of a string literal",
            &["E0201", "E0203", "E0301", "E0402", "E0504", "E0800"],
        ),
    ),
    case("VerifAPS__verifaps-lib__share_PPU_Scenario0_Final", Compiles),
    case("VerifAPS__verifaps-lib__share_PPU_Scenario9_Final", Compiles),
    // CODESYS's access rules: internal variables of instances read from outside,
    // `GVL.x`, `Main.x`, actions called with arguments (`Crane.ACT_Init(SFCReset :=
    // FALSE)`).
    case("VerifAPS__verifaps-lib__share_xPPU_PLCOpenXML_Scenario_1", Compiles),
    case(
        "VerifAPS__verifaps-lib__xml_src_test_resources_FBDExample",
        Fails(
            "a verification tool's test fixture: CODESYS's EXECUTE box (ST code kept in \
             vendor data, no IEC block), a MUX of an INT and BOOLs, jumps on an INT",
            &["E0201", "E0301"],
        ),
    ),
    case(
        "VerifAPS__verifaps-lib__xml_src_test_resources_test_st_in_main_and_nested_sfc",
        Compiles,
    ),
    case(
        "amuslija__fbd-complexity-tool__examples",
        Fails(
            "a TIME variable's initial value is the integer 2, which IEC (and matiec) reject",
            &["E0301"],
        ),
    ),
    case(
        "amuslija__fbd-complexity-tool__src_test_resources_test1",
        Fails(
            "a TIME variable's initial value is the integer 2, which IEC (and matiec) reject",
            &["E0301"],
        ),
    ),
    case("appliedrelevance__epibus__openplc", Compiles),
    case("beremiz__beremiz__NativeLib", Compiles),
    with("beremiz__beremiz__etherlab_pous", &[PY_EXT], &[], Compiles),
    with(
        "beremiz__beremiz__exemples_csv_read",
        &[PY_EXT],
        &["svghmi"],
        Compiles,
    ),
    case("beremiz__beremiz__exemples_modbus", Compiles),
    with(
        "beremiz__beremiz__exemples_python",
        &[PY_EXT, ADDITIONAL],
        &["beremiz_extension_globals"],
        Compiles,
    ),
    with(
        "beremiz__beremiz__exemples_svghmi_foreach",
        &[PY_EXT],
        &["svghmi"],
        Compiles,
    ),
    with(
        "beremiz__beremiz__exemples_svghmi_jumps",
        &[PY_EXT, NATIVE],
        &["svghmi"],
        Compiles,
    ),
    with(
        "beremiz__beremiz__exemples_svghmi_references",
        &[PY_EXT],
        &["svghmi"],
        Compiles,
    ),
    case(
        "beremiz__beremiz__plcopen_Additional_Function_Blocks",
        Compiles,
    ),
    case(
        "beremiz__beremiz__plcopen_Standard_Function_Blocks",
        Compiles,
    ),
    case("beremiz__beremiz__py_ext_pous", Compiles),
    with("beremiz__beremiz__svgui_pous", &[PY_EXT], &[], Compiles),
    with(
        "beremiz__beremiz__tests_ethercat_wago_higen",
        &[],
        &["plcopen_motion"],
        Compiles,
    ),
    case("beremiz__beremiz__tests_projects_BACnet", Compiles),
    with(
        "beremiz__beremiz__tests_projects_c_runtime",
        &[NATIVE],
        &[],
        Compiles,
    ),
    case("beremiz__beremiz__tests_projects_canopen_master", Compiles),
    with(
        "beremiz__beremiz__tests_projects_iec61131_lang_test",
        &[NATIVE, ADDITIONAL],
        &[],
        Compiles,
    ),
    case("beremiz__beremiz__tests_projects_modbus_test_tcp", Compiles),
    case("beremiz__beremiz__tests_projects_mqtt_client", Compiles),
    with(
        "beremiz__beremiz__tests_projects_mqtt_ssl",
        &[],
        &["beremiz_extension_globals"],
        Compiles,
    ),
    with(
        "beremiz__beremiz__tests_projects_opcua_client",
        &[PY_EXT],
        &[],
        Compiles,
    ),
    with(
        "beremiz__beremiz__tests_projects_svghmi",
        &[PY_EXT, NATIVE],
        &["svghmi"],
        Compiles,
    ),
    with(
        "beremiz__beremiz__tests_projects_svghmi_v2",
        &[PY_EXT],
        &["svghmi"],
        Compiles,
    ),
    with(
        "beremiz__beremiz__tests_projects_svghmi_xy",
        &[PY_EXT],
        &["svghmi"],
        Compiles,
    ),
    with(
        "beremiz__beremiz__tests_projects_wamp",
        &[],
        &["beremiz_extension_globals"],
        Compiles,
    ),
    with(
        "beremiz__beremiz__tests_projects_wiimote",
        &[],
        &["beremiz_extension_globals"],
        Compiles,
    ),
    with(
        "beremiz__beremiz__tests_projects_wxGlade",
        &[PY_EXT],
        &[],
        Compiles,
    ),
    with(
        "beremiz__beremiz__tests_projects_wxHMI",
        &[PY_EXT],
        &["beremiz_extension_globals"],
        Compiles,
    ),
    with(
        "beremiz__beremiz__tests_svgui",
        &[PY_EXT, SVGUI],
        &[],
        Compiles,
    ),
    case("beremiz__matiec__tests_LD_TEST", Compiles),
    case("beremiz__matiec__tests_SFC_TEST", Compiles),
    case(
        "beremiz__matiec__tests_STD_TEST",
        Fails(
            "one MUX selects among INT and BOOL inputs (the results of LEN, EQ, EQ and \
             FIND), which IEC's MUX, whose inputs have one type, does not allow",
            &["E0301"],
        ),
    ),
    case(
        "elian15122000__TINF19C-PLCOpen-Editor__SOURCE_src_assets",
        Fails("a student editor's test asset: its chart has no initial step", &["E0761"]),
    ),
    case(
        "elian15122000__TINF19C-PLCOpen-Editor__SOURCE_src_assets_plc_valid",
        Fails(
            "a variable named `Input/OutputVariable`, which is no identifier",
            &["E0101", "E0108"],
        ),
    ),
    case("estidlore__parking-automation__openplc", Compiles),
    case("gastonfeng__kt1260_orig", Compiles),
    case(
        "gracesrm__OpenPLC_Sample_Programs__Gate_Controller",
        Compiles,
    ),
    with(
        "gracesrm__OpenPLC_Sample_Programs__PT_Motor_PID_Wave",
        &[ADDITIONAL],
        &[],
        Compiles,
    ),
    with(
        "gracesrm__OpenPLC_Sample_Programs__RobotStudio_Estun",
        &[],
        &["openplc_robotstudio"],
        Compiles,
    ),
    case(
        "gracesrm__OpenPLC_Sample_Programs__RobotStudio_RobotStudio_PLCPython",
        Fails(
            "an ST body that is prose (`I am ychj；；`), not ST",
            &["E0001", "E0108"],
        ),
    ),
    case("gracesrm__OpenPLC_Sample_Programs__Vet_snippet", Compiles),
    case(
        "gracesrm__OpenPLC_Sample_Programs__esp8266celsius",
        Compiles,
    ),
    case("jubnzv__iec-checker__test_plcopen_example", Fails("a checker's test fixture: IL bodies whose lines were re-wrapped (several instructions per line) and addresses without `%` (`M10`)", &["E0005", "E0101", "E0701", "E0703"])),
    with(
        "sakunamary__Roaster_s7-200__I2C_test",
        &[],
        &["openplc_boards"],
        Compiles,
    ),
    case("sakunamary__Roaster_s7-200__openplc", Compiles),
    // Its methods, properties (getters), inheritance (abstract FBs), interfaces
    // and STRUCT EXTENDS are read (issue 20). Without that action, what remains is
    // CODESYS's libraries, which plcc does not have (SM3_Robotics, COL, Standard,
    // SM3_Error...: E0201, E0203, E0800 for a base and an interface of COL),
    // `E_mcMotionFbType.moveCrcAbs` (an enumeration's value qualified by its
    // type), a UNION, and calls that leave out an input with an initial value
    // (`METH_appendLog('x')`, E0402).
    case(
        "tan-wei-xin-alez__codesys_plcopenxml_for_git__test_example_project",
        Fails(
            "a chart (testSFC) associates the function block instance \
             `testFBD.FB_logAdd_0` of another POU as a step's action, which plcc \
             does not run; then CODESYS libraries plcc does not have",
            &["E0783"],
        ),
    ),
    with(
        "thiagoralves__OpenPLC_Editor__editor_examples_STM32CAN_Read_Write_FBD",
        &[],
        &["openplc_boards"],
        Compiles,
    ),
    case(
        "thiagoralves__OpenPLC_Editor__editor_examples_Traffic_Light_FBD",
        Compiles,
    ),
    case(
        "thiagoralves__OpenPLC_Editor__editor_plcopen_Arduino_Function_Blocks",
        Fails(
            "OpenPLC's declarations of its Arduino blocks, implemented in C: their ST \
             bodies are placeholders that write outputs they do not declare (`OUT`, `SSID`)",
            &["E0201"],
        ),
    ),
    case(
        "thiagoralves__OpenPLC_Editor__editor_plcopen_SM_Cards",
        Compiles,
    ),
];

/// Files without SFC bodies that compile (alone, or with their libraries and stubs).
const MIN_COMPILED: usize = 45;

/// The floor for the files with SFC bodies.
const MIN_SFC_COMPILED: usize = 5;

fn corpus() -> Option<PathBuf> {
    let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/corpus/plcopen");
    p.is_dir().then_some(p)
}

/// The error codes of a build of `c`, none if it compiles; `Err` if plcc could not
/// even start (a file missing).
fn build(dir: &Path, c: &Case) -> Result<Vec<&'static str>, String> {
    let stubs = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/plcopen_stubs");
    let mut files = Vec::new();
    let paths = std::iter::once(dir.join(format!("{}.xml", c.file)))
        .chain(c.libs.iter().map(|l| dir.join(format!("{l}.xml"))))
        .chain(c.stubs.iter().map(|s| stubs.join(format!("{s}.st"))));
    for p in paths {
        let bytes = std::fs::read(&p).map_err(|e| format!("{}: {e}", p.display()))?;
        files.push((p.display().to_string(), bytes));
    }
    // The libraries and stubs are libraries (`--lib`): their PROGRAMs and
    // configurations are not the project's.
    let library = files.split_off(1);
    let b =
        build_sources_with_library(files, library, &BuildOptions::default()).map_err(|e| e.0)?;
    let mut codes: Vec<&'static str> = b
        .diagnostics
        .iter()
        .filter(|d| d.is_error())
        .map(|d| d.code)
        .collect();
    codes.sort();
    codes.dedup();
    if b.module.is_none() && codes.is_empty() {
        return Err("no module and no error".into());
    }
    Ok(codes)
}

#[test]
fn every_corpus_project_comes_out_as_listed() {
    let Some(dir) = corpus() else {
        skip::notice("../shared/corpus/plcopen is absent: the PLCopen corpus test is skipped");
        return;
    };
    let mut files: Vec<String> = std::fs::read_dir(&dir)
        .expect("corpus directory")
        .filter_map(|e| {
            let p = e.ok()?.path();
            let name = p.file_name()?.to_str()?.to_string();
            name.strip_suffix(".xml").map(str::to_string)
        })
        .collect();
    files.sort();
    let mut problems = Vec::new();
    for f in &files {
        if !CASES.iter().any(|c| c.file == f) {
            problems.push(format!("{f}: not listed in CASES"));
        }
    }
    let (mut compiled, mut with_help, mut sfc, mut failed) = (0, 0, 0, 0);
    let mut sfc_compiled = 0;
    for c in CASES {
        if !files.iter().any(|f| f == c.file) {
            problems.push(format!("{}: listed but not in the corpus", c.file));
            continue;
        }
        let codes = match build(&dir, c) {
            Ok(codes) => codes,
            Err(e) => {
                problems.push(format!("{}: {e}", c.file));
                continue;
            }
        };
        let outcome = match (&c.expect, codes.as_slice()) {
            (Compiles, []) => "compiles".to_string(),
            (Fails(_, want), got) if !got.is_empty() && got.iter().all(|g| want.contains(g)) => {
                "fails as listed".to_string()
            }
            (want, got) => {
                problems.push(format!("{}: expected {want:?}, got errors {got:?}", c.file));
                continue;
            }
        };
        match c.expect {
            _ if SFC_FILES.contains(&c.file) => {
                sfc += 1;
                if c.expect == Compiles {
                    sfc_compiled += 1;
                }
            }
            Compiles if c.libs.is_empty() && c.stubs.is_empty() => compiled += 1,
            Compiles => with_help += 1,
            Fails(..) => failed += 1,
        }
        let how = if c.libs.is_empty() && c.stubs.is_empty() {
            String::new()
        } else {
            format!(" (with {})", [c.libs, c.stubs].concat().join(", "))
        };
        eprintln!("{:<80} {outcome}{how}", c.file);
    }
    let without_sfc = compiled + with_help + failed;
    eprintln!(
        "{without_sfc} files without SFC bodies: {compiled} compile alone, {with_help} with \
         their editor's libraries or a user's stubs, {failed} fail; {sfc} have SFC bodies, \
         of which {sfc_compiled} compile"
    );
    assert!(problems.is_empty(), "{}", problems.join("\n"));
    // The floor is today's count: the files that fail are each listed with why.
    assert!(
        compiled + with_help >= MIN_COMPILED,
        "too few files compile: {} of {without_sfc}",
        compiled + with_help
    );
    assert!(
        sfc_compiled >= MIN_SFC_COMPILED,
        "too few files with SFC bodies compile: {sfc_compiled} of {sfc}"
    );
}
