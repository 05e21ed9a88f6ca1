//! The PC link as idle serves it: bytes from the receive queue into the parser, each
//! complete frame executed and answered (or swallowed with no reply while the remote
//! control's link is up, reference §9.2), slave accesses reported to the schedule, the
//! inter-byte timeout (which also ends the skipping after a lost byte), and the opt-in
//! PC-silence failsafe (REGMASTER_PCTIMEOUT).

use crate::link::{now_ms, Clock, Lock, Replies, RxEvent, RxQueue, TxQueue};
use crate::relay::Watched;
use crate::traffic::Traffic;
use shared::exception::MasterException;
use shared::master::{InterByteTimeout, LinkError, PcWatch};
use shared::protocol::{Parser, ReadSets};

/// The parser, the inter-byte timeout, the read sets and when the PC was last heard.
// In declaration order, the small per-byte state first, within a short displacement of
// the link's address on the AVR (see `Parser`).
#[repr(C)]
pub struct PcLink {
    timeout: InterByteTimeout,
    parser: Parser,
    sets: ReadSets,
    watch: PcWatch,
}

impl PcLink {
    /// Between frames.
    pub const fn new() -> Self {
        PcLink {
            parser: Parser::new(),
            timeout: InterByteTimeout::new(),
            sets: ReadSets::new(),
            watch: PcWatch::new(),
        }
    }

    /// Takes every event waiting in `rx` and acts on each frame it completes: executed
    /// and answered through `tx`, or dropped without a reply when `swallow` (the remote
    /// control has the link). Then drops a partial frame whose bytes stopped arriving, and
    /// when no clean byte has come for REGMASTER_PCTIMEOUT ms (not 0, and not `swallow`),
    /// raises PCSILENT and has the schedule spread it to every slave (again every timeout
    /// while the PC stays silent). Returns whether any event was taken.
    #[inline(never)]
    pub fn drain(
        &mut self,
        rx: &mut impl Lock<RxQueue>,
        tx: &mut impl Lock<TxQueue>,
        clock: &mut impl Lock<Clock>,
        swallow: bool,
        s: &mut Traffic<'_>,
    ) -> bool {
        let (mut took, mut heard) = (false, false);
        while let Some(event) = rx.lock(|q| q.pop_front()) {
            took = true;
            let now = now_ms(clock);
            match event {
                RxEvent::Byte(b) => {
                    heard = true;
                    if self.parser.push_byte(b) && !swallow {
                        self.serve(tx, clock, s);
                    }
                }
                _ => {
                    // Skip to a quiet line: the rest of a damaged frame must not run as
                    // frames of its own.
                    self.parser.lose();
                    if let Some(e) = event.error() {
                        s.service.link_error(e);
                    }
                }
            }
            self.timeout.byte(u32::from(now), self.parser.in_frame());
        }
        let now = now_ms(clock);
        let waiting = rx.lock(|q| !q.is_empty());
        if self.timeout.expired(u32::from(now), waiting) && self.parser.abort() {
            s.service.link_error(LinkError::Truncated);
        }
        // A clean byte taken, or one waiting, is the PC heard (serial errors are not: a
        // floating or noisy line must not keep the failsafe off); the remote control's time
        // counts as heard too (the PC is ignored then).
        let timeout = s.service.local.pc_timeout_ms();
        if self.watch.due(now, timeout, heard || waiting || swallow) {
            let latch = &mut s.service.local.exception;
            s.schedule
                .stop_everything(MasterException::PC_SILENT, latch);
        }
        took
    }

    /// Executes and answers the frame the parser has just completed, and reports the
    /// slave it addressed to the schedule. In line: its one call site then saves and
    /// restores the registers once (measured 58 B smaller than out of line).
    #[inline(always)]
    fn serve(
        &mut self,
        tx: &mut impl Lock<TxQueue>,
        clock: &mut impl Lock<Clock>,
        s: &mut Traffic<'_>,
    ) {
        let mut bus = Watched::new(s.relay, s.watchdog);
        let mut out = Replies::new(tx);
        s.service.execute(
            &mut self.sets,
            self.parser.completed(),
            &mut bus,
            &mut |r| out.send(r),
        );
        if let Some((device, answered)) = bus.outcome() {
            let now = now_ms(clock);
            let latch = &mut s.service.local.exception;
            s.schedule.observe_at(device, answered, now, latch);
        }
    }
}
