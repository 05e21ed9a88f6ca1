//! Whole-command tests: a command line in, exact frames and output out,
//! over the fake port.

use clap::Parser;

use crate::error::MasterSays;
use crate::fake::FakePort;
use crate::link::Link;
use crate::{run, Cli, HostError, Style};

/// What one command did.
struct Outcome {
    result: Result<(), HostError>,
    out: String,
    port: FakePort,
    opened: bool,
}

/// Runs `hostctl ARGS` against a fake port answering with `replies`.
fn hostctl<R: AsRef<[u8]>>(args: &str, replies: &[R]) -> Outcome {
    hostctl_with(args, replies, Some("/dev/fake".to_owned()), false)
}

fn hostctl_with<R: AsRef<[u8]>>(
    args: &str,
    replies: &[R],
    env: Option<String>,
    in_place: bool,
) -> Outcome {
    let argv = std::iter::once("hostctl").chain(args.split_whitespace());
    let cli = Cli::try_parse_from(argv).unwrap();
    let mut port = FakePort::with_replies(replies);
    let mut opened = false;
    let mut out = Vec::new();
    let style = Style {
        json: cli.json,
        in_place,
        width: || None,
    };
    let result = run(
        &cli,
        env,
        |_path: &str| {
            opened = true;
            Ok(Link::ready(&mut port))
        },
        style,
        &mut out,
    );
    Outcome {
        result,
        out: String::from_utf8(out).unwrap(),
        port,
        opened,
    }
}

/// Runs a command that must fail on its input: returns the message and
/// checks that the port was never opened and nothing was written.
fn refused(args: &str) -> String {
    let outcome = hostctl::<&[u8]>(args, &[]);
    assert!(!outcome.opened, "{args}: port opened");
    assert!(outcome.port.written.is_empty(), "{args}: bytes sent");
    assert!(outcome.out.is_empty(), "{args}: output {:?}", outcome.out);
    match outcome.result {
        Err(e) => e.to_string(),
        Ok(()) => panic!("{args}: accepted"),
    }
}

/// Runs a command that must succeed: returns what it printed.
fn printed<R: AsRef<[u8]>>(args: &str, replies: &[R]) -> String {
    let outcome = hostctl(args, replies);
    if let Err(e) = outcome.result {
        panic!("{args}: {e}");
    }
    outcome.out
}

// ---- write ----

/// The replies to a write on a controller and the status read that follows it (set 7 holds
/// REG_STATUS, then its value): running, or in exception.
const WRITTEN_RUNNING: [&[u8]; 3] = [&[0x00], &[0x01], &[0x00, 0x00]];
const WRITTEN_IN_EXCEPTION: [&[u8]; 3] = [&[0x00], &[0x01], &[0x01, 0x00]];

#[test]
fn write_drive_speed_sends_the_reference_frame() {
    let o = hostctl("write 1 DRIVE_REQSPEED 1000", &WRITTEN_RUNNING);
    o.result.unwrap();
    // The write, then the controller's status through the scratch set.
    assert_eq!(
        o.port.frames_hex(),
        ["06 12 01 09 fe 9f", "04 14 07 03", "03 13 07"]
    );
    assert_eq!(
        o.out,
        "device 1 REGDS_DRIVE_REQSPEED = 1000 ticks/s (raw 0x9ffe, arrives as 999.908 ticks/s)\n"
    );
}

#[test]
fn a_closed_standard_output_is_not_blamed_on_the_serial_line() {
    struct Closed;
    impl std::io::Write for Closed {
        fn write(&mut self, _: &[u8]) -> std::io::Result<usize> {
            Err(std::io::ErrorKind::BrokenPipe.into())
        }
        fn flush(&mut self) -> std::io::Result<()> {
            Ok(())
        }
    }
    let cli = Cli::try_parse_from(["hostctl", "write", "0", "pctimeout", "1500"]).unwrap();
    let mut port = FakePort::with_replies(&[[0x00]]);
    let style = Style {
        json: false,
        in_place: false,
        width: || None,
    };
    let e = run(
        &cli,
        Some("/dev/fake".into()),
        |_: &str| Ok(Link::ready(&mut port)),
        style,
        &mut Closed,
    )
    .unwrap_err();
    assert!(matches!(e, HostError::Output(_)), "{e:?}");
    assert_eq!(
        e.to_string(),
        "cannot write hostctl's output: broken pipe (standard output was closed, e.g. by \
         `| head`); the rover and the serial link are not at fault"
    );
}

#[test]
fn a_write_that_nothing_will_act_on_says_so() {
    // Fresh from the port's reboot, the controller is in its boot exception.
    assert_eq!(
        printed("write 1 DRIVE_REQSPEED 1000", &WRITTEN_IN_EXCEPTION),
        "device 1 REGDS_DRIVE_REQSPEED = 1000 ticks/s (raw 0x9ffe, arrives as 999.908 ticks/s)\n\
         note: controller 1 is in exception (every controller is after the port opens, which \
         reboots the rover): the board acts on nothing until the exception is reset, a \
         demand (REQSPEED, REQPOS) is replaced meanwhile, and when this command ends, closing \
         the port reboots the rover again, which restores every default. To see it act, put \
         `calibrate`, `reset` and then this write in one script: `hostctl run FILE`.\n"
    );
    // A write of EXCEPTIONDATA stops the board whatever its value.
    let out = printed("write 4 exceptiondata 0", &WRITTEN_IN_EXCEPTION);
    assert!(
        out.ends_with(
            "note: any write to a controller's EXCEPTIONDATA raises REMOTESLAVE (3) on it, \
             whatever the value: controller 4 stops both its motors until its exception is \
             reset, by a `reset` line in a `hostctl run FILE` script (this command's end \
             reboots the rover anyway, as closing the port does)\n"
        ),
        "{out}"
    );
    let o = hostctl("--json write 1 DRIVE_REQSPEED 1000", &WRITTEN_IN_EXCEPTION);
    assert!(o.out.ends_with(",\"in_exception\":true}\n"), "{}", o.out);
    // A register of the common block acts at once, in exception too: no note.
    let o = hostctl("write 1 RESET 4", &WRITTEN_IN_EXCEPTION);
    assert_eq!(
        o.out,
        "device 1 REG_RESET = 4 bits (raw 0x04, arrives as 4 bits)\n"
    );
    // A status that cannot be read leaves the write reported, with the reason.
    let o = hostctl("write 1 DRIVE_REQSPEED 1000", &[[0x00]]);
    o.result.unwrap();
    assert!(
        o.out
            .contains("\nnote: the controller's status could not be read afterwards: "),
        "{}",
        o.out
    );
}

#[test]
fn a_position_right_after_the_port_opened_is_not_called_degrees() {
    let note = "note: not degrees: opening the port rebooted the rover, so the board is on its \
                boot calibration (pot 0..1023 as -512..512, clamped to the register's range). \
                Positions are degrees after `calibrate`, in one `hostctl run FILE` script.\n";
    let o = hostctl("read 1 STEER_ACTUALPOS", &[&[0x01][..], &[0xfe, 0xff]]);
    o.result.unwrap();
    assert_eq!(
        o.out,
        format!(
            "device 1 REGDS_STEER_ACTUALPOS = ≥200.000 deg (raw 0xfffe)\nnote: at the end of the \
             register's range (-200 to 200): the reading is 200 deg or more, since the rover \
             clamps what it reports to that range\n{note}"
        )
    );
    let o = hostctl("--json read 3 ONE_ACTUALPOS", &[&[0x01][..], &[0xfe, 0xff]]);
    assert!(
        o.out.ends_with(",\"boot_calibration\":true}\n"),
        "{}",
        o.out
    );
    let o = hostctl("write 3 ONE_REQPOS 20", &WRITTEN_RUNNING);
    assert!(o.out.ends_with(note), "{}", o.out);
    // A calibration end written since the boot is degrees, and what the board uses.
    assert_eq!(
        printed("read 2 STEER_CALIBMAX", &[&[0x01][..], &[0xc4]]),
        "device 2 REGDS_STEER_CALIBMAX = 65.197 deg (raw 0xc4)\n"
    );
    // At its boot value the register shows ±120, but the board calibrates with ±512.
    let end_note = "note: not what the board uses: opening the port rebooted the rover, and \
                    a board fresh from boot calibrates with -512..512, which this 1-byte \
                    register shows clamped to its range. The board uses this register's \
                    value once it is written, e.g. by `calibrate` in a `hostctl run FILE` \
                    script.\n";
    assert_eq!(
        printed("read 2 STEER_CALIBMIN", &[&[0x01][..], &[0x00]]),
        format!("device 2 REGDS_STEER_CALIBMIN = -120.000 deg (raw 0x00)\n{end_note}")
    );
    assert_eq!(
        printed("read 6 TWO_CALIBMAX", &[&[0x01][..], &[0xfe]]),
        format!("device 6 REGLL_TWO_CALIBMAX = 120.000 deg (raw 0xfe)\n{end_note}")
    );
    let o = hostctl("--json read 1 STEER_CALIBMIN", &[&[0x01][..], &[0x00]]);
    assert!(
        o.out.ends_with(",\"boot_calibration\":true}\n"),
        "{}",
        o.out
    );
}

#[test]
fn write_lift_and_master_reset_send_the_reference_frames() {
    let o = hostctl("write 3 REGLL_ONE_REQPOS 20", &WRITTEN_RUNNING);
    o.result.unwrap();
    assert_eq!(o.port.frames_hex()[0], "06 32 01 09 cb 8c");

    let o = hostctl("write 3 regll_two_reqpos 20", &WRITTEN_RUNNING);
    o.result.unwrap();
    assert_eq!(o.port.frames_hex()[0], "06 32 01 1b cb 8c");

    // The master is not left waiting: no status read.
    let o = hostctl("write 0 REGMASTER_RESET 1", &[[0x00]]);
    o.result.unwrap();
    assert_eq!(o.port.frames_hex(), ["05 02 01 00 01"]);
    assert_eq!(
        o.out,
        "device 0 REGMASTER_RESET = 1 (raw 0x01, arrives as 1)\n"
    );
}

#[test]
fn the_pc_silence_timeout_is_written_as_a_master_word() {
    let o = hostctl("write 0 pctimeout 500", &[[0x00]]);
    o.result.unwrap();
    assert_eq!(o.port.frames_hex(), ["06 02 01 0f f4 01"]);
    assert_eq!(
        o.out,
        "device 0 REGMASTER_PCTIMEOUT = 500 ms (raw 0x01f4, arrives as 500 ms)\n\
         note: armed only until this command ends: closing the port reboots the master, \
         whose boot turns the failsafe off; for a session that should stop the rover when it \
         stops talking, put `write 0 pctimeout MS` first in a `hostctl run FILE` script.\n"
    );
    // Beyond what the master acts on: said so.
    let out = printed("write 0 pctimeout 65000", &[[0x00]]);
    assert!(
        out.starts_with(
            "device 0 REGMASTER_PCTIMEOUT = 65000 ms (raw 0xfde8, arrives as 65000 ms)\n\
             note: the master acts on at most 60000 ms; a longer REGMASTER_PCTIMEOUT counts as \
             60000\nnote: armed only"
        ),
        "{out}"
    );
    // Turning it off needs no note.
    assert_eq!(
        printed("write 0 pctimeout 0", &[[0x00]]),
        "device 0 REGMASTER_PCTIMEOUT = 0 ms (raw 0x0000, arrives as 0 ms)\n"
    );
    assert!(refused("write 0 pctimeout 70000").contains("allowed 0..65535"));
}

#[test]
fn write_says_what_the_board_uses_for_truncated_registers() {
    let o = hostctl("write 1 drive_overcurrentthresh 10", &WRITTEN_RUNNING);
    o.result.unwrap();
    assert_eq!(o.port.frames_hex()[0], "06 12 01 0f 8f 02");
    assert_eq!(
        o.out,
        "device 1 REGDS_DRIVE_OVERCURRENTTHRESH = 10 adc (raw 0x028f, arrives as 9 adc)\n"
    );
    assert_eq!(
        printed("write 1 drive_stallcheck 100", &WRITTEN_RUNNING),
        "device 1 REGDS_DRIVE_STALLCHECK = 100 duty (raw 0x63, arrives as 99 duty)\n"
    );
    assert_eq!(
        printed("write 1 drive_mode 5", &WRITTEN_RUNNING),
        "device 1 REGDS_DRIVE_MODE = 5 mode (raw 0x05, kept as 5, which acts as mode 0)\n"
    );
    assert_eq!(
        printed("write 1 drive_mode 1", &WRITTEN_RUNNING),
        "device 1 REGDS_DRIVE_MODE = 1 mode (raw 0x01, arrives as 1 mode)\n"
    );
    // JSON's "applied" is the same value as a number.
    let o = hostctl(
        "--json write 1 drive_overcurrentthresh 10",
        &WRITTEN_RUNNING,
    );
    assert!(o.out.contains(",\"applied\":9,"), "{}", o.out);
    // Read back, the register shows what it holds (see
    // an_integer_parameter_is_read_with_what_the_board_makes_of_it).
}

#[test]
fn write_takes_negative_values_and_register_numbers() {
    let o = hostctl("write 1 26 -40", &WRITTEN_RUNNING);
    o.result.unwrap();
    assert_eq!(o.port.frames_hex()[0], "06 12 01 1a 65 66");
    let o = hostctl("write 4 RESET 1", &WRITTEN_RUNNING);
    o.result.unwrap();
    assert_eq!(o.port.frames_hex()[0], "05 42 01 00 01");
    // A value clap alone would take for a flag: -0.5 maps to raw 0x7fad on ±200.
    let o = hostctl("write 1 26 -.5", &WRITTEN_RUNNING);
    o.result.unwrap();
    assert_eq!(o.port.frames_hex()[0], "06 12 01 1a ad 7f");
    // -inf reaches hostctl's own check, which refuses it naming the register's range.
    let o = hostctl("write 1 26 -inf", &WRITTEN_RUNNING);
    let message = o.result.unwrap_err().to_string();
    assert!(message.contains("allowed -200..200 deg"), "{message}");
    assert!(o.port.frames_hex().is_empty());
}

#[test]
fn write_json_reports_value_raw_and_applied() {
    let o = hostctl("--json write 1 STEER_REQPOS 40", &WRITTEN_RUNNING);
    o.result.unwrap();
    assert_eq!(o.port.frames_hex()[0], "06 12 01 1a 98 99");
    assert_eq!(
        o.out,
        "{\"command\":\"write\",\"device\":1,\"board\":\"DS\",\"id\":26,\
         \"register\":\"REGDS_STEER_REQPOS\",\"value\":40,\"raw\":39320,\
         \"applied\":39.99756,\"unit\":\"deg\",\"in_exception\":false,\
         \"boot_calibration\":true}\n"
    );
}

#[test]
fn write_error_code_reply_is_put_in_words() {
    // The master's error replies are 0x80 | code (docs/protocol.md).
    let o = hostctl("write 1 DRIVE_REQSPEED 0", &[[0x84]]);
    assert_eq!(o.port.frames_hex(), ["06 12 01 09 ff 7f"]);
    assert_eq!(
        o.result.unwrap_err().to_string(),
        "device 1 refused the write to REGDS_DRIVE_REQSPEED: code 0x84 \
         (write to a register id the device does not have); the frame reached the master \
         damaged or not as sent; retry, and reset the rover or restart the twin if it keeps \
         happening"
    );
    assert!(o.out.is_empty());

    let o = hostctl("write 1 DRIVE_REQSPEED 0", &[[0x99]]);
    assert!(matches!(
        o.result,
        Err(HostError::WriteRefused { code: 0x99, ref words, .. }) if words == "not a known error code"
    ));
}

/// The probe after a timeout: REGMASTER_LASTERROR and ERRORCOUNT through the scratch set.
const PROBE: [&str; 2] = ["05 04 07 0c 0d", "03 03 07"];

#[test]
fn write_without_reply_times_out() {
    // Nothing answers, not even the master's error registers: the line or the master is
    // blamed, not the device.
    let o = hostctl::<&[u8]>("write 2 DRIVE_REQSPEED 0", &[]);
    assert_eq!(o.port.frames_hex(), ["06 22 01 09 ff 7f", PROBE[0]]);
    assert_eq!(
        o.result.unwrap_err().to_string(),
        "device 2 did not answer within 1 s (0 of 1 reply bytes), and neither did the master \
         when asked for its error registers: the master or the serial line is not answering, \
         which is no fault of device 2 (while the remote control has the link, the master \
         ignores the PC); check the cable, turn the remote control off, reset the rover, or \
         restart the twin"
    );
    // A look for stray bytes before the frame (no wait), 1 s for the reply; the probe
    // waits briefly: a drain for stray bytes, then 300 ms for its reply.
    assert_eq!(
        o.port.timeouts,
        [
            std::time::Duration::ZERO,
            crate::link::REPLY_TIMEOUT,
            crate::link::DRAIN_TIMEOUT,
            crate::link::PROBE_TIMEOUT
        ]
    );
}

#[test]
fn a_timeout_names_the_cause_the_master_reports() {
    let err = |args: &str, replies: &[&[u8]]| {
        let o = hostctl(args, replies);
        let frames = o.port.frames_hex();
        assert_eq!(frames[frames.len() - 2..], PROBE, "{args}");
        assert!(o.out.is_empty());
        o.result.unwrap_err().to_string()
    };
    // The write frame lost a byte on the way: the master dropped it as truncated (code 8).
    assert_eq!(
        err(
            "write 2 DRIVE_REQSPEED 0",
            &[&[], &[0x02], &[0x08, 0x01, 0x00]]
        ),
        "device 2 did not answer within 1 s (0 of 1 reply bytes); the master's last link error \
         since its boot (it may be older than this command): frame incomplete: bytes stopped \
         arriving (code 8, 1 in all): a byte was lost on the serial line; retry, and check the \
         cable if it keeps happening"
    );
    // A controller off the bus (code 12).
    assert_eq!(
        err(
            "write 4 DRIVE_REQSPEED 0",
            &[&[], &[0x02], &[0x0c, 0x03, 0x00]]
        ),
        "device 4 did not answer within 1 s (0 of 1 reply bytes); the master's last link error \
         since its boot (it may be older than this command): a slave did not answer on the \
         I2C bus (code 12, 3 in all): controller 4 is not answering the master on the I2C \
         bus; check that it is fitted and powered (on the twin: `twin inject restore 4`), then \
         reset the rover; or, if this was the first command after the port opened, it was \
         still rebooting from the master's boot: leave `--settle-ms` at its default, 2000"
    );
    // No link error: the controller answered the master, so the reply was lost on the
    // way back (or the master rebooted).
    assert_eq!(
        err(
            "write 2 DRIVE_REQSPEED 0",
            &[&[], &[0x02], &[0x00, 0x00, 0x00]]
        ),
        "device 2 did not answer within 1 s (0 of 1 reply bytes), but the master answers now \
         and reports no link error since its boot: the reply was lost on the serial line or \
         the master rebooted meanwhile; retry, and check the cable if it keeps happening"
    );
    // The master's own reply cut short, then nothing wrong on its side: lost on the way back.
    assert_eq!(
        err(
            "read 0 11",
            &[&[0x01][..], &[0x01], &[0x02], &[0x00, 0x00, 0x00]]
        ),
        "the master did not answer within 1 s (1 of 2 reply bytes) but answers now and \
         reports no link error, so its reply was lost on the serial line; retry, and check the \
         cable if it keeps happening"
    );
}

// ---- read ----

#[test]
fn read_uses_scratch_set_7_and_decodes_units() {
    let o = hostctl("read 1 DRIVE_ACTUALSPEED", &[&[0x01][..], &[0xfe, 0x9f]]);
    o.result.unwrap();
    assert_eq!(o.port.frames_hex(), ["04 14 07 10", "03 13 07"]);
    assert_eq!(
        o.out,
        "device 1 REGDS_DRIVE_ACTUALSPEED = 999.908 ticks/s (raw 0x9ffe)\n"
    );
}

#[test]
fn exception_data_is_read_in_words() {
    let o = hostctl("read 1 EXCEPTIONDATA", &[&[0x01][..], &[0x02, 0x05]]);
    assert_eq!(
        o.out,
        "device 1 REG_EXCEPTIONDATA = 1282 (raw 0x0502): boot, the whole board (the last exception)\n"
    );
    // The master's: type | controller << 8 | motor << 12 (reference §6.2).
    let o = hostctl("read 0 EXCEPTIONDATA", &[&[0x01][..], &[0x01, 0x14]]);
    assert_eq!(
        o.out,
        "device 0 REGMASTER_EXCEPTIONDATA = 5121 (raw 0x1401): overcurrent on controller 4, motor 1 (wheel 3's steer)\n"
    );
    let o = hostctl("read 0 EXCEPTIONDATA", &[&[0x01][..], &[0x00, 0x00]]);
    assert!(o.out.ends_with(": no exception\n"), "{}", o.out);
    // In JSON the value comes taken apart too, for a program to branch on.
    let o = hostctl("--json read 1 EXCEPTIONDATA", &[&[0x01][..], &[0x02, 0x05]]);
    assert_eq!(
        o.out,
        "{\"command\":\"read\",\"device\":1,\"board\":\"DS\",\"id\":5,\
         \"register\":\"REG_EXCEPTIONDATA\",\"raw\":1282,\"value\":1282,\"unit\":\"\",\
         \"exception\":{\"type\":2,\"name\":\"BOOT\",\"motor\":5,\
         \"text\":\"boot, the whole board (the last exception)\"}}\n"
    );
}

#[test]
fn status_error_and_sensor_bits_are_read_in_words() {
    // A DS board's boot STATUS (reference §6.2).
    let o = hostctl("read 1 STATUS", &[&[0x01][..], &[0x09, 0x00]]);
    assert_eq!(
        o.out,
        "device 1 REG_STATUS = 9 bits (raw 0x0009): DS board, in exception (its motors are \
         stopped)\n"
    );
    // The master's last link error by its protocol name (docs/protocol.md).
    let o = hostctl("read 0 LASTERROR", &[&[0x01][..], &[0x0c]]);
    assert_eq!(
        o.out,
        "device 0 REGMASTER_LASTERROR = 12 code (raw 0x0c): NoAnswer: a slave did not answer \
         on the I2C bus\n"
    );
    let o = hostctl("--json read 0 TEMPSREAD", &[&[0x01][..], &[0xf7, 0x03]]);
    assert_eq!(
        o.out,
        "{\"command\":\"read\",\"device\":0,\"board\":\"MASTER\",\"id\":14,\
         \"register\":\"REGMASTER_TEMPSREAD\",\"raw\":1015,\"value\":1015,\"unit\":\"bits\",\
         \"sensors_read\":{\"ambient\":true,\"boards\":[1,2,4,5,6,7,8,9],\
         \"text\":\"reading: ambient, board 1, board 2, board 4, board 5, board 6, board 7, \
         board 8, board 9; no reading: board 3\"}}\n"
    );
}

#[test]
fn an_integer_parameter_is_read_with_what_the_board_makes_of_it() {
    // STALLCHECK's power-up register (reference §8.1): 119.469, while the board uses 120.
    let o = hostctl("read 1 DRIVE_STALLCHECK", &[&[0x01][..], &[0x77]]);
    assert_eq!(
        o.out,
        "device 1 REGDS_DRIVE_STALLCHECK = 119.469 duty (raw 0x77)\nnote: the board uses whole \
         numbers: written, this value acts as 119; from boot until the first write it uses 120\n"
    );
    // The drive's threshold at power-up, after a write of 299.997 (0x4ccc) just the same.
    let o = hostctl(
        "read 1 drive_overcurrentthresh",
        &[&[0x01][..], &[0xcc, 0x4c]],
    );
    assert_eq!(
        o.out,
        "device 1 REGDS_DRIVE_OVERCURRENTTHRESH = 299.997 adc (raw 0x4ccc)\nnote: the board \
         uses whole numbers: written, this value acts as 299; from boot until the first write \
         it uses 300\n"
    );
    assert_eq!(
        printed("read 1 DRIVE_MODE", &[&[0x01][..], &[0x05]]),
        "device 1 REGDS_DRIVE_MODE = 5 mode (raw 0x05)\nnote: any value but 1 acts as mode 0\n"
    );
    // A value the board uses as it is: no note.
    assert_eq!(
        printed("read 1 DRIVE_MODE", &[&[0x01][..], &[0x01]]),
        "device 1 REGDS_DRIVE_MODE = 1 mode (raw 0x01)\n"
    );
}

#[test]
fn read_sizes_the_reply_from_the_device_table() {
    // STEER_CALIBMAX is one byte on DS; the same id (43) is TWO_STALLCHECK on LL.
    let o = hostctl("read 2 STEER_CALIBMAX", &[&[0x01][..], &[0xc4]]);
    o.result.unwrap();
    assert_eq!(o.port.frames_hex(), ["04 24 07 2b", "03 23 07"]);
    assert_eq!(
        o.out,
        "device 2 REGDS_STEER_CALIBMAX = 65.197 deg (raw 0xc4)\n"
    );

    let o = hostctl("--json read 0 11", &[&[0x01][..], &[0x01, 0x14]]);
    o.result.unwrap();
    assert_eq!(o.port.frames_hex(), ["04 04 07 0b", "03 03 07"]);
    assert_eq!(
        o.out,
        "{\"command\":\"read\",\"device\":0,\"board\":\"MASTER\",\"id\":11,\
         \"register\":\"REGMASTER_EXCEPTIONDATA\",\"raw\":5121,\"value\":5121,\"unit\":\"\",\
         \"exception\":{\"type\":1,\"name\":\"OVERCURRENT\",\"controller\":4,\"motor\":1,\
         \"wheel\":3,\"wheel_motor\":\"steer\",\
         \"text\":\"overcurrent on controller 4, motor 1 (wheel 3's steer)\"}}\n"
    );
}

#[test]
fn a_temperature_the_master_has_not_read_is_no_reading() {
    // The scratch set holds the temperature and REGMASTER_TEMPSREAD (id 14); bit 0 (the
    // ambient sensor) clear: the 0.0 °C it holds is not shown as a temperature.
    let unread: [&[u8]; 2] = [&[0x02], &[0xaa, 0x2a, 0x00, 0x00]];
    let o = hostctl("read 0 tempambient", &unread);
    o.result.unwrap();
    assert_eq!(o.port.frames_hex(), ["05 04 07 01 0e", "03 03 07"]);
    assert_eq!(
        o.out,
        "device 0 REGMASTER_TEMPAMBIENT: no reading (raw 0x2aaa): not read yet: the master \
         reads one sensor every 2 s from 5 s after boot, and opening the port rebooted it; or \
         the sensor is missing, or its last read failed\nnote: this sensor is first read about \
         5 s after the master's boot: `hostctl --settle-ms 6000 read 0 TEMPAMBIENT` waits for \
         it. With no reading even then, it is missing or its reads fail, or another sensor is \
         missing: the master then never reads the last one(s) in its order (ambient, 1..9). \
         It raises 10, sensor missing, but keeps only its first exception, and \
         a one-shot command sees its boot one: a `hostctl run` script that `reset`s and then \
         waits shows it (`hostctl watch --readset 2` shows every sensor as it is read)\n"
    );
    // Controller 9's sensor is the tenth read, 18 s later.
    let o = hostctl("read 0 temp9", &unread);
    assert!(
        o.out.contains("first read about 23 s after the master's boot: `hostctl --settle-ms 24000 read 0 TEMP9`"),
        "{}",
        o.out
    );
    let o = hostctl("--json read 0 tempambient", &unread);
    assert_eq!(
        o.out,
        "{\"command\":\"read\",\"device\":0,\"board\":\"MASTER\",\"id\":1,\
         \"register\":\"REGMASTER_TEMPAMBIENT\",\"raw\":10922,\"value\":null,\
         \"unit\":\"degC\",\"read\":false}\n"
    );
    // Controller 9's sensor (bit 9) read: its value, as read.
    let read: [&[u8]; 2] = [&[0x02], &[0x87, 0x58, 0x00, 0x02]];
    let o = hostctl("read 0 TEMP9", &read);
    assert_eq!(o.port.frames_hex(), ["05 04 07 0a 0e", "03 03 07"]);
    assert_eq!(
        o.out,
        "device 0 REGMASTER_TEMP9 = 21.498 degC (raw 0x5887)\n"
    );
    let o = hostctl("--json read 0 TEMP9", &read);
    assert!(
        o.out.ends_with(",\"unit\":\"degC\",\"read\":true}\n"),
        "{}",
        o.out
    );
}

#[test]
fn a_reading_at_the_end_of_its_range_is_not_shown_as_exact() {
    // Controller 9's sensor read at 0xfffe: the master clamps anything hotter than 100 °C.
    let hot: [&[u8]; 2] = [&[0x02], &[0xfe, 0xff, 0x00, 0x02]];
    let o = hostctl("read 0 TEMP9", &hot);
    assert_eq!(
        o.out,
        "device 0 REGMASTER_TEMP9 = ≥100.000 degC (raw 0xfffe)\nnote: at the end of the \
         register's range (-20 to 100): the reading is 100 degC or more, since the rover \
         clamps what it reports to that range\n"
    );
    let o = hostctl("--json read 0 TEMP9", &hot);
    assert!(
        o.out
            .ends_with(",\"value\":100,\"unit\":\"degC\",\"at_limit\":\"upper\",\"read\":true}\n"),
        "{}",
        o.out
    );
    // A drive's error below its range: -1000 or less.
    let o = hostctl("--json read 1 drive_error", &[&[0x01][..], &[0x00, 0x00]]);
    assert!(
        o.out
            .contains("\"value\":-1000,\"unit\":\"ticks/s\",\"at_limit\":\"lower\""),
        "{}",
        o.out
    );
    // A written parameter holds what was written, and an interval of 0 ms is 0: no mark.
    let o = hostctl("read 1 drive_reqspeed", &[&[0x01][..], &[0xfe, 0xff]]);
    assert!(
        o.out
            .starts_with("device 1 REGDS_DRIVE_REQSPEED = 4000.000 ticks/s (raw 0xfffe)\n"),
        "{}",
        o.out
    );
    let o = hostctl("read 1 drive_intervalctrl", &[&[0x01][..], &[0x00, 0x00]]);
    assert_eq!(
        o.out,
        "device 1 REGDS_DRIVE_INTERVALCTRL = 0.000 ms (raw 0x0000)\n"
    );
}

#[test]
fn read_stops_when_the_set_is_not_accepted() {
    let o = hostctl("read 1 TIMER", &[[0x86]]);
    assert_eq!(o.port.frames_hex(), ["04 14 07 01"]);
    assert_eq!(
        o.result.unwrap_err().to_string(),
        "device 1 answered 134 to set-read-set 7, expected the count 1; read set index must be 0-7"
    );
}

#[test]
fn read_with_a_short_reply_times_out() {
    let o = hostctl("read 1 TIMER", &[&[0x01][..], &[0x34]]);
    assert!(matches!(
        o.result,
        Err(HostError::Timeout {
            device: 1,
            expected: 2,
            got: 1,
            master: MasterSays::Silent,
            ..
        })
    ));
}

// ---- readset ----

#[test]
fn readset_sends_the_library_set_0_frame() {
    let args = "readset --device 1 0 TIMER INTERVALI2C STATUS EXCEPTIONDATA CHASSIS \
                DRIVE_ACTUALSPEED DRIVE_ERROR DRIVE_ERRORINTEGRAL DRIVE_ERRORDERIV \
                DRIVE_CONTROL DRIVE_INTERVALCTRL DRIVE_CURRENT DRIVE_ODO STEER_ACTUALPOS \
                STEER_ERROR STEER_ERRORINTEGRAL STEER_ERRORDERIV STEER_CONTROL \
                STEER_INTERVALCTRL STEER_CURRENT";
    let o = hostctl(args, &[[0x14]]);
    o.result.unwrap();
    assert_eq!(
        o.port.frames_hex(),
        ["17 14 00 01 02 03 05 2c 10 11 12 13 14 15 16 17 21 22 23 24 25 26 27"]
    );
    assert!(o.out.starts_with("read set 0 = REG_TIMER REG_INTERVALI2C "));
    assert!(o.out.ends_with(" REGDS_STEER_CURRENT (20 registers)\n"));
}

#[test]
fn readset_defaults_to_the_master_table() {
    let o = hostctl("readset 2 1 2 3 4 5 6 7 8 9 10 11", &[[0x0b]]);
    o.result.unwrap();
    assert_eq!(
        o.port.frames_hex(),
        ["0e 04 02 01 02 03 04 05 06 07 08 09 0a 0b"]
    );
    let o = hostctl("--json readset 5 TEMP1 exceptiondata", &[[0x02]]);
    o.result.unwrap();
    assert_eq!(o.port.frames_hex(), ["05 04 05 02 0b"]);
    assert_eq!(
        o.out,
        "{\"command\":\"readset\",\"device\":0,\"set\":5,\"ids\":[2,11],\
         \"registers\":[\"REGMASTER_TEMP1\",\"REGMASTER_EXCEPTIONDATA\"]}\n"
    );
}

#[test]
fn readset_checks_the_count_reply() {
    let o = hostctl(
        "readset --device 3 1 ONE_ACTUALPOS TWO_ACTUALPOS",
        &[[0x01]],
    );
    assert_eq!(o.port.frames_hex(), ["05 34 01 10 22"]);
    assert_eq!(
        o.result.unwrap_err().to_string(),
        "device 3 answered 1 to set-read-set 1, expected the count 2"
    );
}

// ---- watch ----

#[test]
fn watch_configures_then_polls_with_a_table() {
    let replies: [&[u8]; 3] = [
        &[0x03],
        &[0xd2, 0x04, 0xfe, 0x9f, 0x98, 0x99],
        &[0x36, 0x05, 0xff, 0x7f, 0x65, 0x66],
    ];
    let o = hostctl(
        "watch --readset 0 --device 1 --count 2 --interval-ms 0 TIMER DRIVE_ACTUALSPEED 33",
        &replies,
    );
    o.result.unwrap();
    assert_eq!(
        o.port.frames_hex(),
        ["06 14 00 01 10 21", "03 13 00", "03 13 00"]
    );
    // The steer angle is on the board's boot calibration: marked, with the legend.
    let legend = "* not degrees: opening the port rebooted the rover, so the boards are on \
                  their boot calibration (pot 0..1023 as -512..512)";
    assert_eq!(
        o.out,
        format!(
            "read set 0, round 1\n\
             dev  TIMER  DRIVE_ACTUALSPEED  STEER_ACTUALPOS\n\
             \x20       ms            ticks/s             deg*\n\
             1     1234            999.908           39.998\n\
             {legend}\n\
             \n\
             read set 0, round 2\n\
             dev  TIMER  DRIVE_ACTUALSPEED  STEER_ACTUALPOS\n\
             \x20       ms            ticks/s             deg*\n\
             1     1334              0.000          -40.004\n\
             {legend}\n"
        )
    );
}

#[test]
fn watch_table_redraws_in_place_on_a_terminal() {
    // Set 3, then REGMASTER_TEMPSREAD in set 7; each round reads both: the ambient sensor
    // read in round 1, a sensor not read since boot (0.0 °C, raw 0x2aaa) in round 2.
    let replies: [&[u8]; 6] = [
        &[0x01],
        &[0x01],
        &[0x87, 0x58],
        &[0x01, 0x00],
        &[0xaa, 0x2a],
        &[0x00, 0x00],
    ];
    let o = hostctl_with(
        "watch --readset 3 --count 2 --interval-ms 0 TEMPAMBIENT",
        &replies,
        Some("/dev/fake".into()),
        true,
    );
    o.result.unwrap();
    assert_eq!(
        o.port.frames_hex(),
        [
            "04 04 03 01",
            "04 04 07 0e",
            "03 03 03",
            "03 03 07",
            "03 03 03",
            "03 03 07"
        ]
    );
    assert_eq!(
        o.out,
        "read set 3, round 1\x1b[K\n\
         dev  TEMPAMBIENT\x1b[K\n\
         \x20           degC\x1b[K\n\
         0         21.498\x1b[K\n\
         \x1b[J\
         \x1b[4A\r\
         read set 3, round 2\x1b[K\n\
         dev  TEMPAMBIENT\x1b[K\n\
         \x20           degC\x1b[K\n\
         0              -\x1b[K\n\
         - no reading: not read yet: the master reads one sensor every 2 s from 5 s after \
         boot, and opening the port rebooted it; or the sensor is missing, or its last read failed\x1b[K\n\
         \x1b[J"
    );
}

#[test]
fn watch_standard_set_0_polls_every_ds_board() {
    let mut replies: Vec<Vec<u8>> = vec![vec![0x14]];
    replies.extend((0..6).map(|_| vec![0u8; 40]));
    let o = hostctl("watch --readset 0 --count 1", &replies);
    o.result.unwrap();
    assert_eq!(
        o.port.frames_hex(),
        [
            "17 14 00 01 02 03 05 2c 10 11 12 13 14 15 16 17 21 22 23 24 25 26 27",
            "03 13 00",
            "03 23 00",
            "03 43 00",
            "03 53 00",
            "03 73 00",
            "03 83 00",
        ]
    );
    let lines: Vec<&str> = o.out.lines().collect();
    // Title, two header lines, six boards, the coded values in words (STATUS 0 on all six;
    // EXCEPTIONDATA 0, whose motor 0 is another wheel's drive on each) and the
    // boot-calibration legend.
    assert_eq!(lines.len(), 3 + 6 + 7 + 1, "{}", o.out);
    assert_eq!(
        lines[9],
        "STATUS 0 = 0x0000 (dev 1, 2, 4, 5, 7, 8): no board kind, not in exception"
    );
    assert_eq!(
        lines[10],
        "EXCEPTIONDATA 0 = 0x0000 (dev 1): type 0, motor 0 (wheel 1's drive) (the last exception)"
    );
    assert_eq!(
        lines[15],
        "EXCEPTIONDATA 0 = 0x0000 (dev 8): type 0, motor 0 (wheel 6's drive) (the last exception)"
    );
    assert_eq!(lines[0], "read set 0, round 1");
    assert_eq!(
        lines[1],
        "dev  TIMER  INTERVALI2C  STATUS  EXCEPTIONDATA  CHASSIS  DRIVE_ACTUALSPEED  \
         DRIVE_ERROR  DRIVE_ERRORINTEGRAL  DRIVE_ERRORDERIV  DRIVE_CONTROL  DRIVE_INTERVALCTRL  \
         DRIVE_CURRENT  DRIVE_ODO  STEER_ACTUALPOS  STEER_ERROR  STEER_ERRORINTEGRAL  \
         STEER_ERRORDERIV  STEER_CONTROL  STEER_INTERVALCTRL  STEER_CURRENT"
    );
    assert_eq!(
        lines[2],
        "        ms           us    bits                     adc            ticks/s      \
         ticks/s                                ticks/s           duty                  ms         \
         counts  ticks/256             deg*         deg*                                   deg*           \
         duty                  ms         counts"
    );
    // All-zero replies: mapped registers read their minimum, unmapped ones 0; a
    // read-only register's minimum below 0 stands for it or less (≤).
    assert_eq!(
        lines[3],
        "1        0            0       0              0    0.000         ≤-4000.000   \
         ≤-1000.000           ≤-1000.000         ≤-200.000       -255.000               0.000              \
         0          0        ≤-200.000    ≤-200.000           ≤-1000.000         ≤-200.000       \
         -255.000               0.000              0"
    );
    assert_eq!(lines[8], lines[3].replacen('1', "8", 1));
}

#[test]
fn watch_polls_a_set_of_its_own_on_several_boards() {
    // Every DS board's drive duty side by side: set 3 configured once (via device 1), then
    // read from each board in turn.
    let mut replies: Vec<Vec<u8>> = vec![vec![0x01]];
    replies.extend((0..6u8).map(|d| vec![0x80 + d, 0x00]));
    let o = hostctl(
        "watch --readset 3 --device DS drive_control --count 1",
        &replies,
    );
    o.result.unwrap();
    assert_eq!(
        o.port.frames_hex(),
        [
            "04 14 03 14",
            "03 13 03",
            "03 23 03",
            "03 43 03",
            "03 53 03",
            "03 73 03",
            "03 83 03"
        ]
    );
    let rows: Vec<&str> = o
        .out
        .lines()
        .skip(3)
        .map(|l| l.split_whitespace().next().unwrap_or(""))
        .collect();
    assert_eq!(rows, ["1", "2", "4", "5", "7", "8"]);
    // EXCEPTIONDATA beside STATUS bit 0 is the exception the board is in now, named by
    // its wheel; the legend follows the columns.
    let o = hostctl(
        "watch --readset 3 --device 4 exceptiondata status --count 1",
        &[&[0x02][..], &[0x08, 0x01, 0x09, 0x00]],
    );
    o.result.unwrap();
    let legend: Vec<&str> = o.out.lines().skip(4).collect();
    assert_eq!(
        legend,
        [
            "EXCEPTIONDATA 264 = 0x0108: short (overcurrent at a duty of 250 or less: a short, or a blocked motor), motor 1 (wheel 3's steer)",
            "STATUS 9 = 0x0009: DS board, in exception (its motors are stopped)"
        ]
    );
    // A list, in the order given, each device once.
    let o = hostctl(
        "watch --readset 3 --device 7,1,7 status --count 1",
        &[&[0x01][..], &[0x08, 0], &[0x09, 0]],
    );
    o.result.unwrap();
    assert_eq!(o.port.frames_hex(), ["04 74 03 03", "03 73 03", "03 13 03"]);
    assert!(
        o.out
            .contains("STATUS 8 = 0x0008 (dev 7): DS board, not in exception"),
        "{}",
        o.out
    );
    // The same name is another id on the master: refused before anything is sent.
    let o = hostctl(
        "watch --readset 3 --device 0,1 exceptiondata --count 1",
        &[] as &[&[u8]],
    );
    assert_eq!(
        o.result.unwrap_err().to_string(),
        "the set reads REGMASTER_EXCEPTIONDATA (11) on device 0 (MASTER) but \
         REG_EXCEPTIONDATA (5) on device 1 (DS); a read set holds ids, which each device \
         reads on its own table, so watch boards of one kind together (the master apart)"
    );
    assert!(o.port.frames_hex().is_empty());
    // The same ids that are other registers on a lift board: refused too.
    let o = hostctl(
        "watch --readset 3 --device 1,3 9 22 --count 1",
        &[] as &[&[u8]],
    );
    let err = o.result.unwrap_err().to_string();
    assert!(
        err.starts_with("the set reads REGDS_DRIVE_REQSPEED (9), REGDS_DRIVE_CURRENT (22) on device 1 (DS) but REGLL_ONE_"),
        "{err}"
    );
    // Registers common to both kinds are the same on each: polled together.
    let o = hostctl(
        "watch --readset 3 --device 1,3 status --count 1",
        &[&[0x01][..], &[0x08, 0], &[0x05, 0]],
    );
    o.result.unwrap();
    assert_eq!(o.port.frames_hex(), ["04 14 03 03", "03 13 03", "03 33 03"]);
    // A kind's standard set on the other kind's boards is refused as before.
    let o = hostctl(
        "watch --readset 0 --device ds,ll --count 1",
        &[] as &[&[u8]],
    );
    assert!(o
        .result
        .unwrap_err()
        .to_string()
        .starts_with("read set 0's standard contents are for DS boards, but device 3 is LL"),);
}

#[test]
fn watch_standard_sets_1_and_2_match_the_library() {
    let mut replies: Vec<Vec<u8>> = vec![vec![0x12]];
    replies.extend((0..3).map(|_| vec![0u8; 36]));
    let o = hostctl("watch --readset 1 --count 1", &replies);
    o.result.unwrap();
    assert_eq!(
        o.port.frames_hex(),
        [
            "15 34 01 01 02 03 05 10 11 12 13 14 15 16 22 23 24 25 26 27 28",
            "03 33 01",
            "03 63 01",
            "03 93 01",
        ]
    );

    let mut reply = vec![0u8; 22];
    reply[0] = 0x87;
    reply[1] = 0x58;
    reply[20] = 0x01;
    reply[21] = 0x14;
    // The library's set 2 unchanged, then REGMASTER_TEMPSREAD through set 7: only the
    // ambient sensor has been read.
    let replies = [vec![0x0b], vec![0x01], reply.clone(), vec![0x01, 0x00]];
    let o = hostctl("--json watch --readset 2 --count 1", &replies);
    o.result.unwrap();
    assert_eq!(
        o.port.frames_hex(),
        [
            "0e 04 02 01 02 03 04 05 06 07 08 09 0a 0b",
            "04 04 07 0e",
            "03 03 02",
            "03 03 07"
        ]
    );
    let line = o.out.lines().next().unwrap();
    assert!(line.starts_with(
        "{\"command\":\"watch\",\"round\":1,\"set\":2,\"device\":0,\"board\":\"MASTER\",\"values\":[\
         {\"id\":1,\"register\":\"REGMASTER_TEMPAMBIENT\",\"raw\":22663,\"value\":21.498459,\"unit\":\"degC\",\"read\":true},\
         {\"id\":2,\"register\":\"REGMASTER_TEMP1\",\"raw\":0,\"value\":null,\"unit\":\"degC\",\"read\":false},"
    ), "{line}");
    assert!(line.ends_with(
        "{\"id\":11,\"register\":\"REGMASTER_EXCEPTIONDATA\",\"raw\":5121,\"value\":5121,\"unit\":\"\",\
         \"exception\":{\"type\":1,\"name\":\"OVERCURRENT\",\"controller\":4,\"motor\":1,\
         \"wheel\":3,\"wheel_motor\":\"steer\",\
         \"text\":\"overcurrent on controller 4, motor 1 (wheel 3's steer)\"}}]}"
    ), "{line}");
    assert_eq!(o.out.lines().count(), 1);

    // As a table: every sensor but the ambient one unread, shown as "-" with the legend.
    let o = hostctl("watch --readset 2 --count 1", &replies);
    o.result.unwrap();
    assert_eq!(
        o.out,
        "read set 2, round 1\n\
         dev  TEMPAMBIENT  TEMP1  TEMP2  TEMP3  TEMP4  TEMP5  TEMP6  TEMP7  TEMP8  TEMP9  \
         EXCEPTIONDATA\n\
         \x20           degC   degC   degC   degC   degC   degC   degC   degC   degC   degC\n\
         0         21.498      -      -      -      -      -      -      -      -      -  \
         \x20        5121\n\
         EXCEPTIONDATA 5121 = 0x1401: overcurrent on controller 4, motor 1 (wheel 3's steer)\n\
         - no reading: not read yet: the master reads one sensor every 2 s from 5 s after \
         boot, and opening the port rebooted it; or the sensor is missing, or its last read failed\n"
    );
}

#[test]
fn watch_of_set_7_reads_the_sensors_read_through_set_6() {
    let replies: [&[u8]; 4] = [&[0x01], &[0x01], &[0x87, 0x58], &[0x03, 0x00]];
    let o = hostctl("watch --readset 7 --count 1 TEMP1", &replies);
    o.result.unwrap();
    assert_eq!(
        o.port.frames_hex(),
        ["04 04 07 02", "04 04 06 0e", "03 03 07", "03 03 06"]
    );
    assert_eq!(
        o.out,
        "read set 7, round 1\n\
         dev   TEMP1\n\
         \x20      degC\n\
         0    21.498\n"
    );
}

#[test]
fn watch_json_gives_one_line_per_device_per_round() {
    let replies: [&[u8]; 7] = [
        &[0x01],
        &[0x01, 0x00],
        &[0x02, 0x00],
        &[0x03, 0x00],
        &[0x04, 0x00],
        &[0x05, 0x00],
        &[0x06, 0x00],
    ];
    let o = hostctl(
        "--json watch --readset 1 --count 2 --interval-ms 0 TIMER",
        &replies,
    );
    o.result.unwrap();
    assert_eq!(
        o.out,
        "{\"command\":\"watch\",\"round\":1,\"set\":1,\"device\":3,\"board\":\"LL\",\"values\":[{\"id\":1,\"register\":\"REG_TIMER\",\"raw\":1,\"value\":1,\"unit\":\"ms\"}]}\n\
         {\"command\":\"watch\",\"round\":1,\"set\":1,\"device\":6,\"board\":\"LL\",\"values\":[{\"id\":1,\"register\":\"REG_TIMER\",\"raw\":2,\"value\":2,\"unit\":\"ms\"}]}\n\
         {\"command\":\"watch\",\"round\":1,\"set\":1,\"device\":9,\"board\":\"LL\",\"values\":[{\"id\":1,\"register\":\"REG_TIMER\",\"raw\":3,\"value\":3,\"unit\":\"ms\"}]}\n\
         {\"command\":\"watch\",\"round\":2,\"set\":1,\"device\":3,\"board\":\"LL\",\"values\":[{\"id\":1,\"register\":\"REG_TIMER\",\"raw\":4,\"value\":4,\"unit\":\"ms\"}]}\n\
         {\"command\":\"watch\",\"round\":2,\"set\":1,\"device\":6,\"board\":\"LL\",\"values\":[{\"id\":1,\"register\":\"REG_TIMER\",\"raw\":5,\"value\":5,\"unit\":\"ms\"}]}\n\
         {\"command\":\"watch\",\"round\":2,\"set\":1,\"device\":9,\"board\":\"LL\",\"values\":[{\"id\":1,\"register\":\"REG_TIMER\",\"raw\":6,\"value\":6,\"unit\":\"ms\"}]}\n"
    );
}

#[test]
fn a_watch_says_positions_and_calibration_ends_are_on_the_boot_calibration() {
    // Controller 1 alone: STEER_ACTUALPOS and STEER_CALIBMIN as a board fresh from boot
    // shows them (its calibration -512..512; the 1-byte end reads -120, raw 0).
    let replies: [&[u8]; 2] = [&[0x02], &[0x98, 0x99, 0x00]];
    let args = "watch --readset 4 --device 1 --count 1 --interval-ms 0 steer_actualpos \
                steer_calibmin";
    let o = hostctl(&format!("--json {args}"), &replies);
    o.result.unwrap();
    assert!(
        o.out
            .contains("\"value\":39.99756,\"unit\":\"deg\",\"boot_calibration\":true}"),
        "{}",
        o.out
    );
    assert!(
        o.out
            .contains("\"value\":-120,\"unit\":\"deg\",\"boot_calibration\":true}"),
        "{}",
        o.out
    );
    let o = hostctl(args, &replies);
    o.result.unwrap();
    assert!(
        o.out.contains("\n1             39.998       -120.000*\n"),
        "{}",
        o.out
    );
    assert!(
        o.out
            .contains("\n* a calibration end at its register's end"),
        "{}",
        o.out
    );
}

/// Two rounds of TIMER from set 1's controllers (3, 6, 9), as the replies below script them.
const WATCH_SET_1_TWICE: &str = "watch --readset 1 --count 2 --interval-ms 0 TIMER";

/// A watch of set 1 (controllers 3, 6, 9) up to the end of round 1, in which controller 6
/// does not answer (the master's last error NoAnswer, count 1).
const SIX_SILENT_IN_ROUND_1: [&[u8]; 6] = [
    &[0x01],
    &[0x01, 0x00],
    &[],
    &[0x02],
    &[0x0c, 0x01, 0x00],
    &[0x03, 0x00],
];

#[test]
fn watch_goes_on_past_a_controller_that_does_not_answer() {
    // Round 1: controller 6 is off the bus (no reply; the master's last link error is
    // code 12, NoAnswer); round 2: it answers again.
    let replies = [
        &SIX_SILENT_IN_ROUND_1[..],
        &[&[0x04, 0x00], &[0x05, 0x00], &[0x06, 0x00]],
    ]
    .concat();
    let args = WATCH_SET_1_TWICE;
    let o = hostctl(args, &replies);
    o.result.unwrap();
    assert_eq!(
        o.port.frames_hex(),
        [
            "04 34 01 01",
            "03 33 01",
            "03 63 01",
            PROBE[0],
            PROBE[1],
            "03 93 01",
            "03 33 01",
            "03 63 01",
            "03 93 01"
        ]
    );
    let legend = "no answer: controller 6 does not answer the master on the I2C bus (unplugged, \
                  unpowered or rebooting; from 5 s after its boot the master stops every motor \
                  when one it has heard drops off); read again every round, each after a 300 ms wait";
    assert!(
        o.out.contains(&format!(
            "read set 1, round 1\n\
             dev      TIMER\n\
             \x20           ms\n\
             3            1\n\
             6    no answer\n\
             9            3\n\
             {legend}\n"
        )),
        "{}",
        o.out
    );
    assert!(o.out.contains("\n6        5\n"), "{}", o.out);
    assert_eq!(o.out.matches(legend).count(), 1, "round 2 has no legend");
    let o = hostctl(&format!("--json {args}"), &replies);
    o.result.unwrap();
    let lines: Vec<&str> = o.out.lines().collect();
    assert_eq!(
        lines[1],
        "{\"command\":\"watch\",\"round\":1,\"set\":1,\"device\":6,\"board\":\"LL\",\"values\":null,\"no_answer\":true}"
    );
    assert_eq!(lines.len(), 6);
}

#[test]
fn a_watch_shows_no_answer_only_for_a_new_noanswer_error() {
    // Round 1: controller 6 off the bus (NoAnswer, count 1). Round 2: controller 3's reply
    // is lost on the serial line; the master's last error is still that NoAnswer, count 1:
    // an old error, so this is a reply lost, not "no answer", and the watch goes on.
    let replies = [
        &SIX_SILENT_IN_ROUND_1[..],
        &[
            &[],
            &[0x02],
            &[0x0c, 0x01, 0x00],
            &[0x05, 0x00],
            &[0x06, 0x00],
        ],
    ]
    .concat();
    let o = hostctl(WATCH_SET_1_TWICE, &replies);
    // The watch ends without controller 3's values: status 3, naming it.
    assert!(
        matches!(&o.result, Err(HostError::WatchEndedUnread { devices }) if devices == &[3]),
        "{:?}",
        o.result
    );
    let (round1, round2) = o.out.split_once("round 2").expect("a second round");
    assert!(round1.contains("\n6    no answer\n"), "{}", o.out);
    let round2 = collapse(round2);
    assert!(round2.contains("\n3 reply lost\n6 5\n9 6\n"), "{round2}");
    assert!(!round2.contains("no answer"), "{}", o.out);
    // A new error of another kind (the request arrived truncated, code 8) is no "no answer".
    let replies: [&[u8]; 6] = [
        &[0x01],
        &[],
        &[0x02],
        &[0x08, 0x01, 0x00],
        &[0x05, 0x00],
        &[0x06, 0x00],
    ];
    let o = hostctl(
        "watch --readset 1 --count 1 --interval-ms 0 TIMER",
        &replies,
    );
    assert!(
        matches!(&o.result, Err(HostError::WatchEndedUnread { devices }) if devices == &[3]),
        "{:?}",
        o.result
    );
    assert!(o.out.contains("\n3    reply lost\n"), "{}", o.out);
    assert!(
        o.out.ends_with(
            "reply lost: the serial line lost or garbled the read of device 3 this round, the \
             request on its way to the master or the reply on its way back (the master still \
             answers); read again next round; the view stops if one read loses 4 in \
             a row\n"
        ),
        "{}",
        o.out
    );
    let o = hostctl(
        "--json watch --readset 1 --count 1 --interval-ms 0 TIMER",
        &replies,
    );
    assert!(o.result.is_err());
    assert_eq!(
        o.out.lines().next(),
        Some("{\"command\":\"watch\",\"round\":1,\"set\":1,\"device\":3,\"board\":\"LL\",\"values\":null,\"reply_lost\":true}")
    );
    // The JSON ends with the error, which names the device.
    let last = o.out.lines().last().unwrap_or_default();
    assert!(
        last.starts_with(
            "{\"command\":\"watch\",\"error\":\"the watch ended without the values of device(s) 3:"
        ),
        "{last}"
    );
    assert_eq!(
        crate::exit_status(&HostError::WatchEndedUnread { devices: vec![3] }),
        std::process::ExitCode::from(3)
    );
}

/// `text` with each line's runs of blanks made one space (table columns whatever their width).
fn collapse(text: &str) -> String {
    text.lines()
        .map(|l| l.split_whitespace().collect::<Vec<_>>().join(" "))
        .collect::<Vec<_>>()
        .join("\n")
        + "\n"
}

/// One read of controller 3's TIMER whose reply the line loses: no reply, then the probe
/// (the master answers: its last error a truncated frame, error count `count`).
fn lost_read(count: u8) -> [&'static [u8]; 3] {
    const COUNTS: [[u8; 3]; 8] = [
        [8, 1, 0],
        [8, 2, 0],
        [8, 3, 0],
        [8, 4, 0],
        [8, 5, 0],
        [8, 6, 0],
        [8, 7, 0],
        [8, 8, 0],
    ];
    [&[], &[0x02], &COUNTS[usize::from(count - 1)]]
}

#[test]
fn a_watch_stops_when_the_line_loses_four_replies_in_a_row() {
    let args = "watch --readset 1 --device 3 --count 8 --interval-ms 0 TIMER";
    // Three lost, one whole, three lost: each run of losses is forgiven.
    let mut replies: Vec<&[u8]> = vec![&[0x01]];
    (1..=3).for_each(|n| replies.extend(lost_read(n)));
    replies.push(&[0x2a, 0x00]);
    (4..=6).for_each(|n| replies.extend(lost_read(n)));
    replies.push(&[0x2b, 0x00]);
    let o = hostctl(args, &replies);
    o.result.unwrap();
    let out = collapse(&o.out);
    assert_eq!(out.matches("\n3 reply lost\n").count(), 6, "{out}");
    assert!(out.contains("round 4\ndev TIMER\nms\n3 42\n"), "{out}");
    assert!(out.contains("round 8\ndev TIMER\nms\n3 43\n"), "{out}");
    // Four in a row: the fourth is the error, with the master's words; three rounds shown.
    let mut replies: Vec<&[u8]> = vec![&[0x01]];
    (1..=4).for_each(|n| replies.extend(lost_read(n)));
    let o = hostctl(args, &replies);
    assert!(
        matches!(o.result, Err(HostError::Timeout { device: 3, .. })),
        "{:?}",
        o.result
    );
    assert!(o.out.contains("round 3"), "{}", o.out);
    assert!(!o.out.contains("round 4"), "{}", o.out);
}

#[test]
fn a_master_watch_stops_at_four_lost_replies_though_it_configures_the_scratch_set_between() {
    // Set 2 (the master's), with TEMPSREAD beside it in set 7, which every probe overwrites
    // and the watch configures again: those configures do not count as replies come whole.
    let mut replies: Vec<&[u8]> = vec![&[0x0b], &[0x01]];
    for _ in 0..4 {
        // Set 2's reply lost (the probe: no error since boot), set 7 configured again,
        // TEMPSREAD read.
        replies.extend([
            &[][..],
            &[0x02],
            &[0x00, 0x00, 0x00],
            &[0x01],
            &[0xff, 0x03],
        ]);
    }
    let o = hostctl("watch --readset 2 --count 8 --interval-ms 0", &replies);
    assert!(
        matches!(o.result, Err(HostError::Timeout { device: 0, .. })),
        "{:?}",
        o.result
    );
    let out = collapse(&o.out);
    assert_eq!(out.matches("\n0 reply lost\n").count(), 3, "{out}");
    assert!(!out.contains("round 4"), "{out}");
}

#[test]
fn a_master_that_says_its_set_is_empty_has_rebooted_and_is_not_a_lost_reply() {
    // Set 2's read stops short; the probe finds the last error EmptyReadSet (11): the
    // master rebooted since the set was configured.
    let replies: [&[u8]; 5] = [&[0x0b], &[0x01], &[0x8b], &[0x02], &[0x0b, 0x01, 0x00]];
    let o = hostctl("watch --readset 2 --count 2 --interval-ms 0", &replies);
    let err = o.result.expect_err("no view of a rebooted master");
    assert!(
        err.to_string()
            .contains("it has rebooted since the set was configured"),
        "{err}"
    );
    assert!(!o.out.contains("reply lost"), "{}", o.out);
}

#[test]
fn a_reply_with_bytes_after_it_is_lost_and_the_next_round_reads_again() {
    let replies: [&[u8]; 3] = [&[0x01], &[0x2a, 0x00, 0x55], &[0x2b, 0x00]];
    let o = hostctl(
        "watch --readset 1 --device 3 --count 2 --interval-ms 0 TIMER",
        &replies,
    );
    o.result.unwrap();
    let out = collapse(&o.out);
    assert!(
        out.contains("round 1\ndev TIMER\nms\n3 reply lost\n"),
        "{out}"
    );
    assert!(out.contains("round 2\ndev TIMER\nms\n3 43\n"), "{out}");
}

#[test]
fn a_controller_that_did_not_answer_is_read_again_with_the_short_wait() {
    use crate::link::{PROBE_TIMEOUT, REPLY_TIMEOUT, SILENT_REREAD_TIMEOUT};
    // Controller 6 is off the bus in rounds 1 and 2 (NoAnswer, counts 1 and 2) and back
    // in round 3.
    let replies = [
        &SIX_SILENT_IN_ROUND_1[..],
        &[
            &[0x04, 0x00],
            &[],
            &[0x02],
            &[0x0c, 0x02, 0x00],
            &[0x05, 0x00],
            &[0x06, 0x00],
            &[0x07, 0x00],
            &[0x08, 0x00],
            &[0x09, 0x00],
            &[0x0a, 0x00],
            &[0x0b, 0x00],
        ],
    ]
    .concat();
    let o = hostctl(
        "watch --readset 1 --count 4 --interval-ms 0 TIMER",
        &replies,
    );
    o.result.unwrap();
    let (r, s, p) = (REPLY_TIMEOUT, SILENT_REREAD_TIMEOUT, PROBE_TIMEOUT);
    assert!(s < r);
    assert_eq!(
        o.port.reply_timeouts,
        [
            r, // configure
            r, r, p, p, r, // round 1: 6 is found silent after the full wait
            r, s, p, p, r, // round 2: the short wait for 6, still silent
            r, s, r, // round 3: the short wait, and 6 answers
            r, r, r // round 4: 6 answered last time
        ]
    );
    assert_eq!(o.port.frames.len(), 17);
    assert_eq!(o.out.matches("\n6    no answer\n").count(), 2, "{}", o.out);
    assert!(o.out.contains("\n6        7\n"), "{}", o.out);
    assert!(o.out.contains("\n6       10\n"), "{}", o.out);
}

#[test]
fn a_short_wait_that_fails_otherwise_is_read_again_with_the_full_wait() {
    use crate::link::{PROBE_TIMEOUT, REPLY_TIMEOUT, SILENT_REREAD_TIMEOUT};
    // Round 1: controller 6 off the bus (NoAnswer, count 1). Round 2: its reply does not
    // come within the short wait, but the master records no new error (count still 1):
    // the reply may just be slow, so 6 is read again with the full wait, and answers.
    let replies = [
        &SIX_SILENT_IN_ROUND_1[..],
        &[
            &[0x04, 0x00],
            &[],
            &[0x02],
            &[0x0c, 0x01, 0x00],
            &[0x05, 0x00],
            &[0x06, 0x00],
        ],
    ]
    .concat();
    let o = hostctl(WATCH_SET_1_TWICE, &replies);
    o.result.unwrap();
    let (r, s, p) = (REPLY_TIMEOUT, SILENT_REREAD_TIMEOUT, PROBE_TIMEOUT);
    assert_eq!(o.port.reply_timeouts, [r, r, r, p, p, r, r, s, p, p, r, r]);
    assert_eq!(o.port.frames_hex()[10], "03 63 01");
    assert!(o.out.contains("\n6        5\n"), "{}", o.out);
    assert_eq!(o.out.matches("no answer\n").count(), 1, "{}", o.out);
}

#[test]
fn a_watch_of_the_scratch_set_configures_it_again_after_a_silent_controller() {
    // The master's answer about the silent controller went through set 7, the watched one.
    let replies: [&[u8]; 6] = [
        &[0x01],
        &[],
        &[0x02],
        &[0x0c, 0x01, 0x00],
        &[0x01],
        &[0x09, 0x00],
    ];
    let o = hostctl(
        "watch --readset 7 --device 4 --count 2 --interval-ms 0 TIMER",
        &replies,
    );
    o.result.unwrap();
    assert_eq!(
        o.port.frames_hex(),
        [
            "04 44 07 01",
            "03 43 07",
            PROBE[0],
            PROBE[1],
            "04 44 07 01",
            "03 43 07"
        ]
    );
    assert!(o.out.contains("\n4    no answer\n"), "{}", o.out);
    assert!(o.out.contains("\n4        9\n"), "{}", o.out);
}

#[test]
fn watch_stops_at_the_first_failed_read() {
    let replies: [&[u8]; 2] = [&[0x01], &[0x01]];
    let o = hostctl("watch --readset 4 --device 5 --count 3 TIMER", &replies);
    assert_eq!(o.port.frames_hex(), ["04 54 04 01", "03 53 04", PROBE[0]]);
    assert!(matches!(
        o.result,
        Err(HostError::Timeout {
            device: 5,
            expected: 2,
            got: 1,
            master: MasterSays::Silent,
            ..
        })
    ));
    assert!(o.out.is_empty());
}

#[test]
fn watch_stops_when_the_master_reboots_and_shows_no_banner_bytes_as_values() {
    // Round 1 reads TIMER; then the master reboots and its banner arrives in place of
    // round 2's reply: no value from it is printed.
    let replies: [&[u8]; 3] = [&[0x01], &[0x07, 0x00], b"Starting\r\nMar 29 2017"];
    let o = hostctl("watch --readset 4 --device 5 --count 3 TIMER", &replies);
    assert_eq!(o.port.frames_hex(), ["04 54 04 01", "03 53 04", "03 53 04"]);
    assert!(matches!(o.result, Err(HostError::MasterRebooted)));
    assert!(o.out.contains("round 1"), "{}", o.out);
    assert!(!o.out.contains("round 2"), "{}", o.out);
}

// ---- run ----

#[test]
fn run_with_json_prints_json_lines() {
    let path = std::env::temp_dir().join(format!("hostctl-json-{}.rover", std::process::id()));
    std::fs::write(&path, "say Wheel one ready\n").unwrap();
    // init(): read sets 0, 1, 2 via controllers 1..9, then the master (the library's
    // eleven registers and REGMASTER_TEMPSREAD).
    let replies: Vec<Vec<u8>> = (1..=9u8)
        .map(|d| vec![if d % 3 == 0 { 18 } else { 20 }])
        .chain([vec![12]])
        .collect();
    let o = hostctl(&format!("--json run {}", path.display()), &replies);
    std::fs::remove_file(&path).unwrap();
    o.result.unwrap();
    assert_eq!(
        o.out,
        format!(
            "{{\"command\":\"run\",\"script\":\"{}\",\"lines\":1}}\n\
             {{\"command\":\"run\",\"line\":1,\"say\":\"Wheel one ready\"}}\n",
            path.display()
        )
    );
}

#[test]
fn with_json_a_command_line_clap_refuses_is_a_json_line_too() {
    use clap::Parser;
    let refused = |args: &str| {
        let argv: Vec<&str> = std::iter::once("hostctl")
            .chain(args.split_whitespace())
            .collect();
        let e = Cli::try_parse_from(&argv).unwrap_err();
        crate::usage_error_json(&e, argv)
    };
    // A missing argument and a value beyond its limit, with --json before or after.
    let line = refused("--json read 1").expect("a JSON line");
    assert_eq!(
        line,
        "{\"command\":\"read\",\"error\":\"the following required arguments were not provided: \
         <REGISTER>\"}",
        "names what is missing, without the usage"
    );
    let line = refused("--settle-ms 70000 read 1 status --json").expect("a JSON line");
    assert!(line.contains("\"error\":\"invalid value '70000'"), "{line}");
    let line = refused("--json frobnicate").expect("a JSON line");
    assert!(
        line.starts_with("{\"command\":\"\",\"error\":\"unrecognized subcommand"),
        "{line}"
    );
    // Without --json, and for help, clap's own text and status stay.
    assert_eq!(refused("read 1"), None);
    assert_eq!(refused("--json --help"), None);
    assert_eq!(refused("--json read --help"), None);
}

#[test]
fn with_json_a_failure_is_a_json_line_too() {
    // Refused input: nothing sent, the error as JSON on stdout (and as the result).
    let o = hostctl::<&[u8]>("--json write 1 DRIVE_REQSPEED 5000", &[]);
    assert!(!o.opened);
    let e = o.result.unwrap_err().to_string();
    assert!(e.starts_with("5000 is out of range"), "{e}");
    assert_eq!(
        o.out,
        format!(
            "{{\"command\":\"write\",\"error\":{}}}\n",
            crate::json::string(&e)
        )
    );
    // A script line the master refuses: its number and text too, after the lines printed.
    let path = std::env::temp_dir().join(format!("hostctl-jerr-{}.rover", std::process::id()));
    std::fs::write(&path, "say Go\nwrite 1 DRIVE_REQSPEED 10\n").unwrap();
    let mut replies: Vec<Vec<u8>> = (1..=9u8)
        .map(|d| vec![if d % 3 == 0 { 18 } else { 20 }])
        .chain([vec![12]])
        .collect();
    replies.push(vec![0x8c]);
    // (A settle of 5 s: the first write does not wait for the master's watch.)
    let o = hostctl(
        &format!("--json --settle-ms 5000 run {}", path.display()),
        &replies,
    );
    std::fs::remove_file(&path).unwrap();
    let e = o.result.unwrap_err().to_string();
    assert!(
        e.contains("line 2 (`write 1 DRIVE_REQSPEED 10`) failed: device 1 refused"),
        "{e}"
    );
    let last = o.out.lines().last().unwrap_or_default();
    assert_eq!(
        last,
        format!(
            "{{\"command\":\"run\",\"error\":{},\"line\":2,\"text\":\"write 1 DRIVE_REQSPEED 10\"}}",
            crate::json::string(&e)
        )
    );
    assert_eq!(
        o.out.lines().count(),
        4,
        "start, say, echo, error: {}",
        o.out
    );
    // A line refused while the script is checked: nothing sent, its line and text too.
    let path = std::env::temp_dir().join(format!("hostctl-jbad-{}.rover", std::process::id()));
    std::fs::write(&path, "say Go\ndrive 7 10\n").unwrap();
    let o = hostctl::<&[u8]>(&format!("--json run {}", path.display()), &[]);
    std::fs::remove_file(&path).unwrap();
    assert!(!o.opened);
    let e = o.result.unwrap_err().to_string();
    assert_eq!(
        o.out,
        format!(
            "{{\"command\":\"run\",\"error\":{},\"line\":2,\"text\":\"drive 7 10\"}}\n",
            crate::json::string(&e)
        )
    );
}

// ---- bad input: refused before the port is opened ----

#[test]
fn a_bad_pairs_list_is_refused() {
    assert!(refused("run --pairs 3 missing.rover")
        .starts_with("`--pairs 3` is not a list of wheel pairs: give one or more of 0, 1, 2"));
}

#[test]
fn bad_devices_are_refused() {
    assert_eq!(
        refused("write 10 RESET 1"),
        "device `10` does not exist: use 0 for the master or 1..9 for a controller \
         (DS: 1, 2, 4, 5, 7, 8; LL: 3, 6, 9)"
    );
    refused("read 255 TIMER");
    // A negative number is a device that does not exist, not an unknown flag.
    assert!(refused("read -1 TIMER").starts_with("device `-1` does not exist"));
    assert!(refused("readset --device -3 0 TIMER").starts_with("device `-3` does not exist"));
    assert!(refused("watch --readset 0 --device -2").starts_with("device `-2` does not exist"));
    refused("readset --device 12 0 TIMER");
    refused("watch --readset 0 --device 99");
}

#[test]
fn unknown_and_misplaced_registers_are_refused() {
    assert_eq!(
        refused("write 1 DRIVE_REQSPED 10"),
        "device 1 (DS table) has no register named `DRIVE_REQSPED`; \
         did you mean REGDS_DRIVE_REQSPEED?"
    );
    assert!(refused("write 1 REGLL_ONE_REQPOS 20").contains("address one of devices 3, 6, 9"));
    assert!(refused("read 0 45").contains("no register 45"));
    assert!(refused("read 3 47").contains("no register 47"));
    assert_eq!(
        refused("readset 3 timer"),
        "register `timer` is on the DS and LL tables, not on device 0 (MASTER); \
         address one of devices 1, 2, 3, 4, 5, 6, 7, 8, 9 instead (readset and watch: --device)"
    );
    assert!(refused("watch --readset 2 --device 3 DRIVE_ACTUALSPEED").contains("not on device 3"));
    assert!(refused("watch --readset 0 REGLL_ONE_ACTUALPOS").contains("not on device 1"));
    // A name with a multi-byte character where the `REG` prefix would be is no register
    // either (it once panicked looking for the prefix).
    for name in ["ñññ", "ab€", "re€_x", "ток"] {
        let message = refused(&format!("read 1 {name}"));
        assert!(
            message.contains(&format!("no register named `{name}`")),
            "{message}"
        );
    }
}

#[test]
fn out_of_range_values_are_refused() {
    assert_eq!(
        refused("write 1 DRIVE_REQSPEED 5000"),
        "5000 is out of range for REGDS_DRIVE_REQSPEED on device 1: allowed -4000..4000 ticks/s"
    );
    assert_eq!(
        refused("write 6 TWO_CALIBMIN -121"),
        "-121 is out of range for REGLL_TWO_CALIBMIN on device 6: allowed -120..120 deg"
    );
    assert!(refused("write 1 DRIVE_REQSPEED fast").starts_with("`fast` is not a number"));
    assert!(refused("write 0 RESET 256").contains("allowed 0..255"));
}

#[test]
fn fractions_for_whole_number_registers_are_refused() {
    assert_eq!(
        refused("write 1 reset 1.5"),
        "1.5 is not a whole number, but REG_RESET on device 1 holds whole numbers 0..255 bits; \
         give one, e.g. 1"
    );
    assert!(refused("write 1 drive_mode 0.5").starts_with("0.5 is not a whole number"));
}

#[test]
fn watch_count_0_is_refused_before_the_port_opens() {
    assert_eq!(
        refused("watch --readset 2 --count 0"),
        "`watch --count 0` would poll nothing; give --count 1 or more, \
         or leave --count out to poll until interrupted"
    );
}

/// `hostctl SUBCOMMAND --help` as printed.
fn long_help(subcommand: &str) -> String {
    use clap::CommandFactory;
    let mut cli = Cli::command();
    cli.find_subcommand_mut(subcommand)
        .unwrap()
        .render_long_help()
        .to_string()
}

#[test]
fn readset_help_says_the_set_ends_with_the_session() {
    let help = long_help("readset");
    assert!(
        help.contains(
            "The set is gone when this command ends: closing the port resets the master, which \
             empties every read set (reference §4.1), as every command's opening does, so a \
             later `hostctl watch --readset N` cannot use it."
        ),
        "{help}"
    );
}

#[test]
fn run_help_lists_every_script_command_on_a_line_of_its_own() {
    use clap::CommandFactory;
    let help = long_help("run");
    // The script parser's own usage list, command by command.
    let usages: Vec<&str> = crate::cmd::script::COMMANDS.split(" | ").collect();
    assert_eq!(usages.len(), 14, "{usages:?}");
    for usage in usages {
        assert!(
            help.lines().any(|l| l.strip_prefix("  ").is_some_and(|l| {
                l.strip_prefix(usage)
                    .is_some_and(|rest| rest.starts_with("   "))
            })),
            "no line for `{usage}` in:\n{help}"
        );
    }
    // The list of commands shows a one-line summary, not the whole reference.
    let summary = Cli::command().render_help().to_string();
    let run = summary
        .lines()
        .find(|l| l.trim_start().starts_with("run "))
        .unwrap();
    assert!(run.len() < 100, "{run}");
}

#[test]
fn watch_interval_is_bounded_to_an_hour() {
    let parse =
        |ms: &str| Cli::try_parse_from(["hostctl", "watch", "--readset", "2", "--interval-ms", ms]);
    let interval = |cli: Cli| match cli.command {
        crate::cli::Command::Watch(args) => args.interval_ms,
        _ => panic!("not a watch"),
    };
    assert_eq!(parse("3600000").map(interval).ok(), Some(3_600_000));
    let err = parse("3600001").unwrap_err();
    assert_eq!(err.exit_code(), 2);
    assert!(
        err.to_string().contains("3600001 is not in 0..=3600000"),
        "{err}"
    );
}

#[test]
fn settle_ms_is_bounded_to_a_minute() {
    let parse = |ms: &str| Cli::try_parse_from(["hostctl", "--settle-ms", ms, "read", "0", "1"]);
    assert_eq!(parse("60000").unwrap().settle_ms, 60_000);
    assert_eq!(parse("0").unwrap().settle_ms, 0);
    let err = parse("18446744073709551615").unwrap_err();
    assert_eq!(err.exit_code(), 2);
    assert!(
        err.to_string().starts_with(
            "error: invalid value '18446744073709551615' for '--settle-ms <MS>': \
             18446744073709551615 is not in 0..=60000"
        ),
        "{err}"
    );
}

#[test]
fn read_only_registers_are_refused() {
    assert_eq!(
        refused("write 1 DRIVE_ACTUALSPEED 0"),
        "REGDS_DRIVE_ACTUALSPEED on device 1 is read-only; \
         use `hostctl read 1 REGDS_DRIVE_ACTUALSPEED` to see it"
    );
    assert!(refused("write 0 TEMP5 1").contains("read-only"));
}

#[test]
fn bad_sets_and_oversized_sets_are_refused() {
    assert_eq!(
        refused("readset 8 TIMER"),
        "read set `8` does not exist: sets are 0..7 (hostctl's one-off reads use set 7)"
    );
    assert!(refused("watch --readset 8").contains("read set `8`"));
    let many = vec!["TIMER"; 25].join(" ");
    assert_eq!(
        refused(&format!("readset --device 1 3 {many}")),
        "25 registers given, but a read set holds at most 24; split them over two sets"
    );
    assert!(refused(&format!("watch --readset 3 --device 1 {many}")).starts_with("25 registers"));
}

#[test]
fn watch_without_registers_needs_a_standard_set() {
    assert_eq!(
        refused("watch --readset 5"),
        "read set 5 has no standard contents (only sets 0, 1 and 2 do), and a set configured \
         by an earlier `hostctl readset` is gone (opening the port resets the master, which \
         empties every read set); name the registers to watch after the options, \
         e.g. `hostctl watch --readset 5 TEMPAMBIENT`"
    );
    assert_eq!(
        refused("watch --readset 1 --device 2"),
        "read set 1's standard contents are for LL boards, but device 2 is DS; \
         pick one of devices 3, 6, 9 or name the registers"
    );
}

#[test]
fn a_missing_port_is_reported_after_the_input_checks() {
    let o = hostctl_with::<&[u8]>("write 1 DRIVE_REQSPEED 0", &[], None, false);
    assert!(!o.opened);
    assert_eq!(
        o.result.unwrap_err().to_string(),
        "no serial port given: pass --port PATH (e.g. /dev/ttyACM0 or the twin's pty), \
         set BLODWEN_PORT, or start the twin"
    );
    // Bad input is still named first.
    let o = hostctl_with::<&[u8]>("write 11 DRIVE_REQSPEED 0", &[], None, false);
    assert!(matches!(o.result, Err(HostError::BadDevice { .. })));
}

#[test]
fn the_port_flag_wins_over_the_environment() {
    assert_eq!(
        crate::port_path(Some("/dev/a"), Some("/dev/b".into())).unwrap(),
        "/dev/a"
    );
    assert_eq!(
        crate::port_path(None, Some("/dev/b".into())).unwrap(),
        "/dev/b"
    );
    assert!(matches!(
        crate::port_path(None, Some(String::new())),
        Err(HostError::NoPort)
    ));
    // An empty --port is a mistake to name, not a cue to fall back on the twin.
    let empty = crate::port_path(Some(""), Some("/dev/b".into())).unwrap_err();
    assert_eq!(
        empty.to_string(),
        "--port is empty: give the serial device's path (e.g. /dev/ttyACM0 or the twin's pty), \
         or leave --port out to use BLODWEN_PORT or the twin"
    );
}

#[test]
fn ctrl_c_ends_a_watch_after_its_round_with_status_130() {
    // Rounds every 100 ms; Ctrl-C at 250 ms, in the wait after round 3.
    let mut replies: Vec<Vec<u8>> = vec![vec![0x01]];
    replies.extend((1..=5u8).map(|t| vec![t, 0x00]));
    for json in [false, true] {
        let args = format!(
            "{}watch --readset 1 --device 3 --interval-ms 100 TIMER",
            if json { "--json " } else { "" }
        );
        let cli = Cli::try_parse_from(std::iter::once("hostctl").chain(args.split_whitespace()));
        let cli = cli.unwrap();
        let plan = crate::plan(&cli.command).unwrap();
        let mut port = FakePort::with_replies(&replies);
        let mut link = Link::ready(&mut port);
        let mut out = Vec::new();
        let style = Style {
            json,
            in_place: false,
            width: || None,
        };
        let mut clock = crate::fake::CtrlCAt(
            crate::fake::FakeClock(std::time::Duration::ZERO, Vec::new()),
            std::time::Duration::from_millis(250),
        );
        let e =
            crate::execute_with_clock(&plan, &mut link, style, &mut out, &mut clock).unwrap_err();
        assert_eq!(crate::exit_code(&e), 130);
        assert_eq!(
            e.to_string(),
            "stopped by Ctrl-C after round 3; the last round above is the rover as it was \
             then; hostctl closes the port, which reboots the master and so stops every motor"
        );
        let out = String::from_utf8(out).unwrap();
        if json {
            assert_eq!(out.lines().count(), 3, "{out}");
            assert!(
                out.lines()
                    .last()
                    .unwrap()
                    .starts_with("{\"command\":\"watch\",\"round\":3,"),
                "{out}"
            );
            let last = crate::error_json(&cli.command, &e);
            assert!(last.contains(r#""interrupted":"Ctrl-C""#), "{last}");
        } else {
            assert!(out.contains("round 3\n"), "{out}");
            assert!(!out.contains("round 4"), "{out}");
        }
        assert_eq!(port.frames.len(), 1 + 3, "the set, then three rounds");
    }
}
