//! Sensors: the current filter and overcurrent rule (§7.4), pot angles (§7.3), the
//! encoder's speed and odometer (§7.3), and the ADC collector.

mod slave_support;

use shared::pid::Fix;
use shared::regs::id::*;
use shared::slave::clock::{age_of, units};
use shared::slave::current::{overcurrent, CurrentFilter};
use shared::slave::encoder::{rate, DriveMode, Odometer, SpeedMeter};
use shared::slave::pot::Calibration;
use shared::slave::scale::Scale;
use shared::slave::{
    AdcChannel, AdcCollector, AdcSample, EdgeCounter, EdgeSample, Inputs, LocalFault, Variant,
};
use slave_support::Bench;

fn steady(filter: fn(&mut CurrentFilter, u16), sample: u16) -> u8 {
    let mut f = CurrentFilter::new();
    for _ in 0..2000 {
        filter(&mut f, sample);
    }
    f.reading()
}

#[test]
fn current_filter_is_bit_exact_wrap_included() {
    let cases = [
        (0, 0),
        (1, 0),
        (2, 1),
        (10, 9),
        (100, 99),
        (200, 199),
        (255, 254),
        (256, 0),
        (300, 43),
        (1023, 254),
    ];
    for (sample, reading) in cases {
        assert_eq!(steady(CurrentFilter::push, sample), reading, "c = {sample}");
    }
}

#[test]
fn current_filter_rises_fast_and_falls_slowly() {
    let mut f = CurrentFilter::new();
    let mut rise = Vec::new();
    for _ in 0..5 {
        f.push(100);
        rise.push(f.reading());
    }
    // f := ⌊231·f/256⌋ + 2500: 2500, 4755, 6790, 8626, 10283; ⌊f/256⌋ as below.
    assert_eq!(rise, [9, 18, 26, 33, 40]);
    let mut f = CurrentFilter::new();
    for _ in 0..200 {
        f.push(100);
    }
    // Settled at f = 25590; on the way down f := ⌊254·f/256⌋ per sample: 25390 (99)
    // after one, 11648 (45) after a hundred.
    f.push(0);
    assert_eq!(f.reading(), 99);
    for _ in 0..99 {
        f.push(0);
    }
    assert_eq!(f.reading(), 45);
}

#[test]
fn saturating_filter_has_no_wrap() {
    assert_eq!(steady(CurrentFilter::push_saturating, 300), 254);
    assert_eq!(steady(CurrentFilter::push_saturating, 256), 254);
    assert_eq!(steady(CurrentFilter::push_saturating, 100), 99);
}

#[test]
fn overcurrent_rule() {
    assert_eq!(overcurrent(300, 300, 255), None, "equal is not above");
    assert_eq!(overcurrent(301, 300, 251), Some(LocalFault::Overcurrent));
    assert_eq!(overcurrent(301, 300, 250), Some(LocalFault::ShortOc));
    assert_eq!(overcurrent(301, 300, 0), Some(LocalFault::ShortOc));
    assert_eq!(overcurrent(1023, 1000, 255), Some(LocalFault::Overcurrent));
    assert_eq!(overcurrent(0, 0, 255), None);
}

#[test]
fn pot_angles_with_the_calibration() {
    let calib = Scale::of(&shared::regs::DS, REGDS_STEER_CALIBMIN);
    let c = Calibration::new(calib.unmap(0x43), calib.unmap(0xc4));
    assert!((c.min().to_num::<f64>() + 56.6929).abs() < 1e-3);
    assert!((c.max().to_num::<f64>() - 65.1969).abs() < 1e-3);
    let cases = [
        (0u16, -56.6929),
        (512, 4.2520),
        (1023, 65.0778),
        (1024, 65.0778),
    ];
    for (p, angle) in cases {
        let got = c.angle(p).to_num::<f64>();
        let float = f64::from(p.min(1023) as f32 * (65.19685f32 + 56.692913) / 1024.0 - 56.692913);
        assert!((got - angle).abs() < 1e-3, "p {p}: {got}");
        assert!((got - float).abs() < 1e-3, "p {p}: {got} vs {float}");
    }
    // Power-on −512..512: angle = p − 512.
    assert_eq!(Calibration::POWER_ON.angle(0), Fix::from_num(-512));
    assert_eq!(Calibration::POWER_ON.angle(700), Fix::from_num(188));
    let mut c = Calibration::POWER_ON;
    c.set_min(Fix::from_num(-100));
    assert_eq!(c.max(), Fix::from_num(512));
    c.set_max(Fix::from_num(100));
    assert_eq!(c.angle(512), Fix::ZERO);
}

#[test]
fn rate_is_edges_per_second() {
    // Spans in 4-µs units.
    assert_eq!(rate(0, 37_500), Fix::ZERO);
    assert_eq!(rate(150, 37_500), Fix::from_num(1000));
    assert_eq!(rate(1, 37_501).to_num::<f64>().floor(), 6.0);
    let r = rate(3, 1_750).to_num::<f64>();
    assert!((r - 428.571).abs() < 0.01, "{r}");
    // Beyond 4294 edges the product shifted overflows u32: another route, same answer.
    let r = rate(5000, 62_496).to_num::<f64>();
    assert!((r - 5000.0 * 250_000.0 / 62_496.0).abs() < 0.01, "{r}");
    assert_eq!(rate(40_000, 250), Fix::MAX);
}

#[test]
fn edge_counter_counts_and_restarts_on_take() {
    let mut c = EdgeCounter::new();
    c.rising_edge(25, false);
    c.rising_edge(50, true);
    c.rising_edge(75, false);
    assert_eq!(
        c.take(),
        EdgeSample {
            rising: 3,
            b_high: 1,
            last_edge: 75
        }
    );
    assert_eq!(
        c.take(),
        EdgeSample {
            rising: 0,
            b_high: 0,
            last_edge: 75
        }
    );
}

/// A tick's sample: `rising` edges, `b_high` of them with B high, the last edge the counter
/// saw at `last_edge_us` µs (kept across takes).
fn edges(rising: u16, b_high: u16, last_edge_us: u32) -> EdgeSample {
    EdgeSample {
        rising,
        b_high,
        last_edge: units(last_edge_us),
    }
}

/// A meter ticked from `from_us` to `to_us` (one gap) with `sample`.
fn tick(m: &mut SpeedMeter, sample: &EdgeSample, from_us: u32, to_us: u32) {
    m.accumulate(sample, age_of(to_us - from_us));
}

#[test]
fn window_speed_and_its_sign_rule() {
    let mut m = SpeedMeter::new();
    tick(&mut m, &edges(100, 0, 90_000), 0, 100_000);
    tick(&mut m, &edges(50, 0, 149_000), 100_000, 150_000);
    assert!(!m.due(DriveMode::Window), "more than 150 ms, not equal");
    let mut later = m;
    tick(&mut later, &edges(0, 0, 149_000), 150_000, 150_004);
    assert!(later.due(DriveMode::Window));
    tick(&mut m, &edges(0, 0, 149_000), 150_000, 151_000);
    assert!(m.due(DriveMode::Window));
    let s = m.measure(units(151_000), DriveMode::Window).to_num::<f64>();
    assert!((s - 150.0 * 1e6 / 151_000.0).abs() < 0.01, "{s}");
    // Negative when more than ⌊N/3⌋ edges saw B high: N = 30 → 11 of them.
    tick(&mut m, &edges(30, 10, 200_000), 151_000, 302_000);
    assert!(m.measure(units(302_000), DriveMode::Window) > Fix::ZERO);
    tick(&mut m, &edges(30, 11, 400_000), 302_000, 453_000);
    assert!(m.measure(units(453_000), DriveMode::Window) < Fix::ZERO);
    // No edges: 0.
    tick(&mut m, &edges(0, 0, 400_000), 453_000, 604_000);
    assert_eq!(m.measure(units(604_000), DriveMode::Window), Fix::ZERO);
}

#[test]
fn edge_timing_speed() {
    let mut m = SpeedMeter::new();
    // 1000 ticks/s: an edge every 1000 µs from t = 500.
    let mut t = 500;
    let mut now = 0;
    let mut speeds = Vec::new();
    for _ in 0..5 {
        let mut n = 0;
        while t <= now + 10_000 {
            n += 1;
            t += 1000;
        }
        tick(&mut m, &edges(n, 0, t - 1000), now, now + 10_000);
        now += 10_000;
        assert!(m.due(DriveMode::EdgeTiming));
        speeds.push(m.measure(units(now), DriveMode::EdgeTiming).to_num::<f64>());
    }
    // The first interval has no earlier edge, so it spans from the previous update.
    assert!((speeds[0] - 10.0 / 9_500.0 * 1e6).abs() < 0.5, "{speeds:?}");
    for s in &speeds[1..] {
        assert!((s - 1000.0).abs() < 0.01, "{speeds:?}");
    }
    // The edges stop: the speed falls to the bound 10^6/elapsed, then to 0 after 100 ms.
    let last_edge = t - 1000;
    tick(&mut m, &edges(0, 0, last_edge), now, now + 10_000);
    now += 10_000;
    let s = m.measure(units(now), DriveMode::EdgeTiming).to_num::<f64>();
    let bound = 1e6 / f64::from(now - last_edge);
    assert!((s - bound).abs() < 0.5, "{s} vs {bound}");
    tick(&mut m, &edges(0, 0, last_edge), now, now + 10_000);
    now += 10_000;
    let s2 = m.measure(units(now), DriveMode::EdgeTiming).to_num::<f64>();
    assert!(s2 < s && s2 > 0.0, "{s2}");
    tick(&mut m, &edges(0, 0, last_edge), now, last_edge + 100_000);
    now = last_edge + 100_000;
    assert_eq!(m.measure(units(now), DriveMode::EdgeTiming), Fix::ZERO);
    // Reverse: B high at every edge.
    tick(&mut m, &edges(5, 5, now + 9_000), now, now + 10_000);
    let s = m.measure(units(now + 10_000), DriveMode::EdgeTiming);
    assert!(s < Fix::ZERO, "{s}");
}

#[test]
fn drive_mode_register_values() {
    assert_eq!(DriveMode::from_register(0), DriveMode::Window);
    assert_eq!(DriveMode::from_register(1), DriveMode::EdgeTiming);
    assert_eq!(DriveMode::from_register(2), DriveMode::Window);
}

#[test]
fn odometer_counts_every_edge_over_256() {
    let mut o = Odometer::new();
    o.add(255);
    assert_eq!(o.reading(), 0);
    o.add(1);
    assert_eq!(o.reading(), 1);
    for _ in 0..1000 {
        o.add(65535);
    }
    assert_eq!(o.reading(), ((256 + 1000 * 65535u32) >> 8) as u16);
    o.clear();
    assert_eq!(o.reading(), 0);
}

#[test]
fn odometer_register_and_reset_bit_2() {
    let mut bench = Bench::running(Variant::DriveSteer);
    let inputs = Inputs {
        edges: edges(200, 200, 0),
        ..Default::default()
    };
    bench.ticks(3, &inputs);
    assert_eq!(
        bench.read(REGDS_DRIVE_ODO),
        2,
        "600 edges in reverse still count"
    );
    bench.write(REG_RESET, 4);
    bench.tick(&Inputs::default());
    assert_eq!(bench.read(REGDS_DRIVE_ODO), 0);
    assert_eq!(bench.read(REG_RESET), 0, "written back to 0");
}

#[test]
fn adc_collector_keeps_latest_values_and_current_peaks() {
    let mut adc = AdcCollector::new();
    let mut ch = AdcChannel::ORDER[0];
    for value in [100u16, 50, 600, 700, 300, 40, 610, 710] {
        adc.record(ch, value);
        ch = ch.next();
    }
    assert_eq!(ch, AdcChannel::Current1);
    assert_eq!(
        adc.take(),
        AdcSample {
            current: [300, 40],
            current_peak: [300, 50],
            ch6: 610,
            ch7: 710
        }
    );
    // The peaks restart at the latest values.
    adc.record(AdcChannel::Current1, 20);
    let s = adc.take();
    assert_eq!((s.current, s.current_peak), ([20, 40], [300, 40]));
    assert_eq!(
        [
            AdcChannel::Current1,
            AdcChannel::Current2,
            AdcChannel::Pot6,
            AdcChannel::Pot7
        ]
        .map(AdcChannel::mux),
        [0, 1, 6, 7]
    );
}

#[test]
fn chassis_register_is_the_mapped_adc7_reading() {
    let mut bench = Bench::new(Variant::DriveSteer);
    let inputs = Inputs {
        adc: AdcSample {
            ch7: 256,
            ..Default::default()
        },
        ..Default::default()
    };
    bench.tick(&inputs);
    assert_eq!(bench.read(REGDS_CHASSIS), 16383);
    assert!((bench.read_value(REGDS_CHASSIS) - 256.0).abs() < 0.02);
}

#[test]
fn current_registers_show_the_filtered_current() {
    let mut bench = Bench::new(Variant::LiftLift);
    let inputs = Inputs {
        adc: AdcSample {
            current: [100, 300],
            current_peak: [100, 300],
            ..Default::default()
        },
        ..Default::default()
    };
    bench.ticks(2000, &inputs);
    assert_eq!(bench.read(REGLL_ONE_CURRENT), 99);
    assert_eq!(bench.read(REGLL_TWO_CURRENT), 43);
}

/// The angle by the form the product replaced: the span's bits shifted down by 6 (its
/// 10 high bits of fraction kept), times p by 16×16-bit products, shifted down by 4.
fn angle_by_shifts(min: Fix, span: Fix, p: u16) -> Fix {
    let p = i64::from(p.min(1023));
    let span = i64::from(span.to_bits().clamp(-(1 << 26), 1 << 26) >> 6);
    let product = span.unsigned_abs() as i64 * p;
    let product = if span < 0 { -product } else { product };
    Fix::from_bits((product >> 4) as i32).saturating_add(min)
}

#[test]
fn pot_angles_are_the_truncated_exact_product_within_2_pow_minus_10_of_the_shift_form() {
    let calib = Scale::of(&shared::regs::DS, REGDS_STEER_CALIBMIN);
    let readings = (0..=1023u16)
        .step_by(7)
        .chain([1, 511, 512, 1022, 1023, 1024, u16::MAX]);
    let readings: Vec<u16> = readings.collect();
    let (mut cases, mut differ, mut widest) = (0u32, 0u32, 0u32);
    // Every pair of CALIBMIN and CALIBMAX register values.
    for raw_min in 0..=255u16 {
        for raw_max in 0..=255u16 {
            let (min, max) = (calib.unmap(raw_min), calib.unmap(raw_max));
            let c = Calibration::new(min, max);
            let span = max.saturating_sub(min);
            for &p in &readings {
                let got = c.angle(p);
                // p·span/1024 truncated toward zero, exact in 64 bits, then added.
                let exact = i64::from(span.to_bits()) * i64::from(p.min(1023)) / 1024;
                let want = Fix::from_bits(exact as i32).saturating_add(min);
                assert_eq!(got, want, "{raw_min:#x} {raw_max:#x} p {p}");
                let diff = got
                    .to_bits()
                    .abs_diff(angle_by_shifts(min, span, p).to_bits());
                assert!(diff <= 64, "{raw_min:#x} {raw_max:#x} p {p}: {diff}");
                differ += u32::from(diff != 0);
                widest = widest.max(diff);
                cases += 1;
            }
        }
    }
    assert_eq!(cases, 65_536 * 154, "{cases}");
    // The forms do differ (the bound is not vacuous), by the whole bound at most.
    assert!(differ > cases / 2, "{differ} of {cases}");
    assert_eq!(widest, 64);
}

#[test]
fn pot_angles_by_hand() {
    // Span 100.5 (bits 0x64_8000), p 3: 301.5/1024 = 0.294433… → bits 19,296 (exact
    // 19296.0), min −10: −9.705566… = bits −655,360 + 19,296.
    let c = Calibration::new(Fix::from_num(-10), Fix::from_num(90.5));
    assert_eq!(c.angle(3).to_bits(), -655_360 + 19_296);
    // A negative span truncates toward zero: span −1 (bits −65,536), p 1: −64 bits
    // exactly; p 1023 of span −0.5: −32,768·1023/1024 = −32,736 exactly; span of
    // −3 bits at p 1: −3/1024 truncates to 0.
    let c = Calibration::new(Fix::from_num(1), Fix::ZERO);
    assert_eq!(c.angle(1).to_bits(), 65_536 - 64);
    let c = Calibration::new(Fix::from_num(0.5), Fix::ZERO);
    assert_eq!(c.angle(1023).to_bits(), 32_768 - 32_736);
    let c = Calibration::new(Fix::from_bits(3), Fix::ZERO);
    assert_eq!(c.angle(1).to_bits(), 3);
    // The shift form floored that −3/1024 to −1 bit: the forms differ there.
    assert_eq!(
        angle_by_shifts(Fix::from_bits(3), Fix::from_bits(-3), 1).to_bits(),
        2
    );
}

#[test]
fn next_mux_is_the_round_robin_and_the_collector_matches_the_field_by_field_form() {
    use shared::slave::next_mux;
    for ch in AdcChannel::ORDER {
        assert_eq!(next_mux(ch.mux()), ch.next().mux(), "{ch:?}");
    }
    assert_eq!([0, 1, 6, 7].map(next_mux), [1, 6, 7, 0]);
    // The form the collector replaced: one field per channel, the peak a max.
    let mut wide = AdcSample::default();
    let mut adc = AdcCollector::new();
    let mut seed = 0x9e37_79b9u32;
    let mut mux = 0u8;
    for step in 0..20_000u32 {
        seed ^= seed << 13;
        seed ^= seed >> 17;
        seed ^= seed << 5;
        let value = (seed % 1024) as u16;
        // Mostly the round robin, sometimes a channel out of turn.
        let ch = if seed.is_multiple_of(7) {
            AdcChannel::ORDER[(seed >> 8) as usize % 4]
        } else {
            let ch = AdcChannel::ORDER
                .into_iter()
                .find(|c| c.mux() == mux)
                .unwrap();
            mux = next_mux(mux);
            ch
        };
        match ch {
            AdcChannel::Current1 => {
                wide.current[0] = value;
                wide.current_peak[0] = wide.current_peak[0].max(value);
            }
            AdcChannel::Current2 => {
                wide.current[1] = value;
                wide.current_peak[1] = wide.current_peak[1].max(value);
            }
            AdcChannel::Pot6 => wide.ch6 = value,
            AdcChannel::Pot7 => wide.ch7 = value,
        }
        adc.record(ch, value);
        if step.is_multiple_of(9) {
            assert_eq!(adc.take(), wide, "{step}");
            wide.current_peak = wide.current;
        }
    }
}
