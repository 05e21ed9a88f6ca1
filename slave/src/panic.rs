//! On a panic the motors stop first: both PWM outputs disconnected (pins low) and every
//! direction pin low. Then interrupts go off for good, the TWI leaves the bus, both LEDs
//! light (the "no motor" latch), and the 1-s watchdog, no longer fed, resets the board into
//! its boot exception.
//!
//! An interrupt that no task binds takes the same path ([`drivers::fault_entry`]);
//! `tests/tests/slave_panic.rs` runs it on the real images.

use crate::stage::{Led1, Led2, M1Neg, M1Pos, M2Neg, M2Pos};

drivers::fault_entries!(halt);

/// Motors off, interrupts off, both LEDs lit, then wait for the watchdog.
#[inline(always)]
fn halt() -> ! {
    // SAFETY: nothing runs after this but the loop below; TCCR1A = 0 only disconnects
    // the PWM from D9/D10, whose PORT bits are low.
    unsafe { drivers::pwm::force_off() };
    // SAFETY: the pins may be owned by the output stage, which never runs again; each
    // `take` is one cbi/sbi on that pin's own bits and leaves it an output, low.
    unsafe {
        let _ = M1Pos::take();
        let _ = M1Neg::take();
        let _ = M2Pos::take();
        let _ = M2Neg::take();
    }
    executor::freeze();
    // SAFETY: interrupts are off and the TWI task never runs again. Off the bus, the board
    // is found silent by the master, which stops the others.
    unsafe { drivers::twi_slave::force_off() };
    // SAFETY: as above; interrupts are off and no task runs again.
    unsafe {
        Led1::take().set_high();
        Led2::take().set_high();
    }
    #[allow(clippy::empty_loop)]
    loop {}
}
