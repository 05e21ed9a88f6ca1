//! Fixture: prints `halt\r\n`, then executes SLEEP with interrupts disabled, which
//! stops the CPU for good. Used by the harness's halted-CPU test.
#![no_std]
#![no_main]

#[avr_device::entry]
fn main() -> ! {
    let dp = firmware_examples::peripherals();
    let uart = firmware_examples::uart::start(dp.USART0, b"halt\r\n");
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
