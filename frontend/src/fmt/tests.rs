//! Unit tests of the formatter: its parts on small texts (the exact layouts are
//! snapshots in `tests/fmt.rs`).

use super::{format_st, FmtError};

fn fmt(s: &str) -> String {
    match format_st(s) {
        Ok(t) => t,
        Err(e) => panic!("{e}: {s}"),
    }
}

#[test]
fn keywords_upper_names_and_literals_kept() {
    let out = fmt("program p var x : int; s : string := 'if$N'; end_var\nif x = 16#ff then x := t#1s; end_if; end_program\n");
    assert!(out.contains("PROGRAM p"), "{out}");
    assert!(out.contains("IF x = 16#ff THEN"), "{out}");
    assert!(out.contains("'if$N'"), "{out}");
    assert!(out.contains("t#1s"), "{out}");
    // `int` is a type name, not a reserved word.
    assert!(out.contains(": int;"), "{out}");
}

#[test]
fn refuses_what_does_not_parse() {
    match format_st("PROGRAM p\nx := ;\nEND_PROGRAM\n") {
        Err(FmtError::Syntax(d)) => assert!(!d.is_empty()),
        other => panic!("{other:?}"),
    }
}

#[test]
fn crlf_kept() {
    let out = fmt("PROGRAM p\r\nVAR x : INT; END_VAR\r\nx := 1;\r\nEND_PROGRAM\r\n");
    assert_eq!(
        out,
        "PROGRAM p\r\nVAR x : INT; END_VAR\r\n    x := 1;\r\nEND_PROGRAM\r\n"
    );
}

#[test]
fn paren_star_never_glued() {
    let out = fmt("PROGRAM p\nVAR a : ARRAY[*] OF INT; END_VAR\nEND_PROGRAM\n");
    assert!(out.contains("ARRAY[*]"), "{out}");
}

#[test]
fn unary_minus_glued_binary_spaced() {
    let out = fmt("PROGRAM p VAR x : INT; END_VAR\nx:=-x-(-1)*-2;\nEND_PROGRAM\n");
    assert!(out.contains("x := -x - (-1) * -2;"), "{out}");
}

#[test]
fn il_transition_lines_are_instructions() {
    let out = fmt("PROGRAM p\nVAR a, b : BOOL; END_VAR\nINITIAL_STEP s: END_STEP\nSTEP t: END_STEP\nTRANSITION FROM s TO t :\nLD a\nAND b\nEND_TRANSITION\nEND_PROGRAM\n");
    assert!(
        out.contains(
            "    TRANSITION FROM s TO t :\n        LD a\n        AND b\n    END_TRANSITION\n"
        ),
        "{out}"
    );
}

#[test]
fn empty_and_comment_only_texts() {
    assert_eq!(fmt(""), "");
    assert_eq!(fmt("\n\n(* a *)\n\n\n\n// b"), "(* a *)\n\n// b\n");
}

#[test]
fn struct_on_its_own_line_and_until_condition() {
    let out = fmt("TYPE T :\nSTRUCT\na : INT;\nEND_STRUCT\nEND_TYPE\nPROGRAM p\nVAR i : INT; END_VAR\nREPEAT\ni := i + 1;\nUNTIL\ni > 3\nEND_REPEAT;\nEND_PROGRAM\n");
    assert!(
        out.starts_with("TYPE T :\n    STRUCT\n        a : INT;\n    END_STRUCT\nEND_TYPE\n"),
        "{out}"
    );
    assert!(
        out.contains("    UNTIL\n        i > 3\n    END_REPEAT;\n"),
        "{out}"
    );
}

#[test]
fn block_words_are_names_in_declarations() {
    let out = fmt("PROGRAM p\nVAR\nstep AT %IX0.0 : BOOL;\nlonger : INT;\nEND_VAR\nEND_PROGRAM\n");
    assert!(
        out.contains("VAR\n    step AT %IX0.0 : BOOL;\n    longer         : INT;\nEND_VAR\n"),
        "{out}"
    );
}
