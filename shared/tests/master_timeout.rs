//! The PC link's inter-byte timeout.

use shared::master::timeout::{InterByteTimeout, INTER_BYTE_TIMEOUT_MS};

#[test]
fn a_partial_frame_expires_after_the_timeout_and_only_then() {
    let mut t = InterByteTimeout::new();
    assert!(!t.in_frame());
    t.byte(1000, true);
    assert!(t.in_frame());
    assert!(
        !t.expired(1000 + INTER_BYTE_TIMEOUT_MS, false),
        "50 ms is not yet late"
    );
    assert!(t.expired(1000 + INTER_BYTE_TIMEOUT_MS + 1, false));
    assert!(!t.in_frame(), "expiry ends the frame");
    assert!(!t.expired(5000, false), "it fires once");
}

#[test]
fn each_byte_restarts_the_clock_and_a_finished_frame_stops_it() {
    let mut t = InterByteTimeout::new();
    t.byte(0, true);
    t.byte(40, true);
    assert!(!t.expired(85, false));
    assert!(t.expired(91, false));
    t.byte(100, true);
    t.byte(101, false);
    assert!(!t.in_frame());
    assert!(!t.expired(10_000, false), "between frames nothing expires");
}

#[test]
fn a_waiting_byte_holds_the_timeout_off_while_the_loop_is_blocked() {
    let mut t = InterByteTimeout::new();
    t.byte(0, true);
    assert!(!t.expired(500, true), "bytes wait in the buffer: not a gap");
    t.byte(500, true);
    assert!(!t.expired(550, false));
    assert!(t.expired(551, false));
}

#[test]
fn the_clock_may_wrap() {
    let mut t = InterByteTimeout::new();
    t.byte(u32::MAX - 10, true);
    assert!(!t.expired(20, false), "31 ms across the wrap");
    assert!(t.expired(45, false), "56 ms across the wrap");
}

#[test]
fn a_frame_with_usb_sized_gaps_survives_and_a_stalled_one_is_dropped_within_a_tenth_of_the_reply_timeout(
) {
    // Bytes 87 µs apart, but delivered in bursts 20 ms apart by a busy USB bridge.
    let mut t = InterByteTimeout::new();
    let mut now = 0;
    for burst in 0..10 {
        for _ in 0..8 {
            t.byte(now, true);
            assert!(!t.expired(now, false));
        }
        now += 20;
        assert!(!t.expired(now, false), "burst {burst}");
    }
    // The PC library gives up on a reply after 1 s; the link is free again well before.
    t.byte(now, true);
    let dropped_at = (now..now + 1000).find(|&ms| t.expired(ms, false)).unwrap();
    assert_eq!(dropped_at - now, 51);
}
