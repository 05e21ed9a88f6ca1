//! Fixture: UART0 at 115200 8N1 (U2X0, UBRR0 = 16) prints a banner, then echoes
//! every received byte back unchanged. Used by the harness's UART tests.
#![no_std]
#![no_main]

use firmware_examples::uart::put;

/// Sends one byte, waiting for the transmit buffer to be free.

#[avr_device::entry]
fn main() -> ! {
    let dp = firmware_examples::peripherals();
    let uart = dp.USART0;
    uart.ucsr0a().write(|w| w.u2x0().set_bit());
    uart.ucsr0c().write(|w| w.ucsz0().chr8());
    uart.ucsr0b()
        .write(|w| w.rxen0().set_bit().txen0().set_bit());
    // The baud rate is written last: the emulator applies it on this write.
    uart.ubrr0().write(|w| w.set(16));
    for &b in b"echo ready\r\n" {
        put(&uart, b);
    }
    loop {
        while uart.ucsr0a().read().rxc0().bit_is_clear() {}
        let byte = uart.udr0().read().bits();
        put(&uart, byte);
    }
}

firmware_examples::spin_on_panic!();
