//! A steer or lift gearmotor: a small DC motor behind a high-ratio, self-locking gear,
//! turning an axis between two mechanical end stops.
//!
//! The gear's friction dominates and its inertia is negligible, so the model is
//! quasi-static: with mean terminal voltage V (from the [`Bridge`]), winding resistance R,
//! friction current I_f (the current the gear's friction takes while moving) and back-EMF
//! constant k (V per °/s):
//!
//! - |V| ≤ R·I_f: the gear does not move; current V/R;
//! - otherwise the axis turns at (V − sign(V)·R·I_f)/k °/s (speed proportional to voltage
//!   above the friction threshold) and the current is sign(V)·I_f;
//! - at an end stop, driven into it, or when [`Gearmotor::set_stalled`] holds it: no motion,
//!   current V/R (the stall current);
//! - bridge off or braking: no motion (the gear holds), no current.
//!
//! Forward (POS high) turns towards the **maximum** stop, so the pot's millivolts and the
//! firmware's angle rise with a positive duty, as its position PID assumes.

use crate::bridge::Bridge;
use crate::constants::{
    LIFT_DEG_PER_S_AT_SUPPLY, LIFT_FRICTION_A, LIFT_RESISTANCE_OHM, STEER_DEG_PER_S_AT_SUPPLY,
    STEER_FRICTION_A, STEER_RESISTANCE_OHM, SUPPLY_V,
};

/// Parameters of a gearmotor.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GearParams {
    /// Winding resistance (Ω), > 0.
    pub resistance_ohm: f64,
    /// Current the gear's friction takes while moving (A), ≥ 0.
    pub friction_a: f64,
    /// Back-EMF constant (V per °/s), > 0.
    pub volts_per_deg_s: f64,
    /// Angle of the lower end stop (°).
    pub min_stop_deg: f64,
    /// Angle of the upper end stop (°), ≥ the lower one.
    pub max_stop_deg: f64,
}

impl GearParams {
    /// Parameters for a gearmotor that turns at `deg_per_s` at 12 V.
    fn rated(resistance_ohm: f64, friction_a: f64, deg_per_s: f64, stops: (f64, f64)) -> Self {
        GearParams {
            resistance_ohm,
            friction_a,
            volts_per_deg_s: (SUPPLY_V - resistance_ohm * friction_a) / deg_per_s,
            min_stop_deg: stops.0.min(stops.1),
            max_stop_deg: stops.0.max(stops.1),
        }
    }

    /// The rover's steer gearmotor with end stops at `stops` (min, max) degrees.
    pub fn steer(stops: (f64, f64)) -> GearParams {
        GearParams::rated(
            STEER_RESISTANCE_OHM,
            STEER_FRICTION_A,
            STEER_DEG_PER_S_AT_SUPPLY,
            stops,
        )
    }

    /// The rover's lift gearmotor with end stops at `stops` (min, max) degrees.
    pub fn lift(stops: (f64, f64)) -> GearParams {
        GearParams::rated(
            LIFT_RESISTANCE_OHM,
            LIFT_FRICTION_A,
            LIFT_DEG_PER_S_AT_SUPPLY,
            stops,
        )
    }

    /// Free speed (°/s, signed) for a bridge input, ignoring end stops.
    pub fn free_speed_deg_s(&self, bridge: &Bridge) -> f64 {
        let (v, g) = bridge.drive();
        let threshold = self.resistance_ohm * self.friction_a;
        if g < 1.0 || v.abs() <= threshold {
            return 0.0;
        }
        (v - v.signum() * threshold) / self.volts_per_deg_s
    }
}

/// Which end stop an axis rests against.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EndStop {
    /// The lower stop (reached in reverse).
    Min,
    /// The upper stop (reached forward).
    Max,
}

/// One steer or lift gearmotor and its axis.
#[derive(Debug, Clone)]
pub struct Gearmotor {
    params: GearParams,
    bridge: Bridge,
    stalled: bool,
    angle_deg: f64,
    speed_deg_s: f64,
}

impl Gearmotor {
    /// A gearmotor at `angle_deg` (clamped to its stops), bridge off.
    pub fn new(params: GearParams, angle_deg: f64) -> Gearmotor {
        let mut g = Gearmotor {
            params,
            bridge: Bridge::off(),
            stalled: false,
            angle_deg: 0.0,
            speed_deg_s: 0.0,
        };
        g.set_angle_deg(angle_deg);
        g
    }

    /// Its parameters.
    pub fn params(&self) -> &GearParams {
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

    /// Fault injection: holds the axis still (`true`) or lets it go (`false`).
    pub fn set_stalled(&mut self, stalled: bool) {
        self.stalled = stalled;
    }

    /// Whether the axis is held by [`Gearmotor::set_stalled`].
    pub fn is_stalled(&self) -> bool {
        self.stalled
    }

    /// Moves the axis by hand to `angle_deg` (clamped to the stops; NaN is ignored).
    pub fn set_angle_deg(&mut self, angle_deg: f64) {
        if !angle_deg.is_nan() {
            self.angle_deg = angle_deg.clamp(self.params.min_stop_deg, self.params.max_stop_deg);
        }
    }

    /// Axis angle (°).
    pub fn angle_deg(&self) -> f64 {
        self.angle_deg
    }

    /// Axis speed during the last advance (°/s).
    pub fn speed_deg_s(&self) -> f64 {
        self.speed_deg_s
    }

    /// The end stop the axis rests against, if any.
    pub fn at_stop(&self) -> Option<EndStop> {
        if self.angle_deg <= self.params.min_stop_deg {
            Some(EndStop::Min)
        } else if self.angle_deg >= self.params.max_stop_deg {
            Some(EndStop::Max)
        } else {
            None
        }
    }

    /// Whether the axis is blocked from moving at `free` °/s: held, or at the stop it heads for.
    fn blocked(&self, free: f64) -> bool {
        self.stalled
            || (free > 0.0 && self.at_stop() == Some(EndStop::Max))
            || (free < 0.0 && self.at_stop() == Some(EndStop::Min))
    }

    /// Motor current now (A), positive when driving forward.
    pub fn current_a(&self) -> f64 {
        let (v, g) = self.bridge.drive();
        if g < 1.0 {
            return 0.0;
        }
        let free = self.params.free_speed_deg_s(&self.bridge);
        if free == 0.0 || self.blocked(free) {
            v / self.params.resistance_ohm
        } else {
            v.signum() * self.params.friction_a
        }
    }

    /// Advances by `dt_s` seconds with the bridge input held (nothing for a `dt_s` that is
    /// not positive and finite). The axis stops dead at an end stop.
    pub fn advance(&mut self, dt_s: f64) {
        if !(dt_s.is_finite() && dt_s > 0.0) {
            return;
        }
        let free = self.params.free_speed_deg_s(&self.bridge);
        if free == 0.0 || self.blocked(free) {
            self.speed_deg_s = 0.0;
            return;
        }
        self.speed_deg_s = free;
        let target = self.angle_deg + free * dt_s;
        self.set_angle_deg(target);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn steer() -> Gearmotor {
        Gearmotor::new(GearParams::steer((-50.0, 60.0)), 0.0)
    }

    #[test]
    fn speed_is_proportional_to_voltage_above_friction() {
        let p = GearParams::steer((-50.0, 60.0));
        assert!((p.free_speed_deg_s(&Bridge::forward(1.0)) - 60.0).abs() < 1e-12);
        let s = |d: f64| p.free_speed_deg_s(&Bridge::forward(d));
        // Equal voltage steps give equal speed steps.
        assert!(((s(0.75) - s(0.5)) - (s(0.5) - s(0.25))).abs() < 1e-12);
        assert!(s(0.25) > 0.0 && s(0.25) < 0.25 * 60.0);
        // Below R·I_f = 0.8 V (6.7 % duty) the gear does not move.
        assert_eq!(s(0.06), 0.0);
        assert!(s(0.07) > 0.0);
        assert_eq!(p.free_speed_deg_s(&Bridge::reverse(1.0)), -60.0);
        let lift = GearParams::lift((-100.0, 100.0));
        assert!((lift.free_speed_deg_s(&Bridge::forward(1.0)) - 20.0).abs() < 1e-12);
    }

    #[test]
    fn drives_to_the_end_stop_and_stops_there_at_stall_current() {
        let mut g = steer();
        g.set_bridge(Bridge::forward(1.0));
        g.advance(0.5);
        assert!((g.angle_deg() - 30.0).abs() < 1e-9);
        assert!((g.current_a() - 0.2).abs() < 1e-12);
        assert_eq!(g.at_stop(), None);
        g.advance(1.0);
        assert_eq!(g.angle_deg(), 60.0);
        assert_eq!(g.at_stop(), Some(EndStop::Max));
        g.advance(1.0);
        assert_eq!(g.angle_deg(), 60.0);
        assert_eq!(g.speed_deg_s(), 0.0);
        assert!((g.current_a() - 3.0).abs() < 1e-12, "12 V / 4 Ω");
        // Reversing leaves the stop at running current.
        g.set_bridge(Bridge::reverse(1.0));
        assert!((g.current_a() + 0.2).abs() < 1e-12);
        g.advance(3.0);
        assert_eq!(g.angle_deg(), -50.0);
        assert_eq!(g.at_stop(), Some(EndStop::Min));
    }

    #[test]
    fn off_or_brake_holds_the_axis_without_current() {
        let mut g = steer();
        g.set_angle_deg(12.5);
        for bridge in [Bridge::off(), Bridge::from_pins(1.0, false, false)] {
            g.set_bridge(bridge);
            g.advance(1.0);
            assert_eq!(g.angle_deg(), 12.5);
            assert_eq!(g.current_a(), 0.0);
        }
    }

    #[test]
    fn stall_injection_holds_the_axis_at_stall_current() {
        let mut g = steer();
        g.set_bridge(Bridge::forward(0.5));
        g.set_stalled(true);
        g.advance(1.0);
        assert_eq!(g.angle_deg(), 0.0);
        assert!((g.current_a() - 1.5).abs() < 1e-12);
        g.set_stalled(false);
        g.advance(0.1);
        assert!(g.angle_deg() > 0.0);
    }

    #[test]
    fn angles_are_clamped_to_the_stops() {
        let mut g = steer();
        g.set_angle_deg(200.0);
        assert_eq!(g.angle_deg(), 60.0);
        g.set_angle_deg(f64::NAN);
        assert_eq!(g.angle_deg(), 60.0);
        assert_eq!(
            Gearmotor::new(GearParams::lift((10.0, -10.0)), -30.0).angle_deg(),
            -10.0
        );
    }
}
