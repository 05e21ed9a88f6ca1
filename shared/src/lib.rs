//! Definitions shared by every part of the Blodwen rover control stack.
//!
//! This crate is the one home of the register tables (generated from
//! `registers.def` by `regdef`), the value mapping between engineering units and raw
//! register values, the PC-master serial codec (the master's frame parser and the
//! host's encoders) and the master's read-set store. The master and slave firmware,
//! the host tool `hostctl` and the emulator tests all build on it, so there is no
//! second copy of any of these anywhere.
//!
//! It is `no_std` without allocation and builds both on the host and for the AVR
//! boards; everything in it is tested on the host.

#![cfg_attr(not(test), no_std)]
#![cfg_attr(target_arch = "avr", feature(asm_experimental_arch))]
// Denied everywhere but in three AVR-only modules, each explaining why: `progmem` (flash
// reads), `slave::product` and `slave::divide` (arithmetic in assembly). Their host builds
// are plain Rust.
#![deny(unsafe_code)]

pub mod exception;
pub mod mapping;
pub mod master;
pub mod pid;
pub mod progmem;
pub mod protocol;
pub mod regs;
pub mod slave;
#[cfg(test)]
mod test_random;
