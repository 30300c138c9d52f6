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
    let read_anywhere = sources.iter().any(|(_, f)| names_eno(&f.text, true));
    let eno = interner.intern("ENO");
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
    use super::names_eno;

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
