//! A large Structured Text file lexed in two halves at once.
//!
//! The text is split at the start of a line near its middle. The first half is lexed
//! on the calling thread with the build's interner; the second, from the split to the
//! end, on another thread with a copy of it. The copy's new names are then interned
//! in the build's interner in the order the copy met them, which gives each the
//! symbol lexing the whole file would give it; the second half's identifiers and
//! typed literals are renumbered to those symbols and its literal indexes moved past
//! the first half's.
//!
//! Lexing carries no state from one line to the next except inside a comment, a
//! pragma or a string (a string ends with its line). So the halves lex as the whole
//! file does unless the first half ends inside one of those: it then reports running
//! into its end (`eof_in_error`), and the file is lexed whole, the first half's
//! names taken back out of the interner. A test lexes every ST file of the
//! repository and of `../shared` both ways, split at up to 24 lines each, and
//! compares the tokens, the literals, the diagnostics and the interned names.

use super::lexer::{self, Lexed, Tok, INLINE_INT, INLINE_REAL};
use crate::intern::{Interner, Symbol};
use plcc_ir::diag::{Diagnostic, FileId};

/// Smaller files are lexed whole: a thread would cost more than it saves.
const MIN_BYTES: usize = 400_000;

/// Lexes `text`, in two halves on two threads when it is large and the machine has
/// two cores; the result is the same as [`lexer::lex`] gives.
pub(super) fn lex(
    file: FileId,
    text: &str,
    interner: &mut Interner,
    diags: &mut Vec<Diagnostic>,
) -> Lexed {
    if text.len() >= MIN_BYTES && plcc_ir::parallel::threads() >= 2 {
        if let Some(lexed) = line_start(text, text.len() / 2)
            .and_then(|split| lex_at(file, text, split, interner, diags))
        {
            return lexed;
        }
    }
    lexer::lex(file, text, interner, diags)
}

/// The start of the first line that begins after byte `from`, if any does.
fn line_start(text: &str, from: usize) -> Option<usize> {
    let nl = memchr::memchr(b'\n', text.as_bytes().get(from..)?)?;
    Some(from + nl + 1).filter(|&s| s < text.len())
}

/// Lexes `text[..split]` here and `text[split..]` (`split` a line start) on another
/// thread; `None`, with nothing reported or interned, if the halves may differ from
/// the whole.
fn lex_at(
    file: FileId,
    text: &str,
    split: usize,
    interner: &mut Interner,
    diags: &mut Vec<Diagnostic>,
) -> Option<Lexed> {
    lexer::keyword_table(interner);
    let mut copy = interner.clone();
    let known = interner.len();
    let (mut first_diags, mut second_diags) = (Vec::new(), Vec::new());
    let (mut first, second) = plcc_ir::parallel::join(
        || {
            lexer::lex_from(
                file,
                &text[..split],
                0,
                text.len(),
                interner,
                &mut first_diags,
            )
        },
        || {
            lexer::lex_from(
                file,
                text,
                split,
                text.len() - split,
                &mut copy,
                &mut second_diags,
            )
        },
    );
    if first.eof_in_error {
        interner.truncate(known);
        return None;
    }
    // The copy's names, as the build's interner numbers them.
    let renumbered: Vec<Symbol> = copy
        .names_from(known)
        .iter()
        .map(|name| interner.intern_upper(name))
        .collect();
    let symbol = |data: u32| match (data as usize).checked_sub(known) {
        Some(k) => renumbered[k].0,
        None => data,
    };
    let literals_before = first.literals.len() as u32;
    let eof = first.tokens.pop();
    debug_assert!(eof.is_some_and(|t| t.kind == Tok::Eof));
    first.tokens.reserve(second.tokens.len());
    first.tokens.extend(second.tokens.into_iter().map(|mut t| {
        match t.kind {
            Tok::Ident => t.data = symbol(t.data),
            Tok::Lit if t.flags & (INLINE_INT | INLINE_REAL) == 0 => t.data += literals_before,
            _ => {}
        }
        t
    }));
    first
        .literals
        .extend(second.literals.into_iter().map(|mut lit| {
            if let Some(prefix) = &mut lit.type_prefix {
                prefix.sym = Symbol(symbol(prefix.sym.0));
            }
            lit
        }));
    first.c_pragmas.extend(second.c_pragmas);
    first.eof_in_error = second.eof_in_error;
    diags.append(&mut first_diags);
    diags.append(&mut second_diags);
    Some(first)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Lexes each file whole and in halves at up to 24 of its line starts (spread
    /// over the file); returns the splits compared and those refused.
    fn compare(files: &[(String, String)]) -> (usize, usize) {
        let (mut compared, mut refused) = (0, 0);
        let file = FileId(0);
        for (name, text) in files {
            let mut base = Interner::new();
            base.intern("SOME_NAME_FROM_BEFORE");
            // Lexing starts with them, whole or in halves.
            lexer::keyword_table(&mut base);
            let (mut whole_names, mut whole_diags) = (base.clone(), Vec::new());
            let whole = lexer::lex(file, text, &mut whole_names, &mut whole_diags);
            let lines = text.matches('\n').count();
            let step = lines.div_ceil(24).max(1);
            let mut from = 0;
            while let Some(split) = line_start(text, from) {
                from = split;
                for _ in 0..step {
                    from = line_start(text, from).unwrap_or(text.len());
                }
                let (mut names, mut diags) = (base.clone(), Vec::new());
                let Some(halves) = lex_at(file, text, split, &mut names, &mut diags) else {
                    refused += 1;
                    assert_eq!(names.len(), base.len(), "{name}: a refusal interns nothing");
                    assert!(diags.is_empty(), "{name}: a refusal reports nothing");
                    continue;
                };
                compared += 1;
                let at = format!("{name}, split at byte {split}");
                assert_eq!(halves.tokens, whole.tokens, "{at}");
                assert_eq!(halves.literals, whole.literals, "{at}");
                assert_eq!(halves.c_pragmas, whole.c_pragmas, "{at}");
                assert_eq!(halves.eof_in_error, whole.eof_in_error, "{at}");
                assert_eq!(format!("{diags:?}"), format!("{whole_diags:?}"), "{at}");
                assert_eq!(names.names_from(0), whole_names.names_from(0), "{at}");
            }
        }
        (compared, refused)
    }

    #[test]
    fn halves_lex_as_the_whole_file_at_its_line_starts() {
        crate::test_files::compare_over_st_files("splits", (1000, 1000), compare);
    }

    #[test]
    fn a_split_inside_a_comment_string_or_pragma_is_refused() {
        let cases = [
            "x := 1;\n(* a comment\nover lines *)\ny := 2;\n",
            "x := 1;\n/* a comment\nover lines */\ny := 2;\n",
            "x := 1;\n{ a pragma\nover lines }\ny := 2;\n",
            "x := 1;\n(* (* nested *)\n still open *)\ny := 2;\n",
        ];
        for text in cases {
            let split = text.find("over").or(text.find(" still")).unwrap();
            let split = text[..split].rfind('\n').unwrap() + 1;
            let mut names = Interner::new();
            let mut diags = Vec::new();
            assert!(
                lex_at(FileId(0), text, split, &mut names, &mut diags).is_none(),
                "{text:?}"
            );
            assert!(diags.is_empty());
        }
        // A string ends with its line: the split after it is fine, and both ways
        // report it once.
        let text = "s := 'open\nt := 'closed';\nu := WORD#16#FF + v;\n";
        let mut whole_names = Interner::new();
        let mut whole_diags = Vec::new();
        let whole = lexer::lex(FileId(0), text, &mut whole_names, &mut whole_diags);
        let (mut names, mut diags) = (Interner::new(), Vec::new());
        let split = text.find("t :=").unwrap();
        let halves = lex_at(FileId(0), text, split, &mut names, &mut diags).expect("lexed");
        assert_eq!(halves.tokens, whole.tokens);
        assert_eq!(halves.literals, whole.literals);
        assert_eq!(format!("{diags:?}"), format!("{whole_diags:?}"));
        assert_eq!(diags.len(), 1);
    }
}
