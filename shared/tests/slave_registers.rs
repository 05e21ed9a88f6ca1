//! The slave's register file on the I2C bus: write and read transactions, change marks,
//! and the power-up values PC programs can see (reference §5, §8.1).

mod slave_support;

use shared::regs::id::*;
use shared::slave::registers::MISSING;
use shared::slave::{Inputs, RegisterFile, Variant};
use slave_support::Bench;

fn all_changed(file: &mut RegisterFile) -> Vec<u8> {
    std::iter::from_fn(|| file.take_changed()).collect()
}

#[test]
fn a_write_fills_the_register_lsb_first_and_marks_it() {
    let mut f = RegisterFile::new(Variant::DriveSteer);
    f.start_write();
    for b in [REGDS_DRIVE_REQSPEED, 0xfe, 0x9f] {
        f.write(b);
    }
    f.stop();
    assert_eq!(f.get(REGDS_DRIVE_REQSPEED), 0x9ffe);
    assert!(f.is_changed(REGDS_DRIVE_REQSPEED));
    assert_eq!(all_changed(&mut f), vec![REGDS_DRIVE_REQSPEED]);
    assert!(
        !f.is_changed(REGDS_DRIVE_REQSPEED),
        "taking clears the mark"
    );
}

#[test]
fn bytes_after_the_register_are_ignored() {
    // One register per write (reference §5): extra bytes, from a foreign bus master or a
    // corrupted transfer, never reach the registers after it.
    let mut f = RegisterFile::new(Variant::DriveSteer);
    let before = f.clone();
    // REG_DEBUG (2 bytes) then two more, which would otherwise set the drive's demand
    // (the next register) to 4000 ticks/s.
    f.start_write();
    for b in [REG_DEBUG, 0x34, 0x12, 0xfe, 0xff] {
        f.write(b);
    }
    f.stop();
    // A spread exception's write with extra bytes raises REMOTESLAVE and does not mask
    // every exception through DISABLEDEXCEPTIONS.
    f.start_write();
    for b in [REG_EXCEPTIONDATA, 0x64, 0x00, 0xff, 0xff, 0xff] {
        f.write(b);
    }
    f.stop();
    // A one-byte register takes one byte; the next register keeps its value.
    f.start_write();
    for b in [REGDS_STEER_CALIBMIN, 0x43, 0xc4] {
        f.write(b);
    }
    f.stop();
    assert_eq!(f.get(REGDS_STEER_CALIBMIN), 0x43);
    // Each of the other two written registers holds its own two bytes only.
    assert_eq!(f.get(REG_DEBUG), 0x1234);
    assert_eq!(f.get(REG_EXCEPTIONDATA), 0x0064);
    assert_eq!(
        all_changed(&mut f),
        vec![REG_EXCEPTIONDATA, REG_DEBUG, REGDS_STEER_CALIBMIN]
    );
    for id in 0..f.len() {
        if ![REG_DEBUG, REG_EXCEPTIONDATA, REGDS_STEER_CALIBMIN].contains(&id) {
            assert_eq!(f.get(id), before.get(id), "register {id} changed");
        }
    }
    // The pointer stays at the register written, for a read that follows.
    f.start_read();
    assert_eq!(f.read(), 0x43);
}

#[test]
fn empty_writes_change_nothing() {
    let mut f = RegisterFile::new(Variant::LiftLift);
    let before = f.clone();
    // Nothing at all (what the emulator shows after a master read).
    f.start_write();
    f.stop();
    assert!(all_changed(&mut f).is_empty());
    // Pointer only: sets the pointer for a read, changes no register.
    f.start_write();
    f.write(REG_STATUS);
    f.stop();
    assert!(all_changed(&mut f).is_empty());
    for id in 0..f.len() {
        assert_eq!(f.get(id), before.get(id), "register {id}");
    }
    f.start_read();
    assert_eq!(f.read(), 0x05, "the pointer moved to STATUS (0x0005 on LL)");
}

#[test]
fn an_empty_write_after_a_read_keeps_the_pointer() {
    let mut f = RegisterFile::new(Variant::DriveSteer);
    f.start_write();
    f.write(REG_EXCEPTIONDATA);
    f.stop();
    f.start_read();
    assert_eq!((f.read(), f.read()), (0x02, 0x05));
    // The emulator's STOP after the read looks like an empty write.
    f.start_write();
    f.stop();
    f.start_read();
    assert_eq!((f.read(), f.read()), (0x02, 0x05));
}

#[test]
fn a_short_write_is_dropped() {
    let mut f = RegisterFile::new(Variant::DriveSteer);
    f.start_write();
    f.write(REGDS_DRIVE_REQSPEED);
    f.write(0x12);
    f.stop();
    assert_eq!(f.get(REGDS_DRIVE_REQSPEED), 0x7fff);
    assert!(all_changed(&mut f).is_empty());
}

#[test]
fn a_write_to_exceptiondata_cut_after_its_first_byte_still_counts() {
    // Any write raises REMOTESLAVE (reference §2.1): the spread write `05 64 00` cut after
    // `64` by a STOP, a bus error or a new START still marks the register.
    let ends: [fn(&mut RegisterFile); 3] = [
        RegisterFile::stop,
        RegisterFile::start_write,
        RegisterFile::start_read,
    ];
    for end in ends {
        let mut f = RegisterFile::new(Variant::LiftLift);
        f.start_write();
        f.write(REG_EXCEPTIONDATA);
        f.write(0x64);
        end(&mut f);
        assert_eq!(all_changed(&mut f), vec![REG_EXCEPTIONDATA]);
    }
    // The pointer alone is no write, and a complete write counts once.
    let mut f = RegisterFile::new(Variant::DriveSteer);
    f.start_write();
    f.write(REG_EXCEPTIONDATA);
    f.stop();
    f.start_write();
    for b in [REG_EXCEPTIONDATA, 0x64, 0x00] {
        f.write(b);
    }
    f.stop();
    assert_eq!(all_changed(&mut f), vec![REG_EXCEPTIONDATA]);
    // Another register cut after its first byte is still dropped.
    f.start_write();
    f.write(REGDS_DRIVE_REQSPEED);
    f.write(0x01);
    f.start_write();
    assert!(all_changed(&mut f).is_empty());
}

#[test]
fn writes_to_read_only_registers_are_ignored() {
    let mut f = RegisterFile::new(Variant::DriveSteer);
    for id in [
        REG_TIMER,
        REG_STATUS,
        REGDS_DRIVE_ACTUALSPEED,
        REGDS_CHASSIS,
    ] {
        f.start_write();
        for b in [id, 0x34, 0x12] {
            f.write(b);
        }
        f.stop();
    }
    assert_eq!(f.get(REG_STATUS), 0x0009);
    assert_eq!(f.get(REG_TIMER), 0);
    assert_eq!(f.get(REGDS_DRIVE_ACTUALSPEED), 0);
    assert!(all_changed(&mut f).is_empty());
}

#[test]
fn missing_registers_read_0xcd_and_are_never_written() {
    let mut f = RegisterFile::new(Variant::LiftLift);
    let len = f.len();
    assert_eq!(len, 47);
    for pointer in [len, len + 1, 200, 255] {
        f.start_write();
        for b in [pointer, 0x11, 0x22] {
            f.write(b);
        }
        f.stop();
        f.start_read();
        assert_eq!([f.read(), f.read(), f.read()], [MISSING; 3]);
        f.stop();
    }
    assert!(all_changed(&mut f).is_empty());
    // A write that runs off the end of the table drops the rest.
    f.start_write();
    for b in [REGLL_BUSTIMEOUT, 0x10, 0x00, 0x99, 0x99] {
        f.write(b);
    }
    f.stop();
    assert_eq!(f.get(REGLL_BUSTIMEOUT), 0x0010);
    assert_eq!(all_changed(&mut f), vec![REGLL_BUSTIMEOUT]);
}

#[test]
fn a_read_runs_on_through_the_following_registers_then_0xcd() {
    let mut f = RegisterFile::new(Variant::DriveSteer);
    // STATUS (2), DEBUGLED (1), EXCEPTIONDATA (2), DISABLED (2), PING (1).
    f.start_write();
    f.write(REG_STATUS);
    f.stop();
    f.start_read();
    let run: Vec<u8> = (0..8).map(|_| f.read()).collect();
    assert_eq!(run, [0x09, 0x00, 0x00, 0x02, 0x05, 0x00, 0x00, 0x00]);
    f.stop();
    // The last registers, then past the end.
    f.start_write();
    f.write(REGDS_CHASSIS);
    f.stop();
    f.start_read();
    let run: Vec<u8> = (0..9).map(|_| f.read()).collect();
    // CHASSIS 0x0000, FAULTTIME 500 = 0x01f4, DRIVE_MODE 0, BUSTIMEOUT 2500 = 0x09c4,
    // then 0xcd.
    assert_eq!(
        run,
        [0x00, 0x00, 0xf4, 0x01, 0x00, 0xc4, 0x09, MISSING, MISSING]
    );
}

#[test]
fn each_read_transaction_starts_again_at_the_pointer() {
    let mut f = RegisterFile::new(Variant::DriveSteer);
    f.start_write();
    f.write(REGDS_DRIVE_OVERCURRENTTHRESH);
    f.stop();
    for _ in 0..3 {
        f.start_read();
        assert_eq!((f.read(), f.read()), (0xcc, 0x4c));
        f.stop();
    }
}

#[test]
fn both_bytes_of_a_register_come_from_one_moment() {
    let mut f = RegisterFile::new(Variant::DriveSteer);
    f.set(REG_TIMER, 0x01ff);
    f.start_write();
    f.write(REG_TIMER);
    f.stop();
    f.start_read();
    let lo = f.read();
    // The tick updates the timer between the two bytes.
    f.set(REG_TIMER, 0x0200);
    let hi = f.read();
    assert_eq!(u16::from_le_bytes([lo, hi]), 0x01ff);
}

#[test]
fn a_repeated_start_ends_the_write_and_reads_from_the_new_pointer() {
    let mut f = RegisterFile::new(Variant::DriveSteer);
    f.start_write();
    f.write(REGDS_DRIVE_OVERCURRENTTHRESH);
    f.start_read(); // no STOP
    assert_eq!((f.read(), f.read()), (0xcc, 0x4c));
    f.stop();
    assert!(all_changed(&mut f).is_empty());
}

#[test]
fn reset_writes_accumulate_until_the_tick_takes_them() {
    let mut f = RegisterFile::new(Variant::DriveSteer);
    f.start_write();
    f.write(REG_RESET);
    f.write(4);
    f.stop();
    f.start_write();
    f.write(REG_RESET);
    f.write(1);
    f.stop();
    assert_eq!(f.get(REG_RESET), 5, "neither request is lost");
    assert_eq!(all_changed(&mut f), vec![REG_RESET]);
}

#[test]
fn changes_are_taken_lowest_id_first() {
    let mut f = RegisterFile::new(Variant::DriveSteer);
    for (id, byte) in [(REG_EXCEPTIONDATA, 1u8), (REG_RESET, 1), (REG_PING, 0)] {
        f.start_write();
        f.write(id);
        f.write(byte);
        if id == REG_EXCEPTIONDATA {
            f.write(0);
        }
        f.stop();
    }
    assert_eq!(
        all_changed(&mut f),
        vec![REG_RESET, REG_EXCEPTIONDATA, REG_PING]
    );
}

/// Every register's raw value at power-up, before and after the first tick.
#[test]
fn power_up_values_match_the_reference_quirks_included() {
    let ds_nonzero = [
        (REG_STATUS, 0x0009),
        (REG_EXCEPTIONDATA, 0x0502),
        (REGDS_DRIVE_REQSPEED, 0x7fff),
        (REGDS_DRIVE_DGAIN, 0x7fff),
        (REGDS_DRIVE_OVERCURRENTTHRESH, 0x4ccc),
        (REGDS_DRIVE_STALLCHECK, 0x77),
        (REGDS_STEER_REQPOS, 0x7fff),
        (REGDS_STEER_DGAIN, 0x7fff),
        (REGDS_STEER_STALLCHECK, 0x77),
        (REGDS_STEER_CALIBMAX, 0xfe),
        (REGDS_FAULTTIME, 500),
        (REGDS_BUSTIMEOUT, 2500),
    ];
    let mut bench = Bench::new(Variant::DriveSteer);
    for id in 0..bench.regs.len() {
        let expected = ds_nonzero
            .iter()
            .find(|(i, _)| *i == id)
            .map_or(0, |(_, v)| *v);
        assert_eq!(bench.read(id), expected, "DS register {id}");
    }
    let ll_nonzero = [
        (REG_STATUS, 0x0005),
        (REG_EXCEPTIONDATA, 0x0502),
        (REGLL_ONE_REQPOS, 0x7fff),
        (REGLL_ONE_DGAIN, 0x7fff),
        (REGLL_ONE_STALLCHECK, 0x77),
        (REGLL_ONE_CALIBMAX, 0xfe),
        (REGLL_TWO_REQPOS, 0x7fff),
        (REGLL_TWO_DGAIN, 0x7fff),
        (REGLL_TWO_STALLCHECK, 0x77),
        (REGLL_TWO_CALIBMAX, 0xfe),
        (REGLL_FAULTTIME, 500),
        (REGLL_BUSTIMEOUT, 2500),
    ];
    let mut bench = Bench::new(Variant::LiftLift);
    for id in 0..bench.regs.len() {
        let expected = ll_nonzero
            .iter()
            .find(|(i, _)| *i == id)
            .map_or(0, |(_, v)| *v);
        assert_eq!(bench.read(id), expected, "LL register {id}");
    }
    // After the first tick, the settings still read as at power-up, and the monitoring
    // values of a board at rest read as zero in their ranges.
    let mut bench = Bench::new(Variant::DriveSteer);
    bench.tick(&Inputs::default());
    assert_eq!(bench.read(REGDS_STEER_OVERCURRENTTHRESH), 0x0000);
    assert_eq!(bench.read(REGDS_DRIVE_STALLCHECK), 0x77);
    assert_eq!(bench.read(REGDS_STEER_CALIBMIN), 0x00);
    assert_eq!(bench.read(REG_STATUS), 0x0009);
    assert_eq!(bench.read(REG_EXCEPTIONDATA), 0x0502);
    assert_eq!(bench.read(REGDS_DRIVE_ACTUALSPEED), 0x7fff);
    assert_eq!(bench.read(REGDS_DRIVE_CONTROL), 0x7fff);
    assert_eq!(bench.read(REGDS_STEER_ERROR), 0x7fff);
}

#[test]
fn register_file_is_small() {
    let size = std::mem::size_of::<RegisterFile>();
    println!("RegisterFile: {size} bytes on the host");
    assert!(size <= 112, "{size}");
}
