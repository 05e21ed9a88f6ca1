//! Every worked example of the reference's value-mapping section (§3) and the
//! per-wheel calibration table (§8.3): value -> raw -> wire bytes -> the slave's value.

use shared::mapping::{full_scale, in_range, map, unmap};
use shared::protocol::{encode_write, Write};
use shared::regs::{BoardKind, Register};

fn ds(name: &str) -> &'static Register {
    BoardKind::DriveSteer.lookup(name).unwrap()
}

fn ll(name: &str) -> &'static Register {
    BoardKind::LiftLift.lookup(name).unwrap()
}

/// The register's value bytes as a write frame to a board of its kind carries them.
fn wire_bytes(device: u8, reg: &Register, raw: u16) -> Vec<u8> {
    let mut out = heapless::Vec::new();
    encode_write(device, &[Write { id: reg.id, raw }], &mut out).unwrap();
    out[4..].to_vec()
}

/// One row: register, value, raw, wire bytes, the slave's value and the tolerance
/// that the reference's printed digits allow.
fn check(device: u8, reg: &Register, value: f32, raw: u16, wire: &[u8], slave: f32, tol: f32) {
    assert_eq!(map(value, reg), raw, "{} map({value})", reg.name);
    assert_eq!(wire_bytes(device, reg, raw), wire, "{} wire", reg.name);
    let back = unmap(raw, reg);
    assert!(
        (back - slave).abs() <= tol,
        "{} unmap({raw:#06x}) = {back}, reference {slave}",
        reg.name
    );
}

#[test]
fn full_scale_per_size() {
    assert_eq!(full_scale(2), 65534);
    assert_eq!(full_scale(1), 254);
}

#[test]
fn drive_reqspeed_examples() {
    let r = ds("REGDS_DRIVE_REQSPEED");
    check(1, r, 1000.0, 0x9ffe, &[0xfe, 0x9f], 999.9082, 5e-5);
    check(1, r, 0.0, 0x7fff, &[0xff, 0x7f], 0.0, 0.0);
    check(1, r, -1000.0, 0x5fff, &[0xff, 0x5f], -1000.0305, 5e-5);
    check(1, r, -4000.0, 0x0000, &[0x00, 0x00], -4000.0, 0.0);
    check(1, r, 4000.0, 0xfffe, &[0xfe, 0xff], 4000.0, 0.0);
    check(1, r, 1300.0, 0xa998, &[0x98, 0xa9], 1299.966, 5e-4);
}

#[test]
fn steer_reqpos_examples() {
    let r = ds("STEER_REQPOS");
    check(1, r, 40.0, 0x9998, &[0x98, 0x99], 39.9976, 5e-5);
    check(1, r, -40.0, 0x6665, &[0x65, 0x66], -40.0037, 5e-5);
}

#[test]
fn calibration_examples() {
    check(
        1,
        ds("STEER_CALIBMIN"),
        -56.0,
        0x43,
        &[0x43],
        -56.6929,
        5e-5,
    );
    check(1, ds("STEER_CALIBMAX"), 66.0, 0xc4, &[0xc4], 65.1969, 5e-5);
}

#[test]
fn gain_decay_and_cap_examples() {
    check(
        1,
        ds("DRIVE_PGAIN"),
        0.01,
        0x0041,
        &[0x41, 0x00],
        0.0099185,
        5e-8,
    );
    check(
        1,
        ds("STEER_IGAIN"),
        2.0,
        0x3332,
        &[0x32, 0x33],
        1.99988,
        5e-6,
    );
    let decay = ds("DRIVE_INTEGRALDECAY");
    check(1, decay, 0.95, 0xf331, &[0x31, 0xf3], 0.949995, 5e-7);
    check(1, decay, 0.9, 0xe664, &[0x64, 0xe6], 0.899991, 5e-7);
    let cap = ds("STEER_INTEGRALCAP");
    check(1, cap, 300.0, 0x4ccc, &[0xcc, 0x4c], 299.997, 5e-4);
    check(1, cap, 50.0, 0x0ccc, &[0xcc, 0x0c], 49.989, 5e-4);
}

#[test]
fn overcurrent_examples_truncate_to_integers_on_the_slave() {
    let r = ds("DRIVE_OVERCURRENTTHRESH");
    for (value, raw, wire, integer) in [
        (500.0, 0x7fff, [0xff, 0x7f], 500),
        (200.0, 0x3332, [0x32, 0x33], 199),
        (10.0, 0x028f, [0x8f, 0x02], 9),
    ] {
        assert_eq!(map(value, r), raw);
        assert_eq!(wire_bytes(1, r, raw), wire);
        assert_eq!(unmap(raw, r) as i32, integer, "overcurrent {value}");
    }
}

#[test]
fn stallcheck_and_deadzone_examples() {
    check(1, ds("DRIVE_STALLCHECK"), 255.0, 0xfe, &[0xfe], 255.0, 0.0);
    let dz = ds("DRIVE_DEADZONE");
    check(1, dz, 1.0, 0x05, &[0x05], 0.98425, 5e-6);
    check(1, dz, 0.5, 0x02, &[0x02], 0.39370, 5e-6);
}

#[test]
fn temperature_examples() {
    let r = BoardKind::Master.lookup("TEMP1").unwrap();
    check(0, r, 0.0, 0x2aaa, &[0xaa, 0x2a], -0.0006, 5e-5);
    check(0, r, 21.5, 0x5887, &[0x87, 0x58], 21.4985, 5e-5);
}

#[test]
fn raw_values_above_full_scale_still_unmap() {
    let speed = ds("DRIVE_REQSPEED");
    assert!((unmap(65535, speed) - 4000.122).abs() < 5e-4);
    let control = ds("DRIVE_STALLCHECK");
    assert!((unmap(255, control) - 256.004).abs() < 5e-4);
    let calib = ds("STEER_CALIBMIN");
    assert!((unmap(255, calib) - 120.945).abs() < 5e-4);
}

#[test]
fn unmapped_registers_carry_integers() {
    let reset = ds("REG_RESET");
    assert_eq!(map(4.0, reset), 4);
    assert_eq!(map(4.9, reset), 4);
    assert_eq!(map(65535.0, reset), 65535);
    assert_eq!(unmap(0x0502, ds("REG_EXCEPTIONDATA")), 1282.0);
}

#[test]
fn calibration_quantisation_per_wheel() {
    // (steer min, max, raws, on slave), (lift min, max, raws, on slave), §8.3.
    type Side = (f32, f32, u16, u16, f32, f32);
    let wheels: [(Side, Side); 6] = [
        (
            (-56.0, 66.0, 0x43, 0xc4, -56.69, 65.20),
            (-109.0, 109.0, 0x0b, 0xf2, -109.61, 108.66),
        ),
        (
            (-62.0, 59.0, 0x3d, 0xbd, -62.36, 58.58),
            (-102.0, 112.0, 0x13, 0xf5, -102.05, 111.50),
        ),
        (
            (-59.0, 64.0, 0x40, 0xc2, -59.53, 63.31),
            (-110.0, 105.0, 0x0a, 0xee, -110.55, 104.88),
        ),
        (
            (-60.0, 65.0, 0x3f, 0xc3, -60.47, 64.25),
            (-101.0, 110.0, 0x14, 0xf3, -101.10, 109.61),
        ),
        (
            (-66.0, 57.0, 0x39, 0xbb, -66.14, 56.69),
            (-113.0, 113.0, 0x07, 0xf6, -113.39, 112.44),
        ),
        (
            (-62.0, 60.0, 0x3d, 0xbe, -62.36, 59.53),
            (-109.0, 103.0, 0x0b, 0xec, -109.61, 102.99),
        ),
    ];
    let (smin, smax) = (ds("STEER_CALIBMIN"), ds("STEER_CALIBMAX"));
    let (lmin, lmax) = (ll("ONE_CALIBMIN"), ll("ONE_CALIBMAX"));
    for (wheel, (steer, lift)) in wheels.iter().enumerate() {
        for (regs, side) in [((smin, smax), steer), ((lmin, lmax), lift)] {
            let (vmin, vmax, rmin, rmax, smin_v, smax_v) = *side;
            assert_eq!(map(vmin, regs.0), rmin, "wheel {} min", wheel + 1);
            assert_eq!(map(vmax, regs.1), rmax, "wheel {} max", wheel + 1);
            assert!(
                (unmap(rmin, regs.0) - smin_v).abs() <= 0.005,
                "wheel {}",
                wheel + 1
            );
            assert!(
                (unmap(rmax, regs.1) - smax_v).abs() <= 0.005,
                "wheel {}",
                wheel + 1
            );
        }
    }
}

#[test]
fn pc_side_range_check() {
    let speed = ds("DRIVE_REQSPEED");
    assert!(in_range(4000.0, speed));
    assert!(in_range(-4000.0, speed));
    assert!(!in_range(4000.5, speed));
    assert!(!in_range(-4001.0, speed));
    assert!(!in_range(f32::NAN, speed));
    let reset = ds("REG_RESET");
    assert!(in_range(0.0, reset));
    assert!(in_range(65535.0, reset));
    assert!(!in_range(-1.0, reset));
    assert!(!in_range(65536.0, reset));
}
