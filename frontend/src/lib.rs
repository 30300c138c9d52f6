//! plcc's front ends: source files, the shared syntax tree, the Structured Text parser,
//! semantic analysis and lowering to the IR.

pub mod ast;
pub mod codes;
pub mod intern;
pub mod source;
pub mod st;
