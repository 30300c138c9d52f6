//! Tests of the IL front end: the translation of every operator and modifier
//! (rendered as ST-like text and compared, often with the tree ST gives for the same
//! computation), the compiler temporaries, labels and jumps, deferred operations,
//! calls, FUNCTION results, diagnostics and recovery, limits and garbage input.

use super::parse;
use crate::ast::*;
use crate::intern::Interner;
use crate::print::{Printer, Style};
use crate::source::SourceFile;
use plcc_ir::diag::{Diagnostic, FileId, Severity};
use std::fmt::Write;

// ---------------------------------------------------------------- helpers

/// Declarations shared by the test programs.
const DECLS: &str = "a, b, c, d, x, y, z : INT; p, q, r, u, v : BOOL; w : WORD; \
                     tm : TIME; re : REAL; t, t1 : TON; sr1 : SR; cnt : CTU; \
                     arr : ARRAY[1..3] OF INT; st1 : MyStruct;";

fn parse_with(src: &str, lang_il: bool) -> (SourceUnit, Vec<Diagnostic>, Interner) {
    let mut i = Interner::new();
    let mut d = Vec::new();
    let u = if lang_il {
        parse(FileId(0), src, &mut i, &mut d)
    } else {
        crate::st::parse(FileId(0), src, &mut i, &mut d)
    };
    (u, d, i)
}

fn program(body: &str) -> String {
    format!("PROGRAM p\nVAR {DECLS} END_VAR\n{body}\nEND_PROGRAM\n")
}

fn show(d: &[Diagnostic], src: &str) -> String {
    let f = SourceFile::new("t.il", src);
    let mut s = String::new();
    for d in d {
        let (l, c) = d.span.map_or((0, 0), |sp| f.line_col(sp.start));
        let _ = writeln!(s, "{l}:{c}: {d} [{}]", d.label);
    }
    s
}

fn first_pou(u: &SourceUnit) -> &Pou {
    u.items
        .iter()
        .find_map(|it| match it {
            Item::Pou(p) => Some(p),
            _ => None,
        })
        .expect("a POU")
}

/// The rendered body of the PROGRAM around `body` (IL), which must give no
/// diagnostic at all.
fn il(body: &str) -> String {
    let src = program(body);
    let (u, d, i) = parse_with(&src, true);
    assert!(d.is_empty(), "diagnostics for\n{src}\n{}", show(&d, &src));
    render(&first_pou(&u).body.stmts, &i)
}

/// The rendered body of the PROGRAM around `body` (ST).
fn st(body: &str) -> String {
    let src = program(body);
    let (u, d, i) = parse_with(&src, false);
    assert!(d.is_empty(), "diagnostics for\n{src}\n{}", show(&d, &src));
    render(&first_pou(&u).body.stmts, &i)
}

/// Rendered body and diagnostic codes of the first POU of a whole IL file.
fn il_file(src: &str) -> (String, Vec<&'static str>) {
    let (u, d, i) = parse_with(src, true);
    let body = u
        .items
        .iter()
        .find_map(|it| match it {
            Item::Pou(p) => Some(render(&p.body.stmts, &i)),
            _ => None,
        })
        .unwrap_or_default();
    (body, d.iter().map(|d| d.code).collect())
}

/// The codes of the diagnostics of the PROGRAM around `body`.
fn codes(body: &str) -> Vec<&'static str> {
    let src = program(body);
    parse_with(&src, true).1.iter().map(|d| d.code).collect()
}

/// Statements as the printer's tree style writes them, one per line.
fn render(stmts: &[Stmt], i: &Interner) -> String {
    Printer::new(i).with_style(Style::Tree).stmts(stmts)
}

/// The source text of a span.
fn text(src: &str, sp: plcc_ir::diag::Span) -> &str {
    &src[sp.start as usize..sp.end as usize]
}

// ---------------------------------------------------------------- operators

#[test]
fn straight_line_gives_the_st_tree() {
    assert_eq!(il("LD a\nMUL 4\nADD b\nST c"), st("c := a * 4 + b;"));
    assert_eq!(il("LD a\nMUL 4\nADD b\nST c"), "C := ((A * 4) + B);");
    assert_eq!(il("LD p\nAND q\nOR r\nST u"), st("u := p AND q OR r;"));
    assert_eq!(il("LD x\nGT 25\nST p"), st("p := x > 25;"));
}

#[test]
fn every_operator() {
    let cases: &[(&str, &str)] = &[
        ("LD p\nAND q\nST u", "U := (P AND Q);"),
        ("LD p\n& q\nST u", "U := (P AND Q);"),
        ("LD p\nOR q\nST u", "U := (P OR Q);"),
        ("LD p\nXOR q\nST u", "U := (P XOR Q);"),
        ("LD p\nANDN q\nST u", "U := (P AND (NOT Q));"),
        ("LD p\n&N q\nST u", "U := (P AND (NOT Q));"),
        ("LD p\nORN q\nST u", "U := (P OR (NOT Q));"),
        ("LD p\nXORN q\nST u", "U := (P XOR (NOT Q));"),
        ("LD a\nADD b\nST x", "X := (A + B);"),
        ("LD a\nSUB b\nST x", "X := (A - B);"),
        ("LD a\nMUL b\nST x", "X := (A * B);"),
        ("LD a\nDIV b\nST x", "X := (A / B);"),
        ("LD a\nMOD b\nST x", "X := (A MOD B);"),
        ("LD a\nGT b\nST p", "P := (A > B);"),
        ("LD a\nGE b\nST p", "P := (A >= B);"),
        ("LD a\nEQ b\nST p", "P := (A = B);"),
        ("LD a\nNE b\nST p", "P := (A <> B);"),
        ("LD a\nLE b\nST p", "P := (A <= B);"),
        ("LD a\nLT b\nST p", "P := (A < B);"),
        ("LD p\nNOT\nST u", "U := (NOT P);"),
        ("LDN p\nST u", "U := (NOT P);"),
        ("LD p\nSTN u", "U := (NOT P);"),
        ("LD p\nS u", "IF P THEN U := TRUE; END_IF;"),
        ("LD p\nR u", "IF P THEN U := FALSE; END_IF;"),
        // Lower case and odd spacing.
        ("ld a\n  add   b\n st x", "X := (A + B);"),
    ];
    for (body, want) in cases {
        assert_eq!(&il(body), want, "for\n{body}");
    }
}

#[test]
fn operands_of_every_form() {
    let cases: &[(&str, &str)] = &[
        ("LD -5\nST x", "X := (-5);"),
        ("LD +5\nST x", "X := (+5);"),
        ("LD INT#-7\nST x", "INT#-7"),
        ("LD 16#FF\nST w", "W := 255;"),
        ("LD T#1s\nST tm", "TM := T#1s;"),
        ("LD 1.5\nST re", "RE := 1.5;"),
        ("LD arr[2]\nST x", "X := ARR[2];"),
        ("LD arr[a]\nST x", "X := ARR[A];"),
        ("LD w.3\nST p", "P := W.3;"),
        ("LD st1.f\nST x", "X := ST1.F;"),
        ("LD %IX0.1\nST p", "P := %IX0.1;"),
        ("LD t.Q\nST p", "P := T.Q;"),
        ("LD TRUE\nST p", "P := TRUE;"),
    ];
    for (body, want) in cases {
        let got = il(body);
        assert!(got.contains(want), "for\n{body}\ngot {got}, want {want}");
    }
    // The operator words are names elsewhere.
    assert_eq!(il("LD in\nST x"), "X := IN;");
    assert_eq!(il("LD p\nST sr1.R"), "SR1.R := P;");
}

#[test]
fn the_cr_keeps_its_value_after_st() {
    // Plain operands are read again, not copied.
    assert_eq!(il("LD a\nST x\nST y"), "X := A;\nY := A;");
    assert_eq!(
        il("LD p\nS u\nR v"),
        "IF P THEN U := TRUE; END_IF;\nIF P THEN V := FALSE; END_IF;"
    );
    // A computed CR used again goes into a temporary.
    assert_eq!(
        il("LD a\nADD b\nST x\nST y"),
        "__CR1 := (A + B);\nX := __CR1;\nY := __CR1;"
    );
    assert_eq!(
        il("LD a\nADD b\nST x\nMUL 2\nST y"),
        "__CR1 := (A + B);\nX := __CR1;\nY := (__CR1 * 2);"
    );
    // ...but not if nothing reads it afterwards (the next LD replaces it; CAL keeps
    // it without reading it).
    assert_eq!(
        il("LD a\nADD b\nST x\nCAL t\nLD c\nST y"),
        "X := (A + B);\nT();\nY := C;"
    );
    assert_eq!(
        il("LD p\nAND q\nS u\nR v"),
        "__CR1 := (P AND Q);\nIF __CR1 THEN U := TRUE; END_IF;\nIF __CR1 THEN V := FALSE; END_IF;"
    );
    // A store to what the CR reads: the old value is kept.
    assert_eq!(
        il("LD p\nSTN p\nST u"),
        "__CR1 := P;\nP := (NOT __CR1);\nU := __CR1;"
    );
    // A call of an instance may change anything the CR reads.
    assert_eq!(
        il("LD t.Q\nCAL t\nST p"),
        "__CR1 := T.Q;\nT();\nP := __CR1;"
    );
    // Literals never need a temporary, nor constant expressions (a temporary would
    // fix their type).
    assert_eq!(il("LD 5\nCAL t\nST x\nST y"), "T();\nX := 5;\nY := 5;");
    assert_eq!(
        il("LD 5\nADD 3\nST x\nST y"),
        "X := (5 + 3);\nY := (5 + 3);"
    );
}

#[test]
fn temporaries_are_numbered_per_file() {
    let src = format!(
        "{}{}",
        program("LD a\nADD 1\nST x\nST y"),
        "FUNCTION_BLOCK fb VAR a, x, y : INT; END_VAR\nLD a\nADD 2\nST x\nST y\nEND_FUNCTION_BLOCK\n"
    );
    let (u, d, i) = parse_with(&src, true);
    assert!(d.is_empty(), "{}", show(&d, &src));
    let bodies: Vec<String> = u
        .items
        .iter()
        .filter_map(|it| match it {
            Item::Pou(p) => Some(render(&p.body.stmts, &i)),
            _ => None,
        })
        .collect();
    assert!(bodies[0].starts_with("__CR1 :="), "{}", bodies[0]);
    assert!(bodies[1].starts_with("__CR2 :="), "{}", bodies[1]);
}

// ---------------------------------------------------------------- labels, jumps

#[test]
fn labels_and_jumps() {
    assert_eq!(
        il("LD p\nJMPC l1\nLD 1\nST x\nl1:\nLD 2\nST y"),
        "IF P THEN JMP L1; END_IF;\nX := 1;\nL1:\nY := 2;"
    );
    assert_eq!(
        il("LD p\nJMPCN l1\nJMP l2\nl1: LD 1\nST x\nl2: LD 2\nST y"),
        "IF (NOT P) THEN JMP L1; END_IF;\nJMP L2;\nL1:\nX := 1;\nL2:\nY := 2;"
    );
    // The CR is unchanged by a conditional jump: a computed one is kept in a
    // temporary when read after it.
    assert_eq!(
        il("LD a\nGT 5\nJMPC l\nST p\nl: LD 0\nST x"),
        "__CR1 := (A > 5);\nIF __CR1 THEN JMP L; END_IF;\nP := __CR1;\nL:\nX := 0;"
    );
    // Labels are emitted as written; unknown or duplicate ones are lowering's concern.
    assert_eq!(il("JMP nowhere"), "JMP NOWHERE;");
    assert_eq!(il("l: l:\nLD 1\nST x"), "L:\nL:\nX := 1;");
}

#[test]
fn the_cr_is_undefined_after_a_label() {
    let (body, codes) = il_file(&program("LD 1\nl:\nADD 1\nST x"));
    assert_eq!(body, "L:\nX := (0 + 1);");
    assert_eq!(codes, ["W0701"]);
}

// ---------------------------------------------------------------- `(` nesting

#[test]
fn deferred_operations() {
    assert_eq!(
        il("LD p\nAND( q\nOR r\n)\nST u"),
        st("u := p AND (q OR r);")
    );
    assert_eq!(il("LD a\nMUL( b\nADD c\n)\nST x"), st("x := a * (b + c);"));
    // The operand on the following lines.
    assert_eq!(
        il("LD p\nAND(\nLD q\nOR r\n)\nST u"),
        st("u := p AND (q OR r);")
    );
    // Nested, with N.
    assert_eq!(
        il("LD p\nANDN( q\nOR( r\nAND v\n)\n)\nST u"),
        "U := (P AND (NOT ((Q OR ((R AND V))))));"
    );
    // A plain operand needs no parentheses.
    assert_eq!(il("LD a\nSUB( b\n)\nST x"), st("x := a - b;"));
    // Comparisons and the deferred operand of an IL expression from matiec's tests.
    assert_eq!(il("LD a\nGT( b\nADD 1\n)\nST p"), st("p := a > (b + 1);"));
}

#[test]
fn stores_inside_parentheses_keep_the_left_operand() {
    // IL reads `a` at `ADD(`; the store to `a` inside must not change it.
    assert_eq!(
        il("LD a\nADD( b\nST a\n)\nST c"),
        "__CR1 := A;\nA := B;\nC := (__CR1 + B);"
    );
}

#[test]
fn unbalanced_parentheses() {
    let (_, c) = il_file(&program("LD p\nAND q\n)\nST u"));
    assert_eq!(c, ["E0705"]);
    let (_, c) = il_file(&program("LD p\nAND( q\nOR r\nST u"));
    assert_eq!(c, ["E0706"]);
    // Only the innermost unclosed `(` is reported (with a note about the others).
    let src = program("LD p\nAND( q\nOR( r\nST u");
    let (_, d, _) = parse_with(&src, true);
    assert_eq!(d.len(), 1);
    assert_eq!(text(&src, d[0].span.unwrap()), "OR( r");
    assert!(
        d[0].notes.iter().any(|n| n.contains("the `(` before it")),
        "{:?}",
        d[0].notes
    );
    // A label or a jump inside.
    assert_eq!(codes("LD p\nAND( q\nJMPC l\n)\nl: LD 1\nST x"), ["E0709"]);
    assert_eq!(codes("LD p\nAND( q\nl: LD 1\n)\nST x"), ["E0709"]);
    // `)` with an operand.
    assert_eq!(codes("LD p\nAND( q\n) x\nST u"), ["E0703"]);
}

#[test]
fn deep_nesting_is_one_diagnostic() {
    let mut body = String::from("LD p\n");
    body.push_str(&"AND( q\n".repeat(10_000));
    body.push_str(&")\n".repeat(10_000));
    body.push_str("ST u\n");
    assert_eq!(codes(&body), ["E0707"]);
    // Just below the limit is fine.
    let mut body = String::from("LD p\n");
    body.push_str(&"AND( q\n".repeat(super::translate::MAX_PAREN_DEPTH));
    body.push_str(&")\n".repeat(super::translate::MAX_PAREN_DEPTH));
    body.push_str("ST u\n");
    let out = il(&body);
    assert!(out.lines().all(|l| l.starts_with("__CR")) || out.lines().count() > 1);
    assert!(
        out.lines()
            .last()
            .unwrap()
            .starts_with("U := (P AND ((Q AND"),
        "{out}"
    );
}

#[test]
fn long_chains_are_split() {
    let mut body = String::from("LD a\n");
    body.push_str(&"ADD 1\n".repeat(5_000));
    body.push_str("ST x\n");
    let out = il(&body);
    let lets = out.lines().filter(|l| l.starts_with("__CR")).count();
    assert_eq!(lets, 5_000 / (super::translate::SPILL_HEIGHT as usize));
    let last = out.lines().last().unwrap();
    assert!(
        last.starts_with("X := ((((") && last.contains("(__CR19 + 1)"),
        "{last}"
    );
}

// ---------------------------------------------------------------- calls

#[test]
fn function_block_calls() {
    assert_eq!(
        il("CAL t(IN := p, PT := T#1s, Q => u)"),
        st("t(IN := p, PT := T#1s, Q => u);")
    );
    assert_eq!(
        il("CAL t(\n  IN := p,\n  PT := T#1s\n)\nLD t.Q\nST u"),
        st("t(IN := p, PT := T#1s); u := t.Q;")
    );
    // Calling by loading the inputs first.
    assert_eq!(
        il("LD p\nST t1.IN\nCAL t1\nLD t1.Q\nST u"),
        st("t1.IN := p; t1(); u := t1.Q;")
    );
    assert_eq!(il("LD p\nCALC t"), "IF P THEN T(); END_IF;");
    assert_eq!(
        il("LD p\nCALCN t(IN := q)"),
        "IF (NOT P) THEN T(IN := Q); END_IF;"
    );
    assert_eq!(il("CAL sr1(R := p)"), "SR1(R := P);");
    // The FB input operators.
    assert_eq!(il("LD p\nIN t"), "T(IN := P);");
    assert_eq!(il("LD T#2s\nPT t"), "T(PT := T#2s);");
    assert_eq!(
        il("LD p\nCU cnt\nLD 10\nPV cnt"),
        "CNT(CU := P);\nCNT(PV := 10);"
    );
    assert_eq!(
        il("LD p\nS1 sr1\nLD q\nR sr1"),
        "SR1(S1 := P);\nSR1(R := Q);"
    );
    assert_eq!(il("LD p\nCLK st1.trig"), "ST1.TRIG(CLK := P);");
    // S and R on a BOOL set and reset it.
    assert_eq!(il("LD p\nS u"), "IF P THEN U := TRUE; END_IF;");
}

#[test]
fn function_calls() {
    assert_eq!(il("LD a\nLIMIT 0, 100\nST x"), st("x := LIMIT(a, 0, 100);"));
    assert_eq!(il("LD a\nABS\nST x"), st("x := ABS(a);"));
    assert_eq!(
        il("LIMIT(MN := 0, IN := a, MX := 100)\nST x"),
        st("x := LIMIT(MN := 0, IN := a, MX := 100);")
    );
    // An operator with several operands is the extensible function.
    assert_eq!(il("LD a\nADD 1, 2\nST x"), st("x := ADD(a, 1, 2);"));
    assert_eq!(il("LD p\nAND q, r\nST u"), st("u := AND(p, q, r);"));
    // Chained, then used: the call is evaluated once.
    assert_eq!(
        il("LD a\nABS\nST x\nST y"),
        "__CR1 := ABS(A);\nX := __CR1;\nY := __CR1;"
    );
    // A call left unused still runs.
    assert_eq!(il("LD a\nMYFUN\nLD 1\nST x"), "__CR1 := MYFUN(A);\nX := 1;");
}

// ---------------------------------------------------------------- FUNCTION results

fn function(ret: &str, body: &str) -> String {
    format!("FUNCTION f : {ret}\nVAR_INPUT a, b : INT; p : BOOL; END_VAR\n{body}\nEND_FUNCTION\n")
}

#[test]
fn function_result_from_the_cr() {
    assert_eq!(
        il_file(&function("INT", "LD a\nADD b")),
        ("F := (A + B);".into(), vec![])
    );
    assert_eq!(
        il_file(&function("INT", "LD p\nJMPC l\nLD 1\nRET\nl: LD 2")),
        (
            "IF P THEN JMP L; END_IF;\nF := 1;\nRETURN;\nL:\nF := 2;".into(),
            vec![]
        )
    );
    // RETC: the CR is both the condition and the result of a BOOL function.
    assert_eq!(
        il_file(&function("BOOL", "LD a\nGT b\nRETC\nLD FALSE")),
        (
            "__CR1 := (A > B);\nIF __CR1 THEN F := __CR1; RETURN; END_IF;\nF := FALSE;".into(),
            vec![]
        )
    );
    // A function that stores its result explicitly gets nothing more.
    assert_eq!(
        il_file(&function("INT", "LD a\nST f\nADD 1")),
        ("F := A;".into(), vec![])
    );
    // A BOOL left in the CR of an INT function is no result (W0702).
    assert_eq!(
        il_file(&function("INT", "LD a\nGT b")),
        (String::new(), vec!["W0702"])
    );
    // A CR computed from an undefined one neither.
    assert_eq!(
        il_file(&function("INT", "ADD 10")),
        (String::new(), vec!["W0701"])
    );
    // PROGRAMs and FUNCTION_BLOCKs have no result.
    assert_eq!(il("LD a\nADD b"), "");
}

// ---------------------------------------------------------------- undefined CR

#[test]
fn undefined_cr_uses_a_neutral_value() {
    let cases: &[(&str, &str)] = &[
        ("ADD 10", "X := (0 + 10);"),
        ("AND TRUE", "U := (FALSE AND TRUE);"),
        ("& 10", "X := (0 AND 10);"),
        ("XOR p", "U := (FALSE XOR P);"),
        ("EQ a", "U := (0 = A);"),
        ("ADD re", "X := (0.0 + RE);"),
        ("ADD tm", "X := (T#0s + TM);"),
    ];
    for (line, want) in cases {
        let target = if want.starts_with('U') { "u" } else { "x" };
        let (body, c) = il_file(&program(&format!("{line}\nST {target}")));
        assert_eq!(&body, want, "for {line}");
        assert_eq!(c, ["W0701"], "for {line}");
    }
    // Storing an undefined CR stores nothing.
    assert_eq!(il_file(&program("ST x")), (String::new(), vec!["W0701"]));
    // FB inputs get a value of their type.
    assert_eq!(il_file(&program("PT t")).0, "T(PT := T#0s);");
    assert_eq!(il_file(&program("CU cnt")).0, "CNT(CU := FALSE);");
    // One warning, not one per instruction.
    assert_eq!(il_file(&program("ADD 1\nMUL 2\nST x\nST y")).1, ["W0701"]);
}

#[test]
fn warnings_are_warnings() {
    let src = program("ADD 1\nST x");
    let (_, d, _) = parse_with(&src, true);
    assert_eq!(d.len(), 1);
    assert_eq!(d[0].severity, Severity::Warning);
    assert_eq!(text(&src, d[0].span.unwrap()), "ADD 1");
}

// ---------------------------------------------------------------- spans

#[test]
fn nodes_have_the_span_of_their_instruction() {
    let src = program("LD a\n  ADD b\nMUL( c\nSUB 1\n)\nST x");
    let (u, d, _) = parse_with(&src, true);
    assert!(d.is_empty());
    let s = &first_pou(&u).body.stmts[0];
    assert_eq!(text(&src, s.span), "ST x");
    let StmtKind::Assign { value, .. } = &s.kind else {
        panic!()
    };
    // (a + b) * (c - 1): the MUL comes from `MUL( c`, the ADD from `ADD b`.
    assert_eq!(text(&src, value.span), "MUL( c");
    let ExprKind::Binary(BinaryOp::Mul, l, r) = &value.kind else {
        panic!()
    };
    assert_eq!(text(&src, l.span), "ADD b");
    let ExprKind::Paren(inner) = &r.kind else {
        panic!()
    };
    assert_eq!(text(&src, inner.span), "SUB 1");
    // The body's span covers the instructions.
    assert!(text(&src, first_pou(&u).body.span).starts_with("LD a"));
    assert!(text(&src, first_pou(&u).body.span).ends_with("ST x"));
}

// ---------------------------------------------------------------- IL or ST

#[test]
fn il_and_st_bodies_in_one_file() {
    let src = "FUNCTION_BLOCK fb\nVAR a, b : INT; END_VAR\n  a := b + 1;\nEND_FUNCTION_BLOCK\n\
               FUNCTION_BLOCK fb2\nVAR a, b : INT; END_VAR\n  LD b\n  ADD 1\n  ST a\nEND_FUNCTION_BLOCK\n\
               PROGRAM p\nVAR st, ld : INT; END_VAR\n  st := 5; ld := st;\nEND_PROGRAM\n\
               PROGRAM q\nVAR r : INT; x : BOOL; END_VAR\n  r(S := x);\nEND_PROGRAM\n\
               PROGRAM q2\nVAR x : INT; END_VAR\n  lbl: LD 1\n  ST x\nEND_PROGRAM\n";
    let (u, d, i) = parse_with(src, true);
    assert!(d.is_empty(), "{}", show(&d, src));
    let bodies: Vec<String> = u
        .items
        .iter()
        .filter_map(|it| match it {
            Item::Pou(p) => Some(render(&p.body.stmts, &i)),
            _ => None,
        })
        .collect();
    assert_eq!(
        bodies,
        [
            "A := (B + 1);",
            "A := (B + 1);",
            "ST := 5;\nLD := ST;",
            "R(S := X);",
            "LBL:\nX := 1;"
        ]
    );
}

#[test]
fn actions_can_be_il() {
    let src = "FUNCTION_BLOCK fb\nVAR a : INT; sr1 : SR; p : BOOL; END_VAR\n  LD 1\n  ST a\n\
               ACTION act:\n  LD p\n  S sr1\nEND_ACTION\n\
               ACTION act2:\n  a := 2;\nEND_ACTION\nEND_FUNCTION_BLOCK\n";
    let (u, d, i) = parse_with(src, true);
    assert!(d.is_empty(), "{}", show(&d, src));
    let pou = first_pou(&u);
    assert_eq!(render(&pou.body.stmts, &i), "A := 1;");
    assert_eq!(render(&pou.actions[0].body.stmts, &i), "SR1(S := P);");
    assert_eq!(render(&pou.actions[1].body.stmts, &i), "A := 2;");
}

#[test]
fn st_files_are_not_affected() {
    // In a .st file, a body starting with `LD x` is an ST error as before.
    let src = program("LD a\nST x");
    let (_, d, _) = parse_with(&src, false);
    assert!(!d.is_empty());
    assert!(d.iter().all(|d| !d.code.starts_with("E07")));
}

// ---------------------------------------------------------------- diagnostics

#[test]
fn each_malformed_instruction_is_one_diagnostic() {
    let cases: &[(&str, &str)] = &[
        ("LD", "E0702"),
        ("ST", "E0702"),
        ("ADD", "E0702"),
        ("CAL", "E0702"),
        ("LD a,", "E0702"),
        ("NOT p", "W0703"),
        ("RET 1", "E0703"),
        ("JMPN l", "E0704"),
        ("LDC a", "E0704"),
        ("ADDN a", "E0704"),
        ("LDN( a", "E0704"),
        ("ST( a", "E0704"),
        ("LD a b", "E0701"),
        ("LD a + b", "E0701"),
        ("LD a;", "E0701"),
        ("x := 1;", "E0701"),
        ("IF p THEN", "E0701"),
        ("LD (a)", "E0704"),
        ("ST x, (b)", "E0708"),
        ("LD ABS(a)", "E0708"),
        ("JMP 5", "E0708"),
        ("CAL 5", "E0708"),
        ("IN 5", "E0708"),
        ("LD a, b", "E0708"),
        ("LD -a", "E0708"),
        ("LD :=", "E0708"),
        ("LD a.", "E0101"),
    ];
    for (bad, code) in cases {
        // The bad line between good ones: exactly one diagnostic, and the good lines
        // around it are still translated (no cascade, no undefined-CR warning).
        let body = format!("LD 1\nST x\n{bad}\nST y\nLD 2\nST z");
        let src = program(&body);
        let (u, d, i) = parse_with(&src, true);
        assert_eq!(
            d.iter().map(|d| d.code).collect::<Vec<_>>(),
            [*code],
            "for `{bad}`:\n{}",
            show(&d, &src)
        );
        let out = render(&first_pou(&u).body.stmts, &i);
        assert!(out.starts_with("X := 1;"), "for `{bad}`: {out}");
        assert!(out.ends_with("Z := 2;"), "for `{bad}`: {out}");
        // The span is on the culprit's line.
        let line = SourceFile::new("t.il", src.clone())
            .line_col(d[0].span.unwrap().start)
            .0;
        assert_eq!(line, 5, "for `{bad}`:\n{}", show(&d, &src));
    }
}

#[test]
fn several_independent_errors() {
    let body = "LD\nLD a\nRET p\nST x\nJMPN l\nl: LD a b\nLD 1\n)\nST y";
    assert_eq!(codes(body), ["E0702", "E0703", "E0704", "E0701", "E0705"]);
}

#[test]
fn errors_in_st_parts_of_an_il_file_are_st_errors() {
    let src = "PROGRAM p\nVAR x : INT END_VAR\nLD 1\nST x\nEND_PROGRAM\n";
    let (_, c) = il_file(src);
    assert_eq!(c, ["E0102"]);
}

#[test]
fn garbage_never_panics() {
    let good = "FUNCTION f : INT\nVAR_INPUT a : INT; END_VAR\n\
                LD a\nAND( b\nOR c\n)\nJMPC l\nCAL t(IN := x, PT := T#1s, Q => y)\n\
                l: LIMIT 0, 100\nST f\nRETC\nEND_FUNCTION\n\
                PROGRAM p VAR x : INT; END_VAR\nLD x\nADD 1\nST x\nEND_PROGRAM\n";
    for end in 0..=good.len() {
        let (_u, _d, _i) = parse_with(&good[..end], true);
    }
    let junk = [
        ")))))",
        "(((((",
        "AND(\nAND(\n",
        "LD LD LD",
        ": : :",
        "&&&N",
        "LD %",
        "CAL (((",
        "LD 'unterminated",
        "(* open comment",
        "ST ST ST\nST",
        "JMP\nJMPC\nRET RET",
        "LD a[",
        "CAL t(IN :=",
        "LD a.b.c.d.e.f.",
        "l1: l2: l3:",
        "\u{0}\u{1}",
    ];
    for j in junk {
        let src = program(j);
        let (_u, d, _i) = parse_with(&src, true);
        let _ = d;
        let src = format!("PROGRAM p\nLD 1\n{j}");
        parse_with(&src, true);
    }
    // Pseudo-random bytes from a fixed seed.
    let mut rng = plcc_ir::rng::Rng(0x9E37_79B9_7F4A_7C15);
    let alphabet = b"LDSTANDORXNCJMPCALRET()(,:;.=[]%#'\n \t0123456789abxyz&-+END_VAR";
    for _ in 0..200 {
        let mut s = String::from("PROGRAM p\nVAR a, b, x : INT; END_VAR\n");
        for _ in 0..200 {
            s.push(*rng.pick(alphabet) as char);
        }
        parse_with(&s, true);
    }
}

#[test]
fn deep_nesting_with_broken_lines_is_one_diagnostic() {
    let mut body = String::from("LD p\n");
    body.push_str(&"AND( (q)\n".repeat(300));
    body.push_str(&")\n".repeat(300));
    body.push_str("ST u\n");
    let c = codes(&body);
    // One E0708 per broken line, the nesting error once, no `)` reported.
    assert_eq!(c.iter().filter(|c| **c == "E0707").count(), 1);
    assert!(!c.contains(&"E0705"), "{c:?}");
}
