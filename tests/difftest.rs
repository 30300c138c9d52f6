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
    match e {
        Expr::Bin(_, "MOD", ..) => true,
        Expr::Lit(..) | Expr::Var(..) => false,
        Expr::Elem(_, i) | Expr::Un(_, _, i) => mentions_mod(i),
        Expr::Bin(_, _, a, b) => mentions_mod(a) || mentions_mod(b),
        Expr::Call(_, _, args) => args.iter().any(mentions_mod),
    }
}

fn has_mod(body: &[Stmt]) -> bool {
    body.iter().any(|s| match s {
        Stmt::Assign(_, e) => mentions_mod(e),
        Stmt::AssignElem(i, e) => mentions_mod(i) || mentions_mod(e),
        Stmt::If(c, a, b) => mentions_mod(c) || has_mod(a) || has_mod(b),
        Stmt::For(_, _, _, b) | Stmt::While(_, b) => has_mod(b),
        Stmt::Case(c, arms, o) => {
            mentions_mod(c) || arms.iter().any(|(_, b)| has_mod(b)) || has_mod(o)
        }
        Stmt::CallFb(a, b, _) => mentions_mod(a) || mentions_mod(b),
        Stmt::Raw(_) => false,
    })
}

fn size(body: &[Stmt]) -> usize {
    body.iter()
        .map(|s| match s {
            Stmt::If(_, a, b) => 1 + size(a) + size(b),
            Stmt::For(_, _, _, b) | Stmt::While(_, b) => 1 + size(b),
            Stmt::Case(_, arms, o) => {
                1 + arms.iter().map(|(_, b)| size(b)).sum::<usize>() + size(o)
            }
            _ => 1,
        })
        .sum()
}

#[test]
fn the_shrinker_keeps_the_cause_and_drops_the_rest() {
    // A "bug" that every program with a MOD in its body shows.
    let seed = (1..500)
        .find(|&s| {
            let p = difftest::program(s);
            has_mod(&p.body) && size(&p.body) >= 8
        })
        .expect("a large program with a MOD");
    let p = difftest::program(seed);
    let small = shrink::shrink(&p, &mut |q| has_mod(&q.body), 5000);
    assert!(has_mod(&small.body), "the cause stays");
    assert_eq!(
        size(&small.body),
        1,
        "one statement is left:\n{}",
        small.to_st()
    );
    // What is left still compiles and runs everywhere.
    assert!(matches!(
        difftest::check(&small, &MACHINES, 2, seed),
        Verdict::Agree { .. }
    ));
}
