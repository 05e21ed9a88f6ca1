//! The generated tables against an independently typed copy of the reference's
//! register tables (§2), plus the board map and name lookup.

use shared::regs::{self, id, BoardKind, Range, Register};

/// A range as (min, max).
type Span = Option<(f32, f32)>;
/// (id, symbol, size, writable, range) as typed from the reference.
type Expect = (u8, &'static str, u8, bool, Span);
/// The same with an owned symbol, for comparison.
type Row = (u8, String, u8, bool, Span);
/// (suffix, size, writable, range) of one lift motor register.
type Motor = (&'static str, u8, bool, Span);

const W: bool = true;
const R: bool = false;
const NONE: Option<(f32, f32)> = None;

const COMMON: [Expect; 9] = [
    (0, "REG_RESET", 1, W, NONE),
    (1, "REG_TIMER", 2, R, NONE),
    (2, "REG_INTERVALI2C", 2, R, NONE),
    (3, "REG_STATUS", 2, R, NONE),
    (4, "REG_DEBUGLED", 1, W, NONE),
    (5, "REG_EXCEPTIONDATA", 2, W, NONE),
    (6, "REG_DISABLEDEXCEPTIONS", 2, W, NONE),
    (7, "REG_PING", 1, W, NONE),
    (8, "REG_DEBUG", 2, W, NONE),
];

const DS_OWN: [Expect; 36] = [
    (9, "REGDS_DRIVE_REQSPEED", 2, W, Some((-4000.0, 4000.0))),
    (10, "REGDS_DRIVE_PGAIN", 2, W, Some((0.0, 10.0))),
    (11, "REGDS_DRIVE_IGAIN", 2, W, Some((0.0, 10.0))),
    (12, "REGDS_DRIVE_DGAIN", 2, W, Some((-10.0, 10.0))),
    (13, "REGDS_DRIVE_INTEGRALCAP", 2, W, Some((0.0, 1000.0))),
    (14, "REGDS_DRIVE_INTEGRALDECAY", 2, W, Some((0.0, 1.0))),
    (
        15,
        "REGDS_DRIVE_OVERCURRENTTHRESH",
        2,
        W,
        Some((0.0, 1000.0)),
    ),
    (16, "REGDS_DRIVE_ACTUALSPEED", 2, R, Some((-4000.0, 4000.0))),
    (17, "REGDS_DRIVE_ERROR", 2, R, Some((-1000.0, 1000.0))),
    (
        18,
        "REGDS_DRIVE_ERRORINTEGRAL",
        2,
        R,
        Some((-1000.0, 1000.0)),
    ),
    (19, "REGDS_DRIVE_ERRORDERIV", 2, R, Some((-200.0, 200.0))),
    (20, "REGDS_DRIVE_CONTROL", 2, R, Some((-255.0, 255.0))),
    (21, "REGDS_DRIVE_INTERVALCTRL", 2, R, Some((0.0, 1000.0))),
    (22, "REGDS_DRIVE_CURRENT", 2, R, NONE),
    (23, "REGDS_DRIVE_ODO", 2, R, NONE),
    (24, "REGDS_DRIVE_STALLCHECK", 1, W, Some((0.0, 255.0))),
    (25, "REGDS_DRIVE_DEADZONE", 1, W, Some((0.0, 50.0))),
    (26, "REGDS_STEER_REQPOS", 2, W, Some((-200.0, 200.0))),
    (27, "REGDS_STEER_PGAIN", 2, W, Some((0.0, 100.0))),
    (28, "REGDS_STEER_IGAIN", 2, W, Some((0.0, 10.0))),
    (29, "REGDS_STEER_DGAIN", 2, W, Some((-10.0, 10.0))),
    (30, "REGDS_STEER_INTEGRALCAP", 2, W, Some((0.0, 1000.0))),
    (31, "REGDS_STEER_INTEGRALDECAY", 2, W, Some((0.0, 1.0))),
    (
        32,
        "REGDS_STEER_OVERCURRENTTHRESH",
        2,
        W,
        Some((0.0, 1000.0)),
    ),
    (33, "REGDS_STEER_ACTUALPOS", 2, R, Some((-200.0, 200.0))),
    (34, "REGDS_STEER_ERROR", 2, R, Some((-200.0, 200.0))),
    (
        35,
        "REGDS_STEER_ERRORINTEGRAL",
        2,
        R,
        Some((-1000.0, 1000.0)),
    ),
    (36, "REGDS_STEER_ERRORDERIV", 2, R, Some((-200.0, 200.0))),
    (37, "REGDS_STEER_CONTROL", 2, R, Some((-255.0, 255.0))),
    (38, "REGDS_STEER_INTERVALCTRL", 2, R, Some((0.0, 1000.0))),
    (39, "REGDS_STEER_CURRENT", 2, R, NONE),
    (40, "REGDS_STEER_STALLCHECK", 1, W, Some((0.0, 255.0))),
    (41, "REGDS_STEER_DEADZONE", 1, W, Some((0.0, 50.0))),
    (42, "REGDS_STEER_CALIBMIN", 1, W, Some((-120.0, 120.0))),
    (43, "REGDS_STEER_CALIBMAX", 1, W, Some((-120.0, 120.0))),
    (44, "REGDS_CHASSIS", 2, R, Some((0.0, 1024.0))),
];

/// One lift motor's 18 registers (suffix, size, writable, range), ONE at 9, TWO at 27.
const LL_MOTOR: [Motor; 18] = [
    ("REQPOS", 2, W, Some((-200.0, 200.0))),
    ("PGAIN", 2, W, Some((0.0, 100.0))),
    ("IGAIN", 2, W, Some((0.0, 10.0))),
    ("DGAIN", 2, W, Some((-10.0, 10.0))),
    ("INTEGRALCAP", 2, W, Some((0.0, 1000.0))),
    ("INTEGRALDECAY", 2, W, Some((0.0, 1.0))),
    ("OVERCURRENTTHRESH", 2, W, Some((0.0, 1000.0))),
    ("ACTUALPOS", 2, R, Some((-200.0, 200.0))),
    ("ERROR", 2, R, Some((-200.0, 200.0))),
    ("ERRORINTEGRAL", 2, R, Some((-1000.0, 1000.0))),
    ("ERRORDERIV", 2, R, Some((-200.0, 200.0))),
    ("CONTROL", 2, R, Some((-255.0, 255.0))),
    ("INTERVALCTRL", 2, R, Some((0.0, 1000.0))),
    ("CURRENT", 2, R, NONE),
    ("CALIBMIN", 1, W, Some((-120.0, 120.0))),
    ("CALIBMAX", 1, W, Some((-120.0, 120.0))),
    ("STALLCHECK", 1, W, Some((0.0, 255.0))),
    ("DEADZONE", 1, W, Some((0.0, 50.0))),
];

const TEMP: Option<(f32, f32)> = Some((-20.0, 100.0));
/// Registers this project adds after the original master table (docs/protocol.md).
const MASTER_ADDED: [Expect; 4] = [
    (12, "REGMASTER_LASTERROR", 1, R, NONE),
    (13, "REGMASTER_ERRORCOUNT", 2, R, NONE),
    (14, "REGMASTER_TEMPSREAD", 2, R, NONE),
    (15, "REGMASTER_PCTIMEOUT", 2, W, NONE),
];

/// Registers this project adds after the original DS table (stall/fault timing, drive mode,
/// bus-silence timeout).
const DS_ADDED: [Expect; 3] = [
    (45, "REGDS_FAULTTIME", 2, W, NONE),
    (46, "REGDS_DRIVE_MODE", 1, W, NONE),
    (47, "REGDS_BUSTIMEOUT", 2, W, NONE),
];
/// Registers this project adds after the original LL table (stall/fault timing, bus-silence
/// timeout).
const LL_ADDED: [Expect; 2] = [
    (45, "REGLL_FAULTTIME", 2, W, NONE),
    (46, "REGLL_BUSTIMEOUT", 2, W, NONE),
];

const MASTER: [Expect; 12] = [
    (0, "REGMASTER_RESET", 1, W, NONE),
    (1, "REGMASTER_TEMPAMBIENT", 2, R, TEMP),
    (2, "REGMASTER_TEMP1", 2, R, TEMP),
    (3, "REGMASTER_TEMP2", 2, R, TEMP),
    (4, "REGMASTER_TEMP3", 2, R, TEMP),
    (5, "REGMASTER_TEMP4", 2, R, TEMP),
    (6, "REGMASTER_TEMP5", 2, R, TEMP),
    (7, "REGMASTER_TEMP6", 2, R, TEMP),
    (8, "REGMASTER_TEMP7", 2, R, TEMP),
    (9, "REGMASTER_TEMP8", 2, R, TEMP),
    (10, "REGMASTER_TEMP9", 2, R, TEMP),
    (11, "REGMASTER_EXCEPTIONDATA", 2, R, NONE),
];

fn ll_expected() -> Vec<Row> {
    let mut out: Vec<_> = COMMON
        .iter()
        .map(|e| (e.0, e.1.to_string(), e.2, e.3, e.4))
        .collect();
    for (motor, base) in [("ONE", 9u8), ("TWO", 27u8)] {
        for (i, (suffix, size, writable, range)) in LL_MOTOR.iter().enumerate() {
            let id = base + i as u8;
            out.push((
                id,
                format!("REGLL_{motor}_{suffix}"),
                *size,
                *writable,
                *range,
            ));
        }
    }
    out
}

fn owned(list: &[Expect]) -> Vec<Row> {
    list.iter()
        .map(|e| (e.0, e.1.to_string(), e.2, e.3, e.4))
        .collect()
}

fn actual(table: &[Register]) -> Vec<Row> {
    table
        .iter()
        .map(|r| {
            let range = r.range.map(|Range { min, max }| (min, max));
            (r.id, r.name.to_string(), r.size, r.writable, range)
        })
        .collect()
}

#[test]
fn master_table_matches_reference() {
    // The original's twelve registers, unchanged, then this project's additions.
    let mut expected = owned(&MASTER);
    expected.extend(owned(&MASTER_ADDED));
    assert_eq!(actual(BoardKind::Master.table()), expected);
}

#[test]
fn common_block_matches_reference() {
    assert_eq!(actual(&regs::COMMON), owned(&COMMON));
}

#[test]
fn ds_table_is_common_plus_its_own_block() {
    // The original's 45 registers, unchanged, then this project's additions.
    let mut expected = owned(&COMMON);
    expected.extend(owned(&DS_OWN));
    assert_eq!(expected.len(), 45);
    expected.extend(owned(&DS_ADDED));
    assert_eq!(actual(BoardKind::DriveSteer.table()), expected);
}

#[test]
fn ll_table_is_common_plus_one_and_two_blocks() {
    // The original's 45 registers, unchanged, then this project's additions.
    let mut expected = ll_expected();
    assert_eq!(expected.len(), 45);
    expected.extend(owned(&LL_ADDED));
    assert_eq!(actual(BoardKind::LiftLift.table()), expected);
}

#[test]
fn ll_two_is_one_plus_18() {
    let ll = BoardKind::LiftLift;
    for one in 9u8..=26 {
        let a = ll.register(one).unwrap();
        let b = ll.register(one + 18).unwrap();
        assert_eq!(a.short_name().replacen("ONE", "TWO", 1), b.short_name());
        assert_eq!((a.size, a.writable, a.range), (b.size, b.writable, b.range));
    }
}

#[test]
fn every_entry_has_unit_or_none_and_a_meaning() {
    for kind in [
        BoardKind::Master,
        BoardKind::DriveSteer,
        BoardKind::LiftLift,
    ] {
        for (index, reg) in kind.table().iter().enumerate() {
            assert_eq!(usize::from(reg.id), index, "{}", reg.name);
            assert!(!reg.doc.is_empty(), "{} has no meaning", reg.name);
            assert!(!reg.unit.contains(' '), "{}", reg.name);
        }
    }
    let speed = BoardKind::DriveSteer.lookup("DRIVE_REQSPEED").unwrap();
    assert_eq!(speed.unit, "ticks/s");
    assert_eq!(BoardKind::Master.register(1).unwrap().unit, "degC");
}

#[test]
fn flag_bytes_match_the_original_encoding() {
    let ds = BoardKind::DriveSteer;
    assert_eq!(ds.flag_byte(id::REG_RESET), Some(65));
    assert_eq!(ds.flag_byte(id::REGDS_DRIVE_REQSPEED), Some(66));
    assert_eq!(ds.flag_byte(id::REG_TIMER), Some(2));
    assert_eq!(ds.flag_byte(id::REGDS_FAULTTIME), Some(66));
    assert_eq!(ds.flag_byte(id::REGDS_DRIVE_MODE), Some(65));
    assert_eq!(ds.flag_byte(id::REGDS_BUSTIMEOUT), Some(66));
    assert_eq!(ds.flag_byte(48), None);
    assert_eq!(
        ds.register(id::REGDS_STEER_CALIBMIN).unwrap().flag_byte(),
        65
    );
}

#[test]
fn compact_accessors_agree_with_full_tables() {
    for kind in [
        BoardKind::Master,
        BoardKind::DriveSteer,
        BoardKind::LiftLift,
    ] {
        assert_eq!(usize::from(kind.len()), kind.table().len());
        assert!(!kind.is_empty());
        for reg in kind.table() {
            assert_eq!(kind.size_of(reg.id), Some(reg.size));
            assert_eq!(kind.is_writable(reg.id), Some(reg.writable));
            assert_eq!(kind.shape(reg.id), Some(reg.shape()));
        }
        let past = kind.len();
        assert_eq!(kind.size_of(past), None);
        assert_eq!(kind.shape(past), None);
        assert_eq!(kind.register(past), None);
        assert_eq!(kind.register(255), None);
    }
}

#[test]
fn devices_map_to_board_kinds() {
    let expected = [
        (0, Some(BoardKind::Master)),
        (1, Some(BoardKind::DriveSteer)),
        (2, Some(BoardKind::DriveSteer)),
        (3, Some(BoardKind::LiftLift)),
        (4, Some(BoardKind::DriveSteer)),
        (5, Some(BoardKind::DriveSteer)),
        (6, Some(BoardKind::LiftLift)),
        (7, Some(BoardKind::DriveSteer)),
        (8, Some(BoardKind::DriveSteer)),
        (9, Some(BoardKind::LiftLift)),
        (10, None),
        (11, None),
        (15, None),
        (255, None),
    ];
    for (device, kind) in expected {
        assert_eq!(BoardKind::of_device(device), kind, "device {device}");
    }
    assert_eq!(BoardKind::Master.table().len(), 12 + MASTER_ADDED.len());
    assert_eq!(BoardKind::DriveSteer.table().len(), 45 + DS_ADDED.len());
    assert_eq!(BoardKind::LiftLift.table().len(), 45 + LL_ADDED.len());
}

#[test]
fn names_of_board_kinds() {
    assert_eq!(BoardKind::Master.name(), "MASTER");
    assert_eq!(BoardKind::DriveSteer.name(), "DS");
    assert_eq!(BoardKind::LiftLift.name(), "LL");
}

#[test]
fn lookup_accepts_full_or_short_names_in_any_case() {
    let ll = BoardKind::LiftLift;
    assert_eq!(ll.lookup("regll_one_reqpos").map(|r| r.id), Some(9));
    assert_eq!(ll.lookup("ONE_REQPOS").map(|r| r.id), Some(9));
    assert_eq!(ll.lookup("two_reqpos").map(|r| r.id), Some(27));
    assert_eq!(ll.lookup("reset").map(|r| r.id), Some(0));
    assert_eq!(ll.lookup("REG_RESET").map(|r| r.id), Some(0));
    assert_eq!(
        BoardKind::Master.lookup("reset").map(|r| r.name),
        Some("REGMASTER_RESET")
    );
    assert_eq!(BoardKind::Master.lookup("temp9").map(|r| r.id), Some(10));
    let ds = BoardKind::DriveSteer;
    assert_eq!(ds.lookup("Drive_ReqSpeed").map(|r| r.id), Some(9));
    assert_eq!(ds.lookup("chassis").map(|r| r.id), Some(44));
    // A symbol of another board, a bare prefix, or a partial name is not found.
    assert_eq!(ds.lookup("ONE_REQPOS"), None);
    assert_eq!(ds.lookup("REGLL_ONE_REQPOS"), None);
    assert_eq!(ds.lookup("REGDS_"), None);
    assert_eq!(ds.lookup("REQSPEED"), None);
    assert_eq!(ds.lookup(""), None);
    assert_eq!(BoardKind::Master.lookup("REG_RESET"), None);
}

#[test]
fn id_constants_match_table_positions() {
    let checks = [
        (BoardKind::DriveSteer, id::REG_RESET, "REG_RESET"),
        (BoardKind::DriveSteer, id::REG_DEBUG, "REG_DEBUG"),
        (
            BoardKind::DriveSteer,
            id::REGDS_DRIVE_REQSPEED,
            "REGDS_DRIVE_REQSPEED",
        ),
        (
            BoardKind::DriveSteer,
            id::REGDS_STEER_REQPOS,
            "REGDS_STEER_REQPOS",
        ),
        (BoardKind::DriveSteer, id::REGDS_CHASSIS, "REGDS_CHASSIS"),
        (
            BoardKind::LiftLift,
            id::REGLL_ONE_REQPOS,
            "REGLL_ONE_REQPOS",
        ),
        (
            BoardKind::LiftLift,
            id::REGLL_TWO_DEADZONE,
            "REGLL_TWO_DEADZONE",
        ),
        (BoardKind::Master, id::REGMASTER_RESET, "REGMASTER_RESET"),
        (
            BoardKind::Master,
            id::REGMASTER_EXCEPTIONDATA,
            "REGMASTER_EXCEPTIONDATA",
        ),
    ];
    for (kind, id, name) in checks {
        assert_eq!(kind.register(id).map(|r| r.name), Some(name));
    }
    assert_eq!(id::REGDS_STEER_REQPOS, 26);
    assert_eq!(id::REGLL_TWO_REQPOS, 27);
    assert_eq!(id::REGMASTER_EXCEPTIONDATA, 11);
}
