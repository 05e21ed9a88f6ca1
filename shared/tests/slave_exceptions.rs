//! The slave's exception handling (reference §6, the manual's figure 12): every
//! transition of the state machine, then the same through the register file and the
//! tick (STATUS, EXCEPTIONDATA, RESET, motor outputs, E15).

mod slave_support;

use shared::exception::ExceptionType;
use shared::pid::{Direction, Duty, Fix};
use shared::regs::id::*;
use shared::slave::state::{Event, ResetBits, Transition, NO_MOTOR};
use shared::slave::{
    AdcSample, Cause, Inputs, LocalFault, MotorId, MotorOutput, State, Variant, Watchdog,
};
use slave_support::{Bench, DsRig, LlRig};

const NONE: u16 = 0;
const STALL_M2: Event = Event::Fault {
    fault: LocalFault::Stall,
    motor: MotorId::M2,
};
const OC_M1: Event = Event::Fault {
    fault: LocalFault::Overcurrent,
    motor: MotorId::M1,
};

fn local(fault: LocalFault, motor: MotorId) -> Cause {
    Cause::Local { fault, motor }
}

fn running() -> State {
    State::Running { last: Cause::Boot }
}

// ---------------------------------------------------------------------------------------
// The state machine, transition by transition.
// ---------------------------------------------------------------------------------------

#[test]
fn power_up_is_the_boot_exception() {
    let s = State::POWER_UP;
    assert_eq!(s, State::Exception(Cause::Boot));
    assert!(s.in_exception());
    assert_eq!(s.data(), 0x0502);
}

#[test]
fn leave_takes_boot_to_running_and_keeps_the_data() {
    let mut s = State::POWER_UP;
    assert_eq!(s.handle(Event::Leave, NONE), Transition::Left);
    assert_eq!(s, running());
    assert!(!s.in_exception());
    assert_eq!(s.data(), 0x0502, "EXCEPTIONDATA keeps the last type");
}

#[test]
fn leave_while_running_changes_nothing() {
    let mut s = running();
    assert_eq!(s.handle(Event::Leave, NONE), Transition::Unchanged);
    assert_eq!(s, running());
}

#[test]
fn a_local_fault_while_running_enters_its_exception() {
    let mut s = running();
    let t = s.handle(STALL_M2, NONE);
    assert_eq!(
        t,
        Transition::Entered(local(LocalFault::Stall, MotorId::M2))
    );
    assert_eq!(s, State::Exception(local(LocalFault::Stall, MotorId::M2)));
    assert_eq!(s.data(), 0x0105);
    let mut s = running();
    s.handle(OC_M1, NONE);
    assert_eq!(s.data(), 0x0001);
    for (fault, code) in [
        (LocalFault::Overcurrent, 1),
        (LocalFault::Stall, 5),
        (LocalFault::EncoderFault, 6),
        (LocalFault::DriveFault, 7),
        (LocalFault::ShortOc, 8),
    ] {
        let mut s = running();
        s.handle(
            Event::Fault {
                fault,
                motor: MotorId::M1,
            },
            NONE,
        );
        assert_eq!(s.data(), code, "{fault:?}");
        assert_eq!(fault.kind().code(), code as u8);
    }
}

#[test]
fn a_remote_write_while_running_enters_remote_with_no_motor() {
    let mut s = running();
    assert_eq!(
        s.handle(Event::RemoteWrite, NONE),
        Transition::Entered(Cause::Remote)
    );
    assert_eq!(s.data(), 0x0503);
    assert_eq!(NO_MOTOR, 5);
    assert_eq!(Cause::Remote.kind(), ExceptionType::RemoteSlave);
}

#[test]
fn only_the_first_exception_is_latched() {
    for first in [STALL_M2, Event::RemoteWrite] {
        let mut s = running();
        s.handle(first, NONE);
        let latched = s;
        for later in [OC_M1, Event::RemoteWrite, STALL_M2] {
            assert_eq!(s.handle(later, NONE), Transition::Unchanged);
            assert_eq!(s, latched);
        }
    }
    // Boot is an exception too: nothing else is latched over it.
    let mut s = State::POWER_UP;
    assert_eq!(s.handle(OC_M1, NONE), Transition::Unchanged);
    assert_eq!(s.handle(Event::RemoteWrite, NONE), Transition::Unchanged);
    assert_eq!(s, State::POWER_UP);
}

#[test]
fn leave_takes_any_exception_back_to_running_with_its_data() {
    for (event, data) in [(STALL_M2, 0x0105), (Event::RemoteWrite, 0x0503)] {
        let mut s = running();
        s.handle(event, NONE);
        assert_eq!(s.handle(Event::Leave, NONE), Transition::Left);
        assert!(!s.in_exception());
        assert_eq!(s.data(), data);
        // And a new exception can be raised again.
        assert!(matches!(s.handle(OC_M1, NONE), Transition::Entered(_)));
    }
}

#[test]
fn disabled_types_are_never_raised() {
    let mut s = running();
    let stall_bit = 1 << 5;
    assert_eq!(s.handle(STALL_M2, stall_bit), Transition::Masked);
    assert_eq!(s, running());
    // Another type is not masked by that bit.
    assert!(matches!(s.handle(OC_M1, stall_bit), Transition::Entered(_)));
    let mut s = running();
    assert_eq!(s.handle(Event::RemoteWrite, 1 << 3), Transition::Masked);
    assert_eq!(s, running());
    // The mask does not clear a current exception.
    let mut s = running();
    s.handle(STALL_M2, NONE);
    assert_eq!(s.handle(Event::Leave, 0xffff), Transition::Left);
}

#[test]
fn hard_reset_from_any_state_restarts_and_then_nothing_moves_it() {
    let mut exception = running();
    exception.handle(STALL_M2, NONE);
    for mut s in [State::POWER_UP, running(), exception] {
        let data = s.data();
        assert_eq!(s.handle(Event::HardReset, NONE), Transition::Restart);
        assert!(matches!(s, State::Restarting { .. }));
        assert!(s.in_exception());
        assert_eq!(s.data(), data);
        for e in [Event::Leave, Event::RemoteWrite, OC_M1, Event::HardReset] {
            assert_eq!(s.handle(e, NONE), Transition::Unchanged);
        }
    }
}

#[test]
fn reset_bits_in_the_original_order() {
    // Hard reset first; nothing after it runs.
    assert_eq!(ResetBits(2).event(), Some(Event::HardReset));
    assert_eq!(ResetBits(3).event(), Some(Event::HardReset));
    assert!(!ResetBits(6).zero_odometer());
    assert!(!ResetBits(7).zero_odometer());
    // Otherwise leave, then zero the odometer.
    assert_eq!(ResetBits(1).event(), Some(Event::Leave));
    assert_eq!(ResetBits(5).event(), Some(Event::Leave));
    assert!(ResetBits(5).zero_odometer());
    assert_eq!(ResetBits(4).event(), None);
    assert!(ResetBits(4).zero_odometer());
    assert_eq!(ResetBits(0).event(), None);
    assert_eq!(ResetBits(8).event(), None, "other bits do nothing");
}

// ---------------------------------------------------------------------------------------
// Through the registers and the tick.
// ---------------------------------------------------------------------------------------

fn with_current(m1: u16, m2: u16) -> Inputs {
    Inputs {
        adc: AdcSample {
            current: [m1, m2],
            current_peak: [m1, m2],
            ch6: 512,
            ch7: 512,
        },
        ..Default::default()
    }
}

#[test]
fn boot_exception_on_the_bus_pins_forward_duty_zero() {
    let mut bench = Bench::new(Variant::DriveSteer);
    let out = bench.tick(&Inputs::default());
    assert_eq!(out.motors, [MotorOutput::BOOT; 2]);
    assert_eq!(MotorOutput::BOOT.pins(), (true, false));
    assert_eq!(MotorOutput::BOOT.duty(), 0);
    assert_eq!(out.watchdog, Watchdog::Feed);
    assert_eq!(bench.read(REG_STATUS), 0x0009);
    assert_eq!(bench.read(REG_EXCEPTIONDATA), 0x0502);
    // Overcurrent is not latched over boot.
    bench.ticks(5, &with_current(1000, 1000));
    assert_eq!(bench.read(REG_EXCEPTIONDATA), 0x0502);
}

#[test]
fn reset_1_leaves_boot_and_reads_back_0() {
    let mut bench = Bench::new(Variant::LiftLift);
    bench.tick(&Inputs::default());
    bench.write(REG_RESET, 1);
    assert_eq!(bench.read(REG_RESET), 1, "until the tick processes it");
    bench.tick(&Inputs::default());
    assert_eq!(bench.read(REG_RESET), 0);
    assert_eq!(bench.read(REG_STATUS), 0x0004);
    assert_eq!(bench.read(REG_EXCEPTIONDATA), 0x0502);
    assert_eq!(bench.core.state(), running());
}

#[test]
fn overcurrent_at_high_duty_and_short_at_low_duty() {
    // Drive P 10 and a 100 ticks/s demand: the first window asks for full duty.
    let mut bench = Bench::running(Variant::DriveSteer);
    bench.write_value(REGDS_DRIVE_PGAIN, 10.0);
    bench.write_value(REGDS_DRIVE_REQSPEED, 100.0);
    let out = bench.ticks(600, &with_current(0, 0));
    assert_eq!(out.motors[0].duty(), 255);
    // 301 > 300 (the power-on threshold) at duty 255.
    let out = bench.tick(&with_current(301, 0));
    assert_eq!(out.motors, [MotorOutput::Stop; 2]);
    assert_eq!(bench.read(REG_EXCEPTIONDATA), 0x0001);
    assert_eq!(bench.read(REG_STATUS), 0x0009);
    assert!(out.leds.led1 && !out.leds.led2, "M1 → LED1");
    // At duty 0 it is a short: every_motor_trips_above_the_power_on_300….
}

#[test]
fn overcurrent_sees_the_peak_between_ticks() {
    let mut bench = Bench::running(Variant::LiftLift);
    let mut inputs = with_current(10, 10);
    inputs.adc.current_peak = [10, 900];
    bench.tick(&inputs);
    assert_eq!(
        bench.core.state(),
        State::Exception(local(LocalFault::ShortOc, MotorId::M2))
    );
}

#[test]
fn the_threshold_register_sets_the_level() {
    let mut bench = Bench::running(Variant::LiftLift);
    bench.write_value(REGLL_TWO_OVERCURRENTTHRESH, 500.0);
    bench.tick(&with_current(0, 0));
    bench.ticks(3, &with_current(200, 500));
    assert_eq!(bench.core.state(), running());
    bench.tick(&with_current(200, 501));
    assert_eq!(bench.read(REG_EXCEPTIONDATA), 0x0108);
}

#[test]
fn every_motor_trips_above_the_power_on_300_whatever_its_register_reads() {
    // (variant, its threshold register and what it reads at power-up, the sample on M1
    // and M2, EXCEPTIONDATA: SHORTOC at duty 0, with the motor in the high byte). The
    // drive's register shows 300 (300/1000 of 65,535); the others read 0 until written
    // (reference §8.1) but hold 300 all the same.
    let (ll, ds, m1, m2) = (Variant::LiftLift, Variant::DriveSteer, [1, 0], [0, 1]);
    let cases = [
        (ll, REGLL_ONE_OVERCURRENTTHRESH, 0, m1, 0x0008),
        (ll, REGLL_TWO_OVERCURRENTTHRESH, 0, m2, 0x0108),
        (ds, REGDS_DRIVE_OVERCURRENTTHRESH, 19_660, m1, 0x0008),
        (ds, REGDS_STEER_OVERCURRENTTHRESH, 0, m2, 0x0108),
    ];
    for (variant, register, reads, on, code) in cases {
        let mut bench = Bench::running(variant);
        assert_eq!(bench.read(register), reads, "{variant:?} {register}");
        bench.tick(&with_current(300 * on[0], 300 * on[1]));
        assert_eq!(bench.core.state(), running(), "{variant:?} {register}: 300");
        bench.tick(&with_current(301 * on[0], 301 * on[1]));
        let data = bench.read(REG_EXCEPTIONDATA);
        assert_eq!(data, code, "{variant:?} {register}: 301");
    }
}

#[test]
fn disabled_exceptions_register_masks_types() {
    let mut bench = Bench::running(Variant::DriveSteer);
    bench.write(REG_DISABLEDEXCEPTIONS, (1 << 8) | (1 << 3));
    bench.tick(&with_current(0, 0));
    bench.ticks(3, &with_current(1000, 1000));
    assert_eq!(bench.core.state(), running(), "SHORTOC masked");
    bench.write(REG_EXCEPTIONDATA, 0);
    bench.tick(&with_current(0, 0));
    assert_eq!(bench.core.state(), running(), "REMOTESLAVE masked");
    bench.write(REG_DISABLEDEXCEPTIONS, 0);
    bench.tick(&with_current(1000, 0));
    assert_eq!(bench.read(REG_EXCEPTIONDATA), 0x0008);
}

#[test]
fn any_write_to_exception_data_raises_remote() {
    for value in [0u16, 100, 0xffff] {
        let mut bench = Bench::running(Variant::DriveSteer);
        bench.ticks(600, &Inputs::default()); // past the address display
        bench.write(REG_EXCEPTIONDATA, value);
        let out = bench.tick(&Inputs::default());
        assert_eq!(bench.read(REG_EXCEPTIONDATA), 0x0503, "wrote {value:#x}");
        assert_eq!(bench.read(REG_STATUS), 0x0009);
        assert_eq!(out.motors, [MotorOutput::Stop; 2]);
        assert!(out.leds.led1 && out.leds.led2, "no motor: both LEDs");
    }
}

#[test]
fn reset_clears_a_remote_exception_and_the_data_stays() {
    let mut bench = Bench::running(Variant::LiftLift);
    bench.write(REG_EXCEPTIONDATA, 100);
    bench.tick(&Inputs::default());
    bench.write(REG_RESET, 1);
    let out = bench.tick(&Inputs::default());
    assert_eq!(bench.read(REG_STATUS), 0x0004);
    assert_eq!(bench.read(REG_EXCEPTIONDATA), 0x0503);
    assert!(matches!(out.motors[0], MotorOutput::Drive(_)));
}

#[test]
fn a_reset_and_a_remote_write_in_one_tick_apply_in_id_order() {
    let mut bench = Bench::new(Variant::DriveSteer);
    bench.tick(&Inputs::default());
    bench.write(REG_EXCEPTIONDATA, 100);
    bench.write(REG_RESET, 1);
    bench.tick(&Inputs::default());
    // RESET (id 0) first leaves boot, then EXCEPTIONDATA (id 5) raises REMOTE.
    assert_eq!(bench.core.state(), State::Exception(Cause::Remote));
}

#[test]
fn hard_reset_stops_the_motors_and_lets_the_watchdog_fire() {
    let mut bench = Bench::running(Variant::DriveSteer);
    bench.write(REG_RESET, 2 | 4);
    let inputs = Inputs {
        edges: shared::slave::EdgeSample {
            rising: 512,
            b_high: 0,
            last_edge: 0,
        },
        ..Default::default()
    };
    let out = bench.tick(&inputs);
    assert_eq!(out.watchdog, Watchdog::Reset);
    assert_eq!(out.motors, [MotorOutput::Stop; 2]);
    assert_eq!(bench.read(REG_RESET), 0);
    // Every later tick too, whatever is written.
    bench.write(REG_RESET, 1);
    let out = bench.tick(&Inputs::default());
    assert_eq!(out.watchdog, Watchdog::Reset);
}

#[test]
fn exception_stops_motors_but_writes_are_applied() {
    let mut bench = Bench::running(Variant::DriveSteer);
    bench.write(REG_EXCEPTIONDATA, 0);
    bench.tick(&Inputs::default());
    bench.write_value(REGDS_STEER_PGAIN, 5.0);
    bench.write_value(REGDS_STEER_CALIBMIN, -100.0);
    // The pot reads 0, that is -100°, against a demand of 0: out of exception the steer
    // would be at full duty within these ticks (its update comes every 2 ms).
    let out = bench.ticks(5, &Inputs::default());
    assert_eq!(out.motors, [MotorOutput::Stop; 2]);
    let steer = bench.core.motor(MotorId::M2);
    // 5 travels as raw 3276, which stands for 4.99893.
    assert!((steer.params.gains.p.to_num::<f64>() - 4.99893).abs() < 1e-4);
    assert!((steer.params.calibration.min().to_num::<f64>() + 100.157).abs() < 1e-2);
    assert_eq!(bench.read(REGDS_STEER_PGAIN), 3276);
}

/// E15: the control loop runs in exception but its output is not applied, and demands
/// written meanwhile are lost: after the reset the steer holds where it is and the drive
/// aims for 0.
#[test]
fn demands_written_in_exception_are_overwritten() {
    let mut rig = DsRig::calibrated();
    rig.run_ms(10);
    rig.bench.write(REG_EXCEPTIONDATA, 100);
    rig.run_ms(10);
    rig.bench.write_value(REGDS_STEER_REQPOS, 40.0);
    rig.bench.write_value(REGDS_DRIVE_REQSPEED, 1000.0);
    let out = rig.run_ms(500);
    assert_eq!(out.motors, [MotorOutput::Stop; 2]);
    assert_eq!(rig.bench.read(REGDS_STEER_REQPOS), 0x9998, "raw value kept");
    let steer = rig.bench.core.motor(MotorId::M2);
    assert_eq!(
        steer.params.required,
        steer.params.calibration.angle(rig.steer.reading())
    );
    assert_eq!(rig.bench.core.motor(MotorId::M1).params.required, Fix::ZERO);
    let before = rig.steer.angle;
    rig.bench.write(REG_RESET, 1);
    rig.run_ms(2000);
    assert!(
        (rig.steer.angle - before).abs() < 1.0,
        "{} → {}",
        before,
        rig.steer.angle
    );
    assert!(rig.wheel.speed.abs() < 1.0);
    // A demand written after the reset is followed.
    rig.bench.write_value(REGDS_STEER_REQPOS, 40.0);
    rig.run_ms(3000);
    assert!((rig.steer.angle - 40.0).abs() < 2.0, "{}", rig.steer.angle);
}

/// A demand written in exception is gone after the reset even when no control update
/// came between them (a drive updates every 150 ms, a position motor every 2 ms): the
/// board drops both demands as it leaves the exception. One written after the reset is
/// kept.
#[test]
fn a_demand_written_just_before_the_reset_is_dropped_too() {
    let mut rig = DsRig::calibrated();
    rig.run_ms(10);
    rig.bench.write(REG_EXCEPTIONDATA, 100);
    rig.run_ms(300);
    rig.bench.write_value(REGDS_DRIVE_REQSPEED, 1000.0);
    rig.bench.write_value(REGDS_STEER_REQPOS, 40.0);
    // Applied in exception, then the reset at the next tick: no drive update between.
    rig.tick();
    let drive = rig.bench.core.motor(MotorId::M1);
    assert!(
        drive.params.required > Fix::from_num(999),
        "taken in exception"
    );
    rig.bench.write(REG_RESET, 1);
    rig.tick();
    assert_eq!(rig.bench.read(REG_STATUS) & 1, 0, "out of exception");
    assert_eq!(rig.bench.core.motor(MotorId::M1).params.required, Fix::ZERO);
    let steer = rig.bench.core.motor(MotorId::M2);
    // Its angle: the steer stood still through the exception.
    assert_eq!(
        steer.params.required,
        steer.params.calibration.angle(rig.steer.reading())
    );
    let before = rig.steer.angle;
    rig.run_ms(2000);
    assert!(rig.wheel.speed.abs() < 1.0, "{}", rig.wheel.speed);
    assert!(
        (rig.steer.angle - before).abs() < 1.0,
        "{before} → {}",
        rig.steer.angle
    );
    // The same demands written after the reset are followed.
    rig.bench.write_value(REGDS_DRIVE_REQSPEED, 1000.0);
    rig.bench.write_value(REGDS_STEER_REQPOS, 40.0);
    rig.run_ms(3000);
    assert!((rig.steer.angle - 40.0).abs() < 2.0, "{}", rig.steer.angle);
    assert!(rig.wheel.speed > 900.0, "{}", rig.wheel.speed);
}

/// A drive leaves its exception from zero output: the speed controller's running output
/// (reference §7.1: never reset in the original, so a drive stopped at full duty resumed
/// at it after the reset, decaying ×0.96 a window with no demand) and its integral start
/// again from 0, so nothing reaches the motor until a demand does. A steer's integral
/// restarts too, so it holds exactly where it stands.
#[test]
fn a_drive_leaves_its_exception_from_zero_output() {
    let mut rig = DsRig::calibrated();
    rig.bench.write_value(REGDS_DRIVE_REQSPEED, 1000.0);
    rig.run_ms(3000);
    assert!(rig.wheel.speed > 900.0, "{}", rig.wheel.speed);
    let driving = rig.bench.core.motor(MotorId::M1).pid().control();
    assert!(driving > Fix::from_num(50), "{driving}");
    // The steer on its way to 40° (an I-only controller): its integral is built up.
    rig.bench.write_value(REGDS_STEER_REQPOS, 40.0);
    rig.run_ms(100);
    let steering = rig.bench.core.motor(MotorId::M2).pid().integral();
    assert!(steering > Fix::from_num(100), "{steering}");
    rig.bench.write(REG_EXCEPTIONDATA, 100);
    rig.run_ms(50);
    // Held in exception, the integral only decays (e is 0): still there at the reset.
    let held = rig.bench.core.motor(MotorId::M2).pid().integral();
    assert!(held > Fix::from_num(1), "{held}");
    rig.bench.write(REG_RESET, 1);
    let out = rig.tick();
    assert_eq!(rig.bench.read(REG_STATUS) & 1, 0, "out of exception");
    let drive = rig.bench.core.motor(MotorId::M1);
    assert_eq!(drive.pid().control(), Fix::ZERO);
    assert_eq!(out.motors[0].duty(), 0);
    let steer = rig.bench.core.motor(MotorId::M2);
    assert_eq!(steer.pid().integral(), Fix::ZERO);
    assert_eq!(out.motors[1].duty(), 0, "the steer holds where it stands");
    // Through its next updates too: the wheel coasts on, the controller aims for 0 and
    // pushes against the roll at most (never forward).
    for _ in 0..600 {
        let out = rig.tick();
        assert!(
            matches!(out.motors[0], MotorOutput::Drive(d) if d.magnitude == 0 || d.direction == Direction::Reverse),
            "{:?}",
            out.motors[0]
        );
    }
}

/// The same on a lift board: a lift stopped by an exception on its way comes back out of
/// it holding where it stands, not pushed on by the integral it had built.
#[test]
fn a_lift_leaves_its_exception_from_zero_output() {
    let mut rig = LlRig::calibrated();
    rig.bench.write_value(REGLL_ONE_REQPOS, 60.0);
    rig.bench.write_value(REGLL_TWO_REQPOS, -60.0);
    rig.run_ms(100);
    for m in [MotorId::M1, MotorId::M2] {
        let built = rig.bench.core.motor(m).pid().integral().abs();
        assert!(built > Fix::from_num(10), "{m:?}: {built}");
    }
    rig.bench.write(REG_EXCEPTIONDATA, 100);
    rig.run_ms(5);
    rig.bench.write(REG_RESET, 1);
    let out = rig.tick();
    assert_eq!(rig.bench.read(REG_STATUS) & 1, 0, "out of exception");
    for (i, m) in [MotorId::M1, MotorId::M2].into_iter().enumerate() {
        assert_eq!(rig.bench.core.motor(m).pid().integral(), Fix::ZERO, "{m:?}");
        assert_eq!(out.motors[i].duty(), 0, "{m:?}");
    }
}

#[test]
fn control_keeps_the_last_applied_duty_in_exception() {
    let mut rig = LlRig::calibrated();
    rig.bench.write_value(REGLL_ONE_REQPOS, 60.0);
    rig.run_ms(300);
    let applied = rig.bench.read_value(REGLL_ONE_CONTROL);
    assert!(applied > 100.0, "{applied}");
    rig.bench.write(REG_EXCEPTIONDATA, 100);
    rig.run_ms(300);
    let out = rig.run_ms(1);
    assert_eq!(out.motors, [MotorOutput::Stop; 2]);
    let shown = rig.bench.read_value(REGLL_ONE_CONTROL);
    assert!((shown - applied).abs() < 2.0, "{shown} vs {applied}");
    // The monitoring values keep updating: ERROR is 0 (required := actual).
    assert!(rig.bench.read_value(REGLL_ONE_ERROR).abs() < 0.01);
}

#[test]
fn outputs_follow_the_controller_while_running() {
    let mut bench = Bench::running(Variant::LiftLift);
    bench.write_value(REGLL_TWO_PGAIN, 10.0);
    bench.write_value(REGLL_TWO_REQPOS, -20.0);
    // Pot at 512 with the power-on calibration is 0°: e = −20 → u = −200.
    let out = bench.ticks(5, &with_current(0, 0));
    assert_eq!(
        out.motors[1],
        MotorOutput::Drive(Duty {
            magnitude: 200,
            direction: Direction::Reverse
        })
    );
    assert_eq!(out.motors[1].pins(), (false, true));
    assert_eq!(MotorOutput::Stop.pins(), (false, false));
}
