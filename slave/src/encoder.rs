//! The encoder task's body: on a pin change of A (PD0), a rising edge is counted with
//! B's (PD1) level and the time.

use drivers::pin::{Input, PORTD};
use shared::slave::EdgeCounter;

/// Channel A (PD0).
pub type ChannelA = Input<PORTD, 0>;
/// Channel B (PD1).
pub type ChannelB = Input<PORTD, 1>;

/// The two encoder inputs.
pub struct Encoder {
    a: ChannelA,
    b: ChannelB,
}

impl Encoder {
    /// Takes PD0 and PD1 as inputs, pull-ups off (reference §12).
    ///
    /// # Safety
    /// The caller must own PD0 and PD1 (the USART is never enabled on a slave).
    pub unsafe fn new() -> Encoder {
        // SAFETY: ownership is the caller's promise.
        unsafe {
            Encoder {
                a: ChannelA::take(false),
                b: ChannelB::take(false),
            }
        }
    }

    /// A pin change: counts it if A is now high. `now` (16-bit units of 4 µs) is read
    /// only then.
    #[inline(always)]
    pub fn on_change(&self, counter: &mut EdgeCounter, now: impl FnOnce() -> u16) {
        if self.a.is_high() {
            counter.rising_edge(now(), self.b.is_high());
        }
    }
}
