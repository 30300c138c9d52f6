//! Printer tests: literals in their canonical spelling, parentheses where precedence
//! needs them (random trees printed and read back), every kind of item printed to a
//! text that reads back to itself, comments between statements, IL's temporaries
//! and jumps.

use super::*;
use plcc_ir::rng::Rng;

fn parse(src: &str) -> (SourceUnit, Interner) {
    let mut i = Interner::new();
    let mut d = Vec::new();
    let u = crate::st::parse(FileId(0), src, &mut i, &mut d);
    assert!(d.is_empty(), "diagnostics for\n{src}\n{d:?}");
    (u, i)
}

/// `src` parsed and printed (as source text, with the text for names and comments).
fn printed(src: &str) -> String {
    let (u, i) = parse(src);
    Printer::new(&i).with_source(src).unit(&u)
}

/// The statements of the first POU of `src`, printed in `style`.
fn body(src: &str, style: Style) -> String {
    let (u, i) = parse(src);
    let Some(Item::Pou(p)) = u.items.first() else {
        panic!("no POU");
    };
    Printer::new(&i)
        .with_source(src)
        .with_style(style)
        .stmts(&p.body.stmts)
}

fn program(stmts: &str) -> String {
    format!("PROGRAM p\nVAR a, b, c, d : INT; x, y : BOOL; END_VAR\n{stmts}\nEND_PROGRAM\n")
}

#[test]
fn literals_in_canonical_spelling() {
    let cases = [
        ("T#1h2m3s4ms5us6ns", "T#1h2m3s4ms5us6ns"),
        ("T#90m", "T#1h30m"),
        ("TIME#-1.5s", "T#-1s500ms"),
        ("T#0s", "T#0s"),
        ("LTIME#1d", "LT#1d"),
        ("D#2024-02-29", "D#2024-02-29"),
        ("DATE#1970-01-01", "D#1970-01-01"),
        ("TOD#12:30:15.5", "TOD#12:30:15.5"),
        ("DT#2001-09-09-01:46:40", "DT#2001-09-09-01:46:40"),
        ("'a$N$$$'b'", "'a$N$$$'b'"),
        ("\"w$\"\"", "\"w$\"\""),
        ("INT#-7", "INT#-7"),
        ("16#FF", "255"),
        ("2#1010_1010", "170"),
        ("1.5E3", "1.5E3"),
        ("TRUE", "TRUE"),
        ("BOOL#1", "BOOL#TRUE"),
    ];
    for (lit, want) in cases {
        let got = body(&program(&format!("a := {lit};")), Style::Source);
        assert_eq!(got.trim(), format!("a := {want};"), "for {lit}");
        // What is printed reads back to the same value.
        let again = body(&program(&format!("a := {want};")), Style::Source);
        assert_eq!(again, got, "for {want}");
    }
}

#[test]
fn parentheses_where_written_and_where_needed() {
    let cases = [
        ("a := (b + c) * d;", "a := (b + c) * d;"),
        ("a := b + c * d;", "a := b + c * d;"),
        ("a := b - (c - d);", "a := b - (c - d);"),
        ("a := -b ** 2;", "a := -b ** 2;"),
        ("x := NOT (x AND y);", "x := NOT (x AND y);"),
        ("x := a < b = (c < d);", "x := a < b = (c < d);"),
    ];
    for (src, want) in cases {
        assert_eq!(body(&program(src), Style::Source).trim(), want);
    }
    assert_eq!(
        body(&program("a := b + c * d - -5;"), Style::Tree),
        "a := ((b + (c * d)) - (-5));"
    );
}

/// A random expression over INT variables with every binary and prefix operator.
fn random_expr(rng: &mut Rng, depth: u32) -> String {
    if depth == 0 || rng.index(4) == 0 {
        return rng.pick(&["a", "b", "c", "d", "1", "-2", "7"]).to_string();
    }
    match rng.index(8) {
        0 => format!("-{}", random_expr(rng, depth - 1)),
        1 => format!("NOT {}", random_expr(rng, depth - 1)),
        2 => format!("({})", random_expr(rng, depth - 1)),
        _ => {
            let op = *rng.pick(&[
                "OR", "XOR", "AND", "=", "<>", "<", ">=", "+", "-", "*", "/", "MOD", "**",
            ]);
            format!(
                "{} {op} {}",
                random_expr(rng, depth - 1),
                random_expr(rng, depth - 1)
            )
        }
    }
}

/// The tree of an expression (every operation in parentheses) with its `Paren`
/// nodes removed: what the printer must keep.
fn shape(src: &str) -> String {
    body(&program(&format!("a := {src};")), Style::Tree)
        .replace(['(', ')'], "")
        .to_ascii_uppercase()
}

#[test]
fn random_expressions_print_to_the_same_tree() {
    let mut rng = Rng(0x2545_F491_4F6C_DD1D);
    for _ in 0..2000 {
        let src = random_expr(&mut rng, 5);
        let (u, i) = parse(&program(&format!("a := {src};")));
        let Some(Item::Pou(p)) = u.items.first() else {
            panic!("no POU");
        };
        let StmtKind::Assign { value, .. } = &p.body.stmts[0].kind else {
            panic!("not an assignment");
        };
        // Without its written parentheses the tree needs the printer's own.
        let bare = strip_parens(value.clone());
        let text = Printer::new(&i).expr(&bare);
        let want = tree(&bare, &i);
        let (u2, i2) = parse(&program(&format!("a := {text};")));
        let Some(Item::Pou(p2)) = u2.items.first() else {
            panic!("no POU");
        };
        let StmtKind::Assign { value: v2, .. } = &p2.body.stmts[0].kind else {
            panic!("not an assignment");
        };
        assert_eq!(
            tree(&strip_parens(v2.clone()), &i2),
            want,
            "{src}\nprinted {text}"
        );
        assert_eq!(shape(&text), shape(&src), "{src}");
    }
}

fn strip_parens(mut e: Expr) -> Expr {
    struct Strip;
    impl<'a> crate::visit::VisitorMut<'a> for Strip {
        fn visit_expr(&mut self, e: &'a mut Expr) {
            while let ExprKind::Paren(inner) = &mut e.kind {
                *e = std::mem::replace(
                    inner,
                    Expr {
                        kind: ExprKind::Name(Ident {
                            sym: Symbol(0),
                            span: e.span,
                        }),
                        span: e.span,
                    },
                );
            }
            crate::visit::walk_expr_mut(self, e);
        }
    }
    crate::visit::VisitorMut::visit_expr(&mut Strip, &mut e);
    e
}

const EVERYTHING: &str = "TYPE
    Color : (Red, Green := 5, Blue) INT;
    Small : INT(-10..10) := 3;
    Point : STRUCT
        x, y : REAL := 1.5;
        tag : STRING[20] := 'p';
    END_STRUCT;
    Point3 EXTENDS Point : STRUCT
        z : REAL;
    END_STRUCT;
    Grid : ARRAY[1..3, 0..1] OF INT := [2(1), 4(0)];
END_TYPE

VAR_GLOBAL CONSTANT
    limit : INT := 100;
END_VAR

INTERFACE ICounter
    METHOD Count : INT
        VAR_INPUT
            step : INT;
        END_VAR
    END_METHOD
END_INTERFACE

FUNCTION_BLOCK Counter IMPLEMENTS ICounter
    VAR_INPUT
        up : BOOL R_EDGE;
    END_VAR
    VAR_OUTPUT
        cv : INT;
    END_VAR
    VAR
        where AT %MW4 : WORD;
        p : Point := (x := 2.0, tag := 'q');
        r : REF_TO INT;
    END_VAR
    METHOD PUBLIC Count : INT
        VAR_INPUT
            step : INT;
        END_VAR
        cv := cv + step;
        Count := cv;
    END_METHOD
    PROPERTY Value : INT
        GET
            Value := cv;
        END_GET
        SET
            cv := Value;
        END_SET
    END_PROPERTY
    IF up THEN
        Count(step := 1);
    END_IF;
    r REF= cv;
    ACTION Reset:
        cv := 0;
    END_ACTION
END_FUNCTION_BLOCK

PROGRAM main
    VAR
        c : Counter;
        k : INT;
        col : Color := Color#Green;
        flag : BOOL;
    END_VAR
    c(up := flag, cv => k);
    CASE k OF
        1, 2..5:
            k := 0;
        ELSE
            FOR k := 10 TO 0 BY -2 DO
                EXIT;
            END_FOR;
    END_CASE;
    WHILE k < 3 DO
        k := k + 1;
    END_WHILE;
    REPEAT
        k := k - 1;
    UNTIL k <= 0
    END_REPEAT;
    flag := %IX0.1 AND k.3;
    c.Reset();
END_PROGRAM

CONFIGURATION plant
    RESOURCE cpu ON PLC
        TASK fast(INTERVAL := T#10ms, PRIORITY := 1);
        PROGRAM run1 WITH fast : main;
    END_RESOURCE
END_CONFIGURATION
";

#[test]
fn every_kind_of_item_reads_back_to_itself() {
    let once = printed(EVERYTHING);
    assert_eq!(printed(&once), once, "not a fixed point:\n{once}");
    // The parts a reader would look for, as written.
    for part in [
        "Color : (Red, Green := 5, Blue) INT;",
        "Small : INT(-10..10) := 3;",
        "Point3 EXTENDS Point : STRUCT",
        "Grid : ARRAY[1..3, 0..1] OF INT := [2(1), 4(0)];",
        "VAR_GLOBAL CONSTANT",
        "FUNCTION_BLOCK Counter IMPLEMENTS ICounter",
        "up : BOOL R_EDGE;",
        "where AT %MW4 : WORD;",
        "p : Point := (x := 2.0, tag := 'q');",
        "METHOD PUBLIC Count : INT",
        "    PROPERTY Value : INT\n        GET\n",
        "r REF= cv;",
        "    ACTION Reset:\n        cv := 0;\n    END_ACTION",
        "col : Color := Color#Green;",
        "c(up := flag, cv => k);",
        "        1, 2..5:\n            k := 0;\n        ELSE\n",
        "FOR k := 10 TO 0 BY -2 DO",
        "UNTIL k <= 0\n    END_REPEAT;",
        "flag := %IX0.1 AND k.3;",
        "TASK fast(INTERVAL := T#10ms, PRIORITY := 1);",
        "PROGRAM run1 WITH fast : main;",
    ] {
        assert!(once.contains(part), "no {part:?} in\n{once}");
    }
}

#[test]
fn comments_between_and_after_statements_and_declarations_are_kept() {
    let src = "(* the head *)
PROGRAM p
VAR
  (* counts *)
  a : INT; // the count
END_VAR
(* before the first *)
a := 1; // after one
IF a > 0 THEN
    (* inside *)
    a := 2;
    (* before END_IF *)
END_IF;
(* at the end *)
END_PROGRAM
";
    assert_eq!(
        printed(src),
        "(* the head *)
PROGRAM p
    VAR
        (* counts *)
        a : INT; // the count
    END_VAR
    (* before the first *)
    a := 1; // after one
    IF a > 0 THEN
        (* inside *)
        a := 2;
        (* before END_IF *)
    END_IF;
    (* at the end *)
END_PROGRAM
"
    );
}

#[test]
fn il_temporaries_and_jumps() {
    let src = "PROGRAM p
VAR a, b : INT; x : BOOL; END_VAR
    LD a
    ADD b
    ST a
    GT 10
    ST x
    JMPC done
    LD 0
    ST a
done:
    LD a
END_PROGRAM
";
    let mut i = Interner::new();
    let mut d = Vec::new();
    let u = crate::il::parse(FileId(0), src, &mut i, &mut d);
    assert!(d.is_empty(), "{d:?}");
    let mut temps = TempTypes::new();
    let mut lets = Vec::new();
    let Some(Item::Pou(p)) = u.items.first() else {
        panic!("no POU");
    };
    crate::visit::each_stmt(&p.body.stmts, &mut |s| {
        if let StmtKind::Let { name, .. } = &s.kind {
            lets.push(*name);
        }
    });
    assert!(!lets.is_empty(), "the IL made no temporary");
    for l in &lets {
        temps.insert((FileId(0), l.sym), TempType::Value("INT".into()));
    }
    let out = Printer::new(&i)
        .with_source(src)
        .with_temps(&temps)
        .unit(&u);
    let cr = i.name(lets[0].sym);
    assert!(
        out.contains(&format!("    VAR_TEMP\n        {cr} : INT;\n")),
        "{out}"
    );
    assert!(out.contains("JMP done;"), "{out}");
    assert!(out.contains("    done:\n"), "{out}");
    // What it printed is ST that parses.
    parse(&out);
}
