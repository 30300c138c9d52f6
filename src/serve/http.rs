//! The HTTP/JSON API (`docs/serve.md`), served by tiny_http on a thread of its own.
//!
//! Requests are checked here (route, token, JSON, path, type); what needs the
//! machine goes to the scan thread as a [`Cmd`], which answers between two scans.
//! Values are JSON booleans (BOOL), numbers (integers, bit strings, REAL, CHAR) and
//! strings (TIME and dates as IEC literals, STRING and WSTRING as their text).

use super::scan::{Cmd, Reply, Request, Value, Var};
use super::Shared;
use plcc_ir::value::PlcValue;
use plcc_ir::{ElemType, Module};
use serde_json::{json, Value as Json};
use std::collections::HashMap;
use std::io::Read;
use std::net::SocketAddr;
use std::sync::mpsc::Sender;
use std::sync::{Arc, Mutex};
use std::time::Duration;

/// The largest request body read.
const MAX_BODY: u64 = 64 * 1024;
/// How long a request waits for the scan thread.
const PATIENCE: Duration = Duration::from_secs(30);
/// How many event streams may be open at once.
const MAX_STREAMS: usize = 16;
/// The shortest time between two looks at a stream's variables.
const STREAM_PERIOD: Duration = Duration::from_millis(100);
/// A stream with nothing new sends a comment this often, to notice a client gone.
const KEEPALIVE: Duration = Duration::from_secs(10);

/// The variables of the program running.
pub struct Catalog {
    /// The variables a path may name, by canonical path.
    pub vars: HashMap<String, Var>,
    /// The variables in declaration order: path and type.
    pub listing: Vec<(String, String)>,
    /// The module, to resolve paths.
    pub module: Module,
}

/// The largest program an online change takes.
const MAX_PROGRAM: u64 = 8 * 1024 * 1024;

/// Everything the HTTP thread needs.
pub struct Api {
    /// The scan statistics and the stop flag.
    pub shared: Arc<Shared>,
    /// The program's variables (replaced by an online change).
    pub catalog: Mutex<Catalog>,
    /// Builds the programs of online changes.
    pub loader: super::Loader,
    /// The bearer token every write, force and control call needs, if any.
    pub token: Option<String>,
    /// The scan thread's requests.
    pub requests: Sender<Request>,
    /// The target's name, for the status.
    pub target: String,
    /// The cycle, for the status.
    pub cycle_us: u64,
    /// The event streams open.
    pub streams: Arc<std::sync::atomic::AtomicUsize>,
    /// The project, for the workbench (replaced by an online change of one of its
    /// files).
    pub project: std::sync::RwLock<super::project::Project>,
}

/// An error reply: the status and a message.
type Fail = (u16, String);

fn fail<T>(status: u16, msg: impl Into<String>) -> Result<T, Fail> {
    Err((status, msg.into()))
}

/// The request's body, of at most `max` bytes: 400 when it cannot be read, 413 when
/// it is larger (`what` names it in the message: "the program", "the text").
fn read_body(req: &mut tiny_http::Request, max: u64, what: &str) -> Result<Vec<u8>, Fail> {
    let mut body = Vec::new();
    if req
        .as_reader()
        .take(max + 1)
        .read_to_end(&mut body)
        .is_err()
    {
        return fail(400, "cannot read the request body");
    }
    if body.len() as u64 > max {
        return fail(413, format!("{what} is larger than {max} bytes"));
    }
    Ok(body)
}

/// The type of a variable as the API shows it.
pub fn type_name(v: &Var) -> String {
    match v {
        Var::Scalar { elem, .. } => elem.name().to_string(),
        Var::Str(s) => format!("{}[{}]", if s.wide { "WSTRING" } else { "STRING" }, s.cap),
    }
}

/// A value as JSON.
pub fn to_json(v: &Value, wide: bool) -> Json {
    match v {
        Value::Many(vs) => Json::Array(vs.iter().map(|v| to_json(v, wide)).collect()),
        Value::Str(chars) => {
            let text = if wide {
                String::from_utf16_lossy(chars)
            } else {
                chars.iter().map(|&c| char::from(c as u8)).collect()
            };
            Json::String(text)
        }
        Value::Scalar(p) => {
            use ElemType::*;
            match p.ty {
                Bool => Json::Bool(p.bits & 1 != 0),
                SInt | Int | DInt | LInt => json!(p.as_i64()),
                USInt | UInt | UDInt | ULInt | Byte | Word | DWord | LWord | Char | WChar | Ref => {
                    json!(p.bits)
                }
                Real | LReal => serde_json::Number::from_f64(p.as_f64())
                    .map_or_else(|| Json::String(p.to_string()), Json::Number),
                Time | LTime | Date | Tod | Dt | LDate | LTod | LDt => Json::String(p.to_string()),
            }
        }
    }
}

/// A JSON value as a value of `var`'s type; an error for the wrong JSON type or a
/// value out of the type's range.
pub fn from_json(var: &Var, j: &Json) -> Result<Value, String> {
    let wrong = |what: &str| {
        Err(format!(
            "`{}` has type {}: {what}",
            display(var.path()),
            type_name(var)
        ))
    };
    match var {
        Var::Str(s) => {
            let Json::String(text) = j else {
                return wrong("give a JSON string");
            };
            let chars: Vec<u16> = if s.wide {
                text.encode_utf16().collect()
            } else {
                let mut out = Vec::new();
                for c in text.chars() {
                    match u8::try_from(c as u32) {
                        Ok(b) if b != 0 => out.push(b as u16),
                        _ => return wrong("its characters are Latin-1, none NUL"),
                    }
                }
                out
            };
            if chars.contains(&0) {
                return wrong("its text holds no NUL");
            }
            if chars.len() > s.cap as usize {
                return wrong(&format!("it holds at most {} characters", s.cap));
            }
            Ok(Value::Str(chars))
        }
        Var::Scalar { elem, .. } => {
            use ElemType::*;
            let v = match (elem, j) {
                (Bool, Json::Bool(b)) => PlcValue::from_bool(*b),
                (Bool, _) => return wrong("give true or false"),
                (Real, Json::Number(n)) => match n.as_f64() {
                    Some(f) => PlcValue::from_f32(f as f32),
                    None => return wrong("give a number"),
                },
                (LReal, Json::Number(n)) => match n.as_f64() {
                    Some(f) => PlcValue::from_f64(f),
                    None => return wrong("give a number"),
                },
                (Real | LReal, _) => return wrong("give a number"),
                (Time | LTime | Date | Tod | Dt | LDate | LTod | LDt, Json::String(t)) => {
                    PlcValue::parse(*elem, t)?
                }
                (Time | LTime | Date | Tod | Dt | LDate | LTod | LDt, _) => {
                    return wrong("give an IEC literal in a string, e.g. \"T#1s\"")
                }
                (Ref, _) => return wrong("references cannot be written"),
                (_, Json::Number(n)) if n.is_i64() || n.is_u64() => {
                    PlcValue::parse(*elem, &n.to_string())?
                }
                _ => return wrong("give an integer"),
            };
            Ok(Value::Scalar(v))
        }
    }
}

/// A path as the API shows it: a global's by its plain name, as `plcc run` prints it.
pub fn display(path: &str) -> &str {
    path.strip_prefix(plcc_frontend::GLOBALS_DATA)
        .and_then(|p| p.strip_prefix('.'))
        .unwrap_or(path)
}

/// `%XX` escapes decoded; `None` if malformed or not UTF-8.
pub(super) fn percent_decode(s: &str) -> Option<String> {
    let b = s.as_bytes();
    let mut out = Vec::with_capacity(b.len());
    let mut i = 0;
    while i < b.len() {
        if b[i] == b'%' {
            let hex = std::str::from_utf8(b.get(i + 1..i + 3)?).ok()?;
            out.push(u8::from_str_radix(hex, 16).ok()?);
            i += 3;
        } else {
            out.push(b[i]);
            i += 1;
        }
    }
    String::from_utf8(out).ok()
}

impl Api {
    /// The variable a path names: one of those GET /api/vars lists.
    fn var(&self, raw: &str) -> Result<Var, Fail> {
        let Some(path) = percent_decode(raw) else {
            return fail(400, format!("`{raw}` is not a well-formed path"));
        };
        let cat = self.catalog();
        let find = |p: &str| match plcc_ir::vars::resolve(&cat.module, p) {
            Ok(v) => Ok(v.path),
            Err(e) => plcc_ir::vars::resolve_string(&cat.module, p)
                .map(|s| s.path)
                .map_err(|_| e),
        };
        // A global by its plain name, as GET /api/vars lists it.
        let canon = match find(&path) {
            Ok(c) => c,
            Err(e) => match find(&format!("{}.{path}", plcc_frontend::GLOBALS_DATA)) {
                Ok(c) => c,
                Err(_) => return fail(404, format!("unknown variable: {e}")),
            },
        };
        match cat.vars.get(&canon) {
            Some(v) => Ok(v.clone()),
            None => fail(404, format!("unknown variable `{path}`")),
        }
    }

    fn catalog(&self) -> std::sync::MutexGuard<'_, Catalog> {
        self.catalog.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// `POST /api/program?lang=L`: the body is the new program's source.
    /// The project (a poisoned lock still holds a whole project: it is only ever
    /// replaced whole).
    fn project(&self) -> std::sync::RwLockReadGuard<'_, super::project::Project> {
        self.project.read().unwrap_or_else(|e| e.into_inner())
    }

    /// `POST /api/program?lang=L` (the body is the whole program) or `?file=NAME`
    /// (the body replaces the project's file NAME, the other files with it; the
    /// project the page shows becomes the new one).
    fn program(&self, req: &mut tiny_http::Request, query: &str) -> Result<Json, Fail> {
        let (lang, file) = match query {
            "" => ("st", None),
            q => match (q.strip_prefix("lang="), q.strip_prefix("file=")) {
                (Some(l @ ("st" | "il" | "stl" | "xml")), _) => (l, None),
                (_, Some(f)) => match percent_decode(f) {
                    Some(f) => ("", Some(f)),
                    None => return fail(400, format!("`{f}` is not a well-formed name")),
                },
                _ => {
                    return fail(
                        400,
                        format!("`{q}`: use lang=st, il, stl or xml, or file=NAME"),
                    )
                }
            },
        };
        let body = read_body(req, MAX_PROGRAM, "the program")?;
        let (catalog, loaded, project) = match file {
            None => {
                let (c, l) = self.loader.compile(body, lang).map_err(|e| (400, e))?;
                (c, l, None)
            }
            Some(f) => {
                let (files, names) = {
                    let p = self.project();
                    (p.with_file(&f, body)?, p.paths())
                };
                let (c, l, build) = self.loader.compile_files(files).map_err(|e| (400, e))?;
                let project = super::project::Project::new(&build, &names, &c.module);
                (c, l, Some(project))
            }
        };
        match self.ask(Cmd::Load(Box::new(loaded)))? {
            Some(Value::Scalar(kept)) => {
                *self.catalog() = catalog;
                if let Some(p) = project {
                    *self.project.write().unwrap_or_else(|e| e.into_inner()) = p;
                }
                Ok(json!({"ok": true, "kept": kept.bits}))
            }
            _ => fail(500, "no answer from the scan thread"),
        }
    }

    fn ask(&self, cmd: Cmd) -> Reply {
        let (tx, rx) = std::sync::mpsc::channel();
        if self.requests.send(Request { cmd, reply: tx }).is_err() {
            return fail(503, "the scan thread has ended");
        }
        match rx.recv_timeout(PATIENCE) {
            Ok(r) => r,
            Err(_) => fail(503, "the scan thread did not answer"),
        }
    }

    fn authorized(&self, req: &tiny_http::Request) -> bool {
        let Some(token) = &self.token else {
            return true;
        };
        req.headers()
            .iter()
            .filter(|h| h.field.equiv("Authorization"))
            .any(|h| {
                h.value
                    .as_str()
                    .strip_prefix("Bearer ")
                    .is_some_and(|t| constant_time_eq(t.trim().as_bytes(), token.as_bytes()))
            })
    }

    fn status(&self) -> Json {
        let s = self.shared.lock_stats().clone();
        let series = |x: &super::scan::Series| {
            let t = x.summary();
            json!({"min": t.min, "mean": t.mean, "max": t.max, "p50": t.p50, "p99": t.p99})
        };
        json!({
            "state": s.state,
            "target": self.target,
            "cycle_us": self.cycle_us,
            "scans": s.scans,
            "overruns": s.overruns,
            "lateness_us": series(&s.lateness),
            "exec_us": series(&s.exec),
            "forced": s.forced,
            "fault": s.fault,
            "error": s.error,
        })
    }

    /// The `value` of a request body `{"value": ...}`.
    fn body_value(req: &mut tiny_http::Request) -> Result<Json, Fail> {
        let body = read_body(req, MAX_BODY, "the body")?;
        let j: Json = match serde_json::from_slice(&body) {
            Ok(j) => j,
            Err(e) => return fail(400, format!("bad JSON: {e}")),
        };
        match j {
            Json::Object(mut o) if o.len() == 1 && o.contains_key("value") => {
                Ok(o.remove("value").unwrap_or(Json::Null))
            }
            _ => fail(400, "the body must be {\"value\": ...}"),
        }
    }

    /// Answers one request: the status and the JSON body.
    fn handle(&self, req: &mut tiny_http::Request) -> Result<Json, Fail> {
        use tiny_http::Method::*;
        let url = req.url().to_string();
        let (path, query) = url.split_once('?').unwrap_or((&url, ""));
        let method = req.method().clone();
        let route: Vec<&str> = path.trim_start_matches('/').splitn(3, '/').collect();
        if route.first() != Some(&"api") {
            return fail(404, format!("no such resource `{path}`"));
        }
        // A check, a build, or reading a diagram of a text changes nothing: no token.
        let writes =
            !matches!(method, Get | Head) && !matches!(route[1..], ["check"] | ["diagram", _]);
        if writes && !self.authorized(req) {
            return fail(
                401,
                "this call needs the header `Authorization: Bearer <token>`",
            );
        }
        let done = |r: Reply| r.map(|_| json!({"ok": true}));
        match (&method, &route[1..]) {
            (Get, ["status"]) => Ok(self.status()),
            (Get, ["vars"]) => Ok(Json::Array(
                self.catalog()
                    .listing
                    .iter()
                    .map(|(p, t)| json!({"path": display(p), "type": t}))
                    .collect(),
            )),
            (Get, ["vars", p]) => {
                let var = self.var(p)?;
                let wide = matches!(&var, Var::Str(s) if s.wide);
                match self.ask(Cmd::Read(var.clone()))? {
                    Some(v) => Ok(json!({
                        "path": display(var.path()),
                        "type": type_name(&var),
                        "value": to_json(&v, wide),
                    })),
                    None => fail(500, "no value"),
                }
            }
            (Put, ["vars", p]) => {
                let var = self.var(p)?;
                let j = Self::body_value(req)?;
                let v = from_json(&var, &j).map_err(|e| (400, e))?;
                done(self.ask(Cmd::Write(var, v)))
            }
            (Post, ["force", p]) => {
                let var = self.var(p)?;
                let j = Self::body_value(req)?;
                match from_json(&var, &j).map_err(|e| (400, e))? {
                    Value::Scalar(v) => done(self.ask(Cmd::Force(var, v))),
                    Value::Str(_) | Value::Many(_) => fail(
                        400,
                        format!(
                            "`{}` is a string: only elementary variables can be forced",
                            display(var.path())
                        ),
                    ),
                }
            }
            (Delete, ["force", p]) => {
                let var = self.var(p)?;
                done(self.ask(Cmd::Unforce(var.path().to_string())))
            }
            (Post, ["program"]) => self.program(req, query),
            (Get, ["project"]) => Ok(self.project().info()),
            (Get, ["files", n]) => self.project().file(n),
            (Get, ["diagram", p]) => match percent_decode(p) {
                Some(p) => self.project().diagram(&p),
                None => fail(400, format!("`{p}` is not a well-formed name")),
            },
            (Post, ["diagram", p]) => {
                let Some(p) = percent_decode(p) else {
                    return fail(400, format!("`{p}` is not a well-formed name"));
                };
                let body = read_body(req, MAX_PROGRAM, "the text")?;
                super::project::diagram_of(&body, &p)
            }
            (Post, ["build"]) => {
                let body = read_body(req, MAX_PROGRAM, "the text")?;
                self.project().build(&self.loader, query, body)
            }
            (Post, ["check"]) => {
                let body = read_body(req, MAX_PROGRAM, "the text")?;
                self.project().check(&self.loader, query, body)
            }
            (Post, ["stop"]) => done(self.ask(Cmd::Stop)),
            (Post, ["start"]) => done(self.ask(Cmd::Start)),
            (Post, ["restart"]) => match query {
                "" | "mode=cold" => done(self.ask(Cmd::Restart { warm: false })),
                "mode=warm" => done(self.ask(Cmd::Restart { warm: true })),
                q => fail(400, format!("`{q}`: use mode=cold or mode=warm")),
            },
            (
                _,
                ["status"]
                | ["vars"]
                | ["vars", _]
                | ["force", _]
                | ["stop"]
                | ["start"]
                | ["restart"]
                | ["stream"]
                | ["program"]
                | ["project"]
                | ["files", _]
                | ["diagram", _]
                | ["check"]
                | ["build"],
            ) => fail(405, format!("{method} is not allowed on `{path}`")),
            _ => fail(404, format!("no such resource `{path}`")),
        }
    }
}

/// `GET /api/stream?vars=a,b`: the variables, checked.
fn stream_vars(api: &Api, req: &tiny_http::Request) -> Result<Vec<Var>, Fail> {
    let url = req.url();
    let query = url.split_once('?').map_or("", |(_, q)| q);
    let list = query
        .split('&')
        .find_map(|kv| kv.strip_prefix("vars="))
        .unwrap_or("");
    if list.is_empty() {
        return fail(400, "name the variables: /api/stream?vars=a,b");
    }
    let vars = list
        .split(',')
        .map(|p| api.var(p))
        .collect::<Result<Vec<_>, _>>()?;
    if api.streams.load(std::sync::atomic::Ordering::SeqCst) >= MAX_STREAMS {
        return fail(503, format!("at most {MAX_STREAMS} streams at once"));
    }
    Ok(vars)
}

/// Serves one event stream until the client goes or the server stops: an event
/// `{"scan": N, "values": {path: value, ...}}` when the values differ from the last
/// ones sent, looked at every cycle (at most every 100 ms), all read between the
/// same two scans.
fn stream(
    req: tiny_http::Request,
    vars: Vec<Var>,
    requests: Sender<Request>,
    shared: Arc<Shared>,
    period: Duration,
) {
    use std::io::Write;
    let mut w = req.into_writer();
    let head = "HTTP/1.1 200 OK\r\nContent-Type: text/event-stream\r\nCache-Control: no-cache\r\nConnection: close\r\n\r\n";
    if w.write_all(head.as_bytes())
        .and_then(|()| w.flush())
        .is_err()
    {
        return;
    }
    let mut last: Option<Json> = None;
    let mut sent = std::time::Instant::now();
    while !shared.stop.load(std::sync::atomic::Ordering::SeqCst) {
        let (tx, rx) = std::sync::mpsc::channel();
        let asked = requests.send(Request {
            cmd: Cmd::ReadMany(vars.clone()),
            reply: tx,
        });
        let values = match asked.ok().and_then(|()| rx.recv_timeout(PATIENCE).ok()) {
            Some(Ok(Some(Value::Many(vs)))) => vs,
            Some(Err((_, e))) => {
                let _ = write!(w, "event: error\ndata: {}\n\n", json!({"error": e}));
                return;
            }
            _ => return,
        };
        let mut obj = serde_json::Map::new();
        for (var, v) in vars.iter().zip(&values) {
            let wide = matches!(var, Var::Str(s) if s.wide);
            obj.insert(display(var.path()).to_string(), to_json(v, wide));
        }
        let now = Json::Object(obj);
        let out = if last.as_ref() != Some(&now) {
            let scans = shared.lock_stats().scans;
            let text = format!("data: {}\n\n", json!({"scan": scans, "values": now}));
            last = Some(now);
            Some(text)
        } else if sent.elapsed() >= KEEPALIVE {
            Some(": keepalive\n\n".to_string())
        } else {
            None
        };
        if let Some(text) = out {
            if w.write_all(text.as_bytes())
                .and_then(|()| w.flush())
                .is_err()
            {
                return;
            }
            sent = std::time::Instant::now();
        }
        std::thread::sleep(period);
    }
}

/// Compares two byte strings in time independent of where they differ.
fn constant_time_eq(a: &[u8], b: &[u8]) -> bool {
    a.len() == b.len() && a.iter().zip(b).fold(0u8, |acc, (x, y)| acc | (x ^ y)) == 0
}

fn respond(req: tiny_http::Request, status: u16, body: &Json) {
    let mut r = tiny_http::Response::from_string(body.to_string()).with_status_code(status);
    if let Ok(h) = tiny_http::Header::from_bytes(&b"Content-Type"[..], &b"application/json"[..]) {
        r = r.with_header(h);
    }
    // A client that went away is no concern of the PLC's.
    let _ = req.respond(r);
}

/// An asset of the page.
fn respond_bytes(req: tiny_http::Request, ty: &str, bytes: &'static [u8]) {
    let mut r = tiny_http::Response::from_data(bytes);
    for (k, v) in [("Content-Type", ty), ("Cache-Control", "no-cache")] {
        if let Ok(h) = tiny_http::Header::from_bytes(k.as_bytes(), v.as_bytes()) {
            r = r.with_header(h);
        }
    }
    let _ = req.respond(r);
}

/// Binds `addr` and serves the API on a thread of its own; the address bound.
pub fn start(addr: SocketAddr, api: Api) -> std::io::Result<SocketAddr> {
    let server = tiny_http::Server::http(addr).map_err(std::io::Error::other)?;
    let bound = server
        .server_addr()
        .to_ip()
        .ok_or_else(|| std::io::Error::other("not an IP address"))?;
    std::thread::Builder::new()
        .name("http".into())
        .spawn(move || {
            for mut req in server.incoming_requests() {
                let is_stream = *req.method() == tiny_http::Method::Get
                    && req.url().split('?').next() == Some("/api/stream");
                if is_stream {
                    match stream_vars(&api, &req) {
                        Ok(vars) => {
                            let requests = api.requests.clone();
                            let shared = Arc::clone(&api.shared);
                            let period = Duration::from_micros(api.cycle_us).max(STREAM_PERIOD);
                            let count = Arc::clone(&api.streams);
                            count.fetch_add(1, std::sync::atomic::Ordering::SeqCst);
                            let spawned = std::thread::Builder::new()
                                .name("http-stream".into())
                                .spawn(move || {
                                    stream(req, vars, requests, shared, period);
                                    count.fetch_sub(1, std::sync::atomic::Ordering::SeqCst);
                                });
                            if spawned.is_err() {
                                api.streams
                                    .fetch_sub(1, std::sync::atomic::Ordering::SeqCst);
                            }
                        }
                        Err((status, msg)) => respond(req, status, &json!({"error": msg})),
                    }
                    continue;
                }
                // The workbench's page and assets (`project`).
                let get = matches!(
                    *req.method(),
                    tiny_http::Method::Get | tiny_http::Method::Head
                );
                let path = req.url().split('?').next().unwrap_or("").to_string();
                if get && !path.starts_with("/api/") {
                    match super::project::asset(&path) {
                        Some((ty, bytes)) => respond_bytes(req, ty, bytes),
                        None => respond(
                            req,
                            404,
                            &json!({"error": format!("no such resource `{path}`")}),
                        ),
                    }
                    continue;
                }
                match api.handle(&mut req) {
                    Ok(body) => respond(req, 200, &body),
                    Err((status, msg)) => respond(req, status, &json!({"error": msg})),
                }
            }
        })?;
    Ok(bound)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scalar(elem: ElemType) -> Var {
        Var::Scalar {
            path: "p.x".into(),
            elem,
            bind: None,
        }
    }

    #[test]
    fn json_values_take_the_variables_type() {
        let int = scalar(ElemType::Int);
        assert_eq!(
            from_json(&int, &json!(-5)),
            Ok(Value::Scalar(PlcValue::from_i64(ElemType::Int, -5)))
        );
        assert!(from_json(&int, &json!(40000)).is_err());
        assert!(from_json(&int, &json!(1.5)).is_err());
        assert!(from_json(&int, &json!("5")).is_err());
        assert!(from_json(&int, &json!(true)).is_err());
        let b = scalar(ElemType::Bool);
        assert!(from_json(&b, &json!(1)).is_err());
        let t = scalar(ElemType::Time);
        let v = from_json(&t, &json!("T#1s500ms")).unwrap();
        assert_eq!(to_json(&v, false), json!("T#1500ms"));
        assert!(from_json(&t, &json!(1500)).is_err());
        let r = scalar(ElemType::Real);
        assert_eq!(
            to_json(&from_json(&r, &json!(2.5)).unwrap(), false),
            json!(2.5)
        );
        let w = scalar(ElemType::Word);
        assert_eq!(
            to_json(&from_json(&w, &json!(65535)).unwrap(), false),
            json!(65535)
        );
        assert!(from_json(&w, &json!(-1)).is_err());
        let s = Var::Str(plcc_ir::vars::StrRef {
            path: "p.s".into(),
            wide: false,
            cap: 3,
        });
        assert_eq!(
            from_json(&s, &json!("abc")),
            Ok(Value::Str(vec![97, 98, 99]))
        );
        assert!(from_json(&s, &json!("abcd")).is_err());
        assert!(from_json(&s, &json!("€")).is_err());
    }

    #[test]
    fn paths_are_percent_decoded() {
        assert_eq!(percent_decode("a%5B1%5D").as_deref(), Some("a[1]"));
        assert_eq!(percent_decode("a%5"), None);
        assert_eq!(percent_decode("%FF"), None);
        assert!(constant_time_eq(b"abc", b"abc"));
        assert!(!constant_time_eq(b"abc", b"abd"));
        assert!(!constant_time_eq(b"abc", b"ab"));
    }
}
