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
pub struct SerialPort {
    inner: Box<dyn serialport::SerialPort>,
}

impl SerialPort {
    /// Opens `path` at 115200 8N1 without flow control, then pulses DTR low
    /// for 10 ms to reset the master.
    ///
    /// A pty has no DTR line; that failure is ignored, and so is the input
    /// flush that would otherwise follow the reset (without a reset, bytes
    /// already waiting may be the banner we are about to look for).
    pub fn open(path: &str, timeout: Duration) -> Result<Self, serialport::Error> {
        let mut inner = serialport::new(path, BAUD)
            .data_bits(serialport::DataBits::Eight)
            .parity(serialport::Parity::None)
            .stop_bits(serialport::StopBits::One)
            .flow_control(serialport::FlowControl::None)
            .timeout(timeout)
            .open()?;
        let pulsed = inner.write_data_terminal_ready(false).is_ok();
        std::thread::sleep(DTR_PULSE);
        let raised = inner.write_data_terminal_ready(true).is_ok();
        if pulsed && raised {
            // The master is rebooting; anything already buffered predates it.
            let _ = inner.clear(serialport::ClearBuffer::Input);
        }
        Ok(Self { inner })
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
