//! CASE statements: the labels checked, then either a chain of compares or, for a
//! dense CASE, a jump table (`br_table`).
//!
//! The arms are tried in order and the first whose labels hold the selector's value
//! runs (a label overlapping an earlier one is a warning, W0304, and the earlier arm
//! wins); no arm and no ELSE: nothing runs. Both lowerings give exactly that:
//! - the chain tests each label in turn (`icmp eq`, or a range `lo..hi` as the one
//!   unsigned compare `sel - lo <= hi - lo`) and branches to its arm;
//! - the table is `br_table (sel - min)` whose entry `v - min` goes to the first arm
//!   with a label holding `v`, and whose gaps, like every value outside `min..max`,
//!   go to the ELSE part (or past the CASE). The subtraction wraps in the selector's
//!   type and `br_table` reads its index unsigned, so a value below `min` is a large
//!   index past the table.
//!
//! A CASE is **dense**, and becomes a table, when its labels (ranges count their
//! values) cover at least [`TABLE_MIN_VALUES`] values with at least
//! [`TABLE_MIN_LABELS`] labels (a label is one compare of the chain: the table pays
//! off from about four on), the span `max - min + 1` is at most [`TABLE_MAX_SPAN`]
//! entries, and at most [`TABLE_MAX_SPREAD`] times the values covered (so at least a
//! third of the entries go to an arm). Anything else stays a chain: a sparse CASE,
//! a short one, and one whose labels are in error.

use super::body::BodyCx;
use super::consts::ConstVal;
use crate::ast::{self, CaseLabel, Expr, ExprKind, Stmt};
use crate::codes;
use crate::types::Ty;
use plcc_ir::diag::Span;
use plcc_ir::{BinaryOp, Block, BlockCall, ElemType, IntCC};

/// The fewest values a CASE's labels cover for a jump table.
pub(super) const TABLE_MIN_VALUES: u128 = 4;
/// The fewest labels (compares of the chain) for a jump table.
pub(super) const TABLE_MIN_LABELS: usize = 4;
/// The most entries of a jump table (`max - min + 1`).
pub(super) const TABLE_MAX_SPAN: u128 = 256;
/// The most entries of a jump table per value its labels cover.
pub(super) const TABLE_MAX_SPREAD: u128 = 3;

/// The labels of each arm that are checked and not empty, as `lo..=hi`, in order.
type Labels = Vec<Vec<(i128, i128)>>;

/// The entries of a dense CASE's table: the least label value, and for each value
/// from it on the arm that runs, if one does.
struct Table {
    min: i128,
    arms: Vec<Option<usize>>,
}

/// The table of a dense CASE (see the module's doc), or `None` for a chain.
fn dense(labels: &Labels) -> Option<Table> {
    let all = labels.iter().flatten();
    if all.clone().count() < TABLE_MIN_LABELS {
        return None;
    }
    let min = all.clone().map(|l| l.0).min()?;
    let max = all.map(|l| l.1).max()?;
    let span = u128::try_from(max - min + 1).ok()?;
    if span > TABLE_MAX_SPAN {
        return None;
    }
    let mut arms = vec![None; span as usize];
    for (k, arm) in labels.iter().enumerate() {
        for &(lo, hi) in arm {
            for e in &mut arms[(lo - min) as usize..=(hi - min) as usize] {
                // The first arm holding a value runs for it.
                e.get_or_insert(k);
            }
        }
    }
    let covered = arms.iter().filter(|a| a.is_some()).count() as u128;
    (covered >= TABLE_MIN_VALUES && span <= TABLE_MAX_SPREAD * covered)
        .then_some(Table { min, arms })
}

impl<'s> BodyCx<'_, 's> {
    pub(super) fn case_stmt(
        &mut self,
        selector: &'s Expr,
        arms: &'s [ast::CaseArm],
        else_body: Option<&'s [Stmt]>,
    ) {
        self.set_span(selector.span);
        let sel = self.emit(selector, None);
        let ok_type = matches!(sel.ty, Ty::Error | Ty::Enum(..)) || sel.ty.is_int_like();
        if !ok_type {
            let t = self.l.ty_name(sel.ty);
            self.l.error(
                codes::E_TYPE_MISMATCH,
                format!(
                    "a CASE selector must be an integer, a bit string or an enumeration, not {t}"
                ),
                selector.span,
            );
        }
        let sel_elem = match sel.ty {
            Ty::Enum(_, base) => Some(base),
            t => t.elem().filter(|_| ok_type),
        };
        // Every label is checked first (its diagnostics come before those of the
        // arms' bodies), so that the lowering can look at them all.
        let mut seen: Vec<(i128, i128, Span)> = Vec::new();
        let labels: Labels = arms
            .iter()
            .map(|arm| self.case_labels(arm, sel_elem, sel.ty, &mut seen))
            .collect();
        let join = self.b.create_block();
        let table = sel_elem
            .filter(|e| e.ir_type().is_int() && *e != ElemType::Bool)
            .and_then(|e| Some((e, dense(&labels)?)));
        match table {
            Some((e, table)) => {
                self.set_span(selector.span);
                self.case_table(sel.v, e, &table, arms, else_body, join);
            }
            None => self.case_chain(sel.v, sel_elem, &labels, arms, else_body, join),
        }
    }

    /// The ELSE part (if any) where the current block goes on, then `join`.
    fn case_else(&mut self, else_body: Option<&'s [Stmt]>, join: Block) {
        if let Some(e) = else_body {
            self.stmts(e);
        }
        self.b.jump(join, vec![]);
        self.b.switch_to(join);
    }

    /// The compare chain: each arm's labels tested in turn, the arm's body after
    /// them, the ELSE part when none holds. With no selector type (an error), no
    /// compares: the bodies are still lowered, and checked.
    fn case_chain(
        &mut self,
        sel: plcc_ir::Value,
        e: Option<ElemType>,
        labels: &Labels,
        arms: &'s [ast::CaseArm],
        else_body: Option<&'s [Stmt]>,
        join: Block,
    ) {
        for (arm, arm_labels) in arms.iter().zip(labels) {
            let body_b = self.b.create_block();
            for &(lo, hi) in arm_labels {
                let Some(t) = e.map(ElemType::ir_type) else {
                    break;
                };
                let next = self.b.create_block();
                if lo == hi {
                    let c = self.b.iconst(t, lo as i64);
                    let eq = self.b.icmp(IntCC::Eq, sel, c);
                    self.b.brif(eq, body_b, vec![], next, vec![]);
                } else {
                    // lo <= sel <= hi as one unsigned compare: sel - lo <= hi - lo.
                    let lo_c = self.b.iconst(t, lo as i64);
                    let d = self.b.binary(BinaryOp::Isub, sel, lo_c);
                    let span_c = self.b.iconst(t, (hi - lo) as i64);
                    let inr = self.b.icmp(IntCC::Ule, d, span_c);
                    self.b.brif(inr, body_b, vec![], next, vec![]);
                }
                self.b.switch_to(next);
            }
            let after_tests = self.b.current_block();
            self.b.switch_to(body_b);
            self.stmts(&arm.body);
            self.b.jump(join, vec![]);
            if let Some(blk) = after_tests {
                self.b.switch_to(blk);
            }
        }
        self.case_else(else_body, join);
    }

    /// The jump table: `br_table (sel - min)` to the arms' bodies, the gaps and
    /// everything past the table to the ELSE part (or `join`).
    fn case_table(
        &mut self,
        sel: plcc_ir::Value,
        e: ElemType,
        table: &Table,
        arms: &'s [ast::CaseArm],
        else_body: Option<&'s [Stmt]>,
        join: Block,
    ) {
        let t = e.ir_type();
        let index = if table.min == 0 {
            sel
        } else {
            let min = self.b.iconst(t, table.min as i64);
            self.b.binary(BinaryOp::Isub, sel, min)
        };
        let bodies: Vec<Block> = arms.iter().map(|_| self.b.create_block()).collect();
        let other = match else_body {
            Some(_) => self.b.create_block(),
            None => join,
        };
        let entries = table
            .arms
            .iter()
            .map(|a| BlockCall::new(a.map_or(other, |k| bodies[k]), vec![]))
            .collect();
        self.b
            .br_table(index, BlockCall::new(other, vec![]), entries);
        for (arm, &body_b) in arms.iter().zip(&bodies) {
            self.b.switch_to(body_b);
            self.stmts(&arm.body);
            self.b.jump(join, vec![]);
        }
        if other != join {
            self.b.switch_to(other);
        }
        self.case_else(else_body, join);
    }

    /// The labels of one arm, checked against the selector's type (`sel` is the
    /// integer type that holds it) and the labels `seen` before (an overlap is a
    /// warning): those that are constants of the type and not empty.
    fn case_labels(
        &mut self,
        arm: &'s ast::CaseArm,
        sel: Option<ElemType>,
        sel_ty: Ty,
        seen: &mut Vec<(i128, i128, Span)>,
    ) -> Vec<(i128, i128)> {
        let mut out = Vec::new();
        for label in &arm.labels {
            let (lo_e, hi_e) = match label {
                CaseLabel::Value(e) => (e, e),
                CaseLabel::Range(a, b) => (a, b),
            };
            let lo = self.case_label_value(lo_e, sel, sel_ty);
            let hi = if std::ptr::eq(lo_e, hi_e) {
                lo
            } else {
                self.case_label_value(hi_e, sel, sel_ty)
            };
            let (Some(lo), Some(hi)) = (lo, hi) else {
                continue;
            };
            let span = lo_e.span.to(hi_e.span);
            if hi < lo {
                self.l.error(
                    codes::E_BAD_CASE_LABEL,
                    format!("empty CASE range {lo}..{hi}"),
                    span,
                );
                continue;
            }
            if let Some(&(_, _, prev)) = seen.iter().find(|(a, b, _)| lo <= *b && *a <= hi) {
                // Arms are tried in order, so the earlier one wins for the values
                // both cover: legal, but rarely meant.
                self.l.diags.push(
                    plcc_ir::diag::Diagnostic::warning(
                        codes::W_CASE_OVERLAP,
                        "this CASE label overlaps an earlier one",
                        span,
                    )
                    .with_secondary(prev, "earlier label")
                    .with_note("for the values both cover, the earlier arm runs"),
                );
            }
            seen.push((lo, hi, span));
            out.push((lo, hi));
        }
        out
    }

    /// A CASE label's value, checked against the selector's type (`sel_ty`; `sel` is
    /// the integer type that holds it).
    fn case_label_value(&mut self, e: &'s Expr, sel: Option<ElemType>, sel_ty: Ty) -> Option<i128> {
        if let Ty::Enum(en, _) = sel_ty {
            return self.enum_case_label(e, en);
        }
        let label_ty = self.infer(e);
        if let Ty::Enum(..) = label_ty {
            if sel_ty == Ty::Error {
                return None;
            }
            let (l, t) = (self.l.ty_name(label_ty), self.l.ty_name(sel_ty));
            self.l.error(
                codes::E_BAD_CASE_LABEL,
                format!(
                    "this CASE label is a value of the enumeration {l}, but the selector is {t}"
                ),
                e.span,
            );
            return None;
        }
        match self.l.const_eval(e, self.pou) {
            Some((ConstVal::Int(v), _)) => {
                if let Some(t) = sel {
                    if let Some((lo, hi)) = crate::types::int_range(t) {
                        if v < lo || v > hi {
                            self.l.error(
                                codes::E_BAD_CASE_LABEL,
                                format!("CASE label {v} is out of the range of {}", t.name()),
                                e.span,
                            );
                            return None;
                        }
                    }
                }
                Some(v)
            }
            _ => {
                match &e.kind {
                    crate::ast::ExprKind::Name(id) if self.l.is_unsupported_name(id.sym) => {
                        return None
                    }
                    crate::ast::ExprKind::EnumValue { ty, value } => {
                        // A known value was reported above (its type is an
                        // enumeration's); this reports an unknown type or value.
                        let _ = self.l.qualified_enum(**ty, *value, true);
                        return None;
                    }
                    _ => {}
                }
                self.l.error(
                    codes::E_BAD_CASE_LABEL,
                    "a CASE label must be an integer constant",
                    e.span,
                );
                None
            }
        }
    }

    /// A CASE label for a selector of the enumeration `en`: one of its values (or a
    /// constant of the type).
    fn enum_case_label(&mut self, e: &'s Expr, en: crate::types::EnumId) -> Option<i128> {
        let mut x = e;
        while let ExprKind::Paren(i) = &x.kind {
            x = i;
        }
        let sel_ty = Ty::Enum(en, self.l.enum_base(en));
        let found = match &x.kind {
            ExprKind::Name(id) => match self.resolve_name(*id, false, Some(sel_ty)) {
                super::body::Named::Const(ConstVal::Int(v), t) if t == sel_ty => return Some(v),
                super::body::Named::Const(_, t) => Some(t),
                super::body::Named::Place(p) => Some(p.ty),
                super::body::Named::Error => None,
            },
            ExprKind::EnumValue { ty, value } => match self.l.qualified_enum(**ty, *value, true) {
                Some((e2, _, v)) if e2 == en => return Some(v),
                Some((e2, b, _)) => Some(Ty::Enum(e2, b)),
                None => return None,
            },
            // CODESYS's `Color.Red`.
            ExprKind::Member(base, name) => match self.qualifier(base) {
                Some(q @ super::qualified::Qualifier::Enum(..)) => {
                    match self.qualified(q, base, *name) {
                        super::body::Named::Const(ConstVal::Int(v), t) if t == sel_ty => {
                            return Some(v)
                        }
                        super::body::Named::Const(_, t) => Some(t),
                        _ => return None,
                    }
                }
                _ => None,
            },
            _ => None,
        };
        let want = self.l.ty_name(sel_ty);
        let msg = match found {
            Some(t @ Ty::Enum(..)) => format!(
                "this CASE label is a value of {}, but the selector is of the enumeration {want}",
                self.l.ty_name(t)
            ),
            _ => format!(
                "a CASE label for a selector of the enumeration {want} must be one of its values"
            ),
        };
        let names: Vec<&str> = self.l.user.enums[en.0 as usize]
            .values
            .iter()
            .map(|v| v.display.as_str())
            .collect();
        let note = format!("its values are {}", names.join(", "));
        self.l.diags.push(
            plcc_ir::diag::Diagnostic::error(codes::E_BAD_CASE_LABEL, msg, e.span).with_note(note),
        );
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::source::{SourceFile, SourceMap};
    use crate::{compile, Lang, LowerOptions};
    use plcc_ir::interp::Interp;
    use plcc_ir::machine::Machine;
    use plcc_ir::text::{print_module, PrintOptions};
    use plcc_ir::{ElemType, Module, PlcValue};

    /// `PROGRAM main` with `x : INT` and `a : INT`, whose body is `CASE x OF arms
    /// END_CASE;` (and an enumeration `E` for the selectors that want one).
    fn lower(arms: &str, selector: &str) -> Module {
        let src = format!(
            "TYPE E : (e0, e1, e2, e3, e4, e5); END_TYPE\nPROGRAM main\nVAR x : INT; a : INT; e : E; END_VAR\nCASE {selector} OF\n{arms}\nEND_CASE;\nEND_PROGRAM\n"
        );
        let mut sources = SourceMap::new();
        let f = sources.add(SourceFile::new("t.st", &src));
        let c = compile(&mut sources, &[(f, Lang::St)], &LowerOptions::default());
        let errors: Vec<String> = c
            .diagnostics
            .iter()
            .filter(|d| d.is_error())
            .map(|d| d.message.clone())
            .collect();
        assert!(errors.is_empty(), "{src}: {errors:?}");
        c.module.expect("a module")
    }

    fn tables(arms: &str, selector: &str) -> usize {
        let m = lower(arms, selector);
        print_module(&m, &PrintOptions::default())
            .matches("br_table")
            .count()
    }

    #[test]
    fn the_lowering_makes_a_table_of_dense_cases_only() {
        // Three labels are a chain, four a table.
        assert_eq!(tables("1: a := 1; 2: a := 2; 3: a := 3;", "x"), 0);
        assert_eq!(
            tables("1: a := 1; 2: a := 2; 3: a := 3; 4: a := 4;", "x"),
            1
        );
        assert_eq!(tables("1, 2: a := 1; 3, 4: a := 2;", "x"), 1);
        // Ranges: 40 values over two labels are a chain.
        assert_eq!(tables("0..19: a := 1; 20..39: a := 2;", "x"), 0);
        // Spread: 4 values over 13 entries are a chain, over 12 a table.
        assert_eq!(
            tables("0: a := 1; 4: a := 2; 8: a := 3; 12: a := 4;", "x"),
            0
        );
        assert_eq!(
            tables("0: a := 1; 4: a := 2; 8: a := 3; 11: a := 4;", "x"),
            1
        );
        // Span: 257 entries are a chain, 256 a table.
        assert_eq!(
            tables("0: a := 1; 1: a := 2; 2: a := 3; 3..256: a := 4;", "x"),
            0
        );
        assert_eq!(
            tables("0: a := 1; 1: a := 2; 2: a := 3; 3..255: a := 4;", "x"),
            1
        );
        // The selector's type: an expression, an enumeration.
        assert_eq!(
            tables("1: a := 1; 2: a := 2; 3: a := 3; 4: a := 4;", "x * 2"),
            1
        );
        assert_eq!(
            tables("e0: a := 1; e1, e2: a := 2; e3..e5: a := 3;", "e"),
            1
        );
    }

    #[test]
    fn a_table_keeps_the_first_arm_of_overlapping_labels() {
        let arms = "1..3: a := 1; 2: a := 2; 3, 4: a := 3; 6: a := 6; ELSE a := -1;";
        let m = lower(arms, "x");
        assert_eq!(
            print_module(&m, &PrintOptions::default())
                .matches("br_table")
                .count(),
            1
        );
        let mut it = Interp::new(&m).expect("an interpreter");
        it.cold_start().expect("cold start");
        for (x, want) in [
            (0, -1),
            (1, 1),
            (2, 1),
            (3, 1),
            (4, 3),
            (5, -1),
            (6, 6),
            (7, -1),
            (-1, -1),
        ] {
            it.write("main.x", PlcValue::from_i64(ElemType::Int, x))
                .expect("x");
            it.scan().expect("a scan");
            assert_eq!(it.read("main.a").expect("a").as_i64(), want, "x = {x}");
        }
    }

    fn table(labels: &[&[(i128, i128)]]) -> Option<(i128, Vec<Option<usize>>)> {
        let labels: Labels = labels.iter().map(|a| a.to_vec()).collect();
        dense(&labels).map(|t| (t.min, t.arms))
    }

    #[test]
    fn dense_cases_and_their_tables() {
        // Four values, five labels: a table; the first arm wins an overlap.
        let (min, arms) = table(&[&[(1, 1), (2, 2)], &[(2, 2), (4, 4), (5, 5)]]).unwrap();
        assert_eq!(min, 1);
        assert_eq!(arms, vec![Some(0), Some(0), None, Some(1), Some(1)]);
        // Three values are too few, whatever the labels.
        assert!(table(&[&[(1, 1), (2, 2)], &[(2, 2), (4, 4)]]).is_none());
        // Ranges count their values; negative labels.
        let (min, arms) = table(&[&[(-3, -1)], &[(0, 0)], &[(2, 2), (3, 3)]]).unwrap();
        assert_eq!(min, -3);
        assert_eq!(
            arms,
            vec![Some(0), Some(0), Some(0), Some(1), None, Some(2), Some(2)]
        );
        // Too few labels, too few values.
        assert!(table(&[&[(0, 9)], &[(10, 19)], &[(20, 29)]]).is_none());
        assert!(table(&[&[(0, 0)], &[(0, 0)], &[(1, 1)], &[(1, 1)]]).is_none());
        // Too sparse: 4 values over 13 entries; 12 entries are fine.
        assert!(table(&[&[(0, 0), (4, 4), (8, 8), (12, 12)]]).is_none());
        assert!(table(&[&[(0, 0), (4, 4), (8, 8), (11, 11)]]).is_some());
        // Too wide: 257 entries, even all covered; 256 are fine.
        assert!(table(&[&[(0, 0), (1, 1), (2, 2), (3, 256)]]).is_none());
        assert!(table(&[&[(0, 0), (1, 1), (2, 2), (3, 255)]]).is_some());
        // The widest labels do not overflow.
        let huge = (i128::from(i64::MIN), i128::from(u64::MAX));
        assert!(table(&[&[(0, 0), (1, 1), (2, 2), huge]]).is_none());
    }
}
