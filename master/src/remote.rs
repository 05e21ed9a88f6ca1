//! Remote control (reference §9.2), wired to `shared::master::rc`.
//!
//! - The pin-change task ([`RcEdges::on_change`]) only reads the hardware: Timer1's count
//!   and the levels of D2..D4, queued for idle ([`EdgeQueue`]), so the time stamp is
//!   taken at the edge and the handler stays short.
//! - Idle ([`RemoteControl`]) turns the counts into a µs timeline, measures the pulses,
//!   keeps the link state on its millisecond clock, sends the first link-up's writes once
//!   per boot (one per idle loop, so the PC link and the schedule are served in
//!   between), then one pass every
//!   [`PASS_PERIOD_MS`](shared::master::rc::PASS_PERIOD_MS) while the link is up:
//!   REQSPEED and STEER_REQPOS to the six drive/steer boards; and one more when the link
//!   is lost (no edge for 1 s), with drive and steer centred: REQSPEED 0, the steering
//!   left as it was (new: the original left the drives on the last pass's speed).
//!
//! **Pass rate.** The original ran a pass per main-loop pass, and its loop, carrying
//! twelve 100-kHz I2C writes, took about 5 ms: the steer integrator (0.03° per pass)
//! therefore turns at up to about 6°/s. A fixed 5-ms period keeps that rate whatever the
//! bus speed.

use drivers::rc_pins::RcPins;
use drivers::timer1::{EdgeClock, FreeRunning};
use shared::master::rc::setup::DS_CONTROLLERS_FLASH;
use shared::master::rc::{angle_raw_in_range, speed_raw_in_range};
use shared::master::rc::{Next, Pass, PassPlan, PulseTimer, Remote};
use shared::master::{RegWrite, Ring};
use shared::regs::id;

/// One pin change: Timer1's count (half µs) and the channel levels (bit c = channel c),
/// widened to 16 bits so a queue slot is four bytes (its index scales by shifts).
pub type Edge = (u16, u16);

/// Pin changes waiting for idle. A receiver frame makes four changes in 20 ms, and idle
/// is never away for more than a few ms, so eight is ample.
pub type EdgeQueue = Ring<Edge, 8>;

/// The pin-change task's own state: the timer and pins it reads.
pub struct RcEdges {
    timer: FreeRunning,
    pins: RcPins,
}

impl RcEdges {
    /// Stamps with `timer`, reads `pins`.
    pub const fn new(timer: FreeRunning, pins: RcPins) -> Self {
        RcEdges { timer, pins }
    }

    /// A pin change: its time stamp and the levels, queued for idle (dropped if idle is
    /// eight changes behind, which costs one pulse's width).
    #[inline(always)]
    pub fn on_change(&self, queue: &mut EdgeQueue) {
        let count = self.timer.count();
        let levels = self.pins.levels();
        let _ = queue.push_back((count, u16::from(levels)));
    }
}

/// Idle's remote-control state.
pub struct RemoteControl {
    clock: EdgeClock,
    pulses: PulseTimer,
    remote: Remote,
    /// What to send next.
    plan: PassPlan,
}

impl RemoteControl {
    /// At boot: no edge seen.
    pub const fn new() -> Self {
        RemoteControl {
            clock: EdgeClock::new(),
            pulses: PulseTimer::new(),
            remote: Remote::new(),
            plan: PassPlan::new(),
        }
    }

    /// Takes in one pin change, seen by idle at `now_ms`: the pulse that ended, if any,
    /// and the edge for the link state.
    // In line: its one call site, idle's edge loop (measured 42 B smaller).
    #[inline(always)]
    pub fn edge(&mut self, (count, levels): Edge, now_ms: u16) {
        let now_us = self.clock.stamp(count);
        let remote = &mut self.remote;
        self.pulses
            .change_each(levels as u8, now_us, |channel, width| {
                remote.pulse(channel, width)
            });
        self.remote.edge(u32::from(now_ms));
    }

    /// Whether the link is up at `now_ms` (PC frames are then swallowed and the blue
    /// LED is lit).
    pub fn link_up(&mut self, now_ms: u16) -> bool {
        self.remote.link_up_at(now_ms)
    }

    /// Sends through `send` what is due at `now_ms` ([`PassPlan::next`]): a link-up write
    /// (device 0 is the master itself), or a pass, whose twelve writes go out together
    /// (about 1.3 ms at 400 kHz). Returns whether anything was sent.
    #[inline(never)]
    pub fn next(&mut self, now_ms: u16, mut send: impl FnMut(RegWrite)) -> bool {
        let link = self.remote.link_state(u32::from(now_ms));
        match self.plan.next(link, now_ms) {
            Some(Next::Write(w)) => send(w),
            Some(Next::Pass) => pass_writes(&self.remote.pass(), send),
            None => return false,
        }
        true
    }
}

/// The writes of `pass`, in the order of `Pass::writes`: for wheels 1..6, REQSPEED then
/// STEER_REQPOS on the wheel's drive/steer board.
fn pass_writes(pass: &Pass, mut send: impl FnMut(RegWrite)) {
    // Every drive is within ±1000 and every angle within ±30°: the clamp-free mappings.
    let speed = speed_raw_in_range(pass.drive);
    // One call site for all twelve writes, so `send` is inlined once: write i is wheel
    // i / 2's (as `Pass::steer_raw(i / 2 + 1)`), REQSPEED for even i.
    for i in 0..2 * pass.angles.len() {
        let wheel = i / 2;
        let (Some(device), Some(&angle)) =
            (DS_CONTROLLERS_FLASH.get(wheel), pass.angles.get(wheel))
        else {
            return;
        };
        let (id, raw) = if i % 2 == 0 {
            (id::REGDS_DRIVE_REQSPEED, speed)
        } else {
            (id::REGDS_STEER_REQPOS, angle_raw_in_range(angle))
        };
        send(RegWrite::word(device, id, raw));
    }
}
