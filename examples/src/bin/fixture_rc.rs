//! Fixture: measures RC servo pulses on D2, D3 and D4 (PCINT18..20) by pin change.
//! Timer1 runs at the CPU clock; the pin-change interrupt stamps each edge with TCNT1,
//! so a width is exact to a few cycles (pulses up to 4 ms). The main loop sleeps between
//! interrupts, so edges find the CPU asleep and the stamps' latency does not vary. Once
//! every channel has a new width, it prints them in µs over UART0 at 115200:
//! `rc 1500 1200 1800`. Used by the harness's RC receiver tests.
#![no_std]
#![no_main]
#![feature(abi_avr_interrupt)]

use core::cell::Cell;
use firmware_examples::uart::{put, put_dec, put_str};

use avr_device::atmega328p::Peripherals;
use avr_device::interrupt::Mutex;

/// Channel pins in PIND: D2, D3, D4.
const CHANNELS: [u8; 3] = [1 << 2, 1 << 3, 1 << 4];

/// What the interrupt hands to the main loop.
struct Edges {
    /// PIND at the last change.
    levels: Cell<u8>,
    /// TCNT1 at each channel's last rising edge.
    rise: Cell<[u16; 3]>,
    /// Width of each channel's last pulse, in cycles.
    width: Cell<[u16; 3]>,
    /// Channels with a width the main loop has not printed yet.
    fresh: Cell<u8>,
}

static EDGES: Mutex<Edges> = Mutex::new(Edges {
    levels: Cell::new(0),
    rise: Cell::new([0; 3]),
    width: Cell::new([0; 3]),
    fresh: Cell::new(0),
});

#[avr_device::interrupt(atmega328p)]
fn PCINT2() {
    // SAFETY: reading TCNT1 and PIND has no side effects; the interrupt runs with
    // interrupts disabled, so nothing else touches Timer1's 16-bit read latch now.
    let dp = unsafe { Peripherals::steal() };
    let now = dp.TC1.tcnt1().read().bits();
    let levels = dp.PORTD.pind().read().bits();
    avr_device::interrupt::free(|cs| {
        let e = EDGES.borrow(cs);
        let was = e.levels.get();
        let mut rise = e.rise.get();
        let mut width = e.width.get();
        let mut fresh = e.fresh.get();
        for (c, &mask) in CHANNELS.iter().enumerate() {
            match (was & mask != 0, levels & mask != 0) {
                (false, true) => rise[c] = now,
                (true, false) => {
                    width[c] = now.wrapping_sub(rise[c]);
                    fresh |= 1 << c;
                }
                _ => {}
            }
        }
        e.levels.set(levels);
        e.rise.set(rise);
        e.width.set(width);
        e.fresh.set(fresh);
    });
}

#[avr_device::entry]
fn main() -> ! {
    let dp = firmware_examples::peripherals();
    let uart = dp.USART0;
    // UCSR0A and UCSR0C first: the emulator applies the baud rate when UBRR0 is written.
    uart.ucsr0a().write(|w| w.u2x0().set_bit());
    uart.ucsr0c().write(|w| w.ucsz0().chr8());
    uart.ucsr0b().write(|w| w.txen0().set_bit());
    uart.ubrr0().write(|w| w.set(16));
    // Timer1 normal mode at clock/1: TCNT1 counts cycles, wrapping every 4.096 ms.
    // SAFETY: documented TCCR1A/TCCR1B values.
    dp.TC1.tccr1a().write(|w| unsafe { w.bits(0) });
    dp.TC1.tccr1b().write(|w| unsafe { w.bits(0b0000_0001) });
    // D2..D4 are inputs without pull-ups (the reset state); PCINT18..20 on, PCIE2 on.
    // SAFETY: documented PCMSK2/PCICR values.
    dp.EXINT.pcmsk2().write(|w| unsafe { w.bits(0b0001_1100) });
    dp.EXINT.pcicr().write(|w| unsafe { w.bits(1 << 2) });
    put_str(&uart, b"rc ready\r\n");
    // Idle sleep mode, sleep enabled.
    // SAFETY: SE with SM = 000 is a valid SMCR value.
    dp.CPU.smcr().write(|w| unsafe { w.bits(1) });
    // SAFETY: the interrupt's shared state is initialised and only used under `free`.
    unsafe { avr_device::interrupt::enable() };
    loop {
        avr_device::asm::sleep();
        let widths = avr_device::interrupt::free(|cs| {
            let e = EDGES.borrow(cs);
            if e.fresh.get() == 0b111 {
                e.fresh.set(0);
                Some(e.width.get())
            } else {
                None
            }
        });
        if let Some(widths) = widths {
            put_str(&uart, b"rc");
            for w in widths {
                put(&uart, b' ');
                // Cycles to µs, to the nearest: the stamps' latency is a few cycles.
                put_dec(&uart, ((u32::from(w) + 8) / 16) as u16);
            }
            put_str(&uart, b"\r\n");
        }
    }
}

firmware_examples::spin_on_panic!();
