//! The TWI task's body: one bus event into the register file, then the bus moves on.

use crate::registers::Registers;
use drivers::twi_slave::{Event, TwiSlave};

/// Handles the event behind the current TWINT.
#[inline(always)]
pub fn on_event(twi: &mut TwiSlave, live: &mut Registers) {
    let event = twi.event();
    if let Event::Data(_) = event {
        live.mark_written();
    }
    let regs = live.file();
    match event {
        Event::WriteStart => regs.start_write(),
        Event::Data(byte) => regs.write(byte),
        Event::Stop | Event::ReadEnd => regs.stop(),
        Event::ReadStart => {
            regs.start_read();
            twi.send(regs.read());
        }
        Event::ReadMore => twi.send(regs.read()),
        Event::BusError => {
            regs.stop();
            twi.recover();
            return;
        }
        Event::Other => {}
    }
    twi.release();
}
