//! The STL parser: recursive descent over the token vector, precedence climbing for
//! expressions (the precedence itself is described in the [module doc](super)).
//!
//! Error recovery follows the Structured Text parser's rules, so that one mistake
//! gives one diagnostic:
//! - at most one error per token: once an error is reported at a token, errors at that
//!   token or before it are dropped (the parser never moves backwards);
//! - a construct that failed is left out of the tree and the parser resynchronises at
//!   a `;`, a statement or declaration keyword, `end`, `until`, `else`, or a name at
//!   the start of a line that is followed by `:=`;
//! - a missing `;`, `then` or `do` is reported and assumed present when what follows
//!   can follow it, so the rest of the statement is still checked;
//! - too deep a nesting is reported once, and the rest of the file is skipped (any
//!   other error there could be a consequence).
//!
//! Nesting is limited ([`MAX_DEPTH`] recursion levels, [`MAX_HEIGHT`] for the height
//! of an expression tree) so that no input can overflow the stack, here or in the
//! passes that walk the tree.

use super::lexer::{Tok, Token};
use crate::ast::*;
use crate::codes;
use crate::intern::{Interner, Symbol};
use plcc_ir::diag::{Diagnostic, FileId, Span};

mod body;

/// The deepest nesting of parentheses, statements and operators accepted.
pub const MAX_DEPTH: u32 = 200;
/// The types of PLC-UD STL, which are the IEC 61131-3 types of the same names.
const STL_TYPES: [&str; 5] = ["BOOL", "INT", "UINT", "SINT", "USINT"];
/// The greatest height of an expression tree (nesting plus chained operators).
pub const MAX_HEIGHT: u32 = 1000;

/// Binding power of `not` at the condition level: looser than the comparisons,
/// tighter than `and` (`not a = b` is `not (a = b)`, `not a and b` is `(not a) and b`).
const NOT_BP: u8 = 4;
/// Binding power of the comparisons (non-associative).
const CMP_BP: u8 = 5;
/// Binding power of `+` and `-`; a sign at the start of an expression covers the
/// whole first term, as in the paper's `EXPR = [+|-] TERM {(+|-) TERM}`.
const ADD_BP: u8 = 6;
/// Binding power of `*`, `/`, `%`.
const MUL_BP: u8 = 7;
/// A prefix operator in factor position (after `*`, `+`, a comparison...) applies to
/// one factor only.
const FACTOR_BP: u8 = 8;

/// Parses the tokens of one file (see [`super::parse`]).
pub fn parse_tokens(
    file: FileId,
    text: &str,
    toks: &[Token],
    eof_silent: bool,
    interner: &mut Interner,
    diags: &mut Vec<Diagnostic>,
) -> SourceUnit {
    if toks.last().map(|t| t.kind) != Some(Tok::Eof) {
        // `lex` always ends with Eof; a hand-made token vector might not.
        return SourceUnit {
            file,
            items: Vec::new(),
        };
    }
    let syms = Syms::new(interner);
    let mut p = Parser {
        file,
        text,
        toks,
        pos: 0,
        diags,
        last_err: None,
        eof_silent,
        depth: 0,
        height: 0,
        bailed: false,
        order: LocalOrder::default(),
        locals: Vec::new(),
        syms,
    };
    let items = p.unit();
    SourceUnit { file, items }
}

/// Names the parser gives a meaning to.
struct Syms {
    /// `INC DEC SWAP SET CLR` and the internal builtins they call.
    stl_ops: [(Symbol, Symbol); 5],
    /// `SHL SHR ROL ROR`: with one argument they shift by one bit, as the quadruples
    /// of the PLC-UD toolchain do.
    shifts: [Symbol; 4],
    /// The name given to a program whose `program NAME;` header is missing.
    main: Symbol,
}

impl Syms {
    fn new(i: &mut Interner) -> Syms {
        let op =
            |i: &mut Interner, n: &str| (i.intern_upper(n), i.intern_upper(&format!("__STL_{n}")));
        Syms {
            stl_ops: [
                op(i, "INC"),
                op(i, "DEC"),
                op(i, "SWAP"),
                op(i, "SET"),
                op(i, "CLR"),
            ],
            shifts: [
                i.intern_upper("SHL"),
                i.intern_upper("SHR"),
                i.intern_upper("ROL"),
                i.intern_upper("ROR"),
            ],
            main: i.intern_upper("MAIN"),
        }
    }
}

/// Where the declarations of one body (main body or subprogram) stand, to check that
/// local var blocks come before local constants, and both before the statements.
#[derive(Copy, Clone, Default)]
struct LocalOrder {
    /// A local constant was declared.
    constant_seen: bool,
    /// A statement was parsed.
    stmt_seen: bool,
}

/// The global sections in their required order.
#[derive(Copy, Clone, PartialEq, Eq, PartialOrd, Ord)]
enum Section {
    Start,
    Var,
    Constant,
    Subprograms,
}

struct Parser<'a> {
    file: FileId,
    text: &'a str,
    toks: &'a [Token],
    pos: usize,
    diags: &'a mut Vec<Diagnostic>,
    /// The token index of the last error reported (see the module doc).
    last_err: Option<usize>,
    /// The input ends inside an unterminated comment: what is missing at the end of
    /// the file is a consequence, not reported.
    eof_silent: bool,
    depth: u32,
    height: u32,
    /// Nesting went too deep: everything after is skipped and nothing more reported.
    bailed: bool,
    /// Declaration order of the body being parsed.
    order: LocalOrder,
    /// Local blocks of the body being parsed (blocks met among the statements are
    /// reported, then kept here so that their variables do not cause more errors).
    locals: Vec<VarBlock>,
    syms: Syms,
}

fn is_comparison(t: Tok) -> bool {
    matches!(t, Tok::Eq | Tok::Ne | Tok::Lt | Tok::Le | Tok::Gt | Tok::Ge)
}

fn binop(t: Tok) -> Option<(BinaryOp, u8)> {
    Some(match t {
        Tok::Or => (BinaryOp::Or, 1),
        Tok::Xor => (BinaryOp::Xor, 2),
        Tok::And => (BinaryOp::And, 3),
        Tok::Eq => (BinaryOp::Eq, CMP_BP),
        Tok::Ne => (BinaryOp::Ne, CMP_BP),
        Tok::Lt => (BinaryOp::Lt, CMP_BP),
        Tok::Le => (BinaryOp::Le, CMP_BP),
        Tok::Gt => (BinaryOp::Gt, CMP_BP),
        Tok::Ge => (BinaryOp::Ge, CMP_BP),
        Tok::Plus => (BinaryOp::Add, ADD_BP),
        Tok::Minus => (BinaryOp::Sub, ADD_BP),
        Tok::Star => (BinaryOp::Mul, MUL_BP),
        Tok::Slash => (BinaryOp::Div, MUL_BP),
        Tok::Percent => (BinaryOp::Mod, MUL_BP),
        _ => return None,
    })
}

/// Keywords that start a statement.
fn is_stmt_keyword(t: Tok) -> bool {
    matches!(
        t,
        Tok::Begin | Tok::If | Tok::While | Tok::Repeat | Tok::For
    )
}

/// Keywords that start or end a declaration section or the program.
fn is_section_keyword(t: Tok) -> bool {
    matches!(
        t,
        Tok::Var
            | Tok::EndVar
            | Tok::Constant
            | Tok::Function
            | Tok::Procedure
            | Tok::Program
            | Tok::Pragma
            | Tok::Uses
            | Tok::Eof
    )
}

/// Tokens that close a statement list.
fn is_closer(t: Tok) -> bool {
    matches!(t, Tok::End | Tok::Until | Tok::Else)
}

fn binary(op: BinaryOp, l: Expr, r: Expr) -> Expr {
    let span = l.span.to(r.span);
    Expr {
        kind: ExprKind::Binary(op, Box::new(l), Box::new(r)),
        span,
    }
}

impl Parser<'_> {
    // ---------------------------------------------------------------- tokens

    fn tok(&self) -> Token {
        self.toks[self.pos]
    }

    fn peek(&self) -> Tok {
        self.toks[self.pos].kind
    }

    fn peek_at(&self, n: usize) -> Tok {
        self.toks[(self.pos + n).min(self.toks.len() - 1)].kind
    }

    fn at(&self, k: Tok) -> bool {
        self.peek() == k
    }

    /// Consumes the current token (never the final `Eof`).
    fn bump(&mut self) -> Token {
        let t = self.toks[self.pos];
        if t.kind != Tok::Eof {
            self.pos += 1;
        }
        t
    }

    fn eat(&mut self, k: Tok) -> bool {
        if self.at(k) {
            self.bump();
            true
        } else {
            false
        }
    }

    fn sp(&self, start: u32, end: u32) -> Span {
        Span::new(self.file, start, end)
    }

    fn tspan(&self, t: Token) -> Span {
        self.sp(t.start, t.end)
    }

    fn slice(&self, t: Token) -> &str {
        self.text
            .get(t.start as usize..t.end as usize)
            .unwrap_or("")
    }

    fn ident(&self, t: Token) -> Ident {
        let sym = match t.kind {
            Tok::Ident(s) => s,
            _ => self.syms.main,
        };
        Ident {
            sym,
            span: self.tspan(t),
        }
    }

    /// The end of the last token consumed, not counting a final `;` (statement spans
    /// leave their `;` out).
    fn end_no_semi(&self) -> u32 {
        let mut i = self.pos;
        while i > 0 {
            i -= 1;
            if self.toks[i].kind != Tok::Semi {
                return self.toks[i].end;
            }
        }
        0
    }

    fn span_from(&self, start: u32) -> Span {
        self.sp(start, self.end_no_semi().max(start))
    }

    fn prev_end(&self) -> u32 {
        if self.pos == 0 {
            0
        } else {
            self.toks[self.pos - 1].end
        }
    }

    /// The current token, quoted, for messages.
    fn describe(&self) -> String {
        let t = self.tok();
        match t.kind {
            Tok::Eof => "end of file".into(),
            Tok::Error => "an invalid character".into(),
            Tok::Pragma => "a `pragma` line".into(),
            _ => {
                let s = self.slice(t);
                if s.chars().count() > 24 {
                    format!("`{}...`", s.chars().take(20).collect::<String>())
                } else {
                    format!("`{s}`")
                }
            }
        }
    }

    // ---------------------------------------------------------------- diagnostics

    /// Reports `d`, attributed to the token at `idx`, unless an error was already
    /// reported at or after it, or the token is one the lexer reported.
    fn emit(&mut self, idx: usize, d: Diagnostic) {
        if self.bailed || self.last_err.is_some_and(|l| idx <= l) {
            return;
        }
        self.last_err = Some(idx);
        let k = self.toks[idx].kind;
        if k == Tok::Error || (k == Tok::Eof && self.eof_silent) {
            return;
        }
        self.diags.push(d);
    }

    fn error_here(&mut self, code: &'static str, msg: String, label: &str) {
        let d = Diagnostic::error(code, msg, self.tspan(self.tok())).with_label(label);
        self.emit(self.pos, d);
    }

    /// "expected {what}, found ..." at the current token.
    fn expected(&mut self, what: &str) {
        let t = self.tok();
        let msg = format!("expected {what}, found {}", self.describe());
        let mut d = Diagnostic::error(codes::STL_UNEXPECTED_TOKEN, msg, self.tspan(t))
            .with_label(format!("expected {what}"));
        if t.kind.is_keyword() && (what.contains("name") || what.contains("type")) {
            d = d.with_note(format!(
                "`{}` is a reserved word of STL and cannot be used as a name",
                self.slice(t)
            ));
        }
        self.emit(self.pos, d);
    }

    /// Reports that `what` is missing before the current token. When that token starts
    /// a new line, the caret goes just after the previous token, where the missing one
    /// belongs; otherwise it is on the current token.
    fn missing(&mut self, code: &'static str, what: &str) {
        let t = self.tok();
        let msg = format!("expected {what}, found {}", self.describe());
        let d = if t.newline_before && self.pos > 0 {
            let end = self.prev_end();
            let d = Diagnostic::error(code, msg, self.sp(end, end))
                .with_label(format!("expected {what} here"));
            if t.kind == Tok::Eof {
                d
            } else {
                d.with_secondary(self.tspan(t), "unexpected token")
            }
        } else {
            Diagnostic::error(code, msg, self.tspan(t))
                .with_label(format!("expected {what} before this"))
        };
        self.emit(self.pos, d);
    }

    /// Reports that the block opened by `open` is not closed by `closer` at the current
    /// token.
    fn unclosed(&mut self, closer: &str, open: Token, what: &str) {
        let msg = format!("expected {closer}, found {}", self.describe());
        let d = Diagnostic::error(codes::STL_UNCLOSED_BLOCK, msg, self.tspan(self.tok()))
            .with_label(format!("expected {closer} before this"))
            .with_secondary(self.tspan(open), what.to_string());
        self.emit(self.pos, d);
    }

    fn too_deep(&mut self) {
        let msg = if self.depth >= MAX_DEPTH {
            format!("nesting too deep (more than {MAX_DEPTH} levels)")
        } else {
            format!("expression too long or nested too deeply (height over {MAX_HEIGHT})")
        };
        self.error_here(codes::STL_NESTING_TOO_DEEP, msg, "too deep here");
        // Whatever follows is inside the construct that could not be parsed: skip it
        // all rather than report consequences.
        self.bailed = true;
        self.pos = self.toks.len() - 1;
    }

    /// Goes one nesting level deeper, or reports that the limit is reached. Every
    /// successful `enter` is paired with a `leave`.
    fn enter(&mut self) -> bool {
        if self.bailed {
            return false;
        }
        if self.depth >= MAX_DEPTH || self.height >= MAX_HEIGHT {
            self.too_deep();
            return false;
        }
        self.depth += 1;
        self.height += 1;
        true
    }

    fn leave(&mut self) {
        self.depth -= 1;
        self.height -= 1;
    }

    /// One more link in an operator chain (the caller restores `height`).
    fn grow(&mut self) -> bool {
        self.height += 1;
        if self.height >= MAX_HEIGHT {
            self.too_deep();
            return false;
        }
        true
    }

    // ---------------------------------------------------------------- recovery

    /// True where statement-level recovery stops: a `;`, a keyword that starts or ends
    /// something, or a name at the start of a line followed by `:=` (the next
    /// assignment).
    fn at_sync(&self) -> bool {
        let t = self.tok();
        t.kind == Tok::Semi
            || is_stmt_keyword(t.kind)
            || is_closer(t.kind)
            || is_section_keyword(t.kind)
            || (t.newline_before
                && matches!(t.kind, Tok::Ident(_))
                && self.peek_at(1) == Tok::Assign)
    }

    /// Skips a broken statement: up to and including its `;`, or up to a token that
    /// starts or ends something.
    fn recover_stmt(&mut self) {
        while !self.at_sync() {
            self.bump();
        }
        self.eat(Tok::Semi);
    }

    /// Skips to `kw` (consumed) or to a synchronisation token (not consumed).
    fn recover_to(&mut self, kw: Tok) {
        while !self.at(kw) && !self.at_sync() {
            self.bump();
        }
        self.eat(kw);
    }

    /// True if the current token can start a statement.
    fn starts_stmt(&self) -> bool {
        let k = self.peek();
        is_stmt_keyword(k)
            || (matches!(k, Tok::Ident(_))
                && (matches!(
                    self.peek_at(1),
                    Tok::Assign | Tok::LParen | Tok::Semi | Tok::Eq
                ) || (self.peek_at(1) == Tok::Colon && self.peek_at(2) == Tok::Eq)))
    }

    /// After a simple statement: its `;`. A missing one is reported once; the parser
    /// goes on as if it were there when what follows can follow a statement. Before
    /// `else` the `;` may be left out (`if c then x := 1 else x := 2;`).
    fn expect_semi(&mut self) {
        if self.eat(Tok::Semi) || self.at(Tok::Else) {
            return;
        }
        self.missing(codes::STL_MISSING_SEMICOLON, "`;`");
        let t = self.tok();
        let follows = (t.newline_before && self.starts_stmt())
            || is_stmt_keyword(t.kind)
            || is_closer(t.kind)
            || is_section_keyword(t.kind);
        if !follows {
            self.recover_stmt();
        }
    }

    /// After a declaration (or `end_var`, `uses`, the program header): its `;`.
    fn expect_decl_semi(&mut self) {
        if self.eat(Tok::Semi) {
            return;
        }
        self.missing(codes::STL_MISSING_SEMICOLON, "`;`");
        let t = self.tok();
        let follows = (t.newline_before && matches!(t.kind, Tok::Ident(_)))
            || is_section_keyword(t.kind)
            || is_stmt_keyword(t.kind);
        if !follows {
            self.skip_decl();
        }
    }

    /// Skips a broken declaration: to its `;` (consumed), or to `end_var` or a keyword.
    fn skip_decl(&mut self) {
        loop {
            let t = self.peek();
            if t == Tok::Semi {
                self.bump();
                return;
            }
            if is_section_keyword(t) || is_stmt_keyword(t) || t == Tok::End {
                return;
            }
            self.bump();
        }
    }

    /// A header keyword (`then`, `do`). When missing: reported, then assumed present if
    /// a statement follows, else skipped to.
    fn expect_kw(&mut self, kw: Tok, text: &str) {
        if self.eat(kw) {
            return;
        }
        self.missing(codes::STL_UNEXPECTED_TOKEN, text);
        if !self.starts_stmt() && !is_closer(self.peek()) {
            self.recover_to(kw);
        }
    }

    fn expect_ident(&mut self, what: &str) -> Option<Ident> {
        if let Tok::Ident(_) = self.peek() {
            let t = self.bump();
            Some(self.ident(t))
        } else {
            self.expected(what);
            None
        }
    }

    // ---------------------------------------------------------------- program

    fn unit(&mut self) -> Vec<Item> {
        let mut items = Vec::new();
        // `pragma` lines and `uses` come first; plcc has no use for them.
        loop {
            match self.peek() {
                Tok::Pragma => {
                    self.bump();
                }
                Tok::Uses => self.uses(),
                _ => break,
            }
        }
        let header = self.program_header();
        let mut section = Section::Start;
        // Set when garbage was skipped: the main body's absence is then a consequence.
        let mut skipped = false;
        loop {
            if self.bailed {
                return items;
            }
            let t = self.tok();
            match t.kind {
                Tok::Var => {
                    self.global_order(&mut section, Section::Var);
                    let b = self.var_block(VarKind::Global);
                    items.push(Item::Globals(b));
                }
                Tok::Constant => {
                    self.global_order(&mut section, Section::Constant);
                    let b = self.constants(VarKind::Global);
                    items.push(Item::Globals(b));
                }
                Tok::Function | Tok::Procedure => {
                    section = Section::Subprograms;
                    if let Some(p) = self.subprogram() {
                        items.push(Item::Pou(p));
                    }
                }
                Tok::Pragma | Tok::Uses => {
                    let d = Diagnostic::error(
                        codes::STL_DECLARATION_ORDER,
                        format!(
                            "`{}` after the program header",
                            if t.kind == Tok::Uses {
                                "uses"
                            } else {
                                "pragma"
                            }
                        ),
                        self.tspan(t),
                    )
                    .with_label("must come before `program`")
                    .with_note("`pragma` lines and `uses` come first, before `program NAME;`");
                    self.emit(self.pos, d);
                    if t.kind == Tok::Uses {
                        self.uses();
                    } else {
                        self.bump();
                    }
                }
                Tok::Program => {
                    self.error_here(
                        codes::STL_UNEXPECTED_TOKEN,
                        "a second `program` header: an STL file holds one program".into(),
                        "second header",
                    );
                    self.bump();
                    self.skip_decl();
                }
                Tok::Begin | Tok::Eof => break,
                _ if self.starts_stmt() => {
                    // The statements of the main body without their `begin`.
                    self.missing(codes::STL_UNEXPECTED_TOKEN, "`begin`");
                    break;
                }
                _ => {
                    self.expected(
                        "`var`, `constant`, `function`, `procedure` or the main body `begin`",
                    );
                    skipped = true;
                    while !matches!(
                        self.peek(),
                        Tok::Var
                            | Tok::Constant
                            | Tok::Function
                            | Tok::Procedure
                            | Tok::Begin
                            | Tok::Eof
                    ) {
                        self.bump();
                    }
                }
            }
        }
        if let Some(p) = self.main_body(header, skipped) {
            items.push(Item::Pou(p));
        }
        items
    }

    /// `uses id, id;`
    fn uses(&mut self) {
        self.bump();
        loop {
            if self
                .expect_ident("the name of a library or module")
                .is_none()
            {
                self.skip_decl();
                return;
            }
            if !self.eat(Tok::Comma) {
                break;
            }
        }
        self.expect_decl_semi();
    }

    /// `program NAME;`: the keyword and the name.
    fn program_header(&mut self) -> Option<(Token, Ident)> {
        if !self.at(Tok::Program) {
            self.expected("`program NAME;`");
            return None;
        }
        let kw = self.bump();
        let name = self.expect_ident("the program's name");
        if name.is_none() {
            self.skip_decl();
            return None;
        }
        self.expect_decl_semi();
        name.map(|n| (kw, n))
    }

    /// Checks that a global section comes in order.
    fn global_order(&mut self, current: &mut Section, next: Section) {
        if next < *current {
            let (what, after) = match (next, *current) {
                (Section::Var, Section::Constant) => ("a global `var` block", "a global constant"),
                (Section::Var, _) => ("a global `var` block", "a function or procedure"),
                _ => ("a global constant", "a function or procedure"),
            };
            let d = Diagnostic::error(
                codes::STL_DECLARATION_ORDER,
                format!("{what} after {after}"),
                self.tspan(self.tok()),
            )
            .with_label("out of order")
            .with_note(
                "declare, in this order: the global `var` blocks, the global constants, the \
                 functions and procedures, then the main body `begin ... end.`",
            );
            self.emit(self.pos, d);
        } else {
            *current = next;
        }
    }

    /// The main body `begin <locals> <statements> end.` and the PROGRAM it becomes.
    fn main_body(&mut self, header: Option<(Token, Ident)>, skipped: bool) -> Option<Pou> {
        let start = self.tok();
        if self.at(Tok::Eof) {
            if !skipped {
                let msg = format!(
                    "expected the main body `begin ... end.`, found {}",
                    self.describe()
                );
                let mut d = Diagnostic::error(codes::STL_MISSING_END_DOT, msg, self.tspan(start))
                    .with_label("expected `begin ... end.`");
                if let Some((kw, _)) = header {
                    d = d.with_secondary(self.tspan(kw), "this program has no main body");
                }
                self.emit(self.pos, d);
            }
            return None;
        }
        let begin = self.eat(Tok::Begin);
        self.order = LocalOrder::default();
        self.locals = Vec::new();
        self.locals_before_stmts();
        let mut stmts = Vec::new();
        self.stmt_list(&mut stmts);
        if self.bailed {
            return None;
        }
        let body_end;
        if self.at(Tok::End) {
            let end = self.bump();
            body_end = end.end;
            if !self.eat(Tok::Dot) {
                let msg = format!(
                    "expected `.` after the `end` of the main body, found {}",
                    self.describe()
                );
                let d =
                    Diagnostic::error(codes::STL_MISSING_END_DOT, msg, self.sp(end.end, end.end))
                        .with_label("expected `.` here")
                        .with_note("the main body ends with `end` and a dot: `end.`");
                self.emit(self.pos, d);
                self.eat(Tok::Semi);
            }
        } else {
            body_end = self.prev_end();
            let msg = format!("expected `end.`, found {}", self.describe());
            let mut d = if self.at(Tok::Eof) {
                // Nothing to point at: the caret goes after the last token.
                let end = self.prev_end();
                Diagnostic::error(codes::STL_MISSING_END_DOT, msg, self.sp(end, end))
                    .with_label("expected `end.` after this")
            } else {
                Diagnostic::error(codes::STL_MISSING_END_DOT, msg, self.tspan(self.tok()))
                    .with_label("expected `end.` before this")
            };
            if matches!(self.peek(), Tok::Function | Tok::Procedure) {
                d = d.with_note("functions and procedures are declared before the main body");
            }
            if begin {
                d = d.with_secondary(self.tspan(start), "the main body starts here");
            }
            self.emit(self.pos, d);
        }
        if !self.at(Tok::Eof) {
            let mut d = Diagnostic::error(
                codes::STL_TEXT_AFTER_END,
                format!("{} after `end.`", self.describe()),
                self.tspan(self.tok()),
            )
            .with_label("the program has ended");
            if matches!(self.peek(), Tok::Function | Tok::Procedure) {
                d = d.with_note("functions and procedures are declared before the main body");
            }
            self.emit(self.pos, d);
        }
        let (kw_start, name) = match header {
            Some((kw, name)) => (kw.start, name),
            None => (
                start.start,
                Ident {
                    sym: self.syms.main,
                    span: self.sp(start.start, start.start),
                },
            ),
        };
        let var_blocks = std::mem::take(&mut self.locals);
        Some(Pou {
            kind: PouKind::Program,
            name,
            return_type: None,
            extends: None,
            var_blocks,
            body: Body {
                stmts,
                span: self.sp(start.start, body_end.max(start.start)),
            },
            actions: Vec::new(),
            unsupported_members: Vec::new(),
            oo: Default::default(),
            sfc: None,
            span: self.sp(kw_start, self.prev_end().max(kw_start)),
        })
    }

    // ---------------------------------------------------------------- declarations

    /// Local `var` blocks and constants before the first statement.
    fn locals_before_stmts(&mut self) {
        while matches!(self.peek(), Tok::Var | Tok::Constant) && !self.bailed {
            self.local_decl();
        }
    }

    /// A local `var` block or run of constants, with its order checked.
    fn local_decl(&mut self) {
        let t = self.tok();
        let is_var = t.kind == Tok::Var;
        let problem = if self.order.stmt_seen {
            Some(if is_var {
                "a `var` block after the statements"
            } else {
                "a constant after the statements"
            })
        } else if is_var && self.order.constant_seen {
            Some("a local `var` block after a local constant")
        } else {
            None
        };
        if let Some(msg) = problem {
            let d = Diagnostic::error(codes::STL_DECLARATION_ORDER, msg, self.tspan(t))
                .with_label("out of order")
                .with_note(
                    "a body declares its local `var` blocks first, then its constants, then \
                     its statements",
                );
            self.emit(self.pos, d);
        }
        let b = if is_var {
            self.var_block(VarKind::Var)
        } else {
            self.order.constant_seen = true;
            self.constants(VarKind::Var)
        };
        self.locals.push(b);
    }

    /// `var decl; decl; ... end_var;`
    fn var_block(&mut self, kind: VarKind) -> VarBlock {
        let kw = self.bump();
        let mut decls = Vec::new();
        loop {
            match self.peek() {
                // A name followed by `:=` or `(` is a statement: `end_var` is missing.
                Tok::Ident(_) if !matches!(self.peek_at(1), Tok::Assign | Tok::LParen) => {
                    if let Some(d) = self.var_decl(false) {
                        decls.push(d);
                    }
                }
                Tok::EndVar => {
                    self.bump();
                    self.expect_decl_semi();
                    break;
                }
                Tok::Semi => {
                    // A stray `;`: harmless.
                    self.bump();
                }
                // A reserved word used as a name (`var begin : INT;`).
                k if k.is_keyword() && self.peek_at(1) == Tok::Colon => {
                    self.expected("a variable name");
                    self.bump();
                    self.skip_decl();
                }
                k if is_section_keyword(k)
                    || is_stmt_keyword(k)
                    || k == Tok::End
                    || matches!(k, Tok::Ident(_)) =>
                {
                    self.unclosed("`end_var`", kw, "this `var` block is not closed");
                    break;
                }
                _ => {
                    self.expected("a variable name or `end_var`");
                    self.skip_decl();
                }
            }
        }
        VarBlock {
            kind,
            constant: false,
            retain: false,
            list: None,
            decls,
            span: self.span_from(kw.start),
        }
    }

    /// `constant NAME : TYPE := value;`, repeated: one block for the whole run.
    fn constants(&mut self, kind: VarKind) -> VarBlock {
        let start = self.tok().start;
        let mut decls = Vec::new();
        while self.eat(Tok::Constant) {
            if let Some(d) = self.var_decl(true) {
                decls.push(d);
            }
        }
        VarBlock {
            kind,
            constant: true,
            retain: false,
            list: None,
            decls,
            span: self.span_from(start),
        }
    }

    /// `a, b : TYPE := init;` (a constant needs its value).
    fn var_decl(&mut self, constant: bool) -> Option<VarDecl> {
        let start = self.tok().start;
        let d = self.var_decl_inner(constant);
        if d.is_none() {
            self.skip_decl();
        }
        let mut d = d?;
        d.span = self.span_from(start);
        Some(d)
    }

    fn var_decl_inner(&mut self, constant: bool) -> Option<VarDecl> {
        let start = self.tok().start;
        let mut names = vec![self.expect_ident(if constant {
            "the constant's name"
        } else {
            "a variable name"
        })?];
        while self.eat(Tok::Comma) {
            names.push(self.expect_ident("a variable name")?);
        }
        if !self.eat(Tok::Colon) {
            self.expected("`:` and a type");
            return None;
        }
        let ty = self.type_name()?;
        let init = if self.at(Tok::Assign) {
            self.bump();
            Some(Init::Expr(self.expr()?))
        } else {
            if self.at(Tok::Eq) {
                self.error_here(
                    codes::STL_ASSIGN_WITHOUT_COLON,
                    "use `:=` to give an initial value; `=` compares".into(),
                    "expected `:=`",
                );
                return None;
            }
            if constant {
                let first = names[0].span;
                let shown = self
                    .text
                    .get(first.start as usize..first.end as usize)
                    .unwrap_or("")
                    .to_string();
                let d = Diagnostic::error(
                    codes::STL_CONSTANT_WITHOUT_VALUE,
                    format!("the constant `{shown}` has no value"),
                    self.sp(start, self.prev_end()),
                )
                .with_label("expected `:= value`")
                .with_note("a constant is declared `constant NAME : TYPE := value;`");
                // The error is the declaration's, not the next token's; attribute it
                // to the token before so that a missing `;` after it still shows.
                self.emit(self.pos - 1, d);
            }
            None
        };
        self.expect_decl_semi();
        Some(VarDecl {
            names,
            location: None,
            ty,
            init,
            edge: None,
            span: self.sp(start, start),
        })
    }

    /// A type: an elementary type name (BOOL, INT, UINT, SINT, USINT, or any other
    /// IEC name; the lowering checks it).
    fn type_name(&mut self) -> Option<TypeSpec> {
        let at = self.pos;
        let id = self.expect_ident("a type name (BOOL, INT, UINT, SINT, USINT)")?;
        let name = self.slice(self.toks[at]);
        // Not a syntax error: reported without entering error recovery.
        if !self.bailed && !STL_TYPES.iter().any(|t| t.eq_ignore_ascii_case(name)) {
            let d = Diagnostic::error(
                codes::STL_TYPE,
                format!("`{name}` is not a type of STL"),
                id.span,
            )
            .with_label("not BOOL, INT, UINT, SINT or USINT")
            .with_note("STL has five types: BOOL, SINT, USINT (8 bits), INT, UINT (16 bits)");
            self.diags.push(d);
        }
        Some(TypeSpec::Named(id))
    }

    /// `function NAME(params) TYPE; <locals> begin <locals> <statements> end;` or
    /// `procedure NAME(params); ...`: a FUNCTION (without a result for a procedure).
    fn subprogram(&mut self) -> Option<Pou> {
        let kw = self.bump();
        let is_fn = kw.kind == Tok::Function;
        let name_at = self.pos;
        let name = self.expect_ident(if is_fn {
            "the function's name"
        } else {
            "the procedure's name"
        });
        let mut ok = name.is_some();
        let mut inputs = Vec::new();
        let params_start = self.tok().start;
        if name.is_some() && self.at(Tok::LParen) {
            let open = self.bump();
            ok &= self.params(open, &mut inputs);
        }
        let params_span = self.span_from(params_start);
        let mut return_type = None;
        if ok {
            // `(a : INT) INT;`, `(a : INT); INT`, `(a : INT) : INT;`: all accepted.
            let sep = self.eat(Tok::Semi) || self.eat(Tok::Colon);
            if let Tok::Ident(_) = self.peek() {
                let ty = self.type_name();
                if is_fn {
                    return_type = ty;
                } else {
                    let d = Diagnostic::error(
                        codes::STL_RESULT_TYPE,
                        "a procedure has no result type",
                        self.tspan(self.toks[self.pos - 1]),
                    )
                    .with_label("result type of a procedure")
                    .with_note("a subprogram that returns a value is declared with `function`");
                    self.emit(self.pos - 1, d);
                }
                self.eat(Tok::Semi);
            } else if is_fn {
                let fname = if name.is_some() {
                    self.slice(self.toks[name_at])
                } else {
                    ""
                };
                let d = Diagnostic::error(
                    codes::STL_RESULT_TYPE,
                    format!(
                        "function `{fname}` has no result type, found {}",
                        self.describe()
                    ),
                    self.tspan(self.tok()),
                )
                .with_label("expected the result type")
                .with_secondary(params_span, "after the parameters")
                .with_note(
                    "write `function NAME(a : INT) INT;`, or declare a subprogram without a \
                     result with `procedure`",
                );
                self.emit(self.pos, d);
            } else if !sep && !matches!(self.peek(), Tok::Begin | Tok::Var | Tok::Constant) {
                self.missing(codes::STL_MISSING_SEMICOLON, "`;`");
            }
        } else {
            while !matches!(
                self.peek(),
                Tok::Begin | Tok::Var | Tok::Constant | Tok::Function | Tok::Procedure | Tok::Eof
            ) {
                self.bump();
            }
        }
        let saved_order = std::mem::take(&mut self.order);
        let saved_locals = std::mem::take(&mut self.locals);
        self.locals_before_stmts();
        let body_start = self.tok();
        let mut stmts = Vec::new();
        if self.eat(Tok::Begin) {
            self.locals_before_stmts();
            self.stmt_list(&mut stmts);
            if self.at(Tok::End) {
                self.bump();
                if self.at(Tok::Dot) {
                    let d = Diagnostic::error(
                        codes::STL_UNEXPECTED_TOKEN,
                        format!(
                            "`end.` closes a {}: only the main body ends with `end.`",
                            if is_fn { "function" } else { "procedure" }
                        ),
                        self.tspan(self.tok()),
                    )
                    .with_label("expected `;` or nothing")
                    .with_secondary(self.tspan(kw), "the subprogram starts here");
                    self.emit(self.pos, d);
                    self.bump();
                }
                self.eat(Tok::Semi);
            } else {
                self.unclosed(
                    "`end`",
                    body_start,
                    if is_fn {
                        "the function's `begin` is not closed"
                    } else {
                        "the procedure's `begin` is not closed"
                    },
                );
            }
        } else {
            self.missing(codes::STL_UNEXPECTED_TOKEN, "`begin`");
            if self.starts_stmt() {
                self.stmt_list(&mut stmts);
                self.eat(Tok::End);
                self.eat(Tok::Semi);
            }
        }
        let body_span = self.span_from(body_start.start);
        let mut var_blocks = Vec::with_capacity(1 + self.locals.len());
        if !inputs.is_empty() {
            var_blocks.push(VarBlock {
                kind: VarKind::Input,
                constant: false,
                retain: false,
                list: None,
                decls: inputs,
                span: params_span,
            });
        }
        var_blocks.append(&mut self.locals);
        self.order = saved_order;
        self.locals = saved_locals;
        Some(Pou {
            kind: PouKind::Function,
            name: name?,
            return_type,
            extends: None,
            var_blocks,
            body: Body {
                stmts,
                span: body_span,
            },
            actions: Vec::new(),
            unsupported_members: Vec::new(),
            oo: Default::default(),
            sfc: None,
            span: self.span_from(kw.start),
        })
        .filter(|_| ok)
    }

    /// The parameter list after `(`: groups `a, b : TYPE` separated by `;` or `,`, up
    /// to `)`. False (after resynchronising at `)`) if it is broken.
    fn params(&mut self, open: Token, out: &mut Vec<VarDecl>) -> bool {
        if self.eat(Tok::RParen) {
            return true;
        }
        loop {
            let start = self.tok().start;
            let Some(group) = self.param_group() else {
                while !matches!(
                    self.peek(),
                    Tok::RParen | Tok::Begin | Tok::Var | Tok::Constant | Tok::Eof
                ) {
                    self.bump();
                }
                self.eat(Tok::RParen);
                return false;
            };
            let (names, ty) = group;
            out.push(VarDecl {
                names,
                location: None,
                ty,
                init: None,
                edge: None,
                span: self.span_from(start),
            });
            match self.peek() {
                Tok::Semi | Tok::Comma => {
                    self.bump();
                }
                Tok::RParen => {
                    self.bump();
                    return true;
                }
                _ => {
                    let msg = format!("expected `;`, `,` or `)`, found {}", self.describe());
                    let d =
                        Diagnostic::error(codes::STL_UNEXPECTED_TOKEN, msg, self.tspan(self.tok()))
                            .with_label("expected `;`, `,` or `)`")
                            .with_secondary(self.tspan(open), "the parameter list starts here");
                    self.emit(self.pos, d);
                    return false;
                }
            }
        }
    }

    fn param_group(&mut self) -> Option<(Vec<Ident>, TypeSpec)> {
        let mut names = vec![self.expect_ident("a parameter name")?];
        while self.eat(Tok::Comma) {
            names.push(self.expect_ident("a parameter name")?);
        }
        if !self.eat(Tok::Colon) {
            self.expected("`:` and the parameter's type");
            return None;
        }
        Some((names, self.type_name()?))
    }
}
