//! The real-time scan thread: it owns the machine, scans at absolute deadlines
//! (start + n × cycle), sets the PLC clock from real elapsed time, and keeps the
//! statistics of lateness and execution time.

use super::http::display;
use super::image::Binding;
use super::Shared;
use plcc_ir::machine::{read_string, write_string, Machine};
use plcc_ir::value::PlcValue;
use plcc_ir::vars::StrRef;
use plcc_ir::ElemType;
use serde_json::{Map, Value as Json};
use std::collections::{BTreeMap, VecDeque};
use std::sync::atomic::Ordering;
use std::sync::mpsc::{Receiver, Sender};
use std::time::{Duration, Instant};

/// How many recent samples the percentiles (p50, p99) are taken over.
const WINDOW: usize = 1000;

/// Minimum, mean, maximum, median and 99th percentile of a series of durations, in
/// microseconds (the percentiles over the last `WINDOW` samples).
#[derive(Clone, Debug, Default)]
pub struct Series {
    count: u64,
    min: u64,
    max: u64,
    sum: u128,
    recent: VecDeque<u64>,
}

impl Series {
    /// Adds a sample.
    pub fn add(&mut self, d: Duration) {
        let us = d.as_micros().min(u64::MAX as u128) as u64;
        if self.count == 0 || us < self.min {
            self.min = us;
        }
        self.max = self.max.max(us);
        self.count += 1;
        self.sum += us as u128;
        if self.recent.len() == WINDOW {
            self.recent.pop_front();
        }
        self.recent.push_back(us);
    }

    /// The summary in microseconds; zeros before the first sample.
    pub fn summary(&self) -> Summary {
        if self.count == 0 {
            return Summary::default();
        }
        let mut sorted: Vec<u64> = self.recent.iter().copied().collect();
        sorted.sort_unstable();
        // The nearest-rank percentile: the smallest sample with at least p% of the
        // samples at or below it.
        let rank = |p: usize| sorted[(sorted.len() * p).div_ceil(100).max(1) - 1];
        Summary {
            min: self.min,
            mean: self.sum as f64 / self.count as f64,
            max: self.max,
            p50: rank(50),
            p99: rank(99),
        }
    }
}

/// A [`Series`] summed up, in microseconds: minimum, mean and maximum over every
/// sample, median and 99th percentile over the last `WINDOW`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Summary {
    /// The smallest sample.
    pub min: u64,
    /// The mean of the samples.
    pub mean: f64,
    /// The largest sample.
    pub max: u64,
    /// The median of the recent samples.
    pub p50: u64,
    /// The 99th percentile of the recent samples.
    pub p99: u64,
}

/// What the scan thread has done.
#[derive(Clone, Debug, Default)]
pub struct Stats {
    /// Scans run since the server started.
    pub scans: u64,
    /// Scans that ended after the next one's deadline (the deadlines missed are
    /// skipped).
    pub overruns: u64,
    /// How late each scan started after its deadline.
    pub lateness: Series,
    /// How long each scan took, the copies to and from the image included.
    pub exec: Series,
    /// The error that stopped the scans (a watchdog stop, a failed cold start).
    pub error: Option<String>,
    /// `running`, `stopped` or `error`.
    pub state: String,
    /// How many variables are forced.
    pub forced: usize,
    /// The runtime fault flag was raised since the last cold start.
    pub fault: bool,
}

impl Stats {
    /// The line printed when the server ends.
    pub fn line(&self) -> String {
        let text = |s: Summary| format!("{}/{:.1}/{}/{}/{}", s.min, s.mean, s.max, s.p50, s.p99);
        format!(
            "scans: {}, overruns: {}, lateness us min/mean/max/p50/p99: {}, execution us min/mean/max/p50/p99: {}",
            self.scans,
            self.overruns,
            text(self.lateness.summary()),
            text(self.exec.summary())
        )
    }
}

/// A variable a request names, resolved against the module by the server that took
/// the request.
#[derive(Clone, Debug, PartialEq)]
pub enum Var {
    /// An elementary variable: its canonical path, its type, and its binding to the
    /// I/O image if it is located there (an index into the bindings).
    Scalar {
        /// The canonical path.
        path: String,
        /// The IEC type.
        elem: ElemType,
        /// Its binding, if located.
        bind: Option<usize>,
    },
    /// A STRING or WSTRING.
    Str(StrRef),
}

impl Var {
    /// The canonical path.
    pub fn path(&self) -> &str {
        match self {
            Var::Scalar { path, .. } => path,
            Var::Str(s) => &s.path,
        }
    }
}

/// A variable's value.
#[derive(Clone, Debug, PartialEq)]
pub enum Value {
    /// An elementary value.
    Scalar(PlcValue),
    /// A string's characters.
    Str(Vec<u16>),
    /// The values of several variables, read between the same two scans.
    Many(Vec<Value>),
}

/// What a request asks the scan thread to do, between two scans.
#[derive(Clone, Debug)]
pub enum Cmd {
    /// Read a variable.
    Read(Var),
    /// Read several variables between the same two scans.
    ReadMany(Vec<Var>),
    /// Write a variable once (the program may change it in the next scan).
    Write(Var, Value),
    /// Hold an elementary variable at a value, against the program and the I/O.
    Force(Var, PlcValue),
    /// Stop holding the variable of this path.
    Unforce(String),
    /// Stop scanning (requests are still answered).
    Stop,
    /// Scan again after a stop.
    Start,
    /// Online change: run this program instead, its variables keeping the values
    /// of the old program's variables of the same path and type.
    Load(Box<Loaded>),
    /// Cold start, then scan; a warm restart keeps the retained variables.
    Restart {
        /// Warm: the RETAIN variables keep their values.
        warm: bool,
    },
}

/// A new program for [`Cmd::Load`], built and checked by the API's thread.
#[derive(Clone, Debug)]
pub struct Loaded {
    /// Its module.
    pub module: plcc_ir::Module,
    /// The target whose machine runs it.
    pub target: &'static str,
    /// The target settings.
    pub settings: Vec<(String, String)>,
    /// Its located variables.
    pub binds: Vec<Binding>,
    /// Its variables.
    pub vars: Vec<Var>,
    /// Its RETAIN variables.
    pub retained: Vec<Var>,
}

/// The answer to a [`Cmd`]: a value read, or nothing; an error is an HTTP status and
/// a message.
pub type Reply = Result<Option<Value>, (u16, String)>;

/// A command and where its answer goes.
pub struct Request {
    /// What to do.
    pub cmd: Cmd,
    /// Where the answer goes.
    pub reply: Sender<Reply>,
}

/// How often the scan thread looks at the stop flag while it waits.
const POLL: Duration = Duration::from_millis(50);

/// When to hand the RETAIN variables' values to the retain file's writer.
pub struct Periodic {
    /// How often.
    pub every: Duration,
    /// The next time (none: never, past the end of time).
    pub next: Option<Instant>,
    /// The writer's end.
    pub outbox: super::retain::Outbox,
}

/// The scan thread's state.
struct Plc<'a> {
    m: Box<dyn Machine>,
    shared: &'a Shared,
    binds: Vec<Binding>,
    /// Every variable of the program (the API's).
    vars: Vec<Var>,
    requests: Option<Receiver<Request>>,
    /// The RETAIN variables.
    retained: Vec<Var>,
    cycle_ns: u64,
    /// The periodic saving of the RETAIN variables (`--retain-every`).
    periodic: Option<Periodic>,
    /// Held variables, by canonical path.
    forced: BTreeMap<String, PlcValue>,
    running: bool,
    /// When the PLC clock was 0 (the last cold start).
    epoch: Instant,
    /// Deadline n is `start + n × cycle`.
    start: Instant,
    n: u64,
}

impl Plc<'_> {
    fn at(&self, n: u64) -> Instant {
        self.start + Duration::from_nanos(self.cycle_ns.saturating_mul(n))
    }

    /// Between two scans: when due, the RETAIN variables' values to the writer of
    /// the retain file, which writes them on its own thread if they changed.
    fn save_if_due(&mut self, now: Instant) {
        let Some(p) = &mut self.periodic else {
            return;
        };
        if p.next.is_none_or(|t| now < t) {
            return;
        }
        p.next = now.checked_add(p.every);
        match super::retain::snapshot(&*self.m, &self.retained) {
            Ok(values) => p.outbox.offer(values),
            Err(e) => eprintln!("error: retain: {e}"),
        }
    }

    fn set_state(&self, state: &str) {
        let mut s = self.shared.lock_stats();
        s.state = state.to_string();
        s.forced = self.forced.len();
    }

    fn fail(&mut self, e: String) {
        self.running = false;
        let mut s = self.shared.lock_stats();
        s.state = "error".into();
        s.error = Some(e);
    }

    fn apply_forces(&mut self) -> Result<(), String> {
        for (path, v) in &self.forced {
            self.m
                .write(path, *v)
                .map_err(|e| format!("forcing {path}: {e}"))?;
        }
        Ok(())
    }

    /// Cold start: initial values (the retained variables' from `keep` if given),
    /// forces, the outputs into the image, the clock and the deadlines from now.
    fn cold_start(&mut self, keep: Option<&Map<String, Json>>) -> Result<(), String> {
        self.m
            .cold_start()
            .map_err(|e| format!("cold start failed: {e}"))?;
        if let Some(values) = keep {
            for msg in super::retain::restore(&mut *self.m, &self.retained, values) {
                eprintln!("warning: retained value not restored: {msg}");
            }
        }
        self.m.clear_fault();
        self.apply_forces()?;
        self.shared.lock_image().publish(&*self.m, &self.binds)?;
        self.epoch = Instant::now();
        self.start = self.epoch;
        self.n = 0;
        self.running = true;
        {
            let mut s = self.shared.lock_stats();
            s.error = None;
            s.fault = false;
        }
        self.set_state("running");
        Ok(())
    }

    /// One scan: the image into the machine, the forces, the clock, the programs,
    /// the forces again, the outputs back to the image.
    fn scan(&mut self, clock_us: i64) -> Result<(), String> {
        self.shared.lock_image().latch(&mut *self.m, &self.binds)?;
        self.apply_forces()?;
        self.m.set_clock_us(clock_us);
        self.m.scan().map_err(|e| e.to_string())?;
        self.apply_forces()?;
        self.shared.lock_image().publish(&*self.m, &self.binds)
    }

    /// Waits up to `timeout` for a request and answers it.
    fn serve(&mut self, timeout: Duration) {
        let Some(rx) = &self.requests else {
            std::thread::sleep(timeout);
            return;
        };
        let Ok(req) = rx.recv_timeout(timeout) else {
            return;
        };
        let reply = self.answer(req.cmd);
        let _ = req.reply.send(reply);
    }

    fn answer(&mut self, cmd: Cmd) -> Reply {
        let fail = |e: plcc_ir::machine::MachineError| (500, e.to_string());
        match cmd {
            Cmd::Read(Var::Scalar { path, .. }) => {
                Ok(Some(Value::Scalar(self.m.read(&path).map_err(fail)?)))
            }
            Cmd::Read(Var::Str(s)) => {
                Ok(Some(Value::Str(read_string(&*self.m, &s).map_err(fail)?)))
            }
            Cmd::ReadMany(vars) => {
                let mut values = Vec::with_capacity(vars.len());
                for v in vars {
                    values.push(match v {
                        Var::Scalar { path, .. } => {
                            Value::Scalar(self.m.read(&path).map_err(fail)?)
                        }
                        Var::Str(s) => Value::Str(read_string(&*self.m, &s).map_err(fail)?),
                    });
                }
                Ok(Some(Value::Many(values)))
            }
            Cmd::Write(var, _) if self.forced.contains_key(var.path()) => Err((
                409,
                format!("`{}` is forced: unforce it first", display(var.path())),
            )),
            Cmd::Write(Var::Scalar { path, bind, .. }, Value::Scalar(v)) => {
                self.m.write(&path, v).map_err(fail)?;
                if let Some(b) = bind.and_then(|i| self.binds.get(i)) {
                    self.shared.lock_image().store(b, v);
                }
                Ok(None)
            }
            Cmd::Write(Var::Str(s), Value::Str(chars)) => {
                write_string(&mut *self.m, &s, &chars).map_err(|e| (400, e.to_string()))?;
                Ok(None)
            }
            Cmd::Write(var, _) => Err((400, format!("wrong kind of value for `{}`", var.path()))),
            Cmd::Force(Var::Scalar { path, bind, .. }, v) => {
                self.m.write(&path, v).map_err(fail)?;
                if let Some(b) = bind.and_then(|i| self.binds.get(i)) {
                    if !b.slot.is_input() {
                        self.shared.lock_image().store(b, v);
                    }
                }
                self.forced.insert(path, v);
                self.set_state(self.state());
                Ok(None)
            }
            Cmd::Force(Var::Str(s), _) => Err((
                400,
                format!(
                    "`{}` is a string: only elementary variables can be forced",
                    display(&s.path)
                ),
            )),
            Cmd::Unforce(path) => match self.forced.remove(&path) {
                Some(_) => {
                    self.set_state(self.state());
                    Ok(None)
                }
                None => Err((404, format!("`{}` is not forced", display(&path)))),
            },
            Cmd::Stop => {
                if self.running {
                    self.running = false;
                    self.set_state("stopped");
                }
                Ok(None)
            }
            Cmd::Start => {
                if self.shared.lock_stats().error.is_some() {
                    return Err((409, "the PLC stopped on an error: restart it".into()));
                }
                if !self.running {
                    self.running = true;
                    self.start = Instant::now();
                    self.n = 0;
                    self.set_state("running");
                }
                Ok(None)
            }
            Cmd::Load(l) => {
                let kept = self.load(*l)?;
                Ok(Some(Value::Scalar(PlcValue::from_i64(
                    ElemType::UDInt,
                    kept as i64,
                ))))
            }
            Cmd::Restart { warm } => {
                let keep = if warm {
                    Some(super::retain::snapshot(&*self.m, &self.retained).map_err(|e| (500, e))?)
                } else {
                    None
                };
                self.restart(keep.as_ref())
            }
        }
    }

    /// Online change: the new program's machine, cold-started, takes the values of
    /// the old one's variables of the same path and type, and the forces that still
    /// apply; then it runs in place of the old one from the next scan. The number of
    /// variables carried over.
    fn load(&mut self, l: Loaded) -> Result<usize, (u16, String)> {
        let Loaded {
            module,
            target,
            settings,
            binds,
            vars,
            retained,
        } = l;
        let mut new = crate::targets::machine_staged(target, module, &settings).map_err(|d| {
            let msgs: Vec<String> = d
                .iter()
                .map(|d| format!("{}: {}", d.code, d.message))
                .collect();
            (400, msgs.join("; "))
        })?;
        new.cold_start()
            .map_err(|e| (500, format!("cold start of the new program failed: {e}")))?;
        let old: std::collections::HashMap<&str, &Var> =
            self.vars.iter().map(|v| (v.path(), v)).collect();
        let fail = |e: plcc_ir::machine::MachineError| (500, e.to_string());
        let mut kept = 0;
        for v in &vars {
            match (old.get(v.path()), v) {
                (Some(Var::Scalar { elem: was, .. }), Var::Scalar { path, elem, .. })
                    if was == elem =>
                {
                    let x = self.m.read(path).map_err(fail)?;
                    new.write(path, x).map_err(fail)?;
                    kept += 1;
                }
                (Some(Var::Str(was)), Var::Str(now)) if was.wide == now.wide => {
                    let chars = read_string(&*self.m, was).map_err(fail)?;
                    if chars.len() <= now.cap as usize {
                        write_string(&mut *new, now, &chars).map_err(fail)?;
                        kept += 1;
                    }
                }
                _ => {}
            }
        }
        self.forced.retain(|p, x| {
            vars.iter()
                .any(|v| matches!(v, Var::Scalar { path, elem, .. } if path == p && *elem == x.ty))
        });
        self.m = new;
        self.binds = binds;
        self.vars = vars;
        self.retained = retained;
        self.apply_forces().map_err(|e| (500, e))?;
        self.shared
            .lock_image()
            .publish(&*self.m, &self.binds)
            .map_err(|e| (500, e))?;
        self.set_state(self.state());
        Ok(kept)
    }

    fn restart(&mut self, keep: Option<&Map<String, Json>>) -> Reply {
        match self.cold_start(keep) {
            Ok(()) => Ok(None),
            Err(e) => {
                self.fail(e.clone());
                Err((500, e))
            }
        }
    }

    fn state(&self) -> &'static str {
        if self.running {
            "running"
        } else if self.shared.lock_stats().error.is_some() {
            "error"
        } else {
            "stopped"
        }
    }
}

/// What the scan thread is given besides the machine.
pub struct Setup {
    /// The located variables.
    pub binds: Vec<Binding>,
    /// Every variable of the program (the API's).
    pub vars: Vec<Var>,
    /// The time between deadlines.
    pub cycle: Duration,
    /// The API's requests, if it is served.
    pub requests: Option<Receiver<Request>>,
    /// The RETAIN variables.
    pub retained: Vec<Var>,
    /// Their values from the retain file.
    pub saved: Map<String, Json>,
    /// Their periodic saving, if any (`next` from the start).
    pub periodic: Option<Periodic>,
}

/// Asks Linux to wake this thread at its timeouts without the default 50 µs of
/// timer slack (the kernel's leeway to merge wake-ups), which would otherwise add to
/// every scan's lateness.
fn slack() {
    #[cfg(target_os = "linux")]
    // SAFETY: PR_SET_TIMERSLACK takes a number and changes only this thread's slack.
    unsafe {
        libc::prctl(libc::PR_SET_TIMERSLACK, 1 as libc::c_ulong, 0, 0, 0);
    }
}

/// Cold start (the retained variables from `saved`), then scans every `cycle` until
/// a stop is requested, answering `requests` between scans. A failed scan stops the
/// scans; without requests (no HTTP server, so nothing could restart it) it ends
/// the loop. With `periodic`, the retained variables' values go to the retain
/// file's writer every so often, between two scans. Their values at the end.
pub fn run(
    m: Box<dyn Machine>,
    shared: &Shared,
    setup: Setup,
) -> Result<Map<String, Json>, String> {
    let Setup {
        binds,
        vars,
        cycle,
        requests,
        retained,
        saved,
        periodic,
    } = setup;
    slack();
    let now = Instant::now();
    let mut plc = Plc {
        m,
        shared,
        binds,
        vars,
        cycle_ns: cycle.as_nanos().clamp(1, u64::MAX as u128) as u64,
        requests,
        retained,
        periodic,
        forced: BTreeMap::new(),
        running: false,
        epoch: now,
        start: now,
        n: 0,
    };
    let stopping = || shared.stop.load(Ordering::SeqCst);
    if let Err(e) = plc.cold_start(Some(&saved)) {
        plc.fail(e);
    }
    let end = |plc: &Plc| super::retain::snapshot(&*plc.m, &plc.retained);
    loop {
        if stopping() {
            return end(&plc);
        }
        // Here, between two scans (after one, before waiting for the next).
        plc.save_if_due(Instant::now());
        if !plc.running {
            if plc.requests.is_none() {
                return end(&plc);
            }
            plc.serve(POLL);
            continue;
        }
        let deadline = plc.at(plc.n);
        loop {
            let now = Instant::now();
            if stopping() || now >= deadline || !plc.running {
                break;
            }
            plc.serve((deadline - now).min(POLL));
        }
        if stopping() || !plc.running {
            continue;
        }
        let began = Instant::now();
        let clock = began.duration_since(plc.epoch).as_micros() as i64;
        if let Err(e) = plc.scan(clock) {
            let k = shared.lock_stats().scans;
            plc.fail(format!("scan {k}: {e}"));
            continue;
        }
        let ended = Instant::now();
        plc.n = plc.n.saturating_add(1);
        let fault = plc.m.fault();
        let mut stats = shared.lock_stats();
        stats.scans += 1;
        stats.fault |= fault;
        stats
            .lateness
            .add(began.saturating_duration_since(deadline));
        stats.exec.add(ended - began);
        if ended > plc.at(plc.n) {
            // Missed the next deadline: count it and go on at the next one ahead.
            stats.overruns += 1;
            let behind = ended.duration_since(plc.start).as_nanos() / plc.cycle_ns as u128;
            plc.n = u64::try_from(behind + 1).unwrap_or(u64::MAX);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn series_summary() {
        let mut s = Series::default();
        assert_eq!(s.summary(), Summary::default());
        for us in 1..=100 {
            s.add(Duration::from_micros(us));
        }
        let t = s.summary();
        assert_eq!((t.min, t.max, t.p50, t.p99), (1, 100, 50, 99));
        assert!((t.mean - 50.5).abs() < 1e-9);
        // One sample: every statistic is that sample.
        let mut one = Series::default();
        one.add(Duration::from_micros(7));
        let t = one.summary();
        assert_eq!((t.min, t.max, t.p50, t.p99), (7, 7, 7, 7));
        // The percentiles follow the last WINDOW samples; min, mean and max all.
        let mut long = Series::default();
        for _ in 0..WINDOW {
            long.add(Duration::from_micros(1000));
        }
        for _ in 0..WINDOW {
            long.add(Duration::from_micros(10));
        }
        let t = long.summary();
        assert_eq!((t.min, t.max, t.p50, t.p99), (10, 1000, 10, 10));
        assert!((t.mean - 505.0).abs() < 1e-9);
    }
}
