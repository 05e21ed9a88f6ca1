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
}

impl Default for Config {
    fn default() -> Config {
        Config {
            firmware_dir: None,
            quantum_us: DEFAULT_QUANTUM_US,
            slice_us: DEFAULT_SLICE_US,
            answer_timeout_us: DEFAULT_ANSWER_TIMEOUT_US,
        }
    }
}

/// Default bus quantum (see `docs/benchmarks.md` for how it was chosen).
pub const DEFAULT_QUANTUM_US: u64 = 10;
/// Default bound on a slave's answer to one bus event: 5 ms.
///
/// The emulated master does not wait while a slave chip answers (simavr completes its TWI
/// byte inside the IRQ that the bus serves by running the slave), so this bound is only
/// where a stuck slave starts to count as absent; it costs no emulated time. Earlier slave
/// images held their TWI interrupt off for over a millisecond after a burst of register
/// writes (an emergency stop's parameter blocks), which the bus's own 1-ms default called
/// a NACK now and then; the bound keeps a margin for such work.
pub const DEFAULT_ANSWER_TIMEOUT_US: u64 = 5_000;
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
