//! Stack painting: free RAM is filled with a known byte at boot, so the deepest the
//! stack has ever reached can be read back later (by the emulator, or a debugger) as
//! the lowest address that no longer holds the paint.

use core::arch::asm;

extern "C" {
    /// End of static data, placed by the linker: the stack grows down towards it.
    static __heap_start: u8;
}

/// The paint byte.
pub const PAINT: u8 = 0xc5;

/// Bytes left unpainted just below the stack pointer (this function's own use).
const MARGIN: u16 = 8;

/// Paints RAM from the end of static data to just below the stack pointer.
///
/// Call once, early (e.g. first thing in `init`), with interrupts off.
#[inline(never)]
pub fn paint() {
    let (lo, hi): (u8, u8);
    // SAFETY: reads SPL/SPH (I/O 0x3d/0x3e); no side effects.
    unsafe {
        asm!("in {lo}, 0x3d", "in {hi}, 0x3e", lo = out(reg) lo, hi = out(reg) hi, options(nostack, nomem));
    }
    let sp = u16::from_le_bytes([lo, hi]);
    // Only the address of the linker symbol is taken, never its value.
    let mut at = core::ptr::addr_of!(__heap_start) as u16;
    let end = sp.saturating_sub(MARGIN);
    while at < end {
        // SAFETY: [end of static data, SP - MARGIN) is free RAM that nothing uses yet:
        // no heap exists and the stack lies above `end`.
        unsafe { core::ptr::write_volatile(at as *mut u8, PAINT) };
        at += 1;
    }
}
