//! The slave's register file as the I2C bus sees it, with change marks for the tick.
//!
//! **Writes.** A write transaction's first byte sets the register pointer. The bytes
//! after it fill that register (its size, LSB first); any bytes after those are ignored
//! (one register per write, reference §5), so a stray or corrupted extra byte cannot
//! reach the next register. A register's value is committed, and marked changed, when
//! its last byte arrives, so the tick never sees half of a two-byte value; a register
//! left incomplete when the transaction ends is dropped. REG_EXCEPTIONDATA is marked at
//! its first byte too: any write to it raises REMOTESLAVE (reference §2.1), whatever its
//! value, so a spread write that a master reset or a bus error cut short still stops the
//! board. Bytes for a read-only register or an id the table lacks are dropped.
//! An empty write (no byte, or only the pointer) changes no register: the emulator shows
//! the STOP after a master read as an empty write. Writes to REG_RESET are OR-ed into
//! it until the tick processes them, so two quick resets do not merge into one.
//!
//! **Reads.** A read transaction starts at the pointer and continues through the
//! following registers; both bytes of a register come from the same moment. Ids the
//! table lacks read 0xcd, and so does everything past the last register.
//!
//! Every call is O(1), allocation-free and short enough for the TWI interrupt. Registers
//! live in two-byte slots indexed by id (a one-byte register uses the first), so no
//! offset table is needed.

use super::board::{Board, Variant};
use crate::regs::{self, id, BoardKind};

/// What a read of a missing register gives.
pub const MISSING: u8 = 0xcd;

/// Slots: the longer of the two slave tables.
const SLOTS: usize = if regs::DS.len() > regs::LL.len() {
    regs::DS.len()
} else {
    regs::LL.len()
};

/// Change marks: one bit per slot, eight slots a byte (bytes, not a `u64`: 64-bit
/// shifts and bit scans are long loops on the AVR).
const MARK_BYTES: usize = SLOTS.div_ceil(8);

/// Where the bus is within a transaction.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Phase {
    /// Between transactions.
    Idle,
    /// Addressed for writing; the next byte is the pointer.
    Pointer,
    /// Writing register `id`, at byte `byte` of it.
    Writing { id: u8, byte: u8 },
    /// Reading register `id`, at byte `byte` of it.
    Reading { id: u8, byte: u8 },
}

/// The registers of one slave, and the bus's view of them, for a variant `B` chosen at
/// run time ([`Variant`], the default) or at build time (see [`Board`]).
#[derive(Clone, Debug)]
pub struct RegisterFile<B: Board = Variant> {
    board: B,
    len: u8,
    slots: [[u8; 2]; SLOTS],
    changed: [u8; MARK_BYTES],
    pointer: u8,
    phase: Phase,
    /// The byte that completes a register: the low byte while writing, the high byte
    /// while reading.
    held: u8,
}

impl<B: Board> RegisterFile<B> {
    /// The register file of a variant at power-up (reference §8.1).
    pub fn new(board: B) -> RegisterFile<B> {
        let variant = board.variant();
        let mut file = RegisterFile {
            board,
            len: variant.board().len(),
            slots: [[0; 2]; SLOTS],
            changed: [0; MARK_BYTES],
            pointer: 0,
            phase: Phase::Idle,
            held: 0,
        };
        for &(reg, raw) in boot_values(variant) {
            file.set(reg, raw);
        }
        file
    }

    #[inline(always)]
    fn kind(&self) -> BoardKind {
        self.board.variant().board()
    }

    /// The number of registers.
    pub fn len(&self) -> u8 {
        self.len
    }

    /// Always false: a slave has registers (kept for clippy's `len` convention).
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// The raw value of a register (0 for an id the table lacks; a one-byte register
    /// gives its byte).
    pub fn get(&self, reg: u8) -> u16 {
        match (self.slots.get(usize::from(reg)), self.kind().size_of(reg)) {
            (Some(&[lo, _]), Some(1)) => u16::from(lo),
            (Some(&[lo, hi]), Some(_)) => u16::from_le_bytes([lo, hi]),
            _ => 0,
        }
    }

    /// Sets a register's raw value, without marking it changed (the slave's own writes:
    /// monitoring values, defaults). A one-byte register keeps the low byte: the high
    /// byte goes to its slot's unused half, which no read reaches. No table lookup, so
    /// the tick's many monitoring writes stay cheap.
    #[inline]
    pub fn set(&mut self, reg: u8, raw: u16) {
        if let Some(slot) = self.slots.get_mut(usize::from(reg)) {
            *slot = raw.to_le_bytes();
        }
    }

    /// Sets consecutive registers from `first` on, like [`RegisterFile::set`].
    pub fn set_run(&mut self, first: u8, raws: &[u16]) {
        let mut reg = first;
        for &raw in raws {
            self.set(reg, raw);
            reg = reg.wrapping_add(1);
        }
    }

    /// [`RegisterFile::set_run`], not inlined. On the AVR its section's name places it
    /// after the interrupt handlers (the slave links sorted by section name), within an
    /// RCALL's reach of its one caller, the tick.
    #[inline(never)]
    #[cfg_attr(target_arch = "avr", link_section = ".text.z_set_run")]
    pub fn set_run_outlined(&mut self, first: u8, raws: &[u16]) {
        self.set_run(first, raws);
    }

    /// Takes the lowest-numbered register marked changed, clearing its mark.
    pub fn take_changed(&mut self) -> Option<u8> {
        let mut changes = Changes(self.changed);
        let reg = changes.take();
        self.changed = changes.0;
        reg
    }

    /// Whether a register is marked changed.
    pub fn is_changed(&self, reg: u8) -> bool {
        match mark(reg) {
            Some((byte, bit)) => self.changed.get(byte).is_some_and(|m| m & bit != 0),
            None => false,
        }
    }

    /// TWI: addressed for writing (SLA+W). Ends any transaction in progress.
    pub fn start_write(&mut self) {
        self.phase = Phase::Pointer;
    }

    /// TWI: a data byte of a write transaction.
    pub fn write(&mut self, byte: u8) {
        match self.phase {
            Phase::Pointer => {
                self.pointer = byte;
                self.phase = Phase::Writing { id: byte, byte: 0 };
            }
            Phase::Writing { id, byte: index } => self.write_at(id, index, byte),
            Phase::Idle | Phase::Reading { .. } => {}
        }
    }

    /// TWI: addressed for reading (SLA+R), after a STOP or a repeated START.
    pub fn start_read(&mut self) {
        self.phase = Phase::Reading {
            id: self.pointer,
            byte: 0,
        };
    }

    /// TWI: the next byte the master reads. On the AVR its section's name places it after
    /// the interrupt handlers, within an RCALL's reach of the TWI's.
    #[cfg_attr(target_arch = "avr", link_section = ".text.z_read")]
    pub fn read(&mut self) -> u8 {
        let Phase::Reading { id, byte } = self.phase else {
            return MISSING;
        };
        let Some(size) = self.kind().size_of(id) else {
            return MISSING;
        };
        let (value, next) = if byte == 0 {
            let [lo, hi] = self.slots.get(usize::from(id)).copied().unwrap_or([0; 2]);
            self.held = hi;
            (
                lo,
                if size > 1 {
                    (id, 1)
                } else {
                    (id.wrapping_add(1), 0)
                },
            )
        } else {
            (self.held, (id.wrapping_add(1), 0))
        };
        self.phase = Phase::Reading {
            id: next.0,
            byte: next.1,
        };
        value
    }

    /// TWI: STOP (or a bus error). An incomplete register is dropped (REG_EXCEPTIONDATA
    /// was marked at its first byte).
    pub fn stop(&mut self) {
        self.phase = Phase::Idle;
    }

    fn write_at(&mut self, reg: u8, index: u8, byte: u8) {
        let Some(size) = self.kind().size_of(reg) else {
            // Past the table: everything from here on is dropped.
            self.phase = Phase::Idle;
            return;
        };
        let last = index + 1 >= size;
        if last {
            if self.kind().is_writable(reg) == Some(true) {
                let lo = if size > 1 { self.held } else { byte };
                let hi = if size > 1 { byte } else { 0 };
                self.commit(reg, lo, hi);
            }
            // One register per write (reference §5): the bytes after it are ignored.
            self.phase = Phase::Idle;
        } else {
            self.held = byte;
            self.phase = Phase::Writing {
                id: reg,
                byte: index + 1,
            };
            if reg == id::REG_EXCEPTIONDATA {
                // Only the mark: the tick acts on the write, not on the value.
                self.changed[EXCEPTION_DATA_MARK.0] |= EXCEPTION_DATA_MARK.1;
            }
        }
    }

    fn commit(&mut self, reg: u8, lo: u8, hi: u8) {
        let Some(slot) = self.slots.get_mut(usize::from(reg)) else {
            return;
        };
        *slot = if reg == id::REG_RESET {
            [slot[0] | lo, 0]
        } else {
            [lo, hi]
        };
        if let Some((byte, bit)) = mark(reg) {
            if let Some(marks) = self.changed.get_mut(byte) {
                *marks |= bit;
            }
        }
    }
}

/// Change marks taken from a [`RegisterFile`].
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct Changes([u8; MARK_BYTES]);

impl Changes {
    /// Takes the lowest-numbered register marked, clearing its mark.
    pub fn take(&mut self) -> Option<u8> {
        let mut first = 0u8;
        for marks in &mut self.0 {
            if *marks != 0 {
                let bit = marks.trailing_zeros() as u8;
                *marks &= *marks - 1;
                return Some(first + bit);
            }
            first = first.wrapping_add(8);
        }
        None
    }
}

/// REG_EXCEPTIONDATA's change mark: its byte and bit.
const EXCEPTION_DATA_MARK: (usize, u8) = match mark(id::REG_EXCEPTIONDATA) {
    Some(m) => m,
    None => panic!("REG_EXCEPTIONDATA has a change mark"),
};

/// The byte and bit of a register's change mark.
const fn mark(reg: u8) -> Option<(usize, u8)> {
    let byte = (reg >> 3) as usize;
    if byte < MARK_BYTES {
        Some((byte, 1u8 << (reg & 7)))
    } else {
        None
    }
}

/// Power-up raw values that are not zero (reference §8.1), including the quirks PC
/// programs can see: the steer and lift OVERCURRENTTHRESH read 0x0000 (they act as 300),
/// STALLCHECK reads 0x77 (it acts as 120), the calibration reads 0x00 / 0xfe (clamped
/// from −512 / 512).
fn boot_values(variant: Variant) -> &'static [(u8, u16)] {
    match variant {
        Variant::DriveSteer => &DS_BOOT,
        Variant::LiftLift => &LL_BOOT,
    }
}

/// Raw 0 in a symmetric range: 0x7fff.
const MID: u16 = 0x7fff;
/// FAULTTIME's power-on value.
const FAULT_TIME: u16 = super::fault::FAULT_TIME_POWER_ON_MS;
/// BUSTIMEOUT's power-on value.
const BUS_TIMEOUT: u16 = super::silence::BUS_TIMEOUT_POWER_ON_MS;

const DS_BOOT: [(u8, u16); 12] = [
    (id::REG_STATUS, 0x0009),
    (id::REG_EXCEPTIONDATA, 0x0502),
    (id::REGDS_DRIVE_REQSPEED, MID),
    (id::REGDS_DRIVE_DGAIN, MID),
    (id::REGDS_DRIVE_OVERCURRENTTHRESH, 0x4ccc),
    (id::REGDS_DRIVE_STALLCHECK, 0x77),
    (id::REGDS_STEER_REQPOS, MID),
    (id::REGDS_STEER_DGAIN, MID),
    (id::REGDS_STEER_STALLCHECK, 0x77),
    (id::REGDS_STEER_CALIBMAX, 0xfe),
    (id::REGDS_FAULTTIME, FAULT_TIME),
    (id::REGDS_BUSTIMEOUT, BUS_TIMEOUT),
];

const LL_BOOT: [(u8, u16); 12] = [
    (id::REG_STATUS, 0x0005),
    (id::REG_EXCEPTIONDATA, 0x0502),
    (id::REGLL_ONE_REQPOS, MID),
    (id::REGLL_ONE_DGAIN, MID),
    (id::REGLL_ONE_STALLCHECK, 0x77),
    (id::REGLL_ONE_CALIBMAX, 0xfe),
    (id::REGLL_TWO_REQPOS, MID),
    (id::REGLL_TWO_DGAIN, MID),
    (id::REGLL_TWO_STALLCHECK, 0x77),
    (id::REGLL_TWO_CALIBMAX, 0xfe),
    (id::REGLL_FAULTTIME, FAULT_TIME),
    (id::REGLL_BUSTIMEOUT, BUS_TIMEOUT),
];
