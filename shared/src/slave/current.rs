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
    pub fn push(&mut self, sample: u16) {
        self.feed(sample as u8);
    }

    /// Feeds one raw ADC sample without the wrap: samples above 255 count as 255. The
    /// fault detector uses this one, so that a stalled motor drawing 256 counts is not
    /// taken for a motor drawing none.
    pub fn push_saturating(&mut self, sample: u16) {
        self.feed(sample.min(255) as u8);
    }

    /// The filtered current, 0..255 (what CURRENT shows).
    pub fn reading(&self) -> u8 {
        (self.f >> 8) as u8
    }

    /// One step with c = the sample mod 256, so q = 256·c.
    ///
    /// In 16-bit arithmetic only: ⌊(256 − p)·f/256⌋ = f − ⌈p·f/256⌉, and with f = 256·h + l,
    /// ⌈p·f/256⌉ = p·h + ⌈p·l/256⌉; ⌊q·p/256⌋ = p·c exactly. Every product is at most
    /// 25·255, and the result at most max(f, q).
    fn feed(&mut self, c: u8) {
        let f = self.f;
        let q = u16::from(c) << 8;
        // p once per step; each product is one 8×8-bit hardware multiply on the AVR.
        let p: u8 = if q > f { 25 } else { 2 };
        let times_p = |x: u8| -> u16 { u16::from(x) * u16::from(p) };
        let [low, high] = f.to_le_bytes();
        let fall = times_p(high) + ((times_p(low) + 255) >> 8);
        self.f = f.wrapping_sub(fall).wrapping_add(times_p(c));
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
