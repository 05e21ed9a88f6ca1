//! Timer1 as a free-running counter at clk/8 (0.5 µs per count, wrapping every
//! 32.768 ms), for time stamps with µs resolution. The master does not use Timer1 for
//! PWM, and no Timer1 interrupt is enabled (TIMSK1 belongs to the executor anyway).
//!
//! [`EdgeClock`] turns the counts of successive events into a µs timeline, which is what
//! pulse-width measurement needs (`shared::master::rc::PulseTimer`).

use avr_device::atmega328p::TC1;

/// Timer1, counting.
pub struct FreeRunning {
    tc1: TC1,
}

impl FreeRunning {
    /// Starts Timer1 in normal mode (count up, wrap at 0xffff) at clk/8.
    pub fn start(tc1: TC1) -> Self {
        // SAFETY: 0 selects normal mode with both compare outputs disconnected.
        tc1.tccr1a().write(|w| unsafe { w.bits(0) });
        // SAFETY: CS11 alone selects clk/8; normal mode, no input capture options.
        tc1.tccr1b().write(|w| unsafe { w.bits(0b010) });
        FreeRunning { tc1 }
    }

    /// The counter now, in half microseconds. Its 16-bit read goes through the timer's
    /// shared TEMP latch, so call it where no interrupt can read or write another Timer1
    /// 16-bit register in between (from a task at the top priority, or with interrupts
    /// off); nothing else in the master touches them.
    #[inline(always)]
    pub fn count(&self) -> u16 {
        self.tc1.tcnt1().read().bits()
    }
}

/// A µs clock built from counter readings of successive events: each reading adds the
/// time since the previous one. It is exact (the half-µs remainder is carried) as long as
/// successive readings are less than one wrap (32.768 ms) apart; a longer gap loses whole
/// wraps, which leaves every difference between two readings less than a wrap apart
/// correct, as a pulse width (at most a few ms) always is.
#[derive(Clone, Copy, Debug, Default)]
pub struct EdgeClock {
    last: u16,
    half: bool,
    us: u32,
}

impl EdgeClock {
    /// A clock at 0.
    pub const fn new() -> Self {
        EdgeClock {
            last: 0,
            half: false,
            us: 0,
        }
    }

    /// The time (µs, wrapping) of an event whose counter reading is `count`.
    #[inline(always)]
    pub fn stamp(&mut self, count: u16) -> u32 {
        let halves = u32::from(count.wrapping_sub(self.last)) + u32::from(self.half);
        self.last = count;
        self.half = halves & 1 != 0;
        self.us = self.us.wrapping_add(halves >> 1);
        self.us
    }
}
