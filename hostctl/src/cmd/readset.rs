//! `hostctl readset [--device D] SET REG...`: configure a read set.
//!
//! The set lives only for this connection: closing the port resets the master (reference
//! §4.1), which empties every set.

use shared::regs::Register;

use super::Frame;
use crate::error::HostError;
use crate::json;
use crate::link::Link;
use crate::port::Port;
use crate::resolve::{self, Target};

/// Arguments of `readset`.
#[derive(Debug, clap::Args)]
#[command(allow_negative_numbers = true)]
pub struct Args {
    /// Device whose table the names are resolved against (0 = master).
    #[arg(long, value_name = "D", default_value = "0")]
    pub device: String,
    /// Read set index, 0..7 (7 is overwritten by `hostctl read`).
    pub set: String,
    /// The registers, in reply order (names or numbers, at most 24).
    #[arg(required = true, value_name = "REG")]
    pub registers: Vec<String>,
}

/// A checked set-read-set, ready to send.
#[derive(Debug)]
pub struct Plan {
    /// The device addressed.
    pub target: Target,
    /// The set index.
    pub set: u8,
    /// The registers.
    pub regs: Vec<&'static Register>,
    /// The frame.
    pub frame: Frame,
}

/// Checks the arguments and builds the frame; nothing is sent.
pub fn plan(args: &Args) -> Result<Plan, HostError> {
    let target = resolve::device(&args.device)?;
    let set = resolve::set(&args.set)?;
    let regs = resolve::read_set(target, &args.registers)?;
    let frame = super::set_frame(target, set, &regs)?;
    Ok(Plan {
        target,
        set,
        regs,
        frame,
    })
}

/// Sends the frame, checks the count reply and returns the report.
pub fn run<P: Port>(plan: &Plan, link: &mut Link<P>, json: bool) -> Result<String, HostError> {
    super::configure(link, plan.target, plan.set, &plan.frame, plan.regs.len())?;
    if json {
        return Ok(json::Object::new()
            .str("command", "readset")
            .int("device", plan.target.device)
            .int("set", plan.set)
            .raw(
                "ids",
                &json::array(plan.regs.iter().map(|r| r.id.to_string())),
            )
            .raw(
                "registers",
                &json::array(plan.regs.iter().map(|r| json::string(r.name))),
            )
            .finish());
    }
    let names: Vec<&str> = plan.regs.iter().map(|r| r.name).collect();
    Ok(format!(
        "read set {} = {} ({} registers)",
        plan.set,
        names.join(" "),
        plan.regs.len()
    ))
}
