//! The master's ping in the emulator, with nine slave models (reference §5, §6): from
//! 5 s, `07 00` and a STATUS read to each slave (and EXCEPTIONDATA when STATUS bit 0 is
//! set); a slave's exception is latched and spread unless it is BOOT or REMOTESLAVE, and
//! nothing is latched or spread while the master itself is in exception.

mod master_support;

use master_support::Rig;

/// REG_EXCEPTIONDATA = 100, the spreading write.
const SPREAD: [u8; 3] = [0x05, 0x64, 0x00];

/// Slaves that received the spreading write.
fn spread_to(rig: &Rig) -> Vec<u8> {
    (1..=9)
        .filter(|&a| rig.slave(a).writes.contains(&SPREAD.to_vec()))
        .collect()
}

#[test]
fn an_overcurrent_on_slave_4_is_latched_as_0x1401_and_spread_to_the_others() {
    let mut rig = Rig::new();
    // Every slave left its boot exception (as the PC library's reset would do).
    for addr in 1..=9 {
        rig.slave(addr).in_exception = false;
    }
    rig.reset_master();
    rig.slave(4).raise(1, 1);
    rig.run_to(5_200_000);
    assert_eq!(rig.master_exception(), 0x1401);
    assert_eq!(spread_to(&rig), vec![1, 2, 3, 5, 6, 7, 8, 9]);
    // Each of them is now in REMOTESLAVE (type 3, motor 5); the next pings read that
    // and spread nothing more.
    assert_eq!(rig.slave(1).exception_data, 0x0503);
    rig.clear_records();
    rig.run_to(7_300_000);
    assert!(spread_to(&rig).is_empty());
    assert_eq!(rig.master_exception(), 0x1401);
}

#[test]
fn boot_and_remote_exceptions_are_not_spread() {
    let mut rig = Rig::new();
    rig.reset_master();
    // Slaves 1..8 are still in their boot exception; slave 9 reports REMOTESLAVE.
    {
        let mut s = rig.slave(9);
        s.in_exception = false;
        s.raise(3, 5);
    }
    rig.run_to(6_300_000);
    for addr in 1..=9 {
        let s = rig.slave(addr);
        assert!(
            s.reads >= 4,
            "slave {addr} pinged twice ({} reads)",
            s.reads
        );
    }
    assert!(spread_to(&rig).is_empty());
    assert_eq!(rig.master_exception(), 0);
}

#[test]
fn nothing_is_spread_while_the_master_is_in_exception() {
    let mut rig = Rig::new();
    // The master stays in its boot exception: slave 4's overcurrent is neither latched
    // nor spread.
    for addr in 1..=9 {
        rig.slave(addr).in_exception = false;
    }
    rig.slave(4).raise(1, 1);
    rig.run_to(6_300_000);
    assert!(spread_to(&rig).is_empty());
    assert_eq!(rig.master_exception(), 0x0002, "still the boot exception");
    // Reset the master: the next ping finds the slave still in exception and spreads it.
    rig.reset_master();
    rig.run_to(7_400_000);
    assert_eq!(rig.master_exception(), 0x1401);
    assert_eq!(spread_to(&rig), vec![1, 2, 3, 5, 6, 7, 8, 9]);
}
