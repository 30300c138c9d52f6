//! The Structured Text parser: recursive descent over the token vector, precedence
//! climbing for expressions.
//!
//! Error recovery follows three rules, so that one mistake gives one diagnostic:
//! - at most one error per token: once an error is reported at a token, errors at that
//!   token or before it are dropped (the parser never moves backwards);
//! - a construct that failed is left out of the tree and the parser resynchronises at
//!   a `;`, a statement keyword, an END_ keyword, END_VAR or the next POU keyword;
//! - END_ keywords close the innermost construct that expects them, and a construct
//!   that meets another construct's END_ reports itself as not closed, so a missing
//!   END_IF is reported once, at the place it was expected.
//!
//! Nesting is limited ([`MAX_DEPTH`] recursion levels, [`MAX_HEIGHT`] for the height
//! of an expression tree) so that no input can overflow the stack, here or in the
//! passes that walk the tree.

use super::lexer::{Lexed, Tok, Token, INLINE_INT, INLINE_REAL, SWALLOWED};
use crate::ast::*;
use crate::codes;
use crate::intern::{Interner, Symbol};
use plcc_ir::diag::{Diagnostic, FileId, Span};

mod body;
mod decls;
mod members;
mod sfc;

use body::append;

/// The deepest nesting of parentheses, statements, types and initialisers accepted.
pub const MAX_DEPTH: u32 = 200;
/// The greatest height of an expression tree (nesting plus chained operators).
pub const MAX_HEIGHT: u32 = 1000;

/// Parses the tokens of one file (see [`super::parse`]).
pub fn parse_tokens(
    file: FileId,
    text: &str,
    lexed: &Lexed,
    interner: &mut Interner,
    diags: &mut Vec<Diagnostic>,
) -> SourceUnit {
    parse_tokens_with(file, text, lexed, interner, diags, None)
}

/// A parser of POU and ACTION bodies written in another language than ST (the IL
/// front end): files of that language share ST's declarations, only bodies differ.
pub(crate) trait BodyHook {
    /// Called where a body starts (after the declarations). Returns `None`, having
    /// consumed nothing, if the body is Structured Text; otherwise parses the body up
    /// to (not including) the next section stop (END_ keyword, VAR block, POU
    /// keyword, member such as `ACTION a:`) and returns its statements.
    fn body(&mut self, p: &mut Parser<'_>, ctx: &BodyCtx<'_>) -> Option<Vec<Stmt>>;
}

/// What a [`BodyHook`] knows about the body it is asked to parse.
pub(crate) struct BodyCtx<'b> {
    /// The kind of POU, `None` for an ACTION.
    pub kind: Option<PouKind>,
    /// The POU's name (`None` for an ACTION or a POU whose name is missing).
    pub name: Option<Ident>,
    /// A FUNCTION's result type.
    pub return_type: Option<&'b TypeSpec>,
    /// The declaration blocks of the POU (of the enclosing POU for an ACTION
    /// declared inside one; empty for an ACTION declared outside).
    pub var_blocks: &'b [VarBlock],
    /// The hook already parsed code of this body (code resumes after a VAR block
    /// written in the middle of it): it must not give it back to ST.
    pub continuing: bool,
}

/// [`parse_tokens`] with a parser for bodies in another language.
pub(crate) fn parse_tokens_with<'a>(
    file: FileId,
    text: &'a str,
    lexed: &'a Lexed,
    interner: &'a mut Interner,
    diags: &'a mut Vec<Diagnostic>,
    hook: Option<&'a mut dyn BodyHook>,
) -> SourceUnit {
    let why = if hook.is_some() {
        "IL bodies and declarations keep no C code (an ST body keeps it where a statement may stand)"
    } else {
        "it does not stand where a statement may stand"
    };
    // The hook reborrowed for as long as the parse, so that `diags` is free after.
    let hook = hook.map(|h| -> &mut dyn BodyHook { h });
    let (unit, c_next) = parse_range(
        file,
        text,
        lexed,
        &lexed.tokens,
        None,
        interner,
        diags,
        hook,
    );
    lexed.warn_c_pragmas(file, c_next, why, diags);
    unit
}

/// Interns the words the parser matches by symbol, so that a copy of the interner
/// made afterwards lets a parser add nothing when the file holds no new names (see
/// [`super::halves`]).
pub(crate) fn intern_contextual_words(interner: &mut Interner) {
    Syms::new(interner);
}

/// Parses the items of `toks` (a range of `lexed`'s tokens that starts at the top
/// level), which end with an Eof unless `eof` gives the token that follows them.
/// Returns the unit and the index of the first C pragma not yet taken.
#[allow(clippy::too_many_arguments)]
pub(crate) fn parse_range<'a>(
    file: FileId,
    text: &'a str,
    lexed: &'a Lexed,
    toks: &'a [Token],
    eof: Option<Token>,
    interner: &'a mut Interner,
    diags: &'a mut Vec<Diagnostic>,
    hook: Option<&'a mut dyn BodyHook>,
) -> (SourceUnit, usize) {
    let s = Syms::new(interner);
    let eof = match eof.or(toks.last().copied()) {
        Some(t) if t.kind == Tok::Eof => t,
        // `lex` always ends with Eof; a hand-made token vector might not (nothing
        // parsed, no pragma warned about).
        _ => {
            let unit = SourceUnit {
                file,
                items: Vec::new(),
            };
            return (unit, lexed.c_pragmas.len());
        }
    };
    let mut p = Parser {
        file,
        text,
        toks,
        eof,
        lits: &lexed.literals,
        lexed,
        pos: 0,
        interner,
        diags,
        last_err: None,
        eof_silent: lexed.eof_in_error,
        depth: 0,
        height: 0,
        open: [0; 8],
        s,
        last_pou: None,
        extensible: Vec::new(),
        block_access: None,
        stmts: Vec::new(),
        args: Vec::new(),
        hook,
        line_postfix: None,
        c_next: 0,
    };
    let items = p.unit();
    (SourceUnit { file, items }, p.c_next)
}

/// Words that are keywords only in some contexts (and names everywhere else).
struct Syms {
    action: Symbol,
    method: Symbol,
    property: Symbol,
    interface: Symbol,
    class: Symbol,
    step: Symbol,
    initial_step: Symbol,
    transition: Symbol,
    on: Symbol,
    with: Symbol,
    task: Symbol,
    resource: Symbol,
    pointer: Symbol,
    ref_: Symbol,
    jmp: Symbol,
    extends: Symbol,
    implements: Symbol,
    r_edge: Symbol,
    f_edge: Symbol,
    reference: Symbol,
    actions: Symbol,
    functionblock: Symbol,
    library: Symbol,
    end_library: Symbol,
    get: Symbol,
    set: Symbol,
    /// ABSTRACT, FINAL, PUBLIC, PRIVATE, PROTECTED, INTERNAL, OVERRIDE.
    modifiers: [Symbol; 7],
}

impl Syms {
    fn new(i: &mut Interner) -> Syms {
        Syms {
            action: i.intern_upper("ACTION"),
            method: i.intern_upper("METHOD"),
            property: i.intern_upper("PROPERTY"),
            interface: i.intern_upper("INTERFACE"),
            class: i.intern_upper("CLASS"),
            step: i.intern_upper("STEP"),
            initial_step: i.intern_upper("INITIAL_STEP"),
            transition: i.intern_upper("TRANSITION"),
            on: i.intern_upper("ON"),
            with: i.intern_upper("WITH"),
            task: i.intern_upper("TASK"),
            resource: i.intern_upper("RESOURCE"),
            pointer: i.intern_upper("POINTER"),
            ref_: i.intern_upper("REF"),
            jmp: i.intern_upper("JMP"),
            extends: i.intern_upper("EXTENDS"),
            implements: i.intern_upper("IMPLEMENTS"),
            r_edge: i.intern_upper("R_EDGE"),
            f_edge: i.intern_upper("F_EDGE"),
            reference: i.intern_upper("REFERENCE"),
            actions: i.intern_upper("ACTIONS"),
            functionblock: i.intern_upper("FUNCTIONBLOCK"),
            library: i.intern_upper("LIBRARY"),
            end_library: i.intern_upper("END_LIBRARY"),
            get: i.intern_upper("GET"),
            set: i.intern_upper("SET"),
            modifiers: [
                i.intern_upper("ABSTRACT"),
                i.intern_upper("FINAL"),
                i.intern_upper("PUBLIC"),
                i.intern_upper("PRIVATE"),
                i.intern_upper("PROTECTED"),
                i.intern_upper("INTERNAL"),
                i.intern_upper("OVERRIDE"),
            ],
        }
    }
}

/// Members of a POU that start with a contextual keyword.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
enum Member {
    Action,
    Method,
    Property,
    Interface,
    Class,
    Step,
    Transition,
}

/// Where a declaration is, which decides what it may look like.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
enum DeclCtx {
    /// A block of a POU: a located variable needs a name.
    Pou,
    /// VAR_GLOBAL outside POUs: anonymous located variables allowed.
    Global,
    /// VAR_CONFIG: names are instance paths `a.b.c`.
    Config,
    /// VAR_ACCESS: not supported.
    Access,
    /// A STRUCT field.
    Struct,
}

/// Index in `Parser::open` of a token that closes part of a statement.
fn closer_idx(t: Tok) -> Option<usize> {
    Some(match t {
        Tok::Elsif => 0,
        Tok::Else => 1,
        Tok::EndIf => 2,
        Tok::EndCase => 3,
        Tok::EndFor => 4,
        Tok::EndWhile => 5,
        Tok::Until => 6,
        Tok::EndRepeat => 7,
        _ => return None,
    })
}

fn is_end_closer(t: Tok) -> bool {
    matches!(
        t,
        Tok::EndIf | Tok::EndCase | Tok::EndFor | Tok::EndWhile | Tok::EndRepeat
    )
}

fn is_stmt_keyword(t: Tok) -> bool {
    matches!(
        t,
        Tok::If
            | Tok::Case
            | Tok::For
            | Tok::While
            | Tok::Repeat
            | Tok::Exit
            | Tok::Continue
            | Tok::Return
    )
}

fn starts_stmt(t: Tok) -> bool {
    matches!(t, Tok::Ident | Tok::Address | Tok::Semi) || is_stmt_keyword(t)
}

fn var_kind(t: Tok) -> Option<VarKind> {
    Some(match t {
        Tok::Var => VarKind::Var,
        Tok::VarInput => VarKind::Input,
        Tok::VarOutput => VarKind::Output,
        Tok::VarInOut => VarKind::InOut,
        Tok::VarTemp => VarKind::Temp,
        Tok::VarGlobal => VarKind::Global,
        Tok::VarExternal => VarKind::External,
        Tok::VarAccess => VarKind::Access,
        Tok::VarConfig => VarKind::Config,
        Tok::VarStat => VarKind::Stat,
        Tok::VarInst => VarKind::Inst,
        _ => return None,
    })
}

/// Starts of top-level declarations: a POU missing its END_ stops at these.
fn is_top_start(t: Tok) -> bool {
    matches!(
        t,
        Tok::Program | Tok::Function | Tok::FunctionBlock | Tok::Type | Tok::Configuration
    )
}

fn is_pou_end(t: Tok) -> bool {
    matches!(
        t,
        Tok::EndProgram | Tok::EndFunction | Tok::EndFunctionBlock | Tok::EndClass
    )
}

/// Tokens no statement list goes past: section keywords and END_s of non-statements.
fn is_section_stop(t: Tok) -> bool {
    is_top_start(t)
        || var_kind(t).is_some()
        || t == Tok::Eof
        || (t.is_end_keyword() && !is_end_closer(t))
}

/// Keywords that close something.
fn is_end_keyword(t: Tok) -> bool {
    closer_idx(t).is_some() || t.is_end_keyword()
}

/// The binary operator a token is, with how tightly it binds
/// ([`BinaryOp::binding`]).
fn binop(t: Tok) -> Option<(BinaryOp, u8)> {
    let op = match t {
        Tok::Or => BinaryOp::Or,
        Tok::OrElse => BinaryOp::OrElse,
        Tok::Xor => BinaryOp::Xor,
        Tok::And | Tok::Amp => BinaryOp::And,
        Tok::AndThen => BinaryOp::AndThen,
        Tok::Eq => BinaryOp::Eq,
        Tok::Ne => BinaryOp::Ne,
        Tok::Lt => BinaryOp::Lt,
        Tok::Le => BinaryOp::Le,
        Tok::Gt => BinaryOp::Gt,
        Tok::Ge => BinaryOp::Ge,
        Tok::Plus => BinaryOp::Add,
        Tok::Minus => BinaryOp::Sub,
        Tok::Star => BinaryOp::Mul,
        Tok::Slash => BinaryOp::Div,
        Tok::Mod => BinaryOp::Mod,
        Tok::Pow => BinaryOp::Pow,
        _ => return None,
    };
    Some((op, op.binding()))
}

fn opener_of(t: Tok) -> &'static str {
    match t {
        Tok::Elsif | Tok::EndIf => "IF",
        Tok::Else => "IF or CASE",
        Tok::EndCase => "CASE",
        Tok::EndFor => "FOR",
        Tok::EndWhile => "WHILE",
        Tok::Until | Tok::EndRepeat => "REPEAT",
        Tok::EndVar => "VAR block",
        Tok::EndType => "TYPE",
        Tok::EndStruct => "STRUCT",
        Tok::EndConfiguration => "CONFIGURATION",
        Tok::EndResource => "RESOURCE",
        Tok::EndAction => "ACTION",
        Tok::EndMethod => "METHOD",
        Tok::EndProperty => "PROPERTY",
        Tok::EndInterface => "INTERFACE",
        Tok::EndClass => "CLASS",
        Tok::EndStep => "STEP",
        Tok::EndTransition => "TRANSITION",
        Tok::EndActions => "ACTIONS",
        Tok::EndGet => "GET",
        Tok::EndSet => "SET",
        _ => "block",
    }
}

/// The parser's state (visible in the crate for [`BodyHook`]s, which use its token
/// access, error reporting and operand parsing).
pub(crate) struct Parser<'a> {
    file: FileId,
    text: &'a str,
    toks: &'a [Token],
    /// The token after `toks` (their last one, Eof, for a whole file).
    eof: Token,
    lits: &'a [Literal],
    lexed: &'a Lexed,
    pos: usize,
    interner: &'a mut Interner,
    diags: &'a mut Vec<Diagnostic>,
    /// Token index of the last error reported (or suppressed).
    last_err: Option<usize>,
    /// The lexer already reported an unterminated comment or string at the end.
    eof_silent: bool,
    depth: u32,
    height: u32,
    /// How many open statements accept each closer (see [`closer_idx`]).
    open: [u32; 8],
    s: Syms,
    /// The last POU parsed, owner of CODESYS-style actions that follow it.
    last_pou: Option<Ident>,
    /// Extensible inputs (`IN 1 ..`) of the POU being parsed: reported with its
    /// unsupported members, unless the POU is a prototype (see `lower::prototypes`).
    extensible: Vec<Span>,
    /// The access specifier of the VAR block just read (`VAR PROTECTED`).
    block_access: Option<(AccessSpec, Span)>,
    /// Statements of the lists being parsed, innermost last: each list is moved out
    /// into a vector of exactly its size when it ends (growing a `Vec<Stmt>` by
    /// doubling would touch twice the memory the tree needs).
    stmts: Vec<Stmt>,
    /// The same for call arguments.
    args: Vec<Arg>,
    /// The parser of bodies written in another language, if any.
    hook: Option<&'a mut dyn BodyHook>,
    /// While an IL operand is parsed ([`Self::line_operand`]): the nesting depth at
    /// which a postfix on a new line ends the operand.
    line_postfix: Option<u32>,
    /// The first of [`Lexed::c_pragmas`] not yet made a statement or skipped.
    c_next: usize,
}

impl<'a> Parser<'a> {
    // ---------------------------------------------------------------- tokens

    /// The index of the current token.
    pub(crate) fn pos(&self) -> usize {
        self.pos
    }

    /// The token at `idx` (the last one, Eof, past the end).
    pub(crate) fn token(&self, idx: usize) -> Token {
        self.toks.get(idx).copied().unwrap_or(self.eof)
    }

    /// The file being parsed.
    pub(crate) fn file(&self) -> FileId {
        self.file
    }

    /// The source text of `span` (empty if it is not in the text).
    pub(crate) fn source(&self, span: Span) -> &'a str {
        self.text
            .get(span.start as usize..span.end as usize)
            .unwrap_or("")
    }

    /// The build's name table.
    pub(crate) fn interner(&mut self) -> &mut Interner {
        self.interner
    }

    /// Reports a diagnostic as it is, bypassing the one-error-per-token rule of
    /// [`Self::emit`] (for warnings, and for errors found after a body was parsed).
    pub(crate) fn report(&mut self, d: Diagnostic) {
        self.diags.push(d);
    }

    /// True at a token no body goes past: an END_ keyword of a POU or section, a
    /// VAR block, a POU keyword, the end of the file, or a member (`ACTION a:`).
    pub(crate) fn at_body_stop(&self) -> bool {
        is_section_stop(self.peek()) || self.member_at().is_some()
    }

    /// Asks the [`BodyHook`], if any, to parse the body that starts here.
    fn foreign_body(&mut self, ctx: &BodyCtx<'_>) -> Option<Vec<Stmt>> {
        let hook = self.hook.take()?;
        let stmts = hook.body(self, ctx);
        self.hook = Some(hook);
        stmts
    }

    pub(crate) fn tok(&self) -> Token {
        self.token(self.pos)
    }

    pub(crate) fn peek(&self) -> Tok {
        self.tok().kind
    }

    pub(crate) fn peek_at(&self, n: usize) -> Tok {
        self.toks.get(self.pos + n).map_or(Tok::Eof, |t| t.kind)
    }

    pub(crate) fn at(&self, k: Tok) -> bool {
        self.peek() == k
    }

    pub(crate) fn bump(&mut self) -> Token {
        let t = self.tok();
        if t.kind != Tok::Eof {
            self.pos += 1;
        }
        t
    }

    pub(crate) fn eat(&mut self, k: Tok) -> bool {
        if self.at(k) {
            self.bump();
            true
        } else {
            false
        }
    }

    pub(crate) fn sp(&self, start: u32, end: u32) -> Span {
        Span::new(self.file, start, end)
    }

    pub(crate) fn tspan(&self, t: Token) -> Span {
        Span::new(self.file, t.start, t.end)
    }

    pub(crate) fn prev_end(&self) -> u32 {
        if self.pos == 0 {
            0
        } else {
            self.toks[self.pos - 1].end
        }
    }

    pub(crate) fn span_from(&self, start: u32) -> Span {
        self.sp(start, self.prev_end().max(start))
    }

    pub(crate) fn ident(&self, t: Token) -> Ident {
        Ident {
            sym: Symbol(t.data),
            span: self.tspan(t),
        }
    }

    fn at_sym(&self, n: usize, sym: Symbol) -> bool {
        self.toks
            .get(self.pos + n)
            .is_some_and(|t| t.kind == Tok::Ident && t.data == sym.0)
    }

    pub(crate) fn slice(&self, t: Token) -> &'a str {
        self.text
            .get(t.start as usize..t.end as usize)
            .unwrap_or("")
    }

    // ---------------------------------------------------------------- errors

    /// How the token at `idx` is shown in "found ..." messages.
    pub(crate) fn describe(&self, idx: usize) -> String {
        let t = self.token(idx);
        match t.kind {
            Tok::Eof => "end of file".into(),
            Tok::Error => "an invalid character".into(),
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

    /// Reports `d`, attributed to the token at `idx`, unless an error was already
    /// reported at or after it, or the token is one the lexer reported.
    pub(crate) fn emit(&mut self, idx: usize, d: Diagnostic) {
        if self.last_err.is_some_and(|l| idx <= l) {
            return;
        }
        self.last_err = Some(idx);
        let k = self.token(idx).kind;
        let after_swallow = idx > 0 && self.toks[idx - 1].flags & SWALLOWED != 0;
        if k == Tok::Error || (k == Tok::Eof && self.eof_silent) || after_swallow {
            return;
        }
        self.diags.push(d);
    }

    fn error_here(&mut self, code: &'static str, msg: String, label: impl Into<String>) {
        let d = Diagnostic::error(code, msg, self.tspan(self.tok())).with_label(label);
        self.emit(self.pos, d);
    }

    /// "expected {what}, found ..." at the current token. A keyword where a name is
    /// expected gets a note: `BY`, `ON`, `STEP`... cannot name a variable.
    fn expected(&mut self, what: &str) {
        let t = self.tok();
        let msg = format!("expected {what}, found {}", self.describe(self.pos));
        let mut d = Diagnostic::error(codes::UNEXPECTED_TOKEN, msg, self.tspan(t))
            .with_label(format!("expected {what}"));
        if t.kind.is_keyword() && (what.contains("name") || what.contains("variable")) {
            d = d.with_note(format!(
                "`{}` is a keyword and cannot be used as a name",
                self.slice(t)
            ));
        }
        self.emit(self.pos, d);
    }

    /// Reports that `what` is missing before the current token. When that token starts
    /// a new line, the caret goes just after the previous token, where the missing one
    /// belongs, and the current token is shown as the one found; otherwise the caret is
    /// on the current token, with `label`.
    fn missing(&mut self, code: &'static str, what: &str, label: &str) {
        let t = self.tok();
        let msg = format!("expected {what}, found {}", self.describe(self.pos));
        let d = if t.newline_before() && self.pos > 0 {
            let end = self.prev_end();
            let d = Diagnostic::error(code, msg, self.sp(end, end))
                .with_label(format!("expected {what} here"));
            if t.kind == Tok::Eof {
                d
            } else {
                d.with_secondary(self.tspan(t), "unexpected token")
            }
        } else {
            Diagnostic::error(code, msg, self.tspan(t)).with_label(label)
        };
        self.emit(self.pos, d);
    }

    fn expect_tok(&mut self, k: Tok, what: &str) -> Option<Token> {
        if self.at(k) {
            Some(self.bump())
        } else {
            self.expected(what);
            None
        }
    }

    /// Like [`Self::expect_tok`] for the closer `k` of the bracket `open`, which the
    /// error shows.
    fn expect_close(&mut self, k: Tok, what: &str, open: Token) -> Option<Token> {
        if self.at(k) {
            return Some(self.bump());
        }
        let msg = format!("expected {what}, found {}", self.describe(self.pos));
        let d = Diagnostic::error(codes::UNEXPECTED_TOKEN, msg, self.tspan(self.tok()))
            .with_label(format!("expected {what}"))
            .with_secondary(
                self.tspan(open),
                format!("this `{}` is not closed", open.kind.text()),
            );
        self.emit(self.pos, d);
        None
    }

    fn expect_ident(&mut self, what: &str) -> Option<Ident> {
        if self.at(Tok::Ident) {
            let t = self.bump();
            Some(self.ident(t))
        } else {
            self.expected(what);
            None
        }
    }

    fn too_deep(&mut self) {
        let msg = if self.depth >= MAX_DEPTH {
            format!("nesting too deep (more than {MAX_DEPTH} levels)")
        } else {
            format!("expression too long or nested too deeply (height over {MAX_HEIGHT})")
        };
        self.error_here(codes::NESTING_TOO_DEEP, msg, "too deep here");
    }

    /// Goes one nesting level deeper, or reports that the limit is reached. Every
    /// successful `enter` is paired with a `leave`.
    fn enter(&mut self) -> bool {
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

    fn open_add(&mut self, toks: &[Tok], delta: i32) {
        for &t in toks {
            if let Some(i) = closer_idx(t) {
                self.open[i] = self.open[i].saturating_add_signed(delta);
            }
        }
    }

    // ---------------------------------------------------------------- recovery

    /// True at tokens where statement-level recovery stops.
    fn at_sync(&self) -> bool {
        let t = self.peek();
        t == Tok::Semi || is_stmt_keyword(t) || closer_idx(t).is_some() || is_section_stop(t)
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

    /// Skips a broken declaration: to its `;` (consumed), or to END_VAR, END_TYPE,
    /// a section keyword. Nested STRUCT ... END_STRUCT are skipped whole.
    fn skip_decl(&mut self) {
        let mut level = 0u32;
        loop {
            let t = self.peek();
            match t {
                Tok::Struct => level += 1,
                Tok::EndStruct if level > 0 => level -= 1,
                Tok::Semi if level == 0 => {
                    self.bump();
                    return;
                }
                _ if is_section_stop(t) => return,
                _ if level == 0 && (is_stmt_keyword(t) || closer_idx(t).is_some()) => return,
                _ => {}
            }
            self.bump();
        }
    }

    /// Skips a whole compound statement (too deeply nested), counting its nested ones.
    fn skip_balanced_stmt(&mut self) {
        let mut level = 0u32;
        loop {
            let t = self.peek();
            match t {
                Tok::If | Tok::Case | Tok::For | Tok::While | Tok::Repeat => level += 1,
                _ if is_end_closer(t) => {
                    level = level.saturating_sub(1);
                    if level == 0 {
                        self.bump();
                        self.eat(Tok::Semi);
                        return;
                    }
                }
                _ if is_section_stop(t) => return,
                _ => {}
            }
            self.bump();
        }
    }

    /// After a statement: its `;`. A missing one is reported once; the parser goes on
    /// as if it were there when what follows can follow a statement.
    fn expect_semi(&mut self) {
        if self.eat(Tok::Semi) {
            return;
        }
        let t = self.tok();
        if !self.unmatched_closer() {
            self.missing(codes::MISSING_SEMICOLON, "`;`", "expected `;` before this");
        }
        let follows = (t.newline_before() && starts_stmt(t.kind))
            || is_stmt_keyword(t.kind)
            || closer_idx(t.kind).is_some()
            || is_section_stop(t.kind);
        if !follows {
            self.recover_stmt();
        }
    }

    /// At a `)` or `]` after a complete expression or statement, whose brackets are
    /// balanced: reports it as closing nothing and returns true.
    fn unmatched_closer(&mut self) -> bool {
        let t = self.tok();
        let open = match t.kind {
            Tok::RParen => Tok::LParen,
            Tok::RBracket => Tok::LBracket,
            _ => return false,
        };
        let msg = format!(
            "unmatched `{}`: no `{}` is open",
            t.kind.text(),
            open.text()
        );
        self.error_here(codes::UNEXPECTED_TOKEN, msg, "closes nothing");
        true
    }

    /// After a declaration: its `;` (see [`Self::expect_semi`]).
    fn expect_decl_semi(&mut self) {
        if self.eat(Tok::Semi) {
            return;
        }
        let t = self.tok();
        self.missing(codes::MISSING_SEMICOLON, "`;`", "expected `;` before this");
        let follows = (t.newline_before() && matches!(t.kind, Tok::Ident | Tok::At))
            || is_section_stop(t.kind);
        if !follows {
            self.skip_decl();
        }
    }

    /// A header keyword (THEN, DO, OF). When missing: reported, then assumed present
    /// if a statement follows on a new line, else skipped to.
    fn expect_kw(&mut self, kw: Tok) -> bool {
        if self.eat(kw) {
            return true;
        }
        let t = self.tok();
        let what = format!("`{}`", kw.text());
        self.missing(codes::UNEXPECTED_TOKEN, &what, &format!("expected {what}"));
        let follows = (t.newline_before() && starts_stmt(t.kind))
            || is_stmt_keyword(t.kind)
            || closer_idx(t.kind).is_some()
            || is_section_stop(t.kind);
        if !follows {
            self.recover_to(kw);
        }
        false
    }

    /// The END_ keyword of a compound statement opened by `opener`. Another
    /// statement END_ that nothing else is waiting for is taken as a misspelt one.
    fn expect_end(&mut self, end: Tok, opener: Token) -> bool {
        self.expect_end_hint(end, opener, None)
    }

    /// [`Self::expect_end`], with a secondary label `hint` in the error.
    fn expect_end_hint(&mut self, end: Tok, opener: Token, hint: Option<(Span, &str)>) -> bool {
        if self.eat(end) {
            return true;
        }
        let t = self.tok();
        let mismatched =
            is_end_closer(t.kind) && closer_idx(t.kind).is_some_and(|i| self.open[i] == 0);
        let msg = format!(
            "expected `{}`, found {}",
            end.text(),
            self.describe(self.pos)
        );
        let mut d = Diagnostic::error(codes::UNCLOSED_BLOCK, msg, self.tspan(t))
            .with_label(format!("expected `{}`", end.text()))
            .with_secondary(
                self.tspan(opener),
                format!("this `{}` is not closed", opener.kind.text()),
            );
        if let Some((span, label)) = hint {
            d = d.with_secondary(span, label);
        }
        self.emit(self.pos, d);
        if mismatched {
            self.bump();
        }
        mismatched
    }

    // ---------------------------------------------------------------- top level

    fn unit(&mut self) -> Vec<Item> {
        let mut items = Vec::new();
        loop {
            let t = self.tok();
            match t.kind {
                Tok::Eof => break,
                Tok::Program | Tok::Function | Tok::FunctionBlock => {
                    let kind = match t.kind {
                        Tok::Program => PouKind::Program,
                        Tok::Function => PouKind::Function,
                        _ => PouKind::FunctionBlock,
                    };
                    if let Some(p) = self.pou(kind) {
                        self.last_pou = Some(p.name);
                        items.push(Item::Pou(p));
                    }
                }
                Tok::Type => self.type_block(&mut items),
                Tok::VarGlobal => {
                    if let Some(b) = self.var_block(DeclCtx::Global) {
                        items.push(Item::Globals(b));
                    }
                }
                Tok::Configuration => {
                    if let Some(c) = self.configuration() {
                        items.push(Item::Configuration(c));
                    }
                }
                Tok::Semi => {
                    self.bump();
                }
                Tok::Ident if self.at_sym(0, self.s.actions) && self.peek_at(1) == Tok::Ident => {
                    self.actions_block(&mut items);
                }
                // CoDeSys 2.3 accepts this spelling (OSCAT uses it).
                Tok::Ident
                    if self.at_sym(0, self.s.functionblock) && self.peek_at(1) == Tok::Ident =>
                {
                    if let Some(p) = self.pou(PouKind::FunctionBlock) {
                        self.last_pou = Some(p.name);
                        items.push(Item::Pou(p));
                    }
                }
                // The list of libraries at the end of a CoDeSys 2.3 export: not code.
                Tok::Ident
                    if self.at_sym(0, self.s.library) && (t.newline_before() || self.pos == 0) =>
                {
                    self.bump();
                    while !self.at(Tok::Eof) && !self.at_sym(0, self.s.end_library) {
                        self.bump();
                    }
                    if self.at(Tok::Eof) {
                        let msg = "expected `END_LIBRARY`, found end of file".to_string();
                        let d =
                            Diagnostic::error(codes::UNCLOSED_BLOCK, msg, self.tspan(self.tok()))
                                .with_label("expected `END_LIBRARY`")
                                .with_secondary(self.tspan(t), "this LIBRARY list is not closed");
                        self.emit(self.pos, d);
                    }
                    self.bump();
                }
                _ => match self.member_at() {
                    Some(Member::Class) => {
                        if let Some(p) = self.pou_with(PouKind::FunctionBlock, Tok::EndClass) {
                            self.last_pou = Some(p.name);
                            items.push(Item::Pou(p));
                        }
                    }
                    Some(Member::Action) => {
                        if let Some(a) = self.action(true, &[]) {
                            items.push(Item::Action(a));
                        }
                    }
                    Some(Member::Interface) => {
                        if let Some(i) = self.interface() {
                            items.push(Item::Interface(i));
                        }
                    }
                    Some(m) => self.unsupported_member(m),
                    None => {
                        let what = "`PROGRAM`, `FUNCTION`, `FUNCTION_BLOCK`, `TYPE`, \
                                    `VAR_GLOBAL` or `CONFIGURATION`";
                        if is_end_keyword(t.kind) {
                            let msg = format!(
                                "unexpected {}: it closes nothing here",
                                self.describe(self.pos)
                            );
                            self.error_here(codes::UNMATCHED_END, msg, "nothing to close here");
                        } else {
                            self.expected(what);
                        }
                        self.bump();
                        while !matches!(self.peek(), Tok::Eof | Tok::VarGlobal | Tok::Semi)
                            && !is_top_start(self.peek())
                            && self.member_at().is_none()
                        {
                            self.bump();
                        }
                    }
                },
            }
        }
        items
    }

    /// RuSTy's `ACTIONS [pou] ACTION a ... END_ACTION ... END_ACTIONS`.
    fn actions_block(&mut self, items: &mut Vec<Item>) {
        let kw = self.bump();
        let owner = if self.at(Tok::Ident) && self.member_at() != Some(Member::Action) {
            let t = self.bump();
            Some(self.ident(t))
        } else {
            self.last_pou
        };
        self.eat(Tok::Semi);
        loop {
            let t = self.tok();
            match t.kind {
                Tok::EndActions => {
                    self.bump();
                    self.eat(Tok::Semi);
                    break;
                }
                Tok::Semi => {
                    self.bump();
                }
                _ if self.member_at() == Some(Member::Action) => {
                    if let Some(mut a) = self.action(false, &[]) {
                        a.pou = a.pou.or(owner);
                        items.push(Item::Action(a));
                    }
                }
                k if k == Tok::Eof || is_top_start(k) => {
                    let msg = format!("expected `END_ACTIONS`, found {}", self.describe(self.pos));
                    let d = Diagnostic::error(codes::UNCLOSED_BLOCK, msg, self.tspan(t))
                        .with_label("expected `END_ACTIONS`")
                        .with_secondary(self.tspan(kw), "this ACTIONS block is not closed");
                    self.emit(self.pos, d);
                    break;
                }
                _ => {
                    self.expected("`ACTION` or `END_ACTIONS`");
                    self.bump();
                }
            }
        }
    }

    // ---------------------------------------------------------------- POUs

    fn pou(&mut self, kind: PouKind) -> Option<Pou> {
        let end_tok = match kind {
            PouKind::Program => Tok::EndProgram,
            PouKind::Function => Tok::EndFunction,
            PouKind::FunctionBlock => Tok::EndFunctionBlock,
        };
        self.pou_with(kind, end_tok)
    }

    /// A POU closed by `end_tok`: `END_CLASS` makes it a CLASS (a FUNCTION_BLOCK
    /// marked as one).
    fn pou_with(&mut self, kind: PouKind, end_tok: Tok) -> Option<Pou> {
        let kw = self.bump();
        let modifiers = self.modifiers();
        let name = if kind == PouKind::Function
            && matches!(
                self.peek(),
                Tok::And | Tok::Or | Tok::Xor | Tok::Not | Tok::Mod
            ) {
            // The operators' function forms, as matiec's prototypes declare them.
            let t = self.bump();
            let text = t.kind.text().to_string();
            Some(Ident {
                sym: self.interner.intern_upper(&text),
                span: self.tspan(t),
            })
        } else {
            self.expect_ident("a name")
        };
        let mut return_type = None;
        let mut extends = None;
        let mut implements = Vec::new();
        if name.is_some() {
            if self.at(Tok::Colon) {
                self.bump();
                return_type = self.type_spec();
                if return_type.is_none() {
                    self.skip_header_rest();
                }
            }
            if self.at_sym(0, self.s.extends) {
                self.bump();
                extends = self.expect_ident("the name of the base FUNCTION_BLOCK");
            }
            if self.at_sym(0, self.s.implements) {
                self.bump();
                implements = self.ident_list("the name of an INTERFACE");
            }
        }
        self.eat(Tok::Semi);
        let oo = OoParts {
            modifiers,
            implements,
            class: (end_tok == Tok::EndClass).then(|| self.tspan(kw)),
            ..OoParts::default()
        };
        self.pou_rest(kind, kw, end_tok, name, return_type, extends, oo)
    }

    /// The declarations and body of a POU, METHOD or property accessor after its
    /// header, up to `end_tok`.
    #[allow(clippy::too_many_arguments)]
    fn pou_rest(
        &mut self,
        kind: PouKind,
        kw: Token,
        end_tok: Tok,
        name: Option<Ident>,
        return_type: Option<TypeSpec>,
        extends: Option<Ident>,
        mut oo: OoParts,
    ) -> Option<Pou> {
        // A method or accessor: its own END_ keyword, no members of its own.
        let member = !is_pou_end(end_tok);
        let mut unsupported = Vec::new();
        self.eat(Tok::Semi);
        let mut var_blocks = Vec::new();
        let mut stmts: Vec<Stmt> = Vec::new();
        let mut body_start = None;
        let mut body_end = self.prev_end();
        let mut decl_end = self.prev_end();
        let mut actions = Vec::new();
        let mut sfc: Option<Sfc> = None;
        let mut sfc_start: Option<u32> = None;
        // The body was parsed by the hook (IL): what follows belongs to it too.
        let mut foreign = false;
        loop {
            let t = self.tok();
            match t.kind {
                k if k == end_tok => {
                    self.bump();
                    break;
                }
                k if is_pou_end(k) || (member && (is_section_stop(k) && var_kind(k).is_none())) => {
                    if member {
                        // A METHOD or accessor left open: the POU's END_ closes it.
                        let msg = format!(
                            "expected `{}`, found {}",
                            end_tok.text(),
                            self.describe(self.pos)
                        );
                        let d = Diagnostic::error(codes::UNCLOSED_BLOCK, msg, self.tspan(t))
                            .with_label(format!("expected `{}`", end_tok.text()))
                            .with_secondary(self.tspan(kw), "this member is not closed");
                        self.emit(self.pos, d);
                        break;
                    }
                    let msg = format!(
                        "expected `{}`, found {}",
                        end_tok.text(),
                        self.describe(self.pos)
                    );
                    let d = Diagnostic::error(codes::UNCLOSED_BLOCK, msg, self.tspan(t))
                        .with_label(format!("expected `{}`", end_tok.text()))
                        .with_secondary(self.tspan(kw), "this POU is closed by the wrong keyword");
                    self.emit(self.pos, d);
                    self.bump();
                    break;
                }
                k if k == Tok::Eof || is_top_start(k) => {
                    let msg = format!(
                        "expected `{}`, found {}",
                        end_tok.text(),
                        self.describe(self.pos)
                    );
                    let d = Diagnostic::error(codes::UNCLOSED_BLOCK, msg, self.tspan(t))
                        .with_label(format!("expected `{}`", end_tok.text()))
                        .with_secondary(self.tspan(kw), "this POU is not closed");
                    self.emit(self.pos, d);
                    break;
                }
                k if var_kind(k).is_some() => {
                    self.block_access = None;
                    if let Some(b) = self.var_block(DeclCtx::Pou) {
                        if let Some(a) = self.block_access.take() {
                            oo.var_access.push((var_blocks.len() as u32, a.0, a.1));
                        }
                        var_blocks.push(b);
                    }
                    if stmts.is_empty() {
                        decl_end = self.prev_end();
                    }
                }
                k if is_section_stop(k) => {
                    let msg = format!(
                        "unexpected {}: it closes nothing here",
                        self.describe(self.pos)
                    );
                    self.error_here(
                        codes::UNMATCHED_END,
                        msg,
                        format!("no {} is open", opener_of(k)),
                    );
                    self.bump();
                }
                _ => {
                    if let Some(m) = self.member_at() {
                        match m {
                            Member::Method if !member => {
                                if let Some(x) = self.method() {
                                    oo.methods.push(x);
                                }
                            }
                            Member::Property if !member => {
                                if let Some(x) = self.property() {
                                    oo.properties.push(x);
                                }
                            }
                            Member::Action => {
                                if let Some(a) = self.action(false, &var_blocks) {
                                    actions.push(a);
                                }
                            }
                            Member::Interface | Member::Class => self.unsupported_member(m),
                            Member::Step | Member::Transition if kind != PouKind::Function => {
                                let chart = sfc.get_or_insert_with(Sfc::default);
                                if m == Member::Step {
                                    chart.steps.extend(self.sfc_step());
                                } else {
                                    chart.transitions.extend(self.sfc_transition());
                                }
                                let start = *sfc_start.get_or_insert(t.start);
                                chart.span = self.sp(start, self.prev_end());
                            }
                            _ => {
                                let h = self.skip_member(m);
                                unsupported.push(h);
                            }
                        }
                        continue;
                    }
                    let before = self.pos;
                    let mut list = None;
                    if self.hook.is_some() && (body_start.is_none() || foreign) {
                        let ctx = BodyCtx {
                            kind: Some(kind),
                            name,
                            return_type: return_type.as_ref(),
                            var_blocks: &var_blocks,
                            continuing: foreign,
                        };
                        list = self.foreign_body(&ctx);
                        foreign |= list.is_some();
                    }
                    // A foreign body starts at its first token, which may give no
                    // statement (or a later one).
                    let hook_start = list
                        .as_ref()
                        .filter(|_| self.pos > before)
                        .map(|_| self.toks[before].start);
                    let list = match list {
                        Some(l) => l,
                        None => self.stmt_list(&[], false, false),
                    };
                    if let Some(start) = hook_start.or_else(|| list.first().map(|s| s.span.start)) {
                        body_start.get_or_insert(start);
                        body_end = self.prev_end();
                        append(&mut stmts, list);
                    } else if self.pos > before && body_start.is_some() {
                        body_end = self.prev_end();
                    }
                    if self.pos == before {
                        self.bump();
                    }
                }
            }
        }
        let end = self.prev_end();
        self.eat(Tok::Semi);
        let body_span = match body_start {
            Some(s) => self.sp(s, body_end),
            None => self.sp(decl_end, decl_end),
        };
        Some(Pou {
            kind,
            name: name?,
            return_type,
            extends,
            var_blocks,
            body: Body {
                stmts,
                span: body_span,
            },
            actions,
            unsupported_members: {
                unsupported.append(&mut self.extensible);
                unsupported
            },
            oo: Box::new(oo),
            sfc,
            span: self.sp(kw.start, end),
        })
    }

    /// After a broken POU header: skip what is left of its line.
    fn skip_header_rest(&mut self) {
        while !self.tok().newline_before() && !is_section_stop(self.peek()) && !self.at(Tok::Semi) {
            self.bump();
        }
    }

    /// `ACTION name: ... END_ACTION`, `ACTION pou.name: ...`. `decls` are the
    /// declarations of the POU it is written in, if any (for a [`BodyHook`]).
    fn action(&mut self, top_level: bool, decls: &[VarBlock]) -> Option<Action> {
        let kw = self.bump();
        let first = self.expect_ident("an action name");
        let mut pou = None;
        let mut name = first;
        if first.is_some() && self.eat(Tok::Dot) {
            pou = first;
            name = self.expect_ident("an action name");
        }
        if name.is_none() {
            self.skip_member_body(Tok::EndAction);
            return None;
        }
        if top_level && pou.is_none() {
            pou = self.last_pou;
        }
        self.eat(Tok::Colon);
        // An action written as a chart (IEC 61131-3 6.7; CODESYS's SFC actions).
        let mut sfc: Option<Sfc> = None;
        let body = if matches!(self.member_at(), Some(Member::Step | Member::Transition)) {
            let start = self.tok().start;
            let chart = sfc.get_or_insert_with(Sfc::default);
            while let Some(m @ (Member::Step | Member::Transition)) = self.member_at() {
                if m == Member::Step {
                    chart.steps.extend(self.sfc_step());
                } else {
                    chart.transitions.extend(self.sfc_transition());
                }
            }
            chart.span = self.sp(start, self.prev_end());
            let at = self.prev_end();
            if !self.eat(Tok::EndAction) {
                let msg = format!(
                    "expected `END_ACTION` after the chart, found {}",
                    self.describe(self.pos)
                );
                self.error_here(codes::UNCLOSED_BLOCK, msg, "expected `END_ACTION`");
                self.skip_member_body(Tok::EndAction);
            }
            Body {
                stmts: Vec::new(),
                span: self.sp(at, at),
            }
        } else {
            self.code_body(Tok::EndAction, kw, decls)
        };
        let span = self.span_from(kw.start);
        self.eat(Tok::Semi);
        Some(Action {
            pou,
            name: name?,
            body,
            sfc,
            span,
        })
    }

    fn skip_member_body(&mut self, end: Tok) {
        while !self.at(end)
            && !self.at(Tok::Eof)
            && !is_pou_end(self.peek())
            && !is_top_start(self.peek())
        {
            self.bump();
        }
        if self.eat(end) {
            self.eat(Tok::Semi);
        }
    }

    /// Statements up to `end` (consumed), for ACTION bodies.
    fn code_body(&mut self, end: Tok, opener: Token, decls: &[VarBlock]) -> Body {
        let start = self.tok().start;
        let mut stmts = Vec::new();
        let mut foreign = false;
        let mut hook_start = None;
        loop {
            let mut list = None;
            if self.hook.is_some() && (stmts.is_empty() || foreign) && !self.at(end) {
                let ctx = BodyCtx {
                    kind: None,
                    name: None,
                    return_type: None,
                    var_blocks: decls,
                    continuing: foreign,
                };
                let before = self.pos;
                list = self.foreign_body(&ctx);
                foreign |= list.is_some();
                if list.is_some() && self.pos > before && hook_start.is_none() {
                    hook_start = Some(self.toks[before].start);
                }
            }
            let list = match list {
                Some(l) => l,
                None => self.stmt_list(&[end], false, false),
            };
            append(&mut stmts, list);
            let t = self.tok();
            if t.kind == end {
                break;
            }
            if t.kind == Tok::Eof
                || is_top_start(t.kind)
                || is_pou_end(t.kind)
                || var_kind(t.kind).is_some()
                || self.member_at().is_some()
            {
                let msg = format!(
                    "expected `{}`, found {}",
                    end.text(),
                    self.describe(self.pos)
                );
                let d = Diagnostic::error(codes::UNCLOSED_BLOCK, msg, self.tspan(t))
                    .with_label(format!("expected `{}`", end.text()))
                    .with_secondary(self.tspan(opener), "this block is not closed");
                self.emit(self.pos, d);
                let span = self.span_from(start);
                return Body { stmts, span };
            }
            let msg = format!(
                "unexpected {}: it closes nothing here",
                self.describe(self.pos)
            );
            self.error_here(
                codes::UNMATCHED_END,
                msg,
                format!("no {} is open", opener_of(t.kind)),
            );
            self.bump();
        }
        let span = match hook_start.or_else(|| stmts.first().map(|f| f.span.start)) {
            Some(s) => self.sp(s, self.prev_end()),
            None => self.sp(start, start),
        };
        self.bump();
        Body { stmts, span }
    }
}
/// What a CONFIGURATION or RESOURCE declares (see `Parser::config_items`).
#[derive(Default)]
struct ConfigItems {
    var_blocks: Vec<VarBlock>,
    resources: Vec<Resource>,
    tasks: Vec<TaskDecl>,
    programs: Vec<ProgramConfig>,
}
