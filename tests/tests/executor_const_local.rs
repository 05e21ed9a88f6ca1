//! Emulator test of `exec_const_local`: local resources declared with their values are in
//! place from reset without `init` and keep their state between a task's runs.

mod executor_support;

use executor_support::{boot, fields, report};

#[test]
fn const_locals_start_at_their_declared_values_and_keep_state() {
    let mut avr = boot("exec_const_local");
    // Idle's non-zero const local (`.data`), printed before any task ran.
    assert_eq!(report(&mut avr, "exec_const_local", 50_000), "ready");
    let line = report(&mut avr, "const_local", 50_000);
    let f = fields(&line);
    // `bump`'s count started at 1000 and went up by one per run, across three runs.
    assert_eq!(f["first"], 1000, "{line}");
    assert_eq!(f["last"], 1002, "{line}");
    assert_eq!(f["runs"], 3, "{line}");
    // Idle's own counter started at 40 and was bumped once per trigger.
    assert_eq!(f["fired"], 43, "{line}");
}
