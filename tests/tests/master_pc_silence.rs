//! The PC-silence failsafe (new, opt-in, REGMASTER_PCTIMEOUT): off at boot; once the PC
//! writes a timeout, a PC that sends no clean byte for that long has the master raise
//! PCSILENT (type 13) and write REG_EXCEPTIONDATA to all nine slaves, and again every
//! timeout until the PC is heard. The slaves here are register models; that the motors
//! then stop is shown on real slave images by `twin_faults`.

mod master_support;

use master_support::{transactions, Rig};
use shared::regs::id;

/// Writes REGMASTER_PCTIMEOUT = `ms` (device 0, one word).
fn set_timeout(rig: &mut Rig, ms: u16) {
    let [lo, hi] = ms.to_le_bytes();
    let frame = [0x06, 0x02, 0x01, id::REGMASTER_PCTIMEOUT, lo, hi];
    assert_eq!(rig.exchange(&frame, 1), [0x00]);
}

/// The slaves written REG_EXCEPTIONDATA = 100 (the spread) since the last call, in address
/// order (one entry per write), and the start of the first such write (µs).
fn spread_targets(rig: &mut Rig) -> (Vec<u8>, f64) {
    let spread: Vec<_> = transactions(&rig.bus.take_trace())
        .into_iter()
        .filter(|t| !t.read && t.ack && t.bytes == [id::REG_EXCEPTIONDATA, 0x64, 0x00])
        .collect();
    let first = spread.iter().map(|t| t.start_us).fold(f64::MAX, f64::min);
    let mut to: Vec<u8> = spread.iter().map(|t| t.addr).collect();
    to.sort_unstable();
    (to, first)
}

/// Stops tracing and checks the spread since the trace was last taken: `times` writes to
/// each slave, the first starting 300 ms (on the master's 1-ms clock, plus its loop's
/// latency) after the PC was last heard at `heard` µs; prints that delay.
fn spread_after(rig: &mut Rig, heard: f64, times: usize, what: &str) {
    rig.bus.set_tracing(false);
    let (to, first) = spread_targets(rig);
    assert_eq!(to, each_slave(times), "{what}");
    let after = (first - heard) / 1000.0;
    println!("spread started {after:.1} ms after the PC was last heard ({what})");
    assert!((299.0..305.0).contains(&after), "{after} ms");
}

/// Each of the nine slaves `times` times, in address order.
fn each_slave(times: usize) -> Vec<u8> {
    (1..=9)
        .flat_map(|a| std::iter::repeat_n(a, times))
        .collect()
}

#[test]
fn off_at_boot_so_a_silent_pc_stops_nothing() {
    let mut rig = Rig::new();
    rig.reset_master();
    assert_eq!(rig.master_regs(&[id::REGMASTER_PCTIMEOUT], 2), [0, 0]);
    rig.bus.set_tracing(true);
    rig.bus.take_trace();
    rig.run_us(3_000_000);
    assert_eq!(spread_targets(&mut rig).0, each_slave(0));
    assert_eq!(rig.master_exception(), 0);
}

#[test]
fn a_pc_silent_for_the_timeout_gets_the_stop_spread_to_every_slave() {
    let mut rig = Rig::new();
    rig.reset_master();
    // Every slave out of its boot exception, as the library's resetExceptions() leaves it
    // (so the spread is sent to slaves that are running).
    for addr in 1..=9u8 {
        let frame = [0x05, addr << 4 | 2, 0x01, id::REG_RESET, 0x01];
        assert_eq!(rig.exchange(&frame, 1), [0x00]);
        assert!(!rig.slave(addr).in_exception, "slave {addr}");
    }
    set_timeout(&mut rig, 300);
    assert_eq!(rig.master_regs(&[id::REGMASTER_PCTIMEOUT], 2), [0x2c, 0x01]);
    // Frames closer than the timeout keep it quiet.
    rig.bus.set_tracing(true);
    rig.bus.take_trace();
    let mut sent = 0.0;
    for _ in 0..10 {
        rig.run_us(200_000);
        sent = rig.micros() as f64;
        assert_eq!(rig.exchange(&[0x03, 0x03, 0x07], 2).len(), 2);
    }
    assert_eq!(spread_targets(&mut rig).0, each_slave(0));
    // The master last heard the PC when the frame's third byte arrived.
    let heard = sent + 3.0 * master_support::BYTE_US;
    rig.run_us(1_000_000);
    // At 300, 600 and 900 ms of silence.
    spread_after(&mut rig, heard, 3, "a write to each slave every 300 ms");
    assert_eq!(rig.master_exception(), 0x000d, "PCSILENT, slave 0, motor 0");
}

#[test]
fn bytes_with_serial_errors_do_not_count_as_the_pc_heard() {
    let mut rig = Rig::new();
    rig.reset_master();
    set_timeout(&mut rig, 300);
    // A clean frame, then only garbled bytes (a wrong baud rate, or a floating line),
    // one every 50 ms for 650 ms.
    assert_eq!(rig.master_regs(&[id::REGMASTER_PCTIMEOUT], 2), [0x2c, 0x01]);
    let sent = rig.micros() as f64;
    assert_eq!(rig.exchange(&[0x03, 0x03, 0x07], 2), [0x2c, 0x01]);
    // The master last heard the PC when the frame's third byte arrived.
    let heard = sent + 3.0 * master_support::BYTE_US;
    rig.bus.set_tracing(true);
    rig.bus.take_trace();
    for _ in 0..13 {
        rig.bus.uart_send_framing_error(0, &[0x55]);
        rig.run_us(50_000);
    }
    // At 300 and 600 ms: garbled bytes keep nothing running.
    spread_after(&mut rig, heard, 2, "through a garbled byte every 50 ms");
    // After a garbled byte the master skips what follows until the line has been quiet
    // for 50 ms; the last came 50 ms ago.
    rig.run_us(10_000);
    assert_eq!(rig.master_exception(), 0x000d, "PCSILENT");
    // The garbled bytes were seen: the last error is a framing error (code 13).
    assert_eq!(rig.master_regs(&[id::REGMASTER_LASTERROR], 1), [13]);
}

#[test]
fn the_stop_repeats_while_the_pc_is_silent_and_spreads_even_over_another_exception() {
    let mut rig = Rig::new();
    // The master stays in its boot exception (not reset): the spread must still go out.
    set_timeout(&mut rig, 500);
    rig.bus.set_tracing(true);
    rig.bus.take_trace();
    // At 500 and 1,000 ms of silence: a slave that missed a write, or was reset meanwhile,
    // is stopped again.
    rig.run_us(1_200_000);
    assert_eq!(spread_targets(&mut rig).0, each_slave(2));
    // The boot exception stays: it was latched first.
    assert_eq!(rig.master_exception(), 0x0002);
    // That read was the PC heard: nothing for 400 ms, then again.
    rig.bus.take_trace();
    rig.run_us(400_000);
    assert_eq!(spread_targets(&mut rig).0, each_slave(0));
    rig.run_us(300_000);
    assert_eq!(spread_targets(&mut rig).0, each_slave(1));
    // Writing 0 turns it off.
    set_timeout(&mut rig, 0);
    rig.bus.take_trace();
    rig.run_us(1_500_000);
    assert_eq!(spread_targets(&mut rig).0, each_slave(0));
}
