//! `plcc serve` as a child process: it starts, scans in real time, and ends with
//! status 0 on SIGTERM after printing its statistics.
//!
//! Nothing here asserts on speed: conditions are polled with generous timeouts, so a
//! loaded machine only makes the tests slower.

use std::path::PathBuf;
use std::process::Command;
use std::time::{Duration, Instant};

#[path = "common/rng.rs"]
mod rng;
use rng::Rng;
#[path = "common/server.rs"]
#[allow(dead_code)]
mod server;
use server::Server;

/// How long any condition may take to come true.
const PATIENCE: Duration = server::SERVER_PATIENCE;

fn program(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/serve")
        .join(name)
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
    let mut s = Server::start(&[
        plant.to_str().unwrap(),
        "--cycle-ms",
        "5",
        "--modbus",
        "none",
        "--http",
        "127.0.0.1:0",
    ]);
    assert_eq!(s.line("cycle: "), "cycle: 5 ms (--cycle-ms)");
    let serving = s.line("serving: ");
    assert!(serving.contains("12 located variable(s)"), "{serving}");
    let api = http_addr(&mut s);
    until("scans", true, || {
        status_of(api)["scans"].as_u64().unwrap() > 10
    });
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

/// The address the Modbus server listens on, from its line.
fn modbus_addr(s: &mut Server) -> std::net::SocketAddr {
    let line = s.line("modbus: listening on ");
    line["modbus: listening on ".len()..]
        .parse()
        .unwrap_or_else(|_| panic!("no address in `{line}`"))
}

/// A Modbus client with a generous timeout.
fn client(addr: std::net::SocketAddr) -> tokio_modbus::client::sync::Context {
    let mut c = tokio_modbus::client::sync::tcp::connect(addr).expect("connects");
    c.set_timeout(PATIENCE);
    c
}

/// Polls `read` until it gives `want`.
fn until<T: PartialEq + std::fmt::Debug>(what: &str, want: T, mut read: impl FnMut() -> T) {
    let t = Instant::now();
    loop {
        let got = read();
        if got == want {
            return;
        }
        assert!(t.elapsed() < PATIENCE, "{what}: got {got:?}, want {want:?}");
        std::thread::sleep(Duration::from_millis(10));
    }
}

fn holding(c: &mut tokio_modbus::client::sync::Context, addr: u16, n: u16) -> Vec<u16> {
    use tokio_modbus::prelude::SyncReader;
    c.read_holding_registers(addr, n)
        .expect("transport")
        .expect("no exception")
}

fn coils(c: &mut tokio_modbus::client::sync::Context, addr: u16, n: u16) -> Vec<bool> {
    use tokio_modbus::prelude::SyncReader;
    c.read_coils(addr, n)
        .expect("transport")
        .expect("no exception")
}

/// `total` (%MD0, holding registers 2048-2049), which the program counts up every scan.
fn total(c: &mut tokio_modbus::client::sync::Context) -> u32 {
    let w = holding(c, 2048, 2);
    (w[0] as u32) << 16 | w[1] as u32
}

#[test]
fn program_logic_through_a_modbus_round_trip() {
    use tokio_modbus::prelude::{ExceptionCode, SyncReader, SyncWriter};
    let plant = program("plant.st");
    let mut s = Server::start(&[
        plant.to_str().unwrap(),
        "--cycle-ms",
        "2",
        "--modbus",
        "127.0.0.1:0",
        "--http",
        "none",
    ]);
    let addr = modbus_addr(&mut s);
    let mut c1 = client(addr);
    let mut c2 = client(addr);
    // Arithmetic: a, b (%MW0, %MW1 = holding 1024, 1025) to sum (%QW0 = holding 0)
    // and big (%ML0 = holding 4096-4099, high word first).
    c1.write_multiple_registers(1024, &[7, 5]).unwrap().unwrap();
    until("sum", vec![12], || holding(&mut c2, 0, 1));
    until("big", vec![0, 0, 0x6A, 0xCFC0], || {
        holding(&mut c2, 4096, 4)
    });
    // The second client writes, the first sees it; negative values wrap as INT.
    c2.write_single_register(1024, (-3i16) as u16)
        .unwrap()
        .unwrap();
    c2.write_single_register(1025, 1).unwrap().unwrap();
    until("negative sum", vec![(-2i16) as u16], || {
        holding(&mut c1, 0, 1)
    });
    // The latch: a client's start button (coil 8, %QX1.0) sets running (coil 0),
    // which holds after the program has released the button; stop (coil 9) resets it.
    c1.write_single_coil(8, true).unwrap().unwrap();
    until("running", vec![true], || coils(&mut c2, 0, 1));
    until("start released", vec![false, false], || {
        coils(&mut c2, 8, 2)
    });
    assert_eq!(coils(&mut c1, 0, 1), vec![true]);
    c2.write_multiple_coils(9, &[true]).unwrap().unwrap();
    until("stopped", vec![false], || coils(&mut c1, 0, 1));
    // The scans go on: total (%MD0) counts them.
    let t0 = total(&mut c1);
    until("total grows", true, || total(&mut c1) > t0 + 5);
    // Addresses no variable is located at hold what clients write.
    c1.write_single_register(500, 1234).unwrap().unwrap();
    c1.write_single_coil(100, true).unwrap().unwrap();
    let t1 = total(&mut c1);
    until("scans after the writes", true, || total(&mut c2) > t1 + 5);
    assert_eq!(holding(&mut c2, 500, 1), vec![1234]);
    assert_eq!(coils(&mut c2, 100, 1), vec![true]);
    // Discrete inputs and input registers read; nothing drives them here.
    assert_eq!(
        c1.read_discrete_inputs(0, 2).unwrap().unwrap(),
        vec![false, false]
    );
    assert_eq!(c1.read_input_registers(0, 1).unwrap().unwrap(), vec![0]);
    // Exceptions: outside the tables, quantities the protocol refuses.
    assert_eq!(
        c1.read_holding_registers(8190, 5).unwrap(),
        Err(ExceptionCode::IllegalDataAddress)
    );
    assert_eq!(
        c1.read_input_registers(1024, 1).unwrap(),
        Err(ExceptionCode::IllegalDataAddress)
    );
    assert_eq!(
        c1.read_coils(0, 2001).unwrap(),
        Err(ExceptionCode::IllegalDataValue)
    );
    assert_eq!(
        c1.write_single_register(8192, 1).unwrap(),
        Err(ExceptionCode::IllegalDataAddress)
    );
    drop((c1, c2));
    let (status, lines) = s.terminate();
    assert!(status.success(), "{status}: {}", lines.join("\n"));
}

/// A Modbus TCP frame: the MBAP header (transaction 1, protocol 0, unit 1) and `pdu`.
fn frame(pdu: &[u8]) -> Vec<u8> {
    let len = (pdu.len() + 1) as u16;
    let mut f = vec![0, 1, 0, 0, (len >> 8) as u8, len as u8, 1];
    f.extend_from_slice(pdu);
    f
}

/// Sends `bytes` on a connection of its own, closes the writing side and reads
/// whatever comes back until the server closes.
fn exchange(addr: std::net::SocketAddr, bytes: &[u8]) -> Vec<u8> {
    use std::io::{Read, Write};
    let mut sock = std::net::TcpStream::connect(addr).expect("connects");
    sock.set_read_timeout(Some(PATIENCE)).unwrap();
    // The server may close before reading everything: a failed write is fine.
    let _ = sock.write_all(bytes);
    let _ = sock.shutdown(std::net::Shutdown::Write);
    let mut back = Vec::new();
    let _ = sock.read_to_end(&mut back);
    back
}

#[test]
fn a_thousand_malformed_modbus_frames_leave_the_plc_scanning() {
    use tokio_modbus::prelude::SyncWriter;
    let plant = program("plant.st");
    let mut s = Server::start(&[
        plant.to_str().unwrap(),
        "--cycle-ms",
        "2",
        "--modbus",
        "127.0.0.1:0",
        "--http",
        "none",
    ]);
    let addr = modbus_addr(&mut s);
    let mut c = client(addr);
    c.write_multiple_registers(1024, &[7, 5]).unwrap().unwrap();
    c.write_single_coil(100, true).unwrap().unwrap();
    until("sum", vec![12], || holding(&mut c, 0, 1));
    let before = total(&mut c);
    let mut rng = Rng::new(21);
    let mut exceptions = 0;
    for i in 0..1000 {
        // (the bytes, the exception expected: None when the server may close or
        // answer anything that is no write)
        let (bytes, want): (Vec<u8>, Option<(u8, u8)>) = match i % 6 {
            // Garbage: a frame of a protocol that is not Modbus, or fewer bytes than
            // a header.
            0 => {
                let n = 1 + rng.next_u64() as usize % 40;
                let mut b: Vec<u8> = (0..n).map(|_| rng.next_u64() as u8).collect();
                if n > 3 {
                    b[2] = 0x80 | (rng.next_u64() as u8);
                } else {
                    b.truncate(6);
                }
                (b, None)
            }
            // Function codes the server does not implement: unknown ones, and known
            // ones it does not serve (report server id, mask write, read/write
            // registers, device identification), well formed.
            1 => {
                let pdu: Vec<u8> = match rng.next_u64() % 6 {
                    0 => vec![0x11],
                    1 => vec![0x16, 0, 4, 0xFF, 0, 0, 1],
                    2 => vec![0x17, 0, 0, 0, 1, 0, 4, 0, 1, 2, 0, 9],
                    3 => vec![0x2B, 0x0E, 1, 0],
                    _ => {
                        let fc = [0x07, 0x08, 0x0B, 0x0C, 0x14, 0x15, 0x18, 0x41, 0x64, 0x7F]
                            [rng.next_u64() as usize % 10];
                        vec![
                            fc,
                            (rng.next_u64() as u8),
                            (rng.next_u64() as u8),
                            (rng.next_u64() as u8),
                            (rng.next_u64() as u8),
                        ]
                    }
                };
                (frame(&pdu), Some((pdu[0] | 0x80, 1)))
            }
            // Addresses outside the tables.
            2 => {
                let (fc, a, n): (u8, u16, u16) = match rng.next_u64() % 5 {
                    0 => (1, 8000, 500),
                    1 => (2, 8191, 2),
                    2 => (3, 8100, 100),
                    3 => (4, 1000, 25),
                    _ => (6, 8192 + rng.next_u64() as u16 % 1000, 1),
                };
                (
                    frame(&[fc, (a >> 8) as u8, a as u8, (n >> 8) as u8, n as u8]),
                    Some((fc | 0x80, 2)),
                )
            }
            // Quantities the protocol refuses.
            3 => {
                let (fc, n): (u8, u16) = match rng.next_u64() % 3 {
                    0 => (3, 0),
                    1 => (3, 126 + rng.next_u64() as u16 % 1000),
                    _ => (1, 2001 + rng.next_u64() as u16 % 1000),
                };
                (
                    frame(&[fc, 0, 0, (n >> 8) as u8, n as u8]),
                    Some((fc | 0x80, 3)),
                )
            }
            // Truncated: the header promises more than comes.
            4 => {
                let mut f = frame(&[16, 4, 0, 0, 2, 4, 0xAA, 0xBB, 0xCC, 0xDD]);
                let cut = 1 + rng.next_u64() as usize % (f.len() - 1);
                f.truncate(cut);
                (f, None)
            }
            // Inconsistent: a write whose byte count disagrees with its quantity, a
            // header length of 0 or 1.
            _ => match rng.next_u64() % 3 {
                0 => (frame(&[16, 4, 0, 0, 2, 3, 1, 2, 3]), None),
                1 => (vec![0, 1, 0, 0, 0, 0, 1, 3], None),
                _ => (vec![0, 1, 0, 0, 0, 1, 1], None),
            },
        };
        let back = exchange(addr, &bytes);
        if let Some((fc, code)) = want {
            // MBAP (7 bytes), the function code with the high bit, the code.
            assert_eq!(
                back.get(7..9),
                Some(&[fc, code][..]),
                "frame {i} {bytes:02x?}: answer {back:02x?}"
            );
            exceptions += 1;
        }
    }
    assert!(exceptions > 500);
    // The scans went on and nothing was written.
    until("scans after the flood", true, || total(&mut c) > before + 5);
    assert_eq!(holding(&mut c, 1024, 2), vec![7, 5]);
    assert_eq!(holding(&mut c, 0, 1), vec![12]);
    assert_eq!(coils(&mut c, 100, 1), vec![true]);
    assert_eq!(holding(&mut c, 4, 2), vec![0, 0]);
    drop(c);
    let (status, lines) = s.terminate();
    assert!(status.success(), "{status}: {}", lines.join("\n"));
}

/// The address the HTTP API listens on, from its line.
fn http_addr(s: &mut Server) -> std::net::SocketAddr {
    let line = s.line("http: listening on ");
    line["http: listening on ".len()..]
        .parse()
        .unwrap_or_else(|_| panic!("no address in `{line}`"))
}

/// One HTTP/1.1 request on a connection of its own: the status and the body (JSON,
/// or `null` when the body is not JSON).
fn http(
    addr: std::net::SocketAddr,
    method: &str,
    path: &str,
    body: Option<&str>,
    token: Option<&str>,
) -> (u16, serde_json::Value) {
    let mut req = format!("{method} {path} HTTP/1.1\r\nHost: plc\r\nConnection: close\r\n");
    if let Some(t) = token {
        req.push_str(&format!("Authorization: Bearer {t}\r\n"));
    }
    let body = body.unwrap_or("");
    req.push_str(&format!("Content-Length: {}\r\n\r\n{body}", body.len()));
    let back = exchange(addr, req.as_bytes());
    let text = String::from_utf8_lossy(&back);
    let status = text
        .split(' ')
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or_else(|| panic!("{method} {path}: no status in `{text}`"));
    let json = text
        .split_once("\r\n\r\n")
        .and_then(|(_, b)| serde_json::from_str(b).ok())
        .unwrap_or(serde_json::Value::Null);
    (status, json)
}

/// GET /api/vars/PATH's value.
fn value(addr: std::net::SocketAddr, path: &str) -> serde_json::Value {
    let (status, j) = http(addr, "GET", &format!("/api/vars/{path}"), None, None);
    assert_eq!(status, 200, "GET {path}: {j}");
    j["value"].clone()
}

fn put(addr: std::net::SocketAddr, path: &str, v: serde_json::Value, token: Option<&str>) -> u16 {
    let body = serde_json::json!({ "value": v }).to_string();
    http(
        addr,
        "PUT",
        &format!("/api/vars/{path}"),
        Some(&body),
        token,
    )
    .0
}

fn status_of(addr: std::net::SocketAddr) -> serde_json::Value {
    let (status, j) = http(addr, "GET", "/api/status", None, None);
    assert_eq!(status, 200, "{j}");
    j
}

#[test]
fn http_api_reads_writes_forces_and_controls() {
    use serde_json::json;
    let plant = program("plant.st");
    let mut s = Server::start(&[
        plant.to_str().unwrap(),
        "--cycle-ms",
        "2",
        "--modbus",
        "127.0.0.1:0",
        "--http",
        "127.0.0.1:0",
    ]);
    let mb = modbus_addr(&mut s);
    let api = http_addr(&mut s);
    let mut c = client(mb);
    // Every variable with its type; globals by their plain names.
    let (st, list) = http(api, "GET", "/api/vars", None, None);
    assert_eq!(st, 200);
    let list = list.as_array().expect("an array").clone();
    assert!(list.contains(&json!({"path": "plant.level", "type": "INT"})));
    assert!(list.contains(&json!({"path": "plant.scans", "type": "UDINT"})));
    assert!(list.contains(&json!({"path": "total", "type": "DINT"})));
    assert_eq!(list.len(), 14);
    let (st, one) = http(api, "GET", "/api/vars/PLANT.Level", None, None);
    assert_eq!(
        (st, &one["path"], &one["type"]),
        (200, &json!("plant.level"), &json!("INT"))
    );
    // A located input written over HTTP goes to the input image too.
    assert_eq!(put(api, "plant.a", json!(3), None), 200);
    assert_eq!(put(api, "plant.level", json!(60), None), 200);
    until("scaled", json!(123), || value(api, "plant.scaled"));
    {
        use tokio_modbus::prelude::SyncReader;
        assert_eq!(c.read_input_registers(0, 1).unwrap().unwrap(), vec![60]);
    }
    assert_eq!(holding(&mut c, 1, 1), vec![123]);
    assert_eq!(value(api, "plant.alarm"), json!(false));
    assert_eq!(put(api, "plant.level", json!(101), None), 200);
    until("alarm", json!(true), || value(api, "plant.alarm"));
    // The latch through the discrete inputs.
    assert_eq!(put(api, "plant.start", json!(true), None), 200);
    until("running", vec![true], || coils(&mut c, 0, 1));
    assert_eq!(put(api, "plant.start", json!(false), None), 200);
    assert_eq!(put(api, "plant.stop", json!(true), None), 200);
    until("stopped", json!(false), || value(api, "plant.running"));
    // Forcing holds against the program (stop is TRUE) and the I/O (a client's
    // write of coil 0).
    let (st, _) = http(
        api,
        "POST",
        "/api/force/plant.running",
        Some(r#"{"value": true}"#),
        None,
    );
    assert_eq!(st, 200);
    assert_eq!(value(api, "plant.running"), json!(true));
    {
        use tokio_modbus::prelude::SyncWriter;
        c.write_single_coil(0, false).unwrap().unwrap();
    }
    let t0 = total(&mut c);
    until("scans while forced", true, || total(&mut c) > t0 + 5);
    assert_eq!(coils(&mut c, 0, 1), vec![true]);
    assert_eq!(value(api, "plant.running"), json!(true));
    assert_eq!(status_of(api)["forced"], json!(1));
    assert_eq!(put(api, "plant.running", json!(false), None), 409);
    // Unforced, the program has it again.
    assert_eq!(
        http(api, "DELETE", "/api/force/plant.running", None, None).0,
        200
    );
    until("released", json!(false), || value(api, "plant.running"));
    assert_eq!(
        http(api, "DELETE", "/api/force/plant.running", None, None).0,
        404
    );
    // A forced input holds against the I/O image.
    let (st, _) = http(
        api,
        "POST",
        "/api/force/plant.level",
        Some(r#"{"value": 7}"#),
        None,
    );
    assert_eq!(st, 200);
    until("scaled from the forced level", json!(17), || {
        value(api, "plant.scaled")
    });
    assert_eq!(
        http(api, "DELETE", "/api/force/plant.level", None, None).0,
        200
    );
    until("scaled from the image", json!(205), || {
        value(api, "plant.scaled")
    });
    // Stop, start, restart.
    assert_eq!(http(api, "POST", "/api/stop", None, None).0, 200);
    assert_eq!(status_of(api)["state"], json!("stopped"));
    let frozen = value(api, "plant.scans");
    std::thread::sleep(Duration::from_millis(100));
    assert_eq!(value(api, "plant.scans"), frozen);
    assert_eq!(http(api, "POST", "/api/start", None, None).0, 200);
    assert_eq!(status_of(api)["state"], json!("running"));
    until("scans again", true, || {
        value(api, "plant.scans").as_u64() > frozen.as_u64()
    });
    assert_eq!(value(api, "plant.a"), json!(3));
    assert_eq!(
        http(api, "POST", "/api/restart?mode=cold", None, None).0,
        200
    );
    assert_eq!(
        value(api, "plant.a"),
        json!(0),
        "cold restart: initial values"
    );
    let st = status_of(api);
    assert_eq!(st["state"], json!("running"));
    assert!(st["scans"].as_u64().unwrap() > 0);
    for series in ["exec_us", "lateness_us"] {
        let n = |k: &str| st[series][k].as_u64().unwrap_or_else(|| panic!("{st}"));
        assert!(
            n("min") <= n("p50") && n("p50") <= n("p99") && n("p99") <= n("max"),
            "{st}"
        );
    }
    drop(c);
    let (status, lines) = s.terminate();
    assert!(status.success(), "{status}: {}", lines.join("\n"));
}

#[test]
fn a_thousand_bad_api_requests_leave_the_plc_scanning() {
    use serde_json::json;
    let dir = std::env::temp_dir().join(format!("plcc-serve-token-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let token_file = dir.join("token");
    std::fs::write(&token_file, "s3cret-token\n").unwrap();
    let plant = program("plant.st");
    let mut s = Server::start(&[
        plant.to_str().unwrap(),
        "--cycle-ms",
        "2",
        "--modbus",
        "none",
        "--http",
        "127.0.0.1:0",
        "--token-file",
        token_file.to_str().unwrap(),
    ]);
    let api = http_addr(&mut s);
    let tok = Some("s3cret-token");
    assert_eq!(put(api, "plant.a", json!(7), tok), 200);
    assert_eq!(put(api, "plant.b", json!(5), tok), 200);
    until("sum", json!(12), || value(api, "plant.sum"));
    let scans_before = status_of(api)["scans"].as_u64().unwrap();
    let mut rng = Rng::new(1000);
    let mut statuses = std::collections::BTreeMap::new();
    for i in 0..1000 {
        let r = rng.next_u64();
        let (method, path, body, token): (&str, String, Option<String>, Option<&str>) = match i % 10
        {
            // Bad JSON.
            0 => {
                let bodies = [
                    "{",
                    "{\"value\": }",
                    "value=3",
                    "[1, 2",
                    "\u{0}\u{1}",
                    "{\"value\": 1} trailing",
                    "",
                ];
                let b = bodies[r as usize % bodies.len()];
                ("PUT", "/api/vars/plant.a".into(), Some(b.into()), tok)
            }
            // Not {"value": ...}.
            1 => {
                let bodies = ["{}", "{\"v\": 1}", "{\"value\": 1, \"x\": 2}", "1", "null"];
                let b = bodies[r as usize % bodies.len()];
                ("PUT", "/api/vars/plant.b".into(), Some(b.into()), tok)
            }
            // Unknown variables and malformed paths.
            2 => {
                let paths = [
                    "nope",
                    "plant.nope",
                    "plant.a.b",
                    "plant.a[1]",
                    "plant%5",
                    "%FF%FE",
                    "",
                    "plant..a",
                    "__init",
                ];
                let p = paths[r as usize % paths.len()];
                let m = ["GET", "PUT", "POST"][(r >> 8) as usize % 3];
                let route = if m == "POST" { "force" } else { "vars" };
                (
                    m,
                    format!("/api/{route}/{p}"),
                    Some("{\"value\": 1}".into()),
                    tok,
                )
            }
            // Wrong types and values out of range.
            3 => {
                let cases = [
                    ("plant.a", "\"7\""),
                    ("plant.a", "true"),
                    ("plant.a", "1.5"),
                    ("plant.a", "40000"),
                    ("plant.a", "-40000"),
                    ("plant.a", "null"),
                    ("plant.start", "1"),
                    ("plant.start", "\"TRUE\""),
                    ("plant.scans", "-1"),
                    ("plant.scans", "[1]"),
                    ("total", "{\"x\": 1}"),
                    ("total", "3000000000"),
                ];
                let (p, v) = cases[r as usize % cases.len()];
                let route = if (r >> 8).is_multiple_of(2) {
                    "vars"
                } else {
                    "force"
                };
                let m = if route == "vars" { "PUT" } else { "POST" };
                (
                    m,
                    format!("/api/{route}/{p}"),
                    Some(format!("{{\"value\": {v}}}")),
                    tok,
                )
            }
            // No token, or a wrong one, on a write, a force or a control call.
            4 => {
                let t = [None, Some("wrong"), Some(""), Some("s3cret-token-x")][r as usize % 4];
                let (m, p, b) = [
                    ("PUT", "/api/vars/plant.a", Some("{\"value\": 99}")),
                    ("POST", "/api/force/plant.a", Some("{\"value\": 99}")),
                    ("DELETE", "/api/force/plant.a", None),
                    ("POST", "/api/stop", None),
                    ("POST", "/api/restart", None),
                    ("POST", "/api/program", Some("PROGRAM p END_PROGRAM")),
                ][(r >> 8) as usize % 6];
                (m, p.into(), b.map(String::from), t)
            }
            // Unknown resources and methods.
            5 => {
                let (m, p) = [
                    ("GET", "/assets/nope.js"),
                    ("GET", "/api"),
                    ("GET", "/api/nope"),
                    ("DELETE", "/api/status"),
                    ("PUT", "/api/vars"),
                    ("GET", "/api/force/plant.a"),
                    ("POST", "/api/restart?mode=hot"),
                    ("PATCH", "/api/vars/plant.a"),
                    ("GET", "/api/vars/plant.a/extra"),
                ][r as usize % 9];
                (m, p.into(), None, tok)
            }
            // Strings where a number belongs, and the other way round.
            6 => (
                "PUT",
                "/api/vars/plant.level".into(),
                Some("{\"value\": \"T#1s\"}".into()),
                tok,
            ),
            // Unforcing what is not forced.
            7 => ("DELETE", "/api/force/plant.b".into(), None, tok),
            // A body too large.
            8 if i % 100 == 8 => (
                "PUT",
                "/api/vars/plant.a".into(),
                Some(format!("{{\"value\": \"{}\"}}", "x".repeat(70_000))),
                tok,
            ),
            // Integers written where a BOOL is, and floats in integers.
            _ => (
                "POST",
                "/api/force/plant.stop".into(),
                Some("{\"value\": 0}".into()),
                tok,
            ),
        };
        let (st, j) = http(api, method, &path, body.as_deref(), token);
        assert!(
            (400..500).contains(&st) || st == 501,
            "request {i}: {method} {path} {body:?}: {st} {j}"
        );
        *statuses.entry(st).or_insert(0) += 1;
    }
    // Every kind of refusal was met.
    for code in [400, 401, 404, 405, 413] {
        assert!(statuses.contains_key(&code), "no {code} among {statuses:?}");
    }
    // Garbage that is not HTTP at all: an error or a closed connection.
    for k in 0..50u64 {
        let junk: Vec<u8> = (0..(k % 30 + 1)).map(|_| rng.next_u64() as u8).collect();
        let _ = exchange(api, &junk);
    }
    // The scans went on; nothing was written, forced or stopped.
    until("scans after the requests", true, || {
        status_of(api)["scans"].as_u64().unwrap() > scans_before + 10
    });
    let st = status_of(api);
    assert_eq!(
        (&st["state"], &st["forced"]),
        (&json!("running"), &json!(0))
    );
    assert_eq!(value(api, "plant.a"), json!(7));
    assert_eq!(value(api, "plant.b"), json!(5));
    assert_eq!(value(api, "plant.sum"), json!(12));
    assert_eq!(value(api, "plant.stop"), json!(false));
    // With the token, the same calls work.
    assert_eq!(put(api, "plant.a", json!(8), tok), 200);
    until("sum", json!(13), || value(api, "plant.sum"));
    let (status, lines) = s.terminate();
    assert!(status.success(), "{status}: {}", lines.join("\n"));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn listening_beyond_loopback_needs_a_token() {
    let plant = program("plant.st");
    for args in [
        ["--http", "0.0.0.0:0", "--modbus", "none"],
        ["--http", "none", "--modbus", "0.0.0.0:0"],
    ] {
        let out = Command::new(env!("CARGO_BIN_EXE_plcc"))
            .arg("serve")
            .arg(&plant)
            .args(args)
            .output()
            .expect("plcc runs");
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        assert!(String::from_utf8_lossy(&out.stderr).contains("--token-file"));
    }
    let missing = Command::new(env!("CARGO_BIN_EXE_plcc"))
        .arg("serve")
        .arg(&plant)
        .args(["--token-file", "/nonexistent/token"])
        .output()
        .expect("plcc runs");
    assert_eq!(missing.status.code(), Some(2));
}

#[test]
fn retain_survives_restarts_of_the_server_and_warm_restarts() {
    use serde_json::json;
    let dir = std::env::temp_dir().join(format!("plcc-serve-retain-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("plc.retain");
    let prog = program("retained.st");
    let args = |http: &'static str| {
        vec![
            prog.to_str().unwrap().to_string(),
            "--cycle-ms".into(),
            "2".into(),
            "--modbus".into(),
            "127.0.0.1:0".into(),
            "--http".into(),
            http.into(),
            "--retain".into(),
            file.to_str().unwrap().to_string(),
        ]
    };
    let start = || {
        let a = args("127.0.0.1:0");
        Server::start(&a.iter().map(String::as_str).collect::<Vec<_>>())
    };
    // First run: no file yet.
    let mut s = start();
    assert_eq!(
        s.line("retain: "),
        format!(
            "retain: 5 variable(s), kept in {}, saved every 10 s and at the end",
            file.display()
        )
    );
    let api = http_addr(&mut s);
    assert_eq!(put(api, "keeper.name", json!("hello"), None), 200);
    assert_eq!(put(api, "keeper.level", json!(42), None), 200);
    assert_eq!(put(api, "keeper.when", json!("T#2s500ms"), None), 200);
    until("scans", true, || {
        value(api, "keeper.total").as_u64().unwrap() > 50
    });
    let (status, lines) = s.terminate();
    assert!(status.success(), "{status}: {}", lines.join("\n"));
    assert!(lines.iter().any(|l| l.starts_with("retain: saved to")));
    let saved: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&file).unwrap()).unwrap();
    assert_eq!(saved["plcc_retain"], json!(1));
    let values = saved["values"].as_object().unwrap();
    let mut names: Vec<&str> = values.keys().map(String::as_str).collect();
    names.sort();
    assert_eq!(
        names,
        [
            "$globals.g_count",
            "keeper.level",
            "keeper.name",
            "keeper.total",
            "keeper.when"
        ]
    );
    let total = values["keeper.total"].as_u64().unwrap();
    assert!(total > 50);
    assert_eq!(values["keeper.name"], json!("hello"));
    assert_eq!(values["keeper.when"], json!("T#2500ms"));
    // Second run: the retained values are back, the others start again.
    let mut s = start();
    let api = http_addr(&mut s);
    let mb = modbus_addr(&mut s);
    // total goes on from the saved value, plain from 0: read plain first, total
    // has counted at least as many scans since.
    let plain = value(api, "keeper.plain").as_u64().unwrap();
    let g_plain = value(api, "g_plain").as_i64().unwrap() as u64;
    let now = value(api, "keeper.total").as_u64().unwrap();
    assert!(
        now >= total + plain && now >= total + g_plain,
        "{plain} {g_plain} {total} {now}"
    );
    assert!(value(api, "g_count").as_i64().unwrap() as u64 >= total);
    assert_eq!(value(api, "keeper.name"), json!("hello"));
    assert_eq!(value(api, "keeper.when"), json!("T#2500ms"));
    assert_eq!(value(api, "keeper.level"), json!(42));
    assert_eq!(holding(&mut client(mb), 1029, 1), vec![42]);
    // A warm restart keeps them; a cold one does not.
    until("more scans", true, || {
        value(api, "keeper.plain").as_u64().unwrap() > 20
    });
    let before = value(api, "keeper.total").as_u64().unwrap();
    assert_eq!(
        http(api, "POST", "/api/restart?mode=warm", None, None).0,
        200
    );
    let plain = value(api, "keeper.plain").as_u64().unwrap();
    let now = value(api, "keeper.total").as_u64().unwrap();
    assert!(now >= before + plain, "{plain} {before} {now}");
    assert_eq!(value(api, "keeper.name"), json!("hello"));
    assert_eq!(
        http(api, "POST", "/api/restart?mode=cold", None, None).0,
        200
    );
    assert_eq!(value(api, "keeper.name"), json!("init"));
    assert_eq!(value(api, "keeper.when"), json!("T#1000ms"));
    let (status, lines) = s.terminate();
    assert!(status.success(), "{status}: {}", lines.join("\n"));
    // A file that is not a retain file: status 1, nothing served.
    std::fs::write(&file, "{\"values\": 3}").unwrap();
    let a = args("none");
    let out = Command::new(env!("CARGO_BIN_EXE_plcc"))
        .arg("serve")
        .args(&a)
        .output()
        .expect("plcc runs");
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("not a retain file"));
    // Values of variables the program no longer retains are skipped, with a warning.
    std::fs::write(
        &file,
        r#"{"plcc_retain": 1, "values": {"keeper.gone": 1, "keeper.total": "x", "keeper.level": 7}}"#,
    )
    .unwrap();
    let mut s = start();
    let api = http_addr(&mut s);
    s.line("warning: retained value not restored: `keeper.gone`");
    s.line("warning: retained value not restored: `keeper.total`");
    assert_eq!(value(api, "keeper.level"), json!(7));
    let (status, _) = s.terminate();
    assert!(status.success());
    let _ = std::fs::remove_dir_all(&dir);
}

/// Sends SIGKILL (no chance to save anything at the end) and waits for the end.
fn kill_9(mut s: Server) {
    // SAFETY: signalling our own child, which has not been waited for.
    unsafe {
        libc::kill(s.id() as libc::pid_t, libc::SIGKILL);
    }
    let status = s.wait();
    use std::os::unix::process::ExitStatusExt;
    assert_eq!(status.signal(), Some(libc::SIGKILL), "{status}");
}

/// The retain file's `keeper.total`, if the file is there. Whenever it is there it
/// must be a whole retain file: a periodic save is never seen half written.
fn saved_total(file: &std::path::Path) -> Option<u64> {
    let text = match std::fs::read_to_string(file) {
        Ok(t) => t,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return None,
        Err(e) => panic!("{}: {e}", file.display()),
    };
    let j: serde_json::Value =
        serde_json::from_str(&text).unwrap_or_else(|e| panic!("a torn retain file ({e}):\n{text}"));
    assert_eq!(j["plcc_retain"], serde_json::json!(1), "{text}");
    let values = j["values"].as_object().expect("values");
    assert_eq!(values.len(), 5, "{text}");
    Some(values["keeper.total"].as_u64().expect("keeper.total"))
}

/// Polls the retain file until `want` holds of its `keeper.total`.
fn until_saved(file: &std::path::Path, what: &str, want: impl Fn(u64) -> bool) -> u64 {
    let t = Instant::now();
    loop {
        if let Some(n) = saved_total(file).filter(|&n| want(n)) {
            return n;
        }
        assert!(t.elapsed() < PATIENCE, "never saved: {what}");
        std::thread::sleep(Duration::from_millis(10));
    }
}

#[test]
fn retain_is_saved_periodically_and_survives_kill_9() {
    use serde_json::json;
    let dir = std::env::temp_dir().join(format!("plcc-serve-retain9-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("plc.retain");
    let prog = program("retained.st");
    let start = |every: &str| {
        let f = file.to_str().unwrap();
        let p = prog.to_str().unwrap();
        Server::start(&[
            p,
            "--cycle-ms",
            "2",
            "--modbus",
            "none",
            "--http",
            "127.0.0.1:0",
            "--retain",
            f,
            "--retain-every",
            every,
        ])
    };
    // Saved only at the end: nothing is written while the PLC runs.
    let mut s = start("0");
    assert_eq!(
        s.line("retain: "),
        format!(
            "retain: 5 variable(s), kept in {}, saved at the end",
            file.display()
        )
    );
    let api = http_addr(&mut s);
    until("scans", true, || {
        value(api, "keeper.total").as_u64().unwrap() > 300
    });
    assert_eq!(saved_total(&file), None, "saved before the end");
    let (status, lines) = s.terminate();
    assert!(status.success(), "{status}: {}", lines.join("\n"));
    let first = saved_total(&file).expect("saved at the end");
    assert!(first > 300, "{first}");

    // Every 0.2 s: the file follows the counter while the PLC scans, and a kill -9
    // leaves the last whole file.
    let mut s = start("0.2");
    assert_eq!(
        s.line("retain: "),
        format!(
            "retain: 5 variable(s), kept in {}, saved every 0.2 s and at the end",
            file.display()
        )
    );
    let api = http_addr(&mut s);
    let a = until_saved(&file, "a first periodic save", |n| n > first);
    let b = until_saved(&file, "a second periodic save", |n| n > a);
    // The file is read before the API: the value saved was reached before.
    let now = value(api, "keeper.total").as_u64().unwrap();
    assert!(b <= now, "saved {b}, reached {now}");
    kill_9(s);
    let killed = saved_total(&file).expect("the file survives");
    assert!(killed >= b, "the file went back from {b} to {killed}");
    // Warm from the file: the counter goes on from the saved value, as do the
    // other retained variables; plain ones start from their initial values.
    let mut s = start("0.2");
    let api = http_addr(&mut s);
    let plain = value(api, "keeper.plain").as_u64().unwrap();
    let total = value(api, "keeper.total").as_u64().unwrap();
    assert!(total >= killed + plain, "{killed} {plain} {total}");
    assert!(value(api, "g_count").as_i64().unwrap() as u64 >= killed);
    // Written through the API, saved periodically: survives the kill too.
    assert_eq!(put(api, "keeper.name", json!("kept"), None), 200);
    // Stopped, the values still go to the file when they change (a write through
    // the API) and are exactly the ones the PLC holds.
    assert_eq!(http(api, "POST", "/api/stop", None, None).0, 200);
    let stopped = value(api, "keeper.total").as_u64().unwrap();
    assert!(stopped >= total);
    until_saved(&file, "the values of the stopped PLC", |n| n == stopped);
    kill_9(s);
    assert_eq!(saved_total(&file), Some(stopped));
    let mut s = start("0.2");
    let api = http_addr(&mut s);
    let plain = value(api, "keeper.plain").as_u64().unwrap();
    let total = value(api, "keeper.total").as_u64().unwrap();
    assert!(total >= stopped + plain, "{stopped} {plain} {total}");
    assert_eq!(value(api, "keeper.name"), json!("kept"));
    let (status, lines) = s.terminate();
    assert!(status.success(), "{status}: {}", lines.join("\n"));
    assert!(saved_total(&file).unwrap() >= total);
    // Bad intervals, and an interval without a file: usage errors.
    for bad in [
        vec!["--retain", "x.retain", "--retain-every", "soon"],
        vec!["--retain", "x.retain", "--retain-every=-1"],
        vec!["--retain", "x.retain", "--retain-every", "1,5"],
        vec!["--retain-every", "1"],
    ] {
        let out = Command::new(env!("CARGO_BIN_EXE_plcc"))
            .arg("serve")
            .arg(&prog)
            .args(["--http", "none", "--modbus", "none"])
            .args(&bad)
            .current_dir(&dir)
            .output()
            .expect("plcc runs");
        assert_eq!(out.status.code(), Some(2), "{bad:?}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains("--retain"), "{bad:?}: {err}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn server_sent_events_follow_the_variables() {
    use serde_json::json;
    use std::io::{BufRead, Write};
    let plant = program("plant.st");
    let mut s = Server::start(&[
        plant.to_str().unwrap(),
        "--cycle-ms",
        "2",
        "--modbus",
        "none",
        "--http",
        "127.0.0.1:0",
    ]);
    let api = http_addr(&mut s);
    assert_eq!(http(api, "GET", "/api/stream", None, None).0, 400);
    assert_eq!(
        http(api, "GET", "/api/stream?vars=plant.nope", None, None).0,
        404
    );
    assert_eq!(
        http(api, "POST", "/api/stream?vars=plant.a", None, None).0,
        405
    );
    let sock = std::net::TcpStream::connect(api).unwrap();
    sock.set_read_timeout(Some(PATIENCE)).unwrap();
    (&sock)
        .write_all(b"GET /api/stream?vars=plant.a,plant.sum,total HTTP/1.1\r\nHost: plc\r\n\r\n")
        .unwrap();
    let mut lines = std::io::BufReader::new(&sock).lines();
    let mut next_event = || -> serde_json::Value {
        loop {
            let line = lines.next().expect("the stream goes on").expect("reads");
            if let Some(data) = line.strip_prefix("data: ") {
                return serde_json::from_str(data).expect("JSON");
            }
        }
    };
    let first = next_event();
    assert_eq!(first["values"]["plant.sum"], json!(0));
    assert!(first["scan"].as_u64().is_some());
    assert!(first["values"]["total"].as_i64().is_some());
    assert_eq!(put(api, "plant.a", json!(7), None), 200);
    assert_eq!(put(api, "plant.b", json!(5), None), 200);
    let t = Instant::now();
    loop {
        let e = next_event();
        // Each event's values are read between the same two scans.
        let (a, sum) = (&e["values"]["plant.a"], &e["values"]["plant.sum"]);
        if *sum == json!(12) {
            assert_eq!(*a, json!(7));
            break;
        }
        assert!(t.elapsed() < PATIENCE, "no event with sum 12");
    }
    drop(sock);
    // The stream's end leaves the server as it was.
    assert_eq!(status_of(api)["state"], json!("running"));
    let (status, lines) = s.terminate();
    assert!(status.success(), "{status}: {}", lines.join("\n"));
}

#[test]
fn online_change_keeps_the_values_and_the_scans() {
    use serde_json::json;
    use tokio_modbus::prelude::SyncWriter;
    let plant = program("plant.st");
    let mut s = Server::start(&[
        plant.to_str().unwrap(),
        "--cycle-ms",
        "2",
        "--modbus",
        "127.0.0.1:0",
        "--http",
        "127.0.0.1:0",
    ]);
    let api = http_addr(&mut s);
    let mut c = client(modbus_addr(&mut s));
    c.write_multiple_registers(1024, &[7, 5]).unwrap().unwrap();
    until("sum", vec![12], || holding(&mut c, 0, 1));
    let (st, _) = http(
        api,
        "POST",
        "/api/force/plant.alarm",
        Some(r#"{"value": true}"#),
        None,
    );
    assert_eq!(st, 200);
    let scans = value(api, "plant.scans").as_u64().unwrap();
    assert_eq!(http(api, "GET", "/api/vars/plant.extra", None, None).0, 404);
    // The new program: sum gets 1000 more, and a new variable.
    let v2 = std::fs::read_to_string(program("plant_v2.st")).unwrap();
    let (st, j) = http(api, "POST", "/api/program?lang=st", Some(&v2), None);
    assert_eq!(st, 200, "{j}");
    assert!(j["kept"].as_u64().unwrap() >= 10, "{j}");
    until("the new sum", vec![1012], || holding(&mut c, 0, 1));
    assert_eq!(holding(&mut c, 1024, 2), vec![7, 5]);
    assert!(value(api, "plant.scans").as_u64().unwrap() >= scans);
    assert_eq!(value(api, "plant.extra"), json!(5));
    assert_eq!(value(api, "plant.alarm"), json!(true), "the force holds");
    let (_, list) = http(api, "GET", "/api/vars", None, None);
    assert!(list
        .as_array()
        .unwrap()
        .contains(&json!({"path": "plant.extra", "type": "INT"})));
    // A program with errors is refused with its diagnostics; the old one runs on.
    let (st, j) = http(
        api,
        "POST",
        "/api/program",
        Some("PROGRAM plant VAR x : INT; END_VAR x := ; END_PROGRAM"),
        None,
    );
    assert_eq!(st, 400);
    assert!(j["error"].as_str().unwrap().contains("program.st"), "{j}");
    assert_eq!(
        http(api, "POST", "/api/program?lang=cobol", Some(&v2), None).0,
        400
    );
    let t0 = total(&mut c);
    until("scans go on", true, || total(&mut c) > t0 + 5);
    c.write_single_register(1025, 6).unwrap().unwrap();
    until("the new program computes", vec![1013], || {
        holding(&mut c, 0, 1)
    });
    drop(c);
    let (status, lines) = s.terminate();
    assert!(status.success(), "{status}: {}", lines.join("\n"));
}
