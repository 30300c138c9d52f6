//! Notices of tests that skip part of their work because something they need is not
//! here (`../shared` beside the checkout, gputils, a C compiler, avr-gcc): written
//! to standard error past libtest's output capture, so that a passing run shows
//! them, and appended to `skipped.txt` in Cargo's `CARGO_TARGET_TMPDIR`, which
//! `.ci/run` prints as a summary after the tests.

use std::io::Write;
use std::path::Path;

/// The file the notices are appended to.
pub fn log_file() -> std::path::PathBuf {
    Path::new(env!("CARGO_TARGET_TMPDIR")).join("skipped.txt")
}

/// Shows `what` (what is skipped and why) and keeps it for the summary.
pub fn notice(what: &str) {
    let test = std::thread::current()
        .name()
        .unwrap_or("a test")
        .to_string();
    let line = format!("notice: {test}: {what}\n");
    // `std::io::stderr()` written directly is not captured (only the print
    // macros are).
    let _ = std::io::stderr().lock().write_all(line.as_bytes());
    let file = std::fs::OpenOptions::new()
        .create(true)
        .append(true)
        .open(log_file());
    if let Ok(mut f) = file {
        let _ = f.write_all(line.as_bytes());
    }
}
