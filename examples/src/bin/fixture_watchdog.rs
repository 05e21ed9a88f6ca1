//! Fixture: counts its boots in EEPROM byte 0, prints `boot=<n> wdrf=<0|1>\r\n`
//! (MCUSR's watchdog-reset flag), then arms the watchdog in system-reset mode
//! (16 ms) and never feeds it. Used by the harness's watchdog-reset test.
#![no_std]
#![no_main]

use firmware_examples::eeprom::{ee_read, ee_write};
use firmware_examples::uart::{put, put_dec, put_str, uart_init};

#[avr_device::entry]
fn main() -> ! {
    let dp = firmware_examples::peripherals();
    let mcusr = dp.CPU.mcusr().read().bits();
    // After a watchdog reset the watchdog stays on: clear WDRF, then turn it off
    // with the timed WDCE sequence.
    // SAFETY: 0 is a valid MCUSR value; WDCE|WDE then 0 is the documented sequence.
    dp.CPU.mcusr().write(|w| unsafe { w.bits(0) });
    dp.WDT
        .wdtcsr()
        .write(|w| w.wdce().set_bit().wde().set_bit());
    dp.WDT.wdtcsr().write(|w| unsafe { w.bits(0) });
    let uart = dp.USART0;
    uart_init(&uart);
    let boots = ee_read(&dp.EEPROM, 0).wrapping_add(1);
    ee_write(&dp.EEPROM, 0, boots);
    put_str(&uart, b"boot=");
    put_dec(&uart, u16::from(boots));
    put_str(&uart, b" wdrf=");
    put(&uart, if mcusr & (1 << 3) != 0 { b'1' } else { b'0' });
    put_str(&uart, b"\r\n");
    // System-reset mode, WDP = 0: about 16 ms.
    dp.WDT
        .wdtcsr()
        .write(|w| w.wdce().set_bit().wde().set_bit());
    dp.WDT.wdtcsr().write(|w| w.wde().set_bit());
    loop {
        avr_device::asm::nop();
    }
}

firmware_examples::spin_on_panic!();
