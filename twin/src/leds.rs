//! What the boards' LEDs have shown, for `twin inject status`: each LED's level and how long
//! it has held it, so a latched exception (an LED that stays lit) is told apart from a
//! ping's flash (50 ms each second).
//!
//! The twin samples the pins at each physics slice (50 µs), so a level's age is right to
//! that step; a flash shorter than a slice may be missed. A lit pulse of at most
//! [`FLICKER_US`] is a flicker, not a level: the slaves' heartbeat lights LED2 for one 1-ms
//! tick in every 101 ms (reference §6.5), which would otherwise keep its dark level's age
//! below 0.1 s for good.

/// The longest lit pulse taken as a flicker within a dark level, µs.
pub const FLICKER_US: u64 = 2_000;

/// How recent a flicker must be for an LED to read as flickering, µs (the heartbeat's
/// comes every 101 ms).
const FLICKERING_US: u64 = 500_000;

/// One LED's level and the emulated time it took it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Led {
    /// Lit.
    pub on: bool,
    /// When it took this level, µs of emulated time (the first sample for a level held since;
    /// for a dark level, flickers do not restart it).
    pub since_us: u64,
    /// While dark: when its last flicker ended, if it had one.
    pub flickered_us: Option<u64>,
    /// While lit: the dark level before, `(since_us, flickered_us)`, which a flicker resumes
    /// (none for a level lit when first seen).
    dark: Option<(u64, Option<u64>)>,
}

impl Led {
    /// A level first seen at `now_us`.
    fn new(on: bool, now_us: u64) -> Led {
        Led {
            on,
            since_us: now_us,
            flickered_us: None,
            dark: None,
        }
    }

    /// The LED after a sample of level `on` at `now_us`.
    fn next(self, on: bool, now_us: u64) -> Led {
        match (self.on, on) {
            (false, true) => Led {
                dark: Some((self.since_us, self.flickered_us)),
                ..Led::new(true, now_us)
            },
            // Lit for no longer than a flicker: the dark level before goes on.
            (true, false) if now_us.saturating_sub(self.since_us) <= FLICKER_US => {
                match self.dark {
                    Some((since_us, _)) => Led {
                        on: false,
                        since_us,
                        flickered_us: Some(now_us),
                        dark: None,
                    },
                    None => Led::new(false, now_us),
                }
            }
            (true, false) => Led::new(false, now_us),
            _ => self,
        }
    }
}

/// The LEDs of every chip, two each, chip 0 first.
#[derive(Debug, Clone, Default)]
pub struct LedWatch {
    chips: Vec<[Led; 2]>,
}

impl LedWatch {
    /// Records the levels sampled at `now_us`: a changed level restarts its age, except a
    /// dark level's after a flicker.
    pub fn sample(&mut self, levels: impl IntoIterator<Item = [bool; 2]>, now_us: u64) {
        for (chip, levels) in levels.into_iter().enumerate() {
            if chip == self.chips.len() {
                self.chips.push(levels.map(|on| Led::new(on, now_us)));
                continue;
            }
            for (led, on) in self.chips[chip].iter_mut().zip(levels) {
                *led = led.next(on, now_us);
            }
        }
    }

    /// Chip `chip`'s two LEDs; None before its first sample.
    pub fn chip(&self, chip: usize) -> Option<[Led; 2]> {
        self.chips.get(chip).copied()
    }
}

/// An LED in words at `now_us`: `on 3.2 s`, `off 0.4 s`, or `off 3.2 s, flickering` when
/// a flicker (a slave's heartbeat) lit it within the last half second.
pub fn describe(led: Led, now_us: u64) -> String {
    let held_s = now_us.saturating_sub(led.since_us) as f64 / 1e6;
    let flickering = !led.on
        && led
            .flickered_us
            .is_some_and(|t| now_us.saturating_sub(t) < FLICKERING_US);
    format!(
        "{} {held_s:.1} s{}",
        if led.on { "on" } else { "off" },
        if flickering { ", flickering" } else { "" }
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_level_keeps_its_age_until_it_changes() {
        let mut watch = LedWatch::default();
        assert_eq!(watch.chip(0), None);
        watch.sample([[false, true]], 1_000);
        watch.sample([[false, true]], 2_000);
        let leds = watch.chip(0).expect("sampled");
        let level = |l: Led| (l.on, l.since_us);
        assert_eq!(level(leds[0]), (false, 1_000));
        assert_eq!(level(leds[1]), (true, 1_000));
        watch.sample([[true, true]], 3_000);
        let leds = watch.chip(0).expect("sampled");
        assert_eq!(level(leds[0]), (true, 3_000), "LED1 lit at 3 ms");
        assert_eq!(leds[1].since_us, 1_000, "LED2 unchanged");
    }

    #[test]
    fn chips_are_told_apart_and_added_as_they_come() {
        let mut watch = LedWatch::default();
        watch.sample([[false, false], [true, false]], 0);
        watch.sample([[false, false], [false, false], [true, true]], 500);
        assert_eq!(
            watch.chip(1).map(|l| (l[0].on, l[0].since_us)),
            Some((false, 500))
        );
        assert_eq!(watch.chip(0).map(|l| l[0].since_us), Some(0));
        assert_eq!(
            watch.chip(2).map(|l| [l[0].on, l[1].on]),
            Some([true, true])
        );
        assert_eq!(watch.chip(3), None);
    }

    #[test]
    fn an_led_reads_as_its_level_and_how_long_it_held_it() {
        let lit = Led::new(true, 1_000_000);
        assert_eq!(describe(lit, 4_200_000), "on 3.2 s");
        let dark = Led::new(false, 0);
        assert_eq!(describe(dark, 400_000), "off 0.4 s");
        assert_eq!(describe(dark, 0), "off 0.0 s", "no age is no negative age");
    }

    #[test]
    fn a_heartbeats_flicker_keeps_the_dark_levels_age_and_a_ping_does_not() {
        let mut watch = LedWatch::default();
        let at = |watch: &mut LedWatch, on: bool, ms: u64| watch.sample([[false, on]], ms * 1_000);
        at(&mut watch, false, 0);
        // The heartbeat: lit for 1 ms in every 101, for 3 s.
        for beat in 0..30u64 {
            at(&mut watch, true, beat * 101 + 100);
            at(&mut watch, false, beat * 101 + 101);
        }
        let led2 = watch.chip(0).expect("sampled")[1];
        assert_eq!((led2.on, led2.since_us), (false, 0));
        assert_eq!(describe(led2, 3_100_000), "off 3.1 s, flickering");
        // Half a second after the last flicker (at 3.03 s) it reads as plainly dark.
        assert_eq!(describe(led2, 3_600_000), "off 3.6 s");
        // A ping's 20-ms flash is a level of its own: the dark after it starts anew.
        at(&mut watch, true, 4_000);
        assert_eq!(
            describe(watch.chip(0).expect("sampled")[1], 4_010_000),
            "on 0.0 s"
        );
        at(&mut watch, false, 4_020);
        let led2 = watch.chip(0).expect("sampled")[1];
        assert_eq!(
            (led2.on, led2.since_us, led2.flickered_us),
            (false, 4_020_000, None)
        );
        // A flicker while lit is no flicker: a lit level ends as it ends.
        at(&mut watch, true, 5_000);
        at(&mut watch, false, 5_001);
        assert_eq!(watch.chip(0).expect("sampled")[1].since_us, 4_020_000);
    }
}
