//! Potentiometers: the angle sensors of the steer and lift axes, and the chassis pot.
//!
//! An axis pot maps angle linearly onto millivolts so that the slave's calibration holds
//! exactly: angle `min` gives 0 mV (ADC reading 0) and angle `max` gives the full ADC
//! reference (reading "1024"). The slave computes angle = p·(max − min)/1024 + min from a
//! reading p = ⌊1024·mV/Vref⌋ (reference §7.3), so with the calibration of
//! [`Pot::calibrated`] the firmware's angle equals the physical angle to within one ADC
//! step ((max − min)/1024 ≈ 0.12° for steer, 0.21° for lift).
//!
//! The calibration passes through 1-byte registers (±120 over 0..254), so the slave holds
//! quantised values, e.g. −56 arrives as −56.69; [`Pot::calibrated`] applies the same
//! quantisation with the register table's own mapping.

use shared::mapping::{map_shape, unmap_shape};
use shared::regs::{id, BoardKind};

use crate::constants::{
    ADC_REF_MV, ADC_STEPS, CHASSIS_MV_PER_DEG, END_STOP_MARGIN_DEG, LIFT_CALIBRATION_DEG,
    STEER_CALIBRATION_DEG,
};

/// The slave's value of a calibration sent as `sent` degrees: mapped onto the 1-byte
/// calibration register and back.
fn as_slave_holds(sent: f32) -> f32 {
    match BoardKind::DriveSteer.shape(id::REGDS_STEER_CALIBMIN) {
        Some(shape) => unmap_shape(map_shape(sent, &shape), &shape),
        None => sent,
    }
}

/// A linear angle pot on a steer or lift axis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pot {
    /// Angle at 0 mV (the slave's CALIBMIN).
    min_deg: f32,
    /// Angle at the full reference (the slave's CALIBMAX).
    max_deg: f32,
}

impl Pot {
    /// A pot reading `min_deg` at 0 mV and `max_deg` at the ADC reference.
    pub fn new(min_deg: f32, max_deg: f32) -> Pot {
        Pot { min_deg, max_deg }
    }

    /// The pot that agrees with a calibration sent as (min, max) degrees, after the
    /// slave's 1-byte quantisation.
    pub fn calibrated(min_sent: f32, max_sent: f32) -> Pot {
        Pot::new(as_slave_holds(min_sent), as_slave_holds(max_sent))
    }

    /// The steer pot of wheel 1..=6 (reference §8.3), None for another wheel number.
    pub fn steer(wheel: u8) -> Option<Pot> {
        let (min, max) = STEER_CALIBRATION_DEG.get(usize::from(wheel).checked_sub(1)?)?;
        Some(Pot::calibrated(*min, *max))
    }

    /// The lift pot of wheel 1..=6 (reference §8.3), None for another wheel number.
    pub fn lift(wheel: u8) -> Option<Pot> {
        let (min, max) = LIFT_CALIBRATION_DEG.get(usize::from(wheel).checked_sub(1)?)?;
        Some(Pot::calibrated(*min, *max))
    }

    /// Angle at 0 mV: the calibration minimum the slave holds.
    pub fn min_deg(&self) -> f32 {
        self.min_deg
    }

    /// Angle at the reference: the calibration maximum the slave holds.
    pub fn max_deg(&self) -> f32 {
        self.max_deg
    }

    /// Mechanical end stops for an axis read by this pot: [`END_STOP_MARGIN_DEG`] inside
    /// the calibrated range at each end.
    pub fn end_stops(&self) -> (f64, f64) {
        let lo = f64::from(self.min_deg.min(self.max_deg));
        let hi = f64::from(self.min_deg.max(self.max_deg));
        (lo + END_STOP_MARGIN_DEG, hi - END_STOP_MARGIN_DEG)
    }

    /// Output (mV) at `angle_deg`, clamped to 0..=reference.
    pub fn mv(&self, angle_deg: f64) -> f64 {
        let span = f64::from(self.max_deg) - f64::from(self.min_deg);
        if span == 0.0 {
            return 0.0;
        }
        ((angle_deg - f64::from(self.min_deg)) / span * ADC_REF_MV).clamp(0.0, ADC_REF_MV)
    }

    /// The angle (°) at which the pot gives `mv`.
    pub fn angle_at_mv(&self, mv: f64) -> f64 {
        let span = f64::from(self.max_deg) - f64::from(self.min_deg);
        f64::from(self.min_deg) + mv / ADC_REF_MV * span
    }

    /// The slave's angle for an ADC reading `p` (0..=1023), in its own float32 arithmetic:
    /// p·(max − min)/1024 + min.
    pub fn firmware_angle(&self, reading: u16) -> f32 {
        f32::from(reading) * (self.max_deg - self.min_deg) / 1024.0 + self.min_deg
    }
}

/// The real chip's ADC reading for `mv` against the reference: ⌊1024·mV/Vref⌋, 0..=1023.
pub fn adc_reading(mv: f64) -> u16 {
    (mv / ADC_REF_MV * ADC_STEPS)
        .floor()
        .clamp(0.0, ADC_STEPS - 1.0) as u16
}

/// A chassis (bogie) pot: centred at half the reference when level, [`CHASSIS_MV_PER_DEG`]
/// per degree of bogie angle.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ChassisPot {
    /// Bogie angle (°), positive raising the pot's output.
    pub angle_deg: f64,
}

impl ChassisPot {
    /// Output (mV), clamped to 0..=reference.
    pub fn mv(&self) -> f64 {
        (ADC_REF_MV / 2.0 + self.angle_deg * CHASSIS_MV_PER_DEG).clamp(0.0, ADC_REF_MV)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wheel_1_steer_calibration_is_what_the_slave_holds() {
        let pot = Pot::steer(1).expect("wheel 1 has a steer pot");
        assert!((pot.min_deg() - -56.6929).abs() < 1e-4);
        assert!((pot.max_deg() - 65.1969).abs() < 1e-4);
        let lift = Pot::lift(2).expect("wheel 2 has a lift pot");
        assert!((lift.min_deg() - -102.05).abs() < 0.01);
        assert!((lift.max_deg() - 111.50).abs() < 0.01);
        assert!(Pot::steer(0).is_none() && Pot::steer(7).is_none());
    }

    #[test]
    fn calibration_ends_map_onto_the_adc_range() {
        let pot = Pot::steer(1).expect("wheel 1 has a steer pot");
        assert_eq!(pot.mv(f64::from(pot.min_deg())), 0.0);
        assert_eq!(pot.mv(f64::from(pot.max_deg())), ADC_REF_MV);
        assert_eq!(pot.mv(-90.0), 0.0, "clamped below");
        assert_eq!(pot.mv(90.0), ADC_REF_MV, "clamped above");
        assert_eq!(adc_reading(0.0), 0);
        assert_eq!(adc_reading(2500.0), 512);
        assert_eq!(adc_reading(ADC_REF_MV), 1023);
    }

    #[test]
    fn firmware_angle_equals_physical_angle_within_one_step() {
        let mut checked = 0;
        for wheel in 1..=6 {
            let pots = [Pot::steer(wheel), Pot::lift(wheel)];
            for pot in pots.map(|p| p.expect("wheels 1..6 have both pots")) {
                let step = f64::from(pot.max_deg() - pot.min_deg()) / 1024.0;
                let (lo, hi) = pot.end_stops();
                let mut angle = lo;
                while angle <= hi {
                    let fw = f64::from(pot.firmware_angle(adc_reading(pot.mv(angle))));
                    assert!(
                        fw <= angle + 1e-4 && angle - fw < step + 1e-4,
                        "{wheel}: {angle} read {fw}"
                    );
                    assert!((pot.angle_at_mv(pot.mv(angle)) - angle).abs() < 1e-9);
                    angle += 0.37;
                    checked += 1;
                }
            }
        }
        // Six steers over ~112° and six lifts over ~205°, every 0.37°.
        assert!(checked > 6 * 290 + 6 * 540, "{checked} angles");
    }

    #[test]
    fn end_stops_sit_inside_the_calibration_and_outside_the_pc_limits() {
        // Reference §8.3: the value the slave holds of the calibration each wheel is sent
        // (STEER_CALIBRATION_DEG), typed in from the reference's table (min, max).
        let held = [
            (-56.69, 65.20),
            (-62.36, 58.58),
            (-59.53, 63.31),
            (-60.47, 64.25),
            (-66.14, 56.69),
            (-62.36, 59.53),
        ];
        let sent = STEER_CALIBRATION_DEG.map(|(min, max)| (f64::from(min), f64::from(max)));
        for (wheel, ((smin, smax), (hmin, hmax))) in (1..=6u8).zip(sent.into_iter().zip(held)) {
            let pot = Pot::steer(wheel).expect("wheels 1..6 have a steer pot");
            assert!((f64::from(pot.min_deg()) - hmin).abs() < 0.01, "{wheel}");
            assert!((f64::from(pot.max_deg()) - hmax).abs() < 0.01, "{wheel}");
            let (lo, hi) = pot.end_stops();
            assert!(lo > hmin && hi < hmax, "{wheel}: stops {lo} {hi}");
            // The PC accepts calibMin + 10 .. calibMax − 10 of what it sent (§8.4): all
            // reachable between the stops.
            assert!(
                lo < smin + 10.0 && hi > smax - 10.0,
                "{wheel}: stops {lo} {hi}"
            );
        }
        assert_eq!(Pot::steer(7).map(|p| p.min_deg()), None);
    }

    #[test]
    fn chassis_pot_is_centred_when_level() {
        assert_eq!(ChassisPot::default().mv(), 2500.0);
        assert!((ChassisPot { angle_deg: 27.0 }.mv() - 3000.0).abs() < 1e-9);
        assert_eq!(ChassisPot { angle_deg: -500.0 }.mv(), 0.0);
    }
}
