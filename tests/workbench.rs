//! The workbench page of `plcc serve` (`docs/workbench.md`) in a real headless
//! Chromium, driven through chromedriver by a WebDriver client (fantoccini), on the
//! ladder example `examples/ladder_demo.xml`: the page loads in under a second, its
//! rungs are drawn, the PLC stops and starts from the page, forcing an input from the
//! diagram lights the coil it drives, the trend of the counter moves, the ladder is
//! used from the keyboard and its elements are labelled for screen readers. Every
//! step leaves a screenshot `workbench-*.png`, the page as users see it, in
//! `workbench-screens/` under Cargo's `CARGO_TARGET_TMPDIR`; with `PLCC_BLESS=1` in
//! `docs/img/`, where the docs show them (a plain run leaves the checkout as it was).
//!
//! Needs Debian's `chromium` and `chromium-driver` (`.ci/run` installs them): without
//! them the test fails and says so.

use fantoccini::actions::{
    InputSource, KeyAction, KeyActions, MouseActions, PointerAction, MOUSE_BUTTON_LEFT,
};
use fantoccini::key::Key;
use fantoccini::{Client, ClientBuilder, Locator};
use serde_json::{json, Value as Json};
use std::os::unix::process::CommandExt;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

#[path = "common/server.rs"]
#[allow(dead_code)]
mod server;
use server::Server;

const CHROMIUM: &str = "/usr/bin/chromium";
const CHROMEDRIVER: &str = "/usr/bin/chromedriver";
const PATIENCE: Duration = Duration::from_secs(20);

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// A child process killed when dropped. chromedriver runs in a process group of
/// its own, killed whole: the browsers it started must not outlive a failed test
/// (they would poll their pages and take CPU from everything after).
struct Proc(Child);

impl Drop for Proc {
    fn drop(&mut self) {
        let _ = Command::new("kill")
            .args(["-KILL", "--", &format!("-{}", self.0.id())])
            .stderr(Stdio::null())
            .status();
        if let Ok(None) = self.0.try_wait() {
            let _ = self.0.kill();
        }
        let _ = self.0.wait();
    }
}

/// `plcc serve` on the example (with `extra` arguments), HTTP on a free loopback
/// port: the server and the page's address.
fn serve(example: &Path, extra: &[&str]) -> (Server, String) {
    let example = example.to_str().expect("a UTF-8 path");
    let mut args = vec![example, "--http", "127.0.0.1:0", "--modbus", "none"];
    args.extend_from_slice(extra);
    let mut s = Server::start(&args);
    let url = s.http_url();
    (s, url)
}

/// chromedriver on a free loopback port: the process and its address.
fn chromedriver() -> (Proc, String) {
    let port = std::net::TcpListener::bind("127.0.0.1:0")
        .and_then(|l| l.local_addr())
        .expect("a free port")
        .port();
    let child = Command::new(CHROMEDRIVER)
        .arg(format!("--port={port}"))
        .process_group(0)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .expect("chromedriver starts");
    let p = Proc(child);
    let t = Instant::now();
    while std::net::TcpStream::connect(("127.0.0.1", port)).is_err() {
        assert!(t.elapsed() < PATIENCE, "chromedriver does not listen");
        std::thread::sleep(Duration::from_millis(20));
    }
    (p, format!("http://127.0.0.1:{port}"))
}

async fn browser(driver: &str, profile: &Path) -> Client {
    let mut caps = serde_json::Map::new();
    caps.insert(
        "goog:chromeOptions".into(),
        json!({
            "binary": CHROMIUM,
            "args": [
                "--headless",
                "--no-sandbox",
                "--disable-gpu",
                "--disable-quic",
                "--no-first-run",
                "--disable-background-networking",
                "--disable-component-update",
                "--disable-sync",
                // Containers often give /dev/shm 64 MB, too little for Chromium.
                "--disable-dev-shm-usage",
                "--window-size=1400,1000",
                format!("--user-data-dir={}", profile.display()),
            ],
        }),
    );
    ClientBuilder::new(hyper_util::client::legacy::connect::HttpConnector::new())
        .capabilities(caps)
        .connect(driver)
        .await
        .expect("a WebDriver session with Chromium")
}

async fn js(c: &Client, script: &str) -> Json {
    c.execute(script, vec![]).await.expect("the script runs")
}

/// Empties the view's status line, which the page writes last when it has drawn a
/// diagram: waiting for it to fill again waits for the new drawing.
async fn clear_status(c: &Client) {
    js(
        c,
        "document.getElementById('view-info').textContent = ''; return true",
    )
    .await;
}

/// Waits until `script` returns true.
async fn until(c: &Client, what: &str, script: &str) {
    let t = Instant::now();
    loop {
        if js(c, script).await == json!(true) {
            return;
        }
        if t.elapsed() > PATIENCE {
            let info = js(
                c,
                "return document.getElementById('view-info')?.textContent ?? ''",
            )
            .await;
            panic!("the page never showed {what} (its status line: {info})");
        }
        tokio::time::sleep(Duration::from_millis(50)).await;
    }
}

async fn screenshot(c: &Client, name: &str) {
    let png = c.screenshot().await.expect("a screenshot");
    let dir = if std::env::var_os("PLCC_BLESS").is_some() {
        root().join("docs/img")
    } else {
        Path::new(env!("CARGO_TARGET_TMPDIR")).join("workbench-screens")
    };
    std::fs::create_dir_all(&dir).expect("the screenshot directory");
    std::fs::write(dir.join(format!("workbench-{name}.png")), png).expect("the screenshot saved");
}

async fn count(c: &Client, selector: &str) -> usize {
    c.find_all(Locator::Css(selector))
        .await
        .expect("find")
        .len()
}

async fn click(c: &Client, selector: &str) {
    c.find(Locator::Css(selector))
        .await
        .unwrap_or_else(|e| panic!("no `{selector}`: {e}"))
        .click()
        .await
        .unwrap_or_else(|e| panic!("cannot click `{selector}`: {e}"));
}

async fn drive(c: &Client, page: &str) {
    // Loading: the project, the variables, the first ladder POU drawn.
    c.goto(page).await.expect("the page loads");
    until(
        c,
        "the diagram",
        "return document.body.dataset.ready === 'true'",
    )
    .await;
    let timing = "const n = performance.getEntriesByType('navigation')[0]; return n.loadEventEnd - n.startTime;";
    let mut loads = vec![js(c, timing).await.as_f64().expect("navigation timing")];
    // The first navigation of a fresh browser also starts its renderer: under a
    // loaded machine, a second load tells the page's own time.
    if loads[0] >= 1000.0 {
        c.refresh().await.expect("reloaded");
        until(
            c,
            "the diagram",
            "return document.body.dataset.ready === 'true'",
        )
        .await;
        loads.push(js(c, timing).await.as_f64().expect("navigation timing"));
    }
    let parts = js(
        c,
        "const n = performance.getEntriesByType('navigation')[0]; \
         return {response: n.responseEnd - n.startTime, dom: n.domContentLoadedEventEnd - n.startTime, \
         assets: performance.getEntriesByType('resource').map(r => [r.name.split('/').pop(), Math.round(r.responseEnd - r.startTime)])}",
    )
    .await;
    eprintln!("the page loaded in {loads:?} ms ({parts})");
    assert!(
        loads.iter().any(|&l| l < 1000.0),
        "the page took {loads:?} ms to load"
    );

    screenshot(c, "ladder").await;
    // The rungs: 2 rails, 7 contacts, 3 coils, 2 blocks, 2 literals, 1 output
    // variable, and a wire for every connection (20).
    assert_eq!(count(c, "svg .el-leftPowerRail").await, 1);
    assert_eq!(count(c, "svg .el-rightPowerRail").await, 1);
    assert_eq!(count(c, "svg .el-contact").await, 7);
    assert_eq!(count(c, "svg .el-coil").await, 3);
    assert_eq!(count(c, "svg .el-block").await, 2);
    assert_eq!(count(c, "svg .el-inVariable").await, 2);
    assert_eq!(count(c, "svg .el-outVariable").await, 1);
    assert_eq!(count(c, "svg .wire").await, 20);
    // Every element is labelled for screen readers and reachable by the keyboard.
    let unlabelled = js(
        c,
        "return [...document.querySelectorAll('svg .el')].filter(e => !e.getAttribute('aria-label') || e.getAttribute('tabindex') !== '0').length",
    )
    .await;
    assert_eq!(unlabelled, json!(0));
    let unnamed_buttons = js(
        c,
        "return [...document.querySelectorAll('button, input')].filter(b => !(b.getAttribute('aria-label') || b.textContent.trim())).length",
    )
    .await;
    assert_eq!(unnamed_buttons, json!(0));

    // Keyboard: the arrows move along the rung, Enter selects.
    js(
        c,
        "document.querySelector('svg .el-contact[data-var=start_pb]').focus(); return true",
    )
    .await;
    let focused = "return document.activeElement.getAttribute('aria-label')";
    press(c, &[Key::Right.into()]).await;
    let right = js(c, focused).await;
    assert!(
        right
            .as_str()
            .is_some_and(|s| s.contains("normally closed contact stop_pb")),
        "ArrowRight from start_pb went to {right}"
    );
    press(c, &[Key::Left.into()]).await;
    let left = js(c, focused).await;
    assert!(
        left.as_str()
            .is_some_and(|s| s.starts_with("normally open contact start_pb")),
        "ArrowLeft from stop_pb went to {left}"
    );
    press(c, &[Key::Down.into()]).await;
    let down = js(c, focused).await;
    assert!(
        down.as_str()
            .is_some_and(|s| s.starts_with("normally open contact motor")),
        "ArrowDown from start_pb went to {down}"
    );
    press(c, &[Key::Enter.into()]).await;
    until(
        c,
        "the inspector",
        "return !document.getElementById('inspector').hidden",
    )
    .await;

    // Stop and start from the page.
    click(c, "#btn-stop").await;
    until(
        c,
        "the stopped state",
        "return document.getElementById('state').textContent.startsWith('stopped')",
    )
    .await;
    let motor_on =
        "return document.querySelector('svg .el-coil[data-var=motor]').classList.contains('on')";
    assert_eq!(js(c, motor_on).await, json!(false));
    click(c, "#btn-start").await;
    until(
        c,
        "the running state",
        "return document.getElementById('state').textContent.startsWith('running')",
    )
    .await;

    // Forcing the start button from the diagram lights the motor's coil and the
    // wires of its rung.
    click(c, "svg .el-contact[data-var=start_pb]").await;
    click(c, "button[aria-label='Force main.start_pb TRUE']").await;
    until(c, "the motor's coil lit", motor_on).await;
    until(
        c,
        "the start contact lit",
        "return document.querySelector('svg .el-contact[data-var=start_pb]').classList.contains('on')",
    )
    .await;
    assert!(count(c, "svg .wire.on").await >= 4);
    screenshot(c, "force").await;

    // Released, the motor stays sealed in; the counter's trend moves.
    click(c, "button[aria-label='Unforce main.start_pb']").await;
    let input = c
        .find(Locator::Css("#watch-input"))
        .await
        .expect("the watch input");
    input.send_keys("main.parts").await.expect("typed");
    click(c, "#watch-add button").await;
    until(
        c,
        "the counter in the watch table",
        "return document.querySelectorAll('#watch-body tr').length === 1",
    )
    .await;
    let trend =
        "const s = window.plccWorkbench.trend('main.parts').filter(v => v !== null); return s";
    let first = Instant::now();
    until(
        c,
        "the counter's trend rising",
        "const s = window.plccWorkbench.trend('main.parts').filter(v => v !== null); return s.length > 5 && s[s.length - 1] >= s[0] + 3",
    )
    .await;
    let samples = js(c, trend).await;
    let s = samples.as_array().expect("samples");
    assert!(
        s.windows(2).all(|w| w[0].as_f64() <= w[1].as_f64()),
        "the counter went down: {samples}"
    );
    assert!(first.elapsed() < Duration::from_secs(10));
    assert_eq!(js(c, motor_on).await, json!(true));
    assert_eq!(count(c, "#trend .u-over").await, 1, "uPlot draws the trend");
    screenshot(c, "trend").await;

    build(c).await;
    edit(c).await;

    // The source of the project in the editor, checked by the compiler.
    js(c, "[...document.querySelectorAll('.tree-head')].find(b => b.textContent === 'Files').click(); return true").await;
    click(c, "button[aria-label='file examples/ladder_demo.xml']").await;
    until(c, "the editor", "return !!document.querySelector('.cm-editor') && !document.getElementById('editor').hidden").await;
    until(
        c,
        "the check",
        "return document.getElementById('view-info').textContent.startsWith('checked')",
    )
    .await;
    screenshot(c, "editor").await;

    // An edit that names an undeclared variable: the compiler's diagnostic inline,
    // at the XML element.
    let edited = js(
        c,
        "const v = window.plccWorkbench.editor(); const i = v.state.doc.toString().indexOf('<variable>stop_pb</variable>'); \
         if (i < 0) return false; \
         v.dispatch({changes: {from: i + 10, to: i + 17, insert: 'stop_btn'}, selection: {anchor: i + 10}, scrollIntoView: true}); return true",
    )
    .await;
    assert_eq!(edited, json!(true));
    until(
        c,
        "the diagnostic",
        "return document.getElementById('view-info').textContent.startsWith('checked: 1 error') && !!document.querySelector('.cm-lintRange-error')",
    )
    .await;
    screenshot(c, "diagnostics").await;
    // Apply refuses the text with the error: the PLC runs on, the project unchanged.
    click(c, "#ed-tools button[data-op='apply']").await;
    until(
        c,
        "the refusal",
        "return document.getElementById('view-info').classList.contains('bad')",
    )
    .await;
    let project = "return JSON.stringify(window.plccWorkbench.state.project)";
    let before = js(c, project).await;
    assert!(before.as_str().is_some_and(|p| p.contains("T#20ms")));
    // Put right, with the task's interval changed: applied, and the project tree
    // shows the new interval.
    let edited = js(
        c,
        "const v = window.plccWorkbench.editor(); let t = v.state.doc.toString();          t = t.replace('<variable>stop_btn</variable>', '<variable>stop_pb</variable>').replace('interval=\"T#20ms\"', 'interval=\"T#50ms\"');          v.dispatch({changes: {from: 0, to: v.state.doc.length, insert: t}}); return t.includes('T#50ms')",
    )
    .await;
    assert_eq!(edited, json!(true));
    click(c, "#ed-tools button[data-op='apply']").await;
    until(
        c,
        "the online change",
        "return document.getElementById('view-info').textContent.startsWith('loaded into the PLC')",
    )
    .await;
    until(
        c,
        "the new project",
        &format!("{project}.includes('T#50ms')"),
    )
    .await;
    let state = js(c, "return document.getElementById('state').textContent").await;
    assert!(
        state.as_str().is_some_and(|t| t.starts_with("running")),
        "the PLC runs after the change: {state}"
    );
}

/// Builds for the chip, the VM and C from the page: the files to download and the
/// resource report.
async fn build(c: &Client) {
    for (target, files) in [
        (
            "vmasm",
            &["ladder_demo.xcp", "ladder_demo.dcp", "ladder_demo.asm"][..],
        ),
        ("c", &["POUS.c", "POUS.h", "VARIABLES.csv"][..]),
        ("pic16f876a", &["ladder_demo.hex", "ladder_demo.asm"][..]),
    ] {
        click(c, &format!("#build-target option[value={target}]")).await;
        click(
            c,
            "button[aria-label='Build the project for the chosen target']",
        )
        .await;
        let links = format!(
            "const names = [...document.querySelectorAll('#build-out a[download]')].map(a => a.getAttribute('download')); \
             return document.querySelector('#build-out .summary')?.textContent.startsWith('{target}:') && {files:?}.every(f => names.includes(f))"
        );
        until(c, &format!("the files built for {target}"), &links).await;
    }
    let summary = js(
        c,
        "return document.querySelector('#build-out .summary').textContent",
    )
    .await;
    assert!(
        summary
            .as_str()
            .is_some_and(|s| s.contains("flash") && s.contains("ram")),
        "the chip's resource report: {summary}"
    );
    screenshot(c, "build").await;
    // A target setting the VM does not have: its diagnostic; then none again.
    let settings = c
        .find(Locator::Id("build-settings"))
        .await
        .expect("the settings field");
    settings.send_keys("bogus=1").await.expect("typed");
    click(c, "#build-target option[value=vmasm]").await;
    click(
        c,
        "button[aria-label='Build the project for the chosen target']",
    )
    .await;
    until(
        c,
        "the setting refused",
        "return document.getElementById('build-out').textContent.includes('unknown setting `bogus`')",
    )
    .await;
    settings.clear().await.expect("cleared");
}

/// A sequential function chart drawn read-only, its active step lit.
async fn sfc(c: &Client, page: &str) {
    c.goto(page).await.expect("the page loads");
    until(
        c,
        "the chart",
        "return document.body.dataset.ready === 'true'",
    )
    .await;
    assert_eq!(count(c, "svg.lang-SFC").await, 1);
    assert_eq!(count(c, "svg .el-step").await, 3);
    assert_eq!(count(c, "svg .el-transition").await, 3);
    assert_eq!(count(c, "svg .el-actionBlock").await, 3);
    assert_eq!(count(c, "svg .el-jumpStep").await, 1);
    let lit = |step: &str| {
        format!("return [...document.querySelectorAll('svg .el-step.on')].map(e => e.getAttribute('aria-label').split(',')[0]).join() === '{step}'")
    };
    until(c, "the initial step lit", &lit("initial step Idle")).await;
    js(
        c,
        "window.plccWorkbench.force('seq.start', true); return true",
    )
    .await;
    until(c, "the step Fill lit", &lit("step Fill")).await;
    screenshot(c, "sfc").await;
    until(c, "the step Drain lit", &lit("step Drain")).await;
}

/// An FBD body drawn read-only, its values live.
async fn fbd(c: &Client, page: &str) {
    c.goto(page).await.expect("the page loads");
    until(
        c,
        "the FBD diagram",
        "return document.body.dataset.ready === 'true'",
    )
    .await;
    assert_eq!(count(c, "svg.lang-FBD").await, 1);
    assert_eq!(count(c, "svg .el-block").await, 8);
    assert!(count(c, "svg .el-inVariable").await >= 2);
    assert!(count(c, "svg .el-outVariable").await >= 2);
    assert_eq!(
        js(c, "return document.getElementById('ld-tools').hidden").await,
        json!(true),
        "FBD is not edited"
    );
    until(
        c,
        "live values at the variables",
        "return [...document.querySelectorAll('svg .value')].some(t => t.textContent !== '') || document.querySelectorAll('svg .wire.on').length > 0",
    )
    .await;
    screenshot(c, "fbd").await;
}

/// What `script` passes to its callback (the last argument), e.g. a fetch's JSON.
/// The page at `page` with its ladder in edit mode: the block types offered.
async fn editing(c: &Client, page: &str) -> Json {
    c.goto(page).await.expect("the page loads");
    until(
        c,
        "the diagram",
        "return document.body.dataset.ready === 'true'",
    )
    .await;
    click(c, "#ld-edit").await;
    js(
        c,
        "return [...document.querySelectorAll('#ld-block-types option')].map(o => o.value)",
    )
    .await
}

/// Apply (the edited file loaded into the PLC), then `main.switch` forced on.
async fn apply_and_switch_on(c: &Client) {
    click(c, "button[data-op=apply]").await;
    until(
        c,
        "the online change",
        "return document.getElementById('view-info').textContent.startsWith('loaded into the PLC')",
    )
    .await;
    js(
        c,
        "window.plccWorkbench.force('main.switch', true); return true",
    )
    .await;
}

/// A function block of the project's own put in a rung from the ladder editor
/// (`tests/workbench/user_block.xml`): offered beside the standard ones, placed
/// after the contact with its other input given a literal, the rung without
/// problems, applied, and the lamp lit through it; a PROGRAM is refused as a block.
async fn user_block(c: &Client, page: &str) {
    let offered = editing(c, page).await;
    assert!(
        offered
            .as_array()
            .is_some_and(|o| o.contains(&json!("Hold")) && o.contains(&json!("TON"))),
        "the block types offered: {offered}"
    );
    let select = "const e = document.querySelector('svg .el-contact[data-var=switch]'); e.focus(); return true";
    js(c, select).await;
    press(c, &[Key::Enter.into()]).await;
    js(
        c,
        "document.getElementById('ld-block').value = 'lamp_demo'; return true",
    )
    .await;
    press(c, &['l']).await;
    until(
        c,
        "a PROGRAM refused as a block",
        "return document.getElementById('view-info').textContent.includes('lamp_demo is a program')",
    )
    .await;
    js(c, select).await;
    press(c, &[Key::Enter.into()]).await;
    js(
        c,
        "document.getElementById('ld-block').value = 'Hold'; return true",
    )
    .await;
    press(c, &['l']).await;
    until(
        c,
        "the Hold block",
        "return !!document.querySelector('svg .el-block[aria-label^=\"block Hold Hold0\"]')",
    )
    .await;
    let problems = js(c, "return [...document.querySelectorAll('svg .has-warning, svg .has-error')].map(e => e.getAttribute('aria-description')).join(' | ')").await;
    assert_eq!(problems, json!(""), "rung checks after adding a Hold");
    assert_eq!(count(c, "svg .el-inVariable").await, 1, "n gets a literal");
    screenshot(c, "user-block").await;
    apply_and_switch_on(c).await;
    let lit = "fetch('/api/vars/main.lamp').then(r => r.json()).then(v => arguments[0](v.value), e => arguments[0](String(e)))";
    let t = Instant::now();
    while js_async(c, lit, vec![]).await != json!(true) {
        assert!(t.elapsed() < PATIENCE, "the lamp never lit through Hold");
        tokio::time::sleep(Duration::from_millis(50)).await;
    }
    let edges = js_async(
        c,
        "fetch('/api/vars/main.Hold0.edges').then(r => r.json()).then(v => arguments[0](v.value), e => arguments[0](String(e)))",
        vec![],
    )
    .await;
    assert_eq!(edges, json!(1), "Hold counted the switch's rising edge");
}

/// Selects the diagram element with localId `id` (as a click does).
async fn select_id(c: &Client, id: &Json) {
    js_async(
        c,
        "const [id, done] = arguments; const s = window.plccWorkbench.state; s.diagram.select(s.diagram.nodes.get(Number(id))); done(true)",
        vec![id.clone()],
    )
    .await;
}

/// The localId of the element feeding input `pin` of the block of type `ty`.
async fn feeding(c: &Client, ty: &str, pin: &str) -> Json {
    js_async(
        c,
        "const [ty, pin, done] = arguments; const ed = window.plccWorkbench.ladder(); \
         const b = ed.elements().find(e => e.getAttribute('typeName') === ty); \
         const v = [...b.getElementsByTagNameNS('*', 'variable')].find(v => v.getAttribute('formalParameter') === pin); \
         done(v.getElementsByTagNameNS('*', 'connection')[0].getAttribute('refLocalId'))",
        vec![json!(ty), json!(pin)],
    )
    .await
}

/// The position of the element with localId `id` in the edited XML.
async fn position(c: &Client, id: &Json) -> Json {
    js_async(
        c,
        "const [id, done] = arguments; const ed = window.plccWorkbench.ladder(); done(ed.pos(ed.byId(id)))",
        vec![id.clone()],
    )
    .await
}

/// A variable's value in the running PLC, polled until `want(value)` or the test's
/// patience runs out.
async fn until_value(c: &Client, path: &str, what: &str, want: impl Fn(&Json) -> bool) {
    let script = format!("fetch('/api/vars/{path}').then(r => r.json()).then(v => arguments[0](v.value), e => arguments[0](String(e)))");
    let t = Instant::now();
    loop {
        let v = js_async(c, &script, vec![]).await;
        if want(&v) {
            return;
        }
        assert!(t.elapsed() < PATIENCE, "{what}: {path} is {v}");
        tokio::time::sleep(Duration::from_millis(50)).await;
    }
}

/// Functions on a rung with EN and ENO: ADD (its result in a new variable), a
/// function of another file of the project (`tests/workbench/above.st`, its BOOL
/// result carrying the power) with a literal set on an input, a TON whose elapsed
/// time is wired out with + Output; the coil moved with Shift+arrow and dragged
/// back with the mouse; applied, and the lamp lit through all of them.
async fn functions(c: &Client, page: &str) {
    let offered = editing(c, page).await;
    for b in ["TON", "ADD", "MOVE", "GT", "Hold", "Above"] {
        assert!(
            offered.as_array().is_some_and(|o| o.contains(&json!(b))),
            "{b} among the block types offered: {offered}"
        );
    }
    let switch = "const e = document.querySelector('svg .el-contact[data-var=switch]'); e.focus(); return true";
    let add_block = |ty: &'static str| async move {
        js(c, switch).await;
        press(c, &[Key::Enter.into()]).await;
        js(
            c,
            &format!("document.getElementById('ld-block').value = '{ty}'; return true"),
        )
        .await;
        press(c, &['l']).await;
        until(
            c,
            ty,
            &format!(
                "return !!document.querySelector('svg .el-block[aria-label^=\"block {ty}\"]')"
            ),
        )
        .await;
    };
    let problems = "return [...document.querySelectorAll('svg .has-warning, svg .has-error')].map(e => e.getAttribute('aria-description')).join(' | ')";
    // ADD: EN takes the power, ENO passes it on, OUT goes to a new INT variable.
    add_block("ADD").await;
    assert_eq!(js(c, problems).await, json!(""), "rung checks after ADD");
    let declared = "const ed = window.plccWorkbench.ladder(); return [...ed.interface.getElementsByTagNameNS('*', 'variable')].map(v => v.getAttribute('name') + ':' + (v.getElementsByTagNameNS('*', 'type')[0].firstElementChild.localName)).join(' ')";
    assert!(
        js(c, declared)
            .await
            .as_str()
            .is_some_and(|d| d.contains("ADD_OUT:INT")),
        "ADD's result declared: {}",
        js(c, declared).await
    );
    assert_eq!(count(c, "svg .el-outVariable[data-var=ADD_OUT]").await, 1);
    assert_eq!(
        count(c, "svg .el-inVariable").await,
        2,
        "IN1 and IN2 get literals"
    );
    // + Output on ADD: nothing left to wire.
    press(c, &['u']).await;
    until(
        c,
        "+ Output refused",
        "return document.getElementById('view-info').textContent.includes('every output of ADD is wired already')",
    )
    .await;
    // A TON before it, its ET wired out with + Output (U).
    add_block("TON").await;
    press(c, &['u']).await;
    until(
        c,
        "TON0.ET wired out",
        "return !!document.querySelector('svg .el-outVariable[data-var=TON0_ET]')",
    )
    .await;
    // Above (another file's function) before that, x set to the literal 5.
    add_block("Above").await;
    assert_eq!(js(c, problems).await, json!(""), "rung checks after Above");
    let x = feeding(c, "Above", "x").await;
    select_id(c, &x).await;
    js(
        c,
        "document.getElementById('ld-var').value = '5'; return true",
    )
    .await;
    click(c, "#ld-var-form button").await;
    until(
        c,
        "x set to 5",
        "return !!document.querySelector('svg .el-inVariable[data-var=\"5\"]')",
    )
    .await;
    screenshot(c, "functions").await;
    // The coil moves down a grid step with Shift+Down, then is dragged 20 up.
    let coil = js(
        c,
        "return document.querySelector('svg .el-coil[data-var=lamp]').dataset.id",
    )
    .await;
    let start = position(c, &coil).await;
    select_id(c, &coil).await;
    clear_status(c).await;
    press(c, &[Key::Shift.into(), Key::Down.into()]).await;
    let t = Instant::now();
    let y0 = start["y"].as_f64().expect("a y");
    while position(c, &coil).await["y"].as_f64() != Some(y0 + 10.0) {
        assert!(t.elapsed() < PATIENCE, "Shift+Down did not move the coil");
        tokio::time::sleep(Duration::from_millis(50)).await;
    }
    // The model moves at once, the drawing when the rung has been checked again: the
    // drag below must find the new drawing (its status line is written last).
    until(
        c,
        "the moved coil drawn",
        "return document.getElementById('view-info').textContent.includes('elements')",
    )
    .await;
    let at = js(
        c,
        "const g = document.querySelector('svg .el-coil[data-var=lamp]'); const r = g.getBoundingClientRect(); \
         return [r.x + r.width / 2, r.y + r.height / 2, g.ownerSVGElement.getScreenCTM().d]",
    )
    .await;
    let (px, py, scale) = (
        at[0].as_f64().unwrap(),
        at[1].as_f64().unwrap(),
        at[2].as_f64().unwrap(),
    );
    let drag = MouseActions::new("mouse".into())
        .then(PointerAction::MoveTo {
            duration: None,
            x: px,
            y: py,
        })
        .then(PointerAction::Down {
            button: MOUSE_BUTTON_LEFT,
        })
        .then(PointerAction::MoveBy {
            duration: Some(Duration::from_millis(100)),
            x: 0.0,
            y: -20.0 * scale,
        })
        .then(PointerAction::Up {
            button: MOUSE_BUTTON_LEFT,
        });
    c.perform_actions(drag).await.expect("the coil dragged");
    let t = Instant::now();
    while position(c, &coil).await["y"].as_f64() != Some(y0 - 10.0) {
        assert!(
            t.elapsed() < PATIENCE,
            "the drag did not move the coil: {}",
            position(c, &coil).await
        );
        tokio::time::sleep(Duration::from_millis(50)).await;
    }
    assert_eq!(
        js(c, problems).await,
        json!(""),
        "rung checks after the moves"
    );
    screenshot(c, "functions-moved").await;
    apply_and_switch_on(c).await;
    until_value(c, "main.lamp", "the lamp through Above, TON and ADD", |v| {
        v == &json!(true)
    })
    .await;
    until_value(c, "main.ADD_OUT", "ADD's result", |v| v == &json!(1)).await;
    until_value(c, "main.TON0_ET", "TON0.ET wired out", |v| {
        v.as_str().is_some_and(|s| s != "T#0ms" && s != "T#0s")
    })
    .await;
}

/// A server started with `--token-file`: a control call without the token is
/// refused (the PLC keeps running) and the page asks for the token; given it, the
/// same call stops the PLC; a wrong one is refused again.
async fn token(c: &Client, page: &str, secret: &str) {
    c.goto(page).await.expect("the page loads");
    until(
        c,
        "the diagram",
        "return document.body.dataset.ready === 'true'",
    )
    .await;
    let state = "return document.getElementById('state').textContent";
    until(
        c,
        "a running PLC",
        &format!("{state}.startsWith('running')"),
    )
    .await;
    assert_eq!(
        js(c, "return document.getElementById('token-form').hidden").await,
        json!(true),
        "the token field shows before any call was refused"
    );
    click(c, "#btn-stop").await;
    until(
        c,
        "the token field",
        "return !document.getElementById('token-form').hidden",
    )
    .await;
    let info = js(c, "return document.getElementById('view-info').textContent").await;
    assert!(
        info.as_str().is_some_and(|t| t.contains("token")),
        "the page says why: {info}"
    );
    // Refused: the PLC still runs (the next status poll says so).
    tokio::time::sleep(Duration::from_millis(1200)).await;
    let now = js(c, state).await;
    assert!(
        now.as_str().is_some_and(|t| t.starts_with("running")),
        "stopped without the token: {now}"
    );
    screenshot(c, "token").await;
    let input = c
        .find(Locator::Css("#token-input"))
        .await
        .expect("the token input");
    input.send_keys(secret).await.expect("typed");
    click(c, "#token-form button").await;
    until(
        c,
        "the token field hidden",
        "return document.getElementById('token-form').hidden",
    )
    .await;
    click(c, "#btn-stop").await;
    until(
        c,
        "a stopped PLC",
        &format!("{state}.startsWith('stopped')"),
    )
    .await;
    // A wrong token: refused, the field shows again, the PLC stays stopped.
    js(
        c,
        "sessionStorage.setItem('plcc-token', 'wrong'); return true",
    )
    .await;
    click(c, "#btn-start").await;
    until(
        c,
        "the token field again",
        "return !document.getElementById('token-form').hidden",
    )
    .await;
    tokio::time::sleep(Duration::from_millis(1200)).await;
    let now = js(c, state).await;
    assert!(
        now.as_str().is_some_and(|t| t.starts_with("stopped")),
        "started with a wrong token: {now}"
    );
}

async fn js_async(c: &Client, script: &str, args: Vec<Json>) -> Json {
    c.execute_async(script, args)
        .await
        .expect("the script answers")
}

/// The diagram the server reads from a PLCopen text.
async fn model_of(c: &Client, text: &Json) -> Json {
    js_async(
        c,
        "const [t, done] = arguments; fetch('/api/diagram/ladder_demo', {method: 'POST', body: t}).then(r => r.json()).then(done, e => done(String(e)))",
        vec![text.clone()],
    )
    .await
}

/// Real key presses (WebDriver actions), to the focused element: the keys down in
/// order, then up in reverse (`[Key::Control.into(), 'z']` is Ctrl+Z).
async fn press(c: &Client, keys: &[char]) {
    let mut a = KeyActions::new("keyboard".into());
    for &k in keys {
        a = a.then(KeyAction::Down { value: k });
    }
    for &k in keys.iter().rev() {
        a = a.then(KeyAction::Up { value: k });
    }
    c.perform_actions(a).await.expect("the keys pressed");
}

/// Ladder editing from the keyboard, undo and redo, and the edited rung through PLCopen XML
/// (load, save, load: the same model), checked and loaded into the PLC.
async fn edit(c: &Client) {
    let contacts = "return document.querySelectorAll('svg .el-contact').length";
    let coils = "return document.querySelectorAll('svg .el-coil').length";
    // The status line is written when the diagram has been drawn: cleared first, it
    // tells the new drawing from the one still on the page (a key pressed on the old
    // one would be lost when the new one replaces it).
    clear_status(c).await;
    click(c, "button[aria-label='Program ladder_demo, LD']").await;
    until(
        c,
        "the ladder again",
        "return document.querySelectorAll('svg .el-contact').length === 7 \
         && document.getElementById('view-info').textContent.includes('elements')",
    )
    .await;
    click(c, "#ld-edit").await;
    let select = |var: &str| {
        format!("const e = document.querySelector('svg .el-contact[data-var={var}]'); e.focus(); return true")
    };
    // C after stop_pb: a contact in series; Ctrl+Z takes it away; C again.
    js(c, &select("stop_pb")).await;
    press(c, &[Key::Enter.into()]).await;
    until(
        c,
        "stop_pb selected",
        "const e = document.querySelector('svg .el-contact.selected[data-var=stop_pb]'); \
         return e !== null && document.activeElement === e",
    )
    .await;
    press(c, &['c']).await;
    until(
        c,
        "a new contact",
        "return document.querySelectorAll('svg .el-contact').length === 8",
    )
    .await;
    press(c, &[Key::Control.into(), 'z']).await;
    until(
        c,
        "the contact undone",
        "return document.querySelectorAll('svg .el-contact').length === 7",
    )
    .await;
    // Ctrl+Y brings it back, Ctrl+Z takes it away again; Ctrl+Y with nothing undone
    // does nothing.
    press(c, &[Key::Control.into(), 'y']).await;
    until(
        c,
        "the contact redone",
        "return document.querySelectorAll('svg .el-contact').length === 8",
    )
    .await;
    press(c, &[Key::Control.into(), 'y']).await;
    until(
        c,
        "nothing to redo",
        "return document.getElementById('view-info').textContent === 'nothing to redo'",
    )
    .await;
    assert_eq!(js(c, contacts).await, json!(8));
    press(c, &[Key::Control.into(), 'z']).await;
    until(
        c,
        "the contact undone again",
        "return document.querySelectorAll('svg .el-contact').length === 7",
    )
    .await;
    js(c, &select("stop_pb")).await;
    press(c, &[Key::Enter.into()]).await;
    press(c, &['c']).await;
    until(c, "the new contact selected", "const e = document.activeElement; return e.dataset.kind === 'contact' && document.querySelectorAll('svg .el-contact').length === 8 && e.dataset.var === 'stop_pb'").await;
    // K: normally closed; its variable set to `full`.
    press(c, &['k']).await;
    until(c, "the contact normally closed", "const e = document.querySelector('svg .el.selected'); return !!e && e.getAttribute('aria-label').startsWith('normally closed contact stop_pb')").await;
    let var = c
        .find(Locator::Id("ld-var"))
        .await
        .expect("the variable field");
    var.clear().await.expect("cleared");
    var.send_keys("full").await.expect("typed");
    click(c, "#ld-var-form button").await;
    until(
        c,
        "the contact on `full`",
        "return !!document.querySelector('svg .el-contact[data-var=full]')",
    )
    .await;
    assert_eq!(js(c, contacts).await, json!(8));
    // L: a TON after `full`, its PT a literal, its instance declared; Delete takes
    // it away, Ctrl+Z brings it back.
    js(c, &select("full")).await;
    press(c, &[Key::Enter.into()]).await;
    press(c, &['l']).await;
    until(
        c,
        "a TON",
        "return !!document.querySelector('svg .el-block[aria-label^=\"block TON TON0\"]')",
    )
    .await;
    assert_eq!(count(c, "svg .el-block").await, 3);
    let problems = js(c, "return [...document.querySelectorAll('svg .has-warning, svg .has-error')].map(e => e.getAttribute('aria-description')).join(' | ')").await;
    assert_eq!(problems, json!(""), "rung checks after adding a TON");
    screenshot(c, "edit-block").await;
    press(c, &[Key::Delete.into()]).await;
    until(
        c,
        "the TON deleted",
        "return document.querySelectorAll('svg .el-block').length === 2",
    )
    .await;
    let problems = js(c, "return [...document.querySelectorAll('svg .has-warning, svg .has-error')].map(e => e.getAttribute('aria-description')).join(' | ')").await;
    assert_eq!(problems, json!(""), "rung checks after deleting the TON");
    press(c, &[Key::Control.into(), 'z']).await;
    until(
        c,
        "the TON back",
        "return document.querySelectorAll('svg .el-block').length === 3",
    )
    .await;
    // B: a branch beside it; Delete takes it away.
    js(c, &select("full")).await;
    press(c, &[Key::Enter.into()]).await;
    press(c, &['b']).await;
    until(
        c,
        "a branch",
        "return document.querySelectorAll('svg .el-contact').length === 9",
    )
    .await;
    press(c, &[Key::Delete.into()]).await;
    until(
        c,
        "the branch deleted",
        "return document.querySelectorAll('svg .el-contact').length === 8",
    )
    .await;
    // No bare wire around `full` is left behind: the rung checks find nothing.
    assert_eq!(count(c, "svg .has-warning, svg .has-error").await, 0);
    // R: a rung, drawn; its contact deleted leaves the coil on the left rail, which
    // the rung checks show at the coil; undone twice.
    press(c, &['r']).await;
    until(
        c,
        "a new rung",
        "return document.querySelectorAll('svg .el-coil').length === 4",
    )
    .await;
    screenshot(c, "edit").await;
    press(c, &[Key::Delete.into()]).await;
    until(
        c,
        "the rung check at the coil",
        "const e = document.querySelector('svg .el-coil.has-warning, svg .el-coil.has-error'); return !!e && /left (power )?rail/i.test(e.getAttribute('aria-description'))",
    )
    .await;
    screenshot(c, "rung-check").await;
    click(c, "button[aria-label='Undo (Ctrl+Z)']").await;
    until(
        c,
        "the contact back",
        "return document.querySelectorAll('svg .el-contact').length === 9",
    )
    .await;
    click(c, "button[aria-label='Undo (Ctrl+Z)']").await;
    until(
        c,
        "the rung undone",
        "return document.querySelectorAll('svg .el-coil').length === 3",
    )
    .await;
    assert_eq!(js(c, coils).await, json!(3));
    assert_eq!(js(c, contacts).await, json!(8));

    // Saved, loaded and saved again: the same model; the new contact between
    // stop_pb and a new TON feeding the motor's coil, normally closed, on `full`.
    let saved = js(c, "return window.plccWorkbench.ladder().text()").await;
    let again = js(
        c,
        "const e = window.plccWorkbench.ladder(); return new e.constructor(e.text(), 'ladder_demo').text()",
    )
    .await;
    let first = model_of(c, &saved).await;
    let second = model_of(c, &again).await;
    assert!(first["elements"].is_array(), "no model: {first}");
    assert_eq!(first, second, "load, save, load changed the model");
    let elems = first["elements"].as_array().unwrap();
    let full = elems
        .iter()
        .find(|e| e["kind"] == "contact" && e["text"] == "full")
        .expect("the new contact");
    assert_eq!(full["negated"], "true");
    let from: Vec<&Json> = full["ins"][0]["conns"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| &c["from"])
        .collect();
    let stop = elems.iter().find(|e| e["text"] == "stop_pb").unwrap();
    assert_eq!(from, [&stop["id"]]);
    let motor = elems
        .iter()
        .find(|e| e["kind"] == "coil" && e["text"] == "motor")
        .unwrap();
    let ton = elems
        .iter()
        .find(|e| e["kind"] == "block" && e["instanceName"] == "TON0")
        .expect("the new TON");
    assert_eq!(ton["typeName"], "TON");
    assert_eq!(ton["ins"][0]["conns"][0]["from"], full["id"]);
    assert_eq!(motor["ins"][0]["conns"][0]["from"], ton["id"]);
    assert_eq!(motor["ins"][0]["conns"][0]["param"], "Q");
    let pt = &ton["ins"][1]["conns"][0]["from"];
    assert!(elems.iter().any(|e| &e["id"] == pt && e["text"] == "T#1s"));
    assert!(full["x"].as_f64() > stop["x"].as_f64() && full["x"].as_f64() < motor["x"].as_f64());
    let check = js_async(
        c,
        "const [t, done] = arguments; fetch('/api/check?file=examples/ladder_demo.xml', {method: 'POST', body: t}).then(r => r.json()).then(done)",
        vec![saved.clone()],
    )
    .await;
    assert_eq!(check["errors"], json!(0), "{check}");
    // Applied: the PLC runs the edited program.
    click(
        c,
        "button[aria-label='Load the edited program into the running PLC']",
    )
    .await;
    until(
        c,
        "the online change",
        "return document.getElementById('view-info').textContent.startsWith('loaded into the PLC')",
    )
    .await;
}

#[test]
fn the_workbench_in_chromium() {
    for (tool, what) in [(CHROMIUM, "chromium"), (CHROMEDRIVER, "chromedriver")] {
        assert!(
            Path::new(tool).exists(),
            "{tool} is missing: install Debian's chromium and chromium-driver (apt-get install chromium chromium-driver); .ci/run installs them ({what} drives the workbench test)"
        );
    }
    let (_server, page) = serve(Path::new("examples/ladder_demo.xml"), &[]);
    let (_fbd_server, fbd_page) = serve(Path::new("tests/programs/plcopen/fbd_logic.xml"), &[]);
    let (_sfc_server, sfc_page) = serve(Path::new("tests/workbench/sfc_demo.xml"), &[]);
    let (_user_server, user_page) = serve(Path::new("tests/workbench/user_block.xml"), &[]);
    let (_fn_server, fn_page) = serve(
        Path::new("tests/workbench/user_block.xml"),
        &["tests/workbench/above.st"],
    );
    let secret = format!("plcc-test-{}", std::process::id());
    let token_file =
        std::env::temp_dir().join(format!("plcc-workbench-token-{}", std::process::id()));
    std::fs::write(&token_file, format!("{secret}\n")).expect("the token file written");
    let (_token_server, token_page) = serve(
        Path::new("examples/ladder_demo.xml"),
        &["--token-file", token_file.to_str().expect("a UTF-8 path")],
    );
    let (_driver, driver) = chromedriver();
    let profile = std::env::temp_dir().join(format!("plcc-workbench-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&profile);
    let rt = tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
        .expect("a runtime");
    rt.block_on(async {
        let c = browser(&driver, &profile).await;
        let r = tokio::time::timeout(Duration::from_secs(90), async {
            drive(&c, &page).await;
            fbd(&c, &fbd_page).await;
            sfc(&c, &sfc_page).await;
            user_block(&c, &user_page).await;
            functions(&c, &fn_page).await;
            token(&c, &token_page, &secret).await;
        })
        .await;
        let _ = c.close().await;
        r.expect("the test ran in 90 s");
    });
    let _ = std::fs::remove_dir_all(&profile);
    let _ = std::fs::remove_file(&token_file);
}
