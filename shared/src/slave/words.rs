//! A 32-bit value as the two 16-bit register pairs the slave's assembly works on
//! ([`super::product`], [`super::divide`], [`crate::pid::sum`]), and back.

/// `x`'s low and high 16 bits.
#[inline(always)]
pub const fn halves(x: u32) -> (u16, u16) {
    (x as u16, (x >> 16) as u16)
}

/// The value whose low and high 16 bits are `low` and `high`.
#[inline(always)]
pub const fn join(low: u16, high: u16) -> u32 {
    (high as u32) << 16 | low as u32
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn halves_and_join_are_inverse() {
        for x in [0, 1, 0xffff, 0x1_0000, 0x1234_5678, 0x8000_0000, u32::MAX] {
            let (low, high) = halves(x);
            assert_eq!(u32::from(low) | u32::from(high) << 16, x);
            assert_eq!(join(low, high), x);
        }
        assert_eq!(halves(0x1234_5678), (0x5678, 0x1234));
    }
}
