//! The I2C relay to the slaves, as `shared::master::SlaveBus`.

use drivers::twi::TwiMaster;
use shared::master::{BusError, SlaveBus};

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
}

impl SlaveBus for TwiRelay {
    fn write_register(&mut self, device: u8, id: u8, value: &[u8]) -> Result<(), BusError> {
        let mut frame = [id, 0, 0];
        let n = value.len().min(2);
        frame[1..=n].copy_from_slice(&value[..n]);
        self.twi.write(device, &frame[..=n]).map_err(|_| BusError)
    }

    fn read_run(
        &mut self,
        device: u8,
        first: u8,
        len: u8,
        sink: &mut dyn FnMut(u8),
    ) -> Result<(), BusError> {
        self.twi.read(device, first, len, sink).map_err(|_| BusError)
    }
}
