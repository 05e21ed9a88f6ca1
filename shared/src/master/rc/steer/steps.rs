//! The inner wheel's angle as the firmware looks it up: for every outer angle the
//! integrator can reach (5° to 30°, in cdeg), the inner angle rises by 0 or 1 cdeg from
//! one centidegree to the next, so one bit per step holds the whole curve (313 bytes),
//! with the value at every 256th step to start from, one byte each above a line that
//! rises 128 per 256 steps. Both tables are computed at compile time by the same integer
//! geometry as [`super::inner_angle`], so they agree with it by construction (a value
//! that does not fit its byte stops the build, and a host test checks every angle).

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
const CHUNK_BYTES: usize = 32;
/// Starting values: inner(FIRST + 256·c).
const BASES: usize = STEP_BYTES.div_ceil(CHUNK_BYTES);
/// Steps between two starting values.
const CHUNK_STEPS: u16 = CHUNK_BYTES as u16 * 8;
/// The line under the starting values: inner(FIRST + 256·c) = `LINE_AT_0` + 128·c + the
/// byte of chunk c. 128 per chunk is half a step per step, so it is `k / 2` rounded down
/// to a multiple of 128 at step k.
const LINE_AT_0: u16 = 438;

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

/// The line's value at the start of the chunk holding step `k`.
const fn line(k: u16) -> u16 {
    LINE_AT_0 + ((k / 2) & !(CHUNK_STEPS / 2 - 1))
}

/// The starting values, each above the line (a value off its byte stops the build).
const fn bases() -> [u8; BASES] {
    let mut out = [0; BASES];
    let mut c = 0;
    while c < BASES {
        let k = (c * CHUNK_BYTES * 8) as u16;
        let above = inner(FIRST + k) - line(k);
        assert!(above <= 255, "a starting value does not fit its byte");
        out[c] = above as u8;
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
    static BASES_FLASH: [u8; BASES] = bases();
}

/// The inner angle (cdeg) of the outer angle `a`, taken as 5°..=30° (cdeg): the chunk's
/// starting value plus its steps below `a` (at most 255, one bit each).
// Out of line: measured 4 B smaller than in the pass.
#[inline(never)]
pub(super) fn inner_of(a: u16) -> u16 {
    let k = a.clamp(FIRST, LAST) - FIRST;
    let above = BASES_FLASH.get(usize::from(k / CHUNK_STEPS)).unwrap_or(0);
    let mut inner = line(k) + u16::from(above);
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
        assert_eq!((STEPS, STEP_BYTES, BASES), (2500, 313, 10));
        assert_eq!(inner(FIRST), 440);
        assert_eq!(inner(LAST), 1677);
        assert_eq!(bases()[0], 2);
        assert_eq!(line(CHUNK_STEPS * 3 + 5), LINE_AT_0 + 384);
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
