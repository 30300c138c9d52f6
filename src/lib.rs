#![warn(missing_docs)]
//! The `plcc` driver: the command line, the target registry, and the runner that
//! executes programs scan by scan on any machine (`plcc run`, `plcc test`).
//!
//! The binary (`main.rs`) only parses arguments; everything else is here so that the
//! end-to-end tests can drive builds and scenarios in-process.

pub mod commands;
pub mod difftest;
pub mod driver;
pub mod format;
pub mod lsp;
pub mod output;
pub mod render;
pub mod scenario;
pub mod serve;
pub mod targets;
pub mod tiers;
