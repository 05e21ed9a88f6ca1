//! The drive encoder: edge counting in the interrupt, speed measurement in the control
//! tick (reference §7.3), and the odometer.
//!
//! Two speed measurements, chosen by REGDS_DRIVE_MODE:
//! - **Window** (mode 0, the original): the drive updates on the first tick more than
//!   150 ms after the previous update; speed = N·10⁶/T ticks/s for the N rising edges of A
//!   counted over the T µs since then.
//! - **Edge timing** (mode 1, new): the drive updates every 10 ms; speed = n·10⁶/Δt for
//!   the n edges since the last update and the Δt µs between the last edge before them
//!   and the last edge among them. Without a new edge, the speed falls to the bound that
//!   the time since the last edge sets (10⁶/elapsed), and to 0 after 100 ms.
//!
//! In both, the speed is negative when more than ⌊N/3⌋ of the counted edges saw B high.

use super::divide::div_rem;
use super::product::wide;
use crate::pid::{magnitude, Fix};

/// The original's window: the drive updates on the first tick more than this long after
/// the previous update.
pub const WINDOW_US: u32 = 150_000;
/// The update period of the edge-timing mode (100 Hz).
pub const FAST_PERIOD_US: u32 = 10_000;
/// Edge timing: with no edge for this long, the speed is 0 (below 10 ticks/s).
pub const FAST_TIMEOUT_US: u32 = 100_000;

/// The drive's control mode (REGDS_DRIVE_MODE).
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum DriveMode {
    /// 0: the original 150-ms window and edge count.
    Window,
    /// 1: every 10 ms, speed from edge timing.
    EdgeTiming,
}

impl DriveMode {
    /// The mode a register value selects: 1 is edge timing, anything else the window.
    pub const fn from_register(raw: u16) -> DriveMode {
        if raw == 1 {
            DriveMode::EdgeTiming
        } else {
            DriveMode::Window
        }
    }
}

/// The encoder interrupt's counts (PCINT2, on each rising edge of A), kept until the
/// control tick takes them. Eight bytes; each edge costs two increments and a store.
#[derive(Clone, Copy, PartialEq, Eq, Debug, Default)]
pub struct EdgeCounter {
    sample: EdgeSample,
}

/// The edges since the previous take.
#[derive(Clone, Copy, PartialEq, Eq, Debug, Default)]
pub struct EdgeSample {
    /// Rising edges of A.
    pub rising: u16,
    /// Of those, the edges at which B was high.
    pub b_high: u16,
    /// When the last edge came (µs, the clock the tick gets); kept across takes.
    pub last_edge_us: u32,
}

impl EdgeCounter {
    /// No edges yet.
    pub const fn new() -> EdgeCounter {
        EdgeCounter {
            sample: EdgeSample {
                rising: 0,
                b_high: 0,
                last_edge_us: 0,
            },
        }
    }

    /// Counts a rising edge of A at `now_us`; `b_high` is B's level then.
    pub fn rising_edge(&mut self, now_us: u32, b_high: bool) {
        self.sample.rising = self.sample.rising.wrapping_add(1);
        if b_high {
            self.sample.b_high = self.sample.b_high.wrapping_add(1);
        }
        self.sample.last_edge_us = now_us;
    }

    /// The edges since the previous take; the counts restart at zero.
    pub fn take(&mut self) -> EdgeSample {
        let sample = self.sample;
        self.sample.rising = 0;
        self.sample.b_high = 0;
        sample
    }
}

/// Ticks per second for `edges` edges over `span_us` µs, saturating at 32767.
pub fn rate(edges: u16, span_us: u32) -> Fix {
    if edges == 0 || span_us == 0 {
        return Fix::ZERO;
    }
    // 10^6 = 15625·64 and edges·15625 is one 16×16 product (65535·15625 < 2^32).
    // edges·10^6 fits a u32 up to 4294 edges (a compare, not a 64-bit overflow check):
    // the product shifted by 6. Beyond (only for more than 4294 edges in one update):
    // the span in units of 64 µs. One product and one division for both.
    let product = wide(edges, 15_625);
    let (numerator, span) = if edges <= 4_294 {
        (product << 6, span_us)
    } else {
        (product, (span_us >> 6).max(1))
    };
    let (whole, rem) = div_rem(numerator, span);
    if whole > 32_767 {
        return Fix::MAX;
    }
    // rem < span; 8 fraction bits are plenty (none past 2^24 µs, as before): below it,
    // rem·256 < 2^32, so the same division gives them.
    let frac = if span < 1 << 24 {
        div_rem(rem << 8, span).0
    } else {
        0
    };
    Fix::from_bits((whole << 16 | frac << 8) as i32)
}

/// Whether more than ⌊n/3⌋ of `n` edges saw B high: b > ⌊n/3⌋ exactly when 3·b > n,
/// which holds when 2·b > n and otherwise exactly when b > n − 2·b. In 16 bits, with no
/// division and no multiplication (LLVM makes b + b + b one, a library call on the AVR).
#[inline(always)]
fn mostly_backward(n: u16, b_high: u16) -> bool {
    b_high > n.saturating_sub(b_high).saturating_sub(b_high)
}

/// The drive's speed measurement between two control updates.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct SpeedMeter {
    /// When the previous update ran (µs).
    since_us: u32,
    /// Edges counted since then.
    rising: u16,
    /// Of those, with B high.
    b_high: u16,
    /// The last edge seen by the previous update, for edge timing (`None` before an
    /// update saw one).
    reference: Option<u32>,
    /// The last edge seen at all (valid while `rising` > 0: the edges that set it).
    last_edge: u32,
    /// The last measured speed.
    speed: Fix,
}

impl SpeedMeter {
    /// A meter whose first window starts at `now_us`.
    pub const fn new(now_us: u32) -> SpeedMeter {
        SpeedMeter {
            since_us: now_us,
            rising: 0,
            b_high: 0,
            reference: None,
            last_edge: 0,
            speed: Fix::ZERO,
        }
    }

    /// [`SpeedMeter::new`] at `now_us` for a meter that `new` made and nothing has
    /// touched since (the board's first tick): only the window's start moves.
    pub(crate) fn start(&mut self, now_us: u32) {
        self.since_us = now_us;
    }

    /// Adds the edges one tick took from the [`EdgeCounter`].
    pub fn accumulate(&mut self, sample: &EdgeSample) {
        if sample.rising > 0 {
            self.rising = self.rising.saturating_add(sample.rising);
            self.b_high = self.b_high.saturating_add(sample.b_high);
            self.last_edge = sample.last_edge_us;
        }
    }

    /// Whether the drive update is due at `now_us` in `mode`.
    pub fn due(&self, now_us: u32, mode: DriveMode) -> bool {
        let elapsed = now_us.wrapping_sub(self.since_us);
        match mode {
            DriveMode::Window => elapsed > WINDOW_US,
            DriveMode::EdgeTiming => elapsed >= FAST_PERIOD_US,
        }
    }

    /// Measures the speed (ticks/s) at an update and starts the next interval.
    ///
    /// Both modes come down to one [`rate`]: the window's n edges over the time since
    /// the previous update; edge timing's n edges from the reference (the last edge an
    /// update saw) to the last of them, or, without a new edge, one edge over the time
    /// since the reference, which bounds the speed. Before any update saw an edge the
    /// speed is 0 and the interval's start stands in for the reference: the first edges
    /// then count from it, and the bound of a 0 speed is 0 (tested against the form
    /// with each case written out). In line in the tick, its one caller (54 B less
    /// than a call in the drive/steer image).
    #[inline(always)]
    pub fn measure(&mut self, now_us: u32, mode: DriveMode) -> Fix {
        let n = self.rising;
        let reference = self.reference.unwrap_or(self.since_us);
        let bounding = mode == DriveMode::EdgeTiming && n == 0;
        let (edges, from, to) = match mode {
            DriveMode::Window => (n, self.since_us, now_us),
            DriveMode::EdgeTiming if n == 0 => (1, reference, now_us),
            DriveMode::EdgeTiming => (n, reference, self.last_edge),
        };
        // A bound on a speed of 0 (so 0 too), or one the timeout makes 0, needs no
        // division.
        let magnitude = if bounding
            && (self.speed == Fix::ZERO || now_us.wrapping_sub(reference) >= FAST_TIMEOUT_US)
        {
            Fix::ZERO
        } else {
            let rate = rate(edges, to.wrapping_sub(from));
            if bounding {
                capped_magnitude(self.speed, rate)
            } else {
                rate
            }
        };
        let reverse = if n > 0 {
            self.reference = Some(self.last_edge);
            mostly_backward(n, self.b_high)
        } else {
            self.speed < Fix::ZERO
        };
        self.speed = if reverse { -magnitude } else { magnitude };
        self.since_us = now_us;
        self.rising = 0;
        self.b_high = 0;
        self.speed
    }

    /// The last measured speed.
    pub fn speed(&self) -> Fix {
        self.speed
    }
}

/// min(|x|, bound) for a bound ≥ 0 (the bound is a [`rate`], never negative: tested),
/// with |x| saturating (|−32768| the largest value), from the exact magnitude: one
/// unsigned compare and no call (the drive's one saturating absolute value, so the
/// image carries no out-of-line copy of one).
#[inline(always)]
fn capped_magnitude(x: Fix, bound: Fix) -> Fix {
    let m = magnitude(x);
    // m < bound's bits ≤ 2^31 − 1, so m fits.
    if m < bound.to_bits() as u32 {
        Fix::from_bits(m as i32)
    } else {
        bound
    }
}

/// The odometer: every rising edge of A, in either direction.
#[derive(Clone, Copy, PartialEq, Eq, Debug, Default)]
pub struct Odometer {
    edges: u32,
}

impl Odometer {
    /// Zero.
    pub const fn new() -> Odometer {
        Odometer { edges: 0 }
    }

    /// Counts edges.
    pub fn add(&mut self, edges: u16) {
        self.edges = self.edges.wrapping_add(u32::from(edges));
    }

    /// REGDS_DRIVE_ODO: ⌊edges/256⌋ mod 65536.
    pub fn reading(&self) -> u16 {
        (self.edges >> 8) as u16
    }

    /// REG_RESET bit 2.
    pub fn clear(&mut self) {
        self.edges = 0;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn capped_magnitude_is_the_saturating_absolute_value_capped_by_a_bound_not_below_0() {
        let values = [
            i32::MIN,
            i32::MIN + 1,
            -65_536 * 300,
            -65_537,
            -65_536,
            -1,
            0,
            1,
            65_535,
            65_536,
            65_536 * 300,
            i32::MAX - 1,
            i32::MAX,
        ];
        let mut capped = 0;
        for x in values {
            for bound in values.into_iter().filter(|&b| b >= 0) {
                let (x, bound) = (Fix::from_bits(x), Fix::from_bits(bound));
                let expected = x.saturating_abs().min(bound);
                assert_eq!(capped_magnitude(x, bound), expected, "{x} {bound}");
                capped += usize::from(expected == bound && expected != x.saturating_abs());
            }
        }
        assert!(capped > 20, "the cap acted {capped} times");
    }

    #[test]
    fn rate_is_the_truncated_quotient_to_a_256th() {
        // ⌊edges·10^6/span⌋ + ⌊256·remainder/span⌋/256 in 64 bits, saturated; past 4294
        // edges the span counts in 64 µs units, as in the firmware.
        let reference = |edges: u16, span: u32| {
            let (edges, span) = (u64::from(edges), u64::from(span));
            let (numerator, span) = if edges <= 4_294 {
                (edges * 1_000_000, span)
            } else {
                (edges * 15_625, (span >> 6).max(1))
            };
            let whole = numerator / span;
            if whole > 32_767 {
                return Fix::MAX;
            }
            let frac = if span < 1 << 24 {
                (numerator % span) * 256 / span
            } else {
                0
            };
            Fix::from_bits(((whole << 16) | (frac << 8)) as i32)
        };
        let spans = [
            1u32,
            2,
            3,
            30,
            999,
            1_000,
            30_517,
            65_535,
            65_536,
            150_001,
            1 << 24,
            u32::MAX,
        ];
        let mut checked = 0;
        for edges in (0..=u16::MAX).step_by(7).chain([4_294, 4_295, u16::MAX]) {
            for span in spans {
                let want = if edges == 0 {
                    Fix::ZERO
                } else {
                    reference(edges, span)
                };
                assert_eq!(rate(edges, span), want, "{edges} edges in {span} µs");
                // Never negative: a bound for capped_magnitude.
                assert!(want >= Fix::ZERO, "{edges} edges in {span} µs");
                checked += 1;
            }
        }
        assert!(checked > 100_000);
        assert_eq!(rate(150, 150_000), Fix::from_num(1_000));
        assert_eq!(rate(3, 7_000), Fix::from_bits(428 << 16 | 146 << 8));
        assert_eq!(rate(5_000, 100), Fix::MAX);
        assert_eq!(rate(0, 1_000), Fix::ZERO);
        assert_eq!(rate(9, 0), Fix::ZERO);
    }

    #[test]
    fn backward_means_more_than_a_third() {
        let values = (0..=400u16).chain([0x5554, 0x5555, 0x5556, 0xaaaa, 0xaaab, u16::MAX]);
        for n in values.clone().filter(|&n| n > 0) {
            for b in values.clone() {
                assert_eq!(mostly_backward(n, b), b > n / 3, "{b} of {n}");
            }
        }
        assert!(mostly_backward(3, 2) && !mostly_backward(3, 1) && mostly_backward(2, 1));
    }

    /// The measurement with each of edge timing's cases written out (the form
    /// [`SpeedMeter::measure`] replaced), for the test below.
    struct CaseByCase {
        since_us: u32,
        rising: u16,
        b_high: u16,
        reference: Option<u32>,
        last_edge: Option<u32>,
        speed: Fix,
    }

    impl CaseByCase {
        fn accumulate(&mut self, sample: &EdgeSample) {
            if sample.rising > 0 {
                self.rising = self.rising.saturating_add(sample.rising);
                self.b_high = self.b_high.saturating_add(sample.b_high);
                self.last_edge = Some(sample.last_edge_us);
            }
        }

        fn measure(&mut self, now_us: u32, mode: DriveMode) -> Fix {
            let n = self.rising;
            let fresh = |edge: u32| now_us.wrapping_sub(edge) < FAST_TIMEOUT_US;
            let magnitude = match mode {
                DriveMode::Window => rate(n, now_us.wrapping_sub(self.since_us)),
                DriveMode::EdgeTiming => match (n, self.last_edge, self.reference) {
                    (0, _, Some(reference)) if fresh(reference) => {
                        let bound = rate(1, now_us.wrapping_sub(reference));
                        self.speed.saturating_abs().min(bound)
                    }
                    (0, _, _) => Fix::ZERO,
                    (_, Some(last), Some(reference)) => rate(n, last.wrapping_sub(reference)),
                    (_, Some(last), None) => rate(n, last.wrapping_sub(self.since_us)),
                    (_, None, _) => Fix::ZERO,
                },
            };
            let reverse = if n > 0 {
                self.b_high > n / 3
            } else {
                self.speed < Fix::ZERO
            };
            self.speed = if reverse { -magnitude } else { magnitude };
            if n > 0 {
                self.reference = self.last_edge;
            }
            self.since_us = now_us;
            self.rising = 0;
            self.b_high = 0;
            self.speed
        }
    }

    #[test]
    fn one_rate_for_both_modes_equals_each_case_written_out() {
        // Random runs: ticks of 1 ms (sometimes a long stall), 0–3 edges a tick at
        // random times within it, bursts and rests, the mode switching now and then.
        let mut random = crate::test_random::Xorshift(0x2545_f491_4f6c_dd1du64);
        let mut next = |bound: u32| random.below(bound);
        let (mut nonzero, mut bounded, mut capped, mut updates) = (0, 0, 0, 0);
        for run in 0..200u32 {
            let start = next(u32::MAX).wrapping_add(run);
            let mut meter = SpeedMeter::new(start);
            let mut model = CaseByCase {
                since_us: start,
                rising: 0,
                b_high: 0,
                reference: None,
                last_edge: None,
                speed: Fix::ZERO,
            };
            let mut counter = EdgeCounter::new();
            let mut mode = DriveMode::EdgeTiming;
            let mut now = start;
            let mut moving = next(2) == 0;
            for _ in 0..3_000 {
                let tick = if next(500) == 0 {
                    1_000 * next(300)
                } else {
                    1_000
                };
                if next(200) == 0 {
                    moving = !moving;
                }
                if moving {
                    let backward = next(4) == 0;
                    for _ in 0..next(4) {
                        let at = now.wrapping_add(next(tick.max(1)));
                        counter.rising_edge(at, backward != (next(8) == 0));
                    }
                }
                now = now.wrapping_add(tick);
                let sample = counter.take();
                meter.accumulate(&sample);
                model.accumulate(&sample);
                if next(300) == 0 {
                    mode = match mode {
                        DriveMode::Window => DriveMode::EdgeTiming,
                        DriveMode::EdgeTiming => DriveMode::Window,
                    };
                }
                if meter.due(now, mode) {
                    let bounding = mode == DriveMode::EdgeTiming && meter.rising == 0;
                    let before = meter.speed();
                    let speed = meter.measure(now, mode);
                    bounded += usize::from(bounding);
                    capped += usize::from(bounding && speed != Fix::ZERO && speed != before);
                    assert_eq!(speed, model.measure(now, mode), "run {run} at {now}");
                    nonzero += usize::from(speed != Fix::ZERO);
                    updates += 1;
                }
            }
        }
        assert!(
            updates > 30_000 && nonzero > 15_000,
            "{nonzero} of {updates}"
        );
        assert!(
            bounded > 10_000 && capped > 1_000,
            "{bounded}, {capped} capped"
        );
        assert!(nonzero < updates - 10_000, "{nonzero} of {updates}");
    }

    #[test]
    fn starting_a_new_meter_equals_making_it_then() {
        for now in [0, 1, 150_000, u32::MAX] {
            let mut started = SpeedMeter::new(0);
            started.start(now);
            assert_eq!(started, SpeedMeter::new(now), "{now}");
        }
    }
}
