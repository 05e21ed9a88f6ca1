//! Emulator tests of halted CPUs: SLEEP with interrupts off (Done) and a jump
//! past flash (Crashed) are reported, not spun on.

use harness::{Avr, CpuState, HarnessError};

#[test]
fn sleep_with_interrupts_off_is_done() {
    let mut avr = Avr::firmware("fixture_halt").unwrap();
    assert_eq!(avr.uart_read_until(b"\r\n", 10_000).unwrap(), b"halt\r\n");
    assert!(!avr.run_until(1_000_000, |_| false));
    assert_eq!(avr.state(), CpuState::Done);
    assert!(avr.micros() < 10_000, "stopped at {} µs", avr.micros());
    match avr.uart_read_until(b"more", 1_000) {
        Err(HarnessError::Halted { state, .. }) => assert_eq!(state, CpuState::Done),
        other => panic!("unexpected {other:?}"),
    }
}

#[test]
fn jump_past_flash_is_crashed() {
    let mut avr = Avr::firmware("fixture_crash").unwrap();
    assert_eq!(avr.uart_read_until(b"\r\n", 10_000).unwrap(), b"crash\r\n");
    avr.run_us(100_000);
    assert_eq!(avr.state(), CpuState::Crashed);
    let at = avr.micros();
    avr.run_us(100_000);
    assert_eq!(avr.micros(), at, "a crashed CPU does not advance");
    let err = avr.uart_read_exact(1, 1_000).unwrap_err();
    assert!(err.to_string().contains("Crashed"), "{err}");
}
