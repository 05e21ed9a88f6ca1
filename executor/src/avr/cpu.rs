//! The CPU instructions the executor needs: the global interrupt flag and SLEEP.
//!
//! Each is one or two instructions in an `asm!` block without `nomem`, so it is also a
//! compiler barrier: no memory access moves across it.

use core::arch::asm;

/// Sets the global interrupt flag.
///
/// # Safety
/// Only where preemption is allowed: after a task's entry masked its level, or at start.
#[inline(always)]
pub(crate) unsafe fn sei() {
    // SAFETY: the caller upholds the contract above; `sei` touches only SREG.I.
    unsafe { asm!("sei", options(nostack)) };
}

/// Clears the global interrupt flag.
#[inline(always)]
pub(crate) fn cli() {
    // SAFETY: disabling interrupts can never break an invariant.
    unsafe { asm!("cli", options(nostack)) };
}

/// Saves SREG and clears the global interrupt flag; [`restore`] undoes it.
#[inline(always)]
pub(crate) fn save_cli() -> u8 {
    let sreg: u8;
    // SAFETY: reads SREG (I/O 0x3F) and disables interrupts.
    unsafe { asm!("in {0}, 0x3F", "cli", out(reg) sreg, options(nostack)) };
    sreg
}

/// Writes back the SREG saved by [`save_cli`] (and with it the interrupt flag).
///
/// # Safety
/// `sreg` comes from the matching [`save_cli`], and nested save/restore pairs are undone
/// in reverse order.
#[inline(always)]
pub(crate) unsafe fn restore(sreg: u8) {
    // SAFETY: puts back the state that was current when `sreg` was saved.
    unsafe { asm!("out 0x3F, {0}", in(reg) sreg, options(nostack)) };
}

/// Enables interrupts and sleeps, as one unbreakable pair: SEI takes effect only after the
/// next instruction, so an interrupt that became pending before SEI wakes the SLEEP at
/// once instead of being missed.
///
/// # Safety
/// Called by idle only (priority 0, where interrupts are meant to be enabled), with SMCR.SE
/// set by [`crate::start`].
#[inline(always)]
pub(crate) unsafe fn sei_sleep() {
    // SAFETY: see the contract above.
    unsafe { asm!("sei", "sleep", options(nostack)) };
}
