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

    /// The speed in words. Paced, the twin serves real time, so [`Speed::ratio`] is its
    /// headroom (how fast it could run), not the speed it runs at.
    pub fn describe(&self, paced: bool) -> String {
        let (ratio, cpu) = (self.ratio(), self.cpu_ratio());
        let per_cpu = format!("{cpu:.2}x per second of CPU");
        match (paced, ratio < 1.0) {
            (true, false) => format!("paced to real time; compute headroom {ratio:.2}x ({per_cpu})"),
            (true, true) => format!(
                "paced to real time but computes only {ratio:.2}x real time ({per_cpu}), so host timeouts come early"
            ),
            (false, false) => format!("unpaced, running {ratio:.2}x real time ({per_cpu})"),
            (false, true) => format!(
                "unpaced, running {ratio:.2}x real time ({per_cpu}), slower than real time, so host timeouts come early"
            ),
        }
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

#[cfg(test)]
mod tests {
    use super::*;

    fn speed(busy_ms: u64) -> Speed {
        Speed {
            emulated: Duration::from_secs(15),
            busy: Duration::from_millis(busy_ms),
            cpu: Duration::from_millis(busy_ms * 2),
        }
    }

    #[test]
    fn paced_speed_is_told_as_headroom() {
        assert_eq!(
            speed(8475).describe(true),
            "paced to real time; compute headroom 1.77x (0.88x per second of CPU)"
        );
        assert_eq!(
            speed(20_000).describe(true),
            "paced to real time but computes only 0.75x real time (0.38x per second of CPU), \
             so host timeouts come early"
        );
        assert_eq!(
            speed(8475).describe(false),
            "unpaced, running 1.77x real time (0.88x per second of CPU)"
        );
        assert_eq!(
            speed(20_000).describe(false),
            "unpaced, running 0.75x real time (0.38x per second of CPU), slower than real \
             time, so host timeouts come early"
        );
    }
}
