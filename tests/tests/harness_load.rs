//! Emulator tests of image loading and its errors.

use harness::{firmware_path, Avr, HarnessError};

#[test]
fn firmware_path_is_under_target_firmware() {
    let p = firmware_path("fixture_uart_echo");
    let dir = std::env::var("BLODWEN_FIRMWARE_DIR").unwrap_or_default();
    if dir.is_empty() {
        assert!(
            p.ends_with("target/firmware/fixture_uart_echo.elf"),
            "{}",
            p.display()
        );
    } else {
        assert_eq!(p, std::path::Path::new(&dir).join("fixture_uart_echo.elf"));
    }
    assert!(p.exists(), "build fixtures with scripts/firmware.sh");
}

#[test]
fn a_non_elf_file_is_rejected_with_a_reason() {
    let path = std::env::temp_dir().join(format!("harness-bad-{}.elf", std::process::id()));
    std::fs::write(&path, b"this is not an ELF image").unwrap();
    let err = Avr::load(&path).err().unwrap();
    std::fs::remove_file(&path).unwrap();
    match &err {
        HarnessError::BadElf { reason, .. } => assert_eq!(reason, "not an ELF file (bad magic)"),
        other => panic!("unexpected {other}"),
    }
    assert!(err.to_string().contains("scripts/firmware.sh"), "{err}");
}

#[test]
fn time_starts_at_zero_and_advances_exactly() {
    let mut avr = Avr::firmware("fixture_uart_echo").unwrap();
    assert_eq!(avr.cycles(), 0);
    assert_eq!(avr.micros(), 0);
    avr.run_cycles(1_000);
    let c = avr.cycles();
    // An instruction takes at most 5 cycles, so the run stops just past the target.
    assert!((1_000..1_005).contains(&c), "{c}");
    avr.run_us(250);
    assert!((1_000 + 4_000..1_000 + 4_010).contains(&avr.cycles()));
}

#[test]
fn run_until_stops_when_the_predicate_holds() {
    let mut avr = Avr::firmware("fixture_uart_echo").unwrap();
    assert!(avr.run_until(10_000, |a| a.uart_available() >= 3));
    assert_eq!(avr.uart_take(), b"ech");
    assert!(!avr.run_until(2_000, |a| a.uart_available() >= 100));
}
