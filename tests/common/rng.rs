//! The generator of every integration test that draws cases (soft float, ladder and
//! SFC equivalence, mutation fuzzing): plcc's one, `plcc_ir::rng::Rng`.

pub use plcc_ir::rng::Rng;
