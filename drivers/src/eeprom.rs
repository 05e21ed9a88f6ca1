//! EEPROM byte access (the slave's I2C address lives in byte 0).

use avr_device::atmega328p::EEPROM;

/// The 1 KB data EEPROM.
pub struct Eeprom {
    ee: EEPROM,
}

/// Size of the EEPROM in bytes.
pub const SIZE: u16 = 1024;

impl Eeprom {
    /// Takes the EEPROM peripheral.
    pub fn new(ee: EEPROM) -> Self {
        Eeprom { ee }
    }

    /// Reads one byte; addresses wrap at [`SIZE`].
    pub fn read(&self, addr: u16) -> u8 {
        while self.ee.eecr().read().eepe().bit_is_set() {}
        // SAFETY: any address below 1024 is valid; EEAR ignores higher bits.
        self.ee.eear().write(|w| unsafe { w.bits(addr % SIZE) });
        self.ee.eecr().write(|w| w.eere().set_bit());
        self.ee.eedr().read().bits()
    }

    /// Writes one byte (about 3.4 ms; blocks until the previous write is done).
    pub fn write(&mut self, addr: u16, value: u8) {
        while self.ee.eecr().read().eepe().bit_is_set() {}
        // SAFETY: as in `read`; EEDR takes any byte.
        self.ee.eear().write(|w| unsafe { w.bits(addr % SIZE) });
        self.ee.eedr().write(|w| unsafe { w.bits(value) });
        avr_device::interrupt::free(|_| {
            // EEMPE then EEPE within four cycles, so interrupts stay off between them.
            self.ee.eecr().write(|w| w.eempe().set_bit());
            self.ee
                .eecr()
                .write(|w| w.eempe().set_bit().eepe().set_bit());
        });
    }
}
