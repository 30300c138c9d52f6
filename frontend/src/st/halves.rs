//! A large Structured Text file parsed in two halves at once.
//!
//! The tokens are split where a POU starts right after another one ends (a top-level
//! boundary, if the file parses cleanly). The first half is parsed on the calling
//! thread with the build's interner; the second on another thread, with a copy of
//! it. The result is used only when it must equal a parse of the whole file:
//!
//! - neither half reported an error (a half that starts or ends inside a construct
//!   reports one: an unclosed block, or a closer without its opener);
//! - the second half interned no name its copy did not already hold (the lexer has
//!   interned every identifier; the parser adds a name only for a few spellings), so
//!   its symbols mean the same in the build's interner;
//! - the file holds no C pragma (the parser takes them in order across the file).
//!
//! Otherwise the file is parsed whole, as small files always are. A test parses
//! every ST file of the repository and of `../shared` both ways, split at up to 24
//! boundaries each, and compares the trees and the diagnostics.

use super::lexer::{Lexed, Tok, Token};
use super::parser;
use crate::ast::SourceUnit;
use crate::intern::Interner;
use plcc_ir::diag::{Diagnostic, FileId, Severity};

/// Files with fewer tokens are parsed whole: a thread would cost more than it saves.
const MIN_TOKENS: usize = 100_000;

/// Parses `lexed` (all of `text`), in two halves on two threads when the file is
/// large and the machine has two cores; `None` if it must be parsed whole.
pub(super) fn parse(
    file: FileId,
    text: &str,
    lexed: &Lexed,
    interner: &mut Interner,
    diags: &mut Vec<Diagnostic>,
) -> Option<SourceUnit> {
    if lexed.tokens.len() < MIN_TOKENS || plcc_ir::parallel::threads() < 2 {
        return None;
    }
    let split = split_point(lexed, lexed.tokens.len() / 2)?;
    parse_at(file, text, lexed, split, interner, diags)
}

/// The first token at or after `from` that starts a POU right after the end of one,
/// on a new line.
fn split_point(lexed: &Lexed, from: usize) -> Option<usize> {
    if !lexed.c_pragmas.is_empty() || lexed.eof_in_error {
        return None;
    }
    let toks = &lexed.tokens;
    (from.max(1)..toks.len()).find(|&i| is_boundary(toks[i - 1], toks[i]))
}

fn is_boundary(before: Token, t: Token) -> bool {
    matches!(
        before.kind,
        Tok::EndProgram | Tok::EndFunction | Tok::EndFunctionBlock
    ) && matches!(t.kind, Tok::Program | Tok::Function | Tok::FunctionBlock)
        && t.newline_before()
}

/// Parses the tokens before `split` here and those from `split` on on another
/// thread; `None` (and nothing reported) if the halves may differ from the whole.
fn parse_at(
    file: FileId,
    text: &str,
    lexed: &Lexed,
    split: usize,
    interner: &mut Interner,
    diags: &mut Vec<Diagnostic>,
) -> Option<SourceUnit> {
    let toks = &lexed.tokens;
    // The first half ends as a file does, at the second half's first token.
    let at = toks[split].start;
    let eof = Token {
        kind: Tok::Eof,
        flags: 0,
        start: at,
        end: at,
        data: 0,
    };
    parser::intern_contextual_words(interner);
    let mut copy = interner.clone();
    let known = copy.len();
    let (mut first_diags, mut second_diags) = (Vec::new(), Vec::new());
    let ((a, _), (b, _)) = plcc_ir::parallel::join(
        || {
            parser::parse_range(
                file,
                text,
                lexed,
                &toks[..split],
                Some(eof),
                interner,
                &mut first_diags,
                None,
            )
        },
        || {
            parser::parse_range(
                file,
                text,
                lexed,
                &toks[split..],
                None,
                &mut copy,
                &mut second_diags,
                None,
            )
        },
    );
    let error = |d: &Vec<Diagnostic>| d.iter().any(|d| d.severity == Severity::Error);
    if error(&first_diags) || error(&second_diags) || copy.len() != known {
        // The halves' diagnostics are dropped with them; the whole parse reports.
        // Names the first half interned stay: interning is idempotent.
        return None;
    }
    diags.append(&mut first_diags);
    diags.append(&mut second_diags);
    let mut items = a.items;
    items.extend(b.items);
    Some(SourceUnit { file, items })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Parses each file whole and in halves at up to 24 of its boundaries (spread
    /// over the file); returns the splits compared and those refused.
    fn compare(files: &[(String, String)]) -> (usize, usize) {
        let (mut compared, mut refused) = (0, 0);
        for (name, text) in files {
            let file = FileId(0);
            let mut interner = Interner::new();
            let mut lex_diags = Vec::new();
            let lexed = super::super::lexer::lex(file, text, &mut interner, &mut lex_diags);
            let whole = {
                let (mut i, mut d) = (interner.clone(), Vec::new());
                let u = parser::parse_tokens(file, text, &lexed, &mut i, &mut d);
                (format!("{u:?}"), format!("{d:?}"))
            };
            let mut splits = Vec::new();
            let mut from = 1;
            while let Some(split) = split_point(&lexed, from) {
                from = split + 1;
                splits.push(split);
            }
            let step = splits.len().div_ceil(24).max(1);
            for &split in splits.iter().step_by(step) {
                let (mut i, mut d) = (interner.clone(), Vec::new());
                match parse_at(file, text, &lexed, split, &mut i, &mut d) {
                    Some(u) => {
                        compared += 1;
                        assert_eq!(format!("{u:?}"), whole.0, "{name}, split at token {split}");
                        // Each half's warnings come in order, the first half's first.
                        assert_eq!(format!("{d:?}"), whole.1, "{name}, split at token {split}");
                    }
                    None => refused += 1,
                }
            }
        }
        (compared, refused)
    }

    #[test]
    fn a_large_clean_file_is_parsed_in_halves_and_one_with_an_error_whole() {
        let fb = |k: usize| {
            format!(
                "FUNCTION_BLOCK F{k}\nVAR_INPUT a : INT; END_VAR\nVAR x : INT; END_VAR\n\
                 x := (a * {k}) - (x + 1);\nIF x > 3 THEN x := 0; END_IF;\nEND_FUNCTION_BLOCK\n"
            )
        };
        let text: String = (0..4000).map(fb).collect();
        let file = FileId(0);
        let mut interner = Interner::new();
        let mut diags = Vec::new();
        let lexed = super::super::lexer::lex(file, &text, &mut interner, &mut diags);
        assert!(lexed.tokens.len() >= MIN_TOKENS);
        let (mut i, mut d) = (interner.clone(), Vec::new());
        let whole = parser::parse_tokens(file, &text, &lexed, &mut i, &mut d);
        if plcc_ir::parallel::threads() >= 2 {
            let halves = parse(file, &text, &lexed, &mut interner, &mut diags);
            let halves = halves.expect("parsed in halves");
            assert_eq!(format!("{halves:?}"), format!("{whole:?}"));
            assert!(diags.is_empty() && d.is_empty());
        } else {
            eprintln!("NOTICE: one core: the halves were not tried");
        }
        // An END_IF missing in the last POU: the halves refuse, the whole reports.
        let broken = text.replacen(
            "END_IF;\nEND_FUNCTION_BLOCK\nFUNCTION_BLOCK F3999",
            "\nEND_FUNCTION_BLOCK\nFUNCTION_BLOCK F3999",
            1,
        );
        assert_ne!(broken, text);
        let lexed = super::super::lexer::lex(file, &broken, &mut interner, &mut diags);
        let split = split_point(&lexed, lexed.tokens.len() / 2).expect("a boundary");
        assert!(parse_at(file, &broken, &lexed, split, &mut interner, &mut diags).is_none());
        assert!(diags.is_empty(), "the refused halves report nothing");
    }

    #[test]
    fn halves_parse_as_the_whole_file_at_its_boundaries() {
        // Most of ../shared's files hold one POU.
        crate::test_files::compare_over_st_files("splits", (100, 50), compare);
    }
}
