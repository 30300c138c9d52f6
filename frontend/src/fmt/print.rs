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
        // A repetition in an initial value: `[10(0)]`.
        (Lit, LParen) => false,
        // A call, but not a type's enumerated values after a declaration's `:`.
        (Ident, LParen) => before_a == Some(Colon) && !label,
        (Ident | Array | String | WString | RBracket | RParen | Caret, LBracket) => false,
        (Ident | RParen | RBracket | Caret, Caret) => false,
        _ => true,
    }
}

/// True if item `p` is the `(` right after an IL operator (`AND(`): its operand
/// follows after a space.
fn il_paren_operand(layout: &Layout, prev_token: &[Option<usize>], p: usize) -> bool {
    prev_token[p].is_some_and(|k| layout.il_op[k] && k + 1 == p)
}

/// What rendering a line needs besides the line.
struct Ctx<'a> {
    text: &'a str,
    items: &'a [Item],
    /// Per item: the index of the token before it.
    prev_token: Vec<Option<usize>>,
    layout: &'a Layout,
}

/// Where the parts of a line go that depend on other lines.
#[derive(Copy, Clone, Default)]
struct Place {
    /// The column of the declaration's `:`.
    pad: Option<usize>,
    /// The column of the comment ending the line.
    trail: Option<usize>,
    /// End the line before this item.
    stop: Option<usize>,
}

/// The comment ending `line` after code: its item index.
fn trailing_comment(items: &[Item], line: &Line) -> Option<usize> {
    let last = line.items.end.checked_sub(1)?;
    (last > line.items.start && items[last].is_comment() && !items[last - 1].is_comment())
        .then_some(last)
}

/// A comment's text with the lines after its first moved by `shift` columns, when
/// they all begin with at least that many spaces (else as written).
fn shifted_comment(s: &str, shift: isize) -> String {
    if shift == 0 || !s.contains('\n') {
        return s.to_string();
    }
    let mut lines = s.split('\n');
    let first = lines.next().unwrap_or("");
    let rest: Vec<&str> = lines.collect();
    let movable = rest.iter().all(|l| {
        let spaces = l.len() - l.trim_start_matches(' ').len();
        l.trim().is_empty()
            || (!l[spaces..].starts_with('\t') && (shift > 0 || spaces >= shift.unsigned_abs()))
    });
    if !movable {
        return s.to_string();
    }
    let mut out = first.to_string();
    for l in rest {
        out.push('\n');
        if l.trim().is_empty() {
            out.push_str(l);
        } else if shift > 0 {
            out.extend(std::iter::repeat_n(' ', shift as usize));
            out.push_str(l);
        } else {
            out.push_str(&l[shift.unsigned_abs()..]);
        }
    }
    out
}

impl Ctx<'_> {
    /// Writes one line (without its line break).
    fn render_line(&self, line: &Line, place: Place) -> String {
        let items = self.items;
        let mut s = " ".repeat(line.indent * INDENT);
        let mut prev: Option<usize> = None;
        for j in line.items.clone() {
            if place.stop == Some(j) {
                break;
            }
            let it = &items[j];
            if let Some(p) = prev {
                match (items[p].tok, it.tok) {
                    (_, None) => {
                        let col = end_column(&s);
                        let at = if Some(j) == trailing_comment(items, line) {
                            place.trail.unwrap_or(it.col)
                        } else {
                            it.col
                        };
                        s.extend(std::iter::repeat_n(' ', at.max(col + 1) - col));
                    }
                    (None, Some(_)) => s.push(' '),
                    (Some(a), Some(b)) => {
                        if line.decl.is_some_and(|(_, c)| c == j) {
                            let col = end_column(&s);
                            let pad = place.pad.unwrap_or(0);
                            s.extend(std::iter::repeat_n(' ', pad.saturating_sub(col).max(1)));
                        } else if a == Tok::LParen
                            && il_paren_operand(self.layout, &self.prev_token, p)
                        {
                            // `AND( x`: the operand of a parenthesised IL operator.
                            s.push(' ');
                        } else if !(self.layout.glued[j]
                            // `AND(`: an IL operator against its parenthesis.
                            || self.layout.il_op[p] && b == Tok::LParen)
                            && space_between(
                                self.prev_token[p].and_then(|k| items[k].tok),
                                self.prev_token[p].is_some_and(|k| self.layout.glued[k]),
                                a,
                                b,
                            )
                        {
                            s.push(' ');
                        }
                    }
                }
            }
            let mut t = item_text(self.text, it);
            if self.layout.il_op[j] {
                t.make_ascii_uppercase();
            }
            if it.is_comment() && prev.is_none() {
                // A comment starting the line: its other lines move with it.
                let shift = (line.indent * INDENT) as isize - it.col as isize;
                s.push_str(&shifted_comment(&t, shift));
            } else {
                s.push_str(&t);
            }
            prev = Some(j);
        }
        s
    }
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
    let cx = Ctx {
        text,
        items,
        prev_token,
        layout,
    };
    let lines = &layout.lines;
    let mut places = vec![Place::default(); lines.len()];
    // The column of each block's `:`: one past its longest name part.
    let mut pads: HashMap<usize, usize> = HashMap::new();
    for line in lines {
        if let Some((block, colon)) = line.decl {
            let prefix = cx.render_line(
                line,
                Place {
                    stop: Some(colon),
                    ..Place::default()
                },
            );
            let e = pads.entry(block).or_insert(0);
            *e = (*e).max(end_column(&prefix) + 1);
        }
    }
    for (line, place) in lines.iter().zip(&mut places) {
        place.pad = line.decl.and_then(|(b, _)| pads.get(&b).copied());
    }
    // Comments ending consecutive lines at one column stay aligned: at that column,
    // or one past the longest code among them.
    let mut k = 0;
    while k < lines.len() {
        let Some(c) = trailing_comment(items, &lines[k]) else {
            k += 1;
            continue;
        };
        let col = items[c].col;
        let mut end = k;
        let mut target = col;
        while end < lines.len() {
            let Some(c) = trailing_comment(items, &lines[end]) else {
                break;
            };
            if items[c].col != col || (end > k && lines[end].blank_before) {
                break;
            }
            let code = cx.render_line(
                &lines[end],
                Place {
                    stop: Some(c),
                    ..places[end]
                },
            );
            target = target.max(end_column(&code) + 1);
            end += 1;
        }
        for place in &mut places[k..end] {
            place.trail = Some(target);
        }
        k = end;
    }
    let mut out = String::with_capacity(text.len() + text.len() / 8);
    for (line, place) in lines.iter().zip(&places) {
        if line.blank_before {
            out.push('\n');
        }
        let s = cx.render_line(line, *place);
        out.push_str(s.trim_end_matches([' ', '\t']));
        out.push('\n');
    }
    out
}
