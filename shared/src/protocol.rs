//! The PC-master serial protocol: frame types, the byte-at-a-time [`Parser`] the
//! master runs, the encoders the host uses, read-reply decoding and the read-set store.
//!
//! A frame is `[L, (device << 4) | command, payload...]`, L being the total length
//! (3..=255). Value sizes come from the addressed device's register table.

mod encode;
mod error;
mod parser;
mod read_sets;
mod reply;
pub(crate) mod sizes;

pub use encode::{encode_read, encode_set_read_set, encode_write};
pub use error::{DecodeError, EncodeError, FrameError};
pub use parser::Parser;

pub use read_sets::ReadSets;
pub use reply::{decode_read_reply, read_reply_len};
use sizes::Sizes;

/// Longest frame in bytes (the length byte is a `u8`).
pub const MAX_FRAME: usize = 255;
/// Number of read sets the master keeps.
pub const READ_SETS: usize = 8;
/// Most ids one read set holds.
pub const READ_SET_SIZE: usize = 24;
/// Most register writes one frame can carry (1-byte values: (255 - 3) / 2).
pub const MAX_WRITES: usize = 126;
/// Highest device number that addresses a board (0 master, 1..=9 slaves).
pub const MAX_DEVICE: u8 = 9;

/// The command in the low nibble of a frame's second byte.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
#[repr(u8)]
pub enum Command {
    /// Write registers; the master replies `00`.
    Write = 2,
    /// Read the registers of a read set; the reply is their values.
    Read = 3,
    /// Replace a read set; the master replies with the id count.
    SetReadSet = 4,
}

impl Command {
    /// The command with this number, if there is one.
    pub const fn from_u8(value: u8) -> Option<Command> {
        match value {
            2 => Some(Command::Write),
            3 => Some(Command::Read),
            4 => Some(Command::SetReadSet),
            _ => None,
        }
    }
}

/// One register write: an id and its raw value (the low byte only for a 1-byte
/// register).
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct Write {
    /// Register id in the addressed device's table.
    pub id: u8,
    /// Raw (already mapped) value.
    pub raw: u16,
}

/// A complete, validated frame.
// The write variant is ~380 bytes on AVR; without alloc there is nothing to box it in,
// and the master holds one request at a time.
#[allow(clippy::large_enum_variant)]
#[derive(Clone, PartialEq, Eq, Debug)]
pub enum Request {
    /// Write registers, in order. Read-only ids are included; the master skips them.
    Write {
        /// Device 0..=9.
        device: u8,
        /// The writes, in frame order.
        writes: heapless::Vec<Write, MAX_WRITES>,
    },
    /// Read the registers of a read set.
    Read {
        /// Device 0..=9.
        device: u8,
        /// Read set 0..=7.
        set: u8,
    },
    /// Replace a read set.
    SetReadSet {
        /// Device 0..=9 (the sets are shared by all devices).
        device: u8,
        /// Read set 0..=7.
        set: u8,
        /// The new ids, not checked against any table.
        ids: heapless::Vec<u8, READ_SET_SIZE>,
    },
}

/// A frame the parser rejected: why, and its second byte (device and command) if it had
/// one, so the master can decide whether an error reply can be understood.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct Rejected {
    /// Why the frame was rejected.
    pub error: FrameError,
    /// The frame's second byte, absent for a length byte below 2.
    pub header: Option<u8>,
}

/// How a frame's register values are sized: the table of the addressed device, `None`
/// for a device with no board.
pub(crate) type SizesOf = fn(u8) -> Option<Sizes>;

/// A complete, validated frame, borrowed from the parser's buffer (see
/// [`Parser::push_frame`]). [`Frame::to_request`] makes an owned [`Request`].
#[derive(Clone, Debug)]
pub enum Frame<'a> {
    /// Write registers, in order. Read-only ids are included; the master skips them.
    Write {
        /// Device 0..=9.
        device: u8,
        /// The writes, in frame order.
        writes: Writes<'a>,
    },
    /// Read the registers of a read set.
    Read {
        /// Device 0..=9.
        device: u8,
        /// Read set 0..=7.
        set: u8,
    },
    /// Replace a read set.
    SetReadSet {
        /// Device 0..=9 (the sets are shared by all devices).
        device: u8,
        /// Read set 0..=7.
        set: u8,
        /// The new ids (at most 24), not checked against any table.
        ids: &'a [u8],
    },
}

impl Frame<'_> {
    /// The addressed device.
    pub fn device(&self) -> u8 {
        match self {
            Frame::Write { device, .. }
            | Frame::Read { device, .. }
            | Frame::SetReadSet { device, .. } => *device,
        }
    }

    /// The frame's command.
    pub fn command(&self) -> Command {
        match self {
            Frame::Write { .. } => Command::Write,
            Frame::Read { .. } => Command::Read,
            Frame::SetReadSet { .. } => Command::SetReadSet,
        }
    }

    /// An owned copy of the frame.
    pub fn to_request(&self) -> Request {
        match self {
            Frame::Write { device, writes } => Request::Write {
                device: *device,
                writes: writes.clone().collect(),
            },
            Frame::Read { device, set } => Request::Read {
                device: *device,
                set: *set,
            },
            Frame::SetReadSet { device, set, ids } => Request::SetReadSet {
                device: *device,
                set: *set,
                // The parser admits at most READ_SET_SIZE ids.
                ids: ids.iter().copied().take(READ_SET_SIZE).collect(),
            },
        }
    }
}

/// The writes of a validated write frame, decoded as they are iterated. The payload was
/// checked to hold exactly this many well-sized entries, so iteration cannot fail.
#[derive(Clone)]
pub struct Writes<'a> {
    remaining: u8,
    bytes: &'a [u8],
    /// The addressed device's table, looked up once per frame.
    sizes: Sizes,
    /// Whether some entry names a read-only register (found while validating, so the
    /// frame logic needs no pass of its own to check).
    read_only: bool,
}

impl Writes<'_> {
    /// Whether some entry names a read-only register.
    pub fn any_read_only(&self) -> bool {
        self.read_only
    }

    /// The next write and its size in bytes (1 or 2), as the table gave it.
    pub fn next_sized(&mut self) -> Option<(Write, u8)> {
        if self.remaining == 0 {
            return None;
        }
        let [id, rest @ ..] = self.bytes else {
            return None;
        };
        // Bit 0 of the code: a two-byte register.
        let two = self.sizes.code(*id)? & 1;
        let (raw, tail) = match (two, rest) {
            (0, [lo, tail @ ..]) => (u16::from(*lo), tail),
            (_, [lo, hi, tail @ ..]) => (u16::from_le_bytes([*lo, *hi]), tail),
            _ => return None,
        };
        self.remaining -= 1;
        self.bytes = tail;
        Some((Write { id: *id, raw }, two + 1))
    }
}

impl core::fmt::Debug for Writes<'_> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_list().entries(self.clone()).finish()
    }
}

impl Iterator for Writes<'_> {
    type Item = Write;

    fn next(&mut self) -> Option<Write> {
        self.next_sized().map(|(w, _)| w)
    }

    fn size_hint(&self) -> (usize, Option<usize>) {
        (
            usize::from(self.remaining),
            Some(usize::from(self.remaining)),
        )
    }
}

impl ExactSizeIterator for Writes<'_> {}

impl Request {
    /// The addressed device.
    pub fn device(&self) -> u8 {
        match self {
            Request::Write { device, .. }
            | Request::Read { device, .. }
            | Request::SetReadSet { device, .. } => *device,
        }
    }

    /// The frame's command.
    pub fn command(&self) -> Command {
        match self {
            Request::Write { .. } => Command::Write,
            Request::Read { .. } => Command::Read,
            Request::SetReadSet { .. } => Command::SetReadSet,
        }
    }
}

/// The second byte of a frame.
const fn header(device: u8, command: Command) -> u8 {
    ((device & 0x0f) << 4) | command as u8
}

#[cfg(test)]
mod tests;
