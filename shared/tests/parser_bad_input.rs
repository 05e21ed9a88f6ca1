//! Every bad-input case of the parser: which error, after how many bytes, and that the
//! next frame still parses.

use shared::protocol::{FrameError, Parser, Request, Write};

/// The results the parser yields while fed `bytes`, with the index of the byte that
/// ended each frame.
fn feed(p: &mut Parser, bytes: &[u8]) -> Vec<(usize, Result<Request, FrameError>)> {
    bytes
        .iter()
        .enumerate()
        .filter_map(|(i, &b)| p.push(b).map(|r| (i, r)))
        .collect()
}

const GOOD: [u8; 3] = [0x03, 0x13, 0x00];

/// `bad` is one frame ending in `error` at its last byte, and `GOOD` after it parses.
fn assert_rejected(bad: &[u8], error: FrameError) {
    let mut p = Parser::new();
    let mut stream = bad.to_vec();
    stream.extend_from_slice(&GOOD);
    let results = feed(&mut p, &stream);
    assert_eq!(
        results,
        vec![
            (bad.len() - 1, Err(error)),
            (stream.len() - 1, Ok(Request::Read { device: 1, set: 0 }))
        ],
        "input {bad:02x?}"
    );
    assert!(!p.in_frame());
}

#[test]
fn length_zero_and_one_end_at_that_byte() {
    assert_rejected(&[0x00], FrameError::BadLength);
    assert_rejected(&[0x01], FrameError::BadLength);
    let mut p = Parser::new();
    assert_eq!(p.push(0), Some(Err(FrameError::BadLength)));
    assert!(!p.in_frame());
}

#[test]
fn length_two_ends_after_two_bytes() {
    assert_rejected(&[0x02, 0x14], FrameError::BadLength);
    assert_rejected(&[0x02, 0xf2], FrameError::BadLength);
    let mut p = Parser::new();
    assert_eq!(p.push(2), None);
    assert!(p.in_frame());
}

#[test]
fn device_nibble_10_to_15_is_rejected_after_the_whole_frame() {
    for device in 10u8..=15 {
        for command in [2u8, 3, 4, 0, 9] {
            let header = (device << 4) | command;
            assert_rejected(&[0x05, header, 0x01, 0x00, 0x01], FrameError::BadDevice);
        }
    }
}

#[test]
fn unknown_commands() {
    for command in [0u8, 1, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15] {
        assert_rejected(&[0x03, 0x10 | command, 0x00], FrameError::UnknownCommand);
    }
}

#[test]
fn write_to_an_id_the_table_does_not_have() {
    // DS has ids 0..47, LL 0..46, the master 0..15 (ids past 44 on the slaves and 12-15
    // on the master are this project's additions).
    assert_rejected(&[0x05, 0x12, 0x01, 0x30, 0x00], FrameError::UnknownRegister);
    assert_rejected(&[0x05, 0x32, 0x01, 0x2f, 0x00], FrameError::UnknownRegister);
    assert_rejected(&[0x05, 0x32, 0x01, 0xff, 0x00], FrameError::UnknownRegister);
    assert_rejected(&[0x05, 0x02, 0x01, 0x10, 0x01], FrameError::UnknownRegister);
    // Unknown after a good write: still the whole frame is rejected.
    assert_rejected(
        &[0x08, 0x12, 0x02, 0x09, 0xff, 0x7f, 0x30, 0x00],
        FrameError::UnknownRegister,
    );
}

#[test]
fn write_count_that_does_not_fill_the_payload() {
    // k = 2 but one entry.
    assert_rejected(
        &[0x06, 0x12, 0x02, 0x09, 0xff, 0x7f],
        FrameError::LengthMismatch,
    );
    // k = 1 with a trailing byte.
    assert_rejected(
        &[0x07, 0x12, 0x01, 0x09, 0xff, 0x7f, 0x00],
        FrameError::LengthMismatch,
    );
    // A 2-byte register given one value byte.
    assert_rejected(&[0x05, 0x12, 0x01, 0x09, 0xff], FrameError::LengthMismatch);
    // k = 0 with payload bytes.
    assert_rejected(&[0x05, 0x12, 0x00, 0x00, 0x01], FrameError::LengthMismatch);
    // The manual's `03 12 01`: a count of 1 with nothing after it.
    assert_rejected(&[0x03, 0x12, 0x01], FrameError::LengthMismatch);
}

#[test]
fn empty_write_is_valid() {
    let mut p = Parser::new();
    let results = feed(&mut p, &[0x03, 0x52, 0x00]);
    assert_eq!(
        results,
        vec![(
            2,
            Ok(Request::Write {
                device: 5,
                writes: heapless::Vec::new()
            })
        )]
    );
}

#[test]
fn read_only_ids_are_yielded_for_the_master_to_skip() {
    let mut p = Parser::new();
    // REG_TIMER (1, read-only, 2 bytes) then REGDS_DRIVE_STALLCHECK (24, 1 byte).
    let results = feed(&mut p, &[0x08, 0x12, 0x02, 0x01, 0x34, 0x12, 0x18, 0x77]);
    let expected: heapless::Vec<Write, 126> =
        heapless::Vec::from_slice(&[Write { id: 1, raw: 0x1234 }, Write { id: 24, raw: 0x77 }])
            .unwrap();
    assert_eq!(
        results,
        vec![(
            7,
            Ok(Request::Write {
                device: 1,
                writes: expected
            })
        )]
    );
}

#[test]
fn value_sizes_follow_the_addressed_device() {
    // Id 25 is 1 byte on DS (DRIVE_DEADZONE) and on LL (ONE_STALLCHECK); id 23 is
    // 2 bytes on DS (DRIVE_ODO) and 1 byte on LL (ONE_CALIBMIN).
    let mut p = Parser::new();
    let ds = feed(&mut p, &[0x06, 0x12, 0x01, 0x17, 0x01, 0x02]);
    assert!(matches!(&ds[..], [(5, Ok(Request::Write { writes, .. }))] if writes[0].raw == 0x0201));
    let ll = feed(&mut p, &[0x05, 0x32, 0x01, 0x17, 0x01]);
    assert!(matches!(&ll[..], [(4, Ok(Request::Write { writes, .. }))] if writes[0].raw == 0x01));
    assert_rejected(&[0x05, 0x12, 0x01, 0x17, 0x01], FrameError::LengthMismatch);
}

#[test]
fn read_payload_must_be_one_valid_set() {
    assert_rejected(&[0x04, 0x13, 0x00, 0x00], FrameError::LengthMismatch);
    assert_rejected(&[0x03, 0x13, 0x08], FrameError::BadReadSet);
    assert_rejected(&[0x03, 0x03, 0xff], FrameError::BadReadSet);
    let mut p = Parser::new();
    assert_eq!(
        feed(&mut p, &[0x03, 0x93, 0x07]),
        vec![(2, Ok(Request::Read { device: 9, set: 7 }))]
    );
}

#[test]
fn set_read_set_checks_set_and_size_but_not_ids() {
    assert_rejected(&[0x04, 0x14, 0x08, 0x01], FrameError::BadReadSet);
    let mut too_many = vec![28, 0x14, 0x00];
    too_many.extend(0u8..25);
    assert_rejected(&too_many, FrameError::ReadSetTooLarge);

    let mut p = Parser::new();
    let mut full = vec![27, 0x04, 0x07];
    full.extend(200u8..224);
    let results = feed(&mut p, &full);
    let [(
        26,
        Ok(Request::SetReadSet {
            device: 0,
            set: 7,
            ids,
        }),
    )] = &results[..]
    else {
        panic!("{results:?}");
    };
    assert_eq!(ids.as_slice(), (200u8..224).collect::<Vec<_>>().as_slice());

    assert_eq!(
        feed(&mut p, &[0x03, 0x24, 0x05]),
        vec![(
            2,
            Ok(Request::SetReadSet {
                device: 2,
                set: 5,
                ids: heapless::Vec::new()
            })
        )]
    );
}

#[test]
fn bad_set_is_reported_before_size() {
    let mut both = vec![29, 0x14, 0x09];
    both.extend(0u8..26);
    assert_rejected(&both, FrameError::BadReadSet);
}

#[test]
fn abort_drops_a_partial_frame_only() {
    let mut p = Parser::new();
    assert!(!p.abort());
    assert_eq!(p.push(0x06), None);
    assert_eq!(p.push(0x12), None);
    assert!(p.in_frame());
    assert!(p.abort());
    assert!(!p.in_frame());
    assert!(!p.abort());
    assert_eq!(
        feed(&mut p, &GOOD),
        vec![(2, Ok(Request::Read { device: 1, set: 0 }))]
    );
}

#[test]
fn a_long_frame_absorbs_bytes_until_its_length() {
    // The manual's example 2 with its wrong length byte 06: the frame ends after
    // register 2 and the final 03 starts the next frame.
    let mut p = Parser::new();
    let results = feed(&mut p, &[0x06, 0x04, 0x01, 0x00, 0x01, 0x02, 0x03]);
    let ids: heapless::Vec<u8, 24> = heapless::Vec::from_slice(&[0, 1, 2]).unwrap();
    assert_eq!(
        results,
        vec![(
            5,
            Ok(Request::SetReadSet {
                device: 0,
                set: 1,
                ids
            })
        )]
    );
    assert!(p.in_frame());
}

#[test]
fn maximum_length_frame() {
    // 126 one-byte writes to REG_RESET fill exactly 255 bytes.
    let mut frame = vec![255u8, 0x12, 126];
    for i in 0..126u8 {
        frame.extend_from_slice(&[0x00, i]);
    }
    assert_eq!(frame.len(), 255);
    let mut p = Parser::new();
    let results = feed(&mut p, &frame);
    let [(254, Ok(Request::Write { writes, .. }))] = &results[..] else {
        panic!("{results:?}");
    };
    assert_eq!(writes.len(), 126);
    assert_eq!(writes[125], Write { id: 0, raw: 125 });
}

#[test]
fn error_codes_are_stable_and_round_trip() {
    let expected = [
        (FrameError::BadLength, 1),
        (FrameError::BadDevice, 2),
        (FrameError::UnknownCommand, 3),
        (FrameError::UnknownRegister, 4),
        (FrameError::LengthMismatch, 5),
        (FrameError::BadReadSet, 6),
        (FrameError::ReadSetTooLarge, 7),
        (FrameError::Truncated, 8),
    ];
    assert_eq!(FrameError::ALL.len(), expected.len());
    for (error, code) in expected {
        assert_eq!(error.code(), code);
        assert_eq!(FrameError::from_code(code), Some(error));
        assert!(!error.describe().is_empty());
        assert_eq!(error.to_string(), error.describe());
    }
    assert_eq!(FrameError::from_code(0), None);
    assert_eq!(FrameError::from_code(9), None);
    let mut words: Vec<_> = FrameError::ALL.iter().map(|e| e.describe()).collect();
    words.sort();
    words.dedup();
    assert_eq!(words.len(), FrameError::ALL.len());
}
