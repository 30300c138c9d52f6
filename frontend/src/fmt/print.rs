//! Writing the lines: keywords in upper case, every other token and every comment as
//! written, one space or none between tokens, comments after code at the column they
//! had (or one space after the code), the `:` of a block's declarations aligned.

use super::items::Item;
use super::layout::{Layout, Line};
use crate::st::lexer::Tok;
use std::collections::HashMap;

/// Spaces per indentation level.
const INDENT: usize = 4;

/// The text of item `it`: a keyword in upper case; a `//` comment without trailing
/// blanks; anything else as written.
pub(super) fn item_text(text: &str, it: &Item) -> String {
    let s = &text[it.start..it.end];
    match it.tok {
        Some(t) if t.is_keyword() => s.to_ascii_uppercase(),
        None if s.starts_with("//") => s.trim_end().to_string(),
        _ => s.to_string(),
    }
}

/// The visual column at the end of `s` (tabs to multiples of 4).
fn end_column(s: &str) -> usize {
    let line = s.rfind('\n').map_or(s, |i| &s[i + 1..]);
    line.chars().fold(0, |col, c| {
        if c == '\t' {
            (col / INDENT + 1) * INDENT
        } else {
            col + 1
        }
    })
}

/// Tokens after which a `-` or `+` is a binary operator.
fn ends_operand(t: Tok) -> bool {
    matches!(
        t,
        Tok::Ident
            | Tok::Lit
            | Tok::Address
            | Tok::RParen
            | Tok::RBracket
            | Tok::Caret
            | Tok::True
            | Tok::False
    )
}

/// Whether a space goes between the tokens `a` and `b` (`before_a`: the token before
/// `a`; `label`: it is the `:` of a label).
fn space_between(before_a: Option<Tok>, label: bool, a: Tok, b: Tok) -> bool {
    use Tok::*;
    let unary_a = matches!(a, Minus | Plus) && !before_a.is_some_and(ends_operand);
    if unary_a {
        return false;
    }
    match (a, b) {
        // Never `(*`, which opens a comment.
        (LParen, Star) => true,
        (LParen | LBracket, _) => false,
        (_, RParen | RBracket | Comma | Semi) => false,
        (Lit, Dot) => true,
        (Dot, _) | (_, Dot) => false,
        (DotDot, _) | (_, DotDot) => false,
        (Hash, _) | (_, Hash) => false,
        (String | WString, LParen) => false,
        // A call, but not a type's enumerated values after a declaration's `:`.
        (Ident, LParen) => before_a == Some(Colon) && !label,
        (Ident | Array | String | WString | RBracket | RParen | Caret, LBracket) => false,
        (Ident | RParen | RBracket | Caret, Caret) => false,
        _ => true,
    }
}

/// Writes one line (without its line break); `prev_token[j]`: the index of the token
/// before item `j`. With `pad`, the declaration's `:` goes
/// at that column; with `stop`, the line ends before that item.
fn render_line(
    text: &str,
    items: &[Item],
    prev_token: &[Option<usize>],
    layout: &Layout,
    line: &Line,
    pad: Option<usize>,
    stop: Option<usize>,
) -> String {
    let mut s = " ".repeat(line.indent * INDENT);
    let mut prev: Option<usize> = None;
    for j in line.items.clone() {
        if stop == Some(j) {
            break;
        }
        let it = &items[j];
        if let Some(p) = prev {
            match (items[p].tok, it.tok) {
                (_, None) => {
                    let col = end_column(&s);
                    let target = it.col.max(col + 1);
                    s.extend(std::iter::repeat_n(' ', target - col));
                }
                (None, Some(_)) => s.push(' '),
                (Some(a), Some(b)) => {
                    if line.decl.is_some_and(|(_, c)| c == j) {
                        if let Some(pad) = pad {
                            let col = end_column(&s);
                            s.extend(std::iter::repeat_n(' ', pad.saturating_sub(col).max(1)));
                        } else {
                            s.push(' ');
                        }
                    } else if !layout.glued_colon[j]
                        && space_between(
                            prev_token[p].and_then(|k| items[k].tok),
                            prev_token[p].is_some_and(|k| layout.glued_colon[k]),
                            a,
                            b,
                        )
                    {
                        s.push(' ');
                    }
                }
            }
        }
        s.push_str(&item_text(text, it));
        prev = Some(j);
    }
    s
}

/// The whole text.
pub(super) fn print(text: &str, items: &[Item], layout: &Layout) -> String {
    let mut prev_token = Vec::with_capacity(items.len());
    let mut last = None;
    for (j, it) in items.iter().enumerate() {
        prev_token.push(last);
        if it.tok.is_some() {
            last = Some(j);
        }
    }
    // The column of each block's `:`: one past its longest name part.
    let mut pads: HashMap<usize, usize> = HashMap::new();
    for line in &layout.lines {
        if let Some((block, colon)) = line.decl {
            let prefix = render_line(text, items, &prev_token, layout, line, None, Some(colon));
            let col = end_column(&prefix) + 1;
            let e = pads.entry(block).or_insert(0);
            *e = (*e).max(col);
        }
    }
    let mut out = String::with_capacity(text.len() + text.len() / 8);
    for line in &layout.lines {
        if line.blank_before {
            out.push('\n');
        }
        let pad = line.decl.and_then(|(b, _)| pads.get(&b).copied());
        let s = render_line(text, items, &prev_token, layout, line, pad, None);
        out.push_str(s.trim_end_matches([' ', '\t']));
        out.push('\n');
    }
    out
}
