//! Test firmware: a register-file I2C slave on the TWI, at the 7-bit address held in EEPROM byte 0.
//!
//! Demonstrates the slave side of the emulated I2C bus (`harness::bus`). The slave keeps 16 byte
//! registers (ids 0x00..=0x0f) and one read-only counter (id 0x10):
//! - a write `[id, d0, d1, …]` selects register `id` and stores `d0, d1, …` from there on;
//! - a read returns bytes from the selected register on; the pointer advances with every byte and
//!   wraps after id 0x10;
//! - an id above 0x10 selects register 0;
//! - id 0x10 reads the number of completed writes that carried at least one byte (mod 256).
//!
//! A STOP (or repeated START) that ends an empty write is nothing: the emulator shows a slave the
//! STOP that ends a master READ as status 0xA0 as well, so such an "empty write" must not count.
//! An erased or out-of-range EEPROM byte 0 (0, or 0x78 and above) selects address 0x08.
//!
//! The TWI is polled (no interrupt), so there is no state shared with an ISR.

#![no_std]
#![no_main]

use avr_device::atmega328p::{EEPROM, TWI};

/// Address used when EEPROM byte 0 is not a usable 7-bit address.
const DEFAULT_ADDR: u8 = 0x08;
/// Number of read/write byte registers.
const REGS: usize = 16;
/// Register id of the read-only write counter.
const REG_WRITES: usize = 0x10;

/// TWI status codes (TWSR with the prescaler bits masked off) this slave reacts to.
mod status {
    /// Own SLA+W received, ACK returned (also after a lost arbitration / general call).
    pub const SR_ADDR: [u8; 4] = [0x60, 0x68, 0x70, 0x78];
    /// Data byte received while addressed (own address or general call), ACK returned.
    pub const SR_DATA: [u8; 2] = [0x80, 0x90];
    /// STOP or repeated START while addressed as a receiver.
    pub const SR_STOP: u8 = 0xA0;
    /// Own SLA+R received or data byte sent and ACKed: load the next byte.
    pub const ST_NEXT: [u8; 3] = [0xA8, 0xB0, 0xB8];
    /// Illegal START/STOP seen on the bus.
    pub const BUS_ERROR: u8 = 0x00;
}

/// The register file and the write in progress.
struct RegisterFile {
    regs: [u8; REGS],
    pointer: usize,
    received: usize,
    writes: u8,
}

impl RegisterFile {
    const fn new() -> Self {
        RegisterFile {
            regs: [0; REGS],
            pointer: 0,
            received: 0,
            writes: 0,
        }
    }

    /// A new write starts.
    fn begin_write(&mut self) {
        self.received = 0;
    }

    /// One byte of a write: the first selects the register, the rest are stored.
    fn receive(&mut self, byte: u8) {
        if self.received == 0 {
            let id = usize::from(byte);
            self.pointer = if id <= REG_WRITES { id } else { 0 };
        } else {
            if let Some(reg) = self.regs.get_mut(self.pointer) {
                *reg = byte;
            }
            self.advance();
        }
        self.received += 1;
    }

    /// STOP or repeated START: a write that carried no byte is nothing.
    fn end_write(&mut self) {
        if self.received > 0 {
            self.writes = self.writes.wrapping_add(1);
        }
        self.received = 0;
    }

    /// The byte to send for the next read slot.
    fn transmit(&mut self) -> u8 {
        let byte = match self.regs.get(self.pointer) {
            Some(reg) => *reg,
            None => self.writes,
        };
        self.advance();
        byte
    }

    fn advance(&mut self) {
        self.pointer = if self.pointer >= REG_WRITES {
            0
        } else {
            self.pointer + 1
        };
    }
}

/// Reads EEPROM byte 0 (the bus address chosen by the test).
fn eeprom_byte0(eeprom: &EEPROM) -> u8 {
    while eeprom.eecr().read().eepe().bit_is_set() {}
    eeprom.eear().write(|w| w.set(0));
    eeprom.eecr().write(|w| w.eere().set_bit());
    eeprom.eedr().read().bits()
}

/// Clears TWINT and keeps the slave enabled and acknowledging.
fn release(twi: &TWI) {
    twi.twcr()
        .write(|w| w.twint().set_bit().twea().set_bit().twen().set_bit());
}

#[avr_device::entry]
fn main() -> ! {
    let dp = firmware_examples::peripherals();
    let twi = dp.TWI;
    let stored = eeprom_byte0(&dp.EEPROM);
    let addr = if (1..0x78).contains(&stored) {
        stored
    } else {
        DEFAULT_ADDR
    };
    twi.twar().write(|w| w.twa().set(addr));
    release(&twi);

    let mut file = RegisterFile::new();
    loop {
        if twi.twcr().read().twint().bit_is_clear() {
            continue;
        }
        let code = twi.twsr().read().bits() & 0xF8;
        if status::SR_ADDR.contains(&code) {
            file.begin_write();
        } else if status::SR_DATA.contains(&code) {
            file.receive(twi.twdr().read().bits());
        } else if code == status::SR_STOP {
            file.end_write();
        } else if status::ST_NEXT.contains(&code) {
            let byte = file.transmit();
            twi.twdr().write(|w| w.set(byte));
        } else if code == status::BUS_ERROR {
            // Release the bus after an illegal condition, as the datasheet asks.
            twi.twcr().write(|w| {
                w.twint()
                    .set_bit()
                    .twsto()
                    .set_bit()
                    .twea()
                    .set_bit()
                    .twen()
                    .set_bit()
            });
            continue;
        }
        release(&twi);
    }
}

firmware_examples::spin_on_panic!();
