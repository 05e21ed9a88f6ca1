//! Error types: one for the emulated chip's memories, one for running the simulator.

use std::path::PathBuf;

/// A memory access the chip cannot perform.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum MemError {
    /// The access runs past the end of the memory.
    #[error("{memory}: {len} bytes at 0x{addr:04x} run past the end ({size} bytes)")]
    OutOfRange {
        /// Memory name ("flash" or "eeprom").
        memory: &'static str,
        /// First byte address of the access.
        addr: usize,
        /// Length of the access in bytes.
        len: usize,
        /// Size of the memory in bytes.
        size: usize,
    },
    /// The access touches the boot section, which the bootloader's lock bits protect.
    #[error("flash: {len} bytes at 0x{addr:04x} reach the protected boot section at 0x{boot:04x}")]
    BootSection {
        /// First byte address of the access.
        addr: usize,
        /// Length of the access in bytes.
        len: usize,
        /// First byte address of the boot section.
        boot: usize,
    },
    /// The command needs programming mode, which has not been entered.
    #[error("not in programming mode (send Cmnd_STK_ENTER_PROGMODE first)")]
    NotInProgMode,
    /// A page command named a memory type other than 'F' or 'E'.
    #[error("unknown memory type 0x{0:02x} (expected 'F' or 'E')")]
    MemoryType(u8),
}

/// Why the simulator could not run or save its images.
#[derive(Debug, thiserror::Error)]
pub enum SimError {
    /// Opening or configuring the pseudo-terminal failed.
    #[error("cannot set up the pseudo-terminal: {0}")]
    Pty(#[source] nix::Error),
    /// Reading from or writing to the pseudo-terminal failed.
    #[error("pseudo-terminal I/O failed: {0}")]
    PtyIo(#[source] std::io::Error),
    /// Installing the SIGTERM/SIGINT handler failed.
    #[error("cannot install the signal handler: {0}")]
    Signal(#[source] nix::Error),
    /// Writing an output file failed; check that the `--out` directory is writable.
    #[error("cannot write {path}: {source}")]
    Output {
        /// The file that could not be written.
        path: PathBuf,
        /// The underlying error.
        #[source]
        source: std::io::Error,
    },
}
