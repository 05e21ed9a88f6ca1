//! Motor current: the filtered value the CURRENT registers show (reference §7.4) and the
//! overcurrent rule.

use super::state::LocalFault;

/// The original's current filter: 8.8 fixed point in 16 bits, bit for bit.
///
/// Each sample c becomes q = 256·c mod 65536, so only c mod 256 survives (a wrap quirk
/// the CURRENT registers keep: a steady 300 reads 43). With p = 25 if q > f, else 2
/// (0.1 and 0.01 as ⌊R·256.5⌋): f := ⌊(256 − p)·f/256⌋ + ⌊q·p/256⌋; the reading is
/// ⌊f/256⌋.
#[derive(Clone, Copy, PartialEq, Eq, Debug, Default)]
pub struct CurrentFilter {
    f: u16,
}

impl CurrentFilter {
    /// A filter at zero.
    pub const fn new() -> CurrentFilter {
        CurrentFilter { f: 0 }
    }

    /// Feeds one raw ADC sample, with the original's wrap.
    #[inline(always)]
    pub fn push(&mut self, sample: u16) {
        self.feed(sample as u8);
    }

    /// Feeds one raw ADC sample without the wrap: samples above 255 count as 255. The
    /// fault detector uses this one, so that a stalled motor drawing 256 counts is not
    /// taken for a motor drawing none.
    pub fn push_saturating(&mut self, sample: u16) {
        self.feed_outlined(sample.min(255) as u8);
    }

    /// [`CurrentFilter::push`], with the step not inlined: for the rare paths.
    pub fn push_outlined(&mut self, sample: u16) {
        self.feed_outlined(sample as u8);
    }

    #[inline(never)]
    fn feed_outlined(&mut self, c: u8) {
        self.feed(c);
    }

    /// The filtered current, 0..255 (what CURRENT shows).
    pub fn reading(&self) -> u8 {
        (self.f >> 8) as u8
    }

    /// The raw 8.8 filter value, for the emulator check of the AVR step.
    #[doc(hidden)]
    pub fn raw(&self) -> u16 {
        self.f
    }

    /// A filter holding the raw 8.8 value `f`, for the emulator check of the AVR step.
    #[doc(hidden)]
    pub const fn from_raw(f: u16) -> CurrentFilter {
        CurrentFilter { f }
    }

    /// One step with c = the sample mod 256, so q = 256·c.
    ///
    /// In 8-bit products only. With f = 256·h + l: q > f exactly when c > h;
    /// ⌊(256 − p)·f/256⌋ = f − p·h − ⌈p·l/256⌉; ⌊q·p/256⌋ = p·c exactly. So
    /// f' = f ± p·|c − h| − ⌈p·l/256⌉, where each product is one 8×8-bit hardware
    /// multiply on the AVR, and the result is at most max(f, q), so no step wraps.
    ///
    /// On the AVR, 20 instructions of assembly (LLVM made some 110 B of each copy);
    /// elsewhere the same arithmetic in Rust, checked against the formula on every
    /// input. The emulator test `slave_maths` checks the assembly against the formula
    /// on every input too.
    #[cfg(target_arch = "avr")]
    #[inline(always)]
    fn feed(&mut self, c: u8) {
        let mut f = self.f;
        // SAFETY: register arithmetic only (no memory, no stack). `mul` leaves its
        // product in r1:r0: r0 is the scratch register, and r1, the zero register, is
        // cleared again before the block ends, as the AVR ABI requires.
        #[allow(unsafe_code)]
        unsafe {
            core::arch::asm!(
                // p = 25 when c > h (rising), else 2.
                "ldi {p}, 25",
                "cp {f:h}, {c}",
                "brlo 1f",
                "ldi {p}, 2",
                "1:",
                "mov {d}, {c}",
                "sub {d}, {f:h}",
                // l −= ⌈p·l/256⌉: the product's high byte, and the carry of its low
                // one (`neg` sets it for a byte not 0). Never below 0, as p < 256: h
                // stays.
                "mul {f:l}, {p}",
                "neg r0",
                "sbc {f:l}, r1",
                // f ± p·|c − h|.
                "cpi {p}, 25",
                "breq 2f",
                "neg {d}",
                "mul {d}, {p}",
                "sub {f:l}, r0",
                "sbc {f:h}, r1",
                "rjmp 3f",
                "2:",
                "mul {d}, {p}",
                "add {f:l}, r0",
                "adc {f:h}, r1",
                "3:",
                "clr r1",
                f = inout(reg_pair) f,
                c = in(reg) c,
                p = out(reg_upper) _,
                d = out(reg) _,
                options(pure, nomem, nostack),
            );
        }
        self.f = f;
    }

    /// [`CurrentFilter::feed`] off the AVR: the same arithmetic in Rust.
    #[cfg(not(target_arch = "avr"))]
    #[inline(always)]
    fn feed(&mut self, c: u8) {
        let [low, high] = self.f.to_le_bytes();
        let byte = |x: u8, y: u8| u16::from(x) * u16::from(y);
        // ⌈x/256⌉ of a product x < 2^16: its high byte, plus one if its low byte is not 0.
        let ceil_256 = |x: u16| {
            let [lo, hi] = x.to_le_bytes();
            u16::from(hi) + u16::from(lo != 0)
        };
        self.f = if c > high {
            // Rising: p = 25 (0.1).
            let fall = ceil_256(byte(25, low));
            self.f.wrapping_add(byte(25, c - high)).wrapping_sub(fall)
        } else {
            // Falling or steady: p = 2 (0.01).
            let fall = ceil_256(byte(2, low));
            self.f.wrapping_sub(byte(2, high - c)).wrapping_sub(fall)
        };
    }
}

/// The overcurrent rule (reference §7.4), for one raw sample: above the threshold, a
/// motor at duty > 250 has an OVERCURRENT, one at a lower duty a short (SHORTOC).
pub fn overcurrent(sample: u16, threshold: u16, duty: u8) -> Option<LocalFault> {
    if sample <= threshold {
        None
    } else if duty > 250 {
        Some(LocalFault::Overcurrent)
    } else {
        Some(LocalFault::ShortOc)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The reference formula, in wide arithmetic.
    fn reference(f: u16, c: u8) -> u16 {
        let (f, q) = (u32::from(f), u32::from(c) << 8);
        let p = if q > f { 25 } else { 2 };
        ((256 - p) * f / 256 + q * p / 256) as u16
    }

    #[test]
    fn every_step_equals_the_reference_formula() {
        for f in 0..=u16::MAX {
            for c in 0..=u8::MAX {
                let mut filter = CurrentFilter { f };
                filter.feed(c);
                assert_eq!(filter.f, reference(f, c), "f = {f}, c = {c}");
            }
        }
    }
}
