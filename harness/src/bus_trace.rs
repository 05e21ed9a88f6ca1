//! The bus's message log: what went over the wire, when, and who drove it.

use std::fmt;

use crate::avr::CYCLES_PER_US;

/// Who drove a transaction.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Initiator {
    /// The master firmware of the chip with this bus index.
    Chip(usize),
    /// The Rust master peer ([`crate::bus::Bus::write`] and friends).
    Peer,
}

/// One event on the bus.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TwiEvent {
    /// START (or repeated START) and the address byte; `ack` is the slave's answer.
    Start {
        /// 7-bit address.
        addr: u8,
        /// True for SLA+R.
        read: bool,
        /// Acknowledged by a device.
        ack: bool,
    },
    /// A byte written by the master; `ack` is the slave's answer.
    Write {
        /// The byte.
        byte: u8,
        /// Acknowledged by the slave.
        ack: bool,
    },
    /// A byte read by the master; `ack` is the master's answer (false on the last byte).
    Read {
        /// The byte.
        byte: u8,
        /// Acknowledged by the master.
        ack: bool,
    },
    /// STOP.
    Stop,
    /// A slave chip took an event but did not release the bus within the bounded wait; if
    /// its TWINT stays set, it holds SCL low from then on, until [`TwiEvent::Released`].
    Timeout {
        /// 7-bit address of the slave.
        addr: u8,
    },
    /// The slave chip that held SCL low let it go (cleared TWINT, switched its TWI off or
    /// reset); the transaction it held is abandoned (logged as its initiator's).
    Released {
        /// 7-bit address of the slave.
        addr: u8,
    },
    /// A master started while another master's transaction was in progress, and was refused.
    Collision {
        /// 7-bit address it tried.
        addr: u8,
    },
}

/// A logged [`TwiEvent`] with its time stamp.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TraceEntry {
    /// Cycle of the initiator's clock when the event started (16 per µs).
    pub cycle: u64,
    /// Who drove it.
    pub by: Initiator,
    /// What happened.
    pub event: TwiEvent,
}

impl TraceEntry {
    /// The time stamp in emulated microseconds.
    pub fn micros(&self) -> f64 {
        self.cycle as f64 / CYCLES_PER_US as f64
    }
}

fn ack(ack: bool) -> &'static str {
    if ack {
        "ACK"
    } else {
        "NACK"
    }
}

impl fmt::Display for TwiEvent {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            TwiEvent::Start { addr, read, ack: a } => {
                let dir = if read { 'R' } else { 'W' };
                write!(f, "START {addr:#04x} {dir} {}", ack(a))
            }
            TwiEvent::Write { byte, ack: a } => write!(f, "WRITE {byte:#04x} {}", ack(a)),
            TwiEvent::Read { byte, ack: a } => write!(f, "READ  {byte:#04x} {}", ack(a)),
            TwiEvent::Stop => write!(f, "STOP"),
            TwiEvent::Timeout { addr } => write!(f, "TIMEOUT {addr:#04x}"),
            TwiEvent::Released { addr } => write!(f, "RELEASED {addr:#04x}"),
            TwiEvent::Collision { addr } => write!(f, "COLLISION {addr:#04x}"),
        }
    }
}

impl fmt::Display for TraceEntry {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let by = match self.by {
            Initiator::Chip(i) => format!("chip{i}"),
            Initiator::Peer => "peer".to_string(),
        };
        write!(f, "{:>12.3} µs {by:>6} {}", self.micros(), self.event)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn renders_for_people() {
        let e = TraceEntry {
            cycle: 1600,
            by: Initiator::Chip(0),
            event: TwiEvent::Start {
                addr: 2,
                read: false,
                ack: true,
            },
        };
        assert_eq!(e.to_string(), "     100.000 µs  chip0 START 0x02 W ACK");
        let r = TraceEntry {
            cycle: 8,
            by: Initiator::Peer,
            event: TwiEvent::Read {
                byte: 0xAB,
                ack: false,
            },
        };
        assert_eq!(r.to_string(), "       0.500 µs   peer READ  0xab NACK");
    }
}
