//! The PC-silence failsafe (new, opt-in): when REGMASTER_PCTIMEOUT is not 0 and no clean
//! byte (one without a serial error) has come from the PC for that many ms, the master
//! raises PCSILENT (type 13) and spreads it to every slave, so every motor stops, as for any
//! other fault; the PC leaves it as any other, with resetExceptions() (reference §8.5).
//! While the PC stays silent the spread is sent again every timeout, so a slave that missed
//! one write, or an exception cleared meanwhile, is stopped again.
//!
//! The original had no such failsafe: a PC program that hung with the port open left the
//! motors on their last demand (reference §4.6). Off by default, so a program that never
//! writes the register sees the original's behaviour.
//!
//! While the remote control has the link, the PC is ignored (reference §9.2) and the
//! remote control stops the drives on its own loss of link: that time counts as heard, so
//! the PC's timeout starts again when the remote control lets go.

/// The longest timeout, ms: a larger REGMASTER_PCTIMEOUT acts as this. The wait is measured
/// on the 16-bit ms clock, checked every loop pass (a few ms, at most some 20 ms): this
/// leaves 5.5 s of the clock's wrap for the check to see it expire.
pub const MAX_TIMEOUT_MS: u16 = 60_000;

/// When the PC was last heard, or the failsafe last acted.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PcWatch {
    /// The low 16 bits of the ms clock when the PC was last heard (or the remote control
    /// last had the link, or the failsafe last acted).
    since_ms: u16,
}

impl PcWatch {
    /// At boot (the timeout is 0, off, until the PC writes it, and the PC is heard doing
    /// so).
    pub const fn new() -> Self {
        PcWatch { since_ms: 0 }
    }

    /// Whether the failsafe acts at `now_ms`, given whether the PC was `heard` since the
    /// last call (a clean byte taken, or the remote control holding the link, when the PC
    /// is ignored): true when `timeout_ms` is not 0 and nothing was heard for `timeout_ms`
    /// (at most [`MAX_TIMEOUT_MS`]) since the PC was last heard or the failsafe last acted.
    pub fn due(&mut self, now_ms: u16, timeout_ms: u16, heard: bool) -> bool {
        let waited = now_ms.wrapping_sub(self.since_ms);
        if heard || (timeout_ms != 0 && waited >= timeout_ms.min(MAX_TIMEOUT_MS)) {
            self.since_ms = now_ms;
            return !heard;
        }
        false
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The ms at which `due` returned true, called every ms from `from` to `to` with
    /// `heard` at each.
    fn trips(w: &mut PcWatch, from: u32, to: u32, timeout: u16, heard: bool) -> Vec<u32> {
        trips_at(w, from..to, timeout, |_| heard)
    }

    /// The ms at which `due` returned true, called at each of `times` with `heard(t)`.
    fn trips_at(
        w: &mut PcWatch,
        times: impl Iterator<Item = u32>,
        timeout: u16,
        heard: impl Fn(u32) -> bool,
    ) -> Vec<u32> {
        times
            .filter(|&t| w.due(t as u16, timeout, heard(t)))
            .collect()
    }

    /// A watch that has just heard the PC at `ms` (not due then).
    fn heard_at(ms: u16, timeout: u16) -> PcWatch {
        let mut w = PcWatch::new();
        assert!(!w.due(ms, timeout, true));
        w
    }

    #[test]
    fn off_by_default_and_at_zero() {
        let mut w = PcWatch::new();
        assert!(trips(&mut w, 0, 70_000, 0, false).is_empty());
    }

    #[test]
    fn acts_after_the_timeout_and_again_every_timeout_while_silent() {
        let mut w = heard_at(1_000, 300);
        // Exactly 300 ms after the PC was last heard, then every 300 ms.
        assert_eq!(
            trips(&mut w, 1_001, 2_000, 300, false),
            vec![1_300, 1_600, 1_900]
        );
        // Hearing it starts the wait again.
        assert!(!w.due(2_050, 300, true));
        assert_eq!(trips(&mut w, 2_051, 2_400, 300, false), vec![2_350]);
    }

    #[test]
    fn a_loop_that_checks_late_acts_at_its_first_check_past_the_timeout() {
        let mut w = heard_at(0, 300);
        // Checked every 7 ms: the first check at or past 300 ms acts.
        let tripped = trips_at(&mut w, (1..100u32).map(|k| 7 * k), 300, |_| false);
        assert_eq!(tripped[..2], [301, 602]);
    }

    #[test]
    fn a_pc_heard_more_often_than_the_timeout_never_trips_it() {
        let mut w = PcWatch::new();
        let tripped = trips_at(&mut w, 0..20_000u32, 300, |t| t % 299 == 0);
        assert!(tripped.is_empty(), "{tripped:?}");
    }

    #[test]
    fn the_remote_control_holding_the_link_counts_as_heard() {
        let mut w = PcWatch::new();
        // 100 s of remote control (ms 0..=99,999), longer than the 16-bit clock's wrap.
        assert!(trips(&mut w, 0, 100_000, 500, true).is_empty());
        // The timeout runs from the last ms the remote control had the link.
        assert_eq!(
            trips(&mut w, 100_000, 100_600, 500, false),
            vec![99_999 + 500]
        );
    }

    #[test]
    fn across_the_clock_wrap_and_at_the_longest_timeouts() {
        let mut w = heard_at(65_000, 1_000);
        assert_eq!(
            trips(&mut w, 65_001, 67_500, 1_000, false),
            vec![66_000, 67_000]
        );
        // 60 s and above act as 60 s, which a loop checking every 20 ms still sees before
        // the 16-bit clock wraps.
        for timeout in [60_000, 60_001, u16::MAX] {
            let mut w = heard_at(10, timeout);
            let first = (1..10_000u32)
                .map(|k| 10 + 20 * k)
                .find(|&t| w.due(t as u16, timeout, false));
            assert_eq!(first, Some(60_010), "{timeout}");
        }
    }
}
