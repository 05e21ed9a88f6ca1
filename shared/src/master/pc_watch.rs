//! The PC-silence failsafe (new, opt-in): when REGMASTER_PCTIMEOUT is not 0 and nothing
//! (no byte, not even a damaged one) has come from the PC for that many ms, the master
//! raises PCSILENT (type 13) and spreads it to every slave, so every motor stops, as for
//! any other fault; the PC leaves it as any other, with resetExceptions() (reference §8.5).
//!
//! The original had no such failsafe: a PC program that hung with the port open left the
//! motors on their last demand (reference §4.6). Off by default, so a program that never
//! writes the register sees the original's behaviour.
//!
//! While the remote control has the link, the PC is ignored (reference §9.2) and the
//! remote control stops the drives on its own loss of link: that time counts as heard, so
//! the PC's timeout starts again when the remote control lets go.

/// When the PC was last heard, and whether the failsafe acted since.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PcWatch {
    /// The low 16 bits of the ms clock when the PC was last heard (or the remote control
    /// last had the link). A timeout is at most 65,535 ms, so the trip comes before the difference
    /// wraps.
    heard_ms: u16,
    /// The failsafe acted and nothing was heard since: nothing more to do until it is.
    stopped: bool,
}

impl PcWatch {
    /// At boot: heard at 0 ms (the timeout is 0, off, until the PC writes it, and the PC
    /// is heard doing so).
    pub const fn new() -> Self {
        PcWatch {
            heard_ms: 0,
            stopped: false,
        }
    }

    /// The PC was heard at `now_ms`.
    #[inline(always)]
    fn heard(&mut self, now_ms: u16) {
        self.heard_ms = now_ms;
        self.stopped = false;
    }

    /// Whether the failsafe acts at `now_ms`, given whether the PC was `heard`
    /// since the last call (a byte or a serial error taken, or the remote control holding
    /// the link, when the PC is ignored): true once when `timeout_ms` is not 0 and nothing
    /// was heard for `timeout_ms` or more; then false until the PC is heard again.
    pub fn due(&mut self, now_ms: u16, timeout_ms: u16, heard: bool) -> bool {
        if heard {
            self.heard(now_ms);
            return false;
        }
        if timeout_ms == 0 || self.stopped || now_ms.wrapping_sub(self.heard_ms) < timeout_ms {
            return false;
        }
        self.stopped = true;
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The ms at which `due` returned true, called every ms from `from` to `to` with
    /// `heard` at each.
    fn trips(w: &mut PcWatch, from: u32, to: u32, timeout: u16, heard: bool) -> Vec<u32> {
        (from..to)
            .filter(|&t| w.due(t as u16, timeout, heard))
            .collect()
    }

    #[test]
    fn off_by_default_and_at_zero() {
        let mut w = PcWatch::new();
        assert!(trips(&mut w, 0, 70_000, 0, false).is_empty());
    }

    #[test]
    fn acts_once_after_the_timeout_and_again_only_after_the_pc_is_heard() {
        let mut w = PcWatch::new();
        assert!(!w.due(1_000, 300, true));
        // Exactly 300 ms after the PC was last heard, once.
        assert_eq!(trips(&mut w, 1_001, 5_000, 300, false), vec![1_300]);
        // Hearing it re-arms.
        assert!(!w.due(5_000, 300, true));
        assert_eq!(trips(&mut w, 5_001, 6_000, 300, false), vec![5_300]);
    }

    #[test]
    fn a_pc_heard_more_often_than_the_timeout_never_trips_it() {
        let mut w = PcWatch::new();
        let tripped: Vec<u32> = (0..20_000u32)
            .filter(|&t| w.due(t as u16, 300, t % 299 == 0))
            .collect();
        assert!(tripped.is_empty(), "{tripped:?}");
    }

    #[test]
    fn the_remote_control_holding_the_link_counts_as_heard() {
        let mut w = PcWatch::new();
        // 100 s of remote control (ms 0..=99,999), longer than the 16-bit clock's wrap.
        assert!(trips(&mut w, 0, 100_000, 500, true).is_empty());
        // The timeout runs from the last ms the remote control had the link.
        assert_eq!(
            trips(&mut w, 100_000, 102_000, 500, false),
            vec![99_999 + 500]
        );
    }

    #[test]
    fn across_the_clock_wrap_and_at_the_longest_timeout() {
        let mut w = PcWatch::new();
        assert!(!w.due(65_000, 1_000, true));
        assert_eq!(trips(&mut w, 65_001, 70_000, 1_000, false), vec![66_000]);
        assert!(!w.due(10, u16::MAX, true));
        assert_eq!(
            trips(&mut w, 11, 200_000, u16::MAX, false),
            vec![10 + u32::from(u16::MAX)]
        );
    }
}
