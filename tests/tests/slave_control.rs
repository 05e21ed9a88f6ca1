//! Emulator tests of both slave images closing their control loops over the physics
//! model: a drive speed step, a steer step and a lift step, each with the gains and
//! calibration that the PC library's calibrate() sends (reference §8.3), written as the
//! register values of its frames.

mod slave_support;

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

#[test]
fn steer_steps_to_40_degrees() {
    let mut r = rig(1);
    r.run_us(2_000);
    r.reset_exceptions();
    send(&mut r, STEER_GAINS_WHEEL_1);
    r.write_value(id::REGDS_STEER_REQPOS, 40.0);
    let samples = trace(&mut r, id::REGDS_STEER_ACTUALPOS, 100, 5_000);
    println!("steer step: {samples:?}");
    let at =
        settled_from(&samples, 40.0, 2.0).unwrap_or_else(|| panic!("not settled: {samples:?}"));
    assert!(at <= 4_000, "settled only at {at} ms");
    let model = r
        .plant
        .model(r.chip)
        .unwrap()
        .ds()
        .unwrap()
        .steer
        .motor
        .angle_deg();
    assert!((model - 40.0).abs() < 2.5, "model at {model}°");
    assert_eq!(r.read_raw(id::REG_STATUS), 0x0008);
}

#[test]
fn lift_steps_to_30_degrees() {
    let mut r = rig(3);
    r.run_us(2_000);
    r.reset_exceptions();
    send(&mut r, LIFT_GAINS_WHEEL_1);
    r.write_value(id::REGLL_ONE_REQPOS, 30.0);
    let samples = trace(&mut r, id::REGLL_ONE_ACTUALPOS, 100, 5_000);
    println!("lift step: {samples:?}");
    let at =
        settled_from(&samples, 30.0, 2.0).unwrap_or_else(|| panic!("not settled: {samples:?}"));
    assert!(at <= 4_000, "settled only at {at} ms");
    let model = r
        .plant
        .model(r.chip)
        .unwrap()
        .ll()
        .unwrap()
        .one
        .motor
        .angle_deg();
    assert!((model - 30.0).abs() < 2.5, "model at {model}°");
    assert_eq!(r.read_raw(id::REG_STATUS), 0x0004);
}
