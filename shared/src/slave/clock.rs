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

    /// Moves to `now_us`. Returns true on the first call, which counts `now_us` from a
    /// clock at 0 (the interval stays 0). The µs clock may wrap (every 71.6 min); the
    /// ms count carries on across the wrap.
    pub fn advance(&mut self, now_us: u32) -> bool {
        self.advance_with(now_us, |clock, elapsed| clock.skip(elapsed))
    }

    /// [`Clock::advance`] with the long gap's division in line (for a tick where that is
    /// smaller than a call: the lift/lift board's, by 28 B).
    #[inline(always)]
    pub fn advance_in_line(&mut self, now_us: u32) -> bool {
        self.advance_with(now_us, |clock, elapsed| clock.skip_in_line(elapsed))
    }

    /// [`Clock::advance`], the long gap's step given.
    #[inline(always)]
    fn advance_with(&mut self, now_us: u32, skip: impl FnOnce(&mut Clock, u32)) -> bool {
        let first = !self.started;
        let elapsed = if first {
            now_us
        } else {
            let elapsed = now_us.wrapping_sub(self.last_us);
            self.interval_us = elapsed;
            elapsed
        };
        self.started = true;
        self.last_us = now_us;
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
            skip(self, elapsed);
        }
        first
    }

    /// A gap of 2 ms or more (a stalled tick, or a host test's jump).
    #[inline(never)]
    fn skip(&mut self, elapsed: u32) {
        self.skip_in_line(elapsed);
    }

    /// [`Clock::skip`]'s body.
    #[inline(always)]
    fn skip_in_line(&mut self, elapsed: u32) {
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

#[cfg(test)]
mod tests {
    use super::*;

    /// ⌊µs/1000⌋ ms and the interval, counted in wide arithmetic from the first call.
    struct Reference {
        first_us: Option<u32>,
        last_us: u32,
        total_us: u64,
        interval_us: u32,
    }

    #[test]
    fn the_first_call_and_every_later_one_count_as_wide_arithmetic() {
        let mut random = crate::test_random::Xorshift(0x9e37_79b9_7f4a_7c15u64);
        let mut next = |bound: u32| random.below(bound);
        let mut long = 0;
        for run in 0..3_000u32 {
            // First calls from 0 up (both paths), then the far end of the clock.
            let start = if run < 2_500 { run * 2 } else { next(u32::MAX) };
            let mut clock = Clock::new();
            let mut in_line = Clock::new();
            let mut wide = Reference {
                first_us: None,
                last_us: 0,
                total_us: 0,
                interval_us: 0,
            };
            let mut now = start;
            for step in 0..200 {
                if step > 0 {
                    let gap = match next(50) {
                        0 => next(200_000),
                        1 => 2_000 + next(3),
                        _ => 990 + next(20),
                    };
                    long += usize::from(gap >= 2_000);
                    now = now.wrapping_add(gap);
                }
                let first = clock.advance(now);
                assert_eq!(first, wide.first_us.is_none());
                assert_eq!(in_line.advance_in_line(now), first);
                assert_eq!(in_line, clock);
                if wide.first_us.is_none() {
                    wide.first_us = Some(now);
                    wide.total_us = u64::from(now);
                } else {
                    wide.interval_us = now.wrapping_sub(wide.last_us);
                    wide.total_us += u64::from(wide.interval_us);
                }
                wide.last_us = now;
                assert_eq!(
                    u64::from(clock.ms()),
                    wide.total_us / 1000 % (1 << 32),
                    "{run}"
                );
                assert_eq!(clock.interval_us(), wide.interval_us, "{run} {step}");
            }
        }
        assert!(long > 10_000, "{long} long gaps");
    }
}
