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
    let _ = ufmt::uwrite!(out, "{}\r\n", drivers::cpu::free_ram());
    out.send_all(b"Ready\r\n");
}
