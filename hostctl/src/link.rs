//! Request/response over a [`Port`]: send one frame, read its exact reply. A reply that
//! does not come is looked into by asking the master for its last link error since its
//! boot, so the message can name the likely cause instead of blaming the addressed device
//! (the error may be older than the failed frame: the message says so).

use std::io;
use std::path::Path;
use std::time::Duration;

use shared::master::LinkError;
use shared::protocol;
use shared::regs::id;

use crate::banner::{self, BannerFailure};
use crate::cmd::read::SCRATCH_SET;
use crate::error::{HostError, MasterSays};
use crate::port::{Port, SerialPort};
use crate::twin::Inject;

/// How long a reply may take (reference §4.7: 1 s, no retries).
pub const REPLY_TIMEOUT: Duration = Duration::from_secs(1);

/// How long each reply of the probe that follows a timeout may take: the master answers a
/// read of its own registers in a few ms, so a short wait keeps the failure quick.
pub const PROBE_TIMEOUT: Duration = Duration::from_millis(300);

/// How long a read of a controller that did not answer its last read waits for the reply:
/// as long as the probe. The master relays a reply as its I²C bytes come (the first within
/// a few ms), so a controller back on the bus is seen in this time, and one still off it
/// costs a view this, not the full [`REPLY_TIMEOUT`], each round.
pub const SILENT_REREAD_TIMEOUT: Duration = PROBE_TIMEOUT;

/// How long to wait for stray bytes of a late reply (before the probe, so they are not
/// taken for its answer), or for the rest of the bytes after a reply (so the next frame's
/// reply lines up).
pub const DRAIN_TIMEOUT: Duration = Duration::from_millis(50);

/// How long to wait after `Ready` before the first frame, so the slaves the
/// master has just hard-reset are back on the bus (reference §4.1, §13).
pub const SETTLE: Duration = Duration::from_secs(2);

/// How many replies in a row a view may lose on the serial line and go on
/// ([`Link::forgive`]): one lost byte costs one reply, while a line that loses every reply
/// is broken, and the view stops with the error rather than show nothing as if live.
pub const MAX_LOST_IN_A_ROW: u32 = 3;

/// The most stray bytes one check reads.
const STRAY_MAX: usize = 1024;

/// A connected link to the master.
pub struct Link<P: Port> {
    port: P,
    /// REGMASTER_ERRORCOUNT as the last probe after a timeout read it: tells a link error
    /// recorded since then from an older one (REGMASTER_LASTERROR keeps the last).
    errors_seen: Option<u16>,
    /// A bit per device (0..15) whose last read the master could not relay because the
    /// controller did not answer on I²C ([`Link::note_silent`]).
    silent: u16,
    /// Per read (device 0..15, set 0..7), its replies lost on the serial line since it last
    /// came whole ([`Link::forgive`]).
    lost_in_a_row: [u8; 128],
    /// Whether a probe has overwritten the scratch set since [`Link::take_scratch_clobbered`]
    /// last asked.
    scratch_clobbered: bool,
    /// How advice reaches the twin behind this port, if it is one.
    inject: Inject,
}

/// Opens the serial device at `path` (115200 8N1, DTR pulse), waits for the
/// banner and then for `settle`.
pub fn open_serial(path: &str, settle: Duration) -> Result<Link<SerialPort>, HostError> {
    check_port(Path::new(path))?;
    let port = SerialPort::open(path, banner::LINE_TIMEOUT).map_err(|source| HostError::Open {
        path: path.to_owned(),
        source,
    })?;
    Link::connect(port, path, settle)
}

/// Refuses a port that cannot be the rover's before anything touches it: a regular file,
/// or the link of a twin that is gone (its control socket left behind, not answering).
fn check_port(path: &Path) -> Result<(), HostError> {
    #[cfg(unix)]
    {
        let control = crate::twin::control_of(path);
        if control.exists() && !crate::twin::is_running(path) {
            return Err(HostError::TwinGone {
                path: path.display().to_string(),
                control: control.display().to_string(),
            });
        }
    }
    if std::fs::metadata(path).is_ok_and(|m| m.is_file()) {
        return Err(HostError::NotSerial {
            path: path.display().to_string(),
            what: "a regular file",
        });
    }
    Ok(())
}

impl<P: Port> Link<P> {
    /// Waits for the banner on `port` (named `path` in errors), then for
    /// `settle`, and returns the ready link.
    pub fn connect(mut port: P, path: &str, settle: Duration) -> Result<Self, HostError> {
        match banner::wait_ready(&mut port) {
            Ok(_) => {}
            Err(BannerFailure::Io(kind)) => return Err(HostError::Io(io::Error::from(kind))),
            Err(BannerFailure::Interrupted(signal)) => {
                return Err(HostError::Interrupted {
                    signal,
                    at: format!(
                        "while waiting for the master's banner, before the script started{}",
                        crate::interrupt::CLOSES
                    ),
                    line: None,
                })
            }
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
        Ok(Self {
            inject: Inject::for_port(path),
            ..Self::ready(port)
        })
    }

    /// Wraps a port that is already past the banner (tests, reconnects).
    pub fn ready(port: P) -> Self {
        Self {
            port,
            errors_seen: None,
            silent: 0,
            lost_in_a_row: [0; 128],
            scratch_clobbered: false,
            inject: Inject::default(),
        }
    }

    /// The `twin inject` command for the twin behind this port, for advice in messages.
    pub fn inject(&self) -> &Inject {
        &self.inject
    }

    /// REGMASTER_ERRORCOUNT as the last probe after a timeout read it (`None`: no probe
    /// has been answered in this session).
    pub fn errors_seen(&self) -> Option<u16> {
        self.errors_seen
    }

    /// Whether `device`'s last read was one its controller did not answer.
    pub fn was_silent(&self, device: u8) -> bool {
        self.silent & (1 << (device & 15)) != 0
    }

    /// Notes whether `device` answered its last read: a read of one that did not waits
    /// [`SILENT_REREAD_TIMEOUT`] ([`Link::reply_timeout`]).
    pub fn note_silent(&mut self, device: u8, silent: bool) {
        let bit = 1 << (device & 15);
        if silent {
            self.silent |= bit;
        } else {
            self.silent &= !bit;
        }
    }

    /// How long a read of `device` waits for its reply: [`REPLY_TIMEOUT`], or
    /// [`SILENT_REREAD_TIMEOUT`] after a read it did not answer.
    pub fn reply_timeout(&self, device: u8) -> Duration {
        if self.was_silent(device) {
            SILENT_REREAD_TIMEOUT
        } else {
            REPLY_TIMEOUT
        }
    }

    /// Whether a view may go on past `e`, a failed read of `set` from a device: a reply
    /// lost or garbled on the serial line while the master still answers, at most
    /// [`MAX_LOST_IN_A_ROW`] of that read's replies in a row ([`Link::note_whole`] starts
    /// the count again). `errors_before` is [`Link::errors_seen`] from before the read.
    ///
    /// Lost on the line means: the reply came whole with bytes after it (drained, and no
    /// banner among them), or the reply stopped short and the probe that followed found
    /// the master answering with either no new link error (the frame arrived whole, so the
    /// reply was lost on its way back) or a frame that lost a byte on its way (Truncated,
    /// Framing, Overrun), which the master has dropped. A master that does not answer, or
    /// answers that its read set is empty (it rebooted), is not forgiven.
    pub fn forgive(&mut self, e: &HostError, set: u8, errors_before: Option<u16>) -> bool {
        let device = match *e {
            HostError::Timeout {
                device,
                master: MasterSays::Answered { code, count },
                ..
            } if lost_on_the_line(code, count, errors_before) => device,
            HostError::OutOfStep { device, .. } => device,
            _ => return false,
        };
        let lost = &mut self.lost_in_a_row[read_index(device, set)];
        if u32::from(*lost) < MAX_LOST_IN_A_ROW {
            *lost += 1;
            true
        } else {
            false
        }
    }

    /// Notes that the read of `set` from `device` came through the serial line whole (its
    /// values, or the master's word that the controller did not answer): its count of lost
    /// replies ([`Link::forgive`]) starts again.
    pub fn note_whole(&mut self, device: u8, set: u8) {
        self.lost_in_a_row[read_index(device, set)] = 0;
    }

    /// Whether a probe after a timeout has overwritten the scratch set since the last call
    /// (a command that keeps a set of its own there configures it again); clears the flag.
    pub fn take_scratch_clobbered(&mut self) -> bool {
        std::mem::take(&mut self.scratch_clobbered)
    }

    /// The underlying port.
    pub fn port(&self) -> &P {
        &self.port
    }

    /// Sends `frame` to `device` and reads exactly `reply_len` bytes back.
    ///
    /// The master sends nothing unasked but its start-up banner, so bytes waiting before
    /// the frame, or after its reply, mean the reply cannot be trusted as the answer to
    /// this frame: a banner is a reboot ([`HostError::MasterRebooted`]), extra bytes after
    /// a reply put the link out of step ([`HostError::OutOfStep`]). Other bytes waiting
    /// before the frame are dropped, so that its reply lines up.
    pub fn transact(
        &mut self,
        device: u8,
        frame: &[u8],
        reply_len: usize,
    ) -> Result<Vec<u8>, HostError> {
        self.transact_within(device, frame, reply_len, REPLY_TIMEOUT)
    }

    /// [`Link::transact`], waiting at most `timeout` for each part of the reply.
    pub fn transact_within(
        &mut self,
        device: u8,
        frame: &[u8],
        reply_len: usize,
        timeout: Duration,
    ) -> Result<Vec<u8>, HostError> {
        if banner::is_in(&self.stray()?) {
            return Err(HostError::MasterRebooted);
        }
        let (mut reply, got) = self.exchange(frame, reply_len, timeout)?;
        if got < reply_len {
            // Late bytes are drained before the probe, so they are not taken for its answer;
            // a banner among them is a reboot.
            reply.truncate(got);
            reply.extend(self.late());
            if banner::is_in(&reply) {
                return Err(HostError::MasterRebooted);
            }
            return Err(HostError::Timeout {
                device,
                expected: reply_len,
                got,
                master: self.master_says(),
                inject: self.inject.clone(),
            });
        }
        let mut extra = self.stray()?;
        if !extra.is_empty() {
            // The rest of what is coming too, so the next frame's reply lines up.
            extra.extend(self.late());
            let mut all = reply;
            all.extend_from_slice(&extra);
            if banner::is_in(&all) {
                return Err(HostError::MasterRebooted);
            }
            return Err(HostError::OutOfStep {
                device,
                extra: extra.len(),
            });
        }
        Ok(reply)
    }

    /// The bytes waiting to be read now, without waiting for more.
    fn stray(&mut self) -> Result<Vec<u8>, HostError> {
        self.waiting(Duration::ZERO)
    }

    /// The bytes that arrive with no gap longer than `gap` (at most [`STRAY_MAX`], so a
    /// line that never falls silent cannot hold the command up).
    fn waiting(&mut self, gap: Duration) -> Result<Vec<u8>, HostError> {
        self.port.set_timeout(gap)?;
        let mut out = Vec::new();
        let mut buf = [0u8; 64];
        while out.len() < STRAY_MAX {
            match self.port.read(&mut buf) {
                Ok(0) => break,
                Ok(n) => out.extend_from_slice(&buf[..n]),
                Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
                Err(e)
                    if matches!(
                        e.kind(),
                        io::ErrorKind::TimedOut | io::ErrorKind::WouldBlock
                    ) =>
                {
                    break
                }
                Err(e) => return Err(HostError::Io(e)),
            }
        }
        Ok(out)
    }

    /// Sends `frame` and reads up to `reply_len` bytes, each read waiting at most
    /// `timeout`; returns the buffer and how many bytes came.
    fn exchange(
        &mut self,
        frame: &[u8],
        reply_len: usize,
        timeout: Duration,
    ) -> Result<(Vec<u8>, usize), HostError> {
        self.port.write_all(frame)?;
        self.port.flush()?;
        self.port.set_timeout(timeout)?;
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
        Ok((reply, got))
    }

    /// After a timeout: the master's REGMASTER_LASTERROR and REGMASTER_ERRORCOUNT, read
    /// through the scratch set with short timeouts, or [`MasterSays::Silent`]. This
    /// overwrites the scratch set: a command that goes on after a timeout (a view past a
    /// silent controller or a lost reply, [`crate::cmd::SetRead::read_for_view`])
    /// configures it again if it uses it ([`Link::take_scratch_clobbered`]).
    fn master_says(&mut self) -> MasterSays {
        self.scratch_clobbered = true;
        let ids = [id::REGMASTER_LASTERROR, id::REGMASTER_ERRORCOUNT];
        let mut set = heapless::Vec::<u8, { protocol::MAX_FRAME }>::new();
        if protocol::encode_set_read_set(0, SCRATCH_SET, &ids, &mut set).is_err() {
            return MasterSays::Silent;
        }
        match self.exchange(&set, 1, PROBE_TIMEOUT) {
            Ok((reply, 1)) if usize::from(reply[0]) == ids.len() => {}
            _ => return MasterSays::Silent,
        }
        // LASTERROR is one byte, ERRORCOUNT two (LSB first).
        let read = protocol::encode_read(0, SCRATCH_SET);
        match self.exchange(&read, 3, PROBE_TIMEOUT) {
            Ok((reply, 3)) => {
                let count = u16::from_le_bytes([reply[1], reply[2]]);
                self.errors_seen = Some(count);
                MasterSays::Answered {
                    code: reply[0],
                    count,
                }
            }
            _ => MasterSays::Silent,
        }
    }

    /// Whatever arrives within [`DRAIN_TIMEOUT`] of the last byte (at most [`STRAY_MAX`]);
    /// a failing port is left to the exchange that follows.
    fn late(&mut self) -> Vec<u8> {
        self.waiting(DRAIN_TIMEOUT).unwrap_or_default()
    }
}

/// A read's place in [`Link`]'s count of lost replies.
fn read_index(device: u8, set: u8) -> usize {
    usize::from(device & 15) * 8 + usize::from(set & 7)
}

/// Whether a probe's answer (`code`, `count`) after a short reply says the serial line lost
/// it: no link error since `before` (the errors seen at the last probe; none at all when
/// there was none), or a frame damaged on its way to the master. A length below 3 is such
/// damage too: hostctl never sends one, but a read frame that lost two bytes leaves its
/// last byte (a set number, 0..7) to be taken as a length. Never an empty read set: that
/// is a master that rebooted.
fn lost_on_the_line(code: u8, count: u16, before: Option<u16>) -> bool {
    let no_new_error = before == Some(count) || (before.is_none() && count == 0);
    let damaged = [
        LinkError::Truncated,
        LinkError::Framing,
        LinkError::Overrun,
        LinkError::BadLength,
    ]
    .iter()
    .any(|e| e.code() == code);
    code != LinkError::EmptyReadSet.code() && (no_new_error || damaged)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fake::FakePort;

    #[test]
    fn transact_reads_exactly_the_reply() {
        let mut link = Link::ready(FakePort::with_replies(&[[0xaa, 0xbb]]));
        let reply = link.transact(1, &[3, 0x13, 0], 2).unwrap();
        assert_eq!(reply, [0xaa, 0xbb]);
        assert_eq!(link.port().written, [3, 0x13, 0]);
        // A look for stray bytes before the frame and after the reply, neither waiting.
        assert_eq!(
            link.port().timeouts,
            [Duration::ZERO, REPLY_TIMEOUT, Duration::ZERO]
        );
    }

    #[test]
    fn a_reply_with_bytes_after_it_is_out_of_step_not_values() {
        let mut link = Link::ready(FakePort::with_replies(&[[0xaa, 0xbb, 0xcc]]));
        match link.transact(1, &[3, 0x13, 0], 2) {
            Err(HostError::OutOfStep {
                device: 1,
                extra: 1,
            }) => {}
            other => panic!("unexpected {other:?}"),
        }
    }

    #[test]
    fn a_banner_mid_session_is_a_reboot_and_nothing_is_sent() {
        let mut link = Link::ready(FakePort::with_input(
            b"Starting\r\nMar 29 2017 14:03:11\r\n1234\r\nReady\r\n",
        ));
        assert!(matches!(
            link.transact(1, &[3, 0x13, 0], 2),
            Err(HostError::MasterRebooted)
        ));
        assert!(link.port().written.is_empty());
    }

    #[test]
    fn a_banner_that_arrives_as_the_reply_is_a_reboot_not_values() {
        // The master reboots after the frame went out: its banner comes instead of the
        // reply, whole or as its tail ("Ready" last).
        for reply in [&b"Starting\r\nMar 29"[..], b"\r\nReady\r\n", b"Sta"] {
            let mut link = Link::ready(FakePort::with_replies(&[reply]));
            let len = if reply == b"Sta" { 8 } else { 2 };
            let result = link.transact(1, &[3, 0x13, 0], len);
            if reply == b"Sta" {
                // Three bytes of eight are no banner yet: a plain timeout.
                assert!(matches!(result, Err(HostError::Timeout { got: 3, .. })));
            } else {
                assert!(
                    matches!(result, Err(HostError::MasterRebooted)),
                    "{reply:?}: {result:?}"
                );
            }
        }
    }

    #[test]
    fn other_stray_bytes_before_a_frame_are_dropped_so_its_reply_lines_up() {
        // A late byte of some earlier answer, already waiting.
        let port = FakePort::with_input(&[0x7f]).replying(&[[0x01, 0x02]]);
        let mut link = Link::ready(port);
        assert_eq!(link.transact(2, &[3, 0x23, 0], 2).unwrap(), [0x01, 0x02]);
        assert_eq!(link.port().written, [3, 0x23, 0]);
    }

    #[test]
    fn short_reply_is_a_timeout() {
        let mut link = Link::ready(FakePort::with_replies(&[[0x01]]));
        match link.transact(4, &[3, 0x43, 0], 2) {
            Err(HostError::Timeout {
                device: 4,
                expected: 2,
                got: 1,
                master: MasterSays::Silent,
                ..
            }) => {}
            other => panic!("unexpected {other:?}"),
        }
    }

    #[test]
    fn only_a_reply_lost_on_the_line_is_forgiven_and_only_three_in_a_row_per_device() {
        let truncated = LinkError::Truncated.code();
        let empty = LinkError::EmptyReadSet.code();
        let no_answer = LinkError::NoAnswer.code();
        // (code, count, errors seen before): no new error, or a frame damaged on its way.
        assert!(lost_on_the_line(0, 0, None));
        assert!(lost_on_the_line(no_answer, 4, Some(4)));
        assert!(lost_on_the_line(truncated, 5, Some(4)));
        assert!(lost_on_the_line(LinkError::Overrun.code(), 1, None));
        // A read frame that lost two bytes: its set byte read as a length.
        assert!(lost_on_the_line(LinkError::BadLength.code(), 7, Some(6)));
        // A new error of another kind, an old one never probed, or a rebooted master: no.
        assert!(!lost_on_the_line(no_answer, 5, Some(4)));
        assert!(!lost_on_the_line(no_answer, 3, None));
        assert!(!lost_on_the_line(empty, 1, None));
        assert!(!lost_on_the_line(empty, 4, Some(4)));

        let timeout = |device, code| HostError::Timeout {
            device,
            expected: 2,
            got: 0,
            master: MasterSays::Answered { code, count: 1 },
            inject: Inject::default(),
        };
        let mut link = Link::ready(FakePort::default());
        for _ in 0..MAX_LOST_IN_A_ROW {
            assert!(link.forgive(&timeout(3, truncated), 1, Some(0)));
        }
        assert!(
            !link.forgive(&timeout(3, truncated), 1, Some(0)),
            "the fourth"
        );
        // Counted per read, and again from 0 after that read came whole.
        assert!(link.forgive(&timeout(6, truncated), 1, Some(0)));
        assert!(link.forgive(&timeout(3, truncated), 5, Some(0)));
        link.note_whole(3, 5);
        assert!(!link.forgive(&timeout(3, truncated), 1, Some(0)));
        link.note_whole(3, 1);
        assert!(link.forgive(&timeout(3, truncated), 1, Some(0)));
        // Bytes after a whole reply: forgiven; a silent master, a reboot: not.
        assert!(link.forgive(
            &HostError::OutOfStep {
                device: 4,
                extra: 1
            },
            1,
            None
        ));
        let silent = HostError::Timeout {
            device: 4,
            expected: 2,
            got: 0,
            master: MasterSays::Silent,
            inject: Inject::default(),
        };
        assert!(!link.forgive(&silent, 1, None));
        assert!(!link.forgive(&HostError::MasterRebooted, 1, None));
        assert!(!link.forgive(&timeout(4, empty), 1, None));
    }

    #[test]
    fn a_probe_marks_the_scratch_set_overwritten_once() {
        // A short reply, then the probe's two answers.
        let port = FakePort::with_replies(&[&[0x01][..], &[0x02], &[0x08, 0x01, 0x00]]);
        let mut link = Link::ready(port);
        assert!(!link.take_scratch_clobbered());
        assert!(link.transact(4, &[3, 0x43, 0], 2).is_err());
        assert!(link.take_scratch_clobbered());
        assert!(!link.take_scratch_clobbered(), "cleared by the question");
    }

    #[test]
    fn connect_waits_for_ready_and_sets_reply_timeout() {
        let port = FakePort::with_input(b"Starting\r\nReady\r\n");
        let link = Link::connect(port, "/dev/x", Duration::ZERO).unwrap();
        assert_eq!(link.port().timeouts, [banner::LINE_TIMEOUT, REPLY_TIMEOUT]);
        assert!(link.port().written.is_empty());
    }

    #[test]
    fn a_port_that_cannot_be_the_rover_s_is_refused_before_it_is_opened() {
        let dir = std::env::temp_dir().join(format!("hostctl-stale-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        // A twin killed without cleaning up: its link, and its socket that nobody answers.
        let link = dir.join("rover");
        std::os::unix::fs::symlink("/dev/null", &link).unwrap();
        let control = crate::twin::control_of(&link);
        drop(std::os::unix::net::UnixListener::bind(&control).unwrap());
        let refusal = |port: &Path| {
            let opened = open_serial(&port.display().to_string(), Duration::ZERO);
            opened.err().map(|e| e.to_string()).unwrap_or_default()
        };
        let err = refusal(&link);
        assert!(
            err.starts_with(&format!(
                "{} is the link of a twin that is gone (its control socket {} does not answer)",
                link.display(),
                control.display()
            )),
            "{err}"
        );
        // A regular file.
        let file = dir.join("notes.txt");
        std::fs::write(&file, "x").unwrap();
        let err = refusal(&file);
        assert!(
            err.starts_with(&format!(
                "{} is a regular file, not a serial device",
                file.display()
            )),
            "{err}"
        );
        let _ = std::fs::remove_dir_all(&dir);
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
             is the rover/twin running? is /dev/pts/9 right? does another program read it \
             (a serial monitor, ModemManager: `fuser /dev/pts/9` names it)? (a port last closed without \
             HUPCL, e.g. after `stty -hupcl`, does not reset the master when opened: run \
             `stty -F /dev/pts/9 hupcl` and retry; a twin told to lose serial bytes \
             loses the banner too: `twin inject --link /dev/pts/9 status` shows any still \
             pending, `drop-serial clear` cancels them)"
        );
    }
}
