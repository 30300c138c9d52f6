//! The parser of the text form (see `docs/ir.md`).
//!
//! Parsing runs in two steps: the whole file is read into a raw form that names
//! things by their text, then names are resolved (so anything may refer to anything
//! declared later) and the types of instruction results are inferred (so a value may
//! be used in a block printed before the one defining it).
//!
//! Entity numbers are kept: `v7` is `Value(7)` and `block3` is `Block(3)`, so a printed
//! module parses back to one that prints the same. Numbers that no definition uses
//! become parameters of one extra block that is not in the layout (dead, as the IR
//! treats every block outside the layout). Slots are numbered in declaration order.

use crate::diag::{FileId, Span};
use crate::entities::{AggId, Block, DataId, FuncId, Inst, SlotId, TableId, Value};
use crate::function::{BlockData, FuncKind, Function, ValueData, ValueDef};
use crate::inst::{BinaryOp, BlockCall, ConvOp, FloatCC, InstData, IntCC, Intrinsic, UnaryOp};
use crate::module::{
    AggDef, ArrayDef, Configuration, DataDef, DataKind, Field, FieldRole, Module, ProgramEntry,
    Resource, StructDef, StructKind, Table,
};
use crate::types::{ElemType, MemType, Type};
use std::borrow::Cow;
use std::collections::HashMap;
use std::fmt;

mod config;
mod resolve;
mod table;
use config::RawConfiguration;
use resolve::Resolver;
use table::RawTable;

/// Why a text does not parse: the place (1-based line and column, in characters) and
/// what is wrong.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ParseError {
    /// 1-based line.
    pub line: u32,
    /// 1-based column, in characters.
    pub col: u32,
    /// What is wrong.
    pub message: String,
}

impl fmt::Display for ParseError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}: {}", self.line, self.col, self.message)
    }
}

impl std::error::Error for ParseError {}

/// Parses a module from its text form. Never panics; the result is not verified (run
/// [`crate::verify::verify_module`] for that).
pub fn parse_module(text: &str) -> Result<Module, ParseError> {
    let mut p = Parser {
        text,
        lexer: Lexer {
            text,
            b: text.as_bytes(),
            i: 0,
        },
        cur: Token {
            tok: Tok::Eof,
            pos: 0,
        },
        next: None,
        lex_error: None,
        raw: RawModule::default(),
    };
    p.advance();
    p.module()?;
    let raw = std::mem::take(&mut p.raw);
    Resolver {
        text,
        budget: (1usize << 20).saturating_add(text.len().saturating_mul(16)),
    }
    .module(raw)
}

/// A byte offset in the text.
type Pos = u32;

fn error_at(text: &str, pos: Pos, message: impl Into<String>) -> ParseError {
    let pos = (pos as usize).min(text.len());
    let mut line = 1u32;
    let mut line_start = 0usize;
    for (i, b) in text.as_bytes()[..pos].iter().enumerate() {
        if *b == b'\n' {
            line += 1;
            line_start = i + 1;
        }
    }
    // `pos` is always at a char boundary: tokens start at ASCII chars.
    let col = text
        .get(line_start..pos)
        .map_or(pos - line_start, |s| s.chars().count()) as u32
        + 1;
    ParseError {
        line,
        col,
        message: message.into(),
    }
}

// ---------------------------------------------------------------------------------
// Lexer

/// `%name`, `%"name"`, optionally followed by `."field"` (or `.field` after a quoted
/// name).
#[derive(Clone, Debug, PartialEq)]
struct AggTok<'a> {
    name: Cow<'a, str>,
    /// True for an unquoted name.
    plain: bool,
    field: Option<Cow<'a, str>>,
}

#[derive(Clone, Debug, PartialEq)]
enum Tok<'a> {
    /// Identifiers, keywords, mnemonics, `v3`, `block2`, `inf`, `-inf`.
    Word(&'a str),
    /// A numeric literal, as written.
    Num(&'a str),
    /// A quoted string, unescaped.
    Str(Cow<'a, str>),
    /// An aggregate name.
    Agg(Box<AggTok<'a>>),
    /// `@name` or `@"name"`.
    Global(Cow<'a, str>),
    /// `!F:S..E`
    Loc(Span),
    LParen,
    RParen,
    LBrace,
    RBrace,
    LBracket,
    RBracket,
    Comma,
    Colon,
    Equals,
    Arrow,
    /// `-` alone (an empty entry of a table).
    Dash,
    Newline,
    Eof,
    /// The lexer failed here (the error is in `Parser::lex_error`).
    Error,
}

impl Tok<'_> {
    fn describe(&self) -> String {
        match self {
            Tok::Word(w) => format!("`{w}`"),
            Tok::Num(n) => format!("number `{n}`"),
            Tok::Str(_) => "a string".into(),
            Tok::Agg(_) => "an aggregate name".into(),
            Tok::Global(_) => "a `@` name".into(),
            Tok::Loc(_) => "a location".into(),
            Tok::LParen => "`(`".into(),
            Tok::RParen => "`)`".into(),
            Tok::LBrace => "`{`".into(),
            Tok::RBrace => "`}`".into(),
            Tok::LBracket => "`[`".into(),
            Tok::RBracket => "`]`".into(),
            Tok::Comma => "`,`".into(),
            Tok::Colon => "`:`".into(),
            Tok::Equals => "`=`".into(),
            Tok::Arrow => "`->`".into(),
            Tok::Dash => "`-`".into(),
            Tok::Newline => "the end of the line".into(),
            Tok::Eof => "the end of the file".into(),
            Tok::Error => "an invalid token".into(),
        }
    }
}

struct Token<'a> {
    tok: Tok<'a>,
    pos: Pos,
}

fn is_ident_start(b: u8) -> bool {
    b.is_ascii_alphabetic() || b == b'_'
}

fn is_ident_char(b: u8) -> bool {
    b.is_ascii_alphanumeric() || matches!(b, b'_' | b'$' | b'.')
}

struct Lexer<'a> {
    text: &'a str,
    b: &'a [u8],
    i: usize,
}

impl<'a> Lexer<'a> {
    fn err<T>(&self, pos: usize, msg: impl Into<String>) -> Result<T, ParseError> {
        Err(error_at(self.text, pos as Pos, msg))
    }

    fn peek_at(&self, k: usize) -> Option<u8> {
        self.b.get(self.i + k).copied()
    }

    fn ident(&mut self) -> &'a str {
        let start = self.i;
        while self.i < self.b.len() && is_ident_char(self.b[self.i]) {
            self.i += 1;
        }
        &self.text[start..self.i]
    }

    /// Reads a quoted string; `self.i` is at the opening quote.
    fn string(&mut self) -> Result<Cow<'a, str>, ParseError> {
        let open = self.i;
        self.i += 1;
        // Without escapes, the string is a slice of the text.
        let start = self.i;
        while self.i < self.b.len() && !matches!(self.b[self.i], b'"' | b'\\' | b'\n') {
            self.i += 1;
        }
        if self.peek_at(0) == Some(b'"') {
            self.i += 1;
            return Ok(Cow::Borrowed(&self.text[start..self.i - 1]));
        }
        let mut out = String::from(&self.text[start..self.i]);
        loop {
            let Some(c) = self.text[self.i..].chars().next() else {
                return self.err(open, "unterminated string");
            };
            match c {
                '"' => {
                    self.i += 1;
                    return Ok(Cow::Owned(out));
                }
                '\n' => return self.err(open, "unterminated string"),
                '\\' => {
                    let esc_pos = self.i;
                    self.i += 1;
                    let Some(e) = self.text[self.i..].chars().next() else {
                        return self.err(open, "unterminated string");
                    };
                    self.i += e.len_utf8();
                    match e {
                        '"' => out.push('"'),
                        '\\' => out.push('\\'),
                        'n' => out.push('\n'),
                        'r' => out.push('\r'),
                        't' => out.push('\t'),
                        'u' => {
                            if self.peek_at(0) != Some(b'{') {
                                return self.err(esc_pos, "expected `{` after `\\u`");
                            }
                            let start = self.i + 1;
                            let Some(len) = self.text[start..].find(['}', '\n']) else {
                                return self.err(esc_pos, "unterminated `\\u{…}` escape");
                            };
                            let hex = &self.text[start..start + len];
                            let ch = u32::from_str_radix(hex, 16)
                                .ok()
                                .filter(|_| !hex.is_empty() && hex.len() <= 6)
                                .and_then(char::from_u32);
                            if self.b[start + len] != b'}' {
                                return self.err(esc_pos, "unterminated `\\u{…}` escape");
                            }
                            let Some(ch) = ch else {
                                return self.err(esc_pos, format!("bad escape `\\u{{{hex}}}`"));
                            };
                            out.push(ch);
                            self.i = start + len + 1;
                        }
                        _ => return self.err(esc_pos, format!("unknown escape `\\{e}`")),
                    }
                }
                c => {
                    out.push(c);
                    self.i += c.len_utf8();
                }
            }
        }
    }

    /// A name after `%` or `@`: plain or quoted.
    fn sigil_name(&mut self, sigil: char) -> Result<(Cow<'a, str>, bool), ParseError> {
        match self.peek_at(0) {
            Some(b'"') => Ok((self.string()?, false)),
            Some(c) if is_ident_start(c) => Ok((Cow::Borrowed(self.ident()), true)),
            _ => self.err(self.i, format!("expected a name after `{sigil}`")),
        }
    }

    fn digits(&mut self, what: &str) -> Result<u32, ParseError> {
        let start = self.i;
        while self.i < self.b.len() && self.b[self.i].is_ascii_digit() {
            self.i += 1;
        }
        match self.text[start..self.i].parse::<u32>() {
            Ok(n) => Ok(n),
            Err(_) => self.err(start, format!("expected {what} in the location `!F:S..E`")),
        }
    }

    /// A number: `self.i` is at a digit or at a `-` before a digit.
    fn number(&mut self) -> &'a str {
        let start = self.i;
        if self.b[self.i] == b'-' {
            self.i += 1;
        }
        let rest = &self.text[self.i..];
        let hex = rest.starts_with("0x") || rest.starts_with("0X");
        self.i += 1; // the first digit
        while self.i < self.b.len() {
            let c = self.b[self.i];
            let prev = self.b[self.i - 1];
            if c.is_ascii_alphanumeric()
                || c == b'_'
                || c == b'.'
                || (!hex && matches!(c, b'+' | b'-') && matches!(prev, b'e' | b'E'))
            {
                self.i += 1;
            } else {
                break;
            }
        }
        &self.text[start..self.i]
    }

    /// The next token (`Eof` at the end, as often as asked).
    fn token(&mut self) -> Result<Token<'a>, ParseError> {
        loop {
            let Some(&c) = self.b.get(self.i) else {
                return Ok(Token {
                    tok: Tok::Eof,
                    pos: self.b.len() as Pos,
                });
            };
            let pos = self.i;
            let simple = match c {
                b'(' => Some(Tok::LParen),
                b')' => Some(Tok::RParen),
                b'{' => Some(Tok::LBrace),
                b'}' => Some(Tok::RBrace),
                b'[' => Some(Tok::LBracket),
                b']' => Some(Tok::RBracket),
                b',' => Some(Tok::Comma),
                b':' => Some(Tok::Colon),
                b'=' => Some(Tok::Equals),
                b'\n' => Some(Tok::Newline),
                _ => None,
            };
            if let Some(tok) = simple {
                self.i += 1;
                return Ok(Token {
                    tok,
                    pos: pos as Pos,
                });
            }
            let tok = match c {
                b' ' | b'\t' | b'\r' => {
                    self.i += 1;
                    continue;
                }
                b';' => {
                    while self.i < self.b.len() && self.b[self.i] != b'\n' {
                        self.i += 1;
                    }
                    continue;
                }
                b'"' => Tok::Str(self.string()?),
                b'%' => {
                    self.i += 1;
                    let (mut name, plain) = self.sigil_name('%')?;
                    let mut field = None;
                    if plain && name.ends_with('.') && self.peek_at(0) == Some(b'"') {
                        if let Cow::Borrowed(n) = name {
                            name = Cow::Borrowed(&n[..n.len() - 1]);
                        }
                        field = Some(self.string()?);
                    } else if !plain && self.peek_at(0) == Some(b'.') {
                        match self.peek_at(1) {
                            Some(b'"') => {
                                self.i += 1;
                                field = Some(self.string()?);
                            }
                            Some(c) if is_ident_start(c) => {
                                self.i += 1;
                                field = Some(Cow::Borrowed(self.ident()));
                            }
                            _ => return self.err(self.i, "expected a field name after `.`"),
                        }
                    }
                    Tok::Agg(Box::new(AggTok { name, plain, field }))
                }
                b'@' => {
                    self.i += 1;
                    Tok::Global(self.sigil_name('@')?.0)
                }
                b'!' => {
                    self.i += 1;
                    let file = self.digits("a file number")?;
                    if self.peek_at(0) != Some(b':') {
                        return self.err(self.i, "expected `:` in the location `!F:S..E`");
                    }
                    self.i += 1;
                    let start = self.digits("a start offset")?;
                    if self.peek_at(0) != Some(b'.') || self.peek_at(1) != Some(b'.') {
                        return self.err(self.i, "expected `..` in the location `!F:S..E`");
                    }
                    self.i += 2;
                    let end = self.digits("an end offset")?;
                    Tok::Loc(Span::new(FileId(file), start, end))
                }
                b'-' => match self.peek_at(1) {
                    Some(b'>') => {
                        self.i += 2;
                        Tok::Arrow
                    }
                    Some(d) if d.is_ascii_digit() => Tok::Num(self.number()),
                    Some(a) if is_ident_start(a) => {
                        self.i += 1;
                        self.ident();
                        Tok::Word(&self.text[pos..self.i])
                    }
                    _ => {
                        self.i += 1;
                        Tok::Dash
                    }
                },
                c if c.is_ascii_digit() => Tok::Num(self.number()),
                c if is_ident_start(c) => Tok::Word(self.ident()),
                _ => {
                    let ch = self.text[pos..].chars().next().unwrap_or('?');
                    return self.err(pos, format!("unexpected character `{ch}`"));
                }
            };
            return Ok(Token {
                tok,
                pos: pos as Pos,
            });
        }
    }
}

// ---------------------------------------------------------------------------------
// Raw form: everything named by its text, with positions for errors.

/// A name with the position it was written at.
#[derive(Clone, Debug)]
struct Named<'a> {
    name: Cow<'a, str>,
    pos: Pos,
}

#[derive(Clone, Debug)]
enum RawMem<'a> {
    Scalar(Type),
    Agg(Named<'a>),
}

#[derive(Debug)]
struct RawField<'a> {
    name: Cow<'a, str>,
    ty: RawMem<'a>,
    elem: Option<ElemType>,
    role: FieldRole,
    location: Option<Cow<'a, str>>,
}

#[derive(Debug)]
enum RawAggBody<'a> {
    Struct {
        kind: StructKind,
        fields: Vec<RawField<'a>>,
    },
    Array {
        elem: RawMem<'a>,
        elem_type: Option<ElemType>,
        len: u32,
        lower: i64,
    },
}

#[derive(Debug)]
struct RawAgg<'a> {
    name: Named<'a>,
    body: RawAggBody<'a>,
}

#[derive(Debug)]
struct RawData<'a> {
    name: Named<'a>,
    ty: RawMem<'a>,
    elem: Option<ElemType>,
    kind: DataKind,
    location: Option<Cow<'a, str>>,
}

#[derive(Debug)]
struct RawProgram<'a> {
    name: Cow<'a, str>,
    data: Named<'a>,
    body: Named<'a>,
    init: Named<'a>,
    interval_us: Option<u64>,
    priority: Option<u32>,
}

/// A number (of a value, block, slot or file) and where it is written.
#[derive(Copy, Clone, Debug)]
struct V {
    n: u32,
    pos: Pos,
}

#[derive(Debug)]
struct RawBlockCall {
    block: V,
    args: Vec<V>,
}

#[derive(Debug)]
enum RawOp<'a> {
    Iconst(Type, i64),
    Fconst(Type, u64),
    SizeOf(Type, RawMem<'a>),
    Unary(UnaryOp, V),
    Binary(BinaryOp, V, V),
    Icmp(IntCC, V, V),
    Fcmp(FloatCC, V, V),
    Convert(ConvOp, Type, V),
    Select(V, V, V),
    GlobalAddr(Named<'a>),
    SlotAddr(V),
    FieldAddr(Box<(V, Named<'a>, Cow<'a, str>)>),
    ElemAddr(Box<(V, Named<'a>, V)>),
    Load(Type, V),
    Store(V, V),
    Call(Box<(Named<'a>, Vec<V>)>),
    /// The table, the index, the arguments.
    CallTable(Box<(V, V, Vec<V>)>),
    Intrinsic(Intrinsic, Vec<V>),
    InlineC(Box<(Named<'a>, V, Cow<'a, str>)>),
    Jump(Box<RawBlockCall>),
    Brif(Box<(V, RawBlockCall, RawBlockCall)>),
    /// The index, the default, the table.
    BrTable(Box<(V, RawBlockCall, Vec<RawBlockCall>)>),
    Return(Option<V>),
}

#[derive(Debug)]
struct RawInst<'a> {
    result: Option<V>,
    /// Position of the mnemonic.
    pos: Pos,
    mnemonic: &'a str,
    op: RawOp<'a>,
    span: Option<Span>,
}

#[derive(Debug)]
struct RawBlock<'a> {
    label: V,
    params: Vec<(V, Type)>,
    insts: Vec<RawInst<'a>>,
}

#[derive(Debug)]
struct RawSlot<'a> {
    num: V,
    ty: RawMem<'a>,
    name: Cow<'a, str>,
}

#[derive(Debug)]
struct RawFunc<'a> {
    name: Named<'a>,
    kind: FuncKind,
    params: Vec<Type>,
    ret: Option<Type>,
    span: Option<Span>,
    slots: Vec<RawSlot<'a>>,
    blocks: Vec<RawBlock<'a>>,
}

#[derive(Debug, Default)]
struct RawModule<'a> {
    files: Vec<(V, Cow<'a, str>)>,
    aggs: Vec<RawAgg<'a>>,
    data: Vec<RawData<'a>>,
    funcs: Vec<RawFunc<'a>>,
    tables: Vec<RawTable<'a>>,
    programs: Vec<RawProgram<'a>>,
    init_globals: Option<Named<'a>>,
    globals: Option<Named<'a>>,
    configuration: Option<RawConfiguration<'a>>,
    unchecked_pointers: bool,
}

// ---------------------------------------------------------------------------------
// Parser: tokens to the raw form.

struct Parser<'a> {
    text: &'a str,
    lexer: Lexer<'a>,
    /// The current token.
    cur: Token<'a>,
    /// The token after it, if already read.
    next: Option<Token<'a>>,
    /// The first error of the lexer (the token stream ends with `Tok::Error` there).
    lex_error: Option<ParseError>,
    raw: RawModule<'a>,
}

/// The number after a prefix (`v12` with prefix `v` is 12).
fn numbered(word: &str, prefix: &str) -> Option<u32> {
    let digits = word.strip_prefix(prefix)?;
    if digits.is_empty() || !digits.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    digits.parse().ok()
}

fn parse_int(s: &str) -> Option<i64> {
    let (neg, body) = match s.strip_prefix('-') {
        Some(b) => (true, b),
        None => (false, s),
    };
    let mag: u64 = if let Some(h) = body.strip_prefix("0x").or_else(|| body.strip_prefix("0X")) {
        u64::from_str_radix(h, 16).ok()?
    } else {
        if !body.bytes().all(|b| b.is_ascii_digit()) {
            return None;
        }
        body.parse().ok()?
    };
    if neg {
        if mag > 1u64 << 63 {
            return None;
        }
        Some((mag as i64).wrapping_neg())
    } else {
        Some(mag as i64)
    }
}

fn parse_float(ty: Type, s: &str) -> Option<u64> {
    if let Some(h) = s.strip_prefix("0x").or_else(|| s.strip_prefix("0X")) {
        return u64::from_str_radix(h, 16).ok();
    }
    if !s
        .bytes()
        .all(|b| b.is_ascii_alphanumeric() || matches!(b, b'.' | b'-' | b'+'))
    {
        return None;
    }
    match ty {
        Type::F32 => s.parse::<f32>().ok().map(|x| x.to_bits() as u64),
        _ => s.parse::<f64>().ok().map(f64::to_bits),
    }
}

impl<'a> Parser<'a> {
    fn lex(&mut self) -> Token<'a> {
        if self.lex_error.is_some() {
            return Token {
                tok: Tok::Error,
                pos: self.lexer.i as Pos,
            };
        }
        match self.lexer.token() {
            Ok(t) => t,
            Err(e) => {
                self.lex_error = Some(e);
                Token {
                    tok: Tok::Error,
                    pos: self.lexer.i as Pos,
                }
            }
        }
    }

    /// Moves to the next token; returns the current one.
    fn advance(&mut self) -> Token<'a> {
        let next = match self.next.take() {
            Some(t) => t,
            None => self.lex(),
        };
        std::mem::replace(&mut self.cur, next)
    }

    fn peek(&self) -> &Tok<'a> {
        &self.cur.tok
    }

    fn peek2(&mut self) -> &Tok<'a> {
        if self.next.is_none() {
            let t = self.lex();
            self.next = Some(t);
        }
        match &self.next {
            Some(t) => &t.tok,
            None => &Tok::Eof,
        }
    }

    fn pos(&self) -> Pos {
        self.cur.pos
    }

    /// Consumes the current token (never the lexer's error) and returns its position.
    fn bump(&mut self) -> Pos {
        if matches!(self.cur.tok, Tok::Error | Tok::Eof) {
            return self.cur.pos;
        }
        self.advance().pos
    }

    fn err<T>(&self, pos: Pos, msg: impl Into<String>) -> Result<T, ParseError> {
        if let (Tok::Error, Some(e)) = (&self.cur.tok, &self.lex_error) {
            return Err(e.clone());
        }
        Err(error_at(self.text, pos, msg))
    }

    fn unexpected<T>(&self, what: &str) -> Result<T, ParseError> {
        self.err(
            self.pos(),
            format!("expected {what}, found {}", self.peek().describe()),
        )
    }

    fn expect(&mut self, tok: Tok, what: &str) -> Result<Pos, ParseError> {
        if *self.peek() == tok {
            Ok(self.bump())
        } else {
            self.unexpected(what)
        }
    }

    fn eat(&mut self, tok: &Tok) -> bool {
        if self.peek() == tok {
            self.bump();
            true
        } else {
            false
        }
    }

    fn word(&mut self, what: &str) -> Result<(&'a str, Pos), ParseError> {
        match *self.peek() {
            Tok::Word(w) => Ok((w, self.bump())),
            _ => self.unexpected(what),
        }
    }

    fn keyword(&mut self, kw: &str) -> Result<(), ParseError> {
        match *self.peek() {
            Tok::Word(w) if w == kw => {
                self.bump();
                Ok(())
            }
            _ => self.unexpected(&format!("`{kw}`")),
        }
    }

    fn is_word(&self, kw: &str) -> bool {
        matches!(*self.peek(), Tok::Word(w) if w == kw)
    }

    fn string(&mut self, what: &str) -> Result<Cow<'a, str>, ParseError> {
        match self.peek() {
            Tok::Str(_) => match self.advance().tok {
                Tok::Str(s) => Ok(s),
                _ => unreachable!("peeked a string"),
            },
            _ => self.unexpected(what),
        }
    }

    fn num_text(&mut self, what: &str) -> Result<(&'a str, Pos), ParseError> {
        match *self.peek() {
            Tok::Num(n) => Ok((n, self.bump())),
            _ => self.unexpected(what),
        }
    }

    fn u32_num(&mut self, what: &str) -> Result<u32, ParseError> {
        let (n, pos) = self.num_text(what)?;
        match n.parse::<u32>() {
            Ok(v) => Ok(v),
            Err(_) => self.err(pos, format!("`{n}` is not {what}")),
        }
    }

    fn global(&mut self, what: &str) -> Result<Named<'a>, ParseError> {
        match self.peek() {
            Tok::Global(_) => {
                let t = self.advance();
                match t.tok {
                    Tok::Global(name) => Ok(Named { name, pos: t.pos }),
                    _ => unreachable!("peeked a global"),
                }
            }
            _ => self.unexpected(what),
        }
    }

    fn agg_name(&mut self, what: &str) -> Result<Named<'a>, ParseError> {
        match self.peek() {
            Tok::Agg(a) => {
                if a.field.is_some() {
                    return self.err(self.pos(), "unexpected field after an aggregate name");
                }
                let t = self.advance();
                match t.tok {
                    Tok::Agg(a) => Ok(Named {
                        name: a.name,
                        pos: t.pos,
                    }),
                    _ => unreachable!("peeked an aggregate"),
                }
            }
            _ => self.unexpected(what),
        }
    }

    fn end_of_line(&mut self) -> Result<(), ParseError> {
        match self.peek() {
            Tok::Newline => {
                self.bump();
                Ok(())
            }
            Tok::Eof => Ok(()),
            _ => self.unexpected("the end of the line"),
        }
    }

    fn skip_newlines(&mut self) {
        while *self.peek() == Tok::Newline {
            self.bump();
        }
    }

    fn scalar_type(&mut self) -> Result<Type, ParseError> {
        let (w, pos) = self.word("a type")?;
        match Type::from_name(w) {
            Some(t) => Ok(t),
            None => self.err(pos, format!("unknown type `{w}`")),
        }
    }

    fn mem_type(&mut self) -> Result<RawMem<'a>, ParseError> {
        match self.peek() {
            Tok::Agg(_) => Ok(RawMem::Agg(self.agg_name("a type")?)),
            Tok::Word(_) => Ok(RawMem::Scalar(self.scalar_type()?)),
            _ => self.unexpected("a type"),
        }
    }

    fn elem_type(&mut self) -> Result<ElemType, ParseError> {
        let (w, pos) = self.word("an IEC type")?;
        match ElemType::from_name(w) {
            Some(e) => Ok(e),
            None => self.err(pos, format!("unknown IEC type `{w}`")),
        }
    }

    fn location(&mut self) -> Result<Option<Cow<'a, str>>, ParseError> {
        if self.is_word("at") {
            self.bump();
            Ok(Some(self.string("a location string")?))
        } else {
            Ok(None)
        }
    }

    fn loc(&mut self) -> Option<Span> {
        match *self.peek() {
            Tok::Loc(s) => {
                self.bump();
                Some(s)
            }
            _ => None,
        }
    }

    fn module(&mut self) -> Result<(), ParseError> {
        const TOP: &str = "`file`, `unchecked_pointers`, `struct`, `array`, `data`, `table`, `func`, `program`, `init_globals`, `globals`, `configuration` or `resource`";
        loop {
            self.skip_newlines();
            let (w, pos) = match *self.peek() {
                Tok::Eof => return Ok(()),
                Tok::Word(w) => (w, self.pos()),
                _ => return self.unexpected(TOP),
            };
            match w {
                "file" => {
                    self.bump();
                    let npos = self.pos();
                    let n = self.u32_num("a file number")?;
                    let name = self.string("a file name")?;
                    self.raw.files.push((V { n, pos: npos }, name));
                }
                "unchecked_pointers" => {
                    self.bump();
                    self.raw.unchecked_pointers = true;
                }
                "struct" => self.struct_def()?,
                "array" => self.array_def()?,
                "data" => self.data_def()?,
                "table" => self.table_def()?,
                "func" => self.func_def()?,
                "program" => self.program_line()?,
                "init_globals" => {
                    self.bump();
                    let f = self.global("a function name")?;
                    if self.raw.init_globals.is_some() {
                        return self.err(pos, "`init_globals` is given twice");
                    }
                    self.raw.init_globals = Some(f);
                }
                "globals" => self.globals_line()?,
                "configuration" => self.configuration_line()?,
                "resource" => self.resource_line()?,
                _ => return self.err(pos, format!("expected {TOP}, found `{w}`")),
            }
            self.end_of_line()?;
        }
    }

    fn struct_def(&mut self) -> Result<(), ParseError> {
        self.bump();
        let name = self.agg_name("a struct name such as `%S`")?;
        let (k, kpos) = self.word("a struct kind (`program`, `fb`, `struct`, `other`)")?;
        let Some(kind) = StructKind::from_name(k) else {
            return self.err(
                kpos,
                format!(
                    "unknown struct kind `{k}` (expected `program`, `fb`, `struct` or `other`)"
                ),
            );
        };
        self.expect(Tok::LBrace, "`{`")?;
        self.end_of_line()?;
        let mut fields = Vec::new();
        loop {
            self.skip_newlines();
            if self.eat(&Tok::RBrace) {
                break;
            }
            if *self.peek() == Tok::Eof {
                return self.unexpected("`}` closing the struct");
            }
            let (r, rpos) = self.word("a field role (`var`, `in`, `out`, …) or `}`")?;
            let Some(role) = FieldRole::from_name(r) else {
                return self.err(rpos, format!("unknown field role `{r}` (expected `var`, `in`, `out`, `inout`, `temp`, `external` or `hidden`)"));
            };
            let fname = match *self.peek() {
                Tok::Word(w) => {
                    self.bump();
                    Cow::Borrowed(w)
                }
                Tok::Str(_) => self.string("a field name")?,
                _ => return self.unexpected("a field name"),
            };
            self.expect(Tok::Colon, "`:`")?;
            let ty = self.mem_type()?;
            let elem = match *self.peek() {
                Tok::Word(w) if w != "at" => Some(self.elem_type()?),
                _ => None,
            };
            let location = self.location()?;
            self.end_of_line()?;
            fields.push(RawField {
                name: fname,
                ty,
                elem,
                role,
                location,
            });
        }
        self.raw.aggs.push(RawAgg {
            name,
            body: RawAggBody::Struct { kind, fields },
        });
        Ok(())
    }

    fn array_def(&mut self) -> Result<(), ParseError> {
        self.bump();
        let name = self.agg_name("an array name such as `%A`")?;
        self.expect(Tok::Equals, "`=`")?;
        self.expect(Tok::LBracket, "`[`")?;
        let len = self.u32_num("an array length")?;
        self.keyword("x")?;
        let elem = self.mem_type()?;
        let elem_type = match self.peek() {
            Tok::Word(_) => Some(self.elem_type()?),
            _ => None,
        };
        self.expect(Tok::RBracket, "`]`")?;
        self.keyword("lower")?;
        let (n, npos) = self.num_text("the lower bound")?;
        let Ok(lower) = n.parse::<i64>() else {
            return self.err(npos, format!("`{n}` is not a lower bound"));
        };
        self.raw.aggs.push(RawAgg {
            name,
            body: RawAggBody::Array {
                elem,
                elem_type,
                len,
                lower,
            },
        });
        Ok(())
    }

    fn data_def(&mut self) -> Result<(), ParseError> {
        self.bump();
        let name = self.global("a data name such as `@d`")?;
        self.expect(Tok::Colon, "`:`")?;
        let ty = self.mem_type()?;
        const KIND: &str = "a data kind (`program`, `global`, `const`)";
        let (mut w, mut wpos) = self.word(KIND)?;
        let mut elem = None;
        if DataKind::from_name(w).is_none() {
            match ElemType::from_name(w) {
                Some(e) => elem = Some(e),
                None => return self.err(wpos, format!("unknown IEC type or data kind `{w}`")),
            }
            (w, wpos) = self.word(KIND)?;
        }
        let Some(kind) = DataKind::from_name(w) else {
            return self.err(
                wpos,
                format!("unknown data kind `{w}` (expected `program`, `global` or `const`)"),
            );
        };
        let location = self.location()?;
        self.raw.data.push(RawData {
            name,
            ty,
            elem,
            kind,
            location,
        });
        Ok(())
    }

    fn program_line(&mut self) -> Result<(), ParseError> {
        self.bump();
        let name = self.string("the instance name as a string")?;
        self.keyword("data")?;
        let data = self.global("a data name")?;
        self.keyword("body")?;
        let body = self.global("a function name")?;
        self.keyword("init")?;
        let init = self.global("a function name")?;
        let mut interval_us = None;
        let mut priority = None;
        if self.is_word("interval_us") {
            self.bump();
            let (n, pos) = self.num_text("an interval in µs")?;
            interval_us = match n.parse::<u64>() {
                Ok(v) => Some(v),
                Err(_) => return self.err(pos, format!("`{n}` is not an interval in µs")),
            };
        }
        if self.is_word("priority") {
            self.bump();
            priority = Some(self.u32_num("a priority")?);
        }
        self.raw.programs.push(RawProgram {
            name,
            data,
            body,
            init,
            interval_us,
            priority,
        });
        Ok(())
    }

    /// `(types) [-> type]`: the parameters and result of a function or a table.
    pub(super) fn signature(&mut self) -> Result<(Vec<Type>, Option<Type>), ParseError> {
        self.expect(Tok::LParen, "`(`")?;
        let mut params = Vec::new();
        if !self.eat(&Tok::RParen) {
            loop {
                params.push(self.scalar_type()?);
                if self.eat(&Tok::RParen) {
                    break;
                }
                self.expect(Tok::Comma, "`,` or `)`")?;
            }
        }
        let result = if self.eat(&Tok::Arrow) {
            Some(self.scalar_type()?)
        } else {
            None
        };
        Ok((params, result))
    }

    fn func_def(&mut self) -> Result<(), ParseError> {
        self.bump();
        let name = self.global("a function name such as `@f`")?;
        let (params, ret) = self.signature()?;
        let (k, kpos) =
            self.word("a function kind (`function`, `fb`, `program`, `init`, `helper`)")?;
        let Some(kind) = FuncKind::from_name(k) else {
            return self.err(kpos, format!("unknown function kind `{k}` (expected `function`, `fb`, `program`, `init` or `helper`)"));
        };
        let span = self.loc();
        self.expect(Tok::LBrace, "`{`")?;
        self.end_of_line()?;
        let mut func = RawFunc {
            name,
            kind,
            params,
            ret,
            span,
            slots: Vec::new(),
            blocks: Vec::new(),
        };
        loop {
            self.skip_newlines();
            let (w, wpos) = match *self.peek() {
                Tok::RBrace => {
                    self.bump();
                    break;
                }
                Tok::Eof => return self.unexpected("`}` closing the function"),
                Tok::Word(w) => (w, self.pos()),
                _ => return self.unexpected("an instruction, a block label or `}`"),
            };
            let next_is = |t: &Tok| -> u8 {
                match t {
                    Tok::LParen | Tok::Colon => 1,
                    Tok::Equals => 2,
                    _ => 0,
                }
            };
            let next = next_is(self.peek2());
            if let (Some(n), 1) = (numbered(w, "block"), next) {
                self.bump();
                let mut params = Vec::new();
                if self.eat(&Tok::LParen) && !self.eat(&Tok::RParen) {
                    loop {
                        let v = self.value()?;
                        self.expect(Tok::Colon, "`:`")?;
                        let t = self.scalar_type()?;
                        params.push((v, t));
                        if self.eat(&Tok::RParen) {
                            break;
                        }
                        self.expect(Tok::Comma, "`,` or `)`")?;
                    }
                }
                self.expect(Tok::Colon, "`:` after the block label")?;
                self.end_of_line()?;
                func.blocks.push(RawBlock {
                    label: V { n, pos: wpos },
                    params,
                    insts: Vec::new(),
                });
                continue;
            }
            if let (Some(n), 2) = (numbered(w, "ss"), next) {
                self.bump();
                self.bump();
                self.keyword("slot")?;
                let ty = self.mem_type()?;
                let name = self.string("the slot's name as a string")?;
                self.end_of_line()?;
                func.slots.push(RawSlot {
                    num: V { n, pos: wpos },
                    ty,
                    name,
                });
                continue;
            }
            let inst = self.inst()?;
            let Some(block) = func.blocks.last_mut() else {
                return self.err(
                    wpos,
                    "instruction before the first block label (such as `block0:`)",
                );
            };
            block.insts.push(inst);
        }
        self.raw.funcs.push(func);
        Ok(())
    }

    fn value(&mut self) -> Result<V, ParseError> {
        match *self.peek() {
            Tok::Word(w) => match numbered(w, "v") {
                Some(n) => Ok(V {
                    n,
                    pos: self.bump(),
                }),
                None => self.unexpected("a value such as `v0`"),
            },
            _ => self.unexpected("a value such as `v0`"),
        }
    }

    fn at_line_end(&self) -> bool {
        matches!(self.peek(), Tok::Newline | Tok::Eof | Tok::Loc(_))
    }

    /// Comma-separated values up to the end of the line (or a location).
    fn values_to_eol(&mut self) -> Result<Vec<V>, ParseError> {
        let mut out = Vec::new();
        if self.at_line_end() {
            return Ok(out);
        }
        loop {
            out.push(self.value()?);
            if self.at_line_end() {
                return Ok(out);
            }
            self.expect(Tok::Comma, "`,` or the end of the line")?;
        }
    }

    /// Comma-separated values up to `)`, which is consumed.
    fn values_to_paren(&mut self) -> Result<Vec<V>, ParseError> {
        let mut out = Vec::new();
        if self.eat(&Tok::RParen) {
            return Ok(out);
        }
        loop {
            out.push(self.value()?);
            if self.eat(&Tok::RParen) {
                return Ok(out);
            }
            self.expect(Tok::Comma, "`,` or `)`")?;
        }
    }

    fn operands<const N: usize>(&mut self, mnemonic: &str, pos: Pos) -> Result<[V; N], ParseError> {
        let vals = self.values_to_eol()?;
        match <[V; N]>::try_from(vals) {
            Ok(a) => Ok(a),
            Err(v) => self.err(
                pos,
                format!(
                    "`{mnemonic}` takes {N} operand{}, found {}",
                    if N == 1 { "" } else { "s" },
                    v.len()
                ),
            ),
        }
    }

    fn block_call(&mut self) -> Result<RawBlockCall, ParseError> {
        let (w, pos) = self.word("a block such as `block1`")?;
        let Some(n) = numbered(w, "block") else {
            return self.err(
                pos,
                format!("expected a block such as `block1`, found `{w}`"),
            );
        };
        let args = if self.eat(&Tok::LParen) {
            self.values_to_paren()?
        } else {
            Vec::new()
        };
        Ok(RawBlockCall {
            block: V { n, pos },
            args,
        })
    }

    fn inst(&mut self) -> Result<RawInst<'a>, ParseError> {
        let mut result = None;
        if let Tok::Word(w) = *self.peek() {
            if *self.peek2() == Tok::Equals {
                let Some(n) = numbered(w, "v") else {
                    return self.err(
                        self.pos(),
                        format!("expected a value such as `v0` before `=`, found `{w}`"),
                    );
                };
                result = Some(V { n, pos: self.pos() });
                self.bump();
                self.bump();
            }
        }
        let (word, pos) = self.word("an instruction")?;
        let (m, suffix) = match word.split_once('.') {
            Some((a, b)) => (a, Some(b)),
            None => (word, None),
        };
        let typed = matches!(m, "iconst" | "fconst" | "sizeof" | "load")
            || ConvOp::ALL.iter().any(|c| c.name() == m);
        let ty = match (suffix, typed) {
            (None, true) => {
                return self.err(pos, format!("`{m}` needs a type, as in `{m}.i32`"));
            }
            (Some(s), true) => match Type::from_name(s) {
                Some(t) => t,
                None => return self.err(pos, format!("unknown type `{s}` in `{word}`")),
            },
            (Some(_), false) => return self.err(pos, format!("unknown instruction `{word}`")),
            (None, false) => Type::I32,
        };
        let op = if let Some(&op) = UnaryOp::ALL.iter().find(|o| o.name() == m) {
            let [a] = self.operands(m, pos)?;
            RawOp::Unary(op, a)
        } else if let Some(&op) = BinaryOp::ALL.iter().find(|o| o.name() == m) {
            let [a, b] = self.operands(m, pos)?;
            RawOp::Binary(op, a, b)
        } else if let Some(&op) = ConvOp::ALL.iter().find(|o| o.name() == m) {
            let [a] = self.operands(m, pos)?;
            RawOp::Convert(op, ty, a)
        } else if let Some(&op) = Intrinsic::ALL.iter().find(|o| o.name() == m) {
            RawOp::Intrinsic(op, self.values_to_eol()?)
        } else {
            match m {
                "iconst" => {
                    let (n, npos) = self.num_text("an integer")?;
                    match parse_int(n) {
                        Some(v) => RawOp::Iconst(ty, v),
                        None => return self.err(npos, format!("`{n}` is not a 64-bit integer")),
                    }
                }
                "sizeof" => RawOp::SizeOf(ty, self.mem_type()?),
                "fconst" => {
                    if !ty.is_float() {
                        return self.err(pos, format!("`fconst` needs `f32` or `f64`, not `{ty}`"));
                    }
                    let (n, npos) = match *self.peek() {
                        Tok::Num(n) | Tok::Word(n) => (n, self.bump()),
                        _ => return self.unexpected("a float constant"),
                    };
                    match parse_float(ty, n) {
                        Some(bits) => RawOp::Fconst(ty, bits),
                        None => return self.err(npos, format!("`{n}` is not a float constant")),
                    }
                }
                "icmp" => {
                    let (c, cpos) = self.word("a condition (`eq`, `slt`, …)")?;
                    let Some(&cc) = IntCC::ALL.iter().find(|x| x.name() == c) else {
                        return self.err(cpos, format!("unknown integer condition `{c}`"));
                    };
                    let [a, b] = self.operands(m, pos)?;
                    RawOp::Icmp(cc, a, b)
                }
                "fcmp" => {
                    let (c, cpos) = self.word("a condition (`eq`, `lt`, …)")?;
                    let Some(&cc) = FloatCC::ALL.iter().find(|x| x.name() == c) else {
                        return self.err(cpos, format!("unknown float condition `{c}`"));
                    };
                    let [a, b] = self.operands(m, pos)?;
                    RawOp::Fcmp(cc, a, b)
                }
                "select" => {
                    let [c, a, b] = self.operands(m, pos)?;
                    RawOp::Select(c, a, b)
                }
                "global_addr" => RawOp::GlobalAddr(self.global("a data name such as `@d`")?),
                "slot_addr" => {
                    let (w, wpos) = self.word("a slot such as `ss0`")?;
                    let Some(n) = numbered(w, "ss") else {
                        return self
                            .err(wpos, format!("expected a slot such as `ss0`, found `{w}`"));
                    };
                    RawOp::SlotAddr(V { n, pos: wpos })
                }
                "field_addr" => {
                    let base = self.value()?;
                    self.expect(Tok::Comma, "`,`")?;
                    let apos = self.pos();
                    let ok = match self.peek() {
                        Tok::Agg(a) => {
                            a.field.is_some()
                                || (a.plain
                                    && a.name
                                        .rsplit_once('.')
                                        .is_some_and(|(x, f)| !x.is_empty() && !f.is_empty()))
                        }
                        _ => return self.unexpected("a field such as `%S.f`"),
                    };
                    if !ok {
                        return self.err(apos, "expected a field such as `%S.f`");
                    }
                    let Tok::Agg(a) = self.advance().tok else {
                        unreachable!("peeked an aggregate")
                    };
                    let (agg, field) = match (a.field, a.name) {
                        (Some(f), name) => (name, f),
                        (None, Cow::Borrowed(n)) => match n.rsplit_once('.') {
                            Some((x, f)) => (Cow::Borrowed(x), Cow::Borrowed(f)),
                            None => unreachable!("checked above"),
                        },
                        (None, Cow::Owned(n)) => match n.rsplit_once('.') {
                            Some((x, f)) => (Cow::Owned(x.to_string()), Cow::Owned(f.to_string())),
                            None => unreachable!("checked above"),
                        },
                    };
                    RawOp::FieldAddr(Box::new((
                        base,
                        Named {
                            name: agg,
                            pos: apos,
                        },
                        field,
                    )))
                }
                "inline_c" => {
                    let agg = self.agg_name("a struct type such as `%S`")?;
                    self.expect(Tok::Comma, "`,`")?;
                    let data = self.value()?;
                    self.expect(Tok::Comma, "`,`")?;
                    let code = self.string("the C code as a string")?;
                    RawOp::InlineC(Box::new((agg, data, code)))
                }
                "elem_addr" => {
                    let base = self.value()?;
                    self.expect(Tok::Comma, "`,`")?;
                    let agg = self.agg_name("an array type such as `%A`")?;
                    self.expect(Tok::Comma, "`,`")?;
                    let index = self.value()?;
                    RawOp::ElemAddr(Box::new((base, agg, index)))
                }
                "load" => {
                    let [a] = self.operands(m, pos)?;
                    RawOp::Load(ty, a)
                }
                "store" => {
                    let [v, a] = self.operands(m, pos)?;
                    RawOp::Store(v, a)
                }
                "call" => {
                    let f = self.global("a function name such as `@f`")?;
                    self.expect(Tok::LParen, "`(`")?;
                    RawOp::Call(Box::new((f, self.values_to_paren()?)))
                }
                "call_table" => {
                    let t = self.table_ref()?;
                    self.expect(Tok::Comma, "`,`")?;
                    let index = self.value()?;
                    self.expect(Tok::LParen, "`(`")?;
                    RawOp::CallTable(Box::new((t, index, self.values_to_paren()?)))
                }
                "jump" => RawOp::Jump(Box::new(self.block_call()?)),
                "brif" => {
                    let c = self.value()?;
                    self.expect(Tok::Comma, "`,`")?;
                    let t = self.block_call()?;
                    self.expect(Tok::Comma, "`,`")?;
                    let e = self.block_call()?;
                    RawOp::Brif(Box::new((c, t, e)))
                }
                "br_table" => self.br_table()?,
                "return" => {
                    let vals = self.values_to_eol()?;
                    if vals.len() > 1 {
                        return self.err(
                            pos,
                            format!("`return` takes at most 1 operand, found {}", vals.len()),
                        );
                    }
                    RawOp::Return(vals.first().copied())
                }
                _ => return self.err(pos, format!("unknown instruction `{word}`")),
            }
        };
        let span = self.loc();
        self.end_of_line()?;
        Ok(RawInst {
            result,
            pos,
            mnemonic: m,
            op,
            span,
        })
    }
}
