//! Emulator harness: runs real ATmega328P firmware images of the rover in
//! simavr, driven from Rust tests, the twin and host tools.
//!
//! It sits under the emulator tests (`rover-tests`) and the host-side twin: an
//! [`Avr`] is one Uno-class chip at 16 MHz with its UART0, GPIO, ADC, EEPROM and
//! watchdog; a [`Pty`] exposes its UART as a pseudo-terminal so `hostctl` can talk
//! to an emulated master as to a real serial port; the TWI bus module joins
//! several chips on one I²C bus through [`Avr::as_ptr`].
//!
//! # Why it is written over the raw FFI
//! The harness is written directly over `simavr-ffi` instead of an existing
//! higher-level tester because the rover needs what such a tester cannot give:
//! it cannot put two chips, or a TWI master peer, on one bus; it panics when
//! the firmware executes SLEEP and when the watchdog resets the chip; and its
//! UART polling sleeps in real time. Here:
//! - simavr's sleep callback is replaced by one that returns at once, so a
//!   sleeping CPU jumps to its next timer event in zero real time;
//! - UART0's real-time poll sleep and console echo flags are cleared;
//! - a watchdog reset restarts the firmware at its reset vector with MCUSR.WDRF
//!   set and EEPROM kept, and is counted ([`Avr::watchdog_resets`]);
//! - a crashed or finished CPU is reported ([`CpuState`], [`HarnessError::Halted`]),
//!   never spun on.
//!
//! # Example
//! ```no_run
//! use harness::{uno, Avr};
//!
//! let mut avr = Avr::firmware("fixture_uart_echo")?; // built by scripts/firmware.sh
//! let banner = avr.uart_read_until(b"\r\n", 10_000)?; // wait up to 10 ms of emulated time
//! avr.uart_send(b"hi");
//! assert_eq!(avr.uart_read_exact(2, 10_000)?, b"hi");
//! avr.set_pin(uno::D2, true);
//! # Ok::<(), harness::HarnessError>(())
//! ```
//!
//! # Pseudo-terminal
//! [`Pty`] makes UART0 a path a host program opens like the Uno's serial port.
//! A pty has no DTR line, so the Uno's auto-reset on open cannot be seen; a
//! caller that wants it calls [`Avr::reset`] when its host connects.
//!
//! # Timing facts
//! simavr applies the UART baud rate only when UBRR0 is written, and counts 11
//! bit times per byte: 1496 cycles = 93.5 µs per byte at 115200 (U2X0 = 1,
//! UBRR0 = 16). Bytes sent to the firmware arrive one per character time.

mod analog;
mod avr;
pub mod bus;
mod elf;
mod error;
mod fidelity;
mod gpio;
mod memory;
pub mod onewire;
mod pin;
mod pin_timer;
mod pty;
pub mod rc;
mod state;
pub mod twi;
mod uart;

pub use avr::{firmware_path, Avr, F_CPU};
pub use elf::{data_initial_bytes, flash_bytes};
pub use error::HarnessError;
pub use memory::EEPROM_SIZE;
pub use pin::{uno, Pin};
pub use pty::{Pty, SerialEnd};
pub use simavr_ffi;
pub use state::CpuState;
