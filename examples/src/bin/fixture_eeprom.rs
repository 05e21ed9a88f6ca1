//! Fixture: prints EEPROM byte 0 as `E0=<n>\r\n`, writes byte 0 + 1 into EEPROM
//! byte 1, then prints `W\r\n`. Used by the harness's EEPROM tests.
#![no_std]
#![no_main]

use firmware_examples::eeprom::{ee_read, ee_write};
use firmware_examples::uart::{put_dec, put_str, uart_init};

#[avr_device::entry]
fn main() -> ! {
    let dp = firmware_examples::peripherals();
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

firmware_examples::spin_on_panic!();
