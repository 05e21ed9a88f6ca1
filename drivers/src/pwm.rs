//! The motor PWM: Timer1 in 8-bit phase-correct mode, clock/1 (16 MHz / 510 ≈ 31.4 kHz),
//! OC1A on D9 (M1) and OC1B on D10 (M2), non-inverting. A compare value of 0 holds the
//! pin low, 255 holds it high.

use crate::pin::{Output, PORTB};
use avr_device::atmega328p::TC1;

/// Data-space address of TCCR1A.
const TCCR1A: *mut u8 = 0x80 as *mut u8;
/// TCCR1A: COM1A = COM1B = 0b10 (clear on up-count match), WGM10 (8-bit phase correct).
const TCCR1A_PWM: u8 = 0b1010_0001;
/// TCCR1B: clock/1, WGM12/13 clear.
const TCCR1B_CLK1: u8 = 0b0000_0001;

/// One of the two PWM channels.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Channel {
    /// OC1A, D9: motor M1.
    M1,
    /// OC1B, D10: motor M2.
    M2,
}

/// Timer1 as the two-channel motor PWM.
pub struct Pwm {
    tc1: TC1,
    _d9: Output<PORTB, 1>,
    _d10: Output<PORTB, 2>,
}

impl Pwm {
    /// Starts Timer1 with both duties at 0 (pins low): the compare values' reset value,
    /// which nothing but this driver (given TC1, which exists once per reset) writes.
    ///
    /// # Safety
    /// The caller must own D9 (PB1) and D10 (PB2): this driver makes them outputs.
    pub unsafe fn new(tc1: TC1) -> Pwm {
        // SAFETY: ownership of D9/D10 is the caller's promise.
        let (d9, d10) = unsafe { (Output::take(), Output::take()) };
        // Both compare values are still at their reset value, 0 (only the owner of TC1,
        // taken once per reset, writes them): no stores needed for the duties.
        // SAFETY: the documented mode bits above.
        tc1.tccr1a().write(|w| unsafe { w.bits(TCCR1A_PWM) });
        tc1.tccr1b().write(|w| unsafe { w.bits(TCCR1B_CLK1) });
        Pwm {
            tc1,
            _d9: d9,
            _d10: d10,
        }
    }

    /// Sets a channel's duty, 0..=255 of 255.
    #[inline]
    pub fn set(&mut self, channel: Channel, duty: u8) {
        let value = u16::from(duty);
        // SAFETY: any compare value is valid (double-buffered at TOP by the hardware).
        match channel {
            Channel::M1 => {
                self.tc1.ocr1a().write(|w| unsafe { w.bits(value) });
            }
            Channel::M2 => {
                self.tc1.ocr1b().write(|w| unsafe { w.bits(value) });
            }
        }
    }
}

/// Disconnects both PWM outputs from the timer, so D9 and D10 follow their PORT bits
/// (low). For the panic path, which cannot reach the [`Pwm`] owned by a task.
///
/// # Safety
/// Call only where no other code will touch Timer1 again (interrupts off for good).
#[inline(always)]
pub unsafe fn force_off() {
    // SAFETY: the caller guarantees no concurrent Timer1 user; TCCR1A = 0 only
    // disconnects OC1A/OC1B and selects normal mode.
    unsafe { core::ptr::write_volatile(TCCR1A, 0) };
}
