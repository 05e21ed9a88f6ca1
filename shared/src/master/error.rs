//! Errors on the PC link, with the codes that go over the wire.

use crate::protocol::FrameError;

/// An error reply is this flag plus the error's code, so it can never be mistaken for
/// a write's `00` or a set-read-set count (0..=24).
pub const ERROR_REPLY_FLAG: u8 = 0x80;

/// Why the master refused a frame or could not complete it. The code is stored in
/// REGMASTER_LASTERROR and sent in error replies (`0x80 | code`).
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum LinkError {
    /// The frame itself was malformed (codes 1..=8).
    Frame(FrameError),
    /// A write named a read-only register; nothing in the frame was written.
    ReadOnly,
    /// A read set named a register the device does not have; it read as 0xcd.
    MissingRegister,
    /// A read of an empty read set: there is nothing to answer.
    EmptyReadSet,
    /// A slave did not answer on the I2C bus.
    NoAnswer,
    /// A byte arrived with a framing error (wrong baud rate or noise); it was dropped.
    Framing,
    /// A byte was lost because the receiver overran.
    Overrun,
}

impl LinkError {
    /// The wire code (non-zero, below 0x80).
    pub const fn code(self) -> u8 {
        match self {
            LinkError::Frame(e) => e.code(),
            LinkError::ReadOnly => 9,
            LinkError::MissingRegister => 10,
            LinkError::EmptyReadSet => 11,
            LinkError::NoAnswer => 12,
            LinkError::Framing => 13,
            LinkError::Overrun => 14,
        }
    }

    /// The error with this code.
    pub const fn from_code(code: u8) -> Option<LinkError> {
        Some(match code {
            9 => LinkError::ReadOnly,
            10 => LinkError::MissingRegister,
            11 => LinkError::EmptyReadSet,
            12 => LinkError::NoAnswer,
            13 => LinkError::Framing,
            14 => LinkError::Overrun,
            _ => match FrameError::from_code(code) {
                Some(e) => LinkError::Frame(e),
                None => return None,
            },
        })
    }

    /// Words for people.
    pub const fn describe(self) -> &'static str {
        match self {
            LinkError::Frame(e) => e.describe(),
            LinkError::ReadOnly => {
                "write to a read-only register; nothing in the frame was written"
            }
            LinkError::MissingRegister => {
                "read of a register the device does not have (read as 0xcd)"
            }
            LinkError::EmptyReadSet => "read of an empty read set; configure it first",
            LinkError::NoAnswer => "a slave did not answer on the I2C bus",
            LinkError::Framing => "serial framing error: check the baud rate (115200 8N1)",
            LinkError::Overrun => "serial receive overrun: a byte was lost",
        }
    }

    /// The one-byte error reply for frames whose command has a one-byte reply.
    pub const fn reply(self) -> u8 {
        ERROR_REPLY_FLAG | self.code()
    }
}

impl From<FrameError> for LinkError {
    fn from(e: FrameError) -> Self {
        LinkError::Frame(e)
    }
}
