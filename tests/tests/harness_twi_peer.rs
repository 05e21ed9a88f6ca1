//! Emulator tests of the I²C bus with the Rust master peer driving real slave firmware
//! (`fixture_twi_slave`, `fixture_twi_stuck`) and a Rust model.

use harness::bus::{Bus, Initiator, TwiEvent};
use harness::twi::{RegisterTarget, TargetEvent, TwiError};
use harness::Avr;

/// Register id of the fixture slave's completed-writes counter.
const REG_WRITES: u8 = 0x10;
/// Emulated time the fixture slaves need to boot and enable their TWI.
const BOOT_US: u64 = 200;

/// A chip running `firmware` with its bus address in EEPROM byte 0.
fn chip_at(firmware: &str, addr: u8) -> Avr {
    let mut avr = Avr::firmware(firmware).unwrap();
    avr.eeprom_write(0, &[addr]);
    avr
}

/// A bus with fixture slaves at the given addresses, booted.
fn bus_with_slaves(addrs: &[u8]) -> Bus {
    let mut bus = Bus::new();
    for &addr in addrs {
        bus.add_slave(chip_at("fixture_twi_slave", addr)).unwrap();
    }
    bus.run_us(BOOT_US);
    bus
}

#[test]
fn write_then_read_back_exact_bytes() {
    let mut bus = bus_with_slaves(&[0x21]);
    bus.write(0x21, &[3, 0xDE, 0xAD, 0xBE]).unwrap();
    assert_eq!(bus.write_read(0x21, &[3], 3).unwrap(), [0xDE, 0xAD, 0xBE]);
    // The pointer went on past register 5: registers 6 and 7 were never written.
    assert_eq!(bus.read(0x21, 2).unwrap(), [0, 0]);
    assert_eq!(bus.write_read(0x21, &[2], 3).unwrap(), [0, 0xDE, 0xAD]);
    // Completed writes so far: [3,DE,AD,BE], [3], [2], and the [REG_WRITES] select itself,
    // which the repeated START ends (0xA0) before the counter is read.
    assert_eq!(bus.write_read(0x21, &[REG_WRITES], 1).unwrap(), [4]);
}

#[test]
fn trace_logs_every_event_in_order() {
    let mut bus = bus_with_slaves(&[0x21]);
    bus.take_trace();
    bus.write_read(0x21, &[1], 2).unwrap();
    let events: Vec<TwiEvent> = bus.trace().iter().map(|e| e.event).collect();
    assert_eq!(
        events,
        [
            TwiEvent::Start {
                addr: 0x21,
                read: false,
                ack: true
            },
            TwiEvent::Write { byte: 1, ack: true },
            TwiEvent::Start {
                addr: 0x21,
                read: true,
                ack: true
            },
            TwiEvent::Read { byte: 0, ack: true },
            TwiEvent::Read {
                byte: 0,
                ack: false
            },
            TwiEvent::Stop,
        ]
    );
    assert!(bus.trace().iter().all(|e| e.by == Initiator::Peer));
    let stamps: Vec<u64> = bus.trace().iter().map(|e| e.cycle).collect();
    assert!(
        stamps.windows(2).all(|w| w[0] < w[1]),
        "stamps increase: {stamps:?}"
    );
}

#[test]
fn wrong_address_is_nacked() {
    let mut bus = bus_with_slaves(&[0x21]);
    bus.take_trace();
    assert_eq!(
        bus.write(0x22, &[1, 2]),
        Err(TwiError::AddressNack { addr: 0x22 })
    );
    assert_eq!(bus.read(0x20, 1), Err(TwiError::AddressNack { addr: 0x20 }));
    let events: Vec<TwiEvent> = bus.trace().iter().map(|e| e.event).collect();
    assert_eq!(
        events,
        [
            TwiEvent::Start {
                addr: 0x22,
                read: false,
                ack: false
            },
            TwiEvent::Stop,
            TwiEvent::Start {
                addr: 0x20,
                read: true,
                ack: false
            },
            TwiEvent::Stop,
        ]
    );
    // The right address still works afterwards.
    bus.write(0x21, &[0, 0x5A]).unwrap();
    assert_eq!(bus.write_read(0x21, &[0], 1).unwrap(), [0x5A]);
}

#[test]
fn cut_slave_fails_fast_and_restores() {
    let mut bus = bus_with_slaves(&[0x21]);
    bus.write(0x21, &[0, 0x11]).unwrap();
    bus.cut(0x21);
    assert!(bus.is_cut(0x21));
    let before = bus.micros();
    assert_eq!(
        bus.write(0x21, &[0, 0x22]),
        Err(TwiError::AddressNack { addr: 0x21 })
    );
    assert_eq!(bus.read(0x21, 1), Err(TwiError::AddressNack { addr: 0x21 }));
    // Two NACKed transactions: START + address + STOP each, 11 bit times of 10 µs.
    assert_eq!(bus.micros() - before, 220);
    bus.restore(0x21);
    assert_eq!(bus.write_read(0x21, &[0], 1).unwrap(), [0x11]);
}

#[test]
fn stuck_slave_gives_bounded_timeout() {
    let mut bus = Bus::new();
    bus.add_slave(chip_at("fixture_twi_stuck", 0x30)).unwrap();
    bus.run_us(BOOT_US);
    bus.set_answer_timeout_us(300);
    let before = bus.micros();
    let wall = std::time::Instant::now();
    assert_eq!(
        bus.write(0x30, &[1, 2]),
        Err(TwiError::Timeout {
            addr: 0x30,
            waited_us: 300
        })
    );
    let spent = bus.micros() - before;
    assert!((300..=320).contains(&spent), "bus time spent: {spent} µs");
    assert!(wall.elapsed().as_secs() < 2);
    let events: Vec<TwiEvent> = bus.trace().iter().map(|e| e.event).collect();
    assert!(
        events.contains(&TwiEvent::Timeout { addr: 0x30 }),
        "{events:?}"
    );
    // Its firmware never clears TWINT, so it holds SCL low: no other transaction gets
    // through, within the peer's bounded wait, until the chip lets go.
    assert_eq!(bus.held_by(), Some(0x30));
    bus.set_busy_timeout_us(2_000);
    assert_eq!(
        bus.write(0x31, &[]),
        Err(TwiError::BusHeld {
            addr: 0x30,
            waited_us: 2_000
        })
    );
    // A reset (as its watchdog would give it) switches its TWI off: the bus is free again,
    // and the next transaction is answered (NACK: nobody at 0x31).
    bus.chip(0).unwrap().reset();
    bus.run_us(10);
    assert_eq!(bus.held_by(), None);
    let released = bus
        .trace()
        .iter()
        .any(|e| e.event == TwiEvent::Released { addr: 0x30 });
    assert!(released, "the release is logged");
    assert_eq!(
        bus.write(0x31, &[]),
        Err(TwiError::AddressNack { addr: 0x31 })
    );
}

#[test]
fn peer_byte_timing_follows_its_clock() {
    let mut bus = bus_with_slaves(&[0x21]);
    let before = bus.cycles();
    bus.write(0x21, &[0, 1, 2]).unwrap();
    // START 1 + (address + 3 bytes) × 9 + STOP 1 = 38 bit times of 160 cycles at 100 kHz.
    assert_eq!(bus.cycles() - before, 38 * 160);
    bus.set_peer_khz(400);
    let before = bus.cycles();
    bus.write(0x21, &[0, 1, 2]).unwrap();
    assert_eq!(bus.cycles() - before, 38 * 40);
    // The slave chip kept pace with the bus.
    let slave = bus.chip(0).unwrap().cycles();
    assert!(
        slave >= bus.cycles() && slave - bus.cycles() < 2 * 160,
        "slave {slave}"
    );
}

#[test]
fn two_slaves_each_get_their_own_bytes() {
    let mut bus = bus_with_slaves(&[1, 2]);
    bus.write(1, &[0, 0xA1, 0xA2]).unwrap();
    bus.write(2, &[0, 0xB1, 0xB2]).unwrap();
    assert_eq!(bus.write_read(1, &[0], 3).unwrap(), [0xA1, 0xA2, 0]);
    assert_eq!(bus.write_read(2, &[0], 3).unwrap(), [0xB1, 0xB2, 0]);
}

#[test]
fn simavr_stop_after_read_is_an_empty_write_to_the_slave() {
    let mut bus = bus_with_slaves(&[0x21]);
    bus.set_simavr_stop_after_read(true);
    bus.write(0x21, &[0, 7, 8]).unwrap();
    bus.write(0x21, &[0]).unwrap();
    assert_eq!(bus.read(0x21, 2).unwrap(), [7, 8]);
    assert_eq!(bus.read(0x21, 1).unwrap(), [0]);
    // Each read's STOP reached the slave as 0xA0 with no byte: nothing happened. Completed
    // writes: [0,7,8], [0] and the [REG_WRITES] select.
    assert_eq!(bus.write_read(0x21, &[REG_WRITES], 1).unwrap(), [3]);
}

#[test]
fn rust_target_sees_exact_events() {
    let mut bus = Bus::new();
    let id = bus.add_target(RegisterTarget::new(0x50, 8));
    bus.write(0x50, &[4, 0x10, 0x20]).unwrap();
    assert_eq!(bus.write_read(0x50, &[4], 2).unwrap(), [0x10, 0x20]);
    let target = bus.target(&id).unwrap();
    assert_eq!(
        target.events,
        [
            TargetEvent::StartWrite,
            TargetEvent::Write(4),
            TargetEvent::Write(0x10),
            TargetEvent::Write(0x20),
            TargetEvent::Stop,
            TargetEvent::StartWrite,
            TargetEvent::Write(4),
            TargetEvent::StartRead,
            TargetEvent::Read(0x10),
            TargetEvent::Read(0x20),
            TargetEvent::Stop,
        ]
    );
    assert_eq!(target.regs[4..6], [0x10, 0x20]);
}
