//! What a script's `stop` and `calibrate` decide from the update() they read: which
//! fitted controllers are running, which sit in REMOTESLAVE, which to release afterwards
//! and what to say about the rest. Plain decisions on a [`Snapshot`], tested in
//! `run`'s tests; `run` sends the frames.

use shared::exception::ExceptionType;
use shared::regs::id;

use super::live::{slave_exception, Snapshot};
use super::pc::{self, Pairs};
use super::script::Action;
use crate::error::{list, HostError};
use crate::exception::Exception;

/// The controllers a `calibrate`'s start stopped ([`Action::Freeze`]).
#[derive(Debug, Clone, Default)]
pub(super) struct Frozen {
    /// Those it read running.
    pub(super) stopped: Vec<u8>,
    /// Those whose reply the serial line lost: stopped in case they ran.
    pub(super) unread: Vec<u8>,
}

/// What the end of a `calibrate` ([`Action::Thaw`]) does: each controller its start
/// stopped, and that the update() after its frames shows in REMOTESLAVE, leaves it
/// (REG_RESET 1), unless the master may have stopped the rover meanwhile: a fitted
/// controller silent, or the master holding an exception other than its boot state (or
/// its state unread). A board its start could not read stays stopped. Each left stopped,
/// and each that ignored the stop (its DISABLEDEXCEPTIONS masks REMOTESLAVE), is named in
/// a note.
#[derive(Debug, PartialEq)]
pub(super) struct Thaw {
    /// The controllers to release, in order.
    pub(super) release: Vec<u8>,
    /// What to say.
    pub(super) notes: Vec<String>,
}

impl Thaw {
    /// The thaw of `frozen`, with `now` read after the calibration's frames.
    pub(super) fn of(frozen: &Frozen, now: &Snapshot, pairs: Pairs) -> Thaw {
        let silent: Vec<u8> = pairs
            .devices()
            .filter(|d| now.silent().contains(d))
            .collect();
        let why = if !silent.is_empty() {
            Some(format!("controller(s) {} not answering", list(&silent)))
        } else {
            master_stops(now)
        };
        let remote = in_remote_exception(now, pairs);
        let held: Vec<u8> = frozen
            .stopped
            .iter()
            .chain(&frozen.unread)
            .copied()
            .filter(|d| remote.contains(d))
            .collect();
        if let Some(why) = why {
            // None of them in REMOTESLAVE (each in its own fault, or silent): nothing to
            // hold back, and the view says why each is stopped.
            if held.is_empty() {
                return Thaw {
                    release: Vec::new(),
                    notes: Vec::new(),
                };
            }
            let note = format!(
                "the calibrate leaves the controllers it stopped ({}) in REMOTESLAVE: {why}, \
                 so the master may have stopped the rover itself; a `reset` line releases \
                 them once the cause is gone",
                list(&held)
            );
            return Thaw {
                release: Vec::new(),
                notes: vec![note],
            };
        }
        let (unread, release): (Vec<u8>, Vec<u8>) =
            held.iter().partition(|d| frozen.unread.contains(d));
        let mut notes = Vec::new();
        if !unread.is_empty() {
            notes.push(format!(
                "the calibrate leaves controller(s) {} in REMOTESLAVE: the serial line lost \
                 their state before it, so each was stopped in case it ran, and stays \
                 stopped (it may have been stopped before); a `reset` line releases it",
                list(&unread)
            ));
        }
        let ignored: Vec<u8> = running(now, pairs)
            .into_iter()
            .filter(|d| frozen.stopped.contains(d) || frozen.unread.contains(d))
            .collect();
        if !ignored.is_empty() {
            notes.push(format!(
                "controller(s) {} ignored the calibrate's stop (DISABLEDEXCEPTIONS masks \
                 REMOTESLAVE, bit 3): their motors ran on through it, a drive toward its \
                 demand on the new gains, a steer or lift perhaps to the number it held, read \
                 on the new calibration",
                list(&ignored)
            ));
        }
        Thaw { release, notes }
    }
}

/// REG_RESET 1 to each of `devices` through `send`: each tried, the first refusal
/// returned after them.
pub(super) fn release(
    devices: &[u8],
    mut send: impl FnMut(&Action) -> Result<(), HostError>,
) -> Result<(), HostError> {
    let mut refused = Vec::new();
    let mut first = None;
    for &device in devices {
        match send(&Action::Op(pc::reset_of(device)?)) {
            Err(e @ HostError::WriteRefused { .. }) => {
                refused.push(device);
                first.get_or_insert(e);
            }
            other => other?,
        }
    }
    match first {
        None => Ok(()),
        Some(first) => Err(HostError::ReleaseRefused {
            devices: refused,
            first: Box::new(first),
        }),
    }
}

/// Why the master may have stopped the rover, from the exception `now` shows it holding:
/// any but none and its boot state (a missing temperature sensor stops every motor too).
/// Its state unread counts as well.
pub(super) fn master_stops(now: &Snapshot) -> Option<String> {
    let Some(raw) = now.raw(0, id::REGMASTER_EXCEPTIONDATA) else {
        return Some("the master's state was not read".to_owned());
    };
    let e = Exception::master(raw);
    if e.is_none() || e.code == ExceptionType::Boot as u8 {
        return None;
    }
    Some(format!("the master holds an exception ({})", e.words()))
}

/// The fitted controllers that `now` shows running: STATUS read, out of exception.
pub(super) fn running(now: &Snapshot, pairs: Pairs) -> Vec<u8> {
    pairs
        .devices()
        .filter(|&device| now.raw(device, id::REG_STATUS).is_some())
        .filter(|&device| slave_exception(now, device).is_none())
        .collect()
}

/// The fitted controllers that `now` shows in REMOTESLAVE: the ones a `stop`'s
/// REG_EXCEPTIONDATA writes sent there, or the master's spread of another board's fault
/// (that board keeps its own exception, and the master its). A board in its boot state or
/// its own fault is left in it; one not read is left as it is.
pub(super) fn in_remote_exception(now: &Snapshot, pairs: Pairs) -> Vec<u8> {
    pairs
        .devices()
        .filter(|&device| {
            slave_exception(now, device).is_some_and(|e| e.code == ExceptionType::RemoteSlave as u8)
        })
        .collect()
}
