//! Analyses shared by the passes, the verifier and the backends, so that no backend
//! keeps a copy of its own: the call graph of a module ([`callgraph`], its functions
//! re-exported here) and the liveness of a function's values ([`Liveness`]).

pub mod callgraph;
pub mod liveness;

pub use callgraph::*;
pub use liveness::Liveness;
