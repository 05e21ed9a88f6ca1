//! The µs clock the tick and the encoder timestamp with: the compare-A task adds a
//! millisecond to a base, and [`Stamp`] adds the position within the millisecond.

use drivers::timebase::{Stamp, US_PER_PERIOD};

/// µs at the last compare A, and the reader of Timer0.
pub struct Clock {
    base_us: u32,
    stamp: Stamp,
}

impl Clock {
    /// Zero at the first compare A.
    pub const fn new(stamp: Stamp) -> Clock {
        Clock { base_us: 0, stamp }
    }

    /// Compare A: one more millisecond.
    #[inline(always)]
    pub fn advance(&mut self) {
        self.base_us = self.base_us.wrapping_add(US_PER_PERIOD);
    }

    /// Now, in wrapping µs. Call with the compare-A task held off (a lock at its
    /// priority, or from a task at that priority).
    #[inline(always)]
    pub fn now_us(&self) -> u32 {
        self.stamp.since(self.base_us)
    }
}
