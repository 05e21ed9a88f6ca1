//! The PC link's plumbing: the queues between the USART tasks and idle, the clock, and
//! the inter-byte timeout.

use heapless::Deque;
use shared::master::LinkError;

/// What the receive task hands to idle.
#[derive(Clone, Copy, Debug)]
pub enum RxEvent {
    /// A byte received cleanly.
    Byte(u8),
    /// A byte lost or damaged on the way in.
    Error(LinkError),
}

/// Received bytes waiting for idle: 48 bytes is over 4 ms of line time at 115200 baud,
/// longer than idle is ever kept from them except while it relays over I2C.
pub type RxQueue = Deque<RxEvent, 48>;

/// Reply bytes waiting for the transmitter.
pub type TxQueue = Deque<u8, 64>;

/// A frame whose bytes stop for this long is dropped (docs/protocol.md): far above the
/// gaps of a USB-serial bridge or a program writing byte by byte, far below the original
/// PC library's 1 s reply timeout, so the next frame always starts clean.
pub const INTER_BYTE_TIMEOUT_MS: u32 = 50;

/// Whether a partial frame has waited longer than the inter-byte timeout.
pub fn frame_stalled(now_ms: u32, last_byte_ms: u32) -> bool {
    now_ms.wrapping_sub(last_byte_ms) > INTER_BYTE_TIMEOUT_MS
}

/// Milliseconds since boot, advanced by the 1 kHz tick.
pub struct Clock {
    ms: u32,
}

impl Clock {
    /// Zero at boot.
    pub const fn new() -> Self {
        Clock { ms: 0 }
    }

    /// One more millisecond.
    pub fn advance(&mut self) {
        self.ms = self.ms.wrapping_add(1);
    }

    /// Milliseconds since boot (wraps after 49 days).
    pub fn ms(&self) -> u32 {
        self.ms
    }
}

/// Something that can be locked like a shared resource handle.
pub trait Lock<T> {
    /// Runs `f` with exclusive access.
    fn lock<R>(&mut self, f: impl FnOnce(&mut T) -> R) -> R;
}

impl<T, A: executor::App, const C: u8, const P: u8> Lock<T> for executor::Shared<'_, T, A, C, P> {
    fn lock<R>(&mut self, f: impl FnOnce(&mut T) -> R) -> R {
        executor::Shared::lock(self, f)
    }
}

/// Writes reply bytes into the transmit queue, waiting for room when it is full (the
/// transmit task, at a higher priority, drains it meanwhile).
pub struct Replies<'a, L: Lock<TxQueue>> {
    tx: &'a mut L,
}

impl<'a, L: Lock<TxQueue>> Replies<'a, L> {
    /// Replies through `tx`.
    pub fn new(tx: &'a mut L) -> Self {
        Replies { tx }
    }

    /// Queues one byte and makes sure the transmitter is running.
    pub fn send(&mut self, byte: u8) {
        while self.tx.lock(|q| q.push_back(byte).is_err()) {
            crate::transmit::arm();
        }
        crate::transmit::arm();
    }

    /// Queues every byte of `bytes`.
    pub fn send_all(&mut self, bytes: &[u8]) {
        bytes.iter().for_each(|&b| self.send(b));
    }
}

impl<L: Lock<TxQueue>> ufmt::uWrite for Replies<'_, L> {
    type Error = core::convert::Infallible;

    fn write_str(&mut self, s: &str) -> Result<(), Self::Error> {
        self.send_all(s.as_bytes());
        Ok(())
    }
}
