//! Timer0 as the time base of the slave: CTC at 1 kHz (prescaler 64, 4 µs per count).
//! Compare A marks each millisecond; compare B, half a millisecond later, paces the
//! control tick. Both interrupt enables belong to the executor.
//!
//! [`Stamp`] reads the counter and the pending compare-A flag without owning the timer
//! (both reads are side-effect free), so any task can timestamp an event. Every time it
//! gives is a whole number of counts (4 µs).

use avr_device::atmega328p::TC0;

/// Compare A: 250 counts of 4 µs.
const OCR0A_1MS: u8 = 249;
/// Compare B: the control tick, half-way through each millisecond.
const OCR0B_TICK: u8 = 124;
/// Data-space address of TCNT0.
const TCNT0: *const u8 = 0x46 as *const u8;
/// Data-space address of TIFR0.
const TIFR0: *const u8 = 0x35 as *const u8;
/// TIFR0.OCF0A.
const OCF0A: u8 = 1 << 1;

/// Microseconds per count.
pub const US_PER_COUNT: u16 = 4;
/// Counts per compare-A period (1 ms).
pub const COUNTS_PER_PERIOD: u16 = OCR0A_1MS as u16 + 1;

/// The running Timer0.
pub struct Timebase {
    _tc0: TC0,
}

impl Timebase {
    /// Starts Timer0: CTC, clock/64, compare A every 1 ms, compare B at mid-period.
    pub fn start(tc0: TC0) -> (Timebase, Stamp) {
        tc0.tccr0a().write(|w| w.wgm0().ctc());
        // SAFETY: both values are valid compare values, B below A.
        tc0.ocr0a().write(|w| unsafe { w.bits(OCR0A_1MS) });
        tc0.ocr0b().write(|w| unsafe { w.bits(OCR0B_TICK) });
        tc0.tccr0b().write(|w| w.cs0().prescale_64());
        (Timebase { _tc0: tc0 }, Stamp(()))
    }
}

/// A reader of Timer0's position within the millisecond.
#[derive(Clone, Copy)]
pub struct Stamp(());

impl Stamp {
    /// Counts (of 4 µs) since the last compare A that the caller's base already counts:
    /// the counter, plus a whole period if compare A has matched but its interrupt has
    /// not run yet. Call with interrupts off (or from a task at the top priority), so the
    /// compare-A task cannot run between the caller's read of its base and this.
    #[inline(always)]
    pub fn counts(&self) -> u16 {
        // SAFETY: reading TCNT0 and TIFR0 has no side effect; the counter first, so a
        // match between the two reads is seen with a high count and not added twice.
        let (count, flags) = unsafe {
            (
                core::ptr::read_volatile(TCNT0),
                core::ptr::read_volatile(TIFR0),
            )
        };
        let mut counts = u16::from(count);
        if flags & OCF0A != 0 && count < OCR0B_TICK {
            counts += COUNTS_PER_PERIOD;
        }
        counts
    }

    /// `base` + [`Stamp::counts`] in wrapping 16-bit arithmetic, the count added before
    /// the pending period (fewer registers live in a short interrupt task).
    #[inline(always)]
    pub fn counts_from(&self, base: u16) -> u16 {
        // SAFETY: as in `counts`.
        let (count, flags) = unsafe {
            (
                core::ptr::read_volatile(TCNT0),
                core::ptr::read_volatile(TIFR0),
            )
        };
        let mut now = base.wrapping_add(u16::from(count));
        if flags & OCF0A != 0 && count < OCR0B_TICK {
            now = now.wrapping_add(COUNTS_PER_PERIOD);
        }
        now
    }
}
