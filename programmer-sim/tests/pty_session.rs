//! Runs the `programmer-sim` binary and talks to it through its pseudo-terminal, as avrdude
//! does: checks the printed path, the answers, and the files saved for each way a session
//! can end (port closed, SIGTERM, idle timeout).

use nix::poll::{poll, PollFd, PollFlags, PollTimeout};
use nix::sys::signal::{kill, Signal};
use nix::unistd::Pid;
use std::fs::{File, OpenOptions};
use std::io::{BufRead, BufReader, Read, Write};
use std::os::fd::AsFd;
use std::path::PathBuf;
use std::process::{Child, ChildStdout, Command, Stdio};
use std::time::{Duration, Instant};

fn out_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("programmer-sim-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

/// Starts the simulator and returns it with the pseudo-terminal path it printed.
fn start(out: &PathBuf, extra: &[&str]) -> (Child, PathBuf, BufReader<ChildStdout>) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_programmer-sim"))
        .arg("--out")
        .arg(out)
        .args(extra)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut stdout = BufReader::new(child.stdout.take().unwrap());
    let mut line = String::new();
    stdout.read_line(&mut line).unwrap();
    let path = PathBuf::from(line.trim_end());
    assert!(
        path.starts_with("/dev/"),
        "first line is not a device path: {line:?}"
    );
    (child, path, stdout)
}

fn wait_exit(child: &mut Child, within: Duration) -> std::process::ExitStatus {
    let start = Instant::now();
    loop {
        if let Some(status) = child.try_wait().unwrap() {
            return status;
        }
        if start.elapsed() > within {
            let _ = child.kill();
            panic!("programmer-sim did not exit within {within:?}");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// Reads exactly `n` bytes, failing the test after two seconds of silence.
fn read_n(port: &mut File, n: usize) -> Vec<u8> {
    let mut got = Vec::new();
    while got.len() < n {
        let mut fds = [PollFd::new(port.as_fd(), PollFlags::POLLIN)];
        let ready = poll(&mut fds, PollTimeout::from(2000u16)).unwrap();
        assert!(ready > 0, "no answer; got {got:02x?} of {n} bytes");
        let mut buf = vec![0u8; n - got.len()];
        let k = port.read(&mut buf).unwrap();
        got.extend_from_slice(&buf[..k]);
    }
    got
}

fn exchange(port: &mut File, send: &[u8], answer_len: usize) -> Vec<u8> {
    port.write_all(send).unwrap();
    read_n(port, answer_len)
}

#[test]
fn serves_a_session_and_saves_images_when_the_port_closes() {
    let out = out_dir("closed");
    let (mut child, path, _stdout) = start(&out, &["--mode", "isp"]);
    let mut port = OpenOptions::new()
        .read(true)
        .write(true)
        .open(&path)
        .unwrap();
    assert_eq!(exchange(&mut port, &[0x30, 0x20], 2), [0x14, 0x10]);
    assert_eq!(
        exchange(&mut port, &[0x75, 0x20], 5),
        [0x14, 0x1e, 0x95, 0x0f, 0x10]
    );
    assert_eq!(exchange(&mut port, &[0x50, 0x20], 2), [0x14, 0x10]);
    // Flash word 0x10 (byte 0x20): four bytes; EEPROM address 0: one byte.
    assert_eq!(
        exchange(&mut port, &[0x55, 0x10, 0x00, 0x20], 2),
        [0x14, 0x10]
    );
    let page = [0x64, 0x00, 0x04, b'F', 0xde, 0xad, 0xbe, 0xef, 0x20];
    assert_eq!(exchange(&mut port, &page, 2), [0x14, 0x10]);
    assert_eq!(
        exchange(&mut port, &[0x55, 0x00, 0x00, 0x20], 2),
        [0x14, 0x10]
    );
    let ee = [0x64, 0x00, 0x01, b'E', 0x05, 0x20];
    assert_eq!(exchange(&mut port, &ee, 2), [0x14, 0x10]);
    assert_eq!(exchange(&mut port, &[0x51, 0x20], 2), [0x14, 0x10]);
    drop(port);

    let status = wait_exit(&mut child, Duration::from_secs(5));
    assert!(status.success(), "{status}");
    let flash = std::fs::read(out.join("flash.bin")).unwrap();
    let eeprom = std::fs::read(out.join("eeprom.bin")).unwrap();
    assert_eq!(flash.len(), 32768);
    assert_eq!(eeprom.len(), 1024);
    assert_eq!(&flash[0x1f..0x25], &[0xff, 0xde, 0xad, 0xbe, 0xef, 0xff]);
    assert_eq!(flash.iter().filter(|&&b| b != 0xff).count(), 4);
    assert_eq!(eeprom[0], 5);
    assert!(eeprom[1..].iter().all(|&b| b == 0xff));
    let log = std::fs::read_to_string(out.join("log.json")).unwrap();
    assert!(log.contains("\"end\": \"port-closed\""), "{log}");
    assert!(log.contains("{\"memory\": \"flash\", \"address\": 32, \"length\": 4}"));
    assert!(log.contains("{\"memory\": \"eeprom\", \"address\": 0, \"length\": 1}"));
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn sigterm_saves_erased_images_and_exits_cleanly() {
    let out = out_dir("sigterm");
    let (mut child, _path, _stdout) = start(&out, &["--mode", "bootloader"]);
    let pid = Pid::from_raw(i32::try_from(child.id()).unwrap());
    kill(pid, Signal::SIGTERM).unwrap();
    let status = wait_exit(&mut child, Duration::from_secs(5));
    assert!(status.success(), "{status}");
    let flash = std::fs::read(out.join("flash.bin")).unwrap();
    assert_eq!(flash.len(), 32768);
    assert!(flash.iter().all(|&b| b == 0xff));
    let log = std::fs::read_to_string(out.join("log.json")).unwrap();
    assert!(log.contains("\"end\": \"stopped\""), "{log}");
    assert!(log.contains("\"mode\": \"bootloader\""), "{log}");
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn idle_timeout_ends_a_session_nobody_opened() {
    let out = out_dir("idle");
    let started = Instant::now();
    let (mut child, _path, _stdout) = start(&out, &["--idle-timeout", "1"]);
    let status = wait_exit(&mut child, Duration::from_secs(5));
    assert!(status.success(), "{status}");
    assert!(started.elapsed() >= Duration::from_secs(1));
    let log = std::fs::read_to_string(out.join("log.json")).unwrap();
    assert!(log.contains("\"end\": \"idle-timeout\""), "{log}");
    let _ = std::fs::remove_dir_all(&out);
}
