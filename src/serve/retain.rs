//! RETAIN and PERSISTENT variables: which they are, and the `--retain FILE` that
//! keeps their values from one run of `plcc serve` to the next.
//!
//! The variables are those of the `VAR RETAIN` (`PERSISTENT`) blocks of the
//! PROGRAMs (in every instance) and the `VAR_GLOBAL RETAIN` blocks, at top level or
//! in a configuration or resource, each with everything inside it (an FB instance's
//! variables, a struct's fields, an array's elements). The file is JSON,
//! `{"plcc_retain": 1, "values": {"plant.count": 5, ...}}`, written whole to a
//! temporary file, synced, and renamed over the old one (the directory synced too).
//!
//! While the PLC scans, the scan thread takes the values between two scans every
//! `--retain-every` seconds and hands them to a [`Writer`], whose thread writes
//! them when they changed since its last write: the scans never wait for the disk.

use super::http::{from_json, to_json};
use super::scan::{Value, Var};
use crate::driver::Build;
use plcc_frontend::ast::{Item, PouKind, VarBlock, VarKind};
use plcc_ir::machine::{read_string, write_string, Machine};
use plcc_ir::{AggDef, MemType, Module};
use serde_json::{json, Map, Value as Json};
use std::collections::{HashMap, HashSet};
use std::path::{Path, PathBuf};
use std::sync::{Arc, Condvar, Mutex, MutexGuard};
use std::thread::JoinHandle;
use std::time::Duration;

/// The version of the file format.
const FORMAT: u64 = 1;

/// The names declared in RETAIN blocks: per PROGRAM type (upper case), and the
/// globals'.
fn retain_names(build: &Build) -> (HashMap<String, Vec<String>>, Vec<String>) {
    let mut programs: HashMap<String, Vec<String>> = HashMap::new();
    let mut globals = Vec::new();
    let names = |blocks: &[VarBlock], kinds: &[VarKind]| -> Vec<String> {
        blocks
            .iter()
            .filter(|b| b.retain && kinds.contains(&b.kind))
            .flat_map(|b| b.decls.iter().flat_map(|d| d.names.iter()))
            .map(|n| {
                build
                    .sources
                    .get(n.span.file)
                    .slice(n.span)
                    .to_ascii_uppercase()
            })
            .collect()
    };
    let own = [VarKind::Var, VarKind::Input, VarKind::Output, VarKind::Stat];
    for unit in &build.syntax {
        for item in &unit.items {
            match item {
                Item::Pou(p) => {
                    // VAR_GLOBAL in a POU declares globals (the front end also holds
                    // top-level global blocks this way).
                    globals.extend(names(&p.var_blocks, &[VarKind::Global]));
                    if p.kind != PouKind::Program {
                        continue;
                    }
                    // The front end gathers the VAR_GLOBAL blocks (top level, and a
                    // configuration's and its resources') into a PROGRAM of its own
                    // (`plcc_frontend::GLOBALS_POU`), named nowhere in the source (an
                    // empty span), whose VAR blocks are the globals.
                    if p.name.span.start == p.name.span.end {
                        globals.extend(names(&p.var_blocks, &own));
                        continue;
                    }
                    let name = build
                        .sources
                        .get(p.name.span.file)
                        .slice(p.name.span)
                        .to_ascii_uppercase();
                    programs
                        .entry(name)
                        .or_default()
                        .extend(names(&p.var_blocks, &own));
                }
                Item::Globals(b) => {
                    globals.extend(names(std::slice::from_ref(b), &[VarKind::Global]))
                }
                Item::Configuration(c) => {
                    globals.extend(names(&c.var_blocks, &[VarKind::Global]));
                    for r in &c.resources {
                        globals.extend(names(&r.var_blocks, &[VarKind::Global]));
                    }
                }
                _ => {}
            }
        }
    }
    (programs, globals)
}

/// The retained variables among `vars` (the API's, by canonical path), sorted by
/// path.
pub fn retained(build: &Build, module: &Module, vars: &HashMap<String, Var>) -> Vec<Var> {
    let (programs, globals) = retain_names(build);
    let mut roots: Vec<String> = Vec::new();
    for e in &module.programs {
        let MemType::Agg(agg) = module.data[e.data.index()].ty else {
            continue;
        };
        let AggDef::Struct(s) = module.agg(agg) else {
            continue;
        };
        for n in programs
            .get(&s.name.to_ascii_uppercase())
            .into_iter()
            .flatten()
        {
            roots.push(format!("{}.{n}", e.name).to_ascii_uppercase());
        }
    }
    for g in &globals {
        roots.push(format!("{}.{g}", plcc_frontend::GLOBALS_DATA).to_ascii_uppercase());
    }
    let roots: HashSet<String> = roots.into_iter().collect();
    let mut out: Vec<Var> = vars
        .values()
        .filter(|v| {
            let up = v.path().to_ascii_uppercase();
            // The variable itself, or something inside it.
            let mut cut = up.len();
            loop {
                if roots.contains(&up[..cut]) {
                    return true;
                }
                match up[..cut].rfind(['.', '[']) {
                    Some(i) => cut = i,
                    None => return false,
                }
            }
        })
        .cloned()
        .collect();
    out.sort_by(|a, b| a.path().cmp(b.path()));
    out
}

/// The values of `vars` on `m`, by path.
pub fn snapshot(m: &dyn Machine, vars: &[Var]) -> Result<Map<String, Json>, String> {
    let mut values = Map::new();
    for v in vars {
        let (value, wide) = match v {
            Var::Scalar { path, .. } => (
                Value::Scalar(m.read(path).map_err(|e| format!("reading {path}: {e}"))?),
                false,
            ),
            Var::Str(s) => (
                Value::Str(read_string(m, s).map_err(|e| format!("reading {}: {e}", s.path))?),
                s.wide,
            ),
        };
        values.insert(v.path().to_string(), to_json(&value, wide));
    }
    Ok(values)
}

/// Writes the saved `values` into `m`: each of `vars` that has one. The messages
/// of the values that could not be taken (a variable no longer retained, or of
/// another type now).
pub fn restore(m: &mut dyn Machine, vars: &[Var], values: &Map<String, Json>) -> Vec<String> {
    let mut skipped = Vec::new();
    let by_path: HashMap<&str, &Var> = vars.iter().map(|v| (v.path(), v)).collect();
    for (path, j) in values {
        let Some(var) = by_path.get(path.as_str()) else {
            skipped.push(format!(
                "`{path}` is not a retained variable of this program"
            ));
            continue;
        };
        let written = match from_json(var, j) {
            Ok(Value::Scalar(p)) => m.write(path, p).map_err(|e| e.to_string()),
            Ok(Value::Str(chars)) => match var {
                Var::Str(s) => write_string(m, s, &chars).map_err(|e| e.to_string()),
                Var::Scalar { .. } => Err("not a string".into()),
            },
            Ok(Value::Many(_)) => Err("not one value".into()),
            Err(e) => Err(e),
        };
        if let Err(e) = written {
            skipped.push(format!("`{path}`: {e}"));
        }
    }
    skipped
}

/// Reads a retain file: its values; none if there is no file yet. `Err((status,
/// message))`: 2 when it cannot be read, 1 when it is not a retain file.
pub fn load(path: &Path) -> Result<Map<String, Json>, (u8, String)> {
    let text = match std::fs::read_to_string(path) {
        Ok(t) => t,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(Map::new()),
        Err(e) => return Err((2, format!("cannot read {}: {e}", path.display()))),
    };
    let bad = |why: String| Err((1, format!("{}: {why}", path.display())));
    let j: Json = match serde_json::from_str(&text) {
        Ok(j) => j,
        Err(e) => return bad(format!("not a retain file: {e}")),
    };
    match (&j["plcc_retain"], &j["values"]) {
        (Json::Number(n), Json::Object(values)) if n.as_u64() == Some(FORMAT) => {
            Ok(values.clone())
        }
        _ => bad(format!(
            "not a retain file of format {FORMAT} ({{\"plcc_retain\": {FORMAT}, \"values\": {{...}}}})"
        )),
    }
}

/// Writes a retain file atomically: a temporary file beside it, synced, renamed over
/// it, then the directory synced so that the rename itself survives a power cut.
pub fn save(path: &Path, values: &Map<String, Json>) -> Result<(), String> {
    let text = serde_json::to_string_pretty(&json!({"plcc_retain": FORMAT, "values": values}))
        .map_err(|e| e.to_string())?;
    crate::output::write_atomic(path, format!("{text}\n").as_bytes())
        .map_err(|e| format!("cannot write {}: {e}", path.display()))?;
    let dir = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    // A directory opened for reading can be synced on Unix; elsewhere the rename is
    // as durable as the system makes it.
    if cfg!(unix) && path.is_file() {
        std::fs::File::open(dir)
            .and_then(|d| d.sync_all())
            .map_err(|e| format!("cannot sync the directory of {}: {e}", path.display()))?;
    }
    Ok(())
}

/// How often the values are saved while the PLC runs unless `--retain-every` says.
pub const DEFAULT_EVERY: Duration = Duration::from_secs(10);

/// Parses `--retain-every`: seconds, with up to three decimals (`10`, `0.25`); `0`
/// saves only at the end.
pub fn parse_seconds(text: &str) -> Result<Duration, String> {
    crate::scenario::parse_thousandths(text)
        .map(Duration::from_millis)
        .ok_or_else(|| {
            format!("`{text}` is not a number of seconds in whole milliseconds (e.g. 10 or 0.5; 0: only at the end)")
        })
}

/// The retain file and the values last written to it.
struct Kept {
    path: PathBuf,
    /// The values the file holds (those read at start, then those last written).
    last: Option<Map<String, Json>>,
}

impl Kept {
    /// Writes `values` unless the file already holds them: whether it wrote.
    fn save_if_changed(&mut self, values: Map<String, Json>) -> Result<bool, String> {
        if self.last.as_ref() == Some(&values) {
            return Ok(false);
        }
        save(&self.path, &values)?;
        self.last = Some(values);
        Ok(true)
    }
}

/// What the scan thread hands to the writer.
#[derive(Default)]
struct Pending {
    /// The latest values not yet taken (a newer offer replaces an older one).
    values: Option<Map<String, Json>>,
    /// The writer is to end.
    closed: bool,
}

#[derive(Default)]
struct Slot {
    pending: Mutex<Pending>,
    wake: Condvar,
}

impl Slot {
    fn lock(&self) -> MutexGuard<'_, Pending> {
        self.pending.lock().unwrap_or_else(|p| p.into_inner())
    }
}

/// The scan thread's end of a [`Writer`].
#[derive(Clone)]
pub struct Outbox {
    slot: Arc<Slot>,
}

impl Outbox {
    /// Hands `values` to the writer and returns at once (only a lock the writer holds
    /// for a moment, never while it writes). Values the writer has not taken yet are
    /// replaced: it always writes the latest.
    pub fn offer(&self, values: Map<String, Json>) {
        self.slot.lock().values = Some(values);
        self.slot.wake.notify_one();
    }
}

/// A thread that writes the values offered through its [`Outbox`] to the retain
/// file, skipping values the file already holds. A failed write is reported on
/// standard error (once until the next success) and tried again at the next offer.
/// Dropping it ends the thread after the write in progress; values not yet taken are
/// dropped (the final save at the end of the command supersedes them).
pub struct Writer {
    slot: Arc<Slot>,
    thread: Option<JoinHandle<()>>,
}

impl Writer {
    /// Starts the thread for `path`, which holds `last` (the values read at start).
    pub fn start(
        path: PathBuf,
        last: Option<Map<String, Json>>,
    ) -> std::io::Result<(Writer, Outbox)> {
        let slot = Arc::new(Slot::default());
        let theirs = Arc::clone(&slot);
        let thread = std::thread::Builder::new()
            .name("plc-retain".into())
            .spawn(move || {
                let mut kept = Kept { path, last };
                let mut failing: Option<String> = None;
                loop {
                    let values = {
                        let mut p = theirs.lock();
                        loop {
                            if p.closed {
                                return;
                            }
                            if let Some(v) = p.values.take() {
                                break v;
                            }
                            p = theirs.wake.wait(p).unwrap_or_else(|e| e.into_inner());
                        }
                    };
                    match kept.save_if_changed(values) {
                        Ok(wrote) => {
                            if wrote && failing.take().is_some() {
                                eprintln!("retain: saving to {} again", kept.path.display());
                            }
                        }
                        Err(e) => {
                            if failing.as_ref() != Some(&e) {
                                eprintln!("error: retain: {e} (the PLC scans on; tried again at the next save)");
                            }
                            failing = Some(e);
                        }
                    }
                }
            })?;
        Ok((
            Writer {
                slot: Arc::clone(&slot),
                thread: Some(thread),
            },
            Outbox { slot },
        ))
    }
}

impl Drop for Writer {
    fn drop(&mut self) {
        self.slot.lock().closed = true;
        self.slot.wake.notify_one();
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::Instant;

    fn dir(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("plcc-retain-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    fn values(n: i64) -> Map<String, Json> {
        let mut m = Map::new();
        m.insert("keeper.total".into(), json!(n));
        m
    }

    #[test]
    fn seconds() {
        assert_eq!(parse_seconds("10"), Ok(Duration::from_secs(10)));
        assert_eq!(parse_seconds("0.2"), Ok(Duration::from_millis(200)));
        assert_eq!(parse_seconds(".25"), Ok(Duration::from_millis(250)));
        assert_eq!(parse_seconds("1."), Ok(Duration::from_secs(1)));
        assert_eq!(parse_seconds("0"), Ok(Duration::ZERO));
        assert_eq!(parse_seconds("1.005"), Ok(Duration::from_millis(1005)));
        for bad in [
            "",
            ".",
            "-1",
            "1.0001",
            "1e3",
            "ten",
            " 1",
            "99999999999999999999",
        ] {
            let e = parse_seconds(bad).unwrap_err();
            assert!(e.contains("not a number of seconds"), "{bad}: {e}");
        }
    }

    #[test]
    fn saves_what_changed_and_reads_back() {
        let d = dir("kept");
        let path = d.join("plc.retain");
        let mut kept = Kept {
            path: path.clone(),
            last: Some(values(1)),
        };
        // The values the file was read with are not written again.
        assert_eq!(kept.save_if_changed(values(1)), Ok(false));
        assert!(!path.exists());
        assert_eq!(kept.save_if_changed(values(2)), Ok(true));
        assert_eq!(load(&path), Ok(values(2)));
        assert_eq!(kept.save_if_changed(values(2)), Ok(false));
        assert_eq!(kept.save_if_changed(values(3)), Ok(true));
        assert_eq!(load(&path), Ok(values(3)));
        // Only the file is left: no temporary beside it.
        assert_eq!(std::fs::read_dir(&d).unwrap().count(), 1);
        std::fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn a_failed_save_is_tried_again() {
        let d = dir("fail");
        let sub = d.join("gone");
        let path = sub.join("plc.retain");
        let mut kept = Kept {
            path: path.clone(),
            last: None,
        };
        let e = kept.save_if_changed(values(1)).unwrap_err();
        assert!(e.contains("cannot write"), "{e}");
        // The same values once the directory is there: written, not skipped.
        std::fs::create_dir_all(&sub).unwrap();
        assert_eq!(kept.save_if_changed(values(1)), Ok(true));
        assert_eq!(load(&path), Ok(values(1)));
        std::fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn the_writer_thread_writes_the_latest_offer() {
        let d = dir("writer");
        let path = d.join("plc.retain");
        let (writer, outbox) = Writer::start(path.clone(), None).unwrap();
        for n in 1..=50 {
            outbox.offer(values(n));
        }
        let t = Instant::now();
        while load(&path) != Ok(values(50)) {
            assert!(
                t.elapsed() < Duration::from_secs(60),
                "never saved the last offer"
            );
            std::thread::sleep(Duration::from_millis(5));
        }
        drop(writer);
        // Once dropped, the thread has ended: offers are not written any more.
        outbox.offer(values(51));
        std::thread::sleep(Duration::from_millis(50));
        assert_eq!(load(&path), Ok(values(50)));
        std::fs::remove_dir_all(&d).unwrap();
    }
}
