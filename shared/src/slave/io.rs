//! What the firmware hands the control tick, and what it applies afterwards.
//!
//! The interrupts only collect raw facts: [`super::EdgeCounter`] (encoder edges),
//! [`AdcCollector`] (ADC results) and the [`super::RegisterFile`] (I2C). The tick takes
//! their contents as [`Inputs`] and returns [`Outputs`]: pins, PWM duties, LEDs and the
//! watchdog.

use super::encoder::EdgeSample;
use super::leds::LedLevels;
use crate::pid::{Direction, Duty};

/// An ADC channel the slave samples (reference §7.2, §12).
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
#[repr(u8)]
pub enum AdcChannel {
    /// ADC0: current of M1 (drive or lift ONE).
    Current1 = 0,
    /// ADC1: current of M2 (steer or lift TWO).
    Current2 = 1,
    /// ADC6: steer pot (DS) or lift ONE pot (LL).
    Pot6 = 6,
    /// ADC7: chassis pot (DS) or lift TWO pot (LL).
    Pot7 = 7,
}

impl AdcChannel {
    /// The order the original converts them in, round robin.
    pub const ORDER: [AdcChannel; 4] = [
        AdcChannel::Current1,
        AdcChannel::Current2,
        AdcChannel::Pot6,
        AdcChannel::Pot7,
    ];

    /// The multiplexer channel number (ADMUX MUX bits).
    pub const fn mux(self) -> u8 {
        self as u8
    }

    /// The channel converted after this one ([`next_mux`] in channel form).
    pub const fn next(self) -> AdcChannel {
        match self {
            AdcChannel::Current1 => AdcChannel::Current2,
            AdcChannel::Current2 => AdcChannel::Pot6,
            AdcChannel::Pot6 => AdcChannel::Pot7,
            AdcChannel::Pot7 => AdcChannel::Current1,
        }
    }
}

/// The multiplexer number of the channel converted after the one numbered `mux` (one of
/// 0, 1, 6, 7): the round robin's position `mux & 3` plus one, back to a channel number.
/// On the AVR a few register operations, where a `match` is a tree of compares.
pub const fn next_mux(mux: u8) -> u8 {
    let i = mux.wrapping_add(1) & 3;
    i | (i & 2) << 1
}

/// The ADC readings one tick works with.
#[derive(Clone, Copy, PartialEq, Eq, Debug, Default)]
pub struct AdcSample {
    /// The latest current reading of M1 and M2 (raw, 0..1023).
    pub current: [u16; 2],
    /// The highest current reading of M1 and M2 since the previous tick: the overcurrent
    /// rule looks at every sample, so none may slip between two ticks.
    pub current_peak: [u16; 2],
    /// The latest ADC6 reading.
    pub ch6: u16,
    /// The latest ADC7 reading.
    pub ch7: u16,
}

/// The ADC interrupt's collector: the latest value of each channel and the current peaks.
///
/// Kept by the round robin's position (a channel's `mux & 3`: current 1, current 2, ch6,
/// ch7), so that recording is an indexed store, not a `match` per channel.
#[derive(Clone, Copy, PartialEq, Eq, Debug, Default)]
pub struct AdcCollector {
    /// The latest reading by position.
    latest: [u16; 4],
    /// The highest current reading of M1 and M2 since the last take.
    peak: [u16; 2],
}

impl AdcCollector {
    /// All zero.
    pub const fn new() -> AdcCollector {
        AdcCollector {
            latest: [0; 4],
            peak: [0; 2],
        }
    }

    /// Records a conversion result.
    pub fn record(&mut self, channel: AdcChannel, value: u16) {
        self.record_mux(channel.mux(), value);
    }

    /// Records a conversion result of the channel numbered `mux` (one of 0, 1, 6, 7;
    /// others are taken by their `mux & 3`, as the ADC task never passes them).
    #[inline(always)]
    pub fn record_mux(&mut self, mux: u8, value: u16) {
        let i = usize::from(mux & 3);
        if let Some(latest) = self.latest.get_mut(i) {
            *latest = value;
        }
        if let Some(peak) = self.peak.get_mut(i) {
            *peak = (*peak).max(value);
        }
    }

    /// The readings for a tick; the peaks restart from the latest values.
    pub fn take(&mut self) -> AdcSample {
        // Field by field: a whole-struct copy becomes a call to a byte-copy loop on the
        // AVR, some 250 cycles a tick for 12 bytes.
        let [c1, c2, ch6, ch7] = self.latest;
        let [p1, p2] = self.peak;
        self.peak = [c1, c2];
        AdcSample {
            current: [c1, c2],
            current_peak: [p1, p2],
            ch6,
            ch7,
        }
    }
}

/// Everything a tick reads.
#[derive(Clone, Copy, PartialEq, Eq, Debug, Default)]
pub struct Inputs {
    /// Encoder edges since the previous tick (all zero on a lift/lift board).
    pub edges: EdgeSample,
    /// ADC readings.
    pub adc: AdcSample,
}

/// What one motor's pins do.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum MotorOutput {
    /// Direction pins per `Duty::direction` (forward: POS high, NEG low), PWM at the duty.
    Drive(Duty),
    /// Both direction pins low and duty 0: an unbraked coast.
    Stop,
}

impl MotorOutput {
    /// The power-on output: forward pins, duty 0 (no STOP at boot).
    pub const BOOT: MotorOutput = MotorOutput::Drive(Duty::IDLE);

    /// The PWM duty, 0..255.
    pub const fn duty(self) -> u8 {
        match self {
            MotorOutput::Drive(duty) => duty.magnitude,
            MotorOutput::Stop => 0,
        }
    }

    /// The levels of the POS and NEG pins.
    pub const fn pins(self) -> (bool, bool) {
        match self {
            MotorOutput::Drive(Duty {
                direction: Direction::Forward,
                ..
            }) => (true, false),
            MotorOutput::Drive(Duty {
                direction: Direction::Reverse,
                ..
            }) => (false, true),
            MotorOutput::Stop => (false, false),
        }
    }
}

/// What the watchdog gets.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Watchdog {
    /// Reset the watchdog timer: all is well.
    Feed,
    /// Let it fire (or force it): REG_RESET bit 1 asked for a hard reset.
    Reset,
}

/// Everything a tick asks of the hardware.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct Outputs {
    /// M1 and M2.
    pub motors: [MotorOutput; 2],
    /// LED1 and LED2.
    pub leds: LedLevels,
    /// Feed the watchdog, or let it reset the board.
    pub watchdog: Watchdog,
}

impl Outputs {
    /// Both motors stopped, with these LEDs and watchdog: the rare ticks of a board
    /// without an address or about to reset (one out-of-line copy for both).
    #[inline(never)]
    pub fn stopped(leds: LedLevels, watchdog: Watchdog) -> Outputs {
        Outputs {
            motors: [MotorOutput::Stop; 2],
            leds,
            watchdog,
        }
    }
}
