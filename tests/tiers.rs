//! The tiered JIT (`src/tiers.rs`): a large program starts on quick code and the
//! optimised code takes over between scans. Both tiers, and the swap at any scan,
//! must leave every variable as the optimised code alone does, and as the
//! interpreter of the unoptimised IR does.

#[path = "common/cli.rs"]
mod cli;

use plcc::driver::{build_sources, BuildOptions};
use plcc::tiers::TIER_MIN_INSTS;
use plcc_ir::machine::Machine;
use plcc_ir::Module;

/// A program of `n` function blocks, each with state that every scan changes
/// (counters, a loop over an array, a CASE, REAL arithmetic) and one call of a
/// function, and a PROGRAM that calls them all.
fn large_program(n: usize) -> String {
    let mut s = String::from(
        "FUNCTION twice : DINT\nVAR_INPUT x : DINT; END_VAR\n    twice := x * 2;\nEND_FUNCTION\n\n",
    );
    for k in 0..n {
        s += &format!(
            "FUNCTION_BLOCK fb{k}\n\
             VAR_INPUT step : DINT; END_VAR\n\
             VAR_OUTPUT total : DINT; level : REAL; END_VAR\n\
             VAR hist : ARRAY[0..7] OF DINT; i : INT; state : INT; END_VAR\n\
             \x20   FOR i := 7 TO 1 BY -1 DO hist[i] := hist[i - 1] + {k}; END_FOR;\n\
             \x20   hist[0] := step;\n\
             \x20   CASE state OF\n\
             \x20       0: total := total + twice(hist[3]); state := 1;\n\
             \x20       1: total := total - hist[7] MOD 97; state := 2;\n\
             \x20   ELSE\n\
             \x20       total := total / 3 + {k}; state := 0;\n\
             \x20   END_CASE;\n\
             \x20   IF total > 100000 THEN total := total - 99991; END_IF;\n\
             \x20   level := level * 0.5 + DINT_TO_REAL(total) * 0.25;\n\
             END_FUNCTION_BLOCK\n\n"
        );
    }
    s += "PROGRAM main\nVAR\n    scan : DINT;\n";
    for k in 0..n {
        s += &format!("    u{k} : fb{k};\n");
    }
    s += "END_VAR\n    scan := scan + 1;\n";
    for k in 0..n {
        s += &format!("    u{k}(step := scan * {} + {k});\n", k % 7 + 1);
    }
    s += "END_PROGRAM\n";
    s
}

fn build(text: &str, staged: bool, no_opt: bool) -> Module {
    let opts = BuildOptions {
        staged,
        no_opt,
        ..Default::default()
    };
    build_sources(vec![("tiers.st".into(), text.as_bytes().to_vec())], &opts)
        .expect("builds")
        .into_module()
        .expect("compiles")
}

/// Every variable of `m` after the cold start and after each of `scans` scans.
fn trace(mut m: Box<dyn Machine>, module: &Module, scans: u32) -> Vec<String> {
    let vars = plcc::scenario::all_variables(module);
    let mut out = Vec::new();
    m.cold_start().expect("cold start");
    for s in 0..=scans {
        if s > 0 {
            m.set_clock_us(s as i64 * 10_000);
            m.scan().expect("scan");
        }
        for v in &vars {
            out.push(format!(
                "{s} {} = {}",
                v.path,
                m.read(&v.path).expect("read")
            ));
        }
    }
    out
}

fn tiered(staged: &Module, tier: &str) -> Box<dyn Machine> {
    plcc::targets::machine_staged("host", staged.clone(), &[("tier".into(), tier.into())])
        .unwrap_or_else(|e| panic!("tier={tier}: {e:?}"))
}

#[test]
fn the_tiers_and_the_swap_at_every_scan_agree_with_the_unoptimised_ir() {
    let text = large_program(40);
    let staged = build(&text, true, false);
    let raw = build(&text, false, true);
    let scans = 5;
    let reference = trace(plcc::targets::machine("interp", &raw).unwrap(), &raw, scans);
    for tier in [
        "full",
        "quick",
        "auto",
        "swap-at-0",
        "swap-at-1",
        "swap-at-3",
        "swap-at-5",
    ] {
        let got = trace(tiered(&staged, tier), &staged, scans);
        if let Some(k) = (0..reference.len()).find(|&k| reference[k] != got[k]) {
            panic!(
                "tier={tier}: {} on the interpreter of the raw IR, {} on the JIT",
                reference[k], got[k]
            );
        }
    }
}

#[test]
fn a_large_program_starts_on_quick_code_and_prints_what_the_optimised_code_does() {
    let text = large_program(300);
    let staged = build(&text, true, false);
    let insts: usize = staged.funcs.iter().map(|f| f.live_inst_count()).sum();
    assert!(
        insts >= TIER_MIN_INSTS,
        "{insts} instructions: too small to tier"
    );
    let path = std::env::temp_dir().join(format!("plcc-tiers-{}.st", std::process::id()));
    std::fs::write(&path, &text).unwrap();
    let file = path.to_str().unwrap();
    let run = |extra: &[&str]| {
        let mut args = vec!["run", file, "--scans", "4"];
        args.extend_from_slice(extra);
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_plcc"))
            .args(&args)
            .env("PLCC_TIME_PASSES", "1")
            .output()
            .expect("plcc runs");
        assert!(o.status.success(), "{args:?}: {}", cli::stderr(&o));
        assert!(
            !cli::stderr(&o).contains("internal error"),
            "{}",
            cli::stderr(&o)
        );
        o
    };
    let auto = run(&[]);
    assert!(
        cli::stderr(&auto).contains("quick code"),
        "{}",
        cli::stderr(&auto)
    );
    let full = run(&["-s", "tier=full"]);
    assert!(
        !cli::stderr(&full).contains("quick code"),
        "{}",
        cli::stderr(&full)
    );
    let swapped = run(&["-s", "tier=swap-at-2"]);
    let interp = run(&["--target", "interp"]);
    std::fs::remove_file(&path).unwrap();
    assert!(cli::stdout(&full).lines().count() > 300 * 12);
    assert_eq!(cli::stdout(&auto), cli::stdout(&full));
    assert_eq!(cli::stdout(&swapped), cli::stdout(&full));
    assert_eq!(cli::stdout(&interp), cli::stdout(&full));
}

#[test]
fn a_small_program_is_not_tiered_unless_asked() {
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_plcc"))
        .args(["run", "examples/traffic_light.st", "--scans", "3"])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .env("PLCC_TIME_PASSES", "1")
        .output()
        .unwrap();
    assert!(o.status.success());
    assert!(
        !cli::stderr(&o).contains("quick code"),
        "{}",
        cli::stderr(&o)
    );
    assert!(cli::stderr(&o).contains("whole-program optimisation"));
}

#[test]
fn plcc_test_runs_a_scenario_across_the_swap() {
    let o = cli::plcc(&[
        "test",
        "tests/programs/st/regress/promote_through_ref.st",
        "--scenario",
        "tests/programs/st/regress/promote_through_ref.expect",
        "-s",
        "tier=swap-at-1",
    ]);
    assert!(o.status.success(), "{}{}", cli::stdout(&o), cli::stderr(&o));
    assert!(cli::stdout(&o).contains("passed: 5 check(s), 0 failed [host]"));
}

#[test]
fn a_bad_tier_is_an_error_with_its_code() {
    for (args, says) in [
        (
            vec!["-s", "tier=sometimes"],
            "`tier` is `auto`, `full`, `quick` or `swap-at-N` (N a scan number), not `sometimes`",
        ),
        (vec!["-s", "tier=swap-at-x"], "not `swap-at-x`"),
        (
            vec!["--target", "vmasm", "-s", "tier=quick"],
            "unknown setting `tier`",
        ),
    ] {
        let mut all = vec!["run", "examples/traffic_light.st"];
        all.extend_from_slice(&args);
        let o = cli::plcc(&all);
        assert_eq!(o.status.code(), Some(1), "{all:?}");
        assert!(
            cli::stderr(&o).contains(says),
            "{all:?}: {}",
            cli::stderr(&o)
        );
    }
    let o = cli::plcc(&["run", "examples/traffic_light.st", "-s", "tier=sometimes"]);
    assert!(cli::stderr(&o).contains("E8002"), "{}", cli::stderr(&o));
}
