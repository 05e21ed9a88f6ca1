//! One 16×16→32-bit product built from the AVR's 8×8 hardware multiplier.
//!
//! LLVM lowers every `u32` multiplication on the AVR to a libgcc call chain
//! (`__mulsi3` → `__muluhisi3` → `__umulhisi3`), some 70 cycles, even when both
//! operands are zero-extended 16-bit values; written with `u8` products in Rust it
//! recombines them into worse code. On the AVR [`wide`] is therefore four `mul`
//! instructions and their carries, about 20 cycles; elsewhere it is the plain product.
//! Every wide product on the slave's per-tick path goes through it.
//!
//! The crate denies `unsafe`; this module allows it for that one `asm!` block, as
//! `progmem` does for its flash reads.
#![allow(unsafe_code)]

/// `a·b` as a `u32`, exact (the full product of two `u16` fits).
#[cfg(target_arch = "avr")]
#[inline(always)]
pub fn wide(a: u16, b: u16) -> u32 {
    let (low, high): (u16, u16);
    // SAFETY: register arithmetic only (no memory, no stack). `mul` leaves its product in
    // r1:r0: r0 is the scratch register, and r1, the zero register, is cleared again
    // before the block ends, as the AVR ABI requires.
    unsafe {
        core::arch::asm!(
            "clr {zero}",
            "mul {a:l}, {b:l}",
            "movw {low:l}, r0",
            "mul {a:h}, {b:h}",
            "movw {high:l}, r0",
            "mul {a:h}, {b:l}",
            "add {low:h}, r0",
            "adc {high:l}, r1",
            "adc {high:h}, {zero}",
            "mul {a:l}, {b:h}",
            "add {low:h}, r0",
            "adc {high:l}, r1",
            "adc {high:h}, {zero}",
            "clr r1",
            a = in(reg_pair) a,
            b = in(reg_pair) b,
            low = out(reg_pair) low,
            high = out(reg_pair) high,
            zero = out(reg) _,
            options(pure, nomem, nostack),
        );
    }
    u32::from(high) << 16 | u32::from(low)
}

/// `a·b` as a `u32`, exact (the full product of two `u16` fits).
#[cfg(not(target_arch = "avr"))]
#[inline(always)]
pub fn wide(a: u16, b: u16) -> u32 {
    u32::from(a) * u32::from(b)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn equals_the_operator() {
        let values = [
            0u16, 1, 2, 255, 256, 257, 1023, 1573, 0x7fff, 0x8000, 0xfffe, 0xffff,
        ];
        for a in values {
            for b in values {
                assert_eq!(wide(a, b), u32::from(a) * u32::from(b), "{a} × {b}");
            }
        }
        // A sweep of one operand against every other's pattern of bytes.
        for a in (0..=u16::MAX).step_by(97) {
            for b in [3u16, 0x00ff, 0xff00, 0x1234, 0xffff] {
                assert_eq!(wide(a, b), u32::from(a) * u32::from(b), "{a} × {b}");
            }
        }
    }
}
