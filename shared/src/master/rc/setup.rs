//! The writes the master sends the first time the RC link comes up after a boot
//! (reference §9.2): exceptions reset on devices 0..9, then drive and steer parameters
//! and the steer calibration on every drive/steer board. Lifts are not written.
//!
//! Values are raw register values, precomputed so the firmware needs no float; a host
//! test maps the engineering values with `mapping::map` and checks each one.

use crate::master::ping::RegWrite;
use crate::regs::{id, DS};

/// The drive/steer controllers of wheels 1..6.
pub const DS_CONTROLLERS: [u8; 6] = [1, 2, 4, 5, 7, 8];

/// Drive block: P 0.01, I 0, D 0, cap 0, decay 0, overcurrent 500, stall check 255.
pub const DRIVE_BLOCK: [(u8, u16); 7] = [
    (id::REGDS_DRIVE_PGAIN, 0x0041),
    (id::REGDS_DRIVE_IGAIN, 0x0000),
    (id::REGDS_DRIVE_DGAIN, 0x7fff),
    (id::REGDS_DRIVE_INTEGRALCAP, 0x0000),
    (id::REGDS_DRIVE_INTEGRALDECAY, 0x0000),
    (id::REGDS_DRIVE_OVERCURRENTTHRESH, 0x7fff),
    (id::REGDS_DRIVE_STALLCHECK, 0xfe),
];

/// Steer block without calibration: P 0, I 6, D 0, cap 300, decay 0.9, overcurrent
/// 500, stall check 255, dead zone 1.
pub const STEER_BLOCK: [(u8, u16); 8] = [
    (id::REGDS_STEER_PGAIN, 0x0000),
    (id::REGDS_STEER_IGAIN, 0x9998),
    (id::REGDS_STEER_DGAIN, 0x7fff),
    (id::REGDS_STEER_INTEGRALCAP, 0x4ccc),
    (id::REGDS_STEER_INTEGRALDECAY, 0xe664),
    (id::REGDS_STEER_OVERCURRENTTHRESH, 0x7fff),
    (id::REGDS_STEER_STALLCHECK, 0xfe),
    (id::REGDS_STEER_DEADZONE, 0x05),
];

/// Steer calibration (CALIBMIN, CALIBMAX) raw bytes of wheels 1..6 (reference §8.3).
pub const STEER_CALIBRATION: [(u8, u8); 6] = [
    (0x43, 0xc4),
    (0x3d, 0xbd),
    (0x40, 0xc2),
    (0x3f, 0xc3),
    (0x39, 0xbb),
    (0x3d, 0xbe),
];

crate::flash_table! {
    /// [`DS_CONTROLLERS`] as the firmware reads it, kept in flash on the AVR.
    pub static DS_CONTROLLERS_FLASH: [u8; 6] = DS_CONTROLLERS;
}

/// Writes per board from the two blocks.
const BLOCKS: usize = DRIVE_BLOCK.len() + STEER_BLOCK.len();

/// [`DRIVE_BLOCK`] then [`STEER_BLOCK`], as one table of (id, size, raw value), each
/// register's size taken from the drive/steer table at compile time: the firmware reads
/// a write whole, with no size lookup.
const fn both_blocks() -> [(u8, u8, u16); BLOCKS] {
    let mut out = [(0, 0, 0); BLOCKS];
    let mut i = 0;
    while i < BLOCKS {
        let (reg, raw) = if i < DRIVE_BLOCK.len() {
            DRIVE_BLOCK[i]
        } else {
            STEER_BLOCK[i - DRIVE_BLOCK.len()]
        };
        out[i] = (reg, DS[reg as usize].size, raw);
        i += 1;
    }
    out
}

crate::flash_table! {
    /// [`DRIVE_BLOCK`] then [`STEER_BLOCK`] with their sizes, kept in flash on the AVR.
    static BLOCKS_FLASH: [(u8, u8, u16); BLOCKS] = both_blocks();
}

// The calibration registers take one byte each, as their values do.
const _: () = assert!(DS[id::REGDS_STEER_CALIBMIN as usize].size == 1);
const _: () = assert!(DS[id::REGDS_STEER_CALIBMAX as usize].size == 1);

crate::flash_table! {
    /// [`STEER_CALIBRATION`], kept in flash on the AVR.
    static STEER_CALIBRATION_FLASH: [(u8, u8); 6] = STEER_CALIBRATION;
}

/// Writes per drive/steer board: the drive block, the steer block, CALIBMIN, CALIBMAX.
const PER_BOARD: usize = BLOCKS + 2;
/// REG_RESET writes to devices 0..9.
const RESETS: usize = 10;
/// All the writes of the first link-up.
pub const LINK_UP_WRITES: usize = RESETS + DS_CONTROLLERS.len() * PER_BOARD;

/// The first link-up's writes, in order: REG_RESET = 1 to devices 0..9 (device 0 is the
/// master itself: it clears the master exception), then for each drive/steer board in
/// wheel order the drive block, the steer block and the calibration.
#[derive(Clone, Debug, Default)]
pub struct LinkUpWrites {
    /// REG_RESET writes sent (devices 0..`resets`).
    resets: u8,
    /// The drive/steer board being configured (index into [`DS_CONTROLLERS`]).
    wheel: u8,
    /// The next write on that board: the drive block, the steer block, CALIBMIN,
    /// CALIBMAX. Counters rather than one write number, so no division is needed.
    item: u8,
}

impl LinkUpWrites {
    /// From the first write.
    pub const fn new() -> Self {
        LinkUpWrites {
            resets: 0,
            wheel: 0,
            item: 0,
        }
    }

    /// The write at the current position, without moving on.
    fn current(&self) -> Option<RegWrite> {
        if usize::from(self.resets) < RESETS {
            return Some(RegWrite::byte(self.resets, id::REG_RESET, 1));
        }
        let wheel = usize::from(self.wheel);
        let device = DS_CONTROLLERS_FLASH.get(wheel)?;
        let item = usize::from(self.item);
        let (reg, size, raw) = match BLOCKS_FLASH.get(item) {
            Some(w) => w,
            None => {
                let (min, max) = STEER_CALIBRATION_FLASH.get(wheel)?;
                if item == PER_BOARD - 2 {
                    (id::REGDS_STEER_CALIBMIN, 1, u16::from(min))
                } else {
                    (id::REGDS_STEER_CALIBMAX, 1, u16::from(max))
                }
            }
        };
        Some(if size == 1 {
            RegWrite::byte(device, reg, raw as u8)
        } else {
            RegWrite::word(device, reg, raw)
        })
    }
}

impl Iterator for LinkUpWrites {
    type Item = RegWrite;

    fn next(&mut self) -> Option<RegWrite> {
        let w = self.current()?;
        if usize::from(self.resets) < RESETS {
            self.resets += 1;
        } else if usize::from(self.item) + 1 < PER_BOARD {
            self.item += 1;
        } else {
            self.item = 0;
            self.wheel += 1;
        }
        Some(w)
    }
}
