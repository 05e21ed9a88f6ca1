//! The core's power-up state from zeroed memory: the control task's core is a static of
//! zero bytes (`.bss`, no flash), and `init` writes its few nonzero power-up bytes over
//! it from a table in flash ([`shared::slave::image`]), where initial data (`.data`)
//! would keep all of the core's bytes in flash.

use core::mem::{size_of, MaybeUninit};
use shared::progmem::Flash;
use shared::slave::clock::Clock;
use shared::slave::image::apply_from_flash;
use shared::slave::{Board, Core};

/// A new clock's bytes, which [`Core::image`] leaves to the firmware (at
/// [`Core::CLOCK_AT`]).
pub const CLOCK: [u8; size_of::<Clock>()] =
    // SAFETY: on the AVR every field is 1-aligned, so a struct has no padding; a clock
    // holds integers and flags only. A byte that is not initialised (an option's unused
    // payload, say) would stop the build here, not the board.
    unsafe { core::mem::transmute::<Clock, [u8; size_of::<Clock>()]>(Clock::new()) };

/// `bytes` (a core's [`Core::image`] with the clock's) read as a core of type `Core<B>`,
/// for a constant: the compiler checks a constant's value, so the build fails unless
/// they are a valid core, as [`write`] makes zeroed memory and takes it for one.
pub const fn read<B: Board, const N: usize>(bytes: [u8; N]) -> Core<B> {
    assert!(N == size_of::<Core<B>>());
    // SAFETY: the sizes are equal (asserted). Used only for a constant, whose value the
    // compiler checks: invalid bytes stop the build (this is the check).
    let core = unsafe { core::mem::transmute_copy::<[u8; N], MaybeUninit<Core<B>>>(&bytes) };
    // SAFETY: as above.
    unsafe { core.assume_init() }
}

/// Makes the zeroed core at `core` the power-up core of a board whose EEPROM byte 0 is
/// `eeprom_byte`: writes the (step, byte) `pairs` ([`shared::slave::image::Image::pairs`])
/// from its first byte, then the address ([`Core::set_eeprom`]).
///
/// # Safety
/// `core` points to a core's worth of zero bytes that nothing else accesses while this
/// runs, and `pairs` (1..=256 of them) were made for a core of that type from an image
/// that [`read`] passed in a constant: their steps stay inside it and they make it a
/// valid core.
#[inline(always)]
pub unsafe fn write<B: Board>(
    core: *mut MaybeUninit<Core<B>>,
    pairs: &'static Flash<[[u8; 2]]>,
    eeprom_byte: u8,
) {
    // SAFETY: per the contract, the pairs (1..=256 of them: checked where the table is
    // built) stay inside the core, which this function alone accesses.
    unsafe { apply_from_flash(pairs, core.cast::<u8>()) };
    // SAFETY: per the contract, the pairs made a valid core, which nothing else accesses.
    unsafe { (*core).assume_init_mut() }.set_eeprom(eeprom_byte);
}
