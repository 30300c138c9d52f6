//! Parser tests of global variable blocks: the names of CODESYS's global variable
//! lists (`VAR_GLOBAL GVL`).

use super::parse;
use crate::ast::*;
use crate::intern::Interner;
use plcc_ir::diag::FileId;

/// The top-level VAR_GLOBAL blocks of `src` (which must parse without a diagnostic):
/// list name (as interned: upper case), number of declarations, CONSTANT, RETAIN.
fn globals(src: &str) -> Vec<(Option<String>, usize, bool, bool)> {
    let mut i = Interner::new();
    let mut d = Vec::new();
    let u = parse(FileId(0), src, &mut i, &mut d);
    assert!(d.is_empty(), "unexpected diagnostics for\n{src}\n{d:?}");
    u.items
        .iter()
        .filter_map(|it| match it {
            Item::Globals(b) => Some((
                b.list.map(|n| i.name(n.sym).to_string()),
                b.decls.len(),
                b.constant,
                b.retain,
            )),
            _ => None,
        })
        .collect()
}

#[test]
fn a_list_name_stands_on_the_keywords_line_where_no_declaration_starts() {
    let got = globals(
        "VAR_GLOBAL GVL\n  a, b : INT;\nEND_VAR\n\
         VAR_GLOBAL Limits CONSTANT n : INT := 3; END_VAR\n\
         VAR_GLOBAL RETAIN Kept END_VAR\n\
         VAR_GLOBAL x : INT; END_VAR\n\
         VAR_GLOBAL y AT %MW0 : INT; END_VAR\n\
         VAR_GLOBAL u, v : INT; END_VAR\n\
         VAR_GLOBAL\n  z : INT;\nEND_VAR\n",
    );
    let n = |s: &str| Some(s.to_string());
    assert_eq!(
        got,
        [
            (n("GVL"), 1, false, false),
            (n("LIMITS"), 1, true, false),
            (n("KEPT"), 0, false, true),
            (None, 1, false, false),
            (None, 1, false, false),
            (None, 1, false, false),
            (None, 1, false, false),
        ]
    );
}

#[test]
fn a_pous_var_global_has_no_list_name() {
    // Inside a POU (and a configuration's VAR_CONFIG) a name after the keyword is a
    // declaration, as before: `w` is a variable.
    let mut i = Interner::new();
    let mut d = Vec::new();
    let u = parse(
        FileId(0),
        "PROGRAM p VAR_GLOBAL w : INT; END_VAR END_PROGRAM",
        &mut i,
        &mut d,
    );
    assert!(d.is_empty(), "{d:?}");
    let Item::Pou(p) = &u.items[0] else {
        panic!("a POU")
    };
    assert!(p.var_blocks[0].list.is_none());
    assert_eq!(p.var_blocks[0].decls.len(), 1);
}
