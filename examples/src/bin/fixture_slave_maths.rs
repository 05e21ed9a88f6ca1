//! Fixture: the slave's own arithmetic in AVR assembly, run on the chip with values the
//! host picks, so each is checked against the host's own arithmetic (the host builds of
//! all of them are plain Rust). Prints `maths ready\r\n`, then answers 9-byte requests
//! `op, a (u32 LE), b (u32 LE)` with 8 bytes, two u32 LE (the second 0 for one result):
//! - op 0: `divide::div_rem(a, b)`: quotient, remainder (`(u32::MAX, a)` for b = 0);
//! - op 1: `product::wide(a as u16, b as u16)`: the 16×16→32 product;
//! - op 2: `product::fixed(a, b)`: the PID's saturating `I16F16` product;
//! - op 3 / 4: `pid::sum::add(a, b)` / `sub(a, b)`: saturating sum / difference;
//! - op 5: `pid::sum::magnitude(a)`;
//! - op 6: `pid::sum::dead_zone(a, b)`;
//! - op 7: `pid::sum::clamp(a, b)` (b ≥ 0);
//! - op 8: `scale::Mapping::map` of the value with bits a by scale b of [`MAPPINGS`]:
//!   the raw monitoring value;
//! - op 9: `clock::count_ms(a, b as u16, (b >> 16) · 0x10001)`: the µs to the next
//!   whole ms, and the ms count;
//! - op 10: the current filter's step (`current::CurrentFilter::push`) of the sample
//!   `a as u8` from every raw value f = 0..=65535: a hash of the 65,536 results in
//!   order (`h = h.rotate_left(5) ^ f'`) and their wrapping sum;
//! - op 11: `clock::age_add(a as u16, g)` (the speed meter's saturating age) for every
//!   gap g = 0..=65535: a hash of the 65,536 results in order, as op 10's, and their
//!   wrapping sum;
//! - op 20: the pairs of [`SAMPLE`] (in flash) written over 600 zero bytes by
//!   `image::apply_from_flash` (the slave's power-up writer): bytes a..a + 8 of them.
#![no_std]
#![no_main]
#![feature(asm_experimental_arch)]

use core::hint::black_box;
use firmware_examples::uart::{get_request, put_pair};
use shared::pid::{sum, Fix};
use shared::regs::{id, DS};
use shared::slave::clock::{age_add, count_ms};
use shared::slave::current::CurrentFilter;
use shared::slave::image::{apply_from_flash, Image};
use shared::slave::scale::{Mapping, Scale};
use shared::slave::{divide::div_rem, product};

// The division `div_rem` calls, as every slave image has it.
drivers::division_routines!();

/// Op 8's scales, by index: the monitoring ranges (±4000, ±1000, ±200, ±255, 0..1000),
/// CHASSIS (0..1024), and one-byte ranges (±120, 0..50, 0..255): reciprocals from 16 to
/// 24 bits (±200's 10,737,419 is the largest a mapping may have).
static MAPPINGS: [Mapping; 9] = [
    Scale::of(&DS, id::REGDS_DRIVE_ACTUALSPEED).mapping(),
    Scale::of(&DS, id::REGDS_DRIVE_ERROR).mapping(),
    Scale::of(&DS, id::REGDS_STEER_ACTUALPOS).mapping(),
    Scale::of(&DS, id::REGDS_DRIVE_CONTROL).mapping(),
    Scale::of(&DS, id::REGDS_DRIVE_INTERVALCTRL).mapping(),
    Scale::of(&DS, id::REGDS_CHASSIS).mapping(),
    Scale::of(&DS, id::REGDS_STEER_CALIBMIN).mapping(),
    Scale::of(&DS, id::REGDS_DRIVE_DEADZONE).mapping(),
    Scale::of(&DS, id::REGDS_DRIVE_STALLCHECK).mapping(),
];

/// The current filter's step from every raw value with sample `c`: a hash of the
/// 65,536 results in order, and their wrapping sum.
fn filter_sweep(c: u8) -> (u32, u32) {
    let (mut hash, mut sum) = (0u32, 0u32);
    for f in 0..=u16::MAX {
        let mut filter = CurrentFilter::from_raw(black_box(f));
        filter.push(black_box(u16::from(c)));
        let got = filter.raw();
        hash = hash.rotate_left(5) ^ u32::from(got);
        sum = sum.wrapping_add(u32::from(got));
    }
    (hash, sum)
}

/// `age_add(age, g)` for every gap g: a hash of the 65,536 results in order, and their
/// wrapping sum.
fn age_sweep(age: u16) -> (u32, u32) {
    let (mut hash, mut sum) = (0u32, 0u32);
    for gap in 0..=u16::MAX {
        let got = age_add(black_box(age), black_box(gap));
        hash = hash.rotate_left(5) ^ u32::from(got);
        sum = sum.wrapping_add(u32::from(got));
    }
    (hash, sum)
}

/// Op 20's image: 600 bytes, nonzero on every third of the first 120 (from byte 0), at
/// 400 (after a gap longer than a step: a pair that stores a zero on the way) and at 599.
const fn sample_byte(i: usize) -> u8 {
    if (i < 120 && i.is_multiple_of(3)) || i == 400 || i == 599 {
        (i * 37 % 255 + 1) as u8
    } else {
        0
    }
}

/// [`sample_byte`]'s 600 bytes.
const SAMPLE: Image<600> = {
    let mut image = Image::ZERO;
    let mut i = 0;
    while i < 600 {
        image = image.byte(i, sample_byte(i));
        i += 1;
    }
    image
};

shared::flash_table! {
    /// [`SAMPLE`]'s pairs, in flash as the slave's power-up pairs are.
    static SAMPLE_PAIRS: [[u8; 2]; SAMPLE.len()] = SAMPLE.pairs();
}

/// Op 20: [`SAMPLE_PAIRS`] written over zeros, bytes `at..at + 8`.
fn written_sample(at: usize) -> (u32, u32) {
    let mut memory = [0u8; 600];
    // SAFETY: the pairs (43) were made for these 600 bytes, borrowed here only.
    unsafe { apply_from_flash(SAMPLE_PAIRS.as_slice(), black_box(memory.as_mut_ptr())) };
    let mut bytes = [0u8; 8];
    for (k, b) in bytes.iter_mut().enumerate() {
        *b = memory.get(at + k).copied().unwrap_or(0xff);
    }
    let [b0, b1, b2, b3, b4, b5, b6, b7] = bytes;
    (
        u32::from_le_bytes([b0, b1, b2, b3]),
        u32::from_le_bytes([b4, b5, b6, b7]),
    )
}

#[avr_device::entry]
fn main() -> ! {
    let dp = firmware_examples::peripherals();
    let uart = firmware_examples::uart::start(dp.USART0, b"maths ready\r\n");
    loop {
        let req: [u8; 9] = get_request(&uart);
        let a = u32::from_le_bytes([req[1], req[2], req[3], req[4]]);
        let b = u32::from_le_bytes([req[5], req[6], req[7], req[8]]);
        // black_box: the operands must reach the routines at run time, not be folded.
        let (a, b) = (black_box(a), black_box(b));
        let (sa, sb) = (a as i32, b as i32);
        let (x, y) = match req[0] {
            0 => div_rem(a, b),
            1 => (product::wide(a as u16, b as u16), 0),
            2 => (product::fixed(sa, sb) as u32, 0),
            3 => (sum::add(sa, sb) as u32, 0),
            4 => (sum::sub(sa, sb) as u32, 0),
            5 => (sum::magnitude(sa), 0),
            6 => (sum::dead_zone(sa, b) as u32, 0),
            7 if sb >= 0 => (sum::clamp(sa, sb) as u32, 0),
            8 => match MAPPINGS.get(b as usize) {
                Some(mapping) => (u32::from(mapping.map(Fix::from_bits(sa))), 0),
                None => (u32::MAX, u32::MAX),
            },
            9 => {
                let (to_next, ms) = count_ms(a, b as u16, (b >> 16) * 0x1_0001);
                (u32::from(to_next), ms)
            }
            10 => filter_sweep(a as u8),
            11 => age_sweep(a as u16),
            20 => written_sample(a as usize),
            _ => (u32::MAX, u32::MAX),
        };
        put_pair(&uart, x, y);
    }
}

firmware_examples::spin_on_panic!();
