//! The PID forms of reference §7.1 against steps computed by hand.

use shared::pid::{Direction, Duty, Fix, Gains, Pid, Step};

fn fix(v: f64) -> Fix {
    Fix::from_num(v)
}

fn gains(p: f64, i: f64, d: f64, cap: f64, decay: f64, dead_zone: f64) -> Gains {
    Gains {
        p: fix(p),
        i: fix(i),
        d: fix(d),
        cap: fix(cap),
        decay: fix(decay),
        dead_zone: fix(dead_zone),
    }
}

fn expect(step: Step, error: f64, integral: f64, deriv: f64, control: f64, duty: (u8, Direction)) {
    assert_eq!(
        (step.error, step.integral, step.deriv, step.control),
        (fix(error), fix(integral), fix(deriv), fix(control)),
        "{step:?}"
    );
    assert_eq!(
        step.duty,
        Duty {
            magnitude: duty.0,
            direction: duty.1
        }
    );
}

use Direction::{Forward as F, Reverse as R};

/// P 2, I 0.5, D 0.25, cap 10, decay 0.5, dead zone 1; every number is a binary fraction,
/// so the fixed-point results are exact.
#[test]
fn position_form_by_hand() {
    let g = gains(2.0, 0.5, 0.25, 10.0, 0.5, 1.0);
    let mut pid = Pid::new();
    // e = 10 − 4 = 6; I = (0 + 6)·0.5 = 3; D = −(4 − 0) = −4; u = 12 + 1.5 − 1 = 12.5.
    expect(
        pid.position(&g, fix(10.0), fix(4.0)),
        6.0,
        3.0,
        -4.0,
        12.5,
        (12, F),
    );
    // e = 0.5 is inside the dead zone: 0; I = 1.5; D = −5.5; u = 0.75 − 1.375 = −0.625,
    // which truncates toward zero: duty 0, forward.
    expect(
        pid.position(&g, fix(10.0), fix(9.5)),
        0.0,
        1.5,
        -5.5,
        -0.625,
        (0, F),
    );
    // e = −2; I = (1.5 − 2)·0.5 = −0.25; D = −2.5; u = −4 − 0.125 − 0.625 = −4.75.
    expect(
        pid.position(&g, fix(10.0), fix(12.0)),
        -2.0,
        -0.25,
        -2.5,
        -4.75,
        (4, R),
    );
    // e = 100; I = (−0.25 + 100)·0.5 = 49.875, capped at 10; D = 12 − 10 = 2;
    // u = 200 + 5 + 0.5 = 205.5.
    expect(
        pid.position(&g, fix(110.0), fix(10.0)),
        100.0,
        10.0,
        2.0,
        205.5,
        (205, F),
    );
    // e = −300 gives u = −600 − ...: duty saturates at 255, reverse; I clamps at −10.
    let step = pid.position(&g, fix(-290.0), fix(10.0));
    assert_eq!(step.integral, fix(-10.0));
    assert_eq!(
        step.duty,
        Duty {
            magnitude: 255,
            direction: R
        }
    );
}

#[test]
fn dead_zone_edge_and_zero() {
    let g = gains(1.0, 0.0, 0.0, 0.0, 0.0, 1.0);
    let mut pid = Pid::new();
    // |e| = z exactly is kept; just below is zeroed.
    assert_eq!(pid.position(&g, fix(1.0), fix(0.0)).error, fix(1.0));
    assert_eq!(pid.position(&g, fix(1.0), Fix::DELTA).error, Fix::ZERO);
    assert_eq!(pid.position(&g, fix(-1.0), Fix::ZERO).error, fix(-1.0));
}

#[test]
fn power_on_gains_give_no_output_and_no_integral() {
    let mut pid = Pid::new();
    for a in [0.0, 50.0, -120.0] {
        let step = pid.position(&Gains::ZERO, fix(40.0), fix(a));
        assert_eq!((step.integral, step.control), (Fix::ZERO, Fix::ZERO));
        assert_eq!(step.duty, Duty::IDLE);
    }
}

/// P 0.5, no I or D: u accumulates P·e each update.
#[test]
fn speed_form_by_hand() {
    let g = gains(0.5, 0.0, 0.0, 0.0, 0.0, 0.0);
    let mut pid = Pid::new();
    // u = 0 + 0.5·100 = 50.
    expect(
        pid.speed(&g, fix(100.0), fix(0.0)),
        100.0,
        0.0,
        0.0,
        50.0,
        (50, F),
    );
    // u = 50 + 0.5·40 = 70; D = −60 is computed even with Kd = 0.
    expect(
        pid.speed(&g, fix(100.0), fix(60.0)),
        40.0,
        0.0,
        -60.0,
        70.0,
        (70, F),
    );
    // r = 0: u = 70 − 30 = 40, then bled ×0.96 = 38.4.
    let step = pid.speed(&g, fix(0.0), fix(60.0));
    assert!(
        (step.control.to_num::<f64>() - 38.4).abs() < 1e-3,
        "{step:?}"
    );
    assert_eq!(
        step.duty,
        Duty {
            magnitude: 38,
            direction: F
        }
    );
    // A demand of 0.001 or more is a demand: no bleed.
    let mut pid = Pid::new();
    pid.speed(&g, fix(100.0), fix(0.0));
    let step = pid.speed(&g, fix(0.001), fix(0.001));
    assert_eq!(step.control, fix(50.0));
}

/// With zero gains and r = 0 (after an emergency stop) the duty decays ×0.96 per update:
/// from 255, 112 after 20 updates (3 s of 150-ms windows), 0 after some 135.
#[test]
fn speed_form_bleeds_to_zero_after_a_stop() {
    let mut pid = Pid::new();
    let push = gains(1.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    pid.speed(&push, fix(255.0), fix(0.0));
    let mut duties = Vec::new();
    for _ in 0..140 {
        duties.push(pid.speed(&Gains::ZERO, Fix::ZERO, Fix::ZERO).duty.magnitude);
    }
    assert_eq!(duties[0], 244); // 255·0.96 = 244.8
    assert_eq!(duties[19], 112); // 255·0.96^20 = 112.7
    let zero_at = duties.iter().position(|&d| d == 0).unwrap();
    assert!((130..=137).contains(&zero_at), "{zero_at}");
    assert!(duties.windows(2).all(|w| w[1] <= w[0]));
}

#[test]
fn speed_form_winds_up_and_saturates_instead_of_overflowing() {
    let g = gains(1.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    let mut pid = Pid::new();
    for _ in 0..20 {
        pid.speed(&g, fix(4000.0), Fix::ZERO);
    }
    assert_eq!(pid.control(), Fix::MAX);
    // Wound up: a reverse demand takes a while to bring the duty down.
    let step = pid.speed(&g, fix(-4000.0), Fix::ZERO);
    assert_eq!(step.duty.magnitude, 255);
    assert_eq!(step.duty.direction, F);
}

#[test]
fn integral_decays_and_caps() {
    // I 1, cap 300, decay 0.95: steady I for a constant error e is 19·e.
    let g = gains(0.0, 1.0, 0.0, 300.0, 0.95, 0.0);
    let mut pid = Pid::new();
    let mut last = Fix::ZERO;
    for _ in 0..400 {
        last = pid.position(&g, fix(2.0), Fix::ZERO).integral;
    }
    assert!((last.to_num::<f64>() - 38.0).abs() < 0.01, "{last}");
    for _ in 0..400 {
        last = pid.position(&g, fix(100.0), Fix::ZERO).integral;
    }
    assert_eq!(last, fix(300.0));
    assert_eq!(pid.integral(), fix(300.0));
}

/// Reference §7.1 in f64 (exact here to within 10^−6 of the real numbers, far below the
/// bounds' 2^−16 steps: the operands are multiples of 2^−16 below 2^17), with the slave's one
/// documented deviation mirrored: each sum and product saturates at the `I16F16` limits
/// (±32768). The bleed factor is the slave's constant ([`shared::pid::BLEED`], 0.96 to
/// within 10^−5, pinned in its own test).
struct Reference {
    integral: f64,
    prev_actual: f64,
    control: f64,
}

impl Reference {
    fn step(&mut self, g: &Gains, speed: bool, r: f64, a: f64) -> (f64, f64, f64, f64) {
        let sat = |x: f64| x.clamp(-32768.0, Fix::MAX.to_num::<f64>());
        let f = |x: Fix| x.to_num::<f64>();
        let mut e = sat(r - a);
        if e.abs() < f(g.dead_zone) {
            e = 0.0;
        }
        let integral = sat(sat(self.integral + e) * f(g.decay)).clamp(-f(g.cap), f(g.cap));
        let deriv = sat(self.prev_actual - a);
        let sum = sat(sat(sat(f(g.p) * e) + sat(f(g.i) * integral)) + sat(f(g.d) * deriv));
        let control = if speed {
            let u = sat(self.control + sum);
            if r.abs() < f(shared::pid::NO_DEMAND) {
                sat(u * f(shared::pid::BLEED))
            } else {
                u
            }
        } else {
            sum
        };
        self.integral = integral;
        self.prev_actual = a;
        self.control = control;
        (e, integral, deriv, control)
    }
}

/// A fixed-point value from raw bits in `lo..=hi` (units of 2^−16).
fn bits(lo: f64, hi: f64) -> impl proptest::strategy::Strategy<Value = Fix> {
    use proptest::prelude::*;
    ((lo * 65536.0) as i32..=(hi * 65536.0) as i32).prop_map(Fix::from_bits)
}

proptest::proptest! {
    /// Against [`Reference`] over up to 40 updates with gains anywhere in their registers'
    /// ranges (decay up to 1) and demands and measurements anywhere in theirs: e and D
    /// are exact, and each product truncates toward zero by less than 2^−16, so after
    /// update k (from 1)
    /// - |ΔI| ≤ k·2^−16 (the decay at most 1, the clamp and saturation do not widen);
    /// - position form: |Δu| ≤ (3 + 10k)·2^−16 (three products, Ki ≤ 10 times ΔI);
    /// - speed form: |Δu| ≤ (4k + 5k(k + 1))·2^−16 (the terms' errors accumulate in u, the
    ///   bleed adds one truncation and shrinks the rest).
    ///
    /// At 40 updates: 0.0062 (position) and 0.13 (speed); the duty, ⌊|u|⌋, is then off by
    /// at most one count, only where u lies that close to a whole number.
    #[test]
    fn both_forms_stay_within_the_truncation_bound_of_the_exact_rule(
        speed in proptest::bool::ANY,
        p in bits(0.0, 100.0),
        i in bits(0.0, 10.0),
        d in bits(-10.0, 10.0),
        cap in bits(0.0, 1000.0),
        decay in bits(0.0, 1.0),
        dead_zone in bits(0.0, 50.0),
        inputs in proptest::collection::vec(
            (bits(-200.0, 200.0), bits(-200.0, 200.0)),
            1..40,
        ),
        scale in 1i32..=20,
    ) {
        // The drive's P is 0..10 and its values ±4000: the position ranges, scaled.
        let (p, scale) = if speed { (p / 10, scale) } else { (p, 1) };
        let g = Gains { p, i, d, cap, decay, dead_zone };
        let mut pid = Pid::new();
        let mut reference = Reference { integral: 0.0, prev_actual: 0.0, control: 0.0 };
        let lsb = 1.0 / 65536.0;
        for (k, &(r, a)) in inputs.iter().enumerate() {
            let (r, a) = (r.saturating_mul_int(scale), a.saturating_mul_int(scale));
            let step = if speed { pid.speed(&g, r, a) } else { pid.position(&g, r, a) };
            let (e, integral, deriv, control) =
                reference.step(&g, speed, r.to_num(), a.to_num());
            let k = (k + 1) as f64;
            proptest::prop_assert_eq!(step.error.to_num::<f64>(), e);
            proptest::prop_assert_eq!(step.deriv.to_num::<f64>(), deriv);
            let integral_off = (step.integral.to_num::<f64>() - integral).abs();
            proptest::prop_assert!(integral_off <= k * lsb + 1e-6, "update {}: I off", k);
            let steps = if speed { 4.0 * k + 5.0 * k * (k + 1.0) } else { 3.0 + 10.0 * k };
            let bound = steps * lsb;
            let off = (step.control.to_num::<f64>() - control).abs();
            proptest::prop_assert!(off <= bound + 1e-6, "update {}: u off by {}", k, off);
        }
    }
}
