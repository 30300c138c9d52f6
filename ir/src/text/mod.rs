//! The text form of the IR: printer and parser (see `docs/ir.md`).
//!
//! `print(parse(text)) == text` for any printed module, and a parsed module prints
//! the same as the module that was printed.

mod parse;
mod print;
#[cfg(test)]
mod tests;

pub use parse::{parse_module, ParseError};
pub use print::{print_function, print_inst, print_module, PrintOptions};

pub(crate) use print::{write_name, write_quoted};
