//! OSCAT BASIC 3.33 (`../shared/corpus/libs/oscat_basic_333`, a 30,000-line CODESYS
//! library) in the CODESYS dialect: how many of its POUs `plcc check` accepts (the
//! table lists every POU it rejects, with the first error), and that what it accepts
//! lowers to IR and JIT-compiles. Both copies are read: the ISO-8859-1 original and
//! the UTF-8 one. Also the matiec standard library's function blocks. Skips with a
//! notice when `../shared` is absent.

use plcc::driver::{build_sources, BuildOptions};
use plcc_frontend::ast::Item;
use std::path::{Path, PathBuf};

#[path = "common/skip.rs"]
mod skip;

fn libs_dir() -> Option<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/corpus/libs");
    if dir.is_dir() {
        Some(dir)
    } else {
        skip::notice(&format!("{} is absent", dir.display()));
        None
    }
}

/// The POUs of a build's user file, by name and span, and the errors in each.
fn pou_report(text: &[u8], name: &str) -> (usize, Vec<(String, String)>, Option<plcc_ir::Module>) {
    let opts = BuildOptions {
        codesys: true,
        lang: Some(plcc_frontend::Lang::St),
        ..Default::default()
    };
    let build = build_sources(vec![(name.to_string(), text.to_vec())], &opts).expect("builds");
    let mut pous = Vec::new();
    for unit in &build.syntax {
        if build.sources.get(unit.file).name != name {
            continue;
        }
        for item in &unit.items {
            if let Item::Pou(p) = item {
                let n = build.sources.get(unit.file).text
                    [p.name.span.start as usize..p.name.span.end as usize]
                    .to_string();
                pous.push((n, p.span));
            }
        }
    }
    let mut failing = Vec::new();
    for (n, span) in &pous {
        let first = build.diagnostics.iter().find(|d| {
            d.is_error()
                && d.span.is_some_and(|s| {
                    s.file == span.file && s.start >= span.start && s.end <= span.end
                })
        });
        if let Some(d) = first {
            failing.push((n.clone(), d.to_string()));
        }
    }
    // An error outside every POU (a TYPE, the globals) fails the whole library.
    let outside = build.diagnostics.iter().filter(|d| d.is_error()).find(|d| {
        !pous.iter().any(|(_, span)| {
            d.span
                .is_some_and(|s| s.file == span.file && s.start >= span.start && s.end <= span.end)
        })
    });
    if let Some(d) = outside {
        failing.push(("(outside the POUs)".to_string(), d.to_string()));
    }
    (pous.len(), failing, build.module)
}

#[test]
fn oscat_basic_checks_and_jit_compiles() {
    let Some(libs) = libs_dir() else { return };
    let dir = libs.join("oscat_basic_333");
    for file in ["OSCAT_BASIC_333.TXT", "OSCAT_BASIC_333.utf8.st"] {
        let text = std::fs::read(dir.join(file)).expect("OSCAT file");
        let (total, failing, module) = pou_report(&text, file);
        let accepted = total - failing.len().min(total);
        println!(
            "OSCAT BASIC 3.33 ({file}): {total} POUs, {accepted} accepted ({:.1}%)",
            accepted as f64 * 100.0 / total as f64
        );
        for (pou, why) in &failing {
            println!("  rejected {pou}: {why}");
        }
        // 536 by the count; the parser finds every FUNCTION, FUNCTION_BLOCK
        // and PROGRAM (546: the count left a few out).
        assert!(total >= 536, "{file}: only {total} POUs found");
        assert!(
            accepted * 100 >= total * 95,
            "{file}: only {accepted} of {total} POUs are accepted"
        );
        if failing.is_empty() {
            let module = module.expect("a module when nothing is rejected");
            assert!(module.funcs.len() > 536, "every POU has its functions");
            let jit = plcc_native::Jit::new(&module);
            assert!(jit.is_ok(), "{file}: the JIT fails: {:?}", jit.err());
        }
    }
}

#[test]
fn matiec_function_blocks_check() {
    let Some(libs) = libs_dir() else { return };
    let dir = libs.join("matiec_stdlib");
    // Each file alone, except the PID, which uses the integral and derivative FBs.
    let groups: &[&[&str]] = &[
        &["bistable.txt"],
        &["counter.txt"],
        &["edge_detection.txt"],
        &["hysteresis_st.txt"],
        &["ramp_st.txt"],
        &["rtc.txt"],
        &["sema.txt"],
        &["timer.txt"],
        &["derivative_st.txt"],
        &["integral_st.txt"],
        &["pid_st.txt", "integral_st.txt", "derivative_st.txt"],
        // The prototypes of every standard function (W0209: checked, not compiled).
        &["standard_functions.txt"],
    ];
    for group in groups {
        let texts: Vec<(String, Vec<u8>)> = group
            .iter()
            .map(|f| {
                (
                    f.to_string(),
                    std::fs::read(dir.join(f)).expect("matiec file"),
                )
            })
            .collect();
        let opts = BuildOptions {
            lang: Some(plcc_frontend::Lang::St),
            ..Default::default()
        };
        let build = build_sources(texts, &opts).expect("builds");
        let errors: Vec<String> = build
            .diagnostics
            .iter()
            .filter(|d| d.is_error())
            .map(|d| d.to_string())
            .collect();
        assert!(errors.is_empty(), "{group:?}: {errors:?}");
        assert!(build.module.is_some(), "{group:?}");
    }
}
