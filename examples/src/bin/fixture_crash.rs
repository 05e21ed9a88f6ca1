//! Fixture: prints `crash\r\n`, then jumps past the end of flash, which the
//! emulator reports as a crash. Used by the harness's crashed-CPU test.
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
    put_str(&uart, b"crash\r\n");
    while uart.ucsr0a().read().txc0().bit_is_clear() {}
    // Word address 0x4000 is byte address 0x8000, one past the 32 KiB flash.
    // SAFETY: deliberately unsound: this image exists only to crash the emulated
    // CPU, and is never flashed to a board.
    let past_flash: extern "C" fn() = unsafe { core::mem::transmute(0x4000usize) };
    past_flash();
    loop {
        avr_device::asm::nop();
    }
}

#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    loop {
        avr_device::asm::nop();
    }
}
