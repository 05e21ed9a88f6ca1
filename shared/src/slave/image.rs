//! A value's power-up bytes as a short list of its nonzero bytes.
//!
//! The firmware keeps the core's state in zeroed memory (`.bss`: no flash) and gives it
//! its power-up value once at boot by writing the few bytes that are not zero: the core
//! is some 290 B of which some 50 are not zero at power-up, and initial data (`.data`)
//! would cost all of them in flash. [`Image`] lays those bytes out at compile time, at
//! the target's own field offsets (`offset_of!`), and [`Image::pairs`] turns them into
//! (step, byte) pairs: the write pointer moves on by `step` bytes, then stores `byte`.
//! [`apply`] is that loop; the firmware runs `apply_from_flash`, the same in seven
//! instructions a pair over a table in flash.

/// `N` bytes being laid out at compile time, all zero to begin with.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct Image<const N: usize> {
    bytes: [u8; N],
}

#[cfg(target_arch = "avr")]
use crate::progmem::Flash;

/// The longest step one pair takes: a longer gap between two nonzero bytes takes a pair
/// that stores a zero on the way (harmless: the memory is zero).
const MAX_STEP: usize = u8::MAX as usize;

impl<const N: usize> Image<N> {
    /// Every byte zero.
    pub const ZERO: Image<N> = Image { bytes: [0; N] };

    /// The bytes laid out so far.
    pub const fn bytes(&self) -> &[u8; N] {
        &self.bytes
    }

    /// `value` at offset `at`.
    pub const fn byte(mut self, at: usize, value: u8) -> Image<N> {
        self.bytes[at] = value;
        self
    }

    /// `value` at offset `at`, low byte first (the AVR's order, and the host's).
    pub const fn bytes_at(mut self, at: usize, value: &[u8]) -> Image<N> {
        let mut i = 0;
        while i < value.len() {
            self.bytes[at + i] = value[i];
            i += 1;
        }
        self
    }

    /// A `u16` at offset `at`, low byte first.
    pub const fn u16(self, at: usize, value: u16) -> Image<N> {
        self.bytes_at(at, &value.to_le_bytes())
    }

    /// An `i32` at offset `at`, low byte first.
    pub const fn i32(self, at: usize, value: i32) -> Image<N> {
        self.bytes_at(at, &value.to_le_bytes())
    }

    /// A `bool` at offset `at`.
    pub const fn bool(self, at: usize, value: bool) -> Image<N> {
        self.byte(at, value as u8)
    }

    /// How many pairs [`Image::pairs`] gives: one per nonzero byte, and one more for
    /// each gap longer than a step.
    pub const fn len(&self) -> usize {
        self.walk(None)
    }

    /// Whether every byte is zero (no pairs).
    pub const fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The (step, byte) pairs that make zeroed memory these bytes: from the first byte,
    /// the pointer moves on by `step`, then stores `byte`. `K` must be [`Image::len`].
    pub const fn pairs<const K: usize>(&self) -> [[u8; 2]; K] {
        let mut pairs = [[0; 2]; K];
        self.fill(&mut pairs);
        pairs
    }

    /// [`Image::pairs`] into `out`, whose length must be [`Image::len`].
    pub const fn fill(&self, out: &mut [[u8; 2]]) {
        assert!(
            out.len() == self.len(),
            "the pairs' length must be the image's len()"
        );
        self.walk(Some(out));
    }

    /// The one walk behind [`Image::len`] and [`Image::fill`]: counts the pairs, and
    /// writes them to `out` when there is one.
    const fn walk(&self, mut out: Option<&mut [[u8; 2]]>) -> usize {
        let mut k = 0;
        // The pointer starts on byte 0: a nonzero byte 0 takes a step of 0.
        let mut gap = 0;
        let mut i = 0;
        while i < N {
            if gap > MAX_STEP {
                if let Some(out) = &mut out {
                    out[k] = [MAX_STEP as u8, 0];
                }
                k += 1;
                gap -= MAX_STEP;
            }
            if self.bytes[i] != 0 {
                if let Some(out) = &mut out {
                    out[k] = [gap as u8, self.bytes[i]];
                }
                k += 1;
                gap = 0;
            }
            gap += 1;
            i += 1;
        }
        k
    }
}

/// Writes `pairs` ([`Image::pairs`]) into `memory`, as the firmware does at boot.
///
/// # Panics
/// When a step leaves `memory`: the pairs were made for a larger value.
pub fn apply(pairs: &[[u8; 2]], memory: &mut [u8]) {
    let mut at = 0;
    for &[step, byte] in pairs {
        at += usize::from(step);
        memory[at] = byte;
    }
}

/// [`apply`] of `pairs` kept in flash ([`crate::flash_table!`]), from `memory`: seven
/// instructions a pair (two `LPM`, an add with carry to the pointer, a store, a count
/// down). On the AVR only: [`apply`] is the same walk on the host, and
/// `fixture_slave_maths` checks this one against it on the chip.
///
/// # Safety
/// `pairs` has 1..=256 pairs, and `memory` is the start of memory that nothing else
/// accesses while this runs, where every step stays ([`Image::pairs`] of an image of
/// it); the bytes written must make it what its users take it for.
#[cfg(target_arch = "avr")]
#[allow(unsafe_code)]
#[inline(always)]
pub unsafe fn apply_from_flash(pairs: &'static Flash<[[u8; 2]]>, memory: *mut u8) {
    // SAFETY: LPM reads only flash, at Z (the table, per `flash_table!`); each store is
    // inside `memory`, per the contract; the count, 1..=256 pairs (256 as 0), ends the
    // loop. X, Z and the count's register are declared clobbered; r1 stays zero.
    unsafe {
        core::arch::asm!(
            "1:",
            "lpm {byte}, Z+",
            "add r26, {byte}",
            "adc r27, r1",
            "lpm {byte}, Z+",
            "st X, {byte}",
            "dec {count}",
            "brne 1b",
            byte = out(reg) _,
            count = inout(reg) pairs.len() as u8 => _,
            inout("Z") (pairs as *const Flash<[[u8; 2]]>).cast::<u8>() => _,
            inout("X") memory => _,
            options(nostack),
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_random::Xorshift;

    /// An image of `bytes` through the builder, its pairs applied to zeros.
    fn round_trip<const N: usize, const K: usize>(bytes: [u8; N]) -> [u8; N] {
        let image = Image::<N>::ZERO.bytes_at(0, &bytes);
        assert_eq!(image.bytes(), &bytes);
        let pairs = image.pairs::<K>();
        let mut memory = [0; N];
        apply(&pairs, &mut memory);
        memory
    }

    #[test]
    fn pairs_are_steps_from_byte_0_and_the_bytes() {
        let image = Image::<8>::ZERO.byte(0, 7).u16(3, 0x0201).byte(7, 0xff);
        assert_eq!(image.bytes(), &[7, 0, 0, 1, 2, 0, 0, 0xff]);
        assert_eq!(image.len(), 4);
        assert_eq!(image.pairs::<4>(), [[0, 7], [3, 1], [1, 2], [3, 0xff]]);
        let zero = Image::<5>::ZERO;
        assert!(zero.is_empty());
        assert_eq!(zero.pairs::<0>(), [] as [[u8; 2]; 0]);
    }

    #[test]
    fn the_writers_lay_values_out_low_byte_first() {
        let image = Image::<8>::ZERO
            .i32(0, -512 << 16)
            .bool(4, true)
            .u16(5, 0x7fff);
        assert_eq!(image.bytes(), &[0, 0, 0, 0xfe, 1, 0xff, 0x7f, 0]);
    }

    #[test]
    fn a_gap_longer_than_a_step_stores_a_zero_on_the_way() {
        let mut bytes = [0u8; 600];
        bytes[0] = 1;
        bytes[256] = 2; // a step of exactly 256
        bytes[599] = 3; // 343: one filler
        let image = Image::<600>::ZERO.bytes_at(0, &bytes);
        assert_eq!(image.len(), 5);
        assert_eq!(
            image.pairs::<5>(),
            [[0, 1], [255, 0], [1, 2], [255, 0], [88, 3]]
        );
        assert_eq!(round_trip::<600, 5>(bytes), bytes);
        let mut far = [0u8; 600];
        far[599] = 9; // two fillers before the only byte
        let image = Image::<600>::ZERO.bytes_at(0, &far);
        assert_eq!(image.pairs::<3>(), [[255, 0], [255, 0], [89, 9]]);
        assert_eq!(round_trip::<600, 3>(far), far);
    }

    #[test]
    fn pairs_applied_to_zeros_give_the_image_back() {
        let mut rng = Xorshift(0x5eed_0011);
        for round in 0..2_000 {
            let mut bytes = [0u8; 700];
            // From nearly empty (long gaps, fillers) to nearly full.
            let density = round % 40;
            for b in bytes.iter_mut() {
                if rng.below(40) < density {
                    *b = rng.below(255) as u8 + 1;
                }
            }
            let image = Image::<700>::ZERO.bytes_at(0, &bytes);
            let nonzero = bytes.iter().filter(|&&b| b != 0).count();
            let mut pairs = vec![[0u8; 2]; image.len()];
            image.fill(&mut pairs);
            // One pair per nonzero byte, plus zero-storing fillers for long gaps only.
            let fillers: Vec<_> = pairs.iter().filter(|p| p[1] == 0).collect();
            assert_eq!(pairs.len(), nonzero + fillers.len(), "round {round}");
            assert!(fillers.iter().all(|p| p[0] == 255), "round {round}");
            let mut memory = [0u8; 700];
            apply(&pairs, &mut memory);
            assert_eq!(memory, bytes, "round {round}");
        }
    }
}
