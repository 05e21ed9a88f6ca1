//! What the programmer was asked to do, kept for the log file written on exit.

use crate::isp::IspOutcome;
use crate::target::Memory;

/// One page (or part page) written.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Write {
    /// Memory written.
    pub memory: Memory,
    /// First byte address.
    pub addr: usize,
    /// Number of bytes.
    pub len: usize,
}

/// One serial-programming instruction passed through `Cmnd_STK_UNIVERSAL`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Universal {
    /// The four instruction bytes.
    pub instr: [u8; 4],
    /// The byte answered.
    pub answer: u8,
    /// What it did.
    pub outcome: IspOutcome,
}

/// A well-formed command the programmer answered with `Resp_STK_FAILED`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Refusal {
    /// The command byte.
    pub command: u8,
    /// Why, in words.
    pub reason: String,
}

/// Counters and lists of everything the session did.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Record {
    /// `Cmnd_STK_GET_SYNC` frames answered.
    pub syncs: usize,
    /// Frames answered with `Resp_STK_NOSYNC`.
    pub nosyncs: usize,
    /// Frames answered with `Resp_STK_UNKNOWN`.
    pub unknown: usize,
    /// Times programming mode was entered.
    pub progmode_entries: usize,
    /// Chip erases performed (a bootloader ignores them and does not count them).
    pub chip_erases: usize,
    /// Pages read back from flash.
    pub flash_reads: usize,
    /// Pages read back from EEPROM.
    pub eeprom_reads: usize,
    /// Every page write, in order.
    pub writes: Vec<Write>,
    /// Every universal instruction, in order.
    pub universal: Vec<Universal>,
    /// Every refused command, in order.
    pub refusals: Vec<Refusal>,
}

impl Record {
    /// Total bytes written to `memory` (overlapping writes count twice).
    pub fn bytes_written(&self, memory: Memory) -> usize {
        self.writes
            .iter()
            .filter(|w| w.memory == memory)
            .map(|w| w.len)
            .sum()
    }

    /// Counts a page read of `memory`.
    pub fn count_read(&mut self, memory: Memory) {
        match memory {
            Memory::Flash => self.flash_reads += 1,
            Memory::Eeprom => self.eeprom_reads += 1,
        }
    }
}
