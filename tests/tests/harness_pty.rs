//! Emulator tests of the pseudo-terminal: a host program opens the path with
//! plain file I/O and talks to the echo fixture.

use std::fs::OpenOptions;
use std::io::{Read, Write};
use std::sync::mpsc;
use std::time::Duration;

use harness::{Avr, Pty};

/// Reads from the host end on a thread, so a missing byte fails the test
/// instead of blocking it.
fn reader(mut port: std::fs::File) -> mpsc::Receiver<u8> {
    let (tx, rx) = mpsc::channel();
    std::thread::spawn(move || {
        let mut buf = [0u8; 64];
        while let Ok(n) = port.read(&mut buf) {
            if n == 0 || buf[..n].iter().any(|&b| tx.send(b).is_err()) {
                break;
            }
        }
    });
    rx
}

fn collect(rx: &mpsc::Receiver<u8>, n: usize) -> Vec<u8> {
    (0..n)
        .map_while(|_| rx.recv_timeout(Duration::from_secs(2)).ok())
        .collect()
}

#[test]
fn host_round_trip_through_the_pty() {
    let mut avr = Avr::firmware("fixture_uart_echo").unwrap();
    let mut pty = Pty::open().unwrap();
    assert!(pty.path().starts_with("/dev/pts"), "{:?}", pty.path());
    let mut host = OpenOptions::new()
        .read(true)
        .write(true)
        .open(pty.path())
        .unwrap();
    let rx = reader(host.try_clone().unwrap());

    // Banner first, as after an Uno reset.
    for _ in 0..20 {
        avr.run_us(1_000);
        pty.pump(&mut avr).unwrap();
    }
    assert_eq!(collect(&rx, 12), b"echo ready\r\n");

    // Every byte value survives both directions unchanged (raw mode).
    let msg: Vec<u8> = (0u8..=255).rev().collect();
    host.write_all(&msg).unwrap();
    let mut back = Vec::new();
    for _ in 0..200 {
        pty.pump(&mut avr).unwrap();
        avr.run_us(1_000);
        pty.pump(&mut avr).unwrap();
        back.extend(collect_ready(&rx));
        if back.len() >= msg.len() {
            break;
        }
    }
    assert_eq!(back, msg);
}

/// Bytes already received, without waiting.
fn collect_ready(rx: &mpsc::Receiver<u8>) -> Vec<u8> {
    std::thread::sleep(Duration::from_millis(1));
    rx.try_iter().collect()
}

#[test]
fn link_points_at_the_pty_and_is_removed_on_drop() {
    let dir = std::env::temp_dir().join(format!("harness-pty-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let at = dir.join("uno");
    {
        let mut pty = Pty::open().unwrap();
        pty.link(&at).unwrap();
        assert_eq!(std::fs::read_link(&at).unwrap(), pty.path());
    }
    assert!(std::fs::symlink_metadata(&at).is_err());
    std::fs::remove_dir(&dir).unwrap();
}

#[test]
fn serve_never_runs_ahead_of_the_wall_clock() {
    let mut avr = Avr::firmware("fixture_sleep").unwrap();
    let mut pty = Pty::open().unwrap();
    let wall = std::time::Instant::now();
    pty.serve(
        &mut avr,
        Duration::from_millis(200),
        Duration::from_millis(5),
    )
    .unwrap();
    let real = wall.elapsed().as_micros() as u64;
    let emulated = avr.micros();
    // The sleeping fixture emulates far faster than real time, so only pacing
    // keeps it at the wall clock: at most one slice ahead, and not far behind.
    assert!(
        emulated <= real + 5_000,
        "{emulated} µs emulated in {real} µs"
    );
    assert!(
        emulated >= 150_000,
        "only {emulated} µs emulated in {real} µs"
    );
}

/// Sets or clears HUPCL on an open port, as `stty -F PORT [-]hupcl` does.
fn set_hupcl(port: &std::fs::File, on: bool) {
    use nix::sys::termios::{tcgetattr, tcsetattr, ControlFlags, SetArg};
    let mut termios = tcgetattr(port).expect("the port's settings");
    termios.control_flags.set(ControlFlags::HUPCL, on);
    tcsetattr(port, SetArg::TCSANOW, &termios).expect("settings set");
}

#[test]
fn a_close_with_hupcl_resets_even_when_the_next_program_clears_it_at_once() {
    let mut pty = Pty::open().unwrap();
    let first = std::fs::File::open(pty.path()).unwrap();
    assert!(pty.take_dtr_reset(), "the first open raises DTR");
    // The first program closes with HUPCL set (the port's default); the next opens and
    // clears it before the pty has looked at either.
    drop(first);
    let next = std::fs::File::open(pty.path()).unwrap();
    set_hupcl(&next, false);
    assert!(
        pty.take_dtr_reset(),
        "the close dropped DTR and the open raised it: the Uno resets"
    );
    // Its own close without HUPCL leaves DTR up, so neither it nor the next open resets.
    drop(next);
    assert!(!pty.take_dtr_reset());
    let last = std::fs::File::open(pty.path()).unwrap();
    assert!(!pty.take_dtr_reset());
    // One that clears HUPCL and closes before the pty looks resets nothing either...
    set_hupcl(&last, true);
    assert!(!pty.take_dtr_reset());
    set_hupcl(&last, false);
    drop(last);
    assert!(!pty.take_dtr_reset());
    // ...and one that sets it does.
    let again = std::fs::File::open(pty.path()).unwrap();
    assert!(
        !pty.take_dtr_reset(),
        "DTR is still up: the open raises nothing"
    );
    set_hupcl(&again, true);
    drop(again);
    assert!(pty.take_dtr_reset());
}
