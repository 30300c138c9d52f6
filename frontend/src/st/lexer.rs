//! The Structured Text lexer: source text to a flat vector of small `Copy` tokens.
//!
//! One pass over the bytes, no allocation per token: names are interned as they are
//! met (the token keeps the symbol), literal values go to a side table (the token
//! keeps the index). Keywords are recognised through the interner too, so a word
//! costs one hash lookup whether it is a keyword or a name.
//!
//! Lexical errors are reported here, once; a bad character becomes an [`Tok::Error`]
//! token so that the parser can recover without reporting it again, and a malformed
//! literal still becomes a literal token (with a placeholder value).

use super::literals::{self, DigitError};
use crate::ast::{Ident, Literal, LiteralKind};
use crate::codes;
use crate::intern::{Interner, Symbol};
use plcc_ir::diag::{Diagnostic, FileId, Span};

/// Token kinds. Only words the grammar needs to be reserved are keywords; others
/// with a meaning in some context only (`ON`, `WITH`, `STEP`, `METHOD`, ...) are
/// identifiers that the parser recognises by symbol where they matter.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
#[repr(u8)]
pub enum Tok {
    /// End of input (always the last token).
    Eof,
    /// Bytes that start no token; already reported by the lexer.
    Error,
    /// A name; `data` is its [`Symbol`].
    Ident,
    /// A literal; [`Lexed::literal`] gives its value.
    Lit,
    /// A direct address `%IX0.0`, `%QW1`, `%I*`, or a partial access `%X3`, `%B1`.
    Address,
    /// `:=`
    Assign,
    /// `=>`
    Arrow,
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
    /// `**`
    Pow,
    /// `&`
    Amp,
    /// `(`
    LParen,
    /// `)`
    RParen,
    /// `[`
    LBracket,
    /// `]`
    RBracket,
    /// `,`
    Comma,
    /// `;`
    Semi,
    /// `:`
    Colon,
    /// `.`
    Dot,
    /// `..`
    DotDot,
    /// `^`
    Caret,
    /// `#`
    Hash,
    /// `PROGRAM`
    Program,
    /// `END_PROGRAM`
    EndProgram,
    /// `FUNCTION`
    Function,
    /// `END_FUNCTION`
    EndFunction,
    /// `FUNCTION_BLOCK`
    FunctionBlock,
    /// `END_FUNCTION_BLOCK`
    EndFunctionBlock,
    /// `TYPE`
    Type,
    /// `END_TYPE`
    EndType,
    /// `STRUCT`
    Struct,
    /// `END_STRUCT`
    EndStruct,
    /// `VAR`
    Var,
    /// `VAR_INPUT`
    VarInput,
    /// `VAR_OUTPUT`
    VarOutput,
    /// `VAR_IN_OUT`
    VarInOut,
    /// `VAR_TEMP`
    VarTemp,
    /// `VAR_GLOBAL`
    VarGlobal,
    /// `VAR_EXTERNAL`
    VarExternal,
    /// `VAR_ACCESS`
    VarAccess,
    /// `VAR_CONFIG`
    VarConfig,
    /// `VAR_STAT`
    VarStat,
    /// `VAR_INST` (CODESYS: a METHOD's variables kept in the instance)
    VarInst,
    /// `END_VAR`
    EndVar,
    /// `CONSTANT`
    Constant,
    /// `RETAIN`
    Retain,
    /// `NON_RETAIN`
    NonRetain,
    /// `PERSISTENT`
    Persistent,
    /// `AT`
    At,
    /// `ARRAY`
    Array,
    /// `OF`
    Of,
    /// `STRING`
    String,
    /// `WSTRING`
    WString,
    /// `REF_TO`
    RefTo,
    /// `IF`
    If,
    /// `THEN`
    Then,
    /// `ELSIF`
    Elsif,
    /// `ELSE`
    Else,
    /// `END_IF`
    EndIf,
    /// `CASE`
    Case,
    /// `END_CASE`
    EndCase,
    /// `FOR`
    For,
    /// `TO`
    To,
    /// `BY`
    By,
    /// `DO`
    Do,
    /// `END_FOR`
    EndFor,
    /// `WHILE`
    While,
    /// `END_WHILE`
    EndWhile,
    /// `REPEAT`
    Repeat,
    /// `UNTIL`
    Until,
    /// `END_REPEAT`
    EndRepeat,
    /// `EXIT`
    Exit,
    /// `CONTINUE`
    Continue,
    /// `RETURN`
    Return,
    /// `AND`
    And,
    /// `OR`
    Or,
    /// `XOR`
    Xor,
    /// `NOT`
    Not,
    /// `MOD`
    Mod,
    /// `AND_THEN`
    AndThen,
    /// `OR_ELSE`
    OrElse,
    /// `TRUE`
    True,
    /// `FALSE`
    False,
    /// `CONFIGURATION`
    Configuration,
    /// `END_CONFIGURATION`
    EndConfiguration,
    /// `END_RESOURCE`
    EndResource,
    /// `END_ACTION`
    EndAction,
    /// `END_METHOD`
    EndMethod,
    /// `END_PROPERTY`
    EndProperty,
    /// `END_INTERFACE`
    EndInterface,
    /// `END_CLASS`
    EndClass,
    /// `END_STEP`
    EndStep,
    /// `END_TRANSITION`
    EndTransition,
    /// `END_ACTIONS`
    EndActions,
    /// `END_GET` (a PROPERTY's getter)
    EndGet,
    /// `END_SET` (a PROPERTY's setter)
    EndSet,
}

/// The reserved words and their tokens.
const KEYWORDS: &[(&str, Tok)] = &[
    ("PROGRAM", Tok::Program),
    ("END_PROGRAM", Tok::EndProgram),
    ("FUNCTION", Tok::Function),
    ("END_FUNCTION", Tok::EndFunction),
    ("FUNCTION_BLOCK", Tok::FunctionBlock),
    ("END_FUNCTION_BLOCK", Tok::EndFunctionBlock),
    ("TYPE", Tok::Type),
    ("END_TYPE", Tok::EndType),
    ("STRUCT", Tok::Struct),
    ("END_STRUCT", Tok::EndStruct),
    ("VAR", Tok::Var),
    ("VAR_INPUT", Tok::VarInput),
    ("VAR_OUTPUT", Tok::VarOutput),
    ("VAR_IN_OUT", Tok::VarInOut),
    ("VAR_TEMP", Tok::VarTemp),
    ("VAR_GLOBAL", Tok::VarGlobal),
    ("VAR_EXTERNAL", Tok::VarExternal),
    ("VAR_ACCESS", Tok::VarAccess),
    ("VAR_CONFIG", Tok::VarConfig),
    ("VAR_STAT", Tok::VarStat),
    ("VAR_INST", Tok::VarInst),
    ("END_VAR", Tok::EndVar),
    ("CONSTANT", Tok::Constant),
    ("RETAIN", Tok::Retain),
    ("NON_RETAIN", Tok::NonRetain),
    ("PERSISTENT", Tok::Persistent),
    ("AT", Tok::At),
    ("ARRAY", Tok::Array),
    ("OF", Tok::Of),
    ("STRING", Tok::String),
    ("WSTRING", Tok::WString),
    ("REF_TO", Tok::RefTo),
    ("IF", Tok::If),
    ("THEN", Tok::Then),
    ("ELSIF", Tok::Elsif),
    ("ELSE", Tok::Else),
    ("END_IF", Tok::EndIf),
    ("CASE", Tok::Case),
    ("END_CASE", Tok::EndCase),
    ("FOR", Tok::For),
    ("TO", Tok::To),
    ("BY", Tok::By),
    ("DO", Tok::Do),
    ("END_FOR", Tok::EndFor),
    ("WHILE", Tok::While),
    ("END_WHILE", Tok::EndWhile),
    ("REPEAT", Tok::Repeat),
    ("UNTIL", Tok::Until),
    ("END_REPEAT", Tok::EndRepeat),
    ("EXIT", Tok::Exit),
    ("CONTINUE", Tok::Continue),
    ("RETURN", Tok::Return),
    ("AND", Tok::And),
    ("OR", Tok::Or),
    ("XOR", Tok::Xor),
    ("NOT", Tok::Not),
    ("MOD", Tok::Mod),
    ("AND_THEN", Tok::AndThen),
    ("OR_ELSE", Tok::OrElse),
    ("TRUE", Tok::True),
    ("FALSE", Tok::False),
    ("CONFIGURATION", Tok::Configuration),
    ("END_CONFIGURATION", Tok::EndConfiguration),
    ("END_RESOURCE", Tok::EndResource),
    ("END_ACTION", Tok::EndAction),
    ("END_METHOD", Tok::EndMethod),
    ("END_PROPERTY", Tok::EndProperty),
    ("END_INTERFACE", Tok::EndInterface),
    ("END_CLASS", Tok::EndClass),
    ("END_STEP", Tok::EndStep),
    ("END_TRANSITION", Tok::EndTransition),
    ("END_ACTIONS", Tok::EndActions),
    ("END_GET", Tok::EndGet),
    ("END_SET", Tok::EndSet),
];

impl Tok {
    /// True for the `END_` keywords (`END_IF`, `END_VAR`, `END_PROGRAM`, ...).
    pub fn is_end_keyword(self) -> bool {
        matches!(
            self,
            Tok::EndProgram
                | Tok::EndFunction
                | Tok::EndFunctionBlock
                | Tok::EndType
                | Tok::EndStruct
                | Tok::EndVar
                | Tok::EndIf
                | Tok::EndCase
                | Tok::EndFor
                | Tok::EndWhile
                | Tok::EndRepeat
                | Tok::EndConfiguration
                | Tok::EndResource
                | Tok::EndAction
                | Tok::EndMethod
                | Tok::EndProperty
                | Tok::EndInterface
                | Tok::EndClass
                | Tok::EndStep
                | Tok::EndTransition
                | Tok::EndActions
                | Tok::EndGet
                | Tok::EndSet
        )
    }

    /// True for reserved words (`IF`, `BY`, `AND`, ...), which cannot be names.
    pub fn is_keyword(self) -> bool {
        KEYWORDS.iter().any(|&(_, t)| t == self)
    }

    /// How the token is written, for messages (keywords in upper case).
    pub fn text(self) -> &'static str {
        if let Some(&(name, _)) = KEYWORDS.iter().find(|&&(_, t)| t == self) {
            return name;
        }
        match self {
            Tok::Eof => "end of file",
            Tok::Error => "invalid character",
            Tok::Ident => "identifier",
            Tok::Lit => "literal",
            Tok::Address => "direct address",
            Tok::Assign => ":=",
            Tok::Arrow => "=>",
            Tok::Eq => "=",
            Tok::Ne => "<>",
            Tok::Lt => "<",
            Tok::Le => "<=",
            Tok::Gt => ">",
            Tok::Ge => ">=",
            Tok::Plus => "+",
            Tok::Minus => "-",
            Tok::Star => "*",
            Tok::Slash => "/",
            Tok::Pow => "**",
            Tok::Amp => "&",
            Tok::LParen => "(",
            Tok::RParen => ")",
            Tok::LBracket => "[",
            Tok::RBracket => "]",
            Tok::Comma => ",",
            Tok::Semi => ";",
            Tok::Colon => ":",
            Tok::Dot => ".",
            Tok::DotDot => "..",
            Tok::Caret => "^",
            Tok::Hash => "#",
            _ => "keyword",
        }
    }
}

/// `Token::flags` bit: a line break (possibly inside a comment) precedes the token.
pub const NEWLINE_BEFORE: u8 = 1;
/// `Token::flags` bit: an unterminated literal that swallowed the rest of its line
/// (already reported; the parser does not report what is missing after it).
pub const SWALLOWED: u8 = 2;
/// `Token::flags` bit: a [`Tok::Lit`] integer literal without prefix whose value,
/// between 0 and `u32::MAX`, is `data` itself (most literals; no table entry).
pub const INLINE_INT: u8 = 4;
/// `Token::flags` bit: a [`Tok::Lit`] real literal without prefix; its value is the
/// token's text without `_` (no table entry).
pub const INLINE_REAL: u8 = 8;

/// One token: 16 bytes, `Copy`.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct Token {
    /// What it is.
    pub kind: Tok,
    /// [`NEWLINE_BEFORE`], [`SWALLOWED`].
    pub flags: u8,
    /// Byte offset of its first byte.
    pub start: u32,
    /// Byte offset one past its last byte.
    pub end: u32,
    /// The symbol of an [`Tok::Ident`]; for a [`Tok::Lit`] the index of its value in
    /// [`Lexed::literals`], or the value itself with [`INLINE_INT`]; else 0.
    pub data: u32,
}

impl Token {
    /// True if a line break comes between the previous token and this one.
    pub fn newline_before(&self) -> bool {
        self.flags & NEWLINE_BEFORE != 0
    }
}

/// The lexer's output.
#[derive(Debug, Default)]
pub struct Lexed {
    /// The tokens, ending with exactly one [`Tok::Eof`].
    pub tokens: Vec<Token>,
    /// Values of the [`Tok::Lit`] tokens.
    pub literals: Vec<Literal>,
    /// An unterminated comment, pragma or string ran into the end of the file (the
    /// parser then keeps quiet about what is missing at the end).
    pub eof_in_error: bool,
    /// The pragmas holding C code, in source order: byte ranges with their braces.
    /// The ST parser makes those that stand where a statement may stand statements
    /// (copied into the `c` target's output); every other one is skipped with
    /// warning W0010 (see [`Lexed::warn_c_pragmas`]).
    pub c_pragmas: Vec<(u32, u32)>,
}

impl Lexed {
    /// Warning W0010 for each C pragma from index `from` on, for a front end that
    /// keeps none of them (`why` says why).
    pub fn warn_c_pragmas(
        &self,
        file: FileId,
        from: usize,
        why: &str,
        diags: &mut Vec<Diagnostic>,
    ) {
        for &(s, e) in self.c_pragmas.iter().skip(from) {
            diags.push(super::pragma::skipped_c(file, s, e, why));
        }
    }

    /// The value of the literal token `t` (`text` is the lexed source).
    pub fn literal(&self, text: &str, t: Token) -> Literal {
        let kind = if t.flags & INLINE_INT != 0 {
            LiteralKind::Int(t.data as i128)
        } else if t.flags & INLINE_REAL != 0 {
            let s = text.get(t.start as usize..t.end as usize).unwrap_or("0.0");
            LiteralKind::Real(s.chars().filter(|&c| c != '_').collect::<String>().into())
        } else {
            return self
                .literals
                .get(t.data as usize)
                .cloned()
                .unwrap_or(Literal {
                    kind: LiteralKind::Int(0),
                    type_prefix: None,
                });
        };
        Literal {
            kind,
            type_prefix: None,
        }
    }
}

/// What the word before a `#` makes of the literal after it.
#[derive(Copy, Clone, PartialEq, Eq)]
enum Prefix {
    Duration(bool),
    Date(bool),
    Tod(bool),
    Dt(bool),
    /// An elementary type name: `INT#5`, `REAL#1.5`, `BOOL#TRUE`, `STRING#'x'`.
    Typed,
}

fn prefix_of(upper: &[u8]) -> Option<Prefix> {
    Some(match upper {
        b"T" | b"TIME" => Prefix::Duration(false),
        b"LT" | b"LTIME" => Prefix::Duration(true),
        b"D" | b"DATE" => Prefix::Date(false),
        b"LD" | b"LDATE" => Prefix::Date(true),
        b"TOD" | b"TIME_OF_DAY" => Prefix::Tod(false),
        b"LTOD" | b"LTIME_OF_DAY" => Prefix::Tod(true),
        b"DT" | b"DATE_AND_TIME" => Prefix::Dt(false),
        b"LDT" | b"LDATE_AND_TIME" => Prefix::Dt(true),
        b"BOOL" | b"SINT" | b"INT" | b"DINT" | b"LINT" | b"USINT" | b"UINT" | b"UDINT"
        | b"ULINT" | b"BYTE" | b"WORD" | b"DWORD" | b"LWORD" | b"REAL" | b"LREAL" | b"STRING"
        | b"WSTRING" | b"CHAR" | b"WCHAR" => Prefix::Typed,
        _ => return None,
    })
}

fn is_ident_byte(b: u8) -> bool {
    b.is_ascii_alphanumeric() || b == b'_'
}

/// True if `s` is read as one identifier: a name, not a keyword (for text that
/// generates ST, such as the PLCopen view).
pub fn is_identifier(s: &str) -> bool {
    let b = s.as_bytes();
    !b.is_empty()
        && !b[0].is_ascii_digit()
        && b.iter().all(|&c| is_ident_byte(c))
        && !KEYWORDS.iter().any(|(k, _)| k.eq_ignore_ascii_case(s))
}

/// Splits `text` into tokens. Errors go to `diags`; the result always ends with
/// [`Tok::Eof`].
pub fn lex(
    file: FileId,
    text: &str,
    interner: &mut Interner,
    diags: &mut Vec<Diagnostic>,
) -> Lexed {
    lex_from(file, text, 0, text.len(), interner, diags)
}

/// The token kind of each keyword's symbol (interning the keywords).
pub(super) fn keyword_table(interner: &mut Interner) -> Vec<Tok> {
    let mut keywords: Vec<Tok> = Vec::new();
    for &(name, tok) in KEYWORDS {
        let sym = interner.intern_upper(name).0 as usize;
        if keywords.len() <= sym {
            keywords.resize(sym + 1, Tok::Ident);
        }
        keywords[sym] = tok;
    }
    keywords
}

/// Lexes `text` from byte `from` on, which is 0 or the start of a line (whose first
/// token then has [`NEWLINE_BEFORE`]); offsets stay those of `text`. The token vector
/// has room for `room` bytes of text.
pub(super) fn lex_from(
    file: FileId,
    text: &str,
    from: usize,
    room: usize,
    interner: &mut Interner,
    diags: &mut Vec<Diagnostic>,
) -> Lexed {
    let keywords = keyword_table(interner);
    let mut lx = Lexer {
        file,
        text,
        src: text.as_bytes(),
        pos: from,
        // ST averages about 4 bytes per token; pages of the unused tail are never
        // touched, while growing would copy the whole vector.
        tokens: Vec::with_capacity(room / 3 + 16),
        literals: Vec::new(),
        diags,
        interner,
        keywords,
        upper: String::new(),
        flags: if from > 0 { NEWLINE_BEFORE } else { 0 },
        eof_in_error: false,
        c_pragmas: Vec::new(),
        swallowed: false,
        word_cache: vec![
            CachedWord {
                start: 0,
                len: 0,
                kind: Tok::Ident,
                data: 0,
            };
            1 << WORD_CACHE_BITS
        ],
    };
    lx.run();
    Lexed {
        tokens: lx.tokens,
        literals: lx.literals,
        eof_in_error: lx.eof_in_error,
        c_pragmas: lx.c_pragmas,
    }
}

/// log2 of the number of entries of the lexer's word cache.
const WORD_CACHE_BITS: u32 = 12;

/// A word already lexed: where it is written, and its token.
#[derive(Copy, Clone)]
struct CachedWord {
    start: u32,
    /// 0: empty entry.
    len: u32,
    kind: Tok,
    data: u32,
}

struct Lexer<'a> {
    file: FileId,
    text: &'a str,
    src: &'a [u8],
    pos: usize,
    tokens: Vec<Token>,
    literals: Vec<Literal>,
    diags: &'a mut Vec<Diagnostic>,
    interner: &'a mut Interner,
    /// Token kind by symbol index, for symbols of keywords.
    keywords: Vec<Tok>,
    upper: String,
    flags: u8,
    eof_in_error: bool,
    /// See [`Lexed::c_pragmas`].
    c_pragmas: Vec<(u32, u32)>,
    /// The literal being lexed is an unterminated string.
    swallowed: bool,
    word_cache: Vec<CachedWord>,
}

impl<'a> Lexer<'a> {
    fn span(&self, start: usize, end: usize) -> Span {
        Span::new(self.file, start as u32, end as u32)
    }

    fn peek(&self, ahead: usize) -> u8 {
        self.src.get(self.pos + ahead).copied().unwrap_or(0)
    }

    fn error(&mut self, code: &'static str, msg: String, start: usize, end: usize, label: &str) {
        let d = Diagnostic::error(code, msg, self.span(start, end)).with_label(label);
        self.diags.push(d);
    }

    fn push(&mut self, kind: Tok, start: usize, data: u32) {
        self.tokens.push(Token {
            kind,
            flags: self.flags,
            start: start as u32,
            end: self.pos as u32,
            data,
        });
        self.flags = 0;
    }

    fn flag_last(&mut self, flag: u8) {
        if let Some(t) = self.tokens.last_mut() {
            t.flags |= flag;
        }
    }

    fn push_lit(&mut self, start: usize, kind: LiteralKind, type_prefix: Option<Ident>) {
        let idx = self.literals.len() as u32;
        self.literals.push(Literal { kind, type_prefix });
        self.push(Tok::Lit, start, idx);
        if self.swallowed {
            self.swallowed = false;
            if let Some(t) = self.tokens.last_mut() {
                t.flags |= SWALLOWED;
            }
        }
    }

    fn run(&mut self) {
        loop {
            self.skip_trivia();
            let start = self.pos;
            if start >= self.src.len() {
                self.push(Tok::Eof, start, 0);
                return;
            }
            let c = self.src[start];
            let two = |k2: Tok, k1: Tok, second: u8, me: &mut Self| {
                if me.peek(1) == second {
                    me.pos += 2;
                    k2
                } else {
                    me.pos += 1;
                    k1
                }
            };
            let kind = match c {
                b'a'..=b'z' | b'A'..=b'Z' | b'_' => {
                    self.word();
                    continue;
                }
                b'0'..=b'9' => {
                    match self.number(false, true) {
                        LiteralKind::Int(v) if (0..=u32::MAX as i128).contains(&v) => {
                            self.push(Tok::Lit, start, v as u32);
                            self.flag_last(INLINE_INT);
                        }
                        LiteralKind::Real(_) => {
                            self.push(Tok::Lit, start, 0);
                            self.flag_last(INLINE_REAL);
                        }
                        kind => self.push_lit(start, kind, None),
                    }
                    continue;
                }
                b'\'' | b'"' => {
                    let kind = self.string();
                    self.push_lit(start, kind, None);
                    continue;
                }
                b'%' => {
                    self.address();
                    self.push(Tok::Address, start, 0);
                    continue;
                }
                b':' => two(Tok::Assign, Tok::Colon, b'=', self),
                b'=' => two(Tok::Arrow, Tok::Eq, b'>', self),
                b'<' => match self.peek(1) {
                    b'=' => {
                        self.pos += 2;
                        Tok::Le
                    }
                    b'>' => {
                        self.pos += 2;
                        Tok::Ne
                    }
                    _ => {
                        self.pos += 1;
                        Tok::Lt
                    }
                },
                b'>' => two(Tok::Ge, Tok::Gt, b'=', self),
                b'*' => two(Tok::Pow, Tok::Star, b'*', self),
                b'.' => two(Tok::DotDot, Tok::Dot, b'.', self),
                _ => {
                    let single = match c {
                        b'+' => Tok::Plus,
                        b'-' => Tok::Minus,
                        b'/' => Tok::Slash,
                        b'&' => Tok::Amp,
                        b'(' => Tok::LParen,
                        b')' => Tok::RParen,
                        b'[' => Tok::LBracket,
                        b']' => Tok::RBracket,
                        b',' => Tok::Comma,
                        b';' => Tok::Semi,
                        b'^' => Tok::Caret,
                        b'#' => Tok::Hash,
                        _ => {
                            self.garbage();
                            continue;
                        }
                    };
                    self.pos += 1;
                    single
                }
            };
            self.push(kind, start, 0);
        }
    }

    /// Whitespace, comments and pragmas; notes line breaks in `flags`.
    fn skip_trivia(&mut self) {
        let src = self.src;
        let len = src.len();
        loop {
            while self.pos < len {
                match src[self.pos] {
                    b' ' | b'\t' | b'\r' | 0x0b | 0x0c => self.pos += 1,
                    b'\n' => {
                        self.flags |= NEWLINE_BEFORE;
                        self.pos += 1;
                    }
                    // U+00A0 (no-break space): common in files that went through a
                    // Latin-1 editor; harmless as a separator.
                    0xC2 if self.peek(1) == 0xA0 => self.pos += 2,
                    _ => break,
                }
            }
            if self.pos >= len {
                return;
            }
            match (src[self.pos], self.peek(1)) {
                (b'(', b'*') => self.block_comment(),
                (b'/', b'*') => self.c_comment(),
                (b'/', b'/') => {
                    while self.pos < len && src[self.pos] != b'\n' {
                        self.pos += 1;
                    }
                }
                (b'{', _) => self.pragma(),
                _ => return,
            }
        }
    }

    /// `(* ... *)`, nested comments counted.
    fn block_comment(&mut self) {
        let start = self.pos;
        let src = self.src;
        let mut depth = 0usize;
        let mut i = self.pos;
        while i < src.len() {
            match src[i] {
                b'(' if src.get(i + 1) == Some(&b'*') => {
                    depth += 1;
                    i += 2;
                }
                b'*' if src.get(i + 1) == Some(&b')') => {
                    depth -= 1;
                    i += 2;
                    if depth == 0 {
                        self.pos = i;
                        return;
                    }
                }
                b'\n' => {
                    self.flags |= NEWLINE_BEFORE;
                    i += 1;
                }
                _ => i += 1,
            }
        }
        self.pos = src.len();
        self.eof_in_error = true;
        self.error(
            codes::UNTERMINATED_COMMENT,
            "unterminated comment: `(*` has no matching `*)`".into(),
            start,
            start + 2,
            "this comment is never closed",
        );
    }

    /// `/* ... */` (not nested, as in C).
    fn c_comment(&mut self) {
        self.skip_to(
            2,
            b"*/",
            "unterminated comment: `/*` has no matching `*/`",
            "comment",
        );
    }

    /// `{ ... }` or `{{ ... }}`: skipped; one holding C code with a warning
    /// (see [`super::pragma`]).
    fn pragma(&mut self) {
        let start = self.pos;
        let skipped = super::pragma::skip(self.file, self.src, start);
        if self.src[start..skipped.end].contains(&b'\n') {
            self.flags |= NEWLINE_BEFORE;
        }
        self.pos = skipped.end;
        self.eof_in_error |= skipped.unterminated;
        self.diags.extend(skipped.diag);
        if skipped.c {
            self.c_pragmas.push((start as u32, skipped.end as u32));
        }
    }

    /// Skips from an opener of `open` bytes through the first `close` (not nested),
    /// noting newlines; at the end of input, reports `message` at the opener.
    fn skip_to(&mut self, open: usize, close: &[u8], message: &str, what: &str) {
        let start = self.pos;
        let src = self.src;
        let mut i = self.pos + open;
        while i < src.len() {
            if src[i..].starts_with(close) {
                self.pos = i + close.len();
                return;
            }
            if src[i] == b'\n' {
                self.flags |= NEWLINE_BEFORE;
            }
            i += 1;
        }
        self.pos = src.len();
        self.eof_in_error = true;
        self.error(
            codes::UNTERMINATED_COMMENT,
            message.into(),
            start,
            start + open,
            &format!("this {what} is never closed"),
        );
    }

    /// A run of bytes that start no token: one error token, one diagnostic.
    fn garbage(&mut self) {
        let start = self.pos;
        let src = self.src;
        self.pos += 1;
        while self.pos < src.len() {
            let b = src[self.pos];
            let starts_token = b.is_ascii_alphanumeric()
                || b.is_ascii_whitespace()
                || b"_'\"%:=<>*./+-&()[],;^#{".contains(&b);
            if starts_token {
                break;
            }
            self.pos += 1;
        }
        let shown = self.text[start..].chars().next().unwrap_or('?');
        let msg = if shown.is_control() {
            format!("unexpected character U+{:04X}", shown as u32)
        } else {
            format!("unexpected character `{shown}`")
        };
        self.error(
            codes::UNEXPECTED_CHAR,
            msg,
            start,
            self.pos,
            "not valid here",
        );
        self.push(Tok::Error, start, 0);
    }

    /// A name, a keyword, or a literal with a prefix (`T#5s`, `INT#-5`).
    fn word(&mut self) {
        let start = self.pos;
        let src = self.src;
        let mut i = start + 1;
        while i < src.len() && is_ident_byte(src[i]) {
            i += 1;
        }
        self.pos = i;
        let word = &src[start..i];
        if self.peek(0) == b'#' {
            self.upper.clear();
            self.upper
                .extend(word.iter().map(|b| b.to_ascii_uppercase() as char));
            if let Some(p) = prefix_of(self.upper.as_bytes()) {
                self.prefixed_literal(start, p);
                return;
            }
        }
        // Most words were met before, spelt the same way: find them by their bytes.
        let mut h = word.len() as u32;
        for &b in word {
            h = h.wrapping_mul(31).wrapping_add(b as u32);
        }
        let slot = (h.wrapping_mul(0x9E37_79B9) >> (32 - WORD_CACHE_BITS)) as usize;
        let e = self.word_cache[slot];
        if e.len as usize == word.len()
            && &src[e.start as usize..e.start as usize + word.len()] == word
        {
            self.push(e.kind, start, e.data);
            return;
        }
        self.upper.clear();
        self.upper
            .extend(word.iter().map(|b| b.to_ascii_uppercase() as char));
        let sym = self.interner.intern_upper(&self.upper);
        let kind = self
            .keywords
            .get(sym.0 as usize)
            .copied()
            .unwrap_or(Tok::Ident);
        let data = if kind == Tok::Ident { sym.0 } else { 0 };
        self.word_cache[slot] = CachedWord {
            start: start as u32,
            len: word.len() as u32,
            kind,
            data,
        };
        self.push(kind, start, data);
    }

    /// After `PREFIX` and before its `#`.
    fn prefixed_literal(&mut self, start: usize, prefix: Prefix) {
        let word_end = self.pos;
        self.pos += 1; // '#'
        let body = self.pos;
        let src = self.src;
        let class: fn(u8) -> bool = match prefix {
            Prefix::Duration(_) => |b| is_ident_byte(b) || b == b'.',
            Prefix::Date(_) => |b| b.is_ascii_digit() || b == b'-',
            Prefix::Tod(_) => |b| b.is_ascii_digit() || b == b':' || b == b'.',
            Prefix::Dt(_) => |b| b.is_ascii_digit() || b == b'-' || b == b':' || b == b'.',
            Prefix::Typed => {
                let sym = self.interner.intern_upper(&self.upper);
                let ident = Ident {
                    sym,
                    span: self.span(start, word_end),
                };
                let kind = self.typed_value(start, word_end);
                self.push_lit(start, kind, Some(ident));
                return;
            }
        };
        let mut i = body;
        if matches!(prefix, Prefix::Duration(_)) && matches!(src.get(i), Some(b'-' | b'+')) {
            i += 1;
        }
        // A `.` belongs to the literal only before a digit (`T#1s..T#2s` is a range).
        while i < src.len()
            && class(src[i])
            && (src[i] != b'.' || src.get(i + 1).is_some_and(u8::is_ascii_digit))
        {
            i += 1;
        }
        // Letters glued to a date belong to the (bad) literal, not to the next token.
        while i < src.len() && is_ident_byte(src[i]) {
            i += 1;
        }
        self.pos = i;
        let t = &self.text[body..i];
        let (kind, code) = match prefix {
            Prefix::Duration(long) => (
                literals::duration(t).map(|ns| LiteralKind::Duration { ns, long }),
                codes::MALFORMED_DURATION,
            ),
            Prefix::Date(long) => (
                literals::date(t).map(|days| LiteralKind::Date { days, long }),
                codes::MALFORMED_DATE_TIME,
            ),
            Prefix::Tod(long) => (
                literals::time_of_day(t).map(|ns| LiteralKind::TimeOfDay { ns, long }),
                codes::MALFORMED_DATE_TIME,
            ),
            Prefix::Dt(long) => (
                literals::date_time(t).map(|ns| LiteralKind::DateTime { ns, long }),
                codes::MALFORMED_DATE_TIME,
            ),
            Prefix::Typed => unreachable!("handled above"),
        };
        let kind = match kind {
            Ok(k) => k,
            Err(msg) => {
                let what = &self.text[start..word_end];
                self.error(
                    code,
                    format!("malformed `{what}#` literal: {msg}"),
                    start,
                    i.max(body),
                    "malformed literal",
                );
                match prefix {
                    Prefix::Duration(long) => LiteralKind::Duration { ns: 0, long },
                    Prefix::Date(long) => LiteralKind::Date { days: 0, long },
                    Prefix::Tod(long) => LiteralKind::TimeOfDay { ns: 0, long },
                    _ => LiteralKind::DateTime {
                        ns: 0,
                        long: matches!(prefix, Prefix::Dt(true)),
                    },
                }
            }
        };
        self.push_lit(start, kind, None);
    }

    /// The value after `TYPE#`: a signed number, TRUE/FALSE or a string.
    fn typed_value(&mut self, start: usize, word_end: usize) -> LiteralKind {
        let src = self.src;
        let mut neg = false;
        if matches!(self.peek(0), b'-' | b'+') {
            neg = self.peek(0) == b'-';
            self.pos += 1;
        }
        let is_bool = &self.upper == "BOOL";
        let c = self.peek(0);
        let kind = if c.is_ascii_digit() {
            self.number(neg, false)
        } else if c.is_ascii_alphabetic() && !neg {
            let ws = self.pos;
            while self.pos < src.len() && is_ident_byte(src[self.pos]) {
                self.pos += 1;
            }
            match self.text[ws..self.pos].to_ascii_uppercase().as_str() {
                "TRUE" => LiteralKind::Bool(true),
                "FALSE" => LiteralKind::Bool(false),
                other => {
                    let msg = format!(
                        "malformed `{}#` literal: expected a number, TRUE or FALSE, found `{other}`",
                        &self.text[start..word_end]
                    );
                    self.error(
                        codes::MALFORMED_TYPED_LITERAL,
                        msg,
                        start,
                        self.pos,
                        "malformed literal",
                    );
                    LiteralKind::Int(0)
                }
            }
        } else if (c == b'\'' || c == b'"') && !neg {
            self.string()
        } else {
            let msg = format!(
                "malformed `{}#` literal: expected a value after `#`",
                &self.text[start..word_end]
            );
            self.error(
                codes::MALFORMED_TYPED_LITERAL,
                msg,
                start,
                self.pos,
                "value missing",
            );
            LiteralKind::Int(0)
        };
        if is_bool {
            if let LiteralKind::Int(v) = kind {
                return match v {
                    0 => LiteralKind::Bool(false),
                    1 => LiteralKind::Bool(true),
                    _ => {
                        let msg =
                            "malformed `BOOL#` literal: the value must be 0, 1, TRUE or FALSE";
                        self.error(
                            codes::MALFORMED_TYPED_LITERAL,
                            msg.into(),
                            start,
                            self.pos,
                            "not a BOOL",
                        );
                        LiteralKind::Bool(false)
                    }
                };
            }
        }
        kind
    }

    /// A decimal, based or real number starting at a digit. `neg` negates it (for the
    /// `-` of a typed literal). With `inline_real` the text of a real is left empty
    /// (the token's text is the value).
    fn number(&mut self, neg: bool, inline_real: bool) -> LiteralKind {
        let start = self.pos;
        let src = self.src;
        let mut i = start;
        while i < src.len() && (src[i].is_ascii_digit() || src[i] == b'_') {
            i += 1;
        }
        let mut kind;
        if src.get(i) == Some(&b'#') {
            // Based: BASE#DIGITS
            let base = literals::parse_digits(&src[start..i], 10).unwrap_or(0);
            i += 1;
            let ds = i;
            while i < src.len() && is_ident_byte(src[i]) {
                i += 1;
            }
            self.pos = i;
            if !matches!(base, 2 | 8 | 16) {
                let msg = format!(
                    "invalid base `{}` in a based number (use 2#, 8# or 16#)",
                    &self.text[start..ds - 1]
                );
                self.error(codes::MALFORMED_NUMBER, msg, start, i, "invalid base");
                return LiteralKind::Int(0);
            }
            kind = match literals::parse_digits(&src[ds..i], base as u32) {
                Ok(v) => LiteralKind::Int(v),
                Err(e) => {
                    self.digit_error(e, start, i, base as u32);
                    LiteralKind::Int(0)
                }
            };
        } else {
            let mut real = false;
            if src.get(i) == Some(&b'.') && src.get(i + 1).is_some_and(|b| b.is_ascii_digit()) {
                real = true;
                i += 1;
                while i < src.len() && (src[i].is_ascii_digit() || src[i] == b'_') {
                    i += 1;
                }
            }
            if matches!(src.get(i), Some(b'e' | b'E')) {
                let mut j = i + 1;
                if matches!(src.get(j), Some(b'+' | b'-')) {
                    j += 1;
                }
                if src.get(j).is_some_and(|b| b.is_ascii_digit()) {
                    real = true;
                    i = j;
                    while i < src.len() && (src[i].is_ascii_digit() || src[i] == b'_') {
                        i += 1;
                    }
                }
            }
            self.pos = i;
            kind = if real && inline_real {
                LiteralKind::Real(Box::default())
            } else if real {
                let mut t = String::with_capacity(i - start + 1);
                if neg {
                    t.push('-');
                }
                t.extend(self.text[start..i].chars().filter(|&c| c != '_'));
                LiteralKind::Real(t.into_boxed_str())
            } else {
                match literals::parse_digits(&src[start..i], 10) {
                    Ok(v) => LiteralKind::Int(v),
                    Err(e) => {
                        self.digit_error(e, start, i, 10);
                        LiteralKind::Int(0)
                    }
                }
            };
            if !real && neg {
                if let LiteralKind::Int(v) = kind {
                    kind = LiteralKind::Int(-v);
                }
            }
            if i < src.len() && is_ident_byte(src[i]) {
                let ss = i;
                while i < src.len() && is_ident_byte(src[i]) {
                    i += 1;
                }
                self.pos = i;
                let msg = format!(
                    "invalid suffix `{}` after the number `{}`",
                    &self.text[ss..i],
                    &self.text[start..ss]
                );
                self.error(codes::MALFORMED_NUMBER, msg, start, i, "malformed number");
            }
            return kind;
        }
        if neg {
            if let LiteralKind::Int(v) = kind {
                kind = LiteralKind::Int(-v);
            }
        }
        kind
    }

    fn digit_error(&mut self, e: DigitError, start: usize, end: usize, base: u32) {
        let (code, msg, label) = match e {
            DigitError::BadDigit(b) => (
                codes::MALFORMED_NUMBER,
                format!("`{}` is not a digit in base {base}", b as char),
                "invalid digit",
            ),
            DigitError::NoDigits => (
                codes::MALFORMED_NUMBER,
                format!("expected digits in base {base} after `#`"),
                "digits missing",
            ),
            DigitError::TooLarge => (
                codes::INT_LITERAL_TOO_LARGE,
                "integer literal is too large".to_string(),
                "does not fit in 128 bits",
            ),
        };
        self.error(code, msg, start, end, label);
    }

    /// A `'STRING'` or `"WSTRING"` literal; a line break ends an unterminated one.
    fn string(&mut self) -> LiteralKind {
        let start = self.pos;
        let src = self.src;
        let quote = src[start];
        let wide = quote == b'"';
        let mut i = start + 1;
        let mut closed = false;
        while i < src.len() {
            match src[i] {
                b if b == quote => {
                    closed = true;
                    break;
                }
                b'\n' | b'\r' => break,
                b'$' if !matches!(src.get(i + 1), None | Some(b'\n' | b'\r')) => i += 2,
                _ => i += 1,
            }
        }
        let i = i.min(src.len());
        // `i` may sit inside a multi-byte character after `$`; back off to a boundary.
        let mut content_end = i;
        while !self.text.is_char_boundary(content_end) {
            content_end -= 1;
        }
        self.pos = if closed { i + 1 } else { content_end };
        if !closed {
            self.swallowed = true;
            if self.pos >= src.len() {
                self.eof_in_error = true;
            }
            let q = quote as char;
            self.error(
                codes::UNTERMINATED_STRING,
                format!("unterminated string literal: missing closing `{q}`"),
                start,
                self.pos,
                "this string is not closed on its line",
            );
        }
        let mut errors = Vec::new();
        let units = literals::decode_string(&self.text[start + 1..content_end], wide, &mut errors);
        for e in errors {
            let s = start + 1 + e.offset;
            self.error(
                codes::INVALID_ESCAPE,
                e.message,
                s,
                s + e.len,
                "invalid escape",
            );
        }
        LiteralKind::String { wide, units }
    }

    /// `%IX0.0`, `%QW1`, `%MD2`, `%I*`, and the partial accesses `%X3`, `%B1`.
    fn address(&mut self) {
        let start = self.pos;
        let src = self.src;
        let mut i = start + 1;
        let ls = i;
        while i < src.len() && src[i].is_ascii_alphabetic() {
            i += 1;
        }
        let letters = self.text[ls..i].to_ascii_uppercase();
        let mut star = false;
        let ds = i;
        if src.get(i) == Some(&b'*') {
            star = true;
            i += 1;
        } else {
            while i < src.len() && src[i].is_ascii_digit() {
                i += 1;
                if src.get(i) == Some(&b'.') && src.get(i + 1).is_some_and(|b| b.is_ascii_digit()) {
                    i += 1;
                }
            }
        }
        // Glued letters are part of the malformed address.
        while i < src.len() && is_ident_byte(src[i]) {
            i += 1;
        }
        self.pos = i;
        let digits = &self.text[ds..i];
        let l = letters.as_bytes();
        let area_ok = matches!(l.first(), Some(b'I' | b'Q' | b'M'))
            && (l.len() == 1 || (l.len() == 2 && b"XBWDL".contains(&l[1])));
        let partial_ok = l.len() == 1 && b"XBWDL".contains(&l[0]) && !digits.contains('.');
        let digits_ok = star
            || (!digits.is_empty()
                && digits.bytes().all(|b| b.is_ascii_digit() || b == b'.')
                && !digits.ends_with('.'));
        if !((area_ok || partial_ok && !star) && digits_ok) {
            let text = &self.text[start..i];
            let msg = if l.is_empty() {
                format!("malformed direct address `{text}`: expected I, Q or M after `%`")
            } else if !(area_ok || partial_ok) {
                format!("malformed direct address `{text}`: `{letters}` is not a location and size (use I, Q or M, then X, B, W, D or L)")
            } else {
                format!("malformed direct address `{text}`: expected a number or `*`")
            };
            self.error(codes::MALFORMED_ADDRESS, msg, start, i, "malformed address");
        }
    }
}

/// The symbol of an identifier token.
pub fn sym(tok: &Token) -> Symbol {
    Symbol(tok.data)
}

#[cfg(test)]
mod tests;
