//! The lexer's unit tests: literals of every kind, comments and pragmas, addresses,
//! operators and keywords, and error recovery.

use super::*;

fn lx(src: &str) -> (Lexed, Vec<Diagnostic>, Interner) {
    let mut i = Interner::new();
    let mut d = Vec::new();
    let l = lex(FileId(0), src, &mut i, &mut d);
    (l, d, i)
}

fn kinds(src: &str) -> Vec<Tok> {
    let (l, d, _) = lx(src);
    assert!(d.is_empty(), "unexpected diagnostics for {src:?}: {d:?}");
    l.tokens.iter().map(|t| t.kind).collect()
}

fn lit(src: &str) -> Literal {
    let (l, d, _) = lx(src);
    assert!(d.is_empty(), "unexpected diagnostics for {src:?}: {d:?}");
    assert_eq!(
        l.tokens.len(),
        2,
        "{src:?} should be one token: {:?}",
        l.tokens
    );
    assert_eq!(l.tokens[0].kind, Tok::Lit);
    assert_eq!(l.tokens[0].end as usize, src.len());
    l.literal(src, l.tokens[0])
}

fn lit_kind(src: &str) -> LiteralKind {
    lit(src).kind
}

fn errors(src: &str) -> Vec<&'static str> {
    let (_, d, _) = lx(src);
    d.iter().map(|d| d.code).collect()
}

use LiteralKind as L;
use Tok as T;

#[test]
fn integers_and_reals() {
    assert_eq!(lit_kind("123"), L::Int(123));
    assert_eq!(lit_kind("1_000"), L::Int(1000));
    assert_eq!(lit_kind("2#1010_0101"), L::Int(0xA5));
    assert_eq!(lit_kind("8#17"), L::Int(15));
    assert_eq!(lit_kind("16#FF"), L::Int(255));
    assert_eq!(lit_kind("16#ff"), L::Int(255));
    assert_eq!(lit_kind("1.5"), L::Real("1.5".into()));
    assert_eq!(lit_kind("1.5E3"), L::Real("1.5E3".into()));
    assert_eq!(lit_kind("1.0e-3"), L::Real("1.0e-3".into()));
    assert_eq!(lit_kind("1E3"), L::Real("1E3".into()));
    assert_eq!(lit_kind("1_000.000_1"), L::Real("1000.0001".into()));
    assert_eq!(
        lit_kind("170141183460469231731687303715884105727"),
        L::Int(i128::MAX)
    );
}

#[test]
fn ranges_bits_and_members_are_not_reals() {
    assert_eq!(kinds("1..10"), vec![T::Lit, T::DotDot, T::Lit, T::Eof]);
    assert_eq!(kinds("x.3"), vec![T::Ident, T::Dot, T::Lit, T::Eof]);
    assert_eq!(
        kinds("a.b.c"),
        vec![T::Ident, T::Dot, T::Ident, T::Dot, T::Ident, T::Eof]
    );
    assert_eq!(kinds("x.%X3"), vec![T::Ident, T::Dot, T::Address, T::Eof]);
    assert_eq!(
        kinds("E1 := 1E1"),
        vec![T::Ident, T::Assign, T::Lit, T::Eof]
    );
}

#[test]
fn typed_literals() {
    let l = lit("INT#5");
    assert_eq!(l.kind, L::Int(5));
    assert!(l.type_prefix.is_some());
    assert_eq!(lit_kind("INT#-5"), L::Int(-5));
    assert_eq!(lit_kind("DINT#16#FF"), L::Int(255));
    assert_eq!(lit_kind("REAL#1.5"), L::Real("1.5".into()));
    assert_eq!(lit_kind("LREAL#-1.0E10"), L::Real("-1.0E10".into()));
    assert_eq!(lit_kind("BOOL#1"), L::Bool(true));
    assert_eq!(lit_kind("BOOL#0"), L::Bool(false));
    assert_eq!(lit_kind("BOOL#TRUE"), L::Bool(true));
    assert_eq!(lit_kind("bool#false"), L::Bool(false));
    assert_eq!(lit_kind("UINT#2#1010"), L::Int(10));
    assert_eq!(
        lit_kind("STRING#'ABC'"),
        L::String {
            wide: false,
            units: vec![65, 66, 67]
        }
    );
    let (l, _, i) = lx("int#5");
    let p = l.literals[0].type_prefix.unwrap();
    assert_eq!(i.name(p.sym), "INT");
    assert_eq!((p.span.start, p.span.end), (0, 3));
    // Not an elementary type: an enumeration value, left to the parser.
    assert_eq!(
        kinds("Color#Red"),
        vec![T::Ident, T::Hash, T::Ident, T::Eof]
    );
}

#[test]
fn durations_dates_times() {
    const S: i128 = 1_000_000_000;
    let d = |ns: i128| L::Duration { ns, long: false };
    assert_eq!(lit_kind("T#1h2m3s4ms"), d(3723 * S + 4_000_000));
    assert_eq!(lit_kind("TIME#5s"), d(5 * S));
    assert_eq!(lit_kind("t#1.5s"), d(1_500_000_000));
    assert_eq!(lit_kind("T#-5s"), d(-5 * S));
    assert_eq!(lit_kind("T#1d"), d(86_400 * S));
    assert_eq!(lit_kind("T#100us"), d(100_000));
    assert_eq!(lit_kind("T#10ns"), d(10));
    assert_eq!(lit_kind("T#1m_30s"), d(90 * S));
    assert_eq!(lit_kind("T#1.5h"), d(5400 * S));
    assert_eq!(lit_kind("LT#1s"), L::Duration { ns: S, long: true });
    assert_eq!(
        lit_kind("LTIME#1ms"),
        L::Duration {
            ns: 1_000_000,
            long: true
        }
    );
    assert_eq!(
        lit_kind("D#2024-01-31"),
        L::Date {
            days: 19753,
            long: false
        }
    );
    assert_eq!(
        lit_kind("DATE#1970-01-01"),
        L::Date {
            days: 0,
            long: false
        }
    );
    assert_eq!(
        lit_kind("LDATE#1970-01-02"),
        L::Date {
            days: 1,
            long: true
        }
    );
    assert_eq!(
        lit_kind("LD#1970-01-02"),
        L::Date {
            days: 1,
            long: true
        }
    );
    let tod = (12 * 3600 + 30 * 60 + 15) * 1_000_000_000 + 250_000_000;
    assert_eq!(
        lit_kind("TOD#12:30:15.25"),
        L::TimeOfDay {
            ns: tod,
            long: false
        }
    );
    assert_eq!(
        lit_kind("TIME_OF_DAY#12:30:15.25"),
        L::TimeOfDay {
            ns: tod,
            long: false
        }
    );
    assert_eq!(
        lit_kind("LTOD#00:00:01"),
        L::TimeOfDay {
            ns: 1_000_000_000,
            long: true
        }
    );
    let dt = 19753 * 86_400 * S + 45015 * S + 500_000_000;
    assert_eq!(
        lit_kind("DT#2024-01-31-12:30:15.5"),
        L::DateTime {
            ns: dt,
            long: false
        }
    );
    assert_eq!(
        lit_kind("DATE_AND_TIME#2024-01-31-12:30:15.5"),
        L::DateTime {
            ns: dt,
            long: false
        }
    );
    assert_eq!(
        lit_kind("LDT#1970-01-01-00:00:00"),
        L::DateTime { ns: 0, long: true }
    );
    // A duration followed by an operator is not swallowed.
    assert_eq!(kinds("T#5s-x"), vec![T::Lit, T::Minus, T::Ident, T::Eof]);
    assert_eq!(
        kinds("T#1s..T#2.5s"),
        vec![T::Lit, T::DotDot, T::Lit, T::Eof]
    );
    assert_eq!(
        kinds("TOD#12:00..TOD#13:00:00.5"),
        vec![T::Lit, T::DotDot, T::Lit, T::Eof]
    );
    assert_eq!(errors("D#2024-01-31-x"), vec![codes::MALFORMED_DATE_TIME]);
}

#[test]
fn malformed_literals() {
    assert_eq!(errors("T#5x"), vec![codes::MALFORMED_DURATION]);
    assert_eq!(errors("T#"), vec![codes::MALFORMED_DURATION]);
    assert_eq!(errors("D#2024-02-30"), vec![codes::MALFORMED_DATE_TIME]);
    assert_eq!(errors("TOD#25:00:00"), vec![codes::MALFORMED_DATE_TIME]);
    assert_eq!(errors("DT#2024-01-01"), vec![codes::MALFORMED_DATE_TIME]);
    assert_eq!(errors("3#12"), vec![codes::MALFORMED_NUMBER]);
    assert_eq!(errors("2#102"), vec![codes::MALFORMED_NUMBER]);
    assert_eq!(errors("16#"), vec![codes::MALFORMED_NUMBER]);
    assert_eq!(errors("12abc"), vec![codes::MALFORMED_NUMBER]);
    assert_eq!(
        errors("999999999999999999999999999999999999999999"),
        vec![codes::INT_LITERAL_TOO_LARGE]
    );
    assert_eq!(errors("INT#x"), vec![codes::MALFORMED_TYPED_LITERAL]);
    assert_eq!(errors("INT#"), vec![codes::MALFORMED_TYPED_LITERAL]);
    assert_eq!(errors("BOOL#2"), vec![codes::MALFORMED_TYPED_LITERAL]);
    assert_eq!(errors("%Z1"), vec![codes::MALFORMED_ADDRESS]);
    assert_eq!(errors("%IY1"), vec![codes::MALFORMED_ADDRESS]);
    assert_eq!(errors("%IX"), vec![codes::MALFORMED_ADDRESS]);
    assert_eq!(errors("'a$qb'"), vec![codes::INVALID_ESCAPE]);
    // Every malformed literal is still one literal token.
    let (l, _, _) = lx("T#5x");
    assert_eq!(l.tokens.len(), 2);
}

#[test]
fn strings() {
    assert_eq!(
        lit_kind("'a$$b$'c$N$0A'"),
        L::String {
            wide: false,
            units: vec![97, 36, 98, 39, 99, 10, 10]
        }
    );
    assert_eq!(
        lit_kind("\"w$\"$0041\""),
        L::String {
            wide: true,
            units: vec![119, 34, 0x41]
        }
    );
    assert_eq!(
        lit_kind("''"),
        L::String {
            wide: false,
            units: vec![]
        }
    );
    assert_eq!(errors("'abc"), vec![codes::UNTERMINATED_STRING]);
    assert_eq!(errors("'abc\nx"), vec![codes::UNTERMINATED_STRING]);
    assert_eq!(
        errors("\"abc$"),
        vec![codes::UNTERMINATED_STRING, codes::INVALID_ESCAPE]
    );
    // `$` before a multi-byte character must not split it.
    assert_eq!(
        errors("'$\u{e4}"),
        vec![codes::UNTERMINATED_STRING, codes::INVALID_ESCAPE]
    );
}

#[test]
fn comments_and_pragmas() {
    assert_eq!(
        kinds("a (* x (* nested *) y *) b"),
        vec![T::Ident, T::Ident, T::Eof]
    );
    assert_eq!(kinds("a /* x (* y */ b"), vec![T::Ident, T::Ident, T::Eof]);
    assert_eq!(kinds("a // x *)\nb"), vec![T::Ident, T::Ident, T::Eof]);
    assert_eq!(
        kinds("a {attribute 'x'} b"),
        vec![T::Ident, T::Ident, T::Eof]
    );
    assert_eq!(kinds("(*****)x(***)"), vec![T::Ident, T::Eof]);
    assert_eq!(errors("a (* x (* y *)"), vec![codes::UNTERMINATED_COMMENT]);
    assert_eq!(errors("/* x"), vec![codes::UNTERMINATED_COMMENT]);
    assert_eq!(errors("{ x"), vec![codes::UNTERMINATED_COMMENT]);
    let (l, _, _) = lx("a (* \n *) b c");
    assert!(l.tokens[1].newline_before());
    assert!(!l.tokens[2].newline_before());
    assert!(lx("(* x").0.eof_in_error);
}

#[test]
fn addresses() {
    for a in [
        "%IX0.0", "%QW1", "%MD2", "%IB3", "%I*", "%Q*", "%Q0.0", "%MW1.2.3", "%ix1", "%QX0.1",
    ] {
        assert_eq!(kinds(a), vec![T::Address, T::Eof], "{a}");
    }
    assert_eq!(kinds("%IX0.0.."), vec![T::Address, T::DotDot, T::Eof]);
}

#[test]
fn operators_and_keywords() {
    assert_eq!(
        kinds(":= => = <> < <= > >= + - * / ** & ( ) [ ] , ; : . .. ^ #"),
        vec![
            T::Assign,
            T::Arrow,
            T::Eq,
            T::Ne,
            T::Lt,
            T::Le,
            T::Gt,
            T::Ge,
            T::Plus,
            T::Minus,
            T::Star,
            T::Slash,
            T::Pow,
            T::Amp,
            T::LParen,
            T::RParen,
            T::LBracket,
            T::RBracket,
            T::Comma,
            T::Semi,
            T::Colon,
            T::Dot,
            T::DotDot,
            T::Caret,
            T::Hash,
            T::Eof
        ]
    );
    assert_eq!(
        kinds("if Then end_IF"),
        vec![T::If, T::Then, T::EndIf, T::Eof]
    );
    // Contextual words stay names.
    assert_eq!(
        kinds("on with step end method"),
        vec![T::Ident; 5]
            .into_iter()
            .chain([T::Eof])
            .collect::<Vec<_>>()
    );
    let (l, _, i) = lx("Motor_1 motor_1");
    assert_eq!(l.tokens[0].data, l.tokens[1].data);
    assert_eq!(i.name(sym(&l.tokens[0])), "MOTOR_1");
}

#[test]
fn garbage_is_one_error_token() {
    let (l, d, _) = lx("a $?! b \u{20ac}\u{20ac} c");
    assert_eq!(d.len(), 2);
    let k: Vec<Tok> = l.tokens.iter().map(|t| t.kind).collect();
    assert_eq!(
        k,
        vec![T::Ident, T::Error, T::Ident, T::Error, T::Ident, T::Eof]
    );
}

#[test]
fn arbitrary_bytes_never_panic() {
    let mut rng = plcc_ir::rng::Rng(0x1234_5678_9abc_def0);
    for len in 0..400 {
        let mut bytes = Vec::with_capacity(len);
        for _ in 0..len {
            let pool = b"(*)/{}'\"$%#:=.0123456789eE_abcxTtD-+ \n\xc3\xa4\xe2\x82\xac";
            bytes.push(*rng.pick(pool));
        }
        let text = String::from_utf8_lossy(&bytes);
        let (l, _, _) = lx(&text);
        assert_eq!(l.tokens.last().map(|t| t.kind), Some(T::Eof));
        for t in &l.tokens {
            assert!(
                text.is_char_boundary(t.start as usize) && text.is_char_boundary(t.end as usize)
            );
        }
    }
}
