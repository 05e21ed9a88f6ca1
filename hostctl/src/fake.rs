//! An in-memory [`Port`] for tests: it records every frame written and
//! answers each one with the next scripted reply.

use std::collections::VecDeque;
use std::io::{self, Read, Write};
use std::time::Duration;

use crate::cmd::run::Clock;
use crate::port::Port;

/// A clock that only moves when slept on: (now, every sleep taken).
pub struct FakeClock(pub Duration, pub Vec<Duration>);

impl Clock for FakeClock {
    fn now(&self) -> Duration {
        self.0
    }
    fn sleep(&mut self, d: Duration) {
        self.0 += d;
        self.1.push(d);
    }
}

/// The fake clock, with Ctrl-C pressed at the given time.
pub struct CtrlCAt(pub FakeClock, pub Duration);

impl Clock for CtrlCAt {
    fn now(&self) -> Duration {
        self.0.now()
    }
    fn sleep(&mut self, d: Duration) {
        self.0.sleep(d);
    }
    fn interrupted_by(&self) -> Option<i32> {
        (self.0.now() >= self.1).then_some(2)
    }
}

/// A scripted fake of the master's serial link.
#[derive(Debug, Default)]
pub struct FakePort {
    /// Bytes available to read now.
    pending: VecDeque<u8>,
    /// Replies queued for the following frames, one per `write` call.
    replies: VecDeque<Vec<u8>>,
    /// Every `write` call's bytes, in order (one frame each).
    pub frames: Vec<Vec<u8>>,
    /// All bytes written, concatenated.
    pub written: Vec<u8>,
    /// Every timeout set, in order.
    pub timeouts: Vec<Duration>,
    /// Per frame, the first timeout set after it: how long its reply was waited for.
    pub reply_timeouts: Vec<Duration>,
    /// After this many frames the device is gone (unplugged, the twin killed): every
    /// write fails with a broken pipe.
    pub gone_after: Option<usize>,
}

impl FakePort {
    /// A port with `input` already waiting to be read.
    pub fn with_input(input: &[u8]) -> Self {
        Self {
            pending: input.iter().copied().collect(),
            ..Self::default()
        }
    }

    /// A port that answers the frames written to it with `replies`, in order.
    pub fn with_replies<R: AsRef<[u8]>>(replies: &[R]) -> Self {
        Self {
            replies: replies.iter().map(|r| r.as_ref().to_vec()).collect(),
            ..Self::default()
        }
    }

    /// The same port, answering the frames written to it with `replies` (after whatever
    /// input it already has).
    pub fn replying<R: AsRef<[u8]>>(self, replies: &[R]) -> Self {
        Self {
            replies: replies.iter().map(|r| r.as_ref().to_vec()).collect(),
            ..self
        }
    }

    /// Bytes not read yet.
    pub fn remaining(&self) -> Vec<u8> {
        self.pending.iter().copied().collect()
    }

    /// The frames written, as lower-case hex strings with spaces.
    pub fn frames_hex(&self) -> Vec<String> {
        self.frames.iter().map(|f| hex(f)).collect()
    }
}

/// Formats bytes as `06 12 01` (lower-case, space separated).
pub fn hex(bytes: &[u8]) -> String {
    bytes
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect::<Vec<_>>()
        .join(" ")
}

impl Read for FakePort {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        if self.pending.is_empty() {
            return Err(io::Error::new(io::ErrorKind::TimedOut, "fake timeout"));
        }
        let mut n = 0;
        while n < buf.len() {
            match self.pending.pop_front() {
                Some(b) => {
                    buf[n] = b;
                    n += 1;
                }
                None => break,
            }
        }
        Ok(n)
    }
}

impl Write for FakePort {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        if self.gone_after.is_some_and(|n| self.frames.len() >= n) {
            return Err(io::Error::from(io::ErrorKind::BrokenPipe));
        }
        self.frames.push(buf.to_vec());
        self.written.extend_from_slice(buf);
        if let Some(reply) = self.replies.pop_front() {
            self.pending.extend(reply);
        }
        Ok(buf.len())
    }

    fn flush(&mut self) -> io::Result<()> {
        Ok(())
    }
}

impl Port for FakePort {
    fn set_timeout(&mut self, timeout: Duration) -> io::Result<()> {
        self.timeouts.push(timeout);
        if self.reply_timeouts.len() < self.frames.len() {
            self.reply_timeouts.push(timeout);
        }
        Ok(())
    }
}
