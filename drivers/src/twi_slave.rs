//! The TWI as an interrupt-driven I2C slave: each TWINT is one bus event, classified
//! from TWSR; the task answers it and releases the bus with [`TwiSlave::release`].
//!
//! TWCR holds the executor's TWIE beside the driver's bits, so it is written only
//! through `executor::hw`.

use avr_device::atmega328p::TWI;
use executor::hw::{self, DriverReg};

const TWINT: u8 = 1 << 7;
const TWEA: u8 = 1 << 6;
const TWSTO: u8 = 1 << 4;
const TWEN: u8 = 1 << 2;

/// What one TWINT means for a slave.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Event {
    /// Own SLA+W (or a general call) acknowledged: a write starts.
    WriteStart,
    /// A data byte of a write arrived.
    Data(u8),
    /// STOP or repeated START while addressed as a receiver.
    Stop,
    /// Own SLA+R acknowledged: load the first byte.
    ReadStart,
    /// The master acknowledged the byte sent: load the next one.
    ReadMore,
    /// The master ended the read (NACK), or took the last byte.
    ReadEnd,
    /// An illegal START/STOP: the bus must be recovered.
    BusError,
    /// Any other status (arbitration cases of a master, never seen here).
    Other,
}

/// The TWI in slave mode.
pub struct TwiSlave {
    twi: TWI,
}

impl TwiSlave {
    /// Listens on 7-bit address `addr` (general calls ignored), acknowledging.
    pub fn new(twi: TWI, addr: u8) -> TwiSlave {
        // SAFETY: TWAR takes any address; bit 0 (TWGCE) = 0 ignores general calls.
        twi.twar().write(|w| unsafe { w.bits(addr << 1) });
        hw::write(DriverReg::Twcr, TWEA | TWEN);
        TwiSlave { twi }
    }

    /// The TWI left off, as at power-up: it never raises TWINT, so its task never runs
    /// (a slave without a valid address stays off the bus).
    pub fn off(twi: TWI) -> TwiSlave {
        TwiSlave { twi }
    }

    /// The event behind the current TWINT.
    #[inline]
    pub fn event(&self) -> Event {
        let status = self.twi.twsr().read().bits() & 0xf8;
        // The status codes in descending order, by range: the same event as the table of
        // codes for each of the 32 values (checked at compile time below).
        match kind(status) {
            Kind::WriteStart => Event::WriteStart,
            Kind::Data => Event::Data(self.twi.twdr().read().bits()),
            Kind::Stop => Event::Stop,
            Kind::ReadStart => Event::ReadStart,
            Kind::ReadMore => Event::ReadMore,
            Kind::ReadEnd => Event::ReadEnd,
            Kind::BusError => Event::BusError,
            Kind::Other => Event::Other,
        }
    }

    /// Loads the byte the master reads next.
    #[inline]
    pub fn send(&mut self, byte: u8) {
        // SAFETY: TWDR takes any byte while TWINT is set.
        self.twi.twdr().write(|w| unsafe { w.bits(byte) });
    }

    /// Clears TWINT and goes on acknowledging: the bus moves on.
    #[inline]
    pub fn release(&mut self) {
        hw::write(DriverReg::Twcr, TWINT | TWEA | TWEN);
    }

    /// Recovers from a bus error: TWSTO in slave mode releases the lines and returns the
    /// TWI to the unaddressed state.
    #[inline]
    pub fn recover(&mut self) {
        hw::write(DriverReg::Twcr, TWINT | TWSTO | TWEA | TWEN);
    }
}

/// Data-space address of TWCR.
const TWCR: *mut u8 = 0xbc as *mut u8;

/// Switches the TWI off (TWEN clear), ending any transfer and releasing SDA and SCL: a
/// master addressing the board then gets no acknowledge. For the panic path, where a TWI
/// left on would acknowledge its address and then hold SCL low, and the whole bus with
/// it, until the watchdog resets the board.
///
/// # Safety
/// Call only where no other code will touch the TWI again (interrupts off for good).
#[inline(always)]
pub unsafe fn force_off() {
    // SAFETY: the caller guarantees no concurrent TWI user; TWCR = 0 is the power-up value.
    unsafe { core::ptr::write_volatile(TWCR, 0) };
}

/// An [`Event`] without its data byte.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Kind {
    WriteStart,
    Data,
    Stop,
    ReadStart,
    ReadMore,
    ReadEnd,
    BusError,
    Other,
}

/// The event kind of a TWSR status (prescaler bits cleared), by range from the top (the
/// frequent read-more and data codes come early): a few compares where a table of codes
/// takes a tree of them.
#[inline(always)]
const fn kind(status: u8) -> Kind {
    if status >= 0xc0 {
        if status < 0xd0 {
            Kind::ReadEnd
        } else {
            Kind::Other
        }
    } else if status == 0xb8 {
        Kind::ReadMore
    } else if status >= 0xa8 {
        Kind::ReadStart
    } else if status == 0xa0 {
        Kind::Stop
    } else if status >= 0x80 {
        Kind::Data
    } else if status >= 0x60 {
        Kind::WriteStart
    } else if status == 0 {
        Kind::BusError
    } else {
        Kind::Other
    }
}

/// The event kind of each status code as the data sheet's slave tables give it.
const fn kind_by_code(status: u8) -> Kind {
    match status {
        0x60 | 0x68 | 0x70 | 0x78 => Kind::WriteStart,
        0x80 | 0x88 | 0x90 | 0x98 => Kind::Data,
        0xa0 => Kind::Stop,
        0xa8 | 0xb0 => Kind::ReadStart,
        0xb8 => Kind::ReadMore,
        0xc0 | 0xc8 => Kind::ReadEnd,
        0x00 => Kind::BusError,
        _ => Kind::Other,
    }
}

// Every status value (multiples of 8) gets the same kind by range as by code.
const _: () = {
    let mut status: u16 = 0;
    while status < 0x100 {
        assert!(kind(status as u8) as u8 == kind_by_code(status as u8) as u8);
        status += 8;
    }
};
