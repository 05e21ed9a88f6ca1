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
