//! Statements and expressions of PLC-UD STL (the parser's methods for them).

use super::*;

impl Parser<'_> {
    // ---------------------------------------------------------------- statements

    /// Statements up to `end`, `until`, the end of file or a declaration keyword that
    /// cannot be inside a body. `begin ... end` blocks are flattened into `out`.
    pub(super) fn stmt_list(&mut self, out: &mut Vec<Stmt>) {
        loop {
            if self.bailed {
                return;
            }
            let before = self.pos;
            match self.peek() {
                Tok::End
                | Tok::Until
                | Tok::Eof
                | Tok::Function
                | Tok::Procedure
                | Tok::Program
                | Tok::EndVar
                | Tok::Uses => return,
                Tok::Pragma => {
                    let d = Diagnostic::error(
                        codes::STL_DECLARATION_ORDER,
                        "`pragma` among the statements",
                        self.tspan(self.tok()),
                    )
                    .with_label("must come before `program`")
                    .with_note("`pragma` lines and `uses` come first, before `program NAME;`");
                    self.emit(self.pos, d);
                    self.bump();
                }
                Tok::Else => {
                    let d = Diagnostic::error(
                        codes::STL_UNEXPECTED_TOKEN,
                        "`else` without `if`",
                        self.tspan(self.tok()),
                    )
                    .with_label("no `if ... then` statement before this")
                    .with_note(
                        "`then` is followed by one statement; group several with \
                         `begin ... end`",
                    );
                    self.emit(self.pos, d);
                    self.bump();
                }
                Tok::Var | Tok::Constant => self.local_decl(),
                _ => self.stmt(out),
            }
            if self.pos == before {
                // Every path consumes something; this keeps it true for any input.
                self.bump();
            }
        }
    }

    /// One statement (a `begin ... end` block gives its statements).
    pub(super) fn stmt(&mut self, out: &mut Vec<Stmt>) {
        // A stray `;` (after `end_var;` say) is not a statement that declarations
        // must precede.
        self.order.stmt_seen |= !self.at(Tok::Semi);
        if !self.enter() {
            return;
        }
        match self.peek() {
            Tok::Begin => self.block_stmt(out),
            Tok::If => self.if_stmt(out),
            Tok::While => self.while_stmt(out),
            Tok::Repeat => self.repeat_stmt(out),
            Tok::For => self.for_stmt(out),
            Tok::Ident(_) => self.simple_stmt(out),
            Tok::Semi => {
                let t = self.bump();
                out.push(Stmt {
                    kind: StmtKind::Empty,
                    span: self.tspan(t),
                });
            }
            _ => {
                self.expected("a statement");
                self.recover_stmt();
            }
        }
        self.leave();
    }

    /// `begin stmts end`, its optional `;` after.
    pub(super) fn block_stmt(&mut self, out: &mut Vec<Stmt>) {
        let kw = self.bump();
        self.stmt_list(out);
        if self.at(Tok::End) && self.peek_at(1) != Tok::Dot {
            self.bump();
            self.eat(Tok::Semi);
        } else if self.at(Tok::End) {
            // `end.` closes the main body only; a nested block meeting it is not
            // closed (and the main body will find its `end.`).
            let d = Diagnostic::error(
                codes::STL_UNCLOSED_BLOCK,
                "a `begin` is not closed before the `end.` of the main body",
                self.tspan(self.tok()),
            )
            .with_label("`end.` closes the main body only")
            .with_secondary(self.tspan(kw), "this `begin` has no `end`");
            self.emit(self.pos, d);
        } else {
            self.unclosed("`end`", kw, "this `begin` is not closed");
        }
    }

    /// The single statement after `then`, `else`, `do`, as a list.
    pub(super) fn sub_stmt(&mut self) -> Vec<Stmt> {
        let mut v = Vec::new();
        match self.peek() {
            // Nothing where a statement must be: `if c then else ...`, `do end`.
            k if is_closer(k) || is_section_keyword(k) => self.expected("a statement"),
            _ => self.stmt(&mut v),
        }
        v
    }

    pub(super) fn if_stmt(&mut self, out: &mut Vec<Stmt>) {
        let kw = self.bump();
        let cond = self.expr();
        if cond.is_some() {
            self.expect_kw(Tok::Then, "`then`");
        } else {
            self.recover_to(Tok::Then);
        }
        let then_body = self.sub_stmt();
        let else_body = if self.eat(Tok::Else) {
            Some(self.sub_stmt())
        } else {
            None
        };
        let Some(cond) = cond else { return };
        let span = self.span_from(kw.start);
        let mut branches = vec![(cond, then_body)];
        // `else if` chains become ELSIF branches, as ST writes them.
        let else_body = match else_body {
            Some(mut v) if v.len() == 1 && matches!(v[0].kind, StmtKind::If { .. }) => {
                match v.pop().map(|s| s.kind) {
                    Some(StmtKind::If {
                        branches: b,
                        else_body,
                    }) => {
                        branches.extend(b);
                        else_body
                    }
                    _ => None,
                }
            }
            other => other,
        };
        out.push(Stmt {
            kind: StmtKind::If {
                branches,
                else_body,
            },
            span,
        });
    }

    pub(super) fn while_stmt(&mut self, out: &mut Vec<Stmt>) {
        let kw = self.bump();
        let cond = self.expr();
        if cond.is_some() {
            self.expect_kw(Tok::Do, "`do`");
        } else {
            self.recover_to(Tok::Do);
        }
        let body = self.sub_stmt();
        if let Some(cond) = cond {
            let span = self.span_from(kw.start);
            out.push(Stmt {
                kind: StmtKind::While { cond, body },
                span,
            });
        }
    }

    pub(super) fn repeat_stmt(&mut self, out: &mut Vec<Stmt>) {
        let kw = self.bump();
        let mut body = Vec::new();
        self.stmt_list(&mut body);
        if !self.at(Tok::Until) {
            self.unclosed("`until`", kw, "this `repeat` has no `until`");
            return;
        }
        self.bump();
        let Some(until) = self.expr() else {
            self.recover_stmt();
            return;
        };
        let span = self.span_from(kw.start);
        self.expect_semi();
        out.push(Stmt {
            kind: StmtKind::Repeat { body, until },
            span,
        });
    }

    /// `for i := a to b do S` / `for i := a downto b do S` (a step of -1).
    pub(super) fn for_stmt(&mut self, out: &mut Vec<Stmt>) {
        let kw = self.bump();
        let header = self.for_header();
        if header.is_none() {
            self.recover_to(Tok::Do);
        }
        let body = self.sub_stmt();
        if let Some((var, from, to, by)) = header {
            let span = self.span_from(kw.start);
            out.push(Stmt {
                kind: StmtKind::For {
                    var,
                    from: Box::new(from),
                    to: Box::new(to),
                    by: by.map(Box::new),
                    body,
                },
                span,
            });
        }
    }

    pub(super) fn for_header(&mut self) -> Option<(Ident, Expr, Expr, Option<Expr>)> {
        let var = self.expect_ident("the control variable")?;
        if !self.eat(Tok::Assign) {
            self.expected("`:=`");
            return None;
        }
        let from = self.expr()?;
        let by = match self.peek() {
            Tok::To => {
                self.bump();
                None
            }
            Tok::Downto => {
                let t = self.bump();
                Some(Expr {
                    kind: ExprKind::Literal(Box::new(Literal {
                        kind: LiteralKind::Int(-1),
                        type_prefix: None,
                    })),
                    span: self.tspan(t),
                })
            }
            _ => {
                self.expected("`to` or `downto`");
                return None;
            }
        };
        let to = self.expr()?;
        self.expect_kw(Tok::Do, "`do`");
        Some((var, from, to, by))
    }

    /// An assignment `x := e;`, a procedure call `p(a, b);` or `p;`.
    pub(super) fn simple_stmt(&mut self, out: &mut Vec<Stmt>) {
        let t = self.bump();
        let name = self.ident(t);
        let target = Expr {
            kind: ExprKind::Name(name),
            span: name.span,
        };
        match self.peek() {
            Tok::Assign => {
                self.bump();
                self.assignment(target, out);
            }
            Tok::Colon if self.peek_at(1) == Tok::Eq => {
                let c = self.tok();
                let e = self.toks[self.pos + 1];
                let d = Diagnostic::error(
                    codes::STL_ASSIGN_WITHOUT_COLON,
                    "`: =` is not the assignment operator: write `:=` without a space",
                    self.sp(c.start, e.end),
                )
                .with_label("write `:=`");
                self.emit(self.pos, d);
                self.bump();
                self.bump();
                // Checked like an assignment, but not kept: the file has an error.
                self.assignment(target, &mut Vec::new());
            }
            Tok::Eq => {
                let d = Diagnostic::error(
                    codes::STL_ASSIGN_WITHOUT_COLON,
                    "use `:=` to assign; `=` compares",
                    self.tspan(self.tok()),
                )
                .with_label("expected `:=`")
                .with_note(format!(
                    "`{} = ...` alone is a comparison, not a statement",
                    self.slice(t)
                ));
                self.emit(self.pos, d);
                self.bump();
                self.assignment(target, &mut Vec::new());
            }
            Tok::LParen => {
                let Some(call) = self.call(target) else {
                    self.recover_stmt();
                    return;
                };
                if self.at(Tok::Assign) {
                    self.error_here(
                        codes::STL_UNEXPECTED_TOKEN,
                        "a call cannot be assigned".into(),
                        "expected `;`",
                    );
                    self.recover_stmt();
                    return;
                }
                let span = call.span;
                self.expect_semi();
                out.push(self.call_stmt(call, span));
            }
            Tok::Semi | Tok::Else => {
                // A procedure without arguments may be called without parentheses.
                let span = target.span;
                let call = Expr {
                    kind: ExprKind::Call {
                        callee: Box::new(target),
                        args: Box::default(),
                    },
                    span,
                };
                self.expect_semi();
                out.push(Stmt {
                    kind: StmtKind::Call(call),
                    span,
                });
            }
            _ => {
                let msg = format!(
                    "expected `:=` or `(` after `{}`, found {}",
                    self.slice(t),
                    self.describe()
                );
                let d = Diagnostic::error(codes::STL_UNEXPECTED_TOKEN, msg, self.tspan(self.tok()))
                    .with_label("expected `:=` (an assignment) or `(` (a procedure call)");
                self.emit(self.pos, d);
                self.recover_stmt();
            }
        }
    }

    /// After `target :=`: the value and the `;`.
    pub(super) fn assignment(&mut self, target: Expr, out: &mut Vec<Stmt>) {
        let Some(value) = self.expr() else {
            self.recover_stmt();
            return;
        };
        let span = target.span.to(value.span);
        self.expect_semi();
        out.push(Stmt {
            kind: StmtKind::Assign { target, value },
            span,
        });
    }

    /// A call used as a statement. `INC(x);`, `DEC(x);`, `SWAP(x);`, `SET(x, n);` and
    /// `CLR(x, n);` update their variable in place (`x := INC(x)`), as the PLC-UD
    /// quadruple `INC x x` does and as Pascal's `inc(x)` does; a result that is thrown
    /// away would make them useless as statements.
    pub(super) fn call_stmt(&self, call: Expr, span: Span) -> Stmt {
        if let ExprKind::Call { callee, args } = &call.kind {
            let internal = match &callee.kind {
                ExprKind::Name(n) => self.syms.stl_ops.iter().any(|&(_, i)| i == n.sym),
                _ => false,
            };
            if internal {
                if let Some(ArgKind::Positional(first)) = args.first().map(|a| &a.kind) {
                    if let ExprKind::Name(_) = first.kind {
                        return Stmt {
                            kind: StmtKind::Assign {
                                target: first.clone(),
                                value: call,
                            },
                            span,
                        };
                    }
                }
            }
        }
        Stmt {
            kind: StmtKind::Call(call),
            span,
        }
    }

    // ---------------------------------------------------------------- expressions
    //
    // The functions on the recursion path (expr_bp, prefix, primary, call) keep small
    // frames, so that a debug build needs a few KiB of stack per nesting level.

    pub(super) fn expr(&mut self) -> Option<Expr> {
        self.expr_bp(0)
    }

    /// Precedence climbing; binary operators are left-associative, except the
    /// comparisons, which do not chain.
    pub(super) fn expr_bp(&mut self, min: u8) -> Option<Expr> {
        if !self.enter() {
            return None;
        }
        let saved = self.height;
        let mut lhs = self.prefix(min);
        while let Some(l) = lhs.take() {
            let Some((op, bp)) = binop(self.peek()) else {
                lhs = Some(l);
                break;
            };
            if bp < min {
                lhs = Some(l);
                break;
            }
            self.bump();
            if !self.grow() {
                break;
            }
            let Some(r) = self.expr_bp(bp + 1) else {
                break;
            };
            if bp == CMP_BP && is_comparison(self.peek()) {
                let msg = format!(
                    "comparisons do not chain: `{}` after a comparison",
                    self.slice(self.tok())
                );
                let d =
                    Diagnostic::error(codes::STL_CHAINED_COMPARISON, msg, self.tspan(self.tok()))
                        .with_label("second comparison")
                        .with_note("combine comparisons with `and`/`or`: `a < b and b < c`");
                self.emit(self.pos, d);
            }
            lhs = Some(binary(op, l, r));
        }
        self.height = saved;
        self.leave();
        lhs
    }

    /// `not`, `-`, `+`, or a primary. At the start of a condition `not` covers a whole
    /// comparison; at the start of an expression a sign covers the first term; after
    /// another operator, either applies to one factor.
    pub(super) fn prefix(&mut self, min: u8) -> Option<Expr> {
        let (op, bp) = match self.peek() {
            Tok::Not => (UnaryOp::Not, if min <= NOT_BP { NOT_BP } else { FACTOR_BP }),
            Tok::Minus => (UnaryOp::Neg, if min <= ADD_BP { MUL_BP } else { FACTOR_BP }),
            Tok::Plus => (
                UnaryOp::Plus,
                if min <= ADD_BP { MUL_BP } else { FACTOR_BP },
            ),
            _ => return self.primary(),
        };
        let t = self.bump();
        let e = self.expr_bp(bp)?;
        let span = self.sp(t.start, e.span.end);
        Some(Expr {
            kind: ExprKind::Unary(op, Box::new(e)),
            span,
        })
    }

    pub(super) fn primary(&mut self) -> Option<Expr> {
        let t = self.tok();
        let file = self.file;
        let lit = move |kind| {
            Some(Expr {
                kind: ExprKind::Literal(Box::new(Literal {
                    kind,
                    type_prefix: None,
                })),
                span: Span::new(file, t.start, t.end),
            })
        };
        match t.kind {
            Tok::Int(v) => {
                self.bump();
                lit(LiteralKind::Int(v))
            }
            Tok::Real => {
                self.bump();
                let text: String = self.slice(t).chars().filter(|&c| c != '_').collect();
                lit(LiteralKind::Real(text.into()))
            }
            Tok::True | Tok::False => {
                self.bump();
                lit(LiteralKind::Bool(t.kind == Tok::True))
            }
            Tok::Ident(_) => {
                self.bump();
                let name = self.ident(t);
                let e = Expr {
                    kind: ExprKind::Name(name),
                    span: name.span,
                };
                if self.at(Tok::LParen) {
                    self.call(e)
                } else {
                    Some(e)
                }
            }
            Tok::LParen => {
                self.bump();
                let inner = self.expr()?;
                if !self.at(Tok::RParen) {
                    let msg = format!("expected `)`, found {}", self.describe());
                    let d =
                        Diagnostic::error(codes::STL_UNEXPECTED_TOKEN, msg, self.tspan(self.tok()))
                            .with_label("expected `)`")
                            .with_secondary(self.tspan(t), "this `(` is not closed");
                    self.emit(self.pos, d);
                    return None;
                }
                let close = self.bump();
                Some(Expr {
                    kind: ExprKind::Paren(Box::new(inner)),
                    span: self.sp(t.start, close.end),
                })
            }
            _ => {
                self.expected("an expression");
                None
            }
        }
    }

    /// `callee(a, b, ...)` at the `(`: arguments are positional. The STL standard
    /// operations INC, DEC, SWAP, SET, CLR call their internal builtins, and SHL, SHR,
    /// ROL, ROR with one argument shift by one bit.
    pub(super) fn call(&mut self, callee: Expr) -> Option<Expr> {
        let open = self.bump();
        let mut args = Vec::new();
        if !self.eat(Tok::RParen) {
            loop {
                let a = self.expr()?;
                args.push(Arg {
                    span: a.span,
                    kind: ArgKind::Positional(a),
                });
                if self.eat(Tok::Comma) {
                    continue;
                }
                if self.at(Tok::RParen) {
                    self.bump();
                    break;
                }
                let msg = format!("expected `,` or `)`, found {}", self.describe());
                let mut d =
                    Diagnostic::error(codes::STL_UNEXPECTED_TOKEN, msg, self.tspan(self.tok()))
                        .with_label("expected `,` or `)`")
                        .with_secondary(self.tspan(open), "the arguments start here");
                if self.at(Tok::Assign) {
                    d = d.with_note("STL passes arguments by position: `f(a, b)`");
                }
                self.emit(self.pos, d);
                return None;
            }
        }
        let span = self.sp(callee.span.start, self.prev_end());
        let mut callee = callee;
        if let ExprKind::Name(n) = &mut callee.kind {
            if let Some(&(_, internal)) = self.syms.stl_ops.iter().find(|(s, _)| *s == n.sym) {
                n.sym = internal;
            } else if self.syms.shifts.contains(&n.sym) && args.len() == 1 {
                let one = Expr {
                    kind: ExprKind::Literal(Box::new(Literal {
                        kind: LiteralKind::Int(1),
                        type_prefix: None,
                    })),
                    span: self.sp(span.end, span.end),
                };
                args.push(Arg {
                    span: one.span,
                    kind: ArgKind::Positional(one),
                });
            }
        }
        Some(Expr {
            kind: ExprKind::Call {
                callee: Box::new(callee),
                args: args.into(),
            },
            span,
        })
    }
}
