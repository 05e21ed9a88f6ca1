//! CPU facts the firmwares report.

use core::arch::asm;

extern "C" {
    /// End of static data, placed by avr-gcc's linker script: the stack grows down to it.
    static __heap_start: u8;
}

/// Bytes between the end of static data and the stack pointer: the RAM still free.
pub fn free_ram() -> u16 {
    let (lo, hi): (u8, u8);
    // SAFETY: reads SPL/SPH (I/O 0x3d/0x3e); no side effects.
    unsafe {
        asm!("in {lo}, 0x3d", "in {hi}, 0x3e", lo = out(reg) lo, hi = out(reg) hi, options(nostack, nomem));
    }
    let sp = u16::from_le_bytes([lo, hi]);
    // Only the address of the linker symbol is taken, never its value.
    let end = core::ptr::addr_of!(__heap_start) as u16;
    sp.saturating_sub(end)
}
