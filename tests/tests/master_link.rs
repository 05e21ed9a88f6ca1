//! The real master image in the emulator, driven over its UART as a PC program would:
//! the banner, device 0's registers, the library's read set 2, and bad input (garbled
//! bytes on the line included).

mod master_support;

use harness::Avr;
use shared::regs::id;

/// Boots the master and returns it with the banner read.
fn boot() -> (Avr, String) {
    let mut avr = Avr::firmware("master").unwrap();
    let banner = avr.uart_read_until(b"Ready\r\n", 2_000_000).unwrap();
    (avr, String::from_utf8(banner).unwrap())
}

/// Sends a frame and collects the reply bytes that arrive within `us`.
fn exchange(avr: &mut Avr, frame: &[u8], n: usize) -> Vec<u8> {
    avr.uart_send(frame);
    let reply = avr.uart_read_exact(n, 200_000).unwrap();
    // Nothing more may follow.
    avr.run_us(5_000);
    assert!(avr.uart_take().is_empty(), "unexpected extra reply bytes");
    reply
}

/// Sends a frame that must get no reply at all.
fn silence(avr: &mut Avr, frame: &[u8]) {
    avr.uart_send(frame);
    avr.run_us(20_000);
    assert_eq!(
        avr.uart_take(),
        Vec::<u8>::new(),
        "expected no reply to {frame:02x?}"
    );
}

/// Reads master registers through read set 6.
fn read_master(avr: &mut Avr, ids: &[u8], reply_len: usize) -> Vec<u8> {
    let mut frame = vec![3 + ids.len() as u8, 0x04, 6];
    frame.extend_from_slice(ids);
    assert_eq!(exchange(avr, &frame, 1), [ids.len() as u8]);
    exchange(avr, &[0x03, 0x03, 0x06], reply_len)
}

#[test]
fn banner_has_the_four_lines_of_the_original() {
    let (_avr, banner) = boot();
    let lines: Vec<&str> = banner.split("\r\n").collect();
    assert_eq!(lines.len(), 5, "{banner:?}");
    assert_eq!(lines[0], "Starting");
    // `Mmm dd yyyy hh:mm:ss`, the day space-padded.
    let date = lines[1].as_bytes();
    assert_eq!(date.len(), 20, "{:?}", lines[1]);
    assert!(date[..3].iter().all(u8::is_ascii_alphabetic));
    assert_eq!(
        (date[3], date[6], date[11], date[14], date[17]),
        (b' ', b' ', b' ', b':', b':')
    );
    // Free SRAM: from the end of static data up to the stack pointer, which sits a
    // little below the top of RAM while idle prints the banner.
    let free: u32 = lines[2].parse().unwrap();
    let heap = Avr::firmware("master")
        .unwrap()
        .symbol("__heap_start")
        .unwrap();
    let above_statics = 0x900 - heap;
    assert!(
        free < above_statics && free + 128 > above_statics,
        "free SRAM {free} of {above_statics} above the static data"
    );
    assert_eq!(lines[3], "Ready");
    assert_eq!(lines[4], "");
}

#[test]
fn master_reset_clears_the_boot_exception() {
    let (mut avr, _) = boot();
    assert_eq!(
        read_master(&mut avr, &[11], 2),
        [0x02, 0x00],
        "boot exception"
    );
    assert_eq!(
        exchange(&mut avr, &[0x05, 0x02, 0x01, 0x00, 0x01], 1),
        [0x00]
    );
    assert_eq!(read_master(&mut avr, &[11], 2), [0x00, 0x00]);
}

#[test]
fn library_read_set_2_gives_22_bytes() {
    let (mut avr, _) = boot();
    let set2 = [0x0e, 0x04, 0x02, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11];
    assert_eq!(exchange(&mut avr, &set2, 1), [0x0b]);
    let reply = exchange(&mut avr, &[0x03, 0x03, 0x02], 22);
    let mut expected = [0xaa, 0x2a].repeat(10);
    expected.extend_from_slice(&[0x02, 0x00]);
    assert_eq!(reply, expected);
}

#[test]
fn corrected_manual_example_2_sets_a_read_set_of_four() {
    let (mut avr, _) = boot();
    assert_eq!(
        exchange(&mut avr, &[0x07, 0x04, 0x01, 0x00, 0x01, 0x02, 0x03], 1),
        [0x04]
    );
    // Set 1 on device 0 = RESET (1 byte), TEMPAMBIENT, TEMP1, TEMP2 (2 bytes each).
    assert_eq!(
        exchange(&mut avr, &[0x03, 0x03, 0x01], 7),
        [0x00, 0xaa, 0x2a, 0xaa, 0x2a, 0xaa, 0x2a]
    );
}

#[test]
fn bad_input_gets_defined_answers_and_changes_nothing() {
    let (mut avr, _) = boot();
    // Read-only register: error reply, the reset in the same frame is not applied.
    assert_eq!(
        exchange(
            &mut avr,
            &[0x08, 0x02, 0x02, 0x00, 0x01, 0x02, 0x00, 0x00],
            1
        ),
        [0x89]
    );
    // Device 10..15: the original halted; here an error reply, or silence for a read.
    assert_eq!(
        exchange(&mut avr, &[0x05, 0xa2, 0x01, 0x00, 0x01], 1),
        [0x82]
    );
    silence(&mut avr, &[0x03, 0xf3, 0x00]);
    // Unknown command, empty read set, read set 8.
    silence(&mut avr, &[0x03, 0x05, 0x00]);
    silence(&mut avr, &[0x03, 0x03, 0x05]);
    silence(&mut avr, &[0x03, 0x03, 0x08]);
    // Oversize set.
    let mut big = vec![28, 0x04, 0x03];
    big.extend(0..25u8);
    assert_eq!(exchange(&mut avr, &big, 1), [0x87]);
    // Zero and one as a length byte end at once.
    silence(&mut avr, &[0x00]);
    silence(&mut avr, &[0x01]);
    // The master is still in its boot exception; the last error was the short length
    // byte (code 1), and it counted all nine bad frames.
    assert_eq!(
        read_master(&mut avr, &[11, 12, 13], 5),
        [0x02, 0x00, 1, 9, 0]
    );
}

#[test]
fn each_error_reply_of_protocol_md_names_its_code_in_lasterror() {
    // docs/protocol.md's bad-input table, the rows the test above leaves out: each frame
    // gets its reply, and LASTERROR (master id 12) then holds its code.
    let (mut avr, _) = boot();
    let cases: [(&[u8], Option<u8>, u8); 8] = [
        // L = 2: the frame ends after a write's header.
        (&[0x02, 0x12], Some(0x81), 1),
        // A read with a byte more than its set number.
        (&[0x04, 0x03, 0x02, 0x00], None, 5),
        // A write to an id no DS board has.
        (&[0x05, 0x12, 0x01, 0x7f, 0x00], Some(0x84), 4),
        // A write with fewer entries than its count says.
        (&[0x06, 0x12, 0x02, 0x09, 0xff, 0x7f], Some(0x85), 5),
        // DS id 45 sized as the original's table sized it (one byte): FAULTTIME takes two.
        (&[0x05, 0x12, 0x01, 0x2d, 0x00], Some(0x85), 5),
        // Master id 12, just past the original's table, is the read-only LASTERROR.
        (&[0x05, 0x02, 0x01, 0x0c, 0x00], Some(0x89), 9),
        // Set read set 8.
        (&[0x04, 0x14, 0x08, 0x01], Some(0x86), 6),
        // An id the master lacks in a read set reads as one byte `cd`.
        (&[0x04, 0x04, 0x05, 0x30], Some(0x01), 0),
    ];
    for (frame, reply, code) in cases {
        match reply {
            Some(byte) => assert_eq!(exchange(&mut avr, frame, 1), [byte], "{frame:02x?}"),
            None => silence(&mut avr, frame),
        }
        if code != 0 {
            assert_eq!(read_master(&mut avr, &[12], 1), [code], "{frame:02x?}");
        }
    }
    assert_eq!(exchange(&mut avr, &[0x03, 0x03, 0x05], 1), [0xcd]);
    assert_eq!(read_master(&mut avr, &[12, 13], 3), [10, 8, 0]);
}

#[test]
fn a_frame_that_stops_arriving_is_dropped_and_the_link_recovers() {
    let (mut avr, _) = boot();
    // Garbage: a length byte of 0x40 and two more bytes, then nothing for 100 ms.
    silence(&mut avr, &[0x40, 0x12, 0x01]);
    avr.run_us(100_000);
    assert_eq!(
        exchange(&mut avr, &[0x05, 0x02, 0x01, 0x00, 0x01], 1),
        [0x00]
    );
    assert_eq!(
        read_master(&mut avr, &[11, 12, 13], 5),
        [0x00, 0x00, 8, 1, 0]
    );
}

#[test]
fn a_byte_with_a_framing_error_skips_the_rest_of_its_frame_until_the_line_is_quiet() {
    let (mut avr, _) = boot();
    // A 9-byte frame whose length byte arrives garbled. Its other eight bytes hold a write
    // of REGMASTER_PCTIMEOUT = 0x1234 ms (`06 02 01 0f 34 12`) and two zeros: taken as
    // frames of their own they would arm the PC-silence failsafe and count two errors.
    // Then, at once, resetExceptions() for device 0, clean: the line is not quiet yet, so
    // it is skipped too, with no reply.
    avr.uart_send_framing_error(&[0x09]);
    let clean = [0x05, 0x02, 0x01, 0x00, 0x01];
    let mut rest = vec![0x06, 0x02, 0x01, 0x0f, 0x34, 0x12, 0x00, 0x00];
    rest.extend_from_slice(&clean);
    silence(&mut avr, &rest);
    // 50 ms after the last byte the line is quiet, and the next frame is answered.
    avr.run_us(35_000);
    assert_eq!(exchange(&mut avr, &clean, 1), [0x00]);
    // The reset ran once, PCTIMEOUT is untouched, and the framing error is the last error
    // (code 13) and the only one counted.
    assert_eq!(
        read_master(&mut avr, &[11, 12, 13, 15], 7),
        [0x00, 0x00, 13, 1, 0, 0, 0]
    );
}

#[test]
fn frames_sent_without_waiting_for_replies_are_all_answered_up_to_63_bytes() {
    // The Uno's serial core held 63 bytes for the original: a program that sends that many
    // bytes of frames in one write gets every reply. Each reply here is 40 bytes (a set of
    // 20 two-byte registers, as the library's set 0), 3.5 ms on the line, while the next
    // frames keep coming in.
    let mut rig = master_support::Rig::new();
    let mut define = vec![23, 0x14, 0x00];
    define.extend([id::REG_STATUS; 20]);
    assert_eq!(rig.exchange(&define, 1), [20]);
    let frames: Vec<u8> = (0..21).flat_map(|_| [0x03, 0x13, 0x00]).collect();
    assert_eq!(frames.len(), 63);
    let replies = rig.exchange(&frames, 21 * 40);
    assert_eq!(replies.len(), 840);
    // STATUS: a DS board in its boot state, twenty times a reply.
    let status: Vec<u8> = [0x09, 0x00].repeat(20);
    for (i, reply) in replies.chunks(40).enumerate() {
        assert_eq!(reply, status, "reply {i}");
    }
    assert_eq!(rig.master_regs(&[12, 13], 3), [0, 0, 0], "no error counted");
}

#[test]
fn frames_sent_without_waiting_for_replies_lose_bytes_and_none_of_the_rest_runs() {
    // Two 255-byte frames in one write, each 126 writes of REG_DEBUGLED on controller 1:
    // the first takes ~13 ms of bus time while the second's bytes overflow the 64-byte
    // receive queue. The lost byte is an overrun (code 14), and the rest of the second
    // frame is skipped (its `04 05` pairs would otherwise run as read-set frames).
    let mut rig = master_support::Rig::new();
    let mut frame = vec![0xff, 0x12, 126];
    for _ in 0..126 {
        frame.extend_from_slice(&[id::REG_DEBUGLED, 0x05]);
    }
    rig.clear_records();
    let mut both = frame.clone();
    both.extend_from_slice(&frame);
    assert_eq!(rig.exchange(&both, 1), [0x00], "the first frame only");
    rig.run_us(100_000);
    assert_eq!(rig.slave(1).writes_to(id::REG_DEBUGLED).len(), 126);
    // The link works again; read set 5 was never configured by a fragment.
    assert_eq!(rig.master_regs(&[12], 1), [14]);
    rig.silence(&[0x03, 0x03, 0x05]);
}

#[test]
fn writes_to_slaves_without_a_bus_say_so() {
    let (mut avr, _) = boot();
    assert_eq!(
        exchange(&mut avr, &[0x06, 0x12, 0x01, 0x09, 0xfe, 0x9f], 1),
        [0x8c]
    );
}
