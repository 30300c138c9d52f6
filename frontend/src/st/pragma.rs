//! Pragmas: `{ ... }` and `{{ ... }}` in Structured Text and Instruction List.
//!
//! IEC 61131-3 leaves a pragma's meaning to the implementation. plcc meets two kinds:
//!
//! - pragmas of other compilers that change nothing plcc compiles: CODESYS and
//!   TwinCAT (`{attribute 'qualified_only'}`, `{warning 'x'}`, `{IF defined(x)}`,
//!   `{region r}`, `{flag noinit}`, ...), Siemens block attributes
//!   (`{S7_Optimized_Access := 'TRUE'}`), matiec's `{disable code generation}`,
//!   `{enable code generation}` and `{#include "f"}`. They are skipped silently.
//! - C code. matiec (the compiler of Beremiz and OpenPLC) copies the text of every
//!   other pragma into the C it generates, so `{{ ... }}` blocks and pragmas such as
//!   `{__SET_VAR(data__->,Q,,TRUE);}` are how their projects inline C. The lexer
//!   lists such pragmas ([`crate::st::lexer::Lexed::c_pragmas`]); the ST parser makes
//!   those standing where a statement may stand statements (`StmtKind::InlineC`),
//!   which the `c` target copies into its C and the others skip with warning W0010;
//!   every other one is skipped with W0010. None is ever read as ST.
//!
//! `{{` ends at the first `}}`, `{` at the first `}` (as in matiec); neither nests.

use crate::codes;
use plcc_ir::diag::{Diagnostic, FileId, Span};

/// A pragma the lexer skips.
pub(crate) struct Skipped {
    /// The byte offset one past its end (the end of the input if it is never closed).
    pub end: usize,
    /// It is never closed.
    pub unterminated: bool,
    /// It holds C code (the parser decides what becomes of it: see
    /// [`crate::st::lexer::Lexed::c_pragmas`]).
    pub c: bool,
    /// Error E0002 for a pragma never closed.
    pub diag: Option<Diagnostic>,
}

/// Warning W0010 for the C pragma at `start..end`: skipped, and why.
pub(crate) fn skipped_c(file: FileId, start: u32, end: u32, why: &str) -> Diagnostic {
    Diagnostic::warning(
        codes::W_C_PRAGMA,
        format!("C code in a pragma is skipped: {why}"),
        Span::new(file, start, end),
    )
    .with_label("this pragma holds C code")
    .with_note(
        "the code around it is compiled without it: whatever the C did does not \
         happen (write it in ST if the program needs it)",
    )
}

/// The C text matiec copies for the C pragma `text` (with its braces): `{{ x }}`
/// becomes the block `{ x }`, `{ x }` its content.
pub fn c_code(text: &str) -> &str {
    if text.starts_with("{{") && text.ends_with("}}") && text.len() >= 4 {
        &text[1..text.len() - 1]
    } else {
        text.strip_prefix('{')
            .and_then(|t| t.strip_suffix('}'))
            .unwrap_or(text)
    }
}

/// Skips the pragma that starts at `start` in `src` (at a `{`).
pub(crate) fn skip(file: FileId, src: &[u8], start: usize) -> Skipped {
    let span = |a: usize, b: usize| Span::new(file, a as u32, b as u32);
    match scan(&src[start..]) {
        Ok((len, kind)) => Skipped {
            end: start + len,
            unterminated: false,
            c: kind == PragmaKind::C,
            diag: None,
        },
        Err(open) => {
            let (o, c) = if open == 2 { ("{{", "}}") } else { ("{", "}") };
            let d = Diagnostic::error(
                codes::UNTERMINATED_COMMENT,
                format!("unterminated pragma: `{o}` has no matching `{c}`"),
                span(start, start + open),
            )
            .with_label("this pragma is never closed");
            Skipped {
                end: src.len(),
                unterminated: true,
                c: false,
                diag: Some(d),
            }
        }
    }
}

/// What a pragma holds.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub(crate) enum PragmaKind {
    /// A pragma of another compiler that changes nothing plcc compiles.
    Known,
    /// C code (matiec copies it into the C it generates).
    C,
}

/// The first words of the pragmas that are not C (compared ignoring case).
const KNOWN: &[&str] = &[
    // CODESYS, TwinCAT
    "attribute",
    "warning",
    "error",
    "info",
    "text",
    "library",
    "messageguid",
    "flag",
    "bitaccess",
    "parameter",
    "if",
    "elsif",
    "else",
    "end_if",
    "define",
    "undefine",
    "region",
    "endregion",
    // matiec: `{disable code generation}`, `{enable code generation}`
    "disable",
    "enable",
];

/// Scans the pragma at the start of `src` (which starts with `{`): its length and
/// kind, or, if it is never closed, `Err` with the length of its opener (`{` or `{{`).
pub(crate) fn scan(src: &[u8]) -> Result<(usize, PragmaKind), usize> {
    debug_assert_eq!(src.first(), Some(&b'{'));
    if src.get(1) == Some(&b'{') {
        let end = find(&src[2..], b"}}").ok_or(2usize)?;
        return Ok((2 + end + 2, PragmaKind::C));
    }
    let end = find(&src[1..], b"}").ok_or(1usize)?;
    Ok((1 + end + 1, classify(&src[1..1 + end])))
}

/// The offset of the first `needle` in `hay`.
fn find(hay: &[u8], needle: &[u8]) -> Option<usize> {
    hay.windows(needle.len()).position(|w| w == needle)
}

/// The kind of a `{ ... }` pragma by its text (without the braces).
fn classify(body: &[u8]) -> PragmaKind {
    let text = String::from_utf8_lossy(body);
    let text = text.trim();
    if text.is_empty() || text.starts_with("#include") {
        return PragmaKind::Known;
    }
    let word_len = text
        .find(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
        .unwrap_or(text.len());
    let (word, rest) = text.split_at(word_len);
    if word.is_empty() {
        return PragmaKind::C;
    }
    // Siemens: `{S7_Optimized_Access := 'TRUE'}`.
    if rest.trim_start().starts_with(":=") {
        return PragmaKind::Known;
    }
    let next = rest.chars().next();
    let word_alone = next.is_none_or(|c| c.is_whitespace() || c == '\'' || c == '"');
    if word_alone && KNOWN.iter().any(|k| k.eq_ignore_ascii_case(word)) && !looks_like_c(rest) {
        PragmaKind::Known
    } else {
        PragmaKind::C
    }
}

/// True if the text after a pragma's first word has marks of C that no pragma of
/// another compiler has outside its '...' strings: `{if (x) __SET_VAR(...)}` is C,
/// `{IF defined (x)}` (CODESYS) is not.
fn looks_like_c(rest: &str) -> bool {
    let mut outside = String::new();
    for (i, part) in rest.split('\'').enumerate() {
        if i % 2 == 0 {
            outside.push_str(part);
            outside.push(' ');
        }
    }
    [";", "->", "__", "&&", "||", "==", "!=", "\""]
        .iter()
        .any(|m| outside.contains(m))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::intern::Interner;
    use crate::st::lexer::{lex, Tok};

    fn kind(s: &str) -> Result<(usize, PragmaKind), usize> {
        scan(s.as_bytes())
    }

    fn lexed(src: &str) -> (Vec<Tok>, Vec<Diagnostic>) {
        let mut diags = Vec::new();
        let mut interner = Interner::new();
        let l = lex(FileId(0), src, &mut interner, &mut diags);
        (l.tokens.iter().map(|t| t.kind).collect(), diags)
    }

    #[test]
    fn known_pragmas() {
        for p in [
            "{attribute 'qualified_only'}",
            "{ attribute 'to_string' }",
            "{warning 'not done'}",
            "{IF defined (x)}",
            "{IF defined(a) AND NOT hasvalue(b, '1')}",
            "{attribute 'my__name;'}",
            "{END_IF}",
            "{region Inputs}",
            "{endregion}",
            "{flag noinit}",
            "{disable code generation}",
            "{enable code generation}",
            "{#include \"lib.st\"}",
            "{S7_Optimized_Access := 'TRUE'}",
            "{}",
            "{ }",
        ] {
            assert_eq!(kind(p), Ok((p.len(), PragmaKind::Known)), "{p}");
        }
    }

    #[test]
    fn c_pragmas() {
        for p in [
            "{__SET_VAR(data__->,CURRENT_TIME,,__CURRENT_TIME)}",
            "{extern int AcquireSDOLock();}",
            "{if (HasAnswer()) __SET_VAR(data__->,STATE, 4)}",
            "{ printf(\"TEST OK\\n\"); fflush(stdout); }",
            "{ReleaseSDOLock();}",
            "{attribute_x(1);}",
            "{error(1);}",
            "{else x = 1;}",
            "{{ x }}",
            "{{\n if (a) { b(); }\n}}",
        ] {
            assert_eq!(kind(p), Ok((p.len(), PragmaKind::C)), "{p}");
        }
    }

    #[test]
    fn ends() {
        // `{` ends at the first `}`, `{{` at the first `}}`: neither nests.
        assert_eq!(kind("{a} b}"), Ok((3, PragmaKind::C)));
        assert_eq!(kind("{{ a } b }} c }}"), Ok((11, PragmaKind::C)));
        assert_eq!(kind("{ x"), Err(1));
        assert_eq!(kind("{{ x }"), Err(2));
        assert_eq!(kind("{{"), Err(2));
    }

    fn c_pragmas_of(src: &str) -> (Vec<Tok>, Vec<(u32, u32)>, Vec<Diagnostic>) {
        let mut diags = Vec::new();
        let mut interner = Interner::new();
        let l = lex(FileId(0), src, &mut interner, &mut diags);
        (
            l.tokens.iter().map(|t| t.kind).collect(),
            l.c_pragmas,
            diags,
        )
    }

    #[test]
    fn c_pragma_is_left_to_the_parser() {
        let src = "IF a THEN\n{{\n  short v = GetFbVar(IN);\n  if (v) { f(); }\n}}\nEND_IF;";
        let (toks, pragmas, diags) = c_pragmas_of(src);
        assert_eq!(
            toks,
            vec![
                Tok::If,
                Tok::Ident,
                Tok::Then,
                Tok::EndIf,
                Tok::Semi,
                Tok::Eof
            ]
        );
        assert!(diags.is_empty(), "{diags:?}");
        let start = src.find("{{").unwrap_or(0) as u32;
        let end = src.find("}}").unwrap_or(0) as u32 + 2;
        assert_eq!(pragmas, vec![(start, end)]);
        let code = c_code(&src[start as usize..end as usize]);
        assert!(
            code.starts_with("{\n  short") && code.ends_with("}\n}"),
            "{code}"
        );
    }

    #[test]
    fn single_brace_c_pragma() {
        let (toks, pragmas, diags) = c_pragmas_of("{__SET_VAR(data__->,Q,,TRUE);}\nq := 1;");
        assert_eq!(
            toks,
            vec![Tok::Ident, Tok::Assign, Tok::Lit, Tok::Semi, Tok::Eof]
        );
        assert!(diags.is_empty(), "{diags:?}");
        assert_eq!(pragmas, vec![(0, 30)]);
        assert_eq!(
            c_code("{__SET_VAR(data__->,Q,,TRUE);}"),
            "__SET_VAR(data__->,Q,,TRUE);"
        );
        assert_eq!(c_code("{{ x; }}"), "{ x; }");
        let known = lexed("{attribute 'x'}");
        assert!(known.1.is_empty());
    }

    #[test]
    fn known_pragma_is_silent() {
        let (toks, diags) = lexed("{attribute 'qualified_only'}\nx {warning 'w'} y");
        assert_eq!(toks, vec![Tok::Ident, Tok::Ident, Tok::Eof]);
        assert!(diags.is_empty(), "{diags:?}");
    }

    #[test]
    fn unterminated() {
        let (toks, diags) = lexed("a {{ x } y");
        assert_eq!(toks, vec![Tok::Ident, Tok::Eof]);
        assert_eq!(diags.len(), 1, "{diags:?}");
        let d = &diags[0];
        assert_eq!(d.code, codes::UNTERMINATED_COMMENT);
        let span = d.span.expect("a span");
        assert_eq!((span.start, span.end), (2, 4));
        assert!(d.message.contains("`}}`"), "{}", d.message);
    }
}
