//! The slave's sense of time: a wrapping µs clock in, uptime in ms and the interval
//! between ticks out.

/// Time kept from the µs clock the firmware passes to each tick.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct Clock {
    started: bool,
    last_us: u32,
    /// µs to the next whole ms, 1..=1000 (1000 less the µs past the last one).
    to_next_us: u16,
    ms: u32,
    /// µs between the last two ticks, mod 2^16 (what REG_INTERVALI2C shows).
    interval_us: u16,
}

impl Clock {
    /// Not started: the first [`Clock::advance`] starts it.
    pub const fn new() -> Clock {
        Clock {
            started: false,
            last_us: 0,
            to_next_us: 1000,
            ms: 0,
            interval_us: 0,
        }
    }

    /// Moves to `now_us`. Returns true on the first call, which counts `now_us` from a
    /// clock at 0 (the interval stays 0). The µs clock may wrap (every 71.6 min); the
    /// ms count carries on across the wrap.
    ///
    /// The whole ms of the gap are counted off one by one: a tick 1 ms after the last
    /// takes one pass, and no division is linked for the rare long gap (on the board a
    /// gap is never much longer than a tick: the watchdog resets it after 1.024 s, some
    /// 15 cycles a pass; a host test may jump further, exactly).
    pub fn advance(&mut self, now_us: u32) -> bool {
        let first = !self.started;
        let mut elapsed = if first {
            now_us
        } else {
            let elapsed = now_us.wrapping_sub(self.last_us);
            self.interval_us = elapsed as u16;
            elapsed
        };
        self.started = true;
        self.last_us = now_us;
        // Each whole ms reached, one pass: the first after `to_next_us`, the others
        // 1000 µs apart.
        let mut ms = self.ms;
        let mut to_next = self.to_next_us;
        while elapsed >= u32::from(to_next) {
            elapsed = opaque(elapsed - u32::from(to_next));
            to_next = 1000;
            ms = ms.wrapping_add(1);
        }
        // elapsed < to_next ≤ 1000.
        self.to_next_us = to_next - elapsed as u16;
        self.ms = ms;
        first
    }

    /// Uptime in ms (wrapping after 49.7 days).
    pub fn ms(&self) -> u32 {
        self.ms
    }

    /// µs between the last two ticks, mod 2^16 (REG_INTERVALI2C).
    pub fn interval_us(&self) -> u16 {
        self.interval_us
    }
}

impl Default for Clock {
    /// [`Clock::new`].
    fn default() -> Clock {
        Clock::new()
    }
}

/// `x`, through an empty assembly template on the AVR: no instruction, but the
/// optimiser no longer knows the value, so [`Clock::advance`]'s counting loop stays a
/// loop (it turned it into a call of the 32-bit library division, 1.1 KB).
#[inline(always)]
fn opaque(x: u32) -> u32 {
    #[cfg(target_arch = "avr")]
    {
        let mut low = x as u16;
        // SAFETY: a template of only a comment: no instruction, no memory or stack
        // access; it hides the value's low half from the optimiser.
        #[allow(unsafe_code)]
        unsafe {
            core::arch::asm!("; {0}", inout(reg_pair) low, options(pure, nomem, nostack))
        };
        (x & 0xffff_0000) | u32::from(low)
    }
    #[cfg(not(target_arch = "avr"))]
    x
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
            // First calls from 0 up, then the far end of the clock.
            let start = if run < 2_500 { run * 2 } else { next(u32::MAX) };
            let mut clock = Clock::new();
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
                assert_eq!(clock.interval_us(), wide.interval_us as u16, "{run} {step}");
            }
        }
        assert!(long > 10_000, "{long} long gaps");
    }

    #[test]
    fn the_default_clock_is_a_new_one() {
        assert_eq!(Clock::default(), Clock::new());
        assert_eq!(Clock::new().to_next_us, 1000);
    }

    #[test]
    fn the_longest_gap_after_a_residual_counts_exactly() {
        // 999 µs, then a gap of 2^32 − 1 µs: 4,294,968,294 µs in all.
        let mut clock = Clock::new();
        assert!(clock.advance(999));
        assert_eq!((clock.ms(), clock.to_next_us), (0, 1));
        assert!(!clock.advance(998));
        assert_eq!(clock.interval_us(), u16::MAX);
        assert_eq!((clock.ms(), clock.to_next_us), (4_294_968, 706));
    }
}
