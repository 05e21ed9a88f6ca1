//! The register file as a shared resource, and how the control tick takes the bus's
//! writes without holding the TWI off for long.
//!
//! Applying a changed register (`Core::apply`) converts raw values to fixed point, a
//! few hundred cycles each; a burst of writes between two ticks would hold the TWI task
//! off for a millisecond if done under the lock. Instead, when a write arrived since the
//! last tick, the tick takes one marked register at a time (the lowest, its mark
//! cleared, and its value) under a short lock and applies it with the TWI free, until
//! none is marked. No copy of the file or of the marks: a register written again
//! meanwhile is marked again and applied again, with the same final state as applying
//! both values in turn.
//!
//! The ADC readings live in the same resource: the ADC task has the TWI task's
//! priority, so the tick takes the readings, the written flag and the addressed flag
//! under one lock.

use shared::regs::id;
use shared::slave::{AdcCollector, Board, RegisterFile};

/// The live register file, whether a data byte was written since the last take,
/// whether the board was addressed (for the bus-silence failsafe), and the ADC readings.
pub struct Registers<B: Board> {
    file: RegisterFile<B>,
    written: bool,
    addressed: bool,
    adc: AdcCollector,
}

impl<B: Board> Registers<B> {
    /// The power-up file of `board`'s variant.
    pub fn new(board: B) -> Registers<B> {
        Registers {
            file: RegisterFile::new(board),
            written: false,
            addressed: false,
            adc: AdcCollector::new(),
        }
    }

    /// The ADC readings, for the ADC task and the tick.
    #[inline(always)]
    pub fn adc(&mut self) -> &mut AdcCollector {
        &mut self.adc
    }

    /// The file, for the TWI task.
    #[inline(always)]
    pub fn file(&mut self) -> &mut RegisterFile<B> {
        &mut self.file
    }

    /// A data byte of a write arrived.
    #[inline(always)]
    pub fn mark_written(&mut self) {
        self.written = true;
    }

    /// A transaction addressed this board (SLA+W or SLA+R).
    #[inline(always)]
    pub fn mark_addressed(&mut self) {
        self.addressed = true;
    }

    /// Under the lock, for the tick: whether a data byte was written since the last
    /// call (then some register may be marked changed).
    #[inline(always)]
    pub fn take_written(&mut self) -> bool {
        core::mem::take(&mut self.written)
    }

    /// Under the lock, for the tick: the lowest-numbered register marked changed, its
    /// mark cleared, with its value. REG_RESET's bits are taken: cleared in the file, so
    /// that bits written later are applied next time.
    #[inline(always)]
    pub fn take_change(&mut self) -> Option<(u8, u16)> {
        let reg = self.file.take_changed()?;
        let raw = self.file.get(reg);
        if reg == id::REG_RESET {
            self.file.set(id::REG_RESET, 0);
        }
        Some((reg, raw))
    }

    /// Under the lock, for the tick: whether the board was addressed since the last
    /// call.
    #[inline(always)]
    pub fn take_addressed(&mut self) -> bool {
        core::mem::take(&mut self.addressed)
    }
}
