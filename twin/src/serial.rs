//! The master's serial line as the twin presents it, with its one fault: bytes lost on the
//! wire ([`SerialLine::drop_next`]), as a loose USB cable or a noisy line loses them.

/// Which way bytes travel on the serial line.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Direction {
    /// From the host program to the master.
    ToMaster,
    /// From the master to the host program.
    ToHost,
}

impl Direction {
    /// The direction named `word` (`to-master` or `to-host`).
    pub fn parse(word: &str) -> Option<Direction> {
        match word {
            "to-master" => Some(Direction::ToMaster),
            "to-host" => Some(Direction::ToHost),
            _ => None,
        }
    }

    /// The direction's name.
    pub fn name(self) -> &'static str {
        match self {
            Direction::ToMaster => "to-master",
            Direction::ToHost => "to-host",
        }
    }
}

/// Byte losses pending and done, per direction.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct SerialLine {
    /// Bytes still to drop towards the master.
    pending_to_master: u64,
    /// Bytes still to drop towards the host.
    pending_to_host: u64,
    /// Bytes dropped so far towards the master.
    dropped_to_master: u64,
    /// Bytes dropped so far towards the host.
    dropped_to_host: u64,
}

impl SerialLine {
    /// A line that loses nothing.
    pub fn new() -> SerialLine {
        SerialLine::default()
    }

    /// Makes the line lose the next `n` bytes travelling `direction` (added to any loss still
    /// pending).
    pub fn drop_next(&mut self, direction: Direction, n: u64) {
        let pending = match direction {
            Direction::ToMaster => &mut self.pending_to_master,
            Direction::ToHost => &mut self.pending_to_host,
        };
        *pending = pending.saturating_add(n);
    }

    /// Cancels every loss still pending, both ways; returns what was pending (to the master,
    /// to the host). Losses already done stay counted.
    pub fn clear_pending(&mut self) -> (u64, u64) {
        let was = (self.pending_to_master, self.pending_to_host);
        self.pending_to_master = 0;
        self.pending_to_host = 0;
        was
    }

    /// Bytes still to be lost travelling `direction`.
    pub fn pending(&self, direction: Direction) -> u64 {
        match direction {
            Direction::ToMaster => self.pending_to_master,
            Direction::ToHost => self.pending_to_host,
        }
    }

    /// Bytes lost so far travelling `direction`.
    pub fn dropped(&self, direction: Direction) -> u64 {
        match direction {
            Direction::ToMaster => self.dropped_to_master,
            Direction::ToHost => self.dropped_to_host,
        }
    }

    /// What of `bytes`, travelling `direction`, arrives at the far end.
    pub fn pass(&mut self, direction: Direction, bytes: &[u8]) -> Vec<u8> {
        let (pending, dropped) = match direction {
            Direction::ToMaster => (&mut self.pending_to_master, &mut self.dropped_to_master),
            Direction::ToHost => (&mut self.pending_to_host, &mut self.dropped_to_host),
        };
        let lost = usize::try_from(*pending)
            .unwrap_or(usize::MAX)
            .min(bytes.len());
        *pending -= lost as u64;
        *dropped += lost as u64;
        bytes[lost..].to_vec()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn drops_exactly_the_next_n_bytes_one_way() {
        let mut line = SerialLine::new();
        line.drop_next(Direction::ToMaster, 3);
        assert_eq!(line.pass(Direction::ToHost, b"ab"), b"ab");
        assert_eq!(line.pass(Direction::ToMaster, b"xy"), b"");
        assert_eq!(line.pending(Direction::ToMaster), 1);
        assert_eq!(line.pass(Direction::ToMaster, b"pqr"), b"qr");
        assert_eq!(line.pass(Direction::ToMaster, b"s"), b"s");
        assert_eq!(line.dropped(Direction::ToMaster), 3);
        assert_eq!(line.dropped(Direction::ToHost), 0);
    }

    #[test]
    fn a_clear_cancels_what_is_pending_and_keeps_what_was_lost() {
        let mut line = SerialLine::new();
        line.drop_next(Direction::ToMaster, 4);
        line.drop_next(Direction::ToHost, 2);
        assert_eq!(line.pass(Direction::ToMaster, b"a"), b"");
        assert_eq!(line.clear_pending(), (3, 2));
        assert_eq!(line.pass(Direction::ToMaster, b"bc"), b"bc");
        assert_eq!(line.pass(Direction::ToHost, b"d"), b"d");
        assert_eq!(line.dropped(Direction::ToMaster), 1);
        assert_eq!(line.clear_pending(), (0, 0), "nothing left to cancel");
    }

    #[test]
    fn losses_add_up() {
        let mut line = SerialLine::new();
        line.drop_next(Direction::ToHost, 1);
        line.drop_next(Direction::ToHost, 1);
        assert_eq!(line.pass(Direction::ToHost, b"abc"), b"c");
        assert_eq!(Direction::parse("to-host"), Some(Direction::ToHost));
        assert_eq!(Direction::ToMaster.name(), "to-master");
    }
}
