//! The master's RAM in the emulator: static data plus the deepest the stack reaches
//! while everything runs at once (PC frames of every kind, the longest write frame,
//! pings, a slave going silent and the spread, temperature ticks, remote control).
//! `init` paints the free RAM; the paint left below the deepest stack frame is read
//! back through the emulator.
//!
//! The goal is the original firmware's static RAM, 1269 bytes, for static data and
//! stack together. The static bound on the stack (`rover_tests::stack_bound`, tested in
//! `stack_bound.rs`) meets it; this run's high-water mark must stay within that bound.

mod master_support;

use harness::firmware_path;
use master_support::{Options, Rig};
use rover_tests::stack_bound::Program;

/// The original firmware's static RAM, bytes: the goal for static data plus stack.
const ORIGINAL_STATIC_RAM: u16 = 1269;
/// RAM of the ATmega328P, bytes.
const RAM: u16 = 2048;

#[test]
fn static_data_and_the_deepest_stack_stay_within_their_limit() {
    let mut rig = Rig::with(Options {
        rc: true,
        ..Options::default()
    });
    let after_boot = rig.ram();
    // The library's read sets and reads of each kind.
    let set0 = [
        0x17, 0x14, 0x00, 1, 2, 3, 5, 44, 16, 17, 18, 19, 20, 21, 22, 23, 33, 34, 35, 36, 37, 38,
        39,
    ];
    assert_eq!(rig.exchange(&set0, 1), [0x14]);
    rig.exchange(&[0x03, 0x13, 0x00], 40);
    let set2 = [0x0e, 0x04, 0x02, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11];
    assert_eq!(rig.exchange(&set2, 1), [11]);
    rig.exchange(&[0x03, 0x03, 0x02], 22);
    // The longest frame: 255 bytes, 84 two-byte writes to slave 1.
    let mut long = vec![0xff, 0x12, 84];
    for _ in 0..84 {
        long.extend_from_slice(&[0x09, 0xff, 0x7f]);
    }
    assert_eq!(rig.exchange(&long, 1), [0x00]);
    assert_eq!(rig.slave(1).writes_to(0x09).len(), 84);
    rig.reset_master();
    // Pings, liveness checks and temperature ticks, then a slave goes silent.
    rig.run_to(7_100_000);
    rig.bus.cut(4);
    rig.run_us(100_000);
    assert_eq!(rig.master_exception(), 0x040b);
    rig.bus.restore(4);
    // Remote control: link-up writes and passes, with the temperature ticks going on.
    let rc = rig.rc.take().unwrap();
    rc.set_width(0, 1200);
    rc.set_width(1, 1500);
    rc.turn_on();
    rig.run_us(2_500_000);
    rc.turn_off();
    rig.run_us(1_100_000);
    rig.exchange(&[0x03, 0x03, 0x02], 22);
    let ram = rig.ram();
    let bound = Program::of_elf(&firmware_path("master"))
        .and_then(|p| p.bound())
        .expect("a static stack bound")
        .total;
    println!(
        "static RAM {} B, stack high-water {} B (after boot {} B; static bound {bound} B), \
         total {} B, {} B never used; goal {} B",
        ram.statics,
        ram.stack,
        after_boot.stack,
        ram.total(),
        RAM - ram.total(),
        ORIGINAL_STATIC_RAM
    );
    // The workload went deeper than the boot, within the bound, and within the goal.
    assert!(ram.stack > after_boot.stack && ram.stack > 100, "{ram:?}");
    assert!(
        u32::from(ram.stack) <= bound,
        "{ram:?} beyond the bound {bound}"
    );
    assert!(ram.total() < ORIGINAL_STATIC_RAM, "{ram:?}");
}
