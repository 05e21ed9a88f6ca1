//! One small `u32` division for every quotient the slave computes.
//!
//! The AVR has no divide instruction; `/` and `%` on `u32` pull in a general routine of
//! more than 1 KB of flash. The slave divides rarely (a register write, a drive update,
//! the first tick, a late tick), so a 32-step shift-and-subtract loop of a few dozen
//! bytes serves them all, with the same result as `/` and `%`.

/// `(n / d, n % d)`; `(u32::MAX, n)` when `d` is 0 (no panic on any input).
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

/// `⌊(rem · 2^bits) / d⌋` for `rem < d`: the next `bits` (≤ 32) binary digits of a
/// quotient whose integer part [`div_rem`] gave. 0 when `d` is 0.
pub fn fraction(mut rem: u32, d: u32, bits: u8) -> u32 {
    if d == 0 {
        return 0;
    }
    let mut digits = 0u32;
    for _ in 0..bits.min(32) {
        let carry = (rem as i32) < 0;
        rem <<= 1;
        digits <<= 1;
        if carry || rem >= d {
            rem = rem.wrapping_sub(d);
            digits |= 1;
        }
    }
    digits
}

/// `⌊us / 1000⌋`. Below 2^19 µs (every update interval but a stalled one) without a
/// division: ⌊(us/8)/125⌋ by a reciprocal multiply, some 40 cycles on the AVR.
pub fn div_1000(us: u32) -> u32 {
    if us >= 1 << 19 {
        return div_rem(us, 1000).0;
    }
    // y < 2^16. ⌊y/125⌋ = ⌊y·67109/2^23⌋ for every such y (tested exhaustively); with
    // 67109 = 2^16 + 1573 the product is split so nothing exceeds 32 bits.
    let y = us >> 3;
    (y + ((y * 1573) >> 16)) >> 7
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

    #[test]
    fn div_1000_is_exact() {
        for us in 0..1u32 << 20 {
            assert_eq!(div_1000(us), us / 1000, "{us}");
        }
        for us in [u32::MAX, 0x8000_0000, 4_294_967_000, 123_456_789] {
            assert_eq!(div_1000(us), us / 1000, "{us}");
        }
    }

    #[test]
    fn fraction_continues_the_division() {
        // 1/3 in 8 bits: 0.01010101b = 85.
        assert_eq!(fraction(1, 3, 8), 85);
        // 7/8 = 0.111b: 224 in 8 bits.
        assert_eq!(fraction(7, 8, 8), 224);
        for (rem, d) in [
            (0u32, 5u32),
            (999, 1000),
            (123_456, 1 << 23),
            (0x8000_0000, u32::MAX),
        ] {
            let exact = ((u64::from(rem) << 8) / u64::from(d)) as u32;
            assert_eq!(fraction(rem, d, 8), exact, "{rem} / {d}");
        }
        assert_eq!(fraction(3, 0, 8), 0);
    }
}
