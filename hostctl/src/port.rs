//! The byte pipe to the master: a small trait so tests can swap the serial
//! port for an in-memory fake, and the real serial implementation.

use std::io::{self, Read, Write};
use std::time::Duration;

/// A bidirectional byte stream with a settable read timeout.
///
/// A read that sees no byte within the timeout must fail with
/// [`io::ErrorKind::TimedOut`] (or return `Ok(0)`), never block forever.
pub trait Port: Read + Write {
    /// Sets how long one `read` call may wait for the first byte.
    fn set_timeout(&mut self, timeout: Duration) -> io::Result<()>;
}

/// Baud rate of the master's USB-serial link (8N1, no flow control).
pub const BAUD: u32 = 115_200;

/// How long DTR is held low to reset the master (the Uno's auto-reset).
pub const DTR_PULSE: Duration = Duration::from_millis(10);

/// The real link: a serial device such as `/dev/ttyACM0` or the twin's pty.
///
/// Closing it resets the master, which through its boot stops every motor: the port has
/// HUPCL set, as the original library sets it (reference §4.1), from the open and again at
/// the close (a program may clear it meanwhile: `stty -F PORT -hupcl`, an IDE), and the
/// close drops DTR itself where the device has the line, so the reset comes even while
/// another program holds the port open (its last close would not drop DTR). A twin's pty
/// has no modem lines: there the DTR writes go to the twin's control socket.
pub struct SerialPort {
    inner: Box<dyn serialport::SerialPort>,
    /// The descriptor `inner` owns, for HUPCL.
    #[cfg(unix)]
    fd: std::os::fd::RawFd,
    /// The control socket of the twin whose pty this is, if one serves the path.
    #[cfg(unix)]
    twin: Option<std::path::PathBuf>,
}

impl SerialPort {
    /// Opens `path` at 115200 8N1 without flow control and with HUPCL set, then pulses
    /// DTR low for 10 ms to reset the master.
    ///
    /// A pty has no DTR line; that failure is ignored, and so is the input
    /// flush that would otherwise follow the reset (without a reset, bytes
    /// already waiting may be the banner we are about to look for).
    pub fn open(path: &str, timeout: Duration) -> Result<Self, serialport::Error> {
        let builder = serialport::new(path, BAUD)
            .data_bits(serialport::DataBits::Eight)
            .parity(serialport::Parity::None)
            .stop_bits(serialport::StopBits::One)
            .flow_control(serialport::FlowControl::None)
            .timeout(timeout);
        #[cfg(unix)]
        let mut port = {
            use std::os::fd::AsRawFd;
            let native = builder.open_native()?;
            let fd = native.as_raw_fd();
            let control = crate::twin::control_of(std::path::Path::new(path));
            let port = Self {
                inner: Box::new(native),
                fd,
                twin: control.exists().then_some(control),
            };
            port.hang_up_on_close().map_err(io::Error::from)?;
            port
        };
        #[cfg(not(unix))]
        let mut port = Self {
            inner: builder.open()?,
        };
        let pulsed = port.set_dtr(false);
        std::thread::sleep(DTR_PULSE);
        let raised = port.set_dtr(true);
        if pulsed && raised {
            // The master is rebooting; anything already buffered predates it.
            let _ = port.inner.clear(serialport::ClearBuffer::Input);
        }
        Ok(port)
    }

    /// Sets DTR on the device's line or, on a twin's pty, through the twin; whether either
    /// took it.
    fn set_dtr(&mut self, high: bool) -> bool {
        if self.inner.write_data_terminal_ready(high).is_ok() {
            return true;
        }
        #[cfg(unix)]
        if let Some(control) = &self.twin {
            return crate::twin::set_dtr(control, high);
        }
        false
    }

    /// Sets HUPCL, so that the last close of the port drops DTR.
    #[cfg(unix)]
    fn hang_up_on_close(&self) -> nix::Result<()> {
        use nix::sys::termios::{tcgetattr, tcsetattr, ControlFlags, SetArg};
        // SAFETY: `inner` owns the descriptor until `self` is gone, past this borrow.
        let fd = unsafe { std::os::fd::BorrowedFd::borrow_raw(self.fd) };
        let mut termios = tcgetattr(fd)?;
        if !termios.control_flags.contains(ControlFlags::HUPCL) {
            termios.control_flags.insert(ControlFlags::HUPCL);
            tcsetattr(fd, SetArg::TCSANOW, &termios)?;
        }
        Ok(())
    }
}

impl Drop for SerialPort {
    fn drop(&mut self) {
        // Best effort: a port that is gone resets the master by itself (USB unplugged).
        #[cfg(unix)]
        let _ = self.hang_up_on_close();
        let _ = self.set_dtr(false);
    }
}

impl Read for SerialPort {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        self.inner.read(buf)
    }
}

impl Write for SerialPort {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        self.inner.write(buf)
    }

    fn flush(&mut self) -> io::Result<()> {
        self.inner.flush()
    }
}

impl Port for SerialPort {
    fn set_timeout(&mut self, timeout: Duration) -> io::Result<()> {
        self.inner.set_timeout(timeout).map_err(io::Error::from)
    }
}

/// A borrowed port is a port, so a caller can keep its port after the link
/// that used it is gone.
impl<P: Port + ?Sized> Port for &mut P {
    fn set_timeout(&mut self, timeout: Duration) -> io::Result<()> {
        (**self).set_timeout(timeout)
    }
}
