//! Host stand-ins for the AVR core, so that applications and the analysis build and are
//! tested on the development machine. There are no interrupts on the host and task
//! contexts are created only by generated vectors (which exist only on the AVR), so a
//! lock is a plain call here.

use crate::source::Reg;
use crate::App;

/// Host version of the lock: runs `f`.
///
/// # Safety
/// `ptr` points to an initialised value that nothing else borrows.
#[inline(always)]
#[allow(clippy::extra_unused_type_parameters)]
pub(crate) unsafe fn lock<A: App, const C: u8, const P: u8, T, R>(
    ptr: *mut T,
    f: impl FnOnce(&mut T) -> R,
) -> R {
    // SAFETY: per the contract.
    f(unsafe { &mut *ptr })
}

/// Host version of arming a gated source: nothing to switch.
pub(crate) fn arm(_reg: Reg, _bit: u8) {}

/// Host version of disarming a gated source: nothing to switch.
pub(crate) fn disarm(_reg: Reg, _bit: u8) {}

/// Idle's right to sleep (on the host it only evaluates the check).
pub struct Sleep {
    _private: (),
}

impl Sleep {
    /// The token.
    ///
    /// # Safety
    /// Only the generated idle context creates it.
    #[doc(hidden)]
    pub unsafe fn new() -> Sleep {
        Sleep { _private: () }
    }

    /// Evaluates `busy`; there is no CPU to put to sleep on the host.
    pub fn sleep_unless(&mut self, busy: impl FnOnce() -> bool) {
        let _ = busy();
    }

    /// Nothing to do on the host.
    pub fn sleep(&mut self) {}
}

/// Stand-in for the device peripherals handed to `init`.
pub struct Device {
    _private: (),
}

/// Stand-in for taking the peripherals.
///
/// # Safety
/// None on the host; `unsafe` to match the AVR signature.
pub unsafe fn take_device() -> Device {
    Device { _private: () }
}
