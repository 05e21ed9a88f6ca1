//! Every physical constant of the rover model, in one place.
//!
//! The rover is a 6 kg, six-wheeled vehicle on a 12 V supply. Nothing here was measured
//! on the real rover: the values are chosen to be plausible for it and to agree with what
//! the reference does state:
//! - full duty drives a wheel at about 3500 encoder ticks/s on level ground and 2500
//!   ticks/s (≈70 % duty) is "about the highest safe speed" (reference §13);
//! - the drive speed register spans ±4000 ticks/s (§2.2), above the model's free speed;
//! - a code comment equates 150 current counts with "about 1.5 A" (§7.4), so the current
//!   sense gives 100 ADC counts per ampere;
//! - the pots map the §8.3 calibration range onto the ADC range, so the firmware's angle
//!   equals the physical angle.
//!
//! Drive-motor quantities are referred to the **wheel shaft** (after the gearbox): the
//! torque constant, inertia and friction below are what the wheel sees, so the model
//! needs no gear ratio except to size the rotor's reflected inertia and the encoder.
//!
//! Figures at steady state on level ground (derived in the tests of [`crate::drive`]):
//!
//! | Duty | Wheel speed | Encoder (A rising edges/s) | Current | Sense reading |
//! |---|---|---|---|---|
//! | 25 % | 0.22 rev/s (0.08 m/s) | 791.9 | 0.23 A | 23 counts |
//! | 50 % | 0.48 rev/s (0.18 m/s) | 1715.5 | 0.28 A | 27 counts |
//! | 70 % | 0.68 rev/s (0.26 m/s) | 2454.3 | 0.31 A | 31 counts |
//! | 100 % | 0.99 rev/s (0.37 m/s) | 3562.6 | 0.37 A | 36 counts |
//!
//! Free (no-friction) speed at 12 V is 12 / 1.8 = 6.67 rad/s = 3819 ticks/s; the stall
//! current at 12 V is 12 / 2.2 = 5.45 A (545 counts, above the 500-count threshold that
//! `calibrate()` sets).

use std::f64::consts::PI;

// ---------------------------------------------------------------------------------------
// Supply and ADC
// ---------------------------------------------------------------------------------------

/// Motor supply voltage (V). The manual gives 11.5–12 V; the model uses the top.
pub const SUPPLY_V: f64 = 12.0;

/// ADC reference (mV): the slave's AREF pin, assumed tied to the 5 V rail.
pub const ADC_REF_MV: f64 = 5000.0;

/// Steps of the 10-bit ADC over the reference: a reading is ⌊1024·V/Vref⌋, at most 1023.
pub const ADC_STEPS: f64 = 1024.0;

// ---------------------------------------------------------------------------------------
// Rover and wheel
// ---------------------------------------------------------------------------------------

/// Mass of the whole rover (kg).
pub const ROVER_MASS_KG: f64 = 6.0;

/// Number of wheels; each carries an equal share of the rover's mass.
pub const WHEELS: f64 = 6.0;

/// Wheel radius (m).
pub const WHEEL_RADIUS_M: f64 = 0.06;

/// Mass of one wheel with its tyre (kg), treated as a uniform disc.
pub const WHEEL_MASS_KG: f64 = 0.3;

// ---------------------------------------------------------------------------------------
// Drive motor (M1 on a drive/steer board), referred to the wheel shaft
// ---------------------------------------------------------------------------------------

/// Gear ratio between the drive motor's rotor and the wheel.
pub const DRIVE_GEAR_RATIO: f64 = 150.0;

/// Encoder channel-A pulses (rising edges) per rotor revolution: a 96-count quadrature
/// encoder on the motor shaft.
pub const ENCODER_PULSES_PER_MOTOR_REV: f64 = 24.0;

/// Encoder ticks (channel-A rising edges, the firmware's unit of speed) per wheel
/// revolution: 24 × 150 = 3600.
pub const TICKS_PER_WHEEL_REV: f64 = ENCODER_PULSES_PER_MOTOR_REV * DRIVE_GEAR_RATIO;

/// Winding resistance of the drive motor (Ω).
pub const DRIVE_RESISTANCE_OHM: f64 = 2.2;

/// Torque constant = back-EMF constant at the wheel (N·m/A = V·s/rad).
pub const DRIVE_TORQUE_CONSTANT: f64 = 1.8;

/// Rotor inertia of the drive motor at the rotor (kg·m²).
pub const DRIVE_ROTOR_INERTIA: f64 = 2.0e-6;

/// Viscous friction of gearbox and wheel at the wheel (N·m·s/rad).
pub const DRIVE_VISCOUS_NMS: f64 = 0.05;

/// Coulomb (dry) friction of gearbox, bearings and rolling at the wheel (N·m). It is also
/// the breakaway torque: the wheel starts to turn at 2.2 × 0.35 / 1.8 = 0.43 V (3.6 % duty).
pub const DRIVE_COULOMB_NM: f64 = 0.35;

/// Inertia the drive motor accelerates, at the wheel (kg·m²): the rotor reflected through
/// the gearbox (2e-6 × 150² = 0.045), the wheel as a disc (0.00054) and one sixth of the
/// rover's mass at the wheel radius (0.0036). Total 0.04914: a mechanical time constant
/// J / (k²/R + b) of about 32 ms.
pub const DRIVE_INERTIA: f64 = DRIVE_ROTOR_INERTIA * DRIVE_GEAR_RATIO * DRIVE_GEAR_RATIO
    + 0.5 * WHEEL_MASS_KG * WHEEL_RADIUS_M * WHEEL_RADIUS_M
    + (ROVER_MASS_KG / WHEELS) * WHEEL_RADIUS_M * WHEEL_RADIUS_M;

/// Encoder ticks per radian of wheel rotation.
pub const TICKS_PER_RAD: f64 = TICKS_PER_WHEEL_REV / (2.0 * PI);

// ---------------------------------------------------------------------------------------
// Steer and lift gearmotors (quasi-static: speed follows voltage at once)
// ---------------------------------------------------------------------------------------

/// Steer gearmotor winding resistance (Ω): 3 A at 12 V when stalled or at an end stop.
pub const STEER_RESISTANCE_OHM: f64 = 4.0;

/// Current the steer gear's friction takes while it moves (A); below R·I = 0.8 V it does
/// not move at all.
pub const STEER_FRICTION_A: f64 = 0.2;

/// Steer speed at 12 V (°/s).
pub const STEER_DEG_PER_S_AT_SUPPLY: f64 = 60.0;

/// Lift gearmotor winding resistance (Ω): 4 A at 12 V when stalled or at an end stop.
pub const LIFT_RESISTANCE_OHM: f64 = 3.0;

/// Current the lift gear's friction (and the leg's share of the weight) takes while it
/// moves (A); below R·I = 1.05 V it does not move.
pub const LIFT_FRICTION_A: f64 = 0.35;

/// Lift speed at 12 V (°/s).
pub const LIFT_DEG_PER_S_AT_SUPPLY: f64 = 20.0;

/// How far inside the calibrated pot range each mechanical end stop sits (°). Every
/// demand the PC accepts (calibration ± 10°, reference §8.4) is reachable, and the pot
/// never leaves its electrical range.
pub const END_STOP_MARGIN_DEG: f64 = 5.0;

/// Steer calibration per wheel 1..6, in degrees as the PC sends it (min at pot 0, max at
/// pot 1024; reference §8.3). The slave holds these quantised through 1-byte registers;
/// [`crate::pot::Pot::calibrated`] applies the same quantisation.
pub const STEER_CALIBRATION_DEG: [(f32, f32); 6] = [
    (-56.0, 66.0),
    (-62.0, 59.0),
    (-59.0, 64.0),
    (-60.0, 65.0),
    (-66.0, 57.0),
    (-62.0, 60.0),
];

/// Lift calibration per wheel 1..6, as [`STEER_CALIBRATION_DEG`].
pub const LIFT_CALIBRATION_DEG: [(f32, f32); 6] = [
    (-109.0, 109.0),
    (-102.0, 112.0),
    (-110.0, 105.0),
    (-101.0, 110.0),
    (-113.0, 113.0),
    (-109.0, 103.0),
];

// ---------------------------------------------------------------------------------------
// Current sense and chassis pot
// ---------------------------------------------------------------------------------------

/// ADC counts per ampere of motor current: the firmware comment's 150 counts ≈ 1.5 A.
pub const SENSE_COUNTS_PER_A: f64 = 100.0;

/// Current-sense output (mV per A): 100 counts of a 5 V, 1024-step ADC = 488.28 mV/A.
pub const SENSE_MV_PER_A: f64 = SENSE_COUNTS_PER_A * ADC_REF_MV / ADC_STEPS;

/// Chassis pot slope (mV per degree): a 270° single-turn pot across 5 V, centred (2500 mV)
/// when the bogie is level.
pub const CHASSIS_MV_PER_DEG: f64 = ADC_REF_MV / 270.0;

// ---------------------------------------------------------------------------------------
// Numerics
// ---------------------------------------------------------------------------------------

/// Longest internal integration step (s). Steps are exact solutions of the linear motor
/// equation, so this only bounds how finely the Coulomb-friction sign and the bridge
/// input are sampled.
pub const MAX_SUBSTEP_S: f64 = 10e-6;
