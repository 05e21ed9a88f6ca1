//! What the master does with each frame, and what it answers (docs/protocol.md).

use super::{LinkError, LocalRegisters};
use crate::protocol::sizes::Sizes;
use crate::protocol::{Frame, ReadSets, Rejected, Writes};

/// The slave answered nothing (no ACK, or no data).
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct BusError;

/// The master's I2C link to the slaves, as the frame logic sees it.
pub trait SlaveBus {
    /// Writes one register: the id, then its value bytes (LSB first).
    fn write_register(&mut self, device: u8, id: u8, value: &[u8]) -> Result<(), BusError>;
    /// Reads `len` bytes starting at register `first` in one transaction (a slave's read
    /// continues past a register into the following ones), handing each byte to `sink`
    /// as it arrives so it can go out on the serial line while the rest is on the bus.
    fn read_run(
        &mut self,
        device: u8,
        first: u8,
        len: u8,
        sink: &mut dyn FnMut(u8),
    ) -> Result<(), BusError>;
}

/// Byte a register the device does not have reads as (the manual's dummy byte).
pub const MISSING_REGISTER_BYTE: u8 = 0xcd;

/// The master's frame logic and device 0. The read sets are kept apart ([`ReadSets`],
/// passed to [`Service::execute`]): they start as zeros, so the firmware's copy costs no
/// flash for its initial value, where device 0's registers start with set values.
#[derive(Clone, Debug, Default)]
pub struct Service {
    /// Device 0's registers.
    pub local: LocalRegisters,
}

impl Service {
    /// The state at boot.
    pub const fn new() -> Self {
        Service {
            local: LocalRegisters::new(),
        }
    }

    /// Executes one frame as the parser delivered it, with the read sets `sets`, and
    /// sends the answer through `reply`. A failed frame whose command answers with one byte (write, set read set)
    /// gets an error reply (`0x80 | code`); a failed read or unknown command gets no
    /// reply, since no reply could be told apart from data. Every error is recorded in
    /// device 0.
    pub fn execute(
        &mut self,
        sets: &mut ReadSets,
        frame: Result<Frame<'_>, Rejected>,
        bus: &mut impl SlaveBus,
        reply: &mut impl FnMut(u8),
    ) {
        // Whether the command answers with one byte (write, set read set): only those
        // carry an error reply.
        let (result, one_byte_reply) = match frame {
            Ok(Frame::Write { device, writes }) => (self.write(device, writes, bus, reply), true),
            Ok(Frame::Read { device, set }) => (self.read(sets, device, set, bus, reply), false),
            Ok(Frame::SetReadSet { set, ids, .. }) => (
                match sets.set(set, ids) {
                    Ok(()) => {
                        // At most 24 ids, so the count fits a byte.
                        reply(ids.len() as u8);
                        Ok(())
                    }
                    Err(e) => Err(LinkError::of_frame(e)),
                },
                true,
            ),
            Err(r) => (
                Err(LinkError::of_frame(r.error)),
                matches!(r.header.map(|h| h & 0x0f), Some(2) | Some(4)),
            ),
        };
        if let Err(e) = result {
            self.local.record(e);
            let already_answered = matches!(e, LinkError::MissingRegister);
            if one_byte_reply && !already_answered {
                reply(e.reply());
            }
        }
    }

    /// Records an error seen below the frame level (serial framing, overrun, a frame
    /// dropped by the inter-byte timeout).
    pub fn link_error(&mut self, e: LinkError) {
        self.local.record(e);
    }

    /// A write frame: a frame with a read-only register writes nothing (the parser found
    /// them while validating); otherwise the writes are applied in order. A write the
    /// slave does not take does not stop the ones after it (a stop frame's REQSPEED still
    /// goes out, as the original sent every write); the reply then says one failed.
    fn write(
        &mut self,
        device: u8,
        mut writes: Writes<'_>,
        bus: &mut impl SlaveBus,
        reply: &mut impl FnMut(u8),
    ) -> Result<(), LinkError> {
        if Sizes::of_device(device).is_none() {
            return Err(LinkError::BadDevice);
        }
        if writes.any_read_only() {
            return Err(LinkError::ReadOnly);
        }
        let mut answered = Ok(());
        while let Some((w, size)) = writes.next_sized() {
            if device == 0 {
                self.local.write(w.id, w.raw);
            } else {
                let bytes = w.raw.to_le_bytes();
                let value = bytes.get(..usize::from(size)).unwrap_or(&bytes);
                if bus.write_register(device, w.id, value).is_err() {
                    answered = Err(LinkError::NoAnswer);
                }
            }
        }
        answered?;
        reply(0);
        Ok(())
    }

    /// A read frame: each id of the set, sized by the device's table, LSB first. Ids that
    /// follow each other (n, n+1, …) are fetched from a slave as one run in one
    /// transaction. A missing register reads as one 0xcd byte (and is recorded); a slave
    /// that stops answering ends the reply early.
    fn read(
        &mut self,
        sets: &ReadSets,
        device: u8,
        set: u8,
        bus: &mut impl SlaveBus,
        reply: &mut impl FnMut(u8),
    ) -> Result<(), LinkError> {
        let kind = Sizes::of_device(device).ok_or(LinkError::BadDevice)?;
        let ids = sets.get(set).ok_or(LinkError::BadReadSet)?;
        if ids.is_empty() {
            return Err(LinkError::EmptyReadSet);
        }
        let mut missing = false;
        let mut rest = ids;
        while let [first, tail @ ..] = rest {
            let Some(size) = kind.size_of(*first) else {
                reply(MISSING_REGISTER_BYTE);
                missing = true;
                rest = tail;
                continue;
            };
            if device == 0 {
                // The first `size` bytes of the value (at most two), LSB first.
                let [lo, hi] = self.local.read(*first).unwrap_or(0).to_le_bytes();
                if size >= 1 {
                    reply(lo);
                }
                if size >= 2 {
                    reply(hi);
                }
                rest = tail;
                continue;
            }
            let (count, bytes) = run_of(kind, rest);
            bus.read_run(device, *first, bytes, reply)
                .map_err(|_| LinkError::NoAnswer)?;
            // `count` ≤ the ids left (run_of counts ids of `rest`).
            rest = rest.get(count..).unwrap_or_default();
        }
        if missing {
            Err(LinkError::MissingRegister)
        } else {
            Ok(())
        }
    }
}

/// The run at the start of `ids`: how many ids follow each other (n, n+1, …) and exist on
/// the board, and their total size in bytes.
fn run_of(kind: Sizes, ids: &[u8]) -> (usize, u8) {
    let mut count = 0;
    let mut bytes = 0u8;
    // The id that continues the run (none after 255); the first id always does.
    let mut next = ids.first().copied();
    for &id in ids {
        match kind.size_of(id) {
            Some(size) if next == Some(id) => {
                count += 1;
                bytes = bytes.saturating_add(size);
                next = id.checked_add(1);
            }
            _ => break,
        }
    }
    (count, bytes)
}
