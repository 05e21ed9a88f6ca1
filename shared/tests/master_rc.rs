//! Remote control: normalisation, link state, the first link-up's writes, the steer
//! integrator, the Ackermann geometry against an f64 reference, and the pass's writes.

use shared::mapping;
use shared::master::rc::setup::{DRIVE_BLOCK, STEER_BLOCK, STEER_CALIBRATION};
use shared::master::rc::steer::{
    inner_angle, integrate, knots, wheel_angles, ACKERMANN_MIN_CDEG, KNOT_STEP_CDEG,
};
use shared::master::rc::{
    normalise, LinkUpWrites, PulseTimer, Remote, DS_CONTROLLERS, LINK_UP_WRITES,
};
use shared::master::RegWrite;
use shared::regs::{id, BoardKind};

fn ds(reg: u8) -> &'static shared::regs::Register {
    BoardKind::DriveSteer.register(reg).unwrap()
}

#[test]
fn normalisation_follows_the_reference_formula_and_dead_band() {
    // Drive runs backwards: 1940 µs is -1, 1000 µs is +1.
    assert_eq!(normalise(0, 1940), Some(-1000));
    assert_eq!(normalise(0, 1000), Some(1000));
    assert_eq!(normalise(0, 2100), Some(-1000), "clamped");
    assert_eq!(normalise(0, 900), Some(1000), "clamped");
    assert_eq!(normalise(0, 1470), Some(0), "centre");
    assert_eq!(normalise(0, 1420), Some(106), "(1420-1940)·2/(-940) - 1");
    assert_eq!(
        normalise(0, 1430),
        Some(0),
        "0.085 is inside the 0.1 dead band"
    );
    assert_eq!(normalise(1, 940), Some(1000));
    assert_eq!(normalise(1, 1738), Some(-1000));
    assert_eq!(normalise(1, 1200), Some(348));
    assert_eq!(normalise(2, 910), Some(-1000));
    assert_eq!(normalise(2, 1800), Some(1000));
    assert_eq!(normalise(2, 1700), Some(775));
    assert_eq!(normalise(3, 1500), None);
}

#[test]
fn normalisation_matches_the_float_formula_within_a_thousandth() {
    let cal = [(1940.0f64, 1000.0f64), (1738.0, 940.0), (910.0, 1800.0)];
    for (c, &(mn, mx)) in cal.iter().enumerate() {
        for w in 800..=2200u16 {
            let raw = ((f64::from(w) - mn) * 2.0 / (mx - mn)).clamp(0.0, 2.0) - 1.0;
            let v = if raw.abs() < 0.1 { 0.0 } else { raw };
            let got = f64::from(normalise(c, w).unwrap()) / 1000.0;
            // At the dead band's edge the two may fall on either side.
            if (raw.abs() - 0.1).abs() > 0.002 {
                assert!((got - v).abs() <= 0.001, "ch{c} {w} µs: {got} vs {v}");
            }
        }
    }
}

#[test]
fn the_pulse_timer_measures_each_channel_between_its_edges() {
    let mut t = PulseTimer::new();
    assert_eq!(t.change(0b001, 1000), [None; 3]);
    assert_eq!(
        t.change(0b010, 2500),
        [Some(1500), None, None],
        "ch0 falls as ch1 rises"
    );
    assert_eq!(t.change(0b100, 3700), [None, Some(1200), None]);
    assert_eq!(t.change(0b000, 5500), [None, None, Some(1800)]);
    // A fall without a seen rise measures nothing.
    let mut fresh = PulseTimer::new();
    fresh.change(0b000, 0);
    assert_eq!(fresh.change(0b000, 10), [None; 3]);
    // The µs clock wraps.
    let mut w = PulseTimer::new();
    w.change(0b001, u32::MAX - 499);
    assert_eq!(w.change(0b000, 1000), [Some(1500), None, None]);
}

#[test]
fn the_link_is_up_for_1_s_after_an_edge_and_the_wrap_cannot_revive_it() {
    let mut r = Remote::new();
    assert!(!r.link_up(0), "no edge ever seen");
    r.edge(10_000);
    assert!(r.link_up(10_000));
    assert!(r.link_up(10_999));
    assert!(r.swallows_frames(10_999), "PC frames are swallowed");
    assert!(!r.link_up(11_000));
    // 2^16 ms later the old 16-bit stamp would look fresh; it was forgotten.
    assert!(!r.link_up(10_005 + 65_536));
}

#[test]
fn first_link_up_is_reported_once_per_boot() {
    let mut r = Remote::new();
    assert!(!r.first_link_up(0));
    r.edge(100);
    assert!(r.first_link_up(200));
    assert!(!r.first_link_up(300));
    assert!(!r.link_up(2_000));
    r.edge(3_000);
    assert!(
        !r.first_link_up(3_001),
        "the link came back: no second set-up"
    );
}

#[test]
fn the_first_link_up_writes_reset_then_configure_every_drive_steer_board() {
    let writes: Vec<RegWrite> = LinkUpWrites::new().collect();
    assert_eq!(writes.len(), LINK_UP_WRITES);
    assert_eq!(writes.len(), 10 + 6 * 17);
    for (d, w) in writes[..10].iter().enumerate() {
        assert_eq!(*w, RegWrite::byte(d as u8, id::REG_RESET, 1));
    }
    let drive = [
        (id::REGDS_DRIVE_PGAIN, 0.01f32),
        (id::REGDS_DRIVE_IGAIN, 0.0),
        (id::REGDS_DRIVE_DGAIN, 0.0),
        (id::REGDS_DRIVE_INTEGRALCAP, 0.0),
        (id::REGDS_DRIVE_INTEGRALDECAY, 0.0),
        (id::REGDS_DRIVE_OVERCURRENTTHRESH, 500.0),
        (id::REGDS_DRIVE_STALLCHECK, 255.0),
    ];
    let steer = [
        (id::REGDS_STEER_PGAIN, 0.0f32),
        (id::REGDS_STEER_IGAIN, 6.0),
        (id::REGDS_STEER_DGAIN, 0.0),
        (id::REGDS_STEER_INTEGRALCAP, 300.0),
        (id::REGDS_STEER_INTEGRALDECAY, 0.9),
        (id::REGDS_STEER_OVERCURRENTTHRESH, 500.0),
        (id::REGDS_STEER_STALLCHECK, 255.0),
        (id::REGDS_STEER_DEADZONE, 1.0),
    ];
    let calibration = [
        (-56.0f32, 66.0f32),
        (-62.0, 59.0),
        (-59.0, 64.0),
        (-60.0, 65.0),
        (-66.0, 57.0),
        (-62.0, 60.0),
    ];
    for (wheel, chunk) in writes[10..].chunks(17).enumerate() {
        let device = DS_CONTROLLERS[wheel];
        let (min, max) = calibration[wheel];
        let expected: Vec<(u8, f32)> = drive
            .iter()
            .chain(steer.iter())
            .copied()
            .chain([
                (id::REGDS_STEER_CALIBMIN, min),
                (id::REGDS_STEER_CALIBMAX, max),
            ])
            .collect();
        for (w, &(reg, value)) in chunk.iter().zip(&expected) {
            let register = ds(reg);
            let raw = mapping::map(value, register);
            let want = RegWrite::sized(device, reg, raw).unwrap();
            assert_eq!(*w, want, "wheel {} {}", wheel + 1, register.name);
            assert_eq!(w.bytes().len(), usize::from(register.size));
        }
    }
    // The precomputed tables, spot-checked against the reference's bytes.
    assert_eq!(DRIVE_BLOCK[0].1, 0x0041);
    assert_eq!(STEER_BLOCK[3].1, 0x4ccc);
    assert_eq!(STEER_BLOCK[4].1, 0xe664);
    assert_eq!(STEER_CALIBRATION[0], (0x43, 0xc4));
    assert_eq!(writes[10 + 17 * 5].device, 8);
}

#[test]
fn the_steer_integrator_moves_0_03_degrees_per_pass_and_stops_at_30() {
    assert_eq!(integrate(0, 1000), -30_000);
    assert_eq!(integrate(0, -500), 15_000);
    assert_eq!(integrate(29_990_000, -1000), 30_000_000);
    assert_eq!(integrate(-29_990_000, 1000), -30_000_000);
    let mut s = 0;
    for _ in 0..1000 {
        s = integrate(s, -1000);
    }
    assert_eq!(s, 30_000_000, "1000 passes at full stick reach +30°");
}

/// The reference formula in f64, degrees.
fn inner_reference(outer: f64) -> f64 {
    if outer.abs() < 5.0 {
        return outer;
    }
    let (w, s) = (26.5f64, 42.0f64);
    let cot = 1.0 / outer.abs().to_radians().tan();
    let inner = (w / (w * cot + s)).atan().to_degrees();
    inner.copysign(outer)
}

#[test]
fn the_inner_angle_is_within_0_01_degree_of_the_f64_formula() {
    let mut worst = 0.0f64;
    for cdeg in -3000i16..=3000 {
        let got = f64::from(inner_angle(cdeg)) / 100.0;
        let want = inner_reference(f64::from(cdeg) / 100.0);
        worst = worst.max((got - want).abs());
    }
    eprintln!("inner angle: worst error {worst}°");
    assert!(worst < 0.01, "worst error {worst}°");
    // Worked examples.
    assert_eq!(
        inner_angle(499),
        499,
        "below 5° the inner wheel takes the outer angle"
    );
    assert_eq!(inner_angle(500), 439, "the step at 5°: 4.394°");
    assert_eq!(inner_angle(3000), 1677, "30° outer gives 16.777° inner");
    assert_eq!(inner_angle(-3000), -1677);
    assert_eq!(inner_angle(2000), 1300, "20° outer gives 12.997° inner");
    // Beyond the integrator's limit the inner wheel stays at 30°'s angle.
    assert_eq!(inner_angle(4500), 1677);
    assert_eq!(inner_angle(i16::MIN), -1677);
}

#[test]
fn the_knots_are_the_f64_values_and_their_rises_fit_a_byte_product() {
    let knots = knots();
    for (n, pair) in knots.windows(2).enumerate() {
        let rise = pair[1] - pair[0];
        // Rising, and below 64: the firmware's rise times fraction is one 8×8 product.
        assert!((1..64).contains(&rise), "knot {n}: rise {rise}");
    }
    for (n, &v) in knots.iter().enumerate() {
        let outer = f64::from(ACKERMANN_MIN_CDEG as u16 + KNOT_STEP_CDEG * n as u16) / 100.0;
        let want = (inner_reference(outer) * 100.0).round();
        assert_eq!(f64::from(v), want, "knot {n} at {outer}°");
    }
    // The last knot lies past the integrator's 30°.
    let last = ACKERMANN_MIN_CDEG as u16 + KNOT_STEP_CDEG * (knots.len() as u16 - 1);
    assert!(last >= 3000, "{last}");
}

#[test]
fn wheel_angles_follow_the_sign_rules_and_crab_mode() {
    // θo = 20°, θi = inner(20°).
    let i20 = inner_angle(2000);
    assert_eq!(wheel_angles(2000, false), [-i20, -2000, 0, 0, i20, 2000]);
    assert_eq!(wheel_angles(-2000, false), [2000, i20, 0, 0, -2000, -i20]);
    assert_eq!(wheel_angles(300, false), [-300, -300, 0, 0, 300, 300]);
    assert_eq!(wheel_angles(0, false), [0; 6]);
    assert_eq!(wheel_angles(-1500, true), [-1500; 6]);
}

fn remote_with(widths: [u16; 3]) -> Remote {
    let mut r = Remote::new();
    r.edge(0);
    for (c, &w) in widths.iter().enumerate() {
        r.pulse(c, w);
    }
    r
}

#[test]
fn a_pass_applies_dead_bands_crab_mode_and_writes_speed_and_steer_to_all_six_boards() {
    // Full forward, steer 1200 µs (0.348 → past the 0.3 dead band), normal mode.
    let mut r = remote_with([1000, 1200, 1000]);
    let p = r.pass();
    assert_eq!((p.drive, p.steer, p.crab), (1000, 348, false));
    assert_eq!(p.speed_tenths, 13_000);
    assert_eq!(
        p.speed_raw(),
        0xa998,
        "1300 ticks/s, the reference's RC maximum"
    );
    assert_eq!(r.steer_udeg(), -10_440);
    // Drive below 0.2 and steer below 0.3 are zeroed; mode above 0.75 is crab.
    let mut r = remote_with([1400, 1350, 1750]);
    let p = r.pass();
    assert_eq!((p.drive, p.steer, p.crab), (0, 0, true));
    assert_eq!(p.speed_raw(), 0x7fff);
    let writes: Vec<RegWrite> = p.writes().collect();
    assert_eq!(writes.len(), 12);
    for (i, pair) in writes.chunks(2).enumerate() {
        let device = DS_CONTROLLERS[i];
        assert_eq!(
            pair[0],
            RegWrite::word(device, id::REGDS_DRIVE_REQSPEED, 0x7fff)
        );
        assert_eq!(
            pair[1],
            RegWrite::word(device, id::REGDS_STEER_REQPOS, 0x7fff)
        );
    }
}

#[test]
fn holding_the_stick_steers_to_30_degrees_with_the_ackermann_angles() {
    // Full left (940 µs is +1 on the steer channel: s decreases to -30°).
    let mut r = remote_with([1470, 940, 1000]);
    let mut p = r.pass();
    for _ in 0..1100 {
        p = r.pass();
    }
    assert_eq!(r.steer_udeg(), -30_000_000);
    assert_eq!(p.angles, [3000, 1677, 0, 0, -3000, -1677]);
    let reqpos = ds(id::REGDS_STEER_REQPOS);
    for (wheel, &a) in p.angles.iter().enumerate() {
        let float = mapping::map(f32::from(a) / 100.0, reqpos);
        let int = p.steer_raw(wheel + 1).unwrap();
        assert!(
            int.abs_diff(float) <= 1,
            "wheel {}: {int} vs {float}",
            wheel + 1
        );
    }
    assert_eq!(p.steer_raw(1), Some(mapping::map(30.0, reqpos)));
    assert_eq!(p.steer_raw(7), None);
    assert_eq!(p.steer_raw(0), None);
}

#[test]
fn integer_register_values_match_the_float_mapping() {
    let reqspeed = ds(id::REGDS_DRIVE_REQSPEED);
    let reqpos = ds(id::REGDS_STEER_REQPOS);
    let mut r = Remote::new();
    r.edge(0);
    // Every drive value the pass can produce.
    for w in 990..=1950u16 {
        r.pulse(0, w);
        let p = r.pass();
        let float = mapping::map(1300.0 * f32::from(p.drive) / 1000.0, reqspeed);
        assert!(p.speed_raw().abs_diff(float) <= 1, "{w} µs");
    }
    // Reference bytes: ±40° and 0 on STEER_REQPOS.
    let p = remote_with([1470, 1339, 1000]).pass();
    assert_eq!(p.angles, [0; 6]);
    assert_eq!(p.steer_raw(1), Some(0x7fff));
    for (angle, raw) in [(4000i16, 0x9998u16), (-4000, 0x6665)] {
        let mut q = p;
        q.angles = [angle; 6];
        assert_eq!(q.steer_raw(3), Some(raw));
        assert_eq!(mapping::map(f32::from(angle) / 100.0, reqpos), raw);
    }
}

#[test]
fn a_channel_without_pulses_reads_centred() {
    let mut r = Remote::new();
    r.edge(0);
    r.pulse(1, 940);
    let p = r.pass();
    assert_eq!((p.drive, p.steer, p.crab), (0, 1000, false));
    assert_eq!(p.speed_tenths, 0, "no drive pulse: no motion");
    assert_eq!(r.widths(), [None, Some(940), None]);
}
