//! The slave's LEDs (reference §6.5) with durations in ms, and the bad-address state.

mod slave_support;

use shared::regs::id::*;
use shared::slave::leds::{bad_address, BAD_CYCLE_MS};
use shared::slave::{Inputs, LedLevels, MotorOutput, Variant, Watchdog};
use slave_support::Bench;

const OFF: LedLevels = LedLevels::OFF;
const LED1: LedLevels = LedLevels {
    led1: true,
    led2: false,
};
const LED2: LedLevels = LedLevels {
    led1: false,
    led2: true,
};
const BOTH: LedLevels = LedLevels {
    led1: true,
    led2: true,
};

/// The LED levels of `ms` ticks.
fn trace(bench: &mut Bench, ms: usize) -> Vec<LedLevels> {
    (0..ms)
        .map(|_| bench.tick(&Inputs::default()).leds)
        .collect()
}

fn board(variant: Variant, address: u8) -> Bench {
    Bench::at(variant, address)
}

#[test]
fn boot_shows_the_address_for_600_ms_then_nothing_latched() {
    for (address, shown) in [
        (1, LED1),
        (2, LED2),
        (3, BOTH),
        (4, OFF),
        (5, LED1),
        (9, LED1),
    ] {
        let mut bench = board(Variant::DriveSteer, address);
        let t = trace(&mut bench, 700);
        assert!(t[..600].iter().all(|&l| l == shown), "address {address}");
        // Boot lights no latch: after the display only the heartbeat (LED2, 1 ms in
        // 101) flickers, so these 100 ms show it at most once.
        let lit: Vec<_> = (600..700).filter(|&i| t[i] != OFF).collect();
        assert!(lit.len() <= 1, "address {address}: lit at {lit:?} ms");
        assert!(lit.iter().all(|&i| t[i] == LED2), "address {address}");
    }
}

#[test]
fn heartbeat_is_one_tick_in_every_101_ms() {
    let mut bench = board(Variant::LiftLift, 4);
    let t = trace(&mut bench, 2_000);
    let beats: Vec<usize> = (600..2_000).filter(|&i| t[i] == LED2).collect();
    assert_eq!(beats.len(), 14);
    assert!(beats.windows(2).all(|w| w[1] - w[0] == 101), "{beats:?}");
    assert!((600..2_000).all(|i| t[i] == OFF || t[i] == LED2));
}

fn lit_for(t: &[LedLevels], which: fn(&LedLevels) -> bool) -> usize {
    t.iter().filter(|l| which(l)).count()
}

#[test]
fn ping_lights_led1_on_drive_steer_and_led2_on_lift_lift_for_50_ms() {
    let mut ds = board(Variant::DriveSteer, 4);
    trace(&mut ds, 700);
    ds.write(REG_PING, 0);
    let t = trace(&mut ds, 100);
    assert_eq!(lit_for(&t, |l| l.led1), 50);
    assert!(t[..50].iter().all(|l| l.led1));

    let mut ll = board(Variant::LiftLift, 3);
    trace(&mut ll, 700);
    ll.write(REG_PING, 7);
    let t = trace(&mut ll, 100);
    assert!(t[..50].iter().all(|l| l.led2));
    assert!(t[50..].iter().all(|l| !l.led1));
    assert!(lit_for(&t[50..], |l| l.led2) <= 1, "only a heartbeat after");
}

#[test]
fn debugled_0_and_1_light_one_led_for_250_ms_other_values_nothing() {
    let mut bench = board(Variant::DriveSteer, 4);
    trace(&mut bench, 700);
    bench.write(REG_DEBUGLED, 0);
    let t = trace(&mut bench, 300);
    assert_eq!(lit_for(&t, |l| l.led1), 250);
    bench.write(REG_DEBUGLED, 1);
    let t = trace(&mut bench, 300);
    assert!(t[..250].iter().all(|l| l.led2));
    assert!(
        lit_for(&t[250..], |l| l.led2) <= 1,
        "only a heartbeat after"
    );
    assert_eq!(lit_for(&t, |l| l.led1), 0, "LED1 stays dark");
    bench.write(REG_DEBUGLED, 2);
    let t = trace(&mut bench, 300);
    assert_eq!(lit_for(&t, |l| l.led1), 0);
    assert!(lit_for(&t, |l| l.led2) <= 3, "heartbeats only");
}

#[test]
fn exception_latch_shows_the_motor_until_reset() {
    let mut bench = board(Variant::DriveSteer, 4);
    trace(&mut bench, 700);
    bench.write(REG_RESET, 1);
    trace(&mut bench, 5);
    // A short on M2 (steer): LED2 steady.
    let mut inputs = Inputs::default();
    inputs.adc.current_peak = [0, 900];
    bench.tick(&inputs);
    let t = trace(&mut bench, 300);
    assert!(t.iter().all(|&l| l == LED2), "M2 → LED2");
    bench.write(REG_RESET, 1);
    let t = trace(&mut bench, 300);
    assert!(t.iter().all(|&l| l == OFF || l == LED2));
    assert!(lit_for(&t, |l| l.led2) <= 3);
    // Remote: both.
    bench.write(REG_EXCEPTIONDATA, 100);
    let t = trace(&mut bench, 300);
    assert!(t[1..].iter().all(|&l| l == BOTH));
}

#[test]
fn bad_address_keeps_the_board_off_the_bus_with_its_own_pattern() {
    for byte in [0u8, 10, 11, 0x80, 0xff] {
        let mut bench = board(Variant::DriveSteer, byte);
        assert_eq!(bench.core.address(), None, "byte {byte}");
        // A write that somehow arrives is never acted on.
        bench.write(REG_RESET, 1);
        bench.write_value(REGDS_DRIVE_PGAIN, 5.0);
        bench.write_value(REGDS_DRIVE_REQSPEED, 1000.0);
        let outs: Vec<_> = (0..2_400).map(|_| bench.tick(&Inputs::default())).collect();
        assert!(outs
            .iter()
            .all(|o| o.motors == [MotorOutput::Stop; 2] && o.watchdog == Watchdog::Feed));
        let t: Vec<LedLevels> = outs.iter().map(|o| o.leds).collect();
        // Two cycles of: both off 300 ms, LED1 300 ms, LED2 600 ms. The tick at 1 ms is
        // the clock's first.
        for (i, &l) in t.iter().enumerate() {
            assert_eq!(l, bad_address(i as u32 + 1), "byte {byte}, t {i}");
        }
        assert_eq!(lit_for(&t, |l| l.led1 && l.led2), 0, "never both");
        assert_eq!(lit_for(&t, |l| *l == LED1), 600);
        assert_eq!(lit_for(&t, |l| *l == LED2), 1_200);
        // Nothing of the register file changed.
        assert_eq!(bench.read(REG_STATUS), 0x0009);
        assert_eq!(bench.read(REG_TIMER), 0);
    }
    assert_eq!(BAD_CYCLE_MS, 1_200);
    assert_eq!(bad_address(0), OFF);
    assert_eq!(bad_address(299), OFF);
    assert_eq!(bad_address(300), LED1);
    assert_eq!(bad_address(599), LED1);
    assert_eq!(bad_address(600), LED2);
    assert_eq!(bad_address(1_199), LED2);
    assert_eq!(bad_address(1_200), OFF);
}

#[test]
fn good_addresses_are_1_to_9() {
    for byte in 0..=255u8 {
        let expected = (1..=9).contains(&byte).then_some(byte);
        assert_eq!(shared::slave::bus_address(byte), expected);
    }
}
