//! Fixture: prints `halt\r\n`, then executes SLEEP with interrupts disabled, which
//! stops the CPU for good. Used by the harness's halted-CPU test.
#![no_std]
#![no_main]

use firmware_examples::uart::{put_str, uart_init};

#[avr_device::entry]
fn main() -> ! {
    let dp = firmware_examples::peripherals();
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

firmware_examples::spin_on_panic!();
