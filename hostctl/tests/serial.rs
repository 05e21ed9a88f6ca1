//! The real serial path over a pseudo-terminal: open, DTR pulse (which a
//! pty refuses), banner wait and one write, answered by a scripted master
//! on the other end of the pty.

use std::fs::File;
use std::io::{Read, Write};
use std::os::fd::OwnedFd;
use std::time::Duration;

use clap::Parser;
use hostctl::{link, run, Cli, Style};
use nix::pty::openpty;
use nix::sys::termios::{cfmakeraw, tcgetattr, tcsetattr, SetArg};
use nix::unistd::ttyname;

/// A pty whose device end is raw, with the master end as a file.
fn raw_pty() -> (File, OwnedFd, String) {
    let pty = openpty(None, None).unwrap();
    let mut attrs = tcgetattr(&pty.slave).unwrap();
    cfmakeraw(&mut attrs);
    tcsetattr(&pty.slave, SetArg::TCSANOW, &attrs).unwrap();
    let path = ttyname(&pty.slave).unwrap().to_string_lossy().into_owned();
    (File::from(pty.master), pty.slave, path)
}

#[test]
fn write_over_a_pty_after_the_banner() {
    let (mut master, _slave, path) = raw_pty();
    // Junk before the banner, as after a reset; CR LF line ends.
    master
        .write_all(b"\x00\xffnoise\r\nStarting\r\nMar 29 2017 14:03:11\r\n1520\r\nReady\r\n")
        .unwrap();
    let twin = std::thread::spawn(move || {
        let mut frame = [0u8; 6];
        master.read_exact(&mut frame).unwrap();
        master.write_all(&[0x00]).unwrap();
        // Then the controller's status, through the scratch set: in its boot exception.
        let mut set = [0u8; 4];
        master.read_exact(&mut set).unwrap();
        assert_eq!(set, [0x04, 0x34, 0x07, 0x03]);
        master.write_all(&[0x01]).unwrap();
        let mut read = [0u8; 3];
        master.read_exact(&mut read).unwrap();
        assert_eq!(read, [0x03, 0x33, 0x07]);
        master.write_all(&[0x01, 0x00]).unwrap();
        // Keep the master end open until the host has read the reply: a
        // hung-up pty fails the host's next read.
        (frame, master)
    });

    let cli = Cli::try_parse_from([
        "hostctl",
        "--port",
        &path,
        "write",
        "3",
        "REGLL_ONE_REQPOS",
        "20",
    ])
    .unwrap();
    let mut out = Vec::new();
    let style = Style {
        json: false,
        in_place: false,
        width: || None,
    };
    run(
        &cli,
        None,
        |p: &str| link::open_serial(p, Duration::ZERO),
        style,
        &mut out,
    )
    .unwrap();

    let (frame, _master) = twin.join().unwrap();
    assert_eq!(frame, [0x06, 0x32, 0x01, 0x09, 0xcb, 0x8c]);
    let out = String::from_utf8(out).unwrap();
    assert!(
        out.starts_with(
            "device 3 REGLL_ONE_REQPOS = 20 deg (raw 0x8ccb, arrives as 19.996 deg)\n\
             note: controller 3 is in exception"
        ),
        "{out}"
    );
}

#[test]
fn a_missing_device_says_what_to_check() {
    let err = link::open_serial("/dev/no-such-rover", Duration::ZERO)
        .err()
        .unwrap()
        .to_string();
    assert!(err.starts_with("cannot open /dev/no-such-rover: "), "{err}");
    assert!(
        err.ends_with("is the rover/twin running? is /dev/no-such-rover right?"),
        "{err}"
    );
}

#[test]
fn a_port_another_program_holds_says_to_close_it() {
    let (_master, _slave, path) = raw_pty();
    // Another program (here a second handle) has the port open and locked.
    let _held = serialport::new(&path, 115_200).open().unwrap();
    let err = link::open_serial(&path, Duration::ZERO)
        .err()
        .unwrap()
        .to_string();
    assert_eq!(
        err,
        format!(
            "cannot open {path}: Unable to acquire exclusive lock on serial port; {path} is in \
             use by another program (another hostctl, a terminal such as screen or minicom); \
             close it first, then retry"
        )
    );
}
