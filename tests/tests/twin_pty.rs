//! The twin behind a real pseudo-terminal, opened the way hostctl opens a serial port (the
//! `serialport` crate at 115200 8N1, DTR pulse, wait for `Ready`): the master's banner
//! arrives after every open, because opening resets the master (the Uno's DTR auto-reset),
//! and device 0 answers frames. Runs against whatever slave images are built.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{mpsc, Arc};
use std::time::Duration;

use harness::Pty;
use twin::control::ControlSocket;
use twin::serve::{Limits, Server};
use twin::Rover;

/// Starts a paced twin on a thread, its pty linked at `link` (and its control socket next
/// to it) if given; returns the pty path and the flag that stops it.
fn start_twin(
    link: Option<std::path::PathBuf>,
) -> (String, Arc<AtomicBool>, std::thread::JoinHandle<()>) {
    let stop = Arc::new(AtomicBool::new(false));
    let (tx, rx) = mpsc::channel();
    let flag = Arc::clone(&stop);
    let thread = std::thread::spawn(move || {
        let rover = Rover::new().expect("the twin builds (run scripts/firmware.sh)");
        let mut pty = Pty::open().expect("a pty");
        let control = link.as_ref().map(|link| {
            pty.link(link).unwrap();
            ControlSocket::bind(&twin::paths::control_of(link)).unwrap()
        });
        let mut server = Server::new(rover, pty, control, true);
        tx.send(server.path().display().to_string()).unwrap();
        server
            .serve(
                Limits::default(),
                &|| flag.load(Ordering::SeqCst),
                &mut |_, _, _| {},
            )
            .expect("the twin serves");
    });
    let path = rx.recv_timeout(Duration::from_secs(30)).expect("pty path");
    (path, stop, thread)
}

#[test]
fn a_serial_program_sees_the_banner_after_each_open() {
    let (path, stop, thread) = start_twin(None);
    for _ in 0..2 {
        // hostctl's own open: serialport at 115200, DTR pulse (refused by a pty), banner.
        let mut link = hostctl::link::open_serial(&path, Duration::ZERO)
            .expect("the banner with Ready arrives after the open");
        // Device 0 answers: configure the library's read set 2 (11 ids), reply = count.
        let frame = [0x0e, 0x04, 0x02, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11];
        assert_eq!(link.transact(0, &frame, 1).unwrap(), [0x0b]);
        // 22 bytes of master registers; at boot the master is in its boot exception.
        let reply = link.transact(0, &[0x03, 0x03, 0x02], 22).unwrap();
        assert_eq!(&reply[20..], [0x02, 0x00], "EXCEPTIONDATA = boot");
    }
    stop.store(true, Ordering::SeqCst);
    thread.join().unwrap();
}

#[test]
fn hostctl_finds_the_twin_behind_a_link_and_waits_in_its_time() {
    let dir = std::env::temp_dir().join(format!("twin-pty-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let link = dir.join("port");
    let (_path, stop, thread) = start_twin(Some(link.clone()));
    assert!(hostctl::twin::is_running(&link));
    let before = hostctl::twin::emulated_us(&link).expect("the twin tells its time");
    // hostctl's clock for this port is the twin's: 200 ms of it pass in a sleep.
    let mut clock = hostctl::twin::clock_for(&link.display().to_string());
    let t0 = clock.now();
    clock.sleep(Duration::from_millis(200));
    assert!(clock.now() - t0 >= Duration::from_millis(200));
    let after = hostctl::twin::emulated_us(&link).unwrap();
    assert!(after >= before + 200_000, "{before} -> {after}");
    // The link opens as a serial port, banner included.
    let mut port = hostctl::link::open_serial(&link.display().to_string(), Duration::ZERO)
        .expect("banner through the link");
    assert_eq!(port.transact(0, &[0x04, 0x04, 0x06, 0x0b], 1).unwrap(), [1]);
    stop.store(true, Ordering::SeqCst);
    thread.join().unwrap();
    assert!(
        !hostctl::twin::is_running(&link),
        "the link and socket go with the twin"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn hostctl_and_the_twin_agree_on_the_default_link() {
    assert_eq!(hostctl::twin::default_link(), twin::paths::default_link());
    assert_eq!(
        hostctl::twin::control_of(&hostctl::twin::default_link()),
        twin::paths::control_of(&twin::paths::default_link())
    );
}
