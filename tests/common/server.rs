//! `plcc serve` as a child process, for the tests that talk to it (`tests/serve.rs`
//! over Modbus and HTTP, `tests/workbench.rs` through a browser): started in the
//! package's directory, its standard error collected line by line, waited on for a
//! line, ended by SIGTERM or killed when dropped.

use std::io::{BufRead, BufReader};
use std::process::{Child, Command, ExitStatus, Stdio};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// How long the server may take to print a line or to end.
pub const SERVER_PATIENCE: Duration = Duration::from_secs(60);

/// A running `plcc serve` and the lines of its standard error so far.
pub struct Server {
    child: Child,
    lines: Arc<Mutex<Vec<String>>>,
}

impl Server {
    /// `plcc serve ARGS`, in the package's directory (relative paths are the
    /// repository's).
    pub fn start(args: &[&str]) -> Server {
        let mut child = Command::new(env!("CARGO_BIN_EXE_plcc"))
            .current_dir(env!("CARGO_MANIFEST_DIR"))
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

    /// The first line of standard error that starts with `prefix`, waiting for it;
    /// panics with every line printed if the server ends first.
    pub fn line(&mut self, prefix: &str) -> String {
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
            assert!(t.elapsed() < SERVER_PATIENCE, "no line `{prefix}`");
            std::thread::sleep(Duration::from_millis(20));
        }
    }

    /// The address after `http: listening on ` (as `http://host:port`).
    pub fn http_url(&mut self) -> String {
        let prefix = "http: listening on ";
        let line = self.line(prefix);
        format!("http://{}", &line[prefix.len()..])
    }

    /// The child's process id.
    pub fn id(&self) -> u32 {
        self.child.id()
    }

    /// Waits for the process to end (after a signal sent some other way).
    pub fn wait(&mut self) -> ExitStatus {
        self.child.wait().expect("wait")
    }

    /// Sends SIGTERM and waits for the end: the status and every line (the
    /// statistics line `scans: ` included, when it comes).
    pub fn terminate(mut self) -> (ExitStatus, Vec<String>) {
        // SAFETY: signalling our own child, which has not been waited for.
        unsafe {
            libc::kill(self.child.id() as libc::pid_t, libc::SIGTERM);
        }
        let t = Instant::now();
        let status = loop {
            if let Some(s) = self.child.try_wait().expect("wait") {
                break s;
            }
            assert!(
                t.elapsed() < SERVER_PATIENCE,
                "plcc serve did not end on SIGTERM"
            );
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
