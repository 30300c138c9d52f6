//! Running the `plcc` binary from a test: the command in the repository's folder,
//! and its output as text.

use std::process::{Command, Output};

/// `plcc ARGS…` run in the repository's folder (paths relative to it work).
pub fn plcc(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_plcc"))
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("plcc runs")
}

/// What the command printed on standard output.
pub fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// What the command printed on standard error.
pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}
