//! The inner wheel's angle as the firmware looks it up: for every outer angle the
//! integrator can reach (5° to 30°, in cdeg), the inner angle rises by 0 or 1 cdeg from
//! one centidegree to the next, so one bit per step holds the whole curve (313 bytes),
//! with the value at every 128th step to start from. Both tables are computed at compile
//! time by the same integer geometry as [`super::inner_angle`], so they agree with it by
//! construction (and a host test checks every angle).

use super::{ACKERMANN_MIN_CDEG, ATAN_CDEG, ONE_Q15, S10, STEER_LIMIT_UDEG, TAN_Q15, W10};

/// First outer angle of the table (cdeg).
const FIRST: u16 = ACKERMANN_MIN_CDEG as u16;
/// Last outer angle of the table: the integrator's limit (cdeg).
const LAST: u16 = (STEER_LIMIT_UDEG / 10_000) as u16;
/// Steps from `FIRST` to `LAST`.
const STEPS: usize = (LAST - FIRST) as usize;
/// Bytes of step bits, bit k (byte k / 8, bit k % 8) = inner(FIRST + k + 1) − inner(FIRST + k).
const STEP_BYTES: usize = STEPS.div_ceil(8);
/// Bytes of step bits between two starting values.
const CHUNK_BYTES: usize = 16;
/// Starting values: inner(FIRST + 128·c).
const BASES: usize = STEP_BYTES.div_ceil(CHUNK_BYTES);

/// Linear interpolation as `super::lerp` does it, over a plain table, for compile time.
const fn lerp(table: &[u16], index: usize, frac: u32, step: u32) -> u32 {
    let a = table[index] as u32;
    let b = if index + 1 < table.len() {
        table[index + 1] as u32
    } else {
        a
    };
    a + ((b - a) * frac + step / 2) / step
}

/// The inner angle of the outer angle `a` (cdeg, 0..=4500), as `super::inner_angle`
/// computes it for a positive angle of at least 5°.
const fn inner(a: u16) -> u16 {
    let a = a as u32;
    let t = lerp(&TAN_Q15, (a / 100) as usize, a % 100, 100);
    let d = ONE_Q15 + S10 * t / W10;
    let ti = t * ONE_Q15 / d;
    lerp(&ATAN_CDEG, (ti / 1024) as usize, ti % 1024, 1024) as u16
}

/// The step bits (a step other than 0 or 1 stops the build).
const fn step_bits() -> [u8; STEP_BYTES] {
    let mut out = [0; STEP_BYTES];
    let mut k = 0;
    while k < STEPS {
        let a = FIRST + k as u16;
        let rise = inner(a + 1) - inner(a);
        assert!(rise <= 1, "the inner angle rises by more than one step");
        out[k / 8] |= (rise as u8) << (k % 8);
        k += 1;
    }
    out
}

/// The starting values.
const fn bases() -> [u16; BASES] {
    let mut out = [0; BASES];
    let mut c = 0;
    while c < BASES {
        out[c] = inner(FIRST + (c * CHUNK_BYTES * 8) as u16);
        c += 1;
    }
    out
}

crate::flash_table! {
    /// The step bits, kept in flash on the AVR.
    static STEP_BITS_FLASH: [u8; STEP_BYTES] = step_bits();
}

crate::flash_table! {
    /// The starting values, kept in flash on the AVR.
    static BASES_FLASH: [u16; BASES] = bases();
}

/// The inner angle (cdeg) of the outer angle `a`, taken as 5°..=30° (cdeg): the chunk's
/// starting value plus its steps below `a` (at most 127, one bit each).
pub(super) fn inner_of(a: u16) -> u16 {
    let k = a.clamp(FIRST, LAST) - FIRST;
    const CHUNK_STEPS: u16 = CHUNK_BYTES as u16 * 8;
    let mut inner = BASES_FLASH.get(usize::from(k / CHUNK_STEPS)).unwrap_or(0);
    for j in k - k % CHUNK_STEPS..k {
        let bits = STEP_BITS_FLASH.get(usize::from(j / 8)).unwrap_or(0);
        inner += u16::from((bits >> (j % 8)) & 1);
    }
    inner
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_table_sizes_follow_from_the_range() {
        assert_eq!((STEPS, STEP_BYTES, BASES), (2500, 313, 20));
        assert_eq!(inner(FIRST), 440);
        assert_eq!(inner(LAST), 1677);
    }

    #[test]
    fn every_angle_of_the_range_reads_as_computed() {
        for a in FIRST..=LAST {
            assert_eq!(inner_of(a), inner(a), "{a}");
        }
        assert_eq!(inner_of(FIRST - 1), inner(FIRST));
        assert_eq!(inner_of(LAST + 1), inner(LAST));
    }
}
