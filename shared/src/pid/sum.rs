//! The saturating `I16F16` sum and difference of `Saturating`, the magnitude
//! of `magnitude`, and the PID's dead zone and integral clamp, in bits.
//!
//! On the AVR each sum is one short routine in assembly: the 32-bit sum, and on a signed
//! overflow the limit the carry points to (24 B each, where the `fixed` crate's
//! saturating operations compile to 66 and 70 B). The magnitude is nine instructions in
//! line (the standard library's takes 16 and a spare register), the clamp of the
//! integral to ±cap 23 (the two compares and selects in Rust took 37 to 46), the dead
//! zone 21 (6 to 36 B less than the magnitude, compare and select in Rust). Elsewhere they are the
//! standard library's operations, the reference the assembly is checked against.
//!
//! The crate denies `unsafe`; this module allows it for its assembly, as
//! [`crate::slave::product`] does.
#![allow(unsafe_code)]

#[cfg(target_arch = "avr")]
use crate::slave::words::{halves, join};

/// `a + b`, saturating at `i32::MIN`/`i32::MAX`.
///
/// On the AVR: after the 32-bit sum, an overflow (V) means both operands had the sign the
/// sum lacks; a carry out then means both were negative. The limit is 2^31 − 1 + C.
#[cfg(target_arch = "avr")]
#[inline(never)]
pub fn add(a: i32, b: i32) -> i32 {
    let (mut low, mut high) = halves(a as u32);
    let (b_low, b_high) = halves(b as u32);
    // SAFETY: register arithmetic only (no memory, no stack) on the operands' registers;
    // r1 (the zero register) is only read; SREG is not preserved.
    unsafe {
        core::arch::asm!(
            "add r22, r18",
            "adc r23, r19",
            "adc r24, r20",
            "adc r25, r21",
            "brvc 1f",
            // `ldi` keeps the flags: 0x7fffffff + C.
            "ldi r22, 0xff",
            "ldi r23, 0xff",
            "ldi r24, 0xff",
            "ldi r25, 0x7f",
            "adc r22, r1",
            "adc r23, r1",
            "adc r24, r1",
            "adc r25, r1",
            "1:",
            inout("r23r22") low,
            inout("r25r24") high,
            in("r19r18") b_low,
            in("r21r20") b_high,
            options(pure, nomem, nostack),
        );
    }
    join(low, high) as i32
}

/// `a − b`, saturating at `i32::MIN`/`i32::MAX`.
///
/// On the AVR: after the 32-bit difference, an overflow (V) means the operands' signs
/// differed; a borrow (C) then means a was the non-negative one. The limit is
/// 2^31 − C.
#[cfg(target_arch = "avr")]
#[inline(never)]
pub fn sub(a: i32, b: i32) -> i32 {
    let (mut low, mut high) = halves(a as u32);
    let (b_low, b_high) = halves(b as u32);
    // SAFETY: register arithmetic only (no memory, no stack) on the operands' registers;
    // r1 (the zero register) is only read; SREG is not preserved.
    unsafe {
        core::arch::asm!(
            "sub r22, r18",
            "sbc r23, r19",
            "sbc r24, r20",
            "sbc r25, r21",
            "brvc 1f",
            // `ldi` keeps the flags: 0x80000000 − C.
            "ldi r22, 0x00",
            "ldi r23, 0x00",
            "ldi r24, 0x00",
            "ldi r25, 0x80",
            "sbc r22, r1",
            "sbc r23, r1",
            "sbc r24, r1",
            "sbc r25, r1",
            "1:",
            inout("r23r22") low,
            inout("r25r24") high,
            in("r19r18") b_low,
            in("r21r20") b_high,
            options(pure, nomem, nostack),
        );
    }
    join(low, high) as i32
}

/// |x|, exact (|i32::MIN| is 2^31).
///
/// On the AVR, in place: when x is negative, its complement plus one (the carry set,
/// then added through the zero register).
#[cfg(target_arch = "avr")]
#[inline(always)]
pub fn magnitude(x: i32) -> u32 {
    let (mut low, mut high) = halves(x as u32);
    // SAFETY: register arithmetic only (no memory, no stack) on the operand's registers;
    // r1 (the zero register) is only read; SREG is not preserved.
    unsafe {
        core::arch::asm!(
            "sbrs {high:h}, 7",
            "rjmp 1f",
            "com {high:h}",
            "com {high:l}",
            "com {low:h}",
            "com {low:l}",
            "sec",
            "adc {low:l}, r1",
            "adc {low:h}, r1",
            "adc {high:l}, r1",
            "adc {high:h}, r1",
            "1:",
            low = inout(reg_pair) low,
            high = inout(reg_pair) high,
            options(pure, nomem, nostack),
        );
    }
    join(low, high)
}

/// `x`, or 0 when |x| < `zone` (unsigned).
///
/// On the AVR, in line: |x| in a scratch pair of pairs (the magnitude's complement plus
/// one), one unsigned compare, and the clear.
#[cfg(target_arch = "avr")]
#[inline(always)]
pub fn dead_zone(x: i32, zone: u32) -> i32 {
    let (mut low, mut high) = halves(x as u32);
    let (zone_low, zone_high) = halves(zone);
    // SAFETY: register arithmetic only (no memory, no stack) on the operands' and the
    // two scratch pairs' registers; r1 (the zero register) is only read; SREG is not
    // preserved.
    unsafe {
        core::arch::asm!(
            "movw {tl:l}, {low:l}",
            "movw {th:l}, {high:l}",
            "sbrs {th:h}, 7",
            "rjmp 1f",
            "com {th:h}",
            "com {th:l}",
            "com {tl:h}",
            "com {tl:l}",
            "sec",
            "adc {tl:l}, r1",
            "adc {tl:h}, r1",
            "adc {th:l}, r1",
            "adc {th:h}, r1",
            "1: cp {tl:l}, {zl:l}",
            "cpc {tl:h}, {zl:h}",
            "cpc {th:l}, {zh:l}",
            "cpc {th:h}, {zh:h}",
            "brsh 2f",
            "clr {low:l}",
            "clr {low:h}",
            "movw {high:l}, {low:l}",
            "2:",
            low = inout(reg_pair) low,
            high = inout(reg_pair) high,
            zl = in(reg_pair) zone_low,
            zh = in(reg_pair) zone_high,
            tl = out(reg_pair) _,
            th = out(reg_pair) _,
            options(pure, nomem, nostack),
        );
    }
    join(low, high) as i32
}

/// `x`, or 0 when |x| < `zone` (unsigned).
#[cfg(not(target_arch = "avr"))]
#[inline(always)]
pub fn dead_zone(x: i32, zone: u32) -> i32 {
    if x.unsigned_abs() < zone {
        0
    } else {
        x
    }
}

/// `x` clamped to ±`cap`, for cap ≥ 0.
///
/// On the AVR, in line: x > cap (signed) takes cap; otherwise x + cap below 0 (its sign
/// as N ⊕ V, right even when the sum overflows) takes 0 − cap.
#[cfg(target_arch = "avr")]
#[inline(always)]
pub fn clamp(x: i32, cap: i32) -> i32 {
    let (mut low, mut high) = halves(x as u32);
    let (cap_low, cap_high) = halves(cap as u32);
    // SAFETY: register arithmetic only (no memory, no stack) on the operands' and the
    // two scratch pairs' registers; r1 (the zero register) is only read; SREG is not
    // preserved.
    unsafe {
        core::arch::asm!(
            "cp {cl:l}, {low:l}",
            "cpc {cl:h}, {low:h}",
            "cpc {ch:l}, {high:l}",
            "cpc {ch:h}, {high:h}",
            "brge 1f",
            "movw {low:l}, {cl:l}",
            "movw {high:l}, {ch:l}",
            "rjmp 2f",
            "1: movw {tl:l}, {low:l}",
            "movw {th:l}, {high:l}",
            "add {tl:l}, {cl:l}",
            "adc {tl:h}, {cl:h}",
            "adc {th:l}, {ch:l}",
            "adc {th:h}, {ch:h}",
            "brge 2f",
            "clr {low:l}",
            "clr {low:h}",
            "movw {high:l}, {low:l}",
            "sub {low:l}, {cl:l}",
            "sbc {low:h}, {cl:h}",
            "sbc {high:l}, {ch:l}",
            "sbc {high:h}, {ch:h}",
            "2:",
            low = inout(reg_pair) low,
            high = inout(reg_pair) high,
            cl = in(reg_pair) cap_low,
            ch = in(reg_pair) cap_high,
            tl = out(reg_pair) _,
            th = out(reg_pair) _,
            options(pure, nomem, nostack),
        );
    }
    join(low, high) as i32
}

/// `x` clamped to ±`cap`, for cap ≥ 0.
#[cfg(not(target_arch = "avr"))]
#[inline(always)]
pub fn clamp(x: i32, cap: i32) -> i32 {
    x.clamp(-cap, cap)
}

/// |x|, exact (|i32::MIN| is 2^31).
#[cfg(not(target_arch = "avr"))]
#[inline(always)]
pub fn magnitude(x: i32) -> u32 {
    x.unsigned_abs()
}

/// `a + b`, saturating at `i32::MIN`/`i32::MAX`.
#[cfg(not(target_arch = "avr"))]
pub fn add(a: i32, b: i32) -> i32 {
    a.saturating_add(b)
}

/// `a − b`, saturating at `i32::MIN`/`i32::MAX`.
#[cfg(not(target_arch = "avr"))]
pub fn sub(a: i32, b: i32) -> i32 {
    a.saturating_sub(b)
}
