//! The rover twin: the real master image and the nine real slave images in the emulator, on
//! one shared I²C bus, with the physical rover (wheels, pots, currents) simulated around them.
//!
//! It sits where the rover's hardware would: `hostctl`, the tests and any program written for
//! the real rover talk to it as to the Uno's serial port. The library ([`Rover`]) runs in
//! emulated time for tests; the `twin` binary paces it to real time behind a pseudo-terminal.
//!
//! - [`Rover`]: chip 0 = master, chip n = controller n (DS boards 1, 2, 4, 5, 7, 8 run
//!   `slave-drive`, LL boards 3, 6, 9 run `slave-lift`, each with its address in EEPROM byte 0),
//!   a `physics` model closed around every slave, and fault injection.
//! - [`wiring`]: which board and motor slot serve each wheel.
//! - [`serial`]: the serial line and its byte-loss fault.
//! - [`command`]: fault injection and status as text commands; [`control`]: the Unix socket
//!   a running twin takes them on (`twin inject` is its client); [`paths`]: where the twin
//!   that `hostctl` starts by itself keeps its pty link and socket.
//! - [`serve`]: the loop that serves the rover behind a pty, paced to real time (the `twin`
//!   program's main loop).

pub mod command;
mod config;
pub mod control;
mod error;
mod faults;
pub mod leds;
pub mod paths;
mod rover;
pub mod serial;
pub mod serve;
mod speed;
mod status;
pub mod wiring;

pub use config::{
    default_threads, Config, DEFAULT_ANSWER_TIMEOUT_US, DEFAULT_QUANTUM_US, DEFAULT_SLICE_US,
    MAX_DEFAULT_THREADS,
};
pub use error::TwinError;
pub use rover::{start_half_degrees, Rover, WheelState, RC_CHANNELS, SENSORS};
pub use speed::Speed;
pub use status::status;
