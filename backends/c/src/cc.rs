//! The system's C compiler: finding it and building a shared library with it.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;

/// The compilers tried, in order, when none is named (after `$CC`).
const CANDIDATES: [&str; 3] = ["cc", "gcc", "clang"];

fn runs(cc: &str) -> bool {
    Command::new(cc)
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success())
}

/// The compiler to use: `named` if given (it must run), else `$CC`, else the first
/// of `cc`, `gcc`, `clang` that runs. The search without a name is done once.
pub fn find(named: Option<&str>) -> Result<String, String> {
    if let Some(n) = named {
        return if runs(n) {
            Ok(n.to_string())
        } else {
            Err(format!("the C compiler `{n}` does not run"))
        };
    }
    static FOUND: OnceLock<Option<String>> = OnceLock::new();
    FOUND
        .get_or_init(|| {
            std::env::var("CC")
                .ok()
                .filter(|c| !c.is_empty() && runs(c))
                .or_else(|| CANDIDATES.iter().find(|c| runs(c)).map(|c| c.to_string()))
        })
        .clone()
        .ok_or_else(|| "no C compiler found ($CC, cc, gcc, clang)".to_string())
}

/// The warnings every build of generated C must pass clean.
pub const WARNINGS: [&str; 3] = ["-Wall", "-Wextra", "-Werror"];

/// The flags of a sanitizer (`undefined` or `address`), which stop at the first
/// error they find.
pub fn sanitizer_flags(sanitize: &str) -> Vec<&'static str> {
    match sanitize {
        "undefined" => vec![
            "-fsanitize=undefined,float-cast-overflow",
            "-fno-sanitize-recover=all",
        ],
        "address" => vec![
            "-fsanitize=address,undefined,float-cast-overflow",
            "-fno-sanitize-recover=all",
        ],
        _ => Vec::new(),
    }
}

/// Builds `sources` (in `dir`) into the shared library `out` as C99, without
/// contracting floating-point operations (so every operation rounds as the IR says).
/// The error is the compiler's output.
pub fn shared_library(
    cc: &str,
    dir: &Path,
    sources: &[&str],
    out: &Path,
    opt: u8,
    extra: &[&str],
) -> Result<(), String> {
    let mut cmd = Command::new(cc);
    cmd.current_dir(dir)
        .arg("-std=c99")
        .arg(format!("-O{opt}"))
        .args(["-fPIC", "-shared", "-ffp-contract=off", "-fno-math-errno"])
        .args(WARNINGS)
        .args(extra)
        .arg("-I.")
        .arg("-o")
        .arg(out)
        .args(sources)
        .arg("-lm");
    run(cmd)
}

/// Runs a compiler command; the error is what it printed.
pub fn run(mut cmd: Command) -> Result<(), String> {
    let shown = format!("{cmd:?}");
    let o = cmd
        .output()
        .map_err(|e| format!("cannot run the C compiler: {e}"))?;
    if o.status.success() {
        return Ok(());
    }
    let mut msg = String::from_utf8_lossy(&o.stderr).into_owned();
    msg.push_str(&String::from_utf8_lossy(&o.stdout));
    const MAX: usize = 4000;
    if msg.len() > MAX {
        let mut cut = MAX;
        while !msg.is_char_boundary(cut) {
            cut -= 1;
        }
        msg.truncate(cut);
        msg.push_str("\n…");
    }
    Err(format!("{shown} failed:\n{msg}"))
}

/// A fresh directory of its own under the system's temporary directory, removed
/// when dropped.
pub struct TempDir(PathBuf);

impl TempDir {
    /// Creates one.
    pub fn new() -> std::io::Result<TempDir> {
        use std::sync::atomic::{AtomicU64, Ordering};
        static NEXT: AtomicU64 = AtomicU64::new(0);
        let base = std::env::temp_dir();
        loop {
            let n = NEXT.fetch_add(1, Ordering::Relaxed);
            let p = base.join(format!("plcc-c-{}-{n}", std::process::id()));
            match std::fs::create_dir(&p) {
                Ok(()) => return Ok(TempDir(p)),
                Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => continue,
                Err(e) => return Err(e),
            }
        }
    }

    /// Its path.
    pub fn path(&self) -> &Path {
        &self.0
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}
