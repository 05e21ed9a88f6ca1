//! Current sense: motor current to ADC millivolts, with injectable spikes.
//!
//! The slave reads each motor's current on ADC0/ADC1. The sense gives
//! [`SENSE_MV_PER_A`] (488.3 mV/A, i.e. 100 counts per ampere on a 5 V reference, the
//! firmware comment's "150 counts ≈ 1.5 A") of the current's **magnitude**, the mean over
//! a PWM period, clamped to 0..=reference. The bridge's sense resistor sees current only
//! one way, so the direction of the motor is not visible here.
//!
//! **Fault injection.** [`CurrentSense::inject_spike`] adds a current for a while (a
//! shorted winding, a jammed gear); [`CurrentSense::set_offset_a`] adds one for good.

use crate::constants::{ADC_REF_MV, SENSE_MV_PER_A};

/// An injected extra current.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Spike {
    amps: f64,
    left_s: f64,
}

/// One motor's current-sense channel.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct CurrentSense {
    spike: Option<Spike>,
    offset_a: f64,
}

impl CurrentSense {
    /// A sense channel with nothing injected.
    pub fn new() -> CurrentSense {
        CurrentSense::default()
    }

    /// Adds `amps` to the reading for the next `duration_s` seconds of [`CurrentSense::advance`],
    /// replacing any spike still running.
    pub fn inject_spike(&mut self, amps: f64, duration_s: f64) {
        self.spike = (amps.is_finite() && duration_s > 0.0).then_some(Spike {
            amps,
            left_s: duration_s,
        });
    }

    /// Adds `amps` to every reading until changed (0 removes it).
    pub fn set_offset_a(&mut self, amps: f64) {
        self.offset_a = if amps.is_finite() { amps } else { 0.0 };
    }

    /// Extra current injected now (A).
    pub fn injected_a(&self) -> f64 {
        self.offset_a + self.spike.map_or(0.0, |s| s.amps)
    }

    /// The spike running now, as (amperes, seconds left); None when there is none.
    pub fn spike(&self) -> Option<(f64, f64)> {
        self.spike.map(|s| (s.amps, s.left_s))
    }

    /// Lets `dt_s` seconds pass: a spike ends when its time is up.
    pub fn advance(&mut self, dt_s: f64) {
        if let Some(spike) = &mut self.spike {
            spike.left_s -= dt_s.max(0.0);
            if spike.left_s <= 0.0 {
                self.spike = None;
            }
        }
    }

    /// Sense output (mV) for a motor current of `current_a` amperes (either sign).
    pub fn mv(&self, current_a: f64) -> f64 {
        ((current_a.abs() + self.injected_a()) * SENSE_MV_PER_A).clamp(0.0, ADC_REF_MV)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pot::adc_reading;

    #[test]
    fn one_and_a_half_amps_read_150_counts() {
        let s = CurrentSense::new();
        assert_eq!(adc_reading(s.mv(1.5)), 150);
        assert_eq!(adc_reading(s.mv(-3.0)), 300);
        assert_eq!(adc_reading(s.mv(0.0)), 0);
        assert_eq!(s.mv(20.0), ADC_REF_MV, "clamped at the reference");
    }

    #[test]
    fn a_spike_lasts_its_duration() {
        let mut s = CurrentSense::new();
        assert_eq!(s.spike(), None);
        s.inject_spike(4.0, 0.010);
        assert_eq!(adc_reading(s.mv(0.5)), 450);
        s.advance(0.006);
        assert_eq!(adc_reading(s.mv(0.5)), 450);
        let (amps, left_s) = s.spike().expect("still running");
        assert_eq!(amps, 4.0);
        assert!((left_s - 0.004).abs() < 1e-12, "{left_s} s left");
        s.advance(0.006);
        assert_eq!(adc_reading(s.mv(0.5)), 50);
        assert_eq!(s.spike(), None, "over");
    }

    #[test]
    fn an_offset_stays_until_cleared() {
        let mut s = CurrentSense::new();
        s.set_offset_a(2.0);
        s.advance(100.0);
        assert_eq!(adc_reading(s.mv(1.0)), 300);
        s.set_offset_a(0.0);
        assert_eq!(adc_reading(s.mv(1.0)), 100);
    }
}
