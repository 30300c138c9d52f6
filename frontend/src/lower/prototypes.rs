//! Prototypes: FUNCTIONs declared under matiec's `{disable code generation}` pragma
//! (its standard library declares every standard function this way, so that its
//! compiler knows their types). plcc has these functions built in: it checks the
//! declarations' types and compiles nothing, and calls keep going to the built-in
//! functions.

use super::Lowerer;
use crate::ast;
use crate::codes;
use plcc_ir::diag::{FileId, Span};

const DISABLE: &str = "{disable code generation}";
const ENABLE: &str = "{enable code generation}";

impl<'s> Lowerer<'s> {
    /// The byte ranges of `file` under `{disable code generation}` (until
    /// `{enable code generation}` or the end of the file).
    pub(super) fn prototype_regions(&self, file: FileId) -> Vec<(u32, u32)> {
        let text = self.sources.get(file).text.to_ascii_lowercase();
        let mut out = Vec::new();
        let mut at = 0;
        while let Some(i) = text[at..].find(DISABLE) {
            let start = at + i;
            let end = text[start..].find(ENABLE).map_or(text.len(), |j| start + j);
            out.push((start as u32, end as u32));
            at = end;
        }
        out
    }

    /// True if `p` is a FUNCTION declared in one of `regions`.
    pub(super) fn is_prototype(p: &ast::Pou, regions: &[(u32, u32)]) -> bool {
        p.kind == ast::PouKind::Function
            && regions
                .iter()
                .any(|&(s, e)| p.span.start >= s && p.span.end <= e)
    }

    /// Checks the types of the prototypes and says, once per file, that they are
    /// not compiled.
    pub(super) fn check_prototypes(&mut self) {
        let protos = std::mem::take(&mut self.prototypes);
        let mut per_file: Vec<(FileId, usize, Span)> = Vec::new();
        for p in &protos {
            for b in &p.var_blocks {
                for d in &b.decls {
                    let _ = self.resolve_type_tagged(&d.ty, None);
                }
            }
            if let Some(rt) = &p.return_type {
                let _ = self.resolve_type_tagged(rt, None);
            }
            match per_file.iter_mut().find(|(f, ..)| *f == p.span.file) {
                Some(e) => e.1 += 1,
                None => per_file.push((p.span.file, 1, p.name.span)),
            }
        }
        for (_, n, first) in per_file {
            self.diags.push(
                plcc_ir::diag::Diagnostic::warning(
                    codes::W_PROTOTYPES,
                    format!(
                        "{n} FUNCTION(s) under `{{disable code generation}}` are prototypes: their types are checked, they are not compiled"
                    ),
                    first,
                )
                .with_note("calls of standard functions use plcc's own; a prototype of anything else is not callable"),
            );
        }
        self.prototypes = protos;
    }
}
