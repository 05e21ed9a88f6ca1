//! `hostctl read DEV REG`: one register through hostctl's scratch read set.
//!
//! Read set 7 is reserved for these one-off reads: each `read` replaces its
//! contents with the one register, then reads it. Do not use set 7 for
//! anything that must survive a `hostctl read`.

use shared::mapping;
use shared::regs::Register;

use super::{fresh, Frame, SetRead};
use crate::error::HostError;
use crate::json;
use crate::link::Link;
use crate::port::Port;
use crate::resolve::{self, Target};

/// The read set `read` overwrites.
pub const SCRATCH_SET: u8 = 7;

/// Arguments of `read`.
#[derive(Debug, clap::Args)]
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
    /// Frame that puts the register alone in the scratch set.
    pub set_frame: Frame,
    /// The read of the scratch set.
    pub read: SetRead,
}

/// Checks the arguments and builds the frames; nothing is sent.
pub fn plan(args: &Args) -> Result<Plan, HostError> {
    let target = resolve::device(&args.device)?;
    let reg = resolve::register(target, &args.register)?;
    Ok(Plan {
        reg,
        set_frame: super::set_frame(target, SCRATCH_SET, &[reg])?,
        read: SetRead::new(target, SCRATCH_SET, vec![reg])?,
    })
}

/// Configures the scratch set, reads it and returns the report.
pub fn run<P: Port>(plan: &Plan, link: &mut Link<P>, json: bool) -> Result<String, HostError> {
    let target = plan.read.target;
    super::configure(link, target, SCRATCH_SET, &plan.set_frame, 1)?;
    let raws = plan.read.run(link)?;
    let raw = raws.first().copied().unwrap_or_default();
    Ok(report(target, plan.reg, raw, json))
}

/// The value in units and raw; for a position, that it is not degrees (see [`fresh`]).
fn report(target: Target, reg: &Register, raw: u16, json: bool) -> String {
    let boot_scale = target.device != 0 && fresh::on_calibrated_scale(reg);
    if json {
        let object = json::Object::new()
            .str("command", "read")
            .int("device", target.device)
            .str("board", target.board())
            .int("id", reg.id)
            .str("register", reg.name)
            .int("raw", raw)
            .num("value", mapping::unmap(raw, reg))
            .str("unit", reg.unit);
        return if boot_scale {
            object.raw("boot_calibration", "true").finish()
        } else {
            object.finish()
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
    if boot_scale {
        format!("{text}\n{}", fresh::BOOT_CALIBRATION)
    } else {
        text
    }
}
