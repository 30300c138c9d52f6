//! Parser errors and robustness of the text form.

use super::print::{format_float, is_plain_name};
use super::*;
use crate::types::Type;
use crate::verify::verify_module;

#[track_caller]
fn parse_err(text: &str) -> ParseError {
    match parse_module(text) {
        Ok(m) => panic!("parsed, but should not have:\n{text}\n---\n{m}"),
        Err(e) => e,
    }
}

#[track_caller]
fn assert_err(text: &str, line: u32, col: u32, msg: &str) {
    let e = parse_err(text);
    assert!(
        e.message.contains(msg),
        "expected `{msg}` in the error, got `{e}` for:\n{text}"
    );
    assert_eq!((e.line, e.col), (line, col), "{e}\nfor:\n{text}");
}

fn func(body: &str) -> String {
    format!("func @f(i32) -> i32 function {{\nblock0(v0: i32):\n{body}}}\n")
}

#[test]
fn error_display() {
    let e = parse_err("bogus");
    assert_eq!(
        e.to_string(),
        "1:1: expected `file`, `unchecked_pointers`, `struct`, `array`, `data`, `table`, `func`, `program`, `init_globals`, `globals`, `configuration` or `resource`, found `bogus`"
    );
}

#[test]
fn configuration_lines() {
    let e = parse_err("resource \"r\"\n");
    assert!(e.message.contains("after the `configuration` line"), "{e}");
    let e = parse_err("configuration \"a\"\nconfiguration \"b\"\n");
    assert!(e.message.contains("`configuration` is given twice"), "{e}");
    let e = parse_err("globals @nowhere\n");
    assert!(e.message.contains("unknown data `@nowhere`"), "{e}");
    let m = parse_module(
        "configuration \"C\"\nresource \"R\" globals \"g\"\nresource \"S\" programs \"p\" \"q\"\n",
    )
    .unwrap();
    let c = m.configuration.unwrap();
    assert_eq!(c.name, "C");
    assert_eq!(c.resources[0].globals, ["g"]);
    assert_eq!(c.resources[1].programs, ["p", "q"]);
}

#[test]
fn lexical_errors() {
    assert_err("file 0 \"abc", 1, 8, "unterminated string");
    assert_err("file 0 \"a\nb\"", 1, 8, "unterminated string");
    assert_err("file 0 \"a\\qb\"", 1, 10, "unknown escape `\\q`");
    assert_err("file 0 \"\\u{110000}\"", 1, 9, "bad escape");
    assert_err("file 0 \"\\u{41\"", 1, 9, "unterminated `\\u{…}` escape");
    assert_err(
        "data @x: i32 DINT global\n  #",
        2,
        3,
        "unexpected character `#`",
    );
    assert_err("data @: i32 global", 1, 7, "expected a name after `@`");
    assert_err("struct % struct {\n}", 1, 9, "expected a name after `%`");
    assert_err(&func("    return v0   !0:1.2\n"), 3, 21, "expected `..`");
    assert_err(
        &func("    return v0   !x\n"),
        3,
        18,
        "expected a file number",
    );
    assert_err(
        &func("    return v0   !0:99999999999..1\n"),
        3,
        20,
        "expected a start offset",
    );
    // Non-ASCII before the error: columns count characters.
    assert_err(
        "; ééé\ndata @\"ü\": i32 DINT global ?",
        2,
        28,
        "unexpected character `?`",
    );
}

#[test]
fn escapes_roundtrip() {
    let m = parse_module("file 0 \"a\\\"b\\\\c\\n\\t\\r\\u{1}\\u{e9}\"\n").unwrap();
    assert_eq!(m.files[0], "a\"b\\c\n\t\r\u{1}é");
    let t = print_module(&m, &PrintOptions::default());
    assert_eq!(t, "file 0 \"a\\\"b\\\\c\\n\\t\\r\\u{1}é\"\n");
    assert_eq!(parse_module(&t).unwrap(), m);
}

#[test]
fn declaration_errors() {
    assert_err("struct %S blob {\n}", 1, 11, "unknown struct kind `blob`");
    assert_err(
        "struct %S struct {\n    weird x: i32\n}",
        2,
        5,
        "unknown field role `weird`",
    );
    assert_err(
        "struct %S struct {\n    var x: i33\n}",
        2,
        12,
        "unknown type `i33`",
    );
    assert_err(
        "struct %S struct {\n    var x: i32 DINTY\n}",
        2,
        16,
        "unknown IEC type `DINTY`",
    );
    assert_err(
        "struct %S struct {\n    var x: i32\n",
        3,
        1,
        "expected `}` closing the struct",
    );
    assert_err(
        "struct %S struct {\n    var x i32\n}",
        2,
        11,
        "expected `:`",
    );
    assert_err(
        "struct %S struct {\n    var x: %T\n}",
        2,
        12,
        "unknown aggregate `%T`",
    );
    assert_err(
        "struct %S struct {\n}\nstruct %S struct {\n}",
        3,
        8,
        "aggregate `%S` is declared twice",
    );
    assert_err(
        "array %A = [3 x i8] lower x",
        1,
        27,
        "expected the lower bound",
    );
    assert_err("array %A = [3 i8] lower 0", 1, 15, "expected `x`");
    assert_err(
        "array %A = [-3 x i8] lower 0",
        1,
        13,
        "is not an array length",
    );
    assert_err("array %A = [3 x i8 SINT lower 0", 1, 25, "expected `]`");
    assert_err(
        "data @d: i32 DINT globl",
        1,
        19,
        "unknown data kind `globl`",
    );
    assert_err(
        "data @d: i32 INTEGER global",
        1,
        14,
        "unknown IEC type or data kind `INTEGER`",
    );
    assert_err(
        "data @d: i32 global\ndata @d: i32 global",
        2,
        6,
        "data `@d` is declared twice",
    );
    assert_err(
        "data @d: i32 global at",
        1,
        23,
        "expected a location string",
    );
    assert_err(
        "file 0 \"a\"\nfile 0 \"b\"",
        2,
        6,
        "file 0 is declared twice",
    );
    assert_err("file x \"a\"", 1, 6, "expected a file number");
    assert_err(
        "data @d: i32 global extra",
        1,
        21,
        "expected the end of the line",
    );
    assert_err(
        "init_globals @a\ninit_globals @a",
        2,
        1,
        "`init_globals` is given twice",
    );
    assert_err("init_globals @nope", 1, 14, "unknown function `@nope`");
    assert_err(
        "program \"p\" data @d body @b init @i",
        1,
        18,
        "unknown data `@d`",
    );
    assert_err(
        "program p data @d body @b init @i",
        1,
        9,
        "expected the instance name as a string",
    );
    assert_err(
        "data @d: i32 global\nprogram \"p\" data @d body @b init @i interval_us x",
        2,
        49,
        "expected an interval in µs",
    );
}

#[test]
fn function_errors() {
    assert_err(
        "func @f(i32 -> i32 function {\n}",
        1,
        13,
        "expected `,` or `)`",
    );
    assert_err(
        "func @f() -> i32 proc {\n}",
        1,
        18,
        "unknown function kind `proc`",
    );
    assert_err(
        "func @f() function {\nblock0:\n    return\n",
        4,
        1,
        "expected `}` closing the function",
    );
    assert_err(
        "func @f() function {\n    return\n}",
        2,
        5,
        "instruction before the first block label",
    );
    assert_err(
        "func @f() function {\n}\nfunc @f() function {\n}",
        3,
        6,
        "function `@f` is declared twice",
    );
    assert_err(
        "func @f() function {\nblock0:\n    return\nblock0:\n    return\n}",
        4,
        1,
        "block0 is defined twice",
    );
    assert_err(
        "func @f() function { x\n}",
        1,
        22,
        "expected the end of the line",
    );
    assert_err(
        "func @f() function {\n    ss0 = slot i32\n}",
        2,
        19,
        "expected the slot's name",
    );
    assert_err(
        "func @f() function {\n    ss0 = slot i32 \"a\"\n    ss0 = slot i32 \"b\"\n}",
        3,
        5,
        "ss0 is declared twice",
    );
    assert_err(
        "func @f() function {\n    ss0 = slot %Nope \"a\"\n}",
        2,
        16,
        "unknown aggregate `%Nope`",
    );
    assert_err("func @f(q32) function {\n}", 1, 9, "unknown type `q32`");
}

#[test]
fn instruction_errors() {
    let e = |body: &str, col: u32, msg: &str| assert_err(&func(body), 3, col, msg);
    e(
        "    v1 = frobnicate v0\n",
        10,
        "unknown instruction `frobnicate`",
    );
    e(
        "    v1 = iadd.i32 v0, v0\n",
        10,
        "unknown instruction `iadd.i32`",
    );
    e("    v1 = iadd v0\n", 10, "`iadd` takes 2 operands, found 1");
    e(
        "    v1 = iadd v0, v0, v0\n",
        10,
        "`iadd` takes 2 operands, found 3",
    );
    e("    v1 = ineg\n", 10, "`ineg` takes 1 operand, found 0");
    e(
        "    v1 = select v0, v0\n",
        10,
        "`select` takes 3 operands, found 2",
    );
    e("    store v0\n", 5, "`store` takes 2 operands, found 1");
    e("    v1 = iconst 3\n", 10, "`iconst` needs a type");
    e("    v1 = iconst.i31 3\n", 10, "unknown type `i31`");
    e("    v1 = iconst.i32 3.5\n", 21, "is not a 64-bit integer");
    e(
        "    v1 = iconst.i64 99999999999999999999\n",
        21,
        "is not a 64-bit integer",
    );
    e("    v1 = iconst.i32 x\n", 21, "expected an integer");
    e(
        "    v1 = fconst.i32 1.0\n",
        10,
        "`fconst` needs `f32` or `f64`",
    );
    e("    v1 = fconst.f32 1.0.0\n", 21, "is not a float constant");
    e("    v1 = fconst.f64 0x1g\n", 21, "is not a float constant");
    e(
        "    v1 = fconst.f64 banana\n",
        21,
        "is not a float constant",
    );
    e("    v1 = sext v0\n", 10, "`sext` needs a type");
    e(
        "    v1 = icmp foo v0, v0\n",
        15,
        "unknown integer condition `foo`",
    );
    e(
        "    v1 = fcmp slt v0, v0\n",
        15,
        "unknown float condition `slt`",
    );
    e("    v1 = iadd v0, 3\n", 19, "expected a value such as `v0`");
    e(
        "    v1 = iadd v0 v0\n",
        18,
        "expected `,` or the end of the line",
    );
    e("    v1 = iadd v0, v9\n", 19, "v9 is not defined");
    e("    v0 = iconst.i32 1\n", 5, "v0 is defined twice");
    e("    iadd v0, v0\n", 5, "`iadd` produces a value");
    e("    v1 = store v0, v0\n", 10, "`store` produces no value");
    e("    v1 = return v0\n", 10, "`return` produces no value");
    e("    return v0, v0\n", 5, "`return` takes at most 1 operand");
    e(
        "    v1 = raise_fault\n",
        10,
        "`raise_fault` produces no value",
    );
    e("    v1 = global_addr @nope\n", 22, "unknown data `@nope`");
    e("    v1 = global_addr v0\n", 22, "expected a data name");
    e("    v1 = slot_addr ss3\n", 20, "ss3 is not declared");
    e(
        "    v1 = slot_addr v3\n",
        20,
        "expected a slot such as `ss0`",
    );
    e(
        "    v1 = field_addr v0, %S.x\n",
        25,
        "unknown aggregate `%S`",
    );
    e(
        "    v1 = field_addr v0, %S\n",
        25,
        "expected a field such as `%S.f`",
    );
    e(
        "    v1 = field_addr v0, v0\n",
        25,
        "expected a field such as `%S.f`",
    );
    e(
        "    v1 = elem_addr v0, %A, v0\n",
        24,
        "unknown aggregate `%A`",
    );
    e(
        "    v1 = elem_addr v0, %A.x, v0\n",
        24,
        "unknown aggregate `%A.x`",
    );
    e(
        "    v1 = elem_addr v0, %\"A\".x, v0\n",
        24,
        "unexpected field after an aggregate name",
    );
    e("    v1 = call @g(v0)\n", 15, "unknown function `@g`");
    e("    v1 = call @f(v0\n", 20, "expected `,` or `)`");
    e("    v1 = call @f v0\n", 18, "expected `(`");
    e("    jump block9\n", 10, "block9 is not defined");
    e(
        "    jump v0\n",
        10,
        "expected a block such as `block1`, found `v0`",
    );
    e("    jump block0(v0, v8)\n", 21, "v8 is not defined");
    e("    brif v0, block0(v0)\n", 24, "expected `,`");
    e(
        "    return v0 !0:1..2 extra\n",
        23,
        "expected the end of the line",
    );
    e(
        "    v1 = v2 = iadd v0, v0\n",
        10,
        "unknown instruction `v2`",
    );
    e(
        "    x = iadd v0, v0\n",
        5,
        "expected a value such as `v0` before `=`",
    );
    e(
        "    v1 = iadd v1, v1\n    return v1\n",
        5,
        "cannot infer the type of v1",
    );
    e(
        "    v9999999999 = iconst.i32 1\n",
        5,
        "expected a value such as `v0` before `=`",
    );
    e("    v4000000000 = iconst.i32 1\n", 5, "too large");
}

#[test]
fn field_and_struct_checks_in_field_addr() {
    let text = "array %A = [2 x i8] lower 0\nstruct %S struct {\n    var Abc: i8\n}\n";
    let body =
        |b: &str| format!("{text}func @f(ptr) program {{\nblock0(v0: ptr):\n{b}    return\n}}\n");
    assert_err(
        &body("    v1 = field_addr v0, %A.x\n"),
        7,
        25,
        "`%A` is not a struct",
    );
    assert_err(
        &body("    v1 = field_addr v0, %S.nope\n"),
        7,
        25,
        "struct `%S` has no field `nope`",
    );
    // Field names are matched exactly first, then ignoring case.
    let m = parse_module(&body("    v1 = field_addr v0, %S.ABC\n")).unwrap();
    assert_eq!(m.to_string().matches("%S.Abc").count(), 1);
}

#[test]
fn call_results() {
    let text = "func @g() function {\nblock0:\n    return\n}\nfunc @h() -> i8 function {\nblock0:\n    v0 = iconst.i8 1\n    return v0\n}\n";
    assert_err(
        &format!("{text}func @f() function {{\nblock0:\n    v0 = call @g()\n    return\n}}\n"),
        12,
        10,
        "`@g` returns no value",
    );
    // A call without a result to a function with one parses; the verifier objects.
    let m = parse_module(&format!(
        "{text}func @f() function {{\nblock0:\n    call @h()\n    clock_ms\n    return\n}}\n"
    ))
    .unwrap();
    let errs = verify_module(&m).unwrap_err();
    assert_eq!(errs.len(), 2, "{errs:?}");
    assert!(errs[0].message.contains("the result is missing"));
}

#[test]
fn accepted_variants() {
    // `block1()`, hex integers, `+` exponents, `-0x` integers, blank lines and
    // comments everywhere, `\r\n` line ends, fields named like keywords.
    let text = "struct %S struct {\r\n    in in: i1 BOOL ; comment\r\n\r\n    var at: i8\r\n}\r\n\
        func @f() -> i64 function { ; c\n\n; only a comment\nblock0:\n    v1 = iconst.i64 0x10\n    v2 = iconst.i64 -0x10\n    v3 = fconst.f64 1.5e+3\n    v4 = fconst.f32 infinity\n    jump block1()\nblock1:\n    return v1\n}\n";
    let m = parse_module(text).unwrap();
    let f = &m.funcs[0];
    assert_eq!(
        f.insts[0],
        crate::inst::InstData::Iconst {
            ty: Type::I64,
            imm: 16
        }
    );
    assert_eq!(
        f.insts[1],
        crate::inst::InstData::Iconst {
            ty: Type::I64,
            imm: -16
        }
    );
    assert_eq!(
        f.insts[2],
        crate::inst::InstData::Fconst {
            ty: Type::F64,
            bits: 1500f64.to_bits()
        }
    );
    assert_eq!(
        f.insts[3],
        crate::inst::InstData::Fconst {
            ty: Type::F32,
            bits: f32::INFINITY.to_bits() as u64
        }
    );
    let crate::module::AggDef::Struct(s) = &m.aggs[0] else {
        panic!()
    };
    assert_eq!(s.fields[0].name, "in");
    assert_eq!(s.fields[1].name, "at");
    // `at` as a field name prints and parses back.
    let t = m.to_string();
    assert!(t.contains("    var at: i8\n"), "{t}");
    assert_eq!(parse_module(&t).unwrap().to_string(), t);
}

#[test]
fn float_formatting() {
    assert_eq!(format_float(Type::F32, 1.0f32.to_bits() as u64), "1.0");
    assert_eq!(format_float(Type::F32, f32::NAN.to_bits() as u64), "NaN");
    assert_eq!(
        format_float(Type::F32, (-f32::NAN).to_bits() as u64),
        "0xffc00000"
    );
    assert_eq!(format_float(Type::F32, 0x1_0000_0000), "0x100000000");
    assert_eq!(format_float(Type::F64, (-0.0f64).to_bits()), "-0.0");
    assert_eq!(format_float(Type::I32, 5), "0x5");
    // Every printed float reads back to the same bits.
    let mut rng = Rng(0x1234_5678_9abc_def0);
    for _ in 0..20000 {
        let x = rng.next_u64();
        for (ty, bits) in [(Type::F32, x & 0xffff_ffff), (Type::F64, x)] {
            let s = format_float(ty, bits);
            let t = format!(
                "func @f() function {{\nblock0:\n    v0 = fconst.{ty} {s}\n    return\n}}\n"
            );
            let m = parse_module(&t).unwrap();
            assert_eq!(
                m.funcs[0].insts[0],
                crate::inst::InstData::Fconst { ty, bits },
                "{s}"
            );
        }
    }
}

#[test]
fn plain_names() {
    for ok in ["a", "_", "a.b", "x$1", "A_9.", "main$init"] {
        assert!(is_plain_name(ok), "{ok}");
    }
    for bad in ["", "1a", "a b", "a-b", "é", ".a", "$a", "a\"", "a:b"] {
        assert!(!is_plain_name(bad), "{bad}");
    }
}

use crate::rng::Rng;

/// Parses `text`; if it parses, verifies and prints the module (none may panic), and
/// the printed module must print the same after another parse.
fn exercise(text: &str) {
    if let Ok(m) = parse_module(text) {
        let _ = verify_module(&m);
        let t = print_module(&m, &PrintOptions::LOCATED);
        let m2 = parse_module(&t).unwrap_or_else(|e| panic!("{e}\n{t}\nfrom\n{text}"));
        assert_eq!(print_module(&m2, &PrintOptions::LOCATED), t);
    }
}

const SAMPLE: &str = r#"file 0 "a.st"
struct %S fb {
    in x: i32 DINT
    var a: %A at "%MW3"
}
array %A = [4 x i16 INT] lower -1
data @d: %S program
data @g: f64 LREAL global
func @f(i32, f32) -> i32 function !0:1..9 {
    ss0 = slot %A "buf"
block0(v0: i32, v1: f32):
    v2 = iconst.i32 7   !0:3..4
    v3 = iadd v0, v2
    v4 = fconst.f32 NaN
    v5 = fcmp lt v1, v4
    v9 = slot_addr ss0
    v10 = elem_addr v9, %A, v0
    v11 = load.i16 v10
    v12 = sext.i32 v11
    brif v5, block1(v3), block2
block2:
    v6 = select v5, v3, v12
    v13 = clock_ms
    raise_fault
    jump block1(v6)
block1(v7: i32):
    v8 = call @g(v7)
    return v8
}
func @g(i32) -> i32 helper {
block0(v0: i32):
    v1 = global_addr @d
    v2 = field_addr v1, %S.x
    store v0, v2
    return v0
}
func @b(ptr) program {
block0(v0: ptr):
    return
}
func @i(ptr) init {
block0(v0: ptr):
    return
}
func @gi() init {
block0:
    return
}
program "p" data @d body @b init @i interval_us 5000
init_globals @gi
"#;

#[test]
fn sample_is_valid() {
    let m = parse_module(SAMPLE).unwrap();
    verify_module(&m).unwrap();
}

#[test]
fn truncated_inputs_do_not_panic() {
    for (i, _) in SAMPLE.char_indices() {
        exercise(&SAMPLE[..i]);
    }
}

#[test]
fn mutated_inputs_do_not_panic() {
    let alphabet: Vec<char> = "abvkx019%@\"\\!:.,()[]{}=-> \n\t;#é$_".chars().collect();
    let words = [
        "iadd",
        "v0",
        "v99",
        "block1",
        "block0",
        "ss0",
        "%S",
        "%A",
        "@f",
        "@d",
        "i1",
        "f64",
        "ptr",
        "x",
        "0x7fc00000",
        "-inf",
        "NaN",
        "!0:1..2",
        "(",
        ")",
        ",",
        "=",
        "->",
        "{",
        "}",
        "call",
        "jump",
        "brif",
        "return",
        "store",
        "load.i32",
        "field_addr",
        "%S.x",
        "\n",
    ];
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    let sample: Vec<char> = SAMPLE.chars().collect();
    for _ in 0..3000 {
        let mut chars = sample.clone();
        for _ in 0..1 + rng.index(4) {
            let at = rng.index(chars.len());
            match rng.index(4) {
                0 => {
                    chars.remove(at);
                }
                1 => chars.insert(at, alphabet[rng.index(alphabet.len())]),
                2 => chars[at] = alphabet[rng.index(alphabet.len())],
                _ => {
                    let w = words[rng.index(words.len())];
                    for (k, c) in w.chars().enumerate() {
                        chars.insert(at + k, c);
                    }
                }
            }
        }
        let text: String = chars.into_iter().collect();
        exercise(&text);
    }
}

#[test]
fn token_soup_does_not_panic() {
    let words = [
        "func",
        "@f",
        "(",
        ")",
        "i32",
        "->",
        "function",
        "{",
        "}",
        "\n",
        "block0",
        "block1",
        ":",
        "v0",
        "v1",
        "=",
        "iadd",
        ",",
        "return",
        "jump",
        "struct",
        "%S",
        "fb",
        "var",
        "x",
        "array",
        "[",
        "]",
        "lower",
        "0",
        "-1",
        "data",
        "@d",
        "program",
        "global",
        "at",
        "\"s\"",
        "ss0",
        "slot",
        "slot_addr",
        "call",
        "@g",
        "init_globals",
        "file",
        "!0:0..1",
        "iconst.i32",
        "fconst.f64",
        "select",
        "brif",
        "load.i8",
        "store",
        "%S.x",
        "field_addr",
        "elem_addr",
        "icmp",
        "eq",
        "sext.i64",
    ];
    let mut rng = Rng(42);
    for _ in 0..3000 {
        let n = rng.index(60);
        let mut text = String::new();
        for _ in 0..n {
            text.push_str(words[rng.index(words.len())]);
            text.push(' ');
        }
        exercise(&text);
    }
}

/// Canonical numbering renames in order of appearance, from 0, per function, and
/// leaves names from the source (symbols, quoted names) alone.
#[test]
fn canonical_numbering_follows_the_order_of_appearance() {
    use super::print::canonical_numbers;
    let text = "func @f(ptr) program {\n    ss0 = slot i16 \"v9 \\\"block3\\\\\"\nblock3(v7: ptr):\n    v9 = iconst.i16 1\n    \
                brif v9, block5(v7), block3\n}\n";
    let want = "func @f(ptr) program {\n    ss0 = slot i16 \"v9 \\\"block3\\\\\"\nblock0(v0: ptr):\n    v1 = iconst.i16 1\n    \
                brif v1, block1(v0), block0\n}\n";
    assert_eq!(canonical_numbers(text), want);
    let other = "data @v12: %block9 program\n    v = field_addr v0x, %main.v1\n";
    assert_eq!(canonical_numbers(other), other);
}

/// Two builds of one function numbered differently print the same canonically.
#[test]
fn canonical_printing_hides_the_builders_numbering() {
    let a = "func @f(i32) -> i32 function {\nblock0(v0: i32):\n    v1 = iconst.i32 2\n    v2 = iadd v0, v1\n    return v2\n}\n";
    let b = "func @f(i32) -> i32 function {\nblock4(v3: i32):\n    v7 = iconst.i32 2\n    v5 = iadd v3, v7\n    return v5\n}\n";
    let print = |t: &str, canonical| {
        let m = parse_module(t).expect("parses");
        print_module(
            &m,
            &PrintOptions {
                locations: false,
                canonical,
            },
        )
    };
    assert_ne!(print(a, false), print(b, false));
    assert_eq!(print(a, true), print(b, true));
    assert_eq!(print(b, true), print(a, false));
}
