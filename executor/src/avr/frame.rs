//! Masking frames: what a task does on entry and exit, and a lock around its closure.
//!
//! A frame of level `L` over base `BASE` clears, in every enable register, the bits of the
//! sources at levels `BASE+1..=L`, and at its end sets back exactly those of them that
//! were set. Frames nest like the stack does (a task's frame encloses its locks, a
//! preempting task's frame sits on top of everything), so undoing them in reverse order
//! always restores the state the enclosing frame expects.
//!
//! Per register the work is fixed at compile time by [`crate::plan`]: no code for a
//! register the frame does not touch; save-and-write-back for an exact register; for any
//! other, a re-read at the end that sets the frame's bits from witnesses (or from saved
//! bits), with TWINT/ADIF/ADSC written as zero (see [`crate::bits`]). Gated bits are
//! handed back by the outermost frame that cleared them, and only if a driver still wants
//! them.

use core::ptr::{read_volatile, write_volatile};

use super::gates::{HELD, WANT};
use crate::bits;
use crate::plan::{self, Plan};
use crate::source::{Reg, REG_COUNT};
use crate::App;

/// What a frame saved: per register, the bits to put back (or the whole value when it is
/// written back verbatim), and the gated bits that were already held when it began.
pub(crate) struct Frame {
    saved: [u8; REG_COUNT],
    held: [u8; REG_COUNT],
}

#[inline(always)]
unsafe fn read(reg: Reg) -> u8 {
    // SAFETY: `reg.addr()` is an I/O register of the ATmega328P, always readable.
    unsafe { read_volatile(reg.addr() as *const u8) }
}

#[inline(always)]
unsafe fn write(reg: Reg, v: u8) {
    // SAFETY: `reg.addr()` is an I/O register; the values written come from `bits`, which
    // never set a write-one-to-act bit.
    unsafe { write_volatile(reg.addr() as *mut u8, v) };
}

/// Opens a frame of level `L` over `BASE`: clears the enable bits of every source at the
/// levels `BASE+1..=L`.
///
/// `ENTRY` is true for a task's own entry at priority `L` (with `BASE` 0): its source
/// fired, so the system was below `L` and the ungated sources of level `L` itself were all
/// enabled. What is saved is decided per register by [`plan::plan`].
///
/// # Safety
/// Called with interrupts disabled, or (when every register involved is exact, see
/// `analysis::atomic_lock`) from a context at level `BASE`; the returned frame is
/// passed to [`close`] with the same parameters before any enclosing frame ends.
#[inline(always)]
pub(crate) unsafe fn open<A: App, const L: u8, const BASE: u8, const ENTRY: bool>() -> Frame {
    let mut f = Frame {
        saved: [0; REG_COUNT],
        held: [0; REG_COUNT],
    };
    macro_rules! step {
        ($i:literal, $reg:expr) => {{
            let m = const { plan::frame_bits(&A::MASKS, L, BASE, $i) };
            match const { plan::plan(&A::MASKS, &A::GATED, &A::EXACT, L, BASE, ENTRY, $i) } {
                Plan::Untouched => {}
                Plan::Derived => {
                    // SAFETY: see the function's contract.
                    let now = unsafe { read($reg) };
                    // SAFETY: as above.
                    unsafe { write($reg, bits::masked($reg, now, m)) };
                }
                Plan::Exact | Plan::Saved => {
                    // SAFETY: as above.
                    unsafe { save_and_clear::<A>(&mut f, $i, $reg, m) };
                }
            }
        }};
    }
    each_reg!(step);
    f
}

/// Closes a frame opened by [`open`] with the same parameters: sets back exactly the bits
/// it cleared that were enabled, and hands gated bits back to the drivers' wishes if this
/// frame was the one that took them.
///
/// # Safety
/// Same conditions as [`open`]; `f` is the frame it returned.
#[inline(always)]
pub(crate) unsafe fn close<A: App, const L: u8, const BASE: u8, const ENTRY: bool>(f: Frame) {
    macro_rules! step {
        ($i:literal, $reg:expr) => {{
            match const { plan::plan(&A::MASKS, &A::GATED, &A::EXACT, L, BASE, ENTRY, $i) } {
                Plan::Untouched => {}
                Plan::Derived => {
                    // SAFETY: see the function's contract.
                    let now = unsafe { read($reg) };
                    let v = derived::<A, L, BASE, ENTRY, $i>(&f, bits::unmasked($reg, now, 0));
                    // SAFETY: as above; `v` sets only bits this frame cleared.
                    unsafe { write($reg, v) };
                }
                Plan::Exact | Plan::Saved => {
                    let m = const { plan::frame_bits(&A::MASKS, L, BASE, $i) };
                    // SAFETY: as above.
                    unsafe { put_back::<A>(&f, $i, $reg, m) };
                }
            }
        }};
    }
    each_reg!(step);
}

/// [`plan::witness`] for `A`, or register 0 bit 0 when there is none (never used then: a
/// register is derived only when all its witnesses exist).
const fn witness_or_none<A: App, const L: u8, const BASE: u8>(k: u8) -> (usize, u8) {
    match plan::witness(&A::MASKS, &A::GATED, &A::EXACT, L, BASE, k) {
        Some(found) => found,
        None => (0, 0),
    }
}

/// Puts a derived register's bits back into `v` (its current value, write-one-to-act bits
/// cleared): each level's bits are set if that level was enabled when the frame opened,
/// which is known at a task's entry for its own level and read off a witness otherwise.
/// A witness bit is copied with BST/BLD (two cycles per bit, no branch).
#[inline(always)]
fn derived<A: App, const L: u8, const BASE: u8, const ENTRY: bool, const I: usize>(
    f: &Frame,
    mut v: u8,
) -> u8 {
    if ENTRY {
        v |= const { plan::level_bits(&A::MASKS, &A::GATED, L, I) };
    }
    macro_rules! copy {
        ($k:literal, $d:literal) => {{
            const fn wanted<A: App, const L: u8, const BASE: u8, const ENTRY: bool, const I: usize>(
            ) -> bool {
                $k > BASE
                    && $k <= L
                    && !(ENTRY && $k == L)
                    && plan::level_bits(&A::MASKS, &A::GATED, $k, I) & (1 << $d) != 0
                    && plan::witness(&A::MASKS, &A::GATED, &A::EXACT, L, BASE, $k).is_some()
            }
            if const { wanted::<A, L, BASE, ENTRY, I>() } {
                // SAFETY: BST copies the witness bit of the saved register into SREG.T, BLD
                // copies T into bit `$d` of `v`; nothing else is touched, and the compiler
                // keeps no value in SREG.T.
                unsafe {
                    core::arch::asm!(
                        "bst {w}, {bit}",
                        "bld {v}, {d}",
                        w = in(reg) f.saved[const { witness_or_none::<A, L, BASE>($k).0 }],
                        bit = const witness_or_none::<A, L, BASE>($k).1,
                        v = inout(reg) v,
                        d = const $d,
                        options(pure, nomem, nostack),
                    )
                };
            }
        }};
    }
    macro_rules! level {
        ($k:literal) => {
            copy!($k, 0);
            copy!($k, 1);
            copy!($k, 2);
            copy!($k, 3);
            copy!($k, 4);
            copy!($k, 5);
            copy!($k, 6);
            copy!($k, 7);
        };
    }
    level!(1);
    level!(2);
    level!(3);
    level!(4);
    level!(5);
    level!(6);
    level!(7);
    v
}

/// Clears bits `m` of `reg` (index `i`) and records in `f` what to put back.
///
/// # Safety
/// As for [`open`].
#[inline(always)]
unsafe fn save_and_clear<A: App>(f: &mut Frame, i: usize, reg: Reg, m: u8) {
    let gated = A::GATED.get(i) & m;
    // SAFETY: see the contract of `open`.
    let old = unsafe { read(reg) };
    // SAFETY: as above.
    unsafe { write(reg, bits::masked(reg, old, m)) };
    f.saved[i] = if A::EXACT[i] { old } else { old & m & !gated };
    if gated != 0 {
        // SAFETY: interrupts are disabled for levels with gated bits (those levels are
        // always atomic, and task entries run with interrupts off).
        let held = unsafe { HELD.get(i) };
        // SAFETY: as above.
        unsafe { HELD.set(i, held | gated) };
        f.held[i] = held;
    }
}

/// Puts back what [`save_and_clear`] recorded for `reg` (index `i`, bits `m`).
///
/// # Safety
/// As for [`close`].
#[inline(always)]
unsafe fn put_back<A: App>(f: &Frame, i: usize, reg: Reg, m: u8) {
    if A::EXACT[i] {
        // SAFETY: see the contract of `close`.
        unsafe { write(reg, f.saved[i]) };
    } else {
        let gated = A::GATED.get(i) & m;
        let mut set = f.saved[i];
        if gated != 0 {
            // SAFETY: interrupts are disabled (locks over gated bits are atomic).
            unsafe { HELD.set(i, f.held[i]) };
            // SAFETY: as above.
            set |= unsafe { WANT.get(i) } & gated & !f.held[i];
        }
        // SAFETY: see the contract of `close`.
        let now = unsafe { read(reg) };
        // SAFETY: as above.
        unsafe { write(reg, bits::unmasked(reg, now, set)) };
    }
}
