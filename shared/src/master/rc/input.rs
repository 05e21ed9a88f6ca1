//! RC receiver input: pulse widths from pin changes, and their normalised values.
//!
//! Normalised values are integers in thousandths: −1000..=1000 stands for −1.0..=1.0.

/// Channels: 0 = drive (D2), 1 = steer (D3), 2 = mode (D4).
pub const CHANNELS: usize = 3;

/// (mn, mx) per channel, in µs: mn maps to −1, mx to +1 (reference §9.2). The drive and
/// steer channels run backwards (mn > mx).
pub const CALIBRATION: [(u16, u16); CHANNELS] = [(1940, 1000), (1738, 940), (910, 1800)];

crate::flash_table! {
    /// [`CALIBRATION`] as [`normalise`] reads it, kept in flash on the AVR.
    static CALIBRATION_FLASH: [(u16, u16); CHANNELS] = CALIBRATION;
}

/// |value| below this (0.1) reads as 0.
pub const INPUT_DEADBAND: i16 = 100;

/// Whether |`v`| < `band` (for a band of 1..=16 384), as one unsigned comparison: v is
/// inside exactly when v + band − 1 lands in 0..=2·band − 2, and every other v lands
/// above that in 16-bit wrapping arithmetic.
pub const fn within_band(v: i16, band: i16) -> bool {
    (v as u16).wrapping_add(band as u16 - 1) < 2 * band as u16 - 1
}

/// A channel's normalised value in thousandths:
/// clamp((w − mn)·2/(mx − mn), 0, 2) − 1, then |value| < 0.1 → 0. `None` for a channel
/// number above 2.
pub fn normalise(channel: usize, width_us: u16) -> Option<i16> {
    let (mn, mx) = CALIBRATION_FLASH.get(channel)?;
    // The same value in unsigned 16-bit steps (one division, no signs): the distance
    // from mn towards mx, 0 on the far side of mn and the full 2000 past mx.
    let span = mn.abs_diff(mx);
    let from_mn = if mx > mn {
        width_us.checked_sub(mn)
    } else {
        mn.checked_sub(width_us)
    };
    let scaled = match from_mn {
        None => 0,
        Some(d) if d >= span => 2000,
        // d < span ≤ 65535, so d·2000 fits a u32 and the quotient is below 2000.
        Some(d) => (u32::from(d) * 2000 / u32::from(span)) as i16,
    };
    let value = scaled - 1000;
    Some(if within_band(value, INPUT_DEADBAND) {
        0
    } else {
        value
    })
}

/// Measures pulse widths on the three channel pins from pin-change interrupts. It is
/// small enough for the interrupt handler: the handler reads the pins and the µs clock
/// and hands the finished widths over.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PulseTimer {
    /// Pin levels at the last change, bit c for channel c.
    levels: u8,
    /// Channels whose rising edge has been seen.
    rising_seen: u8,
    /// µs clock at each channel's last rising edge.
    rise_us: [u32; CHANNELS],
}

impl PulseTimer {
    /// No edges seen; all pins low.
    pub const fn new() -> Self {
        PulseTimer {
            levels: 0,
            rising_seen: 0,
            rise_us: [0; CHANNELS],
        }
    }

    /// A pin change at `now_us` (the µs clock, wrapping): `levels` bit c is channel c's
    /// level now. Returns, per channel, the width of a pulse that ended now (µs, capped
    /// at 65535).
    pub fn change(&mut self, levels: u8, now_us: u32) -> [Option<u16>; CHANNELS] {
        let mut widths = [None; CHANNELS];
        self.change_each(levels, now_us, |c, w| {
            if let Some(width) = widths.get_mut(c) {
                *width = Some(w);
            }
        });
        widths
    }

    /// As [`PulseTimer::change`], handing each width to `pulse` (channel, µs) instead of
    /// returning them: what the firmware uses, with no array in between.
    pub fn change_each(&mut self, levels: u8, now_us: u32, mut pulse: impl FnMut(usize, u16)) {
        // Channels that rose, and channels that fell after a rise this timer saw. (Level
        // bits above the channels may land in `rising_seen`; nothing reads them.)
        let rose = levels & !self.levels;
        let ended = self.levels & !levels & self.rising_seen;
        self.rising_seen |= rose;
        self.levels = levels;
        for (c, rise_us) in self.rise_us.iter_mut().enumerate() {
            let mask = 1u8 << c;
            if rose & mask != 0 {
                *rise_us = now_us;
            } else if ended & mask != 0 {
                let w = now_us.wrapping_sub(*rise_us);
                pulse(c, u16::try_from(w).unwrap_or(u16::MAX));
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The signed formula the firmware's unsigned steps replace.
    fn reference(channel: usize, width_us: u16) -> Option<i16> {
        let (mn, mx) = *CALIBRATION.get(channel)?;
        let span = i32::from(mx) - i32::from(mn);
        let scaled = (i32::from(width_us) - i32::from(mn)) * 2000 / span;
        let value = (scaled.clamp(0, 2000) - 1000) as i16;
        Some(if value.abs() < INPUT_DEADBAND {
            0
        } else {
            value
        })
    }

    /// The per-channel transitions `change_each` replaces with masks: a rise stamps the
    /// channel, a fall after a seen rise ends a pulse.
    fn reference_change(
        state: &mut (u8, u8, [u32; CHANNELS]),
        levels: u8,
        now_us: u32,
    ) -> [Option<u16>; CHANNELS] {
        let mut out = [None; CHANNELS];
        for (c, slot) in out.iter_mut().enumerate() {
            let mask = 1u8 << c;
            match (state.0 & mask != 0, levels & mask != 0) {
                (false, true) => {
                    state.2[c] = now_us;
                    state.1 |= mask;
                }
                (true, false) if state.1 & mask != 0 => {
                    let w = now_us.wrapping_sub(state.2[c]);
                    *slot = Some(u16::try_from(w).unwrap_or(u16::MAX));
                }
                _ => {}
            }
        }
        state.0 = levels;
        out
    }

    #[test]
    fn every_sequence_of_four_level_changes_gives_the_per_channel_pulses() {
        let mut pulses = 0;
        for seq in 0..8u32.pow(4) {
            let (mut timer, mut reference) = (PulseTimer::new(), (0, 0, [0; CHANNELS]));
            for step in 0..4 {
                let levels = (seq >> (3 * step) & 7) as u8;
                // Steps far apart now and then, so some widths saturate.
                let now = 1000 + step * (700 + 40_000 * (seq % 3));
                let got = timer.change(levels, now);
                assert_eq!(
                    got,
                    reference_change(&mut reference, levels, now),
                    "{seq} {step}"
                );
                pulses += got.iter().flatten().count();
            }
        }
        assert!(pulses > 1000, "{pulses}");
    }

    #[test]
    fn within_band_is_the_absolute_value_below_the_band_for_every_value() {
        for band in [1, 2, 100, 200, 300, 750, 16_384] {
            for v in i16::MIN..=i16::MAX {
                assert_eq!(
                    within_band(v, band),
                    v.unsigned_abs() < band as u16,
                    "{v} {band}"
                );
            }
        }
        assert!(within_band(-99, 100) && !within_band(-100, 100) && !within_band(100, 100));
    }

    #[test]
    fn every_width_on_every_channel_normalises_as_the_signed_formula() {
        for channel in 0..=CHANNELS {
            for w in 0..=u16::MAX {
                assert_eq!(
                    normalise(channel, w),
                    reference(channel, w),
                    "{channel} {w}"
                );
            }
        }
        assert_eq!(normalise(1, 940), Some(1000));
        assert_eq!(normalise(2, 1355), Some(0));
    }
}
