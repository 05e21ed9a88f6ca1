//! Fixture: prints `halt\r\n`, then executes SLEEP with interrupts disabled, which
//! stops the CPU for good. Used by the harness's halted-CPU test.
#![no_std]
#![no_main]

use avr_device::atmega328p::{Peripherals, USART0};

fn uart_init(uart: &USART0) {
    uart.ucsr0a().write(|w| w.u2x0().set_bit());
    uart.ucsr0c().write(|w| w.ucsz0().chr8());
    uart.ucsr0b()
        .write(|w| w.rxen0().set_bit().txen0().set_bit());
    uart.ubrr0().write(|w| w.set(16));
}

fn put(uart: &USART0, byte: u8) {
    while uart.ucsr0a().read().udre0().bit_is_clear() {}
    uart.udr0().write(|w| w.set(byte));
}

fn put_str(uart: &USART0, s: &[u8]) {
    for &b in s {
        put(uart, b);
    }
}

#[avr_device::entry]
fn main() -> ! {
    let Some(dp) = Peripherals::take() else {
        loop {
            avr_device::asm::nop();
        }
    };
    let uart = dp.USART0;
    uart_init(&uart);
    put_str(&uart, b"halt\r\n");
    // Let the last byte leave before stopping.
    while uart.ucsr0a().read().txc0().bit_is_clear() {}
    avr_device::interrupt::disable();
    // SAFETY: SE with SM = 000 (idle) is a valid SMCR value.
    dp.CPU.smcr().write(|w| unsafe { w.bits(1) });
    loop {
        avr_device::asm::sleep();
    }
}

#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    loop {
        avr_device::asm::nop();
    }
}
