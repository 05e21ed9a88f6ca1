//! Unmapping raw registers into the fixed-point values the slave acts on, and mapping
//! monitoring values back: the reference's worked examples (§3), exhaustive checks
//! against the original's float32 arithmetic, and the compile-time scales against the
//! tables.

use shared::mapping;
use shared::pid::Fix;
use shared::regs::{id::*, BoardKind, Register, DS, LL};
use shared::slave::board::{Layout, Monitor, MotorId, Param, Variant};
use shared::slave::motor::Kind;
use shared::slave::scale::Scale;

fn ds(id: u8) -> &'static Register {
    BoardKind::DriveSteer.register(id).unwrap()
}

fn f(x: Fix) -> f64 {
    x.to_num::<f64>()
}

#[test]
fn worked_examples_of_the_reference() {
    let cases: [(u8, u16, f64); 14] = [
        (REGDS_DRIVE_REQSPEED, 0x9ffe, 999.9082),
        (REGDS_DRIVE_REQSPEED, 0x7fff, 0.0),
        (REGDS_DRIVE_REQSPEED, 0x5fff, -1000.0305),
        (REGDS_DRIVE_REQSPEED, 0x0000, -4000.0),
        (REGDS_DRIVE_REQSPEED, 0xfffe, 4000.0),
        (REGDS_DRIVE_REQSPEED, 0xa998, 1299.966),
        (REGDS_STEER_REQPOS, 0x9998, 39.9976),
        (REGDS_STEER_REQPOS, 0x6665, -40.0037),
        (REGDS_STEER_CALIBMIN, 0x43, -56.6929),
        (REGDS_STEER_CALIBMAX, 0xc4, 65.1969),
        (REGDS_DRIVE_PGAIN, 0x0041, 0.0099185),
        (REGDS_STEER_IGAIN, 0x3332, 1.99988),
        (REGDS_DRIVE_INTEGRALDECAY, 0xf331, 0.949995),
        (REGDS_DRIVE_DEADZONE, 0x05, 0.98425),
    ];
    for (id, raw, expected) in cases {
        let got = f(Scale::of(&DS, id).unmap(raw));
        assert!(
            (got - expected).abs() < 1e-3,
            "{} {raw:#x}: {got} vs {expected}",
            ds(id).name
        );
    }
    let more: [(u8, u16, f64); 5] = [
        (REGDS_DRIVE_INTEGRALDECAY, 0xe664, 0.899991),
        (REGDS_DRIVE_INTEGRALCAP, 0x4ccc, 299.997),
        (REGDS_DRIVE_INTEGRALCAP, 0x0ccc, 49.989),
        (REGDS_DRIVE_DEADZONE, 0x02, 0.39370),
        (REGDS_DRIVE_REQSPEED, 0xffff, 4000.122),
    ];
    for (id, raw, expected) in more {
        let got = f(Scale::of(&DS, id).unmap(raw));
        assert!((got - expected).abs() < 1e-3, "{raw:#x}: {got}");
    }
}

#[test]
fn integer_parameters_truncate_as_the_original() {
    let oc = Scale::of(&DS, REGDS_DRIVE_OVERCURRENTTHRESH);
    assert_eq!(oc.unmap_int(0x7fff), 500);
    assert_eq!(oc.unmap_int(0x3332), 199);
    assert_eq!(oc.unmap_int(0x028f), 9);
    assert_eq!(
        oc.unmap_int(0x4ccc),
        299,
        "the DRIVE register's power-up raw"
    );
    let stall = Scale::of(&DS, REGDS_DRIVE_STALLCHECK);
    assert_eq!(stall.unmap_int(0xfe), 255);
    assert_eq!(stall.unmap_int(0x77), 119);
}

/// trunc(float32 unmap) for every raw value equals the integer path.
#[test]
fn integer_truncation_equals_float32_for_every_raw_value() {
    let oc = Scale::of(&DS, REGDS_DRIVE_OVERCURRENTTHRESH);
    for raw in 0..=u16::MAX {
        let float = mapping::unmap(raw, ds(REGDS_DRIVE_OVERCURRENTTHRESH));
        assert_eq!(u32::from(oc.unmap_int(raw)), float as u32, "raw {raw}");
    }
    let stall = Scale::of(&DS, REGDS_DRIVE_STALLCHECK);
    for raw in 0..=255u16 {
        let float = mapping::unmap(raw, ds(REGDS_DRIVE_STALLCHECK));
        assert_eq!(u32::from(stall.unmap_int(raw)), float as u32, "raw {raw}");
    }
}

/// The fixed-point value is within 1e-3 of the float32 one, for every raw value of
/// every writable mapped register (1/65536 truncation against float rounding).
#[test]
fn unmap_is_within_1e3_of_float32_everywhere() {
    for board in [BoardKind::DriveSteer, BoardKind::LiftLift] {
        let table = if board == BoardKind::DriveSteer {
            &DS[..]
        } else {
            &LL[..]
        };
        for reg in board.table().iter().filter(|r| r.range.is_some()) {
            let scale = Scale::of(table, reg.id);
            let top = if reg.size == 1 { 255 } else { u16::MAX };
            for raw in (0..=top).step_by(7).chain([top]) {
                let got = f(scale.unmap(raw));
                let float = f64::from(mapping::unmap(raw, reg));
                assert!(
                    (got - float).abs() < 1e-3,
                    "{} {raw}: {got} vs {float}",
                    reg.name
                );
            }
        }
    }
}

/// Mapping a monitoring value lands within one count of the float32 mapping, and exactly
/// on the landmarks: the ends, and 0 ↔ 0x7fff in symmetric ranges.
#[test]
fn map_matches_float32_within_one_count() {
    for reg in BoardKind::DriveSteer
        .table()
        .iter()
        .filter(|r| r.range.is_some())
    {
        let scale = Scale::of(&DS, reg.id);
        let range = reg.range.unwrap();
        let full = mapping::full_scale(reg.size) as u16;
        assert_eq!(scale.map(Fix::from_num(range.min)), 0, "{}", reg.name);
        assert_eq!(scale.map(Fix::from_num(range.max)), full, "{}", reg.name);
        assert_eq!(scale.map(Fix::from_num(range.max) + Fix::ONE), full);
        assert_eq!(scale.map(Fix::from_num(range.min) - Fix::ONE), 0);
        if range.min == -range.max && reg.size == 2 {
            assert_eq!(scale.map(Fix::ZERO), 0x7fff, "{}", reg.name);
        }
        let steps = 5000;
        for i in 0..=steps {
            let v = range.min + (range.max - range.min) * i as f32 / steps as f32;
            let fixed = Fix::from_num(v);
            let got = i32::from(scale.map(fixed));
            let float = i32::from(mapping::map(fixed.to_num::<f32>(), reg));
            assert!(
                (got - float).abs() <= 1,
                "{} {v}: {got} vs {float}",
                reg.name
            );
        }
    }
}

#[test]
fn map_int_of_chassis_readings() {
    let chassis = Scale::of(&DS, REGDS_CHASSIS);
    for reading in [0u16, 1, 100, 512, 1000, 1023] {
        let float = mapping::map(f32::from(reading), ds(REGDS_CHASSIS));
        assert_eq!(chassis.map_int(reading), float, "reading {reading}");
    }
    assert_eq!(chassis.map_int(512), 32767);
}

/// The slave takes its position-motor scales from the DS steer block; every LL motor
/// register must have the same range and size.
#[test]
fn position_scales_are_the_same_on_every_position_motor() {
    let params = [
        Param::Required,
        Param::P,
        Param::I,
        Param::D,
        Param::Cap,
        Param::Decay,
        Param::Threshold,
        Param::StallCheck,
        Param::DeadZone,
        Param::CalibMin,
        Param::CalibMax,
    ];
    let motors = [
        (Variant::DriveSteer, MotorId::M1, Kind::Drive),
        (Variant::DriveSteer, MotorId::M2, Kind::Position),
        (Variant::LiftLift, MotorId::M1, Kind::Position),
        (Variant::LiftLift, MotorId::M2, Kind::Position),
    ];
    for (variant, motor, kind) in motors {
        let layout = Layout::of(variant, motor);
        let table = if variant == Variant::DriveSteer {
            &DS[..]
        } else {
            &LL[..]
        };
        for param in params {
            let Some(id) = layout.param_id(param) else {
                assert_eq!(kind, Kind::Drive, "{param:?}");
                continue;
            };
            assert_eq!(layout.param(id), Some(param), "{variant:?} {motor:?} {id}");
            assert_eq!(
                kind.param_scale(param),
                Scale::of(table, id),
                "{variant:?} {motor:?} {param:?}"
            );
        }
        for monitor in Monitor::ALL {
            let id = layout.monitor_id(monitor);
            let reg = &table[usize::from(id)];
            match kind.monitor_scale(monitor) {
                Some(scale) => assert_eq!(scale, Scale::of(table, id), "{}", reg.name),
                None => assert!(reg.range.is_none() && reg.name.ends_with("CURRENT")),
            }
        }
    }
}

#[test]
fn layouts_name_the_right_registers() {
    let ll = BoardKind::LiftLift;
    let two = Layout::of(Variant::LiftLift, MotorId::M2);
    assert_eq!(ll.register(two.base).unwrap().name, "REGLL_TWO_REQPOS");
    assert_eq!(
        ll.register(two.monitor_id(Monitor::Current)).unwrap().name,
        "REGLL_TWO_CURRENT"
    );
    assert_eq!(two.param(REGLL_TWO_STALLCHECK), Some(Param::StallCheck));
    assert_eq!(two.param(REGLL_ONE_STALLCHECK), None);
    let drive = Layout::of(Variant::DriveSteer, MotorId::M1);
    assert_eq!(
        drive.param(REGDS_DRIVE_OVERCURRENTTHRESH),
        Some(Param::Threshold)
    );
    assert_eq!(drive.param(REGDS_DRIVE_ACTUALSPEED), None, "monitoring");
    assert_eq!(drive.param(REGDS_DRIVE_ODO), None);
    assert_eq!(drive.param_id(Param::CalibMin), None);
    let steer = Layout::of(Variant::DriveSteer, MotorId::M2);
    assert_eq!(steer.param(REGDS_STEER_CALIBMAX), Some(Param::CalibMax));
    assert_eq!(
        BoardKind::DriveSteer
            .register(steer.monitor_id(Monitor::Interval))
            .unwrap()
            .name,
        "REGDS_STEER_INTERVALCTRL"
    );
}
