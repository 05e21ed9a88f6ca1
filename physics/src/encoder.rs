//! The drive motor's quadrature encoder: channel A/B levels from the wheel angle, and
//! every edge with its time.
//!
//! **Phase relation.** Forward rotation (positive speed, the bridge's forward mode) makes
//! **A lead B by a quarter cycle**: the forward sequence of (A, B) is
//! (0,0) → (1,0) → (1,1) → (0,1) → (0,0), so B is **low** at every A rising edge. In
//! reverse B leads A and is **high** at every A rising edge. The slave's encoder interrupt
//! (reference §7.3) counts A rising edges N and those among them with B high N_B, and
//! negates the speed when N_B > ⌊N/3⌋: forward therefore reads positive.
//!
//! **Ticks.** One tick is one A rising edge ([`TICKS_PER_WHEEL_REV`] per wheel turn);
//! each tick spans four edges (A↑, B↑, A↓, B↓), a quarter of a tick apart.
//!
//! [`TICKS_PER_WHEEL_REV`]: crate::constants::TICKS_PER_WHEEL_REV

use crate::constants::TICKS_PER_RAD;

/// Tick position of the encoder at wheel angle 0: the middle of the (0,0) state, so the
/// pins start low and a small motion either way crosses no edge.
const START_TICKS: f64 = -0.125;

/// One of the encoder's two channels.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Channel {
    /// Channel A, on PD0 (D0), which raises the slave's pin-change interrupt.
    A,
    /// Channel B, on PD1 (D1), read at each A edge.
    B,
}

/// Levels of both channels.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Quadrature {
    /// Channel A level.
    pub a: bool,
    /// Channel B level.
    pub b: bool,
}

/// One level change of one channel, `offset_s` seconds after the start of the
/// [`advance`](crate::drive::DriveMotor::advance) that produced it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EncoderEdge {
    /// Seconds from the start of the advance (0 < offset ≤ the advance's length).
    pub offset_s: f64,
    /// The channel that changes.
    pub channel: Channel,
    /// Its new level.
    pub level: bool,
}

impl EncoderEdge {
    /// The offset in clock cycles of a chip running at `clock_hz`, rounded to nearest.
    pub fn offset_cycles(&self, clock_hz: u64) -> u64 {
        // Offsets are non-negative and small; the float-to-int cast saturates anyway.
        (self.offset_s * clock_hz as f64).round() as u64
    }
}

/// Levels of the quadrature state `q mod 4`.
fn levels(quarter: i64) -> Quadrature {
    let s = quarter.rem_euclid(4);
    Quadrature {
        a: s == 0 || s == 1,
        b: s == 1 || s == 2,
    }
}

/// Tracks the encoder disc and reports its edges.
#[derive(Debug, Clone)]
pub struct Encoder {
    ticks_per_rad: f64,
    /// ⌊4·ticks⌋ of the current position: which quarter of a tick the disc is in.
    quarter: i64,
    a_rises: u64,
    a_rises_b_high: u64,
}

impl Default for Encoder {
    fn default() -> Self {
        Encoder::new(TICKS_PER_RAD)
    }
}

impl Encoder {
    /// An encoder with `ticks_per_rad` A rising edges per radian, at wheel angle 0.
    pub fn new(ticks_per_rad: f64) -> Encoder {
        Encoder {
            ticks_per_rad,
            quarter: (4.0 * START_TICKS).floor() as i64,
            a_rises: 0,
            a_rises_b_high: 0,
        }
    }

    /// Ticks per radian of wheel angle.
    pub fn ticks_per_rad(&self) -> f64 {
        self.ticks_per_rad
    }

    /// The channel levels now.
    pub fn levels(&self) -> Quadrature {
        levels(self.quarter)
    }

    /// Channel-A rising edges so far, in both directions (what the slave's N sums to).
    pub fn a_rises(&self) -> u64 {
        self.a_rises
    }

    /// Channel-A rising edges so far at which B was high (the slave's N_B): reverse ones.
    pub fn a_rises_b_high(&self) -> u64 {
        self.a_rises_b_high
    }

    fn quarter_at(&self, angle_rad: f64) -> i64 {
        (4.0 * (angle_rad * self.ticks_per_rad + START_TICKS)).floor() as i64
    }

    /// Moves the disc linearly from `from_rad` to `to_rad` during `[t0, t0 + h]` and pushes
    /// the edges crossed, in time order, onto `out`.
    pub(crate) fn track(
        &mut self,
        from_rad: f64,
        to_rad: f64,
        t0: f64,
        h: f64,
        out: &mut Vec<EncoderEdge>,
    ) {
        let target = self.quarter_at(to_rad);
        if target == self.quarter {
            return;
        }
        let x0 = from_rad * self.ticks_per_rad + START_TICKS;
        let x1 = to_rad * self.ticks_per_rad + START_TICKS;
        let span = x1 - x0;
        while self.quarter != target {
            let up = target > self.quarter;
            let (next, boundary) = if up {
                (self.quarter + 1, (self.quarter + 1) as f64 / 4.0)
            } else {
                (self.quarter - 1, self.quarter as f64 / 4.0)
            };
            let frac = if span == 0.0 {
                1.0
            } else {
                ((boundary - x0) / span).clamp(0.0, 1.0)
            };
            self.push_edge(next, t0 + h * frac, out);
        }
    }

    /// Enters quarter `next` (one step from the current one) at time `at`.
    fn push_edge(&mut self, next: i64, at: f64, out: &mut Vec<EncoderEdge>) {
        let before = levels(self.quarter);
        let after = levels(next);
        self.quarter = next;
        if before.a != after.a {
            if after.a {
                self.a_rises += 1;
                if after.b {
                    self.a_rises_b_high += 1;
                }
            }
            out.push(EncoderEdge {
                offset_s: at,
                channel: Channel::A,
                level: after.a,
            });
        } else {
            out.push(EncoderEdge {
                offset_s: at,
                channel: Channel::B,
                level: after.b,
            });
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Tracks `ticks` ticks of motion from angle 0 in one step of 1 s.
    fn run(ticks: f64) -> (Encoder, Vec<EncoderEdge>) {
        let mut enc = Encoder::new(1.0);
        let mut out = Vec::new();
        enc.track(0.0, ticks, 0.0, 1.0, &mut out);
        (enc, out)
    }

    #[test]
    fn starts_with_both_channels_low() {
        assert_eq!(
            Encoder::default().levels(),
            Quadrature { a: false, b: false }
        );
    }

    #[test]
    fn forward_is_a_leading_b() {
        let (enc, edges) = run(1.0);
        let seq: Vec<(Channel, bool)> = edges.iter().map(|e| (e.channel, e.level)).collect();
        assert_eq!(
            seq,
            [
                (Channel::A, true),
                (Channel::B, true),
                (Channel::A, false),
                (Channel::B, false)
            ]
        );
        // Edges a quarter tick apart, the first at 1/8 tick.
        let times: Vec<f64> = edges.iter().map(|e| e.offset_s).collect();
        for (t, want) in times.iter().zip([0.125, 0.375, 0.625, 0.875]) {
            assert!((t - want).abs() < 1e-12, "{times:?}");
        }
        assert_eq!((enc.a_rises(), enc.a_rises_b_high()), (1, 0));
    }

    #[test]
    fn reverse_is_b_leading_a_and_b_is_high_at_a_rising() {
        let (enc, edges) = run(-1.0);
        let seq: Vec<(Channel, bool)> = edges.iter().map(|e| (e.channel, e.level)).collect();
        assert_eq!(
            seq,
            [
                (Channel::B, true),
                (Channel::A, true),
                (Channel::B, false),
                (Channel::A, false)
            ]
        );
        assert_eq!((enc.a_rises(), enc.a_rises_b_high()), (1, 1));
    }

    #[test]
    fn many_ticks_count_once_each_and_return_to_start() {
        let (mut enc, edges) = run(100.0);
        assert_eq!(edges.len(), 400);
        assert_eq!(enc.a_rises(), 100);
        assert!(edges.windows(2).all(|w| w[0].offset_s < w[1].offset_s));
        let mut back = Vec::new();
        enc.track(100.0, 0.0, 0.0, 1.0, &mut back);
        assert_eq!(back.len(), 400);
        assert_eq!(enc.a_rises(), 200);
        assert_eq!(enc.a_rises_b_high(), 100);
        assert_eq!(enc.levels(), Quadrature { a: false, b: false });
    }

    #[test]
    fn small_motion_inside_a_state_gives_no_edge() {
        let (enc, edges) = run(0.1);
        assert!(edges.is_empty());
        assert_eq!(enc.levels(), Quadrature { a: false, b: false });
    }

    #[test]
    fn cycles_round_to_nearest() {
        let e = EncoderEdge {
            offset_s: 62.5e-6,
            channel: Channel::A,
            level: true,
        };
        assert_eq!(e.offset_cycles(16_000_000), 1000);
    }
}
