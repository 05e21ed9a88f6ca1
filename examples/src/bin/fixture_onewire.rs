//! Fixture: a OneWire master bit-banged on D6 (PD6) as an open drain, with datasheet
//! timings. Each pass searches the bus (SEARCH ROM), starts a conversion on every sensor
//! at once (SKIP ROM, CONVERT T), polls read slots until it is done, then reads each
//! sensor's scratchpad (MATCH ROM, READ SCRATCHPAD) and prints it over UART0 at 115200:
//!
//! ```text
//! pass 1
//! n=2
//! rom 109c3a020800000b
//! rom 1020...
//! conv 712
//! t 109c3a020800000b 32004b46ffff0c1085 crc=ok T=+25.0
//! end
//! ```
//! `conv` is the number of 1-ms polls the conversion took. Used by the harness's OneWire
//! tests.
#![no_std]
#![no_main]

use avr_device::atmega328p::{PORTD, USART0};
use firmware_examples::uart::{put, put_dec, put_str};

/// PD6's bit in the port registers.
const PIN: u8 = 1 << 6;
/// Cycles per µs at 16 MHz.
const US: u32 = 16;
/// Most devices this fixture lists.
const MAX_DEVICES: usize = 12;

fn uart_init(uart: &USART0) {
    // UCSR0A and UCSR0C first: the emulator applies the baud rate when UBRR0 is written.
    uart.ucsr0a().write(|w| w.u2x0().set_bit());
    uart.ucsr0c().write(|w| w.ucsz0().chr8());
    uart.ucsr0b().write(|w| w.txen0().set_bit());
    uart.ubrr0().write(|w| w.set(16));
}

fn put_hex(uart: &USART0, bytes: &[u8]) {
    const HEX: &[u8; 16] = b"0123456789abcdef";
    for &b in bytes {
        put(uart, HEX[usize::from(b >> 4)]);
        put(uart, HEX[usize::from(b & 15)]);
    }
}

/// Busy-waits `us` µs.
fn delay_us(us: u32) {
    avr_device::asm::delay_cycles(us * US);
}

/// The OneWire line on PD6.
struct Line<'a> {
    port: &'a PORTD,
}

impl Line<'_> {
    fn low(&self) {
        // SAFETY: any DDRD value is valid; only PD6 changes.
        self.port
            .ddrd()
            .modify(|r, w| unsafe { w.bits(r.bits() | PIN) });
    }

    fn release(&self) {
        // SAFETY: as in `low`.
        self.port
            .ddrd()
            .modify(|r, w| unsafe { w.bits(r.bits() & !PIN) });
    }

    fn high(&self) -> bool {
        self.port.pind().read().bits() & PIN != 0
    }

    /// Reset pulse; true if a device answered with a presence pulse.
    fn reset(&self) -> bool {
        self.low();
        delay_us(480);
        self.release();
        delay_us(70);
        let presence = !self.high();
        delay_us(410);
        presence
    }

    fn write_bit(&self, bit: bool) {
        self.low();
        if bit {
            delay_us(6);
            self.release();
            delay_us(64);
        } else {
            delay_us(60);
            self.release();
            delay_us(10);
        }
    }

    fn read_bit(&self) -> bool {
        self.low();
        delay_us(6);
        self.release();
        delay_us(9);
        let bit = self.high();
        delay_us(55);
        bit
    }

    fn write_byte(&self, byte: u8) {
        for i in 0..8 {
            self.write_bit(byte & (1 << i) != 0);
        }
    }

    fn read_byte(&self) -> u8 {
        let mut byte = 0;
        for i in 0..8 {
            if self.read_bit() {
                byte |= 1 << i;
            }
        }
        byte
    }
}

/// Dallas/Maxim CRC8.
fn crc8(bytes: &[u8]) -> u8 {
    let mut crc = 0u8;
    for &byte in bytes {
        let mut b = byte;
        for _ in 0..8 {
            let mix = (crc ^ b) & 1;
            crc >>= 1;
            if mix != 0 {
                crc ^= 0x8c;
            }
            b >>= 1;
        }
    }
    crc
}

/// Finds every device on the line, lowest ROM (read LSB first) first.
fn search(line: &Line, roms: &mut [[u8; 8]; MAX_DEVICES]) -> usize {
    let mut count = 0;
    let mut rom = [0u8; 8];
    // Bit index + 1 of the last discrepancy where the previous pass took 0; 0 = none.
    let mut last_zero = 0u8;
    loop {
        if !line.reset() {
            return count;
        }
        line.write_byte(0xf0);
        let mut pass_zero = 0u8;
        for i in 0..64u8 {
            let bit = line.read_bit();
            let complement = line.read_bit();
            let byte = usize::from(i / 8);
            let mask = 1u8 << (i % 8);
            let direction = match (bit, complement) {
                (true, true) => return count,
                (b, c) if b != c => b,
                _ => {
                    let take = if i + 1 < last_zero {
                        rom[byte] & mask != 0
                    } else {
                        i + 1 == last_zero
                    };
                    if !take {
                        pass_zero = i + 1;
                    }
                    take
                }
            };
            if direction {
                rom[byte] |= mask;
            } else {
                rom[byte] &= !mask;
            }
            line.write_bit(direction);
        }
        if count < MAX_DEVICES {
            roms[count] = rom;
            count += 1;
        }
        last_zero = pass_zero;
        if last_zero == 0 {
            return count;
        }
    }
}

/// Prints half degrees as `+25.5`.
fn put_celsius(uart: &USART0, half: i16) {
    put(uart, if half < 0 { b'-' } else { b'+' });
    let magnitude = half.unsigned_abs();
    put_dec(uart, magnitude / 2);
    put_str(uart, if magnitude & 1 != 0 { b".5" } else { b".0" });
}

#[avr_device::entry]
fn main() -> ! {
    let dp = firmware_examples::peripherals();
    let uart = dp.USART0;
    uart_init(&uart);
    // PD6 released, with PORTD6 = 0 so that making it an output pulls it low.
    // SAFETY: any PORTD/DDRD value is valid.
    dp.PORTD
        .portd()
        .modify(|r, w| unsafe { w.bits(r.bits() & !PIN) });
    let line = Line { port: &dp.PORTD };
    line.release();
    put_str(&uart, b"onewire ready\r\n");
    let mut roms = [[0u8; 8]; MAX_DEVICES];
    let mut pass: u16 = 0;
    loop {
        pass = pass.wrapping_add(1);
        put_str(&uart, b"pass ");
        put_dec(&uart, pass);
        put_str(&uart, b"\r\n");
        let count = search(&line, &mut roms);
        put_str(&uart, b"n=");
        put_dec(&uart, count as u16);
        put_str(&uart, b"\r\n");
        for rom in &roms[..count] {
            put_str(&uart, b"rom ");
            put_hex(&uart, rom);
            put_str(&uart, b"\r\n");
        }
        if count > 0 && line.reset() {
            line.write_byte(0xcc);
            line.write_byte(0x44);
            let mut polls: u16 = 0;
            while !line.read_bit() && polls < 2000 {
                delay_us(1000);
                polls += 1;
            }
            put_str(&uart, b"conv ");
            put_dec(&uart, polls);
            put_str(&uart, b"\r\n");
        }
        for rom in &roms[..count] {
            put_str(&uart, b"t ");
            put_hex(&uart, rom);
            if !line.reset() {
                put_str(&uart, b" absent\r\n");
                continue;
            }
            line.write_byte(0x55);
            for &b in rom {
                line.write_byte(b);
            }
            line.write_byte(0xbe);
            let mut pad = [0u8; 9];
            for b in pad.iter_mut() {
                *b = line.read_byte();
            }
            put(&uart, b' ');
            put_hex(&uart, &pad);
            if crc8(&pad) == 0 {
                put_str(&uart, b" crc=ok T=");
                put_celsius(&uart, i16::from_le_bytes([pad[0], pad[1]]));
            } else {
                put_str(&uart, b" crc=bad");
            }
            put_str(&uart, b"\r\n");
        }
        put_str(&uart, b"end\r\n");
    }
}

firmware_examples::spin_on_panic!();
