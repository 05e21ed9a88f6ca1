//! The message word simavr's TWI raises on its IRQs, decoded.

use std::fmt;

use simavr_ffi as ffi;

/// Condition bits of a [`TwiMsg`] (simavr's `TWI_COND_*`).
pub mod cond {
    use simavr_ffi as ffi;

    /// A START; from a master chip it carries the address byte (SLA+R/W) in `addr`.
    pub const START: u8 = ffi::TWI_COND_START as u8;
    /// A STOP.
    pub const STOP: u8 = ffi::TWI_COND_STOP as u8;
    /// Towards a slave: the START carries its address. From a slave: it released the bus.
    pub const ADDR: u8 = ffi::TWI_COND_ADDR as u8;
    /// An acknowledge (towards a master: `data` bit 0 says ACK or NACK).
    pub const ACK: u8 = ffi::TWI_COND_ACK as u8;
    /// A byte written by the master (or, with START towards a slave, a write transaction).
    pub const WRITE: u8 = ffi::TWI_COND_WRITE as u8;
    /// A byte read by the master (towards a master, `data` is the byte).
    pub const READ: u8 = ffi::TWI_COND_READ as u8;
}

/// One TWI IRQ message: condition bits, an address and a data byte.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TwiMsg {
    /// OR of [`cond`] bits.
    pub cond: u8,
    /// Address: the SLA+R/W byte from a master chip, the 7-bit address towards a slave chip.
    pub addr: u8,
    /// Data byte (or ACK flag in bit 0).
    pub data: u8,
}

impl TwiMsg {
    /// A message with the given condition bits, address and data.
    pub const fn new(cond: u8, addr: u8, data: u8) -> TwiMsg {
        TwiMsg { cond, addr, data }
    }

    /// Decodes the IRQ value (simavr packs `msg`, `addr`, `data` in bits 8.., 16.., 24..).
    pub const fn from_raw(value: u32) -> TwiMsg {
        TwiMsg {
            cond: (value >> 8) as u8,
            addr: (value >> 16) as u8,
            data: (value >> 24) as u8,
        }
    }

    /// Encodes the IRQ value simavr expects.
    pub const fn to_raw(self) -> u32 {
        ((self.cond as u32) << 8) | ((self.addr as u32) << 16) | ((self.data as u32) << 24)
    }

    /// True if every bit of `bits` is set.
    pub const fn has(self, bits: u8) -> bool {
        self.cond & bits == bits
    }

    /// The message simavr itself would build (its `avr_twi_irq_msg`), for cross-checks.
    pub fn from_simavr(cond: u8, addr: u8, data: u8) -> u32 {
        // SAFETY: a pure function of its arguments.
        unsafe { ffi::avr_twi_irq_msg(cond, addr, data) }
    }
}

impl fmt::Display for TwiMsg {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let names = [
            (cond::START, "START"),
            (cond::STOP, "STOP"),
            (cond::ADDR, "ADDR"),
            (cond::ACK, "ACK"),
            (cond::WRITE, "WRITE"),
            (cond::READ, "READ"),
        ];
        let set: Vec<&str> = names
            .iter()
            .filter(|(bit, _)| self.cond & bit != 0)
            .map(|(_, name)| *name)
            .collect();
        write!(
            f,
            "{} addr {:#04x} data {:#04x}",
            set.join("|"),
            self.addr,
            self.data
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn layout_matches_simavr() {
        let raw = TwiMsg::from_simavr(cond::START | cond::ADDR, 0x42, 0xA5);
        assert_eq!(raw, 0xA542_0500);
        assert_eq!(TwiMsg::from_raw(raw), TwiMsg::new(0x05, 0x42, 0xA5));
        assert_eq!(TwiMsg::new(0x05, 0x42, 0xA5).to_raw(), raw);
    }

    #[test]
    fn conditions_are_simavr_bits() {
        assert_eq!(
            [
                cond::START,
                cond::STOP,
                cond::ADDR,
                cond::ACK,
                cond::WRITE,
                cond::READ
            ],
            [1, 2, 4, 8, 16, 32]
        );
        let m = TwiMsg::new(cond::READ | cond::ACK, 3, 0x7F);
        assert!(m.has(cond::READ));
        assert!(m.has(cond::READ | cond::ACK));
        assert!(!m.has(cond::WRITE));
        assert_eq!(m.to_string(), "ACK|READ addr 0x03 data 0x7f");
    }
}
