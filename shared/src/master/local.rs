//! Device 0: the master's own registers.

use super::LinkError;
use crate::exception::MasterLatch;
use crate::regs::id;

/// Raw value of 0.0 °C over -20..100, what a sensor that was never read shows.
const ZERO_CELSIUS_RAW: u16 = 0x2aaa;

/// Registers of device 0 (ids 0..=15).
const REGISTERS: usize = id::REGMASTER_PCTIMEOUT as usize + 1;
/// Where `values` keeps each of the new registers.
const LAST_ERROR: usize = id::REGMASTER_LASTERROR as usize;
const ERROR_COUNT: usize = id::REGMASTER_ERRORCOUNT as usize;
const TEMPS_READ: usize = id::REGMASTER_TEMPSREAD as usize;
const PC_TIMEOUT: usize = id::REGMASTER_PCTIMEOUT as usize;

/// The master-local registers and the state behind them.
#[derive(Clone, Debug)]
pub struct LocalRegisters {
    /// The exception latch behind REGMASTER_EXCEPTIONDATA.
    pub exception: MasterLatch,
    /// The stored registers' raw values, index = id: 0 for REGMASTER_RESET (write-only
    /// in effect), the raw (mapped) temperatures (ambient, then controllers 1..9), an
    /// unused slot for REGMASTER_EXCEPTIONDATA (read from the latch), the last error's
    /// code, the error count, the sensors read and the PC-silence timeout. One array, so
    /// a read is one indexed load.
    values: [u16; REGISTERS],
}

/// The values at boot: temperatures 0.0 °C, no errors, the PC-silence failsafe off.
const BOOT_VALUES: [u16; REGISTERS] = {
    let mut out = [0; REGISTERS];
    let mut i = id::REGMASTER_TEMPAMBIENT as usize;
    while i <= id::REGMASTER_TEMP9 as usize {
        out[i] = ZERO_CELSIUS_RAW;
        i += 1;
    }
    out
};

impl Default for LocalRegisters {
    fn default() -> Self {
        Self::new()
    }
}

impl LocalRegisters {
    /// The state at boot: in the boot exception, temperatures 0.0 °C, no errors, the
    /// PC-silence failsafe off.
    pub const fn new() -> Self {
        LocalRegisters {
            exception: MasterLatch::boot(),
            values: BOOT_VALUES,
        }
    }

    /// The raw value of register `id`, or `None` if the master has no such register.
    // Out of line: measured 4 B smaller than in the frame logic.
    #[inline(never)]
    pub fn read(&self, reg: u8) -> Option<u16> {
        if reg == id::REGMASTER_EXCEPTIONDATA {
            return Some(self.exception.data());
        }
        self.values.get(usize::from(reg)).copied()
    }

    /// Applies a write of `raw` to register `reg`, which the caller checked is writable.
    // Out of line: the frame logic and the remote control's setup both write (one copy).
    #[inline(never)]
    pub fn write(&mut self, reg: u8, raw: u16) {
        if reg == id::REGMASTER_RESET {
            // Any value clears the master exception (reference §2.4).
            self.exception.clear();
        } else if reg == id::REGMASTER_PCTIMEOUT {
            self.values[PC_TIMEOUT] = raw;
        }
    }

    /// The PC-silence timeout in ms, 0 when off (REGMASTER_PCTIMEOUT, see
    /// [`PcWatch`](super::PcWatch)).
    pub fn pc_timeout_ms(&self) -> u16 {
        self.values[PC_TIMEOUT]
    }

    /// Stores the outcome of a read of sensor `index` (0 ambient, then controllers 1..9):
    /// its raw temperature, marked read in REGMASTER_TEMPSREAD; or, for a read that
    /// failed (`None`: a bad CRC, a sensor gone from the line), no reading: the register
    /// back to 0.0 °C and its bit cleared, so that no tool shows a stale temperature as
    /// current. Another index is ignored.
    pub fn set_temperature(&mut self, index: u8, raw: Option<u16>) {
        if index <= id::REGMASTER_TEMP9 - id::REGMASTER_TEMPAMBIENT {
            if let Some(t) = self
                .values
                .get_mut(usize::from(index + id::REGMASTER_TEMPAMBIENT))
            {
                *t = raw.unwrap_or(ZERO_CELSIUS_RAW);
            }
            let bit = 1 << index;
            let read = &mut self.values[TEMPS_READ];
            *read = (*read | bit) ^ if raw.is_some() { 0 } else { bit };
        }
    }

    /// Records a link error for REGMASTER_LASTERROR and REGMASTER_ERRORCOUNT.
    // Out of line: the frame logic and the link's byte errors and timeout share one copy.
    #[inline(never)]
    pub fn record(&mut self, e: LinkError) {
        self.values[LAST_ERROR] = u16::from(e.code());
        self.values[ERROR_COUNT] = self.values[ERROR_COUNT].wrapping_add(1);
    }

    /// The last error recorded, if any.
    pub fn last_error(&self) -> Option<LinkError> {
        // Only `record` writes it, with a one-byte code.
        LinkError::from_code(self.values[LAST_ERROR] as u8)
    }

    /// How many errors were recorded (wraps at 65536).
    pub fn error_count(&self) -> u16 {
        self.values[ERROR_COUNT]
    }
}

// The temperatures sit between RESET and EXCEPTIONDATA, and ten sensors fit the read
// bits: what `read` and `set_temperature` index.
const _: () = assert!(
    id::REGMASTER_RESET == 0
        && id::REGMASTER_TEMP9 - id::REGMASTER_TEMPAMBIENT < 16
        && id::REGMASTER_TEMPAMBIENT == 1
        && id::REGMASTER_EXCEPTIONDATA == id::REGMASTER_TEMP9 + 1
);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_id_reads_its_register() {
        let mut l = LocalRegisters::new();
        l.set_temperature(0, Some(0x1234));
        l.set_temperature(9, Some(0x4321));
        l.set_temperature(10, Some(0xffff));
        l.record(LinkError::NoAnswer);
        l.record(LinkError::BadDevice);
        let mut expected = [Some(ZERO_CELSIUS_RAW); 16];
        expected[0] = Some(0);
        expected[1] = Some(0x1234);
        expected[10] = Some(0x4321);
        // The boot exception (type 2), held since power-up.
        expected[11] = Some(0x0002);
        expected[12] = Some(u16::from(LinkError::BadDevice.code()));
        expected[13] = Some(2);
        // Sensors 0 and 9 read; the out-of-range index 10 marks nothing.
        expected[14] = Some(0b10_0000_0001);
        expected[15] = Some(0);
        for (reg, want) in (0..16u8).zip(expected) {
            assert_eq!(l.read(reg), want, "{reg}");
        }
        assert_eq!(l.read(16), None);
        assert_eq!(l.read(255), None);
        assert_eq!(l.last_error(), Some(LinkError::BadDevice));
        assert_eq!(l.error_count(), 2);
    }

    #[test]
    fn a_failed_read_leaves_no_reading_and_the_next_good_one_restores_it() {
        let mut l = LocalRegisters::new();
        l.set_temperature(2, Some(0x5887));
        l.set_temperature(3, Some(0x4000));
        assert_eq!(l.read(id::REGMASTER_TEMPSREAD), Some(0b1100));
        // Sensor 2's next read fails: 0.0 °C and its bit clear; sensor 3 untouched.
        l.set_temperature(2, None);
        assert_eq!(l.read(id::REGMASTER_TEMP2), Some(ZERO_CELSIUS_RAW));
        assert_eq!(l.read(id::REGMASTER_TEMP3), Some(0x4000));
        assert_eq!(l.read(id::REGMASTER_TEMPSREAD), Some(0b1000));
        // A failed read of a sensor never read changes nothing.
        l.set_temperature(9, None);
        assert_eq!(l.read(id::REGMASTER_TEMPSREAD), Some(0b1000));
        assert_eq!(l.read(id::REGMASTER_TEMP9), Some(ZERO_CELSIUS_RAW));
        // And a good read brings it back.
        l.set_temperature(2, Some(0x5900));
        assert_eq!(l.read(id::REGMASTER_TEMP2), Some(0x5900));
        assert_eq!(l.read(id::REGMASTER_TEMPSREAD), Some(0b1100));
        // An index past the sensors is ignored either way.
        l.set_temperature(10, None);
        assert_eq!(l.read(id::REGMASTER_TEMPSREAD), Some(0b1100));
    }

    #[test]
    fn the_pc_timeout_is_off_at_boot_and_reads_as_written() {
        let mut l = LocalRegisters::new();
        assert_eq!(l.pc_timeout_ms(), 0);
        l.write(id::REGMASTER_PCTIMEOUT, 500);
        assert_eq!(l.pc_timeout_ms(), 500);
        assert_eq!(l.read(id::REGMASTER_PCTIMEOUT), Some(500));
        // Clearing the exception leaves it.
        l.write(id::REGMASTER_RESET, 1);
        assert_eq!(l.pc_timeout_ms(), 500);
        l.write(id::REGMASTER_PCTIMEOUT, 0);
        assert_eq!(l.pc_timeout_ms(), 0);
    }
}
