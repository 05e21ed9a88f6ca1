//! The subcommands, one file each, and the two exchanges they share:
//! configuring a read set and reading one.

pub mod fresh;
mod hold;
pub mod live;
pub mod pc;
pub mod read;
pub mod readset;
pub mod run;
pub mod script;
pub mod watch;
pub mod write;

use heapless::Vec as HVec;
use shared::master::{LinkError, ERROR_REPLY_FLAG};
use shared::protocol::{self, EncodeError};
use shared::regs::Register;

use crate::error::{HostError, MasterSays};
use crate::link::Link;
use crate::port::Port;
use crate::resolve::Target;

/// A frame as the codec builds it.
pub type Frame = HVec<u8, { protocol::MAX_FRAME }>;

/// The master's error for a one-byte reply, if it is one: `0x80 | code`.
pub fn reply_error(reply: u8) -> Option<LinkError> {
    if reply & ERROR_REPLY_FLAG == 0 {
        return None;
    }
    LinkError::from_code(reply & !ERROR_REPLY_FLAG)
}

/// The words for a reply byte that is an error code, with a leading "; ".
fn code_words(code: u8) -> String {
    match reply_error(code) {
        Some(e) => format!("; {}", e.describe()),
        None => String::new(),
    }
}

/// Builds the set-read-set frame for `regs`.
pub fn set_frame(target: Target, set: u8, regs: &[&Register]) -> Result<Frame, HostError> {
    let ids: Vec<u8> = regs.iter().map(|r| r.id).collect();
    let mut frame = Frame::new();
    protocol::encode_set_read_set(target.device, set, &ids, &mut frame)?;
    Ok(frame)
}

/// Sends a set-read-set frame and checks the count reply.
pub fn configure<P: Port>(
    link: &mut Link<P>,
    target: Target,
    set: u8,
    frame: &[u8],
    count: usize,
) -> Result<(), HostError> {
    let reply = link.transact(target.device, frame, 1)?;
    let got = reply.first().copied().unwrap_or_default();
    if usize::from(got) != count {
        return Err(HostError::ReadSetRejected {
            device: target.device,
            set,
            expected: count,
            got,
            words: code_words(got),
        });
    }
    Ok(())
}

/// A planned read of one set from one device.
#[derive(Debug, Clone)]
pub struct SetRead {
    /// Who is read.
    pub target: Target,
    /// The read set, 0..7.
    pub set: u8,
    /// The registers of the set, in order.
    pub regs: Vec<&'static Register>,
    /// The read frame.
    pub frame: [u8; 3],
    /// Reply length per the device's table.
    pub reply_len: usize,
}

impl SetRead {
    /// Plans reading `set` (holding `regs`) from `target`.
    pub fn new(target: Target, set: u8, regs: Vec<&'static Register>) -> Result<Self, HostError> {
        let ids: Vec<u8> = regs.iter().map(|r| r.id).collect();
        // Every register was resolved on the target's table; an id missing
        // from it is a bug, reported as the codec would.
        let reply_len = protocol::read_reply_len(target.kind, &ids).ok_or_else(|| {
            let id = ids
                .iter()
                .copied()
                .find(|&id| target.kind.register(id).is_none())
                .unwrap_or_default();
            HostError::Encode(EncodeError::UnknownRegister(id))
        })?;
        Ok(Self {
            target,
            set,
            regs,
            frame: protocol::encode_read(target.device, set),
            reply_len,
        })
    }

    /// Sends the read and decodes the reply into raw values, in set order.
    pub fn run<P: Port>(&self, link: &mut Link<P>) -> Result<Vec<u16>, HostError> {
        self.run_within(link, crate::link::REPLY_TIMEOUT)
    }

    /// [`SetRead::run`], waiting at most `timeout` for each part of the reply.
    fn run_within<P: Port>(
        &self,
        link: &mut Link<P>,
        timeout: std::time::Duration,
    ) -> Result<Vec<u16>, HostError> {
        let reply =
            link.transact_within(self.target.device, &self.frame, self.reply_len, timeout)?;
        let ids: Vec<u8> = self.regs.iter().map(|r| r.id).collect();
        let mut values: HVec<(u8, u16), { protocol::READ_SET_SIZE }> = HVec::new();
        protocol::decode_read_reply(self.target.kind, &ids, &reply, &mut values).map_err(
            |source| HostError::Decode {
                device: self.target.device,
                source,
            },
        )?;
        Ok(values.iter().map(|&(_, raw)| raw).collect())
    }

    /// [`SetRead::run`] for a view that goes on when a controller drops off the bus or the
    /// serial line loses a reply.
    ///
    /// [`Reading::NoAnswer`] when the master says the controller did not answer on I²C: the
    /// reply stopped short, the master's last link error is NoAnswer, and its error count
    /// has changed since the last probe, so that error is this read's and not an older one
    /// (the master does not record which device an error was for, but this read is the
    /// only frame since). The controller is read again next time, so one that comes back
    /// shows again.
    ///
    /// A controller that did not answer its last read is read with a shorter wait
    /// ([`Link::reply_timeout`]), so that a view with one off the bus goes on at a few
    /// rounds a second. If that shorter read fails for another cause than NoAnswer, the
    /// reply may just have been slow: it is read once more with the full wait (except a
    /// read of the scratch set 7, which the probe has just overwritten).
    ///
    /// [`Reading::Lost`] when the reply was lost on the serial line while the master still
    /// answers ([`Link::forgive`], a few in a row at most). Any other failure is an error.
    pub fn read_for_view<P: Port>(&self, link: &mut Link<P>) -> Result<Reading, HostError> {
        let device = self.target.device;
        let before = link.errors_seen();
        let quick = link.was_silent(device);
        match self.run_within(link, link.reply_timeout(device)) {
            Ok(values) => {
                link.note_silent(device, false);
                link.note_whole(device, self.set);
                Ok(Reading::Values(values))
            }
            Err(HostError::Timeout {
                master: MasterSays::Answered { code, count },
                ..
            }) if device != 0 && code == LinkError::NoAnswer as u8 && before != Some(count) => {
                link.note_silent(device, true);
                link.note_whole(device, self.set);
                Ok(Reading::NoAnswer)
            }
            // The probe has just overwritten the scratch set: a set there is not read again
            // before its owner configures it anew.
            Err(HostError::Timeout { .. }) if quick && self.set != read::SCRATCH_SET => {
                link.note_silent(device, false);
                self.read_for_view(link)
            }
            Err(e) if link.forgive(&e, self.set, before) => Ok(Reading::Lost),
            Err(e) => Err(e),
        }
    }
}

/// What one read of a view gave.
#[derive(Debug, Clone, PartialEq)]
pub enum Reading {
    /// The raw values, in set order.
    Values(Vec<u16>),
    /// The controller did not answer the master on the I²C bus.
    NoAnswer,
    /// The serial line lost or garbled the reply; the master still answers.
    Lost,
}

impl Reading {
    /// The values, if they were read.
    pub fn values(&self) -> Option<&[u16]> {
        match self {
            Reading::Values(v) => Some(v),
            Reading::NoAnswer | Reading::Lost => None,
        }
    }
}

/// The legend of devices whose reply the serial line lost this round.
pub fn reply_lost_legend(devices: &[u8]) -> String {
    let list: Vec<String> = devices.iter().map(u8::to_string).collect();
    let whose = if devices.len() == 1 {
        "device"
    } else {
        "devices"
    };
    format!(
        "reply lost: the serial line lost or garbled the read of {whose} {} this round, the \
         request on its way to the master or the reply on its way back (the master still \
         answers); read again next round; the view stops if one read loses {} in a row",
        list.join(", "),
        crate::link::MAX_LOST_IN_A_ROW + 1
    )
}

/// The legend of a controller that did not answer.
pub fn no_answer_legend(devices: &[u8]) -> String {
    let list: Vec<String> = devices.iter().map(u8::to_string).collect();
    let (who, does) = if devices.len() == 1 {
        ("controller", "does")
    } else {
        ("controllers", "do")
    };
    format!(
        "no answer: {who} {} {does} not answer the master on the I2C bus (unplugged, unpowered \
         or rebooting; from 5 s after its boot the master stops every motor when one it has \
         heard drops off); read again every round, each after a {} ms wait",
        list.join(", "),
        crate::link::SILENT_REREAD_TIMEOUT.as_millis()
    )
}
