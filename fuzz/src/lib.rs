//! The fuzz targets' shared body: one build of the input in one language, checked
//! only (parse, resolve, type-check, lower), as `plcc check` does.

use plcc::driver::{build_sources, BuildOptions};
use plcc_frontend::Lang;

/// Builds `data` as a file of `lang` (named `name`); any outcome but a panic, a hang
/// or a crash is fine.
pub fn check(data: &[u8], lang: Lang, name: &str) {
    let opts = BuildOptions {
        lang: Some(lang),
        check_only: true,
        ..Default::default()
    };
    let _ = build_sources(vec![(name.to_string(), data.to_vec())], &opts);
}
