//! The slave's PID controllers (reference §7.1) in `I16F16` fixed point.
//!
//! Two forms share one update rule for the error, integral and derivative:
//! - e = r − a, set to 0 when 0 < |e| < dead zone;
//! - I = clamp((I + e)·decay, −cap, cap);
//! - D = −(a − a_prev): the negated change of the measurement per update.
//!
//! The **position** form (steer, lift) outputs u = P·e + Ki·I + Kd·D. The **speed** form
//! (drive) is incremental: u = u_prev + P·e + Ki·I + Kd·D, then u := 0.96·u while
//! |r| < 0.001; u itself is never clamped. The motor gets m = trunc(u) toward zero:
//! duty = min(|m|, 255), forward when m ≥ 0.
//!
//! Gains act per update; the interval between updates is never used. Everything is
//! multiplication ([`mul`]) and addition (no division), saturating at the `I16F16` limits
//! (±32768) where the original's float would keep growing. The duty saturates at 255
//! long before, so this shows only after a long wind-up of the speed form's u (a wheel
//! held against a demand it cannot reach): when the demand then goes to 0, the 0.96
//! bleed keeps full duty for 118 updates here (17.7 s of 150-ms windows), where the
//! original's u, wound up further, keeps it longer (163 from u = 200,000: 24.5 s).
//! Documented in docs/protocol.md ("How the slaves compute").

pub mod sum;

use crate::slave::product::fixed;
use fixed::types::I16F16;

/// The fixed-point number type of the slave's control maths: 16 integer bits
/// (±32768) and 16 fraction bits (1/65536).
pub type Fix = I16F16;

/// `a·b`, saturating at the `I16F16` limits and truncating toward zero.
///
/// A zero operand (a zero gain, integral or error) returns at once. One out-of-line
/// routine ([`fixed()`]: assembly on the AVR) with its zero tests: tested at each call site
/// instead, they cost 240 B of flash to save some 20–70 cycles a moving tick.
#[inline(always)]
pub fn mul(a: Fix, b: Fix) -> Fix {
    Fix::from_bits(fixed(a.to_bits(), b.to_bits()))
}

/// Saturating `I16F16` operations, one out-of-line copy each ([`sum`]: assembly on the
/// AVR): the `fixed` crate's are inlined at every use, 40 to 90 bytes each on the AVR.
/// Every saturating sum and difference of the slave goes through these (its one
/// saturating |x|, the encoder's, is two compares in line).
pub(crate) trait Saturating {
    /// `self + other`, saturating.
    fn add_sat(self, other: Self) -> Self;
    /// `self − other`, saturating.
    fn sub_sat(self, other: Self) -> Self;
}

impl Saturating for Fix {
    #[inline(always)]
    fn add_sat(self, other: Fix) -> Fix {
        Fix::from_bits(sum::add(self.to_bits(), other.to_bits()))
    }

    #[inline(always)]
    fn sub_sat(self, other: Fix) -> Fix {
        Fix::from_bits(sum::sub(self.to_bits(), other.to_bits()))
    }
}

/// |x| in bits, exact (no saturation: |−32768| is 2^31): a few inline instructions, for
/// comparing a magnitude on the per-update path without a call.
#[inline(always)]
pub(crate) fn magnitude(x: Fix) -> u32 {
    sum::magnitude(x.to_bits())
}

/// Whether |x| < `limit` for a constant `limit` of at least 2^−16 and below 2^14: one
/// sum and one unsigned compare, no |x|. −l < x < l exactly when x + l − 2^−16 is below
/// 2l − 2^−16 unsigned; a sum that wraps past `i32::MAX` comes out negative, which reads
/// as above that bound too.
#[inline(always)]
pub(crate) fn below(x: Fix, limit: Fix) -> bool {
    let l = limit.to_bits();
    (x.to_bits().wrapping_add(l - 1) as u32) < (2 * l - 1) as u32
}

/// The speed form bleeds its output by this factor per update while |r| < 0.001.
pub const BLEED: Fix = Fix::from_bits(62_915); // 0.96, rounded to the nearest 1/65536
/// |r| below this counts as "no demand" for the bleed (0.001, rounded down).
pub const NO_DEMAND: Fix = Fix::from_bits(65);

/// Which way a motor turns.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Direction {
    /// POS high, NEG low.
    Forward,
    /// POS low, NEG high.
    Reverse,
}

/// A PWM duty (0..255) and a direction: what a controller asks of its motor.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct Duty {
    /// PWM duty, 0..255.
    pub magnitude: u8,
    /// Direction pins.
    pub direction: Direction,
}

impl Duty {
    /// Duty 0, forward: what a motor gets before its first update.
    pub const IDLE: Duty = Duty {
        magnitude: 0,
        direction: Direction::Forward,
    };

    /// The duty for a control value: m = trunc(u) toward zero, duty = min(|m|, 255),
    /// forward when m ≥ 0.
    pub fn from_control(u: Fix) -> Duty {
        // |m| = ⌊|u|⌋, the high half of |u|'s bits; m < 0 when u < 0 and |m| ≠ 0.
        let bits = u.to_bits();
        let whole = (magnitude(u) >> 16) as u16;
        let magnitude = u8::try_from(whole).unwrap_or(u8::MAX);
        let direction = if bits < 0 && whole != 0 {
            Direction::Reverse
        } else {
            Direction::Forward
        };
        Duty {
            magnitude,
            direction,
        }
    }
}

/// The parameters of one controller, as the slave holds them after unmapping its
/// registers.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct Gains {
    /// P gain: duty per unit of error.
    pub p: Fix,
    /// I gain: duty per unit of integral.
    pub i: Fix,
    /// D gain: duty per unit of change per update.
    pub d: Fix,
    /// Integral clamp (applied as ±cap). Never negative (its register's range is
    /// 0..1000): the update negates it without saturation.
    pub cap: Fix,
    /// Integral multiplier per update.
    pub decay: Fix,
    /// Errors smaller than this (and not zero) count as zero. Never negative (its
    /// register's range is 0..50): the update compares |e| with its bits unsigned.
    pub dead_zone: Fix,
}

impl Gains {
    /// All zero: the power-on parameters (the controller outputs nothing).
    pub const ZERO: Gains = Gains {
        p: Fix::ZERO,
        i: Fix::ZERO,
        d: Fix::ZERO,
        cap: Fix::ZERO,
        decay: Fix::ZERO,
        dead_zone: Fix::ZERO,
    };
}

/// What one update computed: the monitoring values and the output.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct Step {
    /// e after the dead zone.
    pub error: Fix,
    /// I after decay and clamp.
    pub integral: Fix,
    /// D = −(a − a_prev).
    pub deriv: Fix,
    /// u, the control value.
    pub control: Fix,
    /// The duty and direction u stands for.
    pub duty: Duty,
}

impl Step {
    /// A position update at rest: every term and the output 0, duty 0 forward.
    ///
    /// A position update that returns it leaves the controller at I = 0 with the
    /// measurement taken, and implies cap ≥ 0 (a negative cap clamps I to the cap), so
    /// another update with the same gains, demand and measurement returns it again and
    /// changes nothing.
    pub const REST: Step = Step {
        error: Fix::ZERO,
        integral: Fix::ZERO,
        deriv: Fix::ZERO,
        control: Fix::ZERO,
        duty: Duty::IDLE,
    };

    /// Whether every term and the output are 0 (see [`Step::REST`]).
    pub fn is_rest(&self) -> bool {
        self.deriv == Fix::ZERO && self.rests()
    }

    /// Whether, after this position step, another update with the same gains, demand
    /// and measurement returns [`Step::REST`] and leaves the controller as it is: e = 0
    /// (the same e again), I = 0 (so (I + e)·δ is 0 again, and cap ≥ 0: a negative cap
    /// clamps I to the cap) and u = 0 (the controller's u and the duty are already
    /// those of the rest). D need not be 0: the next D is 0, the measurement being the
    /// same (tested).
    pub fn rests(&self) -> bool {
        // The three values' bits OR-ed, folded to 16 bits: 0 exactly when all are 0 (the
        // AVR's 32-bit comparisons each materialise a flag).
        let bits = (self.error.to_bits() | self.integral.to_bits() | self.control.to_bits()) as u32;
        (bits as u16 | (bits >> 16) as u16) == 0
    }
}

/// The two forms of [`Pid`]'s update ([`Pid::update`]).
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Form {
    /// u = P·e + Ki·I + Kd·D.
    Position,
    /// u = u_prev + P·e + Ki·I + Kd·D, bled while there is no demand.
    Speed,
}

/// The state of one PID controller between updates.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct Pid {
    integral: Fix,
    prev_actual: Fix,
    control: Fix,
}

impl Default for Pid {
    fn default() -> Self {
        Pid::new()
    }
}

impl Pid {
    /// A controller at power-on: integral, previous measurement and output all zero.
    pub const fn new() -> Pid {
        Pid {
            integral: Fix::ZERO,
            prev_actual: Fix::ZERO,
            control: Fix::ZERO,
        }
    }

    /// One update of the position form: u = P·e + Ki·I + Kd·D.
    ///
    /// At rest (e = 0 after the dead zone, I = 0, the measurement unchanged, cap ≥ 0:
    /// a motor holding its angle) every term is 0 and stays 0: the update returns
    /// [`Step::REST`] (tested). Its products of 0 return at once ([`mul`]); the motor
    /// skips the next such update altogether (`Motor::holds`), so the PID has no rest
    /// path of its own (186 B of flash for one update per settling).
    #[inline(always)]
    pub fn position(&mut self, gains: &Gains, required: Fix, actual: Fix) -> Step {
        self.update(Form::Position, gains, required, actual)
    }

    /// One update of the incremental speed form: u = u_prev + P·e + Ki·I + Kd·D, then
    /// ×0.96 while |r| < 0.001.
    #[inline(always)]
    pub fn speed(&mut self, gains: &Gains, required: Fix, actual: Fix) -> Step {
        self.update(Form::Speed, gains, required, actual)
    }

    /// One update of either form ([`Pid::position`], [`Pid::speed`]).
    ///
    /// Both forms are one routine: they differ only in how u is made from the terms' sum,
    /// so a board with both (drive/steer) carries one copy of the rest. It is left to the
    /// optimiser to inline: each board's one motor update (one copy for both motors) takes
    /// it in line, without the call, the returned step in memory and a second save of
    /// the registers (drive 44 B, lift 112 B smaller than out of line), and a board with
    /// one form (lift/lift) gets it specialised.
    #[inline]
    pub fn update(&mut self, form: Form, gains: &Gains, required: Fix, actual: Fix) -> Step {
        let error = dead_zoned(gains, required, actual);
        let (integral, deriv) = self.terms(gains, error, actual);
        let sum = sum_terms(gains, error, integral, deriv);
        let control = match form {
            Form::Position => sum,
            Form::Speed => {
                let control = self.control.add_sat(sum);
                if below(required, NO_DEMAND) {
                    mul(control, BLEED)
                } else {
                    control
                }
            }
        };
        self.control = control;
        step(error, integral, deriv, control)
    }

    /// The integral state.
    pub fn integral(&self) -> Fix {
        self.integral
    }

    /// The last control value u.
    pub fn control(&self) -> Fix {
        self.control
    }

    /// The measurement of the last update.
    pub fn last_actual(&self) -> Fix {
        self.prev_actual
    }

    /// Starts the output and the integral again from 0, keeping the last measurement
    /// (D stays the change since it): for a motor leaving an exception, so that a drive
    /// stopped at speed does not resume at the output it had (the speed form's u is
    /// otherwise never reset, reference §7.1).
    #[inline(always)]
    pub fn restart(&mut self) {
        self.integral = Fix::ZERO;
        self.control = Fix::ZERO;
    }

    /// I and D for the error `error` (after the dead zone), updating the state.
    fn terms(&mut self, gains: &Gains, error: Fix, actual: Fix) -> (Fix, Fix) {
        let integral = self.integral.add_sat(error);
        let integral = clamp(mul(integral, gains.decay), gains.cap);
        self.integral = integral;
        let deriv = self.prev_actual.sub_sat(actual);
        self.prev_actual = actual;
        (integral, deriv)
    }
}

/// `x` clamped to ±`cap` (cap ≥ 0).
fn clamp(x: Fix, cap: Fix) -> Fix {
    Fix::from_bits(sum::clamp(x.to_bits(), cap.to_bits()))
}

/// e = r − a, 0 when 0 < |e| < dead zone.
fn dead_zoned(gains: &Gains, required: Fix, actual: Fix) -> Fix {
    let error = required.sub_sat(actual);
    // |e| < z: an error of 0 stays 0 either way, and z ≥ 0 (see [`Gains::dead_zone`]).
    Fix::from_bits(sum::dead_zone(
        error.to_bits(),
        gains.dead_zone.to_bits() as u32,
    ))
}

fn sum_terms(gains: &Gains, error: Fix, integral: Fix, deriv: Fix) -> Fix {
    // A zero P or D gain (a position motor's, as calibrate() sets them; D is the drive's
    // too) is skipped before the call to `mul` and to the sum (a saturating sum with 0 is
    // the other operand, bit for bit): two products and a sum fewer a moving position
    // update. The I term is always computed (a zero gain or I returns at once inside
    // `mul`): its test would cost more flash than the drive's skip saves.
    let mut sum = Fix::ZERO;
    if nonzero(gains.p) {
        sum = mul(gains.p, error);
    }
    sum = sum.add_sat(mul(gains.i, integral));
    if nonzero(gains.d) {
        sum = sum.add_sat(mul(gains.d, deriv));
    }
    sum
}

/// Whether `x` is not 0, by its bits folded to 16 (lo | hi): the AVR's 32-bit test
/// against 0 materialises a flag, this is two ORs and one 16-bit test.
#[inline(always)]
fn nonzero(x: Fix) -> bool {
    let bits = x.to_bits() as u32;
    (bits as u16 | (bits >> 16) as u16) != 0
}

fn step(error: Fix, integral: Fix, deriv: Fix, control: Fix) -> Step {
    Step {
        error,
        integral,
        deriv,
        control,
        duty: Duty::from_control(control),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fix(v: f64) -> Fix {
        Fix::from_num(v)
    }

    #[test]
    fn nonzero_is_the_bits_not_0() {
        let edges = [
            0,
            1,
            -1,
            0xffff,
            0x1_0000,
            0x8000,
            i32::MIN,
            i32::MAX,
            0x7fff_0000,
        ];
        let sweep = (i32::MIN..=i32::MAX).step_by(65_521);
        let mut zero = 0;
        for bits in edges.into_iter().chain(sweep) {
            assert_eq!(nonzero(Fix::from_bits(bits)), bits != 0, "{bits:#x}");
            zero += usize::from(bits == 0);
        }
        assert_eq!(zero, 1);
    }

    #[test]
    fn duty_truncates_toward_zero_and_saturates() {
        let cases = [
            (0.0, 0, Direction::Forward),
            (0.99, 0, Direction::Forward),
            (-0.99, 0, Direction::Forward),
            (-1.0, 1, Direction::Reverse),
            (-1.5, 1, Direction::Reverse),
            (254.9, 254, Direction::Forward),
            (300.0, 255, Direction::Forward),
            (-300.0, 255, Direction::Reverse),
            (-32768.0, 255, Direction::Reverse),
        ];
        for (u, magnitude, direction) in cases {
            assert_eq!(
                Duty::from_control(fix(u)),
                Duty {
                    magnitude,
                    direction
                },
                "u = {u}"
            );
        }
    }

    #[test]
    fn mul_matches_exact_products_and_saturates() {
        let cases = [
            (1.5, 2.0, 3.0),
            (-1.5, 2.0, -3.0),
            (-1.5, -2.0, 3.0),
            (0.0099185, 1000.0, 9.9185),
            (300.0, 0.95, 285.0),
            (181.0, 181.0, 32761.0),
            (182.0, 181.0, 32767.99998),
            (-182.0, 181.0, -32768.0),
            (-32768.0, 1.0, -32768.0),
            (-32768.0, -1.0, 32767.99998),
            (0.5, Fix::DELTA.to_num::<f64>(), 0.0),
            (0.95, 300.0, 285.0),
            (-0.95, -32768.0, 31129.5),
            (0.99998, -32768.0, -32767.5),
            (0.99998, 32767.99998, 32767.5),
            (2.0, 0.0001, 0.0002),
        ];
        for (a, b, product) in cases {
            let got = mul(fix(a), fix(b)).to_num::<f64>();
            let exact =
                (fix(a).to_num::<f64>() * fix(b).to_num::<f64>()).clamp(-32768.0, 32767.99998);
            assert!((got - exact).abs() < 2e-5, "{a} × {b} = {got}, not {exact}");
            assert!((got - product).abs() < 1e-3, "{a} × {b} = {got}");
        }
        // Against the fixed crate's saturating multiply: equal up to the rounding of
        // the last bit (toward zero here, toward −∞ there).
        let values = [
            -32768.0, -1000.5, -3.25, -0.999, -0.001, 0.0, 0.0625, 0.5, 0.95, 1.0, 7.77, 255.0,
            32767.0,
        ];
        for a in values {
            for b in values {
                let (x, y) = (fix(a), fix(b));
                let diff = mul(x, y).to_bits().abs_diff(x.saturating_mul(y).to_bits());
                assert!(diff <= 1, "{a} × {b}");
            }
        }
    }

    #[test]
    fn an_update_at_rest_returns_rest_and_keeps_returning_it() {
        // Every state at rest (I = 0, the measurement unchanged, e dead-zoned to 0 or 0,
        // cap ≥ 0): Step::REST, the state as before but u = 0, and the same again.
        let gains = |p: f64, cap: f64, dead_zone: f64| Gains {
            p: fix(p),
            i: fix(2.0),
            d: fix(-1.5),
            cap: fix(cap),
            decay: fix(0.95),
            dead_zone: fix(dead_zone),
        };
        let values = [-3.0, -0.5, -0.25, 0.0, 0.25, 0.5, 20.0];
        let mut rests = 0;
        for g in [gains(0.0, 300.0, 0.5), gains(3.0, 0.0, 0.0)] {
            for actual in values {
                for required in values {
                    let (r, x) = (fix(required), fix(actual));
                    let mut pid = Pid {
                        integral: Fix::ZERO,
                        prev_actual: x,
                        control: fix(7.0),
                    };
                    let step = pid.position(&g, r, x);
                    let at_rest = (r - x).abs() < g.dead_zone || r == x;
                    assert_eq!(step == Step::REST, at_rest, "{required} {actual}");
                    assert_eq!(step.is_rest(), at_rest, "{required} {actual}");
                    if at_rest {
                        rests += 1;
                        let state = Pid {
                            integral: Fix::ZERO,
                            prev_actual: x,
                            control: Fix::ZERO,
                        };
                        assert_eq!(pid, state);
                        assert_eq!(pid.position(&g, r, x), Step::REST);
                        assert_eq!(pid, state);
                    }
                }
            }
        }
        // Dead zone 0.5: the 7 equal pairs and the 8 a quarter apart; dead zone 0: the 7.
        assert_eq!(rests, 15 + 7);
    }

    #[test]
    fn rests_is_every_one_of_error_integral_and_control_zero() {
        // The form it replaced: three comparisons with 0. Bits in one half only, in both,
        // the sign bit alone, and 0, in every combination of the three values.
        let bits = [
            0,
            1,
            -1,
            0x8000,
            0xffff,
            0x1_0000,
            0x7fff_0000,
            i32::MIN,
            i32::MAX,
            0x0001_0001,
        ];
        let mut rests = 0;
        for e in bits {
            for i in bits {
                for c in bits {
                    let step = Step {
                        error: Fix::from_bits(e),
                        integral: Fix::from_bits(i),
                        deriv: Fix::from_bits(e ^ c),
                        control: Fix::from_bits(c),
                        duty: Duty::IDLE,
                    };
                    let want = e == 0 && i == 0 && c == 0;
                    assert_eq!(step.rests(), want, "{e:#x} {i:#x} {c:#x}");
                    rests += usize::from(want);
                }
            }
        }
        assert_eq!(rests, 1);
    }

    #[test]
    fn a_step_that_rests_is_followed_by_rest() {
        // Any position step for which `rests()` holds: the same demand and measurement
        // again give Step::REST and leave the controller as it was, whatever D was.
        let values = [-3.0, -0.5, -0.25, 0.0, 0.25, 0.5, 20.0];
        let mut rests = 0;
        let mut moving_rests = 0;
        for (p, d, cap, decay, dead_zone) in [
            (0.0, 0.0, 300.0, 0.95, 0.5),
            (3.0, 0.0, 0.0, 0.0, 0.0),
            (1.0, -1.5, 50.0, 0.9, 1.0),
            (1.0, 0.0, 5.0, 0.5, 1.0),
        ] {
            let g = Gains {
                p: fix(p),
                i: fix(2.0),
                d: fix(d),
                cap: fix(cap),
                decay: fix(decay),
                dead_zone: fix(dead_zone),
            };
            for prev in values {
                for actual in values {
                    for required in values {
                        for integral in [0.0, 0.75, -0.25] {
                            let mut pid = Pid {
                                integral: fix(integral),
                                prev_actual: fix(prev),
                                control: fix(7.0),
                            };
                            let (r, x) = (fix(required), fix(actual));
                            let step = pid.position(&g, r, x);
                            if !step.rests() {
                                continue;
                            }
                            rests += 1;
                            moving_rests += usize::from(step.deriv != Fix::ZERO);
                            let state = pid;
                            assert_eq!(pid.position(&g, r, x), Step::REST);
                            assert_eq!(pid, state);
                        }
                    }
                }
            }
        }
        assert!(rests > 100 && moving_rests > 20, "{rests} {moving_rests}");
    }

    #[test]
    fn duty_equals_the_rounding_toward_zero_form() {
        // The form it replaced: m = round_to_zero(u) in whole units.
        let reference = |u: Fix| {
            let m = u.round_to_zero().to_bits() >> 16;
            let magnitude = u8::try_from(m.unsigned_abs()).unwrap_or(u8::MAX);
            let direction = if m >= 0 {
                Direction::Forward
            } else {
                Direction::Reverse
            };
            Duty {
                magnitude,
                direction,
            }
        };
        let mut cases = 0u32;
        // Every whole value from −300 to 300 and its neighbours, then a sweep of all bits.
        for whole in -300i32..=300 {
            for offset in [-1, 0, 1, 0x8000] {
                let u = Fix::from_bits((whole << 16).wrapping_add(offset));
                assert_eq!(Duty::from_control(u), reference(u), "{u}");
                cases += 1;
            }
        }
        for bits in (i32::MIN..=i32::MAX).step_by(65_521) {
            let u = Fix::from_bits(bits);
            assert_eq!(Duty::from_control(u), reference(u), "{u}");
            cases += 1;
        }
        assert!(cases > 65_000, "{cases}");
    }

    #[test]
    fn mul_is_the_truncated_saturated_product_bit_for_bit() {
        // ⌊|a·b|/2^16⌋, saturated, with the sign of a·b: in 64 bits.
        let reference = |a: i32, b: i32| {
            let magnitude = (u64::from(a.unsigned_abs()) * u64::from(b.unsigned_abs())) >> 16;
            let negative = (a ^ b) < 0 && magnitude != 0;
            let limit = if negative {
                1u64 << 31
            } else {
                (1u64 << 31) - 1
            };
            let m = magnitude.min(limit) as i64;
            (if negative { -m } else { m }) as i32
        };
        let mut bits = vec![
            0i32,
            1,
            -1,
            0xffff,
            -0xffff,
            0x1_0000,
            -0x1_0000,
            i32::MAX,
            i32::MIN,
        ];
        let mut x = 0x2545_f491u32;
        for _ in 0..400 {
            x ^= x << 13;
            x ^= x >> 17;
            x ^= x << 5;
            // Magnitudes of every size, from below 1/65536 to the limits.
            bits.push((x as i32) >> (x % 31));
        }
        for &a in &bits {
            for &b in &bits {
                let got = mul(Fix::from_bits(a), Fix::from_bits(b)).to_bits();
                assert_eq!(got, reference(a, b), "{a:#x} × {b:#x}");
            }
        }
    }

    #[test]
    fn below_is_a_magnitude_compare() {
        let sweep = (i32::MIN..=i32::MAX).step_by(4_093);
        for limit in [NO_DEMAND, Fix::DELTA, Fix::ONE, fix(16_383.5)] {
            let l = limit.to_bits();
            let edges = [
                i32::MIN,
                -l - 1,
                -l,
                -l + 1,
                -1,
                0,
                1,
                l - 1,
                l,
                l + 1,
                i32::MAX,
            ];
            for bits in edges.into_iter().chain(sweep.clone()) {
                let x = Fix::from_bits(bits);
                assert_eq!(
                    below(x, limit),
                    magnitude(x) < l as u32,
                    "{bits:#x} {limit}"
                );
            }
        }
    }

    #[test]
    fn clamp_equals_max_then_min_for_every_cap() {
        // Every cap its register gives (0..1000.02) and then some, against the form it
        // replaced.
        let caps = [
            0.0,
            Fix::DELTA.to_num(),
            0.5,
            49.989,
            299.997,
            1000.0,
            1000.02,
            32767.0,
        ];
        let sweep = (i32::MIN..=i32::MAX).step_by(65_537);
        for cap in caps.map(fix) {
            let c = cap.to_bits();
            let edges = [i32::MIN, -c - 1, -c, -c + 1, 0, c - 1, c, c + 1, i32::MAX];
            for bits in edges.into_iter().chain(sweep.clone()) {
                let x = Fix::from_bits(bits);
                assert_eq!(clamp(x, cap), x.max(-cap).min(cap), "{x} {cap}");
            }
        }
    }

    #[test]
    fn a_wound_up_speed_form_stops_at_the_limit_and_keeps_full_duty_for_118_bleeds() {
        // A wheel held against 1000 ticks/s with P = 10: u grows by ~10,000 an update.
        let gains = Gains {
            p: fix(10.0),
            ..Gains::ZERO
        };
        let mut pid = Pid::new();
        for _ in 0..20 {
            pid.speed(&gains, fix(1000.0), Fix::ZERO);
        }
        assert_eq!(pid.control(), Fix::MAX, "u saturates at the I16F16 limit");
        // The demand goes to 0 (the wheel still held): only the bleed acts.
        let mut full = 0;
        while pid.speed(&gains, Fix::ZERO, Fix::ZERO).duty.magnitude == 255 {
            full += 1;
        }
        assert_eq!(full, 118, "the 119th bleed is the first below full duty");
        // The original's float u after 20 updates of 10·(1000 − 0) keeps full duty for
        // 163 bleeds.
        let (mut u, mut n) = (200_000.0f64, 0);
        while (u * 0.96).trunc() >= 255.0 {
            u *= 0.96;
            n += 1;
        }
        assert_eq!(n, 163);
    }

    #[test]
    fn constants_are_what_they_stand_for() {
        assert!((BLEED.to_num::<f64>() - 0.96).abs() < 1e-5);
        assert!(NO_DEMAND < fix(0.001) && NO_DEMAND + Fix::DELTA > fix(0.000999));
    }
}
