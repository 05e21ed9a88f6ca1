//! The manual's protocol examples 1-3 (§4.5), which assume register sizes no real table
//! has (ids 0 and 1 one byte, 2 and 3 two bytes): checked at the framing level with
//! those hypothetical sizes, and against the real tables.

use heapless::Vec;

use super::encode::encode_write_sized;
use super::parser::validate;
use super::reply::decode_sized;
use super::sizes::Sizes;
use super::*;
use crate::regs::BoardKind;

fn hypothetical(id: u8) -> Option<u8> {
    match id {
        0 | 1 => Some(1),
        2 | 3 => Some(2),
        _ => None,
    }
}

/// [`hypothetical`] as the parser reads it, for any device.
fn hypothetical_sizes(_device: u8) -> Option<Sizes> {
    Some(Sizes::HYPOTHETICAL)
}

const EXAMPLE_1: [u8; 13] = [
    0x0d, 0x32, 0x04, 0x00, 0xff, 0x01, 0xff, 0x02, 0x01, 0x00, 0x03, 0x02, 0x00,
];

fn writes(list: &[(u8, u16)]) -> Vec<Write, MAX_WRITES> {
    list.iter().map(|&(id, raw)| Write { id, raw }).collect()
}

#[test]
fn example_1_write_to_slave_3_framing() {
    let expected = writes(&[(0, 0xff), (1, 0xff), (2, 0x0001), (3, 0x0002)]);
    assert_eq!(
        validate(&EXAMPLE_1, hypothetical_sizes).map(|f| f.to_request()),
        Ok(Request::Write {
            device: 3,
            writes: expected.clone()
        })
    );
    let mut out = Vec::new();
    encode_write_sized(3, &expected, hypothetical, &mut out).unwrap();
    assert_eq!(out.as_slice(), &EXAMPLE_1);
}

#[test]
fn example_1_against_the_real_ll_table_is_one_rejected_frame() {
    // Real id 1 (REG_TIMER) is 2 bytes, so the entries overrun the payload.
    let mut p = Parser::new();
    for &b in &EXAMPLE_1[..12] {
        assert_eq!(p.push(b), None);
    }
    assert_eq!(p.push(EXAMPLE_1[12]), Some(Err(FrameError::LengthMismatch)));
    assert!(!p.in_frame());
}

#[test]
fn example_2_set_read_set_corrected_length() {
    let frame = [0x07, 0x04, 0x01, 0x00, 0x01, 0x02, 0x03];
    let ids: Vec<u8, READ_SET_SIZE> = [0u8, 1, 2, 3].into_iter().collect();
    assert_eq!(
        validate(&frame, hypothetical_sizes).map(|f| f.to_request()),
        Ok(Request::SetReadSet {
            device: 0,
            set: 1,
            ids: ids.clone()
        })
    );
    let mut out = Vec::new();
    encode_set_read_set(0, 1, &ids, &mut out).unwrap();
    assert_eq!(out.as_slice(), &frame);
    // The reply is the id count, (L - 3) mod 256 = 4.
    assert_eq!(frame[0] - 3, 0x04);
}

#[test]
fn example_3_read_set_1_from_slave_1_and_its_reply() {
    let frame = encode_read(1, 1);
    assert_eq!(frame, [0x03, 0x13, 0x01]);
    assert_eq!(
        validate(&frame, hypothetical_sizes).map(|f| f.to_request()),
        Ok(Request::Read { device: 1, set: 1 })
    );
    let reply = [0xff, 0xff, 0x01, 0x00, 0x02, 0x00];
    let mut out = Vec::new();
    decode_sized(&[0, 1, 2, 3], &reply, hypothetical, &mut out).unwrap();
    assert_eq!(out.as_slice(), &[(0, 0xff), (1, 0xff), (2, 1), (3, 2)]);
    // With the real DS table the same ids call for 7 bytes.
    assert_eq!(
        decode_read_reply(BoardKind::DriveSteer, &[0, 1, 2, 3], &reply, &mut out),
        Err(DecodeError::WrongLength {
            expected: 7,
            actual: 6
        })
    );
}

#[test]
fn request_accessors() {
    let r = Request::Read { device: 4, set: 0 };
    assert_eq!((r.device(), r.command()), (4, Command::Read));
    assert_eq!(Command::from_u8(4), Some(Command::SetReadSet));
    assert_eq!(Command::from_u8(5), None);
    assert_eq!(header(9, Command::Write), 0x92);
}
