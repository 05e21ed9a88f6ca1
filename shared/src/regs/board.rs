//! Board kinds and their tables: which table a device uses and lookups in it.

use super::tables::{
    DS, DS_FLAGS, DS_RANGE_INDEX, LL, LL_FLAGS, LL_RANGE_INDEX, MASTER, MASTER_FLAGS,
    MASTER_RANGE_INDEX, NO_RANGE, RANGES,
};
use super::{Range, Register, Shape, FLAG_SIZE_MASK, FLAG_WRITABLE};

/// The three kinds of board, each with its own register table.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum BoardKind {
    /// The master board, device 0.
    Master,
    /// A drive/steer slave: controllers 1, 2, 4, 5, 7, 8.
    DriveSteer,
    /// A lift/lift slave: controllers 3, 6, 9.
    LiftLift,
}

impl BoardKind {
    /// The kind of board at a device number: 0 is the master, 3, 6 and 9 are lift/lift,
    /// 1, 2, 4, 5, 7 and 8 are drive/steer; any other number has no board.
    pub const fn of_device(device: u8) -> Option<BoardKind> {
        match device {
            0 => Some(BoardKind::Master),
            3 | 6 | 9 => Some(BoardKind::LiftLift),
            1 | 2 | 4 | 5 | 7 | 8 => Some(BoardKind::DriveSteer),
            _ => None,
        }
    }

    /// The board's full register table; index == id.
    pub fn table(self) -> &'static [Register] {
        match self {
            BoardKind::Master => &MASTER,
            BoardKind::DriveSteer => &DS,
            BoardKind::LiftLift => &LL,
        }
    }

    /// The register with this id, if the table has it.
    pub fn register(self, id: u8) -> Option<&'static Register> {
        self.table().get(usize::from(id))
    }

    /// Finds a register by name, ignoring ASCII case: the full symbol
    /// (`REGLL_ONE_REQPOS`) or the symbol without its prefix (`ONE_REQPOS`, `reset`).
    pub fn lookup(self, name: &str) -> Option<&'static Register> {
        self.table().iter().find(|reg| {
            reg.name.eq_ignore_ascii_case(name) || reg.short_name().eq_ignore_ascii_case(name)
        })
    }

    /// The board kind's short name, as the definition file's block: `MASTER`, `DS`, `LL`.
    pub fn name(self) -> &'static str {
        match self {
            BoardKind::Master => "MASTER",
            BoardKind::DriveSteer => "DS",
            BoardKind::LiftLift => "LL",
        }
    }

    /// Number of registers in the table.
    pub fn len(self) -> u8 {
        // Tables hold at most 256 entries (ids are u8); the generator enforces it.
        u8::try_from(self.flags().len()).unwrap_or(u8::MAX)
    }

    /// Always false: every board has registers (kept for clippy's `len` convention).
    pub fn is_empty(self) -> bool {
        self.flags().is_empty()
    }

    fn flags(self) -> &'static [u8] {
        match self {
            BoardKind::Master => &MASTER_FLAGS,
            BoardKind::DriveSteer => &DS_FLAGS,
            BoardKind::LiftLift => &LL_FLAGS,
        }
    }

    fn range_index(self) -> &'static [u8] {
        match self {
            BoardKind::Master => &MASTER_RANGE_INDEX,
            BoardKind::DriveSteer => &DS_RANGE_INDEX,
            BoardKind::LiftLift => &LL_RANGE_INDEX,
        }
    }

    /// The original firmware's flag byte of a register (size | 0x40 if writable).
    /// Reads a small byte table, not the full one.
    pub fn flag_byte(self, id: u8) -> Option<u8> {
        self.flags().get(usize::from(id)).copied()
    }

    /// Size in bytes of a register, or `None` if the table has no such id.
    pub fn size_of(self, id: u8) -> Option<u8> {
        self.flag_byte(id).map(|f| f & FLAG_SIZE_MASK)
    }

    /// Whether a register is writable, or `None` if the table has no such id.
    pub fn is_writable(self, id: u8) -> Option<bool> {
        self.flag_byte(id).map(|f| f & FLAG_WRITABLE != 0)
    }

    /// Size, writability and range of a register, from the compact tables.
    pub fn shape(self, id: u8) -> Option<Shape> {
        let flags = self.flag_byte(id)?;
        let index = self.range_index().get(usize::from(id)).copied()?;
        let range: Option<Range> = if index == NO_RANGE {
            None
        } else {
            Some(*RANGES.get(usize::from(index))?)
        };
        Some(Shape {
            size: flags & FLAG_SIZE_MASK,
            writable: flags & FLAG_WRITABLE != 0,
            range,
        })
    }
}
