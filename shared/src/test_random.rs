//! A fixed pseudo-random sequence for host tests that replay long random runs: the same
//! numbers on every run, so a failure repeats.

/// A 64-bit xorshift generator (shifts 13, 7, 17).
pub(crate) struct Xorshift(pub(crate) u64);

impl Xorshift {
    /// The next number below `bound` (`bound` > 0), from the high 32 bits of the state.
    pub(crate) fn below(&mut self, bound: u32) -> u32 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 32) as u32 % bound
    }
}
