//! Byte-exact frames of the reference (§4.3, §4.5, §8.3, §8.5, §10.3): each is built
//! from values through `map` and the encoders, compared byte for byte, and parsed back.

use shared::mapping::map;
use shared::protocol::{
    encode_read, encode_set_read_set, encode_write, read_reply_len, Parser, Request, Write,
    MAX_FRAME,
};
use shared::regs::BoardKind;

/// Encodes a write of named registers (values mapped through their tables) to `device`.
fn write_frame(device: u8, values: &[(&str, f32)]) -> Vec<u8> {
    let kind = BoardKind::of_device(device).unwrap();
    let writes: Vec<Write> = values
        .iter()
        .map(|(name, v)| {
            let reg = kind
                .lookup(name)
                .unwrap_or_else(|| panic!("{name} on {}", kind.name()));
            Write {
                id: reg.id,
                raw: map(*v, reg),
            }
        })
        .collect();
    let mut out = heapless::Vec::<u8, MAX_FRAME>::new();
    encode_write(device, &writes, &mut out).unwrap();
    out.to_vec()
}

fn hex(s: &str) -> Vec<u8> {
    s.split_whitespace()
        .map(|b| u8::from_str_radix(b, 16).unwrap())
        .collect()
}

/// Parses exactly one frame: no result before its last byte, a request at it.
fn parse_one(bytes: &[u8]) -> Request {
    let mut p = Parser::new();
    let (last, head) = bytes.split_last().unwrap();
    for &b in head {
        assert_eq!(p.push(b), None, "frame {bytes:02x?} ended early");
    }
    let request = p.push(*last).expect("frame did not end").unwrap();
    assert!(!p.in_frame());
    request
}

/// Checks `frame` against the reference bytes and that it parses back to the writes.
fn assert_write_frame(frame: &[u8], reference: &str) {
    assert_eq!(
        frame,
        hex(reference).as_slice(),
        "frame differs from {reference}"
    );
    let Request::Write { device, writes } = parse_one(frame) else {
        panic!("not a write");
    };
    let mut again = heapless::Vec::<u8, MAX_FRAME>::new();
    encode_write(device, &writes, &mut again).unwrap();
    assert_eq!(again.as_slice(), frame);
}

#[test]
fn wheel_one_drive_speed_and_stop() {
    let go = write_frame(1, &[("DRIVE_REQSPEED", 1000.0)]);
    assert_write_frame(&go, "06 12 01 09 fe 9f");
    let stop = write_frame(1, &[("DRIVE_REQSPEED", 0.0)]);
    assert_write_frame(&stop, "06 12 01 09 ff 7f");
}

#[test]
fn wheel_one_steer_plus_40() {
    assert_write_frame(
        &write_frame(1, &[("STEER_REQPOS", 40.0)]),
        "06 12 01 1a 98 99",
    );
}

#[test]
fn wheels_one_and_two_lift_20() {
    assert_write_frame(
        &write_frame(3, &[("ONE_REQPOS", 20.0)]),
        "06 32 01 09 cb 8c",
    );
    assert_write_frame(
        &write_frame(3, &[("TWO_REQPOS", 20.0)]),
        "06 32 01 1b cb 8c",
    );
}

#[test]
fn reset_exceptions_and_odometer() {
    assert_write_frame(&write_frame(4, &[("REG_RESET", 1.0)]), "05 42 01 00 01");
    assert_write_frame(
        &write_frame(0, &[("REGMASTER_RESET", 1.0)]),
        "05 02 01 00 01",
    );
    assert_write_frame(&write_frame(1, &[("RESET", 4.0)]), "05 12 01 00 04");
}

#[test]
fn reset_exceptions_sequence_for_all_pairs() {
    // §8.5: controllers 3p+1, 3p+2, 3p+3 for each pair, then the master.
    let mut frames = Vec::new();
    for pair in 0..3u8 {
        for controller in [3 * pair + 1, 3 * pair + 2, 3 * pair + 3] {
            frames.push(write_frame(controller, &[("RESET", 1.0)]));
        }
    }
    frames.push(write_frame(0, &[("RESET", 1.0)]));
    let expected: Vec<Vec<u8>> = [0x12, 0x22, 0x32, 0x42, 0x52, 0x62, 0x72, 0x82, 0x92, 0x02]
        .iter()
        .map(|&h| vec![0x05, h, 0x01, 0x00, 0x01])
        .collect();
    assert_eq!(frames, expected);
}

#[test]
fn read_master_set_two() {
    assert_eq!(encode_read(0, 2), [0x03, 0x03, 0x02]);
    assert_eq!(parse_one(&[3, 3, 2]), Request::Read { device: 0, set: 2 });
    let ids: Vec<u8> = (1..=11).collect();
    assert_eq!(read_reply_len(BoardKind::Master, &ids), Some(22));
}

const SET0_DS: [u8; 20] = [
    1, 2, 3, 5, 44, 16, 17, 18, 19, 20, 21, 22, 23, 33, 34, 35, 36, 37, 38, 39,
];
const SET1_LL: [u8; 18] = [
    1, 2, 3, 5, 16, 17, 18, 19, 20, 21, 22, 34, 35, 36, 37, 38, 39, 40,
];
const SET2_MASTER: [u8; 11] = [1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11];

#[test]
fn library_read_set_frames() {
    let cases: [(u8, u8, &[u8], &str, u8); 3] = [
        (
            1,
            0,
            &SET0_DS,
            "17 14 00 01 02 03 05 2c 10 11 12 13 14 15 16 17 21 22 23 24 25 26 27",
            0x14,
        ),
        (
            3,
            1,
            &SET1_LL,
            "15 34 01 01 02 03 05 10 11 12 13 14 15 16 22 23 24 25 26 27 28",
            0x12,
        ),
        (
            0,
            2,
            &SET2_MASTER,
            "0e 04 02 01 02 03 04 05 06 07 08 09 0a 0b",
            0x0b,
        ),
    ];
    for (device, set, ids, reference, reply) in cases {
        let mut out = heapless::Vec::<u8, MAX_FRAME>::new();
        encode_set_read_set(device, set, ids, &mut out).unwrap();
        assert_eq!(out.as_slice(), hex(reference).as_slice());
        // The master's reply is the id count, (L - 3) mod 256.
        assert_eq!(usize::from(out[0]) - 3, usize::from(reply));
        let Request::SetReadSet {
            device: d,
            set: s,
            ids: parsed,
        } = parse_one(&out)
        else {
            panic!("not a set-read-set");
        };
        assert_eq!((d, s, parsed.as_slice()), (device, set, ids));
    }
    assert_eq!(read_reply_len(BoardKind::DriveSteer, &SET0_DS), Some(40));
    assert_eq!(read_reply_len(BoardKind::LiftLift, &SET1_LL), Some(36));
    assert_eq!(read_reply_len(BoardKind::Master, &SET2_MASTER), Some(22));
}

#[test]
fn library_initialises_sets_per_pair() {
    // For each pair: set 0 via 3p+1 and 3p+2, set 1 via 3p+3; finally set 2 via the master.
    let mut headers = Vec::new();
    for pair in 0..3u8 {
        for (controller, set, ids) in [
            (3 * pair + 1, 0, &SET0_DS[..]),
            (3 * pair + 2, 0, &SET0_DS[..]),
            (3 * pair + 3, 1, &SET1_LL[..]),
        ] {
            let mut out = heapless::Vec::<u8, MAX_FRAME>::new();
            encode_set_read_set(controller, set, ids, &mut out).unwrap();
            headers.push((out[1], out[2]));
        }
    }
    assert_eq!(
        headers,
        vec![
            (0x14, 0),
            (0x24, 0),
            (0x34, 1),
            (0x44, 0),
            (0x54, 0),
            (0x64, 1),
            (0x74, 0),
            (0x84, 0),
            (0x94, 1)
        ]
    );
}

#[test]
fn update_read_frames_and_reply_bytes() {
    let mut frames = Vec::new();
    let mut reply_bytes = 0;
    for device in 1..=9u8 {
        let kind = BoardKind::of_device(device).unwrap();
        let (set, ids): (u8, &[u8]) = if kind == BoardKind::LiftLift {
            (1, &SET1_LL)
        } else {
            (0, &SET0_DS)
        };
        frames.push(encode_read(device, set));
        reply_bytes += read_reply_len(kind, ids).unwrap();
    }
    frames.push(encode_read(0, 2));
    reply_bytes += read_reply_len(BoardKind::Master, &SET2_MASTER).unwrap();
    let expected: Vec<[u8; 3]> = [
        "03 13 00", "03 23 00", "03 33 01", "03 43 00", "03 53 00", "03 63 01", "03 73 00",
        "03 83 00", "03 93 01", "03 03 02",
    ]
    .iter()
    .map(|s| hex(s).try_into().unwrap())
    .collect();
    assert_eq!(frames, expected);
    // §13: a full update receives 6 x 40 + 3 x 36 + 22 bytes.
    assert_eq!(reply_bytes, 370);
    for f in &frames {
        assert!(matches!(parse_one(f), Request::Read { .. }));
    }
}

#[test]
fn calibrate_wheel_one_drive() {
    let frame = write_frame(
        1,
        &[
            ("DRIVE_PGAIN", 0.01),
            ("DRIVE_IGAIN", 0.0),
            ("DRIVE_DGAIN", 0.0),
            ("DRIVE_INTEGRALCAP", 0.0),
            ("DRIVE_INTEGRALDECAY", 0.0),
            ("DRIVE_OVERCURRENTTHRESH", 500.0),
            ("DRIVE_STALLCHECK", 255.0),
            ("DRIVE_DEADZONE", 1.0),
        ],
    );
    assert_write_frame(
        &frame,
        "19 12 08 0a 41 00 0b 00 00 0c ff 7f 0d 00 00 0e 00 00 0f ff 7f 18 fe 19 05",
    );
}

/// The steer block in sendParams order: 27 28 29 30 31 32 42 43 40 41.
fn steer_block(p: f32, i: f32, cap: f32, decay: f32, oc: f32, dz: f32) -> Vec<u8> {
    write_frame(
        1,
        &[
            ("STEER_PGAIN", p),
            ("STEER_IGAIN", i),
            ("STEER_DGAIN", 0.0),
            ("STEER_INTEGRALCAP", cap),
            ("STEER_INTEGRALDECAY", decay),
            ("STEER_OVERCURRENTTHRESH", oc),
            ("STEER_CALIBMIN", -56.0),
            ("STEER_CALIBMAX", 66.0),
            ("STEER_STALLCHECK", 255.0),
            ("STEER_DEADZONE", dz),
        ],
    )
}

#[test]
fn calibrate_wheel_one_steer_first_and_second_send() {
    assert_write_frame(
        &steer_block(0.0, 0.0, 0.0, 0.0, 10.0, 1.0),
        "1d 12 0a 1b 00 00 1c 00 00 1d ff 7f 1e 00 00 1f 00 00 20 8f 02 2a 43 2b c4 28 fe 29 05",
    );
    assert_write_frame(
        &steer_block(0.0, 2.0, 300.0, 0.95, 500.0, 0.5),
        "1d 12 0a 1b 00 00 1c 32 33 1d ff 7f 1e cc 4c 1f 31 f3 20 ff 7f 2a 43 2b c4 28 fe 29 02",
    );
}

#[test]
fn calibrate_wheel_one_lift_second_send() {
    let frame = write_frame(
        3,
        &[
            ("ONE_PGAIN", 0.0),
            ("ONE_IGAIN", 5.0),
            ("ONE_DGAIN", 0.0),
            ("ONE_INTEGRALCAP", 50.0),
            ("ONE_INTEGRALDECAY", 0.9),
            ("ONE_OVERCURRENTTHRESH", 500.0),
            ("ONE_CALIBMIN", -109.0),
            ("ONE_CALIBMAX", 109.0),
            ("ONE_STALLCHECK", 255.0),
            ("ONE_DEADZONE", 1.0),
        ],
    );
    assert_write_frame(
        &frame,
        "1d 32 0a 0a 00 00 0b ff 7f 0c ff 7f 0d cc 0c 0e 64 e6 0f ff 7f 17 0b 18 f2 19 fe 1a 05",
    );
}

#[test]
fn emergency_stop_wheel_one_drive() {
    let params = write_frame(
        1,
        &[
            ("DRIVE_PGAIN", 0.0),
            ("DRIVE_IGAIN", 0.0),
            ("DRIVE_DGAIN", 0.0),
            ("DRIVE_INTEGRALCAP", 0.0),
            ("DRIVE_INTEGRALDECAY", 0.0),
            ("DRIVE_OVERCURRENTTHRESH", 200.0),
            ("DRIVE_STALLCHECK", 255.0),
            ("DRIVE_DEADZONE", 1.0),
        ],
    );
    assert_write_frame(
        &params,
        "19 12 08 0a 00 00 0b 00 00 0c ff 7f 0d 00 00 0e 00 00 0f 32 33 18 fe 19 05",
    );
    assert_write_frame(
        &write_frame(1, &[("DRIVE_REQSPEED", 0.0)]),
        "06 12 01 09 ff 7f",
    );
}

#[test]
fn frames_back_to_back_parse_in_order() {
    let stream = hex("06 12 01 09 fe 9f 03 13 00 05 42 01 00 01 03 03 02");
    let mut p = Parser::new();
    let results: Vec<Request> = stream
        .iter()
        .filter_map(|&b| p.push(b))
        .map(Result::unwrap)
        .collect();
    assert_eq!(results.len(), 4);
    assert_eq!(results[1], Request::Read { device: 1, set: 0 });
    assert_eq!(results[3], Request::Read { device: 0, set: 2 });
    assert_eq!(results[2].device(), 4);
}
