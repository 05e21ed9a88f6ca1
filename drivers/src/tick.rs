//! A 1 kHz tick on Timer0 in CTC mode (compare A interrupt).

use avr_device::atmega328p::TC0;

/// Timer0 as the millisecond tick.
pub struct Tick {
    tc0: TC0,
}

impl Tick {
    /// Starts Timer0: prescaler 64, OCR0A 249, so compare A fires every 1000 µs at 16 MHz.
    /// The compare interrupt's enable bit (TIMSK0) belongs to the executor, which sets it
    /// for the task bound to TIMER0_COMPA.
    pub fn start(tc0: TC0) -> Self {
        tc0.tccr0a().write(|w| w.wgm0().ctc());
        // SAFETY: 249 is a valid compare value.
        tc0.ocr0a().write(|w| unsafe { w.bits(249) });
        tc0.tccr0b().write(|w| w.cs0().prescale_64());
        Tick { tc0 }
    }

    /// Microseconds into the current millisecond (0..=999), for finer timestamps.
    pub fn sub_ms_us(&self) -> u16 {
        u16::from(self.tc0.tcnt0().read().bits()) * 4
    }
}
