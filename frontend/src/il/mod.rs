//! Instruction List (IEC 61131-3 ed. 3): parsed into the syntax tree ST uses.
//!
//! An `.il` file has the declarations of ST (POU headers, VAR blocks, TYPE,
//! CONFIGURATION...), so the ST parser reads it; only POU and ACTION bodies differ. The
//! ST parser asks this module (through its `BodyHook`) about every
//! body: a body is IL if its first line starts with an IL operator or a label `name:`
//! (see `looks_like_il`), otherwise it is ST, so the two can be mixed in one file as
//! matiec's tests do.
//!
//! An IL body is read line by line (`instr`): one instruction per line, `[label:]
//! operator[modifiers] [operand {, operand}]`; the lexer's NEWLINE_BEFORE flag tells
//! where lines end. Operands are ST primaries with their postfixes (`a.b`, `a[i]`,
//! `w.3`, literals, direct addresses), parsed by the ST parser itself.
//!
//! The instructions are then turned into ST statements (`translate`) by the CPDev
//! method: the current result (CR) is kept as an expression tree over the operands
//! rather than as a value, so `LD A / MUL 4 / ADD B / ST C` becomes the statement
//! `C := A * 4 + B`, the very tree ST gives. Type checking, lowering and every backend
//! then serve IL unchanged, and a FUNCTION written in IL can call one written in ST.

pub(crate) mod instr;
pub(crate) mod translate;

pub use instr::is_operator;

#[cfg(test)]
mod tests;

use crate::ast::{SourceUnit, Stmt, TypeSpec};
use crate::intern::{Interner, Symbol};
use crate::st::lexer::{self, Tok};
use crate::st::parser::{self, BodyCtx, BodyHook, Parser};
use instr::{Word, Words};
use plcc_ir::diag::{Diagnostic, FileId};
use rustc_hash::FxHashMap;
use translate::{Class, Env};

/// Parses one Instruction List file (its ST bodies too). Never panics; errors and
/// warnings go to `diags`, in source order.
pub fn parse(
    file: FileId,
    text: &str,
    interner: &mut Interner,
    diags: &mut Vec<Diagnostic>,
) -> SourceUnit {
    parse_with_bodies(file, text, interner, diags).0
}

/// [`parse`], and the byte ranges of the bodies read as IL (from their first token to
/// the token that ends them), in source order: the formatter lays out their lines
/// as instructions.
pub(crate) fn parse_with_bodies(
    file: FileId,
    text: &str,
    interner: &mut Interner,
    diags: &mut Vec<Diagnostic>,
) -> (SourceUnit, Vec<std::ops::Range<usize>>) {
    let first = diags.len();
    let lexed = lexer::lex(file, text, interner, diags);
    let mut bodies = IlBodies::new(interner);
    let unit = parser::parse_tokens_with(file, text, &lexed, interner, diags, Some(&mut bodies));
    diags[first..].sort_by_key(|d| d.span.map_or(u32::MAX, |s| s.start));
    (unit, bodies.ranges)
}

/// The [`BodyHook`] that recognises and translates IL bodies.
struct IlBodies {
    words: Words,
    /// Number of compiler temporaries made so far in the file (`__CR1`, `__CR2`...).
    temps: u32,
    /// The byte ranges of the IL bodies read so far.
    ranges: Vec<std::ops::Range<usize>>,
}

impl IlBodies {
    fn new(interner: &mut Interner) -> IlBodies {
        IlBodies {
            words: Words::new(interner),
            temps: 0,
            ranges: Vec::new(),
        }
    }
}

impl BodyHook for IlBodies {
    fn body(&mut self, p: &mut Parser<'_>, ctx: &BodyCtx<'_>) -> Option<Vec<Stmt>> {
        if !ctx.continuing && !looks_like_il(p, &self.words) {
            return None;
        }
        let start = p.tok().start as usize;
        let instrs = instr::parse_body(p, &self.words);
        self.ranges.push(start..p.tok().start as usize);
        let mut env = environment(ctx, &self.words);
        if let Some(name) = env.result {
            env.result_text = p.source(name.span).to_string();
        }
        let file = p.file();
        let mut diags = Vec::new();
        let stmts = translate::translate(
            &instrs,
            &env,
            file,
            p.interner(),
            &mut self.temps,
            &mut diags,
        );
        for d in diags {
            p.report(d);
        }
        Some(stmts)
    }
}

/// True if the body starting at the current token is IL: its first line starts with a
/// label `name:`, or with an IL operator that is not the start of an ST statement
/// (`ST := 5;` assigns a variable named ST; `R(S := x);` calls an instance named R;
/// but `AND(`, `ADD(` are IL, an ST statement cannot start with them), or it is a
/// formal function call `f(...)` without `;` followed by a line that starts with an
/// IL operator.
fn looks_like_il(p: &Parser<'_>, w: &Words) -> bool {
    starts_il_line(p, w, p.pos()) || formal_call_then_il(p, w)
}

/// True if the line starting at token `at` starts with an IL operator or a label.
fn starts_il_line(p: &Parser<'_>, w: &Words, at: usize) -> bool {
    let t = p.token(at);
    match t.kind {
        Tok::And | Tok::Or | Tok::Xor | Tok::Mod | Tok::Not | Tok::Amp | Tok::RParen => true,
        Tok::Ident => {
            let next = p.token(at + 1);
            if next.kind == Tok::Colon {
                return true;
            }
            let sym = Symbol(t.data);
            let word = match (w.ops.get(&sym), w.bad.contains_key(&sym)) {
                (Some(&word), _) => Some(word),
                (None, true) => None,
                (None, false) => return false,
            };
            if next.newline_before() || next.kind == Tok::Eof {
                return true;
            }
            match next.kind {
                Tok::Assign | Tok::Dot | Tok::LBracket | Tok::Caret | Tok::Arrow | Tok::Semi => {
                    false
                }
                Tok::LParen => matches!(word, Some(Word::Bin(..))),
                Tok::Ident if next.data == w.ref_.0 => p.token(at + 2).kind != Tok::Eq,
                _ => true,
            }
        }
        _ => false,
    }
}

/// `f(...)` on the first line, then an IL instruction on the next one.
fn formal_call_then_il(p: &Parser<'_>, w: &Words) -> bool {
    let at = p.pos();
    if p.tok().kind != Tok::Ident || p.token(at + 1).kind != Tok::LParen {
        return false;
    }
    let mut depth = 0u32;
    let mut i = at + 1;
    loop {
        let t = p.token(i);
        match t.kind {
            Tok::LParen => depth += 1,
            Tok::RParen => {
                depth -= 1;
                if depth == 0 {
                    let next = p.token(i + 1);
                    return next.newline_before() && starts_il_line(p, w, i + 1);
                }
            }
            Tok::Eof | Tok::Semi => return false,
            // Only operators and TRUE/FALSE among the keywords belong in arguments:
            // another one ends the search (the scan stays inside the body).
            k if k.is_keyword()
                && !matches!(
                    k,
                    Tok::And | Tok::Or | Tok::Xor | Tok::Not | Tok::Mod | Tok::True | Tok::False
                ) =>
            {
                return false
            }
            _ => {}
        }
        i += 1;
    }
}

/// What translation needs to know about the POU from its declarations.
fn environment(ctx: &BodyCtx<'_>, w: &Words) -> Env {
    let mut env = Env::default();
    let class_of = |spec: &TypeSpec| match spec {
        TypeSpec::Named(id) => w.elementary.get(&id.sym).copied(),
        TypeSpec::String { .. } => Some(Class::Other),
        _ => None,
    };
    let mut classes: FxHashMap<Symbol, Class> = FxHashMap::default();
    for block in ctx.var_blocks {
        for decl in &block.decls {
            let class = class_of(&decl.ty);
            for name in &decl.names {
                match class {
                    Some(c) => {
                        classes.insert(name.sym, c);
                    }
                    // A variable of a named, non-elementary type may be an FB
                    // instance: `S x` / `R x` then set an input and call it.
                    None if matches!(decl.ty, TypeSpec::Named(_)) => env.fb_vars.push(name.sym),
                    None => {}
                }
            }
        }
    }
    if ctx.kind == Some(crate::ast::PouKind::Function) {
        if let (Some(name), Some(ty)) = (ctx.name, ctx.return_type) {
            env.result = Some(name);
            env.result_class = class_of(ty);
            if let Some(c) = env.result_class {
                classes.insert(name.sym, c);
            }
        }
    }
    env.classes = classes;
    env
}
