//! Emulator test of `exec_nested_lock`: each unlock releases exactly its own level, and a
//! masked lock nested in a top-ceiling lock leaves interrupts off.

mod executor_support;

use executor_support::{boot, report};

#[test]
fn nested_locks_release_level_by_level() {
    let mut avr = boot("exec_nested_lock");
    let trace = report(&mut avr, "nested trace=", 50_000);
    // ( a: ceiling 2 [ b: ceiling 3 ] → H runs at b's unlock, inside a ) → M runs.
    // { trace: top ceiling ( a ) } → T then H run only after the outer unlock; l: low ends.
    assert_eq!(trace, "L([]H)M{()}THl");
}
