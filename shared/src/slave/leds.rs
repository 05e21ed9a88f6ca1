//! The slave's two LEDs (reference §6.5), with every duration in ms.
//!
//! The original counted main-loop passes, which have no fixed length; here:
//!
//! | What | LED1 (A2) | LED2 (A3) | For |
//! |---|---|---|---|
//! | Boot: address display | address bit 0 | address bit 1 | the first 600 ms, nothing else shown |
//! | Ping (REG_PING written) | DS | LL | 50 ms |
//! | REG_DEBUGLED = 0 / 1 | 0 | 1 | 250 ms |
//! | Heartbeat | | on | one tick in every 101 ms (a faint flicker) |
//! | Exception latch | motor M1, or no motor | motor M2, or no motor | until the exception is left; none for boot |
//! | Bad EEPROM address (not 1..9) | 300–600 ms | 600–1200 ms | a 1.2-s cycle, both off for its first 300 ms |
//!
//! The sources are OR-ed. The bad-address cycle is the only pattern that alternates the
//! two LEDs, so it cannot be taken for any other state.

use super::board::{MotorId, Variant};
use super::divide::div_rem;
use super::state::{Cause, State};

/// How long the address is shown after boot.
pub const BOOT_DISPLAY_MS: u32 = 600;
/// How long a ping lights its LED.
pub const PING_MS: u32 = 50;
/// How long REG_DEBUGLED lights its LED.
pub const DEBUG_LED_MS: u32 = 250;
/// The heartbeat's period.
pub const HEARTBEAT_MS: u32 = 101;
/// The bad-address cycle: both off, then LED1 from here…
pub const BAD_LED1_FROM_MS: u32 = 300;
/// …then LED2 from here…
pub const BAD_LED2_FROM_MS: u32 = 600;
/// …to the end of the cycle.
pub const BAD_CYCLE_MS: u32 = 1200;

/// The levels of the two LEDs.
#[derive(Clone, Copy, PartialEq, Eq, Debug, Default)]
pub struct LedLevels {
    /// LED1 (A2) lit.
    pub led1: bool,
    /// LED2 (A3) lit.
    pub led2: bool,
}

impl LedLevels {
    /// Both off.
    pub const OFF: LedLevels = LedLevels {
        led1: false,
        led2: false,
    };

    fn or(self, other: LedLevels) -> LedLevels {
        LedLevels {
            led1: self.led1 | other.led1,
            led2: self.led2 | other.led2,
        }
    }

    fn one(led: Led) -> LedLevels {
        LedLevels {
            led1: led == Led::Led1,
            led2: led == Led::Led2,
        }
    }
}

/// One of the two LEDs.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Led {
    /// LED1, on A2.
    Led1,
    /// LED2, on A3.
    Led2,
}

/// Whether `now` is before `deadline` on a wrapping ms clock.
fn before(now_ms: u32, deadline: u32) -> bool {
    (now_ms.wrapping_sub(deadline) as i32) < 0
}

/// The timed LED sources of a slave with a good address.
///
/// The levels change only when the ms clock reaches one of the deadlines, when the
/// exception latch changes, or on a ping or a debug write; [`Leds::levels`] keeps its
/// last result until then, so most ticks only compare.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct Leds {
    display_until: u32,
    ping_until: Option<u32>,
    debug: Option<(Led, u32)>,
    heartbeat_at: u32,
    /// The last levels, valid before `valid_until` while the latch shows `latch`.
    shown: LedLevels,
    latch: LedLevels,
    valid_until: u32,
}

impl Leds {
    /// LEDs whose address display starts at `now_ms`.
    pub const fn new(now_ms: u32) -> Leds {
        Leds {
            display_until: now_ms.wrapping_add(BOOT_DISPLAY_MS),
            ping_until: None,
            debug: None,
            heartbeat_at: now_ms.wrapping_add(BOOT_DISPLAY_MS),
            shown: LedLevels::OFF,
            latch: LedLevels::OFF,
            valid_until: now_ms,
        }
    }

    /// REG_PING was written.
    pub fn ping(&mut self, now_ms: u32) {
        self.ping_until = Some(now_ms.wrapping_add(PING_MS));
        self.valid_until = now_ms;
    }

    /// REG_DEBUGLED was written: 0 lights LED1, 1 lights LED2, other values do nothing.
    pub fn debug(&mut self, now_ms: u32, value: u8) {
        let led = match value {
            0 => Led::Led1,
            1 => Led::Led2,
            _ => return,
        };
        self.debug = Some((led, now_ms.wrapping_add(DEBUG_LED_MS)));
        self.valid_until = now_ms;
    }

    /// The levels at `now_ms`, called once per tick.
    pub fn levels(
        &mut self,
        now_ms: u32,
        address: u8,
        variant: Variant,
        state: &State,
    ) -> LedLevels {
        let latch = latch(state);
        if before(now_ms, self.valid_until) && latch == self.latch {
            return self.shown;
        }
        let (levels, valid_until) = self.compute(now_ms, address, variant, latch);
        self.shown = levels;
        self.latch = latch;
        self.valid_until = valid_until;
        levels
    }

    /// The levels at `now_ms` with the latch showing `latch`, and the first ms at which
    /// they may change. Not inlined: it runs only when they may.
    #[inline(never)]
    fn compute(
        &mut self,
        now_ms: u32,
        address: u8,
        variant: Variant,
        latch: LedLevels,
    ) -> (LedLevels, u32) {
        if before(now_ms, self.display_until) {
            let display = LedLevels {
                led1: address & 1 != 0,
                led2: address & 2 != 0,
            };
            return (display, self.display_until);
        }
        let mut levels = latch;
        let mut next = self.heartbeat_at;
        if let Some(until) = self.ping_until {
            if before(now_ms, until) {
                levels = levels.or(LedLevels::one(ping_led(variant)));
                next = earliest(next, until);
            } else {
                self.ping_until = None;
            }
        }
        if let Some((led, until)) = self.debug {
            if before(now_ms, until) {
                levels = levels.or(LedLevels::one(led));
                next = earliest(next, until);
            } else {
                self.debug = None;
            }
        }
        if !before(now_ms, self.heartbeat_at) {
            self.heartbeat_at = now_ms.wrapping_add(HEARTBEAT_MS);
            levels.led2 = true;
            // Lit for this tick only.
            next = now_ms.wrapping_add(1);
        }
        (levels, next)
    }
}

/// The earlier of two deadlines on a wrapping ms clock.
fn earliest(a: u32, b: u32) -> u32 {
    if before(a, b) {
        a
    } else {
        b
    }
}

/// The LED a ping lights: LED1 on drive/steer, LED2 on lift/lift.
pub const fn ping_led(variant: Variant) -> Led {
    match variant {
        Variant::DriveSteer => Led::Led1,
        Variant::LiftLift => Led::Led2,
    }
}

/// The exception latch display: the faulty motor's LED, both for an exception of no
/// motor, none for boot or while running.
pub fn latch(state: &State) -> LedLevels {
    match state {
        State::Exception(Cause::Boot) | State::Running { .. } | State::Restarting { .. } => {
            LedLevels::OFF
        }
        State::Exception(Cause::Remote | Cause::BusSilent) => LedLevels {
            led1: true,
            led2: true,
        },
        State::Exception(Cause::Local { motor, .. }) => LedLevels::one(match motor {
            MotorId::M1 => Led::Led1,
            MotorId::M2 => Led::Led2,
        }),
    }
}

/// The bad-address pattern at `ms` into the cycle's repetition (any ms clock).
pub fn bad_address(phase_ms: u32) -> LedLevels {
    let (_, phase) = div_rem(phase_ms, BAD_CYCLE_MS);
    LedLevels {
        led1: (BAD_LED1_FROM_MS..BAD_LED2_FROM_MS).contains(&phase),
        led2: phase >= BAD_LED2_FROM_MS,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::slave::state::LocalFault;

    #[test]
    fn kept_levels_equal_a_fresh_computation_every_tick() {
        let states = [
            State::POWER_UP,
            State::Running { last: Cause::Boot },
            State::Exception(Cause::Local {
                fault: LocalFault::Stall,
                motor: MotorId::M2,
            }),
            State::Running {
                last: Cause::Remote,
            },
            State::Exception(Cause::Remote),
        ];
        let mut kept = Leds::new(5);
        let mut fresh = Leds::new(5);
        let mut lit = 0;
        for t in 5..6_000u32 {
            // Now and then a tick comes late and the clock skips a ms.
            let now = t + t / 700;
            let state = states[(t / 347) as usize % states.len()];
            if t % 613 == 0 {
                kept.ping(now);
                fresh.ping(now);
            }
            if t % 421 == 0 {
                let value = (t / 421 % 3) as u8;
                kept.debug(now, value);
                fresh.debug(now, value);
            }
            let a = kept.levels(now, 6, Variant::LiftLift, &state);
            let (b, _) = fresh.compute(now, 6, Variant::LiftLift, latch(&state));
            assert_eq!(a, b, "tick {t}");
            lit += usize::from(a.led1) + usize::from(a.led2);
        }
        assert!(lit > 1_000, "the sources lit the LEDs {lit} times");
    }
}
