//! Potentiometer readings to angles (reference §7.3).

use super::image::Image;
use crate::pid::{mul, Fix, Saturating};
use core::mem::offset_of;

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

    /// Its bytes into `image` at `at` (see [`super::image`]).
    pub(crate) const fn put<const N: usize>(&self, image: Image<N>, at: usize) -> Image<N> {
        image
            .i32(at + offset_of!(Calibration, min), self.min.to_bits())
            .i32(at + offset_of!(Calibration, span), self.span.to_bits())
    }

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
    /// The saturating product ([`mul`]) of the span and p/1024 (exact in 16.16 bits:
    /// p·64), truncated toward zero, then the saturating sum with min. The product's
    /// magnitude is below the span's, so it never saturates. One call to the product
    /// the controller already uses: within 2^−10° (64 bits) of the form it replaced
    /// (the span's bits shifted down by 6, times p by two 16×16-bit products, shifted
    /// down by 4; tested over every pair of calibration registers), for some 220 B less
    /// flash and no more cycles a moving tick.
    pub fn angle(&self, reading: u16) -> Fix {
        let p = reading.min(ADC_MAX);
        let fraction = Fix::from_bits(i32::from(p) << 6);
        mul(self.span, fraction).add_sat(self.min)
    }
}
