//! `br_table`, the jump through a table: its text form, the verifier, the
//! interpreter (the index read unsigned at its width, so an `i16` -1 is 65535 and goes
//! to the default), the passes that fold it, and its expansion into a binary search of
//! compares for the targets without an indirect jump (`passes::br_table`), checked
//! against the table on random tables and indexes.

use plcc_ir::interp::Interp;
use plcc_ir::passes::{br_table, const_fold, optimize_function, simplify_cfg};
use plcc_ir::rng::Rng;
use plcc_ir::text::{parse_module, print_module, PrintOptions};
use plcc_ir::verify::verify_module;
use plcc_ir::{FuncId, InstData, Module, Type};

fn module(text: &str) -> Module {
    let m = parse_module(text).unwrap_or_else(|e| panic!("{e}\n{text}"));
    if let Err(errs) = verify_module(&m) {
        let msgs: Vec<String> = errs.iter().map(|e| e.to_string()).collect();
        panic!("{}\n{text}", msgs.join("\n"));
    }
    m
}

/// `@f(i16) -> i32`: 10 + the index for entries 0 and 3, 20 for 1, 30 for 2 (the same
/// block as 0 with other arguments), -1 past the table.
const SWITCH: &str = "\
func @f(i16) -> i32 function {
block0(v0: i16):
    v1 = sext.i32 v0
    v2 = iconst.i32 20
    v3 = iconst.i32 30
    br_table v0, block9, [block1(v1), block2, block1(v3), block1(v1)]

block1(v4: i32):
    v5 = iconst.i32 10
    v6 = iadd v4, v5
    return v6

block2:
    return v2

block9:
    v7 = iconst.i32 -1
    return v7
}
";

fn call(m: &Module, arg: i64) -> (i64, u64) {
    let mut it = Interp::new(m).unwrap();
    assert_eq!(it.problems(), Vec::<String>::new());
    let r = it.call(FuncId::new(0), &[arg as u64]).unwrap().unwrap() as i64;
    (r, it.steps())
}

#[test]
fn text_form_prints_as_written_and_parses_back() {
    let m = module(SWITCH);
    let text = print_module(&m, &PrintOptions::default());
    assert!(
        text.contains("    br_table v0, block9, [block1(v1), block2, block1(v3), block1(v1)]\n"),
        "{text}"
    );
    assert_eq!(parse_module(&text).unwrap(), m);
    // An empty table: everything goes to the default.
    let empty = "func @g(i8) function {\nblock0(v0: i8):\n    br_table v0, block1, []\n\nblock1:\n    return\n}\n";
    let m = module(empty);
    assert_eq!(print_module(&m, &PrintOptions::default()), empty);
}

#[test]
fn syntax_errors_point_at_the_mistake() {
    let body = |t: &str| {
        format!("func @g(i8) function {{\nblock0(v0: i8):\n    {t}\n\nblock1:\n    return\n}}\n")
    };
    for (t, msg) in [
        ("br_table v0, block1, block1", "expected `[`"),
        ("br_table v0, block1 [block1]", "expected `,`"),
        (
            "br_table v0, block1, [block1 block1]",
            "expected `,` or `]`",
        ),
        (
            "br_table v0, block1, [v0]",
            "expected a block such as `block1`",
        ),
        ("br_table block1, [block1]", "expected a value"),
        (
            "v1 = br_table v0, block1, [block1]",
            "`br_table` produces no value",
        ),
        ("br_table v0, block1, [block7]", "block7"),
    ] {
        let e = parse_module(&body(t)).unwrap_err();
        assert!(e.message.contains(msg), "{t}: {e}");
    }
}

#[test]
fn verifier_wants_an_integer_index_and_matching_arguments() {
    let f = |params: &str, t: &str| {
        format!(
            "func @g({params}) function {{\nblock0(v0: {params}):\n    {t}\n\nblock1:\n    return\n\nblock2(v9: i32):\n    return\n}}\n"
        )
    };
    for (ty, ok) in [
        ("i8", true),
        ("i16", true),
        ("i32", true),
        ("i64", true),
        ("i1", false),
        ("f32", false),
        ("f64", false),
        ("ptr", false),
    ] {
        let m = parse_module(&f(ty, "br_table v0, block1, [block1]")).unwrap();
        match verify_module(&m) {
            Ok(()) => assert!(ok, "{ty} accepted"),
            Err(errs) => {
                assert!(!ok, "{ty} rejected: {errs:?}");
                let text = errs[0].to_string();
                assert!(text.contains("the br_table index v0 is"), "{text}");
            }
        }
    }
    for (t, msg) in [
        (
            "br_table v0, block2, [block1]",
            "block2 takes 1 arguments, found 0",
        ),
        (
            "br_table v0, block1, [block1, block2]",
            "block2 takes 1 arguments, found 0",
        ),
        (
            "br_table v0, block1, [block1, block2(v0)]",
            "argument 0 to block2 is i64, but the parameter v9 is i32",
        ),
    ] {
        let m = parse_module(&f("i64", t)).unwrap();
        let errs = verify_module(&m).expect_err(t);
        let text: Vec<String> = errs.iter().map(|e| e.to_string()).collect();
        assert!(text.iter().any(|e| e.contains(msg)), "{t}: {text:?}");
    }
}

#[test]
fn interpreter_reads_the_index_unsigned() {
    let m = module(SWITCH);
    let cases = [
        (0, 10),
        (1, 20),
        (2, 40),
        (3, 13),
        (4, -1),
        (100, -1),
        (32767, -1),
        // -1 as an i16 is 65535: past the table.
        (-1, -1),
        (-32768, -1),
        (-65536, 10), // canonicalised to 0
    ];
    for (arg, want) in cases {
        assert_eq!(call(&m, arg).0, want, "f({arg})");
    }
    // At every width, the top of the unsigned range is past a short table.
    for ty in ["i8", "i16", "i32", "i64"] {
        let text = format!(
            "func @g({ty}) -> i32 function {{\nblock0(v0: {ty}):\n    v1 = iconst.i32 1\n    v2 = iconst.i32 2\n    br_table v0, block1(v2), [block1(v1), block1(v1)]\n\nblock1(v3: i32):\n    return v3\n}}\n"
        );
        let m = module(&text);
        for (arg, want) in [(0, 1), (1, 1), (2, 2), (-1, 2), (-128, 2), (-2, 2)] {
            assert_eq!(call(&m, arg).0, want, "{ty} g({arg})");
        }
    }
}

/// The terminator of the first block of the only function.
fn first_terminator(m: &Module) -> &InstData {
    let f = &m.funcs[0];
    let t = f.terminator(f.layout[0]).unwrap();
    f.inst(t)
}

#[test]
fn a_constant_index_folds_to_a_jump() {
    for (k, dest, args) in [
        ("0", "block1", "(v1)"),
        ("1", "block2", ""),
        ("2", "block1", "(v3)"),
        ("4", "block9", ""),
        ("-1", "block9", ""),
    ] {
        let text = SWITCH.replace(
            "    v1 = sext.i32 v0\n",
            &format!("    v1 = sext.i32 v0\n    v8 = iconst.i16 {k}\n"),
        );
        let text = text.replace("br_table v0,", "br_table v8,");
        let mut m = module(&text);
        let want = call(&m, 7).0;
        assert!(const_fold::run(&mut m.funcs[0]));
        verify_module(&m).unwrap();
        let printed = print_module(&m, &PrintOptions::default());
        assert!(
            printed.contains(&format!("    jump {dest}{args}\n")),
            "{k}: {printed}"
        );
        assert!(matches!(first_terminator(&m), InstData::Jump { .. }));
        assert_eq!(call(&m, 7).0, want);
        // simplify_cfg folds it too, and then drops the blocks nothing reaches.
        let mut m = module(&text);
        assert!(simplify_cfg::run(&mut m.funcs[0]));
        verify_module(&m).unwrap();
        assert!(!print_module(&m, &PrintOptions::default()).contains("br_table"));
        assert_eq!(call(&m, 7).0, want);
    }
}

#[test]
fn a_table_of_one_destination_is_a_jump() {
    let text = "func @g(i32) -> i32 function {\nblock0(v0: i32):\n    v1 = iconst.i32 5\n    br_table v0, block1(v1), [block1(v1), block1(v1)]\n\nblock1(v2: i32):\n    return v2\n}\n";
    let mut m = module(text);
    assert!(simplify_cfg::run(&mut m.funcs[0]));
    verify_module(&m).unwrap();
    assert!(!print_module(&m, &PrintOptions::default()).contains("br_table"));
    // Different arguments are different destinations.
    let mut m = module(&text.replace("[block1(v1), block1(v1)]", "[block1(v1), block1(v0)]"));
    simplify_cfg::run(&mut m.funcs[0]);
    assert!(print_module(&m, &PrintOptions::default()).contains("br_table"));
}

#[test]
fn the_optimiser_keeps_the_table_and_its_meaning() {
    let before = module(SWITCH);
    let mut after = before.clone();
    optimize_function(&mut after.funcs[0]);
    verify_module(&after).unwrap();
    let text = print_module(&after, &PrintOptions::default());
    assert!(text.contains("br_table"), "{text}");
    for arg in -70000..70000 {
        if arg % 97 == 0 || (-10..10).contains(&arg) {
            assert_eq!(call(&before, arg).0, call(&after, arg).0, "f({arg})");
        }
    }
}

/// A random function `@f(T) -> i64` ending in a `br_table` on its parameter, whose
/// destinations return what identifies them and their arguments; and the expected
/// result for each index.
struct Case {
    text: String,
    ty: Type,
    /// The result of each entry, then the default's.
    results: Vec<i64>,
    /// How many runs of equal destinations the table has, the default's included.
    runs: usize,
}

fn random_case(rng: &mut Rng) -> Case {
    let ty = *rng.pick(&[Type::I8, Type::I16, Type::I32, Type::I64]);
    let len = match rng.below(10) {
        0 => 0,
        1 => 250 + rng.index(20), // around the 256 values of an i8
        _ => rng.index(40),
    };
    // Destinations: block1 (returns 1), block2 (returns 2), block3(a) returns a,
    // block4(a, b) returns a * 100 + b; the arguments are the constants v1..v4 (1..4).
    let dest = |rng: &mut Rng| -> (String, i64) {
        let c = |rng: &mut Rng| 1 + rng.index(4) as i64;
        match rng.below(4) {
            0 => ("block1".into(), 1),
            1 => ("block2".into(), 2),
            2 => {
                let a = c(rng);
                (format!("block3(v{a})"), a)
            }
            _ => {
                let (a, b) = (c(rng), c(rng));
                (format!("block4(v{a}, v{b})"), a * 100 + b)
            }
        }
    };
    let mut table: Vec<(String, i64)> = Vec::with_capacity(len);
    for _ in 0..len {
        // Runs: most entries repeat the one before.
        let d = match table.last() {
            Some(last) if rng.chance(60) => last.clone(),
            _ => dest(rng),
        };
        table.push(d);
    }
    let default = dest(rng);
    // An i8 index reaches entries 0 to 255 only, and the default only if the table
    // is shorter.
    let (reach, past) = match ty {
        Type::I8 => (len.min(256), len < 256),
        _ => (len, true),
    };
    let mut runs = 0;
    for k in 0..reach {
        if k == 0 || table[k].0 != table[k - 1].0 {
            runs += 1;
        }
    }
    if past && table.last().is_none_or(|l| l.0 != default.0) {
        runs += 1;
    }
    let entries: Vec<&str> = table.iter().map(|(t, _)| t.as_str()).collect();
    let text = format!(
        "func @f({ty}) -> i64 function {{
block0(v0: {ty}):
    v1 = iconst.i64 1
    v2 = iconst.i64 2
    v3 = iconst.i64 3
    v4 = iconst.i64 4
    br_table v0, {}, [{}]

block1:
    return v1

block2:
    return v2

block3(v5: i64):
    return v5

block4(v6: i64, v7: i64):
    v8 = iconst.i64 100
    v9 = imul v6, v8
    v10 = iadd v9, v7
    return v10
}}
",
        default.0,
        entries.join(", ")
    );
    let mut results: Vec<i64> = table.iter().map(|d| d.1).collect();
    results.push(default.1);
    Case {
        text,
        ty,
        results,
        runs,
    }
}

/// The indexes worth trying for a table of `len` entries at type `ty`: every entry,
/// the edges of the table and of the type, random ones.
fn indexes(rng: &mut Rng, ty: Type, len: usize) -> Vec<i64> {
    let mut out: Vec<i64> = (0..len as i64 + 2).collect();
    let bits = ty.bits();
    let (min, max) = if bits == 64 {
        (i64::MIN, i64::MAX)
    } else {
        (-(1i64 << (bits - 1)), (1i64 << (bits - 1)) - 1)
    };
    out.extend([-1, -2, min, max, min + 1, max - 1]);
    for _ in 0..20 {
        out.push(ty.canon_int(rng.next_u64() as i64));
    }
    out
}

#[test]
fn expansion_into_compares_agrees_with_the_table() {
    let mut rng = Rng::new(24);
    for case in 0..300 {
        let c = random_case(&mut rng);
        let table = module(&c.text);
        let mut expanded = table.clone();
        assert!(br_table::run_module(&mut expanded));
        verify_module(&expanded).unwrap_or_else(|e| panic!("case {case}: {e:?}\n{}", c.text));
        let text = print_module(&expanded, &PrintOptions::default());
        assert!(!text.contains("br_table"), "{text}");
        // A binary search over the runs: one compare per inner node of the tree.
        let compares = text.matches("icmp ult").count();
        assert_eq!(compares, c.runs - 1, "case {case}:\n{}\n{text}", c.text);
        let depth = (usize::BITS - (c.runs - 1).leading_zeros()) as u64; // ceil(log2)
        let len = c.results.len() - 1;
        for k in indexes(&mut rng, c.ty, len) {
            let (want_t, steps_t) = call(&table, k);
            let (got, steps_e) = call(&expanded, k);
            let u = c.ty.zext_bits(k);
            let want = c.results[if u < len as u64 { u as usize } else { len }];
            assert_eq!(want_t, want, "case {case}, index {k}: the interpreter");
            assert_eq!(got, want, "case {case}, index {k}:\n{}\n{text}", c.text);
            // Each level of the search is a constant, a compare and a branch.
            assert!(
                steps_e <= steps_t + 3 * depth,
                "case {case}, index {k}: {steps_e} steps against {steps_t} + 3 x {depth}"
            );
        }
    }
}
