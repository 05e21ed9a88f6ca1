//! How the twin is built: where its images are, and the emulator's time steps.

use std::path::PathBuf;

use harness::firmware_path;

/// How the twin is built.
#[derive(Debug, Clone)]
pub struct Config {
    /// Directory holding `master.elf`, `slave-drive.elf` and `slave-lift.elf`
    /// (default: the workspace's `target/firmware`).
    pub firmware_dir: Option<PathBuf>,
    /// The bus's lock-step quantum, µs of emulated time.
    pub quantum_us: u64,
    /// The physics slice, µs of emulated time between input reads and ADC updates.
    pub slice_us: u64,
    /// How long a slave chip may take to handle one bus event before the bus gives up on
    /// it (a NACK for the master), µs of the slave's time.
    pub answer_timeout_us: u64,
    /// Threads the chips run on, the caller's included: the slave chips of each bus quantum
    /// run side by side on them (the result is the same for any count). 1 (the default)
    /// runs everything on the caller's thread; [`default_threads`] suits a program that
    /// has the machine to itself.
    pub threads: usize,
}

impl Default for Config {
    fn default() -> Config {
        Config {
            firmware_dir: None,
            quantum_us: DEFAULT_QUANTUM_US,
            slice_us: DEFAULT_SLICE_US,
            answer_timeout_us: DEFAULT_ANSWER_TIMEOUT_US,
            threads: 1,
        }
    }
}

/// Default bus quantum: the physics slice, 50 µs.
///
/// Within a quantum a slave chip lags the master by at most the quantum when the master
/// addresses it. The twin tests' timings move by at most the quantum from those at 10 µs
/// (the bus's own default), while the slave chips running side by side
/// ([`Config::threads`]) need two hand-overs between threads per quantum, which at 10 µs
/// cost about as much as they save.
pub const DEFAULT_QUANTUM_US: u64 = 50;
/// Default bound on a slave's answer to one bus event: 5 ms.
///
/// The emulated master does not wait while a slave chip answers (simavr completes its TWI
/// byte inside the IRQ that the bus serves by running the slave), so this bound is only
/// where a stuck slave starts to count as absent; it costs no emulated time. Earlier slave
/// images held their TWI interrupt off for over a millisecond after a burst of register
/// writes (an emergency stop's parameter blocks), which the bus's own 1-ms default called
/// a NACK now and then; the bound keeps a margin for such work.
pub const DEFAULT_ANSWER_TIMEOUT_US: u64 = 5_000;
/// Most threads [`default_threads`] picks: the master runs alone in each quantum and nine
/// slaves share the rest, so more threads than this gain little.
pub const MAX_DEFAULT_THREADS: usize = 4;

/// The machine's available parallelism, at most [`MAX_DEFAULT_THREADS`] (1 if unknown).
pub fn default_threads() -> usize {
    std::thread::available_parallelism()
        .map_or(1, std::num::NonZeroUsize::get)
        .min(MAX_DEFAULT_THREADS)
}

/// Default physics slice.
pub const DEFAULT_SLICE_US: u64 = physics::emulator::DEFAULT_SLICE_US;

impl Config {
    /// The path of image `name` under this configuration.
    pub fn image(&self, name: &str) -> PathBuf {
        match &self.firmware_dir {
            Some(dir) => dir.join(format!("{name}.elf")),
            None => firmware_path(name),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_run_on_one_thread_and_the_slice_quantum() {
        let config = Config::default();
        assert_eq!(config.threads, 1);
        assert_eq!(config.quantum_us, 50);
        assert_eq!(config.quantum_us, config.slice_us);
        assert!((1..=MAX_DEFAULT_THREADS).contains(&default_threads()));
    }
}
