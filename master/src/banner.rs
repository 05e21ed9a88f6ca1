//! The start-up banner of reference §4.1: `Starting`, the build date and time, the free
//! SRAM, `Ready`, each line ending CR LF. The original PC library waits for `Ready`.
//! The fixed text is kept in flash (see `shared::progmem`).

use crate::link::{Lock, Replies, TxQueue};
use shared::progmem::Flash;

/// The build stamp line.
const STAMP: &str = concat!(env!("BUILD_DATE"), " ", env!("BUILD_TIME"), "\r\n");

/// `text` as an array of its `N` bytes (`N` = its length).
const fn bytes<const N: usize>(text: &str) -> [u8; N] {
    let mut out = [0u8; N];
    let mut i = 0;
    while i < N {
        out[i] = text.as_bytes()[i];
        i += 1;
    }
    out
}

shared::flash_table! {
    /// The first line.
    static STARTING: [u8; 10] = *b"Starting\r\n";
}

shared::flash_table! {
    /// The build date and time.
    static STAMP_LINE: [u8; STAMP.len()] = bytes(STAMP);
}

shared::flash_table! {
    /// The last line.
    static READY: [u8; 7] = *b"Ready\r\n";
}

/// The first line, sent before the boot work.
pub fn starting<L: Lock<TxQueue>>(out: &mut Replies<'_, L>) {
    send_text(out, STARTING.as_slice());
}

/// The rest, sent when frames can be accepted.
pub fn finish<L: Lock<TxQueue>>(out: &mut Replies<'_, L>) {
    send_text(out, STAMP_LINE.as_slice());
    decimal(out, drivers::cpu::free_ram());
    out.send_all(b"\r\n");
    send_text(out, READY.as_slice());
}

/// Sends the bytes of a text kept in flash.
fn send_text<L: Lock<TxQueue>>(out: &mut Replies<'_, L>, text: &'static Flash<[u8]>) {
    text.iter().for_each(|b| out.send(b));
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
