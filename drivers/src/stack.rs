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
/// Call once, early (e.g. first thing in `init`), with interrupts off. Ten
/// instructions of assembly (LLVM made 34 of the loop, its bound saturating).
#[inline(never)]
pub fn paint() {
    // SAFETY: [end of static data, SP − MARGIN) is free RAM that nothing uses yet: no
    // heap exists and the stack lies above it (nothing is painted if SP < MARGIN). Only
    // the linker symbol's address is taken. X and r24–r25, r18 are call-clobbered.
    unsafe {
        asm!(
            "in r24, 0x3d",
            "in r25, 0x3e",
            "sbiw r24, {margin}",
            "brlo 2f",
            "ldi r18, {paint}",
            "1:",
            "cp r26, r24",
            "cpc r27, r25",
            "brsh 2f",
            "st X+, r18",
            "rjmp 1b",
            "2:",
            margin = const MARGIN,
            paint = const PAINT,
            inout("X") core::ptr::addr_of!(__heap_start) => _,
            out("r24") _,
            out("r25") _,
            out("r18") _,
            options(nostack),
        );
    }
}
