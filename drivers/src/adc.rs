//! The ADC in single-conversion mode against AREF, prescaler 128 (125 kHz, about 104 µs
//! per conversion). The completion interrupt (ADIE) belongs to the executor; ADCSRA is
//! written only through `executor::hw`.

use avr_device::atmega328p::ADC;
use executor::hw::{self, DriverReg};

const ADEN: u8 = 1 << 7;
const ADSC: u8 = 1 << 6;
/// ADPS2..0 = 111: clock/128.
const PRESCALE_128: u8 = 0b111;

/// The ADC.
pub struct Adc {
    adc: ADC,
}

impl Adc {
    /// Enables the ADC (no conversion yet) and turns off the digital input buffers of
    /// ADC0 and ADC1 (ADC6/7 have none).
    pub fn new(adc: ADC) -> Adc {
        // SAFETY: DIDR0 bits only disable digital input buffers.
        adc.didr0().write(|w| unsafe { w.bits(0b0000_0011) });
        hw::write(DriverReg::Adcsra, ADEN | PRESCALE_128);
        Adc { adc }
    }

    /// Selects `channel` (0..=7, reference AREF) and starts a conversion.
    #[inline]
    pub fn start(&mut self, channel: u8) {
        // SAFETY: REFS = 00 and ADLAR = 0 with a channel number 0..=7 is a valid ADMUX.
        self.adc
            .admux()
            .write(|w| unsafe { w.bits(channel & 0x07) });
        hw::write(DriverReg::Adcsra, ADEN | ADSC | PRESCALE_128);
    }

    /// The result of the finished conversion, 0..=1023.
    #[inline]
    pub fn result(&self) -> u16 {
        self.adc.adc().read().bits()
    }
}
