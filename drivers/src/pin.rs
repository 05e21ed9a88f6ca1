//! Digital pins as zero-sized types. `PORT` is the I/O-space address of the PORTx
//! register (DDRx is one below it, PINx two below), so every access is one `sbi`/`cbi`/`sbic`.

use core::arch::asm;

/// I/O-space address of PORTB.
pub const PORTB: u8 = 0x05;
/// I/O-space address of PORTC.
pub const PORTC: u8 = 0x08;
/// I/O-space address of PORTD.
pub const PORTD: u8 = 0x0b;

/// A pin used as a push-pull output.
pub struct Output<const PORT: u8, const BIT: u8>(());

/// A pin used as an input (pull-up off unless asked for).
pub struct Input<const PORT: u8, const BIT: u8>(());

impl<const PORT: u8, const BIT: u8> Output<PORT, BIT> {
    /// Makes the pin an output, driven low.
    ///
    /// # Safety
    /// The caller must own this pin: no other `Output`/`Input` for the same port and bit may
    /// exist, or two parts of the firmware would drive one wire.
    pub unsafe fn take() -> Self {
        // SAFETY: sbi/cbi on the pin's own DDR/PORT bit touch no other bit and are atomic.
        unsafe {
            asm!("cbi {port}, {bit}", port = const PORT, bit = const BIT, options(nostack));
            asm!("sbi {ddr}, {bit}", ddr = const PORT - 1, bit = const BIT, options(nostack));
        }
        Output(())
    }

    /// Drives the pin high.
    #[inline(always)]
    pub fn set_high(&self) {
        // SAFETY: one atomic sbi on this pin's own PORT bit.
        unsafe { asm!("sbi {port}, {bit}", port = const PORT, bit = const BIT, options(nostack)) }
    }

    /// Drives the pin low.
    #[inline(always)]
    pub fn set_low(&self) {
        // SAFETY: one atomic cbi on this pin's own PORT bit.
        unsafe { asm!("cbi {port}, {bit}", port = const PORT, bit = const BIT, options(nostack)) }
    }

    /// Drives the pin to `high`.
    #[inline(always)]
    pub fn set(&self, high: bool) {
        if high {
            self.set_high()
        } else {
            self.set_low()
        }
    }

    /// Toggles the pin (writing 1 to PINx flips PORTx in one cycle).
    #[inline(always)]
    pub fn toggle(&self) {
        // SAFETY: writing a one to a PINx bit toggles only that pin's PORT bit.
        unsafe { asm!("sbi {pin}, {bit}", pin = const PORT - 2, bit = const BIT, options(nostack)) }
    }
}

impl<const PORT: u8, const BIT: u8> Input<PORT, BIT> {
    /// Makes the pin an input; `pull_up` enables the internal pull-up.
    ///
    /// # Safety
    /// As for [`Output::take`]: the caller must own this pin.
    pub unsafe fn take(pull_up: bool) -> Self {
        // SAFETY: sbi/cbi on the pin's own DDR/PORT bit touch no other bit and are atomic.
        unsafe {
            asm!("cbi {ddr}, {bit}", ddr = const PORT - 1, bit = const BIT, options(nostack));
            if pull_up {
                asm!("sbi {port}, {bit}", port = const PORT, bit = const BIT, options(nostack));
            } else {
                asm!("cbi {port}, {bit}", port = const PORT, bit = const BIT, options(nostack));
            }
        }
        Input(())
    }

    /// Reads the pin level.
    #[inline(always)]
    pub fn is_high(&self) -> bool {
        let v: u8;
        // SAFETY: reads the PINx I/O register; no side effects.
        unsafe {
            asm!("in {v}, {pin}", v = out(reg) v, pin = const PORT - 2, options(nostack, nomem))
        }
        v & (1 << BIT) != 0
    }
}
