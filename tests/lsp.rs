//! `plcc lsp` driven through the protocol: the real binary as a child process, a
//! small client writing Content-Length frames to its standard input and reading
//! them from its standard output, on a temporary workspace.

use serde_json::{json, Value};
use std::io::{BufRead, BufReader, Read, Write};
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdin, Command, Stdio};
use std::sync::mpsc;
use std::time::Duration;

/// How long any answer may take before the test fails (a debug build, a busy machine).
const TIMEOUT: Duration = Duration::from_secs(60);

/// A client of `plcc lsp`.
struct Client {
    child: Child,
    stdin: Option<ChildStdin>,
    rx: mpsc::Receiver<Value>,
    /// Notifications read while waiting for something else.
    pending: Vec<Value>,
    next_id: i64,
}

impl Client {
    fn start() -> Client {
        let mut child = Command::new(env!("CARGO_BIN_EXE_plcc"))
            .arg("lsp")
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("start plcc lsp");
        let stdout = child.stdout.take().expect("stdout");
        let (tx, rx) = mpsc::channel();
        std::thread::spawn(move || {
            let mut r = BufReader::new(stdout);
            while let Some(v) = read_frame(&mut r) {
                if tx.send(v).is_err() {
                    return;
                }
            }
        });
        Client {
            stdin: child.stdin.take(),
            child,
            rx,
            pending: Vec::new(),
            next_id: 1,
        }
    }

    fn write_raw(&mut self, bytes: &[u8]) {
        let stdin = self.stdin.as_mut().expect("stdin open");
        // The server may have exited already (the bad-input tests): ignore EPIPE.
        let _ = stdin.write_all(bytes);
        let _ = stdin.flush();
    }

    fn send(&mut self, msg: Value) {
        let body = msg.to_string();
        self.write_raw(format!("Content-Length: {}\r\n\r\n{body}", body.len()).as_bytes());
    }

    fn next(&mut self) -> Value {
        self.rx
            .recv_timeout(TIMEOUT)
            .expect("the server answered in time")
    }

    /// Sends a request and returns its whole response (`result` or `error`).
    fn request(&mut self, method: &str, params: Value) -> Value {
        let id = self.next_id;
        self.next_id += 1;
        self.send(json!({"jsonrpc": "2.0", "id": id, "method": method, "params": params}));
        loop {
            let v = self.next();
            if v.get("id") == Some(&json!(id)) && v.get("method").is_none() {
                return v;
            }
            self.pending.push(v);
        }
    }

    /// The result of a request that must succeed.
    fn call(&mut self, method: &str, params: Value) -> Value {
        let r = self.request(method, params);
        assert!(r.get("error").is_none(), "{method} failed: {r}");
        r["result"].clone()
    }

    fn notify(&mut self, method: &str, params: Value) {
        self.send(json!({"jsonrpc": "2.0", "method": method, "params": params}));
    }

    /// The next diagnostics published for `uri`.
    fn diagnostics(&mut self, uri: &str) -> Value {
        let is_for = |v: &Value| {
            v["method"] == "textDocument/publishDiagnostics" && v["params"]["uri"] == uri
        };
        if let Some(k) = self.pending.iter().position(is_for) {
            return self.pending.remove(k)["params"]["diagnostics"].clone();
        }
        loop {
            let v = self.next();
            if is_for(&v) {
                return v["params"]["diagnostics"].clone();
            }
            self.pending.push(v);
        }
    }

    fn initialize(&mut self, root: &Path, options: Value) {
        let r = self.call(
            "initialize",
            json!({"capabilities": {}, "rootUri": uri(root), "initializationOptions": options}),
        );
        assert_eq!(r["serverInfo"]["name"], "plcc");
        assert_eq!(r["capabilities"]["hoverProvider"], true);
        self.notify("initialized", json!({}));
    }

    fn open(&mut self, path: &Path) {
        let text = std::fs::read_to_string(path).expect("read");
        self.notify(
            "textDocument/didOpen",
            json!({"textDocument": {"uri": uri(path), "languageId": "st", "version": 1, "text": text}}),
        );
    }

    /// Closes standard input and waits for the exit status; the server must not
    /// have panicked.
    fn finish(mut self) -> i32 {
        self.stdin = None;
        let status = wait_timeout(&mut self.child);
        let mut err = String::new();
        if let Some(mut e) = self.child.stderr.take() {
            let _ = e.read_to_string(&mut err);
        }
        assert!(!err.contains("panicked"), "the server panicked: {err}");
        status
    }

    fn shutdown_and_exit(mut self) -> i32 {
        assert_eq!(self.call("shutdown", Value::Null), Value::Null);
        self.notify("exit", Value::Null);
        self.finish()
    }
}

fn wait_timeout(child: &mut Child) -> i32 {
    let start = std::time::Instant::now();
    loop {
        if let Some(s) = child.try_wait().expect("wait") {
            return s
                .code()
                .expect("exited with a status, not killed by a signal");
        }
        if start.elapsed() > TIMEOUT {
            let _ = child.kill();
            panic!("the server did not exit");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
}

fn read_frame(r: &mut impl BufRead) -> Option<Value> {
    let mut len = None;
    loop {
        let mut line = String::new();
        if r.read_line(&mut line).ok()? == 0 {
            return None;
        }
        let line = line.trim_end();
        if line.is_empty() {
            break;
        }
        if let Some(v) = line.strip_prefix("Content-Length: ") {
            len = v.parse::<usize>().ok();
        }
    }
    let mut body = vec![0; len?];
    r.read_exact(&mut body).ok()?;
    serde_json::from_slice(&body).ok()
}

fn uri(path: &Path) -> String {
    format!("file://{}", path.display())
}

/// A fresh folder of its own for each test.
fn workspace(name: &str, files: &[(&str, &str)]) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("plcc-lsp-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("mkdir");
    for (file, text) in files {
        std::fs::write(dir.join(file), text).expect("write");
    }
    dir
}

const MOTOR: &str = "FUNCTION_BLOCK Motor
VAR_INPUT
    start : BOOL;
    speed : INT := 5;
END_VAR
VAR_OUTPUT
    running : BOOL;
END_VAR
running := start AND speed > 0;
END_FUNCTION_BLOCK
";

/// Line 0 is not ASCII, and so is the error's line before the error: `é` is one
/// UTF-16 unit (two bytes), `𝄞` two (four bytes).
const MAIN: &str = "(* Température of the café: ☕ *)
PROGRAM Main
VAR
    m : Motor;
    go : BOOL;
END_VAR
m(start := go);
go := (* é𝄞 *) m.running AND nope;
END_PROGRAM
";

fn pos(line: u32, character: u32) -> Value {
    json!({"line": line, "character": character})
}

fn range(l0: u32, c0: u32, l1: u32, c1: u32) -> Value {
    json!({"start": pos(l0, c0), "end": pos(l1, c1)})
}

fn at(path: &Path, line: u32, character: u32) -> Value {
    json!({"textDocument": {"uri": uri(path)}, "position": pos(line, character)})
}

#[test]
fn diagnostics_outline_hover_and_definition_across_files() {
    let dir = workspace("main", &[("motor.st", MOTOR), ("main.st", MAIN)]);
    let (main, motor) = (dir.join("main.st"), dir.join("motor.st"));
    let mut c = Client::start();
    c.initialize(&dir, Value::Null);
    c.open(&main);
    // Column 30 in UTF-16 units (29 characters, 35 bytes).
    assert_eq!(
        c.diagnostics(&uri(&main)),
        json!([{
            "code": "E0201",
            "message": "`nope` is not declared",
            "range": range(7, 30, 7, 34),
            "severity": 1,
            "source": "plcc",
        }])
    );

    // Fixed in the editor, not on disk: the unsaved text wins.
    c.notify(
        "textDocument/didChange",
        json!({
            "textDocument": {"uri": uri(&main), "version": 2},
            "contentChanges": [{"text": MAIN.replace("AND nope", "AND go")}],
        }),
    );
    assert_eq!(c.diagnostics(&uri(&main)), json!([]));

    let symbols = c.call(
        "textDocument/documentSymbol",
        json!({"textDocument": {"uri": uri(&motor)}}),
    );
    let var = |name: &str, detail: &str, line: u32, end: u32| {
        json!({
            "name": name, "detail": detail, "kind": 13,
            "range": range(line, 4, line, end),
            "selectionRange": range(line, 4, line, 4 + name.len() as u32),
        })
    };
    assert_eq!(
        symbols,
        json!([{
            "name": "Motor",
            "detail": "FUNCTION_BLOCK",
            "kind": 5,
            "range": range(0, 0, 9, 18),
            "selectionRange": range(0, 15, 0, 20),
            "children": [
                var("start", "VAR_INPUT : BOOL", 2, 16),
                var("speed", "VAR_INPUT : INT", 3, 20),
                var("running", "VAR_OUTPUT : BOOL", 6, 18),
            ],
        }])
    );

    // `running` of `m.running`, in the other file.
    assert_eq!(
        c.call("textDocument/hover", at(&main, 7, 20)),
        json!({
            "contents": {
                "kind": "markdown",
                "value": "```iecst\nrunning : BOOL\n```\n\nVAR_OUTPUT of `Motor`; type `BOOL`",
            },
            "range": range(7, 18, 7, 25),
        })
    );
    // The FB's name: its interface.
    assert_eq!(
        c.call("textDocument/hover", at(&main, 3, 10))["contents"]["value"],
        "```iecst\nFUNCTION_BLOCK Motor\nVAR_INPUT\n    start : BOOL;\n    speed : INT := 5;\nEND_VAR\nVAR_OUTPUT\n    running : BOOL;\nEND_VAR\n```"
    );

    // The instance's type, a parameter of the call, a member: in motor.st.
    let motor_at = |l0, c0, l1, c1| json!({"uri": uri(&motor), "range": range(l0, c0, l1, c1)});
    assert_eq!(
        c.call("textDocument/definition", at(&main, 3, 9)),
        motor_at(0, 15, 0, 20)
    );
    assert_eq!(
        c.call("textDocument/definition", at(&main, 6, 3)),
        motor_at(2, 4, 2, 9)
    );
    assert_eq!(
        c.call("textDocument/definition", at(&main, 7, 19)),
        motor_at(6, 4, 6, 11)
    );
    // A local variable: in main.st; nothing at a keyword.
    assert_eq!(
        c.call("textDocument/definition", at(&main, 6, 0)),
        json!({"uri": uri(&main), "range": range(3, 4, 3, 5)})
    );
    assert_eq!(
        c.call("textDocument/definition", at(&main, 1, 2)),
        Value::Null
    );

    // Every use of `running`, the declaration included.
    let refs = c.call(
        "textDocument/references",
        json!({
            "textDocument": {"uri": uri(&motor)},
            "position": pos(6, 5),
            "context": {"includeDeclaration": true},
        }),
    );
    assert_eq!(
        refs,
        json!([
            {"uri": uri(&main), "range": range(7, 18, 7, 25)},
            motor_at(6, 4, 6, 11),
            motor_at(8, 0, 8, 7),
        ])
    );

    // Completion in Main's body: its variables, the POUs, standard blocks and functions.
    let items = c.call("textDocument/completion", at(&main, 7, 0));
    let labels: Vec<&str> = items
        .as_array()
        .expect("a list")
        .iter()
        .map(|i| i["label"].as_str().expect("label"))
        .collect();
    for want in ["m", "go", "Motor", "Main", "TON", "LIMIT"] {
        assert!(labels.contains(&want), "{want} missing from {labels:?}");
    }
    let limit = items
        .as_array()
        .and_then(|a| a.iter().find(|i| i["label"] == "LIMIT"))
        .expect("LIMIT");
    assert_eq!(
        limit["detail"],
        "LIMIT(MN, IN, MX : ANY_ELEMENTARY) : ANY_ELEMENTARY"
    );
    assert!(!labels.contains(&"start"), "another POU's variable offered");
    assert!(labels.iter().all(|l| !l.contains("__")), "{labels:?}");

    assert_eq!(c.shutdown_and_exit(), 0);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn diagnostics_go_to_the_file_they_are_about_and_are_cleared() {
    // motor.st is wrong on disk and not open; main.st, which uses it, is opened.
    let bad_motor = MOTOR.replace("running := start", "running := stort");
    let dir = workspace("other", &[("motor.st", &bad_motor), ("main.st", MAIN)]);
    let (main, motor) = (dir.join("main.st"), dir.join("motor.st"));
    let mut c = Client::start();
    c.initialize(&dir, Value::Null);
    c.open(&main);
    let d = c.diagnostics(&uri(&motor));
    assert_eq!(d[0]["code"], "E0201");
    assert_eq!(d[0]["range"], range(8, 11, 8, 16));
    assert_eq!(c.diagnostics(&uri(&main))[0]["range"], range(7, 30, 7, 34));

    // Opened and fixed in the editor: motor.st's diagnostics are cleared.
    c.open(&motor);
    c.notify(
        "textDocument/didChange",
        json!({
            "textDocument": {"uri": uri(&motor), "version": 2},
            "contentChanges": [{"text": MOTOR}],
        }),
    );
    loop {
        if c.diagnostics(&uri(&motor)) == json!([]) {
            break;
        }
    }
    // Saved with the fix for main.st too.
    c.notify(
        "textDocument/didSave",
        json!({"textDocument": {"uri": uri(&main)}, "text": MAIN.replace("nope", "go")}),
    );
    loop {
        if c.diagnostics(&uri(&main)) == json!([]) {
            break;
        }
    }
    assert_eq!(c.shutdown_and_exit(), 0);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn il_and_stl_files_get_diagnostics() {
    let il = "FUNCTION_BLOCK Blink\nVAR_INPUT x : BOOL; END_VAR\nVAR_OUTPUT y : BOOL; END_VAR\n    LD x\n    ANDN missing\n    ST y\nEND_FUNCTION_BLOCK\n";
    let dir = workspace("il", &[("blink.il", il)]);
    let path = dir.join("blink.il");
    let mut c = Client::start();
    c.initialize(&dir, Value::Null);
    c.open(&path);
    let d = c.diagnostics(&uri(&path));
    assert_eq!(d[0]["code"], "E0201", "{d}");
    assert_eq!(d[0]["range"], range(4, 9, 4, 16));
    assert_eq!(c.shutdown_and_exit(), 0);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_codesys_dialect_is_chosen_by_initialization_options() {
    let text = "PROGRAM P\nVAR\n    x : INT;\n    p : POINTER TO INT;\nEND_VAR\np := ADR(x);\nEND_PROGRAM\n";
    let dir = workspace("codesys", &[("p.st", text)]);
    let path = dir.join("p.st");
    let mut c = Client::start();
    c.initialize(&dir, Value::Null);
    c.open(&path);
    assert_ne!(
        c.diagnostics(&uri(&path)),
        json!([]),
        "IEC refuses POINTER TO"
    );
    assert_eq!(c.shutdown_and_exit(), 0);

    let mut c = Client::start();
    c.initialize(&dir, json!({"dialect": "codesys"}));
    c.open(&path);
    assert_eq!(c.diagnostics(&uri(&path)), json!([]));
    assert_eq!(c.shutdown_and_exit(), 0);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn malformed_messages_get_protocol_errors() {
    let dir = workspace("errors", &[("a.st", MOTOR)]);
    let mut c = Client::start();
    // Before initialize: ServerNotInitialized.
    let r = c.request("textDocument/hover", at(&dir.join("a.st"), 0, 0));
    assert_eq!(r["error"]["code"], -32002);
    // A body that is not JSON, then JSON that is no message: errors with a null id.
    c.write_raw(b"Content-Length: 5\r\n\r\n{oops");
    let v = c.next();
    assert_eq!(
        (v["id"].clone(), v["error"]["code"].clone()),
        (Value::Null, json!(-32700))
    );
    c.write_raw(b"Content-Length: 2\r\n\r\n[]");
    let v = c.next();
    assert_eq!(
        (v["id"].clone(), v["error"]["code"].clone()),
        (Value::Null, json!(-32600))
    );
    c.initialize(&dir, Value::Null);
    // Bad params, an unknown method, a second initialize.
    let r = c.request("textDocument/hover", json!({"textDocument": 3}));
    assert_eq!(r["error"]["code"], -32602);
    let r = c.request("plcc/nothing", json!({}));
    assert_eq!(r["error"]["code"], -32601);
    let r = c.request("initialize", json!({"capabilities": {}}));
    assert_eq!(r["error"]["code"], -32600);
    // A notification with bad params is dropped; the server goes on.
    c.notify("textDocument/didOpen", json!({"textDocument": "x"}));
    // A document that is not a file, and one in a folder that does not exist.
    c.notify(
        "textDocument/didOpen",
        json!({"textDocument": {"uri": "untitled:1", "languageId": "st", "version": 1, "text": "x"}}),
    );
    let ghost = dir.join("no/such/b.st");
    c.notify(
        "textDocument/didOpen",
        json!({"textDocument": {"uri": uri(&ghost), "languageId": "st", "version": 1, "text": "PROGRAM"}}),
    );
    assert_ne!(c.diagnostics(&uri(&ghost)), json!([]));
    // A position past the end of the text is its end, where the error is.
    let hover = c.call("textDocument/hover", at(&ghost, 99, 99));
    let text = hover["contents"]["value"].as_str().expect("a hover");
    assert!(text.starts_with("**E0101** "), "{text}");
    // After shutdown, requests are refused; exit ends with 0.
    assert_eq!(c.call("shutdown", Value::Null), Value::Null);
    let r = c.request("textDocument/hover", at(&ghost, 0, 0));
    assert_eq!(r["error"]["code"], -32600);
    c.notify("exit", Value::Null);
    assert_eq!(c.finish(), 0);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn broken_input_ends_the_server_with_status_1() {
    let cases: [&[u8]; 5] = [
        b"hello, this is not LSP\n",
        b"Content-Length: 99999999999999999\r\n\r\n",
        b"Content-Length: x\r\n\r\n{}",
        b"Content-Type: text\r\n\r\n{}",
        b"Content-Length: 100\r\n\r\n{\"jsonrpc\"",
    ];
    for input in cases {
        let mut c = Client::start();
        c.write_raw(input);
        assert_eq!(c.finish(), 1, "{}", String::from_utf8_lossy(input));
    }
    // An exit without shutdown, and the end of the input without exit.
    let mut c = Client::start();
    c.notify("exit", Value::Null);
    assert_eq!(c.finish(), 1);
    let c = Client::start();
    assert_eq!(c.finish(), 1);
}

#[test]
fn rename_formatting_and_the_explanation_of_a_code() {
    const MESSY: &str = "program P\nvar x:int;\nend_var\nx:=x+1;\nend_program\n";
    const MESSY_STL: &str = "program tick;\nbegin\nvar x:INT; end_var;\nx:=x+1;\nend.\n";
    const MESSY_IL: &str =
        "function incr : int\nvar_input a:int; end_var\nld a\n add 1\nst incr\nend_function\n";
    let dir = workspace(
        "rename",
        &[
            ("motor.st", MOTOR),
            ("main.st", MAIN),
            ("messy.st", MESSY),
            ("messy.il", MESSY_IL),
            ("messy.stl", MESSY_STL),
        ],
    );
    let (main, motor, messy) = (
        dir.join("main.st"),
        dir.join("motor.st"),
        dir.join("messy.st"),
    );
    let mut c = Client::start();
    c.initialize(&dir, Value::Null);
    c.open(&main);
    assert_eq!(c.diagnostics(&uri(&main))[0]["code"], "E0201");

    // On the undeclared name: the explanation `plcc explain E0201` prints.
    let explain = Command::new(env!("CARGO_BIN_EXE_plcc"))
        .args(["explain", "E0201"])
        .output()
        .expect("plcc explain");
    let explain = String::from_utf8(explain.stdout).expect("UTF-8");
    let (title, text) = explain
        .trim_end()
        .strip_prefix("E0201: ")
        .and_then(|t| t.split_once("\n\n"))
        .expect("a title and a text");
    assert_eq!(
        c.call("textDocument/hover", at(&main, 7, 31)),
        json!({
            "contents": {"kind": "markdown", "value": format!("**E0201** {title}\n\n{text}")},
            "range": range(7, 30, 7, 34),
        })
    );

    // The comment right before a POU is its doc.
    let hover = c.call("textDocument/hover", at(&main, 1, 9));
    assert_eq!(
        hover["contents"]["value"],
        "```iecst\nPROGRAM Main\n```\n\nTempérature of the café: ☕"
    );

    // `running` renamed from its use in main.st: the declaration and both uses.
    let rename = |c: &mut Client, line, character, name: &str| {
        let mut p = at(&main, line, character);
        p["newName"] = json!(name);
        c.request("textDocument/rename", p)
    };
    let edit = |l0, c0, l1, c1| json!({"range": range(l0, c0, l1, c1), "newText": "on"});
    assert_eq!(
        rename(&mut c, 7, 20, "on")["result"],
        json!({"changes": {
            uri(&main): [edit(7, 18, 7, 25)],
            uri(&motor): [edit(6, 4, 6, 11), edit(8, 0, 8, 7)],
        }})
    );
    // Refused: a name taken in the FB, a keyword, something of the standard library.
    let refused = |r: Value| {
        r["error"]["message"]
            .as_str()
            .expect("an error")
            .to_string()
    };
    let taken = refused(rename(&mut c, 7, 20, "speed"));
    assert!(
        taken.starts_with("renaming `running` to `speed` would give E"),
        "{taken}"
    );
    assert!(refused(rename(&mut c, 7, 20, "END_IF")).contains("is not a name"));
    c.notify(
        "textDocument/didChange",
        json!({
            "textDocument": {"uri": uri(&main), "version": 2},
            "contentChanges": [{"text": MAIN
                .replace("    go : BOOL;", "    go : BOOL;\n    latch : SR;")
                .replace("AND nope", "AND go")}],
        }),
    );
    assert_eq!(c.diagnostics(&uri(&main)), json!([]));
    assert!(refused(rename(&mut c, 5, 13, "Latch")).contains("standard library"));

    // Formatting: one edit over the whole text, then none.
    let format = |c: &mut Client| {
        c.call(
            "textDocument/formatting",
            json!({"textDocument": {"uri": uri(&messy)}, "options": {"tabSize": 4, "insertSpaces": true}}),
        )
    };
    let formatted = "PROGRAM P\nVAR x : int;\nEND_VAR\n    x := x + 1;\nEND_PROGRAM\n";
    assert_eq!(
        format(&mut c),
        json!([{"range": range(0, 0, 5, 0), "newText": formatted}])
    );
    c.open(&messy);
    c.notify(
        "textDocument/didChange",
        json!({
            "textDocument": {"uri": uri(&messy), "version": 2},
            "contentChanges": [{"text": formatted}],
        }),
    );
    assert_eq!(format(&mut c), json!([]));
    // An Instruction List document: its instructions indented, the operators in
    // upper case.
    let il = c.call(
        "textDocument/formatting",
        json!({"textDocument": {"uri": uri(&dir.join("messy.il"))}, "options": {"tabSize": 4, "insertSpaces": true}}),
    );
    let formatted_il = "FUNCTION incr : int\nVAR_INPUT a : int; END_VAR\n    LD a\n    ADD 1\n    ST incr\nEND_FUNCTION\n";
    assert_eq!(
        il,
        json!([{"range": range(0, 0, 6, 0), "newText": formatted_il}])
    );
    // And an STL one: reserved words in upper case, the block indented.
    let stl = c.call(
        "textDocument/formatting",
        json!({"textDocument": {"uri": uri(&dir.join("messy.stl"))}, "options": {"tabSize": 4, "insertSpaces": true}}),
    );
    let formatted_stl = "PROGRAM tick;\nBEGIN\n    VAR x : INT; END_VAR;\n    x := x + 1;\nEND.\n";
    assert_eq!(
        stl,
        json!([{"range": range(0, 0, 5, 0), "newText": formatted_stl}])
    );

    assert_eq!(c.shutdown_and_exit(), 0);
    let _ = std::fs::remove_dir_all(&dir);
}

/// A server initialized on `dir`, and the token types of its semantic-token legend.
fn started_with_legend(dir: &Path) -> (Client, Vec<Value>) {
    let mut c = Client::start();
    let init = c.request(
        "initialize",
        json!({"processId": null, "rootUri": uri(dir), "capabilities": {}}),
    );
    let legend = init["result"]["capabilities"]["semanticTokensProvider"]["legend"]["tokenTypes"]
        .as_array()
        .expect("a legend")
        .clone();
    c.notify("initialized", json!({}));
    (c, legend)
}

/// The semantic tokens of `text`, the one file (`name`) of a workspace of its own
/// (`dir`), decoded as [`semantic_tokens`] does; the server shut down after.
fn tokens_of_one_file(dir: &str, name: &str, text: &str) -> Vec<String> {
    let dir = workspace(dir, &[(name, text)]);
    let file = dir.join(name);
    let (mut c, legend) = started_with_legend(&dir);
    c.open(&file);
    let tokens = semantic_tokens(&mut c, &legend, &file);
    assert_eq!(c.shutdown_and_exit(), 0);
    let _ = std::fs::remove_dir_all(&dir);
    tokens
}

/// A document's semantic tokens, decoded: `line:column+length type`.
fn semantic_tokens(c: &mut Client, legend: &[Value], path: &Path) -> Vec<String> {
    let data = c.call(
        "textDocument/semanticTokens/full",
        json!({"textDocument": {"uri": uri(path)}}),
    )["data"]
        .as_array()
        .expect("data")
        .iter()
        .map(|v| v.as_u64().expect("a number") as u32)
        .collect::<Vec<_>>();
    let (mut line, mut col) = (0, 0);
    let mut got = Vec::new();
    for t in data.chunks(5) {
        if t[0] > 0 {
            col = 0;
        }
        line += t[0];
        col += t[1];
        got.push(format!(
            "{line}:{col}+{} {}",
            t[2],
            legend[t[3] as usize].as_str().expect("a name")
        ));
    }
    got
}

#[test]
fn semantic_tokens_of_instruction_list() {
    const TEXT: &str = "FUNCTION_BLOCK Latch
VAR_INPUT set, st : BOOL; END_VAR
VAR_OUTPUT q : BOOL; END_VAR
    LD set
    OR( q
    ANDN st
    )
    ST q
done: RET
END_FUNCTION_BLOCK
";
    // The operators are keywords (`OR` is one to the lexer anyway); `st`, an
    // input named like the operator, is a parameter where it is an operand.
    assert_eq!(
        tokens_of_one_file("il_tokens", "latch.il", TEXT),
        [
            "0:0+14 keyword",
            "0:15+5 class",
            "1:0+9 keyword",
            "1:10+3 parameter",
            "1:15+2 parameter",
            "1:20+4 type",
            "1:26+7 keyword",
            "2:0+10 keyword",
            "2:11+1 parameter",
            "2:15+4 type",
            "2:21+7 keyword",
            "3:4+2 keyword",
            "3:7+3 parameter",
            "4:4+2 keyword",
            "4:8+1 parameter",
            "5:4+4 keyword",
            "5:9+2 parameter",
            "7:4+2 keyword",
            "7:7+1 parameter",
            "8:6+3 keyword",
            "9:0+18 keyword",
        ]
    );
}

#[test]
fn semantic_tokens_of_stl() {
    const TEXT: &str = "(* a counter *)
program count;
begin
  var
    n : INT := 16#0F;
  end_var;
  if n < 100 then n := n + 1;
end.
";
    assert_eq!(
        tokens_of_one_file("stl_tokens", "count.stl", TEXT),
        [
            "0:0+15 comment",
            "1:0+7 keyword",
            "1:8+5 namespace",
            "2:0+5 keyword",
            "3:2+3 keyword",
            "4:4+1 variable",
            "4:8+3 type",
            "4:15+5 number",
            "5:2+7 keyword",
            "6:2+2 keyword",
            "6:5+1 variable",
            "6:9+3 number",
            "6:13+4 keyword",
            "6:18+1 variable",
            "6:23+1 variable",
            "6:27+1 number",
            "7:0+3 keyword",
        ]
    );
}

#[test]
fn semantic_tokens_say_what_each_word_is() {
    const TEXT: &str = "FUNCTION_BLOCK Motor (* a motor,
   two lines *)
VAR_INPUT
    start : BOOL;
END_VAR
VAR
    n : INT := 16#FF;
    s : STRING := 'é';
    p : Pump;
END_VAR
n := ABS(n) + 1;
p(on := start);
END_FUNCTION_BLOCK
FUNCTION_BLOCK Pump
VAR_INPUT on : BOOL; END_VAR
END_FUNCTION_BLOCK
";
    let dir = workspace("tokens", &[("motor.st", TEXT)]);
    let motor = dir.join("motor.st");
    let (mut c, legend) = started_with_legend(&dir);
    c.open(&motor);
    assert_eq!(
        semantic_tokens(&mut c, &legend, &motor),
        [
            "0:0+14 keyword",
            "0:15+5 class",
            "0:21+11 comment",
            "1:3+12 comment",
            "2:0+9 keyword",
            "3:4+5 parameter",
            "3:12+4 type",
            "4:0+7 keyword",
            "5:0+3 keyword",
            "6:4+1 variable",
            "6:8+3 type",
            "6:15+5 number",
            "7:4+1 variable",
            "7:8+6 type",
            "7:18+3 string",
            "8:4+1 variable",
            "8:8+4 class",
            "9:0+7 keyword",
            "10:0+1 variable",
            "10:5+3 function",
            "10:9+1 variable",
            "10:14+1 number",
            "11:0+1 variable",
            "11:2+2 parameter",
            "11:8+5 parameter",
            "12:0+18 keyword",
            "13:0+14 keyword",
            "13:15+4 class",
            "14:0+9 keyword",
            "14:10+2 parameter",
            "14:15+4 type",
            "14:21+7 keyword",
            "15:0+18 keyword",
        ]
    );
    // Names no file declares: a standard function's signature.
    assert_eq!(
        c.call("textDocument/hover", at(&motor, 10, 6)),
        json!({
            "contents": {"kind": "markdown", "value": "```iecst\nABS(IN : ANY_NUM) : ANY_NUM\n```\n\nstandard function"},
            "range": range(10, 5, 10, 8),
        })
    );
    assert_eq!(c.shutdown_and_exit(), 0);
    let _ = std::fs::remove_dir_all(&dir);
}

/// A PLCopen project of two POUs: a FUNCTION_BLOCK with an ST body, a PROGRAM with a
/// ladder body (a contact on `alarm`, a coil on `lamp`).
const PLANT_XML: &str = r#"<?xml version="1.0" encoding="utf-8"?>
<project xmlns="http://www.plcopen.org/xml/tc6_0201" xmlns:xhtml="http://www.w3.org/1999/xhtml">
  <fileHeader companyName="plcc" productName="lsp" productVersion="1" creationDateTime="2024-05-01T10:00:00"/>
  <contentHeader name="plant">
    <coordinateInfo>
      <fbd><scaling x="1" y="1"/></fbd>
      <ld><scaling x="1" y="1"/></ld>
      <sfc><scaling x="1" y="1"/></sfc>
    </coordinateInfo>
  </contentHeader>
  <types>
    <dataTypes/>
    <pous>
      <pou name="Pump" pouType="functionBlock">
        <interface>
          <inputVars>
            <variable name="level"><type><INT/></type></variable>
          </inputVars>
          <outputVars>
            <variable name="run"><type><BOOL/></type></variable>
          </outputVars>
        </interface>
        <body>
          <ST>
            <xhtml:p><![CDATA[run := level > 10;]]></xhtml:p>
          </ST>
        </body>
      </pou>
      <pou name="Plant" pouType="program">
        <interface>
          <localVars>
            <variable name="p"><type><derived name="Pump"/></type></variable>
            <variable name="alarm"><type><BOOL/></type></variable>
          </localVars>
          <outputVars>
            <variable name="lamp"><type><BOOL/></type></variable>
          </outputVars>
        </interface>
        <body>
          <LD>
            <leftPowerRail localId="1" width="2" height="40">
              <position x="10" y="10"/>
              <connectionPointOut formalParameter=""><relPosition x="2" y="20"/></connectionPointOut>
            </leftPowerRail>
            <contact localId="2" negated="false" width="20" height="20">
              <position x="40" y="20"/>
              <connectionPointIn><relPosition x="0" y="10"/><connection refLocalId="1"/></connectionPointIn>
              <connectionPointOut><relPosition x="20" y="10"/></connectionPointOut>
              <variable>alarm</variable>
            </contact>
            <coil localId="3" negated="false" width="20" height="20">
              <position x="80" y="20"/>
              <connectionPointIn><relPosition x="0" y="10"/><connection refLocalId="2"/></connectionPointIn>
              <connectionPointOut><relPosition x="20" y="10"/></connectionPointOut>
              <variable>lamp</variable>
            </coil>
            <rightPowerRail localId="4" width="2" height="40">
              <position x="120" y="10"/>
              <connectionPointIn><relPosition x="0" y="20"/><connection refLocalId="3"/></connectionPointIn>
            </rightPowerRail>
          </LD>
        </body>
      </pou>
    </pous>
  </types>
  <instances>
    <configurations/>
  </instances>
</project>
"#;

/// Uses the function block of `plant.xml`.
const PLANT_MAIN: &str = r#"PROGRAM Main
VAR
    p2 : Pump;
    r : BOOL;
END_VAR
p2(level := 20);
r := p2.run;
END_PROGRAM
"#;

/// A FUNCTION with an output besides its result.
const SPLIT_ST: &str = r#"FUNCTION split : INT
VAR_INPUT
    x : INT;
END_VAR
VAR_OUTPUT
    rest : INT;
END_VAR
split := x / 10;
rest := x MOD 10;
END_FUNCTION
"#;

/// An FBD program calling `split` as a block with both outputs wired: the view
/// writes the output `rest => …` itself, from the block.
const CUT_XML: &str = r#"<?xml version="1.0" encoding="utf-8"?>
<project xmlns="http://www.plcopen.org/xml/tc6_0201">
  <fileHeader companyName="plcc" productName="lsp" productVersion="1" creationDateTime="2024-05-01T10:00:00"/>
  <contentHeader name="cut"/>
  <types>
    <dataTypes/>
    <pous>
      <pou name="Cut" pouType="program">
        <interface>
          <localVars>
            <variable name="n"><type><INT/></type></variable>
            <variable name="hi"><type><INT/></type></variable>
            <variable name="lo"><type><INT/></type></variable>
          </localVars>
        </interface>
        <body>
          <FBD>
            <inVariable localId="1" width="20" height="20">
              <position x="10" y="10"/>
              <connectionPointOut><relPosition x="20" y="10"/></connectionPointOut>
              <expression>n</expression>
            </inVariable>
            <block localId="2" typeName="split" width="40" height="40">
              <position x="50" y="10"/>
              <inputVariables>
                <variable formalParameter="x">
                  <connectionPointIn><relPosition x="0" y="10"/><connection refLocalId="1"/></connectionPointIn>
                </variable>
              </inputVariables>
              <inOutVariables/>
              <outputVariables>
                <variable formalParameter="OUT"><connectionPointOut><relPosition x="40" y="10"/></connectionPointOut></variable>
                <variable formalParameter="rest"><connectionPointOut><relPosition x="40" y="30"/></connectionPointOut></variable>
              </outputVariables>
            </block>
            <outVariable localId="3" width="20" height="20">
              <position x="120" y="10"/>
              <connectionPointIn><relPosition x="0" y="10"/><connection refLocalId="2" formalParameter="OUT"/></connectionPointIn>
              <expression>hi</expression>
            </outVariable>
            <outVariable localId="4" width="20" height="20">
              <position x="120" y="40"/>
              <connectionPointIn><relPosition x="0" y="10"/><connection refLocalId="2" formalParameter="rest"/></connectionPointIn>
              <expression>lo</expression>
            </outVariable>
          </FBD>
        </body>
      </pou>
    </pous>
  </types>
  <instances><configurations/></instances>
</project>
"#;

/// `edits` (LSP text edits, on ASCII text) applied to `text`.
fn apply_edits(text: &str, edits: &Value) -> String {
    let offset = |p: &Value| {
        let line = p["line"].as_u64().expect("line") as usize;
        let start: usize = text.split_inclusive('\n').take(line).map(str::len).sum();
        start + p["character"].as_u64().expect("character") as usize
    };
    let mut edits: Vec<(usize, usize, &str)> = edits
        .as_array()
        .expect("edits")
        .iter()
        .map(|e| {
            (
                offset(&e["range"]["start"]),
                offset(&e["range"]["end"]),
                e["newText"].as_str().expect("text"),
            )
        })
        .collect();
    edits.sort_by_key(|e| std::cmp::Reverse(e.0));
    let mut out = text.to_string();
    for (s, e, t) in edits {
        out.replace_range(s..e, t);
    }
    out
}

#[test]
fn references_and_rename_inside_plcopen_xml() {
    let dir = workspace(
        "plcopen",
        &[
            ("plant.xml", PLANT_XML),
            ("main.st", PLANT_MAIN),
            ("split.st", SPLIT_ST),
            ("cut.xml", CUT_XML),
        ],
    );
    let (plant, main, split, cut) = (
        dir.join("plant.xml"),
        dir.join("main.st"),
        dir.join("split.st"),
        dir.join("cut.xml"),
    );
    let mut c = Client::start();
    c.initialize(&dir, Value::Null);
    c.open(&main);
    assert_eq!(c.diagnostics(&uri(&main)), json!([]));
    let loc = |p: &Path, l0, c0, l1, c1| json!({"uri": uri(p), "range": range(l0, c0, l1, c1)});
    let references = |c: &mut Client, p: &Path, line, character, decl: bool| {
        let mut q = at(p, line, character);
        q["context"] = json!({"includeDeclaration": decl});
        c.call("textDocument/references", q)
    };

    // `run` from its use in main.st: that use, then in plant.xml its declaration
    // (`<variable name="run">`) and its use in the ST body.
    assert_eq!(
        references(&mut c, &main, 6, 9, true),
        json!([
            loc(&main, 6, 8, 6, 11),
            loc(&plant, 19, 28, 19, 31),
            loc(&plant, 24, 30, 24, 33),
        ])
    );
    // `alarm` asked from the ladder contact in the XML: the contact's variable.
    assert_eq!(
        references(&mut c, &plant, 48, 25, false),
        json!([loc(&plant, 48, 24, 48, 29)])
    );
    // The definition of `Pump` from main.st: the POU's name in the XML.
    assert_eq!(
        c.call("textDocument/definition", at(&main, 2, 10)),
        loc(&plant, 13, 17, 13, 21)
    );
    // The input `x` of split.st: also the block's formal parameter in cut.xml; the
    // output `rest`: not its use by the block, which the XML does not write as such.
    assert_eq!(
        references(&mut c, &split, 2, 4, true),
        json!([
            loc(&split, 2, 4, 2, 5),
            loc(&split, 7, 9, 7, 10),
            loc(&split, 8, 8, 8, 9),
            loc(&cut, 25, 43, 25, 44),
        ])
    );
    assert_eq!(
        references(&mut c, &split, 5, 4, true),
        json!([loc(&split, 5, 4, 5, 8), loc(&split, 8, 0, 8, 4)])
    );

    let rename = |c: &mut Client, p: &Path, line, character, name: &str| {
        let mut q = at(p, line, character);
        q["newName"] = json!(name);
        c.request("textDocument/rename", q)
    };
    let edit =
        |l0, c0, l1, c1, name: &str| json!({"range": range(l0, c0, l1, c1), "newText": name});
    // `run` renamed: in main.st, and in the XML's declaration and ST body.
    let run = rename(&mut c, &main, 6, 9, "running")["result"].clone();
    assert_eq!(
        run,
        json!({"changes": {
            uri(&main): [edit(6, 8, 6, 11, "running")],
            uri(&plant): [edit(19, 28, 19, 31, "running"), edit(24, 30, 24, 33, "running")],
        }})
    );
    // `Pump` renamed: the POU's name and the type of `p` in the XML, the type of
    // `p2` in main.st.
    let pump = rename(&mut c, &main, 2, 10, "Pump2")["result"].clone();
    assert_eq!(
        pump,
        json!({"changes": {
            uri(&main): [edit(2, 9, 2, 13, "Pump2")],
            uri(&plant): [edit(13, 17, 13, 21, "Pump2"), edit(31, 52, 31, 56, "Pump2")],
        }})
    );
    // `alarm` renamed from the XML: its declaration and the contact.
    let alarm = rename(&mut c, &plant, 48, 25, "fault")["result"].clone();
    assert_eq!(
        alarm,
        json!({"changes": {
            uri(&plant): [edit(32, 28, 32, 33, "fault"), edit(48, 24, 48, 29, "fault")],
        }})
    );
    // Refused: `rest` is used by the block of cut.xml, whose output the view writes
    // itself (at the block, line 23 column 13 of the XML).
    let refused = rename(&mut c, &split, 5, 5, "remainder");
    let why = refused["error"]["message"].as_str().expect("an error");
    assert_eq!(
        why,
        format!(
            "`rest` is used in the PLCopen project {} at 23:13, where the name is not written as such \
             (plcc makes that use from the element), so the XML cannot be edited there safely: rename by hand",
            cut.display()
        )
    );
    // `split`: its declaration and result in split.st, the block's type in cut.xml.
    assert_eq!(
        rename(&mut c, &split, 0, 10, "divide")["result"],
        json!({"changes": {
            uri(&split): [edit(0, 9, 0, 14, "divide"), edit(7, 0, 7, 5, "divide")],
            uri(&cut): [edit(22, 41, 22, 46, "divide")],
        }})
    );
    // Refused while cut.xml does not convert: its uses are not known.
    c.open(&cut);
    c.notify(
        "textDocument/didChange",
        json!({
            "textDocument": {"uri": uri(&cut), "version": 2},
            "contentChanges": [{"text": CUT_XML.replace("</project>", "")}],
        }),
    );
    let why = rename(&mut c, &split, 0, 10, "divide")["error"]["message"].clone();
    assert_eq!(
        why,
        format!(
            "the PLCopen project {} does not convert (it has errors), and it may use `split`: \
             rename there by hand, or mend it first",
            cut.display()
        )
    );
    assert_eq!(c.shutdown_and_exit(), 0);

    // The three renames applied together: the folder still builds, without errors.
    let plant_text = apply_edits(
        &apply_edits(
            &apply_edits(PLANT_XML, &run["changes"][uri(&plant)]),
            &pump["changes"][uri(&plant)],
        ),
        &alarm["changes"][uri(&plant)],
    );
    assert!(plant_text.contains(r#"<variable name="running">"#));
    assert!(plant_text.contains("<![CDATA[running := level > 10;]]>"));
    assert!(plant_text.contains(r#"<pou name="Pump2""#));
    assert!(plant_text.contains("<variable>fault</variable>"));
    let main_text = apply_edits(
        &apply_edits(PLANT_MAIN, &run["changes"][uri(&main)]),
        &pump["changes"][uri(&main)],
    );
    let texts = [
        ("plant.xml", plant_text),
        ("main.st", main_text),
        ("split.st", SPLIT_ST.to_string()),
        ("cut.xml", CUT_XML.to_string()),
    ];
    let build = plcc::driver::build_sources(
        texts
            .iter()
            .map(|(n, t)| (n.to_string(), t.clone().into_bytes()))
            .collect(),
        &plcc::driver::BuildOptions::default(),
    )
    .expect("builds");
    let errors: Vec<String> = build
        .diagnostics
        .iter()
        .filter(|d| d.is_error())
        .map(|d| d.to_string())
        .collect();
    assert_eq!(errors, Vec::<String>::new());
    assert!(build.module.is_some());
    let _ = std::fs::remove_dir_all(&dir);
}

/// Hover and outline asked on a PLCopen XML document: the names resolved through
/// its view, every range in the XML.
#[test]
fn hover_and_outline_inside_plcopen_xml() {
    let dir = workspace(
        "plcopen-outline",
        &[("plant.xml", PLANT_XML), ("main.st", PLANT_MAIN)],
    );
    let plant = dir.join("plant.xml");
    let mut c = Client::start();
    c.initialize(&dir, Value::Null);
    c.open(&plant);
    assert_eq!(c.diagnostics(&uri(&plant)), json!([]));
    let hover = |value: &str, l0, c0, l1, c1| {
        json!({
            "contents": {"kind": "markdown", "value": value},
            "range": range(l0, c0, l1, c1),
        })
    };
    let level = "```iecst\nlevel : INT\n```\n\nVAR_INPUT of `Pump`; type `INT`";
    let run = "```iecst\nrun : BOOL\n```\n\nVAR_OUTPUT of `Pump`; type `BOOL`";
    let pump = "```iecst\nFUNCTION_BLOCK Pump\nVAR_INPUT\n    level : INT;\nEND_VAR\nVAR_OUTPUT\n    run : BOOL;\nEND_VAR\n```";
    // In the ST body `run := level > 10;`: each name where the CDATA has it.
    assert_eq!(
        c.call("textDocument/hover", at(&plant, 24, 38)),
        hover(level, 24, 37, 24, 42)
    );
    assert_eq!(
        c.call("textDocument/hover", at(&plant, 24, 31)),
        hover(run, 24, 30, 24, 33)
    );
    // A variable's declaration `<variable name="run">`, a contact's variable.
    assert_eq!(
        c.call("textDocument/hover", at(&plant, 19, 29)),
        hover(run, 19, 28, 19, 31)
    );
    assert_eq!(
        c.call("textDocument/hover", at(&plant, 48, 25)),
        hover(
            "```iecst\nalarm : BOOL\n```\n\nVAR of `Plant`; type `BOOL`",
            48,
            24,
            48,
            29
        )
    );
    // The FB's name and the type of `p` (`<derived name="Pump"/>`): its interface.
    assert_eq!(
        c.call("textDocument/hover", at(&plant, 13, 18)),
        hover(pump, 13, 17, 13, 21)
    );
    assert_eq!(
        c.call("textDocument/hover", at(&plant, 31, 53)),
        hover(pump, 31, 52, 31, 56)
    );
    // Nothing on the XML's own markup.
    assert_eq!(c.call("textDocument/hover", at(&plant, 13, 8)), Value::Null);

    // The outline: each POU at its `pou name="…"` (the element the view's head
    // comes from), its name where it is written; each variable at its name.
    let var = |name: &str, detail: &str, line: u32| {
        let r = range(line, 28, line, 28 + name.len() as u32);
        json!({"name": name, "detail": detail, "kind": 13, "range": r, "selectionRange": r})
    };
    assert_eq!(
        c.call(
            "textDocument/documentSymbol",
            json!({"textDocument": {"uri": uri(&plant)}}),
        ),
        json!([
            {
                "name": "Pump",
                "detail": "FUNCTION_BLOCK",
                "kind": 5,
                "range": range(13, 7, 13, 21),
                "selectionRange": range(13, 17, 13, 21),
                "children": [
                    var("level", "VAR_INPUT : INT", 16),
                    var("run", "VAR_OUTPUT : BOOL", 19),
                ],
            },
            {
                "name": "Plant",
                "detail": "PROGRAM",
                "kind": 2,
                "range": range(28, 7, 28, 22),
                "selectionRange": range(28, 17, 28, 22),
                "children": [
                    var("p", "VAR : Pump", 31),
                    var("alarm", "VAR : BOOL", 32),
                    var("lamp", "VAR_OUTPUT : BOOL", 35),
                ],
            },
        ])
    );
    assert_eq!(c.shutdown_and_exit(), 0);
    let _ = std::fs::remove_dir_all(&dir);
}
