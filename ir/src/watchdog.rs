//! A scan watchdog for machines that run compiled code natively (the JIT, the C
//! machine): a thread that asks a scan to stop when it runs too long.
//!
//! Compiled code checks a `stop` byte on every loop back edge (the IR's `watchdog`
//! pass puts the checks there) and leaves its functions when it is set. The thread
//! only watches the clock, so a scan pays two atomic stores for it.

use std::sync::atomic::{AtomicBool, AtomicU64, AtomicU8, Ordering};
use std::sync::{Arc, OnceLock};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

/// State shared with the watching thread.
struct Shared {
    /// When the running scan started, in ns since [`base`]; 0 between scans.
    scan_started: AtomicU64,
    /// The longest a scan may run.
    limit: Duration,
    /// Tells the thread to end.
    quit: AtomicBool,
    /// Address of the runtime's stop byte (valid while the watchdog lives).
    stop: usize,
}

fn base() -> Instant {
    static BASE: OnceLock<Instant> = OnceLock::new();
    *BASE.get_or_init(Instant::now)
}

fn now_ns() -> u64 {
    (base().elapsed().as_nanos() as u64).max(1)
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
            scan_started: AtomicU64::new(0),
            limit,
            quit: AtomicBool::new(false),
            stop: stop as usize,
        });
        let s = shared.clone();
        let poll = (limit / 8).clamp(Duration::from_millis(1), Duration::from_millis(50));
        let thread = std::thread::Builder::new()
            .name("plcc-watchdog".into())
            .spawn(move || {
                while !s.quit.load(Ordering::Acquire) {
                    std::thread::park_timeout(poll);
                    let started = s.scan_started.load(Ordering::Acquire);
                    if started != 0 && now_ns().saturating_sub(started) >= s.limit.as_nanos() as u64
                    {
                        // SAFETY: the byte outlives the thread (joined on drop).
                        unsafe { AtomicU8::from_ptr(s.stop as *mut u8) }
                            .store(1, Ordering::Release);
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
        // SAFETY: see `start`.
        unsafe { AtomicU8::from_ptr(self.shared.stop as *mut u8) }.store(0, Ordering::Release);
        self.shared.scan_started.store(now_ns(), Ordering::Release);
    }

    /// Marks the end of a scan; true if the scan was asked to stop.
    pub fn scan_ends(&self) -> bool {
        self.shared.scan_started.store(0, Ordering::Release);
        // SAFETY: see `start`.
        unsafe { AtomicU8::from_ptr(self.shared.stop as *mut u8) }.load(Ordering::Acquire) != 0
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
