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
    // Every program runs on the three machines that hold everything; most fit the
    // PIC16 too (not those with LREAL arithmetic, error E9001).
    assert!(machines_ran > 300 * 3 + 150, "{machines_ran} machine runs");
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
