//! The catalogue of front-end diagnostic codes.
//!
//! Every diagnostic the front ends emit uses a constant from here, so codes stay stable
//! and `plcc explain CODE` can describe each one. Ranges:
//! `E00xx` lexical, `E01xx` syntax, `E02xx` names and declarations, `E03xx` types,
//! `E04xx` calls, `E05xx` rules about writing and recursion, `E06xx` constructs not
//! supported yet, `W0xxx` warnings.

use plcc_ir::diag::CodeInfo;

macro_rules! codes {
    ($( $name:ident = $code:literal, $title:literal, $expl:literal; )*) => {
        $(
            #[doc = $title]
            pub const $name: &str = $code;
        )*
        /// Every front-end code with its title and explanation.
        pub const ALL: &[CodeInfo] = &[
            $( CodeInfo { code: $code, title: $title, explanation: $expl }, )*
        ];
    };
}

codes! {
    // ---- lexical and syntax (E00xx, E01xx) ----

    // ---- names and declarations (E02xx) ----

    // ---- types (E03xx) ----

    // ---- calls (E04xx) ----

    // ---- writing, recursion (E05xx) ----

    // ---- not supported yet (E06xx) ----
}

/// The description of a code, if it is a front-end code.
pub fn lookup(code: &str) -> Option<&'static CodeInfo> {
    ALL.iter().find(|c| c.code.eq_ignore_ascii_case(code))
}
