//! `hostctl write DEV REG VALUE`: one register, one write frame.

use shared::master::pc_watch::MAX_TIMEOUT_MS;
use shared::protocol::{self, Write};
use shared::regs::{id, Register};

use super::{fresh, Frame};
use crate::error::HostError;
use crate::json;
use crate::link::Link;
use crate::port::Port;
use crate::resolve::{self, Target};

/// Arguments of `write`.
#[derive(Debug, clap::Args)]
#[command(allow_negative_numbers = true)]
pub struct Args {
    /// Device: 0 = master, 1..9 = controllers.
    pub device: String,
    /// Register name (e.g. REGDS_DRIVE_REQSPEED or drive_reqspeed) or number.
    pub register: String,
    /// Value in the register's engineering units, e.g. 1000 (ticks/s) or -40 (°).
    // Any word starting with '-' is a value here (e.g. -.5, which clap would otherwise
    // take for a flag); hostctl's own parser then checks it.
    #[arg(allow_hyphen_values = true)]
    pub value: String,
}

/// A checked write, ready to send.
#[derive(Debug)]
pub struct Plan {
    /// Who is written.
    pub target: Target,
    /// The register.
    pub reg: &'static Register,
    /// The value asked for.
    pub value: f32,
    /// Its raw form.
    pub raw: u16,
    /// The frame.
    pub frame: Frame,
}

/// Checks the arguments and builds the frame; nothing is sent.
pub fn plan(args: &Args) -> Result<Plan, HostError> {
    let target = resolve::device(&args.device)?;
    let reg = resolve::register(target, &args.register)?;
    if !reg.writable {
        return Err(HostError::ReadOnly {
            register: reg.name,
            device: target.device,
        });
    }
    let (value, raw) = resolve::value(target, reg, &args.value)?;
    let mut frame = Frame::new();
    protocol::encode_write(target.device, &[Write { id: reg.id, raw }], &mut frame)?;
    Ok(Plan {
        target,
        reg,
        value,
        raw,
        frame,
    })
}

/// Sends the write, checks the 00 reply and returns the report.
pub fn run<P: Port>(plan: &Plan, link: &mut Link<P>, json: bool) -> Result<String, HostError> {
    let reply = link.transact(plan.target.device, &plan.frame, 1)?;
    let code = reply.first().copied().unwrap_or_default();
    if code != 0 {
        return Err(HostError::WriteRefused {
            device: plan.target.device,
            register: plan.reg.name,
            writes: 1,
            code,
            words: super::reply_error(code)
                .map(|e| e.describe().to_string())
                .unwrap_or_else(|| "not a known error code".to_owned()),
            inject: link.inject().clone(),
        });
    }
    // Whether anything will act on it: a controller fresh from the port's reboot will not.
    let exception = fresh::in_exception(plan.target, link);
    Ok(report(plan, json, exception))
}

/// What was written: the value asked for, the raw value and what the device
/// makes of it, with what stands in its way (see [`fresh`]).
fn report(plan: &Plan, json: bool, exception: Option<Result<bool, HostError>>) -> String {
    let applied = resolve::applied(plan.reg, plan.raw);
    let boot_scale = plan.target.device != 0 && fresh::on_calibrated_scale(plan.reg);
    if json {
        let mut object = json::Object::new()
            .str("command", "write")
            .int("device", plan.target.device)
            .str("board", plan.target.board())
            .int("id", plan.reg.id)
            .str("register", plan.reg.name)
            .num("value", plan.value)
            .int("raw", plan.raw)
            .num("applied", applied)
            .str("unit", plan.reg.unit);
        if let Some(Ok(stopped)) = exception {
            object = object.bool("in_exception", stopped);
        }
        if boot_scale {
            object = object.bool("boot_calibration", true);
        }
        return object.finish();
    }
    let mut text = format!(
        "device {} {} = {}{} (raw 0x{:0width$x}, {})",
        plan.target.device,
        plan.reg.name,
        plan.value,
        resolve::unit_suffix(plan.reg),
        plan.raw,
        resolve::write_effect(plan.reg, plan.raw),
        width = usize::from(plan.reg.size) * 2,
    );
    match exception {
        Some(Ok(true)) if fresh::waits_for_reset(plan.reg) => {
            text += &format!("\n{}", fresh::stored_only(plan.target.device))
        }
        Some(Err(e)) => {
            text += &format!("\nnote: the controller's status could not be read afterwards: {e}")
        }
        _ => {}
    }
    if boot_scale {
        text += &format!("\n{}", fresh::BOOT_CALIBRATION);
    }
    if fresh::arms_for_this_boot(plan.target.device, plan.reg) && plan.raw != 0 {
        if plan.raw > MAX_TIMEOUT_MS {
            text += &format!(
                "\nnote: the master acts on at most {MAX_TIMEOUT_MS} ms; a longer \
                 REGMASTER_PCTIMEOUT counts as {MAX_TIMEOUT_MS}"
            );
        }
        text += &format!("\n{}", fresh::PC_TIMEOUT_ONE_SHOT);
    }
    if plan.target.device != 0 && plan.reg.id == id::REG_EXCEPTIONDATA {
        text += &format!("\n{}", fresh::remote_raised(plan.target.device));
    }
    text
}
