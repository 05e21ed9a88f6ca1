//! Steering under remote control: the steer integrator and the Ackermann geometry
//! (reference §9.2), in integers. Angles are in centidegrees (1/100 °).
//!
//! The inner wheel's angle is θi = acot((W·cot|θo| + S)/W), that is
//! tan θi = tan θo / (1 + (S/W)·tan θo), with W = 26.5 (half the 53 wheelbase) and
//! S = 42 (separation). tan and atan come from 1° and 1/32 tables with linear
//! interpolation in Q15 (2¹⁵ = 1.0); the result is within 0.012° of the f64 formula
//! (checked on the host for every centidegree up to 45°). The firmware reads the same
//! results from a step table built from them at compile time ([`wheel_angles`] through
//! [`inner_angle_within_limit`]), so it carries neither the interpolation nor a division.

use crate::progmem::Flash;

mod steps;

/// Limit of the steer integrator: ±30° in µdeg.
pub const STEER_LIMIT_UDEG: i32 = 30_000_000;
/// Below this outer angle (5°, in cdeg) the inner wheel takes the outer angle.
pub const ACKERMANN_MIN_CDEG: i16 = 500;
/// Largest angle the geometry handles (45°, in cdeg); larger ones are taken as 45°.
pub const GEOMETRY_MAX_CDEG: i16 = 4500;

/// W = 26.5 and S = 42, both scaled by 10.
const W10: u32 = 265;
const S10: u32 = 420;
/// 1.0 in Q15.
const ONE_Q15: u32 = 1 << 15;

/// tan(n°) in Q15, n = 0..=45.
const TAN_Q15: [u16; 46] = [
    0, 572, 1144, 1717, 2291, 2867, 3444, 4023, 4605, 5190, 5778, 6369, 6965, 7565, 8170, 8780,
    9396, 10018, 10647, 11283, 11927, 12578, 13239, 13909, 14589, 15280, 15982, 16696, 17423,
    18164, 18919, 19689, 20476, 21280, 22102, 22944, 23807, 24692, 25601, 26535, 27496, 28485,
    29504, 30557, 31644, 32768,
];

/// atan(n/32) in cdeg, n = 0..=32.
const ATAN_CDEG: [u16; 33] = [
    0, 179, 358, 536, 713, 888, 1062, 1234, 1404, 1571, 1735, 1897, 2056, 2211, 2363, 2511, 2657,
    2798, 2936, 3070, 3201, 3327, 3451, 3571, 3687, 3800, 3909, 4016, 4119, 4218, 4315, 4409, 4500,
];

crate::flash_table! {
    /// [`TAN_Q15`] as the maths reads it, kept in flash on the AVR.
    static TAN_Q15_FLASH: [u16; 46] = TAN_Q15;
}

crate::flash_table! {
    /// [`ATAN_CDEG`] as the maths reads it, kept in flash on the AVR.
    static ATAN_CDEG_FLASH: [u16; 33] = ATAN_CDEG;
}

/// The tables, for the host test that checks them against f64.
pub fn tables() -> (&'static [u16; 46], &'static [u16; 33]) {
    (&TAN_Q15, &ATAN_CDEG)
}

/// Linear interpolation between `table[index]` and `table[index + 1]` at `frac / step`.
/// A rise times `frac` fits 32 bits (rises ≤ 1124, `frac` < 1024), and the result lies
/// between two table values, so it fits 16.
fn lerp(table: &'static Flash<[u16]>, index: u16, frac: u16, step: u16) -> u16 {
    let a = table.get(usize::from(index)).unwrap_or(0);
    let b = table.get(usize::from(index) + 1).unwrap_or(a);
    // Tables rise monotonically, so b ≥ a; round to nearest.
    let rise = (u32::from(b - a) * u32::from(frac) + u32::from(step / 2)) / u32::from(step);
    a + rise as u16
}

/// tan of `cdeg` (0..=4500) in Q15.
fn tan_q15(cdeg: u16) -> u16 {
    lerp(TAN_Q15_FLASH.as_slice(), cdeg / 100, cdeg % 100, 100)
}

/// atan of `t` (Q15, 0..=1.0) in cdeg.
fn atan_cdeg(t: u16) -> u16 {
    lerp(ATAN_CDEG_FLASH.as_slice(), t / 1024, t % 1024, 1024)
}

/// One step of the steer integrator: s := clamp(s − 0.03°·steer, −30°, +30°), with s in
/// µdeg and `steer` in thousandths.
pub fn integrate(s_udeg: i32, steer_milli: i16) -> i32 {
    (s_udeg - 30 * i32::from(steer_milli)).clamp(-STEER_LIMIT_UDEG, STEER_LIMIT_UDEG)
}

/// The inner wheel's angle for the outer angle `outer` (both in cdeg): the outer angle
/// itself below 5°, else acot((W·cot|θo| + S)/W) with θo's sign.
pub fn inner_angle(outer: i16) -> i16 {
    if outer.unsigned_abs() < ACKERMANN_MIN_CDEG as u16 {
        return outer;
    }
    let a = outer.unsigned_abs().min(GEOMETRY_MAX_CDEG as u16);
    let t = u32::from(tan_q15(a));
    // 1 + (S/W)·t in Q15; t ≤ 1.0, so every product fits a u32.
    let d = ONE_Q15 + S10 * t / W10;
    // t ≤ d, so the quotient is at most 1.0 in Q15.
    let ti = (t * ONE_Q15 / d) as u16;
    // ≤ 4500, so it fits an i16.
    let inner = atan_cdeg(ti) as i16;
    if outer < 0 {
        -inner
    } else {
        inner
    }
}

/// [`inner_angle`] for an outer angle within the integrator's ±30°, from the step table
/// (the firmware's path: no interpolation or division at run time). Beyond ±30° the
/// inner wheel takes the angle of ±30°'s.
pub fn inner_angle_within_limit(outer: i16) -> i16 {
    let a = outer.unsigned_abs();
    if a < ACKERMANN_MIN_CDEG as u16 {
        return outer;
    }
    // ≤ 4500, so it fits an i16.
    let inner = steps::inner_of(a) as i16;
    if outer < 0 {
        -inner
    } else {
        inner
    }
}

/// The six steer angles (wheels 1..6, cdeg) for outer angle `outer` (within the
/// integrator's ±30°; see [`inner_angle_within_limit`]). Normal mode: for θo < 0, wheels
/// 1, 2, 5, 6 = −θo, −θi, θo, θi; for θo ≥ 0 they are −θi, −θo, θi, θo; wheels 3 and 4 =
/// 0. Crab mode: all six = θo.
pub fn wheel_angles(outer: i16, crab: bool) -> [i16; 6] {
    if crab {
        return [outer; 6];
    }
    let inner = inner_angle_within_limit(outer);
    let (w1, w2, w5, w6) = if outer < 0 {
        (outer.saturating_neg(), -inner, outer, inner)
    } else {
        (-inner, -outer, inner, outer)
    };
    [w1, w2, 0, 0, w5, w6]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The first integer version of the geometry (u32 throughout), kept as the reference
    /// the firmware's narrower arithmetic must match exactly.
    fn reference_inner(outer: i16) -> i16 {
        fn lerp(table: &[u16], index: usize, frac: u32, step: u32) -> u32 {
            let a = table.get(index).map_or(0, |&v| u32::from(v));
            let b = table.get(index + 1).map_or(a, |&v| u32::from(v));
            a + ((b - a) * frac + step / 2) / step
        }
        if outer.unsigned_abs() < ACKERMANN_MIN_CDEG as u16 {
            return outer;
        }
        let a = u32::from(outer.unsigned_abs().min(GEOMETRY_MAX_CDEG as u16));
        let t = lerp(&TAN_Q15, (a / 100) as usize, a % 100, 100);
        let d = ONE_Q15 + S10 * t / W10;
        let ti = t * ONE_Q15 / d;
        let inner = lerp(&ATAN_CDEG, (ti / 1024) as usize, ti % 1024, 1024) as i16;
        if outer < 0 {
            -inner
        } else {
            inner
        }
    }

    #[test]
    fn within_the_limit_the_step_table_gives_the_inner_angle() {
        let limit = (STEER_LIMIT_UDEG / 10_000) as i16;
        for outer in -limit..=limit {
            assert_eq!(
                inner_angle_within_limit(outer),
                inner_angle(outer),
                "{outer}"
            );
        }
        assert_eq!(inner_angle_within_limit(-3000), -1677);
        assert_eq!(inner_angle_within_limit(i16::MIN), -1677);
        assert_eq!(inner_angle_within_limit(499), 499);
    }

    #[test]
    fn every_outer_angle_gives_the_reference_inner_angle() {
        for outer in i16::MIN..=i16::MAX {
            assert_eq!(inner_angle(outer), reference_inner(outer), "{outer}");
        }
        assert_eq!(inner_angle(-3000), -1677);
    }
}
