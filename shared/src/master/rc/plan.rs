//! What the remote control sends next (reference §9.2, with the new stop on link loss):
//! the first link-up's writes one at a time, then a pass every [`PASS_PERIOD_MS`] while the
//! link is up, and one more pass when the link is lost (its drive centred, so it stops the
//! drives), sent after any link-up writes still in progress so that none comes after it.

use super::{LinkState, LinkUpWrites};
use crate::master::RegWrite;

/// A pass every this many ms while the link is up. The original ran a pass per main-loop
/// pass of about 5 ms (twelve 100-kHz writes); a fixed period keeps the steer integrator's
/// rate whatever the bus speed.
pub const PASS_PERIOD_MS: u16 = 5;

/// The next thing to send.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Next {
    /// One link-up write.
    Write(RegWrite),
    /// A pass: the pass's twelve writes.
    Pass,
}

/// The link-up writes still to send, when the last pass went, and whether the stopping
/// pass is due.
#[derive(Clone, Debug, Default)]
pub struct PassPlan {
    setup: Option<LinkUpWrites>,
    /// The clock's low 16 bits at the last pass (it is checked every loop).
    last_pass_ms: u16,
    /// The link was lost and the stopping pass is still to send.
    stop_due: bool,
}

impl PassPlan {
    /// At boot: nothing sent.
    pub const fn new() -> Self {
        PassPlan {
            setup: None,
            last_pass_ms: 0,
            stop_due: false,
        }
    }

    /// What is due at `now_ms` with the link as `link` ([`super::Remote::link_state`]),
    /// or `None`.
    pub fn next(&mut self, link: LinkState, now_ms: u16) -> Option<Next> {
        if link.first {
            self.setup = Some(LinkUpWrites::new());
        }
        self.stop_due |= link.lost;
        if let Some(setup) = self.setup.as_mut() {
            match setup.next() {
                Some(w) => return Some(Next::Write(w)),
                None => self.setup = None,
            }
        }
        let stop = core::mem::take(&mut self.stop_due);
        if !stop && (!link.up || now_ms.wrapping_sub(self.last_pass_ms) < PASS_PERIOD_MS) {
            return None;
        }
        self.last_pass_ms = now_ms;
        Some(Next::Pass)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::master::rc::LINK_UP_WRITES;

    fn state(up: bool, first: bool, lost: bool) -> LinkState {
        LinkState { up, first, lost }
    }

    #[test]
    fn link_up_writes_first_then_a_pass_every_period() {
        let mut plan = PassPlan::new();
        let mut writes = 0;
        let mut t = 100u16;
        let mut link = state(true, true, false);
        while let Some(Next::Write(_)) = plan.next(link, t) {
            writes += 1;
            link = state(true, false, false);
            t += 1;
        }
        assert_eq!(writes, LINK_UP_WRITES);
        // The call that found the writes done sent the first pass.
        let passes: Vec<u16> = (t + 1..t + 21)
            .filter(|&now| plan.next(state(true, false, false), now) == Some(Next::Pass))
            .collect();
        assert_eq!(passes, [t + 5, t + 10, t + 15, t + 20]);
    }

    #[test]
    fn a_lost_link_gets_one_more_pass_at_once_and_then_none() {
        let mut plan = PassPlan::new();
        while plan.next(state(true, false, false), 0).is_some() {}
        // 2 ms after the last pass: the period has not run, but the stop goes at once.
        assert_eq!(plan.next(state(false, false, true), 2), Some(Next::Pass));
        for now in 3..2_000 {
            assert_eq!(plan.next(state(false, false, false), now), None);
        }
    }

    #[test]
    fn the_stop_waits_for_link_up_writes_in_progress_and_comes_after_them() {
        let mut plan = PassPlan::new();
        assert!(matches!(
            plan.next(state(true, true, false), 0),
            Some(Next::Write(_))
        ));
        // Lost during the link-up writes: they finish, then the stopping pass.
        let mut after = vec![];
        let mut lost = true;
        for now in 1..1_000 {
            match plan.next(state(false, false, lost), now) {
                Some(next) => after.push(next),
                None => break,
            }
            lost = false;
        }
        assert_eq!(after.len(), LINK_UP_WRITES);
        assert_eq!(after.last(), Some(&Next::Pass));
        assert!(after[..LINK_UP_WRITES - 1]
            .iter()
            .all(|n| matches!(n, Next::Write(_))));
    }
}
