//! What the boards' LEDs have shown, for `twin inject status`: each LED's level and how long
//! it has held it, so a latched exception (an LED that stays lit) is told apart from a
//! ping's flash (50 ms each second).
//!
//! The twin samples the pins at each physics slice (50 µs), so a level's age is right to
//! that step; a flash shorter than a slice may be missed.

/// One LED's level and the emulated time it took it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Led {
    /// Lit.
    pub on: bool,
    /// When it took this level, µs of emulated time (the first sample for a level held since).
    pub since_us: u64,
}

/// The LEDs of every chip, two each, chip 0 first.
#[derive(Debug, Clone, Default)]
pub struct LedWatch {
    chips: Vec<[Led; 2]>,
}

impl LedWatch {
    /// Records the levels sampled at `now_us`: a changed level restarts its age.
    pub fn sample(&mut self, levels: impl IntoIterator<Item = [bool; 2]>, now_us: u64) {
        for (chip, levels) in levels.into_iter().enumerate() {
            if chip == self.chips.len() {
                self.chips.push(levels.map(|on| Led {
                    on,
                    since_us: now_us,
                }));
                continue;
            }
            for (led, on) in self.chips[chip].iter_mut().zip(levels) {
                if led.on != on {
                    *led = Led {
                        on,
                        since_us: now_us,
                    };
                }
            }
        }
    }

    /// Chip `chip`'s two LEDs; None before its first sample.
    pub fn chip(&self, chip: usize) -> Option<[Led; 2]> {
        self.chips.get(chip).copied()
    }
}

/// An LED in words at `now_us`: `on 3.2 s` or `off 0.4 s`.
pub fn describe(led: Led, now_us: u64) -> String {
    let held_s = now_us.saturating_sub(led.since_us) as f64 / 1e6;
    format!("{} {held_s:.1} s", if led.on { "on" } else { "off" })
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
        assert_eq!(
            leds[0],
            Led {
                on: false,
                since_us: 1_000
            }
        );
        assert_eq!(
            leds[1],
            Led {
                on: true,
                since_us: 1_000
            }
        );
        watch.sample([[true, true]], 3_000);
        let leds = watch.chip(0).expect("sampled");
        assert_eq!(
            leds[0],
            Led {
                on: true,
                since_us: 3_000
            },
            "LED1 lit at 3 ms"
        );
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
        let lit = Led {
            on: true,
            since_us: 1_000_000,
        };
        assert_eq!(describe(lit, 4_200_000), "on 3.2 s");
        let dark = Led {
            on: false,
            since_us: 0,
        };
        assert_eq!(describe(dark, 400_000), "off 0.4 s");
        assert_eq!(describe(dark, 0), "off 0.0 s", "no age is no negative age");
    }
}
