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
    /// The same gap in units, saturating ([`age_of`]).
    gap: u16,
}

/// Microseconds per unit of the slave's 16-bit time: the timebase's count (Timer0 at
/// clock/64, so every time on the chip is a whole number of units). Timestamps in units
/// wrap every 2^16 units (262,144 µs); ages saturate at [`AGE_MAX`].
pub const US_PER_UNIT: u32 = 4;
/// An age of this many units or more: 262,140 µs or more (saturated).
pub const AGE_MAX: u16 = u16::MAX;
/// A gap of this many units or more is a long one (2^15 µs).
const LONG_GAP: u16 = 1 << 13;

/// The wrapping 16-bit time in units of a wrapping µs clock: bits 2..17 of `now_us`.
#[inline(always)]
pub fn units(now_us: u32) -> u16 {
    (now_us >> 2) as u16
}

/// `age + gap` units, saturating at [`AGE_MAX`]: an age one tick on.
///
/// On the AVR five instructions of assembly (LLVM made a flag of the carry and a
/// select, some 20 B a use); the emulator test `slave_maths` checks it against the
/// host's `saturating_add` for every gap at a dozen ages.
#[doc(hidden)]
#[inline(always)]
pub fn age_add(age: u16, gap: u16) -> u16 {
    #[cfg(target_arch = "avr")]
    {
        let mut sum = age;
        // SAFETY: register arithmetic only (no memory, no stack).
        #[allow(unsafe_code)]
        unsafe {
            core::arch::asm!(
                "add {s:l}, {g:l}",
                "adc {s:h}, {g:h}",
                // 0xff on a carry, else 0: ORed in, the saturated sum.
                "sbc {t}, {t}",
                "or {s:l}, {t}",
                "or {s:h}, {t}",
                s = inout(reg_pair) sum,
                g = in(reg_pair) gap,
                t = out(reg) _,
                options(pure, nomem, nostack),
            );
        }
        sum
    }
    #[cfg(not(target_arch = "avr"))]
    {
        age.saturating_add(gap)
    }
}

/// `elapsed_us` µs in whole units, saturating at [`AGE_MAX`].
#[inline(always)]
pub fn age_of(elapsed_us: u32) -> u16 {
    if elapsed_us >> 18 != 0 {
        AGE_MAX
    } else {
        (elapsed_us >> 2) as u16
    }
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
            gap: 0,
        }
    }

    /// Moves to `now_us`. Returns true on the first call, which counts `now_us` from a
    /// clock at 0 (the interval stays 0). The µs clock may wrap (every 71.6 min); the
    /// ms count carries on across the wrap.
    ///
    /// The whole ms of the gap are counted off one by one, 17 cycles a pass on the AVR:
    /// a tick 1 ms after the last takes one pass, and no division is linked for the rare
    /// long gap. On the board a gap is never much longer than a tick: the watchdog
    /// resets it after 1.024 s. The longest gap a wrapping clock can show, 2^32 − 1 µs
    /// (a clock that stepped back), would take some 4.6 s of passes: the watchdog would
    /// reset the board first, its motors stopped. A host test may jump further, exactly.
    pub fn advance(&mut self, now_us: u32) -> bool {
        let first = !self.started;
        let elapsed = if first {
            now_us
        } else {
            let elapsed = now_us.wrapping_sub(self.last_us);
            self.interval_us = elapsed as u16;
            self.gap = age_of(elapsed);
            elapsed
        };
        self.started = true;
        self.last_us = now_us;
        (self.to_next_us, self.ms) = count_ms(elapsed, self.to_next_us, self.ms);
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

    /// Whether the last two ticks were 2^15 µs or more apart (false after the first):
    /// a 16-bit µs deadline may have been passed by more than its signed range shows
    /// (see [`due_every`]).
    pub fn long_gap(&self) -> bool {
        self.gap >= LONG_GAP
    }

    /// The units between the last two ticks, saturating at [`AGE_MAX`] (0 after the
    /// first): what the speed meter's ages grow by.
    pub fn gap(&self) -> u16 {
        self.gap
    }
}

/// A periodic µs deadline kept in 16 bits: whether `next` is due at `now_us` (mod 2^16),
/// and if so, `next` moved on by `period_us`, or to `now_us + period_us` when that is
/// still not ahead (more than a period late). `long_gap` is [`Clock::long_gap`].
///
/// The same as the 32-bit form (due when `(now − next) as i32 ≥ 0`, `next` and `now`
/// in full µs) when called every tick, for gaps below 2^31 µs: after each call `next`
/// is 1..=`ahead` µs past `now` (`ahead` ≤ 3,000 for the position updates), so `gap` µs
/// later `now − next` lies in `gap − ahead ..= gap − 1`, which the 16-bit signed
/// difference shows exactly for `gap` < 2^15; a longer gap (`long_gap`) leaves `now`
/// more than `period_us` past `next` (2^15 − `ahead` − `period_us` > 0), where both
/// forms restart from now. Tested against the 32-bit form.
#[inline(always)]
pub fn due_every(next: &mut u16, now_us: u16, long_gap: bool, period_us: u16) -> bool {
    if !long_gap {
        if (now_us.wrapping_sub(*next) as i16) < 0 {
            return false;
        }
        *next = next.wrapping_add(period_us);
        if (now_us.wrapping_sub(*next) as i16) < 0 {
            return true;
        }
    }
    // More than a period late (a stalled tick): start again from now.
    *next = now_us.wrapping_add(period_us);
    true
}

impl Default for Clock {
    /// [`Clock::new`].
    fn default() -> Clock {
        Clock::new()
    }
}

/// `elapsed` µs on from `to_next` µs (1..=1000) before the next whole ms, at `ms` ms:
/// the µs then to the next whole ms and the ms count (wrapping). Each whole ms reached
/// is one pass: the first after `to_next`, the others 1000 µs apart.
///
/// On the AVR, 17 instructions of assembly (LLVM made some 90 B of the loop); the
/// emulator test `slave_maths` checks it against the Rust form, which the host builds.
#[doc(hidden)]
#[inline(always)]
pub fn count_ms(elapsed: u32, to_next: u16, ms: u32) -> (u16, u32) {
    #[cfg(target_arch = "avr")]
    {
        let (e_lo, e_hi) = (elapsed as u16, (elapsed >> 16) as u16);
        let (mut to_next, mut m_lo, mut m_hi) = (to_next, ms as u16, (ms >> 16) as u16);
        // SAFETY: register arithmetic only (no memory, no stack); r1 is the zero
        // register throughout, as the AVR ABI keeps it.
        #[allow(unsafe_code)]
        unsafe {
            core::arch::asm!(
                "1:",
                // elapsed < to_next: done.
                "cp {el:l}, {tn:l}",
                "cpc {el:h}, {tn:h}",
                "cpc {eh:l}, r1",
                "cpc {eh:h}, r1",
                "brlo 2f",
                // A whole ms: elapsed −= to_next, to_next = 1000, ms += 1.
                "sub {el:l}, {tn:l}",
                "sbc {el:h}, {tn:h}",
                "sbc {eh:l}, r1",
                "sbc {eh:h}, r1",
                "ldi {tn:l}, 0xe8",
                "ldi {tn:h}, 0x03",
                "adiw {ml:l}, 1",
                "adc {mh:l}, r1",
                "adc {mh:h}, r1",
                "rjmp 1b",
                // elapsed < to_next ≤ 1000: what is left of to_next.
                "2:",
                "sub {tn:l}, {el:l}",
                "sbc {tn:h}, {el:h}",
                el = inout(reg_pair) e_lo => _,
                eh = inout(reg_pair) e_hi => _,
                tn = inout(reg_iw) to_next,
                ml = inout(reg_iw) m_lo,
                mh = inout(reg_pair) m_hi,
                options(pure, nomem, nostack),
            );
        }
        (to_next, u32::from(m_hi) << 16 | u32::from(m_lo))
    }
    #[cfg(not(target_arch = "avr"))]
    {
        let (mut elapsed, mut to_next, mut ms) = (elapsed, to_next, ms);
        while elapsed >= u32::from(to_next) {
            elapsed -= u32::from(to_next);
            to_next = 1000;
            ms = ms.wrapping_add(1);
        }
        // elapsed < to_next ≤ 1000.
        (to_next - elapsed as u16, ms)
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
                        3 => 262_140 + next(8),
                        4 => 261_000 + next(2_000),
                        2 => 32_767 + next(2),
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
                assert_eq!(
                    clock.long_gap(),
                    step > 0 && wide.interval_us >= 1 << 15,
                    "{run} {step}"
                );
                let gap = if step > 0 { wide.interval_us / 4 } else { 0 };
                assert_eq!(u32::from(clock.gap()), gap.min(65_535), "{run} {step}");
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
        assert!(clock.long_gap());
        assert_eq!(clock.gap(), AGE_MAX);
        assert_eq!((clock.ms(), clock.to_next_us), (4_294_968, 706));
    }
}
