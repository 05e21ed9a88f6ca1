//! Request/response over a [`Port`]: send one frame, read its exact reply.

use std::io;
use std::time::Duration;

use crate::banner::{self, BannerFailure};
use crate::error::HostError;
use crate::port::{Port, SerialPort};

/// How long a reply may take (reference §4.7: 1 s, no retries).
pub const REPLY_TIMEOUT: Duration = Duration::from_secs(1);

/// How long to wait after `Ready` before the first frame, so the slaves the
/// master has just hard-reset are back on the bus (reference §4.1, §13).
pub const SETTLE: Duration = Duration::from_secs(2);

/// A connected link to the master.
pub struct Link<P: Port> {
    port: P,
}

/// Opens the serial device at `path` (115200 8N1, DTR pulse), waits for the
/// banner and then for `settle`.
pub fn open_serial(path: &str, settle: Duration) -> Result<Link<SerialPort>, HostError> {
    let port = SerialPort::open(path, banner::LINE_TIMEOUT).map_err(|source| HostError::Open {
        path: path.to_owned(),
        source,
    })?;
    Link::connect(port, path, settle)
}

impl<P: Port> Link<P> {
    /// Waits for the banner on `port` (named `path` in errors), then for
    /// `settle`, and returns the ready link.
    pub fn connect(mut port: P, path: &str, settle: Duration) -> Result<Self, HostError> {
        match banner::wait_ready(&mut port) {
            Ok(_) => {}
            Err(BannerFailure::Io(kind)) => return Err(HostError::Io(io::Error::from(kind))),
            Err(BannerFailure::Silent { lines }) => {
                return Err(HostError::NoBanner {
                    path: path.to_owned(),
                    why: format!(
                        "nothing for {} s after {lines} line(s)",
                        banner::LINE_TIMEOUT.as_secs()
                    ),
                })
            }
            Err(BannerFailure::NoReady { last }) => {
                return Err(HostError::NoBanner {
                    path: path.to_owned(),
                    why: format!("{} lines, the last was {last:?}", banner::MAX_LINES),
                })
            }
        }
        std::thread::sleep(settle);
        port.set_timeout(REPLY_TIMEOUT)?;
        Ok(Self { port })
    }

    /// Wraps a port that is already past the banner (tests, reconnects).
    pub fn ready(port: P) -> Self {
        Self { port }
    }

    /// The underlying port.
    pub fn port(&self) -> &P {
        &self.port
    }

    /// Sends `frame` to `device` and reads exactly `reply_len` bytes back.
    pub fn transact(
        &mut self,
        device: u8,
        frame: &[u8],
        reply_len: usize,
    ) -> Result<Vec<u8>, HostError> {
        self.port.write_all(frame)?;
        self.port.flush()?;
        self.port.set_timeout(REPLY_TIMEOUT)?;
        let mut reply = vec![0u8; reply_len];
        let mut got = 0;
        while got < reply_len {
            match self.port.read(&mut reply[got..]) {
                Ok(0) => break,
                Ok(n) => got += n,
                Err(e) if e.kind() == io::ErrorKind::TimedOut => break,
                Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
                Err(e) => return Err(HostError::Io(e)),
            }
        }
        if got < reply_len {
            return Err(HostError::Timeout {
                device,
                expected: reply_len,
                got,
            });
        }
        Ok(reply)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fake::FakePort;

    #[test]
    fn transact_reads_exactly_the_reply() {
        let mut link = Link::ready(FakePort::with_replies(&[[0xaa, 0xbb, 0xcc]]));
        let reply = link.transact(1, &[3, 0x13, 0], 2).unwrap();
        assert_eq!(reply, [0xaa, 0xbb]);
        assert_eq!(link.port().written, [3, 0x13, 0]);
        assert_eq!(link.port().timeouts, [REPLY_TIMEOUT]);
    }

    #[test]
    fn short_reply_is_a_timeout() {
        let mut link = Link::ready(FakePort::with_replies(&[[0x01]]));
        match link.transact(4, &[3, 0x43, 0], 2) {
            Err(HostError::Timeout {
                device: 4,
                expected: 2,
                got: 1,
            }) => {}
            other => panic!("unexpected {other:?}"),
        }
    }

    #[test]
    fn connect_waits_for_ready_and_sets_reply_timeout() {
        let port = FakePort::with_input(b"Starting\r\nReady\r\n");
        let link = Link::connect(port, "/dev/x", Duration::ZERO).unwrap();
        assert_eq!(link.port().timeouts, [banner::LINE_TIMEOUT, REPLY_TIMEOUT]);
        assert!(link.port().written.is_empty());
    }

    #[test]
    fn connect_without_ready_names_the_port() {
        let port = FakePort::with_input(b"Starting\r\n");
        let err = Link::connect(port, "/dev/pts/9", Duration::ZERO)
            .err()
            .unwrap()
            .to_string();
        assert_eq!(
            err,
            "no `Ready` from /dev/pts/9: nothing for 5 s after 1 line(s); \
             is the rover/twin running? is /dev/pts/9 right?"
        );
    }
}
