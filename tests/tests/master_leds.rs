//! The master's LEDs in the emulator (reference §6.5, with the choices documented in
//! `master/src/leds.rs`): D13 lights at each ping for 100 ms; D7 flashes the type code
//! of the last exception the master raised, 512 ms per pulse with 128 ms lit, in a
//! cycle of 8.192 s.

mod master_support;

use harness::uno;
use master_support::{Options, Rig};

/// Rising edges of a pin trace, with how long each stayed high (µs).
fn pulses(trace: &[(u64, bool)]) -> Vec<(f64, f64)> {
    let us = |c: u64| c as f64 / 16.0;
    trace
        .windows(2)
        .filter(|w| w[1].1 && !w[0].1)
        .map(|w| w[1].0)
        .map(|rise| {
            let fall = trace
                .iter()
                .find(|(c, high)| *c > rise && !*high)
                .map_or(f64::NAN, |(c, _)| us(*c));
            (us(rise), fall - us(rise))
        })
        .collect()
}

/// D7's pulses over the next whole cycle of the type code, with the cycle's start (µs):
/// cycles start at multiples of 8.192 s of the master's clock (which starts at load).
fn next_cycle(rig: &mut Rig) -> (f64, Vec<(f64, f64)>) {
    const CYCLE_US: u64 = 8_192_000;
    let start = rig.micros().div_ceil(CYCLE_US) * CYCLE_US;
    rig.run_to(start - 1_000);
    rig.avr().trace_pin(uno::D7);
    rig.run_to(start + CYCLE_US - 1_000);
    (start as f64, pulses(&rig.avr().pin_trace(uno::D7)))
}

/// Checks a cycle's pulses are type `code`'s: one every 512 ms from its start, each lit
/// 128 ms, a pulse's start at most `late_us` off (its end as late, or half as early).
fn assert_type_code(start: f64, lit: &[(f64, f64)], code: u8, late_us: f64) {
    assert_eq!(lit.len(), usize::from(code), "type {code}: {lit:?}");
    for (i, (at, width)) in lit.iter().enumerate() {
        let expected = start + 512_000.0 * i as f64;
        assert!((at - expected).abs() < late_us, "pulse {i} at {at} us");
        let lit_range = 128_000.0 - late_us / 2.0..128_000.0 + late_us;
        assert!(lit_range.contains(width), "lit {width} us");
    }
}

#[test]
fn d13_lights_for_100_ms_at_each_ping() {
    let mut rig = Rig::new();
    rig.run_to(4_900_000);
    rig.avr().trace_pin(uno::D13);
    rig.run_to(7_300_000);
    let lit = pulses(&rig.avr().pin_trace(uno::D13));
    assert_eq!(lit.len(), 3, "{lit:?}");
    for (i, (at, width)) in lit.iter().enumerate() {
        let ping = 5_000_000.0 + 1_001_000.0 * i as f64;
        assert!((at - ping).abs() < 3_000.0, "ping {i} at {at} us");
        assert!((99_000.0..102_000.0).contains(width), "lit {width} us");
    }
}

#[test]
fn d7_flashes_the_type_code_of_the_raised_exception() {
    // A short (type 8) on slave 2, a stall (type 5) on slave 7: as many pulses a cycle.
    for (slave, code) in [(2u8, 8u8), (7, 5)] {
        let mut rig = Rig::new();
        rig.reset_master();
        // The slave reports it at the first ping.
        for addr in 1..=9 {
            rig.slave(addr).in_exception = false;
        }
        rig.slave(slave).raise(code, 0);
        rig.run_to(5_500_000);
        assert_eq!(
            rig.master_exception(),
            u16::from(slave) << 8 | u16::from(code)
        );
        // A master reset does not stop the flashing.
        rig.reset_master();
        let (start, lit) = next_cycle(&mut rig);
        assert_type_code(start, &lit, code, 2_000.0);
    }
}

#[test]
fn d7_flashes_the_type_code_instead_of_showing_the_remote_controls_link() {
    // Reference §6.5: lit while the RC link is up; after an exception raised on the
    // master it flashes the type code *instead*.
    let mut rig = Rig::with(Options {
        rc: true,
        ..Options::default()
    });
    let rc = rig.rc.take().expect("the receiver");
    rc.turn_on();
    for addr in 1..=9 {
        rig.slave(addr).in_exception = false;
    }
    // The link counts from 5 s after boot; the pings start then too.
    rig.run_to(5_300_000);
    rig.avr().trace_pin(uno::D7);
    rig.run_to(5_900_000);
    assert!(
        pulses(&rig.avr().pin_trace(uno::D7)).is_empty() && rig.avr().pin(uno::D7),
        "solid while the link is up and nothing was raised"
    );
    // A short (type 8) on slave 4, found by the next ping. The service loop sets the LED
    // between the remote control's passes, each a round of I2C writes: up to 3 ms late.
    rig.slave(4).raise(8, 0);
    let (start, lit) = next_cycle(&mut rig);
    assert_type_code(start, &lit, 8, 4_000.0);
    // The master latched it: with the link down for a second it answers the PC again.
    rc.turn_off();
    rig.run_us(1_200_000);
    assert_eq!(rig.master_exception(), 0x0408);
}
