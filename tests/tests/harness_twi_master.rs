//! Emulator tests of the I²C bus with real master firmware (`fixture_twi_master`) driving a
//! Rust model and real slave firmware, and of the bus timing simavr gives the master.

use harness::bus::{Bus, Initiator, TraceEntry, TwiEvent};
use harness::twi::{RegisterTarget, TargetEvent};
use harness::Avr;

/// Longest wait for one UART answer of the master fixture.
const ANSWER_US: u64 = 20_000;

/// A bus whose chip 0 runs the master fixture, booted to its banner.
fn bus_with_master() -> Bus {
    let mut bus = Bus::new();
    let master = bus
        .add_master(Avr::firmware("fixture_twi_master").unwrap())
        .unwrap();
    assert_eq!(master, 0);
    let banner = bus.uart_read_until(0, b"\n", ANSWER_US).unwrap();
    assert_eq!(banner, b"twi master\n");
    bus
}

/// Sends one command line to the master fixture and returns its answer line.
fn command(bus: &mut Bus, line: &str) -> String {
    command_within(bus, line, ANSWER_US)
}

/// The same, waiting up to `us` for the answer.
fn command_within(bus: &mut Bus, line: &str, us: u64) -> String {
    bus.uart_send(0, format!("{line}\n").as_bytes());
    let answer = bus.uart_read_until(0, b"\n", us).unwrap();
    String::from_utf8(answer).unwrap()
}

fn slave_at(addr: u8) -> Avr {
    let mut avr = Avr::firmware("fixture_twi_slave").unwrap();
    avr.eeprom_write(0, &[addr]);
    avr
}

/// Cycle gaps between consecutive data bytes written by the master chip.
fn write_gaps(trace: &[TraceEntry]) -> Vec<u64> {
    let stamps: Vec<u64> = trace
        .iter()
        .filter(|e| e.by == Initiator::Chip(0) && matches!(e.event, TwiEvent::Write { .. }))
        .map(|e| e.cycle)
        .collect();
    stamps.windows(2).map(|w| w[1] - w[0]).collect()
}

#[test]
fn a_slave_that_keeps_twint_set_holds_the_bus_until_it_resets() {
    let mut bus = bus_with_master();
    bus.add_slave(slave_at(0x21)).unwrap();
    let mut stuck = Avr::firmware("fixture_twi_stuck").unwrap();
    stuck.eeprom_write(0, &[0x30]);
    let stuck = bus.add_slave(stuck).unwrap();
    bus.set_answer_timeout_us(300);
    bus.run_us(2_000);
    assert_eq!(command(&mut bus, "w 21 00 5a"), "ok\n", "the bus works");
    // The stuck chip takes its address and never releases SCL: the master's TWINT never
    // rises, so the fixture gives the step up after its polls.
    let at = bus.micros();
    assert_eq!(command_within(&mut bus, "w 30 01", 2_000_000), "err\n");
    assert_eq!(bus.held_by(), Some(0x30));
    assert!(bus.micros() - at > 10_000, "it waited out its polls");
    // Nothing reaches a healthy slave meanwhile, and the bus logs none of it.
    bus.take_trace();
    assert_eq!(command_within(&mut bus, "w 21 00 a5", 2_000_000), "err\n");
    assert_eq!(bus.take_trace(), []);
    // A reset switches the stuck chip's TWI off: the bus is free and works again.
    bus.chip(stuck).unwrap().reset();
    bus.run_us(10);
    assert_eq!(bus.held_by(), None);
    assert_eq!(
        command(&mut bus, "x 21 00 01"),
        "= 5A\n",
        "the write while held never landed"
    );
}

#[test]
fn master_firmware_talks_to_rust_model() {
    let mut bus = bus_with_master();
    let id = bus.add_target(RegisterTarget::new(0x40, 16));
    assert_eq!(command(&mut bus, "w 40 02 11 22 33"), "ok\n");
    assert_eq!(command(&mut bus, "x 40 02 03"), "= 11 22 33\n");
    let model = bus.target(&id).unwrap();
    assert_eq!(
        model.events,
        [
            TargetEvent::StartWrite,
            TargetEvent::Write(0x02),
            TargetEvent::Write(0x11),
            TargetEvent::Write(0x22),
            TargetEvent::Write(0x33),
            TargetEvent::Stop,
            TargetEvent::StartWrite,
            TargetEvent::Write(0x02),
            TargetEvent::Stop,
            TargetEvent::StartRead,
            TargetEvent::Read(0x11),
            TargetEvent::Read(0x22),
            TargetEvent::Read(0x33),
            TargetEvent::Stop,
        ]
    );
    assert_eq!(model.writes(), [vec![0x02, 0x11, 0x22, 0x33], vec![0x02]]);
}

#[test]
fn master_firmware_sees_nack_for_absent_address() {
    let mut bus = bus_with_master();
    bus.add_target(RegisterTarget::new(0x40, 4));
    bus.take_trace();
    assert_eq!(command(&mut bus, "w 41 00 01"), "nack\n");
    assert_eq!(command(&mut bus, "r 41 01"), "nack\n");
    let events: Vec<TwiEvent> = bus.trace().iter().map(|e| e.event).collect();
    assert_eq!(
        events,
        [
            TwiEvent::Start {
                addr: 0x41,
                read: false,
                ack: false
            },
            TwiEvent::Stop,
            TwiEvent::Start {
                addr: 0x41,
                read: true,
                ack: false
            },
            TwiEvent::Stop,
        ]
    );
    bus.cut(0x40);
    assert_eq!(command(&mut bus, "w 40 00 01"), "nack\n");
    bus.restore(0x40);
    assert_eq!(command(&mut bus, "w 40 00 01"), "ok\n");
}

#[test]
fn master_firmware_and_two_slave_chips_on_one_bus() {
    let mut bus = bus_with_master();
    assert_eq!(bus.add_slave(slave_at(1)).unwrap(), 1);
    assert_eq!(bus.add_slave(slave_at(2)).unwrap(), 2);
    bus.run_us(200);
    assert_eq!(command(&mut bus, "w 01 00 A1 A2 A3"), "ok\n");
    assert_eq!(command(&mut bus, "w 02 00 B1 B2"), "ok\n");
    assert_eq!(command(&mut bus, "x 01 00 03"), "= A1 A2 A3\n");
    assert_eq!(command(&mut bus, "x 02 00 03"), "= B1 B2 00\n");
    assert_eq!(command(&mut bus, "x 03 00 01"), "nack\n");
    // The Rust master on the same bus reads the same registers back.
    assert_eq!(bus.write_read(1, &[0], 4).unwrap(), [0xA1, 0xA2, 0xA3, 0]);
    assert_eq!(bus.write_read(2, &[1], 1).unwrap(), [0xB2]);
    // Lock step: every chip is within a quantum plus one slave answer of bus time.
    let now = bus.cycles();
    for i in 0..bus.chip_count() {
        let c = bus.chip(i).unwrap().cycles();
        assert!(c >= now && c - now < 400, "chip {i} at {c}, bus at {now}");
    }
}

#[test]
fn byte_time_is_90_us_at_100_khz_and_22_5_us_at_400_khz() {
    let mut bus = bus_with_master();
    bus.add_target(RegisterTarget::new(0x40, 16));
    bus.take_trace();
    assert_eq!(command(&mut bus, "w 40 00 01 02 03 04"), "ok\n");
    let gaps = write_gaps(&bus.take_trace());
    assert_eq!(gaps.len(), 4);
    // 9 bit times of 160 cycles (TWBR 72, prescaler 1), plus the firmware's instructions
    // between TWINT and the next byte (at most 5 µs).
    for gap in &gaps {
        assert!((1440..=1440 + 80).contains(gap), "100 kHz gaps {gaps:?}");
    }
    assert_eq!(command(&mut bus, "f 0c 00"), "ok\n");
    assert_eq!(command(&mut bus, "w 40 00 01 02 03 04"), "ok\n");
    let gaps = write_gaps(&bus.take_trace());
    assert_eq!(gaps.len(), 4);
    for gap in &gaps {
        assert!((360..=360 + 80).contains(gap), "400 kHz gaps {gaps:?}");
    }
}

#[test]
fn slave_chip_answers_keep_the_master_timing() {
    let mut bus = bus_with_master();
    bus.add_slave(slave_at(1)).unwrap();
    bus.run_us(200);
    bus.take_trace();
    assert_eq!(command(&mut bus, "w 01 00 01 02 03"), "ok\n");
    let gaps = write_gaps(&bus.take_trace());
    assert_eq!(gaps.len(), 3);
    for gap in &gaps {
        assert!((1440..=1440 + 80).contains(gap), "gaps {gaps:?}");
    }
}

#[test]
fn rust_master_waits_for_the_master_chip_to_finish() {
    let mut bus = bus_with_master();
    let id = bus.add_target(RegisterTarget::new(0x40, 16));
    bus.uart_send(0, b"w 40 00 01 02 03 04 05 06 07 08\n");
    let started = bus.run_until(ANSWER_US, |b| !b.trace().is_empty());
    assert!(started);
    // The chip's write is under way: the peer waits for its STOP, then writes.
    bus.write(0x40, &[8, 0xEE]).unwrap();
    assert_eq!(bus.uart_read_until(0, b"\n", ANSWER_US).unwrap(), b"ok\n");
    let trace = bus.trace();
    let chip_stop = trace
        .iter()
        .position(|e| e.by == Initiator::Chip(0) && e.event == TwiEvent::Stop)
        .unwrap();
    let peer_start = trace.iter().position(|e| e.by == Initiator::Peer).unwrap();
    assert!(chip_stop < peer_start, "{trace:#?}");
    assert!(trace[chip_stop].cycle <= trace[peer_start].cycle);
    let model = bus.target(&id).unwrap();
    assert_eq!(model.regs[..9], [1, 2, 3, 4, 5, 6, 7, 8, 0xEE]);
}

#[test]
fn master_chip_starting_during_a_peer_transfer_is_refused() {
    let mut bus = bus_with_master();
    bus.add_target(RegisterTarget::new(0x40, 32));
    // The command takes 11 UART bytes (≈ 1.03 ms) to arrive; the peer's 31-byte write takes
    // ≈ 2.9 ms, so the master firmware starts in the middle of it.
    bus.uart_send(0, b"w 40 00 01\n");
    let data: Vec<u8> = (0..31).collect();
    bus.write(0x40, &data).unwrap();
    assert_eq!(bus.uart_read_until(0, b"\n", ANSWER_US).unwrap(), b"nack\n");
    let trace = bus.trace();
    let collision = trace.iter().find(|e| e.by == Initiator::Chip(0)).unwrap();
    assert_eq!(collision.event, TwiEvent::Collision { addr: 0x40 });
}
