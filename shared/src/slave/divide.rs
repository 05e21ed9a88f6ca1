//! One small `u32` division for every quotient the slave computes.
//!
//! The AVR has no divide instruction; `/` and `%` on `u32` pull in a general routine of
//! more than 1 KB of flash. The slave divides rarely (a register write, a drive update,
//! the first tick, a late tick), so a 32-step shift-and-subtract loop of a few dozen
//! bytes serves them all, with the same result as `/` and `%`.
//!
//! On the AVR that loop is the image's runtime division loop (`drivers_udivmod32` from
//! `drivers::runtime`, some 20 cycles a step; LLVM's code for the same loop takes some 75),
//! called from an inline `asm!` block with everything in registers: as a Rust function
//! returning the pair it made each caller keep a stack frame to receive it (194 / 168 B
//! more in the two slave images). The crate denies `unsafe`; this module allows it for
//! that block, as `progmem` does for its flash reads.
#![allow(unsafe_code)]

#[cfg(target_arch = "avr")]
use super::words::{halves, join};

/// `(n / d, n % d)`; `(u32::MAX, n)` when `d` is 0 (no panic on any input).
///
/// On the AVR a call of the image's runtime division loop, `drivers_udivmod32`
/// (`drivers::runtime`, which every slave image and the fixture that checks this expand),
/// in line: a few moves into its registers. The loop sets every quotient bit for d = 0,
/// which gives `(u32::MAX, n)` with no test.
#[cfg(target_arch = "avr")]
#[inline(always)]
pub fn div_rem(n: u32, d: u32) -> (u32, u32) {
    let (mut n_lo, mut n_hi) = halves(n);
    let (d_lo, d_hi) = halves(d);
    let (r_lo, r_hi): (u16, u16);
    // SAFETY: the loop takes n in r25..r22 and d in r21..r18 and returns the quotient in
    // r25..r22 and the remainder in X and Z; it changes only those and SREG, and of memory
    // only the stack, for its return address; r1 (the zero register) is its counter and
    // zero again on return.
    unsafe {
        core::arch::asm!(
            "call drivers_udivmod32",
            inout("r23r22") n_lo,
            inout("r25r24") n_hi,
            in("r19r18") d_lo,
            in("r21r20") d_hi,
            out("X") r_lo,
            out("Z") r_hi,
            options(pure, nomem),
        );
    }
    (join(n_lo, n_hi), join(r_lo, r_hi))
}

/// `(n / d, n % d)`; `(u32::MAX, n)` when `d` is 0 (no panic on any input).
#[cfg(not(target_arch = "avr"))]
#[inline(never)]
pub fn div_rem(n: u32, d: u32) -> (u32, u32) {
    if d == 0 {
        return (u32::MAX, n);
    }
    let (mut quotient, mut rem) = (n, 0u32);
    for _ in 0..32 {
        // Shift the next bit of n into the remainder; the quotient's bits fill in
        // behind it. `carry` keeps a bit shifted out of the remainder (only when d > 2^31).
        // Top bits are read as signs: a shift by 31 is a loop of 31 steps on the AVR.
        let carry = (rem as i32) < 0;
        rem = rem << 1 | u32::from((quotient as i32) < 0);
        quotient <<= 1;
        if carry || rem >= d {
            rem = rem.wrapping_sub(d);
            quotient |= 1;
        }
    }
    (quotient, rem)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matches_the_operators() {
        let values = [
            0u32,
            1,
            2,
            3,
            7,
            254,
            255,
            999,
            1000,
            1001,
            65_534,
            65_535,
            65_536,
            1_000_000,
            0x7fff_ffff,
            0x8000_0000,
            0x8000_0001,
            0xffff_fffe,
            u32::MAX,
        ];
        for n in values {
            for d in values.iter().copied().filter(|&d| d != 0) {
                assert_eq!(div_rem(n, d), (n / d, n % d), "{n} / {d}");
            }
        }
        assert_eq!(div_rem(5, 0), (u32::MAX, 5));
    }
}
