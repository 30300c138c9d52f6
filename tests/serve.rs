//! `plcc serve` as a child process: it starts, scans in real time, and ends with
//! status 0 on SIGTERM after printing its statistics.
//!
//! Nothing here asserts on speed: conditions are polled with generous timeouts, so a
//! loaded machine only makes the tests slower.

use std::io::{BufRead, BufReader};
use std::path::PathBuf;
use std::process::{Child, Command, ExitStatus, Stdio};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// How long any condition may take to come true.
const PATIENCE: Duration = Duration::from_secs(60);

fn program(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/serve")
        .join(name)
}

/// A running `plcc serve` and the lines of its standard error so far.
struct Server {
    child: Child,
    lines: Arc<Mutex<Vec<String>>>,
}

impl Server {
    fn start(args: &[&str]) -> Server {
        let mut child = Command::new(env!("CARGO_BIN_EXE_plcc"))
            .arg("serve")
            .args(args)
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .expect("plcc starts");
        let lines = Arc::new(Mutex::new(Vec::new()));
        let stderr = child.stderr.take().expect("piped");
        let sink = Arc::clone(&lines);
        std::thread::spawn(move || {
            for line in BufReader::new(stderr).lines() {
                let Ok(line) = line else { break };
                sink.lock().unwrap().push(line);
            }
        });
        Server { child, lines }
    }

    /// The first line of standard error that starts with `prefix`, waiting for it.
    fn line(&mut self, prefix: &str) -> String {
        let t = Instant::now();
        loop {
            if let Some(l) = self
                .lines
                .lock()
                .unwrap()
                .iter()
                .find(|l| l.starts_with(prefix))
            {
                return l.clone();
            }
            if let Ok(Some(status)) = self.child.try_wait() {
                // Let the reader take the last lines.
                std::thread::sleep(Duration::from_millis(200));
                panic!(
                    "plcc serve ended ({status}) before printing `{prefix}`:\n{}",
                    self.lines.lock().unwrap().join("\n")
                );
            }
            assert!(t.elapsed() < PATIENCE, "no line `{prefix}`");
            std::thread::sleep(Duration::from_millis(20));
        }
    }

    /// Sends SIGTERM and waits for the end: the status and every line.
    fn terminate(mut self) -> (ExitStatus, Vec<String>) {
        // SAFETY: signalling our own child, which has not been waited for.
        unsafe {
            libc::kill(self.child.id() as libc::pid_t, libc::SIGTERM);
        }
        let t = Instant::now();
        let status = loop {
            if let Some(s) = self.child.try_wait().expect("wait") {
                break s;
            }
            assert!(t.elapsed() < PATIENCE, "plcc serve did not end on SIGTERM");
            std::thread::sleep(Duration::from_millis(20));
        };
        let t = Instant::now();
        while t.elapsed() < Duration::from_secs(5)
            && !self
                .lines
                .lock()
                .unwrap()
                .iter()
                .any(|l| l.starts_with("scans: "))
        {
            std::thread::sleep(Duration::from_millis(20));
        }
        let lines = self.lines.lock().unwrap().clone();
        (status, lines)
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        if let Ok(None) = self.child.try_wait() {
            let _ = self.child.kill();
            let _ = self.child.wait();
        }
    }
}

/// The number after `scans: ` in the statistics line.
fn scans_in(line: &str) -> u64 {
    line.strip_prefix("scans: ")
        .and_then(|r| r.split(',').next())
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("no scan count in `{line}`"))
}

#[test]
fn serve_scans_until_sigterm_and_exits_0() {
    let plant = program("plant.st");
    let mut s = Server::start(&[plant.to_str().unwrap(), "--cycle-ms", "5"]);
    assert_eq!(s.line("cycle: "), "cycle: 5 ms (--cycle-ms)");
    let serving = s.line("serving: ");
    assert!(serving.contains("12 located variable(s)"), "{serving}");
    // Let it scan a little.
    std::thread::sleep(Duration::from_millis(300));
    let (status, lines) = s.terminate();
    assert!(status.success(), "{status}: {}", lines.join("\n"));
    let stats = lines
        .iter()
        .find(|l| l.starts_with("scans: "))
        .unwrap_or_else(|| panic!("no statistics in:\n{}", lines.join("\n")));
    assert!(scans_in(stats) > 0, "{stats}");
    assert!(stats.contains("overruns: "), "{stats}");
}

#[test]
fn serve_reports_bad_programs_and_targets() {
    let bad = Command::new(env!("CARGO_BIN_EXE_plcc"))
        .args([
            "serve",
            program("plant.st").to_str().unwrap(),
            "--target",
            "nope",
        ])
        .output()
        .expect("plcc runs");
    assert_eq!(bad.status.code(), Some(2));
    let dir = std::env::temp_dir().join(format!("plcc-serve-bad-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let src = dir.join("bad.st");
    std::fs::write(&src, "PROGRAM p VAR x : INT; END_VAR x := ; END_PROGRAM\n").unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_plcc"))
        .args(["serve", src.to_str().unwrap()])
        .output()
        .expect("plcc runs");
    assert_eq!(out.status.code(), Some(1));
    let _ = std::fs::remove_dir_all(&dir);
}
