//! The harness's error type.

use std::path::PathBuf;

use crate::CpuState;

/// Everything that can go wrong while loading or driving an emulated chip.
#[derive(Debug, thiserror::Error)]
pub enum HarnessError {
    /// The firmware image does not exist (usually: the firmware was not built yet).
    #[error("firmware image {path} not found: run scripts/firmware.sh to build it")]
    FirmwareMissing {
        /// The path that was tried.
        path: PathBuf,
    },
    /// The firmware image exists but could not be read.
    #[error("cannot read firmware image {path}: {source}; check its permissions")]
    Read {
        /// The path that was read.
        path: PathBuf,
        /// The operating system's error.
        source: std::io::Error,
    },
    /// The file is not an AVR ELF image the harness can load.
    #[error(
        "{path} is not a loadable AVR ELF image ({reason}); rebuild it with scripts/firmware.sh"
    )]
    BadElf {
        /// The path of the image.
        path: PathBuf,
        /// What is wrong with it.
        reason: String,
    },
    /// The image does not fit in the ATmega328P's 32 KiB of flash.
    #[error(
        "{path} holds {size} bytes of flash, more than the ATmega328P's 32768; shrink the firmware"
    )]
    TooLarge {
        /// The path of the image.
        path: PathBuf,
        /// Flash bytes in the image.
        size: usize,
    },
    /// The emulator could not create or initialise an ATmega328P core.
    #[error("the emulator could not create an ATmega328P core; the simavr-ffi build is broken, rebuild it with `cargo clean -p simavr-ffi`")]
    CoreUnavailable,
    /// A wait ran out of emulated time before its condition came true.
    #[error("timed out after {waited_us} µs of emulated time waiting for {what}; got {} UART bytes so far: {got:?}", got.len())]
    Timeout {
        /// What was awaited.
        what: String,
        /// Emulated microseconds spent waiting.
        waited_us: u64,
        /// UART bytes received (and left unread) while waiting.
        got: Vec<u8>,
    },
    /// The CPU stopped (crashed, or slept with interrupts off) during a wait.
    #[error("the emulated CPU stopped ({state:?}) at {at_us} µs while waiting for {what}; the firmware crashed or executed SLEEP with interrupts off")]
    Halted {
        /// The state the CPU ended in.
        state: CpuState,
        /// What was awaited.
        what: String,
        /// Emulated time when it stopped, in µs since load.
        at_us: u64,
    },
    /// A pseudo-terminal could not be created.
    #[error("cannot open a pseudo-terminal: {0}; check that /dev/ptmx is available")]
    Pty(#[from] nix::Error),
}
