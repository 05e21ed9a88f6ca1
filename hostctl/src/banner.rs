//! Waiting for the master's start-up banner (reference §4.1).
//!
//! After a reset the master prints `Starting`, a build date, its free SRAM
//! and `Ready`, each line ending CR LF. Frames are only accepted after
//! `Ready`, so the host reads lines until one is exactly `Ready`.

use std::io;
use std::time::Duration;

use crate::port::Port;

/// How long one banner line may take to arrive.
pub const LINE_TIMEOUT: Duration = Duration::from_secs(5);

/// How many lines are examined before giving up.
pub const MAX_LINES: usize = 10;

/// Longest line kept; a longer run of bytes without LF counts as one line.
const MAX_LINE_LEN: usize = 256;

/// The banner's first line.
const FIRST_LINE: &str = "Starting";

/// The banner's last line: frames are accepted after it.
const READY: &str = "Ready";

/// Whether `bytes` hold a piece of the banner (its first line, or its last with its line
/// end): among a reply's bytes, the sign that the master rebooted.
pub fn is_in(bytes: &[u8]) -> bool {
    let ready = [READY.as_bytes(), b"\r\n"].concat();
    [FIRST_LINE.as_bytes(), &ready]
        .iter()
        .any(|line| bytes.windows(line.len()).any(|w| w == *line))
}

/// Why the banner wait ended without `Ready`.
#[derive(Debug, PartialEq, Eq)]
pub enum BannerFailure {
    /// Nothing arrived for a whole line timeout; `lines` lines came before.
    Silent {
        /// Complete lines received before the silence.
        lines: usize,
    },
    /// `MAX_LINES` lines arrived and none was `Ready`.
    NoReady {
        /// The last line received, for the error message.
        last: String,
    },
    /// The port reported an error other than a timeout.
    Io(io::ErrorKind),
    /// Ctrl-C or SIGTERM (its number) came meanwhile ([`crate::interrupt`]).
    Interrupted(i32),
}

/// Reads lines (LF ends a line, CR is dropped) until one equals `Ready`.
///
/// Returns the lines seen before `Ready`, which the caller may log.
pub fn wait_ready<P: Port + ?Sized>(port: &mut P) -> Result<Vec<String>, BannerFailure> {
    port.set_timeout(LINE_TIMEOUT)
        .map_err(|e| BannerFailure::Io(e.kind()))?;
    let mut seen = Vec::new();
    while seen.len() < MAX_LINES {
        let line = read_line(port, seen.len())?;
        if line == READY {
            return Ok(seen);
        }
        seen.push(line);
    }
    Err(BannerFailure::NoReady {
        last: seen.pop().unwrap_or_default(),
    })
}

/// Reads one line, dropping CR; `lines` is only used to report silence.
fn read_line<P: Port + ?Sized>(port: &mut P, lines: usize) -> Result<String, BannerFailure> {
    let mut bytes = Vec::new();
    let mut byte = [0u8; 1];
    loop {
        match port.read(&mut byte) {
            Ok(0) => return Err(BannerFailure::Silent { lines }),
            Ok(_) => match byte[0] {
                b'\n' => break,
                b'\r' => {}
                b => {
                    bytes.push(b);
                    if bytes.len() >= MAX_LINE_LEN {
                        break;
                    }
                }
            },
            Err(e) if e.kind() == io::ErrorKind::TimedOut => {
                return Err(BannerFailure::Silent { lines })
            }
            // A signal cut the wait short: go on waiting, unless it asks hostctl to stop.
            Err(e) if e.kind() == io::ErrorKind::Interrupted => {
                if let Some(signal) = crate::interrupt::caught() {
                    return Err(BannerFailure::Interrupted(signal));
                }
            }
            Err(e) => return Err(BannerFailure::Io(e.kind())),
        }
    }
    Ok(String::from_utf8_lossy(&bytes).into_owned())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fake::FakePort;

    #[test]
    fn plain_banner_is_accepted() {
        let mut port =
            FakePort::with_input(b"Starting\r\nMar 29 2017 14:03:11\r\n1234\r\nReady\r\n");
        let seen = wait_ready(&mut port).unwrap();
        assert_eq!(seen, ["Starting", "Mar 29 2017 14:03:11", "1234"]);
        assert_eq!(port.timeouts.first(), Some(&LINE_TIMEOUT));
        assert!(port.written.is_empty());
    }

    #[test]
    fn junk_lines_before_ready_are_skipped() {
        let mut port = FakePort::with_input(b"\xff\x00garbage\nReadyish\r\n\r\nReady\r\nleftover");
        let seen = wait_ready(&mut port).unwrap();
        assert_eq!(seen.len(), 3);
        assert_eq!(seen[1], "Readyish");
        // Bytes after the banner stay unread for the first reply.
        assert_eq!(port.remaining(), b"leftover");
    }

    #[test]
    fn a_piece_of_the_banner_is_found_among_reply_bytes() {
        assert!(is_in(b"\x00\x01Starting\r\nMar"));
        assert!(is_in(b"1103\r\nReady\r\n"));
        // A reply's bytes that spell neither line whole, or Ready without its line end.
        assert!(!is_in(b"Startin"));
        assert!(!is_in(b"\x07Ready"));
        assert!(!is_in(&[0x00, 0x7f, 0xff, 0x0b]));
    }

    #[test]
    fn ready_must_match_exactly() {
        let mut port = FakePort::with_input(b" Ready\r\nready\r\nREADY\n");
        assert_eq!(
            wait_ready(&mut port),
            Err(BannerFailure::Silent { lines: 3 })
        );
    }

    #[test]
    fn ten_lines_without_ready_fail() {
        let mut input = Vec::new();
        for i in 0..MAX_LINES {
            input.extend_from_slice(format!("line {i}\r\n").as_bytes());
        }
        input.extend_from_slice(b"Ready\r\n");
        let mut port = FakePort::with_input(&input);
        assert_eq!(
            wait_ready(&mut port),
            Err(BannerFailure::NoReady {
                last: "line 9".into()
            })
        );
        assert_eq!(port.remaining(), b"Ready\r\n");
    }

    #[test]
    fn silence_fails_with_line_count() {
        let mut port = FakePort::with_input(b"Starting\r\npartial");
        assert_eq!(
            wait_ready(&mut port),
            Err(BannerFailure::Silent { lines: 1 })
        );
    }

    #[test]
    fn endless_line_counts_as_one_line() {
        let mut input = vec![b'x'; MAX_LINE_LEN];
        input.extend_from_slice(b"\nReady\n");
        let mut port = FakePort::with_input(&input);
        let seen = wait_ready(&mut port).unwrap();
        // The over-long run is cut at MAX_LINE_LEN, its LF ends an empty line.
        assert_eq!(seen.len(), 2);
        assert_eq!(seen[0].len(), MAX_LINE_LEN);
        assert_eq!(seen[1], "");
    }
}
