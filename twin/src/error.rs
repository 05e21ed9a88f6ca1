//! The twin's error type.

use std::path::PathBuf;

use harness::twi::TwiError;
use harness::HarnessError;
use physics::PhysicsError;

/// What can go wrong while building, running or steering the twin.
#[derive(Debug, thiserror::Error)]
pub enum TwinError {
    /// A firmware image could not be loaded, or the pty could not be made.
    #[error(transparent)]
    Harness(#[from] HarnessError),
    /// A chip could not be put on the I²C bus.
    #[error("cannot put a chip on the I²C bus: {0}")]
    Bus(#[from] TwiError),
    /// The physics could not be attached or run.
    #[error(transparent)]
    Physics(#[from] PhysicsError),
    /// A wheel number outside 1..=6.
    #[error("wheel {0} does not exist: the rover has wheels 1 to 6")]
    NoSuchWheel(u8),
    /// A controller number outside 1..=9.
    #[error("controller {0} does not exist: the slave controllers are 1 to 9")]
    NoSuchController(u8),
    /// A temperature sensor index outside 0..=9.
    #[error("sensor {0} does not exist: sensors are 0 (ambient) and 1..9 (one per controller)")]
    NoSuchSensor(u8),
    /// An RC channel outside 0..=2.
    #[error("RC channel {0} does not exist: channels are 0 (drive), 1 (steer) and 2 (mode)")]
    NoSuchChannel(u8),
    /// The master's UART did not send what was awaited in time.
    #[error("the master sent no {what} within {waited_us} µs of emulated time (got {got:02x?}); is the master image built and booting?")]
    Timeout {
        /// What was awaited.
        what: String,
        /// Emulated microseconds waited.
        waited_us: u64,
        /// The bytes that did arrive.
        got: Vec<u8>,
    },
    /// A chip's CPU stopped (crashed or slept with interrupts off).
    #[error("chip {chip} ({name}) halted at {at_us} µs of emulated time; its firmware crashed")]
    Halted {
        /// The chip index (0 = master, n = controller n).
        chip: usize,
        /// The image it runs.
        name: String,
        /// Emulated time of the discovery.
        at_us: u64,
    },
    /// A twin already runs with this control socket (`--control`, or the one of `--link`).
    #[error("{}", already_running(control, link.as_deref()))]
    AlreadyRunning {
        /// Its control socket.
        control: PathBuf,
        /// The pty link the socket belongs to, when the socket is named after one.
        link: Option<PathBuf>,
    },
    /// A command that acts on the served port (`dtr`) was given where there is none, such
    /// as `--fault` at start.
    #[error("`{0}` acts on the port a running twin serves: send it over its control socket (`twin inject`)")]
    PortOnly(&'static str),
    /// The control socket or a link path failed.
    #[error("{what} {path}: {source}")]
    Io {
        /// What was being done.
        what: &'static str,
        /// The path involved.
        path: PathBuf,
        /// The operating system's error.
        source: std::io::Error,
    },
}

/// What to do about a twin already running: use it, stop it, or pick another link.
fn already_running(control: &std::path::Path, link: Option<&std::path::Path>) -> String {
    let use_it = match link {
        Some(link) => format!(
            "use it (`hostctl --port {} …`, `twin inject --control {} status`)",
            link.display(),
            control.display()
        ),
        None => format!(
            "use it (`twin inject --control {} status`)",
            control.display()
        ),
    };
    format!(
        "another twin is already running with control socket {}: {use_it}, stop it first \
         (Ctrl-C where it runs), or start this one with another --link (or --control)",
        control.display()
    )
}
