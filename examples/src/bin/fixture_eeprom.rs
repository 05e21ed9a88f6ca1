//! Fixture: prints EEPROM byte 0 as `E0=<n>\r\n`, writes byte 0 + 1 into EEPROM
//! byte 1, then prints `W\r\n`. Used by the harness's EEPROM tests.
#![no_std]
#![no_main]

use avr_device::atmega328p::{Peripherals, EEPROM, USART0};

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

/// Reads one EEPROM byte.
fn ee_read(ee: &EEPROM, addr: u16) -> u8 {
    while ee.eecr().read().eepe().bit_is_set() {}
    // SAFETY: addresses below 1024 are valid EEAR values.
    ee.eear().write(|w| unsafe { w.bits(addr) });
    ee.eecr().write(|w| w.eere().set_bit());
    ee.eedr().read().bits()
}

/// Writes one EEPROM byte (erase and write), interrupts assumed off.
fn ee_write(ee: &EEPROM, addr: u16, value: u8) {
    while ee.eecr().read().eepe().bit_is_set() {}
    // SAFETY: addresses below 1024 are valid EEAR values; any EEDR value is valid.
    ee.eear().write(|w| unsafe { w.bits(addr) });
    ee.eedr().write(|w| unsafe { w.bits(value) });
    ee.eecr().write(|w| w.eempe().set_bit());
    ee.eecr().write(|w| w.eempe().set_bit().eepe().set_bit());
    while ee.eecr().read().eepe().bit_is_set() {}
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
    let b0 = ee_read(&dp.EEPROM, 0);
    put_str(&uart, b"E0=");
    put_dec(&uart, u16::from(b0));
    put_str(&uart, b"\r\n");
    ee_write(&dp.EEPROM, 1, b0.wrapping_add(1));
    put_str(&uart, b"W\r\n");
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
