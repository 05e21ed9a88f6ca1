//! Remote control (reference §9.2): an RC receiver on D2 (drive), D3 (steer) and D4
//! (mode) drives the rover directly, and while its link is up the PC is locked out.
//!
//! - [`input`]: pulse widths from pin changes ([`PulseTimer`], used by the interrupt
//!   handler) and their normalised values;
//! - [`Remote`]: link state, the once-per-boot link-up, and each pass's outputs;
//! - [`steer`]: the steer integrator and the Ackermann geometry;
//! - [`setup`]: the writes of the first link-up.
//!
//! All maths is in integers: normalised values in thousandths, angles in centidegrees,
//! the integrator in µdeg, speeds in tenths of ticks/s.

pub mod input;
pub mod setup;
pub mod steer;

pub use input::{normalise, PulseTimer, CHANNELS};
pub use setup::{LinkUpWrites, DS_CONTROLLERS, LINK_UP_WRITES};

use crate::master::ping::RegWrite;
use crate::regs::id;

/// The link is up while the last edge is less than this old (µs).
pub const LINK_TIMEOUT_US: u32 = 1_000_000;
/// |steer| below 0.3 is taken as 0.
pub const STEER_DEADBAND: i16 = 300;
/// |drive| below 0.2 is taken as 0.
pub const DRIVE_DEADBAND: i16 = 200;
/// Crab mode while the mode channel is above 0.75.
pub const CRAB_THRESHOLD: i16 = 750;
/// REQSPEED at full drive, ticks/s.
pub const MAX_SPEED: i32 = 1300;

/// What the master sends in one pass while the link is up.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Pass {
    /// Drive after its dead band, thousandths.
    pub drive: i16,
    /// Steer after its dead band, thousandths.
    pub steer: i16,
    /// Crab mode: all wheels at the outer angle.
    pub crab: bool,
    /// REQSPEED = 1300·drive, in tenths of ticks/s.
    pub speed_tenths: i32,
    /// The six steer angles, wheels 1..6, in cdeg.
    pub angles: [i16; 6],
}

impl Pass {
    /// Raw REGDS_DRIVE_REQSPEED (±4000 over 0..65534).
    pub fn speed_raw(&self) -> u16 {
        map_scaled(self.speed_tenths, 10, 4000)
    }

    /// Raw REGDS_STEER_REQPOS (±200 over 0..65534) of wheel `wheel` (1..6); `None` for
    /// another number.
    pub fn steer_raw(&self, wheel: usize) -> Option<u16> {
        let angle = *self.angles.get(wheel.checked_sub(1)?)?;
        Some(map_scaled(i32::from(angle), 100, 200))
    }

    /// The pass's twelve writes: for wheels 1..6 in order, REQSPEED then STEER_REQPOS on
    /// the wheel's drive/steer board.
    pub fn writes(&self) -> impl Iterator<Item = RegWrite> + '_ {
        setup::DS_CONTROLLERS_FLASH
            .as_slice()
            .iter()
            .enumerate()
            .flat_map(move |(i, device)| {
                let speed = RegWrite::word(device, id::REGDS_DRIVE_REQSPEED, self.speed_raw());
                let steer = self
                    .steer_raw(i + 1)
                    .map(|raw| RegWrite::word(device, id::REGDS_STEER_REQPOS, raw));
                core::iter::once(speed).chain(steer)
            })
    }
}

/// Maps `value / scale` onto a symmetric range ±`limit` of a 2-byte register:
/// ⌊(v + limit)·65534 / (2·limit)⌋ after clamping, computed exactly in integers (the float
/// mapping can differ from it by one where its rounding crosses an integer).
fn map_scaled(value: i32, scale: i32, limit: i32) -> u16 {
    let span = limit * scale;
    let x = (value.clamp(-span, span) + span) as u32;
    // x ≤ 2·span ≤ 80 000, so x·32767 < 2³²; the quotient is at most 65534.
    (x * 32767 / span as u32) as u16
}

/// The master's remote-control state.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Remote {
    widths: [Option<u16>; CHANNELS],
    last_edge_us: Option<u32>,
    linked_before: bool,
    steer_udeg: i32,
}

impl Remote {
    /// At boot: no edge seen, integrator at 0.
    pub const fn new() -> Self {
        Remote {
            widths: [None; CHANNELS],
            last_edge_us: None,
            linked_before: false,
            steer_udeg: 0,
        }
    }

    /// An edge was seen on any channel at `now_us` (the µs clock, wrapping).
    pub fn edge(&mut self, now_us: u32) {
        self.last_edge_us = Some(now_us);
    }

    /// A pulse of `width_us` ended on `channel` (from [`PulseTimer::change`]).
    pub fn pulse(&mut self, channel: usize, width_us: u16) {
        if let Some(w) = self.widths.get_mut(channel) {
            *w = Some(width_us);
        }
    }

    /// The last pulse width of each channel, µs.
    pub const fn widths(&self) -> [Option<u16>; CHANNELS] {
        self.widths
    }

    /// Whether the link is up at `now_us`: an edge was seen less than 1 s ago. Call it
    /// every pass: an edge older than 1 s is forgotten, so the µs clock's wrap (every
    /// 71.6 min) cannot bring a dead link back.
    // Out of line: three callers here and the firmware's (one copy).
    #[inline(never)]
    pub fn link_up(&mut self, now_us: u32) -> bool {
        match self.last_edge_us {
            Some(t) if now_us.wrapping_sub(t) < LINK_TIMEOUT_US => true,
            _ => {
                self.last_edge_us = None;
                false
            }
        }
    }

    /// True exactly once per boot: at the first pass that finds the link up. The
    /// firmware then sends [`LinkUpWrites`].
    pub fn first_link_up(&mut self, now_us: u32) -> bool {
        if self.linked_before || !self.link_up(now_us) {
            return false;
        }
        self.linked_before = true;
        true
    }

    /// Whether a complete PC frame is swallowed with no reply (the link is up).
    pub fn swallows_frames(&mut self, now_us: u32) -> bool {
        self.link_up(now_us)
    }

    /// The steer integrator, µdeg (the outer wheel's angle).
    pub const fn steer_udeg(&self) -> i32 {
        self.steer_udeg
    }

    /// One pass with the link up: dead bands, crab mode, the steer integrator step and
    /// the outputs. A channel that has not had a pulse reads 0 (centred).
    pub fn pass(&mut self) -> Pass {
        let value = |c: usize| {
            self.widths
                .get(c)
                .copied()
                .flatten()
                .and_then(|w| normalise(c, w))
                .unwrap_or(0)
        };
        let (drive, steer, mode) = (value(0), value(1), value(2));
        let drive = if drive.abs() < DRIVE_DEADBAND {
            0
        } else {
            drive
        };
        let steer = if steer.abs() < STEER_DEADBAND {
            0
        } else {
            steer
        };
        let crab = mode > CRAB_THRESHOLD;
        self.steer_udeg = steer::integrate(self.steer_udeg, steer);
        // ±30° in µdeg → ±3000 cdeg.
        let outer = (self.steer_udeg / 10_000) as i16;
        Pass {
            drive,
            steer,
            crab,
            speed_tenths: MAX_SPEED * 10 * i32::from(drive) / 1000,
            angles: steer::wheel_angles(outer, crab),
        }
    }
}
