//! Fixture: reads ADC0..ADC7 against AVCC (prescaler 128) and prints one line
//! per scan on UART0 (115200): `A 511 0 ... 1023\r\n`. Used by the harness's ADC test.
#![no_std]
#![no_main]

use firmware_examples::uart::{put, put_dec, uart_init};

#[avr_device::entry]
fn main() -> ! {
    let dp = firmware_examples::peripherals();
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

firmware_examples::spin_on_panic!();
