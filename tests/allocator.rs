//! The allocator's settings: mimalloc gives no memory back to the OS as plcc ends
//! (`src/main.rs`), unless `MIMALLOC_PURGE_DELAY` says otherwise. mimalloc's own
//! statistics (`MIMALLOC_SHOW_STATS`) count the purges.

use std::process::Command;

/// How many purges mimalloc reports for `plcc check` of `file` with `env` set.
fn purges(file: &std::path::Path, env: &[(&str, &str)]) -> u64 {
    let out = Command::new(env!("CARGO_BIN_EXE_plcc"))
        .args(["check", file.to_str().unwrap()])
        .env("MIMALLOC_SHOW_STATS", "1")
        .envs(env.iter().copied())
        .output()
        .expect("plcc runs");
    let text = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{text}");
    let line = text
        .lines()
        .find(|l| l.trim_start().starts_with("purges"))
        .unwrap_or_else(|| panic!("no purge count in mimalloc's statistics:\n{text}"));
    line.split(':')
        .nth(1)
        .and_then(|v| v.split_whitespace().next())
        .and_then(|v| v.parse().ok())
        .unwrap_or_else(|| panic!("cannot read `{line}`"))
}

#[test]
fn check_purges_no_memory_unless_mimalloc_purge_delay_is_set() {
    // Large enough to have freed memory to purge (bodies are dropped once checked).
    let text: String = (0..600)
        .map(|k| {
            format!(
                "FUNCTION_BLOCK F{k}\nVAR_INPUT a : INT; END_VAR\nVAR x : INT; y : DINT; END_VAR\n\
                 x := (a * {k}) - (x + 1);\nIF x > 3 THEN x := 0; y := y + x; END_IF;\n\
                 FOR x := 1 TO 10 DO y := y + x * a; END_FOR;\nEND_FUNCTION_BLOCK\n"
            )
        })
        .collect();
    let dir = std::env::temp_dir().join(format!("plcc-alloc-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("many.st");
    std::fs::write(&file, text).unwrap();
    let kept = purges(&file, &[]);
    let purged = purges(&file, &[("MIMALLOC_PURGE_DELAY", "0")]);
    std::fs::remove_dir_all(&dir).ok();
    assert_eq!(kept, 0, "plcc check purged memory");
    assert!(
        purged > 0,
        "with a purge delay of 0 mimalloc purged nothing: the count is not read right"
    );
}
