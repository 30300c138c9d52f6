//! Blocks nobody declared: one diagnostic per unknown name, not one per use.
//!
//! A project written for an editor's runtime calls blocks that runtime implements in
//! C (OpenPLC's Arduino, P1AM, MQTT blocks, Beremiz's `python_eval`, `csv_read_*`,
//! SVGHMI blocks...), which no IEC library declares. Each use of such a name, as the
//! type of a variable (E0203) or as a called FUNCTION (E0201), is reported where it is
//! found and recorded here; at the end of lowering the reports of one name are merged
//! into the one at its first use in the sources, which shows the next few uses,
//! says how many there are, and suggests `--lib FILE` with declarations of it.

use super::Lowerer;
use crate::ast::Ident;
use crate::intern::Symbol;
use plcc_ir::diag::{Diagnostic, Span};

/// How many other uses a merged diagnostic shows.
const SHOWN: usize = 3;

/// One reported use of an undeclared block name.
pub(super) struct UnknownUse {
    /// Its diagnostic in `Lowerer::diags`.
    diag: usize,
    /// The name (the same for every spelling).
    sym: Symbol,
    /// E0203 (a type) or E0201 (a FUNCTION): the two are reported apart.
    code: &'static str,
    /// Where it is used.
    span: Span,
}

impl Lowerer<'_> {
    /// Reports `d`, an error about `name`, a block type or FUNCTION nothing declares;
    /// the reports of one name are merged by [`Lowerer::merge_unknown_blocks`].
    pub(super) fn unknown_block(&mut self, name: Ident, d: Diagnostic) {
        self.unknown_uses.push(UnknownUse {
            diag: self.diags.len(),
            sym: name.sym,
            code: d.code,
            span: name.span,
        });
        self.diags.push(d);
    }

    /// Merges the reports of each unknown block name into the one at its first use
    /// (by file, then position) and drops the others.
    pub(super) fn merge_unknown_blocks(&mut self) {
        let uses = std::mem::take(&mut self.unknown_uses);
        // The names in the order first reported.
        let mut keys: Vec<(&'static str, Symbol)> = Vec::new();
        for u in &uses {
            if !keys.contains(&(u.code, u.sym)) {
                keys.push((u.code, u.sym));
            }
        }
        let mut dropped = vec![false; self.diags.len()];
        for (code, sym) in keys {
            let mut group: Vec<&UnknownUse> = uses
                .iter()
                .filter(|u| u.code == code && u.sym == sym)
                .collect();
            group.sort_by_key(|u| (u.span.file.0, u.span.start, u.diag));
            // A declaration resolved twice is one use.
            group.dedup_by_key(|u| u.span);
            let first = group[0];
            for u in uses.iter().filter(|u| u.code == code && u.sym == sym) {
                dropped[u.diag] = u.diag != first.diag;
            }
            let name = self.text(first.span).to_string();
            let d = &mut self.diags[first.diag];
            for u in group.iter().skip(1).take(SHOWN) {
                d.secondary.push((u.span, "also used here".into()));
            }
            let n = group.len();
            if n > 1 + SHOWN {
                d.notes.push(format!(
                    "`{name}` is used in {n} places, the first {} shown here; one error for them all",
                    1 + SHOWN
                ));
            } else if n > 1 {
                d.notes.push(format!(
                    "`{name}` is used in {n} places, all shown here; one error for them all"
                ));
            }
            d.notes.push(format!(
                "help: if `{name}` is a vendor's block (one an editor's runtime implements, \
                 in no IEC library), declare it, e.g. as stubs in a file given with \
                 `--lib FILE`"
            ));
        }
        let mut k = 0;
        self.diags.retain(|_| {
            k += 1;
            !dropped[k - 1]
        });
    }
}
