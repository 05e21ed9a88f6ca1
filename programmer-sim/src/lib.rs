//! An emulated STK500 v1 programmer with an ATmega328P behind it, served on a
//! pseudo-terminal.
//!
//! This is the far end of `flash.sh --dry-run`: the script runs exactly the avrdude command
//! it would run against a real board, but points `-P` at this simulator's pseudo-terminal.
//! The simulator answers as the master's Uno bootloader ([`Mode::Bootloader`], avrdude
//! `-c arduino`) or as the in-system programmer used for the slave boards ([`Mode::Isp`],
//! avrdude `-c stk500v1` / `-c avrisp`), keeps the chip's flash and EEPROM in memory, and
//! on exit writes them as raw images so tests can check exactly what an upload would put
//! on the boards.
//!
//! Layers, each in its own module: [`stk`] (wire constants and framing), [`target`] (the
//! chip), [`isp`] (serial-programming instructions), [`session`] (the protocol state
//! machine), [`serve`](mod@serve) and [`pty`] (the terminal), [`json`] and [`output`] (what is saved).

pub mod error;
pub mod isp;
pub mod json;
pub mod output;
pub mod pty;
pub mod record;
pub mod serve;
pub mod session;
pub mod stk;
pub mod target;

pub use error::{MemError, SimError};
pub use serve::{serve, End};
pub use session::{Mode, Programmer};
pub use target::{Memory, Target};
