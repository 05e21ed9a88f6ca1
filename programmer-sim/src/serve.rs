//! The I/O loop: moves bytes between the pseudo-terminal and the [`Programmer`] until
//! the host closes the port, a stop is requested, or nothing happens for too long.

use crate::error::SimError;
use crate::session::Programmer;
use nix::errno::Errno;
use nix::poll::{poll, PollFd, PollFlags, PollTimeout};
use std::fs::File;
use std::io::{ErrorKind, Read, Write};
use std::os::fd::AsFd;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

/// How often the loop wakes to check the stop flag and the idle timer.
const TICK_MS: u8 = 50;

/// Why serving ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum End {
    /// The host opened the port, talked, and closed it.
    PortClosed,
    /// A stop was requested (SIGTERM or SIGINT).
    Stopped,
    /// Nothing arrived for the idle timeout.
    IdleTimeout,
}

impl End {
    /// Name used in the log.
    pub fn name(self) -> &'static str {
        match self {
            End::PortClosed => "port-closed",
            End::Stopped => "stopped",
            End::IdleTimeout => "idle-timeout",
        }
    }
}

/// Serves `prog` on the controlling side `port` until the session ends.
pub fn serve(
    port: &mut File,
    prog: &mut Programmer,
    idle: Duration,
    stop: &AtomicBool,
) -> Result<End, SimError> {
    let mut started = false;
    let mut last = Instant::now();
    let mut buf = [0u8; 4096];
    let mut answer = Vec::new();
    loop {
        if stop.load(Ordering::SeqCst) {
            return Ok(End::Stopped);
        }
        if last.elapsed() >= idle {
            return Ok(End::IdleTimeout);
        }
        let revents = {
            let mut fds = [PollFd::new(port.as_fd(), PollFlags::POLLIN)];
            match poll(&mut fds, PollTimeout::from(TICK_MS)) {
                Ok(_) => fds[0].revents().unwrap_or(PollFlags::empty()),
                Err(Errno::EINTR) => continue,
                Err(e) => return Err(SimError::Pty(e)),
            }
        };
        if revents.is_empty() {
            continue;
        }
        let n = match port.read(&mut buf) {
            Ok(n) => n,
            Err(e) if e.kind() == ErrorKind::Interrupted || e.kind() == ErrorKind::WouldBlock => {
                continue
            }
            // EIO: no program has the terminal side open.
            Err(e) if e.raw_os_error() == Some(Errno::EIO as i32) => 0,
            Err(e) => return Err(SimError::PtyIo(e)),
        };
        if n == 0 {
            if started {
                return Ok(End::PortClosed);
            }
            // Nobody has opened the port yet: wait without spinning.
            std::thread::sleep(Duration::from_millis(u64::from(TICK_MS)));
            continue;
        }
        started = true;
        last = Instant::now();
        answer.clear();
        for &b in buf.get(..n).unwrap_or(&[]) {
            prog.feed(b, &mut answer);
        }
        if !answer.is_empty() {
            port.write_all(&answer).map_err(SimError::PtyIo)?;
        }
    }
}
