//! Fixture: the slave's own arithmetic in AVR assembly (`shared::slave::divide::div_rem`,
//! the 32-bit shift-and-subtract division, and `shared::slave::product::wide`, the
//! 16×16→32 product from the hardware multiplier), run on the chip with values the host
//! picks, so each is checked against the host's own arithmetic (the host builds of both
//! are plain Rust). Prints `maths ready\r\n`, then answers 9-byte requests
//! `op, a (u32 LE), b (u32 LE)`:
//! - op 0: `div_rem(a, b)` (b non-zero): 8 bytes, quotient then remainder, LE;
//! - op 1: `wide(a as u16, b as u16)`: 8 bytes, the product then 0, LE.
#![no_std]
#![no_main]

use core::hint::black_box;
use firmware_examples::uart::{get_request, put_pair};
use shared::slave::{divide::div_rem, product::wide};

#[avr_device::entry]
fn main() -> ! {
    let dp = firmware_examples::peripherals();
    let uart = firmware_examples::uart::start(dp.USART0, b"maths ready\r\n");
    loop {
        let req: [u8; 9] = get_request(&uart);
        let a = u32::from_le_bytes([req[1], req[2], req[3], req[4]]);
        let b = u32::from_le_bytes([req[5], req[6], req[7], req[8]]);
        // black_box: the operands must reach the routines at run time, not be folded.
        let (x, y) = match req[0] {
            0 if b != 0 => div_rem(black_box(a), black_box(b)),
            1 => (wide(black_box(a as u16), black_box(b as u16)), 0),
            _ => (u32::MAX, u32::MAX),
        };
        put_pair(&uart, x, y);
    }
}

firmware_examples::spin_on_panic!();
