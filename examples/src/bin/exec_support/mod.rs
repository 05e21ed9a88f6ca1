//! Helpers the executor's example firmwares (`exec_*`) share: UART0 text output, pin-change
//! and external-interrupt triggers the firmware fires on itself, Timer1 as a cycle counter,
//! a trace buffer of task events, and the panic handler.
#![allow(dead_code)]

use avr_device::atmega328p::{EXINT, PORTB, PORTC, PORTD, TC1, USART0};

/// A source the firmware can trigger by toggling one of its own output pins.
#[derive(Clone, Copy)]
pub enum Trigger {
    /// PB0 (D8): PCINT0, the pin-change interrupt of port B.
    Pcint0,
    /// PC0 (A0): PCINT1, the pin-change interrupt of port C.
    Pcint1,
    /// PD4 (D4): PCINT2, the pin-change interrupt of port D.
    Pcint2,
    /// PD2 (D2): INT0, set to fire on any edge.
    Int0,
    /// PD3 (D3): INT1, set to fire on any edge.
    Int1,
}

/// Makes every trigger pin an output and routes it to its interrupt flag. The enable bits
/// (PCICR, EIMSK) are the executor's: it sets them for the sources that have tasks.
pub fn setup_triggers(portb: &PORTB, portc: &PORTC, portd: &PORTD, exint: &EXINT) {
    // SAFETY: plain sense, direction and mask values for the pins listed on `Trigger`.
    unsafe {
        // ISC00 = 1, ISC10 = 1: any logical change on INT0/INT1. Set before the pins
        // become outputs, so the reset default (low level) never sees the low pins.
        exint.eicra().write(|w| w.bits(0b0101));
        portb.ddrb().write(|w| w.bits(1 << 0));
        portc.ddrc().write(|w| w.bits(1 << 0));
        portd
            .ddrd()
            .write(|w| w.bits((1 << 2) | (1 << 3) | (1 << 4)));
        exint.pcmsk0().write(|w| w.bits(1 << 0));
        exint.pcmsk1().write(|w| w.bits(1 << 0));
        exint.pcmsk2().write(|w| w.bits(1 << 4));
        // No flag is cleared here: none was raised (no pin changed after its mask was
        // set), and the emulator models EIFR as plain memory, where writing the clearing
        // ones would raise both flags instead.
    }
}

impl Trigger {
    /// The PINx register (data-space address) and bit mask that toggle the trigger's pin.
    pub const fn pin(self) -> (*mut u8, u8) {
        let (reg, bit): (usize, u8) = match self {
            Trigger::Pcint0 => (0x23, 0),
            Trigger::Pcint1 => (0x26, 0),
            Trigger::Pcint2 => (0x29, 4),
            Trigger::Int0 => (0x29, 2),
            Trigger::Int1 => (0x29, 3),
        };
        (reg as *mut u8, 1 << bit)
    }
}

/// Fires `t` by toggling its pin (writing one to the PINx bit is a single `sbi`, atomic
/// and safe from any priority).
#[inline(always)]
pub fn trigger(t: Trigger) {
    let (pin_reg, mask) = t.pin();
    // SAFETY: PINB/PINC/PIND are I/O registers; writing a one toggles that output only.
    unsafe { core::ptr::write_volatile(pin_reg, mask) };
}

/// Starts Timer1 free-running at the CPU clock, so TCNT1 counts cycles.
pub fn start_cycle_counter(tc1: &TC1) {
    // SAFETY: normal mode, prescaler 1 (CS10).
    unsafe {
        tc1.tccr1a().write(|w| w.bits(0));
        tc1.tccr1b().write(|w| w.bits(1));
    }
}

/// The low byte of TCNT1: the cycle count modulo 256 (one `lds`). Intervals up to 255
/// cycles are differences of two readings, with wrapping subtraction.
#[inline(always)]
pub fn cycles() -> u8 {
    // SAFETY: TCNT1L (0x84) is readable at any time; it latches TCNT1H into the 16-bit
    // TEMP register, which no example reads.
    unsafe { core::ptr::read_volatile(0x84 as *const u8) }
}

/// UART0 at 115200 8N1, transmit only, polled.
pub struct Uart(USART0);

impl Uart {
    /// Configures UART0. UCSR0A and UCSR0C are written before UBRR0 because the emulator
    /// takes its baud settings when UBRR0 is written.
    pub fn new(usart: USART0) -> Uart {
        usart.ucsr0a().write(|w| w.u2x0().set_bit());
        usart.ucsr0c().write(|w| w.ucsz0().chr8());
        // SAFETY: 16 with U2X0 is 115200 baud at 16 MHz.
        usart.ubrr0().write(|w| unsafe { w.bits(16) });
        usart.ucsr0b().write(|w| w.txen0().set_bit());
        Uart(usart)
    }

    /// Sends one byte, waiting for the data register.
    pub fn put(&mut self, b: u8) {
        while self.0.ucsr0a().read().udre0().bit_is_clear() {}
        // SAFETY: UDR0 takes any byte.
        self.0.udr0().write(|w| unsafe { w.bits(b) });
    }

    /// Sends `s`.
    pub fn put_str(&mut self, s: &[u8]) {
        for &b in s {
            self.put(b);
        }
    }

    /// Sends `n` in decimal.
    pub fn put_dec(&mut self, n: u32) {
        for &d in firmware_examples::decimal(n, &mut [0; 10]) {
            self.put(d);
        }
    }

    /// Sends `label`, the trace's events and a newline (the line the emulator tests parse).
    pub fn put_trace(&mut self, label: &[u8], trace: &Trace) {
        self.put_str(label);
        for &e in trace.events() {
            self.put(e);
        }
        self.put(b'\n');
    }

    /// Sends `key=value ` (the format the emulator tests parse).
    pub fn field(&mut self, key: &[u8], value: u32) {
        self.put_str(key);
        self.put(b'=');
        self.put_dec(value);
        self.put(b' ');
    }
}

/// Waits, bounded (200 rounds of `busy(50)`), until `len()` reports at least `n` events.
pub fn wait_for_events(n: usize, mut len: impl FnMut() -> usize) {
    for _ in 0..200 {
        if len() >= n {
            return;
        }
        busy(50);
    }
}

/// Events recorded by tasks, in order: one letter each.
pub struct Trace {
    buf: [u8; 32],
    len: u8,
}

impl Trace {
    /// An empty trace.
    pub const fn new() -> Trace {
        Trace {
            buf: [0; 32],
            len: 0,
        }
    }

    /// Appends `event`; a full trace ends with `!` so an overflow shows in the output.
    pub fn push(&mut self, event: u8) {
        let i = usize::from(self.len);
        if i < self.buf.len() {
            self.buf[i] = event;
            self.len += 1;
        } else {
            self.buf[self.buf.len() - 1] = b'!';
        }
    }

    /// Number of events.
    pub fn len(&self) -> usize {
        usize::from(self.len)
    }

    /// The events so far.
    pub fn events(&self) -> &[u8] {
        &self.buf[..usize::from(self.len)]
    }
}

/// Burns about `n` × 4 cycles, so a preempting task visibly lands in the middle.
#[inline(never)]
pub fn busy(n: u8) {
    for _ in 0..n {
        avr_device::asm::nop();
    }
}

#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    executor::freeze();
    loop {
        avr_device::asm::nop();
    }
}
