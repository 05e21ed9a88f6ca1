//! Emulator tests of EEPROM preload and read-back.

use harness::Avr;

#[test]
fn preloaded_byte_is_read_and_firmware_write_is_visible() {
    let mut avr = Avr::firmware("fixture_eeprom").unwrap();
    avr.eeprom_write(0, &[41]);
    assert_eq!(avr.uart_read_until(b"\r\n", 50_000).unwrap(), b"E0=41\r\n");
    assert_eq!(avr.uart_read_until(b"W\r\n", 50_000).unwrap(), b"W\r\n");
    assert_eq!(avr.eeprom_read(0, 2), vec![41, 42]);
}

#[test]
fn blank_eeprom_reads_erased() {
    let mut avr = Avr::firmware("fixture_eeprom").unwrap();
    assert_eq!(avr.eeprom_read(0, 4), vec![0xFF; 4]);
    assert_eq!(avr.uart_read_until(b"\r\n", 50_000).unwrap(), b"E0=255\r\n");
    avr.uart_read_until(b"W\r\n", 50_000).unwrap();
    assert_eq!(avr.eeprom_read(1, 1), vec![0]);
}

#[test]
fn reads_past_the_end_are_erased() {
    let mut avr = Avr::firmware("fixture_eeprom").unwrap();
    avr.eeprom_write(1022, &[1, 2, 3, 4]);
    assert_eq!(avr.eeprom_read(1022, 4), vec![1, 2, 0xFF, 0xFF]);
}
