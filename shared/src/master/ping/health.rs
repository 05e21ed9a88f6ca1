//! Which slaves answer: present, missed once, silent; and when each was last tried.
//!
//! A slave is *present* once it has answered any access since boot. Only present
//! slaves can go *silent*: a rover built with fewer boards (the PC library's pair mask)
//! has slaves that never answer, and they must not hold the master in exception forever.
//! One failed access marks a present slave *missed* and asks for an immediate re-check;
//! a second consecutive failure makes it silent. Any answer clears both marks.

/// Bit of slave `device` (1..9) in a mask; 0 for any other number.
pub(crate) const fn bit(device: u8) -> u16 {
    if device >= 1 && device <= 9 {
        1 << device
    } else {
        0
    }
}

/// What one failed access means.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub(crate) enum Miss {
    /// Not a present slave: nothing to conclude.
    Ignored,
    /// The first miss: check the slave again at once.
    Recheck,
    /// The second miss in a row: the slave is now silent. Raise SlaveSilent and stop
    /// the others.
    NowSilent,
    /// The slave was silent already: raise SlaveSilent (again, if the master's exception
    /// was cleared meanwhile).
    Silent,
}

/// Answering state of slaves 1..9, one bit each, and the time (ms, wrapping at 2¹⁶) each
/// present slave was last accessed, answered or not.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub(crate) struct Health {
    pub present: u16,
    pub missed: u16,
    pub silent: u16,
    tried_ms: [u16; 10],
}

impl Health {
    /// Nothing known.
    pub const fn new() -> Self {
        Health {
            present: 0,
            missed: 0,
            silent: 0,
            tried_ms: [0; 10],
        }
    }

    /// Records an access to `device` at `now_ms`.
    fn tried(&mut self, device: u8, now_ms: u16) {
        if let Some(t) = self.tried_ms.get_mut(usize::from(device)) {
            *t = now_ms;
        }
    }

    /// The slave answered an access at `now_ms`. Returns whether it had failed one since
    /// it last answered (whatever that access was: a spread write, too).
    pub fn answered(&mut self, device: u8, now_ms: u16) -> bool {
        let b = bit(device);
        let failed = (self.missed | self.silent) & b != 0;
        self.present |= b;
        self.missed &= !b;
        self.silent &= !b;
        self.tried(device, now_ms);
        failed
    }

    /// The slave failed to answer an access at `now_ms`.
    pub fn failed(&mut self, device: u8, now_ms: u16) -> Miss {
        let b = bit(device);
        if self.present & b == 0 {
            return Miss::Ignored;
        }
        self.tried(device, now_ms);
        if self.silent & b != 0 {
            Miss::Silent
        } else if self.missed & b != 0 {
            self.missed &= !b;
            self.silent |= b;
            Miss::NowSilent
        } else {
            self.missed |= b;
            Miss::Recheck
        }
    }

    /// The present slave accessed longest ago at `now_ms` and how long ago (ms); the
    /// lowest number wins a tie. `None` if no slave is present.
    pub fn stalest(&self, now_ms: u16) -> Option<(u8, u16)> {
        // Device 0 is never present, so its slot is skipped like any absent slave.
        let mut best: Option<(u8, u16)> = None;
        let mut present = self.present;
        for (d, &tried) in (0u8..).zip(self.tried_ms.iter()) {
            let here = present & 1 != 0;
            present >>= 1;
            if !here {
                continue;
            }
            let age = now_ms.wrapping_sub(tried);
            if best.is_none_or(|(_, a)| age > a) {
                best = Some((d, age));
            }
        }
        best
    }
}
