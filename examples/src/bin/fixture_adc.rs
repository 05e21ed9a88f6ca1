//! Fixture: reads ADC0..ADC7 against AVCC (prescaler 128) and prints one line
//! per scan on UART0 (115200): `A 511 0 ... 1023\r\n`. Used by the harness's ADC test.
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

/// Prints `n` in decimal without leading zeros.
fn put_dec(uart: &USART0, n: u16) {
    let mut digits = [0u8; 5];
    let mut len = 0;
    let mut v = n;
    loop {
        digits[len] = b'0' + (v % 10) as u8;
        len += 1;
        v /= 10;
        if v == 0 {
            break;
        }
    }
    while len > 0 {
        len -= 1;
        put(uart, digits[len]);
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
    let adc = dp.ADC;
    adc.adcsra()
        .write(|w| w.aden().set_bit().adps().prescaler_128());
    loop {
        put(&uart, b'A');
        for ch in 0u8..8 {
            // REFS = 01: AVCC reference; MUX = channel.
            // SAFETY: any REFS/MUX combination is a valid ADMUX value.
            adc.admux().write(|w| unsafe { w.bits(0x40 | ch) });
            adc.adcsra().modify(|_, w| w.adsc().set_bit());
            while adc.adcsra().read().adsc().bit_is_set() {}
            let value = adc.adc().read().bits();
            put(&uart, b' ');
            put_dec(&uart, value);
        }
        put(&uart, b'\r');
        put(&uart, b'\n');
    }
}

#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    loop {
        avr_device::asm::nop();
    }
}
