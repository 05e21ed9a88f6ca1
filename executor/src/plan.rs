//! How a masking frame treats each enable register: compile-time logic, tested on the host.
//!
//! A frame of level `l` over base level `base` clears the enable bits of levels
//! `base+1..=l` (a task's entry has base 0; a lock taken by a task of priority `p` has base
//! `p`, since the task's entry already masked its own levels). To put them back it must
//! know which of them were set when it began. All sources of one level are masked
//! together, so one bit per level tells for the whole level:
//!
//! - an **exact** register (only ungated enable bits) is saved whole and written back
//!   whole; its bits are *witnesses* of their levels;
//! - at a task's **entry**, its own level was enabled (its source just fired), so the bits
//!   of that level need no witness;
//! - any other register is **derived**: re-read at the end, with each level's bits set
//!   if that level's witness was set, and nothing saved; or, when some level has no
//!   witness (or the register holds gated bits), **saved**: the bits to put back are kept
//!   in the frame.

use crate::analysis::{LevelMasks, RegBits};
use crate::source::REG_COUNT;

/// How a frame handles one register.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Plan {
    /// The frame clears nothing in it.
    Untouched,
    /// Saved whole and written back whole; a witness of the levels it holds.
    Exact,
    /// Restored from witnesses (and, at a task's entry, from the task's own level).
    Derived,
    /// The cleared bits (and the gated bits already held) are saved in the frame.
    Saved,
}

/// The enable bits a frame of level `l` over `base` clears in register `i`.
pub const fn frame_bits(masks: &LevelMasks, l: u8, base: u8, i: usize) -> u8 {
    masks.level(l).get(i) & !masks.level(base).get(i)
}

/// The ungated enable bits of level `k` alone in register `i`.
pub const fn level_bits(masks: &LevelMasks, gated: &RegBits, k: u8, i: usize) -> u8 {
    let below = if k == 0 { 0 } else { masks.level(k - 1).get(i) };
    masks.level(k).get(i) & !below & !gated.get(i)
}

/// A witness of level `k` in a frame of level `l` over `base`: the first exact register the
/// frame saves that holds a bit of level `k`, and that bit's number.
pub const fn witness(
    masks: &LevelMasks,
    gated: &RegBits,
    exact: &[bool; REG_COUNT],
    l: u8,
    base: u8,
    k: u8,
) -> Option<(usize, u8)> {
    let mut i = 0;
    while i < REG_COUNT {
        let bits = level_bits(masks, gated, k, i);
        if exact[i] && frame_bits(masks, l, base, i) != 0 && bits != 0 {
            return Some((i, bits.trailing_zeros() as u8));
        }
        i += 1;
    }
    None
}

/// The plan for register `i` in a frame of level `l` over `base`; `entry` is true for a
/// task's own entry (where `base` is 0).
pub const fn plan(
    masks: &LevelMasks,
    gated: &RegBits,
    exact: &[bool; REG_COUNT],
    l: u8,
    base: u8,
    entry: bool,
    i: usize,
) -> Plan {
    let m = frame_bits(masks, l, base, i);
    if m == 0 {
        return Plan::Untouched;
    }
    if m & gated.get(i) != 0 {
        return Plan::Saved;
    }
    // At a task's entry, a register holding only bits of the task's own level needs no
    // saving at all (and is never a witness: it holds no lower level).
    if entry && level_bits(masks, gated, l, i) == m {
        return Plan::Derived;
    }
    if exact[i] {
        return Plan::Exact;
    }
    let mut k = base + 1;
    while k <= l {
        let known = entry && k == l;
        if level_bits(masks, gated, k, i) != 0
            && !known
            && witness(masks, gated, exact, l, base, k).is_none()
        {
            return Plan::Saved;
        }
        k += 1;
    }
    Plan::Derived
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::{exact_restore, gated_bits, level_masks, Task};
    use crate::source::{Reg, Source};

    const fn task(binds: Source, priority: u8, gated: bool) -> Task {
        Task {
            binds: Some(binds),
            priority,
            shared: &[],
            local: &[],
            gated,
        }
    }

    /// The benchmark's layout: level 1 PCINT0 + ADC, level 2 PCINT1 + TWI, top INT0.
    const BENCH: [Task; 5] = [
        task(Source::PCINT0, 1, false),
        task(Source::ADC, 1, false),
        task(Source::PCINT1, 2, false),
        task(Source::TWI, 2, false),
        task(Source::INT0, 3, false),
    ];

    fn plans(tasks: &[Task], l: u8, base: u8, entry: bool) -> Vec<(Reg, Plan)> {
        let masks = level_masks(tasks);
        let gated = gated_bits(tasks);
        let exact = exact_restore(&gated);
        crate::source::REGS
            .iter()
            .map(|&r| (r, plan(&masks, &gated, &exact, l, base, entry, r.index())))
            .filter(|(_, p)| *p != Plan::Untouched)
            .collect()
    }

    #[test]
    fn level_one_entry_saves_nothing() {
        assert_eq!(
            plans(&BENCH, 1, 0, true),
            [(Reg::Pcicr, Plan::Derived), (Reg::Adcsra, Plan::Derived)]
        );
    }

    #[test]
    fn level_two_entry_saves_one_witness_for_level_one() {
        assert_eq!(
            plans(&BENCH, 2, 0, true),
            [
                (Reg::Pcicr, Plan::Exact),
                (Reg::Adcsra, Plan::Derived),
                (Reg::Twcr, Plan::Derived)
            ]
        );
        let masks = level_masks(&BENCH);
        let gated = gated_bits(&BENCH);
        let exact = exact_restore(&gated);
        // PCIE0 (bit 0 of PCICR) tells whether level 1 was enabled.
        assert_eq!(
            witness(&masks, &gated, &exact, 2, 0, 1),
            Some((Reg::Pcicr.index(), 0))
        );
        // PCIE1 for level 2.
        assert_eq!(
            witness(&masks, &gated, &exact, 2, 0, 2),
            Some((Reg::Pcicr.index(), 1))
        );
    }

    #[test]
    fn a_lock_from_idle_derives_from_witnesses_of_every_level() {
        assert_eq!(
            plans(&BENCH, 2, 0, false),
            [
                (Reg::Pcicr, Plan::Exact),
                (Reg::Adcsra, Plan::Derived),
                (Reg::Twcr, Plan::Derived)
            ]
        );
    }

    #[test]
    fn a_lock_from_a_task_touches_only_the_levels_above_it() {
        assert_eq!(
            plans(&BENCH, 2, 1, false),
            [(Reg::Pcicr, Plan::Exact), (Reg::Twcr, Plan::Derived)]
        );
    }

    #[test]
    fn without_a_witness_the_register_is_saved() {
        // Level 1: ADC; level 2: TWI; top: PCINT2. No exact register below the top.
        let tasks = [
            task(Source::ADC, 1, false),
            task(Source::TWI, 2, false),
            task(Source::PCINT2, 3, false),
        ];
        assert_eq!(
            plans(&tasks, 2, 0, true),
            [(Reg::Adcsra, Plan::Saved), (Reg::Twcr, Plan::Derived)]
        );
        assert_eq!(
            plans(&tasks, 2, 0, false),
            [(Reg::Adcsra, Plan::Saved), (Reg::Twcr, Plan::Saved)]
        );
    }

    #[test]
    fn gated_bits_are_always_saved() {
        let tasks = [
            task(Source::TIMER1_COMPA, 1, false),
            task(Source::USART_UDRE, 1, true),
            task(Source::USART_RX, 2, false),
        ];
        assert_eq!(
            plans(&tasks, 1, 0, true),
            [(Reg::Timsk1, Plan::Derived), (Reg::Ucsr0b, Plan::Saved)]
        );
    }
}
