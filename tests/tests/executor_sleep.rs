//! Emulator test of `exec_sleep`: idle sleeps between interrupts and wakes on each one.

mod executor_support;

use executor_support::{boot, fields, report};
use harness::CpuState;

#[test]
fn idle_wakes_once_per_interrupt() {
    let mut avr = boot("exec_sleep");
    let line = report(&mut avr, "sleep", 20_000);
    let f = fields(&line);
    assert_eq!(f["ticks"], 10);
    // One wake-up per tick: idle never spun without sleeping.
    assert_eq!(f["wakes"], 10);
}

#[test]
fn cpu_sleeps_between_ticks_and_the_tick_wakes_it() {
    let mut avr = boot("exec_sleep");
    report(&mut avr, "sleep ticks", 20_000);
    // Let the report drain, then watch 20 ms (20 ticks) step by step.
    avr.run_us(5_000);
    let end = avr.micros() + 20_000;
    let (mut steps, mut sleeps, mut wakes) = (0u32, 0u32, 0u32);
    let mut asleep = false;
    while avr.micros() < end {
        steps += 1;
        let state = avr.step();
        if state == CpuState::Sleeping {
            sleeps += 1;
            asleep = true;
        } else if asleep && state == CpuState::Running {
            wakes += 1;
            asleep = false;
        }
    }
    // Each 1-ms tick is one sleep jump, one wake-up and a short burst of instructions;
    // a busy idle would have taken 320 000 steps.
    assert!((19..=21).contains(&sleeps), "{sleeps} sleeps");
    assert!((19..=21).contains(&wakes), "{wakes} wakes");
    assert!(steps < 20 * 200, "{steps} steps");
}
