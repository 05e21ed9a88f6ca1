//! Emulator test of `exec_gate`: a gated source (USART_UDRE) is armed and disarmed by its
//! driver from inside masked frames, and masking never turns it back on by itself.

mod executor_support;

use executor_support::boot;
use harness::CpuState;

#[test]
fn every_queued_byte_is_sent_and_the_source_ends_off() {
    let mut avr = boot("exec_gate");
    let text = avr.uart_read_until(b"done\n", 100_000).unwrap();
    assert_eq!(
        String::from_utf8_lossy(&text),
        "gate start\ntick 1\ntick 2\ntick 3\ntick 4\ntick 5\ndone\n"
    );
    // Disarmed for good: no data-register-empty storm, the CPU sleeps.
    avr.run_us(1_000);
    let end = avr.micros() + 10_000;
    let mut steps = 0u32;
    while avr.micros() < end && avr.step() != CpuState::Sleeping {
        steps += 1;
    }
    assert!(steps < 100, "still busy after {steps} steps");
    assert!(avr.uart_take().is_empty());
    // UCSR0B (0xC1): transmitter on, UDRIE0 off.
    assert_eq!(avr.read_data(0xC1) & (1 << 5), 0);
}
