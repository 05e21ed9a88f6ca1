//! One I²C bus joining several emulated chips and Rust-side devices, run in lock step.
//!
//! A [`Bus`] owns its chips: master firmwares ([`Bus::add_master`]), slave firmwares
//! ([`Bus::add_slave`], each reading its address from wherever its firmware does, e.g. EEPROM
//! byte 0 set by the caller with [`Avr::eeprom_write`] before adding it), and Rust slave models
//! ([`Bus::add_target`]). The bus itself is a Rust master peer too: [`Bus::write`],
//! [`Bus::read`] and [`Bus::write_read`] drive real slave firmware.
//!
//! **Time.** [`Bus::run_us`] advances every chip together, a quantum (10 µs by default) at a
//! time: each chip runs until its clock reaches the end of the quantum, so no two chips drift
//! apart by more than a quantum plus one slave answer. Syncing every ~10 µs instead of every
//! instruction gives the same bus timings and runs faster. When a master addresses a slave chip,
//! that chip is run at once, inside the master's step, until its firmware has answered (see
//! [`crate::twi`] for how simavr's TWI is bridged and what it models of bus timing).
//!
//! **Threads.** With [`Bus::set_threads`] above 1, each quantum runs in two phases: first the
//! master chips (and every chip added before the last of them) one after the other, each with
//! the slaves it addresses run on the spot as above; then the slave chips still behind, side
//! by side on worker threads. A slave in that second phase touches only its own core and
//! hooks, so the result is the same as with one thread, whatever the threads' timing.
//!
//! **Faults.** [`Bus::cut`] takes an address off the bus (its device NACKs everything, as if
//! unplugged) and [`Bus::restore`] puts it back. A slave chip that takes an event but never
//! answers costs a bounded wait ([`Bus::set_answer_timeout_us`]), never a hang of the
//! emulator; if its TWINT stays set it then holds SCL low ([`Bus::held_by`]), and nothing
//! moves on the bus until it lets go or resets, checked after every quantum.
//!
//! **Trace.** Every START, address, data byte, ACK/NACK and STOP is logged with the initiator's
//! cycle count ([`Bus::trace`]).

#[path = "bus_engine.rs"]
mod engine;
#[path = "bus_peer.rs"]
mod peer;
#[path = "bus_pool.rs"]
mod pool;
#[path = "bus_trace.rs"]
mod trace;

use std::cell::{RefCell, RefMut};
use std::marker::PhantomData;
use std::ptr::NonNull;
use std::rc::Rc;
use std::time::Duration;

use crate::avr::{Shared, CYCLES_PER_US};
use crate::twi::chip::SlaveChip;
use crate::twi::port::{gate_twint, Tap, TwiIrqs};
use crate::twi::{downcast_mut, I2cTarget, TwiError};
use crate::{Avr, HarnessError};
use engine::{Device, Engine};

pub use trace::{Initiator, TraceEntry, TwiEvent};

/// Default lock-step quantum: 10 µs of emulated time.
pub const DEFAULT_QUANTUM_US: u64 = 10;
/// Default bound on a slave chip's answer: 1 ms of emulated time.
pub const DEFAULT_ANSWER_TIMEOUT_US: u64 = 1_000;
/// Default bound on waiting for another master's transaction to end: 100 ms.
pub const DEFAULT_BUSY_TIMEOUT_US: u64 = 100_000;
/// Default clock of the Rust master peer (the rover's bus speed).
pub const DEFAULT_PEER_KHZ: u64 = 100;

/// A handle to a Rust target on a bus, to get it back with its own type ([`Bus::target`]).
pub struct TargetId<T> {
    index: usize,
    _type: PhantomData<fn() -> T>,
}

/// Several chips and Rust devices on one emulated I²C bus.
pub struct Bus {
    // Field order is drop order: hooks on master chips go before the engine and the chips.
    master_taps: Vec<Tap>,
    /// Worker threads for the slave phase; None runs every chip on the caller's thread.
    pool: Option<pool::Pool>,
    /// Chips run one after the other in each quantum, before the rest run side by side:
    /// every chip up to and including the last master chip.
    serial_chips: usize,
    engine: Rc<RefCell<Engine>>,
    chips: Vec<Rc<RefCell<Avr>>>,
    /// UART0 bytes taken from each chip by the bus helpers and not returned yet.
    uart_pending: Vec<Vec<u8>>,
    /// Chip indices of the master chips.
    masters: Vec<usize>,
    /// Bus time: every chip's clock has reached at least this cycle.
    now: u64,
    quantum: u64,
    peer_bit: u64,
    busy_timeout: u64,
}

impl Default for Bus {
    fn default() -> Self {
        Bus::new()
    }
}

impl Bus {
    /// An empty bus with the default quantum, timeouts and peer speed.
    pub fn new() -> Bus {
        Bus {
            master_taps: Vec::new(),
            pool: None,
            serial_chips: 0,
            engine: Rc::new(RefCell::new(Engine::new(
                DEFAULT_ANSWER_TIMEOUT_US * CYCLES_PER_US,
            ))),
            chips: Vec::new(),
            uart_pending: Vec::new(),
            masters: Vec::new(),
            now: 0,
            quantum: DEFAULT_QUANTUM_US * CYCLES_PER_US,
            peer_bit: peer_bit_cycles(DEFAULT_PEER_KHZ),
            busy_timeout: DEFAULT_BUSY_TIMEOUT_US * CYCLES_PER_US,
        }
    }

    /// Puts a chip running master firmware on the bus; returns its chip index.
    pub fn add_master(&mut self, mut avr: Avr) -> Result<usize, TwiError> {
        let irqs = TwiIrqs::find(avr.as_ptr())?;
        gate_twint(&mut avr);
        let index = self.chips.len();
        let engine = Rc::clone(&self.engine);
        let clock: *const Shared = &*avr.shared;
        let tap = Tap::attach(
            irqs,
            Box::new(move |msg| {
                // SAFETY: `clock` is the chip's own `Shared`, boxed and owned by the chip,
                // which outlives this tap (the bus drops taps first); only its cells are
                // used, as the chip's own simavr hooks do.
                let shared = unsafe { &*clock };
                let mut engine = engine.try_borrow_mut().ok()?;
                let answer = engine.on_master_msg(index, msg, shared.now());
                // A slave that took this step and kept TWINT set holds the clock from now.
                shared.scl_held.set(engine.held_by().is_some());
                answer
            }),
        );
        self.master_taps.push(tap);
        let index = self.push_chip(Rc::new(RefCell::new(avr)));
        self.masters.push(index);
        self.serial_chips = index + 1;
        Ok(index)
    }

    /// Puts a chip running slave firmware on the bus; returns its chip index.
    pub fn add_slave(&mut self, avr: Avr) -> Result<usize, TwiError> {
        let avr = Rc::new(RefCell::new(avr));
        let slave = SlaveChip::attach(Rc::clone(&avr))?;
        self.engine.borrow_mut().devices.push(Device::Chip(slave));
        Ok(self.push_chip(avr))
    }

    fn push_chip(&mut self, avr: Rc<RefCell<Avr>>) -> usize {
        self.now = self.now.max(avr.borrow().cycles());
        self.chips.push(avr);
        self.uart_pending.push(Vec::new());
        self.chips.len() - 1
    }

    /// Puts a Rust slave model on the bus. Devices are asked in the order they were added.
    pub fn add_target<T: I2cTarget>(&mut self, target: T) -> TargetId<T> {
        let mut engine = self.engine.borrow_mut();
        engine.devices.push(Device::Target(Box::new(target)));
        TargetId {
            index: engine.devices.len() - 1,
            _type: PhantomData,
        }
    }

    /// The Rust target added as `id`, to inspect or change it between runs.
    pub fn target<T: I2cTarget>(&self, id: &TargetId<T>) -> Option<RefMut<'_, T>> {
        let engine = self.engine.try_borrow_mut().ok()?;
        RefMut::filter_map(engine, |e| {
            e.target_mut(id.index).and_then(downcast_mut::<T>)
        })
        .ok()
    }

    /// The chip with index `index` (in the order chips were added).
    pub fn chip(&self, index: usize) -> Option<RefMut<'_, Avr>> {
        self.chips.get(index)?.try_borrow_mut().ok()
    }

    /// Number of chips on the bus.
    pub fn chip_count(&self) -> usize {
        self.chips.len()
    }

    /// Bus time in cycles: every chip has run at least this far.
    pub fn cycles(&self) -> u64 {
        self.now
    }

    /// Bus time in emulated microseconds.
    pub fn micros(&self) -> u64 {
        self.now / CYCLES_PER_US
    }

    /// Runs the slave chips of each quantum on `threads` threads in all, the caller's
    /// included (see the module docs); 1 (the default) runs every chip on the caller's thread.
    /// The worker threads live as long as the bus (or until the next call).
    pub fn set_threads(&mut self, threads: usize) {
        let threads = threads.max(1);
        if threads != self.threads() {
            self.pool = (threads > 1).then(|| pool::Pool::new(threads - 1));
        }
    }

    /// Threads the chips run on, the caller's included.
    pub fn threads(&self) -> usize {
        self.pool.as_ref().map_or(1, |p| p.workers() + 1)
    }

    /// CPU time the bus's worker threads have used so far (zero with one thread); the
    /// caller's own thread is not included.
    pub fn worker_cpu(&self) -> Duration {
        self.pool
            .as_ref()
            .map_or(Duration::ZERO, pool::Pool::worker_cpu)
    }

    /// Sets the lock-step quantum (at least 1 µs).
    pub fn set_quantum_us(&mut self, us: u64) {
        self.quantum = us.max(1) * CYCLES_PER_US;
    }

    /// Sets how long a slave chip may take to answer one bus event (at least 1 µs).
    pub fn set_answer_timeout_us(&mut self, us: u64) {
        self.engine.borrow_mut().answer_budget = us.max(1) * CYCLES_PER_US;
    }

    /// Sets how long the Rust master waits for another master's transaction to end.
    pub fn set_busy_timeout_us(&mut self, us: u64) {
        self.busy_timeout = us * CYCLES_PER_US;
    }

    /// Sets the Rust master's SCL clock (1..=1000 kHz).
    pub fn set_peer_khz(&mut self, khz: u64) {
        self.peer_bit = peer_bit_cycles(khz);
    }

    /// Whether slave chips see simavr's STOP after a master read (status 0xA0, which the real
    /// chip does not produce). Off by default.
    pub fn set_simavr_stop_after_read(&mut self, on: bool) {
        self.engine.borrow_mut().stop_after_read = on;
    }

    /// Takes the device at `addr` off the bus: it NACKs everything until [`Bus::restore`].
    pub fn cut(&mut self, addr: u8) {
        self.engine.borrow_mut().cut(addr);
    }

    /// Puts the device at `addr` back on the bus.
    pub fn restore(&mut self, addr: u8) {
        self.engine.borrow_mut().restore(addr);
    }

    /// Whether `addr` is cut off the bus.
    pub fn is_cut(&self, addr: u8) -> bool {
        self.engine.borrow().is_cut(addr)
    }

    /// Turns the message log on or off (on by default).
    pub fn set_tracing(&mut self, on: bool) {
        self.engine.borrow_mut().tracing = on;
    }

    /// The message log so far.
    pub fn trace(&self) -> Vec<TraceEntry> {
        self.engine.borrow().trace().to_vec()
    }

    /// Takes the message log, leaving it empty.
    pub fn take_trace(&mut self) -> Vec<TraceEntry> {
        self.engine.borrow_mut().take_trace()
    }

    /// Runs every chip for `us` emulated microseconds, in lock step.
    pub fn run_us(&mut self, us: u64) {
        self.run_cycles(us.saturating_mul(CYCLES_PER_US));
    }

    /// Runs every chip for `n` cycles, in lock step.
    pub fn run_cycles(&mut self, n: u64) {
        self.advance_to(self.now.saturating_add(n));
    }

    /// Runs in lock step until `pred` is true (checked after every quantum) or `max_us` pass.
    /// Returns whether `pred` became true.
    pub fn run_until(&mut self, max_us: u64, mut pred: impl FnMut(&mut Bus) -> bool) -> bool {
        let end = self
            .now
            .saturating_add(max_us.saturating_mul(CYCLES_PER_US));
        loop {
            if pred(self) {
                return true;
            }
            if self.now >= end {
                return false;
            }
            self.advance_to(self.now.saturating_add(self.quantum).min(end));
        }
    }

    /// Advances bus time to `target`, one quantum at a time.
    fn advance_to(&mut self, target: u64) {
        while self.now < target {
            let next = self.now.saturating_add(self.quantum).min(target);
            match &self.pool {
                Some(pool) => {
                    let (serial, side_by_side) = self.chips.split_at(self.serial_chips);
                    run_chips(serial, next);
                    run_side_by_side(pool, side_by_side, next);
                }
                None => run_chips(&self.chips, next),
            }
            self.now = next;
            self.release_if_free();
        }
    }

    /// The address of the slave chip holding SCL low, if one does: it took a bus event and
    /// its firmware has not released the bus since (see the [`crate::twi`] docs).
    pub fn held_by(&self) -> Option<u8> {
        self.engine.borrow().held_by()
    }

    /// Ends a hold whose chip has let SCL go, and lets the master chips' TWINT rise again.
    fn release_if_free(&mut self) {
        let Ok(mut engine) = self.engine.try_borrow_mut() else {
            return;
        };
        if engine.held_by().is_none() || !engine.release_if_free(self.now) {
            return;
        }
        drop(engine);
        for &index in &self.masters {
            if let Ok(avr) = self.chips[index].try_borrow() {
                avr.shared.scl_held.set(false);
            }
        }
    }

    /// Queues bytes for chip `chip`'s UART0 receiver.
    ///
    /// # Panics
    /// If `chip` is not the index of a chip on this bus.
    pub fn uart_send(&mut self, chip: usize, bytes: &[u8]) {
        self.chips[chip].borrow_mut().uart_send(bytes);
    }

    /// Queues bytes for chip `chip`'s UART0 receiver, each with a framing error (see
    /// [`Avr::uart_send_framing_error`]).
    ///
    /// # Panics
    /// If `chip` is not the index of a chip on this bus.
    pub fn uart_send_framing_error(&mut self, chip: usize, bytes: &[u8]) {
        self.chips[chip].borrow_mut().uart_send_framing_error(bytes);
    }

    /// Runs the bus until chip `chip` has sent `needle` on UART0; returns its output up to and
    /// including `needle` (later bytes are kept for the next call).
    ///
    /// # Panics
    /// If `chip` is not the index of a chip on this bus.
    pub fn uart_read_until(
        &mut self,
        chip: usize,
        needle: &[u8],
        max_us: u64,
    ) -> Result<Vec<u8>, HarnessError> {
        let start = self.now;
        let found = |bus: &mut Bus| {
            let fresh = bus.chips[chip].borrow_mut().uart_take();
            let pending = &mut bus.uart_pending[chip];
            pending.extend(fresh);
            find(pending, needle).is_some()
        };
        let done = self.run_until(max_us, found);
        let pending = &mut self.uart_pending[chip];
        match find(pending, needle) {
            Some(end) if done => Ok(pending.drain(..end).collect()),
            _ => Err(HarnessError::Timeout {
                what: format!(
                    "UART bytes {:?} from chip {chip} on the bus",
                    String::from_utf8_lossy(needle)
                ),
                waited_us: (self.now - start) / CYCLES_PER_US,
                got: pending.clone(),
            }),
        }
    }
}

/// Runs each chip that is behind `next` up to it, one after the other.
fn run_chips(chips: &[Rc<RefCell<Avr>>], next: u64) {
    for chip in chips {
        if let Ok(mut avr) = chip.try_borrow_mut() {
            let behind = next.saturating_sub(avr.cycles());
            if behind > 0 {
                avr.run_cycles(behind);
            }
        }
    }
}

/// Runs each chip that is behind `next` up to it, on the pool's threads and this one.
fn run_side_by_side(pool: &pool::Pool, chips: &[Rc<RefCell<Avr>>], next: u64) {
    let mut behind: Vec<RefMut<'_, Avr>> = chips
        .iter()
        .filter_map(|chip| chip.try_borrow_mut().ok())
        .filter(|avr| avr.cycles() < next)
        .collect();
    // An observer is an arbitrary closure, which may not leave its thread; one chip alone
    // is not worth waking the workers.
    if behind.len() < 2 || behind.iter().any(|avr| avr.has_observer()) {
        for avr in &mut behind {
            let cycles = next.saturating_sub(avr.cycles());
            avr.run_cycles(cycles);
        }
        return;
    }
    let raw: Vec<NonNull<Avr>> = behind
        .iter_mut()
        .map(|avr| NonNull::from(&mut **avr))
        .collect();
    // SAFETY: each pointer comes from a distinct `RefMut` held in `behind` until after the
    // call, which is not touched meanwhile; none of the chips has an observer.
    unsafe { pool.run(&raw, next) };
    drop(behind);
}

/// End index of the first `needle` in `haystack`.
fn find(haystack: &[u8], needle: &[u8]) -> Option<usize> {
    if needle.is_empty() {
        return Some(0);
    }
    haystack
        .windows(needle.len())
        .position(|w| w == needle)
        .map(|i| i + needle.len())
}

/// Cycles of one SCL period at `khz` (clamped to 1..=1000 kHz).
fn peer_bit_cycles(khz: u64) -> u64 {
    let khz = khz.clamp(1, 1000);
    (crate::F_CPU / (khz * 1000)).max(1)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn peer_bit_is_one_scl_period() {
        assert_eq!(peer_bit_cycles(100), 160);
        assert_eq!(peer_bit_cycles(400), 40);
        assert_eq!(peer_bit_cycles(0), 16_000);
    }

    #[test]
    fn threads_start_and_stop_with_the_setting() {
        let mut bus = Bus::new();
        assert_eq!(bus.threads(), 1);
        assert_eq!(bus.worker_cpu(), Duration::ZERO);
        bus.set_threads(3);
        assert_eq!(bus.threads(), 3);
        // Runs with no chips still advance bus time through the threaded path.
        bus.run_us(25);
        assert_eq!(bus.micros(), 25);
        bus.set_threads(0);
        assert_eq!(bus.threads(), 1);
    }

    #[test]
    fn finds_needle_end() {
        assert_eq!(find(b"ok\nrest", b"\n"), Some(3));
        assert_eq!(find(b"abc", b"x"), None);
        assert_eq!(find(b"abc", b""), Some(0));
    }
}
