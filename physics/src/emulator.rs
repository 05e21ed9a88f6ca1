//! The loop closer: runs emulated slave chips against their board models.
//!
//! A [`Plant`] holds one [`SlaveBoardModel`] per slave chip and runs the chips in slices
//! of emulated time ([`DEFAULT_SLICE_US`] by default). For each slice it:
//! 1. reads each chip's bridge inputs: the PWM duty of D9/D10 from the timer registers
//!    (`Avr::pwm_duty`; a pin that is a plain output counts as duty 0 or 1) and the
//!    direction pins D2/D3 and D4/D7;
//! 2. advances each model by the slice with those inputs held;
//! 3. sets each encoder edge on PD0/PD1 for its own cycle (rounded to the nearest;
//!    `Avr::set_pin_at`, applied by the chip itself while it runs), so none is lost or
//!    merged however fast the wheel turns (at 4000 ticks/s edges are 62.5 µs apart), and
//!    runs the chips to the end of the slice in one go;
//! 4. at the end of the slice, puts the models' millivolts on the ADC inputs.
//!
//! The same code drives one [`Avr`] or chips inside a [`Bus`] (through the [`Chips`]
//! trait); on a bus every chip runs in lock step and the plant only splits the bus's runs
//! at slice ends.
//!
//! **Time outside the plant.** The models advance only when the plant runs. If the chips
//! were run directly in between (e.g. `Bus::uart_read_until`), the next call first catches
//! the models up over that gap with the inputs seen then; the edges of the gap arrive
//! late, all at once. Run through the plant to keep every edge on time.

use harness::bus::Bus;
use harness::{Avr, Pin, F_CPU};

use crate::bridge::Bridge;
use crate::encoder::{Channel, EncoderEdge};
use crate::wheel::{pins, Motor, SlaveBoardModel};
use crate::PhysicsError;

/// Default slice: 50 µs of emulated time between input reads and ADC updates.
pub const DEFAULT_SLICE_US: u64 = 50;

/// Emulated chips the plant can drive: one [`Avr`] (chip index 0) or the chips of a [`Bus`].
pub trait Chips {
    /// Emulated time in clock cycles (for a bus, the bus time every chip has reached).
    fn cycles(&self) -> u64;
    /// Runs every chip until `cycle` (nothing if already there).
    fn run_to(&mut self, cycle: u64);
    /// Calls `f` with chip `index`; None if there is no such chip (or it is in use).
    fn with_chip<R>(&mut self, index: usize, f: impl FnOnce(&mut Avr) -> R) -> Option<R>;
}

impl Chips for Avr {
    fn cycles(&self) -> u64 {
        Avr::cycles(self)
    }

    fn run_to(&mut self, cycle: u64) {
        let now = Avr::cycles(self);
        if cycle > now {
            self.run_cycles(cycle - now);
        }
    }

    fn with_chip<R>(&mut self, index: usize, f: impl FnOnce(&mut Avr) -> R) -> Option<R> {
        (index == 0).then(|| f(self))
    }
}

impl Chips for Bus {
    fn cycles(&self) -> u64 {
        Bus::cycles(self)
    }

    fn run_to(&mut self, cycle: u64) {
        let now = Bus::cycles(self);
        if cycle > now {
            self.run_cycles(cycle - now);
        }
    }

    fn with_chip<R>(&mut self, index: usize, f: impl FnOnce(&mut Avr) -> R) -> Option<R> {
        let mut avr = self.chip(index)?;
        Some(f(&mut avr))
    }
}

/// A model attached to a chip.
struct Attached {
    chip: usize,
    model: SlaveBoardModel,
}

/// Reads one motor's bridge input from a chip's pins.
fn read_bridge(avr: &Avr, pwm: u8, pos: u8, neg: u8) -> Bridge {
    let pwm = Pin::d(pwm);
    let duty = match avr.pwm_duty(pwm) {
        Some(d) => f64::from(d),
        None => f64::from(u8::from(avr.pin(pwm))),
    };
    Bridge::from_pins(duty, avr.pin(Pin::d(pos)), avr.pin(Pin::d(neg)))
}

/// Puts a board model's ADC millivolts on a chip (channels the model leaves floating are
/// not touched).
fn apply_adc(avr: &mut Avr, model: &SlaveBoardModel) {
    for (channel, mv) in (0u8..).zip(model.adc_mv()) {
        if let Some(mv) = mv {
            avr.set_adc_mv(channel, mv.round().clamp(0.0, f64::from(u32::MAX)) as u32);
        }
    }
}

/// The encoder pin of a channel.
fn encoder_pin(channel: Channel) -> Pin {
    match channel {
        Channel::A => Pin::d(pins::ENCODER_A),
        Channel::B => Pin::d(pins::ENCODER_B),
    }
}

/// Slave chips closed over their board models.
pub struct Plant {
    boards: Vec<Attached>,
    slice_cycles: u64,
    /// Cycle the models have been advanced to; None before the first run.
    clock: Option<u64>,
}

impl Default for Plant {
    fn default() -> Self {
        Plant::new()
    }
}

impl Plant {
    /// A plant with no boards and the default slice.
    pub fn new() -> Plant {
        Plant {
            boards: Vec::new(),
            slice_cycles: DEFAULT_SLICE_US * F_CPU / 1_000_000,
            clock: None,
        }
    }

    /// A plant for a single chip (index 0, e.g. one [`Avr`]).
    pub fn single(model: SlaveBoardModel) -> Plant {
        let mut plant = Plant::new();
        plant.attach(0, model);
        plant
    }

    /// Attaches `model` to chip `chip` (replacing any model it had).
    pub fn attach(&mut self, chip: usize, model: SlaveBoardModel) {
        self.boards.retain(|b| b.chip != chip);
        self.boards.push(Attached { chip, model });
    }

    /// Sets the slice length (at least 1 µs).
    pub fn set_slice_us(&mut self, us: u64) {
        self.slice_cycles = us.max(1) * F_CPU / 1_000_000;
    }

    /// The model attached to chip `chip`.
    pub fn model(&self, chip: usize) -> Option<&SlaveBoardModel> {
        self.boards
            .iter()
            .find(|b| b.chip == chip)
            .map(|b| &b.model)
    }

    /// The model attached to chip `chip`, to inspect it or inject a fault.
    pub fn model_mut(&mut self, chip: usize) -> Option<&mut SlaveBoardModel> {
        self.boards
            .iter_mut()
            .find(|b| b.chip == chip)
            .map(|b| &mut b.model)
    }

    /// Emulated time the models have reached, in cycles (None before the first run).
    pub fn cycles(&self) -> Option<u64> {
        self.clock
    }

    /// Runs the chips and models together for `us` emulated microseconds.
    pub fn run_us<C: Chips>(&mut self, chips: &mut C, us: u64) -> Result<(), PhysicsError> {
        self.run_until(chips, us, |_| false).map(|_| ())
    }

    /// Runs the chips and models together until `pred` holds (checked before the first
    /// slice and after each one) or `max_us` of emulated time pass. Returns whether
    /// `pred` became true.
    pub fn run_until<C: Chips>(
        &mut self,
        chips: &mut C,
        max_us: u64,
        mut pred: impl FnMut(&mut C) -> bool,
    ) -> Result<bool, PhysicsError> {
        let start = self.sync(chips)?;
        let end = start.saturating_add(max_us.saturating_mul(F_CPU / 1_000_000));
        loop {
            if pred(chips) {
                return Ok(true);
            }
            let now = self.clock.unwrap_or(start);
            if now >= end {
                return Ok(false);
            }
            self.slice(chips, now, self.slice_cycles.min(end - now))?;
        }
    }

    /// Brings the models level with the chips (first run: applies the initial outputs;
    /// later: catches up time the chips ran outside the plant). Returns the cycle now.
    fn sync<C: Chips>(&mut self, chips: &mut C) -> Result<u64, PhysicsError> {
        let now = chips.cycles();
        match self.clock {
            None => {
                for b in &self.boards {
                    let levels = b.model.encoder_levels();
                    chips
                        .with_chip(b.chip, |avr| {
                            if let Some(q) = levels {
                                avr.set_pin(Pin::d(pins::ENCODER_A), q.a);
                                avr.set_pin(Pin::d(pins::ENCODER_B), q.b);
                            }
                            apply_adc(avr, &b.model);
                        })
                        .ok_or(PhysicsError::NoSuchChip(b.chip))?;
                }
                self.clock = Some(now);
            }
            Some(clock) if now > clock => {
                let dt = (now - clock) as f64 / F_CPU as f64;
                self.read_inputs(chips)?;
                for b in &mut self.boards {
                    let edges = b.model.advance(dt);
                    chips
                        .with_chip(b.chip, |avr| {
                            for e in &edges {
                                avr.set_pin(encoder_pin(e.channel), e.level);
                            }
                            apply_adc(avr, &b.model);
                        })
                        .ok_or(PhysicsError::NoSuchChip(b.chip))?;
                }
                self.clock = Some(now);
            }
            Some(_) => {}
        }
        Ok(self.clock.unwrap_or(now))
    }

    /// Reads every chip's bridge inputs into its model.
    fn read_inputs<C: Chips>(&mut self, chips: &mut C) -> Result<(), PhysicsError> {
        for b in &mut self.boards {
            let (m1, m2) = chips
                .with_chip(b.chip, |avr| {
                    (
                        read_bridge(avr, pins::M1_PWM, pins::M1_POS, pins::M1_NEG),
                        read_bridge(avr, pins::M2_PWM, pins::M2_POS, pins::M2_NEG),
                    )
                })
                .ok_or(PhysicsError::NoSuchChip(b.chip))?;
            b.model.set_bridge(Motor::M1, m1);
            b.model.set_bridge(Motor::M2, m2);
        }
        Ok(())
    }

    /// One slice of `len` cycles starting at cycle `start`.
    fn slice<C: Chips>(&mut self, chips: &mut C, start: u64, len: u64) -> Result<(), PhysicsError> {
        self.read_inputs(chips)?;
        let dt = len as f64 / F_CPU as f64;
        let end = start + len;
        let mut due: Vec<(u64, usize, EncoderEdge)> = Vec::new();
        for b in &mut self.boards {
            for e in b.model.advance(dt) {
                let at = (start + e.offset_cycles(F_CPU)).min(end);
                due.push((at, b.chip, e));
            }
        }
        due.sort_by_key(|&(at, _, _)| at);
        for (at, chip, e) in due {
            chips
                .with_chip(chip, |avr| {
                    avr.set_pin_at(encoder_pin(e.channel), e.level, at)
                })
                .ok_or(PhysicsError::NoSuchChip(chip))?;
        }
        chips.run_to(end);
        for b in &self.boards {
            chips
                .with_chip(b.chip, |avr| apply_adc(avr, &b.model))
                .ok_or(PhysicsError::NoSuchChip(b.chip))?;
        }
        self.clock = Some(end);
        Ok(())
    }
}
