//! Fixture: Timer1 in CTC mode interrupts every 10 ms; the main loop executes
//! SLEEP (idle) between interrupts and prints `t=<ticks>\r\n` every 100 ticks
//! (once per second). Used by the harness's sleep fast-forward test.
#![no_std]
#![no_main]
#![feature(abi_avr_interrupt)]

use core::cell::Cell;
use firmware_examples::uart::{put_dec, put_str};

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

#[avr_device::entry]
fn main() -> ! {
    let dp = firmware_examples::peripherals();
    let uart = firmware_examples::uart::start(dp.USART0, b"sleep ready\r\n");
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

firmware_examples::spin_on_panic!();
