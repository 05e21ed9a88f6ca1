//! Pin changes set ahead for a given cycle ([`Avr::set_pin_at`]): one simavr cycle timer per
//! chip applies each at its cycle while the chip runs, so a caller need not stop the chip
//! there (the physics' encoder edges, which would otherwise split every bus run).

use std::ffi::c_void;

use simavr_ffi as ffi;

use crate::avr::Shared;
use crate::{Avr, Pin};

/// One pin change waiting for its cycle.
pub(crate) struct PinChange {
    /// Absolute cycle (monotonic across resets) it is due at.
    pub at: u64,
    /// The pin's IRQ in the chip's core.
    pub irq: *mut ffi::avr_irq_t,
    pub high: bool,
}

impl Avr {
    /// Drives input `pin` to `high` at absolute cycle `at` ([`Avr::cycles`]) while the chip
    /// runs, exactly there (also inside a sleep); at once if `at` has passed. Changes due at
    /// the same cycle are applied in the order they were set.
    pub fn set_pin_at(&mut self, pin: Pin, high: bool, at: u64) {
        if at <= self.cycles() {
            self.set_pin(pin, high);
            return;
        }
        let irq = self.pin_irq(pin);
        if irq.is_null() {
            return;
        }
        {
            let mut queue = self.shared.pin_changes.borrow_mut();
            let index = queue.partition_point(|c| c.at <= at);
            queue.insert(index, PinChange { at, irq, high });
        }
        self.arm_pin_timer();
    }

    /// (Re)registers the pin timer for the first change queued, if any.
    pub(crate) fn arm_pin_timer(&mut self) {
        let shared = &self.shared;
        let Some(first) = shared.pin_changes.borrow().front().map(|c| c.at) else {
            return;
        };
        let delay = first.saturating_sub(shared.now()).max(1);
        let param = std::ptr::from_ref::<Shared>(shared).cast_mut().cast();
        // SAFETY: the live core owns the timer list; `param` is the boxed `Shared`, which
        // outlives the core's timers; registering again moves the one already queued.
        unsafe {
            ffi::avr_cycle_timer_register(self.raw.as_ptr(), delay, Some(on_pin_timer), param);
        }
    }
}

/// simavr's cycle timer for queued pin changes: applies every change due, then asks to run
/// again at the next one.
unsafe extern "C" fn on_pin_timer(
    _avr: *mut ffi::avr_t,
    _when: ffi::avr_cycle_count_t,
    param: *mut c_void,
) -> ffi::avr_cycle_count_t {
    // SAFETY: `param` is the `Shared` box registered in `arm_pin_timer`, alive as long as
    // the core; only shared references to it are made.
    let shared = unsafe { &*param.cast::<Shared>() };
    let now = shared.now();
    loop {
        // The queue is not borrowed while the IRQ runs its hooks (they may trace the pin).
        let due = {
            let mut queue = shared.pin_changes.borrow_mut();
            match queue.front() {
                Some(c) if c.at <= now => queue.pop_front(),
                _ => None,
            }
        };
        let Some(change) = due else {
            break;
        };
        // SAFETY: `irq` is a pin IRQ of this core, which is running this timer.
        unsafe { ffi::avr_raise_irq(change.irq, u32::from(change.high)) };
    }
    let next = shared.pin_changes.borrow().front().map(|c| c.at);
    // simavr wants the raw cycle of the next run (its counter restarts at each reset).
    next.map_or(0, |at| at.saturating_sub(shared.base.get()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::uno;

    /// A core whose program is one `rjmp .-2` (2 cycles, forever).
    fn spinning() -> Avr {
        let mut avr = Avr::blank().unwrap();
        let mut code = [0xFF, 0xCF];
        // SAFETY: the core is live and idle; simavr copies the two bytes into flash.
        unsafe { ffi::avr_loadcode(avr.as_ptr(), code.as_mut_ptr(), 2, 0) };
        avr
    }

    #[test]
    fn changes_land_on_their_cycles_within_one_run() {
        let mut avr = spinning();
        avr.trace_pin(uno::D2);
        avr.set_pin_at(uno::D2, false, 1_500);
        avr.set_pin_at(uno::D2, true, 1_000);
        avr.set_pin_at(uno::D2, true, 900);
        assert_eq!(avr.shared.pin_changes.borrow().len(), 3);
        avr.run_cycles(2_000);
        let trace = avr.pin_trace(uno::D2);
        // The first entry is the level when tracing started; a change lands on the first
        // instruction boundary at or after its cycle (this program's are 2 cycles apart).
        let changes: Vec<(u64, bool)> = trace[1..].to_vec();
        assert_eq!(changes.len(), 2, "{trace:?}");
        assert!(
            (900..902).contains(&changes[0].0) && changes[0].1,
            "{changes:?}"
        );
        assert!(
            (1_500..1_502).contains(&changes[1].0) && !changes[1].1,
            "{changes:?}"
        );
        assert!(avr.shared.pin_changes.borrow().is_empty());
        assert!(!avr.pin(uno::D2));
    }

    #[test]
    fn a_change_already_due_applies_at_once() {
        let mut avr = spinning();
        avr.run_cycles(100);
        avr.set_pin_at(uno::D2, true, 50);
        assert!(avr.pin(uno::D2));
        assert!(avr.shared.pin_changes.borrow().is_empty());
    }
}
