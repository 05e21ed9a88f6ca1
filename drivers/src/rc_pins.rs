//! The RC receiver's three channel inputs on D2, D3 and D4 (PD2..PD4), read together.
//! Which of them raise the pin-change interrupt is set with `pcint::PortDChanges`.

use core::arch::asm;

/// I/O-space address of PIND.
const PIND: u8 = 0x09;
/// I/O-space address of DDRD.
const DDRD: u8 = 0x0a;
/// I/O-space address of PORTD.
const PORTD: u8 = 0x0b;

/// PD2..PD4 as inputs without pull-ups (the receiver drives them).
pub struct RcPins(());

impl RcPins {
    /// Makes PD2, PD3 and PD4 inputs with their pull-ups off.
    ///
    /// # Safety
    /// The caller must own PD2..PD4: nothing else may drive or configure those pins.
    pub unsafe fn take() -> Self {
        // SAFETY: cbi on the three pins' own DDR and PORT bits; each is atomic and
        // touches no other bit.
        unsafe {
            asm!(
                "cbi {ddr}, 2", "cbi {ddr}, 3", "cbi {ddr}, 4",
                "cbi {port}, 2", "cbi {port}, 3", "cbi {port}, 4",
                ddr = const DDRD, port = const PORTD, options(nostack)
            );
        }
        RcPins(())
    }

    /// The pins' levels from one read of PIND: bit 0 = D2 (channel 0), bit 1 = D3,
    /// bit 2 = D4.
    #[inline(always)]
    pub fn levels(&self) -> u8 {
        let v: u8;
        // SAFETY: reads PIND; no side effects.
        unsafe { asm!("in {v}, {pin}", v = out(reg) v, pin = const PIND, options(nostack, nomem)) }
        (v >> 2) & 0b111
    }
}
