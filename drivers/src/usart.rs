//! USART0 at 115200 8N1 with interrupt-driven receive and transmit.
//!
//! The ISRs call [`Usart0::on_receive`] and [`Usart0::on_data_register_empty`]; the queues
//! between them and the tasks belong to the firmware.

use avr_device::atmega328p::USART0;

/// A receive error the hardware flagged on a byte.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum RxError {
    /// Stop bit missing: wrong baud rate or line noise.
    Framing,
    /// A byte arrived before the previous one was read: a task held the CPU too long.
    Overrun,
}

/// USART0, the link to the PC (through the Uno's USB bridge).
pub struct Usart0 {
    usart: USART0,
}

impl Usart0 {
    /// Configures 115200 baud (double speed, UBRR 16: 2.1 % fast, as the Uno's own core does),
    /// 8N1, receiver and transmitter on, receive interrupt on. UCSR0A and UCSR0C are written
    /// before UBRR0 because the emulator applies baud settings when UBRR0 is written.
    pub fn new(usart: USART0) -> Self {
        usart.ucsr0a().write(|w| w.u2x0().set_bit());
        usart.ucsr0c().write(|w| w.ucsz0().chr8());
        // SAFETY: 16 is a valid baud divisor.
        usart.ubrr0().write(|w| unsafe { w.bits(16) });
        usart
            .ucsr0b()
            .write(|w| w.rxen0().set_bit().txen0().set_bit().rxcie0().set_bit());
        Usart0 { usart }
    }

    /// Reads the received byte (call from the receive interrupt).
    #[inline(always)]
    pub fn on_receive(&self) -> Result<u8, RxError> {
        let status = self.usart.ucsr0a().read();
        let byte = self.usart.udr0().read().bits();
        if status.fe0().bit_is_set() {
            Err(RxError::Framing)
        } else if status.dor0().bit_is_set() {
            Err(RxError::Overrun)
        } else {
            Ok(byte)
        }
    }

    /// Sends the next byte from `next` or, when there is none, stops the data-register-empty
    /// interrupt (call from that interrupt).
    #[inline(always)]
    pub fn on_data_register_empty(&self, next: Option<u8>) {
        match next {
            // SAFETY: UDR0 takes any byte.
            Some(b) => {
                self.usart.udr0().write(|w| unsafe { w.bits(b) });
            }
            None => self.set_tx_interrupt(false),
        }
    }

    /// Turns the data-register-empty interrupt on (bytes are queued) or off.
    #[inline(always)]
    pub fn set_tx_interrupt(&self, on: bool) {
        self.usart.ucsr0b().modify(|_, w| w.udrie0().bit(on));
    }

    /// Sends one byte, waiting for the data register (for the panic path and the banner).
    pub fn write_blocking(&self, byte: u8) {
        while self.usart.ucsr0a().read().udre0().bit_is_clear() {}
        // SAFETY: UDR0 takes any byte.
        self.usart.udr0().write(|w| unsafe { w.bits(byte) });
    }
}

impl ufmt::uWrite for Usart0 {
    type Error = core::convert::Infallible;

    fn write_str(&mut self, s: &str) -> Result<(), Self::Error> {
        for b in s.bytes() {
            self.write_blocking(b);
        }
        Ok(())
    }
}
