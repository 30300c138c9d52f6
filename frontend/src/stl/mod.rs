//! The STL of the PLC-UD controller: lexer and parser.
//!
//! PLC-UD's "STL" is a small Pascal-like language (not Siemens STL, not IEC ST), see
//! `shared/reference/stl-plcud.md`. [`parse`] turns one file into the same
//! [`SourceUnit`] the Structured Text parser produces, so that type checking, lowering
//! and every backend serve STL unchanged:
//!
//! | STL | syntax tree |
//! |-----|-------------|
//! | `pragma ...` lines, `uses a, b;` | ignored |
//! | global `var ... end_var;` | [`Item::Globals`](crate::ast::Item::Globals) (`VAR_GLOBAL`) |
//! | global `constant k : T := v;` | [`Item::Globals`](crate::ast::Item::Globals) with `constant` |
//! | `function f(a : T; b : T) T;` / `function f(a : T, b : T); T` | a FUNCTION with VAR_INPUTs and a result |
//! | `procedure p(a : T);` | a FUNCTION without a result |
//! | `program id; ... begin <locals> <stmts> end.` | a PROGRAM `id` (locals: VAR, VAR CONSTANT) |
//! | `begin S; S end` | its statements, flattened into the enclosing list |
//! | `if`/`else if` | IF with ELSIF branches |
//! | `for i := a downto b do S` | FOR with `BY -1` |
//! | `INC(x) DEC(x) SWAP(x) SET(x, n) CLR(x, n)` | calls of `__STL_INC` ... |
//! | `INC(x);` ... as a statement | `x := __STL_INC(x);` (in place, like the quadruple `INC x x`) |
//! | `SHL(x)` `SHR(x)` `ROL(x)` `ROR(x)` (one argument) | `SHL(x, 1)` ...: one bit, as in the quadruples |
//! | `#30` (the paper's constant marker) | the literal 30 |
//! | types BOOL, INT, UINT, SINT, USINT | the IEC types of those names (any other: E0734) |
//!
//! # Expression precedence
//!
//! From the loosest to the tightest binding:
//!
//! 1. `or`
//! 2. `xor`
//! 3. `and`
//! 4. `not` at the start of a condition (it covers a whole comparison)
//! 5. `= <> < > <= >=` (not associative: `a < b < c` is an error, E0730)
//! 6. binary `+ -`; a sign at the start of an expression covers its first term
//! 7. `* / %`
//! 8. `not`, `-`, `+` after another operator (they cover one factor)
//! 9. numbers, TRUE/FALSE, names, calls `f(a, b)`, `( ... )`
//!
//! Why: the paper's LL(1) grammar is `FACT = id | (EXPR) | NUM`,
//! `TERM = FACT {(*|/|%) FACT}`, `EXPR = [+|-] TERM {(+|-) TERM}`, a comparison
//! relates two EXPRs, and conditions combine comparisons with `and`/`or`/`not`: its
//! FOLLOW(EXPR) holds `and`/`or`, and FIRST of a condition holds `not`. So, unlike
//! Pascal (where `and` is a multiplying and `or` an adding operator, and
//! `a > 1 and b < 2` needs parentheses), comparisons bind tighter than the logical
//! operators, and the sign of `EXPR` covers a term. The paper does not say whether
//! `and` binds tighter than `or`; plcc follows ST (`and` > `xor` > `or`), so a
//! condition reads the same in both languages of a mixed project. Logical operators
//! may also combine BOOL values outside conditions (`b := x and y;`), since the
//! paper uses them on BOOL variables.
//!
//! Differences from Structured Text:
//! - `not a = b` is `not (a = b)` (ST: `(NOT a) = b`); `x = not y` is `x = (not y)`.
//! - `-a * b` is `-(a * b)` (ST: `(-a) * b`); the value is the same except when an
//!   operand is the most negative value of its type.
//! - comparisons do not chain; `%` is MOD; there is no `**`, `&`, `AND_THEN`/`OR_ELSE`.
//! - arguments are positional only.

pub mod lexer;
pub mod parser;

#[cfg(test)]
mod tests;

use crate::ast::SourceUnit;
use crate::intern::Interner;
use plcc_ir::diag::{Diagnostic, FileId};

/// Parses one PLC-UD STL file. Never panics and always terminates; errors go to
/// `diags` (in source order), and the parser recovers so that one run reports every
/// independent error of the file.
pub fn parse(
    file: FileId,
    text: &str,
    interner: &mut Interner,
    diags: &mut Vec<Diagnostic>,
) -> SourceUnit {
    let first = diags.len();
    let lexed = lexer::lex(file, text, interner, diags);
    let unit = parser::parse_tokens(
        file,
        text,
        &lexed.tokens,
        lexed.eof_in_error,
        interner,
        diags,
    );
    // Lexical errors were found first; show everything in source order.
    diags[first..].sort_by_key(|d| d.span.map_or(u32::MAX, |s| s.start));
    unit
}
