//! STL parser tests: every construct (compared through an ST-like rendering of the
//! tree), precedence, spans, each diagnostic with exact counts, recovery, and inputs
//! that must neither panic nor loop (garbage, truncation, deep nesting).

use super::parse;
use crate::ast::*;
use crate::intern::Interner;
use crate::print::{Printer, Style};
use crate::source::SourceFile;
use plcc_ir::diag::{Diagnostic, FileId};
use std::fmt::Write;

fn parse_str(src: &str) -> (SourceUnit, Vec<Diagnostic>, Interner) {
    let mut i = Interner::new();
    let mut d = Vec::new();
    let u = parse(FileId(0), src, &mut i, &mut d);
    (u, d, i)
}

fn show(d: &[Diagnostic], src: &str) -> String {
    let f = SourceFile::new("t.stl", src);
    let mut s = String::new();
    for d in d {
        let (l, c) = d.span.map_or((0, 0), |sp| f.line_col(sp.start));
        let _ = writeln!(s, "{l}:{c}: {d} [{}]", d.label);
    }
    s
}

/// Parses and asserts there is no diagnostic.
fn ok(src: &str) -> (SourceUnit, Interner) {
    let (u, d, i) = parse_str(src);
    assert!(
        d.is_empty(),
        "unexpected diagnostics for\n{src}\n{}",
        show(&d, src)
    );
    (u, i)
}

/// The codes reported for `src`, in source order.
fn codes_of(src: &str) -> Vec<&'static str> {
    parse_str(src).1.iter().map(|d| d.code).collect()
}

/// Asserts that `src` gives exactly these codes, in this order.
#[track_caller]
fn errs(src: &str, want: &[&str]) {
    let (_, d, _) = parse_str(src);
    let got: Vec<&str> = d.iter().map(|d| d.code).collect();
    assert_eq!(got, want, "for\n{src}\n{}", show(&d, src));
}

// ---------------------------------------------------------------- rendering

/// The unit printed as ST, every operation in parentheses (names as interned).
fn render(u: &SourceUnit, i: &Interner) -> String {
    Printer::new(i).with_style(Style::Parenthesised).unit(u)
}

/// Parses without errors and renders.
#[track_caller]
fn rendered(src: &str) -> String {
    let (u, i) = ok(src);
    render(&u, &i)
}

/// The main body's statements printed as ST.
#[track_caller]
fn body(stmts_src: &str) -> String {
    let (p, i) = main_program(stmts_src);
    Printer::new(&i)
        .with_style(Style::Parenthesised)
        .stmts(&p.body.stmts)
}

/// The program around the statements `stmts_src`.
#[track_caller]
fn main_program(stmts_src: &str) -> (Pou, Interner) {
    let src = format!("program t;\nbegin\n{stmts_src}\nend.\n");
    let (u, i) = ok(&src);
    let Some(Item::Pou(p)) = u.items.into_iter().last() else {
        panic!("no program")
    };
    (p, i)
}

/// The expression of `x := <src>;`, every operation in parentheses.
#[track_caller]
fn expr(src: &str) -> String {
    let (p, i) = main_program(&format!("x := {src};"));
    let [Stmt {
        kind: StmtKind::Assign { value, .. },
        ..
    }] = &p.body.stmts[..]
    else {
        panic!("not one assignment: {:?}", p.body.stmts)
    };
    Printer::new(&i).with_style(Style::Tree).expr(value)
}

// ---------------------------------------------------------------- program shape

#[test]
fn whole_program() {
    let src = "\
pragma plc gama cero @ 20 MHz (* free text *)
pragma core
uses plcud, io;
program Demo;
var
  total : INT;
  a, b : BOOL := TRUE;
end_var;
var flags : USINT; end_var;
constant LIMIT : INT := 10;
constant STEP : INT := 2 + 1;
function scale(x : INT, k : INT) INT;
begin
  scale := x * k;
end;
procedure bump(n : INT);
var rest : INT; end_var;
begin
  rest := n % LIMIT;
  total := total + rest;
end;
begin
  var i : INT; end_var;
  var j : SINT := -1; end_var;
  constant TWO : INT := 2;
  i := scale(i, TWO);
  bump(i);
end.
";
    let want = "\
VAR_GLOBAL
    TOTAL : INT;
    A, B : BOOL := TRUE;
END_VAR

VAR_GLOBAL
    FLAGS : USINT;
END_VAR

VAR_GLOBAL CONSTANT
    LIMIT : INT := 10;
    STEP : INT := (2 + 1);
END_VAR

FUNCTION SCALE : INT
    VAR_INPUT
        X : INT;
        K : INT;
    END_VAR
    SCALE := (X * K);
END_FUNCTION

FUNCTION BUMP
    VAR_INPUT
        N : INT;
    END_VAR
    VAR
        REST : INT;
    END_VAR
    REST := (N MOD LIMIT);
    TOTAL := (TOTAL + REST);
END_FUNCTION

PROGRAM DEMO
    VAR
        I : INT;
    END_VAR
    VAR
        J : SINT := (-1);
    END_VAR
    VAR CONSTANT
        TWO : INT := 2;
    END_VAR
    I := SCALE(I, TWO);
    BUMP(I);
END_PROGRAM
";
    assert_eq!(rendered(src), want);
}

#[test]
fn parameter_list_forms() {
    // The paper's form (`;` separators, `;` before the result type, no `;` after
    // it), the reference page's form (`,` separators, `;` after the type), a Pascal
    // colon, grouped names, and no parameters at all.
    let want_rd3 = "\
FUNCTION RD3 : INT
    VAR_INPUT
        S1 : INT;
        S2 : INT;
        S3 : INT;
    END_VAR
    RD3 := ((S1 * S2) / S3);
END_FUNCTION
";
    let body = "begin\n    rd3 := s1 * s2 / s3;\nend;\nbegin end.";
    for header in [
        "FUNCTION RD3(S1 : INT; S2 : INT; S3 : INT); INT",
        "function rd3(s1 : INT, s2 : INT, s3 : INT) INT;",
        "function rd3(s1 : INT; s2 : INT; s3 : INT) : INT;",
        "function rd3(s1 : INT, s2 : INT; s3 : INT) INT",
    ] {
        let src = format!("program p;\n{header}\n{body}");
        let r = rendered(&src);
        assert!(r.starts_with(want_rd3), "{header}:\n{r}");
    }
    let r = rendered(
        "program p;\nfunction f(a, b : INT; c : BOOL) INT;\nbegin f := a; end;\nbegin end.",
    );
    assert!(
        r.contains("    VAR_INPUT\n        A, B : INT;\n        C : BOOL;\n    END_VAR"),
        "{r}"
    );
    for header in ["function f INT;", "function f() INT;", "function f: INT;"] {
        let r = rendered(&format!(
            "program p;\n{header}\nbegin f := 1; end;\nbegin end."
        ));
        assert!(
            r.starts_with("FUNCTION F : INT\n    F := 1;\nEND_FUNCTION"),
            "{header}:\n{r}"
        );
    }
    for header in ["procedure p;", "procedure p();", "procedure p"] {
        let r = rendered(&format!("program q;\n{header}\nbegin end\nbegin end."));
        assert!(r.starts_with("FUNCTION P\nEND_FUNCTION"), "{header}:\n{r}");
    }
}

#[test]
fn subprogram_locals_before_or_after_begin() {
    let want = "    VAR\n        T : INT;\n    END_VAR\n    VAR CONSTANT\n        K : INT := 3;\n    END_VAR\n    T := (A * K);\n    F := T;\n";
    for src in [
        "function f(a : INT) INT;\nvar t : INT; end_var;\nconstant k : INT := 3;\nbegin t := a * k; f := t; end;",
        "function f(a : INT) INT;\nbegin var t : INT; end_var;\nconstant k : INT := 3;\nt := a * k; f := t; end;",
        "function f(a : INT) INT;\nvar t : INT; end_var;\nbegin constant k : INT := 3;\nt := a * k; f := t; end;",
    ] {
        let r = rendered(&format!("program p;\n{src}\nbegin end."));
        assert!(r.contains(want), "{src}:\n{r}");
    }
}

#[test]
fn empty_program_and_case_insensitivity() {
    assert_eq!(
        rendered("program p;\nbegin\nend."),
        "PROGRAM P\nEND_PROGRAM\n"
    );
    assert_eq!(
        rendered("PrOgRaM Mixed; BeGiN X := 1; EnD."),
        "PROGRAM MIXED\n    X := 1;\nEND_PROGRAM\n"
    );
    // Nested comments, comments between any tokens, the end of the file after `end.`.
    assert_eq!(
        rendered("(* a (* nested *) comment *) program (*x*) p ; begin end . (* trailing *)\n"),
        "PROGRAM P\nEND_PROGRAM\n"
    );
}

// ---------------------------------------------------------------- statements

#[test]
fn assignments_and_calls() {
    assert_eq!(
        body("x := 1; p(1, x + 2); q(); r; y := f(g(1), 2);"),
        "X := 1;\nP(1, (X + 2));\nQ();\nR();\nY := F(G(1), 2);\n"
    );
}

#[test]
fn if_forms() {
    let want = "IF (A = B) THEN\n    X := 1;\nELSE\n    X := 2;\nEND_IF;\n";
    // With `;` before else, without it, and with blocks (with or without `;` after
    // their `end`).
    assert_eq!(body("if a = b then x := 1; else x := 2;"), want);
    assert_eq!(body("if a = b then x := 1 else x := 2;"), want);
    assert_eq!(
        body("if a = b then begin x := 1; end else begin x := 2; end"),
        want
    );
    assert_eq!(
        body("if a = b then begin x := 1 ; end; else begin x := 2; end;"),
        want
    );
    assert_eq!(
        body("IF A = B THEN\nBEGIN\n    A := A + #1;\nEND\nELSE\nBEGIN\n    B := A - #1;\nEND"),
        "IF (A = B) THEN\n    A := (A + 1);\nELSE\n    B := (A - 1);\nEND_IF;\n"
    );
    assert_eq!(
        body("if c then x := 1;"),
        "IF C THEN\n    X := 1;\nEND_IF;\n"
    );
    // `else if` becomes ELSIF; a dangling else goes to the innermost if.
    assert_eq!(
        body("if a then x := 1; else if b then x := 2; else x := 3;"),
        "IF A THEN\n    X := 1;\nELSIF B THEN\n    X := 2;\nELSE\n    X := 3;\nEND_IF;\n"
    );
    assert_eq!(
        body("if a then if b then x := 1; else x := 2;"),
        "IF A THEN\n    IF B THEN\n        X := 1;\n    ELSE\n        X := 2;\n    END_IF;\nEND_IF;\n"
    );
    // A block after `else` holding one if is not merged (it is written as a block).
    assert_eq!(
        body("if a then x := 1; else begin if b then x := 2; y := 3; end"),
        "IF A THEN\n    X := 1;\nELSE\n    IF B THEN\n        X := 2;\n    END_IF;\n    Y := 3;\nEND_IF;\n"
    );
}

#[test]
fn loops() {
    assert_eq!(
        body("while x <= y do\nbegin\n    x := x + 1;\n    y := y + 2;\nend"),
        "WHILE (X <= Y) DO\n    X := (X + 1);\n    Y := (Y + 2);\nEND_WHILE;\n"
    );
    assert_eq!(
        body("while x <= y do x := x + 1;"),
        "WHILE (X <= Y) DO\n    X := (X + 1);\nEND_WHILE;\n"
    );
    assert_eq!(
        body("repeat\n    a := b + c;\n    d := d + 1;\nuntil d = 30;"),
        "REPEAT\n    A := (B + C);\n    D := (D + 1);\nUNTIL (D = 30)\nEND_REPEAT;\n"
    );
    assert_eq!(
        body("for i := 1 to n do s := s + i;"),
        "FOR I := 1 TO N DO\n    S := (S + I);\nEND_FOR;\n"
    );
    assert_eq!(
        body("for i := 10 downto 1 do begin s := s + i; t := i; end"),
        "FOR I := 10 TO 1 BY -1 DO\n    S := (S + I);\n    T := I;\nEND_FOR;\n"
    );
}

#[test]
fn blocks_are_flattened() {
    assert_eq!(
        body("begin a := 1; begin b := 2; end c := 3; end; d := 4; ;"),
        "A := 1;\nB := 2;\nC := 3;\nD := 4;\n;\n"
    );
}

#[test]
fn standard_operations() {
    assert_eq!(expr("INC(a) + dec(b)"), "(__STL_INC(A) + __STL_DEC(B))");
    assert_eq!(expr("swap(n)"), "__STL_SWAP(N)");
    assert_eq!(
        expr("set(n, 3) + clr(n, 0)"),
        "(__STL_SET(N, 3) + __STL_CLR(N, 0))"
    );
    assert_eq!(expr("abs(a)"), "ABS(A)");
    // One argument: one bit, as the PLC-UD quadruples; two: as in ST.
    assert_eq!(
        expr("shl(a) + shr(a) + rol(a) + ror(a)"),
        "(((SHL(A, 1) + SHR(A, 1)) + ROL(A, 1)) + ROR(A, 1))"
    );
    assert_eq!(expr("shl(a, 3)"), "SHL(A, 3)");
    // As statements they update their variable.
    assert_eq!(
        body("inc(a); DEC(b); swap(c); set(d, 1); clr(e, 2); inc(3); abs(f);"),
        "A := __STL_INC(A);\nB := __STL_DEC(B);\nC := __STL_SWAP(C);\nD := __STL_SET(D, 1);\nE := __STL_CLR(E, 2);\n__STL_INC(3);\nABS(F);\n"
    );
    // Names that are not called stay names.
    assert_eq!(expr("set + inc"), "(SET + INC)");
}

// ---------------------------------------------------------------- expressions

#[test]
fn precedence() {
    let cases = [
        // Arithmetic: * / % over + -, left-associative.
        ("a + b * c", "(A + (B * C))"),
        ("a - b - c", "((A - B) - C)"),
        ("a / b * c % d", "(((A / B) * C) MOD D)"),
        ("(a + b) * c", "(((A + B)) * C)"),
        // A leading sign covers the first term (EXPR = [+|-] TERM {(+|-) TERM}).
        ("-a * b + c", "((-(A * B)) + C)"),
        ("-a + b", "((-A) + B)"),
        ("+a * b", "(+(A * B))"),
        // After an operator a sign covers one factor.
        ("a * -b * c", "((A * (-B)) * C)"),
        ("a + -b * c", "(A + ((-B) * C))"),
        ("a > -b * c", "(A > (-(B * C)))"),
        ("- - a", "(-(-A))"),
        // Comparisons below arithmetic, above the logical operators.
        ("a + 1 > b * 2", "((A + 1) > (B * 2))"),
        ("a > 1 and b < 2", "((A > 1) AND (B < 2))"),
        ("a = b or c <> d", "((A = B) OR (C <> D))"),
        ("a <= b xor c >= d", "((A <= B) XOR (C >= D))"),
        // and > xor > or, as in ST.
        ("a or b and c", "(A OR (B AND C))"),
        ("a and b or c", "((A AND B) OR C)"),
        ("a or b xor c and d", "(A OR (B XOR (C AND D)))"),
        ("a xor b or c", "((A XOR B) OR C)"),
        // `not` at the start of a condition covers a comparison, not an `and`.
        ("not a = b", "(NOT (A = B))"),
        ("not a and b", "((NOT A) AND B)"),
        ("not x > 5 or y", "((NOT (X > 5)) OR Y)"),
        ("a and not b = c", "(A AND (NOT (B = C)))"),
        ("not not a", "(NOT (NOT A))"),
        // After another operator `not` covers one factor.
        ("x = not y", "(X = (NOT Y))"),
        ("x = not y and z", "((X = (NOT Y)) AND Z)"),
        ("a + not b * c", "(A + ((NOT B) * C))"),
        // Parentheses hold whole conditions.
        ("(a or b) and c", "(((A OR B)) AND C)"),
        ("f(a > 1, b or c)", "F((A > 1), (B OR C))"),
        ("(a < b) = c", "(((A < B)) = C)"),
    ];
    for (src, want) in cases {
        assert_eq!(expr(src), want, "{src}");
    }
}

#[test]
fn literals() {
    assert_eq!(expr("16#FF + 2#1010 + 8#17"), "((255 + 10) + 15)");
    assert_eq!(expr("#30 + 1_000"), "(30 + 1000)");
    assert_eq!(expr("TRUE or false"), "(TRUE OR FALSE)");
    assert_eq!(expr("1.5 + 2.0e3"), "(1.5 + 2.0e3)");
    assert_eq!(expr("16#7FFF_FFFF"), "2147483647");
}

#[test]
fn spans() {
    let src = "program p;\nbegin\n    x := a + f(b);\n    if c then y := 1;\n    repeat z := 2; until z = 2;\nend.";
    let (u, _) = ok(src);
    let Some(Item::Pou(p)) = u.items.last() else {
        panic!()
    };
    let text = |s: plcc_ir::diag::Span| &src[s.start as usize..s.end as usize];
    let s = &p.body.stmts;
    // Statements without their `;`.
    assert_eq!(text(s[0].span), "x := a + f(b)");
    assert_eq!(text(s[1].span), "if c then y := 1");
    assert_eq!(text(s[2].span), "repeat z := 2; until z = 2");
    let StmtKind::Assign { target, value } = &s[0].kind else {
        panic!()
    };
    assert_eq!(text(target.span), "x");
    assert_eq!(text(value.span), "a + f(b)");
    let ExprKind::Binary(_, _, call) = &value.kind else {
        panic!()
    };
    assert_eq!(text(call.span), "f(b)");
    assert_eq!(text(p.name.span), "p");
    assert_eq!(
        text(p.body.span),
        "begin\n    x := a + f(b);\n    if c then y := 1;\n    repeat z := 2; until z = 2;\nend"
    );
    // Unary operators start at the operator.
    let src2 = "program p; begin x := -a * b; end.";
    let (u, _) = ok(src2);
    let Some(Item::Pou(p)) = u.items.last() else {
        panic!()
    };
    let StmtKind::Assign { value, .. } = &p.body.stmts[0].kind else {
        panic!()
    };
    assert_eq!(
        &src2[value.span.start as usize..value.span.end as usize],
        "-a * b"
    );
}

// ---------------------------------------------------------------- diagnostics

#[test]
fn lexical_errors() {
    errs("program p; begin x := a & b; end.", &["E0720"]);
    errs("program p; begin x := 'txt'; end.", &["E0720", "E0720"]);
    errs(
        "program p; begin x := a ? b; y := ? 1; end.",
        &["E0720", "E0720"],
    );
    // A run of bad characters is one error.
    errs(
        "program p; begin x := a ?? b; y := ¿¡; end.",
        &["E0720", "E0720"],
    );
    errs("program p; (* open (* nested *) begin end.", &["E0721"]);
    errs(
        "program p; begin x := 16#FG + 3#1 + 12abc + #x; end.",
        &["E0722", "E0722", "E0722", "E0720"],
    );
    errs(
        "program p; begin x := 999999999999999999999999999999999999999999; end.",
        &["E0722"],
    );
    errs("program p; begin x := 2#102; end.", &["E0722"]);
    // The rest of the line after `pragma` is free text.
    errs("pragma range ? & 'x'\nprogram p; begin end.", &[]);
}

#[test]
fn missing_semicolon() {
    errs("program p; begin x := 1\ny := 2; end.", &["E0724"]);
    errs("program p; begin x := 1 end.", &["E0724"]);
    errs(
        "program p; begin x := 1; y := 2\nz := 3\nw := 4; end.",
        &["E0724", "E0724"],
    );
    errs(
        "program p; begin repeat x := 1; until x = 1 end.",
        &["E0724"],
    );
    errs("program p; begin p(1)\nq(2); end.", &["E0724"]);
    errs("program p; var x : INT end_var; begin end.", &["E0724"]);
    errs("program p; var x : INT; end_var begin end.", &["E0724"]);
    errs("program p\nbegin end.", &["E0724"]);
    errs("uses a, b\nprogram p; begin end.", &["E0724"]);
    // The `;` before `else` may be left out; after a block `end` it is optional.
    errs("program p; begin if a then x := 1 else x := 2; end.", &[]);
    errs("program p; begin begin x := 1; end y := 2; end.", &[]);
    // The missing `;` is placed after the statement, the next line shown.
    let (_, d, _) = parse_str("program p; begin\nx := 1\ny := 2; end.");
    assert_eq!(d.len(), 1);
    let sp = d[0].span.unwrap();
    assert_eq!((sp.start, sp.end), (23, 23));
}

#[test]
fn assignment_with_eq() {
    errs("program p; begin x = 5; end.", &["E0725"]);
    errs(
        "program p; begin x = 5; y = 6; z := 1; end.",
        &["E0725", "E0725"],
    );
    errs("program p; begin x : = 5; end.", &["E0725"]);
    errs(
        "program p; var x : INT = 5; end_var; begin end.",
        &["E0725"],
    );
    let (_, d, _) = parse_str("program p; begin x = 5; end.");
    assert!(
        d[0].message.contains("use `:=` to assign"),
        "{}",
        d[0].message
    );
}

#[test]
fn declaration_order() {
    // Globals: var blocks, then constants, then subprograms.
    errs(
        "program p;\nconstant k : INT := 1;\nvar x : INT; end_var;\nbegin end.",
        &["E0726"],
    );
    errs(
        "program p;\nfunction f INT; begin f := 1; end;\nvar x : INT; end_var;\nconstant k : INT := 1;\nbegin end.",
        &["E0726", "E0726"],
    );
    errs("program p;\nuses a;\nbegin end.", &["E0726"]);
    errs("program p;\npragma x\nbegin end.", &["E0726"]);
    // Locals: var blocks, then constants, then statements.
    errs(
        "program p;\nbegin\nconstant k : INT := 1;\nvar x : INT; end_var;\nend.",
        &["E0726"],
    );
    errs(
        "program p;\nbegin\nx := 1;\nvar y : INT; end_var;\ny := 2;\nend.",
        &["E0726"],
    );
    errs(
        "program p;\nprocedure q;\nbegin\nx := 1;\nconstant k : INT := 1;\nend;\nbegin end.",
        &["E0726"],
    );
    errs("program p;\nbegin\nx := 1;\npragma z\nend.", &["E0726"]);
    // A stray `;` is not a statement.
    errs(
        "program p;\nbegin\nvar x : INT; end_var;;\nconstant k : INT := 1;\nend.",
        &[],
    );
    let (_, d, _) =
        parse_str("program p;\nconstant k : INT := 1;\nvar x : INT; end_var;\nbegin end.");
    assert!(
        d[0].message.contains("after a global constant"),
        "{}",
        d[0].message
    );
    assert!(
        d[0].notes.iter().any(|n| n.contains("in this order")),
        "{:?}",
        d[0].notes
    );
    // The right order, in full, is fine.
    errs(
        "pragma a\nuses b;\nprogram p;\nvar x : INT; end_var;\nvar y : INT; end_var;\nconstant k : INT := 1;\nconstant l : INT := 2;\nprocedure q; begin end;\nfunction f INT; begin f := 1; end;\nbegin var z : INT; end_var; constant m : INT := 3; z := 1; end.",
        &[],
    );
}

#[test]
fn missing_end_dot() {
    errs("program p; begin x := 1; end", &["E0727"]);
    errs("program p; begin x := 1; end;", &["E0727"]);
    errs("program p; begin x := 1;", &["E0727"]);
    errs("program p; var x : INT; end_var;", &["E0727"]);
    errs("program p;", &["E0727"]);
    let src = "program p; begin x := 1;\nfunction f INT; begin f := 1; end;";
    errs(src, &["E0727"]);
    let (_, d, _) = parse_str(src);
    assert!(d[0]
        .notes
        .iter()
        .any(|n| n.contains("before the main body")));
}

#[test]
fn unclosed_blocks() {
    errs("program p; begin if a then begin x := 1; end.", &["E0728"]);
    errs("program p; begin repeat x := 1; end.", &["E0728"]);
    errs("program p; var x : INT; begin end.", &["E0728"]);
    errs("program p; begin var x : INT;\nx := 1; end.", &["E0728"]);
    errs(
        "program p;\nfunction f INT;\nbegin\n    f := 1;\nfunction g INT; begin g := 2; end;\nbegin end.",
        &["E0728"],
    );
}

#[test]
fn chained_comparison() {
    errs(
        "program p; begin if 0 < x < 10 then x := 1; end.",
        &["E0730"],
    );
    errs("program p; begin b := a = b = c; end.", &["E0730"]);
    errs("program p; begin b := (a = b) = c; end.", &[]);
}

#[test]
fn constant_without_value() {
    errs("program p; constant k : INT; begin end.", &["E0731"]);
    errs(
        "program p; begin constant k : INT; constant l : INT; end.",
        &["E0731", "E0731"],
    );
    errs(
        "program p; constant k : INT\nbegin end.",
        &["E0731", "E0724"],
    );
}

#[test]
fn result_types() {
    errs(
        "program p; function f(a : INT); begin f := a; end; begin end.",
        &["E0732"],
    );
    errs(
        "program p; function f(a : INT) begin f := a; end; begin end.",
        &["E0732"],
    );
    errs(
        "program p; procedure q(a : INT) INT; begin end; begin end.",
        &["E0732"],
    );
}

#[test]
fn text_after_end() {
    errs("program p; begin end. x := 1;", &["E0733"]);
    errs(
        "program p; begin end.\nfunction f INT; begin f := 1; end;",
        &["E0733"],
    );
    errs("program p; begin end. (* only comments *)", &[]);
}

#[test]
fn unexpected_tokens() {
    errs("program p; begin if a > 1 x := 0; end.", &["E0723"]);
    errs(
        "program p; begin while a do x := 0; while a x := 1; end.",
        &["E0723"],
    );
    errs("program p; begin x := (1 + 2; end.", &["E0723"]);
    errs("program p; begin x := ; end.", &["E0723"]);
    errs("program p; begin x := 1; else y := 2; end.", &["E0723"]);
    errs("program p; begin x y; end.", &["E0723"]);
    errs("program p; begin 5 := x; end.", &["E0723"]);
    errs("program p; begin for := 1 to 3 do x := 1; end.", &["E0723"]);
    errs("program p; begin for i := 1 do x := 1; end.", &["E0723"]);
    errs("program p; begin f(a := 1); end.", &["E0723"]);
    errs(
        "program p; var begin : INT; end_var; begin end.",
        &["E0723"],
    );
    errs("program p; var x : 5; end_var; begin end.", &["E0723"]);
    errs("begin end.", &["E0723"]);
    errs("program p; program q; begin end.", &["E0723"]);
    errs(
        "program p; function f(a INT) INT; begin end; begin end.",
        &["E0723"],
    );
    errs(
        "program p; function f INT; begin f := 1; end. begin end.",
        &["E0723"],
    );
    // Statements of the main body without `begin`.
    errs("program p; x := 1; y := 2; end.", &["E0723"]);
    let (_, d, _) = parse_str("program p; var end : INT; end_var; begin end.");
    assert!(
        d[0].notes.iter().any(|n| n.contains("reserved word")),
        "{:?}",
        d[0]
    );
}

#[test]
fn every_stl_code_is_tested_and_documented() {
    // Each code of the STL section has an explanation with an example, and one of
    // the tests above produces it.
    let all: Vec<_> = crate::codes::ALL
        .iter()
        .filter(|c| ("E0720".."E0740").contains(&c.code))
        .collect();
    assert_eq!(all.len(), 15);
    let samples = [
        "program p; begin x := a & b; end.",
        "program p; (* open",
        "program p; begin x := 16#FG; end.",
        "program p; begin if a x := 1; end.",
        "program p; begin x := 1 end.",
        "program p; begin x = 1; end.",
        "program p; constant k : INT := 1; var x : INT; end_var; begin end.",
        "program p; begin end",
        "program p; begin repeat x := 1; end.",
        &format!(
            "program p; begin x := {}1{}; end.",
            "(".repeat(300),
            ")".repeat(300)
        ),
        "program p; begin b := 1 < 2 < 3; end.",
        "program p; constant k : INT; begin end.",
        "program p; function f; begin end; begin end.",
        "program p; begin end. x",
        "program p; var x : DINT; end_var; begin end.",
    ];
    for (c, src) in all.iter().zip(samples) {
        assert!(c.explanation.contains("    "), "{} has no example", c.code);
        assert_eq!(codes_of(src), vec![c.code], "{src}");
    }
}

// ---------------------------------------------------------------- recovery

#[test]
fn several_errors_no_cascade() {
    let src = "\
program bad;
constant K : INT := 5;
var x : INT; end_var;
function f(a : INT) INT;
begin
  f := a
end;
begin
  x = 5;
  y := (x + 1;
  if x > 1 x := 0;
  while x < 3 do x := x + 1
  z := 4;
  if 0 < x < 10 then x := 1;
  x := 1 + * 2;
  ok := 1;
end.
";
    let (_, d, _) = parse_str(src);
    let got: Vec<(&str, u32)> = d
        .iter()
        .map(|d| {
            let f = SourceFile::new("t", src);
            (d.code, f.line_col(d.span.unwrap().start).0)
        })
        .collect();
    assert_eq!(
        got,
        vec![
            ("E0726", 3),
            ("E0724", 6),
            ("E0725", 9),
            ("E0723", 10),
            ("E0723", 11),
            ("E0724", 12),
            ("E0730", 14),
            ("E0723", 15),
        ],
        "{}",
        show(&d, src)
    );
}

#[test]
fn recovery_keeps_the_good_statements() {
    let (u, d, i) =
        parse_str("program p; begin a := 1; b := ) ; c := 3; if x then d := * ; e := 5; end.");
    assert_eq!(d.len(), 2, "{}", show(&d, ""));
    let Some(Item::Pou(p)) = u.items.last() else {
        panic!()
    };
    let out = Printer::new(&i).stmts(&p.body.stmts);
    assert_eq!(out, "A := 1;\nC := 3;\nIF X THEN\nEND_IF;\nE := 5;\n");
}

/// Runs `f` on a thread with a small stack (what a test thread or a small embedder
/// has), so that the depth limits are known to be low enough.
fn on_small_stack(f: impl FnOnce() + Send + 'static) {
    std::thread::Builder::new()
        .stack_size(2 << 20)
        .spawn(f)
        .unwrap()
        .join()
        .unwrap();
}

#[test]
fn deep_nesting_gives_one_error() {
    on_small_stack(|| {
        let n = 10_000;
        let cases = [
            format!(
                "program p; begin x := {}1{}; end.",
                "(".repeat(n),
                ")".repeat(n)
            ),
            format!("program p; begin x := {}1{}; end.", "(".repeat(n), ""),
            format!("program p; begin x := {}a; end.", "not ".repeat(n)),
            format!("program p; begin x := {}a; end.", "- ".repeat(n)),
            format!("program p; begin x := a{}; end.", " + a".repeat(n)),
            format!("program p; begin x := a{}; end.", " or a".repeat(n)),
            format!("program p; begin x := {}; end.", "f(".repeat(n)),
            format!(
                "program p; begin {} x := 1; {} end.",
                "begin ".repeat(n),
                "end ".repeat(n)
            ),
            format!("program p; begin {} x := 1; end.", "if a then ".repeat(n)),
            format!("program p; begin {} x := 1; end.", "while a do ".repeat(n)),
            format!("program p; begin {} x := 1; end.", "repeat ".repeat(n)),
            format!(
                "program p; begin {} x := 1; end.",
                "for i := 1 to 2 do ".repeat(n)
            ),
        ];
        for src in cases {
            let c = codes_of(&src);
            assert_eq!(c, vec!["E0729"], "{}...", &src[..60]);
        }
        // Just under the limits is fine.
        let src = format!(
            "program p; begin x := {}1{}; end.",
            "(".repeat(150),
            ")".repeat(150)
        );
        assert_eq!(codes_of(&src), Vec::<&str>::new());
        let src = format!("program p; begin x := a{}; end.", " + a".repeat(900));
        assert_eq!(codes_of(&src), Vec::<&str>::new());
    });
}

/// The example programs of `examples/stl`.
fn example_sources() -> Vec<(String, String)> {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/stl");
    let mut out = Vec::new();
    for e in std::fs::read_dir(&dir).unwrap() {
        let p = e.unwrap().path();
        if p.extension().is_some_and(|e| e == "stl") {
            out.push((
                p.display().to_string(),
                std::fs::read_to_string(&p).unwrap(),
            ));
        }
    }
    out.sort();
    assert!(out.len() >= 4, "examples/stl has {} programs", out.len());
    out
}

#[test]
fn examples_parse_cleanly() {
    for (name, text) in example_sources() {
        let (_, d, _) = parse_str(&text);
        assert!(d.is_empty(), "{name}:\n{}", show(&d, &text));
    }
}

#[test]
fn every_truncation_terminates_with_an_error() {
    // Every prefix of every example (cut at any character boundary) parses without
    // panicking; a cut inside the program reports at least one error, and no cut
    // reports more errors than a handful (no cascades).
    on_small_stack(|| {
        for (name, text) in example_sources() {
            let end = text.to_ascii_lowercase().rfind("end.").unwrap();
            for cut in (0..=text.len()).filter(|&c| text.is_char_boundary(c)) {
                let prefix = &text[..cut];
                let (_, d, _) = parse_str(prefix);
                if cut <= end {
                    assert!(!d.is_empty(), "{name} cut at {cut}: no error");
                }
                assert!(d.len() <= 3, "{name} cut at {cut}:\n{}", show(&d, prefix));
            }
        }
    });
}

#[test]
fn garbage_never_panics() {
    on_small_stack(|| {
        // A fixed-seed generator: bytes, STL tokens and fragments in random order.
        let mut rng = plcc_ir::rng::Rng(0x2545_f491_4f6c_dd1d);
        let mut next = move || rng.next_u64();
        let pieces = [
            "program",
            "p",
            ";",
            "begin",
            "end",
            ".",
            "var",
            "end_var",
            "constant",
            ":",
            ":=",
            "=",
            "function",
            "procedure",
            "(",
            ")",
            ",",
            "if",
            "then",
            "else",
            "while",
            "do",
            "repeat",
            "until",
            "for",
            "to",
            "downto",
            "and",
            "or",
            "not",
            "xor",
            "+",
            "-",
            "*",
            "/",
            "%",
            "<",
            "<=",
            "<>",
            "1",
            "16#F",
            "#3",
            "INT",
            "inc",
            "shl",
            "(*",
            "*)",
            "pragma",
            "uses",
            "\n",
            "x",
            "é",
            "'",
            "\0",
        ];
        for round in 0..3000 {
            let len = (next() % 60) as usize;
            let mut s = String::new();
            if round % 2 == 0 {
                s.push_str("program p; begin ");
            }
            for _ in 0..len {
                s.push_str(pieces[(next() % pieces.len() as u64) as usize]);
                s.push(' ');
            }
            let (_, d, _) = parse_str(&s);
            // One error per token at most.
            assert!(d.len() <= len + 2, "{s}\n{}", show(&d, &s));
        }
        // Long inputs stay linear: a megabyte of one bad character, of `(`, of `;`.
        for unit in ["?", "é", "(", ";", "x", "begin "] {
            let s = format!("program p; begin {} end.", unit.repeat(200_000));
            let t = std::time::Instant::now();
            let _ = parse_str(&s);
            assert!(t.elapsed().as_secs() < 5, "{unit:?} took {:?}", t.elapsed());
        }
        // Raw bytes (lossily decoded, as the driver does).
        for _ in 0..500 {
            let bytes: Vec<u8> = (0..(next() % 200)).map(|_| next() as u8).collect();
            let s = String::from_utf8_lossy(&bytes);
            let _ = parse_str(&s);
        }
    });
}
