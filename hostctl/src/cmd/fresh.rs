//! What a one-shot command (`read`, `write`) meets: opening the port reboots the rover (the
//! Uno's DTR reset, reference §4.1), so every controller it reaches is fresh from boot. It
//! is in its boot exception, where a write is stored but nothing acts on it (§6.4), and on
//! its boot calibration, where a position is not in degrees (§8.1: −512..512 internally).
//! The master is fresh too: it has read no temperature sensor yet (REGMASTER_TEMPSREAD).
//! The notes here say so, rather than let a value or a write pass as more than it is.

use shared::mapping;
use shared::regs::{id, Register, MASTER};

use super::read::SCRATCH_SET;
use super::{configure, set_frame, SetRead};
use crate::error::HostError;
use crate::json;
use crate::link::Link;
use crate::meaning::Meaning;
use crate::port::Port;
use crate::resolve::{self, Target};

/// `object` with register `reg`'s members for `--json`: id, name, raw, value in units and
/// unit, and `read` when the register is a master temperature (`read` its TEMPSREAD bit):
/// a temperature not read yet holds 0.0 °C, which is no value, so its value is `null`;
/// a coded value (EXCEPTIONDATA, STATUS, …) also comes taken apart ([`Meaning::json`]).
pub fn register_json(
    object: json::Object,
    device: u8,
    reg: &Register,
    raw: u16,
    read: Option<bool>,
) -> json::Object {
    let flag = read.map(|read| ("read", read));
    value_json(
        object.int("id", reg.id),
        device,
        reg,
        raw,
        read == Some(false),
        flag,
    )
}

/// `object` with `reg`'s name, raw, value (`null` when `no_value`) and unit, `at_limit`
/// ("lower" or "upper") for a reading at its range's end ([`resolve::limit_of`]: that
/// value or beyond), then the boolean member `flag` if any, then a coded value of
/// `device` taken apart under its [`Meaning::key`] (`exception`, `status`, …).
pub fn value_json(
    object: json::Object,
    device: u8,
    reg: &Register,
    raw: u16,
    no_value: bool,
    flag: Option<(&str, bool)>,
) -> json::Object {
    let object = object.str("register", reg.name).int("raw", raw);
    let object = if no_value {
        object.raw("value", "null")
    } else {
        object.num("value", mapping::unmap(raw, reg))
    }
    .str("unit", reg.unit);
    let object = match resolve::limit_of(reg, raw) {
        Some(limit) if !no_value => object.str("at_limit", limit.name()),
        _ => object,
    };
    let object = match flag {
        Some((key, value)) => object.bool(key, value),
        None => object,
    };
    match Meaning::of(device, reg, raw) {
        Some(m) => object.raw(m.key(), &m.json()),
        None => object,
    }
}

/// Whether `reg`'s value is an angle through the controller's pot calibration (a position,
/// its error and derivative, the dead zone): degrees only once the board is calibrated.
/// The calibration registers themselves are degrees whatever the board holds.
pub fn on_calibrated_scale(reg: &Register) -> bool {
    reg.unit == "deg" && !reg.name.ends_with("CALIBMIN") && !reg.name.ends_with("CALIBMAX")
}

/// Whether `raw` is a calibration end (CALIBMIN, CALIBMAX) as a board fresh from boot
/// shows it: the board calibrates with −512..512, which the 1-byte register cannot hold,
/// so it reads its range's end (raw 0x00, −120, or 0xfe, +120) while the board uses ±512
/// (reference E14, §8.1).
pub fn is_boot_calibration_end(reg: &Register, raw: u16) -> bool {
    let boot = if reg.name.ends_with("CALIBMIN") {
        -512.0
    } else if reg.name.ends_with("CALIBMAX") {
        512.0
    } else {
        return false;
    };
    raw == mapping::map(boot, reg)
}

/// The note for a calibration end read right after the port opened.
pub const BOOT_CALIBRATION_END: &str = "note: not what the board uses: opening the port \
rebooted the rover, and a board fresh from boot calibrates with -512..512, which this 1-byte \
register shows clamped to its range. The board uses this register's value once it is \
written, e.g. by `calibrate` in a `hostctl run FILE` script.";

/// The note for such a register, read or written right after the port opened.
pub const BOOT_CALIBRATION: &str = "note: not degrees: opening the port rebooted the rover, so \
the board is on its boot calibration (pot 0..1023 as -512..512, clamped to the register's \
range). Positions are degrees after `calibrate`, in one `hostctl run FILE` script.";

/// The note for a write of a controller's EXCEPTIONDATA: whatever the value, the board
/// takes it as the master's spread of another board's fault (reference §2.1, §6).
pub fn remote_raised(device: u8) -> String {
    format!(
        "note: any write to a controller's EXCEPTIONDATA raises REMOTESLAVE (3) on it, \
         whatever the value: controller {device} stops both its motors until its exception \
         is reset, by a `reset` line in a `hostctl run FILE` script (this command's end \
         reboots the rover anyway, as closing the port does)"
    )
}

/// The note for a one-shot write of REGMASTER_PCTIMEOUT: the master's boot turns the
/// failsafe off, and closing the port at the command's end reboots the master.
pub const PC_TIMEOUT_ONE_SHOT: &str = "note: armed only until this command ends: closing the \
port reboots the master, whose boot turns the failsafe off; for a session that should stop \
the rover when it stops talking, put `write 0 pctimeout MS` first in a `hostctl run FILE` \
script.";

/// Whether a write of `reg` to `device` arms the PC-silence failsafe for this connection
/// only (see [`PC_TIMEOUT_ONE_SHOT`]).
pub fn arms_for_this_boot(device: u8, reg: &Register) -> bool {
    device == 0 && reg.id == id::REGMASTER_PCTIMEOUT
}

/// The bit of REGMASTER_TEMPSREAD that says whether master register `reg` holds a reading:
/// `Some` for the temperatures (bit 0 ambient, bit n controller n's sensor), else `None`.
pub fn sensor_bit(target: Target, reg: &Register) -> Option<u16> {
    let temps = id::REGMASTER_TEMPAMBIENT..=id::REGMASTER_TEMP9;
    (target.device == 0 && temps.contains(&reg.id))
        .then(|| 1 << (reg.id - id::REGMASTER_TEMPAMBIENT))
}

/// How to get a first reading of master temperature `reg` in one command: the master reads
/// sensor i (0 ambient, n controller n's) on its temperature tick i, about 5 + 2·i s after
/// its boot (reference §9.1), which opening the port causes; `--settle-ms` waits that long,
/// and a second more, before the read. `None` for any other register.
pub fn first_read_hint(reg: &Register) -> Option<String> {
    let index = (id::REGMASTER_TEMPAMBIENT..=id::REGMASTER_TEMP9)
        .position(|i| *reg == MASTER[usize::from(i)])?;
    let settle_ms = (5 + 2 * index + 1) * 1000;
    Some(format!(
        "this sensor is first read about {} s after the master's boot: `hostctl --settle-ms \
         {settle_ms} read 0 {}` waits for it. With no reading even then, it is missing or its \
         reads fail, or another sensor is missing: the master then never reads the last one(s) \
         in its order (ambient, 1..9). It raises 10, sensor missing, but keeps \
         only its first exception, and a one-shot command sees its boot one: a `hostctl run` \
         script that `reset`s and then waits shows it (`hostctl watch --readset 2` shows \
         every sensor as it is read)",
        5 + 2 * index,
        reg.short_name()
    ))
}

/// Why a temperature whose REGMASTER_TEMPSREAD bit is clear is no reading (it holds 0.0 °C).
pub const NOT_READ: &str = "not read yet: the master reads one sensor every 2 s from 5 s \
after boot, and opening the port rebooted it; or the sensor is missing, or its last read \
failed";

/// Whether the controller `target` is in exception (REG_STATUS bit 0), read through the
/// scratch read set. `None` for the master, which a write does not leave waiting.
pub fn in_exception<P: Port>(
    target: Target,
    link: &mut Link<P>,
) -> Option<Result<bool, HostError>> {
    if target.device == 0 {
        return None;
    }
    let status = target.kind.register(id::REG_STATUS)?;
    Some(status_bit(target, status, link))
}

fn status_bit<P: Port>(
    target: Target,
    status: &'static Register,
    link: &mut Link<P>,
) -> Result<bool, HostError> {
    let frame = set_frame(target, SCRATCH_SET, &[status])?;
    configure(link, target, SCRATCH_SET, &frame, 1)?;
    let raws = SetRead::new(target, SCRATCH_SET, vec![status])?.run(link)?;
    Ok(raws
        .first()
        .is_some_and(|s| s & crate::meaning::STATUS_EXCEPTION != 0))
}

/// Whether a write of `reg` waits for the exception's reset: the motors' demands and
/// parameters (ids 9..44, and the new DRIVE_MODE) do; the common block (REG_RESET, PING,
/// DEBUGLED, EXCEPTIONDATA, DISABLEDEXCEPTIONS …) and the new FAULTTIME and BUSTIMEOUT
/// act at once, in exception too.
pub fn waits_for_reset(reg: &Register) -> bool {
    (9..=44).contains(&reg.id) || reg.name == "REGDS_DRIVE_MODE"
}

/// The note for a write that found its controller in exception.
pub fn stored_only(device: u8) -> String {
    format!(
        "note: controller {device} is in exception (every controller is after the port opens, \
         which reboots the rover): the board acts on nothing until the exception is reset, a \
         demand (REQSPEED, REQPOS) is replaced meanwhile, and when this command ends, closing \
         the port reboots the rover again, which restores every default. To see it act, put \
         `calibrate`, \
         `reset` and then this write in one script: `hostctl run FILE`."
    )
}
