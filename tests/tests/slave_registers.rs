//! Emulator tests of both slave images' register files over I2C, the test acting as the
//! master and addressing the board the way the master relays a PC program's requests:
//! power-up values (reference §8.1), every writable register written and read back,
//! read-only registers, missing ids, contiguous reads, empty writes, and a bad EEPROM
//! address.

mod slave_support;

use harness::Pin;
use shared::regs::{id, BoardKind};
use slave_support::{rig, rig_with, Rig};

/// Writable registers' power-up raw values that are not 0, drive/steer (§8.1).
const DS_BOOT: &[(u8, u16)] = &[
    (5, 0x0502),  // EXCEPTIONDATA: BOOT, no motor
    (9, 0x7fff),  // DRIVE_REQSPEED
    (12, 0x7fff), // DRIVE_DGAIN
    (15, 0x4ccc), // DRIVE_OVERCURRENTTHRESH
    (24, 0x77),   // DRIVE_STALLCHECK
    (26, 0x7fff), // STEER_REQPOS
    (29, 0x7fff), // STEER_DGAIN
    (40, 0x77),   // STEER_STALLCHECK
    (43, 0xfe),   // STEER_CALIBMAX
    (45, 500),    // FAULTTIME (new)
    (47, 2500),   // BUSTIMEOUT (new)
];

/// Writable registers' power-up raw values that are not 0, lift/lift (§8.1).
const LL_BOOT: &[(u8, u16)] = &[
    (5, 0x0502),  // EXCEPTIONDATA: BOOT, no motor
    (9, 0x7fff),  // ONE_REQPOS
    (12, 0x7fff), // ONE_DGAIN
    (24, 0xfe),   // ONE_CALIBMAX
    (25, 0x77),   // ONE_STALLCHECK
    (27, 0x7fff), // TWO_REQPOS
    (30, 0x7fff), // TWO_DGAIN
    (42, 0xfe),   // TWO_CALIBMAX
    (43, 0x77),   // TWO_STALLCHECK
    (45, 500),    // FAULTTIME (new)
    (46, 2500),   // BUSTIMEOUT (new)
];

fn expected_boot(board: BoardKind, reg: u8) -> u16 {
    let table = match board {
        BoardKind::LiftLift => LL_BOOT,
        _ => DS_BOOT,
    };
    table
        .iter()
        .find(|&&(r, _)| r == reg)
        .map_or(0, |&(_, v)| v)
}

fn booted(addr: u8) -> Rig {
    let mut r = rig(addr);
    r.run_us(5_000);
    r
}

/// Splits a contiguous read into raw values per register of the table.
fn split(r: &Rig, first: u8, bytes: &[u8]) -> Vec<(u8, u16)> {
    let mut out = Vec::new();
    let mut at = 0;
    let mut reg = first;
    while at < bytes.len() {
        let size = usize::from(r.board.size_of(reg).unwrap_or(1));
        let raw = if size == 1 {
            u16::from(bytes[at])
        } else {
            u16::from_le_bytes([bytes[at], bytes[at + 1]])
        };
        out.push((reg, raw));
        at += size;
        reg += 1;
    }
    out
}

fn table_bytes(r: &Rig) -> usize {
    (0..r.board.len())
        .map(|id| usize::from(r.board.size_of(id).unwrap()))
        .sum()
}

fn check_boot_values(addr: u8, status: u16) {
    let mut r = booted(addr);
    assert_eq!(r.read_raw(id::REG_STATUS), status);
    assert_eq!(r.read_raw(id::REG_EXCEPTIONDATA), 0x0502);
    // One register at a time, as a PC program reads them.
    for reg in 0..r.board.len() {
        if r.board.is_writable(reg) == Some(true) && reg != id::REG_DEBUG {
            assert_eq!(
                r.read_raw(reg),
                expected_boot(r.board, reg),
                "register {reg} of {addr}"
            );
        }
    }
    // The whole table as one contiguous read gives the same values.
    let n = table_bytes(&r);
    let bytes = r.read_bytes(0, n);
    assert_eq!(bytes.len(), n);
    for (reg, raw) in split(&r, 0, &bytes) {
        if r.board.is_writable(reg) == Some(true) && reg != id::REG_DEBUG {
            assert_eq!(raw, expected_boot(r.board, reg), "run, register {reg}");
        }
        if reg == id::REG_STATUS {
            assert_eq!(raw, status);
        }
    }
}

#[test]
fn drive_steer_boots_with_the_reference_values() {
    check_boot_values(1, 0x0009);
}

#[test]
fn lift_lift_boots_with_the_reference_values() {
    check_boot_values(3, 0x0005);
}

/// A distinct raw value per register, within its size.
fn probe_value(size: u8, reg: u8) -> u16 {
    if size == 1 {
        u16::from(reg.wrapping_mul(7).wrapping_add(3))
    } else {
        0x1111u16.wrapping_mul(u16::from(reg)).wrapping_add(0x0102)
    }
}

fn check_every_writable_register(addr: u8) {
    let mut r = booted(addr);
    // RESET, EXCEPTIONDATA and DEBUG have their own semantics (tested elsewhere);
    // REG_DEBUG is overwritten every tick.
    let skip = [id::REG_RESET, id::REG_EXCEPTIONDATA, id::REG_DEBUG];
    let regs: Vec<u8> = (0..r.board.len())
        .filter(|&reg| r.board.is_writable(reg) == Some(true) && !skip.contains(&reg))
        .collect();
    assert!(regs.len() >= 25, "{regs:?}");
    for &reg in &regs {
        let size = r.board.size_of(reg).unwrap();
        r.write_raw(reg, probe_value(size, reg));
    }
    r.run_us(5_000);
    for &reg in &regs {
        let size = r.board.size_of(reg).unwrap();
        assert_eq!(r.read_raw(reg), probe_value(size, reg), "register {reg}");
    }
    // Still in the boot exception: no write above raised anything.
    assert_eq!(r.read_raw(id::REG_EXCEPTIONDATA), 0x0502);
}

#[test]
fn every_writable_register_reads_back_drive_steer() {
    check_every_writable_register(2);
}

#[test]
fn every_writable_register_reads_back_lift_lift() {
    check_every_writable_register(6);
}

#[test]
fn read_only_registers_ignore_writes() {
    for addr in [1, 3] {
        let mut r = booted(addr);
        let status = r.read_raw(id::REG_STATUS);
        let read_only: Vec<u8> = (0..r.board.len())
            .filter(|&reg| r.board.is_writable(reg) == Some(false))
            .collect();
        assert!(read_only.len() >= 15);
        // Measured times move on their own: the clock registers, and a position
        // motor's INTERVALCTRL (REG_DEBUG mirrors lift ONE's), which reads 1 or 2 ms as
        // its 2,000 µs period meets the control task's start latency (⌊Δt/1000⌋).
        let intervals = match r.board {
            BoardKind::LiftLift => vec![
                id::REG_DEBUG,
                id::REGLL_ONE_INTERVALCTRL,
                id::REGLL_TWO_INTERVALCTRL,
            ],
            _ => vec![id::REGDS_STEER_INTERVALCTRL],
        };
        // INTERVALCTRL maps 0..1000 ms onto 0..65534, truncating: 1 ms is 65 raw (0.99 ms
        // unmapped), 2 ms 131 (1.999 ms), so the nearest whole ms.
        let interval_ms = |raw: u16| (u32::from(raw) * 1000 + 32_767) / 65_534;
        for &reg in &read_only {
            let before = r.read_raw(reg);
            r.bus.write(r.addr, &[reg, 0x5a, 0xa5]).unwrap();
            // Read at once, within the same millisecond tick as a rule, so that a value
            // the control task republishes every tick could not hide a write taken: the
            // original stored such a write until its next pass overwrote it.
            let at_once = r.read_raw(reg);
            assert_ne!(at_once, 0xa55a, "register {reg} of {addr}, at once");
            r.run_us(2_000);
            let after = r.read_raw(reg);
            if !intervals.contains(&reg) && reg != id::REG_TIMER && reg != id::REG_INTERVALI2C {
                assert_eq!(at_once, before, "register {reg} of {addr}, at once");
            }
            if intervals.contains(&reg) {
                let (b, a) = (interval_ms(before), interval_ms(after));
                let ms = if reg == id::REG_DEBUG {
                    (before, after)
                } else {
                    (b as u16, a as u16)
                };
                assert!(
                    (1..=2).contains(&ms.0) && (1..=2).contains(&ms.1),
                    "register {reg} of {addr}: {before:#x} then {after:#x}"
                );
            } else if reg == id::REG_INTERVALI2C {
                // The µs between the last two control ticks: the 1-ms tick, give or take
                // its start latency.
                assert!(
                    (950..=1050).contains(&after),
                    "INTERVALI2C of {addr}: {after} µs"
                );
            } else if reg != id::REG_TIMER {
                // Every other monitoring value is constant at rest in the boot exception.
                assert_eq!(after, before, "register {reg} of {addr}");
            }
            assert_ne!(after, 0xa55a, "register {reg} of {addr}");
        }
        assert_eq!(r.read_raw(id::REG_STATUS), status);
        // Bytes past a read-only register do not reach the writable one after it:
        // STEER/ONE CURRENT (2 bytes, read-only) then the following writable register.
        let (ro, next) = match r.board {
            BoardKind::LiftLift => (id::REGLL_ONE_CURRENT, id::REGLL_ONE_CALIBMIN),
            _ => (id::REGDS_STEER_CURRENT, id::REGDS_STEER_STALLCHECK),
        };
        assert_eq!(next, ro + 1);
        let kept = r.read_raw(next);
        r.bus.write(r.addr, &[ro, 0x11, 0x22, 0x42]).unwrap();
        r.run_us(2_000);
        assert_eq!(r.read_raw(next), kept);
        assert_ne!(kept, 0x42);
    }
}

#[test]
fn bytes_past_the_register_written_are_ignored() {
    // One register per write (reference §5). Two stray bytes after REG_DEBUG would be
    // a drive demand of 4000 ticks/s in REQSPEED, the next register; after
    // EXCEPTIONDATA they would mask every exception in DISABLEDEXCEPTIONS.
    let mut r = booted(1);
    r.reset_exceptions();
    assert_eq!(id::REGDS_DRIVE_REQSPEED, id::REG_DEBUG + 1);
    assert_eq!(id::REG_DISABLEDEXCEPTIONS, id::REG_EXCEPTIONDATA + 1);
    let demand = r.read_raw(id::REGDS_DRIVE_REQSPEED);
    r.bus
        .write(r.addr, &[id::REG_DEBUG, 0x00, 0x00, 0xfe, 0xff])
        .unwrap();
    r.run_us(2_000);
    assert_eq!(r.read_raw(id::REGDS_DRIVE_REQSPEED), demand);
    assert_eq!(r.read_raw(id::REG_STATUS), 0x0008, "still running");
    let mask = r.read_raw(id::REG_DISABLEDEXCEPTIONS);
    r.bus
        .write(r.addr, &[id::REG_EXCEPTIONDATA, 0x64, 0x00, 0xff, 0xff])
        .unwrap();
    r.run_us(2_000);
    assert_eq!(r.read_raw(id::REG_DISABLEDEXCEPTIONS), mask);
    assert_eq!(
        r.read_raw(id::REG_EXCEPTIONDATA),
        0x0503,
        "REMOTESLAVE raised"
    );
}

#[test]
fn missing_ids_read_0xcd_and_runs_are_contiguous() {
    let mut r = booted(4);
    let len = r.board.len();
    for reg in [len, len + 1, 100, 255] {
        assert_eq!(r.read_bytes(reg, 3), vec![0xcd; 3], "id {reg}");
    }
    // A write to one changes nothing: the original forced the id to 0, so this `02` was a
    // REG_RESET hard reset.
    let (timer, status) = (r.read_raw(id::REG_TIMER), r.read_raw(id::REG_STATUS));
    for reg in [len, 100, 255] {
        r.bus.write(r.addr, &[reg, 0x02]).unwrap();
    }
    r.run_us(100_000);
    let uptime = r.read_raw(id::REG_TIMER).wrapping_sub(timer);
    assert!(
        (100..=102).contains(&uptime),
        "no reboot: {uptime} ms later"
    );
    assert_eq!(r.read_raw(id::REG_STATUS), status);
    // The last registers then past the end.
    r.write_raw(id::REGDS_FAULTTIME, 0x0123);
    r.write_raw(id::REGDS_DRIVE_MODE, 1);
    r.run_us(2_000);
    // FAULTTIME, DRIVE_MODE, BUSTIMEOUT (2500 = 0x09c4), then past the end.
    assert_eq!(
        r.read_bytes(id::REGDS_FAULTTIME, 7),
        vec![0x23, 0x01, 0x01, 0xc4, 0x09, 0xcd, 0xcd]
    );
    // A run through mixed sizes equals the single reads.
    let first = id::REGDS_STEER_REQPOS;
    r.write_raw(id::REGDS_STEER_PGAIN, 0x2345);
    r.write_raw(id::REGDS_STEER_DEADZONE, 0x09);
    r.run_us(2_000);
    let bytes = r.read_bytes(first, 2 * 14 + 4);
    let run = split(&r, first, &bytes);
    assert_eq!(run.len(), 18);
    for (reg, raw) in run {
        if r.board.is_writable(reg) == Some(true) {
            assert_eq!(raw, r.read_raw(reg), "register {reg}");
        }
    }
    // The same run with a repeated START (write-read in one transaction).
    let again = r
        .bus
        .write_read(r.addr, &[id::REGDS_STEER_PGAIN], 2)
        .unwrap();
    assert_eq!(again, vec![0x45, 0x23]);
}

#[test]
fn empty_writes_change_nothing() {
    let mut r = booted(5);
    r.reset_exceptions();
    assert_eq!(r.read_raw(id::REG_STATUS), 0x0008);
    // A probe (address only), and a pointer alone at EXCEPTIONDATA (what the master
    // sends before every read of it): neither raises REMOTESLAVE.
    r.bus.write(r.addr, &[]).unwrap();
    r.bus.write(r.addr, &[id::REG_EXCEPTIONDATA]).unwrap();
    let _ = r.bus.read(r.addr, 2).unwrap();
    r.run_us(3_000);
    assert_eq!(r.read_raw(id::REG_STATUS), 0x0008);
    assert_eq!(r.read_raw(id::REG_EXCEPTIONDATA), 0x0502);
}

#[test]
fn a_bad_address_keeps_the_board_off_the_bus() {
    for (board, eeprom) in [(BoardKind::DriveSteer, 0u8), (BoardKind::LiftLift, 12u8)] {
        let mut r = rig_with(board, eeprom, if eeprom == 0 { 1 } else { 3 });
        let mut led = Vec::new();
        for at_ms in [150u64, 450, 900, 1_350, 1_650, 2_100] {
            let now = r.bus.micros() / 1_000;
            r.run_us((at_ms - now) * 1_000);
            led.push((r.pin(Pin::a(2)), r.pin(Pin::a(3))));
            // Motors off: every direction pin low, no duty.
            for d in [2, 3, 4, 7] {
                assert!(!r.pin(Pin::d(d)), "D{d} at {at_ms} ms");
            }
            assert_eq!(r.duty(Pin::d(9)), 0.0);
            assert_eq!(r.duty(Pin::d(10)), 0.0);
        }
        // Both off, LED1, LED2; and again.
        let cycle = [(false, false), (true, false), (false, true)];
        assert_eq!(led[..3], cycle, "eeprom {eeprom}");
        assert_eq!(led[3..], cycle, "eeprom {eeprom}");
        for addr in [0u8, 1, 3, eeprom] {
            if addr != 0 {
                assert!(r.bus.write(addr, &[id::REG_PING, 0]).is_err(), "{addr}");
            }
        }
    }
}
