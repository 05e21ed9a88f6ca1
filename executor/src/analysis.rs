//! Compile-time analysis of an application: resource ceilings and per-level source masks.
//!
//! Everything here is a `const fn` over the task table that [`crate::app!`] writes, so the
//! results are constants in the firmware (no table is ever walked at run time), and the
//! same functions are unit-tested on the host.
//!
//! - The **ceiling** of a resource is the highest priority of the tasks that use it
//!   (idle counts as priority 0).
//! - The **mask of level L** is, per enable register, the enable bits of every source
//!   bound to a task of priority 1..=L. Running at level L (inside a task of priority L or
//!   a lock with ceiling L) means exactly those bits are clear.
//! - The **top** level is the highest task priority. Tasks at the top run with the global
//!   interrupt flag clear, and locks with the top ceiling clear it too, so the top level
//!   needs no mask.

use crate::source::{Source, REG_COUNT};

/// Highest priority a task may have.
pub const MAX_PRIORITY: u8 = 7;

/// Number of levels, 0 (idle) to [`MAX_PRIORITY`]: the length of [`LevelMasks`].
pub const LEVELS: usize = MAX_PRIORITY as usize + 1;

/// One bit set per enable register (indexed by [`crate::source::Reg::index`]).
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct RegBits(pub [u8; REG_COUNT]);

impl RegBits {
    /// No bit in any register.
    pub const EMPTY: RegBits = RegBits([0; REG_COUNT]);

    /// The bits of register index `reg`.
    pub const fn get(&self, reg: usize) -> u8 {
        self.0[reg]
    }

    /// This set plus the enable bit of `source`.
    pub const fn with(mut self, source: Source) -> RegBits {
        let r = source.reg().index();
        self.0[r] |= source.bit();
        self
    }

    /// True when no register has a bit set.
    pub const fn is_empty(&self) -> bool {
        let mut r = 0;
        while r < REG_COUNT {
            if self.0[r] != 0 {
                return false;
            }
            r += 1;
        }
        true
    }

    /// True when `source`'s enable bit is in the set.
    pub const fn contains(&self, source: Source) -> bool {
        self.0[source.reg().index()] & source.bit() != 0
    }
}

/// The mask of every level, 0..=[`MAX_PRIORITY`].
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct LevelMasks(pub [RegBits; LEVELS]);

impl LevelMasks {
    /// The enable bits that are clear while the system runs at `level`.
    pub const fn level(&self, level: u8) -> RegBits {
        self.0[level as usize]
    }
}

/// One entry of an application's task table: a hardware task, or idle.
#[derive(Clone, Copy, Debug)]
pub struct Task {
    /// The interrupt source the task is bound to; `None` for idle.
    pub binds: Option<Source>,
    /// Static priority: 1..=[`MAX_PRIORITY`] for hardware tasks, 0 for idle.
    pub priority: u8,
    /// Indices of the shared resources the task uses.
    pub shared: &'static [u8],
    /// Indices of the local resources the task owns.
    pub local: &'static [u8],
    /// True when drivers switch the source on and off at run time ([`crate::gate`]).
    pub gated: bool,
}

/// A mistake in an application declaration, reported at compile time.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum DeclError {
    /// A task bound to an interrupt has priority 0, which is idle's.
    PriorityZero,
    /// A task's priority is above [`MAX_PRIORITY`].
    PriorityTooHigh,
    /// Two tasks are bound to the same interrupt source.
    SourceBoundTwice,
    /// A local resource is listed by more than one task (share it instead).
    LocalUsedTwice,
    /// A resource index is outside the declared resources (a bug in the declaration macro).
    NoSuchResource,
}

impl DeclError {
    /// The message shown by the compiler.
    pub const fn message(self) -> &'static str {
        match self {
            DeclError::PriorityZero => {
                "executor: a task bound to an interrupt needs priority 1 or more (0 is idle's)"
            }
            DeclError::PriorityTooHigh => "executor: task priority above executor::MAX_PRIORITY",
            DeclError::SourceBoundTwice => "executor: two tasks are bound to the same interrupt",
            DeclError::LocalUsedTwice => {
                "executor: a local resource belongs to one task only; make it shared instead"
            }
            DeclError::NoSuchResource => "executor: resource index out of range",
        }
    }
}

/// The highest priority of the hardware tasks (0 when there are none).
pub const fn top(tasks: &[Task]) -> u8 {
    let mut top = 0;
    let mut i = 0;
    while i < tasks.len() {
        if tasks[i].binds.is_some() && tasks[i].priority > top {
            top = tasks[i].priority;
        }
        i += 1;
    }
    top
}

/// True when `list` contains `x`.
const fn listed(list: &[u8], x: u8) -> bool {
    let mut i = 0;
    while i < list.len() {
        if list[i] == x {
            return true;
        }
        i += 1;
    }
    false
}

/// The ceiling of shared resource `resource`: the highest priority of the tasks using it.
pub const fn ceiling(tasks: &[Task], resource: u8) -> u8 {
    let mut c = 0;
    let mut i = 0;
    while i < tasks.len() {
        if listed(tasks[i].shared, resource) && tasks[i].priority > c {
            c = tasks[i].priority;
        }
        i += 1;
    }
    c
}

/// How many tasks use shared resource `resource`.
pub const fn users(tasks: &[Task], resource: u8) -> usize {
    let mut n = 0;
    let mut i = 0;
    while i < tasks.len() {
        if listed(tasks[i].shared, resource) {
            n += 1;
        }
        i += 1;
    }
    n
}

/// The masks of every level: level L clears the enable bits of the sources bound to
/// tasks of priority 1..=L. Levels at or above the top are empty (the global flag does
/// their work), and so is level 0.
pub const fn level_masks(tasks: &[Task]) -> LevelMasks {
    let top = top(tasks);
    let mut masks = [RegBits::EMPTY; LEVELS];
    let mut level = 1;
    while level < LEVELS {
        if (level as u8) < top {
            let mut i = 0;
            while i < tasks.len() {
                if let Some(s) = tasks[i].binds {
                    if tasks[i].priority as usize <= level {
                        masks[level] = masks[level].with(s);
                    }
                }
                i += 1;
            }
        }
        level += 1;
    }
    LevelMasks(masks)
}

/// The sources the executor enables at start: every bound source that is not gated.
pub const fn start_bits(tasks: &[Task]) -> RegBits {
    let mut bits = RegBits::EMPTY;
    let mut i = 0;
    while i < tasks.len() {
        if let Some(s) = tasks[i].binds {
            if !tasks[i].gated {
                bits = bits.with(s);
            }
        }
        i += 1;
    }
    bits
}

/// The gated sources: their enable bits follow [`crate::gate::arm`]/`disarm` requests.
pub const fn gated_bits(tasks: &[Task]) -> RegBits {
    let mut bits = RegBits::EMPTY;
    let mut i = 0;
    while i < tasks.len() {
        if let Some(s) = tasks[i].binds {
            if tasks[i].gated {
                bits = bits.with(s);
            }
        }
        i += 1;
    }
    bits
}

/// Per register: true when a saved value may be written back verbatim at the end of a
/// masking frame, because the register holds only enable bits and none of them is gated.
/// Otherwise the frame re-reads the register and puts back only the bits it cleared.
pub const fn exact_restore(gated: &RegBits) -> [bool; REG_COUNT] {
    let mut exact = [false; REG_COUNT];
    let mut r = 0;
    while r < REG_COUNT {
        exact[r] = crate::source::REGS[r].is_pure() && gated.0[r] == 0;
        r += 1;
    }
    exact
}

/// The enable bits a lock with ceiling `ceiling` clears when taken by a task of priority
/// `base`: the levels above the task's own, up to the ceiling. The task's own level and
/// those below it are already masked by the task's entry (idle has none to mask).
pub const fn lock_mask(masks: &LevelMasks, ceiling: u8, base: u8) -> RegBits {
    let top = masks.level(ceiling);
    let below = masks.level(base);
    let mut bits = RegBits::EMPTY;
    let mut r = 0;
    while r < REG_COUNT {
        bits.0[r] = top.0[r] & !below.0[r];
        r += 1;
    }
    bits
}

/// True when a lock with ceiling `ceiling`, taken at priority `base`, must clear the global
/// flag while it rewrites enable registers, for either of two reasons:
///
/// - one of them may also be written by a task above the ceiling (a driver's bits, or a
///   gated source being armed), whose write a preempted read-modify-write would undo;
/// - a level it masks has sources in two registers. Between the two writes, the source
///   not yet masked can fire, and its task's exit enables its whole level again (a task
///   entered by its own source knows that level was enabled, so it saves nothing for it):
///   the lock would then run with the first source enabled (`exec_lock_split`).
///
/// Otherwise the registers hold only ungated bits of one level each, and any task that
/// preempts the rewrite leaves them as it found them.
pub const fn atomic_lock(masks: &LevelMasks, gated: &RegBits, ceiling: u8, base: u8) -> bool {
    let exact = exact_restore(gated);
    let bits = lock_mask(masks, ceiling, base);
    let mut r = 0;
    while r < REG_COUNT {
        if bits.0[r] != 0 && !exact[r] {
            return true;
        }
        r += 1;
    }
    let mut k = base + 1;
    while k <= ceiling {
        if level_registers(masks, gated, k) > 1 {
            return true;
        }
        k += 1;
    }
    false
}

/// How many enable registers hold ungated sources of level `k` (a register with a gated
/// one is never exact, so the lock is atomic for it already).
const fn level_registers(masks: &LevelMasks, gated: &RegBits, k: u8) -> u8 {
    let mut n = 0;
    let mut r = 0;
    while r < REG_COUNT {
        if crate::plan::level_bits(masks, gated, k, r) != 0 {
            n += 1;
        }
        r += 1;
    }
    n
}

/// Checks a declaration: priorities in range, each source bound once, each local
/// resource owned by one task, resource indices in range.
pub const fn validate(tasks: &[Task], shared: usize, local: usize) -> Result<(), DeclError> {
    let mut i = 0;
    while i < tasks.len() {
        let t = &tasks[i];
        if t.priority > MAX_PRIORITY {
            return Err(DeclError::PriorityTooHigh);
        }
        if let Some(s) = t.binds {
            if t.priority == 0 {
                return Err(DeclError::PriorityZero);
            }
            let mut j = i + 1;
            while j < tasks.len() {
                if let Some(o) = tasks[j].binds {
                    if o.vector() == s.vector() {
                        return Err(DeclError::SourceBoundTwice);
                    }
                }
                j += 1;
            }
        }
        let mut k = 0;
        while k < t.shared.len() {
            if t.shared[k] as usize >= shared {
                return Err(DeclError::NoSuchResource);
            }
            k += 1;
        }
        k = 0;
        while k < t.local.len() {
            if t.local[k] as usize >= local {
                return Err(DeclError::NoSuchResource);
            }
            let mut j = i + 1;
            while j < tasks.len() {
                if listed(tasks[j].local, t.local[k]) {
                    return Err(DeclError::LocalUsedTwice);
                }
                j += 1;
            }
            k += 1;
        }
        i += 1;
    }
    Ok(())
}

/// [`validate`], turning a mistake into a compile error with its message.
pub const fn assert_valid(tasks: &[Task], shared: usize, local: usize) {
    if let Err(e) = validate(tasks, shared, local) {
        panic!("{}", e.message());
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::source::Reg;

    const fn task(binds: Source, priority: u8, shared: &'static [u8]) -> Task {
        Task {
            binds: Some(binds),
            priority,
            shared,
            local: &[],
            gated: false,
        }
    }

    const IDLE: Task = Task {
        binds: None,
        priority: 0,
        shared: &[0],
        local: &[],
        gated: false,
    };

    /// A slave-like app: ADC and the tick at 1, TWI at 2, the encoder at 3 (top).
    const SLAVE: [Task; 5] = [
        task(Source::ADC, 1, &[0, 1]),
        task(Source::TIMER2_COMPA, 1, &[1]),
        task(Source::TWI, 2, &[1, 2]),
        task(Source::PCINT2, 3, &[2]),
        IDLE,
    ];

    #[test]
    fn ceiling_is_the_highest_user_priority() {
        assert_eq!(ceiling(&SLAVE, 0), 1); // ADC + idle
        assert_eq!(ceiling(&SLAVE, 1), 2); // ADC, tick, TWI
        assert_eq!(ceiling(&SLAVE, 2), 3); // TWI, encoder
        assert_eq!(ceiling(&SLAVE, 3), 0); // nobody
        assert_eq!(users(&SLAVE, 1), 3);
        assert_eq!(users(&SLAVE, 3), 0);
    }

    #[test]
    fn ceiling_is_computed_at_compile_time() {
        const C: u8 = ceiling(&SLAVE, 2);
        const _: () = assert!(C == 3);
        assert_eq!(C, 3);
    }

    #[test]
    fn top_is_the_highest_task_priority_and_ignores_idle() {
        assert_eq!(top(&SLAVE), 3);
        assert_eq!(top(&[IDLE]), 0);
    }

    #[test]
    fn level_masks_accumulate_upwards_and_stop_below_the_top() {
        let m = level_masks(&SLAVE);
        let adcsra = Reg::Adcsra.index();
        let timsk2 = Reg::Timsk2.index();
        let twcr = Reg::Twcr.index();
        let pcicr = Reg::Pcicr.index();
        assert!(m.level(0).is_empty());
        assert_eq!(m.level(1).get(adcsra), 1 << 3);
        assert_eq!(m.level(1).get(timsk2), 1 << 1);
        assert_eq!(m.level(1).get(twcr), 0);
        assert_eq!(m.level(2).get(adcsra), 1 << 3);
        assert_eq!(m.level(2).get(timsk2), 1 << 1);
        assert_eq!(m.level(2).get(twcr), 1);
        // Level 2 never masks the top-priority encoder.
        assert_eq!(m.level(2).get(pcicr), 0);
        // The top level and above use the global flag.
        for l in 3..=MAX_PRIORITY {
            assert!(m.level(l).is_empty(), "level {l}");
        }
    }

    #[test]
    fn same_priority_sources_share_a_level_and_hold_each_other_off() {
        let tasks = [
            task(Source::PCINT0, 1, &[]),
            task(Source::PCINT1, 1, &[]),
            task(Source::INT0, 2, &[]),
        ];
        let m = level_masks(&tasks);
        assert_eq!(m.level(1).get(Reg::Pcicr.index()), 0b011);
        assert_eq!(m.level(1).get(Reg::Eimsk.index()), 0);
    }

    #[test]
    fn start_and_gated_bits_split_the_sources() {
        let mut tasks = SLAVE;
        tasks[2].gated = true;
        let start = start_bits(&tasks);
        let gated = gated_bits(&tasks);
        assert!(gated.contains(Source::TWI));
        assert!(!start.contains(Source::TWI));
        assert!(start.contains(Source::ADC));
        assert!(start.contains(Source::PCINT2));
        assert!(!gated.contains(Source::ADC));
    }

    #[test]
    fn exact_restore_only_for_pure_ungated_registers() {
        let gated = RegBits::EMPTY.with(Source::TIMER1_COMPB);
        let exact = exact_restore(&gated);
        assert!(exact[Reg::Pcicr.index()]);
        assert!(exact[Reg::Timsk2.index()]);
        assert!(!exact[Reg::Timsk1.index()]);
        assert!(!exact[Reg::Twcr.index()]);
        assert!(!exact[Reg::Adcsra.index()]);
    }

    #[test]
    fn a_lock_masks_only_the_levels_above_its_task() {
        let m = level_masks(&SLAVE);
        // From idle, ceiling 2 clears everything at levels 1 and 2.
        let from_idle = lock_mask(&m, 2, 0);
        assert_eq!(from_idle, m.level(2));
        // From a level-1 task, only TWI (level 2) is left to clear.
        let from_task = lock_mask(&m, 2, 1);
        assert_eq!(from_task.get(Reg::Twcr.index()), Source::TWI.bit());
        assert_eq!(from_task.get(Reg::Adcsra.index()), 0);
        assert_eq!(from_task.get(Reg::Timsk2.index()), 0);
    }

    #[test]
    fn locks_over_driver_registers_are_atomic() {
        let m = level_masks(&SLAVE);
        let g = gated_bits(&SLAVE);
        assert!(atomic_lock(&m, &g, 1, 0)); // ADCSRA
        assert!(atomic_lock(&m, &g, 2, 1)); // TWCR
        let pins = [
            task(Source::PCINT0, 1, &[]),
            task(Source::TIMER1_COMPA, 2, &[]),
            task(Source::INT0, 3, &[]),
        ];
        let m = level_masks(&pins);
        // PCICR and TIMSK1 only: written by nobody but the executor.
        assert!(!atomic_lock(&m, &gated_bits(&pins), 2, 0));
        // Unless a source in them is gated.
        let mut gated = pins;
        gated[1].gated = true;
        assert!(atomic_lock(&level_masks(&gated), &gated_bits(&gated), 2, 0));
    }

    #[test]
    fn locks_over_a_level_split_across_registers_are_atomic() {
        // exec_lock_split's layout: level 1 in EIMSK (INT1) and PCICR (PCINT0).
        let split = [
            task(Source::INT1, 1, &[]),
            task(Source::PCINT0, 1, &[]),
            task(Source::TIMER2_COMPA, 2, &[]),
        ];
        let m = level_masks(&split);
        let g = gated_bits(&split);
        assert!(atomic_lock(&m, &g, 1, 0));
        // From level 1 a lock of ceiling 2 masks only level 2, in one register.
        assert!(!atomic_lock(&m, &g, 2, 1));
        // Two levels in two registers, one each: each level is cleared by one write.
        let one_each = [
            task(Source::INT1, 1, &[]),
            task(Source::PCINT0, 2, &[]),
            task(Source::TIMER2_COMPA, 3, &[]),
        ];
        let m = level_masks(&one_each);
        assert!(!atomic_lock(&m, &gated_bits(&one_each), 2, 0));
        // Both levels of the split layout, from idle.
        let split_two = [
            task(Source::INT1, 1, &[]),
            task(Source::PCINT0, 2, &[]),
            task(Source::TIMER1_COMPA, 2, &[]),
            task(Source::TIMER2_COMPA, 3, &[]),
        ];
        let m = level_masks(&split_two);
        let g = gated_bits(&split_two);
        assert!(atomic_lock(&m, &g, 2, 0));
        assert!(atomic_lock(&m, &g, 2, 1));
        assert!(!atomic_lock(&m, &g, 1, 0));
    }

    #[test]
    fn validation_catches_each_mistake() {
        assert_eq!(validate(&SLAVE, 3, 0), Ok(()));
        assert_eq!(
            validate(&[task(Source::ADC, 0, &[])], 0, 0),
            Err(DeclError::PriorityZero)
        );
        assert_eq!(
            validate(&[task(Source::ADC, 8, &[])], 0, 0),
            Err(DeclError::PriorityTooHigh)
        );
        assert_eq!(
            validate(
                &[task(Source::ADC, 1, &[]), task(Source::ADC, 2, &[])],
                0,
                0
            ),
            Err(DeclError::SourceBoundTwice)
        );
        assert_eq!(validate(&SLAVE, 2, 0), Err(DeclError::NoSuchResource));
        let mut a = task(Source::ADC, 1, &[]);
        let mut b = task(Source::TWI, 2, &[]);
        a.local = &[0];
        b.local = &[0];
        assert_eq!(validate(&[a, b], 0, 1), Err(DeclError::LocalUsedTwice));
        b.local = &[1];
        assert_eq!(validate(&[a, b], 0, 2), Ok(()));
    }
}
