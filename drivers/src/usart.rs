//! USART0 at 115200 8N1 with interrupt-driven receive and transmit.
//!
//! The ISRs call [`Usart0::on_receive`] and [`Usart0::on_data_register_empty`]; the queues
//! between them and the tasks belong to the firmware. UCSR0B also holds the interrupt
//! enable bits, which belong to the executor: this driver writes it only through
//! `executor::hw`, and the data-register-empty interrupt is switched with the executor's
//! gate (`arm`/`disarm` of the gated task), never here.

use avr_device::atmega328p::USART0;
use executor::hw::DriverReg;

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
    /// 8N1, receiver and transmitter on. UCSR0A and UCSR0C are written before UBRR0 because
    /// the emulator applies baud settings when UBRR0 is written.
    pub fn new(usart: USART0) -> Self {
        usart.ucsr0a().write(|w| w.u2x0().set_bit());
        usart.ucsr0c().write(|w| w.ucsz0().chr8());
        // SAFETY: 16 is a valid baud divisor.
        usart.ubrr0().write(|w| unsafe { w.bits(16) });
        const RXEN0: u8 = 1 << 4;
        const TXEN0: u8 = 1 << 3;
        executor::hw::write(DriverReg::Ucsr0b, RXEN0 | TXEN0);
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

    /// Sends `byte` (call from the data-register-empty interrupt, which guarantees room).
    #[inline(always)]
    pub fn send(&self, byte: u8) {
        // SAFETY: UDR0 takes any byte.
        self.usart.udr0().write(|w| unsafe { w.bits(byte) });
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
