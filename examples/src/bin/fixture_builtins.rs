//! Fixture: the images' own runtime routines (`drivers/src/runtime.rs`: 32-bit division,
//! `memcpy`, `memset`), linked in place of the toolchain's exactly as in the firmware images
//! and driven from the UART with values the host picks, so each is checked against the
//! host's own arithmetic. Prints `builtins ready\r\n`, then answers 9-byte requests
//! `op, a (u32 LE), b (u32 LE)`:
//! - op 0: `a / b` and `a % b` as `u32` (b non-zero): 8 bytes, quotient then remainder, LE;
//! - op 1: the same as `i32` (b non-zero, not `i32::MIN / -1`);
//! - op 2: a 40-byte buffer of 0xee after `memcpy` of `a` bytes (0..=32) of the pattern
//!   1, 2, 3, … to offset `b` (0..=8): the 40 bytes;
//! - op 3: the same buffer after `memset` of `a` bytes to offset `b & 0xff` with the value
//!   `b >> 8`: the 40 bytes.
#![no_std]
#![no_main]
#![feature(asm_experimental_arch)]

drivers::division_routines!();
drivers::mem_routines!();

use firmware_examples::uart::{get_request, put_pair, put_str};

/// Bytes of the copy and fill buffer.
const BUF: usize = 40;

#[avr_device::entry]
fn main() -> ! {
    let dp = firmware_examples::peripherals();
    let uart = firmware_examples::uart::start(dp.USART0, b"builtins ready\r\n");
    loop {
        let req: [u8; 9] = get_request(&uart);
        let op = req[0];
        let a = u32::from_le_bytes([req[1], req[2], req[3], req[4]]);
        let b = u32::from_le_bytes([req[5], req[6], req[7], req[8]]);
        match op {
            0 => {
                let (q, r) = (a.checked_div(b), a.checked_rem(b));
                put_pair(&uart, q.unwrap_or(0), r.unwrap_or(0));
            }
            1 => {
                let (a, b) = (a as i32, b as i32);
                let (q, r) = (a.checked_div(b), a.checked_rem(b));
                put_pair(&uart, q.unwrap_or(0) as u32, r.unwrap_or(0) as u32);
            }
            2 => {
                let mut pattern = [0u8; 32];
                for (i, p) in pattern.iter_mut().enumerate() {
                    *p = i as u8 + 1;
                }
                let mut buf = [0xeeu8; BUF];
                let (len, at) = ((a as usize).min(32), (b as usize).min(8));
                // SAFETY: `len` <= 32 bytes from the 32-byte pattern into the buffer at
                // `at` <= 8, ending at most at 40; the two arrays are distinct.
                unsafe {
                    core::ptr::copy_nonoverlapping(pattern.as_ptr(), buf.as_mut_ptr().add(at), len)
                };
                put_str(&uart, &buf);
            }
            _ => {
                let mut buf = [0xeeu8; BUF];
                let (len, at) = ((a as usize).min(32), usize::from(b as u8).min(8));
                // SAFETY: `len` <= 32 bytes at `at` <= 8, inside the 40-byte buffer.
                unsafe { core::ptr::write_bytes(buf.as_mut_ptr().add(at), (b >> 8) as u8, len) };
                put_str(&uart, &buf);
            }
        }
    }
}

firmware_examples::spin_on_panic!();
