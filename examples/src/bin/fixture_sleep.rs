//! Fixture: Timer1 in CTC mode interrupts every 10 ms; the main loop executes
//! SLEEP (idle) between interrupts and prints `t=<ticks>\r\n` every 100 ticks
//! (once per second). Used by the harness's sleep fast-forward test.
#![no_std]
#![no_main]
#![feature(abi_avr_interrupt)]

use core::cell::Cell;

use avr_device::atmega328p::{Peripherals, USART0};
use avr_device::interrupt::Mutex;

/// Timer ticks since boot, shared with the compare-match interrupt. Unmangled so
/// tests can find it by name in the ELF symbol table.
#[no_mangle]
static TICKS: Mutex<Cell<u16>> = Mutex::new(Cell::new(0));

#[avr_device::interrupt(atmega328p)]
fn TIMER1_COMPA() {
    avr_device::interrupt::free(|cs| {
        let t = TICKS.borrow(cs);
        t.set(t.get().wrapping_add(1));
    });
}

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

#[avr_device::entry]
fn main() -> ! {
    let Some(dp) = Peripherals::take() else {
        loop {
            avr_device::asm::nop();
        }
    };
    let uart = dp.USART0;
    uart_init(&uart);
    put_str(&uart, b"sleep ready\r\n");
    // CTC (WGM12), clock/64: 250 kHz, OCR1A = 2499 gives 10 ms.
    // SAFETY: documented OCR1A/TCCR1B/TIMSK1 values.
    dp.TC1.ocr1a().write(|w| unsafe { w.bits(2499) });
    dp.TC1.tccr1b().write(|w| unsafe { w.bits(0b0000_1011) });
    dp.TC1.timsk1().write(|w| unsafe { w.bits(1 << 1) });
    // Idle sleep mode, sleep enabled.
    // SAFETY: SE with SM = 000 is a valid SMCR value.
    dp.CPU.smcr().write(|w| unsafe { w.bits(1) });
    // SAFETY: the only interrupt enabled is TIMER1_COMPA, whose handler is above.
    unsafe { avr_device::interrupt::enable() };
    let mut reported = 0u16;
    loop {
        avr_device::asm::sleep();
        let ticks = avr_device::interrupt::free(|cs| TICKS.borrow(cs).get());
        if ticks / 100 != reported / 100 {
            reported = ticks;
            put_str(&uart, b"t=");
            put_dec(&uart, ticks);
            put_str(&uart, b"\r\n");
        }
    }
}

#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    loop {
        avr_device::asm::nop();
    }
}
