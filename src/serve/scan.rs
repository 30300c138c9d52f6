//! The real-time scan thread: it owns the machine, scans at absolute deadlines
//! (start + n × cycle), sets the PLC clock from real elapsed time, and keeps the
//! statistics of lateness and execution time.

use super::image::Binding;
use super::Shared;
use plcc_ir::machine::Machine;
use std::collections::VecDeque;
use std::sync::atomic::Ordering;
use std::time::{Duration, Instant};

/// How many recent samples the 99th percentile is taken over.
const WINDOW: usize = 1000;

/// Minimum, mean, maximum and 99th percentile of a series of durations, in
/// microseconds (the percentile over the last [`WINDOW`] samples).
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

    /// `(min, mean, max, p99)` in microseconds; zeros before the first sample.
    pub fn summary(&self) -> (u64, f64, u64, u64) {
        if self.count == 0 {
            return (0, 0.0, 0, 0);
        }
        let mut sorted: Vec<u64> = self.recent.iter().copied().collect();
        sorted.sort_unstable();
        let k = (sorted.len() * 99).div_ceil(100).max(1) - 1;
        (
            self.min,
            self.sum as f64 / self.count as f64,
            self.max,
            sorted[k],
        )
    }
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
}

impl Stats {
    /// The line printed when the server ends.
    pub fn line(&self) -> String {
        let (lmin, lmean, lmax, lp99) = self.lateness.summary();
        let (emin, emean, emax, ep99) = self.exec.summary();
        format!(
            "scans: {}, overruns: {}, lateness us min/mean/max/p99: {lmin}/{lmean:.1}/{lmax}/{lp99}, execution us min/mean/max/p99: {emin}/{emean:.1}/{emax}/{ep99}",
            self.scans, self.overruns
        )
    }
}

/// Sleeps until `deadline` in steps short enough to notice a stop request soon.
/// False if the server is to stop.
fn wait_until(deadline: Instant, shared: &Shared) -> bool {
    loop {
        if shared.stop.load(Ordering::SeqCst) {
            return false;
        }
        let now = Instant::now();
        if now >= deadline {
            return true;
        }
        std::thread::sleep((deadline - now).min(Duration::from_millis(50)));
    }
}

/// One scan: the image into the machine, the clock, the programs, the outputs
/// back to the image.
fn scan_once(
    m: &mut dyn Machine,
    shared: &Shared,
    binds: &[Binding],
    clock_us: i64,
) -> Result<(), String> {
    shared.lock_image().latch(m, binds)?;
    m.set_clock_us(clock_us);
    m.scan().map_err(|e| e.to_string())?;
    shared.lock_image().publish(m, binds)
}

/// Cold start, then scans every `cycle` until a stop is requested or a scan fails.
pub fn run(m: &mut dyn Machine, shared: &Shared, binds: &[Binding], cycle: Duration) {
    let fail = |e: String| shared.lock_stats().error = Some(e);
    if let Err(e) = m.cold_start() {
        return fail(format!("cold start failed: {e}"));
    }
    if let Err(e) = shared.lock_image().publish(m, binds) {
        return fail(e);
    }
    let start = Instant::now();
    let cycle_ns = cycle.as_nanos().clamp(1, u64::MAX as u128) as u64;
    let at = |n: u64| start + Duration::from_nanos(cycle_ns.saturating_mul(n));
    let mut n: u64 = 0;
    loop {
        let deadline = at(n);
        if !wait_until(deadline, shared) {
            return;
        }
        let began = Instant::now();
        let clock = began.duration_since(start).as_micros() as i64;
        if let Err(e) = scan_once(m, shared, binds, clock) {
            return fail(format!("scan {}: {e}", shared.lock_stats().scans));
        }
        let ended = Instant::now();
        n = n.saturating_add(1);
        let mut stats = shared.lock_stats();
        stats.scans += 1;
        stats.lateness.add(began - deadline);
        stats.exec.add(ended - began);
        if ended > at(n) {
            // Missed the next deadline: count it and go on at the next one ahead.
            stats.overruns += 1;
            let behind = ended.duration_since(start).as_nanos() / cycle_ns as u128;
            n = u64::try_from(behind + 1).unwrap_or(u64::MAX);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn series_summary() {
        let mut s = Series::default();
        assert_eq!(s.summary(), (0, 0.0, 0, 0));
        for us in 1..=100 {
            s.add(Duration::from_micros(us));
        }
        let (min, mean, max, p99) = s.summary();
        assert_eq!((min, max, p99), (1, 100, 99));
        assert!((mean - 50.5).abs() < 1e-9);
    }
}
