//! RTIC's task model on the ATmega328P, for both Blodwen firmwares (master and slave).
//!
//! RTIC itself cannot run here (its back-ends are Cortex-M and RISC-V only), so this crate
//! gives the rover the same model on AVR:
//!
//! - **Hardware tasks** bound to interrupt vectors, each with a static priority. The AVR
//!   has one global interrupt flag and no priority hardware, so preemption is done in
//!   software: on entry a task clears the enable bits of the sources at its own and lower
//!   priorities, then sets the global flag, so only higher tasks can preempt it (source
//!   masking, as RTIC does on cores without BASEPRI). Tasks at the top priority simply run
//!   with the flag clear.
//! - **Shared resources** with a ceiling computed at compile time from the tasks that use
//!   them ([`analysis`]). `lock` raises the system to the ceiling: it masks the sources at
//!   or below it, or clears the global flag for the top ceiling. A resource whose users
//!   all run at one priority needs no lock and dereferences directly.
//! - **Local resources** owned by one task and handed to it as `&mut`: task-local state,
//!   either returned by `init` or declared with a constant value in the task's attribute
//!   (`const_local`), which puts it straight into static memory.
//! - **Idle** at priority 0, which sleeps the CPU when there is nothing to do.
//! - **Gated sources** ([`gate`]) whose interrupts drivers switch at run time, such as
//!   USART_UDRE, without fighting the masking.
//!
//! An application is declared in one place with [`app!`]: resources, then tasks with
//! their vectors, priorities and the resources each uses. The macro generates the vectors,
//! the contexts and `main`, and checks the declaration at compile time.
//!
//! The AVR core (masking, dispatch, locks, sleep, the driver register helpers in `hw`) is
//! compiled only for the chip; the analysis and the register arithmetic ([`bits`]) build
//! and are tested on the host. `docs/executor.md` explains the design, why it cannot
//! deadlock, and the cycle costs measured in the emulator.
#![cfg_attr(not(test), no_std)]
#![cfg_attr(target_arch = "avr", feature(asm_experimental_arch))]

pub mod analysis;
pub mod bits;
pub mod gate;
mod macros;
pub mod plan;
mod resource;
pub mod source;

#[cfg(target_arch = "avr")]
pub mod hw;

#[cfg(target_arch = "avr")]
#[path = "avr/mod.rs"]
mod port;

#[cfg(not(target_arch = "avr"))]
#[path = "host.rs"]
mod port;

pub use analysis::{LevelMasks, RegBits, MAX_PRIORITY};
pub use port::{Device, Sleep};
pub use resource::{LocalCell, ResourceCell, Shared};
pub use source::{Reg, Source};

#[cfg(target_arch = "avr")]
pub use port::freeze;

/// The constants [`app!`] computes for an application, which the core specialises on.
pub trait App: 'static {
    /// The highest task priority. Tasks at this level run with interrupts disabled, and
    /// locks at this ceiling disable them.
    const TOP: u8;
    /// The enable bits each level masks.
    const MASKS: LevelMasks;
    /// The enable bits of gated sources.
    const GATED: RegBits;
    /// The enable bits set at start (ungated task sources).
    const START: RegBits;
    /// Per register: frames write the saved value back verbatim.
    const EXACT: [bool; source::REG_COUNT];
}

/// Items the generated code uses; not part of the API.
#[doc(hidden)]
pub mod __private {
    pub use crate::port::take_device;
    #[cfg(target_arch = "avr")]
    pub use crate::port::{default_idle, dispatch, start};
}
