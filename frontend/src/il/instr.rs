//! IL lines to instructions.
//!
//! One instruction per line: `[label:] operator[modifiers] [operand {, operand}]`. An
//! IL operator is recognised only at the start of an instruction, so `R`, `S`, `IN`,
//! `PT`... remain ordinary names in operands (`CAL T1(R := x)`, `ST T1.R`). A word at
//! the start of an instruction that is no IL operator is a function called on the
//! current result (`LIMIT 0, 100`, `ABS`, `LIMIT(MN := 0, IN := x, MX := 100)`).
//!
//! Error recovery: a malformed instruction is reported once and the rest of its line
//! skipped. It still becomes an instruction (marked `broken`) so that the translation
//! neither reports the current result as undefined after it nor unbalances the
//! parentheses: one mistake, one diagnostic.

use super::translate::Class;
use crate::ast::{BinaryOp, Expr, ExprKind, Ident, UnaryOp};
use crate::codes;
use crate::intern::{Interner, Symbol};
use crate::st::lexer::Tok;
use crate::st::parser::Parser;
use plcc_ir::diag::{Diagnostic, Span};
use rustc_hash::{FxHashMap, FxHashSet};

/// The condition modifier of JMP, CAL and RET.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub(crate) enum Cond {
    /// No modifier: always.
    Always,
    /// `C`: if the current result is TRUE.
    IfTrue,
    /// `CN`: if the current result is FALSE.
    IfFalse,
}

/// An IL operator word with its `N` and `C` modifiers (the `(` modifier is a token of
/// its own).
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub(crate) enum Word {
    /// LD, LDN
    Ld(bool),
    /// ST, STN
    St(bool),
    /// S
    Set,
    /// R
    Reset,
    /// AND, ANDN, OR, ..., ADD, ..., GT, ...: the operator, and `N` (negated operand).
    Bin(BinaryOp, bool),
    /// NOT
    Not,
    /// JMP, JMPC, JMPCN
    Jmp(Cond),
    /// CAL, CALC, CALCN
    Cal(Cond),
    /// RET, RETC, RETCN
    Ret(Cond),
    /// S1 R1 CLK CU CD PV IN PT: set that input of the operand instance and call it.
    FbInput,
}

/// Interned words the IL parser recognises.
pub(crate) struct Words {
    /// The IL operators written as identifiers.
    pub ops: FxHashMap<Symbol, Word>,
    /// Operator words with a modifier they do not take (`JMPN`, `LDC`, `ADDN`...):
    /// the operator and the modifier, for the message.
    pub bad: FxHashMap<Symbol, (&'static str, &'static str)>,
    /// `N`, of `&N`.
    pub n: Symbol,
    /// `REF`, of ST's `x REF= y`.
    pub ref_: Symbol,
    /// Elementary type names and their classes.
    pub elementary: FxHashMap<Symbol, Class>,
    /// Names of the operators that are ST keywords, for the extensible call form
    /// (`AND a, b` is `AND(CR, a, b)`).
    keyword_ops: [(Tok, Symbol); 5],
}

/// True if `word` is an IL operator written as an identifier (`LD`, `JMPC`, `CAL`...;
/// not `AND`, `OR`, `XOR`, `MOD`, `NOT`, which are ST keywords), in any case.
pub fn is_operator(word: &str) -> bool {
    OPS.iter().any(|(op, _)| op.eq_ignore_ascii_case(word))
}

const OPS: &[(&str, Word)] = &[
    ("LD", Word::Ld(false)),
    ("LDN", Word::Ld(true)),
    ("ST", Word::St(false)),
    ("STN", Word::St(true)),
    ("S", Word::Set),
    ("R", Word::Reset),
    ("ANDN", Word::Bin(BinaryOp::And, true)),
    ("ORN", Word::Bin(BinaryOp::Or, true)),
    ("XORN", Word::Bin(BinaryOp::Xor, true)),
    ("ADD", Word::Bin(BinaryOp::Add, false)),
    ("SUB", Word::Bin(BinaryOp::Sub, false)),
    ("MUL", Word::Bin(BinaryOp::Mul, false)),
    ("DIV", Word::Bin(BinaryOp::Div, false)),
    ("GT", Word::Bin(BinaryOp::Gt, false)),
    ("GE", Word::Bin(BinaryOp::Ge, false)),
    ("EQ", Word::Bin(BinaryOp::Eq, false)),
    ("NE", Word::Bin(BinaryOp::Ne, false)),
    ("LE", Word::Bin(BinaryOp::Le, false)),
    ("LT", Word::Bin(BinaryOp::Lt, false)),
    ("JMP", Word::Jmp(Cond::Always)),
    ("JMPC", Word::Jmp(Cond::IfTrue)),
    ("JMPCN", Word::Jmp(Cond::IfFalse)),
    ("CAL", Word::Cal(Cond::Always)),
    ("CALC", Word::Cal(Cond::IfTrue)),
    ("CALCN", Word::Cal(Cond::IfFalse)),
    ("RET", Word::Ret(Cond::Always)),
    ("RETC", Word::Ret(Cond::IfTrue)),
    ("RETCN", Word::Ret(Cond::IfFalse)),
    ("S1", Word::FbInput),
    ("R1", Word::FbInput),
    ("CLK", Word::FbInput),
    ("CU", Word::FbInput),
    ("CD", Word::FbInput),
    ("PV", Word::FbInput),
    ("IN", Word::FbInput),
    ("PT", Word::FbInput),
];

/// Operators whose words with a wrong modifier are reported as such (the FB input
/// operators are left out: `INC`, `PTN`... are plausible function names).
const MODIFIABLE: &[&str] = &[
    "LD", "ST", "S", "R", "JMP", "CAL", "RET", "NOT", "ADD", "SUB", "MUL", "DIV", "MOD", "GT",
    "GE", "EQ", "NE", "LE", "LT", "AND", "OR", "XOR",
];

const ELEMENTARY: &[(&str, Class)] = &[
    ("BOOL", Class::Bool),
    ("SINT", Class::Int),
    ("INT", Class::Int),
    ("DINT", Class::Int),
    ("LINT", Class::Int),
    ("USINT", Class::Int),
    ("UINT", Class::Int),
    ("UDINT", Class::Int),
    ("ULINT", Class::Int),
    ("BYTE", Class::Int),
    ("WORD", Class::Int),
    ("DWORD", Class::Int),
    ("LWORD", Class::Int),
    ("REAL", Class::Real),
    ("LREAL", Class::Real),
    ("TIME", Class::Time(false)),
    ("LTIME", Class::Time(true)),
    ("DATE", Class::Other),
    ("LDATE", Class::Other),
    ("TIME_OF_DAY", Class::Other),
    ("TOD", Class::Other),
    ("LTIME_OF_DAY", Class::Other),
    ("LTOD", Class::Other),
    ("DATE_AND_TIME", Class::Other),
    ("DT", Class::Other),
    ("LDATE_AND_TIME", Class::Other),
    ("LDT", Class::Other),
    ("CHAR", Class::Other),
    ("WCHAR", Class::Other),
];

impl Words {
    /// Interns the words.
    pub fn new(i: &mut Interner) -> Words {
        let ops: FxHashMap<Symbol, Word> = OPS
            .iter()
            .map(|&(name, w)| (i.intern_upper(name), w))
            .collect();
        let mut bad = FxHashMap::default();
        let valid: FxHashSet<&str> = OPS.iter().map(|&(n, _)| n).collect();
        for &base in MODIFIABLE {
            for m in ["N", "C", "CN", "NC"] {
                let word = format!("{base}{m}");
                if !valid.contains(word.as_str()) {
                    bad.insert(i.intern_upper(&word), (base, m));
                }
            }
        }
        Words {
            ops,
            bad,
            n: i.intern_upper("N"),
            ref_: i.intern_upper("REF"),
            elementary: ELEMENTARY
                .iter()
                .map(|&(n, c)| (i.intern_upper(n), c))
                .collect(),
            keyword_ops: [
                (Tok::And, i.intern_upper("AND")),
                (Tok::Or, i.intern_upper("OR")),
                (Tok::Xor, i.intern_upper("XOR")),
                (Tok::Mod, i.intern_upper("MOD")),
                (Tok::Not, i.intern_upper("NOT")),
            ],
        }
    }

    fn keyword_sym(&self, t: Tok) -> Symbol {
        self.keyword_ops
            .iter()
            .find(|&&(k, _)| k == t)
            .map_or(self.keyword_ops[0].1, |&(_, s)| s)
    }
}

/// A parsed instruction.
#[derive(Clone, Debug)]
pub(crate) enum Op {
    /// `name:`
    Label(Ident),
    /// LD, LDN
    Ld {
        /// LDN
        neg: bool,
    },
    /// ST, STN
    St {
        /// STN
        neg: bool,
    },
    /// S
    Set,
    /// R
    Reset,
    /// AND ... LT, with their `N` and `(` modifiers.
    Bin {
        /// The operator.
        op: BinaryOp,
        /// `N`: the operand is negated.
        neg: bool,
        /// `(`: deferred until the matching `)`.
        paren: bool,
        /// The operator's name (`ADD`), for the extensible form `ADD a, b`.
        word: Ident,
    },
    /// NOT
    Not,
    /// `)`
    Close,
    /// JMP, JMPC, JMPCN; the operand is the label.
    Jmp(Cond),
    /// CAL, CALC, CALCN; the operand is the call (an ExprKind::Call).
    Cal(Cond),
    /// RET, RETC, RETCN
    Ret(Cond),
    /// S1, R1, CLK, CU, CD, PV, IN, PT (and S, R on an instance): the input.
    FbInput(Ident),
    /// A function called on the current result: `LIMIT 0, 100`.
    Func(Ident),
    /// A formal function call, which does not use the current result:
    /// `LIMIT(MN := 0, IN := x, MX := 100)`.
    FormalCall(Expr),
    /// A line that is no instruction at all (already reported).
    Invalid,
}

/// One instruction.
#[derive(Clone, Debug)]
pub(crate) struct Instr {
    /// What it does.
    pub op: Op,
    /// Its operands in order.
    pub operands: Vec<Expr>,
    /// From the operator through the operands (the label alone for a label).
    pub span: Span,
    /// It was malformed (already reported): the translation makes the current result
    /// unknown after it, without further diagnostics.
    pub broken: bool,
}

/// Reads the instructions of a body, up to (not including) the token that ends it.
pub(crate) fn parse_body(p: &mut Parser<'_>, w: &Words) -> Vec<Instr> {
    let mut out = Vec::new();
    while !p.at_body_stop() {
        let before = p.pos();
        line(p, w, &mut out);
        if p.pos() == before {
            p.bump();
        }
    }
    out
}

/// True where the current instruction ends: at a token on a new line, or at the end
/// of the body.
fn at_line_end(p: &Parser<'_>) -> bool {
    p.tok().newline_before() || p.at_body_stop()
}

/// Skips the rest of the line of the instruction that starts at token `first`.
fn skip_line(p: &mut Parser<'_>, first: usize) {
    while !p.at_body_stop() && (p.pos() <= first || !p.tok().newline_before()) {
        p.bump();
    }
}

fn line(p: &mut Parser<'_>, w: &Words, out: &mut Vec<Instr>) {
    while p.tok().kind == Tok::Ident && p.token(p.pos() + 1).kind == Tok::Colon {
        let t = p.bump();
        let colon = p.bump();
        out.push(Instr {
            op: Op::Label(p.ident(t)),
            operands: Vec::new(),
            span: p.sp(t.start, colon.end),
            broken: false,
        });
        if at_line_end(p) {
            return;
        }
    }
    instruction(p, w, out);
}

/// A broken instruction standing for a line that could not be read.
fn invalid(span: Span) -> Instr {
    Instr {
        op: Op::Invalid,
        operands: Vec::new(),
        span,
        broken: true,
    }
}

fn instruction(p: &mut Parser<'_>, w: &Words, out: &mut Vec<Instr>) {
    let idx = p.pos();
    let t = p.tok();
    let tspan = p.tspan(t);
    let word = match t.kind {
        Tok::Ident => {
            let sym = Symbol(t.data);
            if let Some(&word) = w.ops.get(&sym) {
                Some(word)
            } else if let Some(&(base, m)) = w.bad.get(&sym) {
                let text = p.slice(t).to_string();
                let d = Diagnostic::error(
                    codes::IL_BAD_MODIFIER,
                    format!(
                        "`{text}` is not an IL operator: `{base}` does not take the modifier `{m}`"
                    ),
                    tspan,
                )
                .with_label("unknown modifier combination")
                .with_note(modifier_note(base));
                p.emit(idx, d);
                skip_line(p, idx);
                out.push(invalid(tspan));
                return;
            } else {
                None
            }
        }
        Tok::And => Some(Word::Bin(BinaryOp::And, false)),
        Tok::Or => Some(Word::Bin(BinaryOp::Or, false)),
        Tok::Xor => Some(Word::Bin(BinaryOp::Xor, false)),
        Tok::Mod => Some(Word::Bin(BinaryOp::Mod, false)),
        Tok::Not => Some(Word::Not),
        Tok::Amp => {
            // `&N` (no space) is ANDN; `& N` is AND with a variable named N.
            let n = p.token(idx + 1);
            let neg = n.kind == Tok::Ident && n.data == w.n.0 && n.start == t.end;
            if neg {
                p.bump();
            }
            Some(Word::Bin(BinaryOp::And, neg))
        }
        Tok::RParen => {
            p.bump();
            let operands = operands(p, idx, false);
            let span = p.span_from(t.start);
            if let Some(first) = operands.as_ref().and_then(|o| o.first()) {
                operand_not_allowed(p, idx, "`)`", first.span);
            }
            end_of_line(p, idx);
            out.push(Instr {
                op: Op::Close,
                operands: Vec::new(),
                span,
                broken: false,
            });
            return;
        }
        _ => {
            not_an_instruction(p, idx);
            skip_line(p, idx);
            out.push(invalid(tspan));
            return;
        }
    };
    p.bump();
    let name = match t.kind {
        Tok::Ident => p.ident(t),
        Tok::Amp => Ident {
            sym: w.keyword_sym(Tok::And),
            span: tspan,
        },
        k => Ident {
            sym: w.keyword_sym(k),
            span: tspan,
        },
    };
    let op_text = p.slice(t).to_ascii_uppercase();
    let Some(word) = word else {
        function_call(p, idx, name, out);
        return;
    };
    // The `(` modifier.
    let mut paren = false;
    if !at_line_end(p) && p.at(Tok::LParen) {
        if matches!(word, Word::Bin(..)) {
            p.bump();
            paren = true;
        } else {
            let open = p.tok();
            let d = Diagnostic::error(
                codes::IL_BAD_MODIFIER,
                format!("`{op_text}` does not take the modifier `(`"),
                p.sp(t.start, open.end),
            )
            .with_label("unknown modifier combination")
            .with_note(
                "only AND, OR, XOR (with or without N), ADD, SUB, MUL, DIV, MOD and the \
                 comparisons GT, GE, EQ, NE, LE, LT can be deferred with `(`",
            );
            p.emit(idx, d);
            skip_line(p, idx);
            out.push(invalid(p.sp(t.start, open.end)));
            return;
        }
    }
    let Some(mut operands) = operands(p, idx, matches!(word, Word::Cal(_))) else {
        out.push(Instr {
            broken: true,
            ..instr_of(word, name, paren, Vec::new(), p.span_from(t.start))
        });
        return;
    };
    let span = p.span_from(t.start);
    let what = format!("`{op_text}{}`", if paren { "(" } else { "" });
    let mut broken = false;
    let mut word = word;
    match word {
        Word::Not if operands.len() == 1 && !paren => {
            // matiec's `NOT x`: read as `LDN x`, with a warning.
            let d = Diagnostic::warning(
                codes::IL_NOT_WITH_OPERAND,
                "`NOT` with an operand: read as `LDN` of it",
                span,
            )
            .with_note("IEC 61131-3's NOT negates the current result and takes no operand");
            p.emit(idx, d);
            word = Word::Ld(true);
        }
        Word::Not | Word::Ret(_) => {
            if let Some(first) = operands.first() {
                operand_not_allowed(p, idx, &what, first.span);
                operands.clear();
            }
        }
        Word::Bin(..) if paren => {
            if let Some(second) = operands.get(1) {
                let d = Diagnostic::error(
                    codes::IL_BAD_OPERAND,
                    format!("{what} takes at most one operand"),
                    second.span,
                )
                .with_label("unexpected second operand");
                p.emit(idx, d);
                operands.truncate(1);
            }
        }
        Word::Bin(..) => {
            if operands.is_empty() {
                missing_operand(p, idx, &what, span);
                broken = true;
            }
        }
        _ => {
            if operands.is_empty() {
                missing_operand(p, idx, &what, span);
                broken = true;
            } else if let Some(second) = operands.get(1) {
                let d = Diagnostic::error(
                    codes::IL_BAD_OPERAND,
                    format!("{what} takes one operand"),
                    second.span,
                )
                .with_label("unexpected second operand");
                p.emit(idx, d);
                operands.truncate(1);
            }
            if let Some(first) = operands.first_mut() {
                if !operand_shape(p, idx, word, &what, first, span) {
                    broken = true;
                }
            }
        }
    }
    end_of_line(p, idx);
    out.push(Instr {
        broken,
        ..instr_of(word, name, paren, operands, span)
    });
}

fn instr_of(word: Word, name: Ident, paren: bool, operands: Vec<Expr>, span: Span) -> Instr {
    let op = match word {
        Word::Ld(neg) => Op::Ld { neg },
        Word::St(neg) => Op::St { neg },
        Word::Set => Op::Set,
        Word::Reset => Op::Reset,
        Word::Bin(op, neg) => Op::Bin {
            op,
            neg,
            paren,
            word: name,
        },
        Word::Not => Op::Not,
        Word::Jmp(c) => Op::Jmp(c),
        Word::Cal(c) => Op::Cal(c),
        Word::Ret(c) => Op::Ret(c),
        Word::FbInput => Op::FbInput(name),
    };
    Instr {
        op,
        operands,
        span,
        broken: false,
    }
}

/// Checks the operand of JMP (a label), CAL (an instance, or a call of one) and the
/// FB input operators (an instance); makes CAL's operand a call.
/// `span` is the instruction's, given to the call made from a bare `CAL inst`.
fn operand_shape(
    p: &mut Parser<'_>,
    idx: usize,
    word: Word,
    what: &str,
    e: &mut Expr,
    span: Span,
) -> bool {
    let is_instance = |e: &Expr| matches!(e.kind, ExprKind::Name(_) | ExprKind::Member(..));
    let (ok, expected) = match word {
        Word::Jmp(_) => (matches!(e.kind, ExprKind::Name(_)), "a label name"),
        Word::Cal(_) => {
            if is_instance(e) {
                *e = Expr {
                    span,
                    kind: ExprKind::Call {
                        callee: Box::new(e.clone()),
                        args: Box::default(),
                    },
                };
                (true, "")
            } else {
                let ok = matches!(&e.kind, ExprKind::Call { callee, .. } if is_instance(callee));
                (ok, "a function block instance, with or without arguments")
            }
        }
        Word::FbInput => (is_instance(e), "a function block instance"),
        _ => (true, ""),
    };
    if !ok {
        let d = Diagnostic::error(
            codes::IL_BAD_OPERAND,
            format!("the operand of {what} must be {expected}"),
            e.span,
        )
        .with_label(format!("expected {expected}"));
        p.emit(idx, d);
    }
    ok
}

/// The operands of the instruction whose operator is at token `idx`: none at the end
/// of the line. `None` after an error (reported, line skipped).
fn operands(p: &mut Parser<'_>, idx: usize, allow_call: bool) -> Option<Vec<Expr>> {
    let mut list = Vec::new();
    if at_line_end(p) {
        return Some(list);
    }
    loop {
        match operand(p, allow_call) {
            Some(e) => list.push(e),
            None => {
                skip_line(p, idx);
                return None;
            }
        }
        if !at_line_end(p) && p.at(Tok::Comma) {
            p.bump();
            continue;
        }
        return Some(list);
    }
}

/// One operand: an ST primary with its postfixes, or a signed literal.
fn operand(p: &mut Parser<'_>, allow_call: bool) -> Option<Expr> {
    let t = p.tok();
    if at_line_end(p) {
        let end = p.prev_end();
        let d = Diagnostic::error(
            codes::IL_MISSING_OPERAND,
            "expected an operand after `,`",
            p.sp(end, end),
        )
        .with_label("expected an operand here");
        p.emit(p.pos(), d);
        return None;
    }
    match t.kind {
        Tok::Minus | Tok::Plus => {
            let n = p.token(p.pos() + 1);
            if n.kind != Tok::Lit || n.newline_before() {
                let d = Diagnostic::error(
                    codes::IL_BAD_OPERAND,
                    format!("expected a number after `{}`", p.slice(t)),
                    p.tspan(t),
                )
                .with_label("IL operands are single values, not expressions");
                p.emit(p.pos(), d);
                return None;
            }
            p.bump();
            let e = p.line_operand()?;
            let op = if t.kind == Tok::Minus {
                UnaryOp::Neg
            } else {
                UnaryOp::Plus
            };
            Some(Expr {
                span: p.sp(t.start, e.span.end),
                kind: ExprKind::Unary(op, Box::new(e)),
            })
        }
        Tok::Lit | Tok::True | Tok::False | Tok::Ident | Tok::Address => {
            let at = p.pos();
            let e = p.line_operand()?;
            if !allow_call && matches!(e.kind, ExprKind::Call { .. }) {
                let d =
                    Diagnostic::error(codes::IL_BAD_OPERAND, "a call is not an IL operand", e.span)
                        .with_label("not a single value")
                        .with_note(
                            "call a function by writing its name as the operator, on the current \
                     result: `LD x` then `ABS`, or `LIMIT(MN := 0, IN := x, MX := 9)` alone; \
                     call a function block with CAL",
                        );
                p.emit(at, d);
                return None;
            }
            Some(e)
        }
        Tok::LParen => {
            let d = Diagnostic::error(
                codes::IL_BAD_OPERAND,
                "IL operands are single values: no parenthesised expressions",
                p.tspan(t),
            )
            .with_label("unexpected `(`")
            .with_note("defer an operation with the `(` modifier instead: `AND( b`");
            p.emit(p.pos(), d);
            None
        }
        _ => {
            let msg = format!("expected an operand, found {}", p.describe(p.pos()));
            let d = Diagnostic::error(codes::IL_BAD_OPERAND, msg, p.tspan(t))
                .with_label("expected an operand");
            p.emit(p.pos(), d);
            None
        }
    }
}

/// After an instruction: nothing more on its line.
fn end_of_line(p: &mut Parser<'_>, idx: usize) {
    if at_line_end(p) {
        return;
    }
    let t = p.tok();
    let msg = format!(
        "expected the end of the instruction, found {}",
        p.describe(p.pos())
    );
    let mut d = Diagnostic::error(codes::IL_MALFORMED, msg, p.tspan(t))
        .with_label("one instruction per line");
    d = match t.kind {
        Tok::Semi => d.with_note("IL instructions end with their line, without `;`"),
        Tok::Plus | Tok::Minus | Tok::Star | Tok::Slash | Tok::Amp | Tok::And | Tok::Or => d
            .with_note(
                "IL operands are single values: write each operation as an instruction \
                 (`LD a` then `ADD b`)",
            ),
        _ => d,
    };
    p.emit(p.pos(), d);
    skip_line(p, idx);
}

/// At a line that does not start with an IL instruction.
fn not_an_instruction(p: &mut Parser<'_>, idx: usize) {
    let t = p.tok();
    let next = p.token(idx + 1);
    let st_like = matches!(
        t.kind,
        Tok::If | Tok::Case | Tok::For | Tok::While | Tok::Repeat | Tok::Return | Tok::Exit
    ) || (t.kind == Tok::Ident && next.kind == Tok::Assign);
    let msg = format!("expected an IL instruction, found {}", p.describe(p.pos()));
    let mut d = Diagnostic::error(codes::IL_MALFORMED, msg, p.tspan(t))
        .with_label("expected an operator or a label");
    if st_like {
        d = d.with_note(
            "this body is Instruction List (it starts with an IL instruction): Structured \
             Text statements cannot be mixed into it",
        );
    }
    p.emit(idx, d);
}

/// `name ...` at the start of an instruction, `name` not an IL operator: a function
/// called on the current result, or a formal call `name(...)`.
fn function_call(p: &mut Parser<'_>, idx: usize, name: Ident, out: &mut Vec<Instr>) {
    let start = name.span.start;
    if !at_line_end(p) {
        match p.peek() {
            Tok::LParen => {
                let open = p.bump();
                let Some((args, end)) = p.call_args(open) else {
                    skip_line(p, idx);
                    out.push(invalid(p.span_from(start)));
                    return;
                };
                let span = p.sp(start, end);
                end_of_line(p, idx);
                let call = Expr {
                    kind: ExprKind::Call {
                        callee: Box::new(Expr {
                            kind: ExprKind::Name(name),
                            span: name.span,
                        }),
                        args: args.into(),
                    },
                    span,
                };
                out.push(Instr {
                    op: Op::FormalCall(call),
                    operands: Vec::new(),
                    span,
                    broken: false,
                });
                return;
            }
            Tok::Assign | Tok::Dot | Tok::LBracket | Tok::Caret | Tok::Arrow | Tok::Colon => {
                let mut d = Diagnostic::error(
                    codes::IL_MALFORMED,
                    format!("expected an IL instruction, found {}", p.describe(idx)),
                    name.span,
                )
                .with_label("not an IL operator");
                if p.at(Tok::Assign) {
                    d = d.with_note(
                        "this body is Instruction List (it starts with an IL instruction): \
                         Structured Text statements cannot be mixed into it",
                    );
                }
                p.emit(idx, d);
                skip_line(p, idx);
                out.push(invalid(p.span_from(start)));
                return;
            }
            _ => {}
        }
    }
    let Some(operands) = operands(p, idx, false) else {
        out.push(invalid(p.span_from(start)));
        return;
    };
    let span = p.span_from(start);
    end_of_line(p, idx);
    out.push(Instr {
        op: Op::Func(name),
        operands,
        span,
        broken: false,
    });
}

fn missing_operand(p: &mut Parser<'_>, idx: usize, what: &str, span: Span) {
    let d = Diagnostic::error(
        codes::IL_MISSING_OPERAND,
        format!("{what} needs an operand"),
        span,
    )
    .with_label("expected an operand after this");
    p.emit(idx, d);
}

fn operand_not_allowed(p: &mut Parser<'_>, idx: usize, what: &str, span: Span) {
    let mut d = Diagnostic::error(
        codes::IL_OPERAND_NOT_ALLOWED,
        format!("{what} takes no operand"),
        span,
    )
    .with_label("unexpected operand");
    if what == "`NOT`" {
        d = d.with_note("NOT negates the current result; to load a negated value use LDN");
    }
    p.emit(idx, d);
}

/// Which modifiers `base` takes, for the message about a wrong one.
fn modifier_note(base: &str) -> &'static str {
    match base {
        "LD" | "ST" => "LD and ST take only `N` (LDN, STN)",
        "AND" | "OR" | "XOR" => "AND, OR and XOR take `N` and `(` (ANDN, AND(, ANDN()",
        "JMP" | "CAL" | "RET" => "JMP, CAL and RET take `C` and `CN` (JMPC, JMPCN)",
        "S" | "R" | "NOT" => "S, R and NOT take no modifier",
        _ => "arithmetic and comparison operators take only `(` (ADD(, GT()",
    }
}
