//! The clock the tick and the encoder timestamp with: the compare-A task adds a
//! millisecond's counts (of 4 µs) to a base, and [`Stamp`] adds the position within the
//! millisecond. The tick reads it in µs, the encoder in 16-bit units of one count
//! (`shared::slave::clock::units` of the same µs clock).

use drivers::timebase::{Stamp, COUNTS_PER_PERIOD, US_PER_COUNT};

// The tick's µs are the counts times 4, so the encoder's units are the same clock.
const _: () = assert!(US_PER_COUNT as u32 == shared::slave::clock::US_PER_UNIT);

/// Counts (of 4 µs) at the last compare A, and the reader of Timer0.
pub struct Clock {
    base: u32,
    stamp: Stamp,
}

impl Clock {
    /// Zero at the first compare A.
    pub const fn new(stamp: Stamp) -> Clock {
        Clock { base: 0, stamp }
    }

    /// Compare A: one more millisecond.
    #[inline(always)]
    pub fn advance(&mut self) {
        self.base = self.base.wrapping_add(u32::from(COUNTS_PER_PERIOD));
    }

    /// Now, in wrapping µs. Call with the compare-A task held off (a lock at its
    /// priority, or from a task at that priority).
    #[inline(always)]
    pub fn now_us(&self) -> u32 {
        // 4 µs a count: the µs clock wraps with the counts' low 30 bits.
        self.base.wrapping_add(u32::from(self.stamp.counts())) << 2
    }

    /// Now, in wrapping 16-bit units of 4 µs: the low 16 bits of the counts, in 16-bit
    /// arithmetic. Call as [`Clock::now_us`].
    #[inline(always)]
    pub fn now_units(&self) -> u16 {
        self.stamp.counts_from(self.base as u16)
    }
}
