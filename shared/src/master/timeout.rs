//! The inter-byte timeout of the PC link: a partial frame whose bytes stop arriving is
//! dropped, so one lost or extra byte costs one frame instead of desynchronising the link
//! until a reset (the original had no timeout, reference §4.2 and §4.6).
//!
//! # Why 50 ms
//! A frame leaves the PC in one `write()`. At 115200 baud its bytes follow each other every
//! 87 µs; the gaps that really occur come from the USB-serial bridge and the host's
//! scheduler (1-ms USB frames, a write split over two USB packets, a busy host), a few ms
//! and rarely tens of ms. The timeout must be well above those, so a slow but whole frame
//! is never cut, and well below the PC library's 1-s reply timeout, so that after a cut
//! frame the link is back in step before the PC gives up on its next request. 50 ms is
//! ~500 byte times and 1/20 of the reply timeout.
//!
//! # Blocked loops
//! The master's loop blocks while it executes a frame or bit-bangs a temperature sensor;
//! bytes that arrive meanwhile wait in the receive buffer. A gap is therefore measured from
//! the last byte *taken* to now only while no byte is waiting, so a blocked loop never looks
//! like a silent PC.

/// Inter-byte timeout of the PC link, in ms.
pub const INTER_BYTE_TIMEOUT_MS: u32 = 50;

/// Tracks the time since the last byte of a partial frame.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct InterByteTimeout {
    /// When the last byte of the current partial frame was taken: the low 16 bits of the
    /// ms clock (the gaps measured are far below 65 s: the loop checks every few ms);
    /// `None` between frames.
    last_byte_ms: Option<u16>,
}

impl InterByteTimeout {
    /// Between frames.
    pub const fn new() -> Self {
        InterByteTimeout { last_byte_ms: None }
    }

    /// A byte was taken from the receive buffer at `now_ms`; `in_frame` says whether the
    /// parser is now in the middle of a frame (false once the byte completed one).
    pub fn byte(&mut self, now_ms: u32, in_frame: bool) {
        self.last_byte_ms = in_frame.then_some(now_ms as u16);
    }

    /// Whether the partial frame has timed out at `now_ms`. Never true while
    /// `byte_waiting` (a byte sits in the receive buffer) or between frames. When it
    /// returns true the state goes back to "between frames": the caller drops the partial
    /// frame (`Parser::abort`) and records `FrameError::Truncated`.
    pub fn expired(&mut self, now_ms: u32, byte_waiting: bool) -> bool {
        match self.last_byte_ms {
            Some(last)
                if !byte_waiting
                    && u32::from((now_ms as u16).wrapping_sub(last)) > INTER_BYTE_TIMEOUT_MS =>
            {
                self.last_byte_ms = None;
                true
            }
            _ => false,
        }
    }

    /// Whether a partial frame is being timed.
    pub const fn in_frame(&self) -> bool {
        self.last_byte_ms.is_some()
    }
}
