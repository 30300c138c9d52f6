// Library crates never print (ARCHITECTURE.md, "Panics"): what they say is a Diagnostic.
#![cfg_attr(
    not(test),
    deny(clippy::print_stdout, clippy::print_stderr, clippy::unwrap_used)
)]
#![warn(missing_docs)]
//! plcc's SSA intermediate representation: the one language between every front end
//! and every backend.
//!
//! A [`Module`] holds aggregate types, data objects (program instances, globals),
//! functions and the list of programs a scan runs. Functions are SSA with block
//! parameters, explicit widths and signedness in the operations. See `docs/ir.md` for
//! the semantics of every instruction and the text form.

pub mod analysis;
pub mod backend;
pub mod builder;
pub mod diag;
pub mod dominators;
pub mod entities;
pub mod function;
pub mod inst;
pub mod interp;
pub mod layout;
pub mod machine;
pub mod module;
pub mod names;
pub mod parallel;
pub mod passes;
pub mod rng;
pub mod text;
pub mod types;
pub mod value;
pub mod vars;
pub mod verify;
pub mod watchdog;

pub use builder::FuncBuilder;
pub use entities::{AggId, Block, DataId, FuncId, Inst, SlotId, TableId, Value};
pub use function::{FuncKind, Function};
pub use inst::{BinaryOp, BlockCall, ConvOp, FloatCC, InstData, IntCC, Intrinsic, UnaryOp};
pub use module::{
    AggDef, ArrayDef, Configuration, DataDef, DataKind, Field, FieldRole, Module, ProgramEntry,
    Resource, StructDef, StructKind, Table,
};
pub use types::{ElemType, MemType, Type};
pub use value::PlcValue;
