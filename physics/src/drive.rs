//! The drive motor of one wheel: a geared DC motor carrying its share of the rover, with
//! its quadrature encoder.
//!
//! Referred to the wheel shaft, with terminal voltage V (from the [`Bridge`]), back-EMF
//! constant = torque constant k, winding resistance R, inertia J, viscous friction b,
//! Coulomb friction T_c and an external load torque T_L:
//!
//! - current i = g·(V − k·ω)/R, where g is the fraction of time the bridge conducts
//!   (1 when driving, the duty when braking, 0 when off); winding inductance is neglected
//!   (its time constant is far below the mechanical one);
//! - J·dω/dt = k·i − b·ω − T_c·sign(ω) − T_L; at rest the wheel stays put while
//!   |k·i − T_L| ≤ T_c (static friction equals Coulomb friction).
//!
//! Between sign changes of ω the equation is linear, so each sub-step uses its exact
//! solution: ω relaxes exponentially towards its steady value with time constant
//! τ = J/(g·k²/R + b), and the angle is the integral of that. A sub-step in which the
//! wheel decelerates through zero is split at the exact stopping time. Sub-steps are at
//! most [`MAX_SUBSTEP_S`] long, which bounds how finely the encoder's edges are timed
//! (they are interpolated linearly in the angle within a sub-step).
//!
//! **Fault injection.** [`DriveMotor::set_stalled`] holds the wheel (a jammed wheel or a
//! wheel against an obstacle): it stops at once, no encoder edges come out, and the
//! current becomes the stall current g·V/R.

use crate::bridge::Bridge;
use crate::constants::{
    DRIVE_COULOMB_NM, DRIVE_INERTIA, DRIVE_RESISTANCE_OHM, DRIVE_TORQUE_CONSTANT,
    DRIVE_VISCOUS_NMS, MAX_SUBSTEP_S, TICKS_PER_RAD,
};
use crate::encoder::{Encoder, EncoderEdge};

/// Electrical and mechanical parameters of a drive motor, at the wheel shaft.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DriveParams {
    /// Winding resistance (Ω), > 0.
    pub resistance_ohm: f64,
    /// Torque constant = back-EMF constant (N·m/A = V·s/rad), > 0.
    pub torque_constant: f64,
    /// Total inertia the motor accelerates (kg·m²), > 0.
    pub inertia: f64,
    /// Viscous friction (N·m·s/rad), ≥ 0.
    pub viscous: f64,
    /// Coulomb friction and breakaway torque (N·m), ≥ 0.
    pub coulomb: f64,
    /// Encoder ticks (A rising edges) per radian of wheel rotation.
    pub ticks_per_rad: f64,
}

impl Default for DriveParams {
    /// The rover's drive motor ([`crate::constants`]).
    fn default() -> Self {
        DriveParams {
            resistance_ohm: DRIVE_RESISTANCE_OHM,
            torque_constant: DRIVE_TORQUE_CONSTANT,
            inertia: DRIVE_INERTIA,
            viscous: DRIVE_VISCOUS_NMS,
            coulomb: DRIVE_COULOMB_NM,
            ticks_per_rad: TICKS_PER_RAD,
        }
    }
}

impl DriveParams {
    /// (torque at standstill from the bridge minus the load, total damping) for a bridge
    /// state and load: J·dω/dt = drive − damping·ω − T_c·sign(ω).
    fn linear_terms(&self, bridge: &Bridge, load_nm: f64) -> (f64, f64) {
        let (v, g) = bridge.drive();
        let k = self.torque_constant;
        let r = self.resistance_ohm;
        (g * k * v / r - load_nm, g * k * k / r + self.viscous)
    }

    /// Steady-state speed (rad/s) for a constant bridge input and load torque.
    pub fn steady_speed_rad_s(&self, bridge: &Bridge, load_nm: f64) -> f64 {
        let (drive, damping) = self.linear_terms(bridge, load_nm);
        if drive.abs() <= self.coulomb || damping <= 0.0 {
            return 0.0;
        }
        (drive - self.coulomb * drive.signum()) / damping
    }

    /// Steady-state encoder rate (A rising edges per second, signed) for a bridge input.
    pub fn steady_ticks_per_s(&self, bridge: &Bridge, load_nm: f64) -> f64 {
        self.steady_speed_rad_s(bridge, load_nm) * self.ticks_per_rad
    }

    /// Mechanical time constant J/(g·k²/R + b) (s) for a bridge input.
    pub fn time_constant_s(&self, bridge: &Bridge) -> f64 {
        let (_, damping) = self.linear_terms(bridge, 0.0);
        self.inertia / damping
    }
}

/// Energy bookkeeping since the motor was created (joules).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct EnergyLedger {
    /// Energy drawn from the supply through the bridge.
    pub supplied_j: f64,
    /// Heat in the winding.
    pub copper_j: f64,
    /// Heat in viscous and Coulomb friction.
    pub friction_j: f64,
    /// Work done against the external load torque.
    pub load_j: f64,
}

/// One wheel's drive motor with its encoder.
#[derive(Debug, Clone)]
pub struct DriveMotor {
    params: DriveParams,
    encoder: Encoder,
    bridge: Bridge,
    load_nm: f64,
    stalled: bool,
    omega: f64,
    angle: f64,
    energy: EnergyLedger,
    elapsed_s: f64,
}

impl Default for DriveMotor {
    fn default() -> Self {
        DriveMotor::new()
    }
}

impl DriveMotor {
    /// The rover's drive motor at rest, bridge off.
    pub fn new() -> DriveMotor {
        DriveMotor::with_params(DriveParams::default())
    }

    /// A drive motor with other parameters, at rest, bridge off.
    pub fn with_params(params: DriveParams) -> DriveMotor {
        DriveMotor {
            params,
            encoder: Encoder::new(params.ticks_per_rad),
            bridge: Bridge::off(),
            load_nm: 0.0,
            stalled: false,
            omega: 0.0,
            angle: 0.0,
            energy: EnergyLedger::default(),
            elapsed_s: 0.0,
        }
    }

    /// Its parameters.
    pub fn params(&self) -> &DriveParams {
        &self.params
    }

    /// Sets the bridge input, held until the next call.
    pub fn set_bridge(&mut self, bridge: Bridge) {
        self.bridge = bridge;
    }

    /// The bridge input in force.
    pub fn bridge(&self) -> Bridge {
        self.bridge
    }

    /// Fault injection: holds the wheel still (`true`) or lets it go (`false`).
    pub fn set_stalled(&mut self, stalled: bool) {
        self.stalled = stalled;
        if stalled {
            self.omega = 0.0;
        }
    }

    /// Whether the wheel is held by [`DriveMotor::set_stalled`].
    pub fn is_stalled(&self) -> bool {
        self.stalled
    }

    /// Sets an external torque at the wheel (N·m) that opposes forward motion, e.g. a slope
    /// (negative values push forward).
    pub fn set_load_torque(&mut self, nm: f64) {
        self.load_nm = if nm.is_finite() { nm } else { 0.0 };
    }

    /// Wheel speed (rad/s), positive forward.
    pub fn speed_rad_s(&self) -> f64 {
        self.omega
    }

    /// Encoder rate (A rising edges per second), positive forward.
    pub fn ticks_per_s(&self) -> f64 {
        self.omega * self.params.ticks_per_rad
    }

    /// Wheel angle since creation (rad), positive forward.
    pub fn angle_rad(&self) -> f64 {
        self.angle
    }

    /// Motor current (A), positive when it drives forward; the mean over a PWM period.
    pub fn current_a(&self) -> f64 {
        let (v, g) = self.bridge.drive();
        g * (v - self.params.torque_constant * self.omega) / self.params.resistance_ohm
    }

    /// The encoder (levels and edge counts).
    pub fn encoder(&self) -> &Encoder {
        &self.encoder
    }

    /// Kinetic energy of everything the motor moves (J).
    pub fn kinetic_j(&self) -> f64 {
        0.5 * self.params.inertia * self.omega * self.omega
    }

    /// Energy bookkeeping since creation.
    pub fn energy(&self) -> EnergyLedger {
        self.energy
    }

    /// Emulated time advanced so far (s).
    pub fn elapsed_s(&self) -> f64 {
        self.elapsed_s
    }

    /// Advances the motor by `dt_s` seconds with the bridge input held, and returns the
    /// encoder edges in time order, with offsets from the start of this call. A `dt_s`
    /// that is not positive and finite does nothing.
    pub fn advance(&mut self, dt_s: f64) -> Vec<EncoderEdge> {
        let mut edges = Vec::new();
        self.advance_into(dt_s, &mut edges);
        edges
    }

    /// [`DriveMotor::advance`] that appends the edges to `edges` instead.
    pub fn advance_into(&mut self, dt_s: f64, edges: &mut Vec<EncoderEdge>) {
        if !(dt_s.is_finite() && dt_s > 0.0) {
            return;
        }
        let n = (dt_s / MAX_SUBSTEP_S).ceil().max(1.0);
        let h = dt_s / n;
        for i in 0..n as u64 {
            self.substep(i as f64 * h, h, edges);
        }
        self.elapsed_s += dt_s;
    }

    /// One sub-step of `h` seconds starting `t0` seconds into the current advance.
    fn substep(&mut self, t0: f64, h: f64, edges: &mut Vec<EncoderEdge>) {
        let p = self.params;
        let (drive, damping) = p.linear_terms(&self.bridge, self.load_nm);
        if self.stalled {
            self.omega = 0.0;
            self.book(0.0, 0.0, h);
            return;
        }
        let mut t = t0;
        let mut left = h;
        // At most: move, stop at zero, stay (or restart the other way). Three rounds cover it.
        for _ in 0..3 {
            if left <= 0.0 {
                break;
            }
            let sign = if self.omega != 0.0 {
                self.omega.signum()
            } else if drive.abs() > p.coulomb {
                drive.signum()
            } else {
                // Static friction holds the wheel for the rest of the sub-step.
                self.book(0.0, 0.0, left);
                return;
            };
            let net = drive - p.coulomb * sign;
            let seg = Segment::new(self.omega, net, damping, p.inertia);
            let (dt, stops) = match seg.time_to_zero() {
                Some(t_zero) if self.omega != 0.0 && t_zero < left => (t_zero, true),
                _ => (left, false),
            };
            let omega1 = if stops { 0.0 } else { seg.speed(dt) };
            let angle1 = self.angle + seg.distance(dt);
            self.book(self.omega, omega1, dt);
            self.encoder.track(self.angle, angle1, t, dt, edges);
            self.angle = angle1;
            self.omega = omega1;
            t += dt;
            left -= dt;
        }
    }

    /// Adds the energy flows over `dt` seconds during which ω went from `w0` to `w1`
    /// (trapezoid rule on each power).
    fn book(&mut self, w0: f64, w1: f64, dt: f64) {
        let p = self.params;
        let (v, g) = self.bridge.drive();
        let current = |w: f64| g * (v - p.torque_constant * w) / p.resistance_ohm;
        let copper = |w: f64| {
            if g > 0.0 {
                let i = current(w);
                p.resistance_ohm * i * i / g
            } else {
                0.0
            }
        };
        let friction = |w: f64| p.viscous * w * w + p.coulomb * w.abs();
        let half = 0.5 * dt;
        self.energy.supplied_j += half * v * (current(w0) + current(w1));
        self.energy.copper_j += half * (copper(w0) + copper(w1));
        self.energy.friction_j += half * (friction(w0) + friction(w1));
        self.energy.load_j += half * self.load_nm * (w0 + w1);
    }
}

/// The exact solution of J·dω/dt = net − damping·ω from ω(0) = w0.
struct Segment {
    w0: f64,
    /// Steady speed net/damping (when damping > 0).
    w_ss: f64,
    /// Time constant J/damping, or infinite for no damping.
    tau: f64,
    /// Acceleration net/J, used when there is no damping.
    accel: f64,
}

impl Segment {
    fn new(w0: f64, net: f64, damping: f64, inertia: f64) -> Segment {
        if damping > 0.0 {
            Segment {
                w0,
                w_ss: net / damping,
                tau: inertia / damping,
                accel: 0.0,
            }
        } else {
            Segment {
                w0,
                w_ss: 0.0,
                tau: f64::INFINITY,
                accel: net / inertia,
            }
        }
    }

    fn speed(&self, t: f64) -> f64 {
        if self.tau.is_finite() {
            self.w_ss + (self.w0 - self.w_ss) * (-t / self.tau).exp()
        } else {
            self.w0 + self.accel * t
        }
    }

    fn distance(&self, t: f64) -> f64 {
        if self.tau.is_finite() {
            self.w_ss * t + (self.w0 - self.w_ss) * self.tau * -(-t / self.tau).exp_m1()
        } else {
            self.w0 * t + 0.5 * self.accel * t * t
        }
    }

    /// When ω reaches zero, if it is heading through zero.
    fn time_to_zero(&self) -> Option<f64> {
        if self.w0 == 0.0 {
            return None;
        }
        if self.tau.is_finite() {
            // ω(t) = 0 needs w_ss on the other side of zero from w0.
            if self.w_ss * self.w0.signum() >= 0.0 {
                return None;
            }
            Some(self.tau * ((self.w0 - self.w_ss) / -self.w_ss).ln())
        } else if self.accel * self.w0 < 0.0 {
            Some(-self.w0 / self.accel)
        } else {
            None
        }
    }
}

#[cfg(test)]
mod tests;
