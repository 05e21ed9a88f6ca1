//! The register tables of every board, generated from `registers.def`.
//!
//! Each board kind has one table, indexed by register id. Host code uses the full
//! [`Register`] entries (names, units, docs); firmware that only needs sizes,
//! writability and ranges uses the compact accessors ([`BoardKind::size_of`],
//! [`BoardKind::shape`]), which read small byte tables and let the linker drop the
//! names.

mod board;

pub use board::BoardKind;

/// A mapping range: values in `min..=max` travel as `0..=F` (see [`crate::mapping`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Range {
    /// Value that maps to raw 0.
    pub min: f32,
    /// Value that maps to raw F (65534 or 254).
    pub max: f32,
}

/// One register of a board's table.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Register {
    /// Register id; equals its index in the table.
    pub id: u8,
    /// Symbol, e.g. `REGDS_DRIVE_REQSPEED`.
    pub name: &'static str,
    /// Size in bytes on the wire: 1 or 2.
    pub size: u8,
    /// Whether the master forwards writes to it.
    pub writable: bool,
    /// Mapping range, or `None` for an unmapped (raw integer) register.
    pub range: Option<Range>,
    /// Unit, empty when it has none.
    pub unit: &'static str,
    /// One-line meaning.
    pub doc: &'static str,
}

/// What the codec and the mapping need of a register, without its names.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Shape {
    /// Size in bytes: 1 or 2.
    pub size: u8,
    /// Whether the master forwards writes to it.
    pub writable: bool,
    /// Mapping range, or `None` when unmapped.
    pub range: Option<Range>,
}

impl Register {
    /// The register's size, writability and range.
    pub const fn shape(&self) -> Shape {
        Shape {
            size: self.size,
            writable: self.writable,
            range: self.range,
        }
    }

    /// The original firmware's flag byte: bits 0-5 the size, bit 6 (0x40) writable.
    pub const fn flag_byte(&self) -> u8 {
        self.size | if self.writable { FLAG_WRITABLE } else { 0 }
    }

    /// The symbol without its prefix (`REGDS_DRIVE_REQSPEED` gives `DRIVE_REQSPEED`).
    pub fn short_name(&self) -> &'static str {
        match self.name.split_once('_') {
            Some((_, rest)) => rest,
            None => self.name,
        }
    }
}

/// Bit of a flag byte that marks a writable register.
pub const FLAG_WRITABLE: u8 = 0x40;
/// Bits of a flag byte that hold the size.
pub const FLAG_SIZE_MASK: u8 = 0x3f;

/// The generated tables: for each block `B`, `B` (full table), `B_FLAGS` and
/// `B_RANGE_INDEX`; and `RANGES`, `NO_RANGE`. COMMON's compact tables are not used
/// (no device has the common block alone), hence the `dead_code` allowance.
#[allow(dead_code)]
mod tables {
    use super::{Range, Register};
    include!(concat!(env!("OUT_DIR"), "/register_tables.rs"));
}

pub use tables::{COMMON, DS, LL, MASTER};
/// The flag tables as the AVR keeps them in flash (for firmware that reads them there).
pub use tables::{DS_FLAGS_FLASH, LL_FLAGS_FLASH, MASTER_FLAGS_FLASH};

/// One constant per register symbol, holding its id (generated from `registers.def`).
pub mod id {
    include!(concat!(env!("OUT_DIR"), "/register_ids.rs"));
}
