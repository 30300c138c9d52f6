//! `plcc fmt`: Structured Text, Instruction List and STL written again in one layout.
//!
//! A token-stream formatter: the lexer's tokens, with the comments and pragmas found
//! between them (`items`), are split into the lines the user wrote (`layout`: at
//! most one empty line kept in a row; expressions never reflowed), each line indented
//! from the blocks open at its start (POUs and their members, VAR blocks, TYPE and
//! STRUCT, IF, CASE labels and arms, the loops, SFC steps and transitions,
//! continuation lines), and written (`print`) with keywords in upper case, one space
//! or none between tokens, the `:` of the declarations of one VAR block or STRUCT
//! aligned, and comments where they were. Literals and names are written exactly as
//! they were spelt.
//!
//! An Instruction List file has ST's tokens, declarations and POU structure; the IL
//! parser tells which bodies are IL, and their lines are laid out as instructions:
//! one per line at the body's level, a line inside parentheses (`AND(` ... `)`) one
//! level deeper, labels with their `:` against them, the operators in upper case and
//! against a `(` that follows them.
//!
//! STL has a lexer and a block structure of its own (`begin`/`end`, one-statement
//! branches): `stl` lays it out.
//!
//! A file that does not parse is refused with the parser's diagnostics. The result
//! is checked before it is returned: it must lex to the same tokens (keywords
//! compared without case) and the same comments (a comment that starts a line moves
//! its other lines with it), in the same order.

mod items;
mod layout;
mod print;
mod stl;

#[cfg(test)]
mod tests;

use crate::intern::Interner;
use plcc_ir::diag::{Diagnostic, FileId};

/// Why a text was not formatted.
#[derive(Debug)]
pub enum FmtError {
    /// The text does not lex or parse: the front end's diagnostics (file 0, offsets
    /// into the text given).
    Syntax(Vec<Diagnostic>),
    /// The formatter would have changed the program's tokens or comments (a bug of
    /// the formatter; the text is left as it is).
    Internal(String),
}

impl std::fmt::Display for FmtError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            FmtError::Syntax(d) => write!(f, "the text does not parse ({} diagnostics)", d.len()),
            FmtError::Internal(m) => write!(f, "internal formatter error: {m}"),
        }
    }
}

/// Formats one Structured Text file. Its diagnostics, if it does not parse, are for
/// file 0 (`FileId(0)`), at offsets into `text`. Line breaks are written as the
/// text's first one is (`\r\n` or `\n`); the result ends with one line break.
pub fn format_st(text: &str) -> Result<String, FmtError> {
    parsed(|i, d| crate::st::parse(FileId(0), text, i, d))?;
    format_parsed(text, &[])
}

/// What `parse` gives, unless it reports an error: then its diagnostics.
fn parsed<R>(parse: impl FnOnce(&mut Interner, &mut Vec<Diagnostic>) -> R) -> Result<R, FmtError> {
    let mut interner = Interner::new();
    let mut diags = Vec::new();
    let r = parse(&mut interner, &mut diags);
    if diags.iter().any(Diagnostic::is_error) {
        return Err(FmtError::Syntax(diags));
    }
    Ok(r)
}

/// `format` run on `text` with `\r\n` made `\n`; its result written with the line
/// break `text`'s first line ends with.
fn with_lf(
    text: &str,
    format: impl FnOnce(&str) -> Result<String, FmtError>,
) -> Result<String, FmtError> {
    let crlf = text.find('\n').is_some_and(|i| text[..i].ends_with('\r'));
    let out = format(&text.replace("\r\n", "\n"))?;
    Ok(if crlf { out.replace('\n', "\r\n") } else { out })
}

/// Two comments are written the same: their lines compared without the blanks that
/// start them (a comment that starts a line moves its other lines with it).
fn same_comment(a: &str, b: &str) -> bool {
    a.lines()
        .map(str::trim_start)
        .eq(b.lines().map(str::trim_start))
}

/// Formats one Instruction List file (its ST bodies as [`format_st`] does); as
/// [`format_st`] for its diagnostics and line breaks.
pub fn format_il(text: &str) -> Result<String, FmtError> {
    let (_, ranges) = parsed(|i, d| crate::il::parse_with_bodies(FileId(0), text, i, d))?;
    // The ranges are offsets into the text as given; the layout reads the text with
    // `\r\n` made `\n`, so they are mapped there.
    let crs: Vec<usize> = text.match_indices("\r\n").map(|(k, _)| k).collect();
    let lf = |at: usize| at - crs.partition_point(|&k| k < at);
    let ranges: Vec<_> = ranges.iter().map(|r| lf(r.start)..lf(r.end)).collect();
    format_parsed(text, &ranges)
}

/// Formats one file of PLC-UD STL (`stl`): reserved words in upper case, Pascal's
/// indentation; as [`format_st`] for its diagnostics and line breaks.
pub fn format_stl(text: &str) -> Result<String, FmtError> {
    parsed(|i, d| crate::stl::parse(FileId(0), text, i, d))?;
    with_lf(text, stl::format)
}

/// Formats a text that parsed; `il`: the byte ranges of its IL bodies (in the text
/// with `\n` line breaks).
fn format_parsed(text: &str, il: &[std::ops::Range<usize>]) -> Result<String, FmtError> {
    with_lf(text, |text| {
        let items = items::items(text).map_err(|e| match e {
            Some(d) => FmtError::Syntax(d),
            None => FmtError::Internal("text between tokens that is no comment".into()),
        })?;
        let layout = layout::layout(text, &items, il);
        let out = print::print(text, &items, &layout);
        verify(text, &items, &layout.il_op, &out)?;
        Ok(out)
    })
}

/// The formatted text `out` holds the items of `text`, in order, written the same
/// (keywords and the IL operators marked in `il_op` compared without case, comments
/// without the indentation of their lines).
fn verify(text: &str, before: &[items::Item], il_op: &[bool], out: &str) -> Result<(), FmtError> {
    let after = items::items(out)
        .map_err(|_| FmtError::Internal("the formatted text does not lex".into()))?;
    if after.len() != before.len() {
        return Err(FmtError::Internal(format!(
            "{} tokens and comments became {}",
            before.len(),
            after.len()
        )));
    }
    for (k, (b, a)) in before.iter().zip(&after).enumerate() {
        let (mut tb, mut ta) = (print::item_text(text, b), print::item_text(out, a));
        if il_op.get(k).copied().unwrap_or(false) {
            tb.make_ascii_uppercase();
            ta.make_ascii_uppercase();
        }
        let same = if b.is_comment() {
            same_comment(&ta, &tb)
        } else {
            ta == tb
        };
        if a.tok != b.tok || !same {
            return Err(FmtError::Internal(format!(
                "`{tb}` (byte {}) became `{ta}`",
                b.start
            )));
        }
    }
    Ok(())
}
