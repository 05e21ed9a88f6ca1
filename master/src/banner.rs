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
    /// The end of the free-SRAM line, then the last line (one table, so no line end is
    /// kept in RAM).
    static READY: [u8; 9] = *b"\r\nReady\r\n";
}

/// The first line, sent before the boot work.
pub fn starting<L: Lock<TxQueue>>(out: &mut Replies<'_, L>) {
    send_text(out, STARTING.as_slice());
}

/// The rest, sent when frames can be accepted.
pub fn finish<L: Lock<TxQueue>>(out: &mut Replies<'_, L>) {
    send_text(out, STAMP_LINE.as_slice());
    decimal(out, drivers::cpu::free_ram());
    send_text(out, READY.as_slice());
}

/// Sends the bytes of a text kept in flash.
fn send_text<L: Lock<TxQueue>>(out: &mut Replies<'_, L>, text: &'static Flash<[u8]>) {
    text.iter().for_each(|b| out.send(b));
}

shared::flash_table! {
    /// The decimal places of a `u16`, by subtraction instead of division.
    static POWERS_OF_TEN: [u16; 5] = [10_000, 1_000, 100, 10, 1];
}

/// Sends `n` in decimal, without leading zeros.
fn decimal<L: Lock<TxQueue>>(out: &mut Replies<'_, L>, mut n: u16) {
    let mut started = false;
    for power in POWERS_OF_TEN.as_slice().iter() {
        let mut digit = b'0';
        while n >= power {
            n -= power;
            digit += 1;
        }
        started |= digit != b'0' || power == 1;
        if started {
            out.send(digit);
        }
    }
}
