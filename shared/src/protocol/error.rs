//! Error types of the protocol layer: bad frames, failed encodes, bad replies.

use core::fmt;

/// Why a received frame was rejected. The codes go over the wire and are stable.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
// Numbered by wire code: `code` is the discriminant, and `LinkError`, whose other
// variants take the values after these, holds its own code in its one byte.
#[repr(u8)]
pub enum FrameError {
    /// The length byte is 0, 1 or 2: shorter than the 3-byte minimum.
    BadLength = 1,
    /// The device nibble is 10..=15: no such board.
    BadDevice = 2,
    /// The command nibble is not 2 (write), 3 (read) or 4 (set read set).
    UnknownCommand = 3,
    /// A write names an id that the device's table does not have, so it cannot be sized.
    UnknownRegister = 4,
    /// The payload does not exactly fit the command (count, ids and value sizes).
    LengthMismatch = 5,
    /// A read-set index is 8 or more.
    BadReadSet = 6,
    /// A set-read-set frame carries more than 24 ids.
    ReadSetTooLarge = 7,
    /// A frame stopped arriving before its last byte and was dropped (inter-byte
    /// timeout). The parser never yields it; the link that calls `Parser::abort` does.
    Truncated = 8,
}

impl FrameError {
    /// Every variant, in code order.
    pub const ALL: [FrameError; 8] = [
        FrameError::BadLength,
        FrameError::BadDevice,
        FrameError::UnknownCommand,
        FrameError::UnknownRegister,
        FrameError::LengthMismatch,
        FrameError::BadReadSet,
        FrameError::ReadSetTooLarge,
        FrameError::Truncated,
    ];

    /// The error's wire code: non-zero and stable.
    pub const fn code(self) -> u8 {
        self as u8
    }

    /// The error with this wire code, if any.
    pub const fn from_code(code: u8) -> Option<FrameError> {
        match code {
            1 => Some(FrameError::BadLength),
            2 => Some(FrameError::BadDevice),
            3 => Some(FrameError::UnknownCommand),
            4 => Some(FrameError::UnknownRegister),
            5 => Some(FrameError::LengthMismatch),
            6 => Some(FrameError::BadReadSet),
            7 => Some(FrameError::ReadSetTooLarge),
            8 => Some(FrameError::Truncated),
            _ => None,
        }
    }

    /// Words for people (used by the host tool).
    pub const fn describe(self) -> &'static str {
        match self {
            FrameError::BadLength => "frame length byte below 3",
            FrameError::BadDevice => "device number 10-15 does not exist",
            FrameError::UnknownCommand => "unknown command (only 2 write, 3 read, 4 set read set)",
            FrameError::UnknownRegister => "write to a register id the device does not have",
            FrameError::LengthMismatch => "payload length does not match the command",
            FrameError::BadReadSet => "read set index must be 0-7",
            FrameError::ReadSetTooLarge => "read set holds at most 24 ids",
            FrameError::Truncated => "frame incomplete: bytes stopped arriving",
        }
    }
}

impl fmt::Display for FrameError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.describe())
    }
}

impl core::error::Error for FrameError {}

/// Why a frame could not be encoded.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum EncodeError {
    /// The device number has no board (boards are 0..=9).
    UnknownDevice,
    /// This register id is not in the addressed device's table.
    UnknownRegister(u8),
    /// The raw value for this 1-byte register is above 0xff.
    ValueTooWide(u8),
    /// The frame would be longer than 255 bytes.
    TooLong,
    /// The read-set index is 8 or more.
    BadReadSet,
    /// More than 24 ids for one read set.
    ReadSetTooLarge,
}

impl fmt::Display for EncodeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            EncodeError::UnknownDevice => f.write_str("no board at that device number (0-9)"),
            EncodeError::UnknownRegister(id) => {
                write!(f, "register {id} is not in the device's table")
            }
            EncodeError::ValueTooWide(id) => {
                write!(f, "value for 1-byte register {id} is above 255")
            }
            EncodeError::TooLong => f.write_str("frame would exceed 255 bytes"),
            EncodeError::BadReadSet => f.write_str("read set index must be 0-7"),
            EncodeError::ReadSetTooLarge => f.write_str("read set holds at most 24 ids"),
        }
    }
}

impl core::error::Error for EncodeError {}

/// Why a read reply could not be decoded.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum DecodeError {
    /// This id of the read set is not in the board's table, so the reply cannot be sized.
    UnknownRegister(u8),
    /// More than 24 ids were given.
    TooManyIds,
    /// The reply's length differs from the sum of the ids' sizes.
    WrongLength {
        /// Bytes the ids call for.
        expected: usize,
        /// Bytes received.
        actual: usize,
    },
}

impl fmt::Display for DecodeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            DecodeError::UnknownRegister(id) => {
                write!(f, "register {id} is not in the board's table")
            }
            DecodeError::TooManyIds => f.write_str("more than 24 ids in a read set"),
            DecodeError::WrongLength { expected, actual } => {
                write!(f, "read reply has {actual} bytes, expected {expected}")
            }
        }
    }
}

impl core::error::Error for DecodeError {}
