//! The slave's exception state machine (reference §6, the manual's figure 12).
//!
//! ```text
//!            power-up / watchdog reset
//!                      │
//!                      ▼
//!        ┌──── Exception(Boot) ◄──────────────────────────┐
//!        │             │ Leave (RESET bit 0)              │
//!        │             ▼                                  │
//!        │   Running { last } ──Fault (unmasked)──► Exception(Local)
//!        │             │  ▲    ──RemoteWrite (unmasked)──► Exception(Remote)
//!        │             │  └──────── Leave ────────────────┘
//!        │             │
//!        └─ HardReset (RESET bit 1), from any state ──► Restarting ──► (watchdog) power-up
//! ```
//!
//! BusSilence (new, [`super::silence`]) is raised from Running like a fault and enters
//! Exception(BusSilent). In an exception, further faults, remote writes and bus silence
//! change nothing: only the first is latched. A type whose bit is set in DISABLEDEXCEPTIONS is never raised. BOOT is never
//! raised; it is where every power-up starts.

use super::board::MotorId;
use crate::exception::ExceptionType;

/// A fault a slave detects on one of its own motors.
///
/// Each variant's discriminant is its type's wire code, so [`LocalFault::kind`] (and
/// [`Cause::kind`], whose other variants the compiler places in the codes no fault
/// uses) is mostly the byte itself on the AVR.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
#[repr(u8)]
pub enum LocalFault {
    /// Current above the threshold at duty > 250.
    Overcurrent = ExceptionType::Overcurrent as u8,
    /// Current above the threshold at duty ≤ 250: a short.
    ShortOc = ExceptionType::ShortOc as u8,
    /// Duty above STALLCHECK, no motion, nominal current: the motor is blocked.
    Stall = ExceptionType::Stall as u8,
    /// Duty above STALLCHECK, no motion, low current: the sensor misses the motion.
    EncoderFault = ExceptionType::EncoderFault as u8,
    /// Duty above STALLCHECK, no motion, no current: the motor or its wiring is open.
    DriveFault = ExceptionType::DriveFault as u8,
}

impl LocalFault {
    /// The exception type that travels in EXCEPTIONDATA.
    pub const fn kind(self) -> ExceptionType {
        match self {
            LocalFault::Overcurrent => ExceptionType::Overcurrent,
            LocalFault::ShortOc => ExceptionType::ShortOc,
            LocalFault::Stall => ExceptionType::Stall,
            LocalFault::EncoderFault => ExceptionType::EncoderFault,
            LocalFault::DriveFault => ExceptionType::DriveFault,
        }
    }
}

/// Why a slave is (or last was) in exception.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Cause {
    /// Power-up or a watchdog reset.
    Boot,
    /// A write to REG_EXCEPTIONDATA: another board's fault, spread by the master.
    Remote,
    /// Armed by a ping, the board heard no bus transaction for BUSTIMEOUT ms (new; see
    /// [`super::silence`]).
    BusSilent,
    /// A fault on one of this board's motors.
    Local {
        /// What went wrong.
        fault: LocalFault,
        /// On which motor.
        motor: MotorId,
    },
}

/// EXCEPTIONDATA's motor byte when the exception concerns no motor.
pub const NO_MOTOR: u8 = 5;

impl Cause {
    /// The exception type.
    #[inline(never)]
    pub const fn kind(self) -> ExceptionType {
        match self {
            Cause::Boot => ExceptionType::Boot,
            Cause::Remote => ExceptionType::RemoteSlave,
            Cause::BusSilent => ExceptionType::BusSilent,
            Cause::Local { fault, .. } => fault.kind(),
        }
    }

    /// The motor concerned, if any.
    pub const fn motor(self) -> Option<MotorId> {
        match self {
            Cause::Local { motor, .. } => Some(motor),
            Cause::Boot | Cause::Remote | Cause::BusSilent => None,
        }
    }

    /// REG_EXCEPTIONDATA: type in the low byte, motor (0, 1, or 5 for none) in the high.
    pub const fn data(self) -> u16 {
        let motor = match self.motor() {
            Some(m) => m as u8,
            None => NO_MOTOR,
        };
        (motor as u16) << 8 | self.kind().code() as u16
    }
}

/// The slave's exception state.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum State {
    /// In exception. Motors are stopped (at boot: forward, duty 0).
    Exception(Cause),
    /// Running normally; EXCEPTIONDATA still shows the last exception.
    Running {
        /// The exception last left.
        last: Cause,
    },
    /// A hard reset was asked for: the watchdog is left to fire, motors are stopped.
    Restarting {
        /// What EXCEPTIONDATA showed when the reset was asked for.
        last: Cause,
    },
}

/// Something that may change the exception state.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Event {
    /// A local fault was detected.
    Fault {
        /// What went wrong.
        fault: LocalFault,
        /// On which motor.
        motor: MotorId,
    },
    /// REG_EXCEPTIONDATA was written.
    RemoteWrite,
    /// The bus-silence watch expired.
    BusSilence,
    /// REG_RESET bit 0: leave the exception.
    Leave,
    /// REG_RESET bit 1: reset the board through the watchdog.
    HardReset,
}

/// What an event did.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Transition {
    /// Nothing changed (already in exception, or nothing to leave, or restarting).
    Unchanged,
    /// The exception's type is disabled in DISABLEDEXCEPTIONS: nothing changed.
    Masked,
    /// The slave entered an exception.
    Entered(Cause),
    /// The slave left its exception and runs.
    Left,
    /// The slave is restarting through the watchdog.
    Restart,
}

/// REG_RESET's bits.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct ResetBits(pub u8);

impl ResetBits {
    /// Bit 0: leave the exception.
    pub const LEAVE: u8 = 1;
    /// Bit 1: hard reset.
    pub const HARD: u8 = 2;
    /// Bit 2: zero the odometer (DS).
    pub const ODOMETER: u8 = 4;

    /// The state-machine events these bits stand for, in the original's order: a hard
    /// reset alone (the original spins until the watchdog fires, so nothing after it
    /// runs), otherwise leaving the exception.
    pub const fn event(self) -> Option<Event> {
        // Neither bit first: one test before the choice of two events.
        if self.0 & (Self::HARD | Self::LEAVE) == 0 {
            None
        } else if self.0 & Self::HARD != 0 {
            Some(Event::HardReset)
        } else {
            Some(Event::Leave)
        }
    }

    /// Whether the odometer is to be zeroed (never with a hard reset, which comes first).
    pub const fn zero_odometer(self) -> bool {
        self.0 & Self::HARD == 0 && self.0 & Self::ODOMETER != 0
    }
}

impl State {
    /// The state at power-up: the boot exception.
    pub const POWER_UP: State = State::Exception(Cause::Boot);

    /// [`State::POWER_UP`]'s bytes, for the firmware's core made from zeroed memory
    /// ([`super::image`]): the state's tag, then the cause's, which the compiler keeps
    /// in the fault's spare values; the motor's byte is unused. Every field of a state
    /// is one byte wide, so the layout is the same on the AVR and the host. Checked by a
    /// test here and at compile time in the firmware, where these bytes are read back
    /// as a state.
    pub const POWER_UP_BYTES: [u8; 3] = [0, 2, 0];

    /// Applies an event. `disabled` is REG_DISABLEDEXCEPTIONS: type t is never raised
    /// while bit (1 << t) is set.
    ///
    /// Decided by the state first (restarting takes nothing; running or not) and the
    /// event second, with one store of the new state per outcome (tested against the
    /// table of every state and event pair).
    pub fn handle(&mut self, event: Event, disabled: u16) -> Transition {
        let (last, running) = match *self {
            State::Restarting { .. } => return Transition::Unchanged,
            State::Exception(cause) => (cause, false),
            State::Running { last } => (last, true),
        };
        let cause = match event {
            Event::HardReset => {
                *self = State::Restarting { last };
                return Transition::Restart;
            }
            Event::Leave if running => return Transition::Unchanged,
            Event::Leave => {
                *self = State::Running { last };
                return Transition::Left;
            }
            // In an exception only the first is latched.
            _ if !running => return Transition::Unchanged,
            Event::Fault { fault, motor } => Cause::Local { fault, motor },
            Event::RemoteWrite => Cause::Remote,
            Event::BusSilence => Cause::BusSilent,
        };
        let bit = 1u16
            .checked_shl(u32::from(cause.kind().code()))
            .unwrap_or(0);
        if disabled & bit != 0 {
            return Transition::Masked;
        }
        *self = State::Exception(cause);
        Transition::Entered(cause)
    }

    /// Whether REG_STATUS bit 0 is set: in exception, or restarting.
    pub const fn in_exception(&self) -> bool {
        !matches!(self, State::Running { .. })
    }

    /// REG_EXCEPTIONDATA: the current exception, or the last one while running.
    pub const fn data(&self) -> u16 {
        match self {
            State::Exception(cause)
            | State::Running { last: cause }
            | State::Restarting { last: cause } => cause.data(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reset_bits_give_the_events_of_the_hard_bit_first_form_for_every_byte() {
        let mut events = [0; 3];
        for byte in 0..=u8::MAX {
            // The form before the neither-bit test: hard reset first, then leave.
            let expected = if byte & ResetBits::HARD != 0 {
                Some(Event::HardReset)
            } else if byte & ResetBits::LEAVE != 0 {
                Some(Event::Leave)
            } else {
                None
            };
            assert_eq!(ResetBits(byte).event(), expected, "{byte:#x}");
            events[match expected {
                None => 0,
                Some(Event::Leave) => 1,
                _ => 2,
            }] += 1;
        }
        assert_eq!(events, [64, 64, 128]);
    }

    #[test]
    #[allow(unsafe_code)]
    fn the_power_up_bytes_are_the_power_up_state() {
        assert_eq!(core::mem::size_of::<State>(), State::POWER_UP_BYTES.len());
        // SAFETY: the test is that these bytes are a valid state, and this one.
        let state: State = unsafe { core::mem::transmute(State::POWER_UP_BYTES) };
        assert_eq!(state, State::POWER_UP);
        // Another cause in the same place is another state.
        let [tag, _, motor] = State::POWER_UP_BYTES;
        // SAFETY: the boot cause's neighbour among the spare values: the remote cause.
        let remote: State = unsafe { core::mem::transmute([tag, 3, motor]) };
        assert_eq!(remote, State::Exception(Cause::Remote));
    }

    /// The transition table written out pair by pair (the form [`State::handle`]
    /// replaced).
    fn table(current: State, event: Event, disabled: u16) -> (State, Transition) {
        let raise = |cause: Cause| {
            let bit = 1u16
                .checked_shl(u32::from(cause.kind().code()))
                .unwrap_or(0);
            if disabled & bit != 0 {
                (current, Transition::Masked)
            } else {
                (State::Exception(cause), Transition::Entered(cause))
            }
        };
        match (current, event) {
            (State::Restarting { .. }, _) => (current, Transition::Unchanged),
            (State::Exception(last) | State::Running { last }, Event::HardReset) => {
                (State::Restarting { last }, Transition::Restart)
            }
            (State::Exception(cause), Event::Leave) => {
                (State::Running { last: cause }, Transition::Left)
            }
            (State::Running { .. }, Event::Leave) => (current, Transition::Unchanged),
            (State::Exception(_), Event::Fault { .. } | Event::RemoteWrite | Event::BusSilence) => {
                (current, Transition::Unchanged)
            }
            (State::Running { .. }, Event::Fault { fault, motor }) => {
                raise(Cause::Local { fault, motor })
            }
            (State::Running { .. }, Event::RemoteWrite) => raise(Cause::Remote),
            (State::Running { .. }, Event::BusSilence) => raise(Cause::BusSilent),
        }
    }

    #[test]
    fn a_fault_s_discriminant_is_its_wire_code() {
        let expected = [
            (LocalFault::Overcurrent, ExceptionType::Overcurrent, 1),
            (LocalFault::ShortOc, ExceptionType::ShortOc, 8),
            (LocalFault::Stall, ExceptionType::Stall, 5),
            (LocalFault::EncoderFault, ExceptionType::EncoderFault, 6),
            (LocalFault::DriveFault, ExceptionType::DriveFault, 7),
        ];
        for (fault, kind, code) in expected {
            assert_eq!(fault as u8, code);
            assert_eq!(fault.kind(), kind);
            for motor in MotorId::BOTH {
                let cause = Cause::Local { fault, motor };
                assert_eq!(cause.kind(), kind);
                assert_eq!(cause.data(), u16::from(motor as u8) << 8 | u16::from(code));
            }
        }
        assert_eq!(Cause::Boot.data(), 0x0502);
        assert_eq!(Cause::Remote.data(), 0x0503);
        assert_eq!(Cause::BusSilent.data(), 0x050c);
    }

    #[test]
    fn every_state_and_event_as_the_table() {
        let faults = [
            LocalFault::Overcurrent,
            LocalFault::ShortOc,
            LocalFault::Stall,
            LocalFault::EncoderFault,
            LocalFault::DriveFault,
        ];
        let mut causes = vec![Cause::Boot, Cause::Remote, Cause::BusSilent];
        let mut events = vec![
            Event::RemoteWrite,
            Event::BusSilence,
            Event::Leave,
            Event::HardReset,
        ];
        for fault in faults {
            for motor in MotorId::BOTH {
                causes.push(Cause::Local { fault, motor });
                events.push(Event::Fault { fault, motor });
            }
        }
        let mut states = Vec::new();
        for &cause in &causes {
            states.extend([
                State::Exception(cause),
                State::Running { last: cause },
                State::Restarting { last: cause },
            ]);
        }
        let mut seen = std::collections::HashSet::new();
        for &state in &states {
            for &event in &events {
                for disabled in (0..=u16::MAX).step_by(97).chain([0xffff, 1 << 2, 1 << 9]) {
                    let mut s = state;
                    let transition = s.handle(event, disabled);
                    let want = table(state, event, disabled);
                    assert_eq!((s, transition), want, "{state:?} {event:?} {disabled:#x}");
                    seen.insert(format!("{:?}", std::mem::discriminant(&transition)));
                }
            }
        }
        assert_eq!(seen.len(), 5, "every kind of transition: {seen:?}");
    }
}
