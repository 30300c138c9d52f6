//! Doc comments: the comment an engineer wrote to describe a declaration, found in
//! the text around it (the syntax trees keep no comments).
//!
//! Where it is looked for, in order: for a variable, a field or an enumeration value,
//! a comment after it on the same line (`speed : INT; (* rpm *)`); for every
//! declaration, a comment right before it (no empty line between, nothing else on
//! the comment's first line); for a POU or METHOD, the comment that opens its body
//! after the last VAR block (where OSCAT and CODESYS 2 exports put their
//! descriptions). Comments starting with `@` are CODESYS attributes, not docs; in the
//! view of a PLCopen file, the `(* network n *)` comments plcc writes before each
//! network of a diagram are not a POU's doc either.

use super::index::Decl;
use plcc_frontend::source::SourceMap;

/// At most this many lines of a doc comment go into a hover.
const MAX_LINES: usize = 30;

/// The doc comment of `d`, without its delimiters, if it has one.
pub fn doc_comment(sources: &SourceMap, d: &Decl<'_>) -> Option<String> {
    let span = d.span();
    let text: &str = &sources.get(span.file).text;
    let (start, end) = (span.start as usize, span.end as usize);
    if start > end || end > text.len() {
        return None;
    }
    let trailing = || match d {
        Decl::Var { .. } | Decl::Field { .. } | Decl::EnumValue { .. } => after_on_line(text, end),
        _ => None,
    };
    let opening = || {
        let blocks = match d {
            Decl::Pou(p) => &p.var_blocks,
            Decl::Method(_, m) => &m.pou.var_blocks,
            _ => return None,
        };
        let last = blocks.last()?.span.end as usize;
        let rest = text.get(last..end)?;
        let skip = rest.len() - rest.trim_start().len();
        let (a, b) = comment_at(text, last + skip)?;
        let view = sources
            .get(span.file)
            .name
            .ends_with(&plcc_frontend::plcopen::il_view_name(""));
        (!(view && is_network_mark(&text[a..b]))).then_some((a, b))
    };
    let found = |r: Option<(usize, usize)>| r.and_then(|(a, b)| clean(&text[a..b]));
    found(trailing())
        .or_else(|| found(before(text, start)))
        .or_else(|| found(opening()))
}

/// True for `(* network 3 *)`, the comment the view of a PLCopen file writes before
/// each network of a diagram.
fn is_network_mark(comment: &str) -> bool {
    comment
        .strip_prefix("(* network ")
        .and_then(|r| r.strip_suffix(" *)"))
        .is_some_and(|n| !n.is_empty() && n.bytes().all(|b| b.is_ascii_digit()))
}

/// The comment starting at byte `i`, as a byte range.
fn comment_at(text: &str, i: usize) -> Option<(usize, usize)> {
    let rest = text.get(i..)?;
    let close = |open: &str, close: &str| {
        rest.strip_prefix(open)?;
        rest[open.len()..]
            .find(close)
            .map(|k| (i, i + open.len() + k + close.len()))
    };
    if rest.starts_with("//") {
        Some((i, i + rest.find('\n').unwrap_or(rest.len())))
    } else {
        close("(*", "*)").or_else(|| close("/*", "*/"))
    }
}

/// A comment on the same line after byte `end` (past a `;`).
fn after_on_line(text: &str, end: usize) -> Option<(usize, usize)> {
    let rest = text.get(end..)?;
    let rest_t = rest.trim_start_matches([' ', '\t']);
    let rest_t = rest_t
        .strip_prefix(';')
        .unwrap_or(rest_t)
        .trim_start_matches([' ', '\t']);
    comment_at(text, end + (rest.len() - rest_t.len()))
}

/// A comment right before byte `start`: ending on the line before it (or on its
/// line), with nothing but blanks before the comment on the comment's first line.
fn before(text: &str, start: usize) -> Option<(usize, usize)> {
    let head = text.get(..start)?;
    let j = head.trim_end().len();
    if head[j..].matches('\n').count() > 1 {
        return None;
    }
    let line_start = |k: usize| head[..k].rfind('\n').map_or(0, |n| n + 1);
    let alone = |k: usize| head[line_start(k)..k].trim().is_empty();
    if head[..j].ends_with("*)") || head[..j].ends_with("*/") {
        let open = if head[..j].ends_with("*)") {
            "(*"
        } else {
            "/*"
        };
        let k = head[..j - 2].rfind(open)?;
        return alone(k).then_some((k, j));
    }
    // Consecutive `//` lines, the last ending at `j`.
    let mut first = None;
    let mut end_of_line = j;
    loop {
        let ls = line_start(end_of_line);
        let line = &head[ls..end_of_line];
        let trimmed = line.trim_start();
        if !trimmed.starts_with("//") {
            break;
        }
        first = Some(ls + (line.len() - trimmed.len()));
        if ls == 0 {
            break;
        }
        end_of_line = ls - 1;
        if head[..end_of_line].ends_with('\r') {
            end_of_line -= 1;
        }
    }
    first.map(|k| (k, j))
}

/// The comment's text without delimiters and surrounding blank lines; `None` for an
/// empty comment or a CODESYS attribute (`{attribute}` is a pragma, `(* @… *)` the
/// export's marks).
fn clean(comment: &str) -> Option<String> {
    let lines: Vec<&str> = comment
        .lines()
        .map(|l| {
            let l = l.trim();
            let l = l.strip_prefix("//").unwrap_or(l);
            let l = l
                .strip_prefix("(*")
                .or_else(|| l.strip_prefix("/*"))
                .unwrap_or(l);
            let l = l
                .strip_suffix("*)")
                .or_else(|| l.strip_suffix("*/"))
                .unwrap_or(l);
            l.trim()
        })
        .collect();
    let first = lines.iter().position(|l| !l.is_empty())?;
    let last = lines.iter().rposition(|l| !l.is_empty())?;
    if lines[first].starts_with('@') {
        return None;
    }
    let mut kept: Vec<&str> = lines[first..=last]
        .iter()
        .copied()
        .take(MAX_LINES)
        .collect();
    if last + 1 - first > MAX_LINES {
        kept.push("…");
    }
    Some(kept.join("\n"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn comments_found_before_after_and_cleaned() {
        let t = "a : INT; (* speed in rpm *)\n";
        assert_eq!(
            after_on_line(t, 7).map(|(a, b)| &t[a..b]),
            Some("(* speed in rpm *)")
        );
        let t = "x : INT; (* not mine *)\n  (* mine,\n  two lines *)\n  b : INT;";
        let start = t.find("b :").unwrap();
        assert_eq!(
            before(t, start).map(|(a, b)| clean(&t[a..b])),
            Some(Some("mine,\ntwo lines".into()))
        );
        let t = "x : INT; (* not mine *)\n  b : INT;";
        assert_eq!(before(t, t.find("b :").unwrap()), None);
        let t = "// one\n// two\r\nFUNCTION f";
        assert_eq!(
            before(t, t.find("FUNCTION").unwrap()).map(|(a, b)| clean(&t[a..b])),
            Some(Some("one\ntwo".into()))
        );
        let t = "(* far *)\n\nFUNCTION f";
        assert_eq!(before(t, t.find("FUNCTION").unwrap()), None);
        assert_eq!(clean("(* @END_DECLARATION := '0' *)"), None);
        assert_eq!(clean("(*   *)"), None);
        assert!(is_network_mark("(* network 12 *)"));
        assert!(!is_network_mark("(* network of pumps *)"));
    }
}
