//! Emulator test of `exec_lock`: a lock with ceiling 2 holds off the tasks at priorities
//! 1 and 2 and lets the tasks at 3 and 4 run inside it.

mod executor_support;

use executor_support::{boot, report};

#[test]
fn lock_holds_off_exactly_the_tasks_at_or_below_its_ceiling() {
    let mut avr = boot("exec_lock");
    let trace = report(&mut avr, "lock trace=", 50_000);
    // L: low starts; [ ]: its lock (ceiling 2). Inside, H (3) and T (4) run at once; M
    // (2, the ceiling) runs at the unlock; P (1, low's own level) after low ends (l).
    assert_eq!(trace, "L[HT]MlP");
}
