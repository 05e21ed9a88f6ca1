//! The register file as a shared resource, and how the control tick takes the bus's
//! writes without holding the TWI off for long.
//!
//! Applying a changed register (`Core::take_writes`) converts raw values to fixed
//! point, a few hundred cycles each; a burst of writes between two ticks would hold the
//! TWI task off for a millisecond if done under the lock. Instead the tick copies the
//! file under the lock (only when a write arrived since the last tick), clears the live
//! marks, and applies the copy with the TWI free.

use shared::regs::id;
use shared::slave::{Core, RegisterFile, Variant};

/// The live register file, and whether a data byte was written since the last take.
pub struct Registers {
    file: RegisterFile,
    written: bool,
}

impl Registers {
    /// The power-up file of `variant`.
    pub fn new(variant: Variant) -> Registers {
        Registers {
            file: RegisterFile::new(variant),
            written: false,
        }
    }

    /// The file, for the TWI task.
    #[inline(always)]
    pub fn file(&mut self) -> &mut RegisterFile {
        &mut self.file
    }

    /// A data byte of a write arrived.
    #[inline(always)]
    pub fn mark_written(&mut self) {
        self.written = true;
    }
}

/// The control tick's copy of the file.
pub struct Staging {
    copy: RegisterFile,
    /// REG_RESET's bits in the copy being applied.
    reset: u16,
}

impl Staging {
    /// An unused copy.
    pub fn new(variant: Variant) -> Staging {
        Staging {
            copy: RegisterFile::new(variant),
            reset: 0,
        }
    }

    /// Under the lock: copies the file if anything was written, and clears the live
    /// change marks. Returns whether there is anything to apply.
    pub fn take(&mut self, live: &mut Registers) -> bool {
        if !live.written {
            return false;
        }
        live.written = false;
        self.copy.clone_from(&live.file);
        while live.file.take_changed().is_some() {}
        self.reset = self.copy.get(id::REG_RESET);
        true
    }

    /// Without the lock: applies the copied writes.
    pub fn apply(&mut self, core: &mut Core) {
        core.take_writes(&mut self.copy);
    }

    /// Under the lock: REG_RESET's applied bits are cleared in the live file (bits
    /// written since the copy stay, and are applied next tick).
    pub fn settle(&mut self, live: &mut Registers) {
        if self.reset != 0 {
            let now = live.file.get(id::REG_RESET);
            live.file.set(id::REG_RESET, now & !self.reset);
            self.reset = 0;
        }
    }
}
