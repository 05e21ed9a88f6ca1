//! The bus-silence failsafe through the whole slave core: armed by a ping, restarted by
//! any transaction, BUSSILENT (0x050c) after BUSTIMEOUT ms of silence while running.

mod slave_support;

use shared::regs::id::*;
use shared::slave::{Cause, Inputs, MotorOutput, State, Variant};
use slave_support::Bench;

/// A running board past its address display, driving its motors at a fixed demand
/// (P gain only, so the demand follows the error at once).
fn driving(variant: Variant) -> Bench {
    let mut bench = Bench::running(variant);
    bench.ticks(700, &Inputs::default());
    match variant {
        Variant::DriveSteer => {
            bench.write_value(REGDS_DRIVE_PGAIN, 1.0);
            bench.write_value(REGDS_DRIVE_STALLCHECK, 255.0);
            bench.write_value(REGDS_DRIVE_REQSPEED, 1000.0);
        }
        Variant::LiftLift => {
            bench.write_value(REGLL_ONE_PGAIN, 10.0);
            bench.write_value(REGLL_ONE_STALLCHECK, 255.0);
            bench.write_value(REGLL_ONE_REQPOS, 90.0);
        }
    }
    bench.ticks(200, &Inputs::default());
    assert!(
        bench.last.map(|o| o.motors[0].duty()).unwrap_or(0) > 0,
        "the motor is driven"
    );
    bench
}

/// A write the board hears (the firmware's TWI task reports the address match).
fn write(bench: &mut Bench, id: u8, raw: u16) {
    bench.write(id, raw);
    bench.core.bus_heard();
}

/// Ticks until the board leaves `Running`; returns how many, or `None` within `limit`.
fn ticks_until_exception(bench: &mut Bench, limit: u32) -> Option<u32> {
    (1..=limit).find(|_| {
        bench.tick(&Inputs::default());
        !matches!(bench.core.state(), State::Running { .. })
    })
}

#[test]
fn a_board_never_pinged_is_never_silenced() {
    let mut bench = driving(Variant::DriveSteer);
    assert!(!bench.core.silence().is_armed());
    assert_eq!(ticks_until_exception(&mut bench, 10_000), None);
    assert!(bench.last.map(|o| o.motors[0].duty()).unwrap_or(0) > 0);
}

#[test]
fn armed_by_a_ping_it_raises_bussilent_exactly_at_the_timeout() {
    let mut bench = driving(Variant::DriveSteer);
    write(&mut bench, REG_PING, 0);
    bench.tick(&Inputs::default());
    assert!(bench.core.silence().is_armed());
    assert_eq!(ticks_until_exception(&mut bench, 10_000), Some(2_500));
    assert_eq!(bench.core.state(), State::Exception(Cause::BusSilent));
    let out = bench.last.expect("ticked");
    assert_eq!(out.motors, [MotorOutput::Stop; 2]);
    assert!(out.leds.led1 && out.leds.led2, "no motor: both LEDs");
    assert_eq!(bench.read(REG_EXCEPTIONDATA), 0x050c);
    assert_eq!(bench.read(REG_STATUS), 0x0009);
}

/// The firmware calls `bus_heard` for every transaction addressed to the board, a read as
/// much as a write (shown on the chip by `slave_faults`'
/// `a_read_alone_restarts_the_silence_count`).
#[test]
fn bus_heard_restarts_the_count() {
    let mut bench = driving(Variant::DriveSteer);
    write(&mut bench, REG_PING, 0);
    bench.tick(&Inputs::default());
    assert_eq!(ticks_until_exception(&mut bench, 2_000), None);
    bench.core.bus_heard();
    bench.tick(&Inputs::default());
    assert_eq!(ticks_until_exception(&mut bench, 10_000), Some(2_500));
    assert_eq!(bench.read(REG_EXCEPTIONDATA), 0x050c);
}

#[test]
fn pings_once_a_second_keep_it_quiet() {
    let mut bench = driving(Variant::LiftLift);
    for _ in 0..10 {
        write(&mut bench, REG_PING, 0);
        assert_eq!(ticks_until_exception(&mut bench, 1_000), None);
    }
    assert!(bench.last.map(|o| o.motors[0].duty()).unwrap_or(0) > 0);
}

#[test]
fn bustimeout_zero_turns_it_off_and_a_new_value_applies() {
    let mut bench = driving(Variant::DriveSteer);
    write(&mut bench, REG_PING, 0);
    write(&mut bench, REGDS_BUSTIMEOUT, 0);
    assert_eq!(ticks_until_exception(&mut bench, 10_000), None);
    write(&mut bench, REGDS_BUSTIMEOUT, 100);
    bench.tick(&Inputs::default());
    assert_eq!(ticks_until_exception(&mut bench, 1_000), Some(100));
    assert_eq!(bench.core.state(), State::Exception(Cause::BusSilent));
}

#[test]
fn the_lift_board_uses_its_own_register_id() {
    let mut bench = driving(Variant::LiftLift);
    assert_eq!(bench.read(REGLL_BUSTIMEOUT), 2_500);
    write(&mut bench, REGLL_BUSTIMEOUT, 50);
    write(&mut bench, REG_PING, 0);
    bench.tick(&Inputs::default());
    assert_eq!(ticks_until_exception(&mut bench, 1_000), Some(50));
    assert_eq!(bench.read(REG_EXCEPTIONDATA), 0x050c);
    assert_eq!(bench.read(REG_STATUS), 0x0005);
}

#[test]
fn bit_12_of_disabledexceptions_masks_it() {
    let mut bench = driving(Variant::DriveSteer);
    write(&mut bench, REG_DISABLEDEXCEPTIONS, 1 << 12);
    write(&mut bench, REG_PING, 0);
    assert_eq!(ticks_until_exception(&mut bench, 10_000), None);
    // Unmasked: the write was heard, so a whole timeout runs from it.
    write(&mut bench, REG_DISABLEDEXCEPTIONS, 0);
    bench.tick(&Inputs::default());
    assert_eq!(ticks_until_exception(&mut bench, 10_000), Some(2_500));
}

#[test]
fn reset_leaves_it_and_a_new_silence_raises_it_again() {
    let mut bench = driving(Variant::DriveSteer);
    write(&mut bench, REGDS_BUSTIMEOUT, 200);
    write(&mut bench, REG_PING, 0);
    bench.tick(&Inputs::default());
    assert_eq!(ticks_until_exception(&mut bench, 1_000), Some(200));
    // In exception, more silence changes nothing.
    bench.ticks(1_000, &Inputs::default());
    assert_eq!(bench.core.state(), State::Exception(Cause::BusSilent));
    write(&mut bench, REG_RESET, 1);
    let out = bench.tick(&Inputs::default());
    assert!(matches!(bench.core.state(), State::Running { .. }));
    assert!(matches!(out.motors[0], MotorOutput::Drive(_)));
    assert_eq!(bench.read(REG_EXCEPTIONDATA), 0x050c, "the last one stays");
    assert_eq!(ticks_until_exception(&mut bench, 1_000), Some(200));
}

#[test]
fn another_exception_comes_first_and_is_kept() {
    let mut bench = driving(Variant::DriveSteer);
    write(&mut bench, REG_PING, 0);
    write(&mut bench, REG_EXCEPTIONDATA, 100);
    bench.tick(&Inputs::default());
    bench.ticks(5_000, &Inputs::default());
    assert_eq!(bench.core.state(), State::Exception(Cause::Remote));
    assert_eq!(bench.read(REG_EXCEPTIONDATA), 0x0503);
}

#[test]
fn boot_disarms_and_a_ping_in_the_boot_exception_arms_for_later() {
    let mut bench = Bench::new(Variant::DriveSteer);
    assert!(!bench.core.silence().is_armed());
    bench.tick(&Inputs::default());
    write(&mut bench, REG_PING, 0);
    bench.ticks(5_000, &Inputs::default());
    assert!(bench.core.silence().is_armed());
    assert_eq!(
        bench.core.state(),
        State::Exception(Cause::Boot),
        "not checked in exception"
    );
    write(&mut bench, REG_RESET, 1);
    bench.tick(&Inputs::default());
    assert_eq!(ticks_until_exception(&mut bench, 10_000), Some(2_500));
    assert_eq!(bench.read(REG_EXCEPTIONDATA), 0x050c);
}
