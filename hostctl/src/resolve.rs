//! Command-line text to checked rover terms: devices, read sets, registers
//! and values. Every check here runs before the port is opened.

use shared::mapping;
use shared::protocol::{MAX_DEVICE, READ_SETS, READ_SET_SIZE};
use shared::regs::{id, BoardKind, Register};
use shared::slave::board::{Layout, Param};
use shared::slave::{DriveMode, MotorId, Variant};

use crate::error::{Allowed, HostError};
use crate::suggest;

/// The board kinds, for searching every table.
const KINDS: [BoardKind; 3] = [
    BoardKind::Master,
    BoardKind::DriveSteer,
    BoardKind::LiftLift,
];

/// A device and the table it uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Target {
    /// Device number, 0..=9.
    pub device: u8,
    /// Its board kind.
    pub kind: BoardKind,
}

impl Target {
    /// The target for a device number, if it is one.
    pub fn of(device: u8) -> Option<Self> {
        if device > MAX_DEVICE {
            return None;
        }
        BoardKind::of_device(device).map(|kind| Self { device, kind })
    }

    /// The table's name, e.g. `DS`.
    pub fn board(&self) -> &'static str {
        self.kind.name()
    }
}

/// Parses a number in decimal or `0x` hex (one too large for 32 bits is `u32::MAX`, out of
/// every range).
fn number(text: &str) -> Option<u32> {
    let t = text.trim();
    match t.strip_prefix("0x").or_else(|| t.strip_prefix("0X")) {
        Some(digits) => hex_number(digits).map(|v| u32::try_from(v).unwrap_or(u32::MAX)),
        None => t.parse().ok(),
    }
}

/// `digits` as hexadecimal: hex digits only (`from_str_radix` would also take a sign, so
/// `0x+1` would pass); a number too large for 64 bits is `u64::MAX`, out of every range.
fn hex_number(digits: &str) -> Option<u64> {
    if digits.is_empty() || !digits.bytes().all(|b| b.is_ascii_hexdigit()) {
        return None;
    }
    Some(u64::from_str_radix(digits, 16).unwrap_or(u64::MAX))
}

/// Parses a device number (0..9).
pub fn device(text: &str) -> Result<Target, HostError> {
    number(text)
        .and_then(|n| u8::try_from(n).ok())
        .and_then(Target::of)
        .ok_or_else(|| HostError::BadDevice {
            given: text.to_owned(),
        })
}

/// Parses a read-set index (0..7).
pub fn set(text: &str) -> Result<u8, HostError> {
    number(text)
        .filter(|&n| n < READ_SETS as u32)
        .and_then(|n| u8::try_from(n).ok())
        .ok_or_else(|| HostError::BadSet {
            given: text.to_owned(),
        })
}

/// The devices that use `kind`'s table, e.g. `1, 2, 4, 5, 7, 8`.
pub fn devices_of(kind: BoardKind) -> String {
    (0..=MAX_DEVICE)
        .filter(|&d| BoardKind::of_device(d) == Some(kind))
        .map(|d| d.to_string())
        .collect::<Vec<_>>()
        .join(", ")
}

/// Resolves a register name or number against the target's table.
pub fn register(target: Target, text: &str) -> Result<&'static Register, HostError> {
    // Spaces around the name (a quoted argument), as around a device or value, are no part
    // of it.
    let text = text.trim();
    let table = target.kind.table();
    if let Some(id) = number(text) {
        return u8::try_from(id)
            .ok()
            .and_then(|id| target.kind.register(id))
            .ok_or(HostError::NoSuchId {
                id,
                device: target.device,
                board: target.board(),
                last: u8::try_from(table.len().saturating_sub(1)).unwrap_or(u8::MAX),
            });
    }
    if let Some(reg) = target.kind.lookup(text) {
        return Ok(reg);
    }
    let others: Vec<BoardKind> = KINDS
        .into_iter()
        .filter(|&k| k != target.kind && k.lookup(text).is_some())
        .collect();
    if !others.is_empty() {
        // The common block (REG_TIMER …) is on both controller tables: name them both.
        let names: Vec<&str> = others.iter().map(|k| k.name()).collect();
        let other = match names.as_slice() {
            [one] => format!("{one} table"),
            _ => format!("{} tables", names.join(" and ")),
        };
        let devices = (0..=MAX_DEVICE)
            .filter(|&d| BoardKind::of_device(d).is_some_and(|k| others.contains(&k)))
            .map(|d| d.to_string())
            .collect::<Vec<_>>()
            .join(", ");
        return Err(HostError::WrongBoard {
            name: text.to_owned(),
            device: target.device,
            board: target.board(),
            other,
            devices,
        });
    }
    let close = suggest::close_names(text, table.iter().map(|r| r.name));
    let elsewhere: Vec<String> = KINDS
        .into_iter()
        .filter(|&k| k != target.kind)
        .flat_map(|k| {
            suggest::close_names(text, k.table().iter().map(|r| r.name))
                .into_iter()
                .map(move |n| format!("{n} ({}: devices {})", k.name(), devices_of(k)))
        })
        .take(3)
        .collect();
    let hint = if !close.is_empty() {
        format!("; did you mean {}?", close.join(", "))
    } else if !elsewhere.is_empty() {
        format!("; other boards have {}", elsewhere.join(", "))
    } else {
        "; the register names are listed in docs/registers.md".to_owned()
    };
    Err(HostError::UnknownRegister {
        name: text.to_owned(),
        device: target.device,
        board: target.board(),
        hint,
    })
}

/// Resolves the registers of one read set (at most 24).
pub fn read_set(target: Target, texts: &[String]) -> Result<Vec<&'static Register>, HostError> {
    if texts.len() > READ_SET_SIZE {
        return Err(HostError::TooManyRegisters { count: texts.len() });
    }
    texts.iter().map(|t| register(target, t)).collect()
}

/// The values a register accepts: its range when mapped, otherwise what its
/// raw size holds.
pub fn allowed(reg: &Register) -> (f32, f32) {
    match reg.range {
        Some(r) => (r.min, r.max),
        None if reg.size == 1 => (0.0, 255.0),
        None => (0.0, 65535.0),
    }
}

impl Allowed {
    /// What `reg` on `device` allows ([`allowed`], [`unit_suffix`]).
    pub fn of(reg: &Register, device: u8) -> Allowed {
        let (min, max) = allowed(reg);
        Allowed {
            register: reg.name,
            device,
            min,
            max,
            unit: unit_suffix(reg),
        }
    }
}

/// A register's unit with a leading space, or nothing.
pub fn unit_suffix(reg: &Register) -> String {
    if reg.unit.is_empty() {
        String::new()
    } else {
        format!(" {}", reg.unit)
    }
}

/// `text` with each Unicode minus sign (U+2212, "−", as the docs print negative numbers
/// and a copy from them brings along) made the ASCII `-` that Rust's parsers read.
pub fn ascii_minus(text: &str) -> String {
    text.replace('\u{2212}', "-")
}

/// Parses and checks a value for a write, returning it and its raw form.
pub fn value(target: Target, reg: &'static Register, text: &str) -> Result<(f32, u16), HostError> {
    let given = text.trim();
    let hex = given
        .strip_prefix("0x")
        .or_else(|| given.strip_prefix("0X"));
    let parsed = match hex {
        // An unmapped register (a bit field, a count) takes hexadecimal too, as device and
        // register numbers do; its values fit 16 bits, so the f32 is exact where it counts.
        Some(digits) if reg.range.is_none() => hex_number(digits).map(|v| v as f32),
        // "nan" parses as an f32, but is no number; "inf" and 1e39 are out of range below.
        _ => ascii_minus(given)
            .parse::<f32>()
            .ok()
            .filter(|v| !v.is_nan()),
    };
    let value = parsed.ok_or_else(|| HostError::BadValue {
        given: text.to_owned(),
    })?;
    let bounds = Allowed::of(reg, target.device);
    if !value.is_finite()
        || value < bounds.min
        || value > bounds.max
        || !mapping::in_range(value, reg)
    {
        return Err(HostError::OutOfRange {
            given: given.to_owned(),
            allowed: bounds,
        });
    }
    // An unmapped register is an integer (a bit field, a count): map() would drop the
    // fraction silently.
    if reg.range.is_none() && value.fract() != 0.0 {
        return Err(HostError::NotWhole {
            value,
            allowed: bounds,
            example: value.trunc(),
        });
    }
    let raw = mapping::map(value, reg);
    // A value the mapping truncates to the register's 0 would be sent as "off" without a
    // word: a gain of 0.0001 on a register whose step is 0.00015.
    if value != 0.0 && mapping::unmap(raw, reg) == 0.0 {
        if let Some(step) = step_above_zero(reg) {
            return Err(HostError::BelowStep {
                given: given.to_owned(),
                allowed: bounds,
                step: round_up(step),
                steps: mapping::full_scale(reg.size),
            });
        }
    }
    Ok((value, raw))
}

/// What a slave makes of a register's value, where that is not the unmapped value.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum SlaveUse {
    /// The unmapped value itself.
    Value,
    /// Truncated toward zero to an integer (OVERCURRENTTHRESH, STALLCHECK; reference §3).
    Integer,
    /// REGDS_DRIVE_MODE: 1 selects mode 1, any other value mode 0.
    DriveMode,
}

/// How the slave uses `reg`, from the slaves' own parameter layout.
fn slave_use(reg: &Register) -> SlaveUse {
    for kind in [BoardKind::DriveSteer, BoardKind::LiftLift] {
        // Names are unique across the tables, so this finds the table `reg` is from.
        if kind.register(reg.id).is_none_or(|r| r.name != reg.name) {
            continue;
        }
        if kind == BoardKind::DriveSteer && reg.id == id::REGDS_DRIVE_MODE {
            return SlaveUse::DriveMode;
        }
        let Some(variant) = Variant::of_board(kind) else {
            continue;
        };
        for motor in [MotorId::M1, MotorId::M2] {
            if let Some(Param::Threshold | Param::StallCheck) =
                Layout::of(variant, motor).param(reg.id)
            {
                return SlaveUse::Integer;
            }
        }
    }
    SlaveUse::Value
}

/// What a board makes of `raw` written to `reg`: the unmapped value, except that integer
/// parameters are truncated as the slave truncates them and DRIVE_MODE is the mode
/// applied. (A register read back shows its own value, [`show`]: at boot a threshold's
/// register holds 299.997 while the board uses its default, 300.)
pub fn applied(reg: &Register, raw: u16) -> f32 {
    match slave_use(reg) {
        // The float32 result truncated equals the slave's fixed-point integer for every
        // raw value (shared::slave::scale, tested exhaustively there).
        SlaveUse::Integer => mapping::unmap(raw, reg).trunc(),
        SlaveUse::DriveMode => match DriveMode::from_register(raw) {
            DriveMode::Window => 0.0,
            DriveMode::EdgeTiming => 1.0,
        },
        SlaveUse::Value => mapping::unmap(raw, reg),
    }
}

/// [`applied`] for people: as [`show`] writes a value, whole numbers without decimals.
pub fn arrives_as(reg: &Register, raw: u16) -> String {
    match slave_use(reg) {
        SlaveUse::Value => show(reg, raw),
        SlaveUse::Integer | SlaveUse::DriveMode => format!("{:.0}", applied(reg, raw)),
    }
}

/// For `write`: what the board makes of `raw`, in words: `arrives as 999.908 ticks/s`,
/// or for a drive mode other than 0 and 1, that the board keeps it and acts as mode 0
/// (it reads back as written).
pub fn write_effect(reg: &Register, raw: u16) -> String {
    match slave_use(reg) {
        SlaveUse::DriveMode if raw > 1 => format!("kept as {raw}, which acts as mode 0"),
        _ => format!("arrives as {}{}", arrives_as(reg, raw), unit_suffix(reg)),
    }
}

/// For `read`: what a board does with a register it does not use as its value, or
/// `None` where it does. A threshold's register also differs from the board's own value
/// from boot until its first write (reference §8.1: DRIVE_OVERCURRENTTHRESH reads 299.997
/// and STALLCHECK 119.469 while the board uses 300 and 120).
pub fn use_note(reg: &Register, raw: u16) -> Option<String> {
    match slave_use(reg) {
        SlaveUse::Value => None,
        SlaveUse::Integer => Some(format!(
            "the board uses whole numbers: written, this value acts as {}; from boot until \
             the first write it uses {}",
            arrives_as(reg, raw),
            power_on_integer(reg),
        )),
        SlaveUse::DriveMode => (raw > 1).then(|| "any value but 1 acts as mode 0".to_owned()),
    }
}

/// The board's own value of an integer parameter at power-up.
fn power_on_integer(reg: &Register) -> u16 {
    if reg.name.ends_with("STALLCHECK") {
        u16::from(shared::slave::fault::STALL_CHECK_POWER_ON)
    } else {
        shared::slave::motor::THRESHOLD_POWER_ON
    }
}

/// The end of its range a reading stands at, where the rover clamps what it reports.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Limit {
    /// Raw 0: the range's low end, or anything below it.
    Lower,
    /// Raw F or above: the range's high end, or anything above it.
    Upper,
}

impl Limit {
    /// The sign written before such a value: "≤" or "≥".
    pub fn sign(self) -> &'static str {
        match self {
            Limit::Lower => "≤",
            Limit::Upper => "≥",
        }
    }

    /// Its name in JSON: "lower" or "upper".
    pub fn name(self) -> &'static str {
        match self {
            Limit::Lower => "lower",
            Limit::Upper => "upper",
        }
    }
}

/// The decimals that tell one raw value of a mapped register from the next: at least 3,
/// more for a fine step (a gain on 0..10 in 65,534 steps of 0.00015 shows 4, so its raw 2
/// reads 0.0003, not 0.000), at most 6.
pub fn decimals(reg: &Register) -> usize {
    let Some(range) = reg.range else {
        return 0;
    };
    let step = f64::from(range.max - range.min) / f64::from(mapping::full_scale(reg.size));
    let needed = (-step.log10()).ceil();
    // A step of 1 or more needs none; NaN (an empty range) falls to the minimum.
    if needed.is_nan() || needed < 3.0 {
        3
    } else {
        (needed as usize).min(6)
    }
}

/// The smallest value above 0 that `reg` carries: one raw step above its low end, for a
/// register whose range starts at 0. `None` for other ranges (their 0 is not a raw value's
/// own) and for unmapped registers.
pub fn step_above_zero(reg: &Register) -> Option<f32> {
    let range = reg.range.filter(|r| r.min == 0.0)?;
    Some(mapping::unmap(1, reg)).filter(|_| range.max > 0.0)
}

/// `x` (> 0) rounded up to two significant digits, as text: a value to type that is not
/// below `x` (0.00015259 → 0.00016).
fn round_up(x: f32) -> String {
    let x = f64::from(x);
    let exponent = x.log10().floor() as i32 - 1;
    let scale = 10f64.powi(exponent);
    let decimals = usize::try_from(-exponent).unwrap_or(0);
    format!("{:.*}", decimals, (x / scale).ceil() * scale)
}

/// Whether `raw` of `reg` is a reading at an end of the register's range. A read-only
/// mapped register holds a value the board (or the master) measured and mapped with
/// clamping (reference §3), so its ends stand for "this or beyond": a board at 110 °C
/// reads 100. A low end at 0 or above is no clamp (an interval, the chassis pot: nothing
/// reads below it), a writable register holds what was written, and a duty (CONTROL) is
/// the PWM level itself, which has no value beyond ±255.
pub fn limit_of(reg: &Register, raw: u16) -> Option<Limit> {
    let range = reg.range.filter(|_| !reg.writable && reg.unit != "duty")?;
    if u32::from(raw) >= mapping::full_scale(reg.size) {
        Some(Limit::Upper)
    } else if raw == 0 && range.min < 0.0 {
        Some(Limit::Lower)
    } else {
        None
    }
}

/// A register's value for people: unmapped registers as integers, mapped ones with the
/// decimals [`decimals`] gives, a reading at its range's end with "≥" or "≤"
/// ([`limit_of`]).
pub fn show(reg: &Register, raw: u16) -> String {
    if reg.range.is_none() {
        return raw.to_string();
    }
    let text = format!("{:.*}", decimals(reg), mapping::unmap(raw, reg));
    // A value that rounds to zero shows as 0, not -0.
    let text = match text.strip_prefix('-') {
        Some(rest) if rest.chars().all(|c| c == '0' || c == '.') => rest.to_owned(),
        _ => text,
    };
    match limit_of(reg, raw) {
        Some(limit) => format!("{}{text}", limit.sign()),
        None => text,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ds() -> Target {
        device("1").unwrap()
    }

    fn ll() -> Target {
        device("3").unwrap()
    }

    #[test]
    fn devices_map_to_their_tables() {
        assert_eq!(device("0").unwrap().kind, BoardKind::Master);
        assert_eq!(device("1").unwrap().kind, BoardKind::DriveSteer);
        assert_eq!(device("8").unwrap().kind, BoardKind::DriveSteer);
        assert_eq!(device("0x6").unwrap().kind, BoardKind::LiftLift);
        assert_eq!(device("9").unwrap().device, 9);
        for bad in ["10", "15", "256", "-1", "one", "", "0x+1", "0x-0"] {
            assert!(
                matches!(device(bad), Err(HostError::BadDevice { ref given }) if given == bad),
                "{bad}"
            );
        }
        assert_eq!(devices_of(BoardKind::LiftLift), "3, 6, 9");
        assert_eq!(devices_of(BoardKind::DriveSteer), "1, 2, 4, 5, 7, 8");
        assert_eq!(devices_of(BoardKind::Master), "0");
    }

    #[test]
    fn sets_are_0_to_7() {
        assert_eq!(set("0").unwrap(), 0);
        assert_eq!(set("7").unwrap(), 7);
        for bad in ["8", "255", "x", "-1"] {
            assert!(matches!(set(bad), Err(HostError::BadSet { .. })), "{bad}");
        }
    }

    #[test]
    fn names_resolve_with_or_without_prefix_in_any_case() {
        for text in [
            "REGLL_ONE_REQPOS",
            "regll_one_reqpos",
            "ONE_REQPOS",
            "One_ReqPos",
            " one_reqpos",
            "9",
        ] {
            let reg = register(ll(), text).unwrap();
            assert_eq!((reg.id, reg.name), (9, "REGLL_ONE_REQPOS"), "{text}");
        }
        assert_eq!(register(ds(), "drive_reqspeed").unwrap().id, 9);
        assert_eq!(register(ds(), "0x1a").unwrap().name, "REGDS_STEER_REQPOS");
        assert_eq!(register(ds(), "timer").unwrap().id, 1);
        assert_eq!(
            register(device("0").unwrap(), "reset").unwrap().name,
            "REGMASTER_RESET"
        );
    }

    #[test]
    fn numbers_beyond_the_table_are_refused() {
        // The original 45 registers plus this project's 45 (FAULTTIME), 46 (DRIVE_MODE)
        // and 47 (BUSTIMEOUT).
        let err = register(ds(), "48").unwrap_err();
        assert_eq!(
            err.to_string(),
            "device 1 (DS table) has registers 0..47; there is no register 48"
        );
        let err = register(device("0").unwrap(), "16").unwrap_err();
        assert_eq!(
            err.to_string(),
            "device 0 (MASTER table) has registers 0..15; there is no register 16"
        );
        assert!(matches!(
            register(ds(), "300"),
            Err(HostError::NoSuchId { id: 300, .. })
        ));
    }

    #[test]
    fn names_of_another_board_say_which_devices_have_them() {
        let err = register(ds(), "REGLL_ONE_REQPOS").unwrap_err();
        assert_eq!(
            err.to_string(),
            "register `REGLL_ONE_REQPOS` is on the LL table, not on device 1 (DS); \
             address one of devices 3, 6, 9 instead (readset and watch: --device)"
        );
        // A register of the common block is on every controller, DS and LL alike.
        let err = register(device("0").unwrap(), "TIMER").unwrap_err();
        assert_eq!(
            err.to_string(),
            "register `TIMER` is on the DS and LL tables, not on device 0 (MASTER); \
             address one of devices 1, 2, 3, 4, 5, 6, 7, 8, 9 instead (readset and watch: --device)"
        );
    }

    #[test]
    fn unknown_names_get_suggestions() {
        let err = register(ds(), "DRIVE_REQSPED").unwrap_err();
        assert_eq!(
            err.to_string(),
            "device 1 (DS table) has no register named `DRIVE_REQSPED`; \
             did you mean REGDS_DRIVE_REQSPEED?"
        );
        let err = register(device("0").unwrap(), "REQPOS").unwrap_err();
        assert_eq!(
            err.to_string(),
            "device 0 (MASTER table) has no register named `REQPOS`; other boards have \
             REGDS_STEER_REQPOS (DS: devices 1, 2, 4, 5, 7, 8), \
             REGLL_ONE_REQPOS (LL: devices 3, 6, 9), REGLL_TWO_REQPOS (LL: devices 3, 6, 9)"
        );
        let err = register(ds(), "BANANA").unwrap_err();
        assert_eq!(
            err.to_string(),
            "device 1 (DS table) has no register named `BANANA`; \
             the register names are listed in docs/registers.md"
        );
    }

    #[test]
    fn values_map_through_the_register_range() {
        let speed = register(ds(), "DRIVE_REQSPEED").unwrap();
        assert_eq!(value(ds(), speed, "1000").unwrap(), (1000.0, 0x9ffe));
        assert_eq!(value(ds(), speed, "-1000").unwrap(), (-1000.0, 0x5fff));
        assert_eq!(value(ds(), speed, "-4000").unwrap().1, 0x0000);
        assert_eq!(value(ds(), speed, "4000").unwrap().1, 0xfffe);
        let calib = register(ds(), "STEER_CALIBMIN").unwrap();
        assert_eq!(value(ds(), calib, "-56").unwrap().1, 0x43);
        let lift = register(ll(), "ONE_REQPOS").unwrap();
        assert_eq!(value(ll(), lift, "20").unwrap().1, 0x8ccb);
        let reset = register(ds(), "RESET").unwrap();
        assert_eq!(value(ds(), reset, "4").unwrap().1, 4);
        // Unmapped registers take hexadecimal; mapped ones do not (0x10 ticks/s is no unit).
        let disabled = register(ds(), "DISABLEDEXCEPTIONS").unwrap();
        assert_eq!(value(ds(), disabled, "0x1000").unwrap(), (4096.0, 0x1000));
        assert_eq!(value(ds(), disabled, "0XfFfF").unwrap().1, 0xffff);
        assert!(matches!(
            value(ds(), disabled, "0x10000"),
            Err(HostError::OutOfRange { .. })
        ));
        for bad in ["0x", "0xg1", "0x-1", "0x+1", "0x 1"] {
            assert!(
                matches!(value(ds(), disabled, bad), Err(HostError::BadValue { .. })),
                "{bad}"
            );
        }
        // Hex too long for any register is out of range, not "not a number".
        for long in ["0xffffffffff", "0xffffffffffffffffffff"] {
            assert!(
                matches!(
                    value(ds(), disabled, long),
                    Err(HostError::OutOfRange { .. })
                ),
                "{long}"
            );
        }
        assert!(matches!(
            value(ds(), speed, "0x10"),
            Err(HostError::BadValue { .. })
        ));
    }

    #[test]
    fn out_of_range_values_name_register_device_and_range() {
        let speed = register(ds(), "DRIVE_REQSPEED").unwrap();
        assert_eq!(
            value(ds(), speed, "4000.5").unwrap_err().to_string(),
            "4000.5 is out of range for REGDS_DRIVE_REQSPEED on device 1: \
             allowed -4000..4000 ticks/s"
        );
        for bad in ["inf", "-inf", "-4001"] {
            assert!(
                matches!(value(ds(), speed, bad), Err(HostError::OutOfRange { .. })),
                "{bad}"
            );
        }
        // The message echoes what was typed, not the f32 it parsed to.
        for typed in ["1e39", "99999999999"] {
            assert_eq!(
                value(ds(), speed, typed).unwrap_err().to_string(),
                format!(
                    "{typed} is out of range for REGDS_DRIVE_REQSPEED on device 1: \
                     allowed -4000..4000 ticks/s"
                )
            );
        }
        // NaN is no number at all.
        for nan in ["nan", "NaN", "-nan"] {
            assert!(
                matches!(value(ds(), speed, nan), Err(HostError::BadValue { .. })),
                "{nan}"
            );
        }
        let reset = register(ds(), "RESET").unwrap();
        assert_eq!(
            value(ds(), reset, "256").unwrap_err().to_string(),
            "256 is out of range for REG_RESET on device 1: allowed 0..255 bits"
        );
        assert!(matches!(
            value(ds(), reset, "-1"),
            Err(HostError::OutOfRange { .. })
        ));
        let status = register(ds(), "STATUS").unwrap();
        assert_eq!(allowed(status), (0.0, 65535.0));
        assert_eq!(
            value(ds(), reset, "1.5").unwrap_err().to_string(),
            "1.5 is not a whole number, but REG_RESET on device 1 holds whole numbers \
             0..255 bits; give one, e.g. 1"
        );
        let faulttime = register(ds(), "FAULTTIME").unwrap();
        assert!(matches!(
            value(ds(), faulttime, "500.25"),
            Err(HostError::NotWhole { .. })
        ));
        assert_eq!(value(ds(), faulttime, "500.0").unwrap(), (500.0, 500));
        // Mapped registers take fractions.
        assert_eq!(value(ds(), speed, "0.5").unwrap().0, 0.5);
        // A Unicode minus (U+2212, as the docs print "−40") is a minus.
        assert_eq!(
            value(ds(), speed, "\u{2212}40.5").unwrap(),
            value(ds(), speed, "-40.5").unwrap()
        );
        assert!(matches!(
            value(ds(), speed, "fast"),
            Err(HostError::BadValue { ref given }) if given == "fast"
        ));
    }

    #[test]
    fn a_fine_step_is_shown_and_a_value_below_it_refused() {
        let pgain = register(ds(), "drive_pgain").unwrap();
        // 0..10 in 65,534 steps of 0.000153: four decimals, so raw 2 is not 0.000.
        assert_eq!(decimals(pgain), 4);
        assert_eq!(show(pgain, 2), "0.0003");
        assert_eq!(show(pgain, 0), "0.0000");
        assert_eq!(show(pgain, 0x41), "0.0099");
        // ±4000 in steps of 0.12: three, as before.
        let speed = register(ds(), "drive_reqspeed").unwrap();
        assert_eq!(decimals(speed), 3);
        assert_eq!(show(speed, 0x7fff), "0.000");
        // A gain above 0 that would arrive as 0 is refused; one step is taken.
        assert_eq!(
            value(ds(), pgain, "0.0001").unwrap_err().to_string(),
            "0.0001 is finer than REGDS_DRIVE_PGAIN on device 1 can carry: it would arrive \
             as 0 (its values run 0..10 in 65534 steps); write 0, or 0.00016 or more"
        );
        assert_eq!(value(ds(), pgain, "0.00016").unwrap(), (0.00016, 1));
        assert_eq!(value(ds(), pgain, "0").unwrap(), (0.0, 0));
        // A signed range has no such floor: 0.05 ticks/s arrives as the step below it,
        // raw 0x7fff, which is 0 on ±4000.
        assert_eq!(value(ds(), speed, "0.05").unwrap(), (0.05, 0x7fff));
    }

    #[test]
    fn read_sets_hold_at_most_24() {
        let names: Vec<String> = (0..25).map(|_| "TIMER".to_owned()).collect();
        assert!(matches!(
            read_set(ds(), &names),
            Err(HostError::TooManyRegisters { count: 25 })
        ));
        assert_eq!(read_set(ds(), &names[..24]).unwrap().len(), 24);
    }

    #[test]
    fn shown_values_use_units_and_precision() {
        let speed = register(ds(), "DRIVE_REQSPEED").unwrap();
        assert_eq!(show(speed, 0x9ffe), "999.908");
        assert_eq!(show(speed, 0x7fff), "0.000");
        assert_eq!(show(speed, 0xffff), "4000.122");
        let temp = register(device("0").unwrap(), "TEMPAMBIENT").unwrap();
        // -0.0006 °C rounds to -0.001, not to a negative zero.
        assert_eq!(show(temp, 0x2aaa), "-0.001");
        assert_eq!(show(temp, 0x5887), "21.498");
        let timer = register(ds(), "TIMER").unwrap();
        assert_eq!(show(timer, 65535), "65535");
        assert_eq!(unit_suffix(speed), " ticks/s");
    }

    #[test]
    fn written_values_arrive_as_the_slave_uses_them() {
        // Thresholds and stall checks are truncated to integers (reference §3: 10 → 9).
        let thresh = register(ds(), "DRIVE_OVERCURRENTTHRESH").unwrap();
        assert_eq!(arrives_as(thresh, 0x028f), "9");
        assert_eq!(applied(thresh, 0x028f), 9.0);
        assert_eq!(arrives_as(thresh, 0x3332), "199");
        assert_eq!(arrives_as(thresh, 0xfffe), "1000");
        let stall = register(ds(), "STEER_STALLCHECK").unwrap();
        assert_eq!(arrives_as(stall, 0x63), "99");
        let lift = register(ll(), "TWO_OVERCURRENTTHRESH").unwrap();
        assert_eq!(arrives_as(lift, 0x028f), "9");
        assert_eq!(
            arrives_as(register(ll(), "ONE_STALLCHECK").unwrap(), 0xfe),
            "255"
        );
        // DRIVE_MODE: 1 is mode 1; anything else is mode 0.
        let mode = register(ds(), "DRIVE_MODE").unwrap();
        assert_eq!(arrives_as(mode, 1), "1");
        assert_eq!(arrives_as(mode, 0), "0");
        assert_eq!(arrives_as(mode, 5), "0");
        assert_eq!(write_effect(mode, 1), "arrives as 1 mode");
        assert_eq!(write_effect(mode, 7), "kept as 7, which acts as mode 0");
        assert_eq!(applied(mode, 5), 0.0);
        // Other registers keep their mapped value.
        let cap = register(ds(), "DRIVE_INTEGRALCAP").unwrap();
        assert_eq!(arrives_as(cap, 0x4ccc), "299.997");
        assert_eq!(arrives_as(register(ds(), "FAULTTIME").unwrap(), 500), "500");
        // Read back, a register shows what it holds: at boot a threshold's register holds
        // 299.997 (the board uses its default, 300), not a truncated 299.
        assert_eq!(show(thresh, 0x4ccc), "299.997");
        assert_eq!(show(mode, 5), "5");
        assert_eq!(unit_suffix(register(ds(), "DRIVE_PGAIN").unwrap()), "");
    }
}
