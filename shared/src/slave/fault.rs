//! Stall and sensor-fault detection (the manual's figure 11; new: the original has it
//! disabled, reference §7.5).
//!
//! A motor is suspect while its applied duty is above its STALLCHECK level and it does
//! not move. If that lasts longer than FAULTTIME (ms), the filtered current decides what
//! is wrong:
//!
//! | Filtered current (counts) | Result |
//! |---|---|
//! | > 50 (nominal) | STALL: the motor is blocked |
//! | 1..50 (low) | ENCODERFAULT: the motor turns but its sensor does not see it |
//! | 0 (zero) | DRIVEFAULT: the motor or its wiring is open |
//!
//! The original's (never enabled) code put the STALL boundary at 10 counts. A motor that
//! spins freely draws its no-load current, some 20–40 counts, so a broken encoder would
//! read as a stall; a blocked motor at a duty above any useful STALLCHECK draws hundreds.
//! Hence 50 counts, 0.5 A at the 100 counts/A the reference's "150 ≈ 1.5 A" implies.
//!
//! "Moves" means |speed| ≥ 1 tick/s for the drive, and a change of at least 1° since the
//! suspect period began (or since the last such change) for a position motor: a
//! per-update change is far too small to tell at 500 Hz. STALLCHECK 255 disables the
//! check, since no duty exceeds 255. The high-current rows of the table are the
//! overcurrent rule's ([`super::current::overcurrent`]).

use super::state::LocalFault;
use crate::pid::{below, Fix};

/// STALLCHECK's power-on level (the register reads 0x77).
pub const STALL_CHECK_POWER_ON: u8 = 120;
/// FAULTTIME's power-on value, ms.
pub const FAULT_TIME_POWER_ON_MS: u16 = 500;
/// Filtered current above this is "nominal": a stall.
pub const STALL_CURRENT: u8 = 50;
/// A drive at this speed or more (ticks/s) moves.
pub const MOTION_SPEED: Fix = Fix::ONE;
/// A position motor that has turned this far (degrees) moves.
pub const MOTION_ANGLE: Fix = Fix::ONE;

/// What tells whether a motor moves.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Motion {
    /// The drive's measured speed, ticks/s.
    Speed(Fix),
    /// A position motor's measured angle, degrees.
    Angle(Fix),
}

/// The levels a check compares against, from the motor's registers.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct Limits {
    /// STALLCHECK: duty above this is high.
    pub stall_check: u8,
    /// FAULTTIME: how long a suspect state must last, ms.
    pub fault_time_ms: u16,
}

impl Limits {
    /// The power-on limits: 120 and 500 ms.
    pub const POWER_ON: Limits = Limits {
        stall_check: STALL_CHECK_POWER_ON,
        fault_time_ms: FAULT_TIME_POWER_ON_MS,
    };
}

/// One motor's detector.
#[derive(Clone, Copy, PartialEq, Eq, Debug, Default)]
pub struct FaultDetector {
    /// When the suspect state began (ms), or `None` when not suspect.
    since_ms: Option<u32>,
    /// The angle when it began, or when the motor last moved 1°.
    anchor: Fix,
}

impl FaultDetector {
    /// Not suspect.
    pub const fn new() -> FaultDetector {
        FaultDetector {
            since_ms: None,
            anchor: Fix::ZERO,
        }
    }

    /// One check, at each control update of the motor. `duty` is the duty applied to the
    /// motor, `current` the wrap-free filtered current.
    pub fn update(
        &mut self,
        now_ms: u32,
        duty: u8,
        motion: Motion,
        current: u8,
        limits: &Limits,
    ) -> Option<LocalFault> {
        let angle = match motion {
            Motion::Angle(angle) => angle,
            Motion::Speed(_) => Fix::ZERO,
        };
        if duty <= limits.stall_check {
            self.since_ms = None;
            return None;
        }
        let Some(since) = self.since_ms else {
            self.restart(now_ms, angle);
            return None;
        };
        let moved = match motion {
            Motion::Speed(speed) => !below(speed, MOTION_SPEED),
            Motion::Angle(angle) => {
                angle.to_bits().abs_diff(self.anchor.to_bits()) >= MOTION_ANGLE.to_bits() as u32
            }
        };
        if moved {
            self.restart(now_ms, angle);
            return None;
        }
        if now_ms.wrapping_sub(since) <= u32::from(limits.fault_time_ms) {
            return None;
        }
        self.since_ms = None;
        Some(if current > STALL_CURRENT {
            LocalFault::Stall
        } else if current >= 1 {
            LocalFault::EncoderFault
        } else {
            LocalFault::DriveFault
        })
    }

    fn restart(&mut self, now_ms: u32, angle: Fix) {
        self.since_ms = Some(now_ms);
        self.anchor = angle;
    }
}
