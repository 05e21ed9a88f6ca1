//! The four-byte serial-programming instructions that `Cmnd_STK_UNIVERSAL` passes through.
//!
//! Only the instructions a programmer needs around a page-mode upload are modelled: chip
//! erase, signature, calibration, fuse and lock reads and writes, byte reads of flash and
//! EEPROM, EEPROM byte writes and the busy poll. Anything else answers 0x00 and is
//! reported as [`IspOutcome::Ignored`].

use crate::target::{Memory, Target};

/// What an instruction did.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum IspOutcome {
    /// Read-only instruction; the chip answered the byte.
    Read,
    /// The chip was erased.
    ChipErase,
    /// A fuse, lock or EEPROM byte changed.
    Wrote,
    /// The instruction is not modelled; it answered 0x00.
    Ignored,
}

/// Executes one instruction on `target`; returns the byte the chip shifts out during the
/// fourth byte, and what happened.
pub fn execute(target: &mut Target, instr: [u8; 4]) -> (u8, IspOutcome) {
    let [a, b, c, d] = instr;
    let word = usize::from(u16::from_be_bytes([b, c]));
    let read = |r: Option<u8>| match r {
        Some(v) => (v, IspOutcome::Read),
        None => (0x00, IspOutcome::Ignored),
    };
    match (a, b) {
        (0xac, 0x80) => {
            target.chip_erase();
            (0x00, IspOutcome::ChipErase)
        }
        (0xac, 0x53) => (0x00, IspOutcome::Read), // programming enable: echo happens on byte 3
        (0xac, 0xa0) => write_fuse(&mut target.fuses.low, d),
        (0xac, 0xa8) => write_fuse(&mut target.fuses.high, d),
        (0xac, 0xa4) => write_fuse(&mut target.fuses.extended, d),
        (0xac, 0xe0) => write_fuse(&mut target.fuses.lock, d),
        (0x30, _) => read(crate::target::SIGNATURE.get(usize::from(c & 0x03)).copied()),
        (0x38, _) => read(Some(target.calibration)),
        (0x50, 0x00) => read(Some(target.fuses.low)),
        (0x50, 0x08) => read(Some(target.fuses.extended)),
        (0x58, 0x00) => read(Some(target.fuses.lock)),
        (0x58, 0x08) => read(Some(target.fuses.high)),
        (0x20, _) => read(flash_byte(target, word * 2)),
        (0x28, _) => read(flash_byte(target, word * 2 + 1)),
        (0xa0, _) => read(eeprom_byte(target, word)),
        (0xc0, _) => match target.write(Memory::Eeprom, word, &[d]) {
            Ok(()) => (0x00, IspOutcome::Wrote),
            Err(_) => (0x00, IspOutcome::Ignored),
        },
        (0xf0, _) => (0x00, IspOutcome::Read), // never busy
        _ => (0x00, IspOutcome::Ignored),
    }
}

fn write_fuse(fuse: &mut u8, value: u8) -> (u8, IspOutcome) {
    *fuse = value;
    (0x00, IspOutcome::Wrote)
}

fn flash_byte(target: &Target, addr: usize) -> Option<u8> {
    target.flash().get(addr).copied()
}

fn eeprom_byte(target: &Target, addr: usize) -> Option<u8> {
    target.eeprom().get(addr).copied()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_signature_fuses_and_lock() {
        let mut t = Target::default();
        assert_eq!(execute(&mut t, [0x30, 0, 0, 0]).0, 0x1e);
        assert_eq!(execute(&mut t, [0x30, 0, 1, 0]).0, 0x95);
        assert_eq!(execute(&mut t, [0x30, 0, 2, 0]).0, 0x0f);
        assert_eq!(execute(&mut t, [0x50, 0x00, 0, 0]).0, 0xff);
        assert_eq!(execute(&mut t, [0x58, 0x08, 0, 0]).0, 0xde);
        assert_eq!(execute(&mut t, [0x50, 0x08, 0, 0]).0, 0xfd);
        assert_eq!(execute(&mut t, [0x58, 0x00, 0, 0]).0, 0xff);
        assert_eq!(execute(&mut t, [0x38, 0, 0, 0]).0, 0x9d);
    }

    #[test]
    fn fuse_write_reads_back() {
        let mut t = Target::default();
        assert_eq!(execute(&mut t, [0xac, 0xa8, 0, 0xd6]).1, IspOutcome::Wrote);
        assert_eq!(execute(&mut t, [0x58, 0x08, 0, 0]).0, 0xd6);
    }

    #[test]
    fn byte_reads_address_words_and_bytes() {
        let mut t = Target::default();
        t.write(Memory::Flash, 0x202, &[0x12, 0x34]).unwrap();
        // word 0x101: low byte then high byte
        assert_eq!(execute(&mut t, [0x20, 0x01, 0x01, 0]).0, 0x12);
        assert_eq!(execute(&mut t, [0x28, 0x01, 0x01, 0]).0, 0x34);
        assert_eq!(
            execute(&mut t, [0xc0, 0x00, 0x05, 0x42]).1,
            IspOutcome::Wrote
        );
        assert_eq!(t.eeprom()[5], 0x42);
        assert_eq!(execute(&mut t, [0xa0, 0x00, 0x05, 0]).0, 0x42);
    }

    #[test]
    fn chip_erase_erases_and_unknown_is_ignored() {
        let mut t = Target::default();
        t.write(Memory::Flash, 0, &[0]).unwrap();
        assert_eq!(execute(&mut t, [0xac, 0x80, 0, 0]).1, IspOutcome::ChipErase);
        assert_eq!(t.flash()[0], 0xff);
        assert_eq!(
            execute(&mut t, [0x4c, 0, 0, 0]),
            (0x00, IspOutcome::Ignored)
        );
        assert_eq!(
            execute(&mut t, [0xa0, 0x04, 0x00, 0]),
            (0x00, IspOutcome::Ignored)
        );
    }
}
