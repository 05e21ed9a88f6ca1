//! The I2C relay to the slaves, as `shared::master::SlaveBus`, and the same relay as the
//! PC frames use it: feeding the watchdog before every access and noting how it went.

use drivers::twi::TwiMaster;
use drivers::watchdog::Watchdog;
use shared::master::{BusError, RegWrite, SlaveBus};

/// Bus clock: the slaves keep up at 400 kHz, four times the original's 100 kHz.
pub const BUS_KHZ: u16 = 400;

/// The slaves behind the TWI master. Every transfer is bounded in time, so a slave that
/// stops answering costs about a millisecond and an error, never a hang.
pub struct TwiRelay {
    twi: TwiMaster,
}

impl TwiRelay {
    /// Relays through `twi`.
    pub fn new(twi: TwiMaster) -> Self {
        TwiRelay { twi }
    }

    /// Reads a 2-byte register, LSB first.
    pub fn read_word(&mut self, device: u8, id: u8) -> Result<u16, BusError> {
        // Each byte shifts in from the top: after the two a successful read delivers, the
        // first is the low byte.
        let mut word = 0u16;
        self.read_run(device, id, 2, &mut |b| {
            word = (word >> 8) | (u16::from(b) << 8);
        })?;
        Ok(word)
    }

    /// Performs one register write the master decided on (the schedule's, or the remote
    /// control's).
    pub fn write(&mut self, w: &RegWrite) -> Result<(), BusError> {
        self.write_register(w.device, w.id, w.bytes())
    }
}

impl SlaveBus for TwiRelay {
    // Out of line: the PC frames, the schedule and the remote control share one copy.
    #[inline(never)]
    fn write_register(&mut self, device: u8, id: u8, value: &[u8]) -> Result<(), BusError> {
        let mut frame = [id, 0, 0];
        let n = value.len().min(2);
        frame[1..=n].copy_from_slice(&value[..n]);
        self.twi.write(device, &frame[..=n]).map_err(|_| BusError)
    }

    // Out of line: measured 14 B smaller than in the PC link's frame logic.
    #[inline(never)]
    fn read_run(
        &mut self,
        device: u8,
        first: u8,
        len: u8,
        sink: &mut dyn FnMut(u8),
    ) -> Result<(), BusError> {
        self.twi
            .read(device, first, len, sink)
            .map_err(|_| BusError)
    }
}

/// The relay while it serves one PC frame: the watchdog is fed before every access, and
/// the last access's slave and result are kept, so the frame can be reported to the
/// schedule as evidence of that slave's liveness (a frame addresses one slave; a read
/// stops at the first access that fails, a write frame goes on with its other writes,
/// and a slave that took a later one answered).
pub struct Watched<'a> {
    relay: &'a mut TwiRelay,
    watchdog: &'a Watchdog,
    last: Option<(u8, bool)>,
}

impl<'a> Watched<'a> {
    /// Watches `relay` for one frame.
    pub fn new(relay: &'a mut TwiRelay, watchdog: &'a Watchdog) -> Self {
        Watched {
            relay,
            watchdog,
            last: None,
        }
    }

    /// The slave the frame accessed and whether every access was answered; `None` if
    /// the frame made no I2C access.
    pub fn outcome(&self) -> Option<(u8, bool)> {
        self.last
    }
}

impl SlaveBus for Watched<'_> {
    fn write_register(&mut self, device: u8, id: u8, value: &[u8]) -> Result<(), BusError> {
        self.watchdog.feed();
        let result = self.relay.write_register(device, id, value);
        self.last = Some((device, result.is_ok()));
        result
    }

    fn read_run(
        &mut self,
        device: u8,
        first: u8,
        len: u8,
        sink: &mut dyn FnMut(u8),
    ) -> Result<(), BusError> {
        self.watchdog.feed();
        let result = self.relay.read_run(device, first, len, sink);
        self.last = Some((device, result.is_ok()));
        result
    }
}
