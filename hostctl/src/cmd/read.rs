//! `hostctl read DEV REG`: one register through hostctl's scratch read set.
//!
//! Read set 7 is reserved for these one-off reads: each `read` replaces its
//! contents with the one register, then reads it. A master temperature is read with
//! REGMASTER_TEMPSREAD beside it, which says whether it is a reading at all. Do not use set 7 for
//! anything that must survive a `hostctl read`.

use shared::regs::{id, Register};

use super::{fresh, Frame, SetRead};
use crate::error::HostError;
use crate::json;
use crate::link::Link;
use crate::meaning::Meaning;
use crate::port::Port;
use crate::resolve::{self, Target};

/// The read set `read` overwrites.
pub const SCRATCH_SET: u8 = 7;

/// Arguments of `read`.
#[derive(Debug, clap::Args)]
#[command(allow_negative_numbers = true)]
pub struct Args {
    /// Device: 0 = master, 1..9 = controllers.
    pub device: String,
    /// Register name (e.g. REGDS_DRIVE_ACTUALSPEED or drive_actualspeed) or number.
    pub register: String,
}

/// A checked read, ready to send.
#[derive(Debug)]
pub struct Plan {
    /// The register.
    pub reg: &'static Register,
    /// For a master temperature, its bit in REGMASTER_TEMPSREAD (read second in the set).
    pub sensor_bit: Option<u16>,
    /// Frame that puts the register (and REGMASTER_TEMPSREAD) in the scratch set.
    pub set_frame: Frame,
    /// The read of the scratch set.
    pub read: SetRead,
}

/// Checks the arguments and builds the frames; nothing is sent.
pub fn plan(args: &Args) -> Result<Plan, HostError> {
    let target = resolve::device(&args.device)?;
    let reg = resolve::register(target, &args.register)?;
    let sensor_bit = fresh::sensor_bit(target, reg);
    let mut regs = vec![reg];
    if sensor_bit.is_some() {
        regs.push(resolve::register(
            target,
            &id::REGMASTER_TEMPSREAD.to_string(),
        )?);
    }
    Ok(Plan {
        reg,
        sensor_bit,
        set_frame: super::set_frame(target, SCRATCH_SET, &regs)?,
        read: SetRead::new(target, SCRATCH_SET, regs)?,
    })
}

/// Configures the scratch set, reads it and returns the report.
pub fn run<P: Port>(plan: &Plan, link: &mut Link<P>, json: bool) -> Result<String, HostError> {
    let target = plan.read.target;
    let count = plan.read.regs.len();
    super::configure(link, target, SCRATCH_SET, &plan.set_frame, count)?;
    let raws = plan.read.run(link)?;
    let raw = raws.first().copied().unwrap_or_default();
    let read = plan
        .sensor_bit
        .map(|bit| raws.get(1).is_some_and(|bits| bits & bit != 0));
    Ok(report(target, plan.reg, raw, read, json))
}

/// The value in units and raw; for a position, that it is not degrees; for a calibration
/// end, that the board uses ±512 meanwhile; for a temperature the master has not read,
/// that it is no reading (see [`fresh`]).
fn report(target: Target, reg: &Register, raw: u16, read: Option<bool>, json: bool) -> String {
    let boot_scale = target.device != 0 && fresh::on_calibrated_scale(reg);
    let boot_end = target.device != 0 && fresh::is_boot_calibration_end(reg, raw);
    if json {
        let object = json::Object::new()
            .str("command", "read")
            .int("device", target.device)
            .str("board", target.board());
        let object = fresh::register_json(object, target.device, reg, raw, read);
        return if boot_scale || boot_end {
            object.bool("boot_calibration", true).finish()
        } else {
            object.finish()
        };
    }
    if read == Some(false) {
        // 0.0 °C here is no reading: not shown as a temperature.
        let text = format!(
            "device {} {}: no reading (raw 0x{raw:04x}): {}",
            target.device,
            reg.name,
            fresh::NOT_READ
        );
        return match fresh::first_read_hint(reg) {
            Some(hint) => format!("{text}\nnote: {hint}"),
            None => text,
        };
    }
    let text = format!(
        "device {} {} = {}{} (raw 0x{:0width$x})",
        target.device,
        reg.name,
        resolve::show(reg, raw),
        resolve::unit_suffix(reg),
        raw,
        width = usize::from(reg.size) * 2,
    );
    let text = match (resolve::limit_of(reg, raw), reg.range) {
        (Some(limit), Some(range)) => {
            let (end, beyond) = match limit {
                resolve::Limit::Lower => (range.min, "or less"),
                resolve::Limit::Upper => (range.max, "or more"),
            };
            format!(
                "{text}\nnote: at the end of the register's range ({} to {}): the reading is {end}{} \
                 {beyond}, since the rover clamps what it reports to that range",
                range.min,
                range.max,
                resolve::unit_suffix(reg),
            )
        }
        _ => text,
    };
    if boot_scale {
        format!("{text}\n{}", fresh::BOOT_CALIBRATION)
    } else if boot_end {
        format!("{text}\n{}", fresh::BOOT_CALIBRATION_END)
    } else if let Some(m) = Meaning::of(target.device, reg, raw) {
        format!("{text}: {}", m.words())
    } else if let Some(note) = resolve::use_note(reg, raw) {
        format!("{text}\nnote: {note}")
    } else {
        text
    }
}
