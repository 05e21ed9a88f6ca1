//! The twin's speed: emulated time against the wall-clock and CPU time spent on it.

use std::time::{Duration, Instant};

/// Emulated time against the time spent computing it.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Speed {
    /// Emulated time run.
    pub emulated: Duration,
    /// Wall-clock time the runs took.
    pub busy: Duration,
    /// CPU time the runs took (this thread's and the bus's worker threads'), which other
    /// programs on the machine do not inflate.
    pub cpu: Duration,
}

fn per(emulated: Duration, spent: Duration) -> f64 {
    let spent = spent.as_secs_f64();
    if spent > 0.0 {
        emulated.as_secs_f64() / spent
    } else {
        0.0
    }
}

impl Speed {
    /// Emulated seconds per wall-clock second while running (0 before any run): the
    /// twin's speed as a ratio to real time.
    pub fn ratio(&self) -> f64 {
        per(self.emulated, self.busy)
    }

    /// Emulated seconds per second of CPU time: the speed on an otherwise idle core.
    pub fn cpu_ratio(&self) -> f64 {
        per(self.emulated, self.cpu)
    }
}

/// This thread's CPU time so far.
pub(crate) fn thread_cpu() -> Duration {
    let mut ts = nix::libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: `ts` is a valid, writable timespec; the call only writes it.
    let rc = unsafe { nix::libc::clock_gettime(nix::libc::CLOCK_THREAD_CPUTIME_ID, &mut ts) };
    if rc != 0 {
        return Duration::ZERO;
    }
    Duration::new(
        u64::try_from(ts.tv_sec).unwrap_or(0),
        u32::try_from(ts.tv_nsec).unwrap_or(0),
    )
}

/// Where a run started, to account its cost.
pub(crate) struct RunStart {
    pub(crate) wall: Instant,
    pub(crate) cpu: Duration,
    pub(crate) at_us: u64,
}
