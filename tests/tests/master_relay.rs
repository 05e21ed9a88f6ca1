//! The real master image on an emulated I2C bus with Rust-side slave models: the boot
//! hard reset, relayed writes and reads (contiguous runs in one transaction), a slave that
//! does not answer, and the time one read of the library's set 0 takes.

use harness::bus::Bus;
use harness::twi::{RegisterTarget, TargetEvent};
use harness::Avr;

/// Emulated time of one byte at 115200 (11 bit times in simavr).
const BYTE_US: f64 = 93.5;

struct Rig {
    bus: Bus,
    slaves: Vec<harness::bus::TargetId<RegisterTarget>>,
}

/// The master with a register-file model at each of addresses 1..9 (byte i of each model
/// holds `addr * 16 + i`), booted to `Ready`.
fn rig() -> Rig {
    let mut bus = Bus::new();
    bus.add_master(Avr::firmware("master").unwrap()).unwrap();
    let slaves = (1..=9u8)
        .map(|addr| {
            let mut model = RegisterTarget::new(addr, 96);
            for (i, r) in model.regs.iter_mut().enumerate() {
                *r = addr.wrapping_mul(16).wrapping_add(i as u8);
            }
            bus.add_target(model)
        })
        .collect();
    bus.uart_read_until(0, b"Ready\r\n", 2_000_000).unwrap();
    Rig { bus, slaves }
}

impl Rig {
    fn exchange(&mut self, frame: &[u8], n: usize) -> Vec<u8> {
        self.bus.uart_send(0, frame);
        let ok = self.bus.run_until(500_000, |b| {
            b.chip(0).map(|c| c.uart_available() >= n).unwrap_or(false)
        });
        assert!(ok, "no {n}-byte reply to {frame:02x?}");
        let reply = self.bus.chip(0).unwrap().uart_take();
        assert_eq!(reply.len(), n, "reply {reply:02x?}");
        reply
    }

    fn model(&self, addr: u8) -> RegisterTarget {
        self.bus
            .target(&self.slaves[usize::from(addr - 1)])
            .unwrap()
            .clone()
    }

    fn clear_events(&mut self) {
        for id in &self.slaves {
            self.bus.target(id).unwrap().events.clear();
        }
    }
}

#[test]
fn boot_hard_resets_every_slave() {
    let rig = rig();
    for addr in 1..=9 {
        assert_eq!(
            rig.model(addr).writes(),
            vec![vec![0x00, 0x02]],
            "slave {addr}"
        );
    }
}

#[test]
fn writes_are_relayed_with_the_boards_sizes() {
    let mut rig = rig();
    rig.clear_events();
    // Wheel 1 drive 1000; wheel 1 lift 20 (controller 3, ONE); reset odometer on 1.
    assert_eq!(rig.exchange(&[0x06, 0x12, 0x01, 0x09, 0xfe, 0x9f], 1), [0]);
    assert_eq!(rig.exchange(&[0x06, 0x32, 0x01, 0x09, 0xcb, 0x8c], 1), [0]);
    assert_eq!(rig.exchange(&[0x05, 0x12, 0x01, 0x00, 0x04], 1), [0]);
    assert_eq!(
        rig.model(1).writes(),
        vec![vec![0x09, 0xfe, 0x9f], vec![0x00, 0x04]]
    );
    assert_eq!(rig.model(3).writes(), vec![vec![0x09, 0xcb, 0x8c]]);
    // A read-only register is refused before any traffic.
    assert_eq!(
        rig.exchange(&[0x06, 0x12, 0x01, 0x10, 0x00, 0x00], 1),
        [0x89]
    );
    assert_eq!(rig.model(1).writes().len(), 2);
}

#[test]
fn library_set_0_is_read_as_five_runs() {
    let mut rig = rig();
    let set0 = [
        0x17, 0x14, 0x00, 1, 2, 3, 5, 44, 16, 17, 18, 19, 20, 21, 22, 23, 33, 34, 35, 36, 37, 38,
        39,
    ];
    assert_eq!(rig.exchange(&set0, 1), [0x14]);
    rig.clear_events();
    let reply = rig.exchange(&[0x03, 0x13, 0x00], 40);
    // The model returns bytes from the register pointer on: 16 + i for byte i.
    let run = |first: u8, n: u8| (first..first + n).map(|i| 16 + i).collect::<Vec<u8>>();
    let mut expected = run(1, 6);
    expected.extend(run(5, 2));
    expected.extend(run(44, 2));
    expected.extend(run(16, 16));
    expected.extend(run(33, 14));
    assert_eq!(reply, expected);
    let reads = rig
        .model(1)
        .events
        .iter()
        .filter(|e| **e == TargetEvent::StartRead)
        .count();
    assert_eq!(reads, 5, "one transaction per run of contiguous ids");
}

#[test]
fn a_slave_that_does_not_answer_is_reported_and_the_master_keeps_answering() {
    let mut rig = rig();
    rig.bus.cut(4);
    assert_eq!(
        rig.exchange(&[0x06, 0x42, 0x01, 0x09, 0xfe, 0x9f], 1),
        [0x8c]
    );
    assert_eq!(rig.exchange(&[0x04, 0x04, 0x00, 0x01], 1), [1]);
    rig.bus.uart_send(0, &[0x03, 0x43, 0x00]);
    rig.bus.run_us(20_000);
    assert!(
        rig.bus.chip(0).unwrap().uart_take().is_empty(),
        "no made-up data"
    );
    // Device 0 answers at once, and the error is on record (NoAnswer = 12).
    assert_eq!(rig.exchange(&[0x06, 0x04, 0x06, 11, 12, 13], 1), [3]);
    assert_eq!(rig.exchange(&[0x03, 0x03, 0x06], 5), [0x02, 0x00, 12, 2, 0]);
}

#[test]
fn one_read_of_set_0_takes_little_more_than_its_wire_time() {
    let mut rig = rig();
    let set0 = [
        0x17, 0x14, 0x00, 1, 2, 3, 5, 44, 16, 17, 18, 19, 20, 21, 22, 23, 33, 34, 35, 36, 37, 38,
        39,
    ];
    rig.exchange(&set0, 1);
    let start = rig.bus.micros();
    rig.exchange(&[0x03, 0x13, 0x00], 40);
    let took = (rig.bus.micros() - start) as f64;
    let wire = 43.0 * BYTE_US;
    println!(
        "set 0 read: {took:.0} us, wire time {wire:.0} us, ratio {:.3}",
        took / wire
    );
    // The original took 13.1 ms for this read; the goal for a whole update, 1.07 x wire,
    // holds for this read alone.
    assert!(took < 1.07 * wire, "{took} us for {wire} us of wire time");
}

#[test]
fn one_write_reaches_the_slave_and_is_answered_right_after_its_last_byte() {
    let mut rig = rig();
    rig.clear_events();
    // Wheel 1 drive 1000, as the PC library writes it: 6 bytes in, 1 byte back.
    let frame = [0x06, 0x12, 0x01, 0x09, 0xfe, 0x9f];
    let start = rig.bus.micros();
    rig.bus.uart_send(0, &frame);
    let controller_1 = &rig.slaves[0];
    let written = rig.bus.run_until(100_000, |b| {
        !b.target(controller_1).unwrap().writes().is_empty()
    });
    assert!(written, "the write never reached controller 1");
    let on_bus = (rig.bus.micros() - start) as f64;
    let ok = rig.bus.run_until(100_000, |b| {
        b.chip(0).map(|c| c.uart_available() >= 1).unwrap_or(false)
    });
    assert!(ok, "no reply");
    let answered = (rig.bus.micros() - start) as f64;
    assert_eq!(rig.bus.chip(0).unwrap().uart_take(), [0]);
    assert_eq!(rig.model(1).writes(), vec![vec![0x09, 0xfe, 0x9f]]);
    let frame_in = frame.len() as f64 * BYTE_US;
    println!(
        "one write: on the slave {on_bus:.0} us after its first byte (the frame takes \
         {frame_in:.0} us), answered at {answered:.0} us (wire time {:.0} us)",
        frame_in + BYTE_US
    );
    // The I2C write (4 bytes at 400 kHz, ~100 us) follows the frame's last byte; the
    // reply byte follows the I2C write.
    assert!(on_bus > frame_in && on_bus < frame_in + 250.0, "{on_bus}");
    assert!(answered < frame_in + BYTE_US + 300.0, "{answered}");
}
