//! Helpers shared by the emulator tests.
pub mod stack_bound;
