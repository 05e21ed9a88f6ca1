//! Register sizes and writability as the master's frame logic reads them: from packed
//! flag tables the AVR keeps in flash, two bits per register (bit 0: size − 1, bit 1:
//! writable), four registers a byte, built at compile time from the register tables
//! ([`crate::regs::DS`] and its siblings). A register of another size stops the build.

use crate::regs::{BoardKind, Register, DS, FLAG_SIZE_MASK, FLAG_WRITABLE, LL, MASTER};

/// Registers per packed byte.
const PER_BYTE: usize = 4;

/// The two-bit code of a flag byte (size 1 or 2, writable bit); a flag byte of another
/// size stops the build.
const fn code_of_flag(flag: u8) -> u8 {
    let size = flag & FLAG_SIZE_MASK;
    assert!(
        size == 1 || size == 2,
        "a register is neither one nor two bytes"
    );
    (size - 1) | if flag & FLAG_WRITABLE != 0 { 2 } else { 0 }
}

/// Flag bytes (size | writable), packed: register i in bits 2·(i % 4) and up of byte
/// i / 4. `N` must be the bytes that takes.
const fn pack<const N: usize>(flags: &[u8]) -> [u8; N] {
    assert!(
        flags.len().div_ceil(PER_BYTE) == N,
        "the packed length is wrong"
    );
    let mut out = [0; N];
    let mut i = 0;
    while i < flags.len() {
        out[i / PER_BYTE] |= code_of_flag(flags[i]) << (2 * (i % PER_BYTE));
        i += 1;
    }
    out
}

/// A register table's flag bytes.
const fn flag_bytes<const N: usize>(table: &[Register; N]) -> [u8; N] {
    let mut out = [0; N];
    let mut i = 0;
    while i < N {
        out[i] = table[i].flag_byte();
        i += 1;
    }
    out
}

/// Packed bytes for `n` registers.
const fn packed_len(n: usize) -> usize {
    n.div_ceil(PER_BYTE)
}

/// The manual's examples' sizes (ids 0 and 1 one byte, 2 and 3 two bytes), which no
/// real table has: a table for the protocol tests only.
const HYPOTHETICAL_FLAGS: &[u8] = if cfg!(test) { &[1, 1, 2, 2] } else { &[] };

/// Where each table starts in [`PACKED`]: the master's, the drive/steer board's, the
/// lift/lift board's, the tests' table.
const STARTS: [usize; 4] = {
    let ds = packed_len(MASTER.len());
    let ll = ds + packed_len(DS.len());
    [0, ds, ll, ll + packed_len(LL.len())]
};

/// Bytes of all packed tables.
const PACKED_LEN: usize = STARTS[3] + packed_len(HYPOTHETICAL_FLAGS.len());

/// All packed tables, one after the other.
const fn all_packed() -> [u8; PACKED_LEN] {
    let parts: [&[u8]; 4] = [
        &pack::<{ packed_len(MASTER.len()) }>(&flag_bytes(&MASTER)),
        &pack::<{ packed_len(DS.len()) }>(&flag_bytes(&DS)),
        &pack::<{ packed_len(LL.len()) }>(&flag_bytes(&LL)),
        &pack::<{ packed_len(HYPOTHETICAL_FLAGS.len()) }>(HYPOTHETICAL_FLAGS),
    ];
    let mut out = [0; PACKED_LEN];
    let mut t = 0;
    while t < parts.len() {
        let mut i = 0;
        while i < parts[t].len() {
            out[STARTS[t] + i] = parts[t][i];
            i += 1;
        }
        t += 1;
    }
    out
}

crate::flash_table! {
    /// All packed tables, kept in flash on the AVR.
    static PACKED: [u8; PACKED_LEN] = all_packed();
}

/// Register counts fit a byte (ids are u8), and packed offsets too.
const _: () = assert!(PACKED_LEN < 256 && DS.len() < 256 && LL.len() < 256);

crate::flash_table! {
    /// Per table, by [`Sizes`]' index: none (no registers), the master's, the
    /// drive/steer board's, the lift/lift board's, the tests': its first byte in
    /// [`PACKED`] and its number of registers.
    static TABLES: [(u8, u8); 5] = [
        (0, 0),
        (STARTS[0] as u8, MASTER.len() as u8),
        (STARTS[1] as u8, DS.len() as u8),
        (STARTS[2] as u8, LL.len() as u8),
        (STARTS[3] as u8, HYPOTHETICAL_FLAGS.len() as u8),
    ];
}

/// Which packed flag table a device's registers are looked up in: its index in
/// [`TABLES`] (one byte).
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct Sizes(u8);

/// [`TABLES`]'s index of each board kind's table.
const fn index_of(kind: BoardKind) -> u8 {
    match kind {
        BoardKind::Master => 1,
        BoardKind::DriveSteer => 2,
        BoardKind::LiftLift => 3,
    }
}

/// The table of each device 0..=9 as [`Sizes::of_device`] gives it.
const fn device_tables() -> [u8; 10] {
    let mut out = [0; 10];
    let mut device = 0;
    while device < out.len() {
        out[device] = match BoardKind::of_device(device as u8) {
            Some(kind) => index_of(kind),
            None => panic!("a device up to 9 has no board"),
        };
        device += 1;
    }
    out
}

crate::flash_table! {
    /// [`TABLES`]'s index of the table of each device 0..=9 (the board's).
    static DEVICE_TABLES: [u8; 10] = device_tables();
}

// Every device from 10 up has no board.
const _: () = assert!(BoardKind::of_device(10).is_none() && BoardKind::of_device(255).is_none());

impl Sizes {
    /// The table of a device with no board: it has no register.
    pub const EMPTY: Sizes = Sizes(0);

    /// The manual's examples' sizes (ids 0 and 1 one byte, 2 and 3 two bytes), which no
    /// real table has.
    #[cfg(test)]
    pub(crate) const HYPOTHETICAL: Sizes = Sizes(4);

    /// The table of the board at `device`, or `None` if no board has that number.
    pub fn of_device(device: u8) -> Option<Sizes> {
        DEVICE_TABLES.get(usize::from(device)).map(Sizes)
    }

    /// The table of a board kind.
    #[cfg(test)]
    pub fn of(kind: BoardKind) -> Sizes {
        Sizes(index_of(kind))
    }

    /// Number of registers.
    #[cfg(test)]
    pub fn count(self) -> u8 {
        TABLES
            .get(usize::from(self.0))
            .map_or(0, |(_, count)| count)
    }

    /// The flag byte (size | writable) of register `id`, or `None` if the table has no
    /// such id (what the tests compare with the board tables).
    #[cfg(test)]
    pub fn flags(self, id: u8) -> Option<u8> {
        self.code(id)
            .map(|c| ((c & 1) + 1) | if c & 2 != 0 { FLAG_WRITABLE } else { 0 })
    }

    /// The two-bit code of register `id` (bit 0: size − 1, bit 1: writable), or `None`
    /// if the table has no such id. Out of line: one copy of the unpacking serves every
    /// caller.
    #[inline(never)]
    pub(crate) fn code(self, id: u8) -> Option<u8> {
        let (start, count) = TABLES.get(usize::from(self.0))?;
        if id >= count {
            return None;
        }
        let byte = PACKED.get(usize::from(start) + usize::from(id) / PER_BYTE)?;
        Some((byte >> (2 * (id % PER_BYTE as u8))) & 3)
    }

    /// Size in bytes of register `id`, or `None` if the table has no such id.
    pub fn size_of(self, id: u8) -> Option<u8> {
        self.code(id).map(|c| (c & 1) + 1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::regs::FLAG_WRITABLE;

    fn writable(sizes: Sizes, id: u8) -> Option<bool> {
        sizes.flags(id).map(|f| f & FLAG_WRITABLE != 0)
    }

    #[test]
    fn flash_tables_answer_as_the_board_tables_for_every_id() {
        for kind in [
            BoardKind::Master,
            BoardKind::DriveSteer,
            BoardKind::LiftLift,
        ] {
            let sizes = Sizes::of(kind);
            assert_eq!(sizes.count(), kind.len());
            for id in 0..=u8::MAX {
                assert_eq!(sizes.size_of(id), kind.size_of(id), "{kind:?} {id}");
                assert_eq!(writable(sizes, id), kind.is_writable(id), "{kind:?} {id}");
            }
        }
        // Spot values: REG_RESET is a writable byte; the master's last id is 15, a
        // writable word.
        let ds = Sizes::of(BoardKind::DriveSteer);
        assert_eq!((ds.size_of(0), writable(ds, 0)), (Some(1), Some(true)));
        let master = Sizes::of(BoardKind::Master);
        assert_eq!(
            (master.size_of(15), writable(master, 15)),
            (Some(2), Some(true))
        );
        assert_eq!(master.size_of(16), None);
        assert_eq!(Sizes::of(BoardKind::LiftLift).size_of(47), None);
    }

    #[test]
    fn the_empty_and_the_tests_tables_hold_what_they_say() {
        for id in 0..=u8::MAX {
            assert_eq!(Sizes::EMPTY.flags(id), None, "{id}");
            let expected = match id {
                0 | 1 => Some(1),
                2 | 3 => Some(2),
                _ => None,
            };
            assert_eq!(Sizes::HYPOTHETICAL.size_of(id), expected, "{id}");
        }
        assert_eq!((Sizes::EMPTY.count(), Sizes::HYPOTHETICAL.count()), (0, 4));
        // Four registers a byte: 14 + 48 + 47 registers, then the tests' 4.
        assert_eq!((PACKED_LEN, STARTS), (4 + 12 + 12 + 1, [0, 4, 16, 28]));
    }

    #[test]
    fn devices_map_to_their_boards_tables() {
        for device in 0..=u8::MAX {
            let kind = BoardKind::of_device(device);
            let sizes = Sizes::of_device(device);
            assert_eq!(sizes.is_some(), kind.is_some(), "device {device}");
            if let (Some(sizes), Some(kind)) = (sizes, kind) {
                assert_eq!(sizes.size_of(9), kind.size_of(9), "device {device}");
                assert_eq!(sizes.count(), kind.len(), "device {device}");
            }
        }
    }
}
