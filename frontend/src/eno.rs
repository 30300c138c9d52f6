//! The ENO of function blocks (IEC 61131-3, 6.6.1.4): every FB has an implicit BOOL
//! output ENO, TRUE when a call runs its body (which may set it FALSE), FALSE when
//! the call's EN is FALSE; callers read it as `inst.ENO` or with `ENO => x`.
//!
//! plcc declares it, as an ordinary `VAR_OUTPUT ENO : BOOL`, in the user's function
//! blocks that need it: those whose text names ENO (the body sets it), and all of
//! them when some source reads `<something>.ENO`, so that programs that never use it
//! pay nothing (an instance on the PIC16 would carry one more bit). A FUNCTION whose
//! text names ENO gets `VAR_OUTPUT ENO : BOOL := TRUE` (TRUE at every call unless the
//! body clears it), which its caller's `ENO => x` reads. A POU that declares ENO
//! itself keeps its declaration. The call protocol is in `lower/calls.rs`
//! (`instance_call`, `func_call`) and `lower/en_eno.rs`.

use crate::ast::{
    Expr, ExprKind, Ident, Init, Item, Literal, LiteralKind, PouKind, SourceUnit, TypeSpec,
    VarBlock, VarDecl, VarKind,
};
use crate::intern::Interner;
use crate::source::SourceMap;

/// True if `text` holds the identifier ENO (any case): right after `.` when
/// `after_dot`, anywhere otherwise; never a call's `ENO => x`.
fn names_eno(text: &str, after_dot: bool) -> bool {
    let b = text.as_bytes();
    let ident = |c: u8| c.is_ascii_alphanumeric() || c == b'_';
    let mut i = 0;
    while i + 3 <= b.len() {
        // Most bytes are not an `e`: one test rejects them (this runs over whole files).
        if b[i] | 0x20 != b'e' {
            i += 1;
            continue;
        }
        if b[i..i + 3].eq_ignore_ascii_case(b"ENO")
            && (i + 3 == b.len() || !ident(b[i + 3]))
            && (i == 0 || !ident(b[i - 1]))
        {
            let before = text[..i].trim_end();
            let after = text[i + 3..].trim_start();
            // `ENO => x` in a call is the call's own ENO, not the FB's.
            let call_output = after.starts_with("=>");
            if !call_output && (!after_dot || before.ends_with('.')) {
                return true;
            }
        }
        i += 1;
    }
    false
}

/// Declares the implicit ENO output in the function blocks of `units` that need it.
pub fn declare(units: &mut [SourceUnit], sources: &SourceMap, interner: &mut Interner) {
    // The lexers intern every identifier: where no file names ENO as one, nothing
    // needs it, and the scans of every text below are skipped (a comment that says
    // ENO declares nothing).
    let Some(eno) = interner.lookup("ENO") else {
        return;
    };
    let read_anywhere = sources.iter().any(|(_, f)| names_eno(&f.text, true));
    let bool_ty = interner.intern("BOOL");
    for unit in units.iter_mut() {
        let text = &sources.get(unit.file).text;
        for item in &mut unit.items {
            let Item::Pou(pou) = item else { continue };
            if pou.kind == PouKind::Program {
                continue;
            }
            let declared = pou
                .var_blocks
                .iter()
                .flat_map(|b| &b.decls)
                .flat_map(|d| &d.names)
                .any(|n| n.sym == eno);
            let own = text
                .get(pou.span.start as usize..pou.span.end as usize)
                .is_some_and(|t| names_eno(t, false));
            // A FUNCTION's ENO is read only by its caller's `ENO => x`.
            let function = pou.kind == PouKind::Function;
            if declared || !(own || (read_anywhere && !function)) {
                continue;
            }
            let at = pou.name.span;
            pou.var_blocks.push(VarBlock {
                kind: VarKind::Output,
                constant: false,
                retain: false,
                list: None,
                decls: vec![VarDecl {
                    names: vec![Ident { sym: eno, span: at }],
                    location: None,
                    ty: TypeSpec::Named(Ident {
                        sym: bool_ty,
                        span: at,
                    }),
                    // A FUNCTION's outputs start from their initial values at every
                    // call: its ENO starts TRUE.
                    init: function.then_some({
                        Init::Expr(Expr {
                            kind: ExprKind::Literal(Box::new(Literal {
                                kind: LiteralKind::Bool(true),
                                type_prefix: None,
                            })),
                            span: at,
                        })
                    }),
                    edge: None,
                    span: at,
                }],
                span: at,
            });
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::source::SourceFile;

    /// The output blocks `declare` leaves in the one function block of `text`.
    fn outputs_after_declare(text: &str) -> usize {
        let mut sources = SourceMap::new();
        let file = sources.add(SourceFile::new("t.st", text));
        let (mut interner, mut diags) = (Interner::new(), Vec::new());
        let mut units = vec![crate::st::parse(
            file,
            &sources.get(file).text,
            &mut interner,
            &mut diags,
        )];
        assert!(diags.is_empty(), "{diags:?}");
        declare(&mut units, &sources, &mut interner);
        let Item::Pou(fb) = &units[0].items[0] else {
            panic!("a function block")
        };
        fb.var_blocks
            .iter()
            .filter(|b| b.kind == VarKind::Output)
            .count()
    }

    #[test]
    fn eno_is_declared_where_a_body_names_it_and_not_for_a_comment() {
        let fb = |body: &str| {
            format!("FUNCTION_BLOCK F\nVAR x : INT; END_VAR\n{body}\nEND_FUNCTION_BLOCK\n")
        };
        assert_eq!(outputs_after_declare(&fb("ENO := x > 0;")), 1);
        assert_eq!(outputs_after_declare(&fb("(* sets ENO *) x := 1;")), 0);
        assert_eq!(outputs_after_declare(&fb("x := 1;")), 0);
    }

    #[test]
    fn eno_as_a_word_and_after_a_dot() {
        assert!(names_eno("ENO := FALSE;", false));
        assert!(names_eno("IF fb.eno THEN", true));
        assert!(names_eno("x := fb . ENO;", true));
        assert!(!names_eno("ENO := FALSE;", true));
        assert!(!names_eno("ENOUGH := 1; xENO := 2;", false));
        assert!(!names_eno("f(ENO => ok);", true));
        assert!(!names_eno("f(EN := c, ENO => ok);", false));
    }
}
