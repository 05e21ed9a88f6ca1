//! Property tests of the parser and the encoders: no panic on any input, resync after
//! `abort`, nothing parsed after `lose` until `abort`, and encode -> parse round trips.

use proptest::prelude::*;
use shared::protocol::{
    encode_set_read_set, encode_write, EncodeError, Parser, Request, Write, MAX_FRAME,
};
use shared::regs::BoardKind;

/// A device 0..=9 and up to `max` valid writes for its table.
fn device_and_writes(max: usize) -> impl Strategy<Value = (u8, Vec<Write>)> {
    (0u8..=9).prop_flat_map(move |device| {
        let kind = BoardKind::of_device(device).unwrap();
        let entry = (0..kind.len(), any::<u16>()).prop_map(move |(id, raw)| {
            let raw = if kind.size_of(id) == Some(1) {
                raw & 0xff
            } else {
                raw
            };
            Write { id, raw }
        });
        (Just(device), proptest::collection::vec(entry, 0..=max))
    })
}

fn encoded_write(device: u8, writes: &[Write]) -> Result<Vec<u8>, EncodeError> {
    let mut out = heapless::Vec::<u8, MAX_FRAME>::new();
    encode_write(device, writes, &mut out).map(|()| out.to_vec())
}

/// A parser that has been fed `bytes`, whatever they made of it.
fn parser_after(bytes: &[u8]) -> Parser {
    let mut p = Parser::new();
    for &b in bytes {
        let _ = p.push(b);
    }
    p
}

/// The request a write frame of `writes` to `device` parses as.
fn write_request(device: u8, writes: &[Write]) -> Request {
    Request::Write {
        device,
        writes: heapless::Vec::from_slice(writes).unwrap(),
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    #[test]
    fn never_panics_on_any_bytes(
        input in proptest::collection::vec((any::<u8>(), any::<bool>()), 0..1200)
    ) {
        let mut p = Parser::new();
        for (byte, abort) in input {
            if let Some(Ok(request)) = p.push(byte) {
                prop_assert!(request.device() <= 9);
            }
            if abort && byte % 7 == 0 {
                p.abort();
            }
        }
    }

    #[test]
    fn abort_after_garbage_resyncs_on_a_valid_frame(
        garbage in proptest::collection::vec(any::<u8>(), 0..600),
        (device, writes) in device_and_writes(40),
    ) {
        let frame = encoded_write(device, &writes).unwrap();
        let mut p = parser_after(&garbage);
        p.abort();
        prop_assert!(!p.in_frame());
        let (last, head) = frame.split_last().unwrap();
        for &b in head {
            prop_assert_eq!(p.push(b), None);
        }
        prop_assert_eq!(p.push(*last), Some(Ok(write_request(device, &writes))));
    }

    #[test]
    fn after_a_lost_byte_nothing_is_a_frame_until_the_link_finds_the_line_quiet(
        before in proptest::collection::vec(any::<u8>(), 0..300),
        after in proptest::collection::vec(any::<u8>(), 0..1200),
        (device, writes) in device_and_writes(40),
    ) {
        let frame = encoded_write(device, &writes).unwrap();
        let mut p = parser_after(&before);
        // A damaged byte: whatever came before and follows, no frame ends (a whole valid
        // frame among the bytes included), and the link's timeout keeps timing.
        p.lose();
        for b in after.into_iter().chain(frame.iter().copied()) {
            prop_assert!(p.push(b).is_none());
            prop_assert!(p.in_frame());
        }
        // The quiet line ends the skipping without a partial frame to count.
        prop_assert!(!p.abort());
        let replies: Vec<_> = frame.iter().filter_map(|&b| p.push(b)).collect();
        prop_assert_eq!(replies, vec![Ok(write_request(device, &writes))]);
    }

    #[test]
    fn encode_then_parse_round_trips_writes((device, writes) in device_and_writes(130)) {
        let kind = BoardKind::of_device(device).unwrap();
        let length: usize = 3 + writes.iter().map(|w| 1 + usize::from(kind.size_of(w.id).unwrap())).sum::<usize>();
        match encoded_write(device, &writes) {
            Err(e) => {
                prop_assert_eq!(e, EncodeError::TooLong);
                prop_assert!(length > MAX_FRAME);
            }
            Ok(frame) => {
                prop_assert_eq!(frame.len(), length);
                prop_assert_eq!(usize::from(frame[0]), length);
                let mut p = Parser::new();
                let results: Vec<_> = frame.iter().filter_map(|&b| p.push(b)).collect();
                prop_assert_eq!(results, vec![Ok(write_request(device, &writes))]);
            }
        }
    }

    #[test]
    fn encode_then_parse_round_trips_read_sets(
        device in 0u8..=9,
        set in 0u8..8,
        ids in proptest::collection::vec(any::<u8>(), 0..=24),
    ) {
        let mut out = heapless::Vec::<u8, MAX_FRAME>::new();
        encode_set_read_set(device, set, &ids, &mut out).unwrap();
        let mut p = Parser::new();
        let results: Vec<_> = out.iter().filter_map(|&b| p.push(b)).collect();
        let expected = Request::SetReadSet { device, set, ids: heapless::Vec::from_slice(&ids).unwrap() };
        prop_assert_eq!(results, vec![Ok(expected)]);
    }

    #[test]
    fn every_frame_ends_at_its_length_byte(
        frames in proptest::collection::vec(
            (2u8..=40).prop_flat_map(|len| proptest::collection::vec(any::<u8>(), usize::from(len) - 1)
                .prop_map(move |body| (len, body))),
            1..20,
        )
    ) {
        // Whatever the content, each frame of length L yields exactly one result at
        // its L-th byte: sync is never lost beyond the frame.
        let mut p = Parser::new();
        for (len, body) in frames {
            prop_assert_eq!(p.push(len), None);
            let (last, head) = body.split_last().unwrap();
            for &b in head {
                prop_assert_eq!(p.push(b), None);
            }
            prop_assert!(p.push(*last).is_some());
            prop_assert!(!p.in_frame());
        }
    }
}
