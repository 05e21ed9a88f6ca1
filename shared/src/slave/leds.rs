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
use super::image::Image;
use super::state::{Cause, State};
use core::mem::offset_of;

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

    /// The levels of a [`Mask`].
    const fn from_mask(mask: Mask) -> LedLevels {
        LedLevels {
            led1: mask & LED1 != 0,
            led2: mask & LED2 != 0,
        }
    }
}

/// Levels as bits, as [`Leds`] keeps and combines them (one byte, one `or`, one
/// compare): LED1 bit 0, LED2 bit 1, the bits of the address display.
type Mask = u8;
/// LED1's bit.
const LED1: Mask = 1;
/// LED2's bit.
const LED2: Mask = 2;

/// One of the two LEDs, its discriminant its bit in a `Mask`: no LED is 0, so the
/// zero bytes of an `Option<(Led, _)>` are `None` (the firmware's core starts as zero
/// bytes: see [`super::image`]).
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
#[repr(u8)]
pub enum Led {
    /// LED1, on A2.
    Led1 = LED1,
    /// LED2, on A3.
    Led2 = LED2,
}

impl Led {
    /// Its bit.
    const fn mask(self) -> Mask {
        match self {
            Led::Led1 => LED1,
            Led::Led2 => LED2,
        }
    }
}

/// The low 16 bits of the ms clock: every deadline here is at most 600 ms ahead, and
/// every one that has passed is dropped or moved up within 101 ms (see [`Leds`]), so a
/// 16-bit clock that wraps every 65.5 s orders them as the full one does, in half the
/// registers on the AVR.
type Ms = u16;

/// Whether `now` is before `deadline` on a wrapping 16-bit ms clock.
fn before(now_ms: Ms, deadline: Ms) -> bool {
    (now_ms.wrapping_sub(deadline) as i16) < 0
}

/// The low 16 bits of a ms clock.
const fn low(now_ms: u32) -> Ms {
    now_ms as Ms
}

/// The timed LED sources of a slave with a good address.
///
/// The levels change only when the ms clock reaches one of the deadlines, when the
/// exception latch changes, or on a ping or a debug write; [`Leds::levels`] keeps its
/// last result until then, so most ticks only compare.
///
/// Deadlines are 16-bit (`Ms`): the levels are computed again at least every 101 ms
/// (the heartbeat), and each computation drops a passed ping or debug deadline and
/// moves a passed display deadline up to now, so none is ever 32.8 s stale, where a
/// wrapped 16-bit clock would take it for a future one.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct Leds {
    display_until: Ms,
    ping_until: Option<Ms>,
    debug: Option<(Led, Ms)>,
    heartbeat_at: Ms,
    /// The last levels, valid before `valid_until` while the latch shows `latch`.
    shown: Mask,
    latch: Mask,
    valid_until: Ms,
}

impl Leds {
    /// LEDs whose address display starts at `now_ms`.
    pub const fn new(now_ms: u32) -> Leds {
        let end = low(now_ms).wrapping_add(BOOT_DISPLAY_MS as Ms);
        Leds {
            display_until: end,
            ping_until: None,
            debug: None,
            heartbeat_at: end,
            shown: 0,
            latch: 0,
            valid_until: low(now_ms),
        }
    }

    /// These LEDs' bytes into `image` at `at` (see [`super::image`]): the deadlines and
    /// the kept levels. The ping and the debug sources, none at power-up, are zero bytes
    /// (see [`Led`]).
    pub(crate) const fn put<const N: usize>(&self, image: Image<N>, at: usize) -> Image<N> {
        image
            .u16(at + offset_of!(Leds, display_until), self.display_until)
            .u16(at + offset_of!(Leds, heartbeat_at), self.heartbeat_at)
            .byte(at + offset_of!(Leds, shown), self.shown)
            .byte(at + offset_of!(Leds, latch), self.latch)
            .u16(at + offset_of!(Leds, valid_until), self.valid_until)
    }

    /// [`Leds::new`] at `now_ms` for LEDs that `new` made and nothing has touched since
    /// (the board's first tick): only the three deadlines move.
    pub(crate) fn start(&mut self, now_ms: u32) {
        let end = low(now_ms).wrapping_add(BOOT_DISPLAY_MS as Ms);
        self.display_until = end;
        self.heartbeat_at = end;
        self.valid_until = low(now_ms);
    }

    /// REG_PING was written.
    pub fn ping(&mut self, now_ms: u32) {
        let now = low(now_ms);
        self.ping_until = Some(now.wrapping_add(PING_MS as Ms));
        self.valid_until = now;
    }

    /// REG_DEBUGLED was written: 0 lights LED1, 1 lights LED2, other values do nothing.
    pub fn debug(&mut self, now_ms: u32, value: u8) {
        let led = match value {
            0 => Led::Led1,
            1 => Led::Led2,
            _ => return,
        };
        let now = low(now_ms);
        self.debug = Some((led, now.wrapping_add(DEBUG_LED_MS as Ms)));
        self.valid_until = now;
    }

    /// The levels at `now_ms`, called once per tick.
    pub fn levels(
        &mut self,
        now_ms: u32,
        address: u8,
        variant: Variant,
        state: &State,
    ) -> LedLevels {
        let latch = latch_mask(state);
        if before(low(now_ms), self.valid_until) && latch == self.latch {
            return LedLevels::from_mask(self.shown);
        }
        let (levels, valid_until) = self.compute(now_ms, address, variant, latch);
        self.shown = levels;
        self.latch = latch;
        self.valid_until = valid_until;
        LedLevels::from_mask(levels)
    }

    /// The levels at `now_ms` with the latch showing `latch`, and the first ms at which
    /// they may change. In line in [`Leds::levels`], its one caller: a branch skips it
    /// on most ticks, and a call cost the drive/steer image 116 B more (its arguments
    /// and the variant's tests, which fold away in line).
    #[inline(always)]
    fn compute(&mut self, now_ms: u32, address: u8, variant: Variant, latch: Mask) -> (Mask, Ms) {
        let now_ms = low(now_ms);
        if before(now_ms, self.display_until) {
            // Address bit 0 on LED1, bit 1 on LED2.
            return (address & (LED1 | LED2), self.display_until);
        }
        // Passed for good: kept at most 101 ms behind, so the wrap never revives it.
        self.display_until = now_ms;
        let mut levels = latch;
        let mut next = self.heartbeat_at;
        if let Some(until) = self.ping_until {
            if before(now_ms, until) {
                levels |= ping_led(variant).mask();
                next = earliest(next, until);
            } else {
                self.ping_until = None;
            }
        }
        if let Some((led, until)) = self.debug {
            if before(now_ms, until) {
                levels |= led.mask();
                next = earliest(next, until);
            } else {
                self.debug = None;
            }
        }
        if !before(now_ms, self.heartbeat_at) {
            self.heartbeat_at = now_ms.wrapping_add(HEARTBEAT_MS as Ms);
            levels |= LED2;
            // Lit for this tick only.
            next = now_ms.wrapping_add(1);
        }
        (levels, next)
    }
}

/// The earlier of two deadlines on a wrapping ms clock.
fn earliest(a: Ms, b: Ms) -> Ms {
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
    LedLevels::from_mask(latch_mask(state))
}

/// [`latch`] as a [`Mask`].
fn latch_mask(state: &State) -> Mask {
    match state {
        State::Exception(Cause::Boot) | State::Running { .. } | State::Restarting { .. } => 0,
        State::Exception(Cause::Remote | Cause::BusSilent) => LED1 | LED2,
        State::Exception(Cause::Local { motor, .. }) => match motor {
            MotorId::M1 => LED1,
            MotorId::M2 => LED2,
        },
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
            let (b, _) = fresh.compute(now, 6, Variant::LiftLift, latch_mask(&state));
            assert_eq!(a, LedLevels::from_mask(b), "tick {t}");
            lit += usize::from(a.led1) + usize::from(a.led2);
        }
        assert!(lit > 1_000, "the sources lit the LEDs {lit} times");
    }

    #[test]
    fn the_latch_is_the_faulty_motor_s_led_both_for_no_motor_none_otherwise() {
        use crate::slave::state::LocalFault::*;
        let mut states = vec![
            State::POWER_UP,
            State::Exception(Cause::Remote),
            State::Exception(Cause::BusSilent),
        ];
        for last in [Cause::Boot, Cause::Remote, Cause::BusSilent] {
            states.push(State::Running { last });
            states.push(State::Restarting { last });
        }
        for fault in [Overcurrent, ShortOc, Stall, EncoderFault, DriveFault] {
            for motor in MotorId::BOTH {
                let local = Cause::Local { fault, motor };
                states.extend([
                    State::Exception(local),
                    State::Running { last: local },
                    State::Restarting { last: local },
                ]);
            }
        }
        let mut lit = [0; 3];
        for state in &states {
            let (led1, led2) = match state {
                State::Exception(Cause::Remote | Cause::BusSilent) => (true, true),
                State::Exception(Cause::Local { motor, .. }) => {
                    (*motor == MotorId::M1, *motor == MotorId::M2)
                }
                _ => (false, false),
            };
            assert_eq!(latch(state), LedLevels { led1, led2 }, "{state:?}");
            lit[usize::from(led1) + usize::from(led2)] += 1;
        }
        assert_eq!(lit, [states.len() - 12, 10, 2]);
    }

    #[test]
    fn starting_new_leds_equals_making_them_then() {
        for now in [0, 1, 599, 65_535, 65_536, 1_000_000, u32::MAX] {
            let mut started = Leds::new(0);
            started.start(now);
            assert_eq!(started, Leds::new(now), "{now}");
        }
    }

    #[test]
    fn the_16_bit_deadlines_survive_the_clock_s_wrap() {
        // Started 300 ms before the 16-bit clock wraps, run past two more wraps: the
        // address display (LED1 for address 1) ends after 600 ms and never comes back,
        // the heartbeat keeps its 101-ms period, and a ping after the wrap lasts 50 ms.
        let running = State::Running { last: Cause::Boot };
        let start = 65_236u32;
        let mut leds = Leds::new(start);
        let (mut led1, mut beats, mut last_beat) = (Vec::new(), 0, None);
        for now in start..start + 140_000 {
            if now == 200_000 {
                leds.ping(now);
            }
            let levels = leds.levels(now, 1, Variant::DriveSteer, &running);
            if levels.led1 {
                led1.push(now);
            }
            if levels.led2 {
                if let Some(last) = last_beat {
                    assert_eq!(now - last, 101, "heartbeat at {now}");
                }
                last_beat = Some(now);
                beats += 1;
            }
        }
        let display: Vec<u32> = (start..start + 600).collect();
        let ping: Vec<u32> = (200_000..200_050).collect();
        assert_eq!(led1, [display, ping].concat());
        assert_eq!(beats, (140_000 - 600 - 1) / 101 + 1);
    }
}
