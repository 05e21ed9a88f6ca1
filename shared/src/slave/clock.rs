//! The slave's sense of time: a wrapping µs clock in, uptime in ms and the interval
//! between ticks out.

use super::divide::div_rem;

/// Time kept from the µs clock the firmware passes to each tick.
#[derive(Clone, Copy, PartialEq, Eq, Debug, Default)]
pub struct Clock {
    started: bool,
    last_us: u32,
    /// µs past the last whole ms, < 1000.
    residual_us: u16,
    ms: u32,
    interval_us: u32,
}

impl Clock {
    /// Not started: the first [`Clock::advance`] starts it.
    pub const fn new() -> Clock {
        Clock {
            started: false,
            last_us: 0,
            residual_us: 0,
            ms: 0,
            interval_us: 0,
        }
    }

    /// Moves to `now_us`. Returns true on the first call. The µs clock may wrap (every
    /// 71.6 min); the ms count carries on across the wrap.
    pub fn advance(&mut self, now_us: u32) -> bool {
        if !self.started {
            self.begin(now_us);
            return true;
        }
        let elapsed = now_us.wrapping_sub(self.last_us);
        self.last_us = now_us;
        self.interval_us = elapsed;
        if elapsed < 2_000 {
            // The usual case, one tick: 16-bit compares instead of a 32-bit division
            // (which costs some 900 cycles on the AVR). total < 3000.
            let mut total = self.residual_us + elapsed as u16;
            if total >= 1000 {
                total -= 1000;
                self.ms = self.ms.wrapping_add(1);
            }
            if total >= 1000 {
                total -= 1000;
                self.ms = self.ms.wrapping_add(1);
            }
            self.residual_us = total;
        } else {
            self.skip(elapsed);
        }
        false
    }

    /// The first call: `now_us` from a clock at 0, as one long gap ([`Clock::skip`]).
    #[inline(always)]
    fn begin(&mut self, now_us: u32) {
        // Every other field is still as `new` made it: only `advance` changes them.
        self.started = true;
        self.last_us = now_us;
        self.skip(now_us);
    }

    /// A gap of 2 ms or more (a stalled tick, or a host test's jump).
    #[inline(never)]
    fn skip(&mut self, elapsed: u32) {
        let total = u32::from(self.residual_us).saturating_add(elapsed);
        let (ms, rest) = div_rem(total, 1000);
        self.ms = self.ms.wrapping_add(ms);
        self.residual_us = rest as u16;
    }

    /// Uptime in ms (wrapping after 49.7 days).
    pub fn ms(&self) -> u32 {
        self.ms
    }

    /// µs between the last two ticks.
    pub fn interval_us(&self) -> u32 {
        self.interval_us
    }
}
