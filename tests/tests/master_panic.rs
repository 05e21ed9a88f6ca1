//! The master's panic path in the real image: running (pinging its nine slave models), the
//! CPU is sent to `__vector_default`, where an unbound interrupt lands and which runs the
//! panic handler's halt (looked up in the ELF). No call in the image can panic, so the
//! linker drops the handler itself; the test checks that this is still so. What a user sees: interrupts
//! off, LED D13 lit, then the 125-ms watchdog reboots the master, which sends the banner
//! again and hard-resets every slave (`00 02`), which stops every motor.

mod master_support;

use harness::{Avr, Pin};
use master_support::Rig;

/// Whether the CPU has interrupts enabled (SREG's I bit, which the emulator keeps
/// apart from the data space).
fn interrupts_on(avr: &mut Avr) -> bool {
    // SAFETY: plain field read of the live core.
    unsafe { (*avr.as_ptr()).sreg[7] != 0 }
}

#[test]
fn a_panic_freezes_the_master_and_its_reboot_hard_resets_every_slave() {
    let mut rig = Rig::new();
    // Past 5 s: pinging the slaves, on the 125-ms watchdog.
    rig.run_to(6_000_000);
    assert_eq!(rig.avr().watchdog_resets(), 0);
    assert!(rig.slave(4).reads > 0, "pinging");
    rig.clear_records();
    {
        let mut avr = rig.avr();
        // A call that can panic would link core's panicking module and the handler: then
        // this test must run the handler itself (it calls the same `halt`).
        let panics = avr
            .symbol_containing("panicking")
            .or(avr.symbol_containing("rust_begin_unwind"));
        assert_eq!(panics, None, "the image can now panic");
        let (name, entry) = avr
            .symbol_containing("__vector_default")
            .expect("the panic entry is in the image");
        println!("panic entry {name} at {entry:#06x}");
        avr.jump_to(entry);
    }
    let at = rig.micros();
    rig.run_us(1_000);
    {
        let mut avr = rig.avr();
        assert!(!interrupts_on(&mut avr), "interrupts off");
        assert!(avr.pin(Pin::d(13)), "LED D13 lit");
        assert_eq!(avr.watchdog_resets(), 0);
    }
    // Frozen: no bus traffic at all.
    rig.run_us(50_000);
    for addr in 1..=9 {
        let s = rig.slave(addr);
        assert!(s.writes.is_empty() && s.reads == 0, "slave {addr} accessed");
    }
    // The 125-ms watchdog, fed last before the panic, reboots it.
    let reset = rig
        .bus
        .run_until(200_000, |bus| bus.chip(0).unwrap().watchdog_resets() == 1);
    assert!(reset, "no watchdog reset");
    let took = rig.micros() - at;
    println!("master: watchdog reboot {took} µs after the panic");
    // The "125-ms" setting is 16K cycles of the 128-kHz watchdog oscillator, 128 ms, fed
    // within the last pass (a few ms) before the panic; 140 leaves room for a slow
    // oscillator, 110 refuses a shorter period.
    assert!((110_000..=140_000).contains(&took), "{took} µs");
    // The banner again, and a hard reset to every slave.
    let banner = rig.read_until(b"Ready\r\n", 1_000_000);
    let text = String::from_utf8_lossy(&banner);
    assert!(text.contains("Starting"), "{text:?}");
    assert_eq!(rig.avr().watchdog_resets(), 1);
    let rebooted_after = rig.micros() - at;
    println!("master: banner again {rebooted_after} µs after the panic");
    for addr in 1..=9 {
        assert_eq!(
            rig.slave(addr).writes,
            vec![vec![0x00, 0x02]],
            "slave {addr} hard-reset"
        );
    }
    // Running again (the LED back to its normal use is not asserted: it shows the
    // boot exception).
    rig.run_us(1_000);
    assert!(interrupts_on(&mut rig.avr()), "interrupts back on");
}
