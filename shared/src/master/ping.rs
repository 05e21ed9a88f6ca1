//! The master's schedule of slave traffic (reference §5 Ping, Spreading, Boot; §6.3), as a
//! pure state machine driven by the millisecond clock.
//!
//! The firmware asks [`Schedule::poll`] for the next [`Action`], performs it on I2C (or on
//! the OneWire bus for [`Action::TemperatureTick`]) and reports the [`Outcome`] with
//! [`Schedule::feed`], until `poll` returns `None`; then it serves the PC link and comes
//! back. [`Schedule::run`] does that loop with a closure. Everything here runs on the host
//! against fake clocks and buses.
//!
//! # What it does, in priority order
//! 1. **Spreading.** When an exception is latched, REG_EXCEPTIONDATA = 100 (`05 64 00`) is
//!    written to every slave 1..9 except the one it came from (all nine for a master-side
//!    type), before anything else. [`Schedule::stop_everything`] (new: the PC-silence
//!    failsafe) spreads to all nine even while the master is already in exception.
//! 2. **Boot.** REG_RESET = 2 (`00 02`) to slaves 1..9, once. The firmware holds its 1-s
//!    watchdog until [`Schedule::booted`], then switches to 125 ms (the watchdog's step
//!    nearest the original's 120 ms).
//! 3. From 5 s after boot (the slaves' reboot time):
//!    - **Ping**, when more than 1000 ms have passed since the last one: for slaves 1..9 in
//!      order, write REG_PING = 0 (`07 00`), read REG_STATUS and, if its bit 0 is set, read
//!      REG_EXCEPTIONDATA. A type other than BOOT and REMOTESLAVE is latched as (slave,
//!      motor, type) and spread. While the master is in exception (boot included) the
//!      latch refuses it, so nothing is recorded or spread.
//!    - **Temperature tick**, when more than 2000 ms have passed since the last one.
//!    - **Liveness check** (new): read REG_STATUS of the present slave accessed longest
//!      ago, every [`LIVENESS_PERIOD_MS`] (pacing, while the loop runs freely), and at once
//!      for every present slave not accessed for [`LIVENESS_MAX_AGE_MS`] (catching up after
//!      the loop was blocked). Only the answer counts; exceptions are left to the 1-s ping,
//!      so PC programs see the original's exception timing, and a slave the PC has just
//!      reset is not caught before it has processed the reset.
//!
//! # Silent slaves (new)
//! A slave that has answered since boot (PC-relayed accesses count from the start, so one
//! the PC drove and lost before the first ping is found then) and then fails two
//! consecutive accesses from 5 s after boot (any of the above, or PC-relayed ones reported
//! with [`Schedule::observe`]) is *silent*: the
//! master raises [`ExceptionType::SlaveSilent`] naming it (motor 0), which spreads to all
//! other slaves, so every motor stops: on being found silent it spreads even while the
//! master holds another exception (its boot state, for one), which the latch keeps. The
//! first failure triggers an immediate re-check, so a single disturbed transfer is not
//! enough. A slave that never answered is absent, not silent (a rover may be built with
//! fewer pairs). A silent slave stays monitored: if the master's exception is cleared
//! while it is still silent, the next failure raises it again, as a slave still in
//! exception is re-detected by the next ping.
//!
//! **Lost spreads.** A spread write can fail with the rest of the bus (a slave holding
//! SCL low fails every access until its watchdog frees it). So when a slave answers
//! again after a failed access while the master holds an exception other than its boot
//! state, the spread goes out again to all nine; a board already in exception is not
//! changed by it.
//!
//! **Bound.** Every present slave is accessed at least every L = [`LIVENESS_MAX_AGE_MS`]
//! = 16 ms whenever the loop polls, so a slave that stops answering is found at most
//! L + B + 8·R + 2·T after its last answer, where B is the longest time the firmware spends
//! between two polls (one PC frame, up to ~15 ms for a 24-register read, or one
//! temperature tick, ~16 ms of OneWire), R ≈ 0.65 ms is one status read at 100 kHz (less
//! at the firmware's 400 kHz; up to eight other stale slaves may be checked first) and T
//! is the I2C driver's timeout (a missing ACK costs ~0.1 ms; 1 ms assumed), paid for the
//! failed read and the re-check.
//! The spread is then 8 writes of ~0.4 ms. With B = 16 ms: 16 + 16 + 5.2 + 2 + 3.2 ≈ 42 ms,
//! leaving the slaves ≥ 8 ms of the 50-ms goal to act on the write. A firmware that also
//! polls between the register accesses of a long PC frame shrinks B to one transfer.
//!
//! **Cost.** Idle, the checks take ~0.65 ms of bus time every 2 ms; a PC frame waits for at
//! most one of them. Under back-to-back PC frames, each frame is followed by the checks of
//! the slaves it did not touch (up to ~5 ms per 15-ms frame): that is the price of the bound.

mod action;
mod health;

pub use action::{Action, Outcome, RegWrite};

use crate::exception::{ExceptionType, MasterException, MasterLatch};
use crate::regs::id;
use health::{bit, Health, Miss};

/// Time from boot before pings, checks and temperature ticks start, in ms.
pub const BOOT_SETTLE_MS: u32 = 5000;
/// A ping runs when more than this many ms have passed since the last.
pub const PING_PERIOD_MS: u32 = 1000;
/// A temperature tick runs when more than this many ms have passed since the last.
pub const TEMPERATURE_PERIOD_MS: u32 = 2000;
/// One liveness check every this many ms while the loop runs freely.
pub const LIVENESS_PERIOD_MS: u32 = 2;
/// A present slave not accessed for this many ms is checked at the next poll.
pub const LIVENESS_MAX_AGE_MS: u16 = 16;
/// The schedule's part of the silent-slave bound, ms: a present slave is accessed at most
/// this long after its previous access whenever the loop polls (see the module doc for
/// what the firmware adds).
pub const SILENT_DETECT_BOUND_MS: u32 = LIVENESS_MAX_AGE_MS as u32;
/// Value written to REG_EXCEPTIONDATA to spread an exception.
pub const SPREAD_VALUE: u16 = 100;

/// Where the schedule stands.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Phase {
    /// Sending the boot resets (1-s watchdog).
    Boot,
    /// Waiting for the slaves to reboot (5 s from boot).
    Settling,
    /// Pinging, checking and reading temperatures.
    Running,
}

/// The job an action belongs to.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
// Numbered from 1 so that `None` around it is stored as 0: the schedule starts as all
// zeros, which the firmware keeps in `.bss` instead of copying an initial value from flash.
#[repr(u8)]
enum Job {
    Boot = 1,
    Spread,
    Ping,
    Check,
    Temperature,
}

/// Where the ping of one slave stands.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
// Numbered from 1 for the same reason as `Job`.
#[repr(u8)]
enum PingStage {
    Ping = 1,
    Status,
    ExceptionData,
}

/// The remaining writes of a spread: to slaves 10 − `left` ..= 9, skipping `except`.
/// Counted down, so the state with nothing left is all zeros (no tag, and the schedule
/// stays all zeros at boot).
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
struct Spread {
    left: u8,
    except: u8,
}

impl Spread {
    /// Slaves 1..=9 except `except`.
    const fn to_all_but(except: u8) -> Self {
        Spread { left: 9, except }
    }

    fn take(&mut self) -> Option<u8> {
        while self.left > 0 {
            let d = 10 - self.left;
            self.left -= 1;
            if d != self.except {
                return Some(d);
            }
        }
        None
    }
}

/// The master's schedule of slave traffic.
#[derive(Clone, Debug)]
pub struct Schedule {
    /// Boot resets sent so far (slaves 1..=`boot_sent`).
    boot_sent: u8,
    started: bool,
    // Times are kept as the low 16 bits of the ms clock: every period measured is far
    // below 65 s, and the loop polls every few ms.
    last_ping: u16,
    last_temperature: u16,
    last_check: u16,
    ping: Option<(u8, PingStage)>,
    // The slave being checked and the one to re-check next, 0 for none: only slaves
    // 1..=9 are ever checked, so device 0 is free to mean "none" (one byte each, no tag).
    check: u8,
    recheck: u8,
    spread: Spread,
    health: Health,
    /// The current action, its job and the poll time it was issued at.
    in_flight: Option<(Action, Job, u16)>,
}

impl Default for Schedule {
    fn default() -> Self {
        Self::new()
    }
}

impl Schedule {
    /// The schedule at power-up: the boot resets come first.
    pub const fn new() -> Self {
        Schedule {
            boot_sent: 0,
            started: false,
            last_ping: 0,
            last_temperature: 0,
            last_check: 0,
            ping: None,
            check: 0,
            recheck: 0,
            spread: Spread { left: 0, except: 0 },
            health: Health::new(),
            in_flight: None,
        }
    }

    /// Where the schedule stands.
    pub fn phase(&self) -> Phase {
        if !self.booted() {
            Phase::Boot
        } else if !self.started {
            Phase::Settling
        } else {
            Phase::Running
        }
    }

    /// Whether the boot resets have all been performed (the firmware then shortens its
    /// watchdog to 125 ms).
    pub fn booted(&self) -> bool {
        self.boot_sent >= 9 && !matches!(self.in_flight, Some((_, Job::Boot, _)))
    }

    /// Whether the slaves have had [`BOOT_SETTLE_MS`] to come back from the boot resets:
    /// pings and checks run from then on, and so does the remote control, whose link-up
    /// writes a slave still rebooting would miss.
    pub const fn started(&self) -> bool {
        self.started
    }

    /// Slaves that have answered since boot: bit n for slave n.
    pub const fn present(&self) -> u16 {
        self.health.present
    }

    /// Slaves found silent and not answering since: bit n for slave n.
    pub const fn silent(&self) -> u16 {
        self.health.silent
    }

    /// The next action to perform at `now_ms`, or `None` when nothing is due. An action
    /// stays current until [`Schedule::feed`] reports its outcome; polling again before
    /// that returns it again.
    /// Periods are measured on the clock's low 16 bits: poll at least once a minute
    /// (the firmware polls every few ms).
    pub fn poll(&mut self, now_ms: u32) -> Option<Action> {
        if let Some((action, _, _)) = self.in_flight {
            return Some(action);
        }
        let (action, job) = self.next_action(now_ms)?;
        self.in_flight = Some((action, job, now_ms as u16));
        Some(action)
    }

    /// Reports the outcome of the action [`Schedule::poll`] returned. Exceptions are
    /// latched in `latch` (the master's, behind REGMASTER_EXCEPTIONDATA) and spread.
    pub fn feed(&mut self, outcome: Outcome, latch: &mut MasterLatch) {
        let Some((action, job, at)) = self.in_flight.take() else {
            return;
        };
        let answered = outcome != Outcome::NoAnswer;
        match job {
            Job::Boot | Job::Temperature => {}
            Job::Spread => {
                if let Some(d) = action.device() {
                    self.evidence(d, answered, at, latch);
                }
            }
            Job::Check => {
                if let Some(d) = take_slave(&mut self.check) {
                    self.evidence(d, answered, at, latch);
                }
            }
            Job::Ping => self.ping_result(outcome, at, latch),
        }
    }

    /// Performs everything due at `now_ms`, calling `perform` for each action.
    pub fn run(
        &mut self,
        now_ms: u32,
        latch: &mut MasterLatch,
        mut perform: impl FnMut(Action) -> Outcome,
    ) {
        while let Some(action) = self.poll(now_ms) {
            let outcome = perform(action);
            self.feed(outcome, latch);
        }
    }

    /// Reports whether a slave answered an access at `now_ms` that the schedule did not
    /// ask for (the PC frames the master relays), as evidence of its liveness.
    pub fn observe(&mut self, device: u8, answered: bool, now_ms: u32, latch: &mut MasterLatch) {
        self.observe_at(device, answered, now_ms as u16, latch);
    }

    /// [`Schedule::observe`] on the clock's low 16 bits, which is all it keeps (what the
    /// firmware's 16-bit clock passes).
    // Out of line: PC frames and the remote control's writes both report (one copy).
    #[inline(never)]
    pub fn observe_at(&mut self, device: u8, answered: bool, now_ms: u16, latch: &mut MasterLatch) {
        self.evidence(device, answered, now_ms, latch);
    }

    /// Raises an exception on the master (e.g. type 10, a missing temperature sensor):
    /// latched unless one already is, and then spread to every slave except `e.slave`.
    /// Returns whether it was latched.
    pub fn raise(&mut self, e: MasterException, latch: &mut MasterLatch) -> bool {
        if !latch.raise(e) {
            return false;
        }
        self.spread = Spread::to_all_but(e.slave);
        true
    }

    /// Raises `e` on the master (latched unless one already is) and spreads to every
    /// slave in any case, so that every motor stops even while the master is already in
    /// exception (from boot until the PC resets it, for one): the PC-silence failsafe.
    pub fn stop_everything(&mut self, e: MasterException, latch: &mut MasterLatch) {
        latch.raise(e);
        self.spread = Spread::to_all_but(0);
    }

    fn next_action(&mut self, now_ms: u32) -> Option<(Action, Job)> {
        if let Some(d) = self.spread.take() {
            return Some((spread_write(d), Job::Spread));
        }
        if self.boot_sent < 9 {
            self.boot_sent += 1;
            let d = self.boot_sent;
            let reset = RegWrite::byte(d, id::REG_RESET, 2);
            return Some((Action::WriteReg(reset), Job::Boot));
        }
        if let Some(d) = take_slave(&mut self.recheck) {
            self.check = d;
            return Some((Action::ReadStatus { device: d }, Job::Check));
        }
        if let Some((d, stage)) = self.ping {
            return Some((ping_action(d, stage), Job::Ping));
        }
        if !self.started {
            if now_ms <= BOOT_SETTLE_MS {
                return None;
            }
            self.started = true;
        }
        let now = now_ms as u16;
        if u32::from(now.wrapping_sub(self.last_ping)) > PING_PERIOD_MS {
            self.last_ping = now;
            self.ping = Some((1, PingStage::Ping));
            return Some((ping_action(1, PingStage::Ping), Job::Ping));
        }
        if u32::from(now.wrapping_sub(self.last_temperature)) > TEMPERATURE_PERIOD_MS {
            self.last_temperature = now;
            return Some((Action::TemperatureTick, Job::Temperature));
        }
        let (d, age) = self.health.stalest(now)?;
        let paced = u32::from(now.wrapping_sub(self.last_check)) >= LIVENESS_PERIOD_MS;
        if paced || age >= LIVENESS_MAX_AGE_MS {
            self.last_check = now;
            self.check = d;
            return Some((Action::ReadStatus { device: d }, Job::Check));
        }
        None
    }

    /// Advances the ping after one of its actions.
    // Out of line: measured 6 B smaller than in `feed`.
    #[inline(never)]
    fn ping_result(&mut self, outcome: Outcome, at: u16, latch: &mut MasterLatch) {
        let Some((d, stage)) = self.ping else {
            return;
        };
        self.evidence(d, outcome != Outcome::NoAnswer, at, latch);
        let next_stage = match (stage, outcome) {
            (PingStage::Ping, _) => Some(PingStage::Status),
            (PingStage::Status, Outcome::Value(status)) if status & 1 != 0 => {
                Some(PingStage::ExceptionData)
            }
            (PingStage::ExceptionData, Outcome::Value(data)) => {
                self.slave_exception(d, data, latch);
                None
            }
            _ => None,
        };
        self.ping = match next_stage {
            Some(s) => Some((d, s)),
            None if d < 9 => Some((d + 1, PingStage::Ping)),
            None => None,
        };
    }

    /// A slave's EXCEPTIONDATA read by the ping: latch and spread a spreading type.
    fn slave_exception(&mut self, device: u8, data: u16, latch: &mut MasterLatch) {
        let [code, motor] = data.to_le_bytes();
        match ExceptionType::from_code(code) {
            Some(kind) if kind.spreads() => {
                let e = MasterException {
                    kind,
                    slave: device,
                    motor,
                };
                self.raise(e, latch);
            }
            // BOOT and REMOTESLAVE never spread; an unknown code names no exception.
            _ => {}
        }
    }

    /// An access to `device` at `at` (ms) succeeded or failed.
    fn evidence(&mut self, device: u8, answered: bool, at: u16, latch: &mut MasterLatch) {
        if bit(device) == 0 {
            return;
        }
        if answered {
            // Before the settle too: a slave the PC reached is fitted, so one lost before the
            // first ping is found silent by it, not taken for a board never fitted.
            // Back after a failed access while the master holds an exception (not its
            // boot state): a spread may have missed it (a held bus, a glitch), so the
            // spread goes out again, to all nine (the one the exception names may have
            // been lost with the rest; a board in exception already is not changed by it).
            if self.health.answered(device, at)
                && latch
                    .current()
                    .is_some_and(|e| e.kind != ExceptionType::Boot)
            {
                self.spread = Spread::to_all_but(0);
            }
            return;
        }
        if !self.started {
            // A failure during the settle proves nothing: the slaves reboot from the boot resets.
            return;
        }
        match self.health.failed(device, at) {
            Miss::Ignored => {}
            Miss::Recheck => self.recheck = device,
            miss @ (Miss::NowSilent | Miss::Silent) => {
                if self.recheck == device {
                    self.recheck = 0;
                }
                let e = MasterException {
                    kind: ExceptionType::SlaveSilent,
                    slave: device,
                    motor: 0,
                };
                // A slave newly found silent stops the others even while the master holds
                // another exception (its boot state, for one): the latch keeps the first.
                if latch.raise(e) || miss == Miss::NowSilent {
                    self.spread = Spread::to_all_but(device);
                }
            }
        }
    }
}

/// The slave in `slot` (0 for none), leaving none.
fn take_slave(slot: &mut u8) -> Option<u8> {
    match core::mem::take(slot) {
        0 => None,
        d => Some(d),
    }
}

/// REG_EXCEPTIONDATA = 100 to slave `device`.
fn spread_write(device: u8) -> Action {
    Action::WriteReg(RegWrite::word(device, id::REG_EXCEPTIONDATA, SPREAD_VALUE))
}

/// The action of one ping stage.
fn ping_action(device: u8, stage: PingStage) -> Action {
    match stage {
        PingStage::Ping => Action::WriteReg(RegWrite::byte(device, id::REG_PING, 0)),
        PingStage::Status => Action::ReadStatus { device },
        PingStage::ExceptionData => Action::ReadExceptionData { device },
    }
}

#[cfg(test)]
mod tests {
    use super::Spread;

    #[test]
    fn a_spread_counts_down_through_slaves_1_to_9_but_one_and_zero_is_none() {
        for except in 0..=10u8 {
            let mut s = Spread::to_all_but(except);
            let got: std::vec::Vec<u8> = core::iter::from_fn(|| s.take()).collect();
            let want: std::vec::Vec<u8> = (1..=9).filter(|&d| d != except).collect();
            assert_eq!(got, want, "{except}");
            assert_eq!(s.take(), None);
        }
        let mut none = Spread { left: 0, except: 0 };
        assert_eq!(none.take(), None);
    }
}
