//! Idle sleep: the CPU stops until the next interrupt.

use core::arch::asm;

/// Enables idle sleep mode (SMCR = SE, mode 0: all peripherals keep running).
pub fn enable_idle(cpu: &avr_device::atmega328p::CPU) {
    cpu.smcr().write(|w| w.se().set_bit());
}

/// Enables interrupts and sleeps, atomically: `sei` takes effect after the next
/// instruction, so an interrupt that became pending after the caller's check with
/// interrupts off still wakes the CPU instead of being slept through.
///
/// # Safety
/// Enables interrupts globally: call only where that is allowed (the idle loop).
#[inline(always)]
pub unsafe fn sei_and_sleep() {
    // SAFETY: the caller allows interrupts here; `sleep` only halts until one arrives.
    unsafe { asm!("sei", "sleep", options(nostack, nomem)) }
}
