//! The master's temperature sensors (reference §9.1): ten DS18S20s on the OneWire bus
//! (D6), one per controller plus an ambient one, read into REGMASTER_TEMPAMBIENT and
//! REGMASTER_TEMP1..9.
//!
//! The firmware's OneWire driver only moves bits; this module decides:
//! - scratchpad bytes to half degrees to the raw register value ([`reading`],
//!   [`register_raw`]), in integers and exactly equal to the float mapping, and the
//!   scratchpad CRC ([`crc8`]);
//! - the choices of the ROM search that discovers the sensors at start-up
//!   ([`RomSearch`]);
//! - which discovered device is which sensor, by ROM byte 1 ([`Sensors`]), and the
//!   polling order: read sensor i, start a conversion on sensor i + 1 ([`Poller`]).
//!
//! # Defined where the original was not
//! - **A missing sensor** raises type 10 (slave 0, motor 0) as in the original, but then
//!   reads nothing (the original read from an undefined index). Its register keeps the
//!   value it had: 0.0 °C (raw 0x2aaa) if it was never read. That is the value the
//!   original shows for every sensor it never reads (ids ≥ D), so a PC program sees one
//!   rule for "no reading", always inside the register's −20..100 range; the alarm is the
//!   exception (EXCEPTIONDATA 0x000a), not a made-up temperature.
//! - **No sensors at all** (D = 0, undefined in the original): every tick raises type 10
//!   for the ambient sensor and reads nothing.
//! - **A bad scratchpad CRC** (the original checked none) is no reading: the register
//!   goes to 0.0 °C (raw 0x2aaa) and its REGMASTER_TEMPSREAD bit is cleared
//!   ([`super::local::LocalRegisters::set_temperature`]), never a stale value.
//! - **The first reading**: the firmware starts a conversion on sensor 0 right after the
//!   discovery ([`Poller::first_conversion`]), so sensor 0's first reading, 5 s later, is a
//!   measurement and not the sensor's power-on value (85 °C).

mod convert;
mod poll;
mod search;

pub use convert::{crc8, half_degrees, reading, register_raw, ReadingError};
pub use poll::{Plan, Poller, Sensors, Tick};
pub use search::{RomSearch, SearchError};

/// A OneWire ROM id: family code, six serial bytes (byte 1 first), CRC8.
pub type Rom = [u8; 8];

/// Number of temperature sensors: ambient, then one per controller 1..9.
pub const SENSORS: usize = 10;

/// Family code of the DS18S20 (and DS1820). The original checked no family code; nor
/// does this module, but the emulated sensors carry it.
pub const FAMILY_DS18S20: u8 = 0x10;

/// ROM byte 1 (the first serial byte) that identifies each sensor: index 0 is the
/// ambient sensor (REGMASTER_TEMPAMBIENT), index n the sensor of controller n
/// (REGMASTER_TEMPn).
pub const SENSOR_ROM_BYTE1: [u8; SENSORS] =
    [0x9c, 0x20, 0x51, 0xa8, 0x89, 0x2f, 0xb1, 0xb5, 0x6f, 0x9e];

crate::flash_table! {
    /// [`SENSOR_ROM_BYTE1`] as the firmware reads it, kept in flash on the AVR.
    pub static SENSOR_ROM_BYTE1_FLASH: [u8; SENSORS] = SENSOR_ROM_BYTE1;
}

/// Length of a DS18S20 scratchpad, CRC included.
pub const SCRATCHPAD_LEN: usize = 9;

/// DS18S20 function and ROM commands the master uses.
pub mod command {
    /// SEARCH ROM: discover the devices on the bus.
    pub const SEARCH_ROM: u8 = 0xf0;
    /// MATCH ROM: address one device by its ROM.
    pub const MATCH_ROM: u8 = 0x55;
    /// SKIP ROM: address every device at once.
    pub const SKIP_ROM: u8 = 0xcc;
    /// CONVERT T: start a temperature conversion (750 ms at most).
    pub const CONVERT_T: u8 = 0x44;
    /// READ SCRATCHPAD: read the 9-byte scratchpad, temperature first.
    pub const READ_SCRATCHPAD: u8 = 0xbe;
}
