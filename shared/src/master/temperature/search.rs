//! The decisions of the OneWire ROM search (command 0xf0).
//!
//! In one pass the master reads, for each of the 64 ROM bits (LSB of byte 0 first), the
//! wired-AND of every taking-part device's bit and then of its complement, and writes the
//! direction it takes; devices whose bit differs drop out. Where both values occur (both
//! reads 0, a discrepancy) the search takes 0 the first time, and each later pass takes 1
//! at the last discrepancy where it took 0 before, so successive passes enumerate every
//! device in ascending order of their ROMs read as 64-bit numbers LSB first.

use super::convert::crc8;
use super::Rom;

/// Why a search pass found no device.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum SearchError {
    /// A bit and its complement both read 1: no device took part (none present, or one
    /// left the bus during the pass).
    NoDevice,
    /// The ROM the pass assembled has a bad CRC byte (a disturbed pass).
    BadCrc,
    /// Every device has already been found; start again with [`RomSearch::new`].
    Finished,
}

/// State of a ROM search across passes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RomSearch {
    /// The ROM of the current (or last) pass.
    rom: Rom,
    /// Bit index of the last discrepancy where the previous pass took 0.
    last_zero: Option<u8>,
    /// Bit index of the last discrepancy where this pass took 0.
    pass_zero: Option<u8>,
    /// The previous pass found the last device.
    finished: bool,
}

impl Default for RomSearch {
    fn default() -> Self {
        Self::new()
    }
}

impl RomSearch {
    /// A new search: its first pass finds the device with the lowest ROM.
    pub const fn new() -> Self {
        RomSearch {
            rom: [0; 8],
            last_zero: None,
            pass_zero: None,
            finished: false,
        }
    }

    /// Whether every device has been found.
    pub const fn finished(&self) -> bool {
        self.finished
    }

    /// Bit `index` (0..64) of the pass: `bit` and `complement` are the two values read.
    /// Returns the direction to write (true = 1).
    pub fn step(&mut self, index: u8, bit: bool, complement: bool) -> Result<bool, SearchError> {
        if self.finished {
            return Err(SearchError::Finished);
        }
        if index == 0 {
            self.pass_zero = None;
        }
        // The ROM byte and the bit within it, found once for the read and the write.
        let (at, mask) = (usize::from(index / 8) % 8, 1u8 << (index % 8));
        let direction = match (bit, complement) {
            (true, true) => return Err(SearchError::NoDevice),
            (b, c) if b != c => b,
            _ => {
                // A discrepancy: both values occur among the devices still taking part.
                let take = match self.last_zero {
                    Some(last) if index < last => self.rom[at] & mask != 0,
                    Some(last) if index == last => true,
                    _ => false,
                };
                if !take {
                    self.pass_zero = Some(index);
                }
                take
            }
        };
        let byte = &mut self.rom[at];
        *byte = (*byte & !mask) | if direction { mask } else { 0 };
        Ok(direction)
    }

    /// Ends a pass after bit 63: returns the ROM found. After the last device,
    /// [`RomSearch::finished`] is true.
    pub fn finish(&mut self) -> Result<Rom, SearchError> {
        if self.finished {
            return Err(SearchError::Finished);
        }
        self.last_zero = self.pass_zero;
        self.finished = self.last_zero.is_none();
        if crc8(&self.rom) != 0 {
            // A disturbed pass: stop rather than walk a tree that may not exist.
            self.finished = true;
            return Err(SearchError::BadCrc);
        }
        Ok(self.rom)
    }
}
