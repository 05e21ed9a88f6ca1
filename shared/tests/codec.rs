//! Encoder errors, read-reply decoding and the read-set store.

use shared::protocol::{
    decode_read_reply, encode_read, encode_set_read_set, encode_write, read_reply_len, DecodeError,
    EncodeError, FrameError, ReadSets, Write, MAX_FRAME, READ_SET_SIZE,
};
use shared::regs::BoardKind;

fn w(id: u8, raw: u16) -> Write {
    Write { id, raw }
}

#[test]
fn encode_write_errors() {
    let mut out = heapless::Vec::<u8, MAX_FRAME>::new();
    assert_eq!(
        encode_write(10, &[w(0, 1)], &mut out),
        Err(EncodeError::UnknownDevice)
    );
    // The first id past the DS table (45 in the original; the table has grown since).
    let past = BoardKind::DriveSteer.len();
    assert_eq!(
        encode_write(1, &[w(9, 0), w(past, 0)], &mut out),
        Err(EncodeError::UnknownRegister(past))
    );
    let past_master = BoardKind::Master.len();
    assert_eq!(
        encode_write(0, &[w(past_master, 0)], &mut out),
        Err(EncodeError::UnknownRegister(past_master))
    );
    assert_eq!(
        encode_write(1, &[w(0, 0x100)], &mut out),
        Err(EncodeError::ValueTooWide(0))
    );
    assert!(out.is_empty(), "failed encodes leave `out` empty");
}

#[test]
fn encode_write_length_limit() {
    let mut out = heapless::Vec::<u8, MAX_FRAME>::new();
    // 84 two-byte writes: 3 + 84 * 3 = 255 bytes, the maximum.
    let fits: Vec<Write> = (0..84).map(|i| w(9, i)).collect();
    encode_write(1, &fits, &mut out).unwrap();
    assert_eq!(out.len(), 255);
    assert_eq!(&out[..3], &[255, 0x12, 84]);
    let over: Vec<Write> = (0..85).map(|i| w(9, i)).collect();
    assert_eq!(encode_write(1, &over, &mut out), Err(EncodeError::TooLong));
    // 126 one-byte writes: 3 + 126 * 2 = 255.
    let small: Vec<Write> = (0..126).map(|i| w(0, i)).collect();
    encode_write(2, &small, &mut out).unwrap();
    assert_eq!(&out[..3], &[255, 0x22, 126]);
    let too_many: Vec<Write> = (0..127).map(|i| w(0, i)).collect();
    assert_eq!(
        encode_write(2, &too_many, &mut out),
        Err(EncodeError::TooLong)
    );
}

#[test]
fn encode_empty_write() {
    let mut out = heapless::Vec::<u8, MAX_FRAME>::new();
    encode_write(7, &[], &mut out).unwrap();
    assert_eq!(out.as_slice(), &[3, 0x72, 0]);
}

#[test]
fn encode_set_read_set_errors() {
    let mut out = heapless::Vec::<u8, MAX_FRAME>::new();
    assert_eq!(
        encode_set_read_set(12, 0, &[1], &mut out),
        Err(EncodeError::UnknownDevice)
    );
    assert_eq!(
        encode_set_read_set(1, 8, &[1], &mut out),
        Err(EncodeError::BadReadSet)
    );
    let ids = [1u8; 25];
    assert_eq!(
        encode_set_read_set(1, 0, &ids, &mut out),
        Err(EncodeError::ReadSetTooLarge)
    );
    encode_set_read_set(1, 0, &ids[..24], &mut out).unwrap();
    assert_eq!(out.len(), 27);
    encode_set_read_set(1, 3, &[], &mut out).unwrap();
    assert_eq!(out.as_slice(), &[3, 0x14, 3]);
    assert_eq!(encode_read(9, 7), [3, 0x93, 7]);
}

#[test]
fn reply_length_depends_on_the_board() {
    // Id 23: DRIVE_ODO (2 bytes) on DS, ONE_CALIBMIN (1 byte) on LL; 44: CHASSIS (2) / TWO_DEADZONE (1).
    assert_eq!(read_reply_len(BoardKind::DriveSteer, &[23, 44]), Some(4));
    assert_eq!(read_reply_len(BoardKind::LiftLift, &[23, 44]), Some(2));
    assert_eq!(read_reply_len(BoardKind::Master, &[0, 11]), Some(3));
    assert_eq!(read_reply_len(BoardKind::Master, &[14]), Some(2));
    assert_eq!(
        read_reply_len(BoardKind::Master, &[BoardKind::Master.len()]),
        None
    );
    let past = BoardKind::DriveSteer.len();
    assert_eq!(read_reply_len(BoardKind::DriveSteer, &[past]), None);
    assert_eq!(read_reply_len(BoardKind::DriveSteer, &[]), Some(0));
}

#[test]
fn decode_read_reply_values_in_order() {
    let mut out = heapless::Vec::new();
    // REG_STATUS 0x0009, REGDS_DRIVE_DEADZONE 0x05, REGDS_CHASSIS 0x1234.
    decode_read_reply(
        BoardKind::DriveSteer,
        &[3, 25, 44],
        &[0x09, 0x00, 0x05, 0x34, 0x12],
        &mut out,
    )
    .unwrap();
    assert_eq!(out.as_slice(), &[(3, 0x0009), (25, 0x05), (44, 0x1234)]);
}

#[test]
fn decode_read_reply_errors_leave_out_empty() {
    let mut out = heapless::Vec::new();
    out.push((1, 1)).unwrap();
    assert_eq!(
        decode_read_reply(BoardKind::DriveSteer, &[3, 25], &[0, 0], &mut out),
        Err(DecodeError::WrongLength {
            expected: 3,
            actual: 2
        })
    );
    assert!(out.is_empty());
    let past_master = BoardKind::Master.len();
    assert_eq!(
        decode_read_reply(BoardKind::Master, &[1, past_master], &[0, 0, 0], &mut out),
        Err(DecodeError::UnknownRegister(past_master))
    );
    let ids = [1u8; READ_SET_SIZE + 1];
    let bytes = [0u8; 2 * (READ_SET_SIZE + 1)];
    assert_eq!(
        decode_read_reply(BoardKind::DriveSteer, &ids, &bytes, &mut out),
        Err(DecodeError::TooManyIds)
    );
    assert!(out.is_empty());
}

#[test]
fn decode_a_full_ds_set_zero_reply() {
    let ids = [
        1u8, 2, 3, 5, 44, 16, 17, 18, 19, 20, 21, 22, 23, 33, 34, 35, 36, 37, 38, 39,
    ];
    let bytes: Vec<u8> = (0..40).collect();
    let mut out = heapless::Vec::new();
    decode_read_reply(BoardKind::DriveSteer, &ids, &bytes, &mut out).unwrap();
    assert_eq!(out.len(), 20);
    assert_eq!(out[0], (1, 0x0100));
    assert_eq!(out[4], (44, 0x0908));
    assert_eq!(out[19], (39, 0x2726));
}

#[test]
fn read_sets_start_empty_and_replace() {
    let mut sets = ReadSets::new();
    for s in 0..8 {
        assert_eq!(sets.get(s), Some(&[][..]));
    }
    assert_eq!(sets.get(8), None);
    sets.set(2, &[1, 2, 3]).unwrap();
    assert_eq!(sets.get(2), Some(&[1u8, 2, 3][..]));
    sets.set(2, &[9]).unwrap();
    assert_eq!(sets.get(2), Some(&[9u8][..]));
    let full: Vec<u8> = (100..124).collect();
    sets.set(7, &full).unwrap();
    assert_eq!(sets.get(7), Some(full.as_slice()));
    sets.set(7, &[]).unwrap();
    assert_eq!(sets.get(7), Some(&[][..]));
    assert_eq!(sets.get(2), Some(&[9u8][..]));
    assert_eq!(ReadSets::default(), ReadSets::new());
}

#[test]
fn read_sets_refuse_bad_index_and_size_without_change() {
    let mut sets = ReadSets::new();
    sets.set(0, &[5, 6]).unwrap();
    assert_eq!(sets.set(8, &[1]), Err(FrameError::BadReadSet));
    assert_eq!(sets.set(255, &[1]), Err(FrameError::BadReadSet));
    assert_eq!(sets.set(0, &[1; 25]), Err(FrameError::ReadSetTooLarge));
    assert_eq!(sets.get(0), Some(&[5u8, 6][..]));
}

#[test]
fn error_texts() {
    assert_eq!(
        EncodeError::UnknownRegister(45).to_string(),
        "register 45 is not in the device's table"
    );
    assert_eq!(
        DecodeError::WrongLength {
            expected: 40,
            actual: 39
        }
        .to_string(),
        "read reply has 39 bytes, expected 40"
    );
}
