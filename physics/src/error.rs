//! The physics crate's error type.

/// What can go wrong when building board models or closing the loop around chips.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum PhysicsError {
    /// A wheel number outside 1..=6 was asked for.
    #[error("wheel {0} does not exist: the rover has wheels 1 to 6")]
    NoSuchWheel(u8),
    /// A wheel pair outside 0..=2 was asked for.
    #[error("wheel pair {0} does not exist: pairs are 0, 1 and 2")]
    NoSuchPair(u8),
    /// A controller number that is not a slave board (1..=9) was asked for.
    #[error("controller {0} is not a slave board: slaves are 1 to 9")]
    NoSuchController(u8),
    /// A model is attached to a chip index the emulator does not have.
    #[error("chip {0} is not in the emulator: attach models to the indices the bus returned")]
    NoSuchChip(usize),
}
