//! A OneWire bus master on D6 (PD6), bit-banged as an open drain: the pin's PORT bit is
//! 0, so setting its DDR bit pulls the line low and clearing it lets the external pull-up
//! (or a sensor) decide the level. The one exception is [`OneWire::write_byte_powered`],
//! whose last slot ends by driving the line high to feed a parasite-powered conversion
//! until the next reset.
//!
//! This is all the master's temperature sensors need: reset/presence, and read and write
//! time slots, one bit or one byte at a time. What to send, and what the bits mean, is
//! decided in `shared::master::temperature`.
//!
//! # Timing
//! Every delay is a cycle-counted busy loop at 16 MHz. Interrupts are off only where a
//! handler's few µs would break the slot: the short low pulse of a write-1 and a read
//! slot's low pulse up to its sample (at most ~13 µs each), and they are left as they
//! were afterwards. Elsewhere an interrupt only stretches a time that has room for it
//! (the master's handlers take a few µs each, ~25 µs if all of them run back to back):
//!
//! | Step | Line low | Then | Interrupts off |
//! |---|---|---|---|
//! | reset | 500 µs | release, watch for presence from 15 to ~300 µs, then ~230 µs | never |
//! | write 1 | 6 µs | release, 64 µs recovery | the 6 µs low |
//! | write 0 | 62 µs | release, 8 µs recovery | never |
//! | read | 2 µs | release, sample at ~12 µs, 55 µs recovery | low to sample (~13 µs) |
//! | powered last slot | 6 or 62 µs | driven high until the next reset | the 6 µs low |
//!
//! The datasheet windows, with the room each leaves: reset ≥ 480 µs (no upper bound
//! that matters); a presence pulse starts 15-60 µs after the release and lasts 60-240
//! µs, so the line is low for certain only from 60 to 75 µs: a single sample there
//! would miss a fast sensor whenever a handler ran first, so the line is read
//! continuously from 15 µs (before any sensor pulls) until well past 75 µs, and a
//! handler can only stretch that watch; write-0 low 60-120 µs (up to 58 µs late);
//! write-1 low 1-15 µs and a read sample within 15 µs of the falling edge (no room:
//! interrupts off); slots at least 60 µs apart (recovery may stretch freely); the
//! strong pull-up of a parasite-powered conversion within 10 µs of CONVERT T's last
//! slot (it follows the slot's low time directly, no release between).

use core::arch::asm;

/// I/O-space address of PIND.
const PIND: u8 = 0x09;
/// I/O-space address of DDRD.
const DDRD: u8 = 0x0a;
/// I/O-space address of PORTD.
const PORTD: u8 = 0x0b;
/// The line's bit in port D.
const BIT: u8 = 6;

/// The OneWire line on D6.
pub struct OneWire(());

impl OneWire {
    /// Releases the line (input, no pull-up, PORT bit 0) and returns the bus master.
    ///
    /// # Safety
    /// The caller must own PD6: nothing else may drive or configure that pin.
    pub unsafe fn take() -> Self {
        // SAFETY: cbi on PD6's own DDR and PORT bits; atomic, and no other bit changes.
        unsafe {
            asm!("cbi {ddr}, {bit}", ddr = const DDRD, bit = const BIT, options(nostack));
            asm!("cbi {port}, {bit}", port = const PORTD, bit = const BIT, options(nostack));
        }
        OneWire(())
    }

    /// Sends a reset pulse; returns whether any device answered with a presence pulse.
    /// Ends [`OneWire::power`].
    #[inline(never)]
    pub fn reset(&mut self) -> bool {
        // SAFETY: cbi on PD6's own PORT bit: back to open drain (a no-op unless powered),
        // so the DDR bit set next pulls the line low.
        unsafe { asm!("cbi {port}, {bit}", port = const PORTD, bit = const BIT, options(nostack)) }
        pull_low();
        delay_us::<500>();
        release();
        delay_us::<15>();
        // 120 reads ~2.4 µs apart: ~290 µs of watching, which a handler only lengthens.
        let mut present = false;
        for _ in 0..120u8 {
            present |= !line_high();
            delay_us::<2>();
        }
        delay_us::<230>();
        present
    }

    /// Writes one bit in one time slot.
    pub fn write_bit(&mut self, bit: bool) {
        self.slot(bit, false);
    }

    /// One write slot, which ends by releasing the line or, with `power`, by driving it
    /// high from low with no released moment between (the strong pull-up).
    #[inline(never)]
    fn slot(&mut self, bit: bool, power: bool) {
        if bit {
            avr_device::interrupt::free(|_| {
                pull_low();
                delay_us::<6>();
                end_slot(power);
            });
            delay_us::<64>();
        } else {
            pull_low();
            delay_us::<62>();
            end_slot(power);
            delay_us::<8>();
        }
    }

    /// Reads one bit in one time slot.
    #[inline(never)]
    pub fn read_bit(&mut self) -> bool {
        let bit = avr_device::interrupt::free(|_| {
            pull_low();
            delay_us::<2>();
            release();
            delay_us::<10>();
            line_high()
        });
        delay_us::<55>();
        bit
    }

    /// Writes a byte, least significant bit first.
    pub fn write_byte(&mut self, byte: u8) {
        self.write(byte, false);
    }

    /// Writes a byte like [`OneWire::write_byte`], but its last slot ends by driving the
    /// line high (a strong pull-up) instead of releasing it, so that parasite-powered
    /// sensors can carry out the command (CONVERT T) until the next [`OneWire::reset`].
    pub fn write_byte_powered(&mut self, byte: u8) {
        self.write(byte, true);
    }

    #[inline(never)]
    fn write(&mut self, mut byte: u8, power: bool) {
        for i in 0..8u8 {
            self.slot(byte & 1 != 0, power && i == 7);
            byte >>= 1;
        }
    }

    /// Reads a byte, least significant bit first.
    #[inline(never)]
    pub fn read_byte(&mut self) -> u8 {
        let mut byte = 0u8;
        for _ in 0..8u8 {
            byte >>= 1;
            if self.read_bit() {
                byte |= 0x80;
            }
        }
        byte
    }
}

/// Pulls the line low (PD6 an output at 0).
#[inline(always)]
fn pull_low() {
    // SAFETY: one atomic sbi on PD6's DDR bit, owned by the `OneWire` that calls this.
    unsafe { asm!("sbi {ddr}, {bit}", ddr = const DDRD, bit = const BIT, options(nostack)) }
}

/// Ends a write slot: releases the line, or with `power` drives it high from low (PORT
/// bit set while PD6 is an output), a strong pull-up with no released moment in between.
/// [`OneWire::reset`] clears the PORT bit again.
#[inline(always)]
fn end_slot(power: bool) {
    if power {
        // SAFETY: one atomic sbi on PD6's PORT bit, owned by the `OneWire` that calls this.
        unsafe { asm!("sbi {port}, {bit}", port = const PORTD, bit = const BIT, options(nostack)) }
    } else {
        release();
    }
}

/// Lets the line go (PD6 an input).
#[inline(always)]
fn release() {
    // SAFETY: one atomic cbi on PD6's DDR bit, owned by the `OneWire` that calls this.
    unsafe { asm!("cbi {ddr}, {bit}", ddr = const DDRD, bit = const BIT, options(nostack)) }
}

/// The line's level now.
#[inline(always)]
fn line_high() -> bool {
    let v: u8;
    // SAFETY: reads PIND; no side effects.
    unsafe { asm!("in {v}, {pin}", v = out(reg) v, pin = const PIND, options(nostack, nomem)) }
    v & (1 << BIT) != 0
}

/// Busy-waits `US` µs (1..=16383): a loop of `sbiw` (2 cycles) and a taken `brne` (2
/// cycles) runs four times per µs at 16 MHz.
#[inline(always)]
fn delay_us<const US: u16>() {
    let loops: u16 = US * (crate::F_CPU / 4_000_000) as u16;
    // SAFETY: only the counter register pair changes; no memory or stack is touched.
    unsafe {
        asm!(
            "1:",
            "sbiw {n}, 1",
            "brne 1b",
            n = inout(reg_iw) loops => _,
            options(nomem, nostack),
        )
    }
}
