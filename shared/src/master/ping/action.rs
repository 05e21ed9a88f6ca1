//! What the schedule asks the firmware to do, and what the firmware reports back.

use crate::protocol::sizes::Sizes;

/// One register write to a board: the id, then its value bytes, LSB first.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct RegWrite {
    /// The board: 1..9 a slave, 0 the master itself (served locally).
    pub device: u8,
    /// The register id.
    pub id: u8,
    value: [u8; 2],
    len: u8,
}

impl RegWrite {
    /// A write of a 1-byte register.
    pub const fn byte(device: u8, id: u8, value: u8) -> Self {
        RegWrite {
            device,
            id,
            value: [value, 0],
            len: 1,
        }
    }

    /// A write of a 2-byte register.
    pub const fn word(device: u8, id: u8, value: u16) -> Self {
        let [lo, hi] = value.to_le_bytes();
        RegWrite {
            device,
            id,
            value: [lo, hi],
            len: 2,
        }
    }

    /// A write of `raw`, sized by the device's table; `None` if the device or the id
    /// does not exist.
    pub fn sized(device: u8, id: u8, raw: u16) -> Option<Self> {
        match Sizes::of_device(device)?.size_of(id)? {
            1 => Some(RegWrite::byte(device, id, raw as u8)),
            _ => Some(RegWrite::word(device, id, raw)),
        }
    }

    /// The value bytes as they go on the wire after the id, LSB first.
    pub fn bytes(&self) -> &[u8] {
        // `len` is 1 or 2 (the constructors set it).
        self.value
            .get(..usize::from(self.len))
            .unwrap_or(&self.value)
    }

    /// The value as a number.
    pub const fn raw(&self) -> u16 {
        u16::from_le_bytes(self.value)
    }
}

/// One thing for the firmware to do now.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
// Numbered from 1 so that no action in flight is stored as 0 (see `Job`).
#[repr(u8)]
pub enum Action {
    /// Write one slave register (one I2C transaction).
    WriteReg(RegWrite) = 1,
    /// Read REG_STATUS (2 bytes) of a slave; report [`Outcome::Value`].
    ReadStatus {
        /// The slave, 1..9.
        device: u8,
    },
    /// Read REG_EXCEPTIONDATA (2 bytes) of a slave; report [`Outcome::Value`].
    ReadExceptionData {
        /// The slave, 1..9.
        device: u8,
    },
    /// Run one temperature tick on the OneWire bus (see `temperature::Poller`); report
    /// [`Outcome::Done`].
    TemperatureTick,
}

impl Action {
    /// The slave the action addresses on I2C, if any.
    pub const fn device(&self) -> Option<u8> {
        match self {
            Action::WriteReg(w) => Some(w.device),
            Action::ReadStatus { device } | Action::ReadExceptionData { device } => Some(*device),
            Action::TemperatureTick => None,
        }
    }
}

/// What happened when the firmware performed an action.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Outcome {
    /// A write was acknowledged, or a tick ran.
    Done,
    /// A read returned this value (its two bytes, LSB first).
    Value(u16),
    /// The slave did not answer: no acknowledge, no data, or the bus timed out.
    NoAnswer,
}
