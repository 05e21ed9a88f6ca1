//! The TWI (I2C) bus master, polled, with every wait bounded: a slave that stops
//! answering gives an error within about a millisecond instead of hanging the master.
//!
//! TWCR holds the executor's TWIE beside the driver's bits, so it is written only
//! through `executor::hw` (which also never writes TWINT back by accident).

use avr_device::atmega328p::TWI;
use executor::hw::{self, DriverReg};

const TWINT: u8 = 1 << 7;
const TWEA: u8 = 1 << 6;
const TWSTA: u8 = 1 << 5;
const TWSTO: u8 = 1 << 4;
const TWEN: u8 = 1 << 2;

/// TWSR status codes (prescaler bits masked off) the master expects.
mod status {
    pub const START: u8 = 0x08;
    pub const REPEATED_START: u8 = 0x10;
    pub const SLA_W_ACK: u8 = 0x18;
    pub const DATA_W_ACK: u8 = 0x28;
    pub const SLA_R_ACK: u8 = 0x40;
    pub const DATA_R_ACK: u8 = 0x50;
    pub const DATA_R_NACK: u8 = 0x58;
}

/// Polls of TWINT before a step is given up: about 0.9 ms at 16 MHz, ten byte times at
/// 100 kHz, so only a slave that stopped answering (or holds the clock) runs out.
const SPIN_LIMIT: u16 = 2_000;

/// Why a transfer failed.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum TwiError {
    /// Nobody acknowledged the address: the slave is absent, unpowered or not at that address.
    AddressNack,
    /// The slave refused a data byte.
    DataNack,
    /// A step did not complete in time: the bus is stuck or a slave holds the clock.
    Timeout,
    /// The bus reported a state the transfer did not expect (e.g. lost arbitration).
    Bus(u8),
}

/// The bus master.
pub struct TwiMaster {
    twi: TWI,
}

impl TwiMaster {
    /// Enables the TWI as a master at `khz` (100 or 400), prescaler 1, with the internal
    /// pull-ups left off (the master's shield has external pull-ups).
    pub fn new(twi: TWI, khz: u16) -> Self {
        let twbr = ((crate::F_CPU / 1000 / u32::from(khz)).saturating_sub(16) / 2) as u8;
        // SAFETY: any TWBR value is a valid bit rate; TWSR's prescaler bits 0 = 1.
        twi.twbr().write(|w| unsafe { w.bits(twbr) });
        twi.twsr().write(|w| unsafe { w.bits(0) });
        hw::write(DriverReg::Twcr, TWEN);
        TwiMaster { twi }
    }

    /// Writes `bytes` to the slave at `addr` in one transaction.
    pub fn write(&mut self, addr: u8, bytes: &[u8]) -> Result<(), TwiError> {
        let result = self.write_inner(addr, bytes);
        self.stop();
        result
    }

    fn write_inner(&mut self, addr: u8, bytes: &[u8]) -> Result<(), TwiError> {
        self.start(status::START)?;
        self.send(addr << 1, status::SLA_W_ACK, TwiError::AddressNack)?;
        for &b in bytes {
            self.send(b, status::DATA_W_ACK, TwiError::DataNack)?;
        }
        Ok(())
    }

    /// Reads `n` bytes starting at register `first` of the slave at `addr`: the register
    /// pointer is written, then a repeated START reads the run. Each byte goes to `sink`
    /// as soon as it arrives, so a caller can forward it while the rest is on the bus.
    pub fn read(
        &mut self,
        addr: u8,
        first: u8,
        n: u8,
        sink: &mut dyn FnMut(u8),
    ) -> Result<(), TwiError> {
        let result = self.read_inner(addr, first, n, sink);
        self.stop();
        result
    }

    fn read_inner(
        &mut self,
        addr: u8,
        first: u8,
        n: u8,
        sink: &mut dyn FnMut(u8),
    ) -> Result<(), TwiError> {
        self.write_inner(addr, &[first])?;
        self.start(status::REPEATED_START)?;
        self.send((addr << 1) | 1, status::SLA_R_ACK, TwiError::AddressNack)?;
        for i in 0..n {
            let last = i + 1 == n;
            let (ack, expect) = if last {
                (0, status::DATA_R_NACK)
            } else {
                (TWEA, status::DATA_R_ACK)
            };
            hw::write(DriverReg::Twcr, TWINT | TWEN | ack);
            self.wait(expect)?;
            sink(self.twi.twdr().read().bits());
        }
        Ok(())
    }

    fn start(&mut self, expect: u8) -> Result<(), TwiError> {
        hw::write(DriverReg::Twcr, TWINT | TWSTA | TWEN);
        self.wait(expect)
    }

    fn send(&mut self, byte: u8, expect: u8, nack: TwiError) -> Result<(), TwiError> {
        // SAFETY: TWDR takes any byte while TWINT is set.
        self.twi.twdr().write(|w| unsafe { w.bits(byte) });
        hw::write(DriverReg::Twcr, TWINT | TWEN);
        match self.wait(expect) {
            Err(TwiError::Bus(_)) if expect != status::DATA_R_ACK => Err(nack),
            other => other,
        }
    }

    /// Waits for TWINT and checks the status.
    fn wait(&mut self, expect: u8) -> Result<(), TwiError> {
        let mut spins = 0u16;
        while hw::read(DriverReg::Twcr) & TWINT == 0 {
            spins += 1;
            if spins >= SPIN_LIMIT {
                return Err(TwiError::Timeout);
            }
        }
        let got = self.twi.twsr().read().bits() & 0xf8;
        if got == expect {
            Ok(())
        } else {
            Err(TwiError::Bus(got))
        }
    }

    /// Sends STOP and waits (bounded) for it to go out; after a timeout the TWI is
    /// disabled and re-enabled, which releases the lines.
    fn stop(&mut self) {
        hw::write(DriverReg::Twcr, TWINT | TWSTO | TWEN);
        let mut spins = 0u16;
        while hw::read(DriverReg::Twcr) & TWSTO != 0 {
            spins += 1;
            if spins >= SPIN_LIMIT {
                hw::write(DriverReg::Twcr, 0);
                hw::write(DriverReg::Twcr, TWEN);
                return;
            }
        }
    }
}
