//! The master's frame logic against a fake I2C bus, fed through the real parser.

use super::*;
use crate::protocol::Parser;
use crate::regs::id;
use std::vec::Vec;

/// A bus that records every transaction and answers reads from a byte pattern.
#[derive(Default)]
struct FakeBus {
    writes: Vec<(u8, u8, Vec<u8>)>,
    reads: Vec<(u8, u8, usize)>,
    silent: Vec<u8>,
    /// (device, register) writes that are not acknowledged.
    refused: Vec<(u8, u8)>,
}

impl SlaveBus for FakeBus {
    fn write_register(&mut self, device: u8, id: u8, value: &[u8]) -> Result<(), BusError> {
        if self.silent.contains(&device) || self.refused.contains(&(device, id)) {
            return Err(BusError);
        }
        self.writes.push((device, id, value.to_vec()));
        Ok(())
    }

    fn read_run(
        &mut self,
        device: u8,
        first: u8,
        len: u8,
        sink: &mut dyn FnMut(u8),
    ) -> Result<(), BusError> {
        if self.silent.contains(&device) {
            return Err(BusError);
        }
        self.reads.push((device, first, usize::from(len)));
        // A slave's register file as bytes: register r's bytes are 2r, 2r+1.
        for i in 0..len {
            sink(first.wrapping_mul(2).wrapping_add(i));
        }
        Ok(())
    }
}

/// The frame logic with its read sets, as the firmware keeps them.
#[derive(Default)]
struct Master {
    service: Service,
    sets: crate::protocol::ReadSets,
}

impl core::ops::Deref for Master {
    type Target = Service;

    fn deref(&self) -> &Service {
        &self.service
    }
}

/// Feeds `bytes` through a parser into `master`; returns every reply byte.
fn run(master: &mut Master, bus: &mut FakeBus, bytes: &[u8]) -> Vec<u8> {
    let mut parser = Parser::new();
    let mut out = Vec::new();
    for &b in bytes {
        if let Some(frame) = parser.push_frame(b) {
            let sets = &mut master.sets;
            master
                .service
                .execute(sets, frame, bus, &mut |r| out.push(r));
        }
    }
    out
}

fn exception_data(service: &Service) -> Option<u16> {
    service.local.read(id::REGMASTER_EXCEPTIONDATA)
}

#[test]
fn master_reset_write_clears_the_boot_exception_and_answers_00() {
    let (mut s, mut bus) = (Master::default(), FakeBus::default());
    assert_eq!(exception_data(&s), Some(0x0002));
    assert_eq!(
        run(&mut s, &mut bus, &[0x05, 0x02, 0x01, 0x00, 0x01]),
        [0x00]
    );
    assert_eq!(exception_data(&s), Some(0));
    assert!(bus.writes.is_empty());
    assert_eq!(s.local.error_count(), 0);
}

#[test]
fn library_set_2_then_read_gives_22_bytes_of_master_state() {
    let (mut s, mut bus) = (Master::default(), FakeBus::default());
    let set2 = [0x0e, 0x04, 0x02, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11];
    assert_eq!(run(&mut s, &mut bus, &set2), [0x0b]);
    let reply = run(&mut s, &mut bus, &[0x03, 0x03, 0x02]);
    let mut expected = Vec::new();
    for _ in 0..10 {
        expected.extend_from_slice(&[0xaa, 0x2a]); // 0.0 °C
    }
    expected.extend_from_slice(&[0x02, 0x00]); // boot exception
    assert_eq!(reply, expected);
}

#[test]
fn write_to_a_read_only_register_changes_nothing_and_says_why() {
    let (mut s, mut bus) = (Master::default(), FakeBus::default());
    // REGMASTER_RESET (ok) and TEMP1 (read-only) in one frame: neither is applied.
    let frame = [0x08, 0x02, 0x02, 0x00, 0x01, 0x02, 0x00, 0x00];
    assert_eq!(run(&mut s, &mut bus, &frame), [0x80 | 9]);
    assert_eq!(exception_data(&s), Some(0x0002), "reset was not applied");
    assert_eq!(s.local.read(id::REGMASTER_LASTERROR), Some(9));
    assert_eq!(s.local.read(id::REGMASTER_ERRORCOUNT), Some(1));
    // The same on a slave: no I2C traffic at all.
    let frame = [0x09, 0x12, 0x02, 0x09, 0xfe, 0x9f, 0x10, 0x00, 0x00];
    assert_eq!(run(&mut s, &mut bus, &frame), [0x89]);
    assert!(bus.writes.is_empty());
}

#[test]
fn slave_writes_are_relayed_in_order_with_their_sizes() {
    let (mut s, mut bus) = (Master::default(), FakeBus::default());
    // Wheel 1 drive 1000 (reference §4.5), then a 1-byte write (DEADZONE 25 = 0x05).
    assert_eq!(
        run(&mut s, &mut bus, &[0x06, 0x12, 0x01, 0x09, 0xfe, 0x9f]),
        [0]
    );
    assert_eq!(run(&mut s, &mut bus, &[0x05, 0x12, 0x01, 0x19, 0x05]), [0]);
    assert_eq!(
        bus.writes,
        vec![(1, 9, vec![0xfe, 0x9f]), (1, 25, vec![0x05])]
    );
}

#[test]
fn slave_reads_follow_the_set_and_the_board_table() {
    let (mut s, mut bus) = (Master::default(), FakeBus::default());
    // Set 1 of the library (LL): 18 ids, 36 bytes.
    let set1 = [
        0x15, 0x34, 0x01, 1, 2, 3, 5, 16, 17, 18, 19, 20, 21, 22, 34, 35, 36, 37, 38, 39, 40,
    ];
    assert_eq!(run(&mut s, &mut bus, &set1), [18]);
    let reply = run(&mut s, &mut bus, &[0x03, 0x33, 0x01]);
    assert_eq!(reply.len(), 36);
    assert_eq!(&reply[..4], &[2, 3, 4, 5]); // the run from id 1
                                            // Contiguous ids go as one run each: 1-3, 5, 16-22, 34-40 (all 2-byte on LL here).
    assert_eq!(
        bus.reads,
        vec![(3, 1, 6), (3, 5, 2), (3, 16, 14), (3, 34, 14)]
    );
}

#[test]
fn library_set_0_on_a_drive_board_is_five_runs_of_mixed_sizes() {
    let (mut s, mut bus) = (Master::default(), FakeBus::default());
    let set0 = [
        0x17, 0x14, 0x00, 1, 2, 3, 5, 44, 16, 17, 18, 19, 20, 21, 22, 23, 33, 34, 35, 36, 37, 38,
        39,
    ];
    assert_eq!(run(&mut s, &mut bus, &set0), [20]);
    assert_eq!(run(&mut s, &mut bus, &[0x03, 0x13, 0x00]).len(), 40);
    assert_eq!(
        bus.reads,
        vec![(1, 1, 6), (1, 5, 2), (1, 44, 2), (1, 16, 16), (1, 33, 14)]
    );
}

#[test]
fn a_run_stops_at_a_one_byte_gap_in_sizes_correctly() {
    let (mut s, mut bus) = (Master::default(), FakeBus::default());
    // LL ids 22 (2 bytes), 23, 24, 25, 26 (1 byte each): one run of 6 bytes.
    assert_eq!(
        run(&mut s, &mut bus, &[0x08, 0x34, 0x04, 22, 23, 24, 25, 26]),
        [5]
    );
    assert_eq!(run(&mut s, &mut bus, &[0x03, 0x33, 0x04]).len(), 6);
    assert_eq!(bus.reads, vec![(3, 22, 6)]);
}

#[test]
fn bad_device_write_answers_an_error_and_a_bad_device_read_answers_nothing() {
    let (mut s, mut bus) = (Master::default(), FakeBus::default());
    assert_eq!(
        run(&mut s, &mut bus, &[0x05, 0xa2, 0x01, 0x00, 0x01]),
        [0x82]
    );
    assert_eq!(run(&mut s, &mut bus, &[0x03, 0xf3, 0x00]), [0u8; 0]);
    assert_eq!(s.local.read(id::REGMASTER_LASTERROR), Some(2));
    assert_eq!(s.local.error_count(), 2);
    assert!(bus.writes.is_empty() && bus.reads.is_empty());
}

#[test]
fn unknown_command_and_short_lengths_are_recorded_and_answered_only_if_a_write() {
    let (mut s, mut bus) = (Master::default(), FakeBus::default());
    assert_eq!(run(&mut s, &mut bus, &[0x03, 0x15, 0x00]), [0u8; 0]);
    assert_eq!(s.local.last_error(), Some(LinkError::UnknownCommand));
    assert_eq!(run(&mut s, &mut bus, &[0x00]), [0u8; 0]);
    // L = 2 with a write header: a write's one-byte reply can carry the error.
    assert_eq!(run(&mut s, &mut bus, &[0x02, 0x12]), [0x81]);
    assert_eq!(run(&mut s, &mut bus, &[0x02, 0x13]), [0u8; 0]);
    assert_eq!(s.local.last_error(), Some(LinkError::BadLength));
    assert_eq!(s.local.error_count(), 4);
}

#[test]
fn empty_set_and_missing_registers() {
    let (mut s, mut bus) = (Master::default(), FakeBus::default());
    assert_eq!(run(&mut s, &mut bus, &[0x03, 0x03, 0x05]), [0u8; 0]);
    assert_eq!(s.local.last_error(), Some(LinkError::EmptyReadSet));
    // Set 6 = [EXCEPTIONDATA, 16 (no such register), LASTERROR].
    assert_eq!(run(&mut s, &mut bus, &[0x06, 0x04, 0x06, 11, 16, 12]), [3]);
    let reply = run(&mut s, &mut bus, &[0x03, 0x03, 0x06]);
    assert_eq!(reply, [0x02, 0x00, 0xcd, 11]);
    assert_eq!(s.local.last_error(), Some(LinkError::MissingRegister));
}

#[test]
fn oversize_set_gets_an_error_reply_that_no_count_can_equal() {
    let (mut s, mut bus) = (Master::default(), FakeBus::default());
    let mut frame = vec![28, 0x04, 0x03];
    frame.extend(0..25u8);
    assert_eq!(run(&mut s, &mut bus, &frame), [0x87]);
    assert_eq!(
        run(&mut s, &mut bus, &[0x03, 0x03, 0x03]),
        [0u8; 0],
        "set 3 stayed empty"
    );
}

#[test]
fn a_write_the_slave_refuses_does_not_stop_the_writes_after_it() {
    // An emergency stop's frame for wheel 1's drive: P, I, then REQSPEED 0 (0x7fff), with
    // I's write not acknowledged.
    let (mut s, mut bus) = (Master::default(), FakeBus::default());
    bus.refused.push((1, 0x0b));
    let frame = [
        0x0c, 0x12, 0x03, 0x0a, 0x00, 0x00, 0x0b, 0x00, 0x00, 0x09, 0xff, 0x7f,
    ];
    assert_eq!(
        run(&mut s, &mut bus, &frame),
        [0x8c],
        "the failure reported"
    );
    assert_eq!(
        bus.writes,
        [(1, 0x0a, vec![0x00, 0x00]), (1, 0x09, vec![0xff, 0x7f])],
        "the demand still written"
    );
    assert_eq!(s.local.last_error(), Some(LinkError::NoAnswer));
}

#[test]
fn a_silent_slave_is_reported_and_the_master_keeps_answering() {
    let (mut s, mut bus) = (Master::default(), FakeBus::default());
    bus.silent.push(4);
    assert_eq!(
        run(&mut s, &mut bus, &[0x06, 0x42, 0x01, 0x09, 0xfe, 0x9f]),
        [0x8c]
    );
    assert_eq!(run(&mut s, &mut bus, &[0x04, 0x04, 0x00, 0x01]), [1]);
    assert_eq!(run(&mut s, &mut bus, &[0x03, 0x43, 0x00]), [0u8; 0]);
    assert_eq!(s.local.last_error(), Some(LinkError::NoAnswer));
    // Device 0 still answers.
    assert_eq!(run(&mut s, &mut bus, &[0x05, 0x02, 0x01, 0x00, 0x01]), [0]);
}

#[test]
fn garbage_then_abort_then_a_valid_frame_is_answered() {
    let (mut s, mut bus) = (Master::default(), FakeBus::default());
    let mut parser = Parser::new();
    let mut out = Vec::new();
    for &b in &[0x40u8, 0x99, 0x12, 0x00] {
        assert!(parser.push_frame(b).is_none());
    }
    assert!(
        parser.abort(),
        "the inter-byte timeout drops the partial frame"
    );
    s.service.link_error(LinkError::Truncated);
    for &b in &[0x05u8, 0x02, 0x01, 0x00, 0x01] {
        if let Some(f) = parser.push_frame(b) {
            s.service
                .execute(&mut s.sets, f, &mut bus, &mut |r| out.push(r));
        }
    }
    assert_eq!(out, [0]);
    assert_eq!(exception_data(&s), Some(0));
    assert_eq!(s.local.read(id::REGMASTER_LASTERROR), Some(8));
}

#[test]
fn error_codes_round_trip_and_replies_carry_the_flag() {
    let mut known = 0;
    for code in 0..=255u8 {
        if let Some(e) = LinkError::from_code(code) {
            assert_eq!(e.code(), code);
            assert_eq!(e.reply(), 0x80 | code);
            assert!(!e.describe().is_empty());
            known += 1;
        }
    }
    // Codes 1..=14 (docs/protocol.md), and nothing else.
    assert_eq!(known, 14);
    assert_eq!(LinkError::from_code(0), None);
}
