//! The pass against the original on the reference interpreter (same result, same
//! fault flag, for every combination of edge operands), and which checks it removes
//! or keeps.

use super::run;
use crate::function::Function;
use crate::inst::{InstData, IntCC, Intrinsic};
use crate::interp::Interp;
use crate::machine::Machine;
use crate::module::Module;
use crate::text::parse_module;
use crate::types::Type;
use crate::verify::verify_module;

fn parse(text: &str) -> Module {
    let m = parse_module(text).unwrap_or_else(|e| panic!("{e}\n{text}"));
    verify_module(&m).unwrap_or_else(|e| panic!("{e:?}\n{text}"));
    m
}

fn faults(f: &Function) -> usize {
    f.inst_iter()
        .filter(|&(_, i)| {
            matches!(
                f.inst(i),
                InstData::Intrinsic {
                    op: Intrinsic::RaiseFault,
                    ..
                }
            )
        })
        .count()
}

/// Runs the pass on `@f` of `text`; checks that it verifies and agrees with the
/// original on every combination of `args` (the result and the fault flag).
/// Returns the number of fault paths before and after.
fn agree(text: &str, args: &[Vec<u64>]) -> (usize, usize) {
    let original = parse(text);
    let mut m = original.clone();
    let id = m.func_by_name("f").expect("@f");
    run(&mut m.funcs[id.index()]);
    verify_module(&m).unwrap_or_else(|e| {
        panic!(
            "{e:?}\n{}",
            crate::text::print_module(&m, &Default::default())
        )
    });
    let mut a = Interp::new(&original).unwrap();
    let mut b = Interp::new(&m).unwrap();
    let mut idx = vec![0usize; args.len()];
    loop {
        let xs: Vec<u64> = idx.iter().zip(args).map(|(&k, v)| v[k]).collect();
        a.clear_fault();
        b.clear_fault();
        let ra = a.call(id, &xs).unwrap();
        let rb = b.call(id, &xs).unwrap();
        assert_eq!(ra, rb, "args {xs:x?}: result");
        assert_eq!(a.fault(), b.fault(), "args {xs:x?}: fault flag");
        let mut k = 0;
        loop {
            if k == idx.len() {
                let f = &m.funcs[id.index()];
                return (faults(&original.funcs[id.index()]), faults(f));
            }
            idx[k] += 1;
            if idx[k] < args[k].len() {
                break;
            }
            idx[k] = 0;
            k += 1;
        }
    }
}

fn i32s(xs: &[i64]) -> Vec<u64> {
    xs.iter().map(|&x| x as i32 as u32 as u64).collect()
}

/// The sieve of the benchmark, on 100 flags in a stack slot: the outer loop runs
/// while `i * i <= 99` and reads `flags[i]` (checked); the inner loop marks
/// `flags[j]` for `j` from `i * i` by `i` while `j <= 99` (checked). Returns the
/// number of flags left set, plus `n` (an argument, so the interpreter has one).
const SIEVE: &str = "array %arr = [100 x i8] lower 0

func @f(i32) -> i32 function {
    ss0 = slot %arr \"flags\"
block0(v0: i32):
    v1 = slot_addr ss0
    v2 = iconst.i32 0
    v3 = iconst.i32 99
    v4 = iconst.i32 1
    v5 = iconst.i32 100
    v6 = iconst.i8 1
    v7 = iconst.i8 0
    v8 = iconst.i1 0
    jump block1(v2)

block1(v10: i32):
    v11 = icmp sgt v10, v3
    brif v11, block3, block2

block2:
    v12 = elem_addr v1, %arr, v10
    store v6, v12
    v13 = iadd v10, v4
    jump block1(v13)

block3:
    v14 = iconst.i32 2
    jump block5(v14)

block5(v20: i32):
    v21 = imul v20, v20
    v22 = icmp sle v21, v3
    brif v22, block6, block20(v2, v2)

block6:
    v23 = icmp ult v20, v5
    v24 = select v23, v20, v2
    v25 = elem_addr v1, %arr, v24
    brif v23, block9, block10

block9:
    v26 = load.i8 v25
    v27 = icmp ne v26, v7
    jump block11(v27)

block10:
    raise_fault
    jump block11(v8)

block11(v28: i1):
    brif v28, block14(v21), block8

block14(v30: i32):
    v31 = icmp sle v30, v3
    brif v31, block15, block8

block15:
    v32 = icmp ult v30, v5
    v33 = select v32, v30, v2
    v34 = elem_addr v1, %arr, v33
    brif v32, block17, block18

block17:
    store v7, v34
    jump block19

block18:
    raise_fault
    jump block19

block19:
    v35 = iadd v30, v20
    jump block14(v35)

block8:
    v36 = iadd v20, v4
    jump block5(v36)

block20(v40: i32, v41: i32):
    v42 = icmp sgt v40, v3
    brif v42, block23, block21

block21:
    v43 = elem_addr v1, %arr, v40
    v44 = load.i8 v43
    v45 = uext.i32 v44
    v46 = iadd v41, v45
    v47 = iadd v40, v4
    jump block20(v47, v46)

block23:
    v48 = iadd v41, v0
    return v48
}
";

#[test]
fn the_sieve_s_inner_check_goes() {
    let (before, after) = agree(SIEVE, &[i32s(&[0, 7])]);
    // The inner index stays in 0..=99: its check goes; the outer one stays (the
    // analysis does not see that `i` stops at 10 before `i * i` could wrap).
    assert_eq!((before, after), (2, 1), "fault paths before and after");
    let mut a = Interp::new(&parse(SIEVE)).unwrap();
    let f = parse(SIEVE).func_by_name("f").unwrap();
    // The 25 primes below 100, and 0 and 1 (never cleared here).
    assert_eq!(a.call(f, &[0]).unwrap(), Some(27));
}

/// An inner loop like the sieve's whose start and step come from the arguments:
/// `j` from `s` by `d` while `j <= 99`, writing `flags[j]` (checked), at most 50
/// times. Returns the count of writes plus 1000 times the number in range.
const FROM_ARGS: &str = "array %arr = [100 x i8] lower 0

func @f(i32, i32) -> i32 function {
    ss0 = slot %arr \"flags\"
block0(v0: i32, v1: i32):
    v2 = slot_addr ss0
    v3 = iconst.i32 0
    v4 = iconst.i32 99
    v5 = iconst.i32 100
    v6 = iconst.i32 1
    v7 = iconst.i8 1
    v8 = iconst.i32 50
    v9 = iconst.i32 1000
    jump block1(v0, v3, v3)

block1(v10: i32, v11: i32, v12: i32):
    v13 = icmp sle v10, v4
    v14 = icmp slt v11, v8
    v15 = band v13, v14
    brif v15, block2, block9

block2:
    v16 = icmp ult v10, v5
    v17 = select v16, v10, v3
    v18 = elem_addr v2, %arr, v17
    brif v16, block3, block4

block3:
    store v7, v18
    v19 = iadd v12, v9
    jump block5(v19)

block4:
    raise_fault
    jump block5(v12)

block5(v20: i32):
    v21 = iadd v10, v1
    v22 = iadd v11, v6
    v23 = iadd v20, v6
    jump block1(v21, v22, v23)

block9:
    return v12
}
";

#[test]
fn a_check_whose_index_may_leave_the_array_stays() {
    let starts = i32s(&[0, 5, 99, 100, -1, -200, i32::MIN as i64, i32::MAX as i64]);
    let steps = i32s(&[0, 1, 7, -1, -3, 1 << 30, i32::MIN as i64]);
    let (before, after) = agree(FROM_ARGS, &[starts, steps]);
    assert_eq!((before, after), (1, 1));
}

/// `j := n * n` wraps for large `n`, so `j <= 99` does not keep it from being
/// negative: the check stays.
const SQUARE_WRAPS: &str = "array %arr = [100 x i8] lower 0

func @f(i32) -> i32 function {
    ss0 = slot %arr \"flags\"
block0(v0: i32):
    v1 = slot_addr ss0
    v2 = iconst.i32 0
    v3 = iconst.i32 99
    v4 = iconst.i32 100
    v5 = iconst.i8 1
    v6 = imul v0, v0
    v7 = icmp sle v6, v3
    brif v7, block1, block3

block1:
    v8 = icmp ult v6, v4
    v9 = select v8, v6, v2
    v10 = elem_addr v1, %arr, v9
    brif v8, block2, block4

block2:
    store v5, v10
    return v6

block4:
    raise_fault
    return v2

block3:
    return v3
}
";

#[test]
fn a_product_that_may_wrap_keeps_its_check() {
    let ns = i32s(&[
        0,
        3,
        9,
        10,
        -9,
        46341,
        65536,
        65537,
        -65536,
        i32::MIN as i64,
    ]);
    assert_eq!(agree(SQUARE_WRAPS, &[ns]), (1, 1));
}

/// The same square, of an argument checked first to be in 0..=9: then `n * n`
/// cannot wrap and its check goes.
const SQUARE_CHECKED: &str = "array %arr = [100 x i8] lower 0

func @f(i32) -> i32 function {
    ss0 = slot %arr \"flags\"
block0(v0: i32):
    v1 = slot_addr ss0
    v2 = iconst.i32 0
    v3 = iconst.i32 99
    v4 = iconst.i32 100
    v5 = iconst.i8 1
    v11 = iconst.i32 10
    v6 = imul v0, v0
    v12 = icmp ult v0, v11
    brif v12, block5, block3

block5:
    v7 = icmp sle v6, v3
    brif v7, block1, block3

block1:
    v8 = icmp ult v6, v4
    v9 = select v8, v6, v2
    v10 = elem_addr v1, %arr, v9
    brif v8, block2, block4

block2:
    store v5, v10
    return v6

block4:
    raise_fault
    return v2

block3:
    return v3
}
";

#[test]
fn a_product_of_checked_factors_is_bounded_after_the_check() {
    let ns = i32s(&[0, 3, 9, 10, -9, 46341, 65536, i32::MIN as i64]);
    // The product is computed before the check of `n`, and bounded after it.
    assert_eq!(agree(SQUARE_CHECKED, &[ns]), (1, 0));
}

/// A branch on a block parameter that one edge passes as a constant: that edge goes
/// straight to the destination the constant picks.
#[test]
fn a_branch_on_a_constant_argument_is_threaded() {
    let text = "func @f(i32) -> i32 function {
block0(v0: i32):
    v1 = iconst.i32 0
    v2 = icmp sgt v0, v1
    v3 = iconst.i1 0
    brif v2, block1, block2(v3)

block1:
    v4 = icmp slt v0, v1
    jump block2(v4)

block2(v5: i1):
    brif v5, block3(v0), block4(v1)

block3(v6: i32):
    return v6

block4(v7: i32):
    v8 = iconst.i32 5
    v9 = iadd v7, v8
    return v9
}
";
    let xs = i32s(&[-3, 0, 4, i32::MIN as i64]);
    agree(text, std::slice::from_ref(&xs));
    let mut m = parse(text);
    let f = &mut m.funcs[0];
    assert!(run(f));
    // block1's compare is decided (v0 > 0 there), so every path returns 5.
    let returns: Vec<String> = f
        .inst_iter()
        .map(|(_, i)| format!("{:?}", f.inst(i)))
        .collect();
    assert!(
        !returns.iter().any(|r| r.contains("Brif")),
        "every branch decided: {returns:?}"
    );
}

/// A block that branches on a parameter whose other parameters are read below it
/// (found by difftest on c): bypassing it would leave those reads without a value,
/// so the edge stays.
#[test]
fn a_branch_whose_block_s_parameters_are_read_below_stays() {
    let text = "func @f(i32, i1) -> i32 function {
block0(v0: i32, v1: i1):
    brif v1, block1, block2

block1:
    v2 = iconst.i32 7
    v3 = imul v0, v2
    v4 = iconst.i1 1
    jump block3(v3, v4)

block2:
    v5 = iconst.i1 0
    v6 = iconst.i32 0
    jump block3(v6, v5)

block3(v7: i32, v8: i1):
    brif v8, block5, block4

block5:
    v9 = iconst.i32 1
    v10 = iadd v7, v9
    return v10

block4:
    return v7
}
";
    let xs = i32s(&[-3, 0, 4]);
    agree(text, &[xs, vec![0, 1]]);
}

/// Runs `@f` of each text on every `i8` (all 256) before and after the pass; the
/// number of compares the pass decided in all of them. The texts fold their compares
/// into one number, `acc * 3 + bit` each, so no two wrong ones cancel.
fn exhaustive_i8(texts: &[String]) -> usize {
    let mut decided = 0;
    for text in texts {
        let original = parse(text);
        let mut m = original.clone();
        let id = m.func_by_name("f").expect("@f");
        let cmps = |f: &Function| {
            f.inst_iter()
                .filter(|&(_, i)| matches!(f.inst(i), InstData::Icmp { .. }))
                .count()
        };
        let before = cmps(&original.funcs[id.index()]);
        run(&mut m.funcs[id.index()]);
        verify_module(&m).unwrap_or_else(|e| panic!("{e:?}\n{text}"));
        decided += before.saturating_sub(cmps(&m.funcs[id.index()]));
        let mut a = Interp::new(&original).unwrap();
        let mut b = Interp::new(&m).unwrap();
        for x in 0..256u64 {
            let (ra, rb) = (a.call(id, &[x]).unwrap(), b.call(id, &[x]).unwrap());
            assert_eq!(
                ra,
                rb,
                "x = {}: {text}\nafter:\n{}",
                x as u8 as i8,
                crate::text::print_module(&m, &Default::default())
            );
        }
    }
    decided
}

/// Every condition on every edge, as a fact about `x` (either side of the compare),
/// against every compare of `x` with constants near the fact's: the pass decides
/// what it can, and never wrongly (checked on every `i8`).
#[test]
fn facts_of_every_condition_decide_rightly() {
    let mut texts = Vec::new();
    for cc1 in IntCC::ALL {
        for c in [-128i64, -1, 0, 5, 127] {
            for flip in [false, true] {
                for cc2 in IntCC::ALL {
                    let ds: Vec<i64> = [c - 1, c, c + 1, 0, -1]
                        .iter()
                        .map(|&d| Type::I8.canon_int(d))
                        .collect();
                    let first = if flip {
                        format!("icmp {} v1, v0", cc1.name())
                    } else {
                        format!("icmp {} v0, v1", cc1.name())
                    };
                    // The same compares in both successors (values 20.. and 120..).
                    let body = |base: usize| {
                        let mut body = String::new();
                        let mut sum = String::from("v9");
                        for (k, d) in ds.iter().enumerate() {
                            let n = base + 4 * k;
                            body.push_str(&format!(
                                "    v{a} = iconst.i8 {d}\n    v{b} = icmp {} v0, v{a}\n    v{e} = uext.i32 v{b}\n    v{m} = imul {sum}, v8\n    v{s} = iadd v{m}, v{e}\n",
                                cc2.name(),
                                a = n,
                                b = n + 1,
                                e = n + 2,
                                s = n + 3,
                                m = n + 1000,
                            ));
                            sum = format!("v{}", n + 3);
                        }
                        (body, sum)
                    };
                    let ((b1, s1), (b2, s2)) = (body(20), body(120));
                    texts.push(format!(
                        "func @f(i8) -> i32 function {{\nblock0(v0: i8):\n    v1 = iconst.i8 {c}\n    v2 = {first}\n    v9 = iconst.i32 0\n    v8 = iconst.i32 3\n    brif v2, block1, block2\n\nblock1:\n{b1}    return {s1}\n\nblock2:\n{b2}    v99 = iconst.i32 100\n    v98 = iadd {s2}, v99\n    return v98\n}}\n",
                        c = Type::I8.canon_int(c),
                    ));
                }
            }
        }
    }
    let decided = exhaustive_i8(&texts);
    assert!(decided > 1000, "only {decided} compares decided");
}

/// Each operation on an `x` bounded by two facts (`lo <= x <= hi`), its result
/// compared with constants: checked on every `i8`, wrapping included.
#[test]
fn ranges_of_operations_decide_rightly() {
    let ops = [
        "iadd", "isub", "imul", "band", "bor", "urem", "srem", "sdiv", "udiv", "ushr", "sshr",
        "ishl",
    ];
    let bounds = [
        (-128i64, 127i64),
        (0, 10),
        (-5, 5),
        (-128, -100),
        (100, 127),
        (3, 3),
    ];
    let mut texts = Vec::new();
    for (lo, hi) in bounds {
        let mut results: Vec<String> = Vec::new();
        for op in ops {
            for k in [0i64, 1, 3, -1, 7, 100, -128] {
                results.push(format!("{op} v0, v{{K{}}}", Type::I8.canon_int(k)));
            }
        }
        for un in ["ineg", "iabs"] {
            results.push(format!("{un} v0"));
        }
        // Conversions: widened (compared as i16), and widened, moved and truncated
        // back (the sum leaves i8 for some x).
        results.push("sext.i16 v0|".into());
        results.push("uext.i16 v0|".into());
        results.push("sext.i16 v0|iadd 100|itrunc.i8".into());
        results.push("uext.i16 v0|isub 200|itrunc.i8".into());
        for r in results {
            let mut consts = String::new();
            let mut inst = r.clone();
            for k in [0i64, 1, 3, -1, 7, 100, -128] {
                let k = Type::I8.canon_int(k);
                let name = format!("v{{K{k}}}");
                if inst.contains(&name) {
                    let v = format!("v{}", 200 + (k + 128));
                    consts.push_str(&format!("    {v} = iconst.i8 {k}\n"));
                    inst = inst.replace(&name, &v);
                }
            }
            // The result `v3` and its type.
            let (compute, ty) = match inst.split('|').collect::<Vec<_>>().as_slice() {
                [wide, ""] => (format!("    v3 = {wide}\n"), "i16"),
                [wide, add, back] => {
                    let (op, k) = add.split_once(' ').expect("op k");
                    (
                        format!(
                            "    v50 = {wide}\n    v51 = iconst.i16 {k}\n    v52 = {op} v50, v51\n    v3 = {back} v52\n"
                        ),
                        "i8",
                    )
                }
                _ => (format!("    v3 = {inst}\n"), "i8"),
            };
            let mut tail = String::new();
            let mut sum = String::from("v9");
            let thresholds = [
                -128i64, -127, -101, -100, -99, -6, -5, -4, -1, 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10,
                11, 99, 100, 101, 126, 127, 128, 254, 255, 256,
            ];
            for (j, t) in thresholds.iter().enumerate() {
                let t = if ty == "i8" {
                    Type::I8.canon_int(*t)
                } else {
                    *t
                };
                for (q, cc) in [IntCC::Slt, IntCC::Sge, IntCC::Ult, IntCC::Eq]
                    .iter()
                    .enumerate()
                {
                    let n = 600 + 16 * j + 4 * q;
                    tail.push_str(&format!(
                        "    v{a} = iconst.{ty} {t}\n    v{b} = icmp {} v3, v{a}\n    v{c} = uext.i32 v{b}\n    v{m} = imul {sum}, v8\n    v{d} = iadd v{m}, v{c}\n",
                        cc.name(),
                        a = n,
                        b = n + 1,
                        c = n + 2,
                        d = n + 3,
                        m = n + 1000,
                    ));
                    sum = format!("v{}", n + 3);
                }
            }
            texts.push(format!(
                "func @f(i8) -> i32 function {{\nblock0(v0: i8):\n    v1 = iconst.i8 {lo}\n    v2 = iconst.i8 {hi}\n    v9 = iconst.i32 0\n    v8 = iconst.i32 3\n    v4 = icmp sge v0, v1\n    brif v4, block1, block3\n\nblock1:\n    v5 = icmp sle v0, v2\n    brif v5, block2, block3\n\nblock2:\n{consts}{compute}{tail}    return {sum}\n\nblock3:\n    return v9\n}}\n"
            ));
        }
    }
    let decided = exhaustive_i8(&texts);
    assert!(decided > 500, "only {decided} compares decided");
}
