//! The I²C (TWI) link of an emulated chip, seen from Rust.
//!
//! simavr models the ATmega328P's TWI as a state machine that talks to the outside world through
//! two IRQs: the chip raises its *output* IRQ with a message (START, address, data, ACK, STOP
//! bits plus an address and a data byte), and reads messages raised on its *input* IRQ. Nothing in
//! simavr connects two chips; [`crate::bus::Bus`] does, using the pieces in this module:
//! - [`TwiMsg`] and [`cond`]: the message word, decoded;
//! - [`I2cTarget`]: a slave written in Rust (a fake sensor, a recording model) that a real master
//!   firmware can talk to; [`RegisterTarget`] is a ready-made one;
//! - [`TwiError`]: why a transfer failed.
//!
//! # What simavr does, and what the bus makes of it
//! - **A master chip expects its peer to answer inside the IRQ.** When it sends an address or a
//!   data byte, it decides ACK or NACK the moment the output IRQ returns. The bus therefore runs
//!   the addressed slave chip, inside that call, until its firmware has handled the event (the
//!   emulated counterpart of clock stretching), with a bounded wait: a slave that never answers
//!   yields a NACK (for a master chip) or [`TwiError::Timeout`] (for the Rust master), never a
//!   hang of the emulator.
//! - **A slave that keeps TWINT set holds SCL low**, as the real TWI does: after that timeout
//!   nothing moves on the bus until its firmware clears TWINT, switches the TWI off or the chip
//!   resets. A master chip's TWINT does not rise meanwhile (the step it started never
//!   completes, so its firmware's own bounded wait must give it up), and the Rust master gets
//!   [`TwiError::BusHeld`] after its bounded wait. STOP is not held: simavr completes it at
//!   once.
//! - **ACK is decided as on real hardware**: a slave chip acknowledges its address when TWEN and
//!   TWEA are set and TWAR matches, and a data byte when TWEA was set before the byte arrived.
//!   (simavr still shows the slave firmware status 0x80 for a byte it NACKs, not 0x88.)
//! - **A slave's byte to send** is whatever its firmware left in TWDR when it released the bus.
//! - **Transfer time** of a master chip is simavr's: one bit takes `16 + 2·TWBR·4^TWPS` CPU
//!   cycles (the datasheet's SCL formula), and a data byte or SLA+R takes 9 bits (byte + ACK):
//!   90 µs at 100 kHz (TWBR 72, prescaler 1), 22.5 µs at 400 kHz (TWBR 12). Quirks: START,
//!   repeated START, STOP and SLA+W complete in zero time, so a write `[addr+W, a, b]` costs two
//!   byte times, not three.
//! - **STOP after a master read.** simavr shows a slave the STOP that ends a master READ as status
//!   0xA0 (STOP received while addressed), which real TWI does not do. The bus does not pass that
//!   STOP on by default, matching the real chip;
//!   [`Bus::set_simavr_stop_after_read`](crate::bus::Bus::set_simavr_stop_after_read) passes it
//!   on. Slave firmware must treat such an "empty write" (0xA0 with no byte received) as nothing.
//! - **Repeated START** while a slave chip is addressed as a receiver reaches it as 0xA0, as on
//!   the real chip (simavr alone would not show it).
//! - Not modelled: general call (address 0), 10-bit addresses, address masks (TWAMR), arbitration
//!   between two master chips (the later one is refused with a NACK, logged as a collision).

#[path = "twi_chip.rs"]
pub(crate) mod chip;
#[path = "twi_model.rs"]
mod model;
#[path = "twi_msg.rs"]
mod msg;
#[path = "twi_port.rs"]
pub(crate) mod port;

use std::any::Any;

/// The ATmega328P's TWI registers (data-space addresses) and the TWCR bits the bus reads.
mod reg {
    pub const TWAR: u16 = 0xBA;
    pub const TWCR: u16 = 0xBC;
    pub const TWEN: u8 = 1 << 2;
    pub const TWEA: u8 = 1 << 6;
    pub const TWINT: u8 = 1 << 7;
}

pub use model::{RegisterTarget, TargetEvent};
pub use msg::{cond, TwiMsg};

/// A slave device written in Rust, put on the bus next to emulated chips.
///
/// Addresses are 7-bit. Each method is one bus event; the bus calls them in protocol order:
/// `start_write`/`start_read`, then `write`s or `read`s, then `stop` (a repeated START is a new
/// `start_*` without `stop`). A target that does not answer to an address returns `false` from
/// `start_*` and hears nothing more of that transaction.
pub trait I2cTarget: Any {
    /// The master addressed `addr` for writing; return true to acknowledge.
    fn start_write(&mut self, addr: u8) -> bool;
    /// The master sent a data byte; return true to acknowledge it.
    fn write(&mut self, byte: u8) -> bool;
    /// The master addressed `addr` for reading; return true to acknowledge.
    fn start_read(&mut self, addr: u8) -> bool;
    /// The master clocks in one byte; return it.
    fn read(&mut self) -> u8;
    /// The master ended the transaction with STOP.
    fn stop(&mut self);
}

/// Why an I²C transfer did not complete.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum TwiError {
    /// No device acknowledged the address: none listens there, it is cut off the bus, or its
    /// firmware has not enabled the TWI with TWEA yet.
    #[error(
        "no device acknowledged address {addr:#04x}; check the slave's address (EEPROM byte 0 \
         for the fixture slave), that its firmware has booted, and that the address is not cut"
    )]
    AddressNack {
        /// The 7-bit address.
        addr: u8,
    },
    /// The addressed device refused a data byte (TWEA clear, or it was cut off mid-transfer).
    #[error(
        "device {addr:#04x} did not acknowledge data byte {index}; the slave stopped accepting \
         data (TWEA clear) or was cut off the bus"
    )]
    DataNack {
        /// The 7-bit address.
        addr: u8,
        /// Index of the refused byte in the data written.
        index: usize,
    },
    /// A slave chip took the event but its firmware did not release the bus in time.
    #[error(
        "device {addr:#04x} did not answer within {waited_us} µs of emulated time; its firmware \
         is stuck with TWINT set or its CPU halted, and it holds SCL low until it lets go or \
         resets; if it is only slow, raise Bus::set_answer_timeout_us"
    )]
    Timeout {
        /// The 7-bit address.
        addr: u8,
        /// Emulated microseconds waited.
        waited_us: u64,
    },
    /// Another master kept the bus busy for longer than the bounded wait.
    #[error(
        "the bus stayed busy for {waited_us} µs of emulated time: another master's transaction \
         never ended with STOP; check that master's firmware"
    )]
    BusBusy {
        /// Emulated microseconds waited.
        waited_us: u64,
    },
    /// A slave chip held SCL low for longer than the bounded wait.
    #[error(
        "device {addr:#04x} held the bus (SCL low) for {waited_us} µs of emulated time: it \
         took a bus event and its firmware never cleared TWINT; the bus is free again once \
         it does, switches its TWI off or resets (e.g. by its watchdog)"
    )]
    BusHeld {
        /// The 7-bit address of the chip holding SCL.
        addr: u8,
        /// Emulated microseconds waited.
        waited_us: u64,
    },
    /// A transfer asked for no bytes where at least one is needed.
    #[error("a read must ask for at least one byte")]
    EmptyRead,
    /// The chip exposes no TWI to attach to.
    #[error("the emulated chip has no TWI peripheral to attach to; load an ATmega328P image")]
    NoTwi,
}

/// A target boxed on the bus, which can still be found again by its concrete type.
pub(crate) fn downcast_mut<T: I2cTarget>(target: &mut dyn I2cTarget) -> Option<&mut T> {
    (target as &mut dyn Any).downcast_mut::<T>()
}
