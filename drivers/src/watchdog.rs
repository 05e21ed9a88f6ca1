//! The watchdog in system-reset mode, and the reset cause it leaves behind.

use avr_device::atmega328p::{CPU, WDT};
use core::arch::asm;

/// Data-space address of WDTCSR.
const WDTCSR: u16 = 0x60;

/// Watchdog periods the firmwares use (nominal, at the 128 kHz watchdog oscillator).
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Timeout {
    /// 16 ms: used to reset the chip on purpose, quickly.
    Ms16 = 0,
    /// 125 ms: the master's running period ("120 ms" in the original).
    Ms125 = 3,
    /// 1 s: boot, and the slave's running period.
    S1 = 6,
}

/// What caused the last reset.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum ResetCause {
    /// Power-on or brown-out.
    PowerOn,
    /// The external reset pin (the Uno's DTR auto-reset, or a programmer).
    External,
    /// The watchdog expired.
    Watchdog,
    /// No flag was set (a jump to the reset vector, e.g. by a bootloader).
    Unknown,
}

/// The running watchdog. Dropping it does not stop it.
pub struct Watchdog {
    wdt: WDT,
}

impl Watchdog {
    /// Reads and clears the reset cause, and stops a watchdog left running by a watchdog
    /// reset (it would otherwise fire again after 16 ms, before the firmware has booted).
    pub fn new(wdt: WDT, cpu: &CPU) -> (Self, ResetCause) {
        let (mut dog, cause) = Watchdog::take(wdt, cpu);
        dog.configure(0);
        (dog, cause)
    }

    /// [`Watchdog::new`] and [`Watchdog::start`] in one: reads and clears the reset
    /// cause and runs the watchdog with `timeout` at once (a watchdog left running by a
    /// watchdog reset is re-timed, with no stop between: one timed sequence, not two).
    pub fn started(wdt: WDT, cpu: &CPU, timeout: Timeout) -> (Self, ResetCause) {
        let (mut dog, cause) = Watchdog::take(wdt, cpu);
        dog.start(timeout);
        (dog, cause)
    }

    /// The driver, with the reset cause read and cleared; WDTCSR untouched.
    #[inline(always)]
    fn take(wdt: WDT, cpu: &CPU) -> (Self, ResetCause) {
        let flags = cpu.mcusr().read().bits();
        // SAFETY: clearing MCUSR flags has no effect other than on these flags; WDRF must be
        // cleared before WDE can be cleared.
        cpu.mcusr().write(|w| unsafe { w.bits(0) });
        let cause = if flags & 0b1000 != 0 {
            ResetCause::Watchdog
        } else if flags & 0b0010 != 0 {
            ResetCause::External
        } else if flags & 0b0101 != 0 {
            ResetCause::PowerOn
        } else {
            ResetCause::Unknown
        };
        (Watchdog { wdt }, cause)
    }

    /// Starts (or re-times) the watchdog in system-reset mode.
    pub fn start(&mut self, timeout: Timeout) {
        let p = timeout as u8;
        // WDE plus the prescaler bits WDP0..2 (bit 0..2) and WDP3 (bit 5).
        self.configure(0b0000_1000 | (p & 0b111) | ((p & 0b1000) << 2));
    }

    /// Stops the watchdog.
    pub fn stop(&mut self) {
        self.configure(0);
    }

    /// Restarts the watchdog period.
    #[inline(always)]
    pub fn feed(&self) {
        // SAFETY: `wdr` only restarts the watchdog timer.
        unsafe { asm!("wdr", options(nostack, nomem)) }
    }

    /// Writes WDTCSR with the timed sequence (WDCE|WDE, then the value within four cycles).
    fn configure(&mut self, value: u8) {
        // Ownership of WDT is what makes the raw stores below ours to do.
        let _owned = &self.wdt;
        avr_device::interrupt::free(|_| {
            // SAFETY: interrupts are off, so nothing can delay the second store past the
            // four-cycle window; both stores target WDTCSR, which this driver owns.
            unsafe {
                asm!(
                    "wdr",
                    "sts {reg}, {enable}",
                    "sts {reg}, {value}",
                    reg = const WDTCSR,
                    enable = in(reg) 0b0001_1000u8,
                    value = in(reg) value,
                    options(nostack),
                );
            }
        });
    }
}
