//! Walking the statements and expressions of a syntax tree.
//!
//! [`Visitor`] (shared references) and [`VisitorMut`] (mutable ones) have one method
//! per kind of node; each defaults to its `walk_` function, which visits the node's
//! children in source order. A visitor overrides the methods of the nodes it cares
//! about and calls the `walk_` function where it wants to go deeper:
//!
//! ```
//! use plcc_frontend::ast::{Expr, ExprKind};
//! use plcc_frontend::visit::{walk_expr, Visitor};
//!
//! /// Counts the names a body reads or writes.
//! struct Names(usize);
//!
//! impl<'a> Visitor<'a> for Names {
//!     fn visit_expr(&mut self, e: &'a Expr) {
//!         if let ExprKind::Name(_) = e.kind {
//!             self.0 += 1;
//!         }
//!         walk_expr(self, e);
//!     }
//! }
//! ```
//!
//! Both traits come from one macro, so they cannot drift apart. For the two common
//! questions there are shortcuts: [`each_stmt`] and [`each_expr`].

use crate::ast::*;

macro_rules! visitor {
    (
        $(#[$doc:meta])*
        trait $Visitor:ident<$a:lifetime>, $($mut_:ident)?;
        $walk_stmts:ident, $walk_stmt:ident, $walk_expr:ident, $walk_arg:ident
    ) => {
        $(#[$doc])*
        pub trait $Visitor<$a> {
            /// A statement (nested ones come through here too).
            fn visit_stmt(&mut self, s: &$a $($mut_)? Stmt) {
                $walk_stmt(self, s);
            }
            /// An expression (every subexpression comes through here too).
            fn visit_expr(&mut self, e: &$a $($mut_)? Expr) {
                $walk_expr(self, e);
            }
            /// An argument of a call.
            fn visit_arg(&mut self, a: &$a $($mut_)? Arg) {
                $walk_arg(self, a);
            }
        }

        /// Visits each statement of a list.
        pub fn $walk_stmts<$a, V: $Visitor<$a> + ?Sized>(v: &mut V, stmts: &$a $($mut_)? [Stmt]) {
            for s in stmts {
                v.visit_stmt(s);
            }
        }

        /// Visits the expressions and statements of `s`, in source order.
        pub fn $walk_stmt<$a, V: $Visitor<$a> + ?Sized>(v: &mut V, s: &$a $($mut_)? Stmt) {
            match &$($mut_)? s.kind {
                StmtKind::Assign { target, value } | StmtKind::RefAssign { target, value } => {
                    v.visit_expr(target);
                    v.visit_expr(value);
                }
                StmtKind::Call(e) | StmtKind::Let { value: e, .. } => v.visit_expr(e),
                StmtKind::If {
                    branches,
                    else_body,
                } => {
                    for (c, body) in branches {
                        v.visit_expr(c);
                        $walk_stmts(v, body);
                    }
                    if let Some(b) = else_body {
                        $walk_stmts(v, b);
                    }
                }
                StmtKind::Case {
                    selector,
                    arms,
                    else_body,
                } => {
                    v.visit_expr(selector);
                    for arm in arms {
                        for label in & $($mut_)? arm.labels {
                            match label {
                                CaseLabel::Value(e) => v.visit_expr(e),
                                CaseLabel::Range(lo, hi) => {
                                    v.visit_expr(lo);
                                    v.visit_expr(hi);
                                }
                            }
                        }
                        $walk_stmts(v, & $($mut_)? arm.body);
                    }
                    if let Some(b) = else_body {
                        $walk_stmts(v, b);
                    }
                }
                StmtKind::For {
                    from, to, by, body, ..
                } => {
                    v.visit_expr(from);
                    v.visit_expr(to);
                    if let Some(b) = by {
                        v.visit_expr(b);
                    }
                    $walk_stmts(v, body);
                }
                StmtKind::While { cond, body } => {
                    v.visit_expr(cond);
                    $walk_stmts(v, body);
                }
                StmtKind::Repeat { body, until } => {
                    $walk_stmts(v, body);
                    v.visit_expr(until);
                }
                StmtKind::Exit
                | StmtKind::Continue
                | StmtKind::Return
                | StmtKind::Empty
                | StmtKind::InlineC(_)
                | StmtKind::Label(_)
                | StmtKind::Goto(_) => {}
            }
        }

        /// Visits the subexpressions of `e` (a call's arguments through
        /// `visit_arg`), in source order.
        pub fn $walk_expr<$a, V: $Visitor<$a> + ?Sized>(v: &mut V, e: &$a $($mut_)? Expr) {
            match &$($mut_)? e.kind {
                ExprKind::Literal(_)
                | ExprKind::Name(_)
                | ExprKind::EnumValue { .. }
                | ExprKind::DirectAddress(_) => {}
                ExprKind::Member(b, _)
                | ExprKind::Partial(b, ..)
                | ExprKind::Deref(b)
                | ExprKind::Unary(_, b)
                | ExprKind::Paren(b)
                | ExprKind::UsedBy { value: b, .. } => v.visit_expr(b),
                ExprKind::Bit(a, b) | ExprKind::Binary(_, a, b) => {
                    v.visit_expr(a);
                    v.visit_expr(b);
                }
                ExprKind::Index(b, ix) => {
                    v.visit_expr(b);
                    for i in ix {
                        v.visit_expr(i);
                    }
                }
                ExprKind::Call { callee, args } => {
                    v.visit_expr(callee);
                    for a in args {
                        v.visit_arg(a);
                    }
                }
            }
        }

        /// Visits the expression of an argument (an output's target, if any).
        pub fn $walk_arg<$a, V: $Visitor<$a> + ?Sized>(v: &mut V, a: &$a $($mut_)? Arg) {
            match &$($mut_)? a.kind {
                ArgKind::Positional(x) | ArgKind::Input { value: x, .. } => v.visit_expr(x),
                ArgKind::Output { target: Some(t), .. } => v.visit_expr(t),
                ArgKind::Output { target: None, .. } => {}
            }
        }
    };
}

visitor! {
    /// Walks a tree through shared references (see the module's text).
    trait Visitor<'a>, ;
    walk_stmts, walk_stmt, walk_expr, walk_arg
}

visitor! {
    /// Walks a tree through mutable references, to rewrite it in place.
    trait VisitorMut<'a>, mut;
    walk_stmts_mut, walk_stmt_mut, walk_expr_mut, walk_arg_mut
}

/// Calls `f` on every statement of `stmts`, nested ones included, each before the
/// statements inside it.
pub fn each_stmt<'a>(stmts: &'a [Stmt], f: &mut dyn FnMut(&'a Stmt)) {
    struct Each<'f, 'a>(&'f mut dyn FnMut(&'a Stmt));
    impl<'a> Visitor<'a> for Each<'_, 'a> {
        fn visit_stmt(&mut self, s: &'a Stmt) {
            (self.0)(s);
            walk_stmt(self, s);
        }
        fn visit_expr(&mut self, _: &'a Expr) {}
    }
    walk_stmts(&mut Each(f), stmts);
}

/// Calls `f` on every expression of `stmts`, subexpressions included, each before
/// its subexpressions.
pub fn each_expr<'a>(stmts: &'a [Stmt], f: &mut dyn FnMut(&'a Expr)) {
    struct Each<'f, 'a>(&'f mut dyn FnMut(&'a Expr));
    impl<'a> Visitor<'a> for Each<'_, 'a> {
        fn visit_expr(&mut self, e: &'a Expr) {
            (self.0)(e);
            walk_expr(self, e);
        }
    }
    walk_stmts(&mut Each(f), stmts);
}

/// Calls `f` on every expression of `stmts` to change it, each before its
/// subexpressions (which are those of what `f` left).
pub fn each_expr_mut(stmts: &mut [Stmt], f: &mut dyn FnMut(&mut Expr)) {
    struct Each<'f>(&'f mut dyn FnMut(&mut Expr));
    impl<'a> VisitorMut<'a> for Each<'_> {
        fn visit_expr(&mut self, e: &'a mut Expr) {
            (self.0)(e);
            walk_expr_mut(self, e);
        }
    }
    walk_stmts_mut(&mut Each(f), stmts);
}
