//! Test firmware: a broken I2C slave that takes its address and then never releases the bus.
//!
//! Demonstrates the bus's bounded wait: the TWI listens at the 7-bit address in EEPROM byte 0
//! (0x08 if that byte is not a usable address) with TWEA set, so a master's START is taken, but
//! the firmware never clears TWINT afterwards — as firmware stuck in a loop would.

#![no_std]
#![no_main]

use avr_device::atmega328p::{Peripherals, EEPROM};

/// Address used when EEPROM byte 0 is not a usable 7-bit address.
const DEFAULT_ADDR: u8 = 0x08;

/// Reads EEPROM byte 0 (the bus address chosen by the test).
fn eeprom_byte0(eeprom: &EEPROM) -> u8 {
    while eeprom.eecr().read().eepe().bit_is_set() {}
    eeprom.eear().write(|w| w.set(0));
    eeprom.eecr().write(|w| w.eere().set_bit());
    eeprom.eedr().read().bits()
}

#[avr_device::entry]
fn main() -> ! {
    if let Some(dp) = Peripherals::take() {
        let stored = eeprom_byte0(&dp.EEPROM);
        let addr = if (1..0x78).contains(&stored) {
            stored
        } else {
            DEFAULT_ADDR
        };
        dp.TWI.twar().write(|w| w.twa().set(addr));
        dp.TWI.twcr().write(|w| w.twea().set_bit().twen().set_bit());
    }
    #[allow(clippy::empty_loop)]
    loop {}
}

firmware_examples::spin_on_panic!();
