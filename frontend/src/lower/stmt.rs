//! Statements.

use super::body::{Access, BodyCx, LoopTargets};
use super::consts::ConstVal;
use crate::ast::{self, Expr, ExprKind, Stmt, StmtKind, VarKind};
use crate::codes;
use crate::print::TempType;
use crate::types::Ty;
use plcc_ir::diag::Span;
use plcc_ir::{BinaryOp, IntCC, Type, Value};

impl<'s> BodyCx<'_, 's> {
    /// A C pragma where a statement stands: kept for the `c` target (with the
    /// instance as `data__`, as matiec gives it), else skipped with W0010.
    fn inline_c(&mut self, code: &str, span: Span) {
        let agg = self.l.ir[self.pou.0 as usize].agg;
        let why = match (self.l.inline_c, self.self_ptr, agg) {
            (true, Some(this), Some(agg)) => {
                self.b.inline_c(code, agg, this);
                return;
            }
            (true, ..) => "only a PROGRAM's or FUNCTION_BLOCK's body keeps C code (matiec's `data__` is their instance)",
            (false, ..) => "only the `c` target copies C code into its output",
        };
        self.l.diags.push(crate::st::pragma::skipped_c(
            span.file, span.start, span.end, why,
        ));
    }

    /// Lowers a statement list.
    pub(super) fn stmts(&mut self, stmts: &'s [Stmt]) {
        for s in stmts {
            self.stmt(s);
        }
    }

    fn stmt(&mut self, s: &'s Stmt) {
        self.set_span(s.span);
        match &s.kind {
            StmtKind::Assign { target, value } => self.assign(target, value),
            StmtKind::RefAssign { target, value } => self.ref_assign(target, value, s.span),
            StmtKind::Call(e) => self.call_stmt(e),
            StmtKind::If {
                branches,
                else_body,
            } => self.if_stmt(branches, else_body.as_deref()),
            StmtKind::Case {
                selector,
                arms,
                else_body,
            } => self.case_stmt(selector, arms, else_body.as_deref()),
            StmtKind::For {
                var,
                from,
                to,
                by,
                body,
            } => self.for_stmt(*var, from, to, by.as_deref(), body, s.span),
            StmtKind::While { cond, body } => {
                let header = self.b.create_block();
                let body_b = self.b.create_block();
                let exit = self.b.create_block();
                self.b.jump(header, vec![]);
                self.b.switch_to(header);
                let c = self.cond(cond, "WHILE");
                self.b.brif(c, body_b, vec![], exit, vec![]);
                self.b.switch_to(body_b);
                self.loops.push(LoopTargets { exit, cont: header });
                self.stmts(body);
                self.loops.pop();
                self.b.jump(header, vec![]);
                self.b.switch_to(exit);
            }
            StmtKind::Repeat { body, until } => {
                let body_b = self.b.create_block();
                let test = self.b.create_block();
                let exit = self.b.create_block();
                self.b.jump(body_b, vec![]);
                self.b.switch_to(body_b);
                self.loops.push(LoopTargets { exit, cont: test });
                self.stmts(body);
                self.loops.pop();
                self.b.jump(test, vec![]);
                self.b.switch_to(test);
                self.set_span(until.span);
                let c = self.cond(until, "UNTIL");
                self.b.brif(c, exit, vec![], body_b, vec![]);
                self.b.switch_to(exit);
            }
            StmtKind::Exit | StmtKind::Continue => {
                let exit = matches!(s.kind, StmtKind::Exit);
                match self.loops.last() {
                    Some(t) => {
                        let dest = if exit { t.exit } else { t.cont };
                        self.b.jump(dest, vec![]);
                    }
                    None => {
                        let w = if exit { "EXIT" } else { "CONTINUE" };
                        self.l.error(
                            codes::E_OUTSIDE_LOOP,
                            format!("{w} outside of a FOR, WHILE or REPEAT loop"),
                            s.span,
                        );
                    }
                }
            }
            StmtKind::Return => match self.ret_block {
                Some(rb) => self.b.jump(rb, vec![]),
                None => self.b.ret(None),
            },
            StmtKind::Empty => {}
            StmtKind::InlineC(code) => self.inline_c(code, s.span),
            StmtKind::Label(id) => {
                if let Some(&(b, _)) = self.labels.get(&id.sym) {
                    self.b.jump(b, vec![]);
                    self.b.switch_to(b);
                }
            }
            StmtKind::Goto(id) => match self.labels.get(&id.sym) {
                Some(&(b, _)) => self.b.jump(b, vec![]),
                None => {
                    let n = self.l.text(id.span).to_string();
                    self.l.error(
                        codes::E_UNKNOWN_LABEL,
                        format!("there is no label `{n}` in this body: the jump goes nowhere"),
                        id.span,
                    );
                }
            },
            StmtKind::Let { name, value } => {
                // IL keeps a call whose current result is dropped, even one that gives
                // no value: the call is made, and only reading its value is an error.
                if let Some(p) = self.void_call(value) {
                    self.call_stmt(value);
                    self.void_temps.insert(name.sym, (p, false));
                    self.l
                        .temp_types
                        .insert((name.span.file, name.sym), TempType::Void);
                    return;
                }
                let v = self.emit(value, None);
                if matches!(v.ty, Ty::Struct(_) | Ty::Array(_) | Ty::Fb(_)) {
                    let t = self.l.ty_name(v.ty);
                    self.l.error(
                        codes::E_UNSUPPORTED,
                        format!("not supported yet: a whole {t} as the current result"),
                        value.span,
                    );
                }
                // A temporary whose value had an error stays known (as an error), so
                // its uses report nothing more.
                let t = v.ty.ir().unwrap_or(plcc_ir::Type::I32);
                let ty = if v.ty.ir().is_some() { v.ty } else { Ty::Error };
                if ty != Ty::Error {
                    let name_of_type = temp_type_name(self.l, ty, t);
                    self.l
                        .temp_types
                        .insert((name.span.file, name.sym), TempType::Value(name_of_type));
                }
                let slot = self.b.slot(
                    self.l.sym_name(name.sym).to_string(),
                    plcc_ir::MemType::Scalar(t),
                );
                if ty != Ty::Error {
                    let addr = self.b.slot_addr(slot);
                    self.b.store(v.v, addr);
                }
                self.temps.insert(name.sym, (slot, ty));
            }
        }
    }

    /// A BOOL condition of the statement `what` (`IF`, `WHILE`, ...).
    pub(super) fn cond(&mut self, e: &'s Expr, what: &str) -> Value {
        // An instruction's test is reported at the instruction, in its words.
        let (e, span, tested_by) = match &e.kind {
            ExprKind::UsedBy { instr, value } => (&**value, e.span, Some(&**instr)),
            _ => (e, e.span, None),
        };
        let t = self.infer(e);
        if t != Ty::BOOL && t != Ty::Error {
            let v = self.emit(e, Some(Ty::BOOL));
            if v.ty == Ty::BOOL || v.ty == Ty::Error {
                return self.coerce(v, Ty::BOOL, e.span);
            }
            // A literal is named as such (`an integer literal`), not by the type
            // it was given.
            let found = self.l.ty_name(if t.is_literal() { t } else { v.ty });
            let (message, note) = match tested_by {
                Some(op) => (
                    format!("`{op}` tests the current result, which must be BOOL; it is {found}"),
                    "compare it first, e.g. `NE 0`",
                ),
                None => (
                    format!("the {what} condition must be BOOL, found {found}"),
                    "compare the value, e.g. `x <> 0`",
                ),
            };
            let mut d = plcc_ir::diag::Diagnostic::error(codes::E_TYPE_MISMATCH, message, span);
            if v.ty.is_numeric() {
                d = d.with_note(note);
            }
            self.l.diags.push(d);
            return self.zero(Ty::BOOL);
        }
        self.emit_as(e, Ty::BOOL)
    }

    fn assign(&mut self, target: &'s Expr, value: &'s Expr) {
        if let ExprKind::Partial(base, size, n) = &target.kind {
            self.partial_write(target, base, *size, *n, value);
            return;
        }
        // A FUNCTION's name outside the FUNCTION: the result cannot be assigned there.
        if let ExprKind::Name(id) = &target.kind {
            let is_local = self.l.pou(self.pou).var(id.sym).is_some()
                || (self.l.pou(self.pou).name.sym == id.sym);
            if !is_local {
                if let Some(&p) = self.l.pou_by_name.get(&id.sym) {
                    if self.l.pou(p).kind == crate::ast::PouKind::Function {
                        let n = self.l.text(id.span).to_string();
                        self.l.error(
                            codes::E_NOT_A_PLACE,
                            format!(
                                "`{n}` is a FUNCTION: its result can only be assigned inside `{n}`"
                            ),
                            id.span,
                        );
                        let _ = self.emit(value, None);
                        return;
                    }
                }
            }
        }
        if let Some(p) = self.property_of(target) {
            self.property_write(p, value, target.span);
            return;
        }
        let Some(place) = self.place(target) else {
            // Still check the value for errors of its own.
            self.check_only(value);
            return;
        };
        if place.access == Access::OtherOutput {
            if let Some(d) = self.output_write_error(target, "assign to") {
                self.l.diags.push(d);
                self.check_only(value);
                return;
            }
        }
        if !self.check_writable(&place, target.span) {
            self.check_only(value);
            return;
        }
        match place.ty {
            Ty::Elem(_) | Ty::Enum(..) => {
                self.check_range(place.tag, value);
                let v = self.emit_as(value, place.ty);
                self.store_place(&place, v);
            }
            Ty::Struct(_) | Ty::Array(_) => self.assign_aggregate(&place, value, target.span),
            Ty::Str(_) => self.assign_string(&place, value),
            Ty::Ref(_) => {
                let v = self.emit_ref(value, place.ty);
                self.store_place(&place, v);
            }
            Ty::Error => self.check_only(value),
            _ => {
                let what = self.l.ty_name(place.ty);
                let vt = self.infer(value);
                if vt == place.ty {
                    self.l.error(
                        codes::E_UNSUPPORTED,
                        format!("not supported yet: assigning a whole {what}"),
                        target.span,
                    );
                } else if vt != Ty::Error {
                    let found = self.l.ty_name(vt);
                    self.l.error(
                        codes::E_TYPE_MISMATCH,
                        format!("expected {what}, found {found}"),
                        value.span,
                    );
                }
            }
        }
    }

    /// Checks an expression whose value is not used (its target had an error):
    /// reports its own errors, but not those its context caused (a lone literal of an
    /// unsupported type for a variable of an unsupported type, say).
    fn check_only(&mut self, value: &'s Expr) {
        let mut e = value;
        while let ExprKind::Paren(i) = &e.kind {
            e = i;
        }
        if !matches!(e.kind, ExprKind::Literal(_)) {
            let _ = self.emit(value, None);
        }
    }

    /// Reports a write to something that may not be written; true if it may.
    /// The error for writing `target` (an assignment, or a call of an instance) where
    /// it is, or is inside, an output of another instance: E0503 naming that output.
    pub(super) fn output_write_error(
        &mut self,
        target: &Expr,
        what: &str,
    ) -> Option<plcc_ir::diag::Diagnostic> {
        let mut e = target;
        let (base, name, p) = loop {
            match &e.kind {
                ExprKind::Member(base, name) => {
                    if let Ty::Fb(p) = self.infer(base) {
                        let pou = self.l.pou(p);
                        let output = pou
                            .var(name.sym)
                            .is_some_and(|vi| pou.vars[vi as usize].section == VarKind::Output);
                        if output {
                            break (base, name, p);
                        }
                    }
                    e = base;
                }
                ExprKind::Index(base, _) | ExprKind::Bit(base, _) | ExprKind::Paren(base) => {
                    e = base
                }
                _ => return None,
            }
        };
        let fb = self.l.pou(p).display.clone();
        let (n, inst) = (
            self.l.text(name.span).to_string(),
            self.l.text(base.span).to_string(),
        );
        let msg = if std::ptr::eq(e, target) {
            format!("cannot {what} `{n}`: it is an output of the {fb} instance `{inst}`")
        } else {
            let whole = self.l.text(target.span).to_string();
            format!("cannot {what} `{whole}`: `{n}` is an output of the {fb} instance `{inst}`")
        };
        Some(
            plcc_ir::diag::Diagnostic::error(codes::E_WRITE_OUTPUT, msg, target.span)
                .with_note("an instance writes its own outputs; outside code can only read them"),
        )
    }

    pub(super) fn check_writable(&mut self, place: &super::body::Place, span: Span) -> bool {
        let (code, msg) = match place.access {
            Access::ReadWrite => return true,
            Access::OwnInput => {
                // Common practice (matiec, CODESYS) allows it; but the value the
                // caller set on the instance is lost until its next call: warn.
                self.l.diags.push(
                    plcc_ir::diag::Diagnostic::warning(
                        codes::W_WRITE_INPUT,
                        "assignment to an input (VAR_INPUT) of this instance",
                        span,
                    )
                    .with_note("the caller's value is overwritten; a local copy in VAR is clearer"),
                );
                return true;
            }
            Access::OtherOutput => (
                codes::E_WRITE_OUTPUT,
                "cannot assign to an output of a function block instance from outside",
            ),
            Access::Constant => (codes::E_WRITE_CONSTANT, "this is a CONSTANT"),
            Access::Internal => {
                let t = self.l.text(span).to_string();
                self.l.diags.push(
                    plcc_ir::diag::Diagnostic::error(
                        codes::E_WRITE_INTERNAL,
                        format!(
                            "cannot write `{t}`: outside its instance, an internal variable (VAR) and what it holds are read-only"
                        ),
                        span,
                    )
                    .with_note("CODESYS lets code outside an instance read its internal variables, not write them"),
                );
                return false;
            }
        };
        self.l.error(code, msg, span);
        false
    }

    fn if_stmt(&mut self, branches: &'s [(Expr, Vec<Stmt>)], else_body: Option<&'s [Stmt]>) {
        let join = self.b.create_block();
        for (k, (cond, body)) in branches.iter().enumerate() {
            self.set_span(cond.span);
            let c = self.cond(cond, if k == 0 { "IF" } else { "ELSIF" });
            let then_b = self.b.create_block();
            let next = self.b.create_block();
            self.b.brif(c, then_b, vec![], next, vec![]);
            self.b.switch_to(then_b);
            self.stmts(body);
            self.b.jump(join, vec![]);
            self.b.switch_to(next);
        }
        if let Some(e) = else_body {
            self.stmts(e);
        }
        self.b.jump(join, vec![]);
        self.b.switch_to(join);
    }

    /// True for a variable of this POU itself (not a global, which a call could
    /// change behind the body's back).
    fn is_own_variable(&self, sym: crate::intern::Symbol) -> bool {
        let p = self.l.pou(self.pou);
        p.var(sym)
            .is_some_and(|vi| p.vars[vi as usize].section != crate::ast::VarKind::External)
    }

    /// `FOR v := from TO to BY by DO body END_FOR`. The end and step are evaluated
    /// once. The loop stops when the control variable passes the end, and also when
    /// the next step would overflow the variable's type (so `FOR i := 0 TO 32767` on an
    /// INT terminates); after the loop the variable holds the first value past the end.
    fn for_stmt(
        &mut self,
        var: ast::Ident,
        from: &'s Expr,
        to: &'s Expr,
        by: Option<&'s Expr>,
        body: &'s [Stmt],
        span: Span,
    ) {
        let var_expr_place = match self.resolve_name(var, true, None) {
            super::body::Named::Place(p) => Some(p),
            super::body::Named::Const(..) => {
                self.l.error(
                    codes::E_WRITE_CONSTANT,
                    "a FOR control variable cannot be a constant",
                    var.span,
                );
                None
            }
            super::body::Named::Error => None,
        };
        let place = var_expr_place.filter(|p| self.check_writable(p, var.span));
        // BYTE, WORD, DWORD and LWORD count like the unsigned integers of their width,
        // as CPDev allows (`FOR i := 2 TO MAX_NUM` with `i : DWORD`); BOOL does not.
        let elem = place.and_then(|p| p.ty.elem().filter(|_| p.ty.is_int_like()));
        if let (Some(p), None) = (place, elem) {
            if p.ty != Ty::Error {
                let t = self.l.ty_name(p.ty);
                self.l.error(
                    codes::E_TYPE_MISMATCH,
                    format!(
                        "a FOR control variable must be an integer \
                         (or BYTE, WORD, DWORD, LWORD), not {t}"
                    ),
                    var.span,
                );
            }
        }
        let (Some(place), Some(e)) = (place, elem) else {
            // Still check the bounds and the body for errors of their own, in code that
            // never runs.
            let _ = self.emit(from, None);
            let _ = self.emit(to, None);
            if let Some(b) = by {
                let _ = self.emit(b, None);
            }
            let dead = self.b.create_block();
            let after = self.b.create_block();
            self.b.jump(after, vec![]);
            self.b.switch_to(dead);
            self.loops.push(LoopTargets {
                exit: after,
                cont: after,
            });
            self.stmts(body);
            self.loops.pop();
            self.b.jump(after, vec![]);
            self.b.switch_to(after);
            return;
        };
        let ty = place.ty;
        let t = e.ir_type();
        let signed = e.is_signed();
        let (lt, ge, gt) = if signed {
            (IntCC::Slt, IntCC::Sge, IntCC::Sgt)
        } else {
            (IntCC::Ult, IntCC::Uge, IntCC::Ugt)
        };
        self.set_span(from.span);
        let start = self.emit_as(from, ty);
        self.store_place(&place, start);
        self.set_span(to.span);
        let end = self.emit_as(to, ty);
        let (step, step_const) = match by {
            Some(b) => {
                self.set_span(b.span);
                let c = match self.l.const_eval(b, self.pou) {
                    Some((ConstVal::Int(v), _)) => Some(v),
                    _ => None,
                };
                if c == Some(0) {
                    self.l.error(
                        codes::E_BAD_FOR,
                        "a FOR loop with step 0 never ends",
                        b.span,
                    );
                }
                match c {
                    // An unsigned variable counts down by the step's size (`BY -1`,
                    // STL's `downto`): the step itself does not fit the type.
                    Some(v) if v < 0 && !signed => match crate::types::int_range(e) {
                        Some((_, hi)) if -v <= hi => (self.b.iconst(t, (-v) as i64), c),
                        _ => (self.emit_as(b, ty), c),
                    },
                    _ => (self.emit_as(b, ty), c),
                }
            }
            None => (self.b.iconst(t, 1), Some(1)),
        };
        let counts_down_unsigned = !signed && step_const.is_some_and(|c| c < 0);
        // With constant bounds and a body that never writes the variable, the body
        // sees only values from..=to: indexes by it need no bounds check.
        let range = match (
            self.l.const_eval(from, self.pou),
            self.l.const_eval(to, self.pou),
            step_const,
        ) {
            (Some((ConstVal::Int(a), _)), Some((ConstVal::Int(z), _)), Some(st))
                if st != 0 && self.is_own_variable(var.sym) && !writes_var(body, var.sym) =>
            {
                Some(if st > 0 { (a, z) } else { (z, a) })
            }
            _ => None,
        };
        let header = self.b.create_block();
        let body_b = self.b.create_block();
        let latch = self.b.create_block();
        let exit = self.b.create_block();
        self.set_span(span);
        self.b.jump(header, vec![]);
        self.b.switch_to(header);
        let i = self.load_place(&place);
        // Counting down only for a negative step (signed types only).
        let going_up = match step_const {
            Some(c) => {
                let up = c >= 0;
                self.b.iconst(Type::I1, up as i64)
            }
            None if signed => {
                let zero = self.b.iconst(t, 0);
                self.b.icmp(ge, step, zero)
            }
            None => self.b.iconst(Type::I1, 1),
        };
        let past_up = self.b.icmp(gt, i, end);
        let past_down = self.b.icmp(lt, i, end);
        let past = self.b.select(going_up, past_up, past_down);
        self.b.brif(past, exit, vec![], body_b, vec![]);
        self.b.switch_to(body_b);
        self.loops.push(LoopTargets { exit, cont: latch });
        if let Some((a, z)) = range {
            self.known_ranges.push((var.sym, a, z));
        }
        self.stmts(body);
        if range.is_some() {
            self.known_ranges.pop();
        }
        self.loops.pop();
        self.b.jump(latch, vec![]);
        self.b.switch_to(latch);
        self.set_span(span);
        let i = self.load_place(&place);
        let next = if counts_down_unsigned {
            self.b.binary(BinaryOp::Isub, i, step)
        } else {
            self.b.binary(BinaryOp::Iadd, i, step)
        };
        self.store_place(&place, next);
        // With a constant end and step the last step cannot overflow when the end is
        // at least one step inside the type's range: no check needed then.
        let end_const = match self.l.const_eval(to, self.pou) {
            Some((ConstVal::Int(v), _)) => Some(v),
            _ => None,
        };
        let safe = match (end_const, step_const, crate::types::int_range(e)) {
            (Some(end), Some(st), Some((lo, hi))) => {
                (st > 0 && end.checked_add(st).is_some_and(|x| x <= hi))
                    || (st < 0 && end.checked_add(st).is_some_and(|x| x >= lo))
            }
            _ => false,
        };
        if safe {
            self.b.jump(header, vec![]);
        } else {
            // Overflow: stepping up gave a smaller value, or down a larger one.
            let wrapped_up = self.b.icmp(lt, next, i);
            let wrapped_down = self.b.icmp(gt, next, i);
            let wrapped = self.b.select(going_up, wrapped_up, wrapped_down);
            self.b.brif(wrapped, exit, vec![], header, vec![]);
        }
        self.b.switch_to(exit);
    }
}

/// True if the statements may write the variable `sym`: assign it (or a bit of it),
/// use it as a FOR variable, or pass it to a call (where it could be a VAR_IN_OUT or
/// an output target). Nothing else can reach a POU's own variables (there are no
/// globals or references yet; when they come, calls must count as writes of them).
fn writes_var(stmts: &[Stmt], sym: crate::intern::Symbol) -> bool {
    fn root_is(e: &Expr, sym: crate::intern::Symbol) -> bool {
        match &e.kind {
            ExprKind::Name(id) => id.sym == sym,
            ExprKind::Paren(x) | ExprKind::Bit(x, _) | ExprKind::Partial(x, _, _) => {
                root_is(x, sym)
            }
            _ => false,
        }
    }
    let mut writes = false;
    crate::visit::each_stmt(stmts, &mut |s| match &s.kind {
        StmtKind::Assign { target, .. } | StmtKind::RefAssign { target, .. } => {
            writes |= root_is(target, sym)
        }
        StmtKind::For { var, .. } => writes |= var.sym == sym,
        _ => {}
    });
    crate::visit::each_expr(stmts, &mut |e| {
        if let ExprKind::Call { args, .. } = &e.kind {
            writes |= args.iter().any(|a| match &a.kind {
                ast::ArgKind::Positional(x) | ast::ArgKind::Input { value: x, .. } => {
                    root_is(x, sym)
                }
                ast::ArgKind::Output { target, .. } => {
                    target.as_ref().is_some_and(|t| root_is(t, sym))
                }
            });
        }
    });
    writes
}

/// The IEC type a compiler temporary holding a value of type `ty` (`ir` in the IR)
/// is declared with when the build is printed as ST: a literal's generic type by
/// the width lowering gave it.
fn temp_type_name(l: &super::Lowerer, ty: Ty, ir: Type) -> String {
    match ty {
        Ty::AnyInt => match ir {
            Type::I8 => "SINT",
            Type::I16 => "INT",
            Type::I64 => "LINT",
            _ => "DINT",
        }
        .to_string(),
        Ty::AnyReal if ir == Type::F32 => "REAL".to_string(),
        Ty::AnyReal => "LREAL".to_string(),
        _ => l.ty_name(ty),
    }
}
