//! Potentiometer readings to angles (reference §7.3).

use super::product::wide;
use crate::pid::{Fix, Saturating};

/// The highest reading of the 10-bit ADC.
pub const ADC_MAX: u16 = 1023;

/// A position motor's calibration: the angles at pot readings 0 and 1024.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct Calibration {
    min: Fix,
    span: Fix,
}

impl Calibration {
    /// The power-on calibration, −512..512 (the registers read 0x00 / 0xfe, clamped).
    pub const POWER_ON: Calibration = Calibration {
        min: Fix::from_bits(-512 << 16),
        span: Fix::from_bits(1024 << 16),
    };

    /// A calibration from the angles at readings 0 and 1024.
    pub fn new(min: Fix, max: Fix) -> Calibration {
        Calibration {
            min,
            span: max.sub_sat(min),
        }
    }

    /// The angle at reading 0 (CALIBMIN).
    pub fn min(&self) -> Fix {
        self.min
    }

    /// The angle at reading 1024 (CALIBMAX).
    pub fn max(&self) -> Fix {
        self.min.add_sat(self.span)
    }

    /// Replaces CALIBMIN, keeping CALIBMAX.
    pub fn set_min(&mut self, min: Fix) {
        *self = Calibration::new(min, self.max());
    }

    /// Replaces CALIBMAX, keeping CALIBMIN.
    pub fn set_max(&mut self, max: Fix) {
        *self = Calibration::new(self.min, max);
    }

    /// The angle of a reading: p·(max − min)/1024 + min, with p clamped to 0..1023.
    ///
    /// (span/64)·p/16 in 16.16 bits, the product from two 16×16-bit products (see
    /// [`wide`]). Dropping the span's 6 lowest bits costs less than 0.001°.
    pub fn angle(&self, reading: u16) -> Fix {
        let p = reading.min(ADC_MAX);
        // |span| ≤ 2^26 bits (±1024°), so |span/64| ≤ 2^20 and |span/64·p| < 2^30.
        let span = self.span.to_bits().clamp(-(1 << 26), 1 << 26) >> 6;
        let magnitude = span.unsigned_abs();
        let (high, low) = ((magnitude >> 16) as u16, magnitude as u16);
        let product = ((wide(high, p) << 16) + wide(low, p)) as i32;
        let product = if span < 0 { -product } else { product };
        // The one out-of-line saturating add: a new reading (a moving motor) already
        // costs a call to the conversion, and this adds a few cycles to it (measured: 1
        // a tick on a lift/lift board with both lifts moving) for 60 B less flash.
        Fix::from_bits(product >> 4).add_sat(self.min)
    }
}
