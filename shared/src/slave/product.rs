//! The slave's two products, built from the AVR's 8×8 hardware multiplier.
//!
//! LLVM lowers every `u32` multiplication on the AVR to a libgcc call chain
//! (`__mulsi3` → `__muluhisi3` → `__umulhisi3`), some 70 cycles, even when both
//! operands are zero-extended 16-bit values; written with `u8` products in Rust it
//! recombines them into worse code. On the AVR [`wide`] is therefore four `mul`
//! instructions and their carries, about 20 cycles; elsewhere it is the plain product.
//! Every wide product on the slave's per-tick path goes through it.
//!
//! [`fixed()`], the saturating `I16F16` product of the PID and of the pot's angle
//! ([`crate::pid::mul`]), is one routine in assembly on the AVR: the sixteen byte
//! products of the magnitudes summed column by column, then the sign and the saturation
//! (about 260 B, where the same arithmetic in Rust over [`wide`] took 500 B). Elsewhere
//! it is Rust in 64 bits, the reference the emulator checks the routine against.
//!
//! The crate denies `unsafe`; this module allows it for its assembly, as `progmem` does
//! for its flash reads.
#![allow(unsafe_code)]

#[cfg(target_arch = "avr")]
use super::words::{halves, join};

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
    join(low, high)
}

/// `a·b` as a `u32`, exact (the full product of two `u16` fits).
#[cfg(not(target_arch = "avr"))]
#[inline(always)]
pub fn wide(a: u16, b: u16) -> u32 {
    u32::from(a) * u32::from(b)
}

/// `a·b` for two `I16F16` values in bits: ⌊|a·b|/2^16⌋ with the sign of a·b, saturated
/// at `i32::MIN`/`i32::MAX` (the product truncated toward zero). 0 at once when an operand
/// is 0.
///
/// On the AVR, one routine in assembly with the operands where the calling convention
/// has them (`a` in r25..r22, `b` in r21..r18, the result in r25..r22), so a call moves
/// little. Column k of the magnitudes' product (the byte products a_i·b_j with i + j = k)
/// is summed into three rotating bytes (r26, r27, r30), one of which leaves as byte k of
/// the 64-bit product: bytes 2..5 are the result, each moved into the register of a_(k−2)
/// once column k + 1's first product (a_(k−2)·b3) has spent it, so the result ends where
/// the convention returns it and the routine touches no register it must save; bytes 6
/// and 7 and bit 31 tell an overflow. The sign of the result waits in the T flag. When
/// |a| and |b| are both below 256 (their top bytes 0), a short form skips the seven
/// products of a3 or b3: 9 products instead of 16.
#[cfg(target_arch = "avr")]
#[inline(never)]
pub fn fixed(a: i32, b: i32) -> i32 {
    // The halves as register pairs: bytes would cost moves to reassemble the result.
    let (mut low, mut high) = halves(a as u32);
    let (b_low, b_high) = halves(b as u32);
    // SAFETY: register arithmetic only (no memory, no stack); every register it writes is
    // an operand or a clobber below, besides r0 (the scratch register), r1 (the zero
    // register, which `mul` overwrites and which is cleared again before the block ends,
    // as the AVR ABI requires) and SREG (not preserved).
    unsafe {
        core::arch::asm!(
            // a == 0: the result is a (0), in place.
            "cp r22, r1",
            "cpc r23, r1",
            "cpc r24, r1",
            "cpc r25, r1",
            "brne 0f",
            "rjmp 9f",
            "0: cp r18, r1",
            "cpc r19, r1",
            "cpc r20, r1",
            "cpc r21, r1",
            "brne 1f",
            // b == 0: the result is b (0).
            "movw r22, r18",
            "movw r24, r20",
            "rjmp 9f",
            // T := the sign of a·b; a := |a|, b := |b| (|i32::MIN| is 2^31, unsigned).
            "1: mov r26, r25",
            "eor r26, r21",
            "bst r26, 7",
            "sbrs r25, 7",
            "rjmp 2f",
            "com r25",
            "com r24",
            "com r23",
            "neg r22",
            "sbci r23, 0xff",
            "sbci r24, 0xff",
            "sbci r25, 0xff",
            "2: sbrs r21, 7",
            "rjmp 3f",
            "com r21",
            "com r20",
            "com r19",
            "neg r18",
            "sbci r19, 0xff",
            "sbci r20, 0xff",
            "sbci r21, 0xff",
            "3: clr r31",
            // Column 0: a0·b0. Byte 0 (r26) only carries.
            "mul r22, r18",
            "movw r26, r0",
            "clr r30",
            // Column 1 into r27, r30, r26: a0·b1, a1·b0. Byte 1 (r27) only carries.
            "clr r26",
            "mul r22, r19",
            "add r27, r0",
            "adc r30, r1",
            "adc r26, r31",
            "mul r23, r18",
            "add r27, r0",
            "adc r30, r1",
            "adc r26, r31",
            // Column 2 into r30, r26, r27: a0·b2, a1·b1, a2·b0.
            "clr r27",
            "mul r22, r20",
            "add r30, r0",
            "adc r26, r1",
            "adc r27, r31",
            "mul r23, r19",
            "add r30, r0",
            "adc r26, r1",
            "adc r27, r31",
            "mul r24, r18",
            "add r30, r0",
            "adc r26, r1",
            "adc r27, r31",
            // |a| and |b| both below 256 (a3 and b3 0, as a PID's gains and terms and the
            // pot's operands are): the short form at 8 below, without the seven products
            // of a3 or b3.
            "cp r25, r31",
            "cpc r21, r31",
            "breq 8f",
            // Column 3 into r26, r27, r30: a0·b3 first, which frees a0's r22 for byte 2,
            // then a1·b2, a2·b1, a3·b0.
            "mul r22, r21",
            "mov r22, r30",
            "clr r30",
            "add r26, r0",
            "adc r27, r1",
            "adc r30, r31",
            "mul r23, r20",
            "add r26, r0",
            "adc r27, r1",
            "adc r30, r31",
            "mul r24, r19",
            "add r26, r0",
            "adc r27, r1",
            "adc r30, r31",
            "mul r25, r18",
            "add r26, r0",
            "adc r27, r1",
            "adc r30, r31",
            // Column 4 into r27, r30, r26: a1·b3 first (byte 3 to a1's r23), a2·b2, a3·b1.
            "mul r23, r21",
            "mov r23, r26",
            "clr r26",
            "add r27, r0",
            "adc r30, r1",
            "adc r26, r31",
            "mul r24, r20",
            "add r27, r0",
            "adc r30, r1",
            "adc r26, r31",
            "mul r25, r19",
            "add r27, r0",
            "adc r30, r1",
            "adc r26, r31",
            // Column 5 into r30, r26, r27: a2·b3 first (byte 4 to a2's r24), a3·b2.
            "mul r24, r21",
            "mov r24, r27",
            "clr r27",
            "add r30, r0",
            "adc r26, r1",
            "adc r27, r31",
            "mul r25, r20",
            "add r30, r0",
            "adc r26, r1",
            "adc r27, r31",
            // Column 6 into r26, r27: a3·b3 (byte 5 to a3's r25). Bytes 6 and 7: the
            // product is below 2^64.
            "mul r25, r21",
            "mov r25, r30",
            "add r26, r0",
            "adc r27, r1",
            "clr r1",
            // |a·b|/2^16 ≥ 2^31 (a byte 6 or 7, or bit 31): 2^31 − 1, complemented to −2^31
            // when negative.
            "or r26, r27",
            "brne 4f",
            "sbrs r25, 7",
            "rjmp 5f",
            "4: ldi r25, 0x7f",
            "ldi r24, 0xff",
            "ldi r23, 0xff",
            "ldi r22, 0xff",
            "brtc 9f",
            "com r25",
            "com r24",
            "com r23",
            "com r22",
            "rjmp 9f",
            // The short form of columns 3 and 4, the product below 2^48: bytes 6 and 7
            // are 0, and column 4's carry out of byte 5 too. Byte 2 to r22 and byte 3 to
            // r23 as a0 and a1 are spent; bytes 4 and 5 to r24, r25 at the end.
            "8: mov r22, r30",
            "clr r30",
            "mul r23, r20",
            "add r26, r0",
            "adc r27, r1",
            "adc r30, r31",
            "mul r24, r19",
            "add r26, r0",
            "adc r27, r1",
            "adc r30, r31",
            "mov r23, r26",
            "mul r24, r20",
            "add r27, r0",
            "adc r30, r1",
            "clr r1",
            "mov r24, r27",
            "mov r25, r30",
            // Bit 31: the saturation above; else in range, below.
            "sbrc r25, 7",
            "rjmp 4b",
            // In range: negated when negative.
            "5: brtc 9f",
            "com r25",
            "com r24",
            "com r23",
            "neg r22",
            "sbci r23, 0xff",
            "sbci r24, 0xff",
            "sbci r25, 0xff",
            "9:",
            inout("r23r22") low,
            inout("r25r24") high,
            inout("r19r18") b_low => _,
            inout("r21r20") b_high => _,
            out("X") _,
            out("Z") _,
            options(pure, nomem, nostack),
        );
    }
    join(low, high) as i32
}

/// `a·b` for two `I16F16` values in bits: ⌊|a·b|/2^16⌋ with the sign of a·b, saturated
/// at `i32::MIN`/`i32::MAX` (the product truncated toward zero). 0 at once when an operand
/// is 0.
#[cfg(not(target_arch = "avr"))]
pub fn fixed(a: i32, b: i32) -> i32 {
    if a == 0 || b == 0 {
        return 0;
    }
    let negative = (a ^ b) < 0;
    let (ua, ub) = (a.unsigned_abs(), b.unsigned_abs());
    let (ah, al) = ((ua >> 16) as u16, ua as u16);
    let (bh, bl) = ((ub >> 16) as u16, ub as u16);
    // |a·b|/2^16 = ah·bh·2^16 + ah·bl + al·bh + ⌊al·bl/2^16⌋, summed in 64 bits.
    let magnitude = (u64::from(wide(ah, bh)) << 16)
        + u64::from(wide(ah, bl))
        + u64::from(wide(al, bh))
        + u64::from(wide(al, bl) >> 16);
    // 2^31 for a negative product, 2^31 − 1 for a positive one.
    let limit = (1u64 << 31) - u64::from(!negative);
    let magnitude = magnitude.min(limit) as u32;
    if negative {
        0i32.wrapping_sub_unsigned(magnitude)
    } else {
        magnitude as i32
    }
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
