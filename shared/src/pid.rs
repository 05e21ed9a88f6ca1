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
//! (±32768) where the original's float would keep growing: a difference no working
//! program can see, since the duty saturates at 255 long before.

use fixed::types::I16F16;

/// The fixed-point number type of the slave's control maths: 16 integer bits
/// (±32768) and 16 fraction bits (1/65536).
pub type Fix = I16F16;

/// `a·b`, saturating at the `I16F16` limits and truncating toward zero.
///
/// Four 16×16→32-bit products instead of the 64-bit multiplication a widening multiply
/// needs: on the AVR this takes some 600 cycles, a 64-bit multiply more. A zero operand
/// returns at once.
#[inline(never)]
pub fn mul(a: Fix, b: Fix) -> Fix {
    let (a, b) = (a.to_bits(), b.to_bits());
    if a == 0 || b == 0 {
        return Fix::ZERO;
    }
    let negative = (a ^ b) < 0;
    let (ua, ub) = (a.unsigned_abs(), b.unsigned_abs());
    let (ah, al) = ((ua >> 16) as u16, ua as u16);
    let (bh, bl) = ((ub >> 16) as u16, ub as u16);
    let wide = |x: u16, y: u16| u32::from(x) * u32::from(y);
    // |a·b| in 16.16 = ah·bh·2^16 + ah·bl + al·bh + al·bl/2^16, with ah, bh ≤ 2^15.
    let high = wide(ah, bh);
    let magnitude = if high > 0x7fff {
        None
    } else {
        (high << 16)
            .checked_add(wide(ah, bl))
            .and_then(|m| m.checked_add(wide(al, bh)))
            .and_then(|m| m.checked_add(wide(al, bl) >> 16))
    };
    let limit = if negative {
        1u32 << 31
    } else {
        (1u32 << 31) - 1
    };
    let magnitude = magnitude.map_or(limit, |m| m.min(limit));
    Fix::from_bits(if negative {
        0i32.wrapping_sub_unsigned(magnitude)
    } else {
        magnitude as i32
    })
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
    /// Integral clamp (applied as ±cap).
    pub cap: Fix,
    /// Integral multiplier per update.
    pub decay: Fix,
    /// Errors smaller than this (and not zero) count as zero.
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
    pub fn position(&mut self, gains: &Gains, required: Fix, actual: Fix) -> Step {
        let (error, integral, deriv) = self.terms(gains, required, actual);
        let control = sum_terms(gains, error, integral, deriv);
        self.control = control;
        step(error, integral, deriv, control)
    }

    /// One update of the incremental speed form: u = u_prev + P·e + Ki·I + Kd·D, then
    /// ×0.96 while |r| < 0.001.
    pub fn speed(&mut self, gains: &Gains, required: Fix, actual: Fix) -> Step {
        let (error, integral, deriv) = self.terms(gains, required, actual);
        let mut control = self
            .control
            .saturating_add(sum_terms(gains, error, integral, deriv));
        if required.saturating_abs() < NO_DEMAND {
            control = mul(control, BLEED);
        }
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

    fn terms(&mut self, gains: &Gains, required: Fix, actual: Fix) -> (Fix, Fix, Fix) {
        let mut error = required.saturating_sub(actual);
        if error != Fix::ZERO && error.saturating_abs() < gains.dead_zone {
            error = Fix::ZERO;
        }
        let integral = self.integral.saturating_add(error);
        let integral = mul(integral, gains.decay)
            .max(gains.cap.saturating_neg())
            .min(gains.cap);
        self.integral = integral;
        let deriv = self.prev_actual.saturating_sub(actual);
        self.prev_actual = actual;
        (error, integral, deriv)
    }
}

fn sum_terms(gains: &Gains, error: Fix, integral: Fix, deriv: Fix) -> Fix {
    // A zero gain (the usual P or D of a position motor) costs no multiplication.
    let term = |gain: Fix, value: Fix| {
        if gain == Fix::ZERO {
            Fix::ZERO
        } else {
            mul(gain, value)
        }
    };
    term(gains.p, error)
        .saturating_add(term(gains.i, integral))
        .saturating_add(term(gains.d, deriv))
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
            -32768.0, -1000.5, -3.25, -0.001, 0.0, 0.0625, 1.0, 7.77, 255.0, 32767.0,
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
    fn constants_are_what_they_stand_for() {
        assert!((BLEED.to_num::<f64>() - 0.96).abs() < 1e-5);
        assert!(NO_DEMAND < fix(0.001) && NO_DEMAND + Fix::DELTA > fix(0.000999));
    }
}
