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
use crate::pid::Fix;

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
        // What must change by 1 to count as motion, and the anchor a restart keeps: the
        // speed against 0 (the drive's anchor stays 0), the angle against its anchor.
        let (value, anchor) = match motion {
            Motion::Speed(speed) => (speed, Fix::ZERO),
            Motion::Angle(angle) => (angle, angle),
        };
        if duty <= limits.stall_check {
            self.since_ms = None;
            return None;
        }
        // Not suspect yet, or moved: suspect from now (one copy of the restart).
        let since = match self.since_ms {
            Some(since) if !moved(value.to_bits().wrapping_sub(self.anchor.to_bits())) => since,
            _ => {
                self.restart(now_ms, anchor);
                return None;
            }
        };
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

/// Whether a change of `bits` (I16F16) is motion: |change| ≥ 1 ([`MOTION_SPEED`],
/// [`MOTION_ANGLE`]). One sum and one unsigned compare: −1 < x < 1 exactly when
/// x + (1 − 2^−16) lies in 0..2 − 2^−16, and a sum that wraps past `i32::MAX` comes out
/// negative, which reads as above that range too. A position motor's change never
/// wraps: angles stay within ±1536° (the calibration's ±512° and span of 1024° at most).
#[inline(always)]
fn moved(bits: i32) -> bool {
    const ONE: i32 = MOTION_SPEED.to_bits();
    const _: () = assert!(MOTION_ANGLE.to_bits() == ONE);
    bits.wrapping_add(ONE - 1) as u32 > (2 * ONE - 2) as u32
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn moved_is_a_magnitude_of_one_or_more() {
        let edges = [
            i32::MIN,
            i32::MIN + 1,
            -0x1_0001,
            -0x1_0000,
            -0xffff,
            -1,
            0,
            1,
            0xffff,
            0x1_0000,
            0x1_0001,
            i32::MAX - 0xffff,
            i32::MAX,
        ];
        let sweep = (i32::MIN..=i32::MAX).step_by(4_093);
        let mut cases = 0u32;
        for bits in edges.into_iter().chain(sweep) {
            assert_eq!(moved(bits), bits.unsigned_abs() >= 0x1_0000, "{bits:#x}");
            cases += 1;
        }
        assert!(cases > 1_000_000, "{cases}");
    }
}
