//! Gated sources: interrupts that drivers switch on and off at run time.
//!
//! USART_UDRE is the typical one: its flag is set whenever the data register is empty, so
//! its interrupt must be on only while bytes are queued. A task bound to such a source is
//! declared `gated = true`; the executor then leaves its enable bit off at start and keeps
//! a separate record of what the driver wants, so that masking and the driver never fight:
//!
//! - [`arm`] says "I want this interrupt". If no masking frame holds the source, the bit
//!   goes on at once; otherwise the frame that masked it turns it on when it ends.
//! - [`disarm`] says "no more". The bit goes off and no frame will turn it back on, even
//!   the task's own entry frame when the task disarms itself.
//!
//! The generated task module offers these as `task::arm()` and `task::disarm()`.

use crate::source::REGS;
use crate::App;

/// Arms the gated source whose enable bit is `B` in register index `R`.
#[inline(always)]
pub fn arm<A: App, const R: usize, const B: u8>() {
    const {
        assert!(
            A::GATED.0[R] & B != 0,
            "arm/disarm apply to gated tasks only"
        )
    };
    crate::port::arm(REGS[R], B);
}

/// Disarms the gated source whose enable bit is `B` in register index `R`.
#[inline(always)]
pub fn disarm<A: App, const R: usize, const B: u8>() {
    const {
        assert!(
            A::GATED.0[R] & B != 0,
            "arm/disarm apply to gated tasks only"
        )
    };
    crate::port::disarm(REGS[R], B);
}
