//! The PC link's plumbing: the queues between the USART tasks and idle, and the clock.

use shared::master::{LinkError, Ring};

/// What the receive task hands to idle: two bytes each, so the queue stays small.
#[derive(Clone, Copy, Debug)]
pub enum RxEvent {
    /// A byte received cleanly.
    Byte(u8),
    /// A byte arrived with a framing error and was dropped.
    Framing,
    /// A byte was lost: the receiver overran, or the queue was full.
    Overrun,
}

impl RxEvent {
    /// The error a damaged or lost byte is recorded as; `None` for a clean byte.
    pub fn error(self) -> Option<LinkError> {
        match self {
            RxEvent::Byte(_) => None,
            RxEvent::Framing => Some(LinkError::Framing),
            RxEvent::Overrun => Some(LinkError::Overrun),
        }
    }
}

/// Received bytes waiting for idle: 64, as many as the Uno's serial core held for the
/// original (its 64-byte ring, 63 of them usable), so a PC program that sends frames
/// without waiting for each reply loses none here where it lost none there. They are
/// 5.6 ms of line time at 115200 baud, longer than idle is ever kept from them between
/// frames (it drains them between any two pieces of work, the longest being a
/// remote-control pass of ~1.5 ms); they fill only while a frame's bus work runs.
pub type RxQueue = Ring<RxEvent, 64>;

/// Reply bytes waiting for the transmitter. A longer reply is streamed: the relay waits
/// for room between the bytes it reads, so the reply goes out at line speed anyway.
pub type TxQueue = Ring<u8, 32>;

/// Milliseconds since boot, advanced by the 1 kHz tick. Sixteen bits: everything the
/// master times is far shorter than their 65.5-s wrap, and what it measures from boot
/// (the slaves' 5-s settling) is over long before the first wrap.
pub struct Clock {
    ms: u16,
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

    /// Milliseconds since boot (wraps after 65.5 s).
    pub fn ms(&self) -> u16 {
        self.ms
    }
}

/// Milliseconds since boot (wrapping after 65.5 s), read from the shared clock. Out of
/// line: the loop and the PC link read it in six places, which share one copy of the
/// lock and the 2-byte read. Sixteen bits all the way: the shared logic takes its `u32`
/// times widened at the call, so the upper bytes are known zeros there.
#[inline(never)]
pub fn now_ms(clock: &mut impl Lock<Clock>) -> u16 {
    clock.lock(|c| c.ms())
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
        loop {
            let queued = self.tx.lock(|q| q.push_back(byte).is_ok());
            crate::transmit::arm();
            if queued {
                return;
            }
        }
    }
}
