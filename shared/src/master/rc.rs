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
pub mod plan;
pub mod setup;
pub mod steer;

pub use input::{normalise, within_band, PulseTimer, CHANNELS};
pub use plan::{Next, PassPlan, PASS_PERIOD_MS};
pub use setup::{LinkUpWrites, DS_CONTROLLERS, LINK_UP_WRITES};

use crate::master::ping::RegWrite;
use crate::regs::id;

/// The link is up while the last edge is less than this old (ms).
pub const LINK_TIMEOUT_MS: u16 = 1000;
/// |steer| below 0.3 is taken as 0.
pub const STEER_DEADBAND: i16 = 300;
/// |drive| below 0.2 is taken as 0.
pub const DRIVE_DEADBAND: i16 = 200;
/// Crab mode while the mode channel is above 0.75.
pub const CRAB_THRESHOLD: i16 = 750;
/// REQSPEED at full drive, ticks/s.
pub const MAX_SPEED: i32 = 1300;
// A pass's speed in tenths is MAX_SPEED·10·drive/1000 = (MAX_SPEED/100)·drive, exact only
// while MAX_SPEED is a multiple of 100.
const _: () = assert!(MAX_SPEED % 100 == 0);

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
        Some(angle_raw(angle))
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

/// REQSPEED's raw value for a pass whose drive is `drive` (thousandths, within ±1000 as
/// [`normalise`] gives it): [`Pass::speed_raw`] of the speed 13·`drive` tenths, in 16-bit
/// steps so the firmware needs no 32-bit clamp.
pub fn speed_raw_of(drive: i16) -> u16 {
    const SPAN: u16 = 40_000;
    // ±1000·13 = ±13 000 plus 40 000 is 27 000..=53 000, which fits a u16; x·32767 fits a
    // u32.
    let tenths = drive.clamp(-1000, 1000) * (MAX_SPEED / 100) as i16;
    let x = (tenths as u16).wrapping_add(SPAN);
    (u32::from(x) * 32767 / u32::from(SPAN)) as u16
}

/// Raw REGDS_STEER_REQPOS (±200° over 0..65534) of an angle in cdeg: `map_scaled`
/// with the clamp in 16 bits, as the firmware maps one per wheel and pass.
pub fn angle_raw(cdeg: i16) -> u16 {
    const SPAN: i16 = 200 * 100;
    // −20 000..=20 000 plus 20 000 is 0..=40 000, which fits a u16; x·32767 fits a u32.
    let x = (cdeg.clamp(-SPAN, SPAN) as u16).wrapping_add(SPAN as u16);
    (u32::from(x) * 32767 / SPAN as u32) as u16
}

/// [`speed_raw_of`] for a drive within ±1000, the only drives [`Remote::pass`] gives
/// (from [`normalise`]): the same steps without the clamp (a host test checks every
/// drive in range). Outside the range the value is meaningless.
pub fn speed_raw_in_range(drive: i16) -> u16 {
    const SPAN: u16 = 40_000;
    let tenths = drive.wrapping_mul((MAX_SPEED / 100) as i16);
    let x = (tenths as u16).wrapping_add(SPAN);
    (u32::from(x) * 32767 / u32::from(SPAN)) as u16
}

/// [`angle_raw`] for an angle within ±200°, which every steer angle of a pass is (within
/// the integrator's ±30°): the same steps without the clamp (a host test checks every
/// angle in range). Outside the range the value is meaningless.
pub fn angle_raw_in_range(cdeg: i16) -> u16 {
    const SPAN: u16 = 200 * 100;
    let x = (cdeg as u16).wrapping_add(SPAN);
    (u32::from(x) * 32767 / u32::from(SPAN)) as u16
}

/// The master's remote-control state.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Remote {
    widths: [Option<u16>; CHANNELS],
    /// The low 16 bits of the ms clock at the last edge.
    last_edge_ms: Option<u16>,
    linked_before: bool,
    /// The link was up at the last [`Remote::link_state`].
    was_up: bool,
    steer_udeg: i32,
}

/// The link as the firmware's pass sees it (see [`Remote::link_state`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct LinkState {
    /// An edge was seen less than 1 s ago.
    pub up: bool,
    /// Up for the first time since boot: the link-up writes are due.
    pub first: bool,
    /// Down, and up at the previous look: one more pass is due, which stops the drives
    /// (new; the original left them on the last pass's speed, a runaway with the
    /// transmitter out of range or switched off). The loss forgets the drive and steer
    /// channels' pulses, so that pass has REQSPEED 0 and leaves the steering as it was.
    pub lost: bool,
}

impl Remote {
    /// At boot: no edge seen, integrator at 0.
    pub const fn new() -> Self {
        Remote {
            widths: [None; CHANNELS],
            last_edge_ms: None,
            linked_before: false,
            was_up: false,
            steer_udeg: 0,
        }
    }

    /// An edge was seen on any channel at `now_ms` (the ms clock, wrapping).
    pub fn edge(&mut self, now_ms: u32) {
        self.last_edge_ms = Some(now_ms as u16);
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

    /// Whether the link is up at `now_ms`: an edge was seen less than 1 s ago. Call it
    /// every pass: an edge older than 1 s is forgotten, so the wrap of the 16-bit time
    /// stamp (every 65.5 s) cannot bring a dead link back.
    pub fn link_up(&mut self, now_ms: u32) -> bool {
        self.link_up_at(now_ms as u16)
    }

    /// [`Remote::link_up`] on the clock's low 16 bits, which is all it looks at (what the
    /// firmware's 16-bit clock passes).
    // Out of line: idle's look at the link and the pass's both use it (one copy).
    #[inline(never)]
    pub fn link_up_at(&mut self, now_ms: u16) -> bool {
        match self.last_edge_ms {
            Some(t) if now_ms.wrapping_sub(t) < LINK_TIMEOUT_MS => true,
            _ => {
                self.last_edge_ms = None;
                false
            }
        }
    }

    /// True exactly once per boot: at the first pass that finds the link up. The
    /// firmware then sends [`LinkUpWrites`].
    pub fn first_link_up(&mut self, now_ms: u32) -> bool {
        if self.linked_before || !self.link_up(now_ms) {
            return false;
        }
        self.linked_before = true;
        true
    }

    /// [`Remote::link_up`], [`Remote::first_link_up`] and whether the link was lost
    /// since the previous call, from one look at the link, as the firmware's pass needs
    /// all three. A loss centres the drive and steer channels (see [`LinkState::lost`]).
    pub fn link_state(&mut self, now_ms: u32) -> LinkState {
        let up = self.link_up(now_ms);
        let first = up && !self.linked_before;
        let lost = self.was_up && !up;
        if lost {
            // Channel 0 is the drive, 1 the steer; the mode (2) is kept, so crab mode
            // keeps its angles.
            self.widths[0] = None;
            self.widths[1] = None;
        }
        self.linked_before |= up;
        self.was_up = up;
        LinkState { up, first, lost }
    }

    /// Whether a complete PC frame is swallowed with no reply (the link is up).
    pub fn swallows_frames(&mut self, now_ms: u32) -> bool {
        self.link_up(now_ms)
    }

    /// The steer integrator, µdeg (the outer wheel's angle).
    pub const fn steer_udeg(&self) -> i32 {
        self.steer_udeg
    }

    /// One pass with the link up: dead bands, crab mode, the steer integrator step and
    /// the outputs. A channel that has not had a pulse reads 0 (centred).
    pub fn pass(&mut self) -> Pass {
        let mut values = [0i16; CHANNELS];
        for (c, (value, width)) in values.iter_mut().zip(self.widths).enumerate() {
            *value = width.and_then(|w| normalise(c, w)).unwrap_or(0);
        }
        let [drive, steer, mode] = values;
        let drive = if within_band(drive, DRIVE_DEADBAND) {
            0
        } else {
            drive
        };
        let steer = if within_band(steer, STEER_DEADBAND) {
            0
        } else {
            steer
        };
        let crab = mode > CRAB_THRESHOLD;
        self.steer_udeg = steer::integrate(self.steer_udeg, steer);
        // ±30° in µdeg → ±3000 cdeg.
        // Truncated toward zero like `/`, in unsigned arithmetic: the firmware then needs
        // no signed 32-bit division routine.
        let whole = (self.steer_udeg.unsigned_abs() / 10_000) as i16;
        let outer = if self.steer_udeg < 0 { -whole } else { whole };
        Pass {
            drive,
            steer,
            crab,
            // 1300·10·drive/1000 = 13·drive exactly: no division needed.
            speed_tenths: MAX_SPEED / 100 * i32::from(drive),
            angles: steer::wheel_angles(outer, crab),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn link_state_is_link_up_first_link_up_and_loss_in_one() {
        let (mut one, mut two) = (Remote::new(), Remote::new());
        let mut seen = [LinkState::default(); 6];
        let steps = [
            (None, 5),
            (Some(10), 20),
            (None, 500),
            (None, 1500),
            (Some(2000), 2100),
            (None, 3500),
        ];
        for (state, (edge, now)) in seen.iter_mut().zip(steps) {
            if let Some(t) = edge {
                one.edge(t);
                two.edge(t);
            }
            *state = one.link_state(now);
            let first = two.first_link_up(now);
            assert_eq!((state.up, state.first), (two.link_up(now), first), "{now}");
        }
        let state = |up, first, lost| LinkState { up, first, lost };
        assert_eq!(
            seen,
            [
                state(false, false, false),
                state(true, true, false),
                state(true, false, false),
                // 1 s without an edge: lost once, then just down.
                state(false, false, true),
                state(true, false, false),
                state(false, false, true),
            ]
        );
        // Down stays down without a second loss.
        assert_eq!(one.link_state(4000), state(false, false, false));
    }

    #[test]
    fn the_pass_after_a_loss_stops_the_drives_and_keeps_the_steering() {
        let mut remote = Remote::new();
        remote.edge(0);
        remote.pulse(0, 1000); // full forward
        remote.pulse(1, 940); // full turn
        remote.pulse(2, 1800); // crab mode
        assert!(remote.link_state(10).up);
        for _ in 0..100 {
            remote.pass();
        }
        let driving = remote.pass();
        assert_eq!((driving.drive, driving.crab), (1000, true));
        let lost = remote.link_state(1_010);
        assert!(lost.lost && !lost.up);
        let stop = remote.pass();
        assert_eq!(stop.drive, 0);
        assert_eq!(stop.speed_raw(), 0x7fff, "REQSPEED 0");
        assert_eq!((stop.steer, stop.crab), (0, true));
        assert_eq!(stop.angles, driving.angles, "the steering as it was");
        assert_eq!(remote.widths(), [None, None, Some(1800)]);
    }

    #[test]
    fn every_drive_maps_as_the_passs_speed() {
        for drive in -1000..=1000i16 {
            let tenths = MAX_SPEED / 100 * i32::from(drive);
            assert_eq!(speed_raw_of(drive), map_scaled(tenths, 10, 4000), "{drive}");
        }
        assert_eq!(speed_raw_of(0), 32767);
        assert_eq!(speed_raw_of(1000), 43416);
        assert_eq!(speed_raw_of(-1000), 22117);
        // Beyond ±1000 (which `normalise` never gives) the drive saturates.
        assert_eq!(speed_raw_of(i16::MAX), speed_raw_of(1000));
    }

    #[test]
    fn within_their_ranges_the_clamp_free_mappings_are_the_clamped_ones() {
        for drive in -1000..=1000i16 {
            assert_eq!(speed_raw_in_range(drive), speed_raw_of(drive), "{drive}");
        }
        for cdeg in -20_000..=20_000i16 {
            assert_eq!(angle_raw_in_range(cdeg), angle_raw(cdeg), "{cdeg}");
        }
        assert_eq!(speed_raw_in_range(-1000), 22117);
        assert_eq!(angle_raw_in_range(3000), 37682);
        // Every angle of a pass is within the range: the integrator's limit is ±30°.
        let mut r = Remote::new();
        r.pulse(1, 940);
        for _ in 0..1200 {
            for a in r.pass().angles {
                assert!(a.unsigned_abs() <= 3000, "{a}");
            }
        }
        assert_eq!(r.steer_udeg(), -steer::STEER_LIMIT_UDEG);
    }

    #[test]
    fn every_angle_maps_as_the_general_mapping() {
        for cdeg in i16::MIN..=i16::MAX {
            assert_eq!(
                angle_raw(cdeg),
                map_scaled(i32::from(cdeg), 100, 200),
                "{cdeg}"
            );
        }
        assert_eq!(angle_raw(0), 32767);
        assert_eq!(angle_raw(-20_000), 0);
        assert_eq!(angle_raw(i16::MAX), 65534);
    }

    #[test]
    fn the_outer_angle_truncates_the_integrator_toward_zero() {
        let mut r = Remote::new();
        let mut signs = [false; 2];
        // Steer one way past the limit, then back past zero to the other limit.
        for (width, passes) in [(1100, 2000), (1600, 3500)] {
            r.pulse(1, width);
            for _ in 0..passes {
                let p = r.pass();
                let outer = (r.steer_udeg() / 10_000) as i16;
                assert_eq!(
                    p.angles,
                    steer::wheel_angles(outer, false),
                    "{}",
                    r.steer_udeg()
                );
                if r.steer_udeg() % 10_000 != 0 {
                    signs[usize::from(r.steer_udeg() > 0)] = true;
                }
            }
        }
        assert_eq!(
            signs,
            [true, true],
            "remainders of both signs were truncated"
        );
        assert_eq!(r.steer_udeg(), steer::STEER_LIMIT_UDEG);
    }
}
