//! Statements.

use super::{Printer, Style, TempType};
use crate::ast::*;

impl Printer<'_> {
    /// Statements, each on a line of its own at the current depth.
    pub(super) fn statements(&mut self, stmts: &[Stmt]) {
        for s in stmts {
            self.statement(s);
        }
    }

    /// `stmts` one level deeper.
    pub(super) fn block(&mut self, stmts: &[Stmt]) {
        self.depth += 1;
        self.statements(stmts);
        self.depth -= 1;
    }

    /// A compound statement's closing keyword, after the comments before it.
    fn close(&mut self, s: &Stmt, keyword: &str) {
        self.depth += 1;
        let closer = s.span.end.saturating_sub(keyword.len() as u32 - 1);
        self.comments_before(s.span.file, closer);
        self.depth -= 1;
        self.line();
        self.push(keyword);
    }

    fn statement(&mut self, s: &Stmt) {
        self.comments_before(s.span.file, s.span.start);
        if self.style == Style::Tree && self.depth == 0 && !self.out.is_empty() {
            self.push("\n");
        }
        self.line();
        match &s.kind {
            StmtKind::Assign { target, value } => {
                self.expression(target, 0);
                self.push(" := ");
                self.expression(value, 0);
                self.push(";");
            }
            StmtKind::RefAssign { target, value } => {
                self.expression(target, 0);
                self.push(" REF= ");
                self.expression(value, 0);
                self.push(";");
            }
            StmtKind::Call(e) => {
                self.expression(e, 0);
                self.push(";");
            }
            StmtKind::If {
                branches,
                else_body,
            } => {
                for (k, (cond, body)) in branches.iter().enumerate() {
                    if k > 0 {
                        self.line();
                    }
                    self.push(if k == 0 { "IF " } else { "ELSIF " });
                    self.expression(cond, 0);
                    self.push(" THEN");
                    self.end_line();
                    self.block(body);
                }
                if let Some(e) = else_body {
                    self.line();
                    self.push("ELSE");
                    self.end_line();
                    self.block(e);
                }
                self.close(s, "END_IF;");
            }
            StmtKind::Case {
                selector,
                arms,
                else_body,
            } => {
                self.push("CASE ");
                self.expression(selector, 0);
                self.push(" OF");
                self.end_line();
                self.depth += 1;
                for arm in arms {
                    self.line();
                    for (k, l) in arm.labels.iter().enumerate() {
                        if k > 0 {
                            self.push(", ");
                        }
                        match l {
                            CaseLabel::Value(v) => self.expression(v, 0),
                            CaseLabel::Range(lo, hi) => {
                                self.expression(lo, 0);
                                self.push("..");
                                self.expression(hi, 0);
                            }
                        }
                    }
                    self.push(":");
                    self.end_line();
                    self.block(&arm.body);
                }
                if let Some(e) = else_body {
                    self.line();
                    self.push("ELSE");
                    self.end_line();
                    self.block(e);
                }
                self.depth -= 1;
                self.close(s, "END_CASE;");
            }
            StmtKind::For {
                var,
                from,
                to,
                by,
                body,
            } => {
                self.push("FOR ");
                self.push_name(var);
                self.push(" := ");
                self.expression(from, 0);
                self.push(" TO ");
                self.expression(to, 0);
                if let Some(by) = by {
                    self.push(" BY ");
                    self.expression(by, 0);
                }
                self.push(" DO");
                self.end_line();
                self.block(body);
                self.close(s, "END_FOR;");
            }
            StmtKind::While { cond, body } => {
                self.push("WHILE ");
                self.expression(cond, 0);
                self.push(" DO");
                self.end_line();
                self.block(body);
                self.close(s, "END_WHILE;");
            }
            StmtKind::Repeat { body, until } => {
                self.push("REPEAT");
                self.end_line();
                self.block(body);
                self.line();
                self.push("UNTIL ");
                self.expression(until, 0);
                self.end_line();
                self.line();
                self.push("END_REPEAT;");
            }
            StmtKind::Exit => self.push("EXIT;"),
            StmtKind::Continue => self.push("CONTINUE;"),
            StmtKind::Return => self.push("RETURN;"),
            StmtKind::Empty => self.push(";"),
            // The tree holds the pragma without one brace on each side.
            StmtKind::InlineC(c) => {
                self.push("{");
                self.push(c);
                self.push("}");
            }
            StmtKind::Label(id) => {
                self.push_name(id);
                self.push(":");
            }
            StmtKind::Goto(id) => {
                self.push("JMP ");
                self.push_name(id);
                self.push(";");
            }
            StmtKind::Let { name, value } => {
                let void = self
                    .temps
                    .and_then(|t| t.get(&(name.span.file, name.sym)))
                    .is_some_and(|t| *t == TempType::Void);
                if !void {
                    self.push_name(name);
                    self.push(" := ");
                }
                self.expression(value, 0);
                self.push(";");
            }
        }
        self.trailing_comment(s.span.file, s.span.end);
        self.end_line();
    }
}
