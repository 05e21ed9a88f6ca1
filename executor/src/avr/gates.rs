//! The executor's only mutable global state: what gated sources want, and which of them a
//! masking frame currently holds off.
//!
//! A gated source (declared `gated = true`) is switched on and off by drivers at run time,
//! such as USART_UDRE while bytes are queued. Its enable bit then means two things at once:
//! the driver's "I want this interrupt" and the executor's "not now, the level is masked".
//! These two tables keep them apart: [`WANT`] holds the driver's wish, [`HELD`] says which
//! gated bits some masking frame has cleared. The hardware bit is `WANT && !HELD`.
//!
//! Both are read and written only with the global interrupt flag clear (in a task's entry
//! or exit, in a lock made atomic, or in `gate::arm`/`disarm`), so no access can be torn.

use core::cell::UnsafeCell;
use core::ptr::{read_volatile, write_volatile};

use crate::source::REG_COUNT;

/// A per-register byte table in RAM.
pub(crate) struct Table(UnsafeCell<[u8; REG_COUNT]>);

// SAFETY: every access happens with interrupts disabled on a single core (see the module
// documentation), so no two accesses overlap.
unsafe impl Sync for Table {}

impl Table {
    const fn new() -> Table {
        Table(UnsafeCell::new([0; REG_COUNT]))
    }

    /// The byte of register index `r`.
    ///
    /// # Safety
    /// Interrupts are disabled.
    #[inline(always)]
    pub(crate) unsafe fn get(&self, r: usize) -> u8 {
        // SAFETY: `r < REG_COUNT` for every caller (a `Reg` index); exclusive per contract.
        unsafe { read_volatile(self.0.get().cast::<u8>().add(r)) }
    }

    /// Sets the byte of register index `r`.
    ///
    /// # Safety
    /// Interrupts are disabled.
    #[inline(always)]
    pub(crate) unsafe fn set(&self, r: usize, v: u8) {
        // SAFETY: as for `get`.
        unsafe { write_volatile(self.0.get().cast::<u8>().add(r), v) };
    }
}

/// Gated enable bits that drivers want on.
pub(crate) static WANT: Table = Table::new();

/// Gated enable bits that a masking frame has cleared and will hand back.
pub(crate) static HELD: Table = Table::new();
