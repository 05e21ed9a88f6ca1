//! Errors on the PC link, with the codes that go over the wire.

use crate::protocol::FrameError;

/// An error reply is this flag plus the error's code, so it can never be mistaken for
/// a write's `00` or a set-read-set count (0..=24).
pub const ERROR_REPLY_FLAG: u8 = 0x80;

/// Why the master refused a frame or could not complete it. The code is stored in
/// REGMASTER_LASTERROR and sent in error replies (`0x80 | code`).
///
/// The discriminants are the wire codes: codes 1..=8 are the frame errors, with the
/// names and numbers of [`FrameError`]'s variants, so taking the code is reading the byte.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
#[repr(u8)]
pub enum LinkError {
    /// The length byte is 0, 1 or 2 ([`FrameError::BadLength`]).
    BadLength = FrameError::BadLength as u8,
    /// The device nibble is 10..=15 ([`FrameError::BadDevice`]).
    BadDevice = FrameError::BadDevice as u8,
    /// The command nibble is not 2, 3 or 4 ([`FrameError::UnknownCommand`]).
    UnknownCommand = FrameError::UnknownCommand as u8,
    /// A write names an id the device does not have ([`FrameError::UnknownRegister`]).
    UnknownRegister = FrameError::UnknownRegister as u8,
    /// The payload does not fit the command ([`FrameError::LengthMismatch`]).
    LengthMismatch = FrameError::LengthMismatch as u8,
    /// A read-set index is 8 or more ([`FrameError::BadReadSet`]).
    BadReadSet = FrameError::BadReadSet as u8,
    /// A set-read-set frame carries more than 24 ids ([`FrameError::ReadSetTooLarge`]).
    ReadSetTooLarge = FrameError::ReadSetTooLarge as u8,
    /// A frame stopped arriving and was dropped ([`FrameError::Truncated`]).
    Truncated = FrameError::Truncated as u8,
    /// A write named a read-only register; nothing in the frame was written.
    ReadOnly = 9,
    /// A read set named a register the device does not have; it read as 0xcd.
    MissingRegister = 10,
    /// A read of an empty read set: there is nothing to answer.
    EmptyReadSet = 11,
    /// A slave did not answer on the I2C bus.
    NoAnswer = 12,
    /// A byte arrived with a framing error (wrong baud rate or noise); it was dropped.
    Framing = 13,
    /// A byte was lost because the receiver overran.
    Overrun = 14,
}

impl LinkError {
    /// Every variant, in code order.
    pub const ALL: [LinkError; 14] = [
        LinkError::BadLength,
        LinkError::BadDevice,
        LinkError::UnknownCommand,
        LinkError::UnknownRegister,
        LinkError::LengthMismatch,
        LinkError::BadReadSet,
        LinkError::ReadSetTooLarge,
        LinkError::Truncated,
        LinkError::ReadOnly,
        LinkError::MissingRegister,
        LinkError::EmptyReadSet,
        LinkError::NoAnswer,
        LinkError::Framing,
        LinkError::Overrun,
    ];

    /// The wire code (non-zero, below 0x80): the discriminant.
    pub const fn code(self) -> u8 {
        self as u8
    }

    /// The error with this code.
    pub const fn from_code(code: u8) -> Option<LinkError> {
        // Codes run 1..=14 in `ALL`'s order.
        match code {
            1..=14 => Some(LinkError::ALL[code as usize - 1]),
            _ => None,
        }
    }

    /// The frame error behind a code of 1..=8, if it is one.
    pub const fn frame(self) -> Option<FrameError> {
        FrameError::from_code(self.code())
    }

    /// The link error of a frame error: the same code.
    pub const fn of_frame(e: FrameError) -> LinkError {
        match e {
            FrameError::BadLength => LinkError::BadLength,
            FrameError::BadDevice => LinkError::BadDevice,
            FrameError::UnknownCommand => LinkError::UnknownCommand,
            FrameError::UnknownRegister => LinkError::UnknownRegister,
            FrameError::LengthMismatch => LinkError::LengthMismatch,
            FrameError::BadReadSet => LinkError::BadReadSet,
            FrameError::ReadSetTooLarge => LinkError::ReadSetTooLarge,
            FrameError::Truncated => LinkError::Truncated,
        }
    }

    /// The error's name, as docs/protocol.md's table gives it (what a program matches on).
    pub const fn name(self) -> &'static str {
        match self {
            LinkError::BadLength => "BadLength",
            LinkError::BadDevice => "BadDevice",
            LinkError::UnknownCommand => "UnknownCommand",
            LinkError::UnknownRegister => "UnknownRegister",
            LinkError::LengthMismatch => "LengthMismatch",
            LinkError::BadReadSet => "BadReadSet",
            LinkError::ReadSetTooLarge => "ReadSetTooLarge",
            LinkError::Truncated => "Truncated",
            LinkError::ReadOnly => "ReadOnly",
            LinkError::MissingRegister => "MissingRegister",
            LinkError::EmptyReadSet => "EmptyReadSet",
            LinkError::NoAnswer => "NoAnswer",
            LinkError::Framing => "Framing",
            LinkError::Overrun => "Overrun",
        }
    }

    /// Words for people.
    pub const fn describe(self) -> &'static str {
        if let Some(e) = self.frame() {
            return e.describe();
        }
        match self {
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
            // The frame errors were answered above.
            _ => "malformed frame",
        }
    }

    /// The one-byte error reply for frames whose command has a one-byte reply.
    pub const fn reply(self) -> u8 {
        ERROR_REPLY_FLAG | self.code()
    }
}

impl From<FrameError> for LinkError {
    fn from(e: FrameError) -> Self {
        LinkError::of_frame(e)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_code_is_its_variants_discriminant_and_frame_errors_keep_theirs() {
        for (i, e) in LinkError::ALL.into_iter().enumerate() {
            assert_eq!(usize::from(e.code()), i + 1);
            assert_eq!(LinkError::from_code(e.code()), Some(e));
        }
        for e in FrameError::ALL {
            let l = LinkError::from(e);
            assert_eq!(l.code(), e.code());
            assert_eq!(l.frame(), Some(e));
            assert_eq!(l.describe(), e.describe());
        }
        assert_eq!(LinkError::NoAnswer.code(), 12);
        assert_eq!(LinkError::Overrun.code(), 14);
        assert_eq!(LinkError::Overrun.frame(), None);
        assert_eq!(LinkError::from_code(15), None);
        assert_eq!(LinkError::from_code(0), None);
        assert_eq!(core::mem::size_of::<LinkError>(), 1);
    }
}
