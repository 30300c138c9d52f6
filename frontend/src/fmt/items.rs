//! The formatter's input: the lexer's tokens and, between them, the comments and
//! pragmas the lexer skips, found again by scanning the gaps between tokens (the lexer
//! keeps every token's byte range, so the gaps are exactly its trivia).

use crate::intern::Interner;
use crate::st::lexer::{self, Tok};
use plcc_ir::diag::{Diagnostic, FileId};

/// A token or a comment, in source order.
#[derive(Clone, Debug)]
pub(super) struct Item {
    /// The token's kind, or `None` for a comment or pragma.
    pub tok: Option<Tok>,
    /// Byte range in the text.
    pub start: usize,
    /// One past the last byte.
    pub end: usize,
    /// Line breaks in the whitespace before the item (2 stands for two or more).
    pub breaks: u8,
    /// The visual column the item starts at in the text (tabs to multiples of 4).
    pub col: usize,
}

impl Item {
    /// True for a comment or a pragma.
    pub fn is_comment(&self) -> bool {
        self.tok.is_none()
    }
}

/// The items of `text`, which must lex without errors. `Err` holds the lexer's
/// diagnostics, or `None` when a gap holds something that is no comment (a lexer
/// this scan does not follow: a bug).
pub(super) fn items(text: &str) -> Result<Vec<Item>, Option<Vec<Diagnostic>>> {
    let mut interner = Interner::new();
    let mut diags = Vec::new();
    let lexed = lexer::lex(FileId(0), text, &mut interner, &mut diags);
    if diags.iter().any(|d| d.is_error()) {
        return Err(Some(diags));
    }
    let mut out = Vec::with_capacity(lexed.tokens.len() + 16);
    let mut pos = 0usize;
    for t in &lexed.tokens {
        let start = t.start as usize;
        let breaks = gap(text, pos, start, &mut out).map_err(|()| None)?;
        if t.kind == Tok::Eof {
            break;
        }
        out.push(Item {
            tok: Some(t.kind),
            start,
            end: t.end as usize,
            breaks,
            col: column(text, start),
        });
        pos = t.end as usize;
    }
    Ok(out)
}

/// The lines the user wrote, from the line breaks before each item (`breaks[k]`, 2
/// for two or more): each line's item range, and whether an empty line comes before
/// it (never before the first).
pub(super) fn source_lines(breaks: &[u8]) -> Vec<(std::ops::Range<usize>, bool)> {
    let mut out = Vec::new();
    let mut i = 0;
    while i < breaks.len() {
        let start = i;
        i += 1;
        while i < breaks.len() && breaks[i] == 0 {
            i += 1;
        }
        out.push((start..i, !out.is_empty() && breaks[start] >= 2));
    }
    out
}

/// The visual column of byte `at` (tabs to multiples of 4).
pub(super) fn column(text: &str, at: usize) -> usize {
    let line_start = text[..at].rfind('\n').map_or(0, |i| i + 1);
    let mut col = 0;
    for c in text[line_start..at].chars() {
        if c == '\t' {
            col = (col / 4 + 1) * 4;
        } else {
            col += 1;
        }
    }
    col
}

/// Scans the gap `text[from..to]`: comments and pragmas become items; the line breaks
/// before each item are counted; the result is the count before the token at `to`.
fn gap(text: &str, from: usize, to: usize, out: &mut Vec<Item>) -> Result<u8, ()> {
    let src = text.as_bytes();
    let mut i = from;
    let mut breaks = 0u8;
    while i < to {
        match src[i] {
            b'\n' => {
                breaks = (breaks + 1).min(2);
                i += 1;
            }
            b' ' | b'\t' | b'\r' | 0x0b | 0x0c => i += 1,
            0xC2 if src.get(i + 1) == Some(&0xA0) => i += 2,
            b'(' if src.get(i + 1) == Some(&b'*') => {
                let end = nested_comment_end(src, i, to);
                push_comment(text, i, end, &mut breaks, out);
                i = end;
            }
            b'/' if src.get(i + 1) == Some(&b'*') => {
                let end = text[i + 2..to].find("*/").map_or(to, |k| i + 2 + k + 2);
                push_comment(text, i, end, &mut breaks, out);
                i = end;
            }
            b'/' if src.get(i + 1) == Some(&b'/') => {
                let end = text[i..to].find('\n').map_or(to, |k| i + k);
                push_comment(text, i, end, &mut breaks, out);
                i = end;
            }
            b'{' => {
                let end = crate::st::pragma::skip(FileId(0), src, i).end.min(to);
                push_comment(text, i, end, &mut breaks, out);
                i = end;
            }
            _ => return Err(()),
        }
    }
    Ok(breaks)
}

fn push_comment(text: &str, start: usize, end: usize, breaks: &mut u8, out: &mut Vec<Item>) {
    out.push(Item {
        tok: None,
        start,
        end,
        breaks: *breaks,
        col: column(text, start),
    });
    *breaks = 0;
}

/// End of the `(* ... *)` comment at `i` (nested comments counted), at most `to`.
pub(super) fn nested_comment_end(src: &[u8], mut i: usize, to: usize) -> usize {
    let mut depth = 0usize;
    while i < to {
        if src[i] == b'(' && src.get(i + 1) == Some(&b'*') {
            depth += 1;
            i += 2;
        } else if src[i] == b'*' && src.get(i + 1) == Some(&b')') {
            depth -= 1;
            i += 2;
            if depth == 0 {
                return i;
            }
        } else {
            i += 1;
        }
    }
    to
}
