//! EEPROM, data space and ELF symbols of an emulated chip.

use simavr_ffi as ffi;

use crate::avr::ioctl_def;
use crate::elf::DATA_OFFSET;
use crate::Avr;

/// EEPROM size of the ATmega328P.
pub const EEPROM_SIZE: usize = 1024;
/// Data-space size (registers, I/O and 2 KiB of SRAM).
const DATA_SIZE: u16 = 0x900;

impl Avr {
    /// The EEPROM contents as simavr holds them (`EEPROM_SIZE` bytes), or None.
    fn eeprom_mem(&self) -> Option<*mut u8> {
        let mut desc = ffi::avr_eeprom_desc_t {
            ee: std::ptr::null_mut(),
            offset: 0,
            size: EEPROM_SIZE as u32,
        };
        // SAFETY: the live core's EEPROM ioctl with a NULL `ee` stores a pointer to its
        // own EEPROM_SIZE-byte array in `desc.ee` and touches nothing else.
        let rc = unsafe {
            ffi::avr_ioctl(
                self.raw.as_ptr(),
                ioctl_def(b'e', b'e', b'g', b'p'),
                std::ptr::from_mut(&mut desc).cast(),
            )
        };
        (rc == 0 && !desc.ee.is_null()).then_some(desc.ee)
    }

    /// Writes EEPROM bytes from `addr` on (before or after boot); bytes past the
    /// end of the 1 KiB EEPROM are ignored.
    pub fn eeprom_write(&mut self, addr: u16, bytes: &[u8]) {
        let Some(mem) = self.eeprom_mem() else {
            return;
        };
        for (i, &b) in bytes.iter().enumerate() {
            let a = usize::from(addr) + i;
            if a < EEPROM_SIZE {
                // SAFETY: `mem` points to EEPROM_SIZE bytes and `a` is in range.
                unsafe { *mem.add(a) = b };
            }
        }
    }

    /// Reads `len` EEPROM bytes from `addr` on; addresses past the end read 0xFF.
    pub fn eeprom_read(&self, addr: u16, len: usize) -> Vec<u8> {
        let mem = self.eeprom_mem();
        (0..len)
            .map(|i| {
                let a = usize::from(addr) + i;
                match mem {
                    // SAFETY: `m` points to EEPROM_SIZE bytes and `a` is in range.
                    Some(m) if a < EEPROM_SIZE => unsafe { *m.add(a) },
                    _ => 0xFF,
                }
            })
            .collect()
    }

    /// One byte of data space (registers, I/O registers, SRAM); 0 past its end.
    pub fn read_data(&self, addr: u16) -> u8 {
        if addr >= DATA_SIZE {
            return 0;
        }
        // SAFETY: the live core's data array spans DATA_SIZE bytes; `addr` is in range.
        unsafe { *(*self.raw.as_ptr()).data.add(usize::from(addr)) }
    }

    /// Writes one byte of data space directly (no peripheral side effects).
    pub fn write_data(&mut self, addr: u16, value: u8) {
        if addr < DATA_SIZE {
            // SAFETY: as in `read_data`.
            unsafe { *(*self.raw.as_ptr()).data.add(usize::from(addr)) = value };
        }
    }

    /// The first ELF symbol whose name contains `part`, with its address as
    /// [`Avr::symbol`] gives it: for Rust's mangled names, whose hash changes with the
    /// build (e.g. `panic_bounds_check`).
    pub fn symbol_containing(&self, part: &str) -> Option<(String, u32)> {
        let (name, _) = self.symbols.iter().find(|(n, _)| n.contains(part))?;
        Some((name.clone(), self.symbol(name)?))
    }

    /// The address of an ELF symbol. Data-space symbols come without the linker's
    /// 0x800000 offset, so the value can go straight to [`Avr::read_data`].
    pub fn symbol(&self, name: &str) -> Option<u32> {
        self.symbols.iter().find(|(n, _)| n == name).map(|&(_, v)| {
            if v >= DATA_OFFSET {
                v - DATA_OFFSET
            } else {
                v
            }
        })
    }
}
