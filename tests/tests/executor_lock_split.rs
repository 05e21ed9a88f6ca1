//! Emulator test of `exec_lock_split`: a lock whose level has sources in two enable
//! registers (INT1 in EIMSK, PCINT0 in PCICR) holds both off, even when the other source
//! fires while the lock is clearing them one register at a time.

mod executor_support;

use std::cell::Cell;
use std::rc::Rc;

use executor_support::{boot, fields, report};
use harness::{Avr, Pin};

/// Data-space addresses of the registers the probe watches.
const EIMSK: u16 = 0x3d;
const PCICR: u16 = 0x68;
const PORTD: u16 = 0x2b;
/// INT1's enable in EIMSK, PCIE0 in PCICR, the firmware's "armed" flag PD5 in PORTD.
const INT1: u8 = 1 << 1;
const PCIE0: u8 = 1 << 0;
const ARMED: u8 = 1 << 5;

/// Toggles PB1 (PCINT0) once per armed round, at the first instruction after which INT1
/// is disabled while PCINT0 is still enabled: the middle of the lock's masking.
fn probe(avr: &mut Avr, injected: Rc<Cell<u32>>) {
    let mut was_enabled = false;
    let mut done = false;
    let mut level = false;
    avr.set_observer(move |avr| {
        let armed = avr.read_data(PORTD) & ARMED != 0;
        if !armed {
            done = false;
        }
        let int1 = avr.read_data(EIMSK) & INT1 != 0;
        let pcie0 = avr.read_data(PCICR) & PCIE0 != 0;
        if armed && !done && was_enabled && !int1 && pcie0 {
            level = !level;
            avr.set_pin(Pin::new('B', 1), level);
            injected.set(injected.get() + 1);
            done = true;
        }
        was_enabled = int1;
    });
}

#[test]
fn a_lock_over_a_level_split_across_two_registers_holds_the_whole_level_off() {
    let mut avr = boot("exec_lock_split");
    let injected = Rc::new(Cell::new(0));
    probe(&mut avr, injected.clone());
    let line = report(&mut avr, "split", 200_000);
    let f = fields(&line);
    let rounds = f["rounds"];
    // Every round was probed at its worst instant, and each pin change was served once.
    assert_eq!(injected.get(), rounds, "{line}");
    assert_eq!(f["pin"], rounds, "{line}");
    // Each INT1 fired inside the lock ran once, after it: never while the lock was held.
    assert_eq!(f["edge"], rounds, "{line}");
    assert_eq!(f["inside"], 0, "{line}");
}
