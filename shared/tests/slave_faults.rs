//! Stall and sensor-fault detection against small plants: normal motion raises nothing,
//! a blocked motor raises STALL, a dead encoder ENCODERFAULT, an open motor DRIVEFAULT;
//! STALLCHECK 255 and DISABLEDEXCEPTIONS switch it off; FAULTTIME sets the delay.

mod slave_support;

use shared::regs::id::*;
use shared::slave::{MotorId, MotorOutput, State};
use slave_support::{DsRig, LlRig};

/// A drive/steer rig after calibrate(), with the stall checks enabled at 120.
fn ds_rig() -> DsRig {
    let mut rig = DsRig::calibrated();
    rig.bench.write_value(REGDS_DRIVE_STALLCHECK, 120.0);
    rig.bench.write_value(REGDS_STEER_STALLCHECK, 120.0);
    rig.run_ms(700);
    assert!(matches!(rig.bench.core.state(), State::Running { .. }));
    rig
}

/// Runs `ms` ticks and returns the tick (from now) at which the slave entered an
/// exception, if it did.
fn run_until_exception(rig: &mut DsRig, ms: u32) -> Option<u32> {
    (0..ms).find(|_| {
        rig.tick();
        rig.bench.core.state().in_exception()
    })
}

/// Ticks (each call of `tick` one, giving motor 1's duty and whether the slave is in
/// an exception) for up to 3 s; returns the ms from the first duty above 120 to the
/// exception. Fails if either never comes.
fn ms_from_duty_120_to_exception(mut tick: impl FnMut() -> (u8, bool)) -> u32 {
    let mut first_high = None;
    for ms in 0..3_000u32 {
        let (duty, in_exception) = tick();
        if first_high.is_none() && duty > 120 {
            first_high = Some(ms);
        }
        if in_exception {
            let high = first_high.expect("an exception before the duty passed 120");
            return ms - high;
        }
    }
    panic!("no stall in 3 s (duty above 120 from {first_high:?} ms)");
}

fn assert_running(rig: &mut DsRig, what: &str) {
    assert!(
        !rig.bench.core.state().in_exception(),
        "{what}: {:?}, data {:#06x}",
        rig.bench.core.state(),
        rig.bench.read(REG_EXCEPTIONDATA)
    );
}

#[test]
fn a_speed_step_raises_nothing() {
    let mut rig = ds_rig();
    // 2500 ticks/s needs a duty of about 176, well above the 120 level.
    rig.bench.write_value(REGDS_DRIVE_REQSPEED, 2500.0);
    rig.run_ms(10_000);
    assert_running(&mut rig, "speed step");
    assert!(
        (rig.wheel.speed - 2500.0).abs() < 60.0,
        "{}",
        rig.wheel.speed
    );
    assert!(rig.bench.last.unwrap().motors[0].duty() > 150);
}

#[test]
fn a_reversal_raises_nothing() {
    let mut rig = ds_rig();
    rig.bench.write_value(REGDS_DRIVE_REQSPEED, 2500.0);
    rig.run_ms(8_000);
    rig.bench.write_value(REGDS_DRIVE_REQSPEED, -2500.0);
    rig.run_ms(12_000);
    assert_running(&mut rig, "reversal");
    assert!(
        (rig.wheel.speed + 2500.0).abs() < 60.0,
        "{}",
        rig.wheel.speed
    );
    let speed = rig.bench.read_value(REGDS_DRIVE_ACTUALSPEED);
    assert!((speed + 2500.0).abs() < 60.0, "measured {speed}");
}

#[test]
fn a_steer_sweep_raises_nothing() {
    let mut rig = ds_rig();
    for target in [40.0, -40.0, 20.0, -45.0, 0.0, 45.0] {
        rig.bench.write_value(REGDS_STEER_REQPOS, target);
        rig.run_ms(2_500);
        assert_running(&mut rig, "steer sweep");
        assert!((rig.steer.angle - f64::from(target)).abs() < 2.0);
    }
    // A slow ramp, 20 °/s: a demand every 50 ms.
    for step in 0..=80 {
        rig.bench
            .write_value(REGDS_STEER_REQPOS, 45.0 - step as f32);
        rig.run_ms(50);
    }
    assert_running(&mut rig, "steer ramp");
    let peak = rig.bench.peak_duty[1];
    assert!(peak > 120, "the check never looked: duty at most {peak}");
}

#[test]
fn a_held_wheel_raises_stall() {
    let mut rig = ds_rig();
    rig.wheel.held = true;
    rig.bench.write_value(REGDS_DRIVE_REQSPEED, 1000.0);
    // The duty grows by about 10 per 150-ms window: above 120 after some 1.8 s, then
    // 500 ms of no motion.
    let at = run_until_exception(&mut rig, 5_000).expect("a stall");
    assert!((2_000..3_000).contains(&at), "after {at} ms");
    assert_eq!(
        rig.bench.read(REG_EXCEPTIONDATA),
        0x0005,
        "STALL on motor 0"
    );
    assert_eq!(rig.bench.read(REG_STATUS), 0x0009);
    let out = rig.run_ms(1);
    assert_eq!(out.motors, [MotorOutput::Stop; 2]);
    assert!(out.leds.led1 && !out.leds.led2);
}

#[test]
fn a_held_steer_raises_stall_after_faulttime() {
    let mut rig = ds_rig();
    rig.steer.held = true;
    rig.bench.write_value(REGDS_STEER_REQPOS, 40.0);
    // Detected at the update that follows the duty rise, raised more than 500 ms later.
    let delay = ms_from_duty_120_to_exception(|| {
        let duty = rig.tick().motors[1].duty();
        (duty, rig.bench.core.state().in_exception())
    });
    assert!((501..=505).contains(&delay), "{delay} ms");
    assert_eq!(
        rig.bench.read(REG_EXCEPTIONDATA),
        0x0105,
        "STALL on motor 1"
    );
}

#[test]
fn faulttime_register_sets_the_delay() {
    let mut rig = ds_rig();
    rig.bench.write(REGDS_FAULTTIME, 2_000);
    rig.steer.held = true;
    rig.bench.write_value(REGDS_STEER_REQPOS, 40.0);
    let at = run_until_exception(&mut rig, 5_000).expect("a stall");
    assert!((2_000..2_200).contains(&at), "after {at} ms");
}

#[test]
fn a_dead_encoder_raises_encoder_fault() {
    let mut rig = ds_rig();
    rig.wheel.encoder_broken = true;
    rig.bench.write_value(REGDS_DRIVE_REQSPEED, 1000.0);
    run_until_exception(&mut rig, 5_000).expect("a fault");
    assert!(rig.wheel.speed > 1000.0, "the wheel ran away unseen");
    assert_eq!(rig.bench.read(REG_EXCEPTIONDATA), 0x0006);
}

#[test]
fn an_open_drive_raises_drive_fault() {
    let mut rig = ds_rig();
    rig.wheel.open_circuit = true;
    rig.bench.write_value(REGDS_DRIVE_REQSPEED, 1000.0);
    run_until_exception(&mut rig, 5_000).expect("a fault");
    assert_eq!(rig.bench.read(REG_EXCEPTIONDATA), 0x0007);
}

#[test]
fn stallcheck_255_disables_the_check() {
    let mut rig = ds_rig();
    rig.bench.write_value(REGDS_STEER_STALLCHECK, 255.0);
    rig.steer.held = true;
    rig.bench.write_value(REGDS_STEER_REQPOS, 40.0);
    assert_eq!(run_until_exception(&mut rig, 5_000), None);
    assert_eq!(
        rig.bench.last.unwrap().motors[1].duty(),
        255,
        "full duty, held"
    );
}

#[test]
fn disabled_stall_type_is_not_raised() {
    let mut rig = ds_rig();
    rig.bench.write(REG_DISABLEDEXCEPTIONS, 1 << 5);
    rig.steer.held = true;
    rig.bench.write_value(REGDS_STEER_REQPOS, 40.0);
    assert_eq!(run_until_exception(&mut rig, 3_000), None);
    // The held steer ran at full duty all along, far past its STALLCHECK: only the mask
    // kept the stall from being raised, and the status shows the board running.
    assert_eq!(rig.bench.peak_duty[1], 255);
    assert_eq!(rig.bench.last.unwrap().motors[1].duty(), 255);
    assert_eq!(rig.bench.read(REG_STATUS), 0x0008);
    // The check kept watching while the type was masked: unmasked, the stall (3 s old by
    // now, past the 500-ms filter) is raised within a few updates.
    rig.bench.write(REG_DISABLEDEXCEPTIONS, 0);
    let at = run_until_exception(&mut rig, 3_000).expect("a stall once unmasked");
    assert!(at <= 50, "after {at} ms");
    assert_eq!(
        rig.bench.read(REG_EXCEPTIONDATA),
        0x0105,
        "STALL on motor 1"
    );
}

#[test]
fn power_on_level_is_120() {
    // A P gain written but STALLCHECK never: the power-on 120 applies (the register reads
    // 0x77, 119.47, so this tells 120 from what a read-back would suggest).
    let mut rig = DsRig::new();
    rig.bench.write_value(REGDS_STEER_PGAIN, 3.0);
    rig.bench.write_value(REGDS_STEER_CALIBMIN, -56.0);
    rig.bench.write_value(REGDS_STEER_CALIBMAX, 66.0);
    rig.bench.write(REG_RESET, 1);
    rig.run_ms(10);
    rig.steer.held = true;
    // The demand creeps up 0.005° a ms from 35°, so the duty P·e passes 119, 120 and 121
    // several ms apart.
    let (mut above_119, mut above_120, mut raised) = (None, None, None);
    for ms in 0..3_000u16 {
        let demand = 35.0 + f32::from(ms) * 0.005;
        rig.bench.write_value(REGDS_STEER_REQPOS, demand);
        let duty = rig.tick().motors[1].duty();
        if above_119.is_none() && duty > 119 {
            above_119 = Some(ms);
        }
        if above_120.is_none() && duty > 120 {
            above_120 = Some(ms);
        }
        if rig.bench.core.state().in_exception() {
            raised = Some(ms);
            break;
        }
    }
    let (a119, a120) = (above_119.expect("duty 120"), above_120.expect("duty 121"));
    let raised = raised.expect("a stall");
    assert!(
        a120 >= a119 + 10,
        "120 reached at {a119} ms, 121 at {a120} ms"
    );
    // Suspect from the first duty above 120, raised 500 ms later.
    let delay = raised - a120;
    assert!((501..=505).contains(&delay), "{delay} ms after duty 121");
    assert_eq!(rig.bench.read(REG_EXCEPTIONDATA), 0x0105);
}

#[test]
fn a_held_lift_raises_stall_and_the_other_lift_moves_on() {
    let mut rig = LlRig::calibrated();
    rig.bench.write_value(REGLL_ONE_STALLCHECK, 120.0);
    rig.bench.write_value(REGLL_TWO_STALLCHECK, 120.0);
    rig.run_ms(10);
    rig.lifts[1].held = true;
    rig.bench.write_value(REGLL_ONE_REQPOS, 20.0);
    rig.bench.write_value(REGLL_TWO_REQPOS, 20.0);
    // As the steer's: raised FAULTTIME (500 ms) after the duty rose past STALLCHECK.
    let delay = ms_from_duty_120_to_exception(|| {
        let duty = rig.tick().motors[1].duty();
        (duty, rig.bench.core.state().in_exception())
    });
    assert!((501..=505).contains(&delay), "{delay} ms");
    assert_eq!(rig.bench.read(REG_EXCEPTIONDATA), 0x0105);
    assert!(
        rig.lifts[0].angle > 5.0,
        "ONE was moving: {}",
        rig.lifts[0].angle
    );
    assert!(rig.bench.core.motor(MotorId::M2).current_level() > 50);
}

#[test]
fn a_lift_step_raises_nothing() {
    let mut rig = LlRig::calibrated();
    rig.bench.write_value(REGLL_ONE_STALLCHECK, 120.0);
    rig.bench.write_value(REGLL_TWO_STALLCHECK, 120.0);
    rig.bench.write_value(REGLL_ONE_REQPOS, 30.0);
    rig.bench.write_value(REGLL_TWO_REQPOS, -30.0);
    rig.run_ms(5_000);
    assert!(!rig.bench.core.state().in_exception());
    assert!((rig.lifts[0].angle - 30.0).abs() < 2.0);
    assert!((rig.lifts[1].angle + 30.0).abs() < 2.0);
    let peak = rig.bench.peak_duty;
    assert!(peak.iter().all(|&d| d > 120), "duty at most {peak:?}");
}
