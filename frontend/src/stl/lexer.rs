//! The STL lexer: source text to a vector of small `Copy` tokens.
//!
//! STL has few tokens: names, integers, a handful of operators and ~25 reserved words.
//! Keywords are matched on the upper-cased spelling (the language ignores case) and
//! names are interned as they are met, so the parser compares symbols, not strings.
//!
//! Lexical errors are reported here, once: a bad character becomes a [`Tok::Error`]
//! token (the parser stays silent about it), and a malformed number still becomes a
//! number token (value 0), so that one typo gives one diagnostic.
//!
//! A `pragma` line is one [`Tok::Pragma`] token: its text is a free-form directive
//! for the PLC-UD toolchain (the PLC range, the core) that plcc ignores, so it must
//! not be lexed as STL (it may contain characters STL has no token for).

use crate::codes;
use crate::intern::{Interner, Symbol};
use plcc_ir::diag::{Diagnostic, FileId, Span};

/// Token kinds. Names carry their interned symbol, numbers their value.
#[derive(Copy, Clone, Debug, PartialEq)]
pub enum Tok {
    /// End of input (always the last token).
    Eof,
    /// Bytes that start no token; already reported by the lexer.
    Error,
    /// A name.
    Ident(Symbol),
    /// An integer literal (decimal, `16#FF`, or the paper's constant marker `#30`).
    Int(i128),
    /// A real literal `1.5` (STL has no REAL type, but the IEC names are accepted).
    Real,
    /// A whole `pragma ...` line.
    Pragma,
    /// `:=`
    Assign,
    /// `=`
    Eq,
    /// `<>`
    Ne,
    /// `<`
    Lt,
    /// `<=`
    Le,
    /// `>`
    Gt,
    /// `>=`
    Ge,
    /// `+`
    Plus,
    /// `-`
    Minus,
    /// `*`
    Star,
    /// `/`
    Slash,
    /// `%` (modulo)
    Percent,
    /// `(`
    LParen,
    /// `)`
    RParen,
    /// `,`
    Comma,
    /// `;`
    Semi,
    /// `:`
    Colon,
    /// `.`
    Dot,
    /// `program`
    Program,
    /// `uses`
    Uses,
    /// `var`
    Var,
    /// `end_var`
    EndVar,
    /// `constant`
    Constant,
    /// `function`
    Function,
    /// `procedure`
    Procedure,
    /// `begin`
    Begin,
    /// `end`
    End,
    /// `if`
    If,
    /// `then`
    Then,
    /// `else`
    Else,
    /// `while`
    While,
    /// `do`
    Do,
    /// `repeat`
    Repeat,
    /// `until`
    Until,
    /// `for`
    For,
    /// `to`
    To,
    /// `downto`
    Downto,
    /// `and`
    And,
    /// `or`
    Or,
    /// `xor`
    Xor,
    /// `not`
    Not,
    /// `true`
    True,
    /// `false`
    False,
}

/// The reserved words, upper case (the lexer upper-cases before matching).
const KEYWORDS: &[(&str, Tok)] = &[
    ("PROGRAM", Tok::Program),
    ("USES", Tok::Uses),
    ("VAR", Tok::Var),
    ("END_VAR", Tok::EndVar),
    ("CONSTANT", Tok::Constant),
    ("FUNCTION", Tok::Function),
    ("PROCEDURE", Tok::Procedure),
    ("BEGIN", Tok::Begin),
    ("END", Tok::End),
    ("IF", Tok::If),
    ("THEN", Tok::Then),
    ("ELSE", Tok::Else),
    ("WHILE", Tok::While),
    ("DO", Tok::Do),
    ("REPEAT", Tok::Repeat),
    ("UNTIL", Tok::Until),
    ("FOR", Tok::For),
    ("TO", Tok::To),
    ("DOWNTO", Tok::Downto),
    ("AND", Tok::And),
    ("OR", Tok::Or),
    ("XOR", Tok::Xor),
    ("NOT", Tok::Not),
    ("TRUE", Tok::True),
    ("FALSE", Tok::False),
];

impl Tok {
    /// True for the reserved words (which cannot name a variable).
    pub fn is_keyword(self) -> bool {
        KEYWORDS.iter().any(|&(_, k)| k == self) || self == Tok::Pragma
    }
}

/// One token: its kind, its byte range, and whether a line break precedes it (the
/// parser uses that to place "missing `;`" carets and to resynchronise).
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Token {
    /// What it is.
    pub kind: Tok,
    /// First byte.
    pub start: u32,
    /// One past the last byte.
    pub end: u32,
    /// A line break (possibly inside a comment) separates it from the previous token.
    pub newline_before: bool,
}

/// The lexer's output.
#[derive(Debug, Default)]
pub struct Lexed {
    /// The tokens, ending with exactly one [`Tok::Eof`].
    pub tokens: Vec<Token>,
    /// The input ends inside an unterminated comment (already reported): the parser
    /// must not report what it misses at the end of the file as well.
    pub eof_in_error: bool,
}

/// Lexes one STL file. Never panics; errors go to `diags`.
pub fn lex(
    file: FileId,
    text: &str,
    interner: &mut Interner,
    diags: &mut Vec<Diagnostic>,
) -> Lexed {
    let mut lx = Lexer {
        file,
        src: text.as_bytes(),
        text,
        pos: 0,
        interner,
        diags,
        out: Lexed::default(),
        newline: false,
        word: String::new(),
    };
    lx.run();
    lx.out
}

struct Lexer<'a> {
    file: FileId,
    src: &'a [u8],
    text: &'a str,
    pos: usize,
    interner: &'a mut Interner,
    diags: &'a mut Vec<Diagnostic>,
    out: Lexed,
    /// A line break was seen since the last token.
    newline: bool,
    /// Scratch buffer for upper-casing words.
    word: String,
}

impl Lexer<'_> {
    fn span(&self, start: usize, end: usize) -> Span {
        Span::new(self.file, start as u32, end as u32)
    }

    fn peek_at(&self, i: usize) -> u8 {
        self.src.get(i).copied().unwrap_or(0)
    }

    fn push(&mut self, kind: Tok, start: usize) {
        self.out.tokens.push(Token {
            kind,
            start: start as u32,
            end: self.pos as u32,
            newline_before: self.newline,
        });
        self.newline = false;
    }

    fn run(&mut self) {
        while self.pos < self.src.len() {
            let c = self.src[self.pos];
            let start = self.pos;
            match c {
                b'\n' => {
                    self.newline = true;
                    self.pos += 1;
                }
                b' ' | b'\t' | b'\r' | 0x0B | 0x0C => self.pos += 1,
                b'(' if self.peek_at(self.pos + 1) == b'*' => {
                    if !self.comment() {
                        self.out.eof_in_error = true;
                    }
                }
                b'a'..=b'z' | b'A'..=b'Z' | b'_' => self.word_tok(),
                b'0'..=b'9' => self.number(),
                b'#' => self.hash_number(),
                _ => {
                    let (kind, len) = match (c, self.peek_at(self.pos + 1)) {
                        (b':', b'=') => (Tok::Assign, 2),
                        (b'<', b'>') => (Tok::Ne, 2),
                        (b'<', b'=') => (Tok::Le, 2),
                        (b'>', b'=') => (Tok::Ge, 2),
                        (b'=', _) => (Tok::Eq, 1),
                        (b'<', _) => (Tok::Lt, 1),
                        (b'>', _) => (Tok::Gt, 1),
                        (b'+', _) => (Tok::Plus, 1),
                        (b'-', _) => (Tok::Minus, 1),
                        (b'*', _) => (Tok::Star, 1),
                        (b'/', _) => (Tok::Slash, 1),
                        (b'%', _) => (Tok::Percent, 1),
                        (b'(', _) => (Tok::LParen, 1),
                        (b')', _) => (Tok::RParen, 1),
                        (b',', _) => (Tok::Comma, 1),
                        (b';', _) => (Tok::Semi, 1),
                        (b':', _) => (Tok::Colon, 1),
                        (b'.', _) => (Tok::Dot, 1),
                        _ => {
                            self.bad_char();
                            continue;
                        }
                    };
                    self.pos += len;
                    self.push(kind, start);
                }
            }
        }
        let end = self.src.len();
        self.out.tokens.push(Token {
            kind: Tok::Eof,
            start: end as u32,
            end: end as u32,
            newline_before: true,
        });
    }

    /// The character at `pos` (the lexer only stops at character boundaries).
    fn char_at(&self, pos: usize) -> char {
        self.text
            .get(pos..)
            .and_then(|t| t.chars().next())
            .unwrap_or('\u{FFFD}')
    }

    /// A run of characters that start no token: one diagnostic, one error token, so
    /// that a stray word in another script is one error, not one per letter.
    fn bad_char(&mut self) {
        let start = self.pos;
        let ch = self.char_at(start);
        self.pos += ch.len_utf8();
        let mut count = 1;
        while self.pos < self.src.len() {
            let c = self.char_at(self.pos);
            let starts_token = c.is_ascii_alphanumeric()
                || c.is_ascii_whitespace()
                || "_#:=<>+-*/%(),;.".contains(c);
            if starts_token {
                break;
            }
            self.pos += c.len_utf8();
            count += 1;
        }
        let shown = if ch.is_control() {
            format!("U+{:04X}", ch as u32)
        } else {
            format!("`{ch}`")
        };
        let msg = if count == 1 {
            format!("unexpected character {shown}")
        } else {
            format!("unexpected characters, starting with {shown}")
        };
        let mut d = Diagnostic::error(codes::STL_UNEXPECTED_CHAR, msg, self.span(start, self.pos))
            .with_label("no STL token starts with this");
        d = match ch {
            '\'' | '"' => d.with_note("STL has no string literals"),
            '[' | ']' => d.with_note("STL has no arrays"),
            '{' | '}' => d.with_note("comments are written `(* ... *)`"),
            '&' => d.with_note("the logical operators are `and`, `or`, `xor`, `not`"),
            '!' => d.with_note("`<>` means not equal; `not` negates"),
            _ => d,
        };
        self.diags.push(d);
        self.push(Tok::Error, start);
    }

    /// `(* ... *)`, nested. Returns false (after reporting) when it is not closed.
    fn comment(&mut self) -> bool {
        let start = self.pos;
        self.pos += 2;
        let mut level = 1u32;
        while self.pos < self.src.len() {
            match (self.src[self.pos], self.peek_at(self.pos + 1)) {
                (b'(', b'*') => {
                    level += 1;
                    self.pos += 2;
                }
                (b'*', b')') => {
                    level -= 1;
                    self.pos += 2;
                    if level == 0 {
                        return true;
                    }
                }
                (b'\n', _) => {
                    self.newline = true;
                    self.pos += 1;
                }
                _ => self.pos += 1,
            }
        }
        self.diags.push(
            Diagnostic::error(
                codes::STL_UNTERMINATED_COMMENT,
                "unterminated comment",
                self.span(start, start + 2),
            )
            .with_label("this comment is never closed")
            .with_note("comments nest: every `(*` inside a comment needs its own `*)`"),
        );
        false
    }

    fn word_tok(&mut self) {
        let start = self.pos;
        self.skip_word_chars();
        // The bytes are ASCII, so this cannot fail.
        let text = std::str::from_utf8(&self.src[start..self.pos]).unwrap_or("");
        self.word.clear();
        self.word.push_str(text);
        self.word.make_ascii_uppercase();
        if self.word == "PRAGMA" {
            self.pragma_line(start);
            return;
        }
        let kind = match KEYWORDS.iter().find(|(k, _)| *k == self.word) {
            Some(&(_, k)) => k,
            None => Tok::Ident(self.interner.intern_upper(&self.word)),
        };
        self.push(kind, start);
    }

    /// `pragma` and the rest of its line (comments on it are skipped whole, even when
    /// they run over several lines).
    fn pragma_line(&mut self, start: usize) {
        let mut end = self.pos;
        while self.pos < self.src.len() && self.src[self.pos] != b'\n' {
            if self.src[self.pos] == b'(' && self.peek_at(self.pos + 1) == b'*' {
                let newline = self.newline;
                if !self.comment() {
                    self.out.eof_in_error = true;
                }
                // A line break inside the comment does not end the pragma's line, nor
                // separate the pragma from the previous token.
                self.newline = newline;
            } else {
                if !self.src[self.pos].is_ascii_whitespace() {
                    end = self.pos + 1;
                }
                self.pos += 1;
            }
        }
        let after = self.pos;
        self.pos = end;
        self.push(Tok::Pragma, start);
        self.pos = after;
    }

    /// Digits, `_` separators allowed between them (as in IEC literals).
    fn digits(&mut self, radix: u32) -> (i128, bool, bool) {
        let mut v: i128 = 0;
        let mut any = false;
        let mut overflow = false;
        while self.pos < self.src.len() {
            let c = self.src[self.pos];
            if c == b'_' {
                self.pos += 1;
                continue;
            }
            let Some(d) = (c as char).to_digit(16).filter(|&d| d < radix.max(10)) else {
                break;
            };
            if d >= radix {
                // A digit of a larger base (`2#102`): the number is malformed.
                self.skip_word_chars();
                return (0, false, false);
            }
            any = true;
            match v
                .checked_mul(radix as i128)
                .and_then(|x| x.checked_add(d as i128))
            {
                Some(n) => v = n,
                None => overflow = true,
            }
            self.pos += 1;
        }
        (v, any, overflow)
    }

    /// Skips the rest of a malformed number (letters and digits glued to it), so that
    /// it is reported as one token.
    fn skip_word_chars(&mut self) {
        while self.at_word_char() {
            self.pos += 1;
        }
    }

    fn at_word_char(&self) -> bool {
        let c = self.peek_at(self.pos);
        c.is_ascii_alphanumeric() || c == b'_'
    }

    fn number(&mut self) {
        let start = self.pos;
        let (mut v, mut ok, mut overflow) = self.digits(10);
        let mut kind = None;
        if self.peek_at(self.pos) == b'#' {
            // A based number `16#FF`.
            self.pos += 1;
            let base = v;
            if matches!(base, 2 | 8 | 16) && !overflow && ok {
                (v, ok, overflow) = self.digits(base as u32);
            } else {
                self.skip_word_chars();
                ok = false;
            }
        } else if self.peek_at(self.pos) == b'.' && self.peek_at(self.pos + 1).is_ascii_digit() {
            // `1.5`: a real (`end.` never follows a digit, so this is unambiguous).
            self.pos += 1;
            self.digits(10);
            if matches!(self.peek_at(self.pos), b'e' | b'E') {
                let sign = matches!(self.peek_at(self.pos + 1), b'+' | b'-') as usize;
                if self.peek_at(self.pos + 1 + sign).is_ascii_digit() {
                    self.pos += 1 + sign;
                    self.digits(10);
                }
            }
            kind = Some(Tok::Real);
        }
        // Letters glued to a number (`12abc`) make it malformed.
        if self.at_word_char() {
            self.skip_word_chars();
            ok = false;
        }
        self.finish_number(start, v, ok, overflow, kind);
    }

    /// The paper's constant marker: `#30` is the number 30.
    fn hash_number(&mut self) {
        let start = self.pos;
        self.pos += 1;
        if !self.peek_at(self.pos).is_ascii_digit() {
            self.pos = start;
            self.bad_char();
            return;
        }
        let (v, mut ok, overflow) = self.digits(10);
        if self.at_word_char() {
            self.skip_word_chars();
            ok = false;
        }
        self.finish_number(start, v, ok, overflow, None);
    }

    fn finish_number(
        &mut self,
        start: usize,
        v: i128,
        ok: bool,
        overflow: bool,
        kind: Option<Tok>,
    ) {
        if !ok || overflow {
            let text = String::from_utf8_lossy(&self.src[start..self.pos]).into_owned();
            let msg = if overflow {
                format!("the number `{text}` is too large")
            } else {
                format!("malformed number `{text}`")
            };
            self.diags.push(
                Diagnostic::error(codes::STL_MALFORMED_NUMBER, msg, self.span(start, self.pos))
                    .with_label("not a valid number")
                    .with_note(
                        "numbers are decimal (`42`), based (`2#1010`, `8#17`, `16#FF`) or \
                         marked as constants (`#30`)",
                    ),
            );
            self.push(Tok::Int(0), start);
            return;
        }
        self.push(kind.unwrap_or(Tok::Int(v)), start);
    }
}
