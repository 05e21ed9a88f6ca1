//! Pin-change mask of port D (PCMSK2). The group enable (PCICR) belongs to the executor,
//! which sets it for a task bound to PCINT2; this driver chooses which pins fire it.

use avr_device::atmega328p::EXINT;

/// The pin-change mask of port D.
pub struct PortDChanges {
    _exint: EXINT,
}

impl PortDChanges {
    /// Lets the pins of `mask` (bit n = PDn) raise PCINT2; the others are ignored.
    pub fn new(exint: EXINT, mask: u8) -> PortDChanges {
        // SAFETY: PCMSK2 takes any mask; PCICR and EIMSK are not touched.
        exint.pcmsk2().write(|w| unsafe { w.bits(mask) });
        PortDChanges { _exint: exint }
    }
}
