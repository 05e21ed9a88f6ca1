//! The emulated CPU's run state.

use simavr_ffi as ffi;

/// What the emulated CPU is doing, as the emulator reports it after each run step.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CpuState {
    /// Not yet initialised.
    Limbo,
    /// Stopped by the emulator (e.g. waiting for a debugger).
    Stopped,
    /// Executing instructions.
    Running,
    /// In SLEEP, waiting for an interrupt.
    Sleeping,
    /// Single-stepping for a debugger.
    Step,
    /// A debugger single step finished.
    StepDone,
    /// The firmware stopped for good: SLEEP with interrupts disabled.
    Done,
    /// The firmware crashed (bad opcode, execution past flash, ...).
    Crashed,
}

impl CpuState {
    /// Maps simavr's numeric state.
    pub(crate) fn from_raw(raw: i32) -> CpuState {
        match u32::try_from(raw).unwrap_or(u32::MAX) {
            ffi::cpu_Limbo => CpuState::Limbo,
            ffi::cpu_Stopped => CpuState::Stopped,
            ffi::cpu_Running => CpuState::Running,
            ffi::cpu_Sleeping => CpuState::Sleeping,
            ffi::cpu_Step => CpuState::Step,
            ffi::cpu_StepDone => CpuState::StepDone,
            ffi::cpu_Done => CpuState::Done,
            _ => CpuState::Crashed,
        }
    }

    /// True when the CPU will never run again by itself (Stopped, Done or Crashed).
    pub fn is_halted(self) -> bool {
        matches!(
            self,
            CpuState::Stopped | CpuState::Done | CpuState::Crashed | CpuState::Limbo
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn maps_raw_states() {
        assert_eq!(CpuState::from_raw(2), CpuState::Running);
        assert_eq!(CpuState::from_raw(3), CpuState::Sleeping);
        assert_eq!(CpuState::from_raw(6), CpuState::Done);
        assert_eq!(CpuState::from_raw(7), CpuState::Crashed);
        assert_eq!(CpuState::from_raw(-1), CpuState::Crashed);
        assert!(CpuState::Done.is_halted());
        assert!(!CpuState::Sleeping.is_halted());
    }
}
