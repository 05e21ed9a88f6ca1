//! Emulator test of `exec_preempt`: a high-priority task preempts a low-priority task in
//! the middle of its run, and an event of the running task's own level waits for it.

mod executor_support;

use executor_support::{boot, report};

#[test]
fn high_task_lands_mid_way_through_low_task() {
    let mut avr = boot("exec_preempt");
    let trace = report(&mut avr, "preempt trace=", 50_000);
    // L: low starts; H: high preempts it; l: low finishes; then low's own event, which
    // arrived while low ran, runs low again (L l) instead of nesting inside it.
    assert_eq!(trace, "LHlLl");
}
