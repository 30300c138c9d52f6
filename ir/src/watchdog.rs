//! A scan watchdog for machines that run compiled code natively (the JIT, the C
//! machine): a thread that asks a scan to stop when it runs too long.
//!
//! Compiled code checks a `stop` byte on every loop back edge (the IR's `watchdog`
//! pass puts the checks there) and leaves its functions when it is set. The scanning
//! thread only counts scans (a number, odd while a scan runs): it reads no clock,
//! so a scan pays two plain stores and a load for the watchdog. The watching thread
//! wakes every eighth of the limit, notes when it first saw a scan running and stops
//! it once it has seen it run for the limit: a scan is never stopped early, and at
//! most about a quarter of the limit late.

use std::sync::atomic::{AtomicBool, AtomicU64, AtomicU8, Ordering};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

/// State shared with the watching thread.
struct Shared {
    /// Scans begun and ended: odd while a scan runs. Written only by the scanning
    /// thread.
    scans: AtomicU64,
    /// The longest a scan may run.
    limit: Duration,
    /// Tells the thread to end.
    quit: AtomicBool,
    /// Address of the runtime's stop byte (valid while the watchdog lives).
    stop: usize,
}

impl Shared {
    /// The runtime's stop byte.
    fn stop(&self) -> &AtomicU8 {
        // SAFETY: valid while the watchdog lives (`Watchdog::start`), and written
        // only atomically.
        unsafe { AtomicU8::from_ptr(self.stop as *mut u8) }
    }
}

/// A running watchdog. Dropping it stops and joins the thread.
pub struct Watchdog {
    shared: Arc<Shared>,
    thread: Option<JoinHandle<()>>,
}

impl Watchdog {
    /// Starts a watchdog for the stop byte at `stop`.
    ///
    /// # Safety
    /// `stop` must stay valid until the watchdog is dropped, and be written by others
    /// only atomically (or while no scan runs).
    pub unsafe fn start(stop: *mut u8, limit: Duration) -> Watchdog {
        let shared = Arc::new(Shared {
            scans: AtomicU64::new(0),
            limit,
            quit: AtomicBool::new(false),
            stop: stop as usize,
        });
        let s = shared.clone();
        let poll = (limit / 8).clamp(Duration::from_millis(1), Duration::from_millis(50));
        let thread = std::thread::Builder::new()
            .name("plcc-watchdog".into())
            .spawn(move || {
                // The running scan as last seen, and when it was first seen.
                let mut seen: Option<(u64, Instant)> = None;
                while !s.quit.load(Ordering::Acquire) {
                    std::thread::park_timeout(poll);
                    let n = s.scans.load(Ordering::Relaxed);
                    if n.is_multiple_of(2) {
                        seen = None;
                        continue;
                    }
                    match seen {
                        Some((m, since)) if m == n => {
                            if since.elapsed() >= s.limit {
                                s.stop().store(1, Ordering::Release);
                            }
                        }
                        _ => seen = Some((n, Instant::now())),
                    }
                }
            })
            .ok();
        Watchdog { shared, thread }
    }

    /// The limit it enforces.
    pub fn limit(&self) -> Duration {
        self.shared.limit
    }

    /// Marks the start of a scan (and clears an old stop request).
    pub fn scan_begins(&self) {
        let s = &self.shared;
        if s.stop().load(Ordering::Relaxed) != 0 {
            s.stop().store(0, Ordering::Release);
        }
        // Only this thread writes the count.
        let n = s.scans.load(Ordering::Relaxed);
        s.scans.store(n | 1, Ordering::Relaxed);
    }

    /// Marks the end of a scan; true if the scan was asked to stop.
    pub fn scan_ends(&self) -> bool {
        let s = &self.shared;
        let n = s.scans.load(Ordering::Relaxed);
        s.scans.store((n | 1) + 1, Ordering::Relaxed);
        s.stop().load(Ordering::Acquire) != 0
    }
}

impl Drop for Watchdog {
    fn drop(&mut self) {
        self.shared.quit.store(true, Ordering::Release);
        if let Some(t) = self.thread.take() {
            t.thread().unpark();
            let _ = t.join();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const LIMIT: Duration = Duration::from_millis(80);

    #[test]
    fn a_long_scan_is_stopped_after_the_limit_and_not_before() {
        let mut stop = 0u8;
        // SAFETY: `stop` outlives the watchdog (dropped at the end of the test).
        let w = unsafe { Watchdog::start(&mut stop, LIMIT) };
        let byte = w.shared.stop();
        let started = Instant::now();
        w.scan_begins();
        while byte.load(Ordering::Acquire) == 0 {
            assert!(started.elapsed() < LIMIT * 3, "never stopped");
            std::thread::sleep(Duration::from_millis(1));
        }
        assert!(
            started.elapsed() >= LIMIT,
            "stopped after {:?}",
            started.elapsed()
        );
        assert!(w.scan_ends(), "the scan's end reports the stop");
        // The next scan starts without the old request.
        w.scan_begins();
        assert_eq!(byte.load(Ordering::Acquire), 0);
        assert!(!w.scan_ends());
    }

    #[test]
    fn many_short_scans_are_never_stopped() {
        let mut stop = 0u8;
        // SAFETY: as above.
        // A generous limit: a loaded machine may stretch a 2 ms sleep.
        let limit = LIMIT * 3;
        let w = unsafe { Watchdog::start(&mut stop, limit) };
        let started = Instant::now();
        // Back to back for two limits: each scan the thread sees is a new one.
        while started.elapsed() < limit * 2 {
            w.scan_begins();
            std::thread::sleep(Duration::from_millis(2));
            assert!(!w.scan_ends(), "a 2 ms scan was stopped");
        }
    }
}
