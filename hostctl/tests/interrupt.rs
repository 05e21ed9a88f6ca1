//! Ctrl-C to the real `hostctl` binary during `run`: with its output going to a pipe, as
//! to a log file, the `wait` it interrupts still prints its view, and it exits with status
//! 130 and says why. The rover is a scripted master on a pseudo-terminal that answers
//! every frame with zeros (every board running, no exception).

use std::fs::File;
use std::io::{Read, Write};
use std::process::{Command, Stdio};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use nix::pty::openpty;
use nix::sys::signal::{kill, Signal};
use nix::sys::termios::{cfmakeraw, tcgetattr, tcsetattr, SetArg};
use nix::unistd::{ttyname, Pid};
use shared::regs::BoardKind;

/// Answers hostctl's frames until the pty closes, counting the reads (update rounds).
fn scripted_master(mut pty: File, reads: Arc<AtomicUsize>) {
    pty.write_all(b"Starting\r\nMar 29 2017 14:03:11\r\n1520\r\nReady\r\n")
        .unwrap();
    let mut sets: Vec<Vec<u8>> = vec![Vec::new(); 8];
    let mut len = [0u8; 1];
    while pty.read_exact(&mut len).is_ok() {
        let mut rest = vec![0u8; usize::from(len[0]).saturating_sub(1)];
        if pty.read_exact(&mut rest).is_err() {
            return;
        }
        let (device, command) = (rest[0] >> 4, rest[0] & 0x0f);
        let reply = match command {
            // Set read set s: the number of ids.
            4 => {
                sets[usize::from(rest[1])] = rest[2..].to_vec();
                vec![(rest.len() - 2) as u8]
            }
            // Read set s: its registers' bytes, all zero.
            3 => {
                reads.fetch_add(1, Ordering::Relaxed);
                let kind = BoardKind::of_device(device).unwrap();
                let size: usize = sets[usize::from(rest[1])]
                    .iter()
                    .map(|&id| usize::from(kind.size_of(id).unwrap()))
                    .sum();
                vec![0; size]
            }
            _ => vec![0],
        };
        if pty.write_all(&reply).is_err() {
            return;
        }
    }
}

#[test]
fn ctrl_c_during_a_wait_to_a_pipe_prints_the_view_and_exits_130() {
    let pty = openpty(None, None).unwrap();
    let mut attrs = tcgetattr(&pty.slave).unwrap();
    cfmakeraw(&mut attrs);
    tcsetattr(&pty.slave, SetArg::TCSANOW, &attrs).unwrap();
    let path = ttyname(&pty.slave).unwrap().to_string_lossy().into_owned();
    let reads = Arc::new(AtomicUsize::new(0));
    let counted = Arc::clone(&reads);
    let master = File::from(pty.master);
    std::thread::spawn(move || scripted_master(master, counted));

    let script = std::env::temp_dir().join(format!("hostctl-ctrl-c-{}.rover", std::process::id()));
    std::fs::write(&script, "wait 60\nsay after the wait\n").unwrap();
    let child = Command::new(env!("CARGO_BIN_EXE_hostctl"))
        .args(["--port", &path, "--settle-ms", "0", "run"])
        .arg(&script)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // Some update() rounds (ten reads each) into the wait, then Ctrl-C.
    let start = Instant::now();
    while reads.load(Ordering::Relaxed) < 10 * 20 {
        assert!(
            start.elapsed() < Duration::from_secs(20),
            "hostctl never polled"
        );
        std::thread::sleep(Duration::from_millis(5));
    }
    kill(Pid::from_raw(child.id() as i32), Signal::SIGINT).unwrap();
    let out = child.wait_with_output().unwrap();
    let _ = std::fs::remove_file(&script);
    let stdout = String::from_utf8(out.stdout).unwrap();
    let stderr = String::from_utf8(out.stderr).unwrap();

    assert_eq!(out.status.code(), Some(130), "{stdout}\n{stderr}");
    assert_eq!(
        stdout.matches(" updates, ").count(),
        1,
        "one view: {stdout}"
    );
    // All-zero replies read as the bottom of each range.
    assert!(
        stdout.contains("\n1              -   ≤-4000 "),
        "wheel 1: {stdout}"
    );
    assert!(!stdout.contains("after the wait"), "{stdout}");
    assert!(
        stderr.contains(
            "line 1 (`wait 60`) failed: stopped by Ctrl-C during this line's view; the view \
             above is the rover as it was then; hostctl closes the port, which reboots the \
             master and so stops every motor"
        ),
        "{stderr}"
    );
    assert!(
        start.elapsed() < Duration::from_secs(30),
        "the wait was cut short"
    );
}
