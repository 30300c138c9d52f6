//! The parser's error recovery: one diagnostic per mistake, no cascade, no panic on
//! garbage, truncation or deep nesting.

use super::*;

pub(super) fn check_errors(src: &str, expected: &[&str]) {
    let (_, d, _) = parse_str(src);
    let got: Vec<String> = d.iter().map(|d| d.to_string()).collect();
    assert_eq!(got, expected, "for\n{src}\n{}", show(&d, src));
}

#[test]
fn missing_semicolon_is_one_error() {
    check_errors(
        "PROGRAM p\n x := 1\n y := 2;\n IF a THEN z := 3 END_IF;\n w := 4\nEND_PROGRAM",
        &[
            "error[E0102]: expected `;`, found `y`",
            "error[E0102]: expected `;`, found `END_IF`",
            "error[E0102]: expected `;`, found `END_PROGRAM`",
        ],
    );
    // The statement after a missing `;` on a new line is kept.
    let (u, _, _) = parse_str("PROGRAM p\n x := 1\n y := 2;\nEND_PROGRAM");
    let Item::Pou(p) = &u.items[0] else { panic!() };
    assert_eq!(p.body.stmts.len(), 2);
}

#[test]
fn unclosed_blocks_are_one_error() {
    check_errors(
        "PROGRAM p\n IF a THEN x := 1;\nEND_PROGRAM\nPROGRAM q x := 1; END_PROGRAM",
        &["error[E0104]: expected `END_IF`, found `END_PROGRAM`"],
    );
    check_errors(
        "PROGRAM p\n IF a THEN WHILE b DO x := 1; END_IF;\nEND_PROGRAM",
        &["error[E0104]: expected `END_WHILE`, found `END_IF`"],
    );
    check_errors(
        "PROGRAM p\n FOR i := 1 TO 3 DO x := 1; END_WHILE;\n y := 2;\nEND_PROGRAM",
        &["error[E0104]: expected `END_FOR`, found `END_WHILE`"],
    );
    check_errors(
        "PROGRAM p\n x := 1;\nFUNCTION f : INT f := 1; END_FUNCTION",
        &["error[E0104]: expected `END_PROGRAM`, found `FUNCTION`"],
    );
    check_errors(
        "FUNCTION f : INT\n f := 1;\nEND_FUNCTION_BLOCK\nPROGRAM p END_PROGRAM",
        &["error[E0104]: expected `END_FUNCTION`, found `END_FUNCTION_BLOCK`"],
    );
    check_errors(
        "PROGRAM p VAR x : INT;\n x := 1;\nEND_PROGRAM",
        &["error[E0104]: expected `END_VAR`, found `x`"],
    );
    check_errors(
        "PROGRAM p\n REPEAT x := 1; END_REPEAT;\nEND_PROGRAM",
        &["error[E0104]: expected `UNTIL`, found `END_REPEAT`"],
    );
    check_errors(
        "TYPE s : STRUCT a : INT;\nEND_TYPE\nPROGRAM p END_PROGRAM",
        &["error[E0104]: expected `END_STRUCT`, found `END_TYPE`"],
    );
}

#[test]
fn stray_closers() {
    check_errors(
        "PROGRAM p\n x := 1;\n END_IF;\n ELSE\n y := 2;\nEND_PROGRAM",
        &[
            "error[E0103]: unexpected `END_IF`: no IF is open",
            "error[E0103]: unexpected `ELSE`: no IF or CASE is open",
        ],
    );
    check_errors(
        "PROGRAM p\n WHILE a DO x := 1; ELSE y := 2; END_WHILE;\nEND_PROGRAM",
        &["error[E0103]: unexpected `ELSE`: no IF or CASE is open"],
    );
    check_errors(
        "PROGRAM p\n IF a THEN x := 1; ELSE y := 1; ELSE z := 1; END_IF;\nEND_PROGRAM",
        &["error[E0103]: unexpected `ELSE`: no IF or CASE is open"],
    );
    check_errors(
        "END_IF; PROGRAM p END_PROGRAM",
        &["error[E0103]: unexpected `END_IF`: it closes nothing here"],
    );
}

#[test]
fn header_errors() {
    check_errors(
        "PROGRAM p\n IF a > 1\n   x := 0;\n END_IF;\n y := 1;\nEND_PROGRAM",
        &["error[E0101]: expected `THEN`, found `x`"],
    );
    check_errors(
        "PROGRAM p\n IF a = THEN x := 0; END_IF;\n WHILE DO y := 1; END_WHILE;\n FOR 1 := 2 TO 3 DO END_FOR;\nEND_PROGRAM",
        &[
            "error[E0101]: expected an expression, found `THEN`",
            "error[E0101]: expected an expression, found `DO`",
            "error[E0101]: expected the control variable, found `1`",
        ],
    );
    check_errors(
        "PROGRAM p\n CASE x OF 1: y := 1; 2 3: y := 2; 4: y := 3; END_CASE;\nEND_PROGRAM",
        &["error[E0101]: expected `:`, `,` or `..` after a CASE label, found `3`"],
    );
}

#[test]
fn expression_statement_errors() {
    check_errors(
        "PROGRAM p x = 5; y := 1; END_PROGRAM",
        &["error[E0108]: expected `:=` or a call, found `=`"],
    );
    check_errors(
        "PROGRAM p a + b; END_PROGRAM",
        &["error[E0108]: expected `:=` or a call, found `+`"],
    );
    check_errors(
        "PROGRAM p x := (a + ; y := 1; END_PROGRAM",
        &["error[E0101]: expected an expression, found `;`"],
    );
    check_errors(
        "PROGRAM p x := f(a b); END_PROGRAM",
        &["error[E0101]: expected `,` or `)`, found `b`"],
    );
    check_errors(
        "PROGRAM p x := 1 2 3; y := 4; END_PROGRAM",
        &["error[E0102]: expected `;`, found `2`"],
    );
    check_errors(
        "PROGRAM p ) := 1; y := 4; END_PROGRAM",
        &["error[E0101]: expected a statement, found `)`"],
    );
    check_errors(
        "PROGRAM p x := %X3; END_PROGRAM",
        &["error[E0101]: `%X3` selects part of a variable: write it after one, as in `x.%X3`"],
    );
}

#[test]
fn several_independent_errors_give_exactly_that_many_diagnostics() {
    let src = "\
PROGRAM a
VAR
  x : INT
  y : INT;
END_VAR
  x := 1 +;
  IF x > 1 THEN
    y := 2
  END_IF;
  z := $;
END_PROGRAM

FUNCTION f : INT
  f := 16#GG;
  CASE f OF 1: f := 2; END_WHILE;
END_FUNCTION

TYPE t : (a, b; END_TYPE

PROGRAM b
  x := T#5q;
  y := 'unterminated;
END_PROGRAM
";
    let (u, d, _) = parse_str(src);
    let codes: Vec<&str> = d.iter().map(|d| d.code).collect();
    assert_eq!(
        codes,
        ["E0102", "E0101", "E0102", "E0001", "E0005", "E0104", "E0101", "E0007", "E0003"],
        "{}",
        show(&d, src)
    );
    // The good parts are still there.
    assert_eq!(
        u.items.iter().filter(|i| matches!(i, Item::Pou(_))).count(),
        3
    );
}

#[test]
fn lexical_errors_are_not_repeated_by_the_parser() {
    check_errors(
        "PROGRAM p x := ?; y := 1; END_PROGRAM",
        &["error[E0001]: unexpected character `?`"],
    );
    check_errors(
        "PROGRAM p x := 1 ?; END_PROGRAM",
        &["error[E0001]: unexpected character `?`"],
    );
    check_errors(
        "PROGRAM p x := 1; (* open comment\n y := 2;",
        &["error[E0002]: unterminated comment: `(*` has no matching `*)`"],
    );
    check_errors(
        "PROGRAM p x := 'abc",
        &["error[E0003]: unterminated string literal: missing closing `'`"],
    );
}

#[test]
fn unnamed_located_variables() {
    check_errors(
        "PROGRAM p VAR AT %QX0.1 : BOOL; ok AT %QX0.2 : BOOL; END_VAR END_PROGRAM",
        &["error[E0106]: a located variable needs a name here"],
    );
    ok("VAR_GLOBAL AT %QX0.1 : BOOL; END_VAR");
}

#[test]
fn unsupported_declarations() {
    // Edge-detecting inputs parse (`crate::edges` gives them their meaning).
    check_errors(
        "FUNCTION_BLOCK f VAR_INPUT c : BOOL R_EDGE; d : BOOL F_EDGE; END_VAR END_FUNCTION_BLOCK",
        &[],
    );
    check_errors(
        "PROGRAM p VAR r : REFERENCE TO INT; x : INT; END_VAR END_PROGRAM",
        &[],
    );
    check_errors(
        "CONFIGURATION c VAR_ACCESS a : p.x : INT READ_WRITE; END_VAR END_CONFIGURATION",
        &["error[E0107]: VAR_ACCESS declarations are not supported"],
    );
}

#[test]
fn garbage_and_truncation_never_panic() {
    let src = "TYPE s : STRUCT a : INT := 1; END_STRUCT; e : (x, y := 2); END_TYPE\n\
        FUNCTION_BLOCK fb EXTENDS b VAR_INPUT i : ARRAY[1..2] OF INT := [1, 2(3)]; END_VAR\n\
        IF a THEN b := c.d[1]^.%X2; ELSIF e THEN f(g := 1, h => i); ELSE j := -k ** 2; END_IF;\n\
        CASE x OF 1, 2..3: ; ELSE END_CASE; FOR i := 1 TO 2 BY 3 DO EXIT; END_FOR;\n\
        WHILE TRUE DO CONTINUE; END_WHILE; REPEAT RETURN; UNTIL T#1s > TIME#2ms END_REPEAT;\n\
        METHOD m : INT m := 1; END_METHOD ACTION act: x := 'a$N'; END_ACTION END_FUNCTION_BLOCK\n\
        CONFIGURATION c RESOURCE r ON p TASK t(INTERVAL := T#1s); PROGRAM i WITH t : x(a := 1); END_RESOURCE END_CONFIGURATION";
    // Every prefix: the parser stops, with errors only.
    for end in 0..=src.len() {
        if src.is_char_boundary(end) {
            let _ = parse_str(&src[..end]);
        }
    }
    // Every prefix of a token soup, and random byte strings.
    let mut rng = plcc_ir::rng::Rng(0x9e37_79b9_7f4a_7c15);
    let words = [
        "IF",
        "THEN",
        "ELSE",
        "END_IF",
        "CASE",
        "OF",
        ":",
        ":=",
        ";",
        "(",
        ")",
        "[",
        "]",
        "x",
        "1",
        "..",
        ",",
        "FOR",
        "TO",
        "DO",
        "END_FOR",
        "WHILE",
        "END_WHILE",
        "REPEAT",
        "UNTIL",
        "END_REPEAT",
        "VAR",
        "END_VAR",
        "PROGRAM",
        "END_PROGRAM",
        "FUNCTION",
        "TYPE",
        "STRUCT",
        "END_STRUCT",
        "END_TYPE",
        "ARRAY",
        "AT",
        "%IX0.0",
        ".",
        "^",
        "#",
        "=>",
        "NOT",
        "+",
        "-",
        "**",
        "'s'",
        "T#1s",
        "METHOD",
        "ACTION",
        "CONFIGURATION",
        "RESOURCE",
        "TASK",
        "END_CONFIGURATION",
        "ELSIF",
        "EXIT",
        "$",
        "(*",
        "*)",
    ];
    for _ in 0..300 {
        let mut s = String::new();
        let n = (rng.0 % 60) as usize;
        for _ in 0..n {
            s.push_str(rng.pick::<&str>(&words));
            s.push(' ');
        }
        let _ = parse_str(&s);
    }
}

/// Runs `f` on a thread with a small stack (what a test thread or a small embedder
/// gives), so that a recursion limit that is too generous shows up here.
fn on_small_stack(f: impl FnOnce() + Send + 'static) {
    std::thread::Builder::new()
        .stack_size(2 << 20)
        .spawn(f)
        .unwrap()
        .join()
        .unwrap();
}

#[test]
fn deep_nesting_is_one_error_and_no_overflow() {
    on_small_stack(|| {
        let n = 10_000;
        let parens = format!(
            "PROGRAM p x := {}1{}; y := 2; END_PROGRAM",
            "(".repeat(n),
            ")".repeat(n)
        );
        assert_eq!(codes_of(&parens), ["E0105"]);
        let ifs = format!(
            "PROGRAM p {} x := 1; {} y := 2; END_PROGRAM",
            "IF a THEN ".repeat(n),
            "END_IF; ".repeat(n)
        );
        let (u, d, _) = parse_str(&ifs);
        assert_eq!(d.iter().map(|d| d.code).collect::<Vec<_>>(), ["E0105"]);
        let Item::Pou(p) = &u.items[0] else { panic!() };
        assert_eq!(p.body.stmts.len(), 2);
        let nots = format!("PROGRAM p x := {}a; END_PROGRAM", "NOT ".repeat(n));
        assert_eq!(codes_of(&nots), ["E0105"]);
        let arrays = format!(
            "PROGRAM p VAR x : {}INT; y : INT; END_VAR END_PROGRAM",
            "ARRAY[1..2] OF ".repeat(n)
        );
        assert_eq!(codes_of(&arrays), ["E0105"]);
        let structs = format!("TYPE t : {} END_TYPE", "STRUCT a : ".repeat(n));
        assert!(codes_of(&structs).contains(&"E0105"));
        let inits = format!(
            "PROGRAM p VAR x : S := {}1{}; END_VAR END_PROGRAM",
            "(a := ".repeat(n),
            ")".repeat(n)
        );
        assert_eq!(codes_of(&inits), ["E0105"]);
        let calls = format!(
            "PROGRAM p x := {}1{}; END_PROGRAM",
            "f(".repeat(n),
            ")".repeat(n)
        );
        assert_eq!(codes_of(&calls), ["E0105"]);
        let chain = format!(
            "PROGRAM p x := 1{}; y := 1; END_PROGRAM",
            " + 1".repeat(100_000)
        );
        assert_eq!(codes_of(&chain), ["E0105"]);
        let members = format!("PROGRAM p x := a{}; END_PROGRAM", ".b".repeat(100_000));
        assert_eq!(codes_of(&members), ["E0105"]);
        // Just below the limits everything parses (and the tree can be dropped).
        let d = (super::super::parser::MAX_DEPTH - 2) as usize;
        ok(&format!(
            "PROGRAM p x := {}1{}; END_PROGRAM",
            "(".repeat(d),
            ")".repeat(d)
        ));
        ok(&format!(
            "PROGRAM p {} x := 1; {} END_PROGRAM",
            "IF a THEN ".repeat(d),
            "END_IF; ".repeat(d)
        ));
        ok(&format!(
            "PROGRAM p x := 1{}; END_PROGRAM",
            " + 1".repeat(900)
        ));
    });
}
