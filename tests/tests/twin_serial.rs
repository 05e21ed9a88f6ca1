//! The twin's serial line faults, at the byte level (reference §4.6): bytes lost towards the
//! master leave a frame incomplete, so it gets no reply (the master drops it after its
//! inter-byte timeout) and the next frame is served; a byte lost towards the host shortens
//! a reply. Runs against whatever slave images are built: only device 0 is addressed.

use twin::serial::Direction;
use twin::Rover;

/// A rover booted to `Ready`.
fn booted() -> Rover {
    let mut r = Rover::new().expect("the twin builds (run scripts/firmware.sh)");
    let banner = r.uart_read_until(b"Ready\r\n", 3_000_000).unwrap();
    assert!(banner.starts_with(b"Starting\r\n"), "{banner:?}");
    r
}

/// The library's set 2 on device 0.
const SET2: [u8; 14] = [0x0e, 0x04, 0x02, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11];

#[test]
fn a_byte_lost_towards_the_master_costs_one_reply_only() {
    let mut r = booted();
    r.uart_send(&SET2[..5]);
    r.drop_serial(Direction::ToMaster, 1);
    r.uart_send(&SET2[5..]);
    // The frame lacks one byte: no reply within the library's 1-s timeout.
    assert!(r.uart_read_exact(1, 1_000_000).is_err());
    assert_eq!(r.serial().dropped(Direction::ToMaster), 1);
    // The next frame is whole and answered with its count.
    r.uart_send(&SET2);
    assert_eq!(r.uart_read_exact(1, 1_000_000).unwrap(), [0x0b]);
    r.uart_send(&[0x03, 0x03, 0x02]);
    let reply = r.uart_read_exact(22, 1_000_000).unwrap();
    assert_eq!(&reply[20..], [0x02, 0x00], "EXCEPTIONDATA = boot");
}

#[test]
fn a_byte_lost_towards_the_host_shortens_the_reply() {
    let mut r = booted();
    r.uart_send(&SET2);
    assert_eq!(r.uart_read_exact(1, 1_000_000).unwrap(), [0x0b]);
    r.drop_serial(Direction::ToHost, 2);
    r.uart_send(&[0x03, 0x03, 0x02]);
    let reply = r.uart_read_exact(20, 1_000_000).unwrap();
    // The first two bytes (TEMPAMBIENT) are gone; the reply ends with EXCEPTIONDATA.
    assert_eq!(&reply[18..], [0x02, 0x00]);
    assert!(r.uart_read_exact(1, 200_000).is_err(), "nothing more");
    assert_eq!(r.serial().dropped(Direction::ToHost), 2);
}

/// What the twin does when a program opens its port (the open itself, through a pty, is
/// `twin_pty`'s `a_serial_program_sees_the_banner_after_each_open`).
#[test]
fn a_master_reset_reboots_it_with_the_banner_and_hard_resets_every_slave() {
    let mut r = booted();
    r.run_us(100_000).unwrap();
    let before = r.watchdog_resets();
    r.reset_master();
    let banner = r.uart_read_until(b"Ready\r\n", 3_000_000).unwrap();
    assert!(banner.starts_with(b"Starting\r\n"), "{banner:?}");
    r.run_us(1_500_000).unwrap();
    let after = r.watchdog_resets();
    assert_eq!(after[0], before[0], "an external reset, not the watchdog");
    // The master's boot writes REG_RESET = 2 to every slave: each reboots through its
    // watchdog once.
    for chip in 1..=9 {
        assert_eq!(
            after[chip],
            before[chip] + 1,
            "controller {chip}: {before:?} -> {after:?}"
        );
    }
}

/// A frame a program sent just before its port closed (a reset, with HUPCL) dies with the
/// reset, as on the Uno: the next program's session starts from the banner, not from it.
#[test]
fn bytes_on_their_way_at_a_master_reset_die_with_it() {
    let mut r = booted();
    r.run_us(100_000).unwrap();
    // REGMASTER_PCTIMEOUT = 300 (the failsafe's timeout), sent and not yet received.
    r.uart_send(&[0x06, 0x02, 0x01, 0x0f, 0x2c, 0x01]);
    r.reset_master();
    r.uart_read_until(b"Ready\r\n", 3_000_000).unwrap();
    r.run_us(100_000).unwrap();
    assert_eq!(r.uart_take(), b"", "no reply to the old frame");
    // PCTIMEOUT (master register 15) reads as its boot value 0, through read set 7.
    r.uart_send(&[0x04, 0x04, 0x07, 0x0f]);
    r.run_us(20_000).unwrap();
    assert_eq!(r.uart_take(), [0x01], "set 7 holds one register");
    r.uart_send(&[0x03, 0x03, 0x07]);
    r.run_us(20_000).unwrap();
    assert_eq!(r.uart_take(), [0x00, 0x00], "PCTIMEOUT still 0");
}
