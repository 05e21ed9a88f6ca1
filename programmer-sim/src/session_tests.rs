//! Byte-level tests of the STK500 v1 state machine.

use super::*;

const OK: [u8; 2] = [RESP_INSYNC, RESP_OK];

fn isp_in_progmode() -> Programmer {
    let mut p = Programmer::new(Mode::Isp);
    assert_eq!(p.feed_all(&[0x50, 0x20]), OK);
    p
}

#[test]
fn get_sync_answers_insync_ok() {
    let mut p = Programmer::new(Mode::Isp);
    assert_eq!(p.feed_all(&[0x30, 0x20]), [0x14, 0x10]);
    assert_eq!(
        p.feed_all(&[0x30, 0x20, 0x30, 0x20]),
        [0x14, 0x10, 0x14, 0x10]
    );
    assert_eq!(p.record().syncs, 3);
}

#[test]
fn bytes_may_arrive_one_at_a_time() {
    let mut p = Programmer::new(Mode::Isp);
    let mut out = Vec::new();
    p.feed(0x30, &mut out);
    assert!(out.is_empty());
    assert!(p.mid_frame());
    p.feed(0x20, &mut out);
    assert_eq!(out, [0x14, 0x10]);
    assert!(!p.mid_frame());
}

#[test]
fn missing_end_of_packet_answers_nosync() {
    let mut p = Programmer::new(Mode::Isp);
    assert_eq!(p.feed_all(&[0x30, 0x21]), [0x15]);
    assert_eq!(p.record().nosyncs, 1);
    // Back in step at once.
    assert_eq!(p.feed_all(&[0x30, 0x20]), OK);
}

#[test]
fn stray_end_of_packet_answers_nosync() {
    let mut p = Programmer::new(Mode::Isp);
    assert_eq!(p.feed_all(&[0x20, 0x30, 0x20]), [0x15, 0x14, 0x10]);
}

#[test]
fn unknown_command_answers_unknown_then_resyncs_on_garbage() {
    let mut p = Programmer::new(Mode::Isp);
    assert_eq!(p.feed_all(&[0x57, 0x20]), [0x14, 0x12]);
    // Garbage then a sync: the sync's first byte is not swallowed.
    assert_eq!(p.feed_all(&[0x99, 0x30, 0x20]), [0x15, 0x14, 0x10]);
    assert_eq!(p.record().unknown, 1);
}

#[test]
fn sign_on_differs_by_mode() {
    let mut isp = Programmer::new(Mode::Isp);
    assert_eq!(isp.feed_all(&[0x31, 0x20]), b"\x14AVR ISP\x10");
    let mut boot = Programmer::new(Mode::Bootloader);
    assert_eq!(boot.feed_all(&[0x31, 0x20]), OK);
}

#[test]
fn parameters_report_versions_and_remember_writes() {
    let mut p = Programmer::new(Mode::Isp);
    assert_eq!(p.feed_all(&[0x41, 0x80, 0x20]), [0x14, 2, 0x10]);
    assert_eq!(p.feed_all(&[0x41, 0x81, 0x20]), [0x14, 1, 0x10]);
    assert_eq!(p.feed_all(&[0x41, 0x82, 0x20]), [0x14, 18, 0x10]);
    assert_eq!(p.feed_all(&[0x40, 0x89, 0x07, 0x20]), OK);
    assert_eq!(p.feed_all(&[0x41, 0x89, 0x20]), [0x14, 7, 0x10]);
    let mut b = Programmer::new(Mode::Bootloader);
    assert_eq!(b.feed_all(&[0x41, 0x81, 0x20]), [0x14, 8, 0x10]);
    assert_eq!(b.feed_all(&[0x41, 0x82, 0x20]), [0x14, 0, 0x10]);
}

#[test]
fn set_device_and_ext_are_accepted() {
    let mut p = Programmer::new(Mode::Isp);
    let mut dev = vec![0x42, 0x86];
    dev.extend_from_slice(&[0u8; 19]);
    dev.push(0x20);
    assert_eq!(p.feed_all(&dev), OK);
    assert_eq!(p.feed_all(&[0x45, 0x05, 0x04, 0xd7, 0xc2, 0x00, 0x20]), OK);
    // A size byte of 4 (three parameters) is a shorter frame.
    assert_eq!(p.feed_all(&[0x45, 0x04, 0x04, 0xd7, 0xc2, 0x20]), OK);
}

#[test]
fn read_sign_answers_the_atmega328p() {
    let mut p = Programmer::new(Mode::Bootloader);
    assert_eq!(p.feed_all(&[0x75, 0x20]), [0x14, 0x1e, 0x95, 0x0f, 0x10]);
}

#[test]
fn progmode_is_tracked() {
    let mut p = Programmer::new(Mode::Isp);
    assert!(!p.in_progmode());
    assert_eq!(p.feed_all(&[0x50, 0x20]), OK);
    assert!(p.in_progmode());
    assert_eq!(p.feed_all(&[0x51, 0x20]), OK);
    assert!(!p.in_progmode());
    assert_eq!(p.record().progmode_entries, 1);
}

#[test]
fn universal_reads_signature_and_fuses() {
    let mut p = isp_in_progmode();
    assert_eq!(p.feed_all(&[0x56, 0x30, 0, 1, 0, 0x20]), [0x14, 0x95, 0x10]);
    assert_eq!(
        p.feed_all(&[0x56, 0x58, 0x08, 0, 0, 0x20]),
        [0x14, 0xde, 0x10]
    );
    assert_eq!(
        p.feed_all(&[0x56, 0x58, 0x00, 0, 0, 0x20]),
        [0x14, 0xff, 0x10]
    );
    assert_eq!(p.record().universal.len(), 3);
}

#[test]
fn universal_outside_progmode_fails() {
    let mut p = Programmer::new(Mode::Isp);
    assert_eq!(p.feed_all(&[0x56, 0x30, 0, 0, 0, 0x20]), [0x14, 0x00, 0x11]);
    assert_eq!(p.record().refusals.len(), 1);
}

#[test]
fn flash_page_write_and_read_use_word_addresses() {
    let mut p = isp_in_progmode();
    // word address 0x0040 = byte 0x80
    assert_eq!(p.feed_all(&[0x55, 0x40, 0x00, 0x20]), OK);
    let mut cmd = vec![0x64, 0x00, 0x04, b'F', 1, 2, 3, 4, 0x20];
    assert_eq!(p.feed_all(&cmd), OK);
    assert_eq!(&p.target().flash()[0x7f..0x85], &[0xff, 1, 2, 3, 4, 0xff]);
    // The address does not advance: a read at the same address returns the same bytes.
    assert_eq!(
        p.feed_all(&[0x74, 0x00, 0x04, b'F', 0x20]),
        [0x14, 1, 2, 3, 4, 0x10]
    );
    cmd[4] = 9;
    assert_eq!(p.feed_all(&cmd), OK);
    assert_eq!(p.target().flash()[0x80], 9);
    let w = &p.record().writes;
    assert_eq!(w.len(), 2);
    assert_eq!((w[0].memory, w[0].addr, w[0].len), (Memory::Flash, 0x80, 4));
    assert_eq!(p.record().flash_reads, 1);
}

#[test]
fn eeprom_page_write_lands_at_twice_the_loaded_address() {
    let mut p = isp_in_progmode();
    assert_eq!(p.feed_all(&[0x55, 0x00, 0x00, 0x20]), OK);
    assert_eq!(p.feed_all(&[0x64, 0x00, 0x01, b'E', 3, 0x20]), OK);
    assert_eq!(p.target().eeprom()[0], 3);
    assert_eq!(p.feed_all(&[0x55, 0x02, 0x00, 0x20]), OK);
    assert_eq!(p.feed_all(&[0x64, 0x00, 0x02, b'E', 7, 8, 0x20]), OK);
    assert_eq!(&p.target().eeprom()[..6], &[3, 0xff, 0xff, 0xff, 7, 8]);
    assert_eq!(
        p.feed_all(&[0x74, 0x00, 0x02, b'E', 0x20]),
        [0x14, 7, 8, 0x10]
    );
    assert_eq!(p.record().eeprom_reads, 1);
    assert_eq!(p.record().bytes_written(Memory::Eeprom), 3);
    assert_eq!(p.record().bytes_written(Memory::Flash), 0);
}

#[test]
fn page_commands_refuse_bad_requests() {
    let mut p = Programmer::new(Mode::Isp);
    // Not in programming mode.
    assert_eq!(p.feed_all(&[0x64, 0x00, 0x01, b'F', 0, 0x20]), [0x14, 0x11]);
    assert_eq!(p.feed_all(&[0x50, 0x20]), OK);
    // Unknown memory type.
    assert_eq!(p.feed_all(&[0x74, 0x00, 0x01, b'X', 0x20]), [0x14, 0x11]);
    // Past the end of EEPROM: word 0x1ff = byte 0x3fe, 4 bytes.
    assert_eq!(p.feed_all(&[0x55, 0xff, 0x01, 0x20]), OK);
    assert_eq!(p.feed_all(&[0x74, 0x00, 0x04, b'E', 0x20]), [0x14, 0x11]);
    assert_eq!(
        p.feed_all(&[0x74, 0x00, 0x02, b'E', 0x20]),
        [0x14, 0xff, 0xff, 0x10]
    );
    assert_eq!(p.record().refusals.len(), 3);
    assert!(p.record().refusals[2].reason.contains("eeprom"));
    assert!(p.record().writes.is_empty());
}

#[test]
fn bad_end_of_packet_on_a_page_write_writes_nothing() {
    let mut p = isp_in_progmode();
    assert_eq!(p.feed_all(&[0x64, 0x00, 0x01, b'F', 0, 0x21]), [0x15]);
    assert_eq!(p.target().flash()[0], 0xff);
}

#[test]
fn isp_chip_erase_erases_flash_and_eeprom() {
    let mut p = isp_in_progmode();
    p.feed_all(&[0x64, 0x00, 0x01, b'F', 0, 0x20]);
    p.feed_all(&[0x64, 0x00, 0x01, b'E', 0, 0x20]);
    assert_eq!(p.target().flash()[0], 0);
    assert_eq!(p.feed_all(&[0x56, 0xac, 0x80, 0, 0, 0x20]), [0x14, 0, 0x10]);
    assert_eq!(p.target().flash()[0], 0xff);
    assert_eq!(p.target().eeprom()[0], 0xff);
    p.feed_all(&[0x64, 0x00, 0x01, b'F', 0, 0x20]);
    assert_eq!(p.feed_all(&[0x52, 0x20]), OK);
    assert_eq!(p.target().flash()[0], 0xff);
    assert_eq!(p.record().chip_erases, 2);
}

#[test]
fn bootloader_ignores_erase_and_protects_its_section() {
    let mut p = Programmer::new(Mode::Bootloader);
    assert_eq!(p.feed_all(&[0x50, 0x20]), OK);
    p.feed_all(&[0x64, 0x00, 0x01, b'F', 0, 0x20]);
    assert_eq!(p.feed_all(&[0x56, 0xac, 0x80, 0, 0, 0x20]), [0x14, 0, 0x10]);
    assert_eq!(p.feed_all(&[0x52, 0x20]), OK);
    assert_eq!(p.target().flash()[0], 0);
    assert_eq!(p.record().chip_erases, 0);
    // The last application page (0x7d80) is writable, the boot section (0x7e00) is not.
    let mut page = vec![0x64, 0x00, 0x80, b'F'];
    page.extend_from_slice(&[0x55; 128]);
    page.push(0x20);
    assert_eq!(p.feed_all(&[0x55, 0xc0, 0x3e, 0x20]), OK);
    assert_eq!(p.feed_all(&page), OK);
    assert_eq!(p.feed_all(&[0x55, 0x00, 0x3f, 0x20]), OK);
    assert_eq!(p.feed_all(&page), [0x14, 0x11]);
    assert!(p.target().flash()[0x7e00..].iter().all(|&b| b == 0xff));
    assert!(p.record().refusals[0].reason.contains("boot section"));
}

#[test]
fn oversized_page_is_refused() {
    let mut p = isp_in_progmode();
    let mut page = vec![0x64, 0x01, 0x01, b'F'];
    page.extend_from_slice(&[0; 257]);
    page.push(0x20);
    assert_eq!(p.feed_all(&page), [0x14, 0x11]);
}
