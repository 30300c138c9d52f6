//! Statements and expressions of Structured Text bodies: the parser's methods for
//! them, and the helpers that build their syntax trees.

use super::*;

impl<'a> Parser<'a> {
    // ---------------------------------------------------------------- statements

    /// Statements until a token in `stop`, a section keyword, or a closer that an
    /// enclosing construct is waiting for. `compound`: inside IF/CASE/loops, where a
    /// foreign END_ ends the list (the construct reports it). `case_arm`: also stop
    /// at the next CASE label.
    pub(super) fn stmt_list(&mut self, stop: &[Tok], compound: bool, case_arm: bool) -> Vec<Stmt> {
        let base = self.stmts.len();
        loop {
            self.c_pragma_statements();
            let t = self.peek();
            if stop.contains(&t) || is_section_stop(t) {
                break;
            }
            if let Some(ci) = closer_idx(t) {
                if self.open[ci] > 0 || (compound && is_end_closer(t)) {
                    break;
                }
                self.stray_closer();
                continue;
            }
            if t == Tok::Ident && self.member_at().is_some() {
                break;
            }
            if case_arm && self.at_case_label() {
                break;
            }
            let before = self.pos;
            self.stmt();
            if self.pos == before {
                self.bump();
            }
        }
        self.stmts.drain(base..).collect()
    }

    /// The C pragmas before the current token: those between it and the token before
    /// it stand where a statement may stand and become [`StmtKind::InlineC`]; earlier
    /// ones (inside a statement, among declarations) are skipped with warning W0010.
    fn c_pragma_statements(&mut self) {
        let pragmas = &self.lexed.c_pragmas;
        let here = self.tok().start;
        let gap_start = match self.pos {
            0 => 0,
            p => self.token(p - 1).end,
        };
        while let Some(&(s, e)) = pragmas.get(self.c_next) {
            if s >= here {
                break;
            }
            self.c_next += 1;
            if s >= gap_start {
                let code = crate::st::pragma::c_code(&self.text[s as usize..e as usize]);
                let span = Span::new(self.file, s, e);
                push(&mut self.stmts, StmtKind::InlineC(code.into()), span);
            } else {
                self.diags.push(crate::st::pragma::skipped_c(
                    self.file,
                    s,
                    e,
                    "it does not stand where a statement may stand",
                ));
            }
        }
    }

    /// An END_IF, ELSE, UNTIL... that no open construct accepts.
    pub(super) fn stray_closer(&mut self) {
        let t = self.tok();
        let msg = format!(
            "unexpected {}: no {} is open",
            self.describe(self.pos),
            opener_of(t.kind)
        );
        self.error_here(codes::UNMATCHED_END, msg, "nothing to close here");
        self.bump();
        match t.kind {
            Tok::Elsif => self.recover_to(Tok::Then),
            Tok::Until => self.recover_to(Tok::EndRepeat),
            _ => {}
        }
    }

    /// Looks ahead for `label, label..label :` (not `:=`).
    pub(super) fn at_case_label(&self) -> bool {
        match self.peek() {
            Tok::Lit | Tok::Minus | Tok::Plus | Tok::True | Tok::False => return true,
            Tok::Ident => {}
            _ => return false,
        }
        let mut i = self.pos;
        loop {
            match self.toks.get(i).map_or(Tok::Eof, |t| t.kind) {
                Tok::Ident
                | Tok::Lit
                | Tok::Dot
                | Tok::Hash
                | Tok::Minus
                | Tok::Plus
                | Tok::Comma
                | Tok::DotDot => i += 1,
                Tok::Colon => return true,
                _ => return false,
            }
        }
    }

    // Statements are pushed onto `out` by the function that parses them, rather than
    // returned through every level of the recursion (a Stmt is 300 bytes, and debug
    // builds keep a copy of it in every frame it passes through).

    /// One statement onto `out` (nothing if it is broken).
    pub(super) fn stmt(&mut self) {
        let t = self.tok();
        match t.kind {
            Tok::Semi => {
                self.bump();
                let span = self.sp(t.start, t.start);
                push(&mut self.stmts, StmtKind::Empty, span);
            }
            Tok::If | Tok::Case | Tok::For | Tok::While | Tok::Repeat => self.compound_stmt(t),
            Tok::Exit | Tok::Continue | Tok::Return => self.jump_stmt(t),
            // CODESYS's `JMP label;` and `label:` (the PLCopen front end writes them
            // for jumps and labels of diagrams).
            Tok::Ident
                if self.at_sym(0, self.s.jmp)
                    && self.peek_at(1) == Tok::Ident
                    && self.peek_at(2) == Tok::Semi =>
            {
                self.bump();
                let l = self.tok();
                self.bump();
                self.bump();
                let label = Ident {
                    sym: Symbol(l.data),
                    span: self.tspan(l),
                };
                let span = self.span_from(t.start);
                push(&mut self.stmts, StmtKind::Goto(label), span);
            }
            Tok::Ident if self.peek_at(1) == Tok::Colon => {
                self.bump();
                self.bump();
                let label = Ident {
                    sym: Symbol(t.data),
                    span: self.tspan(t),
                };
                let span = self.tspan(t);
                push(&mut self.stmts, StmtKind::Label(label), span);
            }
            Tok::Ident | Tok::Address => self.simple_stmt(),
            _ => {
                self.expected("a statement");
                self.recover_stmt();
            }
        }
    }

    pub(super) fn compound_stmt(&mut self, t: Token) {
        if !self.enter() {
            self.skip_balanced_stmt();
            return;
        }
        match t.kind {
            Tok::If => self.if_stmt(),
            Tok::Case => self.case_stmt(),
            Tok::For => self.for_stmt(),
            Tok::While => self.while_stmt(),
            _ => self.repeat_stmt(),
        }
        self.leave();
        // IEC wants `END_IF;`, but CODESYS and RuSTy accept `END_IF` alone, and code
        // written for them leaves the `;` out.
        self.eat(Tok::Semi);
    }

    pub(super) fn jump_stmt(&mut self, t: Token) {
        self.bump();
        let kind = match t.kind {
            Tok::Exit => StmtKind::Exit,
            Tok::Continue => StmtKind::Continue,
            _ => StmtKind::Return,
        };
        self.expect_semi();
        let span = self.tspan(t);
        push(&mut self.stmts, kind, span);
    }

    /// Assignment, reference assignment or call.
    pub(super) fn simple_stmt(&mut self) {
        if let Some(s) = self.simple_stmt_inner() {
            self.stmts.push(s);
        }
    }

    pub(super) fn simple_stmt_inner(&mut self) -> Option<Stmt> {
        let Some(target) = self.postfix() else {
            self.recover_stmt();
            return None;
        };
        let start = target.span.start;
        let kind = if self.at(Tok::Assign) {
            self.bump();
            let Some(value) = self.expr() else {
                self.recover_stmt();
                return None;
            };
            StmtKind::Assign { target, value }
        } else if self.at_sym(0, self.s.ref_) && self.peek_at(1) == Tok::Eq {
            self.bump();
            self.bump();
            let Some(value) = self.expr() else {
                self.recover_stmt();
                return None;
            };
            StmtKind::RefAssign { target, value }
        } else if matches!(target.kind, ExprKind::Call { .. }) {
            StmtKind::Call(target)
        } else if self.unmatched_closer() {
            self.recover_stmt();
            return None;
        } else {
            let found = self.describe(self.pos);
            let d = Diagnostic::error(
                codes::NOT_A_STATEMENT,
                format!("expected `:=` or a call, found {found}"),
                self.tspan(self.tok()),
            )
            .with_label("expected `:=`");
            let d = if self.at(Tok::Eq) {
                d.with_note("`=` compares two values; assignment is written `:=`")
            } else {
                d.with_secondary(target.span, "this is not a statement on its own")
            };
            self.emit(self.pos, d);
            self.recover_stmt();
            return None;
        };
        let span = self.span_from(start);
        self.expect_semi();
        Some(Stmt { kind, span })
    }

    pub(super) fn if_stmt(&mut self) {
        let kw = self.bump();
        self.open_add(&[Tok::Elsif, Tok::Else, Tok::EndIf], 1);
        let mut ok = true;
        let mut branches = Vec::with_capacity(1);
        loop {
            let cond = self.expr();
            if cond.is_some() {
                self.expect_kw(Tok::Then);
            } else {
                ok = false;
                self.recover_to(Tok::Then);
            }
            let body = self.stmt_list(&[Tok::Elsif, Tok::Else, Tok::EndIf], true, false);
            if let Some(c) = cond {
                branches.push((c, body));
            }
            if !self.eat(Tok::Elsif) {
                break;
            }
        }
        self.open_add(&[Tok::Elsif, Tok::Else], -1);
        // `ELSE IF` opens a nested IF, which needs an END_IF of its own.
        let mut else_if = None;
        let else_body = if self.at(Tok::Else) {
            let e = self.bump();
            if self.at(Tok::If) {
                else_if = Some(self.sp(e.start, self.tok().end));
            }
            Some(self.stmt_list(&[Tok::EndIf], true, false))
        } else {
            None
        };
        self.open_add(&[Tok::EndIf], -1);
        let hint = else_if.map(|s| (s, "this opens a nested IF: did you mean `ELSIF`?"));
        self.expect_end_hint(Tok::EndIf, kw, hint);
        if ok {
            let span = self.span_from(kw.start);
            branches.shrink_to_fit();
            push_if(&mut self.stmts, branches, else_body, span);
        }
    }

    pub(super) fn case_stmt(&mut self) {
        let kw = self.bump();
        self.open_add(&[Tok::Else, Tok::EndCase], 1);
        let mut ok = true;
        let selector = self.expr();
        if selector.is_some() {
            self.expect_kw(Tok::Of);
        } else {
            ok = false;
            self.recover_to(Tok::Of);
        }
        let mut arms = Vec::new();
        let mut else_body = None;
        let mut else_open = true;
        loop {
            let t = self.peek();
            if t == Tok::Else {
                self.bump();
                self.open_add(&[Tok::Else], -1);
                else_open = false;
                else_body = Some(self.stmt_list(&[Tok::EndCase], true, false));
                break;
            }
            if closer_idx(t).is_some() || is_section_stop(t) {
                break;
            }
            if t == Tok::Semi {
                self.bump();
                continue;
            }
            let before = self.pos;
            let labels = self.case_labels();
            let body = self.stmt_list(&[Tok::Else, Tok::EndCase], true, true);
            match labels {
                Some((labels, span)) => arms.push(CaseArm { labels, body, span }),
                None => ok = false,
            }
            if self.pos == before {
                self.bump();
            }
        }
        if else_open {
            self.open_add(&[Tok::Else], -1);
        }
        self.open_add(&[Tok::EndCase], -1);
        self.expect_end(Tok::EndCase, kw);
        if ok {
            let span = self.span_from(kw.start);
            arms.shrink_to_fit();
            push_case(&mut self.stmts, selector, arms, else_body, span);
        }
    }

    pub(super) fn case_labels(&mut self) -> Option<(Vec<CaseLabel>, Span)> {
        let r = self.case_labels_inner();
        if r.is_none() {
            while !self.at(Tok::Colon) && !self.at_sync() {
                self.bump();
            }
            self.eat(Tok::Colon);
        }
        r
    }

    pub(super) fn case_labels_inner(&mut self) -> Option<(Vec<CaseLabel>, Span)> {
        let start = self.tok().start;
        let mut labels = Vec::with_capacity(1);
        loop {
            let lo = self.expr()?;
            if self.eat(Tok::DotDot) {
                let hi = self.expr()?;
                labels.push(CaseLabel::Range(lo, hi));
            } else {
                labels.push(CaseLabel::Value(lo));
            }
            if !self.eat(Tok::Comma) {
                break;
            }
        }
        self.expect_tok(Tok::Colon, "`:`, `,` or `..` after a CASE label")?;
        labels.shrink_to_fit();
        Some((labels, self.span_from(start)))
    }

    pub(super) fn for_stmt(&mut self) {
        let kw = self.bump();
        self.open_add(&[Tok::EndFor], 1);
        let header = self.for_header();
        if header.is_none() {
            self.recover_to(Tok::Do);
        }
        let body = self.stmt_list(&[Tok::EndFor], true, false);
        self.open_add(&[Tok::EndFor], -1);
        self.expect_end(Tok::EndFor, kw);
        if let Some(h) = header {
            let span = self.span_from(kw.start);
            push_for(&mut self.stmts, *h, body, span);
        }
    }

    /// `v := from TO to [BY by] DO` (boxed: it is large and lives across the body).
    pub(super) fn for_header(&mut self) -> Option<Box<ForHeader>> {
        let var = self.expect_ident("the control variable")?;
        self.expect_tok(Tok::Assign, "`:=`")?;
        let from = self.expr()?;
        self.expect_tok(Tok::To, "`TO`")?;
        let to = self.expr()?;
        let by = if self.eat(Tok::By) {
            Some(self.expr()?)
        } else {
            None
        };
        self.expect_kw(Tok::Do);
        Some(Box::new(ForHeader { var, from, to, by }))
    }

    pub(super) fn while_stmt(&mut self) {
        let kw = self.bump();
        self.open_add(&[Tok::EndWhile], 1);
        let cond = self.expr();
        if cond.is_some() {
            self.expect_kw(Tok::Do);
        } else {
            self.recover_to(Tok::Do);
        }
        let body = self.stmt_list(&[Tok::EndWhile], true, false);
        self.open_add(&[Tok::EndWhile], -1);
        self.expect_end(Tok::EndWhile, kw);
        if let Some(cond) = cond {
            let span = self.span_from(kw.start);
            push_while(&mut self.stmts, cond, body, span);
        }
    }

    pub(super) fn repeat_stmt(&mut self) {
        let kw = self.bump();
        self.open_add(&[Tok::Until, Tok::EndRepeat], 1);
        let body = self.stmt_list(&[Tok::Until], true, false);
        self.open_add(&[Tok::Until], -1);
        let until = if self.eat(Tok::Until) {
            let c = self.expr();
            if c.is_none() {
                while !self.at(Tok::EndRepeat) && !self.at_sync() {
                    self.bump();
                }
            }
            c
        } else {
            let msg = format!("expected `UNTIL`, found {}", self.describe(self.pos));
            let d = Diagnostic::error(codes::UNCLOSED_BLOCK, msg, self.tspan(self.tok()))
                .with_label("expected `UNTIL`")
                .with_secondary(self.tspan(kw), "this `REPEAT` has no `UNTIL`");
            self.emit(self.pos, d);
            None
        };
        self.open_add(&[Tok::EndRepeat], -1);
        self.expect_end(Tok::EndRepeat, kw);
        if let Some(until) = until {
            let span = self.span_from(kw.start);
            push_repeat(&mut self.stmts, body, until, span);
        }
    }

    // ---------------------------------------------------------------- expressions
    //
    // The functions on the recursion path (expr_bp, unary, postfix, primary,
    // paren_expr, call_suffix, index_suffix, arg) keep small frames: the building of
    // nodes is done in separate functions, so that a debug build needs a few KiB of
    // stack per nesting level, not tens.

    pub(super) fn expr(&mut self) -> Option<Expr> {
        self.expr_bp(0)
    }

    /// Precedence climbing; every binary operator is left-associative (`**` too, as
    /// in IEC 61131-3 ed. 3).
    pub(super) fn expr_bp(&mut self, min: u8) -> Option<Expr> {
        let saved = self.height;
        let mut lhs = self.unary();
        while lhs.is_some() {
            let Some((op, bp)) = binop(self.peek()) else {
                break;
            };
            if bp < min {
                break;
            }
            self.bump();
            if !self.grow() {
                lhs = None;
                break;
            }
            let rhs = self.expr_bp(bp + 1);
            lhs = binary(op, lhs, rhs);
        }
        self.height = saved;
        lhs
    }

    /// Prefix `-`, `+`, `NOT`: they bind tighter than every binary operator, so
    /// `-2**2` is `(-2)**2` and `NOT a AND b` is `(NOT a) AND b`.
    pub(super) fn unary(&mut self) -> Option<Expr> {
        let op = match self.peek() {
            Tok::Minus => UnaryOp::Neg,
            Tok::Plus => UnaryOp::Plus,
            Tok::Not => UnaryOp::Not,
            _ => return self.postfix(),
        };
        // Too deep: the error points at the operator itself.
        if !self.enter() {
            return None;
        }
        let start = self.bump().start;
        let e = self.unary();
        self.leave();
        unary(op, start, e, self.file)
    }

    /// An IL operand: a primary and its postfixes, which must be on the same line as
    /// what precedes them (an IL instruction ends with its line; inside brackets and
    /// call arguments line breaks are free).
    pub(crate) fn line_operand(&mut self) -> Option<Expr> {
        let saved = self.line_postfix.replace(self.depth);
        let e = self.postfix();
        self.line_postfix = saved;
        e
    }

    pub(super) fn postfix(&mut self) -> Option<Expr> {
        let saved = self.height;
        let e = self.postfix_chain();
        self.height = saved;
        e
    }

    /// A primary and its postfixes (`height` counts them).
    fn postfix_chain(&mut self) -> Option<Expr> {
        let mut e = self.primary()?;
        loop {
            if self.line_postfix == Some(self.depth) && self.tok().newline_before() {
                return Some(e);
            }
            e = match self.peek() {
                Tok::LParen => self.call_suffix(e)?,
                Tok::LBracket => self.index_suffix(e)?,
                Tok::Dot => {
                    self.bump();
                    if self.line_postfix == Some(self.depth) && self.tok().newline_before() {
                        // An IL operand ends with its line.
                        let what = "a member name or a bit number after `.`";
                        self.missing(codes::UNEXPECTED_TOKEN, what, what);
                        return None;
                    }
                    self.member_access(e)?
                }
                Tok::Caret => self.deref_suffix(e)?,
                _ => return Some(e),
            };
            if !self.grow() {
                return None;
            }
        }
    }

    pub(super) fn deref_suffix(&mut self, base: Expr) -> Option<Expr> {
        self.bump();
        Some(self.wrap(base, Wrap::Deref))
    }

    pub(super) fn call_suffix(&mut self, callee: Expr) -> Option<Expr> {
        if !self.enter() {
            return None;
        }
        let open = self.bump();
        let end = self.call_args(open);
        self.leave();
        let (args, end) = end?;
        Some(call(callee, args, end, self.file))
    }

    pub(super) fn index_suffix(&mut self, base: Expr) -> Option<Expr> {
        if !self.enter() {
            return None;
        }
        self.bump();
        let idx = self.index_list();
        self.leave();
        Some(self.wrap(base, Wrap::Index(idx?)))
    }

    pub(super) fn index_list(&mut self) -> Option<Vec<Expr>> {
        let mut idx = Vec::with_capacity(1);
        loop {
            idx.push(self.expr()?);
            if !self.eat(Tok::Comma) {
                break;
            }
        }
        self.expect_tok(Tok::RBracket, "`,` or `]`")?;
        idx.shrink_to_fit();
        Some(idx)
    }

    /// A postfix node over `base` ending at the last token consumed.
    pub(super) fn wrap(&self, base: Expr, w: Wrap) -> Expr {
        let span = self.span_from(base.span.start);
        let kind = match w {
            Wrap::Deref => ExprKind::Deref(Box::new(base)),
            Wrap::Index(idx) => ExprKind::Index(Box::new(base), idx.into()),
            Wrap::Member(m) => ExprKind::Member(Box::new(base), m),
            Wrap::Bit(b) => ExprKind::Bit(Box::new(base), Box::new(b)),
            Wrap::Partial(size, n) => ExprKind::Partial(Box::new(base), size, n),
        };
        Expr { kind, span }
    }

    /// After `base.`: a member name, a bit number, or `%X3`/`%B1`/`%W0`/`%D0`/`%L0`.
    pub(super) fn member_access(&mut self, base: Expr) -> Option<Expr> {
        let t = self.tok();
        match t.kind {
            Tok::Ident => {
                self.bump();
                let m = self.ident(t);
                Some(self.wrap(base, Wrap::Member(m)))
            }
            Tok::Lit if self.is_plain_int(t) => {
                self.bump();
                let bit = self.literal_expr(t);
                Some(self.wrap(base, Wrap::Bit(bit)))
            }
            Tok::Address => {
                let text = self.slice(t);
                let size = match text.as_bytes().get(1).map(|c| c.to_ascii_uppercase()) {
                    Some(b'X') => Some(1u8),
                    Some(b'B') => Some(8),
                    Some(b'W') => Some(16),
                    Some(b'D') => Some(32),
                    Some(b'L') => Some(64),
                    _ => None,
                };
                let index = text.get(2..).and_then(|d| d.parse::<u32>().ok());
                let (Some(size), Some(index)) = (size, index) else {
                    self.expected(
                        "a member name, a bit number or `%X`, `%B`, `%W`, `%D`, `%L` after `.`",
                    );
                    return None;
                };
                self.bump();
                if size == 1 {
                    let bit = Expr {
                        kind: ExprKind::Literal(Box::new(Literal {
                            kind: LiteralKind::Int(index as i128),
                            type_prefix: None,
                        })),
                        span: self.tspan(t),
                    };
                    Some(self.wrap(base, Wrap::Bit(bit)))
                } else {
                    Some(self.wrap(base, Wrap::Partial(size, index)))
                }
            }
            _ => {
                self.expected("a member name or a bit number after `.`");
                None
            }
        }
    }

    /// After `open`, a `(`: the arguments and the end offset of the `)`.
    pub(crate) fn call_args(&mut self, open: Token) -> Option<(Vec<Arg>, u32)> {
        let base = self.args.len();
        let end = self.call_args_into(open);
        let args = self.args.drain(base..).collect();
        Some((args, end?))
    }

    /// The arguments onto `self.args`.
    pub(super) fn call_args_into(&mut self, open: Token) -> Option<u32> {
        if self.at(Tok::RParen) {
            return Some(self.bump().end);
        }
        loop {
            if !self.arg() {
                return None;
            }
            if self.eat(Tok::Comma) {
                // `f(a := 1, b := 2,)`: CODESYS accepts a comma before the `)`, and
                // its exports have them; plcc does in both dialects.
                if self.at(Tok::RParen) {
                    return Some(self.bump().end);
                }
                continue;
            }
            return Some(self.expect_close(Tok::RParen, "`,` or `)`", open)?.end);
        }
    }

    /// One argument onto `self.args`; false if it is broken.
    pub(super) fn arg(&mut self) -> bool {
        let t = self.tok();
        let (n1, n2) = (self.peek_at(1), self.peek_at(2));
        let (negated, output) = match (t.kind, n1, n2) {
            (Tok::Ident, Tok::Assign, _) => {
                self.bump();
                self.bump();
                let value = self.expr();
                return self.push_arg(t, ArgShape::Input(t), value);
            }
            (Tok::Ident, Tok::Arrow, _) => (false, true),
            (Tok::Not, Tok::Ident, Tok::Arrow) => (true, true),
            _ => (false, false),
        };
        if !output {
            let value = self.expr();
            return self.push_arg(t, ArgShape::Positional, value);
        }
        if negated {
            self.bump();
        }
        let n = self.bump();
        self.bump();
        let target = if matches!(self.peek(), Tok::Comma | Tok::RParen) {
            None
        } else {
            match self.expr() {
                Some(e) => Some(e),
                None => return false,
            }
        };
        self.push_arg(t, ArgShape::Output(n, negated), target)
    }

    /// `first` is the first token of the argument; `value` its value, or the target of
    /// an output. False if a needed value is missing.
    pub(super) fn push_arg(&mut self, first: Token, shape: ArgShape, value: Option<Expr>) -> bool {
        let kind = match shape {
            ArgShape::Output(n, negated) => ArgKind::Output {
                name: self.ident(n),
                negated,
                target: value,
            },
            ArgShape::Input(n) => {
                let Some(value) = value else { return false };
                ArgKind::Input {
                    name: self.ident(n),
                    value,
                }
            }
            ArgShape::Positional => {
                let Some(value) = value else { return false };
                ArgKind::Positional(value)
            }
        };
        let span = self.span_from(first.start);
        self.args.push(Arg { kind, span });
        true
    }

    /// An integer literal without type prefix.
    pub(super) fn is_plain_int(&self, t: Token) -> bool {
        t.kind == Tok::Lit
            && (t.flags & INLINE_INT != 0
                || t.flags & INLINE_REAL == 0
                    && self.lits.get(t.data as usize).is_some_and(|l| {
                        l.type_prefix.is_none() && matches!(l.kind, LiteralKind::Int(_))
                    }))
    }

    /// A literal without type prefix.
    pub(super) fn is_plain_lit(&self, t: Token) -> bool {
        t.kind == Tok::Lit
            && (t.flags & (INLINE_INT | INLINE_REAL) != 0
                || self
                    .lits
                    .get(t.data as usize)
                    .is_some_and(|l| l.type_prefix.is_none()))
    }

    pub(super) fn literal(&self, t: Token) -> Literal {
        self.lexed.literal(self.text, t)
    }

    pub(super) fn literal_expr(&self, t: Token) -> Expr {
        Expr {
            kind: ExprKind::Literal(Box::new(self.literal(t))),
            span: self.tspan(t),
        }
    }

    pub(super) fn primary(&mut self) -> Option<Expr> {
        let t = self.tok();
        match t.kind {
            Tok::LParen => self.paren_expr(t),
            Tok::Address => self.address_expr(t),
            _ => self.atom(t),
        }
    }

    /// Literals and names.
    pub(super) fn atom(&mut self, t: Token) -> Option<Expr> {
        match t.kind {
            Tok::Lit => {
                self.bump();
                Some(self.literal_expr(t))
            }
            Tok::True | Tok::False => {
                self.bump();
                Some(Expr {
                    kind: ExprKind::Literal(Box::new(Literal {
                        kind: LiteralKind::Bool(t.kind == Tok::True),
                        type_prefix: None,
                    })),
                    span: self.tspan(t),
                })
            }
            Tok::Ident => Some(self.name_expr(t)),
            // The standard functions AND(a, b), OR, XOR, MOD.
            Tok::And | Tok::Or | Tok::Xor | Tok::Mod if self.peek_at(1) == Tok::LParen => {
                self.bump();
                let id = Ident {
                    sym: self.interner.intern_upper(t.kind.text()),
                    span: self.tspan(t),
                };
                Some(Expr {
                    kind: ExprKind::Name(id),
                    span: id.span,
                })
            }
            _ => {
                self.expected("an expression");
                None
            }
        }
    }

    pub(super) fn paren_expr(&mut self, open: Token) -> Option<Expr> {
        // Too deep: the error points at this `(`.
        if !self.enter() {
            return None;
        }
        self.bump();
        let inner = self.expr();
        self.leave();
        self.close_paren(open, inner)
    }

    pub(super) fn close_paren(&mut self, open: Token, inner: Option<Expr>) -> Option<Expr> {
        let inner = inner?;
        let close = self.expect_close(Tok::RParen, "`)`", open)?;
        Some(Expr {
            kind: ExprKind::Paren(Box::new(inner)),
            span: self.sp(open.start, close.end),
        })
    }

    /// A name, `Enum#Value`, or a literal typed by a derived type (`MyInt#5`).
    pub(super) fn name_expr(&mut self, t: Token) -> Expr {
        self.bump();
        let id = self.ident(t);
        if self.at(Tok::Hash) {
            let n = self.token(self.pos + 1);
            if n.kind == Tok::Ident {
                self.bump();
                self.bump();
                return Expr {
                    kind: ExprKind::EnumValue {
                        ty: Box::new(id),
                        value: self.ident(n),
                    },
                    span: self.sp(t.start, n.end),
                };
            }
            if self.is_plain_lit(n) {
                self.bump();
                self.bump();
                let mut e = self.literal_expr(n);
                if let ExprKind::Literal(l) = &mut e.kind {
                    l.type_prefix = Some(id);
                }
                e.span = self.sp(t.start, n.end);
                return e;
            }
        }
        Expr {
            kind: ExprKind::Name(id),
            span: id.span,
        }
    }

    pub(super) fn address_expr(&mut self, t: Token) -> Option<Expr> {
        let text = self.slice(t);
        let area = text.as_bytes().get(1).map(|c| c.to_ascii_uppercase());
        if !matches!(area, Some(b'I' | b'Q' | b'M')) {
            let msg = format!(
                "`{text}` selects part of a variable: write it after one, as in `x.{text}`"
            );
            self.error_here(
                codes::UNEXPECTED_TOKEN,
                msg,
                "partial access without a variable",
            );
            return None;
        }
        self.bump();
        Some(Expr {
            kind: ExprKind::DirectAddress(text.into()),
            span: self.tspan(t),
        })
    }
}

/// Appends `more` to `stmts` (taking it whole when `stmts` is empty, the usual case).
pub(super) fn append(stmts: &mut Vec<Stmt>, mut more: Vec<Stmt>) {
    if stmts.is_empty() {
        *stmts = more;
    } else {
        stmts.append(&mut more);
    }
}

/// The header of a FOR statement.
pub(super) struct ForHeader {
    var: Ident,
    from: Expr,
    to: Expr,
    by: Option<Expr>,
}

pub(super) fn push(out: &mut Vec<Stmt>, kind: StmtKind, span: Span) {
    out.push(Stmt { kind, span });
}

#[allow(clippy::type_complexity)]
pub(super) fn push_if(
    out: &mut Vec<Stmt>,
    branches: Vec<(Expr, Vec<Stmt>)>,
    else_body: Option<Vec<Stmt>>,
    span: Span,
) {
    push(
        out,
        StmtKind::If {
            branches,
            else_body,
        },
        span,
    );
}

pub(super) fn push_case(
    out: &mut Vec<Stmt>,
    selector: Option<Expr>,
    arms: Vec<CaseArm>,
    else_body: Option<Vec<Stmt>>,
    span: Span,
) {
    if let Some(selector) = selector {
        push(
            out,
            StmtKind::Case {
                selector,
                arms,
                else_body,
            },
            span,
        );
    }
}

pub(super) fn push_for(out: &mut Vec<Stmt>, h: ForHeader, body: Vec<Stmt>, span: Span) {
    let ForHeader { var, from, to, by } = h;
    push(
        out,
        StmtKind::For {
            var,
            from: Box::new(from),
            to: Box::new(to),
            by: by.map(Box::new),
            body,
        },
        span,
    );
}

pub(super) fn push_while(out: &mut Vec<Stmt>, cond: Expr, body: Vec<Stmt>, span: Span) {
    push(out, StmtKind::While { cond, body }, span);
}

pub(super) fn push_repeat(out: &mut Vec<Stmt>, body: Vec<Stmt>, until: Expr, span: Span) {
    push(out, StmtKind::Repeat { body, until }, span);
}

/// The form of an argument, known before its value is parsed.
pub(super) enum ArgShape {
    Positional,
    /// `name :=`
    Input(Token),
    /// `name =>` / `NOT name =>`
    Output(Token, bool),
}

/// What [`Parser::wrap`] puts around an expression.
pub(super) enum Wrap {
    Deref,
    Index(Vec<Expr>),
    Member(Ident),
    Bit(Expr),
    Partial(u8, u32),
}

pub(super) fn call(callee: Expr, args: Vec<Arg>, end: u32, file: FileId) -> Expr {
    Expr {
        span: Span::new(file, callee.span.start, end),
        kind: ExprKind::Call {
            callee: Box::new(callee),
            args: args.into(),
        },
    }
}

pub(super) fn binary(op: BinaryOp, lhs: Option<Expr>, rhs: Option<Expr>) -> Option<Expr> {
    let (lhs, rhs) = (lhs?, rhs?);
    let span = lhs.span.to(rhs.span);
    Some(Expr {
        kind: ExprKind::Binary(op, Box::new(lhs), Box::new(rhs)),
        span,
    })
}

pub(super) fn unary(op: UnaryOp, start: u32, e: Option<Expr>, file: FileId) -> Option<Expr> {
    let e = e?;
    let span = Span::new(file, start, e.span.end);
    Some(Expr {
        kind: ExprKind::Unary(op, Box::new(e)),
        span,
    })
}
