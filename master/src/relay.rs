//! The I2C relay to the slaves, as `shared::master::SlaveBus`.

use shared::master::{BusError, SlaveBus};

/// No slave bus yet: every slave access fails, so the PC is told (error reply, or the
/// recorded NoAnswer) instead of being answered with made-up data.
pub struct NoSlaves;

impl SlaveBus for NoSlaves {
    fn write_register(&mut self, _device: u8, _id: u8, _value: &[u8]) -> Result<(), BusError> {
        Err(BusError)
    }

    fn read_registers(&mut self, _device: u8, _id: u8, _out: &mut [u8]) -> Result<(), BusError> {
        Err(BusError)
    }
}
