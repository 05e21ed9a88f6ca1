//! The Rust master peer: transactions driven from a test, with bus timing.
//!
//! Each bus event costs its time at the peer's SCL clock ([`Bus::set_peer_khz`], 100 kHz by
//! default), and the whole bus runs in lock step through it: START 1 bit, every byte with its
//! ACK 9 bits, STOP 1 bit. A slave chip slower than that stretches the byte until it answers.
//! On any failure the peer still ends the transaction with STOP.

use super::engine::Engine;
use super::{Bus, Initiator};
use crate::avr::CYCLES_PER_US;
use crate::twi::TwiError;

/// Bit times of each bus event.
const START_BITS: u64 = 1;
const BYTE_BITS: u64 = 9;
const STOP_BITS: u64 = 1;

impl Bus {
    /// Writes `bytes` to the device at 7-bit address `addr` in one transaction
    /// (START, SLA+W, bytes, STOP). An empty `bytes` only probes the address.
    pub fn write(&mut self, addr: u8, bytes: &[u8]) -> Result<(), TwiError> {
        self.transaction(addr, bytes, 0).map(|_| ())
    }

    /// Reads `n` bytes (at least one) from the device at `addr` (START, SLA+R, n bytes, the last
    /// one NACKed, STOP).
    pub fn read(&mut self, addr: u8, n: usize) -> Result<Vec<u8>, TwiError> {
        if n == 0 {
            return Err(TwiError::EmptyRead);
        }
        self.transaction(addr, &[], n)
    }

    /// Writes `bytes`, then reads `n` bytes after a repeated START, then STOP.
    pub fn write_read(&mut self, addr: u8, bytes: &[u8], n: usize) -> Result<Vec<u8>, TwiError> {
        if n == 0 {
            return Err(TwiError::EmptyRead);
        }
        self.transaction(addr, bytes, n)
    }

    /// One transaction: a write part (if there are bytes, or nothing to read), a read part (if
    /// `n` > 0), and always a STOP at the end.
    fn transaction(&mut self, addr: u8, bytes: &[u8], n: usize) -> Result<Vec<u8>, TwiError> {
        self.wait_idle()?;
        let result = self.parts(addr, bytes, n);
        // STOP cannot fail; its result is always Ok.
        self.peer_stop();
        result
    }

    fn parts(&mut self, addr: u8, bytes: &[u8], n: usize) -> Result<Vec<u8>, TwiError> {
        let by = Initiator::Peer;
        if !bytes.is_empty() || n == 0 {
            self.peer_event(START_BITS + BYTE_BITS, |e, at| e.start(by, addr, false, at))?;
            for &byte in bytes {
                self.peer_event(BYTE_BITS, |e, at| e.write(by, byte, at))?;
            }
        }
        let mut out = Vec::with_capacity(n);
        if n > 0 {
            self.peer_event(START_BITS + BYTE_BITS, |e, at| e.start(by, addr, true, at))?;
            for i in 0..n {
                let more = i + 1 < n;
                out.push(self.peer_event(BYTE_BITS, |e, at| e.read(by, more, at))?);
            }
        }
        Ok(out)
    }

    /// STOP: one bit time. A slave chip handles it (status 0xA0) while the bus is already
    /// free, so it never stretches the bus.
    fn peer_stop(&mut self) {
        let at = self.now;
        if let Ok(mut engine) = self.engine.try_borrow_mut() {
            engine.stop(Initiator::Peer, at);
        }
        self.advance_to(at.saturating_add(STOP_BITS * self.peer_bit));
    }

    /// Runs one bus event of `bits` bit times: the engine acts at the current bus time, then
    /// the whole bus advances by the event's length, or until the slave that answered, if it
    /// took longer.
    fn peer_event<R>(
        &mut self,
        bits: u64,
        event: impl FnOnce(&mut Engine, u64) -> Result<R, TwiError>,
    ) -> Result<R, TwiError> {
        let at = self.now;
        let (result, answered) = {
            let Ok(mut engine) = self.engine.try_borrow_mut() else {
                return Err(TwiError::BusBusy { waited_us: 0 });
            };
            engine.last_answer = 0;
            let result = event(&mut engine, at);
            (result, engine.last_answer)
        };
        let end = at.saturating_add(bits * self.peer_bit).max(answered);
        self.advance_to(end);
        result
    }

    /// Runs the bus until no other master's transaction is in progress and no slave chip
    /// holds SCL low (bounded).
    fn wait_idle(&mut self) -> Result<(), TwiError> {
        let start = self.now;
        let end = start.saturating_add(self.busy_timeout);
        loop {
            let (busy, held) = self
                .engine
                .try_borrow()
                .map_or((true, None), |e| (e.busy(), e.held_by()));
            if !busy && held.is_none() {
                return Ok(());
            }
            if self.now >= end {
                let waited_us = (self.now - start) / CYCLES_PER_US;
                return Err(match held {
                    Some(addr) => TwiError::BusHeld { addr, waited_us },
                    None => TwiError::BusBusy { waited_us },
                });
            }
            self.advance_to(self.now.saturating_add(self.quantum).min(end));
        }
    }
}
