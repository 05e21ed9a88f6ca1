//! The master's boot in the emulator, with nine slave models: the banner, the hard reset
//! of every slave while the 1-s watchdog runs, then the 125-ms watchdog.

mod master_support;

use harness::Avr;
use master_support::{transactions, watchdog, Rig};

/// WDP of the 1-s and 125-ms watchdog periods.
const WDP_1S: u8 = 6;
const WDP_125MS: u8 = 3;

#[test]
fn every_slave_gets_a_hard_reset_and_the_banner_follows() {
    let rig = Rig::new();
    for addr in 1..=9 {
        assert_eq!(
            rig.slave(addr).writes,
            vec![vec![0x00, 0x02]],
            "slave {addr}"
        );
    }
    let lines: Vec<&str> = rig.banner.split("\r\n").collect();
    assert_eq!(lines[0], "Starting");
    assert_eq!(lines[3], "Ready");
    assert_eq!(rig.watchdog(), (WDP_125MS, true), "125 ms after boot");
}

#[test]
fn the_watchdog_runs_at_1_s_during_the_boot_work() {
    let mut avr = Avr::firmware("master").unwrap();
    avr.uart_read_until(b"Starting\r\n", 100_000).unwrap();
    assert_eq!(watchdog(&avr), (WDP_1S, true), "1 s while booting");
    avr.uart_read_until(b"Ready\r\n", 2_000_000).unwrap();
    assert_eq!(watchdog(&avr), (WDP_125MS, true));
    // No slave answers here: the boot is not held up by them, and the master stays up.
    avr.run_us(500_000);
    assert_eq!(avr.watchdog_resets(), 0);
}

#[test]
fn the_ping_starts_after_5_s_and_nothing_else_reaches_the_slaves_before() {
    let mut rig = Rig::new();
    rig.clear_records();
    rig.run_to(4_990_000);
    for addr in 1..=9 {
        let s = rig.slave(addr);
        assert!(
            s.writes.is_empty() && s.reads == 0,
            "slave {addr} before 5 s"
        );
    }
    rig.bus.set_tracing(true);
    rig.bus.take_trace();
    rig.run_to(5_100_000);
    let ts = transactions(&rig.bus.take_trace());
    assert!(
        ts[0].start_us >= 5_000_000.0,
        "first access at {} us",
        ts[0].start_us
    );
    // For slaves 1..9 in order: `07 00`, STATUS (boot exception: bit 0 set), then
    // EXCEPTIONDATA (BOOT, motor 5); each read is the register id, then the value.
    let mut expected = Vec::new();
    for addr in 1..=9u8 {
        let status = if addr % 3 == 0 { 0x05 } else { 0x09 };
        expected.push((addr, false, vec![0x07, 0x00]));
        expected.push((addr, false, vec![0x03]));
        expected.push((addr, true, vec![status, 0x00]));
        expected.push((addr, false, vec![0x05]));
        expected.push((addr, true, vec![0x02, 0x05]));
    }
    let got: Vec<_> = ts
        .iter()
        .take(expected.len())
        .map(|t| (t.addr, t.read, t.bytes.clone()))
        .collect();
    assert_eq!(got, expected);
}
