//! Serving the twin behind a pseudo-terminal: the loop of the `twin` program, also used by
//! tests that open the pty as a host program would.
//!
//! Each turn of the loop: reset the master if a program has just opened the port (the Uno's
//! DTR auto-reset), closed it with HUPCL set, or told DTR's change over the control socket
//! (`dtr`), move bytes between the pty and the master's serial line, run a slice of
//! emulated time, move bytes again, answer the control socket, and (when paced) sleep until
//! the wall clock has caught up with emulated time.

use std::path::Path;
use std::time::{Duration, Instant};

use harness::Pty;

use crate::command::Command;
use crate::control::ControlSocket;
use crate::{Rover, TwinError};

/// Emulated time run between two looks at the pty and the control socket.
pub const SLICE_US: u64 = 1_000;

/// When a [`Server`] stops by itself.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Limits {
    /// After this much emulated time.
    pub emulated: Option<Duration>,
    /// After this much wall-clock time during which no program had the port open.
    pub idle: Option<Duration>,
}

/// Why [`Server::serve`] returned.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stopped {
    /// The stop flag was raised (a signal).
    Asked,
    /// The emulated-time limit was reached.
    Emulated,
    /// Nobody used the port for the idle limit.
    Idle,
}

/// The rover behind a pty (and optionally a control socket).
pub struct Server {
    rover: Rover,
    pty: Pty,
    control: Option<ControlSocket>,
    paced: bool,
}

/// Parses and applies one command line; the reply says what happened. `dtr` goes to the
/// port, the rest to the rover.
pub fn handle(rover: &mut Rover, pty: &mut Pty, line: &str) -> String {
    match Command::parse(line) {
        Ok(Command::Dtr(high)) => {
            pty.set_dtr(high);
            format!("DTR {}", if high { "high" } else { "low" })
        }
        Ok(c) => match c.apply(rover) {
            Ok(text) => text,
            Err(e) => format!("error: {e}"),
        },
        Err(e) => format!("error: {e}"),
    }
}

/// A failure of `pty`'s file.
fn pty_failed(pty: &Pty, source: std::io::Error) -> TwinError {
    TwinError::Io {
        what: "the pty failed:",
        path: pty.path().to_path_buf(),
        source,
    }
}

impl Server {
    /// Serves `rover` on `pty`, paced to real time unless `paced` is false.
    pub fn new(rover: Rover, pty: Pty, control: Option<ControlSocket>, paced: bool) -> Server {
        Server {
            rover,
            pty,
            control,
            paced,
        }
    }

    /// The pty's path.
    pub fn path(&self) -> &Path {
        self.pty.path()
    }

    /// The rover served.
    pub fn rover(&mut self) -> &mut Rover {
        &mut self.rover
    }

    /// Whether a host program has the port open.
    pub fn host_connected(&self) -> bool {
        self.pty.host_connected()
    }

    fn pump(&mut self) -> Result<(), TwinError> {
        // The Uno resets when DTR rises as a program opens the port (the auto-reset) and,
        // with HUPCL set, when it drops as the last one closes it (reference §4.1): the
        // master then hard-resets every slave, so a rover left driving stops with its
        // program. Bytes a program wrote before the reset die with it: on the Uno they reach
        // the old session's firmware or the bootloader, never the next session.
        if self.pty.take_dtr_reset() {
            let discarded = self.pty.discard_input();
            discarded.map_err(|e| pty_failed(&self.pty, e))?;
            self.rover.reset_master();
        }
        let pumped = self.pty.pump_end(&mut self.rover);
        pumped.map_err(|e| pty_failed(&self.pty, e))
    }

    /// One turn: pump, run [`SLICE_US`], pump, answer the control socket (no pacing).
    pub fn step(&mut self) -> Result<(), TwinError> {
        self.pump()?;
        self.rover.run_us(SLICE_US)?;
        self.pump()?;
        if let Some(socket) = &mut self.control {
            let (rover, pty) = (&mut self.rover, &mut self.pty);
            socket.serve(&mut |line| handle(rover, pty, line));
        }
        Ok(())
    }

    /// Serves until `stop` returns true, a limit is reached or something fails; calls
    /// `every` about once per wall-clock second with the emulated and wall time so far.
    pub fn serve(
        &mut self,
        limits: Limits,
        stop: &dyn Fn() -> bool,
        every: &mut dyn FnMut(&Rover, Duration, Duration),
    ) -> Result<Stopped, TwinError> {
        let wall_start = Instant::now();
        let emu_start = self.rover.micros();
        let mut last_report = Instant::now();
        let mut idle_since = Some(Instant::now());
        loop {
            if stop() {
                return Ok(Stopped::Asked);
            }
            self.step()?;
            let emulated = Duration::from_micros(self.rover.micros() - emu_start);
            if limits.emulated.is_some_and(|limit| emulated >= limit) {
                return Ok(Stopped::Emulated);
            }
            if self.paced {
                if let Some(ahead) = emulated.checked_sub(wall_start.elapsed()) {
                    std::thread::sleep(ahead);
                }
            }
            if last_report.elapsed() >= Duration::from_secs(1) {
                last_report = Instant::now();
                every(&self.rover, emulated, wall_start.elapsed());
            }
            if self.pty.host_connected() {
                idle_since = None;
            } else {
                let since = *idle_since.get_or_insert_with(Instant::now);
                if limits.idle.is_some_and(|limit| since.elapsed() >= limit) {
                    return Ok(Stopped::Idle);
                }
            }
        }
    }
}
