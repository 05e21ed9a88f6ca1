//! Fixture: a stand-in slave motor stage, so the physics model can be closed around a chip
//! before the real slave firmware exists. It demonstrates the slave's motor wiring:
//! - Timer1 in 8-bit phase-correct PWM, clock/1 (31.4 kHz) on D9 (M1) and D10 (M2);
//!   direction pins D2/D3 (M1 POS/NEG) and D4/D7 (M2 POS/NEG);
//! - the encoder interrupt on PD0 (PCINT16): each A rising edge counts N, and N_B when
//!   PD1 (B) is high at that edge, as the slave's encoder interrupt does;
//! - ADC0, ADC1, ADC6, ADC7 converted round-robin against AREF (prescaler 128).
//!
//! UART0 at 115200: send `M <motor> <dir> <duty>` as four bytes: motor `1` or `2`, dir
//! `F` (POS high), `R` (NEG high), `S` (both low) or `B` (both high), duty a raw byte
//! 0..=255 (OCR1x). Every 100 ms (Timer2, 1 ms ticks) it prints
//! `W <N> <N_B> <adc0> <adc1> <adc6> <adc7>\r\n` for the window just closed.
//!
//! PD0/PD1 are the UART's pins on a real chip; the emulator's UART does not take them, so
//! this fixture can use both. The real slave has no UART.
#![no_std]
#![no_main]
#![feature(abi_avr_interrupt)]

use core::cell::Cell;
use firmware_examples::uart::uart_init;

use avr_device::atmega328p::{Peripherals, ADC, PORTB, PORTD, TC1, USART0};
use avr_device::interrupt::Mutex;

/// Encoder counts of the open window: (A rising edges, those with B high).
static OPEN: Mutex<Cell<(u16, u16)>> = Mutex::new(Cell::new((0, 0)));
/// Counts of the last closed window.
static CLOSED: Mutex<Cell<(u16, u16)>> = Mutex::new(Cell::new((0, 0)));
/// Milliseconds into the open window.
static MILLIS: Mutex<Cell<u8>> = Mutex::new(Cell::new(0));
/// Number of windows closed so far (wrapping).
static WINDOWS: Mutex<Cell<u8>> = Mutex::new(Cell::new(0));

/// Window length in Timer2 ticks (ms).
const WINDOW_MS: u8 = 100;
/// ADC channels converted, in order.
const CHANNELS: [u8; 4] = [0, 1, 6, 7];

#[avr_device::interrupt(atmega328p)]
fn PCINT2() {
    // SAFETY: only PIND is read, a read-only input register; no code relies on owning PORTD
    // for it.
    let pind = unsafe { PORTD::steal() }.pind().read().bits();
    if pind & 1 != 0 {
        avr_device::interrupt::free(|cs| {
            let open = OPEN.borrow(cs);
            let (n, nb) = open.get();
            let nb = if pind & 2 != 0 {
                nb.wrapping_add(1)
            } else {
                nb
            };
            open.set((n.wrapping_add(1), nb));
        });
    }
}

#[avr_device::interrupt(atmega328p)]
fn TIMER2_COMPA() {
    avr_device::interrupt::free(|cs| {
        let ms = MILLIS.borrow(cs);
        let next = ms.get() + 1;
        if next < WINDOW_MS {
            ms.set(next);
            return;
        }
        ms.set(0);
        CLOSED.borrow(cs).set(OPEN.borrow(cs).replace((0, 0)));
        let w = WINDOWS.borrow(cs);
        w.set(w.get().wrapping_add(1));
    });
}

/// A line being sent without blocking the loop.
struct TxLine {
    buf: [u8; 48],
    len: usize,
    sent: usize,
}

impl TxLine {
    fn push(&mut self, b: u8) {
        if self.len < self.buf.len() {
            self.buf[self.len] = b;
            self.len += 1;
        }
    }

    fn push_dec(&mut self, n: u16) {
        for &d in firmware_examples::decimal(n.into(), &mut [0; 10]) {
            self.push(d);
        }
    }

    /// Sends the next byte if the transmitter is free.
    fn pump(&mut self, uart: &USART0) {
        if self.sent < self.len && uart.ucsr0a().read().udre0().bit_is_set() {
            uart.udr0().write(|w| w.set(self.buf[self.sent]));
            self.sent += 1;
        }
    }

    fn idle(&self) -> bool {
        self.sent >= self.len
    }

    fn start(&mut self) {
        self.len = 0;
        self.sent = 0;
    }
}

/// Applies a motor command.
fn command(tc1: &TC1, portd: &PORTD, motor: u8, dir: u8, duty: u8) {
    let (pos, neg) = if motor == b'1' { (2, 3) } else { (4, 7) };
    let (p, n) = match dir {
        b'F' => (true, false),
        b'R' => (false, true),
        b'B' => (true, true),
        _ => (false, false),
    };
    portd.portd().modify(|r, w| {
        let mut v = r.bits() & !((1 << pos) | (1 << neg));
        if p {
            v |= 1 << pos;
        }
        if n {
            v |= 1 << neg;
        }
        // SAFETY: any PORTD value is valid; only the direction bits change.
        unsafe { w.bits(v) }
    });
    if motor == b'1' {
        // SAFETY: any OCR1A value is a valid compare value.
        tc1.ocr1a().write(|w| unsafe { w.bits(u16::from(duty)) });
    } else {
        // SAFETY: any OCR1B value is a valid compare value.
        tc1.ocr1b().write(|w| unsafe { w.bits(u16::from(duty)) });
    }
}

fn start_conversion(adc: &ADC, channel: u8) {
    // REFS = 00 (AREF), as the slave: ADMUX holds the channel only.
    // SAFETY: any channel 0..=7 is a valid ADMUX value.
    adc.admux().write(|w| unsafe { w.bits(channel) });
    adc.adcsra().modify(|_, w| w.adsc().set_bit());
}

fn setup_timers(dp: &Peripherals, portb: &PORTB) {
    // D9 (PB1) and D10 (PB2) are the PWM outputs.
    // SAFETY: any DDRB value is valid.
    portb
        .ddrb()
        .write(|w| unsafe { w.bits((1 << 1) | (1 << 2)) });
    // Timer1 mode 1 (8-bit phase correct), COM1A = COM1B = 10 (non-inverting), clock/1.
    // SAFETY: documented TCCR1A/TCCR1B values; compare values start at 0.
    dp.TC1.ocr1a().write(|w| unsafe { w.bits(0) });
    dp.TC1.ocr1b().write(|w| unsafe { w.bits(0) });
    dp.TC1.tccr1a().write(|w| unsafe { w.bits(0b1010_0001) });
    dp.TC1.tccr1b().write(|w| unsafe { w.bits(0b0000_0001) });
    // Timer2 CTC (WGM21), clock/128 = 125 kHz, OCR2A = 124: 1 ms compare interrupts.
    // SAFETY: documented TCCR2A/TCCR2B/OCR2A/TIMSK2 values.
    dp.TC2.ocr2a().write(|w| unsafe { w.bits(124) });
    dp.TC2.tccr2a().write(|w| unsafe { w.bits(0b0000_0010) });
    dp.TC2.tccr2b().write(|w| unsafe { w.bits(0b0000_0101) });
    dp.TC2.timsk2().write(|w| unsafe { w.bits(1 << 1) });
}

#[avr_device::entry]
fn main() -> ! {
    let dp = firmware_examples::peripherals();
    uart_init(&dp.USART0);
    // Direction pins D2, D3, D4, D7 are outputs, low; PD0/PD1 inputs without pull-ups.
    // SAFETY: any DDRD/PORTD value is valid.
    dp.PORTD
        .ddrd()
        .write(|w| unsafe { w.bits((1 << 2) | (1 << 3) | (1 << 4) | (1 << 7)) });
    // SAFETY: as above.
    dp.PORTD.portd().write(|w| unsafe { w.bits(0) });
    setup_timers(&dp, &dp.PORTB);
    // PCINT16 (PD0) only, port D's pin-change interrupt on.
    // SAFETY: documented PCMSK2/PCICR values.
    dp.EXINT.pcmsk2().write(|w| unsafe { w.bits(1) });
    dp.EXINT.pcicr().write(|w| unsafe { w.bits(1 << 2) });
    let adc = &dp.ADC;
    adc.adcsra()
        .write(|w| w.aden().set_bit().adps().prescaler_128());
    let mut readings = [0u16; 4];
    let mut current = 0;
    start_conversion(adc, CHANNELS[current]);

    let mut line = TxLine {
        buf: [0; 48],
        len: 0,
        sent: 0,
    };
    for &b in b"motor ready\r\n" {
        line.push(b);
    }
    let mut cmd = [0u8; 4];
    let mut got = 0;
    let mut seen = 0u8;
    // SAFETY: the only interrupts enabled are PCINT2 and TIMER2_COMPA, handled above.
    unsafe { avr_device::interrupt::enable() };
    loop {
        if dp.USART0.ucsr0a().read().rxc0().bit_is_set() {
            let b = dp.USART0.udr0().read().bits();
            if got > 0 || b == b'M' {
                cmd[got] = b;
                got += 1;
            }
            if got == cmd.len() {
                command(&dp.TC1, &dp.PORTD, cmd[1], cmd[2], cmd[3]);
                got = 0;
            }
        }
        if adc.adcsra().read().adsc().bit_is_clear() {
            readings[current] = adc.adc().read().bits();
            current = (current + 1) % CHANNELS.len();
            start_conversion(adc, CHANNELS[current]);
        }
        let (windows, counts) =
            avr_device::interrupt::free(|cs| (WINDOWS.borrow(cs).get(), CLOSED.borrow(cs).get()));
        if windows != seen && line.idle() {
            seen = windows;
            line.start();
            line.push(b'W');
            for v in [counts.0, counts.1]
                .into_iter()
                .chain(readings.iter().copied())
            {
                line.push(b' ');
                line.push_dec(v);
            }
            line.push(b'\r');
            line.push(b'\n');
        }
        line.pump(&dp.USART0);
    }
}

firmware_examples::spin_on_panic!();
