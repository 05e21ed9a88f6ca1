//! Emulator test of `exec_twi_mask`: masking the TWI task never clears a pending TWINT.

mod executor_support;

use executor_support::{boot, fields, report};

#[test]
fn a_pending_twi_event_survives_the_lock_and_runs_the_task_after_it() {
    let mut avr = boot("exec_twi_mask");
    let f = fields(&report(&mut avr, "twimask", 50_000));
    // The START completed inside the lock and TWINT was still set after a nested
    // mask/unmask of TWCR.
    assert_eq!(f["pending_in_lock"], 1, "{f:?}");
    // The TWI task (priority 2 = the lock's ceiling) did not run inside the lock...
    assert_eq!(f["ran_inside"], 0);
    // ...and ran exactly once after it, seeing "START transmitted".
    assert_eq!(f["ran_after"], 1);
    assert_eq!(f["status"], 0x08);
}

#[test]
fn the_naive_read_modify_write_loses_the_event() {
    // The same emulator does model the trap, so the first test is not vacuous.
    let mut avr = boot("exec_twi_mask");
    let f = fields(&report(&mut avr, "twimask", 50_000));
    assert_eq!(f["naive_twint"], 0);
    assert_eq!(f["naive_ran"], 0);
}
