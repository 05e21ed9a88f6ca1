//! The bus-silence failsafe (new in this project): a slave whose master has gone quiet
//! stops its motors.
//!
//! A slave cut off the I2C bus (cable off, master dead) would otherwise keep its motors
//! at their last demand for ever. The watch is **armed** by the first write to REG_PING
//! after the board's boot: the master pings every slave once a second from 5 s after its
//! own boot, while a PC program written for the original never pings, so a bench master
//! that never pings never arms it. Boot disarms it (the board starts with a new watch).
//!
//! While armed, every bus transaction addressed to this slave (SLA+W or SLA+R: a write or
//! a read of any register) restarts the count. When the last one is BUSTIMEOUT ms or more
//! ago, [`SilenceWatch::expired`] says so; the core then raises BUSSILENT (type 12, motor
//! 5, none) if the board is running. BUSTIMEOUT = 0 turns the check off. Entering or
//! leaving an exception leaves the watch as it is: leaving takes a REG_RESET write, which
//! restarts the count, and a board in exception is not checked.
//!
//! Only the low 16 bits of the ms clock are kept (half the registers on the AVR); only
//! differences are taken. A running board is checked every tick, so the watch expires
//! (BUSTIMEOUT ≤ 65,535 ms) before the 16-bit difference can wrap; a board in exception
//! is not checked, and it leaves the exception only through a bus write, which restarts
//! the count before the next check.

/// BUSTIMEOUT's power-on value, ms.
pub const BUS_TIMEOUT_POWER_ON_MS: u16 = 2500;

/// Whether the master is still heard from.
#[derive(Clone, Copy, PartialEq, Eq, Debug, Default)]
pub struct SilenceWatch {
    /// When a transaction was last heard (the ms clock's low 16 bits), once armed;
    /// `None` until the first ping.
    heard_ms: Option<u16>,
}

impl SilenceWatch {
    /// Disarmed: the state at boot.
    pub const fn new() -> SilenceWatch {
        SilenceWatch { heard_ms: None }
    }

    /// Whether a ping has armed the watch.
    pub const fn is_armed(&self) -> bool {
        self.heard_ms.is_some()
    }

    /// REG_PING was written at `now_ms`: arms the watch (if not yet) and restarts the
    /// count.
    pub fn ping(&mut self, now_ms: u32) {
        self.heard_ms = Some(now_ms as u16);
    }

    /// A transaction addressed to this slave was heard by `now_ms`: restarts the count
    /// if armed.
    pub fn heard(&mut self, now_ms: u32) {
        if self.heard_ms.is_some() {
            self.heard_ms = Some(now_ms as u16);
        }
    }

    /// Whether, at `now_ms`, the armed watch has heard nothing for `timeout_ms` or more.
    /// Never with `timeout_ms` = 0 or before the first ping.
    pub fn expired(&self, now_ms: u32, timeout_ms: u16) -> bool {
        match self.heard_ms {
            Some(at) if timeout_ms != 0 => (now_ms as u16).wrapping_sub(at) >= timeout_ms,
            _ => false,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn not_armed_before_a_ping_whatever_the_silence() {
        let mut w = SilenceWatch::new();
        assert!(!w.is_armed());
        w.heard(10);
        assert!(!w.is_armed(), "a transaction alone does not arm it");
        for now in [0, 2_500, 10_000, u32::MAX] {
            assert!(!w.expired(now, 2_500));
            assert!(!w.expired(now, 1));
        }
    }

    #[test]
    fn armed_by_a_ping_it_expires_exactly_at_the_timeout() {
        let mut w = SilenceWatch::new();
        w.ping(1_000);
        assert!(w.is_armed());
        assert!(!w.expired(1_000, 2_500));
        assert!(!w.expired(3_499, 2_500));
        assert!(w.expired(3_500, 2_500));
        assert!(w.expired(100_000, 2_500));
        assert!(!w.expired(1_000, 1));
        assert!(w.expired(1_001, 1));
        assert!(w.expired(1_000 + 65_535, u16::MAX));
        assert!(!w.expired(1_000 + 65_534, u16::MAX));
    }

    #[test]
    fn the_boundary_holds_across_the_clock_wrap() {
        let mut w = SilenceWatch::new();
        let at = u32::MAX - 999;
        w.ping(at);
        assert!(!w.expired(at.wrapping_add(2_499), 2_500));
        assert_eq!(at.wrapping_add(2_500), 1_500, "the clock wrapped");
        assert!(w.expired(1_500, 2_500));
    }

    #[test]
    fn zero_turns_it_off() {
        let mut w = SilenceWatch::new();
        w.ping(0);
        for now in [0, 1, 2_500, 65_535, u32::MAX] {
            assert!(!w.expired(now, 0));
        }
        assert!(
            w.expired(2_500, 2_500),
            "still armed: a non-zero timeout acts again"
        );
    }

    #[test]
    fn any_transaction_restarts_the_count() {
        let mut w = SilenceWatch::new();
        w.ping(0);
        w.heard(2_000);
        assert!(!w.expired(2_500, 2_500));
        assert!(!w.expired(4_499, 2_500));
        assert!(w.expired(4_500, 2_500));
        w.ping(4_600);
        assert!(!w.expired(7_099, 2_500));
        assert!(w.expired(7_100, 2_500));
    }

    #[test]
    fn a_new_watch_is_disarmed_as_after_boot() {
        let mut w = SilenceWatch::new();
        w.ping(5);
        w = SilenceWatch::new();
        assert!(!w.is_armed());
        assert!(!w.expired(100_000, 2_500));
        assert_eq!(SilenceWatch::default(), SilenceWatch::new());
    }
}
