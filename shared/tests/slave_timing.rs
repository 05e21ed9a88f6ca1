//! Time-keeping registers (reference §2.1, §7.1): REG_TIMER, REG_INTERVALI2C,
//! INTERVALCTRL, REG_DEBUG; the µs clock's wrap; and the size of the logic in RAM.

mod slave_support;

use shared::regs::id::*;
use shared::slave::clock::Clock;
use shared::slave::{Core, Inputs, MotorId, RegisterFile, Variant, POSITION_PERIOD_US, TICK_US};
use slave_support::Bench;

#[test]
fn timer_counts_ms_mod_65536() {
    let mut bench = Bench::new(Variant::DriveSteer);
    bench.ticks(1_234, &Inputs::default());
    assert_eq!(bench.read(REG_TIMER), 1_234);
    bench.ticks(70_000 - 1_234, &Inputs::default());
    assert_eq!(bench.read(REG_TIMER), (70_000 % 65_536) as u16);
}

#[test]
fn timer_carries_on_across_the_us_clock_wrap() {
    let mut clock = Clock::new();
    let start = u32::MAX - 2_500;
    assert!(clock.advance(start));
    let ms0 = clock.ms();
    assert_eq!(ms0, start / 1000);
    let mut now = start;
    for _ in 0..10 {
        now = now.wrapping_add(1_000);
        assert!(!clock.advance(now));
    }
    assert_eq!(clock.ms(), ms0 + 10);
    assert_eq!(clock.interval_us(), 1_000);
    // Fractions of a ms add up; a long gap goes through the division path.
    now = now.wrapping_add(1_500);
    clock.advance(now);
    now = now.wrapping_add(1_500);
    clock.advance(now);
    assert_eq!(clock.ms(), ms0 + 13);
    now = now.wrapping_add(123_456);
    clock.advance(now);
    assert_eq!(clock.ms(), ms0 + 137);
    assert_eq!(clock.interval_us(), (123_456 % 65_536) as u16);
}

#[test]
fn core_runs_through_the_us_wrap() {
    let mut bench = Bench::new(Variant::LiftLift);
    bench.now_us = u32::MAX - 5_500;
    bench.tick(&Inputs::default());
    bench.write(REG_RESET, 1);
    let before = bench.core.uptime_ms();
    bench.write_value(REGLL_ONE_PGAIN, 1.0);
    bench.write_value(REGLL_ONE_REQPOS, 10.0);
    bench.ticks(20, &Inputs::default());
    assert!(bench.now_us < 20_000, "wrapped");
    assert_eq!(bench.core.uptime_ms(), before + 20);
    assert_eq!(bench.read(REG_INTERVALI2C), 1_000);
    assert_eq!(bench.read_value(REGLL_ONE_INTERVALCTRL).round(), 2.0);
    assert!(
        bench.last.unwrap().motors[0].duty() > 0,
        "the controller still runs"
    );
}

#[test]
fn intervali2c_is_the_us_between_the_last_two_ticks() {
    let mut bench = Bench::new(Variant::DriveSteer);
    bench.ticks(3, &Inputs::default());
    assert_eq!(bench.read(REG_INTERVALI2C), 1_000);
    bench.now_us += 1_777;
    bench.tick(&Inputs::default());
    assert_eq!(bench.read(REG_INTERVALI2C), 2_777);
    // mod 65536.
    bench.now_us += 100_000;
    bench.tick(&Inputs::default());
    assert_eq!(bench.read(REG_INTERVALI2C), (101_000 % 65_536) as u16);
}

#[test]
fn position_controllers_run_every_2_ms_and_drive_per_window() {
    assert_eq!((TICK_US, POSITION_PERIOD_US), (1_000, 2_000));
    let mut bench = Bench::running(Variant::DriveSteer);
    bench.ticks(400, &Inputs::default());
    assert_eq!(bench.read_value(REGDS_STEER_INTERVALCTRL).round(), 2.0);
    assert_eq!(bench.read_value(REGDS_DRIVE_INTERVALCTRL).round(), 151.0);
    assert_eq!(bench.read(REG_DEBUG), 0, "DS: always 0");
}

#[test]
fn ll_debug_shows_lift_one_interval_and_writes_are_overwritten() {
    let mut bench = Bench::running(Variant::LiftLift);
    bench.ticks(10, &Inputs::default());
    assert_eq!(bench.read(REG_DEBUG), 2);
    bench.write(REG_DEBUG, 999);
    bench.tick(&Inputs::default());
    assert_eq!(bench.read(REG_DEBUG), 2);
    bench.ticks(10, &Inputs::default());
    assert_eq!(bench.read_value(REGLL_TWO_INTERVALCTRL).round(), 2.0);
}

#[test]
fn lift_motors_update_on_alternate_ticks() {
    let mut bench = Bench::running(Variant::LiftLift);
    bench.write_value(REGLL_ONE_PGAIN, 1.0);
    bench.write_value(REGLL_TWO_PGAIN, 1.0);
    bench.write_value(REGLL_ONE_REQPOS, 10.0);
    bench.write_value(REGLL_TWO_REQPOS, 10.0);
    // The demands land between updates: one motor answers a tick before the other.
    let mut first = [None, None];
    for t in 0..4u32 {
        let out = bench.tick(&Inputs::default());
        for (seen, motor) in first.iter_mut().zip(out.motors) {
            if motor.duty() != 0 && seen.is_none() {
                *seen = Some(t);
            }
        }
    }
    let [one, two] = first.map(|t| t.expect("updated"));
    assert_eq!(one.abs_diff(two), 1, "ONE at {one}, TWO at {two}");
}

#[test]
fn a_stalled_tick_does_not_burst_updates() {
    let mut bench = Bench::running(Variant::LiftLift);
    bench.ticks(20, &Inputs::default());
    bench.now_us += 50_000;
    bench.tick(&Inputs::default());
    assert_eq!(bench.read_value(REGLL_ONE_INTERVALCTRL).round(), 52.0);
    let one = |bench: &Bench| bench.core.motor(MotorId::M1).monitors().interval_ms;
    assert_eq!(one(&bench), 52);
    bench.tick(&Inputs::default());
    assert_eq!(one(&bench), 52, "no update at once");
    bench.tick(&Inputs::default());
    // The next update comes a period after the late one.
    assert_eq!(one(&bench), 2);
}

/// Mapping is costly on the AVR, so a motor's monitoring registers are refreshed from
/// its updates at most every 10 ms: never staler than that.
#[test]
fn monitoring_registers_refresh_every_10_ms() {
    let mut bench = Bench::running(Variant::LiftLift);
    bench.write_value(REGLL_ONE_PGAIN, 1.0);
    bench.ticks(20, &Inputs::default());
    let mut inputs = Inputs::default();
    let mut changes = Vec::new();
    let mut last = bench.read(REGLL_ONE_ACTUALPOS);
    for t in 0..100u32 {
        // The pot moves every tick.
        inputs.adc.ch6 = 600 + t as u16;
        bench.tick(&inputs);
        let now = bench.read(REGLL_ONE_ACTUALPOS);
        if now != last {
            changes.push(t);
            last = now;
        }
    }
    assert!(changes.windows(2).all(|w| w[1] - w[0] == 10), "{changes:?}");
    assert_eq!(changes.len(), 10);
    // What it shows is the angle at that update: p − 512 with the power-on calibration.
    let shown = bench.read_value(REGLL_ONE_ACTUALPOS);
    let t = *changes.last().unwrap();
    let expected = f32::from(600 + t as u16) - 512.0;
    assert!(
        (shown - expected.clamp(-200.0, 200.0)).abs() < 1.0,
        "{shown} vs {expected}"
    );
}

/// The RAM the logic takes. On the AVR (8-bit, 16-bit pointers, 1-byte alignment) the
/// structs are no bigger than here, where fields are aligned to 4 bytes: built for the
/// ATmega328P, `Core` is 269 bytes and `RegisterFile` 109.
#[test]
fn ram_size_of_the_logic() {
    let core = std::mem::size_of::<Core>();
    let regs = std::mem::size_of::<RegisterFile>();
    let counter = std::mem::size_of::<shared::slave::EdgeCounter>();
    let adc = std::mem::size_of::<shared::slave::AdcCollector>();
    println!("Core {core} B, RegisterFile {regs} B, EdgeCounter {counter} B, AdcCollector {adc} B");
    assert!(core <= 360, "Core is {core} bytes");
    assert!(regs <= 112, "RegisterFile is {regs} bytes");
    assert_eq!(counter, 6);
    assert_eq!(adc, 12);
}

/// The 32-bit deadline form the position updates used before `due_every`.
fn due_wide(next: &mut u32, now: u32, period: u32) -> bool {
    if (now.wrapping_sub(*next) as i32) < 0 {
        return false;
    }
    *next = next.wrapping_add(period);
    if (now.wrapping_sub(*next) as i32) >= 0 {
        *next = now.wrapping_add(period);
    }
    true
}

#[test]
fn a_16_bit_deadline_with_the_long_gap_flag_is_due_as_the_32_bit_one() {
    use shared::slave::clock::due_every;
    const P: u32 = POSITION_PERIOD_US;
    // Gaps: every value up to 40,000 µs once each (past 2^15 both ways), then
    // pseudo-random ones (mostly a tick, some long, some up to 2^31 − 1).
    let mut seed = 0x2545_f491_4f6c_dd1du64;
    let mut random = move |bound: u32| {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed % u64::from(bound)) as u32
    };
    let mut dues = [0u32; 2];
    let mut long = 0;
    for start in [0u32, 1, 31_000, 65_535, u32::MAX - 2_500, 0x8000_0000] {
        // A deadline 1..=3,000 µs ahead, as Core::start leaves them.
        for ahead in [1u32, 999, 1_000, 2_000, 3_000] {
            let mut now = start;
            let mut wide = now.wrapping_add(ahead);
            let mut narrow = wide as u16;
            for step in 0..60_000u32 {
                let gap = match step {
                    0..40_000 => step,
                    _ => match random(20) {
                        0 => random(0x8000_0000),
                        1 => random(100_000),
                        2 => 32_760 + random(16),
                        _ => 995 + random(10),
                    },
                };
                now = now.wrapping_add(gap);
                // Clock::long_gap (its own tests check it against the gap).
                let long_gap = gap >= 1 << 15;
                long += u32::from(long_gap);
                let due = due_wide(&mut wide, now, P);
                assert_eq!(
                    due_every(&mut narrow, now as u16, long_gap, P as u16),
                    due,
                    "{start} {ahead} {step}"
                );
                assert_eq!(narrow, wide as u16, "{start} {ahead} {step}");
                // The invariant the 16-bit form rests on: 1..=3,000 µs ahead.
                assert!((1..=3_000).contains(&wide.wrapping_sub(now)));
                dues[usize::from(due)] += 1;
            }
        }
    }
    assert!(dues[0] > 100_000 && dues[1] > 100_000, "{dues:?}");
    assert!(long > 100_000, "{long}");
}

#[test]
fn a_16_bit_deadline_steps_by_its_period_and_restarts_when_late() {
    use shared::slave::clock::due_every;
    let mut next = 65_000u16;
    // Not yet due: 1 µs before, unchanged.
    assert!(!due_every(&mut next, 64_999, false, 2_000));
    assert_eq!(next, 65_000);
    // Due on time: one period on, across the 16-bit wrap.
    assert!(due_every(&mut next, 65_000, false, 2_000));
    assert_eq!(next, 1_464);
    // Due 1,999 µs late: still one period on.
    assert!(due_every(&mut next, 3_463, false, 2_000));
    assert_eq!(next, 3_464);
    // Due a whole period late: restarts from now.
    assert!(due_every(&mut next, 5_464, false, 2_000));
    assert_eq!(next, 7_464);
    // A long gap: due and restarted from now, whatever the 16 bits say.
    assert!(due_every(&mut next, 7_000, true, 2_000));
    assert_eq!(next, 9_000);
}
