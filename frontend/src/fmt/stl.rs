//! `plcc fmt` for the PLC-UD STL: its tokens (its own lexer) and the `(* *)`
//! comments between them, in the lines the user wrote, indented Pascal-style:
//! `begin`/`end`, `var`/`end_var` and `repeat`/`until` one level in; the one
//! statement a `then`, `do` or `else` ending a line controls, one level in (a
//! `begin` there stays at the level of its `if`, `while` or `for`); an `else` at
//! the level of its `if`; a line continuing a statement one level in. Reserved
//! words in upper case, one space or none between tokens, the `:` of a `var`
//! block's declarations aligned, comments at their column as in ST.

use super::items::{column, nested_comment_end, source_lines};
use super::{same_comment, FmtError};
use crate::stl::lexer::{self, Tok};
use plcc_ir::diag::FileId;

/// Spaces per level.
const INDENT: usize = 4;

/// A token or a comment, in source order.
#[derive(Clone, Debug)]
struct Item {
    /// The token's kind, `None` for a comment.
    tok: Option<Tok>,
    start: usize,
    end: usize,
    /// Line breaks before it (2: two or more).
    breaks: u8,
    /// Its column in the text.
    col: usize,
}

/// The items of `text` (which lexes without errors).
fn items(text: &str) -> Result<Vec<Item>, FmtError> {
    let mut interner = crate::intern::Interner::new();
    let mut diags = Vec::new();
    let lexed = lexer::lex(FileId(0), text, &mut interner, &mut diags);
    if diags.iter().any(|d| d.is_error()) {
        return Err(FmtError::Syntax(diags));
    }
    let src = text.as_bytes();
    let mut out = Vec::new();
    let mut pos = 0usize;
    for t in &lexed.tokens {
        let (start, end) = (t.start as usize, t.end as usize);
        // The gap: blanks and comments only.
        let mut i = pos;
        let mut breaks = 0u8;
        while i < start {
            match src[i] {
                b'\n' => {
                    breaks = (breaks + 1).min(2);
                    i += 1;
                }
                b' ' | b'\t' | b'\r' | 0x0b | 0x0c => i += 1,
                b'(' if src.get(i + 1) == Some(&b'*') => {
                    let e = nested_comment_end(src, i, start);
                    out.push(Item {
                        tok: None,
                        start: i,
                        end: e,
                        breaks,
                        col: column(text, i),
                    });
                    breaks = 0;
                    i = e;
                }
                _ => {
                    return Err(FmtError::Internal(
                        "text between tokens that is no comment".into(),
                    ))
                }
            }
        }
        if t.kind == Tok::Eof {
            break;
        }
        out.push(Item {
            tok: Some(t.kind),
            start,
            end,
            breaks,
            col: column(text, start),
        });
        pos = end;
    }
    Ok(out)
}

/// One output line: its items, an empty line before it, its level, and for a
/// declaration the `var` block's number and the item index of its `:`.
struct Line {
    items: std::ops::Range<usize>,
    blank_before: bool,
    indent: usize,
    decl: Option<(usize, usize)>,
}

#[derive(Copy, Clone, PartialEq, Eq)]
enum Block {
    Begin,
    Var,
    Repeat,
}

/// A block open at some line: what it is, its level, the depth of the control
/// stack and of the `if` stack when it opened, its number.
struct Frame {
    kind: Block,
    level: usize,
    ctl: usize,
    ifs: usize,
    id: usize,
}

/// Closes, at the word `closer` (`END`, `END_VAR`, `UNTIL`), the innermost block it
/// ends and those inside it; the control and `if` stacks go back to where they were
/// when that block opened. The block's level, if one was open.
fn close(
    frames: &mut Vec<Frame>,
    ctl: &mut Vec<usize>,
    ifs: &mut Vec<usize>,
    closer: Tok,
) -> Option<usize> {
    let kind = match closer {
        Tok::End => Block::Begin,
        Tok::EndVar => Block::Var,
        _ => Block::Repeat,
    };
    let k = frames.iter().rposition(|f| f.kind == kind)?;
    let f = frames.drain(k..).next()?;
    ctl.truncate(f.ctl);
    ifs.truncate(f.ifs);
    Some(f.level)
}

/// The indentation of each line.
fn layout(items: &[Item]) -> Vec<Line> {
    let tok = |i: usize| items[i].tok;
    let mut frames: Vec<Frame> = Vec::new();
    // The levels of the `if`, `while`, `for` and `else` lines whose one statement
    // is still to come or to end.
    let mut ctl: Vec<usize> = Vec::new();
    // The levels of the `if`s that an `else` may still follow.
    let mut ifs: Vec<usize> = Vec::new();
    let mut paren = 0usize;
    // In the middle of a statement or declaration.
    let mut open = false;
    let mut next_id = 0;
    let mut lines = Vec::new();
    let breaks: Vec<u8> = items.iter().map(|it| it.breaks).collect();
    for (range, blank_before) in source_lines(&breaks) {
        let content = |frames: &[Frame], ctl: &[usize]| {
            let base = frames.last().map_or(0, |f| f.level + 1);
            let from = frames.last().map_or(0, |f| f.ctl);
            match ctl.get(from..).and_then(|c| c.last()) {
                Some(&l) => l + 1,
                None => base,
            }
        };
        let first = range.clone().find(|&j| items[j].tok.is_some());
        let Some(first) = first else {
            // Comments only: indented like the code around (fixed below).
            lines.push(Line {
                items: range,
                blank_before,
                indent: usize::MAX,
                decl: None,
            });
            continue;
        };
        let t = tok(first).expect("a token");
        let indent = match t {
            Tok::End | Tok::EndVar | Tok::Until => {
                match close(&mut frames, &mut ctl, &mut ifs, t) {
                    Some(level) => {
                        open = t == Tok::Until;
                        level
                    }
                    None => content(&frames, &ctl),
                }
            }
            Tok::Else => {
                let from = frames.last().map_or(0, |f| f.ifs);
                let level = if ifs.len() > from {
                    ifs.pop().expect("an if")
                } else {
                    content(&frames, &ctl)
                };
                // The statements of the `then` branch are over.
                let keep = ctl.iter().rposition(|&l| l < level).map_or(0, |k| k + 1);
                ctl.truncate(keep.max(frames.last().map_or(0, |f| f.ctl)));
                open = false;
                level
            }
            Tok::Begin if paren == 0 => {
                // The statement a control line left to come: at that line's level.
                let from = frames.last().map_or(0, |f| f.ctl);
                let level = if ctl.len() > from && !open {
                    ctl.pop().expect("a control line")
                } else {
                    content(&frames, &ctl)
                };
                open = false;
                level
            }
            _ if open || paren > 0 => {
                let closing = t == Tok::RParen && paren <= 1;
                content(&frames, &ctl) + usize::from(!closing)
            }
            _ => content(&frames, &ctl),
        };
        // A declaration of a `var` block: its `:`.
        let decl = match frames.last() {
            Some(f) if f.kind == Block::Var && !open && matches!(t, Tok::Ident(_)) => range
                .clone()
                .find(|&j| tok(j) == Some(Tok::Colon))
                .map(|c| (f.id, c)),
            _ => None,
        };
        // Step over the line's tokens.
        let mut last = None;
        for j in range.clone() {
            let Some(k) = tok(j) else { continue };
            match k {
                Tok::LParen => paren += 1,
                Tok::RParen => paren = paren.saturating_sub(1),
                Tok::Begin | Tok::Var | Tok::Repeat if paren == 0 => {
                    // `then begin` on one line: the begin is the statement.
                    if k == Tok::Begin && j != first {
                        let from = frames.last().map_or(0, |f| f.ctl);
                        if ctl.len() > from {
                            ctl.pop();
                        }
                    }
                    let level = if j == first {
                        indent
                    } else {
                        content(&frames, &ctl)
                    };
                    frames.push(Frame {
                        kind: match k {
                            Tok::Begin => Block::Begin,
                            Tok::Var => Block::Var,
                            _ => Block::Repeat,
                        },
                        level,
                        ctl: ctl.len(),
                        ifs: ifs.len(),
                        id: next_id,
                    });
                    next_id += 1;
                }
                Tok::End | Tok::EndVar if j != first && paren == 0 => {
                    close(&mut frames, &mut ctl, &mut ifs, k);
                }
                Tok::Until if j != first => {
                    close(&mut frames, &mut ctl, &mut ifs, k);
                }
                Tok::If => ifs.push(if j == first {
                    indent
                } else {
                    content(&frames, &ctl)
                }),
                Tok::Else if j != first => {
                    let from = frames.last().map_or(0, |f| f.ifs);
                    if ifs.len() > from {
                        ifs.pop();
                    }
                }
                Tok::Semi if paren == 0 => {
                    // The statement is over, and with it every one-statement
                    // branch it ended.
                    ctl.truncate(frames.last().map_or(0, |f| f.ctl));
                }
                _ => {}
            }
            last = Some(k);
        }
        match last {
            Some(Tok::Then | Tok::Do | Tok::Else) if paren == 0 => {
                ctl.push(indent);
                open = false;
            }
            Some(Tok::Semi | Tok::Begin | Tok::Var | Tok::Repeat | Tok::End | Tok::EndVar) => {
                open = false
            }
            Some(Tok::Dot) => open = false,
            Some(Tok::Pragma) => open = false,
            _ => open = paren > 0 || last.is_some(),
        }
        lines.push(Line {
            items: range,
            blank_before,
            indent,
            decl,
        });
    }
    // A line of comments is indented like the next line of code.
    let mut next = 0;
    for l in lines.iter_mut().rev() {
        if l.indent == usize::MAX {
            l.indent = next;
        } else {
            next = l.indent;
        }
    }
    lines
}

/// The text of an item: a reserved word in upper case, anything else as written.
fn item_text(text: &str, it: &Item) -> String {
    let s = &text[it.start..it.end];
    match it.tok {
        Some(t) if t.is_keyword() && t != Tok::Pragma => s.to_ascii_uppercase(),
        _ => s.to_string(),
    }
}

/// Whether a space goes between the tokens `a` and `b` (`before`: the token
/// before `a`).
fn space_between(before: Option<Tok>, a: Tok, b: Tok) -> bool {
    use Tok::*;
    let operand_end =
        |t: Option<Tok>| matches!(t, Some(Ident(_) | Int(_) | Real | RParen | True | False));
    if matches!(a, Minus | Plus) && !operand_end(before) {
        return false;
    }
    // None after `(`, before `)`, `,`, `;` and `end.`'s dot, between a name and
    // the `(` of its call.
    !matches!(
        (a, b),
        (LParen, _) | (_, RParen | Comma | Semi | Dot) | (Ident(_), LParen)
    )
}

/// Writes the lines.
fn print(text: &str, items: &[Item], lines: &[Line]) -> String {
    let render = |line: &Line, stop: Option<usize>, pad: Option<usize>| -> String {
        let mut s = " ".repeat(line.indent * INDENT);
        let mut prev: Option<usize> = None;
        let mut before: Option<Tok> = None;
        for j in line.items.clone() {
            if stop == Some(j) {
                break;
            }
            let it = &items[j];
            if let Some(p) = prev {
                match (items[p].tok, it.tok) {
                    (_, None) => {
                        let col = s.chars().count();
                        s.extend(std::iter::repeat_n(' ', it.col.max(col + 1) - col));
                    }
                    (None, Some(_)) => s.push(' '),
                    (Some(a), Some(b)) => {
                        if line.decl.is_some_and(|(_, c)| c == j) {
                            let col = s.chars().count();
                            let to = pad.unwrap_or(col + 1);
                            s.extend(std::iter::repeat_n(' ', to.saturating_sub(col).max(1)));
                        } else if space_between(before, a, b) {
                            s.push(' ');
                        }
                        before = Some(a);
                    }
                }
            }
            s.push_str(&item_text(text, it));
            prev = Some(j);
        }
        s
    };
    // The column of each block's `:`.
    let mut pads: std::collections::HashMap<usize, usize> = Default::default();
    for l in lines {
        if let Some((block, colon)) = l.decl {
            let w = render(l, Some(colon), None).trim_end().chars().count() + 1;
            let e = pads.entry(block).or_insert(0);
            *e = (*e).max(w);
        }
    }
    let mut out = String::with_capacity(text.len() + text.len() / 8);
    for l in lines {
        if l.blank_before {
            out.push('\n');
        }
        let pad = l.decl.and_then(|(b, _)| pads.get(&b).copied());
        out.push_str(render(l, None, pad).trim_end());
        out.push('\n');
    }
    out
}

/// Formats one STL file that parsed, its line breaks `\n`.
pub(super) fn format(text: &str) -> Result<String, FmtError> {
    let items = items(text)?;
    let lines = layout(&items);
    let out = print(text, &items, &lines);
    // The same tokens (reserved words without case) and comments, in order.
    let after = items_of(&out)?;
    let same = after.len() == items.len()
        && items.iter().zip(&after).all(|(b, a)| {
            let (tb, ta) = (item_text(text, b), item_text(&out, a));
            b.tok == a.tok
                && if b.tok.is_none() {
                    same_comment(&tb, &ta)
                } else {
                    tb == ta
                }
        });
    if !same {
        return Err(FmtError::Internal(
            "the formatted text has other tokens or comments".into(),
        ));
    }
    Ok(out)
}

fn items_of(text: &str) -> Result<Vec<Item>, FmtError> {
    items(text).map_err(|_| FmtError::Internal("the formatted text does not lex".into()))
}
