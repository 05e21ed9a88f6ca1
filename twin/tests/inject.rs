//! `twin inject` as a user runs it: a refused command is told on stderr with the `twin: `
//! prefix and exit 2, whether this process or the running twin refuses it.

use std::io::{BufRead, BufReader, Write};
use std::os::unix::net::UnixListener;
use std::path::PathBuf;
use std::process::{Command, Output};

fn inject(control: &PathBuf, words: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_twin"))
        .arg("inject")
        .arg("--control")
        .arg(control)
        .args(words)
        .output()
        .unwrap()
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("twin-inject-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join("port.ctl")
}

#[test]
fn a_negative_spike_is_refused_before_any_twin_is_asked() {
    let control = scratch("negative");
    let out = inject(&control, &["spike", "1", "drive", "-5", "10"]);
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(out.stdout, b"");
    assert_eq!(
        String::from_utf8(out.stderr).unwrap(),
        "twin: the spike current (A) `-5` is out of range; give more than 0 and at most 10.24 A \
         (the current sense reads no more)\n"
    );
    let out = inject(&control, &["stall", "7", "on"]);
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(
        String::from_utf8(out.stderr).unwrap(),
        "twin: `7` is not a wheel number (1..6)\n"
    );
}

#[test]
fn a_drop_of_no_byte_is_refused_not_reported_as_set() {
    let control = scratch("drop0");
    let out = inject(&control, &["drop-serial", "0"]);
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(out.stdout, b"");
    assert_eq!(
        String::from_utf8(out.stderr).unwrap(),
        "twin: drop-serial 0 would lose no byte, so nothing was changed; give N of 1 or more\n"
    );
}

#[test]
fn an_rc_width_the_receiver_cannot_send_is_refused_not_clamped() {
    let control = scratch("rcwidth");
    let out = inject(&control, &["rc", "1", "5000"]);
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(out.stdout, b"");
    assert_eq!(
        String::from_utf8(out.stderr).unwrap(),
        "twin: the RC pulse width (µs) `5000` is out of range; give 500 to 2500 µs (what a \
         receiver sends; the sticks span about 940 to 1940)\n"
    );
}

#[test]
fn a_refusal_by_the_twin_reads_like_one_here() {
    let control = scratch("remote");
    let _ = std::fs::remove_file(&control);
    let listener = UnixListener::bind(&control).unwrap();
    // Stands in for the twin's control socket: one command, one refusal.
    let server = std::thread::spawn(move || {
        let (mut stream, _) = listener.accept().unwrap();
        let mut line = String::new();
        BufReader::new(&stream).read_line(&mut line).unwrap();
        stream
            .write_all(b"error: controller 12 does not exist: the slave controllers are 1 to 9\n")
            .unwrap();
        line
    });
    let out = inject(&control, &["cut", "12"]);
    assert_eq!(server.join().unwrap(), "cut 12\n");
    std::fs::remove_file(&control).unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(out.stdout, b"");
    assert_eq!(
        String::from_utf8(out.stderr).unwrap(),
        "twin: controller 12 does not exist: the slave controllers are 1 to 9\n"
    );
}
