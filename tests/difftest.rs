//! A fixed-seed batch of random programs on every machine (`plcc difftest` runs
//! longer campaigns; TESTING.md has the method), and the shrinker on a known cause.

use plcc::difftest::{self, gen::Expr, gen::Stmt, shrink, Verdict};

const MACHINES: [&str; 4] = ["interp", "host", "vmasm", "pic16f876a"];

#[test]
fn three_hundred_random_programs_agree_on_every_machine() {
    let mut machines_ran = 0;
    let mut findings = Vec::new();
    for seed in 1..=300 {
        match difftest::check(&difftest::program(seed), &MACHINES, 4, seed) {
            Verdict::Agree { machines } => machines_ran += machines,
            v => {
                let f = difftest::run_seed(seed, &MACHINES, 4).expect("still failing");
                findings.push(format!("seed {seed}: {v:?}\n{}", f.reproducer));
            }
        }
    }
    println!("300 programs, {machines_ran} machine runs");
    assert!(findings.is_empty(), "{}", findings.join("\n\n"));
    // Every program runs on the three machines that hold everything; about half
    // fit the PIC16 too (not those with LREAL arithmetic, error E9001, nor most of
    // those with an EXPT, whose soft-float routines need more RAM than is left).
    assert!(machines_ran > 300 * 3 + 130, "{machines_ran} machine runs");
}

#[test]
fn every_kind_of_program_comes_often_enough() {
    // Each of the constructs that reach memory through run-time addresses, the
    // configurations and the exact EXPT is in 20-40% of the programs.
    let n = 1000;
    let mut counts = [0usize; 6];
    for seed in 1..=n {
        let p = difftest::program(seed);
        let st = p.to_st();
        let main = &st[st.find("PROGRAM main").expect("main")..];
        let main = &main[..main.find("END_PROGRAM").expect("end")];
        let body = &main[main.rfind("END_VAR").expect("VAR")..];
        let has = [
            p.config.as_ref().is_some_and(|c| c.instances.len() > 1),
            body.contains("**") || body.contains("EXPT("),
            body.contains("recs["),
            body.contains("fbs["),
            body.contains("fio(") || body.contains("f2("),
            body.contains('^') || body.contains("REF("),
        ];
        for (c, h) in counts.iter_mut().zip(has) {
            *c += h as usize;
        }
    }
    let names = [
        "CONFIGURATION",
        "EXPT",
        "ARRAY OF STRUCT",
        "ARRAY OF FB",
        "VAR_IN_OUT",
        "REF_TO",
    ];
    println!("{names:?}: {counts:?} of {n}");
    for (name, c) in names.iter().zip(counts) {
        let share = c as f64 / n as f64;
        assert!(
            (0.2..=0.4).contains(&share),
            "{name} in {share:.2} of the programs"
        );
    }
}

fn mentions_mod(e: &Expr) -> bool {
    matches!(e, Expr::Bin(_, "MOD", ..)) || e.children().into_iter().any(mentions_mod)
}

fn has_mod(body: &[Stmt]) -> bool {
    body.iter().any(|s| {
        s.exprs().into_iter().any(mentions_mod) || s.bodies().into_iter().any(|b| has_mod(b))
    })
}

fn size(body: &[Stmt]) -> usize {
    body.iter()
        .map(|s| 1 + s.bodies().into_iter().map(|b| size(b)).sum::<usize>())
        .sum()
}

#[test]
fn the_shrinker_keeps_the_cause_and_drops_the_rest() {
    // A "bug" that every program with a MOD in its body shows; a program with a
    // CONFIGURATION and parts reached through run-time addresses, so that the
    // shrinker has those to drop too.
    let seed = (1..2000)
        .find(|&s| {
            let p = difftest::program(s);
            has_mod(&p.body)
                && size(&p.body) >= 8
                && p.config.is_some()
                && p.inout
                && (p.recs.is_some() || p.refs)
        })
        .expect("a large program with a MOD");
    let p = difftest::program(seed);
    // Only programs the front end takes: a step that drops a declaration the body
    // still uses is not taken.
    let compiles = |q: &difftest::gen::Prog| {
        !matches!(
            difftest::check(q, &["interp"], 0, seed),
            Verdict::Rejected(_)
        )
    };
    let small = shrink::shrink(&p, &mut |q| has_mod(&q.body) && compiles(q), 5000);
    assert!(has_mod(&small.body), "the cause stays");
    assert_eq!(
        size(&small.body),
        1,
        "one statement is left:\n{}",
        small.to_st()
    );
    assert!(small.config.is_none(), "the configuration goes");
    assert!(!small.inout, "the in-out POUs go");
    // What is left still compiles and runs everywhere.
    assert!(matches!(
        difftest::check(&small, &MACHINES, 2, seed),
        Verdict::Agree { .. }
    ));
}
