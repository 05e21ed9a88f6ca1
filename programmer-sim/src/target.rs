//! The programmed chip: an ATmega328P's flash, EEPROM, fuses, lock bits and signature.

use crate::error::MemError;

/// Flash size in bytes (32 KB).
pub const FLASH_SIZE: usize = 32 * 1024;
/// EEPROM size in bytes (1 KB).
pub const EEPROM_SIZE: usize = 1024;
/// Flash page size in bytes: the largest block one page command may write.
pub const FLASH_PAGE: usize = 128;
/// EEPROM page size in bytes.
pub const EEPROM_PAGE: usize = 4;
/// The ATmega328P's signature bytes.
pub const SIGNATURE: [u8; 3] = [0x1e, 0x95, 0x0f];
/// Value of an erased flash or EEPROM byte.
pub const ERASED: u8 = 0xff;

/// Which memory a page command addresses.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Memory {
    /// Program memory.
    Flash,
    /// Data EEPROM.
    Eeprom,
}

impl Memory {
    /// Name used in logs and output file names.
    pub fn name(self) -> &'static str {
        match self {
            Memory::Flash => "flash",
            Memory::Eeprom => "eeprom",
        }
    }
}

/// Fuse and lock bytes, as the chip would report them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Fuses {
    /// Low fuse: external full-swing crystal, slowest start-up (an Uno's 0xff).
    pub low: u8,
    /// High fuse: SPIEN programmed, EESAVE unprogrammed, 512-byte boot section (0xde).
    pub high: u8,
    /// Extended fuse: brown-out at 2.7 V (0xfd).
    pub extended: u8,
    /// Lock byte.
    pub lock: u8,
}

impl Default for Fuses {
    fn default() -> Self {
        Fuses {
            low: 0xff,
            high: 0xde,
            extended: 0xfd,
            lock: 0xff,
        }
    }
}

/// The chip's memories, all erased at start.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Target {
    flash: Vec<u8>,
    eeprom: Vec<u8>,
    /// Fuse and lock bytes.
    pub fuses: Fuses,
    /// Oscillator calibration byte.
    pub calibration: u8,
}

impl Default for Target {
    fn default() -> Self {
        Self::new(Fuses::default())
    }
}

impl Target {
    /// An erased chip with the given fuses.
    pub fn new(fuses: Fuses) -> Self {
        Target {
            flash: vec![ERASED; FLASH_SIZE],
            eeprom: vec![ERASED; EEPROM_SIZE],
            fuses,
            calibration: 0x9d,
        }
    }

    /// The whole flash image.
    pub fn flash(&self) -> &[u8] {
        &self.flash
    }

    /// The whole EEPROM image.
    pub fn eeprom(&self) -> &[u8] {
        &self.eeprom
    }

    fn mem(&self, memory: Memory) -> &[u8] {
        match memory {
            Memory::Flash => &self.flash,
            Memory::Eeprom => &self.eeprom,
        }
    }

    fn mem_mut(&mut self, memory: Memory) -> &mut [u8] {
        match memory {
            Memory::Flash => &mut self.flash,
            Memory::Eeprom => &mut self.eeprom,
        }
    }

    /// Erases the chip as a serial-programming chip erase does: flash, and EEPROM unless
    /// the EESAVE fuse (high fuse bit 3, active low) is programmed; the lock byte clears.
    pub fn chip_erase(&mut self) {
        self.flash.fill(ERASED);
        if self.fuses.high & 0x08 != 0 {
            self.eeprom.fill(ERASED);
        }
        self.fuses.lock = 0xff;
    }

    /// Writes `data` at byte address `addr` of `memory`.
    pub fn write(&mut self, memory: Memory, addr: usize, data: &[u8]) -> Result<(), MemError> {
        let range = checked_range(memory, self.mem(memory).len(), addr, data.len())?;
        self.mem_mut(memory)[range].copy_from_slice(data);
        Ok(())
    }

    /// Reads `len` bytes at byte address `addr` of `memory`.
    pub fn read(&self, memory: Memory, addr: usize, len: usize) -> Result<&[u8], MemError> {
        let range = checked_range(memory, self.mem(memory).len(), addr, len)?;
        Ok(&self.mem(memory)[range])
    }
}

fn checked_range(
    memory: Memory,
    size: usize,
    addr: usize,
    len: usize,
) -> Result<core::ops::Range<usize>, MemError> {
    match addr.checked_add(len) {
        Some(end) if end <= size => Ok(addr..end),
        _ => Err(MemError::OutOfRange {
            memory: memory.name(),
            addr,
            len,
            size,
        }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn starts_erased() {
        let t = Target::default();
        assert_eq!(t.flash().len(), 32768);
        assert_eq!(t.eeprom().len(), 1024);
        assert!(t.flash().iter().all(|&b| b == 0xff));
        assert!(t.eeprom().iter().all(|&b| b == 0xff));
    }

    #[test]
    fn write_then_read_round_trips() {
        let mut t = Target::default();
        t.write(Memory::Flash, 0x100, &[1, 2, 3]).unwrap();
        assert_eq!(
            t.read(Memory::Flash, 0xff, 5).unwrap(),
            &[0xff, 1, 2, 3, 0xff]
        );
        t.write(Memory::Eeprom, 0, &[7]).unwrap();
        assert_eq!(t.eeprom()[0], 7);
        assert_eq!(t.flash()[0], 0xff);
    }

    #[test]
    fn out_of_range_is_refused() {
        let mut t = Target::default();
        assert!(t.write(Memory::Eeprom, 1022, &[0; 4]).is_err());
        assert!(t.read(Memory::Flash, 32767, 2).is_err());
        assert!(t.read(Memory::Flash, usize::MAX, 2).is_err());
        assert!(t.read(Memory::Flash, 32766, 2).is_ok());
    }

    #[test]
    fn chip_erase_honours_eesave() {
        let mut t = Target::default();
        t.write(Memory::Flash, 0, &[0]).unwrap();
        t.write(Memory::Eeprom, 0, &[0]).unwrap();
        t.chip_erase();
        assert_eq!(t.flash()[0], 0xff);
        assert_eq!(t.eeprom()[0], 0xff);

        let mut t = Target::new(Fuses {
            high: 0xd6,
            ..Fuses::default()
        });
        t.write(Memory::Eeprom, 0, &[5]).unwrap();
        t.chip_erase();
        assert_eq!(t.eeprom()[0], 5);
    }
}
