//! The master's frame parser: fed one byte at a time, it yields each frame as a
//! validated [`Request`] or a [`FrameError`], all or nothing, and never loses sync
//! beyond the frame it is in.

use super::sizes::Sizes;
use super::{Command, Frame, FrameError, Rejected, Request, SizesOf, Writes};
use super::{MAX_DEVICE, MAX_FRAME};
use super::{MAX_WRITES, READ_SETS, READ_SET_SIZE};

/// Collects the bytes of one frame at a time in a fixed 255-byte buffer, or skips bytes
/// after a damaged or lost one ([`Parser::lose`]) until the link's timeout finds the line
/// quiet ([`Parser::abort`]).
// In declaration order, the count first: the AVR reaches it from the parser's address
// with a short displacement, where after the buffer it would need its own pointer.
#[derive(Clone, Debug)]
#[repr(C)]
pub struct Parser {
    /// Bytes of the current frame received so far; 0 between frames; [`SKIPPING`] after a
    /// lost byte (a count never kept: a frame ends by its 255th byte).
    len: u8,
    buf: [u8; MAX_FRAME],
}

/// [`Parser::len`] while bytes are skipped: the index just past the buffer.
const SKIPPING: u8 = u8::MAX;
const _: () = assert!(SKIPPING as usize == MAX_FRAME);

impl Default for Parser {
    fn default() -> Self {
        Self::new()
    }
}

impl Parser {
    /// A parser waiting for a frame's length byte.
    pub const fn new() -> Self {
        Parser {
            buf: [0; MAX_FRAME],
            len: 0,
        }
    }

    /// Feeds one byte. Returns `Some` when it ends a frame: the request, or why the frame
    /// is rejected. A length byte of 0 or 1 ends its (error) frame at once; a frame of
    /// length L >= 2 ends at its L-th byte.
    pub fn push(&mut self, byte: u8) -> Option<Result<Request, FrameError>> {
        self.push_frame(byte).map(|r| match r {
            Ok(frame) => Ok(frame.to_request()),
            Err(rejected) => Err(rejected.error),
        })
    }

    /// As [`Parser::push`], but the frame is a view into the parser's buffer: nothing is
    /// copied, which is what the master uses (a 2 KB RAM budget has no room for a copy).
    pub fn push_frame(&mut self, byte: u8) -> Option<Result<Frame<'_>, Rejected>> {
        if self.push_byte(byte) {
            Some(self.completed())
        } else {
            None
        }
    }

    /// Feeds one byte; returns whether it ended a frame, which [`Parser::completed`] then
    /// validates (until the next byte). The master's byte loop uses this, so that only a
    /// completed frame reaches the validation and the frame logic.
    pub fn push_byte(&mut self, byte: u8) -> bool {
        // In a frame `len` < L <= 255, so `index` is inside the buffer (a length byte
        // below 2 is kept too, for `completed` to reject); only SKIPPING is past its end.
        let Some(slot) = self.buf.get_mut(usize::from(self.len)) else {
            return false;
        };
        *slot = byte;
        self.len = self.len.wrapping_add(1);
        // A frame of length L >= 2 ends at its L-th byte; a length byte of 0 or 1 ends its
        // (error) frame at once.
        if self.buf[0] >= 2 && self.len < self.buf[0] {
            return false;
        }
        self.len = 0;
        true
    }

    /// The frame the last byte ended: the request, or why the frame is rejected.
    pub fn completed(&self) -> Result<Frame<'_>, Rejected> {
        let frame_len = usize::from(self.buf[0]);
        if frame_len < 2 {
            return Err(Rejected {
                error: FrameError::BadLength,
                header: None,
            });
        }
        // `frame_len` <= 255 = the buffer's length.
        let frame = self.buf.get(..frame_len).unwrap_or(&[]);
        let header = frame.get(1).copied();
        validate(frame, Sizes::of_device).map_err(|error| Rejected { error, header })
    }

    /// Drops a partial frame, or ends the skipping (the link's inter-byte timeout: the
    /// line is quiet); returns true if a partial frame was dropped.
    pub fn abort(&mut self) -> bool {
        let dropped = self.len != 0 && self.len != SKIPPING;
        self.len = 0;
        dropped
    }

    /// A byte was damaged or lost: drops a partial frame, and skips every byte until
    /// [`Parser::abort`]. The rest of the damaged frame must not run as frames of its
    /// own, and where they end only a quiet line tells.
    pub fn lose(&mut self) {
        self.len = SKIPPING;
    }

    /// Whether part of a frame has been received, or bytes are being skipped: what the
    /// link's inter-byte timeout times.
    pub fn in_frame(&self) -> bool {
        self.len != 0
    }
}

/// Validates a complete frame. `sizes_of(device)` gives the table that sizes the
/// device's registers.
pub(crate) fn validate(frame: &[u8], sizes_of: SizesOf) -> Result<Frame<'_>, FrameError> {
    let [_, header, payload @ ..] = frame else {
        return Err(FrameError::BadLength);
    };
    if payload.is_empty() {
        return Err(FrameError::BadLength);
    }
    let device = header >> 4;
    if device > MAX_DEVICE {
        return Err(FrameError::BadDevice);
    }
    match Command::from_u8(header & 0x0f) {
        None => Err(FrameError::UnknownCommand),
        Some(Command::Write) => {
            // A device with no board has no register to size.
            let sizes = sizes_of(device).unwrap_or(Sizes::EMPTY);
            let writes = parse_writes(payload, sizes)?;
            Ok(Frame::Write { device, writes })
        }
        Some(Command::Read) => match payload {
            [set] if usize::from(*set) < READ_SETS => Ok(Frame::Read { device, set: *set }),
            [_] => Err(FrameError::BadReadSet),
            _ => Err(FrameError::LengthMismatch),
        },
        Some(Command::SetReadSet) => {
            let [set, ids @ ..] = payload else {
                return Err(FrameError::LengthMismatch);
            };
            if usize::from(*set) >= READ_SETS {
                return Err(FrameError::BadReadSet);
            }
            if ids.len() > READ_SET_SIZE {
                return Err(FrameError::ReadSetTooLarge);
            }
            Ok(Frame::SetReadSet {
                device,
                set: *set,
                ids,
            })
        }
    }
}

/// Checks a write payload: count k, then k × (id, value of the id's size, LSB first),
/// filling the payload exactly.
fn parse_writes(payload: &[u8], sizes: Sizes) -> Result<Writes<'_>, FrameError> {
    let [count, entries @ ..] = payload else {
        return Err(FrameError::LengthMismatch);
    };
    if usize::from(*count) > MAX_WRITES {
        return Err(FrameError::LengthMismatch);
    }
    let mut rest = entries;
    let mut read_only = false;
    for _ in 0..*count {
        let [id, after_id @ ..] = rest else {
            return Err(FrameError::LengthMismatch);
        };
        // Bit 0: a two-byte register; bit 1: writable.
        let code = sizes.code(*id).ok_or(FrameError::UnknownRegister)?;
        read_only |= code & 2 == 0;
        rest = match (code & 1, after_id) {
            (0, [_, tail @ ..]) => tail,
            (_, [_, _, tail @ ..]) => tail,
            _ => return Err(FrameError::LengthMismatch),
        };
    }
    if rest.is_empty() {
        Ok(Writes {
            remaining: *count,
            bytes: entries,
            sizes,
            read_only,
        })
    } else {
        Err(FrameError::LengthMismatch)
    }
}
