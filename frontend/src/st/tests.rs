//! Parser tests: precedence, statements, declarations, recovery, limits, and the
//! external corpus.

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

fn show(d: &[Diagnostic], src: &str) -> String {
    let f = SourceFile::new("t.st", src);
    let mut s = String::new();
    for d in d {
        let (l, c) = d.span.map_or((0, 0), |sp| f.line_col(sp.start));
        let _ = writeln!(s, "{l}:{c}: {d} [{}]", d.label);
    }
    s
}

fn codes_of(src: &str) -> Vec<&'static str> {
    parse_str(src).1.iter().map(|d| d.code).collect()
}

/// An expression with every operation in parentheses (the printer's tree style).
fn sx(e: &Expr, i: &Interner) -> String {
    crate::print::tree(e, i)
}

/// The expression of `x := <src>;` in a PROGRAM.
fn expr(src: &str) -> String {
    let prog = format!("PROGRAM p x := {src}; END_PROGRAM");
    let (u, i) = ok(&prog);
    let Item::Pou(p) = &u.items[0] else { panic!() };
    let StmtKind::Assign { value, .. } = &p.body.stmts[0].kind else {
        panic!()
    };
    sx(value, &i)
}

fn body(src: &str) -> (Vec<Stmt>, Interner) {
    let prog = format!("PROGRAM p\n{src}\nEND_PROGRAM");
    let (u, i) = ok(&prog);
    let Item::Pou(p) = u.items.into_iter().next().unwrap() else {
        panic!()
    };
    (p.body.stmts, i)
}

fn pou(src: &str) -> (Pou, Interner) {
    let (u, i) = ok(src);
    let Item::Pou(p) = u.items.into_iter().next().unwrap() else {
        panic!()
    };
    (p, i)
}

// ------------------------------------------------------------------ expressions

#[test]
fn precedence() {
    assert_eq!(expr("a OR b AND c"), "(A OR (B AND C))");
    assert_eq!(expr("a OR_ELSE b XOR c"), "(A OR_ELSE (B XOR C))");
    assert_eq!(
        expr("a XOR b & c AND_THEN d"),
        "(A XOR ((B AND C) AND_THEN D))"
    );
    assert_eq!(expr("a = b < c"), "(A = (B < C))");
    assert_eq!(expr("a <> b + c * d"), "(A <> (B + (C * D)))");
    assert_eq!(expr("a - b - c"), "((A - B) - C)");
    assert_eq!(expr("a / b MOD c * d"), "(((A / B) MOD C) * D)");
    assert_eq!(expr("a + b * c ** d"), "(A + (B * (C ** D)))");
    assert_eq!(expr("2 ** 3 ** 2"), "((2 ** 3) ** 2)");
    assert_eq!(expr("-2 ** 2"), "((-2) ** 2)");
    assert_eq!(expr("- x * y"), "((-X) * Y)");
    assert_eq!(expr("NOT a AND b"), "((NOT A) AND B)");
    assert_eq!(expr("NOT a = b"), "((NOT A) = B)");
    assert_eq!(expr("a AND NOT b OR c"), "((A AND (NOT B)) OR C)");
    assert_eq!(expr("a >= b AND c <= d"), "((A >= B) AND (C <= D))");
    assert_eq!(expr("(a + b) * c"), "(((A + B)) * C)");
    assert_eq!(expr("- - +x"), "(-(-(+X)))");
    assert_eq!(expr("2 ** -1"), "(2 ** (-1))");
    assert_eq!(expr("t.Q AND x"), "(T.Q AND X)");
}

#[test]
fn postfix_forms() {
    assert_eq!(expr("a.b.c"), "A.B.C");
    assert_eq!(expr("a[1, j + 1].x"), "A[1, (J + 1)].X");
    assert_eq!(expr("p^.x^"), "P^.X^");
    assert_eq!(expr("x.3"), "X.3");
    assert_eq!(expr("x.%X3"), "X.3");
    assert_eq!(
        expr("w.%B1 + w.%W0 + d.%D0 + l.%L0"),
        "(((W.%B1 + W.%W0) + D.%D0) + L.%L0)"
    );
    assert_eq!(expr("a.b[2].3"), "A.B[2].3");
    assert_eq!(expr("f(1, 2)"), "F(1, 2)");
    assert_eq!(expr("f()"), "F()");
    assert_eq!(expr("inst.act()"), "INST.ACT()");
    assert_eq!(expr("SUPER^.calc()"), "SUPER^.CALC()");
    assert_eq!(expr("%IX0.0 AND %QW1 > 0"), "(%IX0.0 AND (%QW1 > 0))");
    assert_eq!(expr("Color#Red"), "COLOR#RED");
    assert_eq!(expr("INT#-5 + DINT#16#FF"), "(INT#-5 + DINT#255)");
    assert_eq!(expr("MyInt#5"), "MYINT#5");
    assert_eq!(expr("T#1s + TIME#2ms"), "(T#1s + T#2ms)");
    assert_eq!(expr("TRUE AND FALSE"), "(TRUE AND FALSE)");
    assert_eq!(expr("'a$'b' = \"w\""), "('a$'b' = \"w\")");
    assert_eq!(expr("1.5E3 * 2"), "(1.5E3 * 2)");
}

#[test]
fn call_arguments() {
    let (s, i) = body("fb(IN := x, PT := T#5s, Q => y, NOT ET => z, CV =>);");
    let StmtKind::Call(c) = &s[0].kind else {
        panic!()
    };
    assert_eq!(
        sx(c, &i),
        "FB(IN := X, PT := T#5s, Q => Y, NOT ET => Z, CV =>)"
    );
    let (s, i) = body("f(1, a + 2, g(h(3)));");
    let StmtKind::Call(c) = &s[0].kind else {
        panic!()
    };
    assert_eq!(sx(c, &i), "F(1, (A + 2), G(H(3)))");
}

#[test]
fn spans_are_tight() {
    let src = "PROGRAM p\n  x := (a + b) * c;\n  t(IN := x);\nEND_PROGRAM";
    let (u, _) = ok(src);
    let Item::Pou(p) = &u.items[0] else { panic!() };
    let at = |s: plcc_ir::diag::Span| &src[s.start as usize..s.end as usize];
    assert_eq!(at(p.span), src);
    assert_eq!(at(p.body.stmts[0].span), "x := (a + b) * c");
    assert_eq!(at(p.body.stmts[1].span), "t(IN := x)");
    assert_eq!(at(p.body.span), "x := (a + b) * c;\n  t(IN := x);");
    let StmtKind::Assign { value, .. } = &p.body.stmts[0].kind else {
        panic!()
    };
    assert_eq!(at(value.span), "(a + b) * c");
    let ExprKind::Binary(_, l, _) = &value.kind else {
        panic!()
    };
    assert_eq!(at(l.span), "(a + b)");
    let StmtKind::Call(c) = &p.body.stmts[1].kind else {
        panic!()
    };
    let ExprKind::Call { args, .. } = &c.kind else {
        panic!()
    };
    assert_eq!(at(args[0].span), "IN := x");
}

// ------------------------------------------------------------------ statements

#[test]
fn if_elsif_else() {
    let (s, i) = body("IF a THEN x := 1; ELSIF b THEN x := 2; y := 3; ELSE x := 4; END_IF;");
    let StmtKind::If {
        branches,
        else_body,
    } = &s[0].kind
    else {
        panic!()
    };
    assert_eq!(branches.len(), 2);
    assert_eq!(sx(&branches[1].0, &i), "B");
    assert_eq!(branches[1].1.len(), 2);
    assert_eq!(else_body.as_ref().unwrap().len(), 1);
    let (s, _) = body("IF a THEN END_IF;");
    let StmtKind::If {
        branches,
        else_body,
    } = &s[0].kind
    else {
        panic!()
    };
    assert!(branches[0].1.is_empty() && else_body.is_none());
}

#[test]
fn case_labels_and_arms() {
    let (s, i) = body(
        "CASE x OF\n 1, 2, 5..10: y := 1; z := 2;\n RED, -3: y := 3;\n Color#Green: ;\n -5..-1: y := 4;\n E.A: \nELSE y := 0; z := 0;\nEND_CASE;",
    );
    let StmtKind::Case {
        selector,
        arms,
        else_body,
    } = &s[0].kind
    else {
        panic!()
    };
    assert_eq!(sx(selector, &i), "X");
    assert_eq!(arms.len(), 5);
    let labels: Vec<String> = arms
        .iter()
        .map(|a| {
            a.labels
                .iter()
                .map(|l| match l {
                    CaseLabel::Value(e) => sx(e, &i),
                    CaseLabel::Range(a, b) => format!("{}..{}", sx(a, &i), sx(b, &i)),
                })
                .collect::<Vec<_>>()
                .join(",")
        })
        .collect();
    assert_eq!(
        labels,
        ["1,2,5..10", "RED,(-3)", "COLOR#GREEN", "(-5)..(-1)", "E.A"]
    );
    assert_eq!(arms[0].body.len(), 2);
    assert_eq!(arms[2].body.len(), 1); // the empty statement
    assert!(arms[4].body.is_empty());
    assert_eq!(else_body.as_ref().unwrap().len(), 2);
}

#[test]
fn case_arm_statements_that_look_like_labels() {
    // Calls, assignments to members and indexed targets are statements, not labels.
    let (s, _) = body("CASE x OF 1: f(a, b); s.a := 1; arr[1] := 2; 2: y := 1; END_CASE;");
    let StmtKind::Case { arms, .. } = &s[0].kind else {
        panic!()
    };
    assert_eq!(arms.len(), 2);
    assert_eq!(arms[0].body.len(), 3);
}

#[test]
fn loops_and_jumps() {
    let (s, i) = body(
        "FOR i := 10 TO 1 BY -1 DO x := x + i; IF x > 5 THEN EXIT; END_IF; CONTINUE; END_FOR;\n\
         WHILE a < 5 DO a := a + 1; END_WHILE;\n\
         REPEAT a := a - 1; UNTIL a = 0 END_REPEAT;\n\
         RETURN; ;",
    );
    let StmtKind::For {
        var,
        from,
        to,
        by,
        body,
    } = &s[0].kind
    else {
        panic!()
    };
    assert_eq!(i.name(var.sym), "I");
    assert_eq!(
        (sx(from, &i), sx(to, &i), sx(by.as_ref().unwrap(), &i)),
        ("10".into(), "1".into(), "(-1)".into())
    );
    assert_eq!(body.len(), 3);
    assert!(matches!(s[1].kind, StmtKind::While { .. }));
    let StmtKind::Repeat { until, body } = &s[2].kind else {
        panic!()
    };
    assert_eq!((sx(until, &i), body.len()), ("(A = 0)".into(), 1));
    assert!(matches!(s[3].kind, StmtKind::Return));
    assert!(matches!(s[4].kind, StmtKind::Empty));
}

#[test]
fn assignments() {
    let (s, i) = body("a.b[1]^ := 1; r REF= v; %QX0.1 := TRUE;");
    let StmtKind::Assign { target, .. } = &s[0].kind else {
        panic!()
    };
    assert_eq!(sx(target, &i), "A.B[1]^");
    assert!(matches!(s[1].kind, StmtKind::RefAssign { .. }));
    assert!(matches!(s[2].kind, StmtKind::Assign { .. }));
}

// ------------------------------------------------------------------ corpus

/// Files that use syntax plcc does not support (object-oriented extensions), with
/// the reason; they may give diagnostics. Every other corpus file must parse clean.
const CORPUS_UNSUPPORTED: &[(&str, &str)] = &[
    (
        "reference_to__array_of_reference_to_element_bound_then_reads.st",
        "CODESYS `REFERENCE TO` (auto-dereferencing references; the AST has only REF_TO)",
    ),
    ("reference_to__reference_to_written_then_updates_referent.st", "CODESYS `REFERENCE TO`"),
    (
        "reference_to__reference_to_written_without_caret_then_auto_dereferences.st",
        "CODESYS `REFERENCE TO`",
    ),
    ("reference_to__two_references_alias_then_writes_are_observed.st", "CODESYS `REFERENCE TO`"),
    (
        "standard_functions.txt",
        "matiec's internal prototypes: extensible inputs `IN 1 ..` (not IEC syntax)",
    ),
    (
        "ironplc_res_var_decl.st",
        "located variables without a name inside a PROGRAM (`AT %IX1.1 : BOOL;`), rejected by design",
    ),
];

/// Parses every ST file of the shared corpus and lists those with diagnostics.
#[test]
fn corpus_parses_without_diagnostics() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/corpus");
    if !root.exists() {
        eprintln!("notice: {} not found; corpus test skipped", root.display());
        return;
    }
    let mut files = Vec::new();
    for dir in [
        "bulk/ironplc_e2e",
        "st",
        "libs/oscat_basic_333",
        "libs/matiec_stdlib",
    ] {
        let Ok(rd) = std::fs::read_dir(root.join(dir)) else {
            continue;
        };
        for e in rd.flatten() {
            let p = e.path();
            let ext = p
                .extension()
                .and_then(|e| e.to_str())
                .unwrap_or("")
                .to_ascii_lowercase();
            let st = ext == "st"
                || (dir.starts_with("libs/") && ext == "txt" && !p.ends_with("COPYING.LESSER"));
            if st {
                files.push(p);
            }
        }
    }
    files.sort();
    assert!(
        files.len() > 300,
        "corpus looks incomplete: {} files",
        files.len()
    );
    let mut unexpected = Vec::new();
    let mut interner = Interner::new();
    for p in &files {
        let bytes = std::fs::read(p).unwrap();
        let f = SourceFile::from_bytes(p.display().to_string(), bytes);
        let mut d = Vec::new();
        let unit = parse(FileId(0), &f.text, &mut interner, &mut d);
        // matiec's timers read the clock in C pragmas (`{__SET_VAR(...)}`): W0010 is
        // right there and is no parse problem.
        d.retain(|d| d.code != crate::codes::W_C_PRAGMA);
        let name = p.file_name().unwrap().to_string_lossy().to_string();
        let allowed = CORPUS_UNSUPPORTED.iter().any(|(n, _)| *n == name);
        if !d.is_empty() {
            eprintln!("{name}: {} diagnostic(s)", d.len());
            for d in d.iter().take(5) {
                let (l, c) = d.span.map_or((0, 0), |s| f.line_col(s.start));
                eprintln!("    {l}:{c}: {d} [{}]", d.label);
            }
            if !allowed {
                unexpected.push(name.clone());
            }
        } else if unit.items.is_empty() {
            unexpected.push(format!("{name} (no items)"));
        }
        if name.starts_with("OSCAT_BASIC_333") {
            let pous = unit
                .items
                .iter()
                .filter(|i| matches!(i, Item::Pou(_)))
                .count();
            let types = unit
                .items
                .iter()
                .filter(|i| matches!(i, Item::Type(_)))
                .count();
            let globals = unit
                .items
                .iter()
                .filter(|i| matches!(i, Item::Globals(_)))
                .count();
            assert_eq!((pous, types, globals), (545, 14, 3), "{name}");
        }
    }
    assert!(
        unexpected.is_empty(),
        "corpus files with diagnostics: {unexpected:#?}"
    );
}

// ------------------------------------------------------------------ declarations

fn ty(t: &TypeSpec, i: &Interner) -> String {
    Printer::new(i).with_style(Style::Tree).type_spec(t)
}

fn decl(d: &VarDecl, i: &Interner) -> String {
    Printer::new(i).with_style(Style::Tree).var_decl(d)
}

fn decls(src: &str) -> Vec<String> {
    let (p, i) = pou(&format!("PROGRAM p\nVAR\n{src}\nEND_VAR\nEND_PROGRAM"));
    p.var_blocks[0].decls.iter().map(|d| decl(d, &i)).collect()
}

#[test]
fn variable_declarations() {
    assert_eq!(
        decls(
            "a, b : INT := 5;\n x AT %IX0.0 : BOOL;\n s1 : STRING; s2 : STRING[20]; s3 : STRING(20); w : WSTRING[10];\n\
             arr : ARRAY[1..10, 0..2] OF INT; va : ARRAY[*] OF INT; r : INT(0..100); neg : INT(-10..10);\n\
             e : (red, green := 5, blue); e2 : (a, b) INT := a; e3 : BYTE (x := 1, y := 2);\n\
             p : REF_TO INT; q : POINTER TO ARRAY[0..1] OF BYTE; t : TON := (PT := T#5s);\n\
             m : ARRAY[0..N-1] OF ARRAY[1..2] OF REAL;"
        ),
        [
            "A, B : INT := 5;",
            "X AT %IX0.0 : BOOL;",
            "S1 : STRING;",
            "S2 : STRING[20];",
            "S3 : STRING[20];",
            "W : WSTRING[10];",
            "ARR : ARRAY[1..10, 0..2] OF INT;",
            "VA : ARRAY[*] OF INT;",
            "R : INT(0..100);",
            "NEG : INT((-10)..10);",
            "E : (RED, GREEN := 5, BLUE);",
            "E2 : (A, B) INT := A;",
            "E3 : (X := 1, Y := 2) BYTE;",
            "P : REF_TO INT;",
            "Q : POINTER TO ARRAY[0..1] OF BYTE;",
            "T : TON := (PT := T#5s);",
            "M : ARRAY[0..(N - 1)] OF ARRAY[1..2] OF REAL;",
        ]
    );
}

#[test]
fn initialisers() {
    assert_eq!(
        decls(
            "a : ARRAY[0..5] OF INT := [1, 2, 3(0), 2()];\n\
             b : ARRAY[0..2] OF INT := 1, 2, 3;\n\
             c : ARRAY[0..9] OF INT := 10(7);\n\
             d : ARRAY[0..1] OF S := [(x := 1), (x := 2, y := [1, 2])];\n\
             e : S := (a := 1, b := (c := 2));\n\
             f : INT := (1 + 2);\n\
             g : ARRAY[0..1, 0..1] OF INT := [[1, 2], [3, 4]];\n\
             h : ARRAY[0..1] OF INT := other;"
        ),
        [
            "A : ARRAY[0..5] OF INT := [1, 2, 3(0), 2()];",
            "B : ARRAY[0..2] OF INT := [1, 2, 3];",
            "C : ARRAY[0..9] OF INT := [10(7)];",
            "D : ARRAY[0..1] OF S := [(X := 1), (X := 2, Y := [1, 2])];",
            "E : S := (A := 1, B := (C := 2));",
            "F : INT := ((1 + 2));",
            "G : ARRAY[0..1, 0..1] OF INT := [[1, 2], [3, 4]];",
            "H : ARRAY[0..1] OF INT := OTHER;",
        ]
    );
}

/// CPDev's `LIBRARY.TYPE` names the type by its last name; the span keeps the
/// qualifier, so diagnostics quote the name as written.
#[test]
fn library_qualified_type_names() {
    let src = "PROGRAM p\nVAR\n ton1: IEC_61131.TON;\n tff1: Basic_blocks.TFF;\n \
               a : ARRAY[0..1] OF IEC_61131.R_TRIG;\n c : IEC_61131.CTU := (PV := 3);\n\
               END_VAR\nEND_PROGRAM";
    let (p, i) = pou(src);
    let got: Vec<String> = p.var_blocks[0].decls.iter().map(|d| decl(d, &i)).collect();
    assert_eq!(
        got,
        [
            "TON1 : TON;",
            "TFF1 : TFF;",
            "A : ARRAY[0..1] OF R_TRIG;",
            "C : CTU := (PV := 3);",
        ]
    );
    let TypeSpec::Named(n) = &p.var_blocks[0].decls[1].ty else {
        panic!("a named type")
    };
    assert_eq!(
        &src[n.span.start as usize..n.span.end as usize],
        "Basic_blocks.TFF"
    );
    // One qualifier only: `A.B.C` is not a type name.
    assert_eq!(
        codes_of("PROGRAM p VAR x : A.B.C; END_VAR END_PROGRAM"),
        [crate::codes::MISSING_SEMICOLON]
    );
}

#[test]
fn var_block_kinds_and_qualifiers() {
    let (p, _) = pou(
        "FUNCTION_BLOCK fb\n VAR_INPUT a : INT; END_VAR\n VAR_OUTPUT b : INT; END_VAR\n VAR_IN_OUT c : INT; END_VAR\n\
         VAR_TEMP d : INT; END_VAR\n VAR_EXTERNAL CONSTANT e : INT; END_VAR\n VAR_STAT f : INT; END_VAR\n\
         VAR RETAIN CONSTANT g : INT; END_VAR\n VAR CONSTANT PERSISTENT h : INT; END_VAR\n VAR NON_RETAIN i : INT; END_VAR\n\
         VAR_GLOBAL j : INT; END_VAR\nEND_FUNCTION_BLOCK",
    );
    let kinds: Vec<(VarKind, bool, bool)> = p
        .var_blocks
        .iter()
        .map(|b| (b.kind, b.constant, b.retain))
        .collect();
    use VarKind::*;
    assert_eq!(
        kinds,
        [
            (Input, false, false),
            (Output, false, false),
            (InOut, false, false),
            (Temp, false, false),
            (External, true, false),
            (Stat, false, false),
            (Var, true, true),
            (Var, true, true),
            (Var, false, false),
            (Global, false, false),
        ]
    );
}

#[test]
fn type_declarations() {
    let src = "TYPE\n  S : STRUCT a : INT := 1; b : ARRAY[1..2] OF BOOL; END_STRUCT;\n  E : (red, green, blue) := green;\n\
               R : INT(0..10);\n  A : ARRAY[1..3] OF R := [1, 2, 3];\n  Al : INT;\n  TE : INT (x := 100, y := 200);\n\
               Str : STRING[5] := 'value';\nEND_TYPE\nTYPE C : STRUCT re : REAL; END_STRUCT\nEND_TYPE";
    let (u, i) = ok(src);
    let got: Vec<String> = u
        .items
        .iter()
        .map(|it| {
            let Item::Type(t) = it else { panic!() };
            Printer::new(&i).with_style(Style::Tree).type_decl(t)
        })
        .collect();
    assert_eq!(
        got,
        [
            "S : STRUCT A : INT := 1; B : ARRAY[1..2] OF BOOL; END_STRUCT;",
            "E : (RED, GREEN, BLUE) := GREEN;",
            "R : INT(0..10);",
            "A : ARRAY[1..3] OF R := [1, 2, 3];",
            "AL : INT;",
            "TE : (X := 100, Y := 200) INT;",
            "STR : STRING[5] := 'value';",
            "C : STRUCT RE : REAL; END_STRUCT;",
        ]
    );
    let Item::Type(t) = &u.items[0] else { panic!() };
    assert_eq!(
        &src[t.span.start as usize..t.span.end as usize],
        "S : STRUCT a : INT := 1; b : ARRAY[1..2] OF BOOL; END_STRUCT"
    );
}

#[test]
fn pou_headers() {
    let (u, i) = ok(
        "FUNCTION f : INT; VAR_INPUT a : INT; END_VAR f := a; END_FUNCTION;\n\
         FUNCTION g VAR_INPUT a : INT; END_VAR END_FUNCTION\n\
         FUNCTION h : STRING[10] h := 'x'; END_FUNCTION\n\
         FUNCTION_BLOCK fb EXTENDS base\n VAR x : INT; END_VAR\n x := 1;\nEND_FUNCTION_BLOCK\n\
         PROGRAM p; END_PROGRAM",
    );
    let pous: Vec<&Pou> = u
        .items
        .iter()
        .map(|it| if let Item::Pou(p) = it { p } else { panic!() })
        .collect();
    assert_eq!(pous.len(), 5);
    assert_eq!(
        (pous[0].kind, i.name(pous[0].name.sym)),
        (PouKind::Function, "F")
    );
    assert_eq!(ty(pous[0].return_type.as_ref().unwrap(), &i), "INT");
    assert!(pous[1].return_type.is_none());
    assert_eq!(ty(pous[2].return_type.as_ref().unwrap(), &i), "STRING[10]");
    assert_eq!(i.name(pous[3].extends.unwrap().sym), "BASE");
    assert_eq!(pous[3].kind, PouKind::FunctionBlock);
    assert_eq!(pous[4].kind, PouKind::Program);
    // An empty body sits at the end of the declarations.
    assert_eq!(pous[1].body.span.start, pous[1].body.span.end);
    assert!(pous[1].body.stmts.is_empty());
}

#[test]
fn object_oriented_members_are_parsed() {
    let src = "FUNCTION_BLOCK PUBLIC fb EXTENDS base IMPLEMENTS I1, I2\nVAR s : STRING; END_VAR\n\
               METHOD PUBLIC baz : INT\n  VAR_INPUT x : INT; END_VAR\n  baz := x;\nEND_METHOD\n\
               METHOD ABSTRACT FINAL OVERRIDE PRIVATE q END_METHOD\n\
               PROPERTY P : INT\n  GET P := 1; END_GET\n  SET s := 'b'; END_SET\nEND_PROPERTY\n\
               s := 'a';\nEND_FUNCTION_BLOCK";
    let (p, i) = pou(src);
    assert!(p.unsupported_members.is_empty());
    assert_eq!(p.body.stmts.len(), 1);
    assert_eq!(i.name(p.name.sym), "FB");
    assert_eq!(i.name(p.extends.expect("a base").sym), "BASE");
    let oo = &p.oo;
    assert_eq!(oo.modifiers.access.map(|a| a.0), Some(AccessSpec::Public));
    let names: Vec<&str> = oo.implements.iter().map(|n| i.name(n.sym)).collect();
    assert_eq!(names, ["I1", "I2"]);
    assert_eq!(oo.methods.len(), 2);
    let baz = &oo.methods[0];
    assert_eq!(i.name(baz.pou.name.sym), "BAZ");
    assert!(baz.pou.return_type.is_some());
    assert_eq!(baz.pou.var_blocks.len(), 1);
    assert_eq!(baz.pou.body.stmts.len(), 1);
    let q = &oo.methods[1].modifiers;
    assert!(q.abstract_.is_some() && q.final_.is_some() && q.override_.is_some());
    assert_eq!(q.access.map(|a| a.0), Some(AccessSpec::Private));
    let prop = &oo.properties[0];
    assert_eq!(i.name(prop.name.sym), "P");
    let get = prop.get.as_ref().expect("a getter");
    assert_eq!(get.body.stmts.len(), 1);
    // The setter's value is an input of the property's name.
    let set = prop.set.as_ref().expect("a setter");
    assert_eq!(set.var_blocks[0].kind, VarKind::Input);
    assert_eq!(i.name(set.var_blocks[0].decls[0].names[0].sym), "P");
    // Interfaces at top level, extending others.
    let src = "INTERFACE I EXTENDS A, B\n METHOD m : INT VAR_INPUT x : INT; END_VAR END_METHOD\n\
               PROPERTY v : REAL GET END_GET END_PROPERTY\nEND_INTERFACE\nPROGRAM p x := 1; END_PROGRAM";
    let (u, d, i) = parse_str(src);
    assert!(d.is_empty(), "{d:?}");
    assert_eq!(u.items.len(), 2);
    let Item::Interface(itf) = &u.items[0] else {
        panic!("an interface")
    };
    assert_eq!(i.name(itf.name.sym), "I");
    assert_eq!(itf.extends.len(), 2);
    assert_eq!(itf.methods.len(), 1);
    assert_eq!(itf.methods[0].pou.var_blocks.len(), 1);
    assert!(itf.properties[0].get.is_some() && itf.properties[0].set.is_none());
    // A method left open is reported at the POU's end.
    let (_, d, _) = parse_str("FUNCTION_BLOCK f METHOD m x := 1; END_FUNCTION_BLOCK");
    assert_eq!(
        d.iter().map(|d| d.code).collect::<Vec<_>>(),
        [crate::codes::UNCLOSED_BLOCK]
    );
}

#[test]
fn sfc_elements_make_a_chart() {
    let src = "FUNCTION_BLOCK sfc\nVAR c : INT; END_VAR\nINITIAL_STEP Start:\nEND_STEP\n\
               TRANSITION (PRIORITY := 3) FROM Start TO (Mid, Other)\n  := c > 1;\nEND_TRANSITION\n\
               STEP Mid:\n  RESET(N);\n  RESET(L, T#2s, c);\nEND_STEP\n\
               ACTION RESET:\n  c := 0;\nEND_ACTION\nEND_FUNCTION_BLOCK";
    let (p, i) = pou(src);
    assert!(p.unsupported_members.is_empty());
    let chart = p.sfc.as_ref().expect("a chart");
    assert_eq!(chart.steps.len(), 2);
    assert!(chart.steps[0].initial && !chart.steps[1].initial);
    let assocs = &chart.steps[1].assocs;
    assert_eq!(assocs.len(), 2);
    assert_eq!(i.name(assocs[1].qualifier.expect("L").sym), "L");
    assert!(assocs[1].duration.is_some());
    assert_eq!(i.name(assocs[1].indicators[0].sym), "C");
    let t = &chart.transitions[0];
    assert_eq!(t.priority.map(|(p, _)| p), Some(3));
    assert_eq!(t.to.len(), 2);
    assert_eq!(
        &src[t.condition.expect("a condition").start as usize..][..5],
        "c > 1"
    );
    assert_eq!(p.actions.len(), 1);
    assert_eq!(i.name(p.actions[0].name.sym), "RESET");
    assert!(p.actions[0].pou.is_none());
    // `step` is still an ordinary name elsewhere.
    body("step := 1; step(x := 2);");
}

#[test]
fn actions() {
    let src = "FUNCTION_BLOCK fb\nVAR x : INT; END_VAR\nx := 1;\nACTION a1:\n x := 2;\nEND_ACTION\nEND_FUNCTION_BLOCK\n\
               ACTION a2:\n x := 3;\nEND_ACTION\nACTION fb.a3: x := 4; END_ACTION\n\
               ACTIONS fb\n  ACTION a4\n    x := 5;\n  END_ACTION\nEND_ACTIONS";
    let (u, i) = ok(src);
    let Item::Pou(p) = &u.items[0] else { panic!() };
    assert_eq!(p.actions.len(), 1);
    assert_eq!(p.body.stmts.len(), 1);
    let tops: Vec<(Option<&str>, &str)> = u.items[1..]
        .iter()
        .map(|it| {
            let Item::Action(a) = it else { panic!() };
            (a.pou.map(|p| i.name(p.sym)), i.name(a.name.sym))
        })
        .collect();
    assert_eq!(
        tops,
        [(Some("FB"), "A2"), (Some("FB"), "A3"), (Some("FB"), "A4")]
    );
}

#[test]
fn configuration() {
    let src = "CONFIGURATION cfg\n VAR_GLOBAL g : INT; AT %QX0.0 : BOOL; END_VAR\n\
               RESOURCE res ON PLC\n  VAR_GLOBAL rg : BOOL; END_VAR\n  TASK fast(INTERVAL := T#10ms, PRIORITY := 1);\n\
               PROGRAM inst WITH fast : Main(IN := g, OUT => rg);\n  PROGRAM other : Main;\n END_RESOURCE\n\
               TASK t2(SINGLE := trig, PRIORITY := 2);\n PROGRAM RETAIN p2 WITH t2 : Prog2;\n\
               VAR_CONFIG inst.a.b AT %IX1.0 : BOOL; inst.fb : FBT := (ELEM := 1); END_VAR\nEND_CONFIGURATION";
    let (u, i) = ok(src);
    let Item::Configuration(c) = &u.items[0] else {
        panic!()
    };
    assert_eq!(i.name(c.name.sym), "CFG");
    assert_eq!(c.var_blocks.len(), 2);
    assert!(c.var_blocks[0].decls[1].names.is_empty());
    let paths: Vec<&str> = c.var_blocks[1]
        .decls
        .iter()
        .map(|d| i.name(d.names[0].sym))
        .collect();
    assert_eq!(paths, ["INST.A.B", "INST.FB"]);
    assert_eq!(c.resources.len(), 2);
    let r = &c.resources[0];
    assert_eq!(
        (i.name(r.name.sym), r.on.map(|o| i.name(o.sym))),
        ("RES", Some("PLC"))
    );
    assert_eq!(r.var_blocks.len(), 1);
    assert_eq!(r.tasks.len(), 1);
    let props: Vec<String> = r.tasks[0]
        .props
        .iter()
        .map(|(n, v)| format!("{}={}", i.name(n.sym), sx(v, &i)))
        .collect();
    assert_eq!(props, ["INTERVAL=T#10ms", "PRIORITY=1"]);
    assert_eq!(r.programs.len(), 2);
    assert_eq!(i.name(r.programs[0].task.unwrap().sym), "FAST");
    assert_eq!(i.name(r.programs[0].pou.sym), "MAIN");
    assert_eq!(r.programs[0].args.len(), 2);
    assert!(r.programs[1].task.is_none());
    // Tasks and programs written directly in the configuration: an implicit resource.
    let imp = &c.resources[1];
    assert_eq!((i.name(imp.name.sym), imp.on), ("CFG", None));
    assert_eq!((imp.tasks.len(), imp.programs.len()), (1, 1));
    assert_eq!(
        &src[imp.span.start as usize..imp.span.end as usize],
        "TASK t2(SINGLE := trig, PRIORITY := 2);\n PROGRAM RETAIN p2 WITH t2 : Prog2"
    );
}

#[test]
fn globals_and_comments_everywhere() {
    let (u, _) = ok(
        "(* header (* nested *) *)\n{attribute 'x'}\nVAR_GLOBAL CONSTANT\n  limit : INT := 10; // c\nEND_VAR\n\
         /* c */ PROGRAM p (* a *) VAR (* b *) x : INT; END_VAR x := (* c *) 1; END_PROGRAM",
    );
    assert!(matches!(
        u.items[0],
        Item::Globals(VarBlock { constant: true, .. })
    ));
}

// ------------------------------------------------------------------ error recovery

mod recovery;
use recovery::check_errors;

// ------------------------------------------------------------------ snapshots

/// A whole unit printed with every operation in parentheses, for snapshots.
fn dump(u: &SourceUnit, i: &Interner) -> String {
    Printer::new(i).with_style(Style::Parenthesised).unit(u)
}

/// Diagnostics as `line:col-line:col error[code]: message` with labels, for snapshots.
fn render(src: &str, d: &[Diagnostic]) -> String {
    let f = SourceFile::new("t.st", src);
    let mut out = String::new();
    for d in d {
        let at = |s: plcc_ir::diag::Span| {
            let (l1, c1) = f.line_col(s.start);
            let (l2, c2) = f.line_col(s.end);
            format!("{l1}:{c1}-{l2}:{c2}")
        };
        let _ = writeln!(out, "{} {d}", d.span.map_or("-".into(), at));
        let _ = writeln!(out, "    label: {}", d.label);
        for (s, l) in &d.secondary {
            let _ = writeln!(out, "    also {}: {l}", at(*s));
        }
        for n in &d.notes {
            let _ = writeln!(out, "    note: {n}");
        }
    }
    out
}

#[test]
fn snapshot_program() {
    let src = r#"
TYPE
  Color : (Red, Green := 5, Blue) := Red;
  Point : STRUCT x, y : REAL := 0.0; tag : STRING[8] := 'p'; END_STRUCT;
  Grid : ARRAY[0..2, 0..2] OF INT := [3(1), 3(), 0, 1, 2];
END_TYPE

FUNCTION_BLOCK Blinker
VAR_INPUT enable : BOOL; period : TIME := T#500ms; END_VAR
VAR_OUTPUT lamp AT %QX0.1 : BOOL; END_VAR
VAR t : TON; state : Color := Color#Red; n : INT(0..100); END_VAR
  t(IN := enable AND NOT t.Q, PT := period, Q => lamp, ET =>);
  IF t.Q THEN
    n := (n + 1) MOD 10;
  ELSIF NOT enable THEN
    n := 0;
  END_IF;
  CASE n OF
    0, 2..4: state := Green;
    Color#Blue, -1: ;
  ELSE
    state := Red;
  END_CASE;
  FOR n := 10 TO 0 BY -2 DO
    IF n.0 THEN CONTINUE; END_IF;
  END_FOR;
  WHILE n < 5 DO n := n + 1; END_WHILE;
  REPEAT n := n - 1; UNTIL n <= 0 OR n ** 2 > 100 END_REPEAT;
ACTION reset:
  n := 0; RETURN;
END_ACTION
END_FUNCTION_BLOCK

PROGRAM Main
VAR b : Blinker; p : Point := (x := 1.5, tag := 'a$'b'); r : REF_TO INT; w : WORD; END_VAR
  b(enable := TRUE);
  r REF= p.x;
  w.%B1 := 16#FF;
  %QX0.0 := b.lamp XOR w.3;
END_PROGRAM

CONFIGURATION Cell
  TASK cyclic(INTERVAL := T#10ms, PRIORITY := 1);
  PROGRAM main WITH cyclic : Main;
END_CONFIGURATION
"#;
    let (u, i) = ok(src);
    insta::assert_snapshot!(dump(&u, &i));
}

#[test]
fn snapshot_recovery_diagnostics() {
    let src = "\
FUNCTION_BLOCK Broken
VAR
  a : INT
  b : ARRAY[1..3 OF INT;
  AT %QX0.0 : BOOL;
END_VAR
  a := 3 +* 4;
  IF a = 1
    b[1] := 2;
  END_IF;
  WHILE a < 10 DO
    a := a + 1
  END_WHILE;
  CASE a OF
    1: a := 2;
    2 a := 3;
  END_CASE;
  FOR i := 1 TO 3 DO
    a := a + i;
  END_WHILE;
  x = 5;
  s := 'abc$Q';
  END_IF;
END_FUNCTION_BLOCK
";
    let (_, d, _) = parse_str(src);
    insta::assert_snapshot!(render(src, &d));
}

#[test]
fn declaration_level_errors() {
    check_errors(
        "FUNCTION f : ;\n VAR x : INT; END_VAR\n f := 1;\nEND_FUNCTION\nPROGRAM q END_PROGRAM",
        &["error[E0101]: expected a type, found `;`"],
    );
    check_errors(
        "PROGRAM\n VAR x : INT; END_VAR\n x := 1;\nEND_PROGRAM\nPROGRAM q END_PROGRAM",
        &["error[E0101]: expected a name, found `VAR`"],
    );
    check_errors(
        "PROGRAM p VAR a : INT; VAR_INPUT b : INT; END_VAR END_PROGRAM",
        &["error[E0104]: expected `END_VAR`, found `VAR_INPUT`"],
    );
    check_errors(
        "CONFIGURATION c\n RESOURCE r ON p\n  TASK t(INTERVAL := T#1s);\nEND_CONFIGURATION",
        &["error[E0104]: expected `END_RESOURCE`, found `END_CONFIGURATION`"],
    );
    check_errors(
        "CONFIGURATION c\n TASK t(INTERVAL := T#1s);\nPROGRAM p END_PROGRAM",
        &["error[E0104]: expected `END_CONFIGURATION`, found `PROGRAM`"],
    );
    check_errors(
        "TYPE t : INT;\nFUNCTION f : INT f := 1; END_FUNCTION",
        &["error[E0104]: expected `END_TYPE`, found `FUNCTION`"],
    );
    check_errors(
        "PROGRAM p\n x := 1;",
        &["error[E0104]: expected `END_PROGRAM`, found end of file"],
    );
    check_errors("x := 1;", &[
        "error[E0101]: expected `PROGRAM`, `FUNCTION`, `FUNCTION_BLOCK`, `TYPE`, `VAR_GLOBAL` or `CONFIGURATION`, found `x`",
    ]);
    check_errors(
        "PROGRAM p x := 'a very long string literal indeed' 1; END_PROGRAM",
        &["error[E0102]: expected `;`, found `1`"],
    );
    check_errors(
        "PROGRAM p x := 1 'a very long string literal indeed'; END_PROGRAM",
        &["error[E0102]: expected `;`, found `'a very long string ...`"],
    );
}

#[test]
fn empty_and_comment_only_files() {
    assert!(parse_str("").0.items.is_empty());
    assert!(parse_str("  \n(* only a comment *)\n// and another\n")
        .1
        .is_empty());
    assert_eq!(codes_of("(* never closed"), ["E0002"]);
}

/// C pragmas where statements stand become statements (in nested lists too); one
/// inside a statement, or among declarations, is skipped with W0010.
#[test]
fn c_pragmas_become_statements_where_statements_stand() {
    let src = "PROGRAM p VAR {x = 1;} a : INT; END_VAR\n\
               {__SET_VAR(data__->,A,,1);}\n\
               IF a > 0 THEN {{ f(); }} a := 2 {g();} + 1; {h();} END_IF;\n\
               {{ last(); }}\n\
               END_PROGRAM";
    let (unit, diags, interner) = parse_str(src);
    let crate::ast::Item::Pou(pou) = &unit.items[0] else {
        panic!("a POU")
    };
    let out = Printer::new(&interner).stmts(&pou.body.stmts);
    assert!(out.contains("{__SET_VAR(data__->,A,,1);}"), "{out}");
    assert!(out.contains("{{ f(); }}"), "{out}");
    assert!(out.contains("{h();}"), "{out}");
    assert!(out.contains("{{ last(); }}"), "{out}");
    assert!(!out.contains("g();") && !out.contains("x = 1"), "{out}");
    let skipped: Vec<&str> = diags
        .iter()
        .filter(|d| d.code == crate::codes::W_C_PRAGMA)
        .map(|d| d.message.as_str())
        .collect();
    assert_eq!(skipped.len(), 2, "{diags:?}");
    assert!(skipped
        .iter()
        .all(|m| m.contains("where a statement may stand")));
}

#[test]
fn var_access_var_inst_and_struct_extends_are_parsed() {
    let src = "FUNCTION_BLOCK fb\nVAR PROTECTED w : INT; END_VAR\nVAR PUBLIC v : INT; END_VAR\n\
               METHOD m\n  VAR_INST n : INT; END_VAR\n  n := n + 1;\nEND_METHOD\nEND_FUNCTION_BLOCK";
    let (p, _) = pou(src);
    let access: Vec<(u32, AccessSpec)> = p.oo.var_access.iter().map(|a| (a.0, a.1)).collect();
    assert_eq!(
        access,
        [(0, AccessSpec::Protected), (1, AccessSpec::Public)]
    );
    assert_eq!(p.oo.methods[0].pou.var_blocks[0].kind, VarKind::Inst);
    let (u, i) = ok(
        "TYPE A : STRUCT x : INT; END_STRUCT; B EXTENDS A : STRUCT y : INT; END_STRUCT; END_TYPE",
    );
    let Item::Type(b) = &u.items[1] else {
        panic!("a type")
    };
    assert_eq!(i.name(b.extends.expect("a base").sym), "A");
}
