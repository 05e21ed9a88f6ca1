//! The TWI task's body: one bus event into the register file, then the bus moves on.

use crate::registers::Registers;
use drivers::twi_slave::{Event, TwiSlave};
use shared::slave::Board;

/// Handles the event behind the current TWINT.
#[inline(always)]
pub fn on_event<B: Board>(twi: &mut TwiSlave, live: &mut Registers<B>) {
    let event = twi.event();
    if let Event::Data(_) = event {
        live.mark_written();
    }
    if let Event::WriteStart | Event::ReadStart = event {
        live.mark_addressed();
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
