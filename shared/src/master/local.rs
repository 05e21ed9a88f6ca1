//! Device 0: the master's own registers.

use super::LinkError;
use crate::exception::MasterLatch;
use crate::regs::id;

/// Raw value of 0.0 °C over -20..100, what a sensor that was never read shows.
const ZERO_CELSIUS_RAW: u16 = 0x2aaa;

/// The master-local registers and the state behind them.
#[derive(Clone, Debug)]
pub struct LocalRegisters {
    /// Raw (mapped) temperatures: ambient, then controllers 1..9.
    temps: [u16; 10],
    /// The exception latch behind REGMASTER_EXCEPTIONDATA.
    pub exception: MasterLatch,
    last_error: u8,
    error_count: u16,
}

impl Default for LocalRegisters {
    fn default() -> Self {
        Self::new()
    }
}

impl LocalRegisters {
    /// The state at boot: in the boot exception, temperatures 0.0 °C, no errors.
    pub const fn new() -> Self {
        LocalRegisters {
            temps: [ZERO_CELSIUS_RAW; 10],
            exception: MasterLatch::boot(),
            last_error: 0,
            error_count: 0,
        }
    }

    /// The raw value of register `id`, or `None` if the master has no such register.
    pub fn read(&self, reg: u8) -> Option<u16> {
        Some(match reg {
            // Write-only in effect; the original read back an undefined value.
            id::REGMASTER_RESET => 0,
            id::REGMASTER_TEMPAMBIENT..=id::REGMASTER_TEMP9 => {
                self.temps[usize::from(reg - id::REGMASTER_TEMPAMBIENT)]
            }
            id::REGMASTER_EXCEPTIONDATA => self.exception.data(),
            id::REGMASTER_LASTERROR => u16::from(self.last_error),
            id::REGMASTER_ERRORCOUNT => self.error_count,
            _ => return None,
        })
    }

    /// Applies a write of `raw` to register `reg`, which the caller checked is writable.
    // Out of line: the frame logic and the remote control both call it (one copy).
    #[inline(never)]
    pub fn write(&mut self, reg: u8, _raw: u16) {
        if reg == id::REGMASTER_RESET {
            // Any value clears the master exception (reference §2.4).
            self.exception.clear();
        }
    }

    /// Stores raw temperature `raw` of sensor `index` (0 ambient, then controllers 1..9);
    /// another index is ignored.
    pub fn set_temperature(&mut self, index: u8, raw: u16) {
        if let Some(t) = self.temps.get_mut(usize::from(index)) {
            *t = raw;
        }
    }

    /// Records a link error for REGMASTER_LASTERROR and REGMASTER_ERRORCOUNT.
    // Out of line: the frame logic and the link's byte errors and timeout share one copy.
    #[inline(never)]
    pub fn record(&mut self, e: LinkError) {
        self.last_error = e.code();
        self.error_count = self.error_count.wrapping_add(1);
    }

    /// The last error recorded, if any.
    pub fn last_error(&self) -> Option<LinkError> {
        LinkError::from_code(self.last_error)
    }

    /// How many errors were recorded (wraps at 65536).
    pub fn error_count(&self) -> u16 {
        self.error_count
    }
}
