//! The master board's decisions about the PC link: what each frame does and what it
//! answers (see docs/protocol.md), the master-local registers of device 0, and the error
//! record behind REGMASTER_LASTERROR / REGMASTER_ERRORCOUNT. The firmware only moves
//! bytes; the I2C relay is behind the [`SlaveBus`] trait, so all of this runs on the host
//! against fake buses.
//!
//! Also the master's other decisions: the schedule of slave traffic (boot resets, ping,
//! exception spreading, silent-slave detection) in [`ping`], the temperature sensors in
//! [`temperature`], remote control in [`rc`], the PC link's inter-byte timeout in [`timeout`]
//! and its opt-in silence failsafe in [`pc_watch`]; the interrupt queues' FIFO in [`ring`].

mod error;
mod local;
pub mod pc_watch;
pub mod ping;
pub mod rc;
pub mod ring;
mod service;
pub mod temperature;
pub mod timeout;

pub use error::{LinkError, ERROR_REPLY_FLAG};
pub use local::LocalRegisters;
pub use pc_watch::PcWatch;
pub use ping::{Action, Outcome, RegWrite, Schedule};
pub use rc::Remote;
pub use ring::Ring;
pub use service::{BusError, Service, SlaveBus};
pub use timeout::InterByteTimeout;

#[cfg(test)]
mod tests;
