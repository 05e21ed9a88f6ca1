//! On a panic the motors stop first: both PWM outputs disconnected (pins low) and every
//! direction pin low. Then interrupts go off for good, both LEDs light (the "no motor"
//! latch), and the 1-s watchdog, no longer fed, resets the board into its boot exception.
//!
//! An interrupt that no task binds (a stray enable: a fault of the firmware, not of the
//! rover) takes the same path through `__vector_default`, instead of avr-libc's default
//! jump to address 0, a restart that would skip the watchdog and leave the last demand on
//! the pins until boot sets them. No call in the firmware can panic today, so the vector
//! also keeps the handler in the image, where the emulator test
//! (tests/tests/slave_panic.rs) runs it.

use core::panic::PanicInfo;

use crate::stage::{Led1, Led2, M1Neg, M1Pos, M2Neg, M2Pos};

#[panic_handler]
fn panic(_info: &PanicInfo) -> ! {
    halt()
}

/// The vector every unbound interrupt jumps to (avr-libc's crt calls it by this name).
#[no_mangle]
extern "avr-interrupt" fn __vector_default() {
    halt()
}

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
    // SAFETY: as above; interrupts are off and no task runs again.
    unsafe {
        Led1::take().set_high();
        Led2::take().set_high();
    }
    #[allow(clippy::empty_loop)]
    loop {}
}
