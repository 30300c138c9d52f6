//! The fuzz targets' shared body: one build of the input in one language, through
//! the front end and the IR verifier (no optimisation, no backend).

use plcc::driver::{build_sources, BuildOptions, E_INTERNAL};
use plcc_frontend::Lang;

/// Builds `data` as a file of `lang` (named `name`): parse, resolve, type-check,
/// lower, verify the IR. Any outcome but a panic, a hang, a crash or an internal
/// error (the front end made IR the verifier rejects, E9901) is fine; an internal
/// error panics, so that AFL++ keeps the input as a crash.
pub fn check(data: &[u8], lang: Lang, name: &str) {
    let opts = BuildOptions {
        lang: Some(lang),
        no_opt: true,
        ..Default::default()
    };
    if let Ok(build) = build_sources(vec![(name.to_string(), data.to_vec())], &opts) {
        if let Some(d) = build.diagnostics.iter().find(|d| d.code == E_INTERNAL) {
            panic!("internal error: {}", d.message);
        }
    }
}
