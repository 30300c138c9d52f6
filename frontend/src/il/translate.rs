//! IL instructions to ST statements: the current result as an expression tree.
//!
//! The current result (CR) is kept as the expression that computes it (the CPDev
//! method): `LD A` makes it `A`, `MUL 4` makes it `A * 4`, `ADD B` makes it
//! `A * 4 + B`, and `ST C` emits the statement `C := A * 4 + B`. So straight-line IL
//! gives the tree ST gives, and everything after parsing serves both languages.
//!
//! Keeping an expression rather than a value delays its evaluation to where the CR is
//! used, which is only sound while nothing changes what it reads and while it is not
//! evaluated twice. Hence the compiler temporaries (`StmtKind::Let`, named `__CR1`,
//! `__CR2`... which no user can write): the CR is evaluated into one ("spilled")
//! - when a statement uses it and it is used again later, unless it is a plain
//!   operand (a literal or a variable, whose reading has no effect) or a constant
//!   expression (a temporary would fix its type: `LD 5 / ADD 3 / ST s / ST l` must
//!   work for a SINT `s` as `s := 5 + 3` does): `LD a / ADD b / ST x / ST y` gives
//!   `__CR1 := a + b; x := __CR1; y := __CR1`;
//! - before an instruction that may change what it reads (a store to a variable it
//!   reads, a call of a function block) when it is used after that instruction: in
//!   `LD x / STN x / ST y`, `y` gets the old `x`;
//! - when it is dropped (by LD, a label, a jump...) without having been used while it
//!   contains a call, so the call's effects still happen;
//! - when its tree grows taller than [`SPILL_HEIGHT`] (a long chain of operations),
//!   so that no later pass recurses too deeply.
//!
//! The deferred operations `op( ... )` keep their left operand on a stack; the same
//! rules apply to it.
//!
//! Where an instruction uses a CR that is undefined (at the start of a body, after a
//! label, which control can reach from anywhere), IL has no meaning to give it; plcc
//! warns (W0701) and uses a neutral value of the operand's type (0, FALSE, T#0s, so
//! that matiec's syntax tests, whose functions start with `ADD 10`, still type-check).
//! Such a CR is "tainted": it is never taken as a FUNCTION's result.

use super::instr::{Cond, Instr, Op};
use crate::ast::*;
use crate::codes;
use crate::intern::{Interner, Symbol};
use plcc_ir::diag::{Diagnostic, FileId, Span};
use rustc_hash::{FxHashMap, FxHashSet};

/// The deepest nesting of deferred operations `op(` accepted (as ST's parentheses).
pub(crate) const MAX_PAREN_DEPTH: usize = crate::st::parser::MAX_DEPTH as usize;

/// The height of the CR's tree above which it is spilled into a temporary. ST's
/// parser accepts trees up to `MAX_HEIGHT` (1000) high; this stays well below.
pub(crate) const SPILL_HEIGHT: u32 = 256;

/// The kind of an elementary type, as far as a neutral value is concerned.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub(crate) enum Class {
    /// BOOL
    Bool,
    /// Integers and bit strings (BYTE, WORD...)
    Int,
    /// REAL, LREAL
    Real,
    /// TIME (`false`), LTIME (`true`)
    Time(bool),
    /// Dates, times of day, strings, characters.
    Other,
}

/// What the translation knows about the POU from its declarations.
#[derive(Default)]
pub(crate) struct Env {
    /// A FUNCTION with a result type: its name.
    pub result: Option<Ident>,
    /// That name as written, for messages.
    pub result_text: String,
    /// The class of that result type, if elementary.
    pub result_class: Option<Class>,
    /// Variables declared with a named, non-elementary type (possibly FB instances,
    /// for which `S x` and `R x` are input operators).
    pub fb_vars: Vec<Symbol>,
    /// The classes of variables declared with an elementary type.
    pub classes: FxHashMap<Symbol, Class>,
}

/// The current result.
#[derive(Clone, Debug)]
struct Cr {
    /// The expression that computes it.
    e: Expr,
    /// The height of `e`'s tree (over the operands).
    h: u32,
    /// It derives from an undefined CR (W0701): its value means nothing.
    tainted: bool,
    /// A statement evaluated it already, so its effects (calls) have happened.
    consumed: bool,
}

/// A deferred operation `op( ...`, waiting for its `)`.
struct Frame {
    op: BinaryOp,
    neg: bool,
    /// The instruction that opened it.
    span: Span,
    /// Its name as written (`AND`), for messages.
    word: Ident,
    /// The CR before it: the left operand.
    saved: Cr,
}

/// What an instruction may change, apart from the CR.
enum Effect<'e> {
    /// Nothing.
    Pure,
    /// The variable (or element, member...) `target`.
    Write(&'e Expr),
    /// Anything: a function block is called.
    Call,
}

/// Translates the instructions of one body. `temps` numbers the temporaries of the
/// file; diagnostics go to `diags`.
pub(crate) fn translate(
    instrs: &[Instr],
    env: &Env,
    file: FileId,
    interner: &mut Interner,
    temps: &mut u32,
    diags: &mut Vec<Diagnostic>,
) -> Vec<Stmt> {
    let implicit = env.result.is_some_and(|r| !stores_to(instrs, r.sym));
    let used_after = used_after(instrs, implicit);
    let mut t = Tr {
        instrs,
        env,
        file,
        sym_s: interner.intern_upper("S"),
        sym_r: interner.intern_upper("R"),
        sym_pt: interner.intern_upper("PT"),
        sym_pv: interner.intern_upper("PV"),
        interner,
        temps,
        diags,
        out: Vec::new(),
        cr: None,
        quiet: false,
        stack: Vec::new(),
        implicit,
        used_after,
        made: FxHashSet::default(),
        bool_temps: FxHashSet::default(),
        result_warned: false,
        dropped: 0,
        aborted: false,
    };
    t.run();
    t.out
}

struct Tr<'a> {
    instrs: &'a [Instr],
    env: &'a Env,
    file: FileId,
    interner: &'a mut Interner,
    temps: &'a mut u32,
    diags: &'a mut Vec<Diagnostic>,
    out: Vec<Stmt>,
    cr: Option<Cr>,
    /// The CR is undefined because of a broken instruction (reported already), or
    /// in unreachable code: using it gives no warning.
    quiet: bool,
    stack: Vec<Frame>,
    /// The body is a FUNCTION's that never stores its result: the CR is the result.
    implicit: bool,
    /// `used_after[i]`: the CR after instruction `i` is read before it is replaced.
    used_after: Vec<bool>,
    /// The temporaries made in this body.
    made: FxHashSet<Symbol>,
    /// Those that hold a BOOL for sure.
    bool_temps: FxHashSet<Symbol>,
    /// W0702 was reported in this body.
    result_warned: bool,
    /// Deferred operations dropped at an error (E0709): their `)` are ignored.
    dropped: usize,
    /// Deferred operations are nested too deeply (E0707): translation stopped.
    aborted: bool,
    sym_s: Symbol,
    sym_r: Symbol,
    sym_pt: Symbol,
    sym_pv: Symbol,
}

/// How an instruction treats the CR, for [`used_after`].
enum CrUse {
    Reads,
    Replaces,
    Keeps,
}

fn cr_use(ins: &Instr, implicit: bool) -> CrUse {
    if ins.broken {
        return match ins.op {
            Op::Bin { paren: true, .. } => CrUse::Reads,
            Op::St { .. } | Op::Set | Op::Reset | Op::Cal(_) | Op::FbInput(_) | Op::Jmp(_) => {
                CrUse::Keeps
            }
            _ => CrUse::Replaces,
        };
    }
    match &ins.op {
        Op::Ld { .. } | Op::Label(_) | Op::Jmp(Cond::Always) | Op::FormalCall(_) | Op::Invalid => {
            CrUse::Replaces
        }
        Op::Ret(Cond::Always) if implicit => CrUse::Reads,
        Op::Ret(Cond::Always) => CrUse::Replaces,
        Op::Cal(Cond::Always) => CrUse::Keeps,
        _ => CrUse::Reads,
    }
}

/// For every instruction, whether the CR it leaves is read later (before something
/// replaces it); computed backwards in one pass.
fn used_after(instrs: &[Instr], implicit: bool) -> Vec<bool> {
    let mut v = vec![false; instrs.len()];
    let mut next = implicit; // the end of the body reads the CR of an implicit result
    for i in (0..instrs.len()).rev() {
        v[i] = next;
        next = match cr_use(&instrs[i], implicit) {
            CrUse::Reads => true,
            CrUse::Replaces => false,
            CrUse::Keeps => next,
        };
    }
    v
}

impl Tr<'_> {
    fn run(&mut self) {
        self.body();
        if !self.aborted {
            self.finish();
        }
    }

    /// Translates the instructions in order.
    fn body(&mut self) {
        let instrs = self.instrs;
        for (i, ins) in instrs.iter().enumerate() {
            if self.aborted {
                // Nested too deeply (reported): the rest of the body is not read.
                return;
            }
            if ins.broken {
                self.broken(i);
                continue;
            }
            let span = ins.span;
            match &ins.op {
                Op::Label(id) => {
                    self.discard(i);
                    if !self.stack.is_empty() {
                        self.not_in_parens(i, "a label");
                    }
                    self.push(StmtKind::Label(*id), span);
                    self.cr = None;
                    self.quiet = false;
                }
                Op::Ld { neg } => {
                    self.discard(i);
                    let x = ins.operands[0].clone();
                    let e = if *neg { not(x, span) } else { x };
                    self.cr = Some(fresh(e, 1, false));
                    self.quiet = false;
                }
                Op::St { neg } => self.store(i, *neg),
                Op::Set | Op::Reset => {
                    let set = matches!(ins.op, Op::Set);
                    let target = &ins.operands[0];
                    let instance = match &target.kind {
                        ExprKind::Name(id) => self.env.fb_vars.contains(&id.sym),
                        _ => false,
                    };
                    let not_bool = match &target.kind {
                        ExprKind::Name(id) => self
                            .env
                            .classes
                            .get(&id.sym)
                            .is_some_and(|c| *c != Class::Bool),
                        _ => false,
                    };
                    let word = if set { "S" } else { "R" };
                    if instance {
                        let input = Ident {
                            sym: if set { self.sym_s } else { self.sym_r },
                            span: Span::new(self.file, span.start, span.start + 1),
                        };
                        self.fb_input(i, input, target.clone());
                    } else if not_bool {
                        let verb = if set { "sets" } else { "resets" };
                        self.diags.push(
                            Diagnostic::error(
                                codes::E_TYPE_MISMATCH,
                                format!(
                                    "`{word}` {verb} a BOOL (or an input of a function \
                                     block instance), and this is not a BOOL"
                                ),
                                target.span,
                            )
                            .with_label("not a BOOL"),
                        );
                    } else {
                        self.prepare(i, Effect::Write(target), true);
                        let v = self.value(i, Class::Bool);
                        let c = used_by(word, v, span);
                        let assign = Stmt {
                            kind: StmtKind::Assign {
                                target: target.clone(),
                                value: lit(LiteralKind::Bool(set), span),
                            },
                            span,
                        };
                        self.push_if(c, vec![assign], span);
                    }
                }
                Op::Bin {
                    op,
                    neg,
                    paren,
                    word,
                } => {
                    if *paren {
                        self.open(i, *op, *neg, *word);
                    } else {
                        self.binary(i, *op, *neg, *word);
                    }
                }
                Op::Not => {
                    let c = self.take_or_neutral(i, Class::Bool);
                    let e = not(c.e, span);
                    self.set_cr(
                        i,
                        Cr {
                            e,
                            h: c.h + 1,
                            tainted: c.tainted,
                            consumed: false,
                        },
                    );
                }
                Op::Close => self.close(i),
                Op::Jmp(cond) => {
                    if !self.stack.is_empty() {
                        self.not_in_parens(i, "a jump");
                    }
                    let ExprKind::Name(label) = ins.operands[0].kind else {
                        continue;
                    };
                    let goto = Stmt {
                        kind: StmtKind::Goto(label),
                        span,
                    };
                    if *cond == Cond::Always {
                        self.discard(i);
                        self.out.push(goto);
                        self.cr = None;
                        self.quiet = true;
                    } else {
                        self.prepare(i, Effect::Pure, true);
                        let c = self.condition(i, *cond);
                        self.push_if(c, vec![goto], span);
                    }
                }
                Op::Cal(cond) => {
                    if !self.stack.is_empty() {
                        self.not_in_parens(i, "CAL");
                    }
                    let word = match cond {
                        Cond::Always => "CAL",
                        Cond::IfTrue => "CALC",
                        Cond::IfFalse => "CALCN",
                    };
                    let call = Stmt {
                        kind: StmtKind::Call(used_by(word, ins.operands[0].clone(), span)),
                        span,
                    };
                    if *cond == Cond::Always {
                        self.prepare(i, Effect::Call, false);
                        self.out.push(call);
                    } else {
                        self.prepare(i, Effect::Call, true);
                        let c = self.condition(i, *cond);
                        self.push_if(c, vec![call], span);
                    }
                }
                Op::Ret(cond) => self.ret(i, *cond),
                Op::FbInput(input) => self.fb_input(i, *input, ins.operands[0].clone()),
                Op::Func(name) => {
                    let hint = ins
                        .operands
                        .first()
                        .and_then(|x| self.class_of(x))
                        .unwrap_or(Class::Int);
                    let first = self.take_or_neutral(i, hint);
                    let (h, tainted) = (first.h, first.tainted);
                    let mut args = vec![positional(first.e)];
                    args.extend(ins.operands.iter().cloned().map(positional));
                    let e = call_expr(name_expr(*name), args, span);
                    self.set_cr(
                        i,
                        Cr {
                            e,
                            h: h + 1,
                            tainted,
                            consumed: false,
                        },
                    );
                }
                Op::FormalCall(e) => {
                    self.discard(i);
                    self.cr = Some(fresh(e.clone(), 1, false));
                    self.quiet = false;
                }
                Op::Invalid => {
                    self.cr = None;
                    self.quiet = true;
                }
            }
        }
    }

    // ---------------------------------------------------------------- instructions

    /// A malformed instruction (reported): keep the structure, make the CR unknown.
    fn broken(&mut self, i: usize) {
        let ins = &self.instrs[i];
        match ins.op {
            Op::Bin {
                paren: true,
                op,
                neg,
                word,
            } => {
                self.quiet = true;
                self.open(i, op, neg, word);
                self.quiet = true;
            }
            Op::St { .. } | Op::Set | Op::Reset | Op::Cal(_) | Op::FbInput(_) | Op::Jmp(_) => {}
            _ => {
                self.cr = None;
                self.quiet = true;
            }
        }
    }

    /// ST, STN.
    fn store(&mut self, i: usize, neg: bool) {
        let ins = &self.instrs[i];
        let target = &ins.operands[0];
        if self.cr.is_none() {
            // What would be stored is unknown: store nothing.
            self.undefined(i, "nothing is stored: no value was loaded before this");
            return;
        }
        self.prepare(i, Effect::Write(target), true);
        let v = self.value(i, Class::Other);
        let value = if neg { not(v, ins.span) } else { v };
        self.push(
            StmtKind::Assign {
                target: target.clone(),
                value,
            },
            ins.span,
        );
    }

    /// `op x` (non-deferred): CR := CR op x; several operands give the extensible
    /// function `op(CR, x, y...)`.
    fn binary(&mut self, i: usize, op: BinaryOp, neg: bool, word: Ident) {
        let ins = &self.instrs[i];
        let span = ins.span;
        let hint = self.class_of(&ins.operands[0]).unwrap_or(default_class(op));
        let lhs = self.take_or_neutral(i, hint);
        let operand = |x: &Expr| {
            if neg {
                not(x.clone(), span)
            } else {
                x.clone()
            }
        };
        let e = if ins.operands.len() == 1 {
            binary(op, lhs.e, operand(&ins.operands[0]), span)
        } else {
            let mut args = vec![positional(lhs.e)];
            args.extend(ins.operands.iter().map(|x| positional(operand(x))));
            call_expr(name_expr(word), args, span)
        };
        self.set_cr(
            i,
            Cr {
                e,
                h: lhs.h + 1,
                tainted: lhs.tainted,
                consumed: false,
            },
        );
    }

    /// `op( [x]`: saves the CR and the operation; the CR becomes `x` (or undefined).
    /// Nested too deeply, it reports it and abandons the body.
    fn open(&mut self, i: usize, op: BinaryOp, neg: bool, word: Ident) {
        let ins = &self.instrs[i];
        let span = ins.span;
        if self.stack.len() >= MAX_PAREN_DEPTH {
            self.diags.push(
                Diagnostic::error(
                    codes::IL_NESTING_TOO_DEEP,
                    format!(
                        "deferred operations `op(` nested too deeply (more than {MAX_PAREN_DEPTH} levels)"
                    ),
                    span,
                )
                .with_label("too deep here"),
            );
            self.aborted = true;
            return;
        }
        let hint = ins
            .operands
            .first()
            .and_then(|x| self.class_of(x))
            .unwrap_or(default_class(op));
        let saved = self.take_or_neutral(i, hint);
        self.stack.push(Frame {
            op,
            neg,
            span,
            word,
            saved,
        });
        self.cr = ins.operands.first().map(|x| fresh(x.clone(), 1, false));
        self.quiet = false;
    }

    /// `)`: CR := saved op (CR).
    fn close(&mut self, i: usize) {
        let span = self.instrs[i].span;
        let Some(f) = self.stack.pop() else {
            if self.dropped > 0 {
                // Closes a deferred operation dropped at an error (reported).
                self.dropped -= 1;
                self.cr = None;
                self.quiet = true;
                return;
            }
            self.diags.push(
                Diagnostic::error(
                    codes::IL_UNMATCHED_CLOSE,
                    "`)` without `(`: no deferred operation is open here",
                    span,
                )
                .with_label("closes nothing"),
            );
            return;
        };
        let inner = self.take_or_neutral(i, default_class(f.op));
        let rhs = match inner.e.kind {
            // As ST would write it: `a AND (b OR c)`.
            ExprKind::Binary(..) => Expr {
                span: inner.e.span,
                kind: ExprKind::Paren(Box::new(inner.e)),
            },
            _ => inner.e,
        };
        let rhs = if f.neg { not(rhs, f.span) } else { rhs };
        let e = binary(f.op, f.saved.e, rhs, f.span);
        self.set_cr(
            i,
            Cr {
                e,
                h: f.saved.h.max(inner.h) + 2,
                tainted: f.saved.tainted || inner.tainted,
                consumed: false,
            },
        );
        self.quiet = false;
    }

    /// RET, RETC, RETCN.
    fn ret(&mut self, i: usize, cond: Cond) {
        let span = self.instrs[i].span;
        if !self.stack.is_empty() {
            self.not_in_parens(i, "a return");
        }
        let ret = Stmt {
            kind: StmtKind::Return,
            span,
        };
        if cond == Cond::Always {
            self.store_result(span);
            self.discard(i);
            self.out.push(ret);
            self.cr = None;
            self.quiet = true;
            return;
        }
        // The CR is a condition, a BOOL: it can be the result of a BOOL function only.
        let result = self.env.result.filter(|_| {
            self.implicit
                && self.cr.as_ref().is_some_and(|c| !c.tainted)
                && matches!(self.env.result_class, None | Some(Class::Bool))
        });
        let Some(name) = result else {
            self.prepare(i, Effect::Pure, true);
            let c = self.condition(i, cond);
            self.push_if(c, vec![ret], span);
            return;
        };
        let target = name_expr(Ident {
            sym: name.sym,
            span,
        });
        self.prepare(i, Effect::Write(&target), true);
        // Read twice (the condition and the result).
        if let Some(cr) = self.cr.take() {
            let cr = if duplicable(&cr.e) {
                cr
            } else {
                self.spill(cr, span)
            };
            self.cr = Some(cr);
        }
        let v = self.value(i, Class::Bool);
        let c = if cond == Cond::IfFalse {
            not(v.clone(), span)
        } else {
            v.clone()
        };
        let assign = Stmt {
            kind: StmtKind::Assign { target, value: v },
            span,
        };
        self.push_if(c, vec![assign, ret], span);
    }

    /// `OP inst` (S1, R1, CLK, CU, CD, PV, IN, PT; S and R on an instance):
    /// `inst(OP := CR)`.
    fn fb_input(&mut self, i: usize, input: Ident, instance: Expr) {
        let span = self.instrs[i].span;
        let class = if input.sym == self.sym_pt {
            Class::Time(false)
        } else if input.sym == self.sym_pv {
            Class::Int
        } else {
            Class::Bool
        };
        self.prepare(i, Effect::Call, true);
        let value = self.value(i, class);
        let arg = Arg {
            span,
            kind: ArgKind::Input { name: input, value },
        };
        let call = call_expr(instance, vec![arg], span);
        self.push(StmtKind::Call(call), span);
    }

    /// The end of the body.
    fn finish(&mut self) {
        if let Some(f) = self.stack.last() {
            let word = self.interner.name(f.word.sym).to_string();
            let mut d = Diagnostic::error(
                codes::IL_UNCLOSED_PAREN,
                format!("`{word}(` is not closed: the body ends before its `)`"),
                f.span,
            )
            .with_label("this `(` is not closed");
            match self.stack.len() - 1 {
                0 => {}
                1 => d = d.with_note("the `(` before it is not closed either"),
                n => d = d.with_note(format!("the {n} `(` before it are not closed either")),
            }
            self.diags.push(d);
            return;
        }
        let span = self.instrs.last().map(|l| l.span);
        if let Some(span) = span {
            self.store_result(span);
            self.discard(self.instrs.len() - 1);
        }
    }

    // ---------------------------------------------------------------- the CR

    /// The class of an operand, if it shows: a literal's, a declared variable's.
    fn class_of(&self, x: &Expr) -> Option<Class> {
        match &x.kind {
            ExprKind::Literal(l) => Some(match l.kind {
                LiteralKind::Bool(_) => Class::Bool,
                LiteralKind::Int(_) => Class::Int,
                LiteralKind::Real(_) => Class::Real,
                LiteralKind::Duration { long, .. } => Class::Time(long),
                _ => Class::Other,
            }),
            ExprKind::Unary(_, a) => self.class_of(a),
            ExprKind::Name(id) => self.env.classes.get(&id.sym).copied(),
            _ => None,
        }
    }

    /// Takes the CR to build on it; an undefined one is reported (W0701) and replaced
    /// by a neutral value of `class`.
    fn take_or_neutral(&mut self, i: usize, class: Class) -> Cr {
        match self.cr.take() {
            Some(cr) => cr,
            None => {
                self.undefined(i, "no value was loaded before this");
                let span = self.instrs[i].span;
                Cr {
                    e: neutral(class, span),
                    h: 0,
                    tainted: true,
                    consumed: false,
                }
            }
        }
    }

    /// The CR's value for a statement (it stays the CR); an undefined one is reported
    /// and replaced by a neutral value of `class`.
    fn value(&mut self, i: usize, class: Class) -> Expr {
        if self.cr.is_none() {
            let cr = self.take_or_neutral(i, class);
            self.cr = Some(cr);
        }
        match self.cr.as_mut() {
            Some(cr) => {
                cr.consumed = true;
                cr.e.clone()
            }
            None => neutral(class, self.instrs[i].span),
        }
    }

    /// The condition of a C or CN modifier, marked as tested by instruction `i` (so a
    /// current result that is not BOOL is reported there, as `JMPC`'s error).
    fn condition(&mut self, i: usize, cond: Cond) -> Expr {
        let span = self.instrs[i].span;
        let v = self.value(i, Class::Bool);
        let v = if cond == Cond::IfFalse {
            not(v, span)
        } else {
            v
        };
        let base = match self.instrs[i].op {
            Op::Jmp(_) => "JMP",
            Op::Cal(_) => "CAL",
            _ => "RET",
        };
        let suffix = if cond == Cond::IfFalse { "CN" } else { "C" };
        used_by(&format!("{base}{suffix}"), v, span)
    }

    /// Makes `cr` the CR, spilling it if its tree is too tall.
    fn set_cr(&mut self, i: usize, cr: Cr) {
        let cr = if cr.h > SPILL_HEIGHT {
            self.spill(cr, self.instrs[i].span)
        } else {
            cr
        };
        self.cr = Some(cr);
    }

    /// Evaluates `cr` into a new temporary (`span`: the instruction that needs it).
    fn spill(&mut self, cr: Cr, span: Span) -> Cr {
        *self.temps += 1;
        let sym = self.interner.intern_upper(&format!("__CR{}", self.temps));
        self.made.insert(sym);
        if self.obviously_bool(&cr.e) {
            self.bool_temps.insert(sym);
        }
        let name = Ident {
            sym,
            span: cr.e.span,
        };
        self.push(StmtKind::Let { name, value: cr.e }, span);
        Cr {
            e: name_expr(name),
            h: 0,
            tainted: cr.tainted,
            consumed: true,
        }
    }

    /// Before instruction `i`, which has effect `eff` and reads the CR if `reads`:
    /// spills what would otherwise be evaluated twice or too late.
    fn prepare(&mut self, i: usize, eff: Effect<'_>, reads: bool) {
        let span = self.instrs[i].span;
        for k in 0..self.stack.len() {
            if self.affected(&self.stack[k].saved.e, &eff) {
                let saved = self.stack[k].saved.clone();
                self.stack[k].saved = self.spill(saved, span);
            }
        }
        let Some(cr) = &self.cr else {
            return;
        };
        // A call in a CR that this instruction does not read must still happen before
        // the instruction's own call (IL runs in order), whether or not the CR is
        // used later.
        let pending_call = !reads
            && matches!(eff, Effect::Call)
            && !cr.consumed
            && any(&cr.e, &|e| matches!(e.kind, ExprKind::Call { .. }));
        let need = pending_call
            || self.used_after[i] && ((reads && !duplicable(&cr.e)) || self.affected(&cr.e, &eff));
        if need {
            if let Some(cr) = self.cr.take() {
                let cr = self.spill(cr, span);
                self.cr = Some(cr);
            }
        }
    }

    /// Before the CR is replaced at instruction `i`: a CR that was never used but
    /// contains a call is evaluated anyway, for the call's effects.
    fn discard(&mut self, i: usize) {
        let Some(cr) = self.cr.take() else {
            return;
        };
        if !cr.consumed && any(&cr.e, &|e| matches!(e.kind, ExprKind::Call { .. })) {
            self.spill(cr, self.instrs[i].span);
        }
    }

    /// At RET and at the end of a FUNCTION whose result is the CR: `f := CR`.
    fn store_result(&mut self, span: Span) {
        let (Some(name), true) = (self.env.result, self.implicit) else {
            return;
        };
        let Some(cr) = &self.cr else {
            // The result would be the CR, which has no value here (after a label):
            // the FUNCTION would silently return its result variable's initial value.
            if !self.quiet && !self.result_warned {
                self.result_warned = true;
                let n = &self.env.result_text;
                self.diags.push(
                    Diagnostic::warning(
                        codes::IL_CR_UNDEFINED,
                        "the current result is undefined here",
                        span,
                    )
                    .with_label(format!("FUNCTION `{n}` returns here with no result"))
                    .with_note(format!(
                        "after a label the current result has no value: store the result \
                         with `ST {n}` on every path before it reaches the label"
                    )),
                );
            }
            return;
        };
        if cr.tainted {
            return;
        }
        let mismatch = self.env.result_class.is_some_and(|c| c != Class::Bool);
        if mismatch && self.obviously_bool(&cr.e) {
            if !self.result_warned {
                self.result_warned = true;
                let n = &self.env.result_text;
                self.diags.push(
                    Diagnostic::warning(
                        codes::IL_CR_NOT_RESULT,
                        format!(
                            "the current result is a BOOL, not the result type of FUNCTION \
                             `{n}`: it is not taken as the result"
                        ),
                        cr.e.span,
                    )
                    .with_label("this BOOL is left over")
                    .with_note(format!("store the result explicitly with `ST {n}`")),
                );
            }
            return;
        }
        let target = name_expr(Ident {
            sym: name.sym,
            span,
        });
        let value = cr.e.clone();
        if let Some(cr) = self.cr.as_mut() {
            cr.consumed = true;
        }
        self.push(StmtKind::Assign { target, value }, span);
    }

    // ---------------------------------------------------------------- analyses

    /// True if `e` may read something that `eff` changes.
    fn affected(&self, e: &Expr, eff: &Effect<'_>) -> bool {
        let temp = matches!(&e.kind, ExprKind::Name(id) if self.made.contains(&id.sym));
        match eff {
            Effect::Pure => false,
            _ if temp || is_constant(e) => false,
            Effect::Call => true,
            Effect::Write(target) => match root(target) {
                Some(sym) => any(e, &|x| match &x.kind {
                    ExprKind::Name(id) => id.sym == sym,
                    // Through a call, a pointer or an address anything may be read.
                    ExprKind::Call { .. } | ExprKind::Deref(_) | ExprKind::DirectAddress(_) => true,
                    _ => false,
                }),
                None => true,
            },
        }
    }

    /// True if `e` is a BOOL for sure: a BOOL literal or variable, a comparison, a
    /// logical operation on one of those.
    fn obviously_bool(&self, e: &Expr) -> bool {
        match &e.kind {
            ExprKind::Literal(l) => matches!(l.kind, LiteralKind::Bool(_)),
            ExprKind::Name(id) => {
                self.bool_temps.contains(&id.sym)
                    || self.env.classes.get(&id.sym) == Some(&Class::Bool)
            }
            ExprKind::Binary(op, a, b) => match op {
                BinaryOp::Eq
                | BinaryOp::Ne
                | BinaryOp::Lt
                | BinaryOp::Le
                | BinaryOp::Gt
                | BinaryOp::Ge => true,
                BinaryOp::And | BinaryOp::Or | BinaryOp::Xor => {
                    self.obviously_bool(a) || self.obviously_bool(b)
                }
                _ => false,
            },
            ExprKind::Unary(UnaryOp::Not, a) | ExprKind::Paren(a) => self.obviously_bool(a),
            _ => false,
        }
    }

    // ---------------------------------------------------------------- output

    fn push(&mut self, kind: StmtKind, span: Span) {
        self.out.push(Stmt { kind, span });
    }

    fn push_if(&mut self, cond: Expr, body: Vec<Stmt>, span: Span) {
        self.push(
            StmtKind::If {
                branches: vec![(cond, body)],
                else_body: None,
            },
            span,
        );
    }

    /// W0701 at instruction `i`, unless the CR is undefined for a reason already
    /// reported.
    fn undefined(&mut self, i: usize, label: &str) {
        if self.quiet {
            return;
        }
        let d = Diagnostic::warning(
            codes::IL_CR_UNDEFINED,
            "the current result is undefined here",
            self.instrs[i].span,
        )
        .with_label(label)
        .with_note(
            "at the start of a body and after a label the current result has no value; \
             load one with LD",
        );
        self.diags.push(d);
    }

    /// E0709 at instruction `i` (`what`: a label, a jump...); the open deferred
    /// operations are dropped.
    fn not_in_parens(&mut self, i: usize, what: &str) {
        let span = self.instrs[i].span;
        let mut d = Diagnostic::error(
            codes::IL_NOT_IN_PARENS,
            format!("{what} is not allowed inside `(` ... `)`"),
            span,
        )
        .with_label("inside a deferred operation");
        if let Some(f) = self.stack.last() {
            d = d.with_secondary(f.span, "this `(` is still open");
        }
        self.diags.push(d);
        self.dropped += self.stack.len();
        self.stack.clear();
    }
}

// -------------------------------------------------------------------- helpers

/// The operand class an operation suggests when its operand does not tell.
fn default_class(op: BinaryOp) -> Class {
    match op {
        BinaryOp::And | BinaryOp::Or | BinaryOp::Xor => Class::Bool,
        _ => Class::Int,
    }
}

/// A neutral value of `class` standing for an undefined CR.
fn neutral(class: Class, span: Span) -> Expr {
    let kind = match class {
        Class::Bool => LiteralKind::Bool(false),
        Class::Real => LiteralKind::Real("0.0".into()),
        Class::Time(long) => LiteralKind::Duration { ns: 0, long },
        Class::Int | Class::Other => LiteralKind::Int(0),
    };
    lit(kind, span)
}

fn fresh(e: Expr, h: u32, tainted: bool) -> Cr {
    Cr {
        e,
        h,
        tainted,
        consumed: false,
    }
}

fn lit(kind: LiteralKind, span: Span) -> Expr {
    Expr {
        kind: ExprKind::Literal(Box::new(Literal {
            kind,
            type_prefix: None,
        })),
        span,
    }
}

fn not(e: Expr, span: Span) -> Expr {
    Expr {
        kind: ExprKind::Unary(UnaryOp::Not, Box::new(e)),
        span,
    }
}

fn binary(op: BinaryOp, l: Expr, r: Expr, span: Span) -> Expr {
    Expr {
        kind: ExprKind::Binary(op, Box::new(l), Box::new(r)),
        span,
    }
}

fn name_expr(id: Ident) -> Expr {
    Expr {
        kind: ExprKind::Name(id),
        span: id.span,
    }
}

fn positional(e: Expr) -> Arg {
    Arg {
        span: e.span,
        kind: ArgKind::Positional(e),
    }
}

fn call_expr(callee: Expr, args: Vec<Arg>, span: Span) -> Expr {
    Expr {
        kind: ExprKind::Call {
            callee: Box::new(callee),
            args: args.into(),
        },
        span,
    }
}

/// True if reading `e` has no effect and gives the same value at any point where no
/// store to what it reads happened: literals, variables, members, bits, array
/// elements with constant indexes.
fn is_plain(e: &Expr) -> bool {
    match &e.kind {
        ExprKind::Literal(_)
        | ExprKind::Name(_)
        | ExprKind::EnumValue { .. }
        | ExprKind::DirectAddress(_) => true,
        ExprKind::Unary(UnaryOp::Neg | UnaryOp::Plus, a) => {
            matches!(a.kind, ExprKind::Literal(_))
        }
        ExprKind::Member(b, _) | ExprKind::Partial(b, ..) => is_plain(b),
        ExprKind::Bit(b, n) => is_plain(b) && matches!(n.kind, ExprKind::Literal(_)),
        ExprKind::Index(b, ix) => is_plain(b) && ix.iter().all(is_constant),
        _ => false,
    }
}

/// True if `e` can be written twice instead of being computed once into a
/// temporary: a plain operand, or a constant expression (which, unlike a temporary,
/// takes the type its use needs: `x := 5 + 3` is fine for a SINT `x`).
fn duplicable(e: &Expr) -> bool {
    is_plain(e) || is_constant(e)
}

/// `value` as instruction `instr` (at `span`) uses it.
fn used_by(instr: &str, value: Expr, span: Span) -> Expr {
    Expr {
        kind: ExprKind::UsedBy {
            instr: instr.into(),
            value: Box::new(value),
        },
        span,
    }
}

/// True if `e` is computed from literals alone.
fn is_constant(e: &Expr) -> bool {
    match &e.kind {
        ExprKind::Literal(_) | ExprKind::EnumValue { .. } => true,
        ExprKind::Unary(_, a) | ExprKind::Paren(a) => is_constant(a),
        ExprKind::Binary(_, a, b) => is_constant(a) && is_constant(b),
        _ => false,
    }
}

/// The variable a store target belongs to (`a` of `a.b[3].c`); `None` for a store
/// through a pointer or to an address.
fn root(e: &Expr) -> Option<Symbol> {
    match &e.kind {
        ExprKind::Name(id) => Some(id.sym),
        ExprKind::Member(b, _)
        | ExprKind::Index(b, _)
        | ExprKind::Bit(b, _)
        | ExprKind::Partial(b, ..)
        | ExprKind::Paren(b) => root(b),
        _ => None,
    }
}

/// True if `f` holds for `e` or a part of it.
fn any(e: &Expr, f: &dyn Fn(&Expr) -> bool) -> bool {
    if f(e) {
        return true;
    }
    match &e.kind {
        ExprKind::Literal(_)
        | ExprKind::Name(_)
        | ExprKind::EnumValue { .. }
        | ExprKind::DirectAddress(_) => false,
        ExprKind::Member(b, _)
        | ExprKind::Partial(b, ..)
        | ExprKind::Deref(b)
        | ExprKind::Unary(_, b)
        | ExprKind::Paren(b)
        | ExprKind::UsedBy { value: b, .. } => any(b, f),
        ExprKind::Bit(a, b) | ExprKind::Binary(_, a, b) => any(a, f) || any(b, f),
        ExprKind::Index(b, ix) => any(b, f) || ix.iter().any(|x| any(x, f)),
        ExprKind::Call { callee, args } => {
            any(callee, f)
                || args.iter().any(|a| match &a.kind {
                    ArgKind::Positional(v) | ArgKind::Input { value: v, .. } => any(v, f),
                    ArgKind::Output { target, .. } => target.as_ref().is_some_and(|t| any(t, f)),
                })
        }
    }
}

/// True if some instruction stores to the variable `sym` (a FUNCTION's result): ST,
/// STN, S, R, or an output `=>` of a call.
fn stores_to(instrs: &[Instr], sym: Symbol) -> bool {
    let outputs_to = |e: &Expr| {
        any(e, &|x| {
            match &x.kind {
            ExprKind::Call { args, .. } => args.iter().any(|a| {
                matches!(&a.kind, ArgKind::Output { target: Some(t), .. } if root(t) == Some(sym))
            }),
            _ => false,
        }
        })
    };
    instrs.iter().any(|ins| match &ins.op {
        Op::St { .. } | Op::Set | Op::Reset => ins.operands.first().and_then(root) == Some(sym),
        Op::Cal(_) => ins.operands.first().is_some_and(outputs_to),
        Op::FormalCall(e) => outputs_to(e),
        _ => false,
    })
}
