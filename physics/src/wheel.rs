//! Everything one slave board sees: its motors, their sensors, and which pin or ADC channel
//! carries each (reference §12).
//!
//! | Board | M1 (PWM D9, POS D2, NEG D3, current ADC0) | M2 (PWM D10, POS D4, NEG D7, current ADC1) | ADC6 | ADC7 | PD0 / PD1 |
//! |---|---|---|---|---|---|
//! | drive/steer (DS) | drive motor | steer gearmotor | steer pot | chassis pot (first DS of a pair; floats on the other) | encoder A / B |
//! | lift/lift (LL) | lift ONE gearmotor | lift TWO gearmotor | lift ONE pot | lift TWO pot | unused |
//!
//! A board model takes each motor's [`Bridge`] input, advances in time, and gives the
//! encoder's edges and levels and the millivolts on each ADC channel.

use crate::bridge::Bridge;
use crate::drive::DriveMotor;
use crate::encoder::{EncoderEdge, Quadrature};
use crate::gearmotor::{GearParams, Gearmotor};
use crate::pot::{ChassisPot, Pot};
use crate::sense::CurrentSense;
use crate::PhysicsError;

/// Pins and ADC channels of a slave board, in the Uno's numbering.
pub mod pins {
    /// M1 enable (PWM, Timer1 OC1A): D9.
    pub const M1_PWM: u8 = 9;
    /// M1 POS direction pin: D2.
    pub const M1_POS: u8 = 2;
    /// M1 NEG direction pin: D3.
    pub const M1_NEG: u8 = 3;
    /// M2 enable (PWM, Timer1 OC1B): D10.
    pub const M2_PWM: u8 = 10;
    /// M2 POS direction pin: D4.
    pub const M2_POS: u8 = 4;
    /// M2 NEG direction pin: D7.
    pub const M2_NEG: u8 = 7;
    /// Encoder channel A: D0 (PD0, PCINT16).
    pub const ENCODER_A: u8 = 0;
    /// Encoder channel B: D1 (PD1).
    pub const ENCODER_B: u8 = 1;
    /// M1 current sense: ADC0.
    pub const ADC_M1_CURRENT: u8 = 0;
    /// M2 current sense: ADC1.
    pub const ADC_M2_CURRENT: u8 = 1;
    /// Steer pot (DS) or lift ONE pot (LL): ADC6.
    pub const ADC_POT_6: u8 = 6;
    /// Chassis pot (DS) or lift TWO pot (LL): ADC7.
    pub const ADC_POT_7: u8 = 7;
}

/// A motor of a slave board by its slot.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Motor {
    /// M1: the drive motor (DS) or lift ONE (LL); the slave's motor id 0.
    M1,
    /// M2: the steer motor (DS) or lift TWO (LL); the slave's motor id 1.
    M2,
}

/// A gearmotor with the pot that reads its angle.
#[derive(Debug, Clone)]
pub struct Axis {
    /// The gearmotor.
    pub motor: Gearmotor,
    /// Its angle pot.
    pub pot: Pot,
}

impl Axis {
    /// An axis read by `pot`, with end stops just inside the pot's calibrated range, at
    /// `angle_deg`; `params` picks steer or lift.
    fn new(pot: Pot, params: fn((f64, f64)) -> GearParams, angle_deg: f64) -> Axis {
        Axis {
            motor: Gearmotor::new(params(pot.end_stops()), angle_deg),
            pot,
        }
    }

    /// Pot output (mV) at the axis's angle now.
    pub fn pot_mv(&self) -> f64 {
        self.pot.mv(self.motor.angle_deg())
    }
}

/// A drive/steer board: one wheel's drive motor and steer axis.
#[derive(Debug, Clone)]
pub struct DsBoard {
    /// Wheel 1..=6.
    pub wheel: u8,
    /// Drive motor (M1) with its encoder.
    pub drive: DriveMotor,
    /// Steer axis (M2) with its pot (ADC6).
    pub steer: Axis,
    /// The chassis pot on ADC7, or None where the input floats.
    pub chassis: Option<ChassisPot>,
    /// Drive current sense (ADC0).
    pub drive_sense: CurrentSense,
    /// Steer current sense (ADC1).
    pub steer_sense: CurrentSense,
}

/// A lift/lift board: the lift axes of one wheel pair.
#[derive(Debug, Clone)]
pub struct LlBoard {
    /// Pair 0..=2 (wheels 2p+1 and 2p+2).
    pub pair: u8,
    /// Lift ONE (M1, wheel 2p+1) with its pot (ADC6).
    pub one: Axis,
    /// Lift TWO (M2, wheel 2p+2) with its pot (ADC7).
    pub two: Axis,
    /// Lift ONE current sense (ADC0).
    pub one_sense: CurrentSense,
    /// Lift TWO current sense (ADC1).
    pub two_sense: CurrentSense,
}

/// The physics behind one slave board.
#[derive(Debug, Clone)]
pub enum SlaveBoardModel {
    /// A drive/steer board.
    Ds(DsBoard),
    /// A lift/lift board.
    Ll(LlBoard),
}

impl SlaveBoardModel {
    /// The drive/steer board of `wheel` (1..=6): drive at rest, steer at 0°, with a chassis
    /// pot (level) if `chassis_pot`.
    pub fn drive_steer(wheel: u8, chassis_pot: bool) -> Result<SlaveBoardModel, PhysicsError> {
        let pot = Pot::steer(wheel).ok_or(PhysicsError::NoSuchWheel(wheel))?;
        Ok(SlaveBoardModel::Ds(DsBoard {
            wheel,
            drive: DriveMotor::new(),
            steer: Axis::new(pot, GearParams::steer, 0.0),
            chassis: chassis_pot.then(ChassisPot::default),
            drive_sense: CurrentSense::new(),
            steer_sense: CurrentSense::new(),
        }))
    }

    /// The lift/lift board of `pair` (0..=2): both lifts at 0°.
    pub fn lift_lift(pair: u8) -> Result<SlaveBoardModel, PhysicsError> {
        let wheel = pair.checked_mul(2).map(|w| w + 1).filter(|&w| w <= 5);
        let (one, two) = wheel
            .and_then(|w| Some((Pot::lift(w)?, Pot::lift(w + 1)?)))
            .ok_or(PhysicsError::NoSuchPair(pair))?;
        Ok(SlaveBoardModel::Ll(LlBoard {
            pair,
            one: Axis::new(one, GearParams::lift, 0.0),
            two: Axis::new(two, GearParams::lift, 0.0),
            one_sense: CurrentSense::new(),
            two_sense: CurrentSense::new(),
        }))
    }

    /// The board of controller `n` as wired on the rover (reference §1): DS boards 1, 2,
    /// 4, 5, 7, 8 for wheels 1..6 (the chassis pot on 1, 4 and 7), LL boards 3, 6, 9.
    pub fn for_controller(n: u8) -> Result<SlaveBoardModel, PhysicsError> {
        match n {
            1 | 2 | 4 | 5 | 7 | 8 => {
                let pair = (n - 1) / 3;
                let first = (n - 1).is_multiple_of(3);
                SlaveBoardModel::drive_steer(2 * pair + if first { 1 } else { 2 }, first)
            }
            3 | 6 | 9 => SlaveBoardModel::lift_lift(n / 3 - 1),
            _ => Err(PhysicsError::NoSuchController(n)),
        }
    }

    /// Sets one motor's bridge input.
    pub fn set_bridge(&mut self, motor: Motor, bridge: Bridge) {
        match (self, motor) {
            (SlaveBoardModel::Ds(b), Motor::M1) => b.drive.set_bridge(bridge),
            (SlaveBoardModel::Ds(b), Motor::M2) => b.steer.motor.set_bridge(bridge),
            (SlaveBoardModel::Ll(b), Motor::M1) => b.one.motor.set_bridge(bridge),
            (SlaveBoardModel::Ll(b), Motor::M2) => b.two.motor.set_bridge(bridge),
        }
    }

    /// One motor's bridge input, as last read from the chip's pins.
    pub fn bridge(&self, motor: Motor) -> Bridge {
        match (self, motor) {
            (SlaveBoardModel::Ds(b), Motor::M1) => b.drive.bridge(),
            (SlaveBoardModel::Ds(b), Motor::M2) => b.steer.motor.bridge(),
            (SlaveBoardModel::Ll(b), Motor::M1) => b.one.motor.bridge(),
            (SlaveBoardModel::Ll(b), Motor::M2) => b.two.motor.bridge(),
        }
    }

    /// One motor's current (A, signed).
    pub fn current_a(&self, motor: Motor) -> f64 {
        match (self, motor) {
            (SlaveBoardModel::Ds(b), Motor::M1) => b.drive.current_a(),
            (SlaveBoardModel::Ds(b), Motor::M2) => b.steer.motor.current_a(),
            (SlaveBoardModel::Ll(b), Motor::M1) => b.one.motor.current_a(),
            (SlaveBoardModel::Ll(b), Motor::M2) => b.two.motor.current_a(),
        }
    }

    /// One motor's current-sense channel, to see what is injected.
    pub fn sense(&self, motor: Motor) -> &CurrentSense {
        match (self, motor) {
            (SlaveBoardModel::Ds(b), Motor::M1) => &b.drive_sense,
            (SlaveBoardModel::Ds(b), Motor::M2) => &b.steer_sense,
            (SlaveBoardModel::Ll(b), Motor::M1) => &b.one_sense,
            (SlaveBoardModel::Ll(b), Motor::M2) => &b.two_sense,
        }
    }

    /// One motor's current-sense channel, to inject spikes.
    pub fn sense_mut(&mut self, motor: Motor) -> &mut CurrentSense {
        match (self, motor) {
            (SlaveBoardModel::Ds(b), Motor::M1) => &mut b.drive_sense,
            (SlaveBoardModel::Ds(b), Motor::M2) => &mut b.steer_sense,
            (SlaveBoardModel::Ll(b), Motor::M1) => &mut b.one_sense,
            (SlaveBoardModel::Ll(b), Motor::M2) => &mut b.two_sense,
        }
    }

    /// Fault injection: holds one motor still (`true`) or lets it go.
    pub fn set_stalled(&mut self, motor: Motor, stalled: bool) {
        match (self, motor) {
            (SlaveBoardModel::Ds(b), Motor::M1) => b.drive.set_stalled(stalled),
            (SlaveBoardModel::Ds(b), Motor::M2) => b.steer.motor.set_stalled(stalled),
            (SlaveBoardModel::Ll(b), Motor::M1) => b.one.motor.set_stalled(stalled),
            (SlaveBoardModel::Ll(b), Motor::M2) => b.two.motor.set_stalled(stalled),
        }
    }

    /// Advances every motor and sense by `dt_s` seconds with the bridge inputs held, and
    /// returns the encoder's edges (none on an LL board) with offsets from the start of
    /// this call.
    pub fn advance(&mut self, dt_s: f64) -> Vec<EncoderEdge> {
        match self {
            SlaveBoardModel::Ds(b) => {
                let edges = b.drive.advance(dt_s);
                b.steer.motor.advance(dt_s);
                b.drive_sense.advance(dt_s);
                b.steer_sense.advance(dt_s);
                edges
            }
            SlaveBoardModel::Ll(b) => {
                b.one.motor.advance(dt_s);
                b.two.motor.advance(dt_s);
                b.one_sense.advance(dt_s);
                b.two_sense.advance(dt_s);
                Vec::new()
            }
        }
    }

    /// Encoder levels (DS boards only).
    pub fn encoder_levels(&self) -> Option<Quadrature> {
        match self {
            SlaveBoardModel::Ds(b) => Some(b.drive.encoder().levels()),
            SlaveBoardModel::Ll(_) => None,
        }
    }

    /// Millivolts on ADC0..ADC7; None for a channel the board leaves floating or unused.
    pub fn adc_mv(&self) -> [Option<f64>; 8] {
        let mut mv = [None; 8];
        match self {
            SlaveBoardModel::Ds(b) => {
                mv[0] = Some(b.drive_sense.mv(b.drive.current_a()));
                mv[1] = Some(b.steer_sense.mv(b.steer.motor.current_a()));
                mv[6] = Some(b.steer.pot_mv());
                mv[7] = b.chassis.map(|c| c.mv());
            }
            SlaveBoardModel::Ll(b) => {
                mv[0] = Some(b.one_sense.mv(b.one.motor.current_a()));
                mv[1] = Some(b.two_sense.mv(b.two.motor.current_a()));
                mv[6] = Some(b.one.pot_mv());
                mv[7] = Some(b.two.pot_mv());
            }
        }
        mv
    }

    /// The DS board, if this is one.
    pub fn ds(&self) -> Option<&DsBoard> {
        match self {
            SlaveBoardModel::Ds(b) => Some(b),
            SlaveBoardModel::Ll(_) => None,
        }
    }

    /// The DS board, mutably, if this is one.
    pub fn ds_mut(&mut self) -> Option<&mut DsBoard> {
        match self {
            SlaveBoardModel::Ds(b) => Some(b),
            SlaveBoardModel::Ll(_) => None,
        }
    }

    /// The LL board, if this is one.
    pub fn ll(&self) -> Option<&LlBoard> {
        match self {
            SlaveBoardModel::Ll(b) => Some(b),
            SlaveBoardModel::Ds(_) => None,
        }
    }

    /// The LL board, mutably, if this is one.
    pub fn ll_mut(&mut self) -> Option<&mut LlBoard> {
        match self {
            SlaveBoardModel::Ll(b) => Some(b),
            SlaveBoardModel::Ds(_) => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pot::adc_reading;

    #[test]
    fn controllers_map_to_the_rover_wiring() {
        let wheel_of = |n| match SlaveBoardModel::for_controller(n) {
            Ok(SlaveBoardModel::Ds(b)) => Some((b.wheel, b.chassis.is_some())),
            _ => None,
        };
        assert_eq!(wheel_of(1), Some((1, true)));
        assert_eq!(wheel_of(2), Some((2, false)));
        assert_eq!(wheel_of(4), Some((3, true)));
        assert_eq!(wheel_of(8), Some((6, false)));
        let pair_of = |n| match SlaveBoardModel::for_controller(n) {
            Ok(SlaveBoardModel::Ll(b)) => Some(b.pair),
            _ => None,
        };
        assert_eq!(pair_of(3), Some(0));
        assert_eq!(pair_of(9), Some(2));
        assert!(matches!(
            SlaveBoardModel::for_controller(10),
            Err(PhysicsError::NoSuchController(10))
        ));
        assert!(matches!(
            SlaveBoardModel::lift_lift(3),
            Err(PhysicsError::NoSuchPair(3))
        ));
        assert!(matches!(
            SlaveBoardModel::drive_steer(0, false),
            Err(PhysicsError::NoSuchWheel(0))
        ));
    }

    #[test]
    fn ds_board_channels_carry_currents_and_pots() -> Result<(), PhysicsError> {
        let mut board = SlaveBoardModel::for_controller(1)?;
        board.set_bridge(Motor::M1, Bridge::forward(1.0));
        board.set_bridge(Motor::M2, Bridge::forward(1.0));
        let mv = board.adc_mv();
        // At rest: drive and steer start at stall current 12/2.2 A and 12/4 A.
        assert_eq!(mv[0].map(adc_reading), Some(545));
        assert_eq!(
            mv[1].map(adc_reading),
            Some(20),
            "the steer moves at once: 0.2 A"
        );
        assert_eq!(mv[7], Some(2500.0));
        assert_eq!(mv[2], None);
        let pot0 = mv[6].expect("the steer pot on ADC6");
        let edges = board.advance(0.1);
        assert!(edges.len() > 100);
        let mv = board.adc_mv();
        let pot1 = mv[6].expect("the steer pot on ADC6");
        assert!(pot1 > pot0 + 200.0, "steer turned towards max");
        let drive_current = mv[0].map(adc_reading).expect("the drive current on ADC0");
        assert!(drive_current < 200, "{drive_current}");
        assert!(board.encoder_levels().is_some());
        // The second DS board of a pair has no chassis pot.
        assert_eq!(SlaveBoardModel::for_controller(2)?.adc_mv()[7], None);
        Ok(())
    }

    #[test]
    fn ll_board_moves_both_lifts() -> Result<(), PhysicsError> {
        let mut board = SlaveBoardModel::for_controller(6)?;
        board.set_bridge(Motor::M1, Bridge::forward(1.0));
        board.set_bridge(Motor::M2, Bridge::reverse(1.0));
        assert!(board.advance(1.0).is_empty());
        let ll = board
            .ll()
            .map(|b| (b.one.motor.angle_deg(), b.two.motor.angle_deg()));
        assert_eq!(ll.map(|(a, b)| (a.round(), b.round())), Some((20.0, -20.0)));
        assert!(board.encoder_levels().is_none());
        board.set_stalled(Motor::M1, true);
        board.sense_mut(Motor::M2).inject_spike(5.0, 1.0);
        board.advance(0.1);
        let mv = board.adc_mv();
        assert_eq!(mv[0].map(adc_reading), Some(400), "12 V / 3 Ω");
        assert_eq!(mv[1].map(adc_reading), Some(535), "0.35 A + 5 A");
        Ok(())
    }
}
