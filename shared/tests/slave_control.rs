//! Closed-loop behaviour with the PC library's calibrate() gains (reference §8.3) on small
//! plants: steer and lift steps settle, the drive keeps the original 150-ms window and
//! incremental form, and the new edge-timing mode runs at 100 Hz.

mod slave_support;

use shared::regs::id::*;
use shared::slave::{DriveMode, MotorId};
use slave_support::{DsRig, LlRig};

/// Runs until the angle stays within `tolerance` of `target` for the rest of `ms`;
/// returns the time it entered that band for good.
fn settle(angle: &mut dyn FnMut() -> f64, ms: u32, target: f64, tolerance: f64) -> Option<u32> {
    let mut inside_since = None;
    for t in 0..ms {
        let a = angle();
        if (a - target).abs() <= tolerance {
            inside_since.get_or_insert(t);
        } else {
            inside_since = None;
        }
    }
    inside_since
}

#[test]
fn steer_steps_to_40_settle_within_2_degrees() {
    for (from, to) in [(0.0, 40.0), (40.0, -40.0), (-40.0, 0.0)] {
        let mut rig = DsRig::new();
        rig.steer.angle = from;
        rig.bench.calibrate();
        rig.bench.write_value(REGDS_STEER_REQPOS, from as f32);
        rig.run_ms(1_000);
        rig.bench.write_value(REGDS_STEER_REQPOS, to as f32);
        let mut overshoot: f64 = 0.0;
        let at = settle(
            &mut || {
                rig.tick();
                overshoot = overshoot.max((rig.steer.angle - to) * (to - from).signum());
                rig.steer.angle
            },
            4_000,
            to,
            2.0,
        );
        let at = at.unwrap_or_else(|| panic!("{from} → {to}: ended at {}", rig.steer.angle));
        // 60°/s for 40-80°, then the leaky integrator's tail.
        assert!(at < 2_000, "{from} → {to}: settled after {at} ms");
        assert!(overshoot < 2.0, "{from} → {to}: overshoot {overshoot}");
        let measured = rig.bench.read_value(REGDS_STEER_ACTUALPOS);
        assert!(
            (f64::from(measured) - rig.steer.angle).abs() < 0.2,
            "{measured}"
        );
    }
}

#[test]
fn lift_steps_settle_within_2_degrees() {
    let mut rig = LlRig::calibrated();
    rig.bench.write_value(REGLL_ONE_REQPOS, 20.0);
    rig.bench.write_value(REGLL_TWO_REQPOS, -30.0);
    let mut pair = [None, None];
    for t in 0..4_000u32 {
        rig.tick();
        for (i, target) in [(0, 20.0), (1, -30.0)] {
            let ok = (rig.lifts[i].angle - target).abs() <= 2.0;
            pair[i] = if ok { pair[i].or(Some(t)) } else { None };
        }
    }
    // 20°/s: 1 s for 20°, 1.5 s for 30°, then the tail.
    let [one, two] = pair.map(|t| t.expect("settled"));
    assert!(one < 1_500, "ONE after {one} ms");
    assert!(two < 2_000, "TWO after {two} ms");
}

#[test]
fn drive_keeps_the_original_window_and_incremental_form() {
    let mut rig = DsRig::calibrated();
    rig.bench.write_value(REGDS_DRIVE_REQSPEED, 1000.0);
    // The first window closes on the first tick more than 150 ms after the first tick
    // (t = 1 ms): at t = 152 ms. The PID's first step is P·e = 0.0099·1000 ≈ 9.9 → 9.
    rig.run_ms(151);
    assert_eq!(rig.bench.last.unwrap().motors[0].duty(), 0);
    rig.run_ms(1);
    assert_eq!(rig.bench.last.unwrap().motors[0].duty(), 9);
    assert_eq!(
        rig.bench.read_value(REGDS_DRIVE_INTERVALCTRL).round(),
        151.0
    );
    // The duty only changes at window boundaries: every 151 ms from t = 152 ms (the first
    // tick more than 150 ms after the last window), and does change while the wheel
    // speeds up.
    let mut changes = Vec::new();
    let mut last = 9;
    for t in 153..153 + 1_510u32 {
        let duty = rig.tick().motors[0].duty();
        if duty != last {
            changes.push(t);
            last = duty;
        }
    }
    assert!(
        changes.iter().all(|t| (t - 152).is_multiple_of(151)),
        "changes at {changes:?} ms"
    );
    assert!(changes.len() >= 5, "changes at {changes:?} ms");
    rig.run_ms(8_000);
    let speed = rig.wheel.speed;
    assert!((speed - 1000.0).abs() < 20.0, "{speed}");
    let measured = rig.bench.read_value(REGDS_DRIVE_ACTUALSPEED);
    assert!(
        (f64::from(measured) - 1000.0).abs() < 15.0,
        "measured {measured}"
    );
}

#[test]
fn drive_stop_coasts_down_by_bleeding() {
    let mut rig = DsRig::calibrated();
    rig.bench.write_value(REGDS_DRIVE_REQSPEED, 1000.0);
    rig.run_ms(8_000);
    let duty = rig.bench.last.unwrap().motors[0].duty();
    // The emergency stop sends zero gains and a zero demand.
    rig.bench.write_value(REGDS_DRIVE_PGAIN, 0.0);
    rig.bench.write_value(REGDS_DRIVE_REQSPEED, 0.0);
    rig.run_ms(1_510);
    let after = rig.bench.last.unwrap().motors[0].duty();
    // Ten windows at ×0.96: 0.665 of the duty.
    let expected = f64::from(duty) * 0.96f64.powi(10);
    assert!(
        (f64::from(after) - expected).abs() <= 2.0,
        "{duty} → {after}"
    );
}

#[test]
fn fast_mode_updates_every_10_ms_from_edge_timing() {
    let mut rig = DsRig::calibrated();
    rig.bench.write(REGDS_DRIVE_MODE, 1);
    rig.bench.write_value(REGDS_DRIVE_PGAIN, 0.005);
    rig.bench.write_value(REGDS_DRIVE_REQSPEED, 1000.0);
    rig.run_ms(30);
    assert_eq!(rig.bench.core.drive_mode(), DriveMode::EdgeTiming);
    assert_eq!(rig.bench.read_value(REGDS_DRIVE_INTERVALCTRL).round(), 10.0);
    let at = settle(
        &mut || {
            rig.tick();
            rig.wheel.speed
        },
        2_000,
        1000.0,
        20.0,
    )
    .expect("settles");
    assert!(at < 1_000, "within 2 % after {at} ms");
    let measured = f64::from(rig.bench.read_value(REGDS_DRIVE_ACTUALSPEED));
    assert!(
        (measured - rig.wheel.speed).abs() < 10.0,
        "{measured} vs {}",
        rig.wheel.speed
    );
    // Back to the original mode.
    rig.bench.write(REGDS_DRIVE_MODE, 0);
    rig.run_ms(400);
    assert_eq!(rig.bench.core.drive_mode(), DriveMode::Window);
    let interval = rig.bench.read_value(REGDS_DRIVE_INTERVALCTRL).round();
    assert_eq!(interval, 151.0);
}

#[test]
fn fast_mode_measures_reverse_speed_and_rest() {
    let mut rig = DsRig::calibrated();
    rig.bench.write(REGDS_DRIVE_MODE, 1);
    rig.bench.write_value(REGDS_DRIVE_PGAIN, 0.005);
    rig.bench.write_value(REGDS_DRIVE_REQSPEED, -1500.0);
    rig.run_ms(2_000);
    let measured = f64::from(rig.bench.read_value(REGDS_DRIVE_ACTUALSPEED));
    assert!((measured + 1500.0).abs() < 30.0, "{measured}");
    // Held: the speed estimate falls to 0 within 100 ms of the last edge.
    rig.wheel.held = true;
    rig.run_ms(120);
    assert_eq!(rig.bench.read(REGDS_DRIVE_ACTUALSPEED), 0x7fff);
    assert!(rig.bench.core.motor(MotorId::M1).params.required < shared::pid::Fix::ZERO);
}

#[test]
fn monitoring_registers_follow_the_controller() {
    let mut rig = DsRig::calibrated();
    rig.bench.write_value(REGDS_STEER_REQPOS, 30.0);
    rig.run_ms(100);
    let error = rig.bench.read_value(REGDS_STEER_ERROR);
    let actual = rig.bench.read_value(REGDS_STEER_ACTUALPOS);
    assert!((error - (30.0 - actual)).abs() < 0.2, "{error} {actual}");
    let integral = rig.bench.read_value(REGDS_STEER_ERRORINTEGRAL);
    let control = rig.bench.read_value(REGDS_STEER_CONTROL);
    assert!((integral - 300.0).abs() < 0.1, "capped: {integral}");
    assert!((control - 255.0).abs() < 0.1, "{control}");
    // D is −Δangle per 2-ms update: about −60°/s × 2 ms = −0.12° while it turns.
    let deriv = rig.bench.read_value(REGDS_STEER_ERRORDERIV);
    assert!((deriv + 0.12).abs() < 0.05, "{deriv}");
}
