//! Steering under remote control: the steer integrator and the Ackermann geometry
//! (reference §9.2), in integers. Angles are in centidegrees (1/100 °).
//!
//! The inner wheel's angle is θi = acot((W·cot|θo| + S)/W), that is
//! tan θi = tan θo / (1 + (S/W)·tan θo), with W = 26.5 (half the 53 wheelbase) and
//! S = 42 (separation). The integrator keeps |θo| ≤ 30°, and above 5° θi is a smooth,
//! slowly bending curve, so the firmware carries it as the formula's values every
//! 0.64° and interpolates between them with one 8×8 product and a shift: no tan, atan or
//! division at run time, and within 0.01° of the f64 formula at every centidegree
//! (a host test checks all of them).

/// Limit of the steer integrator: ±30° in µdeg.
pub const STEER_LIMIT_UDEG: i32 = 30_000_000;
/// Below this outer angle (5°, in cdeg) the inner wheel takes the outer angle.
pub const ACKERMANN_MIN_CDEG: i16 = 500;
/// The integrator's limit in cdeg: the largest outer angle the geometry is asked for.
const LIMIT_CDEG: u16 = (STEER_LIMIT_UDEG / 10_000) as u16;

/// log2 of the outer angle between two knots (cdeg): 64 cdeg, a power of two so the
/// interpolation divides by a shift.
const KNOT_SHIFT: u32 = 6;
/// Outer angle between two knots (cdeg).
pub const KNOT_STEP_CDEG: u16 = 1 << KNOT_SHIFT;

/// The inner angle (cdeg, rounded) of the outer angle 5° + 0.64°·n, n = 0..=40 (the last
/// knot is past 30°, so every angle up to the limit lies between two). The rises from
/// one knot to the next are 21..=49 (tested below 64), so a rise times the step's
/// fraction (< 64) fits a u16 and comes from one 8×8 product.
const KNOTS: [u16; 41] = [
    439, 488, 535, 581, 626, 669, 711, 752, 792, 831, 869, 906, 942, 977, 1011, 1045, 1077, 1109,
    1141, 1171, 1201, 1231, 1259, 1288, 1315, 1342, 1369, 1395, 1421, 1446, 1471, 1495, 1519, 1542,
    1566, 1588, 1611, 1633, 1655, 1676, 1698,
];

/// Knot n rises about 32 cdeg (half the step) a knot: the firmware keeps knot n as
/// `LINE_BASE + 32·n + OFFSETS[n]`, one byte of table a knot instead of two.
const LINE_SLOPE_SHIFT: u32 = 5;
// 32·index is then `(k >> 1)` with its low five bits cleared.
const _: () = assert!(LINE_SLOPE_SHIFT + 1 == KNOT_SHIFT);
/// The lowest of `KNOTS[n] − 32·n` (at the last knot), so every offset is ≥ 0.
const LINE_BASE: u16 = {
    let mut base = u16::MAX;
    let mut n = 0;
    while n < KNOTS.len() {
        let v = KNOTS[n] - ((n as u16) << LINE_SLOPE_SHIFT);
        if v < base {
            base = v;
        }
        n += 1;
    }
    base
};
/// `KNOTS[n] − 32·n − LINE_BASE`, 0..=147; a value past a byte fails the build.
const OFFSETS: [u8; 41] = {
    let mut out = [0; 41];
    let mut n = 0;
    while n < KNOTS.len() {
        let v = KNOTS[n] - ((n as u16) << LINE_SLOPE_SHIFT) - LINE_BASE;
        assert!(v <= u8::MAX as u16);
        out[n] = v as u8;
        n += 1;
    }
    out
};

crate::flash_table! {
    /// [`OFFSETS`] as the firmware reads it, kept in flash on the AVR.
    static OFFSETS_FLASH: [u8; 41] = OFFSETS;
}

/// The knots, for the host test that checks them against f64.
pub fn knots() -> &'static [u16; 41] {
    &KNOTS
}

/// One step of the steer integrator: s := clamp(s − 0.03°·steer, −30°, +30°), with s in
/// µdeg and `steer` in thousandths.
pub fn integrate(s_udeg: i32, steer_milli: i16) -> i32 {
    (s_udeg - 30 * i32::from(steer_milli)).clamp(-STEER_LIMIT_UDEG, STEER_LIMIT_UDEG)
}

/// The inner wheel's angle for the outer angle `outer` (both in cdeg): the outer angle
/// itself below 5°, else acot((W·cot|θo| + S)/W) with θo's sign, by linear interpolation
/// between the two knots around |θo| (rounded to nearest). Beyond the integrator's ±30°
/// the inner wheel takes the angle of ±30°'s.
pub fn inner_angle(outer: i16) -> i16 {
    let a = outer.unsigned_abs();
    if a < ACKERMANN_MIN_CDEG as u16 {
        return outer;
    }
    let k = a.min(LIMIT_CDEG) - ACKERMANN_MIN_CDEG as u16;
    let index = usize::from(k >> KNOT_SHIFT);
    let low = OFFSETS_FLASH.get(index).unwrap_or(0);
    let high = OFFSETS_FLASH.get(index + 1).unwrap_or(low);
    // 32·index is k's bits above the knot step, halved.
    let below = LINE_BASE + ((k >> 1) & !((1 << LINE_SLOPE_SHIFT) - 1)) + u16::from(low);
    // The rise is 21..=49 (so the byte arithmetic's wraps cancel), and the fraction
    // below 64: the product is one 8×8 `mul` on the chip.
    let rise = (1u8 << LINE_SLOPE_SHIFT)
        .wrapping_add(high)
        .wrapping_sub(low);
    let frac = (k % KNOT_STEP_CDEG) as u8;
    let step = (u16::from(rise) * u16::from(frac) + KNOT_STEP_CDEG / 2) >> KNOT_SHIFT;
    // ≤ 1698, so it fits an i16.
    let inner = (below + step) as i16;
    if outer < 0 {
        -inner
    } else {
        inner
    }
}

/// The six steer angles (wheels 1..6, cdeg) for outer angle `outer` (within the
/// integrator's ±30°; see [`inner_angle`]). Normal mode: for θo < 0, wheels 1, 2, 5, 6 =
/// −θo, −θi, θo, θi; for θo ≥ 0 they are −θi, −θo, θi, θo; wheels 3 and 4 = 0. Crab
/// mode: all six = θo.
pub fn wheel_angles(outer: i16, crab: bool) -> [i16; 6] {
    if crab {
        return [outer; 6];
    }
    let inner = inner_angle(outer);
    let (w1, w2, w5, w6) = if outer < 0 {
        (outer.saturating_neg(), -inner, outer, inner)
    } else {
        (-inner, -outer, inner, outer)
    };
    [w1, w2, 0, 0, w5, w6]
}
