//! The pseudo-terminal the host's avrdude opens as its serial port.

use crate::error::SimError;
use nix::pty::openpty;
use nix::sys::termios::{cfmakeraw, tcgetattr, tcsetattr, SetArg};
use std::fs::File;
use std::path::PathBuf;

/// An open pseudo-terminal: the controlling side the simulator serves, and the path of
/// the terminal side that avrdude opens.
#[derive(Debug)]
pub struct Pty {
    /// The controlling side, read and written by the simulator.
    pub master: File,
    /// Path of the terminal side, e.g. `/dev/pts/7`.
    pub path: PathBuf,
}

/// Opens a pseudo-terminal in raw mode (no echo, no line editing, 8-bit clean).
///
/// The simulator's own handle on the terminal side is closed before returning, so that
/// the controlling side reports a hang-up once the last program that opened the path
/// (avrdude) closes it.
pub fn open_raw() -> Result<Pty, SimError> {
    let pair = openpty(None, None).map_err(SimError::Pty)?;
    let mut termios = tcgetattr(&pair.slave).map_err(SimError::Pty)?;
    cfmakeraw(&mut termios);
    tcsetattr(&pair.slave, SetArg::TCSANOW, &termios).map_err(SimError::Pty)?;
    let path = nix::unistd::ttyname(&pair.slave).map_err(SimError::Pty)?;
    drop(pair.slave);
    Ok(Pty {
        master: File::from(pair.master),
        path,
    })
}
