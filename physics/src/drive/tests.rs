//! Unit tests of the drive-motor model against closed-form results.

use super::*;
use crate::constants::{SUPPLY_V, TICKS_PER_WHEEL_REV};
use crate::encoder::Channel;

/// Runs `motor` for `seconds` in 100 µs advances, returning all edges (offsets made absolute).
fn run(motor: &mut DriveMotor, seconds: f64) -> Vec<EncoderEdge> {
    let dt = 100e-6;
    let steps = (seconds / dt).round() as u64;
    let mut all = Vec::new();
    for i in 0..steps {
        let base = i as f64 * dt;
        for mut e in motor.advance(dt) {
            e.offset_s += base;
            all.push(e);
        }
    }
    all
}

fn rel(a: f64, b: f64) -> f64 {
    ((a - b) / b).abs()
}

#[test]
fn steady_tick_rates_at_quarter_half_and_full_duty() {
    let p = DriveParams::default();
    let rate = |d: f64| p.steady_ticks_per_s(&Bridge::forward(d), 0.0);
    // Closed form: (k·d·V/R − Tc) / (k²/R + b), in ticks/s.
    let k = p.torque_constant;
    let r = p.resistance_ohm;
    for d in [0.25, 0.5, 1.0] {
        let w = (k * d * SUPPLY_V / r - p.coulomb) / (k * k / r + p.viscous);
        assert!(
            rel(
                rate(d),
                w * TICKS_PER_WHEEL_REV / (2.0 * std::f64::consts::PI)
            ) < 1e-12
        );
    }
    assert!((3000.0..4000.0).contains(&rate(1.0)), "{}", rate(1.0));
    assert!((1650.0..1800.0).contains(&rate(0.5)), "{}", rate(0.5));
    assert!((700.0..900.0).contains(&rate(0.25)), "{}", rate(0.25));
    // 2500 ticks/s, "about the highest safe speed", needs about 70 % duty.
    assert!(rate(0.68) < 2500.0 && rate(0.73) > 2500.0);
    // The simulated motor settles on the closed-form rate.
    let mut m = DriveMotor::new();
    m.set_bridge(Bridge::forward(0.5));
    run(&mut m, 0.5);
    assert!(
        rel(m.ticks_per_s(), rate(0.5)) < 1e-6,
        "{}",
        m.ticks_per_s()
    );
}

#[test]
fn spin_up_follows_the_mechanical_time_constant() {
    let p = DriveParams::default();
    let bridge = Bridge::forward(1.0);
    let tau = p.time_constant_s(&bridge);
    assert!((0.025..0.040).contains(&tau), "tau {tau}");
    let w_ss = p.steady_speed_rad_s(&bridge, 0.0);
    let mut m = DriveMotor::new();
    m.set_bridge(bridge);
    m.advance(tau);
    assert!(rel(m.speed_rad_s(), w_ss * (1.0 - (-1.0f64).exp())) < 1e-9);
    m.advance(2.0 * tau);
    assert!(rel(m.speed_rad_s(), w_ss * (1.0 - (-3.0f64).exp())) < 1e-9);
    // The start current is the stall current, then it falls to the running current.
    let mut fresh = DriveMotor::new();
    fresh.set_bridge(bridge);
    assert!(rel(fresh.current_a(), SUPPLY_V / p.resistance_ohm) < 1e-12);
    fresh.advance(10.0 * tau);
    let running = (p.viscous * w_ss + p.coulomb) / p.torque_constant;
    assert!(
        rel(fresh.current_a(), running) < 1e-3,
        "{}",
        fresh.current_a()
    );
}

#[test]
fn encoder_counts_match_the_speed_and_lose_no_edge() {
    let mut m = DriveMotor::new();
    m.set_bridge(Bridge::forward(1.0));
    run(&mut m, 0.3);
    let before = m.encoder().a_rises();
    let angle0 = m.angle_rad();
    let edges = run(&mut m, 1.0);
    let counted = m.encoder().a_rises() - before;
    let expected = (m.angle_rad() - angle0) * m.params().ticks_per_rad;
    assert!(
        (counted as f64 - expected).abs() <= 1.0,
        "{counted} vs {expected}"
    );
    assert!((counted as f64 - m.ticks_per_s()).abs() <= 2.0);
    // Times increase, the channels alternate, and each channel alternates its level.
    for w in edges.windows(2) {
        assert!(w[0].offset_s < w[1].offset_s);
        assert_ne!(w[0].channel, w[1].channel);
    }
    for ch in [Channel::A, Channel::B] {
        let levels: Vec<bool> = edges
            .iter()
            .filter(|e| e.channel == ch)
            .map(|e| e.level)
            .collect();
        assert!(levels.windows(2).all(|w| w[0] != w[1]));
    }
    // Four edges per tick, give or take the partial ticks at either end.
    assert!((edges.len() as i64 - 4 * counted as i64).abs() <= 3);
    assert_eq!(
        m.encoder().a_rises_b_high(),
        0,
        "forward never sees B high at A rising"
    );
}

#[test]
fn reverse_runs_backwards_with_b_high_at_every_a_rise() {
    let mut m = DriveMotor::new();
    m.set_bridge(Bridge::reverse(0.5));
    run(&mut m, 0.5);
    let rate = DriveParams::default().steady_ticks_per_s(&Bridge::forward(0.5), 0.0);
    assert!(rel(m.ticks_per_s(), -rate) < 1e-6);
    assert!(m.encoder().a_rises() > 500);
    assert_eq!(m.encoder().a_rises_b_high(), m.encoder().a_rises());
    assert!(m.current_a() < 0.0);
}

#[test]
fn coulomb_friction_stops_a_coasting_wheel_in_finite_time() {
    let p = DriveParams::default();
    let mut m = DriveMotor::new();
    m.set_bridge(Bridge::forward(1.0));
    m.advance(0.5);
    let w0 = m.speed_rad_s();
    m.set_bridge(Bridge::off());
    // Coasting: J·dω/dt = −b·ω − Tc, so it stops at (J/b)·ln(1 + b·ω0/Tc).
    let t_stop = p.inertia / p.viscous * (1.0 + p.viscous * w0 / p.coulomb).ln();
    assert!((0.4..0.8).contains(&t_stop), "{t_stop}");
    m.advance(t_stop * 0.99);
    assert!(m.speed_rad_s() > 0.0);
    m.advance(t_stop * 0.02);
    assert_eq!(m.speed_rad_s(), 0.0);
    let angle = m.angle_rad();
    m.advance(1.0);
    assert_eq!(m.speed_rad_s(), 0.0);
    assert_eq!(m.angle_rad(), angle, "a stopped wheel stays put");
    assert_eq!(m.current_a(), 0.0);
}

#[test]
fn braking_stops_faster_than_coasting() {
    let time_to_stop = |bridge: Bridge| {
        let mut m = DriveMotor::new();
        m.set_bridge(Bridge::forward(1.0));
        m.advance(0.5);
        m.set_bridge(bridge);
        let mut t = 0.0;
        while m.speed_rad_s() > 0.0 && t < 2.0 {
            m.advance(1e-3);
            t += 1e-3;
        }
        t
    };
    let coast = time_to_stop(Bridge::off());
    let brake = time_to_stop(Bridge::from_pins(1.0, false, false));
    assert!(brake < coast / 3.0, "brake {brake} coast {coast}");
}

#[test]
fn breakaway_needs_about_four_percent_duty() {
    let mut m = DriveMotor::new();
    m.set_bridge(Bridge::forward(0.03));
    m.advance(0.5);
    assert_eq!(m.speed_rad_s(), 0.0);
    assert!(m.encoder().a_rises() == 0);
    m.set_bridge(Bridge::forward(0.05));
    m.advance(0.5);
    assert!(m.speed_rad_s() > 0.0);
}

#[test]
fn stall_injection_holds_the_wheel_and_draws_stall_current() {
    let mut m = DriveMotor::new();
    m.set_bridge(Bridge::forward(0.5));
    m.advance(0.3);
    let running = m.current_a();
    m.set_stalled(true);
    let edges = m.advance(0.2);
    assert!(edges.is_empty());
    assert_eq!(m.speed_rad_s(), 0.0);
    assert!(rel(m.current_a(), 6.0 / 2.2) < 1e-12);
    assert!(m.current_a() > 5.0 * running);
    m.set_stalled(false);
    m.advance(0.3);
    assert!(m.ticks_per_s() > 1000.0);
}

#[test]
fn a_load_torque_slows_the_wheel_and_can_roll_it_back() {
    let p = DriveParams::default();
    let bridge = Bridge::forward(0.5);
    let mut m = DriveMotor::new();
    m.set_load_torque(2.0);
    m.set_bridge(bridge);
    m.advance(0.5);
    assert!(rel(m.speed_rad_s(), p.steady_speed_rad_s(&bridge, 2.0)) < 1e-6);
    assert!(m.speed_rad_s() < p.steady_speed_rad_s(&bridge, 0.0));
    m.set_load_torque(6.0);
    m.advance(1.0);
    assert!(m.speed_rad_s() < 0.0, "a steep slope overpowers half duty");
}

#[test]
fn energy_is_conserved() {
    let mut m = DriveMotor::new();
    let plan = [
        (Bridge::forward(1.0), 0.3, 0.0),
        (Bridge::forward(0.3), 0.2, 1.0),
        (Bridge::from_pins(0.5, true, true), 0.05, 0.0),
        (Bridge::off(), 0.2, 0.0),
        (Bridge::reverse(0.8), 0.3, -0.5),
    ];
    for (bridge, seconds, load) in plan {
        m.set_bridge(bridge);
        m.set_load_torque(load);
        run(&mut m, seconds);
        let e = m.energy();
        let out = e.copper_j + e.friction_j + e.load_j + m.kinetic_j();
        assert!(
            (e.supplied_j - out).abs() < 1e-4 * e.supplied_j,
            "{e:?} kinetic {}",
            m.kinetic_j()
        );
    }
    assert!(m.energy().supplied_j > 1.0);
}

#[test]
fn advance_length_does_not_change_the_trajectory() {
    let trajectory = |dt: f64| {
        let mut m = DriveMotor::new();
        m.set_bridge(Bridge::forward(0.7));
        let steps = (0.4 / dt).round() as u64;
        for _ in 0..steps {
            m.advance(dt);
        }
        (m.angle_rad(), m.encoder().a_rises())
    };
    let (a, n) = trajectory(10e-6);
    for dt in [50e-6, 100e-6, 1e-3] {
        let (b, k) = trajectory(dt);
        assert!((a - b).abs() < 1e-9, "dt {dt}: {a} vs {b}");
        assert_eq!(n, k);
    }
}

#[test]
fn bad_advances_do_nothing() {
    let mut m = DriveMotor::new();
    m.set_bridge(Bridge::forward(1.0));
    assert!(m.advance(0.0).is_empty());
    assert!(m.advance(-1.0).is_empty());
    assert!(m.advance(f64::NAN).is_empty());
    assert_eq!(m.elapsed_s(), 0.0);
    assert_eq!(m.speed_rad_s(), 0.0);
}
