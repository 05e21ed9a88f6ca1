//! An emulated UART0 exposed as a pseudo-terminal, so a host program (hostctl,
//! a terminal) can open a path and talk to the emulated chip as to the Uno's
//! USB serial port.
//!
//! Bytes the host writes are queued with [`Avr::uart_send`] and reach the
//! firmware at the line rate; bytes the firmware sends are written to the host.
//! The pty is raw (no echo, no line editing, 8-bit clean), and the baud rate
//! the host sets is ignored: the emulated line runs at the firmware's rate.
//!
//! A pseudo-terminal has no DTR line, so the Uno's auto-reset when a host opens
//! the port cannot come from the line itself. Instead the pty watches its path with
//! inotify and follows DTR through the host programs' opens and closes: the first open
//! raises it, the last close drops it when the host left HUPCL set
//! ([`Pty::hangs_up_on_close`]) and leaves it up otherwise. [`Pty::take_dtr_reset`]
//! says when it moved in a way that resets an Uno, and the twin then resets its master.
//! The modem-control ioctls (TIOCMBIS/TIOCMBIC) fail on a pty, so a program cannot pulse
//! DTR on an open port here: it closes and reopens it instead. While no host has the port
//! open, firmware output is discarded, as bytes sent to a closed USB serial port are, so
//! a host that opens the port never reads a stale banner.

use std::fs::File;
use std::io::{self, Read, Write};
use std::os::fd::AsFd;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use nix::fcntl::{fcntl, FcntlArg, OFlag};
use nix::pty::openpty;
use nix::sys::inotify::{AddWatchFlags, InitFlags, Inotify};
use nix::sys::termios::{cfmakeraw, tcgetattr, tcsetattr, ControlFlags, SetArg};

use crate::{Avr, HarnessError};

/// A pseudo-terminal pair whose far end stands for the chip's serial port.
pub struct Pty {
    /// Our end (the "master" side of the pair), non-blocking.
    controller: File,
    /// The host's end, kept open so the controller never sees a hang-up while
    /// no host has the path open.
    _device: File,
    /// Path of the host's end, e.g. `/dev/pts/7`.
    path: PathBuf,
    /// Firmware output not yet accepted by the pty (its buffer was full).
    pending: Vec<u8>,
    /// Symlink made by [`Pty::link`], removed on drop.
    link: Option<PathBuf>,
    /// Watches the host's end for opens and closes by other programs.
    watch: Inotify,
    /// How many host opens of the path are currently open.
    host_opens: u32,
    /// DTR as the hosts left it: raised by the first open, dropped by the last close when
    /// HUPCL is set, left raised by a close without it.
    dtr_high: bool,
    /// DTR moved in a way that resets an Uno since [`Pty::take_dtr_reset`] last said so.
    dtr_reset: bool,
    /// HUPCL as last seen while a host had the port open: what a close that the next
    /// program's open follows at once is judged by, since by the time the close is seen
    /// the port's settings may be that program's.
    hupcl_while_open: bool,
}

/// The chip side of a [`Pty`]: where the host's bytes go and where the firmware's come
/// from. An [`Avr`] is one (its UART0); the twin, which puts a serial line with faults
/// between the host and a master chip that lives inside a bus, is another.
pub trait SerialEnd {
    /// Queues bytes the host sent, towards the firmware.
    fn host_sent(&mut self, bytes: &[u8]);
    /// Takes the bytes the firmware sent since the last call.
    fn firmware_output(&mut self) -> Vec<u8>;
}

impl SerialEnd for Avr {
    fn host_sent(&mut self, bytes: &[u8]) {
        self.uart_send(bytes);
    }

    fn firmware_output(&mut self) -> Vec<u8> {
        self.uart_take()
    }
}

impl Pty {
    /// Opens a new raw pseudo-terminal.
    pub fn open() -> Result<Pty, HarnessError> {
        let pair = openpty(None, None)?;
        let mut termios = tcgetattr(&pair.slave)?;
        cfmakeraw(&mut termios);
        // HUPCL on, as a USB serial port starts (a pty starts without it), so a host
        // that keeps the default resets the board when it closes the port.
        termios.control_flags.insert(ControlFlags::HUPCL);
        tcsetattr(&pair.slave, SetArg::TCSANOW, &termios)?;
        let flags = OFlag::from_bits_truncate(fcntl(pair.master.as_fd(), FcntlArg::F_GETFL)?);
        fcntl(
            pair.master.as_fd(),
            FcntlArg::F_SETFL(flags | OFlag::O_NONBLOCK),
        )?;
        let path = nix::unistd::ttyname(&pair.slave)?;
        // Watch only after our own open, so only host programs' opens are seen.
        let watch = Inotify::init(InitFlags::IN_NONBLOCK | InitFlags::IN_CLOEXEC)?;
        watch.add_watch(
            &path,
            AddWatchFlags::IN_OPEN
                | AddWatchFlags::IN_CLOSE_WRITE
                | AddWatchFlags::IN_CLOSE_NOWRITE,
        )?;
        Ok(Pty {
            controller: File::from(pair.master),
            _device: File::from(pair.slave),
            path,
            pending: Vec::new(),
            link: None,
            watch,
            host_opens: 0,
            dtr_high: false,
            dtr_reset: false,
            hupcl_while_open: true,
        })
    }

    /// Whether a host program has the port open.
    pub fn host_connected(&self) -> bool {
        self.host_opens > 0
    }

    /// Whether closing the port drops DTR: the termios HUPCL flag the host left set (the
    /// default, and what the original PC library sets). On an Uno that resets the board
    /// (reference §4.1). Read from the port's own settings, which outlive the host's close
    /// because this side keeps the port open.
    pub fn hangs_up_on_close(&self) -> bool {
        tcgetattr(&self._device).is_ok_and(|t| t.control_flags.contains(ControlFlags::HUPCL))
    }

    /// Whether DTR has moved since the last call in a way that resets an Uno (reference
    /// §4.1): raised by an open while it was down, or dropped by the last close with HUPCL
    /// set. A close and an open between two calls make one reset.
    pub fn take_dtr_reset(&mut self) -> bool {
        self.poll_watch();
        std::mem::take(&mut self.dtr_reset)
    }

    /// Counts the opens and closes inotify has seen and follows DTR through them.
    fn poll_watch(&mut self) {
        let mut events = Vec::new();
        while let Ok(batch) = self.watch.read_events() {
            if batch.is_empty() {
                break;
            }
            events.extend(batch.into_iter().map(|e| e.mask));
        }
        for (i, mask) in events.iter().enumerate() {
            if mask.contains(AddWatchFlags::IN_OPEN) {
                // Only the first open can raise DTR: a second program opening a port
                // already open (`stty -F`, a second hostctl) resets nothing.
                if self.host_opens == 0 {
                    self.pending.clear();
                    if !self.dtr_high {
                        self.dtr_high = true;
                        self.dtr_reset = true;
                    }
                }
                self.host_opens += 1;
            } else {
                self.host_opens = self.host_opens.saturating_sub(1);
                if self.host_opens == 0 && self.dtr_high {
                    // The port's settings now are the closer's, unless another program
                    // has opened it since (and may have changed them): then the last ones
                    // seen while the closer had it.
                    let reopened = events[i + 1..]
                        .iter()
                        .any(|m| m.contains(AddWatchFlags::IN_OPEN));
                    let hupcl = if reopened {
                        self.hupcl_while_open
                    } else {
                        self.hangs_up_on_close()
                    };
                    // A host that dropped DTR already ([`Pty::set_dtr`]) makes no second
                    // edge.
                    if hupcl {
                        self.dtr_high = false;
                        self.dtr_reset = true;
                    }
                }
            }
        }
        if self.host_opens > 0 {
            self.hupcl_while_open = self.hangs_up_on_close();
        }
    }

    /// Sets DTR as a host set it through the twin's control socket: a pty has no modem
    /// lines, so hostctl sends this way the DTR writes it makes on a USB serial port (its
    /// open's 10-ms pulse, its close's drop), which reach the board there whoever else
    /// holds the port. A change resets an Uno, as a first open or a last close does.
    pub fn set_dtr(&mut self, high: bool) {
        // Opens and closes already made first, so a drop told after a close counts once.
        self.poll_watch();
        if self.dtr_high != high {
            self.dtr_high = high;
            self.dtr_reset = true;
        }
    }

    /// The path a host program opens, e.g. `/dev/pts/7`.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Makes `at` a symlink to the pty (e.g. `/tmp/rover-master`), replacing a stale
    /// symlink there (never a regular file); removed on drop. A second call moves it.
    pub fn link(&mut self, at: &Path) -> io::Result<()> {
        self.remove_link();
        if std::fs::symlink_metadata(at).is_ok_and(|m| m.file_type().is_symlink()) {
            std::fs::remove_file(at)?;
        }
        std::os::unix::fs::symlink(&self.path, at)?;
        self.link = Some(at.to_path_buf());
        Ok(())
    }

    /// Moves bytes both ways without running the emulation: host bytes are queued
    /// for the firmware (delivered at the line rate as it runs), firmware bytes are
    /// written to the host.
    pub fn pump(&mut self, avr: &mut Avr) -> io::Result<()> {
        self.pump_end(avr)
    }

    /// Drops the bytes host programs wrote that are not read yet: at a reset of the board
    /// they would otherwise reach its next boot, where on an Uno they reach the old
    /// session's firmware or its bootloader, never the next session's.
    pub fn discard_input(&mut self) -> io::Result<()> {
        let mut buf = [0u8; 512];
        loop {
            match self.controller.read(&mut buf) {
                Ok(0) => return Ok(()),
                Ok(_) => {}
                Err(e) if e.kind() == io::ErrorKind::WouldBlock => return Ok(()),
                Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
                Err(e) => return Err(e),
            }
        }
    }

    /// [`Pty::pump`] for any [`SerialEnd`], e.g. a twin that models the line between the
    /// host and the chip (lost bytes) or whose chip sits inside a bus.
    pub fn pump_end(&mut self, end: &mut dyn SerialEnd) -> io::Result<()> {
        self.poll_watch();
        if !self.host_connected() {
            // Nobody listens: the bytes are lost, as on a closed serial port.
            end.firmware_output();
            self.pending.clear();
            return Ok(());
        }
        let mut buf = [0u8; 512];
        loop {
            match self.controller.read(&mut buf) {
                Ok(0) => break,
                Ok(n) => end.host_sent(&buf[..n]),
                Err(e) if e.kind() == io::ErrorKind::WouldBlock => break,
                Err(e) if e.kind() == io::ErrorKind::Interrupted => continue,
                Err(e) => return Err(e),
            }
        }
        self.pending.extend(end.firmware_output());
        while !self.pending.is_empty() {
            match self.controller.write(&self.pending) {
                Ok(n) => {
                    self.pending.drain(..n);
                }
                Err(e) if e.kind() == io::ErrorKind::WouldBlock => break,
                Err(e) if e.kind() == io::ErrorKind::Interrupted => continue,
                Err(e) => return Err(e),
            }
        }
        Ok(())
    }

    /// Runs the emulation paced to the wall clock for `wall` (emulated time never
    /// runs ahead of real time), pumping bytes every `slice` of emulated time.
    /// This is how a twin serves a host program that uses real-time timeouts.
    pub fn serve(&mut self, avr: &mut Avr, wall: Duration, slice: Duration) -> io::Result<()> {
        let start = Instant::now();
        let emu_start = avr.micros();
        let slice_us = u64::try_from(slice.as_micros()).unwrap_or(u64::MAX).max(1);
        while start.elapsed() < wall && !avr.state().is_halted() {
            self.pump(avr)?;
            avr.run_us(slice_us);
            self.pump(avr)?;
            let emulated = Duration::from_micros(avr.micros() - emu_start);
            if let Some(ahead) = emulated.checked_sub(start.elapsed()) {
                std::thread::sleep(ahead);
            }
        }
        Ok(())
    }

    fn remove_link(&mut self) {
        if let Some(link) = self.link.take() {
            // Best effort: a link someone else already removed is fine.
            let _ = std::fs::remove_file(link);
        }
    }
}

impl Drop for Pty {
    fn drop(&mut self) {
        self.remove_link();
    }
}
