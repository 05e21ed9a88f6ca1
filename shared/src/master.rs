//! The master board's decisions about the PC link: what each frame does and what it
//! answers (see docs/protocol.md), the master-local registers of device 0, and the error
//! record behind REGMASTER_LASTERROR / REGMASTER_ERRORCOUNT. The firmware only moves
//! bytes; the I2C relay is behind the [`SlaveBus`] trait, so all of this runs on the host
//! against fake buses.

mod error;
mod local;
mod service;

pub use error::{LinkError, ERROR_REPLY_FLAG};
pub use local::LocalRegisters;
pub use service::{BusError, Service, SlaveBus};

#[cfg(test)]
mod tests;
