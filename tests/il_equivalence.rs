//! IL is translated into the syntax tree ST gives (the CPDev method), so a program
//! written in IL and the same program written in ST must give the same optimised IR.
//! Each test builds both and compares the printed modules; the last ones mix the two
//! languages in one build, and check that lowering's diagnostics point at the IL
//! instruction they come from.

use plcc::driver::{build_sources, BuildOptions};
use plcc_ir::text::{print_module, PrintOptions};

/// Builds the given (name, text) files together and prints the optimised IR, without
/// the table of source files (their names differ); with `canonical`, values and
/// blocks numbered in order of appearance.
fn ir(files: &[(&str, &str)], canonical: bool) -> String {
    let texts = files
        .iter()
        .map(|(n, t)| (n.to_string(), t.as_bytes().to_vec()))
        .collect();
    let build = build_sources(texts, &BuildOptions::default()).expect("build");
    let Some(module) = build.module else {
        let errors: Vec<String> = build.diagnostics.iter().map(|d| d.to_string()).collect();
        panic!("does not compile:\n{}", errors.join("\n"));
    };
    let warnings: Vec<String> = build.diagnostics.iter().map(|d| d.to_string()).collect();
    assert!(
        warnings.is_empty(),
        "unexpected warnings:\n{}",
        warnings.join("\n")
    );
    let opts = PrintOptions {
        canonical,
        ..PrintOptions::default()
    };
    print_module(&module, &opts)
        .lines()
        .filter(|l| !l.starts_with("file "))
        .collect::<Vec<_>>()
        .join("\n")
}

fn same(st: &str, il: &str) {
    let a = ir(&[("prog.st", st)], false);
    let b = ir(&[("prog.il", il)], false);
    assert_eq!(
        a, b,
        "ST and IL give different IR:\n--- ST\n{a}\n--- IL\n{b}"
    );
}

/// Like [`same`], for IL with jumps: labels get their blocks before the code is
/// lowered, so values and blocks are numbered differently; they are printed with
/// canonical numbering (in the order they appear in each function) to compare.
fn same_up_to_numbering(st: &str, il: &str) {
    let a = ir(&[("prog.st", st)], true);
    let b = ir(&[("prog.il", il)], true);
    assert_eq!(
        a, b,
        "ST and IL give different IR:\n--- ST\n{a}\n--- IL\n{b}"
    );
}

#[test]
fn arithmetic_and_logic() {
    same(
        "PROGRAM p
         VAR a, b, c : INT; x, y : BOOL; w : WORD; END_VAR
           c := a * 4 + b;
           x := a > b AND NOT y;
           y := x OR (a = c);
           w := (w XOR 16#FF) AND NOT w;
           c := (a - b) * (c + 1) MOD 7;
         END_PROGRAM",
        "PROGRAM p
         VAR a, b, c : INT; x, y : BOOL; w : WORD; END_VAR
           LD a
           MUL 4
           ADD b
           ST c
           LD a
           GT b
           ANDN y
           ST x
           LD x
           OR( a
           EQ c
           )
           ST y
           LD w
           XOR 16#FF
           ANDN w
           ST w
           LD a
           SUB b
           MUL( c
           ADD 1
           )
           MOD 7
           ST c
         END_PROGRAM",
    );
}

#[test]
fn timers_and_counters() {
    same(
        "PROGRAM p
         VAR start, stop, motor, done, full : BOOL; t : TON; et : TIME; c : CTU; END_VAR
           motor := (start OR motor) AND NOT stop;
           t(IN := motor, PT := T#2s);
           done := t.Q;
           et := t.ET;
           c(CU := done);
           c.PV := 10;
           c();
           full := c.Q;
         END_PROGRAM",
        "PROGRAM p
         VAR start, stop, motor, done, full : BOOL; t : TON; et : TIME; c : CTU; END_VAR
           LD start
           OR motor
           ANDN stop
           ST motor
           CAL t(IN := motor, PT := T#2s)
           LD t.Q
           ST done
           LD t.ET
           ST et
           LD done
           CU c
           LD 10
           ST c.PV
           CAL c
           LD c.Q
           ST full
         END_PROGRAM",
    );
}

#[test]
fn set_reset_and_conditional_calls() {
    same(
        "PROGRAM p
         VAR start, stop, run : BOOL; n : INT; t : TON; END_VAR
           IF start THEN run := TRUE; END_IF;
           IF stop THEN run := FALSE; END_IF;
           IF run THEN t(IN := run, PT := T#1s); END_IF;
         END_PROGRAM",
        "PROGRAM p
         VAR start, stop, run : BOOL; n : INT; t : TON; END_VAR
           LD start
           S run
           LD stop
           R run
           LD run
           CALC t(IN := run, PT := T#1s)
         END_PROGRAM",
    );
}

#[test]
fn jumps() {
    same_up_to_numbering(
        "PROGRAM p
         VAR run : BOOL; n, m : INT; END_VAR
           IF NOT run THEN n := n + 1; END_IF;
           m := n;
         END_PROGRAM",
        "PROGRAM p
         VAR run : BOOL; n, m : INT; END_VAR
           LD run
           JMPC skip
           LD n
           ADD 1
           ST n
         skip:
           LD n
           ST m
         END_PROGRAM",
    );
}

#[test]
fn functions_and_results_from_the_current_result() {
    same(
        "FUNCTION scale : INT
         VAR_INPUT v : INT; END_VAR
           scale := MIN(v * 2, 100);
         END_FUNCTION
         PROGRAM p
         VAR a, b, c : INT; END_VAR
           b := scale(a) + 1;
           c := LIMIT(0, b, 50);
         END_PROGRAM",
        "FUNCTION scale : INT
         VAR_INPUT v : INT; END_VAR
           LD v
           MUL 2
           MIN 100
         END_FUNCTION
         PROGRAM p
         VAR a, b, c : INT; END_VAR
           LD a
           scale
           ADD 1
           ST b
           LIMIT(MN := 0, IN := b, MX := 50)
           ST c
         END_PROGRAM",
    );
}

#[test]
fn a_temporary_is_computed_once_and_optimised_away() {
    // `x := __CR1; y := __CR1` with `__CR1 := a + b`: one addition, no slot left.
    let out = ir(
        &[(
            "prog.il",
            "PROGRAM p
         VAR a, b, x, y : INT; END_VAR
           LD a
           ADD b
           ST x
           ST y
         END_PROGRAM",
        )],
        false,
    );
    let body = out.split("func @p$init").next().unwrap_or_default();
    assert_eq!(body.matches("iadd").count(), 1, "{out}");
    assert_eq!(body.matches("store").count(), 2, "{out}");
    assert!(!body.contains("slot"), "{out}");
}

#[test]
fn mixed_languages_in_one_build() {
    let st_fn = "FUNCTION twice : INT
                 VAR_INPUT v : INT; END_VAR
                   twice := v * 2;
                 END_FUNCTION";
    let il_fn = "FUNCTION twice : INT
                 VAR_INPUT v : INT; END_VAR
                   LD v
                   MUL 2
                   ST twice
                 END_FUNCTION";
    let st_prog = "PROGRAM p
                   VAR a, b : INT; END_VAR
                     b := twice(a);
                   END_PROGRAM";
    let il_prog = "PROGRAM p
                   VAR a, b : INT; END_VAR
                     LD a
                     twice
                     ST b
                   END_PROGRAM";
    let all_st = ir(&[("f.st", st_fn), ("p.st", st_prog)], false);
    assert_eq!(all_st, ir(&[("f.st", st_fn), ("p.il", il_prog)], false));
    assert_eq!(all_st, ir(&[("f.il", il_fn), ("p.st", st_prog)], false));
    assert_eq!(all_st, ir(&[("f.il", il_fn), ("p.il", il_prog)], false));
}

#[test]
fn type_errors_point_at_the_instruction() {
    let src = "PROGRAM p\nVAR x : BOOL; n : INT; END_VAR\nLD x\nAND n\nST x\nEND_PROGRAM\n";
    let build = build_sources(
        vec![("p.il".into(), src.as_bytes().to_vec())],
        &BuildOptions::default(),
    )
    .expect("build");
    assert!(build.module.is_none());
    let errors: Vec<_> = build.diagnostics.iter().filter(|d| d.is_error()).collect();
    assert_eq!(errors.len(), 1, "{errors:?}");
    assert_eq!(errors[0].code, "E0301");
    let span = errors[0].span.expect("a span");
    assert_eq!(&src[span.start as usize..span.end as usize], "AND n");
}

#[test]
fn unknown_and_duplicate_labels_are_reported_by_lowering() {
    let src =
        "PROGRAM p\nVAR x : INT; END_VAR\nJMP nowhere\nl: LD 1\nST x\nl: LD 2\nST x\nEND_PROGRAM\n";
    let build = build_sources(
        vec![("p.il".into(), src.as_bytes().to_vec())],
        &BuildOptions::default(),
    )
    .expect("build");
    let mut codes: Vec<&str> = build.diagnostics.iter().map(|d| d.code).collect();
    codes.sort();
    assert_eq!(codes, ["E0508", "E0509"]);
}

/// IL programs for [`mutated_il_never_breaks_the_compiler`]: every instruction kind.
const FUZZ_SEEDS: &[&str] = &["FUNCTION f : INT
     VAR_INPUT a : INT; p : BOOL; END_VAR
       LD p
       JMPC pos
       LD a
       MUL( 2
       ADD a
       )
       RET
     pos: LD a
       ABS
       LIMIT 0, 100
     END_FUNCTION
     FUNCTION g : BOOL
     VAR_INPUT a : INT; END_VAR
       LD a
       GT 5
       RETC
       LD a
       LT -5
     END_FUNCTION
     PROGRAM p
     VAR a, b, c : INT; x, y, z : BOOL; t : TON; n : CTU; s : SR; w : WORD;
         arr : ARRAY[1..3] OF INT; tm : TIME; END_VAR
       LD a
       ADD 1
       ST a
       ST arr[2]
       f x
       ST b
       LD x
       ANDN y
       OR( z
       AND x
       )
       ST z
       S y
       R x
       LD a
       g
       ST x
       CAL t(IN := x, PT := T#5ms, Q => y)
       LD t.ET
       ST tm
       LD y
       CU n
       LD 3
       PV n
       LD n.Q
       S1 s
       LD z
       R s
       LD w
       XOR 16#F0
       ST w
       LD a
       MOD 7
       EQ 3
       JMPCN done
       LD c
       SUB b
       ST c
     done:
       LIMIT(MN := 0, IN := c, MX := 9)
       ST c
     END_PROGRAM"];

const FUZZ_WORDS: &[&str] = &[
    "LD a",
    "LDN x",
    "ST b",
    "STN y",
    "S z",
    "R x",
    "AND x",
    "ANDN y",
    "OR(",
    "AND( y",
    ")",
    "ADD 1",
    "MUL( b",
    "GT 2",
    "NOT",
    "JMP done",
    "JMPC done",
    "l9:",
    "RET",
    "RETCN",
    "CAL t",
    "CALC t(IN := x)",
    "IN t",
    "PT t",
    "ABS",
    "ST a",
    "LD 5",
    "ADD 1, 2",
    "&N x",
];

#[allow(dead_code)]
#[path = "common/rng.rs"]
mod rng;
use rng::Rng;

/// Line-level mutations of IL (deleted, duplicated, swapped, inserted instructions)
/// go through the whole compiler and the interpreter without a panic or an internal
/// error: the temporaries, the deferred operations and the jumps the translation
/// makes from any instruction sequence are valid input for lowering.
#[test]
fn mutated_il_never_breaks_the_compiler() {
    let mut rng = Rng(0x2545_F491_4F6C_DD1D);
    let mut failures = Vec::new();
    let mut compiled = 0;
    for seed in FUZZ_SEEDS {
        // The seed itself is valid: the mutants exercise lowering, not only errors.
        ir(&[("seed.il", seed)], false);
        for _ in 0..300 {
            let mut lines: Vec<String> = seed.lines().map(str::to_string).collect();
            for _ in 0..1 + rng.index(4) {
                let n = lines.len();
                let k = 2 + rng.index(n - 3);
                match rng.index(4) {
                    0 => {
                        lines.remove(k);
                    }
                    1 => {
                        let l = lines[k].clone();
                        lines.insert(k, l);
                    }
                    2 => {
                        let j = 2 + rng.index(n - 3);
                        lines.swap(k, j);
                    }
                    _ => lines.insert(k, FUZZ_WORDS[rng.index(FUZZ_WORDS.len())].into()),
                }
            }
            let src = lines.join("\n");
            let outcome = std::panic::catch_unwind(|| {
                let b = build_sources(
                    vec![("fuzz.il".into(), src.as_bytes().to_vec())],
                    &BuildOptions::default(),
                )
                .expect("build");
                if b.diagnostics
                    .iter()
                    .any(|d| d.code == plcc::driver::E_INTERNAL)
                {
                    return Err(plcc::render::render(&b.sources, &b.diagnostics));
                }
                let Some(module) = b.module else {
                    return Ok(false);
                };
                if let Ok(mut m) = plcc::targets::machine("interp", &module) {
                    m.set_watchdog(Some(std::time::Duration::from_millis(200)));
                    if m.cold_start().is_ok() {
                        for k in 0..3 {
                            m.set_clock_us(k * 10_000);
                            if m.scan().is_err() {
                                break;
                            }
                        }
                    }
                }
                Ok(true)
            });
            match outcome {
                Ok(Ok(ok)) => compiled += ok as u32,
                Ok(Err(e)) => failures.push(format!("{src}\n{e}")),
                Err(_) => failures.push(format!("{src}\nPANIC")),
            }
        }
    }
    assert!(compiled >= 30, "only {compiled} mutants compile");
    assert!(
        failures.is_empty(),
        "{} failures, the first:\n{}",
        failures.len(),
        failures[0]
    );
}
