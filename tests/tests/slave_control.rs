//! Emulator tests of both slave images closing their control loops over the physics
//! model: a drive speed step, a steer step and a lift step, each with the gains and
//! calibration that the PC library's calibrate() sends (reference §8.3), written as the
//! register values of its frames.

mod slave_support;

use physics::wheel::SlaveBoardModel;

use shared::regs::id;
use slave_support::{rig, Rig, DRIVE_GAINS, LIFT_GAINS_WHEEL_1, STEER_GAINS_WHEEL_1};

fn send(r: &mut Rig, block: &[(u8, u16)]) {
    for &(reg, raw) in block {
        r.write_raw(reg, raw);
    }
}

/// Samples `reg` every `period_ms` for `total_ms`, returning (ms, value).
fn trace(r: &mut Rig, reg: u8, period_ms: u64, total_ms: u64) -> Vec<(u64, f32)> {
    let mut out = Vec::new();
    let mut t = 0;
    while t < total_ms {
        r.run_us(period_ms * 1_000);
        t += period_ms;
        out.push((t, r.read_value(reg)));
    }
    out
}

/// The time from which every sample stays within `band` of `target`, if any.
fn settled_from(samples: &[(u64, f32)], target: f32, band: f32) -> Option<u64> {
    let last_out = samples
        .iter()
        .rposition(|&(_, v)| (v - target).abs() > band);
    match last_out {
        None => samples.first().map(|s| s.0),
        Some(i) if i + 1 < samples.len() => Some(samples[i + 1].0),
        Some(_) => None,
    }
}

#[test]
fn drive_steps_to_1000_ticks_per_second() {
    let mut r = rig(1);
    r.run_us(2_000);
    r.reset_exceptions();
    send(&mut r, DRIVE_GAINS);
    r.write_value(id::REGDS_DRIVE_REQSPEED, 1000.0);
    let samples = trace(&mut r, id::REGDS_DRIVE_ACTUALSPEED, 150, 6_000);
    let settled = settled_from(&samples, 1000.0, 50.0);
    println!("drive step: {samples:?}");
    let at = settled.unwrap_or_else(|| panic!("not settled: {samples:?}"));
    assert!(at <= 5_000, "settled only at {at} ms");
    // The physics agrees: the wheel turns at the speed the slave reports.
    let model = r
        .plant
        .model(r.chip)
        .unwrap()
        .ds()
        .unwrap()
        .drive
        .ticks_per_s();
    assert!((model - 1000.0).abs() < 50.0, "model at {model} ticks/s");
    assert_eq!(
        r.read_raw(id::REG_STATUS),
        0x0008,
        "no exception on the way"
    );
}

/// A position step as a PC program makes it: reset, calibrate()'s `gains`, REQPOS
/// `target`; the board's ACTUALPOS must settle within 2 degrees by 4 s, the model's
/// `angle` be within 2.5 degrees of it, and STATUS read `status` (no exception).
fn position_step(
    controller: u8,
    gains: &[(u8, u16)],
    (req, actual): (u8, u8),
    target: f32,
    status: u16,
    angle: fn(&SlaveBoardModel) -> Option<f64>,
) {
    let mut r = rig(controller);
    r.run_us(2_000);
    r.reset_exceptions();
    send(&mut r, gains);
    r.write_value(req, target);
    let samples = trace(&mut r, actual, 100, 5_000);
    println!("position step: {samples:?}");
    let at =
        settled_from(&samples, target, 2.0).unwrap_or_else(|| panic!("not settled: {samples:?}"));
    assert!(at <= 4_000, "settled only at {at} ms");
    let model = r.plant.model(r.chip).and_then(angle).unwrap();
    assert!((model - f64::from(target)).abs() < 2.5, "model at {model}°");
    assert_eq!(r.read_raw(id::REG_STATUS), status);
}

#[test]
fn steer_steps_to_40_degrees() {
    let regs = (id::REGDS_STEER_REQPOS, id::REGDS_STEER_ACTUALPOS);
    position_step(1, STEER_GAINS_WHEEL_1, regs, 40.0, 0x0008, |m| {
        m.ds().map(|d| d.steer.motor.angle_deg())
    });
}

#[test]
fn lift_steps_to_30_degrees() {
    let regs = (id::REGLL_ONE_REQPOS, id::REGLL_ONE_ACTUALPOS);
    position_step(3, LIFT_GAINS_WHEEL_1, regs, 30.0, 0x0004, |m| {
        m.ll().map(|l| l.one.motor.angle_deg())
    });
}
