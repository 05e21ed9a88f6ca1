//! Worker threads that run the bus's slave chips side by side, one quantum at a time.
//!
//! Within a quantum, once every master chip has run to the quantum's end (running on the
//! spot any slave it addressed), the slave chips that are still behind do not touch each
//! other, a master or the bus: each one only runs its own core and its own hooks. So they can
//! run on several threads at once and reach the same state whatever the threads' timing.
//!
//! A [`Pool`] keeps its threads for the bus's life. Per phase the owner queues the chips,
//! wakes the workers and takes chips from the same queue itself until it is empty, then
//! waits for the chips the workers took. Every wait spins briefly, then yields its core
//! between looks, then blocks ([`std::thread::park`]), so a machine with fewer free cores
//! than threads slows down instead of collapsing: the owner runs whatever no worker took.

use std::any::Any;
use std::os::unix::thread::JoinHandleExt;
use std::panic::{self, AssertUnwindSafe};
use std::ptr::NonNull;
use std::sync::atomic::{AtomicBool, AtomicU64, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex, MutexGuard, PoisonError};
use std::thread::{self, JoinHandle, Thread};
use std::time::{Duration, Instant};

use crate::Avr;

/// How long a waiting thread spins before it starts yielding its core between looks.
const SPIN: Duration = Duration::from_micros(5);
/// How long a waiting thread keeps looking (spinning, then yielding) before it blocks. A
/// worker that blocked takes long to wake (tens of µs, far more on a busy machine), by which
/// time the owner has run the phase alone; yielding keeps it in step with phases that come
/// every few µs while giving the core away to anything else that wants it.
const LOOK: Duration = Duration::from_millis(1);
/// Spin iterations between two looks at the clock.
const SPINS_PER_CHECK: u32 = 64;

/// One chip handed to a worker for one phase.
struct Job {
    chip: ChipPtr,
    /// Absolute cycle the chip runs to.
    target: u64,
}

/// A chip borrowed by the pool's owner for one phase, to be run on another thread.
struct ChipPtr(NonNull<Avr>);

// SAFETY: an `Avr` is a simavr core plus the boxed state its own hooks use; nothing in it
// is tied to a thread (simavr keeps no mutable globals while running, the harness no
// thread-locals). Its `Rc`/`RefCell` parts (the slave's TWI answer queue, which the bus's
// engine shares with the chip's hook) are only borrowed, never cloned or dropped, on the
// worker, and the engine touches them only in the master phase, when no worker runs. The
// bus hands a chip to the pool only while it holds the chip's `RefMut` and waits, touching
// no chip of the phase, until the phase ends, and the queue gives each chip to exactly one
// thread, so a chip is used by one thread at a time; the queue's mutex and the `running`
// count (release/acquire) order each hand-over. Chips with an observer (an arbitrary
// closure) are never handed over.
unsafe impl Send for ChipPtr {}

/// What the owner and the workers share.
struct Shared {
    /// Chips waiting for a thread in the current phase.
    queue: Mutex<Vec<Job>>,
    /// Chips of the current phase not finished yet.
    running: AtomicUsize,
    /// Bumped once per phase; workers wait for it to change.
    epoch: AtomicU64,
    /// Set once when the pool is dropped.
    quit: AtomicBool,
    /// The first panic of a chip run on a worker, to be resumed on the owner.
    panic: Mutex<Option<Box<dyn Any + Send>>>,
    /// The owner's thread, woken when the last chip finishes.
    owner: Thread,
}

impl Shared {
    fn queue(&self) -> MutexGuard<'_, Vec<Job>> {
        // A panicking chip run leaves the queue itself intact.
        self.queue.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// Takes and runs chips until the queue is empty.
    fn drain(&self) {
        loop {
            let Some(job) = self.queue().pop() else {
                return;
            };
            // SAFETY: see `ChipPtr`: the owner holds this chip's borrow for the phase and
            // does not touch it until `running` reaches 0; only this thread got the job.
            let avr = unsafe { &mut *job.chip.0.as_ptr() };
            let run = panic::catch_unwind(AssertUnwindSafe(|| {
                let behind = job.target.saturating_sub(avr.cycles());
                if behind > 0 {
                    avr.run_cycles(behind);
                }
            }));
            if let Err(payload) = run {
                let mut first = self.panic.lock().unwrap_or_else(PoisonError::into_inner);
                first.get_or_insert(payload);
            }
            if self.running.fetch_sub(1, Ordering::AcqRel) == 1 {
                self.owner.unpark();
            }
        }
    }
}

/// Waits until `ready` holds: spins for [`SPIN`], yields until [`LOOK`], then blocks (woken
/// by `unpark`).
fn wait(ready: impl Fn() -> bool) {
    let start = Instant::now();
    while !ready() {
        let waited = start.elapsed();
        if waited < SPIN {
            for _ in 0..SPINS_PER_CHECK {
                std::hint::spin_loop();
            }
        } else if waited < LOOK {
            thread::yield_now();
        } else {
            thread::park();
        }
    }
}

/// A worker: waits for each new phase and helps drain its queue.
fn work(shared: &Shared) {
    let mut seen = shared.epoch.load(Ordering::Acquire);
    loop {
        wait(|| {
            shared.quit.load(Ordering::Acquire) || shared.epoch.load(Ordering::Acquire) != seen
        });
        if shared.quit.load(Ordering::Acquire) {
            return;
        }
        seen = shared.epoch.load(Ordering::Acquire);
        shared.drain();
    }
}

/// Persistent worker threads for the bus's slave phase.
pub(crate) struct Pool {
    shared: Arc<Shared>,
    workers: Vec<JoinHandle<()>>,
}

impl Pool {
    /// A pool whose owner is the calling thread, with `workers` extra threads (at least 1).
    /// Threads the system refuses are done without.
    pub fn new(workers: usize) -> Pool {
        let shared = Arc::new(Shared {
            queue: Mutex::new(Vec::new()),
            running: AtomicUsize::new(0),
            epoch: AtomicU64::new(0),
            quit: AtomicBool::new(false),
            panic: Mutex::new(None),
            owner: thread::current(),
        });
        let workers = (0..workers.max(1))
            .filter_map(|i| {
                let shared = Arc::clone(&shared);
                thread::Builder::new()
                    .name(format!("bus-worker-{i}"))
                    .spawn(move || work(&shared))
                    .ok()
            })
            .collect();
        Pool { shared, workers }
    }

    /// Runs each chip to `target` on the pool's threads and the caller's; returns when all
    /// have got there.
    ///
    /// # Safety
    /// Every pointer must come from a `&mut Avr` the caller holds exclusively until this
    /// returns, each chip must appear once, and none may have an observer set.
    pub unsafe fn run(&self, chips: &[NonNull<Avr>], target: u64) {
        if chips.is_empty() {
            return;
        }
        {
            let mut queue = self.shared.queue();
            queue.extend(chips.iter().map(|&chip| Job {
                chip: ChipPtr(chip),
                target,
            }));
            self.shared.running.store(chips.len(), Ordering::Release);
        }
        self.shared.epoch.fetch_add(1, Ordering::AcqRel);
        for worker in &self.workers {
            worker.thread().unpark();
        }
        self.shared.drain();
        wait(|| self.shared.running.load(Ordering::Acquire) == 0);
        let payload = self
            .shared
            .panic
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .take();
        if let Some(payload) = payload {
            // A chip's run panicked (on whichever thread): the caller sees it as if it had
            // run the chip itself.
            panic::resume_unwind(payload);
        }
    }

    /// Number of worker threads.
    pub fn workers(&self) -> usize {
        self.workers.len()
    }

    /// CPU time the worker threads have used so far (the owner's is not included).
    pub fn worker_cpu(&self) -> Duration {
        self.workers
            .iter()
            .map(|w| thread_cpu(w.as_pthread_t()))
            .sum()
    }
}

impl Drop for Pool {
    fn drop(&mut self) {
        self.shared.quit.store(true, Ordering::Release);
        for worker in self.workers.drain(..) {
            worker.thread().unpark();
            // A worker that panicked has nothing left to clean up.
            let _ = worker.join();
        }
    }
}

/// CPU time of one live thread of this process.
fn thread_cpu(thread: nix::libc::pthread_t) -> Duration {
    let mut clock: nix::libc::clockid_t = 0;
    // SAFETY: `thread` is a live thread of this process (its handle is not joined yet);
    // the call only writes `clock`.
    if unsafe { nix::libc::pthread_getcpuclockid(thread, &mut clock) } != 0 {
        return Duration::ZERO;
    }
    let mut ts = nix::libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: `ts` is a valid, writable timespec; the call only writes it.
    if unsafe { nix::libc::clock_gettime(clock, &mut ts) } != 0 {
        return Duration::ZERO;
    }
    Duration::new(
        u64::try_from(ts.tv_sec).unwrap_or(0),
        u32::try_from(ts.tv_nsec).unwrap_or(0),
    )
}
