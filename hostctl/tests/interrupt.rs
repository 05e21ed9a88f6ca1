//! Ctrl-C and SIGTERM to the real `hostctl` binary during `run`: with its output going to
//! a pipe, as to a log file, the `wait` it interrupts still prints its view, and it exits
//! at once with status 130 (143 for SIGTERM) and says why; also while it waits for the
//! master's banner. During `watch`, Ctrl-C ends it after its round, the same way. The rover is a scripted master on a pseudo-terminal that answers
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

/// Answers hostctl's frames until the pty closes, counting the reads (update rounds); a
/// master that never boots (`banner` false) sends nothing.
fn scripted_master(mut pty: File, reads: Arc<AtomicUsize>, banner: bool) {
    if !banner {
        return std::thread::park();
    }
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

/// What hostctl printed and its exit status after `signal` came once `ready` said so.
struct Stopped {
    code: Option<i32>,
    stdout: String,
    stderr: String,
    /// From the signal to hostctl's exit.
    took: Duration,
    /// Reads the master answered after the signal.
    reads_after: usize,
}

/// Runs `hostctl COMMAND` (with no command, `run` on a script of a 60-s wait) against the
/// scripted master and sends `signal` once `ready(reads so far, time since start)` says so.
fn run_and_signal(
    banner: bool,
    signal: Signal,
    command: &[&str],
    ready: impl Fn(usize, Duration) -> bool,
) -> Stopped {
    let pty = openpty(None, None).unwrap();
    let mut attrs = tcgetattr(&pty.slave).unwrap();
    cfmakeraw(&mut attrs);
    tcsetattr(&pty.slave, SetArg::TCSANOW, &attrs).unwrap();
    let path = ttyname(&pty.slave).unwrap().to_string_lossy().into_owned();
    let reads = Arc::new(AtomicUsize::new(0));
    let counted = Arc::clone(&reads);
    let master = File::from(pty.master);
    std::thread::spawn(move || scripted_master(master, counted, banner));

    let name = format!("hostctl-signal-{}-{signal}.rover", std::process::id());
    let script = std::env::temp_dir().join(name);
    std::fs::write(&script, "wait 60\nsay after the wait\n").unwrap();
    let script_text = script.display().to_string();
    let run = ["run", script_text.as_str()];
    let child = Command::new(env!("CARGO_BIN_EXE_hostctl"))
        .args(["--port", &path, "--settle-ms", "0"])
        .args(if command.is_empty() {
            &run[..]
        } else {
            command
        })
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let start = Instant::now();
    while !ready(reads.load(Ordering::Relaxed), start.elapsed()) {
        assert!(
            start.elapsed() < Duration::from_secs(20),
            "hostctl never polled"
        );
        std::thread::sleep(Duration::from_millis(5));
    }
    let sent = Instant::now();
    let before = reads.load(Ordering::Relaxed);
    kill(Pid::from_raw(child.id() as i32), signal).unwrap();
    let out = child.wait_with_output().unwrap();
    let took = sent.elapsed();
    let _ = std::fs::remove_file(&script);
    Stopped {
        code: out.status.code(),
        stdout: String::from_utf8(out.stdout).unwrap(),
        stderr: String::from_utf8(out.stderr).unwrap(),
        took,
        reads_after: reads.load(Ordering::Relaxed) - before,
    }
}

/// That hostctl exited with `code` within 2 s of the signal, saying `says`.
fn assert_stopped(s: &Stopped, code: i32, says: &str) {
    assert_eq!(s.code, Some(code), "{}\n{}", s.stdout, s.stderr);
    assert!(s.stderr.contains(says), "{}", s.stderr);
    assert!(s.took < Duration::from_secs(2), "{:?}", s.took);
}

/// Twenty update() rounds (ten reads each) into the wait.
fn into_the_wait(reads: usize, _: Duration) -> bool {
    reads >= 10 * 20
}

#[test]
fn ctrl_c_during_a_wait_to_a_pipe_prints_the_view_and_exits_130() {
    let s = run_and_signal(true, Signal::SIGINT, &[], into_the_wait);
    assert_stopped(
        &s,
        130,
        "stopped by Ctrl-C during line 1 (`wait 60`); the view above is the rover as it was \
         then; hostctl closes the port, which reboots the master and so stops every motor",
    );
    let stdout = &s.stdout;
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
    // At once: the round in progress, and nothing after it.
    assert!(s.reads_after <= 10, "{} reads after Ctrl-C", s.reads_after);
}

#[test]
fn sigterm_stops_a_script_as_ctrl_c_does_with_status_143() {
    let s = run_and_signal(true, Signal::SIGTERM, &[], into_the_wait);
    assert_stopped(&s, 143, "stopped by SIGTERM during line 1 (`wait 60`)");
    assert_eq!(s.stdout.matches(" updates, ").count(), 1, "{}", s.stdout);
}

#[test]
fn ctrl_c_while_the_master_is_silent_stops_at_once() {
    // No banner: hostctl would wait 5 s for each line of it.
    let s = run_and_signal(false, Signal::SIGINT, &[], |_, t| {
        t > Duration::from_millis(500)
    });
    let says = "stopped by Ctrl-C while waiting for the master's banner";
    assert_stopped(&s, 130, says);
}

#[test]
fn ctrl_c_during_a_watch_ends_it_after_its_round_with_status_130() {
    let watch = [
        "--json",
        "watch",
        "--readset",
        "1",
        "--device",
        "3",
        "--interval-ms",
        "20",
        "TIMER",
    ];
    let s = run_and_signal(true, Signal::SIGINT, &watch, |reads, _| reads >= 5);
    assert_stopped(&s, 130, "stopped by Ctrl-C after round ");
    // Its rounds, then the last JSON line says it was interrupted.
    let last = s.stdout.lines().last().unwrap_or_default();
    assert!(last.contains(r#""interrupted":"Ctrl-C""#), "{}", s.stdout);
    assert!(
        s.stdout.contains(r#"{"command":"watch","round":5,"#),
        "{}",
        s.stdout
    );
    assert!(s.reads_after <= 1, "{} reads after Ctrl-C", s.reads_after);
}
