//! The slave's sense of time: a wrapping µs clock in, uptime in ms and the interval
//! between ticks out.

use super::divide::div_rem;

/// Time kept from the µs clock the firmware passes to each tick.
#[derive(Clone, Copy, PartialEq, Eq, Debug, Default)]
pub struct Clock {
    last_us: Option<u32>,
    residual_us: u32,
    ms: u32,
    interval_us: u32,
}

impl Clock {
    /// Not started: the first [`Clock::advance`] starts it.
    pub const fn new() -> Clock {
        Clock {
            last_us: None,
            residual_us: 0,
            ms: 0,
            interval_us: 0,
        }
    }

    /// Moves to `now_us`. Returns true on the first call. The µs clock may wrap (every
    /// 71.6 min); the ms count carries on across the wrap.
    pub fn advance(&mut self, now_us: u32) -> bool {
        let Some(last) = self.last_us else {
            self.last_us = Some(now_us);
            (self.ms, self.residual_us) = div_rem(now_us, 1000);
            return true;
        };
        let elapsed = now_us.wrapping_sub(last);
        self.last_us = Some(now_us);
        self.interval_us = elapsed;
        let mut total = self.residual_us.saturating_add(elapsed);
        if total < 2_000 {
            // The usual case, one tick: a compare instead of a 32-bit division (which
            // costs some 900 cycles on the AVR).
            if total >= 1000 {
                total -= 1000;
                self.ms = self.ms.wrapping_add(1);
            }
        } else {
            let (ms, rest) = div_rem(total, 1000);
            self.ms = self.ms.wrapping_add(ms);
            total = rest;
        }
        self.residual_us = total;
        false
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
