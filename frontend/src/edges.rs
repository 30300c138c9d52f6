//! Edge-detecting inputs (IEC 61131-3, 6.5.2.2): `x : BOOL R_EDGE` in the VAR_INPUT
//! of a function block or program is TRUE in the body only when the value passed
//! rose since the previous call (`F_EDGE`: fell), as if the call went through an
//! R_TRIG (F_TRIG) of its own.
//!
//! Each such input gets a hidden memory `__EDGE_<x>` in the instance, and the body
//! starts with the edge detector, written in the syntax tree (the spans of its
//! statements are the qualifier's):
//!
//! ```text
//! R_EDGE: IF x THEN IF m THEN x := FALSE; ELSE m := TRUE; END_IF; ELSE m := FALSE; END_IF;
//! F_EDGE: IF x THEN m := FALSE; x := FALSE; ELSIF m THEN x := FALSE;
//!         ELSE m := TRUE; x := TRUE; END_IF;
//! ```
//!
//! For R_EDGE `m` is the previous value (FALSE at cold start); for F_EDGE it is its
//! negation, TRUE at cold start, as plcc's F_TRIG (no edge in the first call).

use crate::ast::{
    Expr, ExprKind, Ident, Init, Item, Literal, LiteralKind, PouKind, SourceUnit, Stmt, StmtKind,
    TypeSpec, VarBlock, VarDecl, VarKind,
};
use crate::codes;
use crate::intern::Interner;
use plcc_ir::diag::{Diagnostic, Span};

fn name(sym: crate::intern::Symbol, span: Span) -> Expr {
    Expr {
        kind: ExprKind::Name(Ident { sym, span }),
        span,
    }
}

fn boolean(v: bool, span: Span) -> Expr {
    Expr {
        kind: ExprKind::Literal(Box::new(Literal {
            kind: LiteralKind::Bool(v),
            type_prefix: None,
        })),
        span,
    }
}

fn assign(target: Expr, value: Expr, span: Span) -> Stmt {
    Stmt {
        kind: StmtKind::Assign { target, value },
        span,
    }
}

fn if_else(
    cond: Expr,
    then: Vec<Stmt>,
    elsif: Option<(Expr, Vec<Stmt>)>,
    other: Vec<Stmt>,
    span: Span,
) -> Stmt {
    let mut branches = vec![(cond, then)];
    branches.extend(elsif);
    Stmt {
        kind: StmtKind::If {
            branches,
            else_body: Some(other),
        },
        span,
    }
}

/// The detector of input `x` with memory `m` (see the module's text).
fn detector(rising: bool, x: crate::intern::Symbol, m: crate::intern::Symbol, at: Span) -> Stmt {
    let set = |s, v| assign(name(s, at), boolean(v, at), at);
    if rising {
        let inner = if_else(
            name(m, at),
            vec![set(x, false)],
            None,
            vec![set(m, true)],
            at,
        );
        if_else(name(x, at), vec![inner], None, vec![set(m, false)], at)
    } else {
        if_else(
            name(x, at),
            vec![set(m, false), set(x, false)],
            Some((name(m, at), vec![set(x, false)])),
            vec![set(m, true), set(x, true)],
            at,
        )
    }
}

/// Gives the edge-detecting inputs of `units` their meaning; reports the qualifiers
/// written where they have none (not a BOOL VAR_INPUT of an FB or program).
pub fn expand(units: &mut [SourceUnit], interner: &mut Interner, diags: &mut Vec<Diagnostic>) {
    let bool_sym = interner.intern("BOOL");
    for unit in units.iter_mut() {
        for item in &mut unit.items {
            let Item::Pou(pou) = item else { continue };
            let mut memories = Vec::new();
            let mut prologue = Vec::new();
            for b in &pou.var_blocks {
                for d in &b.decls {
                    let Some((rising, at)) = d.edge else { continue };
                    let is_bool = matches!(&d.ty, TypeSpec::Named(t) if t.sym == bool_sym);
                    if b.kind != VarKind::Input || pou.kind == PouKind::Function || !is_bool {
                        diags.push(
                            Diagnostic::error(
                                codes::E_BAD_DECLARATION,
                                format!(
                                    "`{}` qualifies only a BOOL VAR_INPUT of a FUNCTION_BLOCK or PROGRAM",
                                    if rising { "R_EDGE" } else { "F_EDGE" }
                                ),
                                at,
                            )
                            .with_label("no edge to detect here"),
                        );
                        continue;
                    }
                    for n in &d.names {
                        let m = interner.intern(&format!("__EDGE_{}", interner.name(n.sym)));
                        memories.push(VarDecl {
                            names: vec![Ident { sym: m, span: at }],
                            location: None,
                            ty: TypeSpec::Named(Ident {
                                sym: bool_sym,
                                span: at,
                            }),
                            init: (!rising).then(|| Init::Expr(boolean(true, at))),
                            edge: None,
                            span: at,
                        });
                        prologue.push(detector(rising, n.sym, m, at));
                    }
                }
            }
            if memories.is_empty() {
                continue;
            }
            let at = memories[0].span;
            pou.var_blocks.push(VarBlock {
                kind: VarKind::Var,
                constant: false,
                retain: false,
                list: None,
                decls: memories,
                span: at,
            });
            prologue.append(&mut pou.body.stmts);
            pou.body.stmts = prologue;
        }
    }
}
