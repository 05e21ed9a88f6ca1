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

use super::clock::{age_add, AGE_MAX, US_PER_UNIT};
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
/// `us` µs in units (exact for a multiple of [`US_PER_UNIT`]).
const fn units_of(us: u32) -> u16 {
    (us / US_PER_UNIT) as u16
}

const WINDOW: u16 = units_of(WINDOW_US);
const FAST_PERIOD: u16 = units_of(FAST_PERIOD_US);
const FAST_TIMEOUT: u16 = units_of(FAST_TIMEOUT_US);
// Each period is a whole number of units, the window and the timeout well inside an
// age's range.
const _: () = assert!(WINDOW_US.is_multiple_of(US_PER_UNIT));
const _: () = assert!(FAST_PERIOD_US.is_multiple_of(US_PER_UNIT));
const _: () = assert!(FAST_TIMEOUT_US.is_multiple_of(US_PER_UNIT));
const _: () = assert!(WINDOW < AGE_MAX - FAST_TIMEOUT);

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
/// control tick takes them. Six bytes; each edge costs two increments and a 16-bit store.
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
    /// When the last edge came, in units ([`super::clock::units`] of the µs clock the tick gets); kept
    /// across takes.
    pub last_edge: u16,
}

impl EdgeCounter {
    /// No edges yet.
    pub const fn new() -> EdgeCounter {
        EdgeCounter {
            sample: EdgeSample {
                rising: 0,
                b_high: 0,
                last_edge: 0,
            },
        }
    }

    /// Counts a rising edge of A at `now` (units); `b_high` is B's level then.
    pub fn rising_edge(&mut self, now: u16, b_high: bool) {
        self.sample.rising = self.sample.rising.wrapping_add(1);
        if b_high {
            self.sample.b_high = self.sample.b_high.wrapping_add(1);
        }
        self.sample.last_edge = now;
    }

    /// The edges since the previous take; the counts restart at zero.
    pub fn take(&mut self) -> EdgeSample {
        let sample = self.sample;
        self.sample.rising = 0;
        self.sample.b_high = 0;
        sample
    }
}

/// Ticks per second for `edges` edges over `span` units (4·`span` µs), saturating at
/// 32767: ⌊edges·250,000/span⌋ and 8 fraction bits, as the µs form ⌊edges·10⁶/(4·span)⌋
/// gave (tested against it).
pub fn rate(edges: u16, span: u16) -> Fix {
    if edges == 0 || span == 0 {
        return Fix::ZERO;
    }
    // edges·250,000 fits a u32 up to 17,179 edges; up to 4,294 (the µs form's limit for
    // edges·10^6) it is one 16×16 product, (4·edges)·62,500. Beyond (only for more than
    // 4,294 edges in one update) the µs form took edges·15,625 over the span in units of
    // 64 µs, s = ⌊span/16⌋ (at least 1): here edges·62,500 over 4·s, the same quotient
    // and 4 times the remainder, so the same fraction. One product for both.
    let (factor, span) = if edges <= 4_294 {
        (edges << 2, span)
    } else {
        (edges, (span >> 4).max(1) << 2)
    };
    let numerator = wide(factor, 62_500);
    let (whole, rem) = div_rem(numerator, u32::from(span));
    // Above 32767 (bit 15 or a high byte set): saturated. Tested as bits, which LLVM
    // keeps as branches on the AVR (a 32-bit compare made a flag).
    let [low, high] = (whole as u16).to_le_bytes();
    if (whole >> 16) as u16 != 0 || high & 0x80 != 0 {
        return Fix::MAX;
    }
    // rem < span < 2^16, so rem·256 < 2^24 and the same division gives 8 fraction bits:
    // the bits are whole·2^16 + frac·2^8, whole < 2^15 and frac < 2^8, put together as
    // bytes.
    let frac = div_rem(rem << 8, u32::from(span)).0 as u8;
    Fix::from_bits(i32::from_le_bytes([0, frac, low, high]))
}

/// Whether more than ⌊n/3⌋ of `n` edges saw B high, for `b_high` ≤ `n` (they count a
/// subset of the same edges): b > ⌊n/3⌋ exactly when 3·b > n, that is when d = n − b
/// (no borrow) is below 2·b: when d < b, and otherwise exactly when d − b < b. In 16
/// bits, with no division and no multiplication (LLVM makes b + b + b one, a library
/// call on the AVR) and no saturation.
#[inline(always)]
fn mostly_backward(n: u16, b_high: u16) -> bool {
    let d = n.wrapping_sub(b_high);
    d < b_high || d.wrapping_sub(b_high) < b_high
}

/// The drive's speed measurement between two control updates, in 16-bit time: ages in
/// units that each tick's gap adds to, saturating at [`AGE_MAX`], and the last edge's
/// 16-bit timestamp.
///
/// The same speeds as the µs form it replaced (32-bit timestamps, tested against it over
/// long random runs) while every tick gap is below 2^15 µs (the board's ticks are 1 ms
/// apart; the clock flags a longer gap), with one stated exception: an edge-timing
/// update whose reference is [`AGE_MAX`] units old or more (a wheel that rested longer
/// than 262 ms, then moved) measures its n edges from [`AGE_MAX`] units before the
/// update, where the µs form measured from the reference, further back: a speed never
/// below the µs form's and at most n·10⁶/(262,140 − a) ticks/s for a last edge a µs
/// before the update (the µs form's is below that too: 3.9 ticks/s an edge for the last
/// edge on the tick of the update, at most 12.6 for one 182,768 µs before it). The ages are
/// exact (or saturated) whatever the gaps; the last edge's timestamp is dated right when
/// it is less than 2^16 units old at the update, which gaps below 2^15 µs ensure.
///
/// The edge counts between two updates wrap at 2^16, where the µs form saturated: the
/// same while fewer than 65,536 edges come between two updates, which the chip ensures.
/// Updates are at most 182,768 µs apart (150 ms, then a tick gap below 2^15 µs), and a
/// rising edge of A takes two runs of the encoder task (PD0's rise and fall), each at
/// least 20 cycles of 16 MHz: at most 400,000 runs/s, 36,554 rising edges in that time.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct SpeedMeter {
    /// Units since the previous update (or the start).
    elapsed: u16,
    /// Units since the reference: the last edge an update saw, or while none has, the
    /// previous update (so `elapsed`).
    reference_age: u16,
    /// An update saw an edge.
    referenced: bool,
    /// Edges counted since the previous update (wrapping; see above).
    rising: u16,
    /// Of those, with B high.
    b_high: u16,
    /// The last edge seen at all, in units (valid while `rising` > 0: the edges that set
    /// it).
    last_edge: u16,
    /// The last measured speed.
    speed: Fix,
}

impl SpeedMeter {
    /// A meter whose first interval starts at the board's first tick.
    pub const fn new() -> SpeedMeter {
        SpeedMeter {
            elapsed: 0,
            reference_age: 0,
            referenced: false,
            rising: 0,
            b_high: 0,
            last_edge: 0,
            speed: Fix::ZERO,
        }
    }

    /// A tick: `gap` units since the previous one ([`super::clock::age_of`] the clock's
    /// interval), and the edges it took from the [`EdgeCounter`]. The sample's last edge
    /// is the last one the counter ever saw (it keeps it across takes), so it is taken
    /// whatever the count: with no new edge it is the one already kept (no branch).
    #[inline(always)]
    pub fn accumulate(&mut self, sample: &EdgeSample, gap: u16) {
        self.elapsed = age_add(self.elapsed, gap);
        self.reference_age = age_add(self.reference_age, gap);
        self.rising = self.rising.wrapping_add(sample.rising);
        self.b_high = self.b_high.wrapping_add(sample.b_high);
        self.last_edge = sample.last_edge;
    }

    /// Whether the drive update is due in `mode`.
    pub fn due(&self, mode: DriveMode) -> bool {
        match mode {
            DriveMode::Window => self.elapsed > WINDOW,
            DriveMode::EdgeTiming => self.elapsed >= FAST_PERIOD,
        }
    }

    /// Measures the speed (ticks/s) at an update at `now` (units) and starts the next
    /// interval.
    ///
    /// Both modes come down to one [`rate`]: the window's n edges over the time since
    /// the previous update; edge timing's n edges from the reference (the last edge an
    /// update saw) to the last of them, or, without a new edge, one edge over the time
    /// since the reference, which bounds the speed. Before any update saw an edge the
    /// speed is 0 and the interval's start stands in for the reference: the first edges
    /// then count from it, and the bound of a 0 speed is 0 (tested against the form
    /// with each case written out). In line in the tick, its one caller.
    #[inline(always)]
    pub fn measure(&mut self, now: u16, mode: DriveMode) -> Fix {
        let n = self.rising;
        // The last edge's age (valid while n > 0): below 2^16 units, so exact.
        let edge_age = now.wrapping_sub(self.last_edge);
        let (edges, span) = if n == 0 {
            // The bound (edge timing): one edge over the time since the reference.
            (1, self.reference_age)
        } else if mode == DriveMode::Window {
            (n, self.elapsed)
        } else {
            // The reference precedes the last edge. From a saturated reference: from
            // AGE_MAX units before the update.
            (n, self.reference_age.wrapping_sub(edge_age))
        };
        // No edge in the window (0), a bound before any update saw an edge (the speed is
        // 0 until then, so the bound is 0 too), or one the timeout makes 0: no division.
        let rate =
            if n == 0 && (mode == DriveMode::Window || !self.referenced || span >= FAST_TIMEOUT) {
                Fix::ZERO
            } else {
                rate(edges, span)
            };
        let (magnitude, reverse) = if n == 0 {
            if !self.referenced {
                // The previous update stands in for the reference.
                self.reference_age = 0;
            }
            // The speed capped by the bound (by 0: 0), its sign kept.
            (capped_magnitude(self.speed, rate), self.speed < Fix::ZERO)
        } else {
            self.referenced = true;
            self.reference_age = edge_age;
            (rate, mostly_backward(n, self.b_high))
        };
        self.speed = if reverse { -magnitude } else { magnitude };
        self.elapsed = 0;
        self.rising = 0;
        self.b_high = 0;
        self.speed
    }

    /// The last measured speed.
    pub fn speed(&self) -> Fix {
        self.speed
    }
}

impl Default for SpeedMeter {
    /// [`SpeedMeter::new`].
    fn default() -> SpeedMeter {
        SpeedMeter::new()
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

/// The odometer: every rising edge of A, in either direction, counted mod 2^24 (the
/// reading needs bits 8..23 only): three bytes, little-endian.
#[derive(Clone, Copy, PartialEq, Eq, Debug, Default)]
pub struct Odometer {
    edges: [u8; 3],
}

impl Odometer {
    /// Zero.
    pub const fn new() -> Odometer {
        Odometer { edges: [0; 3] }
    }

    /// Counts edges.
    #[inline(always)]
    pub fn add(&mut self, edges: u16) {
        let [b0, b1, b2] = self.edges;
        let sum = u32::from_le_bytes([b0, b1, b2, 0]).wrapping_add(u32::from(edges));
        let [b0, b1, b2, _] = sum.to_le_bytes();
        self.edges = [b0, b1, b2];
    }

    /// REGDS_DRIVE_ODO: ⌊edges/256⌋ mod 65536.
    pub fn reading(&self) -> u16 {
        u16::from_le_bytes([self.edges[1], self.edges[2]])
    }

    /// REG_RESET bit 2.
    pub fn clear(&mut self) {
        self.edges = [0; 3];
    }
}

#[cfg(test)]
mod tests {
    use super::super::clock::units;
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

    /// The µs form [`rate`] replaced: `edges` edges over `span_us` µs, as a 32-bit
    /// quotient with 8 fraction bits (none past 2^24 µs), saturated; past 4294 edges the
    /// span in units of 64 µs.
    fn rate_us(edges: u16, span_us: u32) -> Fix {
        if edges == 0 || span_us == 0 {
            return Fix::ZERO;
        }
        let product = wide(edges, 15_625);
        let (numerator, span) = if edges <= 4_294 {
            (product << 6, span_us)
        } else {
            (product, (span_us >> 6).max(1))
        };
        let (whole, rem) = (numerator / span, numerator % span);
        if whole > 32_767 {
            return Fix::MAX;
        }
        let frac = if span < 1 << 24 { (rem << 8) / span } else { 0 };
        Fix::from_bits((whole << 16 | frac << 8) as i32)
    }

    #[test]
    fn rate_is_the_truncated_quotient_to_a_256th() {
        // ⌊edges·250,000/span⌋ + ⌊256·remainder/span⌋/256 in 64 bits, saturated; past
        // 4294 edges the span counts in 16-unit (64 µs) steps.
        let reference = |edges: u16, span: u16| {
            let (edges, span) = (u64::from(edges), u64::from(span));
            let (numerator, span) = if edges <= 4_294 {
                (edges * 250_000, span)
            } else {
                (edges * 15_625, (span >> 4).max(1))
            };
            let whole = numerator / span;
            if whole > 32_767 {
                return Fix::MAX;
            }
            let frac = (numerator % span) * 256 / span;
            Fix::from_bits(((whole << 16) | (frac << 8)) as i32)
        };
        let spans = [
            1u16, 2, 3, 7, 249, 250, 7_629, 16_383, 16_384, 37_501, 65_534,
        ];
        let mut checked = 0;
        for edges in (0..=u16::MAX).step_by(7).chain([4_294, 4_295, u16::MAX]) {
            for span in spans.into_iter().chain([u16::MAX]) {
                let want = if edges == 0 {
                    Fix::ZERO
                } else {
                    reference(edges, span)
                };
                assert_eq!(rate(edges, span), want, "{edges} edges in {span} units");
                // Never negative: a bound for capped_magnitude.
                assert!(want >= Fix::ZERO, "{edges} edges in {span} units");
                checked += 1;
            }
        }
        assert!(checked > 100_000);
        assert_eq!(rate(150, 37_500), Fix::from_num(1_000));
        assert_eq!(rate(3, 1_750), Fix::from_bits(428 << 16 | 146 << 8));
        assert_eq!(rate(5_000, 25), Fix::MAX);
        assert_eq!(rate(0, 250), Fix::ZERO);
        assert_eq!(rate(9, 0), Fix::ZERO);
    }

    #[test]
    fn rate_in_units_is_the_us_form_at_four_times_the_span() {
        // Every span at a spread of edge counts (both routes), and every 13th edge count
        // at a spread of spans.
        let edge_counts = [1u16, 2, 3, 10, 150, 1_000, 4_294, 4_295, 17_179, u16::MAX];
        let mut checked = 0;
        for edges in edge_counts {
            for span in 0..=u16::MAX {
                assert_eq!(
                    rate(edges, span),
                    rate_us(edges, US_PER_UNIT * u32::from(span)),
                    "{edges} edges in {span} units"
                );
                checked += 1;
            }
        }
        for edges in (0..=u16::MAX).step_by(13) {
            for span in (0..=u16::MAX).step_by(997).chain([u16::MAX]) {
                assert_eq!(
                    rate(edges, span),
                    rate_us(edges, US_PER_UNIT * u32::from(span)),
                    "{edges} edges in {span} units"
                );
                checked += 1;
            }
        }
        assert!(checked > 900_000, "{checked}");
    }

    #[test]
    fn backward_means_more_than_a_third() {
        let values = (0..=400u16).chain([0x5554, 0x5555, 0x5556, 0xaaaa, 0xaaab, u16::MAX]);
        let mut checked = 0;
        for n in values.clone().filter(|&n| n > 0) {
            for b in values.clone().filter(|&b| b <= n) {
                assert_eq!(mostly_backward(n, b), b > n / 3, "{b} of {n}");
                checked += 1;
            }
        }
        assert!(checked > 80_000, "{checked}");
        assert!(mostly_backward(3, 2) && !mostly_backward(3, 1) && mostly_backward(2, 1));
    }

    /// The µs form of the measurement (32-bit timestamps, [`rate_us`]) with each of
    /// edge timing's cases written out: the form [`SpeedMeter`] replaced, for the test
    /// below.
    struct CaseByCase {
        since_us: u32,
        rising: u16,
        b_high: u16,
        reference: Option<u32>,
        last_edge: Option<u32>,
        speed: Fix,
    }

    impl CaseByCase {
        fn accumulate(&mut self, rising: u16, b_high: u16, last_edge_us: u32) {
            if rising > 0 {
                self.rising = self.rising.saturating_add(rising);
                self.b_high = self.b_high.saturating_add(b_high);
                self.last_edge = Some(last_edge_us);
            }
        }

        fn due(&self, now_us: u32, mode: DriveMode) -> bool {
            let elapsed = now_us.wrapping_sub(self.since_us);
            match mode {
                DriveMode::Window => elapsed > WINDOW_US,
                DriveMode::EdgeTiming => elapsed >= FAST_PERIOD_US,
            }
        }

        fn measure(&mut self, now_us: u32, mode: DriveMode) -> Fix {
            let n = self.rising;
            let fresh = |edge: u32| now_us.wrapping_sub(edge) < FAST_TIMEOUT_US;
            let magnitude = match mode {
                DriveMode::Window => rate_us(n, now_us.wrapping_sub(self.since_us)),
                DriveMode::EdgeTiming => match (n, self.last_edge, self.reference) {
                    (0, _, Some(reference)) if fresh(reference) => {
                        let bound = rate_us(1, now_us.wrapping_sub(reference));
                        self.speed.saturating_abs().min(bound)
                    }
                    (0, _, _) => Fix::ZERO,
                    (_, Some(last), Some(reference)) => rate_us(n, last.wrapping_sub(reference)),
                    (_, Some(last), None) => rate_us(n, last.wrapping_sub(self.since_us)),
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

    /// Whether a µs span is one the meter saturates: [`AGE_MAX`] units or more.
    fn saturates(span_us: u32) -> bool {
        span_us >= US_PER_UNIT * u32::from(AGE_MAX)
    }

    #[test]
    fn the_16_bit_meter_gives_the_us_form_s_speeds() {
        // Random runs on the chip's time (whole 4-µs units, the µs clock wrapping): ticks
        // of 1 ms, now and then a late one (up to 2^15 µs less a unit); edges at random
        // times since the previous tick's take (which precedes its clock read by a
        // little), 0..k a tick with k stepping now and then, rests of random length,
        // reversals, the mode switching now and then.
        let mut random = crate::test_random::Xorshift(0x2545_f491_4f6c_dd1du64);
        let mut next = |bound: u32| random.below(bound);
        let (mut nonzero, mut bounded, mut capped, mut updates) = (0, 0, 0, 0);
        let (mut long_rests, mut saturated, mut windows) = (0, 0, 0);
        for run in 0..300u32 {
            // Starts near the clock's wrap on some runs.
            let start = if run % 3 == 0 {
                0u32.wrapping_sub(4 * next(100_000))
            } else {
                4 * next(1 << 30)
            };
            let mut meter = SpeedMeter::new();
            let mut clock = super::super::clock::Clock::new();
            let mut model = CaseByCase {
                since_us: start,
                rising: 0,
                b_high: 0,
                reference: None,
                last_edge: None,
                speed: Fix::ZERO,
            };
            let mut counter = EdgeCounter::new();
            let mut mode = if run % 2 == 0 {
                DriveMode::EdgeTiming
            } else {
                DriveMode::Window
            };
            let mut now = start;
            clock.advance(now);
            let mut moving = next(2) == 0;
            let mut most = 1 + next(4);
            let mut last_edge_us = None::<u32>;
            let mut rest_from = now;
            for _ in 0..3_000 {
                let tick = match next(400) {
                    0 => 4 * (1 + next(8_191)),
                    1..=3 => 4 * (1 + next(2_000)),
                    _ => 1_000,
                };
                if next(150) == 0 {
                    moving = !moving;
                    if !moving {
                        rest_from = now;
                    } else if now.wrapping_sub(rest_from) > 262_144 {
                        long_rests += 1;
                    }
                }
                if next(100) == 0 {
                    most = 1 + next(6);
                }
                // The tick takes the edges 8 µs before it reads the clock: those it
                // takes came after the previous take and up to its own, in order.
                let taken = now.wrapping_add(tick);
                if moving {
                    let backward = next(4) == 0;
                    let mut times: Vec<u32> = (0..next(most + 1))
                        .map(|_| 4 * (next(tick / 4) + 1))
                        .collect();
                    times.sort();
                    for after in times {
                        let at = now.wrapping_sub(8).wrapping_add(after);
                        last_edge_us = Some(at);
                        counter.rising_edge(units(at), backward != (next(8) == 0));
                    }
                }
                now = taken;
                clock.advance(now);
                let sample = counter.take();
                meter.accumulate(&sample, clock.gap());
                model.accumulate(sample.rising, sample.b_high, last_edge_us.unwrap_or(0));
                if next(300) == 0 {
                    mode = match mode {
                        DriveMode::Window => DriveMode::EdgeTiming,
                        DriveMode::EdgeTiming => DriveMode::Window,
                    };
                }
                let due = meter.due(mode);
                assert_eq!(due, model.due(now, mode), "run {run} at {now}");
                if due {
                    let n = meter.rising;
                    let bounding = mode == DriveMode::EdgeTiming && n == 0;
                    let before = meter.speed();
                    // The one stated difference: an edge-timing update with edges whose
                    // reference is AGE_MAX units old or more measures from AGE_MAX units
                    // before the update.
                    let stale = mode == DriveMode::EdgeTiming
                        && n > 0
                        && saturates(now.wrapping_sub(model.reference.unwrap_or(model.since_us)));
                    let (reverse, last) = (model.b_high > n / 3, model.last_edge);
                    let want = model.measure(now, mode);
                    let speed = meter.measure(units(now), mode);
                    if stale {
                        let age = last.map(|last| now.wrapping_sub(last)).unwrap_or(0);
                        let span = US_PER_UNIT * u32::from(AGE_MAX) - age;
                        let far = rate_us(n, span);
                        assert_eq!(speed, if reverse { -far } else { far }, "run {run}");
                        // Never below the µs form's speed, and at most n·10^6/span.
                        assert!(speed.abs() >= want.abs(), "run {run} at {now}");
                        let most = f64::from(n) * 1e6 / f64::from(span);
                        assert!(far <= Fix::from_num(most) && age < 182_768, "{n} {span}");
                        // The µs form carries the meter's speed on.
                        model.speed = speed;
                        saturated += 1;
                    } else {
                        assert_eq!(speed, want, "run {run} at {now} ({mode:?})");
                    }
                    bounded += usize::from(bounding);
                    capped += usize::from(bounding && speed != Fix::ZERO && speed != before);
                    windows += usize::from(mode == DriveMode::Window && n > 0);
                    nonzero += usize::from(speed != Fix::ZERO);
                    updates += 1;
                }
            }
        }
        assert!(
            updates > 40_000 && nonzero > 20_000,
            "{nonzero} of {updates}"
        );
        assert!(
            bounded > 10_000 && capped > 1_000,
            "{bounded}, {capped} capped"
        );
        assert!(nonzero < updates - 10_000, "{nonzero} of {updates}");
        assert!(
            long_rests > 200 && saturated > 100 && windows > 1_000,
            "{long_rests} long rests, {saturated} saturated, {windows} windows"
        );
    }

    #[test]
    fn the_24_bit_odometer_reads_as_a_32_bit_count() {
        let mut random = crate::test_random::Xorshift(0x9e37_79b9_7f4a_7c15u64);
        let (mut odometer, mut wide) = (Odometer::new(), 0u64);
        for k in 0..200_000 {
            let edges = match random.below(4) {
                0 => u16::MAX - random.below(3) as u16,
                1 => random.below(65_536) as u16,
                _ => random.below(40) as u16,
            };
            odometer.add(edges);
            wide += u64::from(edges);
            assert_eq!(odometer.reading(), (wide >> 8) as u16, "{k}");
        }
        assert!(
            wide >> 24 > 100,
            "the 24-bit count wrapped {} times",
            wide >> 24
        );
        odometer.clear();
        assert_eq!((odometer, odometer.reading()), (Odometer::new(), 0));
    }

    #[test]
    fn a_new_meter_is_the_default() {
        assert_eq!(SpeedMeter::default(), SpeedMeter::new());
        assert!(!SpeedMeter::new().due(DriveMode::EdgeTiming));
        let mut meter = SpeedMeter::new();
        meter.accumulate(&EdgeSample::default(), 2_500);
        assert!(meter.due(DriveMode::EdgeTiming) && !meter.due(DriveMode::Window));
        meter.accumulate(&EdgeSample::default(), 35_000);
        assert!(!meter.due(DriveMode::Window));
        meter.accumulate(&EdgeSample::default(), 1);
        assert!(meter.due(DriveMode::Window));
    }
}
