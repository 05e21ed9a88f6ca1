//! The start-up banner of reference §4.1: `Starting`, the build date and time, the free
//! SRAM, `Ready`, each line ending CR LF. The original PC library waits for `Ready`.

use crate::link::{Lock, Replies, TxQueue};

/// The first line, sent before the boot work.
pub fn starting<L: Lock<TxQueue>>(out: &mut Replies<'_, L>) {
    out.send_all(b"Starting\r\n");
}

/// The rest, sent when frames can be accepted.
pub fn finish<L: Lock<TxQueue>>(out: &mut Replies<'_, L>) {
    out.send_all(env!("BUILD_DATE").as_bytes());
    out.send(b' ');
    out.send_all(env!("BUILD_TIME").as_bytes());
    out.send_all(b"\r\n");
    decimal(out, drivers::cpu::free_ram());
    out.send_all(b"\r\n");
    out.send_all(b"Ready\r\n");
}

/// Sends `n` in decimal, without leading zeros.
fn decimal<L: Lock<TxQueue>>(out: &mut Replies<'_, L>, mut n: u16) {
    let mut digits = [0u8; 5];
    let mut len = 0;
    for slot in digits.iter_mut() {
        *slot = b'0' + (n % 10) as u8;
        len += 1;
        n /= 10;
        if n == 0 {
            break;
        }
    }
    digits[..len].iter().rev().for_each(|&d| out.send(d));
}
