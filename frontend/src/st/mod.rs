//! Structured Text: lexer and parser.
//!
//! [`parse`] turns one source file into a [`SourceUnit`]. Syntax errors are reported
//! into `diags` and the parser recovers, so one run reports every independent error of
//! a file; what could not be parsed is left out of the tree.

mod halves;
mod lex_halves;
pub mod lexer;
pub mod literals;
pub mod parser;
pub(crate) mod pragma;

#[cfg(test)]
mod tests;
#[cfg(test)]
mod tests_globals;

use crate::ast::SourceUnit;
use crate::intern::Interner;
use plcc_ir::diag::{Diagnostic, FileId};

/// Parses one Structured Text file. Never panics; errors go to `diags`.
pub fn parse(
    file: FileId,
    text: &str,
    interner: &mut Interner,
    diags: &mut Vec<Diagnostic>,
) -> SourceUnit {
    let first = diags.len();
    let lexed = lex_halves::lex(file, text, interner, diags);
    let unit = match halves::parse(file, text, &lexed, interner, diags) {
        Some(unit) => unit,
        None => parser::parse_tokens(file, text, &lexed, interner, diags),
    };
    // Lexical errors were found first; show everything in source order.
    diags[first..].sort_by_key(|d| d.span.map_or(u32::MAX, |s| s.start));
    unit
}
