//! Emulator tests of the RC receiver model: the `fixture_rc` firmware measures the
//! pulses on D2, D3 and D4 by pin change and prints them.

use harness::rc::{RcReceiver, DEFAULT_WIDTHS_US, FRAME_US};
use harness::{uno, Avr, F_CPU};
use shared::master::rc::{normalise, PulseTimer};

const CYCLES_PER_US: u64 = F_CPU / 1_000_000;

fn fixture() -> (Avr, RcReceiver) {
    let mut avr = Avr::firmware("fixture_rc").unwrap();
    let rc = RcReceiver::attach(&mut avr);
    avr.uart_read_until(b"rc ready\r\n", 10_000).unwrap();
    (avr, rc)
}

/// The next `rc a b c` line, as numbers.
fn next_widths(avr: &mut Avr) -> [u16; 3] {
    let line = avr.uart_read_until(b"\r\n", 2 * FRAME_US).unwrap();
    let line = String::from_utf8(line).unwrap();
    let words: Vec<&str> = line.trim_end().split(' ').collect();
    assert_eq!(words.len(), 4, "{line:?}");
    assert_eq!(words[0], "rc");
    [1, 2, 3].map(|i| words[i].parse().unwrap())
}

#[test]
fn the_receiver_is_off_until_turned_on() {
    let (mut avr, rc) = fixture();
    assert!(!rc.is_on());
    avr.run_us(100_000);
    assert!(avr.uart_take().is_empty(), "no pulses, nothing measured");
    assert!(!avr.pin(uno::D2) && !avr.pin(uno::D3) && !avr.pin(uno::D4));
    assert_eq!(rc.frames(), 0);
    assert_eq!(rc.widths(), DEFAULT_WIDTHS_US);
}

#[test]
fn the_default_widths_are_the_sticks_at_rest_for_the_master() {
    let mut remote = shared::master::rc::Remote::new();
    for (channel, width) in DEFAULT_WIDTHS_US.into_iter().enumerate() {
        remote.pulse(channel, width);
    }
    let pass = remote.pass();
    assert_eq!((pass.drive, pass.steer, pass.crab), (0, 0, false));
    assert_eq!(pass.angles, [0; 6]);
}

#[test]
fn widths_are_measured_exactly_from_the_first_frame() {
    let (mut avr, rc) = fixture();
    rc.set_width(0, 1000);
    rc.set_width(1, 1200);
    rc.set_width(2, 1800);
    rc.turn_on();
    for _ in 0..5 {
        assert_eq!(next_widths(&mut avr), [1000, 1200, 1800]);
    }
    assert_eq!(rc.frames(), 5);
}

#[test]
fn new_widths_take_effect_from_the_next_frame() {
    let (mut avr, rc) = fixture();
    rc.turn_on();
    assert_eq!(next_widths(&mut avr), [1470, 1339, 910]);
    rc.set_width(0, 1940);
    rc.set_width(1, 940);
    rc.set_width(2, 910);
    // The line just read ended a frame; the next frame starts after the set.
    assert_eq!(next_widths(&mut avr), [1940, 940, 910]);
    // Out-of-range widths are clamped to 500..=2500 µs.
    rc.set_width(0, 3000);
    rc.set_width(1, 100);
    assert_eq!(rc.widths(), [2500, 500, 910]);
}

#[test]
fn frames_repeat_every_20_ms_with_each_channel_starting_as_the_previous_ends() {
    let (mut avr, rc) = fixture();
    for pin in [uno::D2, uno::D3, uno::D4] {
        avr.trace_pin(pin);
    }
    rc.set_width(0, 1100);
    rc.set_width(1, 1700);
    rc.set_width(2, 1300);
    rc.turn_on();
    avr.run_us(5 * FRAME_US);
    let d2 = avr.pin_trace(uno::D2);
    let d3 = avr.pin_trace(uno::D3);
    let d4 = avr.pin_trace(uno::D4);
    let rises = |t: &[(u64, bool)]| -> Vec<u64> {
        t.iter().filter(|&&(_, l)| l).map(|&(c, _)| c).collect()
    };
    let falls = |t: &[(u64, bool)]| -> Vec<u64> {
        t.iter()
            .skip(1)
            .filter(|&&(_, l)| !l)
            .map(|&(c, _)| c)
            .collect()
    };
    let (r2, f2, r3, f3, r4, f4) = (
        rises(&d2),
        falls(&d2),
        rises(&d3),
        falls(&d3),
        rises(&d4),
        falls(&d4),
    );
    // Edges land at the first instruction boundary at or after their cycle.
    let close = |got: u64, want_us: u64| got.abs_diff(want_us * CYCLES_PER_US) <= 4;
    assert_eq!(r2.len(), 5);
    for pair in r2.windows(2) {
        assert!(close(pair[1] - pair[0], FRAME_US), "{r2:?}");
    }
    let first = r2[0];
    for k in 0..5 {
        let start = k as u64 * FRAME_US;
        assert!(close(r2[k] - first, start), "no drift: {r2:?}");
        assert!(close(f2[k] - first, start + 1100));
        assert_eq!(r3[k], f2[k], "ch1 starts as ch0 ends");
        assert!(close(f3[k] - first, start + 1100 + 1700));
        assert_eq!(r4[k], f3[k]);
        assert!(close(f4[k] - first, start + 1100 + 1700 + 1300));
    }
}

#[test]
fn the_masters_pulse_timer_and_normalisation_read_the_receiver() {
    let (mut avr, rc) = fixture();
    for pin in [uno::D2, uno::D3, uno::D4] {
        avr.trace_pin(pin);
    }
    rc.set_width(0, 1000); // full forward
    rc.set_width(1, 1738); // full right
    rc.set_width(2, 1800); // crab
    rc.turn_on();
    avr.run_us(2 * FRAME_US);
    // Merge the three traces into pin-change events, as the interrupt sees them.
    let mut events: Vec<(u64, usize, bool)> = Vec::new();
    for (c, pin) in [uno::D2, uno::D3, uno::D4].into_iter().enumerate() {
        events.extend(
            avr.pin_trace(pin)
                .into_iter()
                .skip(1)
                .map(|(t, l)| (t, c, l)),
        );
    }
    events.sort_by_key(|&(t, c, l)| (t, l, c));
    let mut timer = PulseTimer::new();
    let mut levels = 0u8;
    let mut widths = Vec::new();
    for (t, c, l) in events {
        if l {
            levels |= 1 << c;
        } else {
            levels &= !(1 << c);
        }
        let us = (t / CYCLES_PER_US) as u32;
        for (ch, w) in timer.change(levels, us).into_iter().enumerate() {
            if let Some(w) = w {
                widths.push((ch, w));
            }
        }
    }
    // Stamps are whole µs and edges may land a few cycles late: ±1 µs.
    let channels: Vec<usize> = widths.iter().map(|&(c, _)| c).collect();
    assert_eq!(channels, [0, 1, 2, 0, 1, 2]);
    let want = [1000u16, 1738, 1800];
    for &(c, w) in &widths {
        assert!(w.abs_diff(want[c]) <= 1, "channel {c}: {w} µs");
    }
    // Full forward, full right, crab: what the master's pass would act on.
    let values: Vec<i16> = widths[..3]
        .iter()
        .map(|&(c, w)| normalise(c, w).unwrap())
        .collect();
    assert_eq!(values[0], 1000);
    assert_eq!(values[1], -1000);
    assert!(values[2] >= 995, "{values:?}");
}

#[test]
fn turning_off_stops_the_pulses_and_leaves_the_pins_low() {
    let (mut avr, rc) = fixture();
    rc.turn_on();
    next_widths(&mut avr);
    rc.turn_off();
    assert!(!rc.is_on());
    let frames = rc.frames();
    avr.run_us(5 * FRAME_US);
    assert!(!avr.pin(uno::D2) && !avr.pin(uno::D3) && !avr.pin(uno::D4));
    assert_eq!(rc.frames(), frames);
    let text = String::from_utf8(avr.uart_take()).unwrap();
    assert!(
        text.lines().count() <= 1,
        "at most the frame under way: {text:?}"
    );
}

#[test]
fn frames_go_on_after_a_chip_reset() {
    let (mut avr, rc) = fixture();
    rc.set_width(1, 1250);
    rc.turn_on();
    assert_eq!(next_widths(&mut avr), [1470, 1250, 910]);
    // Reset in the middle of channel 0's pulse.
    avr.run_us(FRAME_US - 2000);
    avr.reset();
    avr.uart_read_until(b"rc ready\r\n", 10_000).unwrap();
    assert_eq!(next_widths(&mut avr), [1470, 1250, 910]);
    assert_eq!(next_widths(&mut avr), [1470, 1250, 910]);
}
