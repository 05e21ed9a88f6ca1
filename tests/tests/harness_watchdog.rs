//! Emulator tests of watchdog resets: the firmware restarts with WDRF set and
//! EEPROM kept, and the harness counts the resets.

use harness::{Avr, CpuState};

#[test]
fn watchdog_reset_restarts_with_wdrf_and_keeps_eeprom() {
    let mut avr = Avr::firmware("fixture_watchdog").unwrap();
    avr.eeprom_write(0, &[0]);
    let first = avr.uart_read_until(b"\r\n", 50_000).unwrap();
    assert_eq!(first, b"boot=1 wdrf=0\r\n");
    assert_eq!(avr.watchdog_resets(), 0);
    let before = avr.cycles();
    let second = avr.uart_read_until(b"\r\n", 100_000).unwrap();
    assert_eq!(second, b"boot=2 wdrf=1\r\n");
    assert_eq!(avr.watchdog_resets(), 1);
    let third = avr.uart_read_until(b"\r\n", 100_000).unwrap();
    assert_eq!(third, b"boot=3 wdrf=1\r\n");
    assert_eq!(avr.watchdog_resets(), 2);
    assert!(avr.cycles() > before, "time keeps running across resets");
    assert_eq!(avr.eeprom_read(0, 1), vec![3]);
    assert_eq!(avr.state(), CpuState::Running);
}

#[test]
fn watchdog_period_is_about_16_ms() {
    let mut avr = Avr::firmware("fixture_watchdog").unwrap();
    avr.eeprom_write(0, &[0]);
    avr.uart_read_until(b"\r\n", 50_000).unwrap();
    let t0 = avr.micros();
    avr.uart_read_until(b"\r\n", 100_000).unwrap();
    let period = avr.micros() - t0;
    // 16 ms timeout, plus the boot and banner (~1.5 ms of UART at 115200).
    assert!((16_000..20_000).contains(&period), "{period} µs");
}

#[test]
fn external_reset_restarts_without_counting_as_watchdog() {
    let mut avr = Avr::firmware("fixture_watchdog").unwrap();
    avr.eeprom_write(0, &[7]);
    assert_eq!(avr.read_data(0x54) & 1, 1, "PORF after power-on");
    assert_eq!(
        avr.uart_read_until(b"\r\n", 50_000).unwrap(),
        b"boot=8 wdrf=0\r\n"
    );
    let before = avr.cycles();
    avr.reset();
    assert!(avr.cycles() >= before);
    assert_eq!(avr.read_data(0x54) & 0b10, 0b10, "EXTRF after reset");
    assert_eq!(
        avr.uart_read_until(b"\r\n", 10_000).unwrap(),
        b"boot=9 wdrf=0\r\n"
    );
    assert_eq!(avr.watchdog_resets(), 0);
}
