//! Emulator tests of the harness's UART0: banner, exact echo, line rate and
//! zero-real-time waiting.

use harness::{Avr, CpuState, HarnessError};

/// Emulated time per byte at 115200 with U2X0 (11 bit times of 136 cycles).
const BYTE_US: f64 = 93.5;

fn echo() -> Avr {
    Avr::firmware("fixture_uart_echo").unwrap()
}

#[test]
fn banner_arrives() {
    let mut avr = echo();
    let banner = avr.uart_read_until(b"\r\n", 10_000).unwrap();
    assert_eq!(banner, b"echo ready\r\n");
    assert_eq!(avr.state(), CpuState::Running);
}

#[test]
fn echo_returns_exact_bytes() {
    let mut avr = echo();
    avr.uart_read_until(b"ready\r\n", 10_000).unwrap();
    let msg: Vec<u8> = (0u8..=255).collect();
    avr.uart_send(&msg);
    let back = avr.uart_read_exact(msg.len(), 100_000).unwrap();
    assert_eq!(back, msg);
    assert!(avr.uart_take().is_empty());
}

#[test]
fn output_line_rate_is_93_5_us_per_byte() {
    let mut avr = echo();
    assert_eq!(avr.uart_cycles_per_byte(), 1600, "before UBRR0 is written");
    avr.run_until(10_000, |a| a.uart_available() >= 12);
    assert_eq!(avr.uart_cycles_per_byte(), 1496);
    let timed = avr.uart_take_timed();
    assert_eq!(timed.len(), 12);
    let span = (timed[11].0 - timed[1].0) as f64 / 16.0;
    let per_byte = span / 10.0;
    // The polling loop adds a few cycles between UDRE and the next UDR0 write.
    assert!(
        (BYTE_US..BYTE_US + 1.0).contains(&per_byte),
        "{per_byte} µs per byte"
    );
}

#[test]
fn input_arrives_at_line_rate() {
    let mut avr = echo();
    avr.uart_read_until(b"\r\n", 10_000).unwrap();
    avr.uart_send(b"0123456789");
    let t0 = avr.micros();
    avr.uart_read_exact(10, 100_000).unwrap();
    let elapsed = avr.micros() - t0;
    // Ten bytes in, each echoed as it arrives: ~10 character times, not ~0.
    assert!(
        (930..=1100).contains(&elapsed),
        "10 bytes took {elapsed} µs"
    );
}

#[test]
fn timeout_reports_partial_output() {
    let mut avr = echo();
    let err = avr.uart_read_until(b"never", 5_000).unwrap_err();
    match err {
        HarnessError::Timeout { waited_us, got, .. } => {
            assert!((5_000..5_010).contains(&waited_us), "{waited_us}");
            assert_eq!(got, b"echo ready\r\n");
        }
        other => panic!("unexpected {other}"),
    }
}

#[test]
fn missing_firmware_says_how_to_fix() {
    let err = Avr::firmware("no_such_image").err().unwrap();
    assert!(err.to_string().contains("run scripts/firmware.sh"), "{err}");
}
