//! Scratchpad bytes to the raw value of a TEMP register, in integers.
//!
//! The original computed T = sign·(⌊|raw|/2⌋ + 0.5·(byte0 & 1)) with raw = (byte1 << 8) +
//! byte0, which is exactly raw/2: the scratchpad counts half degrees. It then stored
//! map(T) over −20..100 (2 bytes) in float32: trunc(((T + 20)·65534)/120).
//!
//! With h = raw half degrees and k = clamp(h, −40, 200) + 40 (0..=240), that is
//! trunc(k·32767/120). In float32 the product k·32767 ≤ 7 864 080 < 2²⁴ is exact, and the
//! quotient's fractional part is a multiple of 1/120, larger than half a float32 ulp at
//! that size (2⁻⁹), so rounding never carries it across an integer: the float result is
//! exactly the integer ⌊k·32767/120⌋ computed here. A host test checks every i16.

use super::SCRATCHPAD_LEN;

/// Why a scratchpad was not turned into a reading.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum ReadingError {
    /// The scratchpad's CRC byte does not match its first eight bytes (a disturbed read,
    /// or a sensor that stopped answering, whose bytes all read 0xff).
    BadCrc,
}

/// The Dallas/Maxim CRC8 (x⁸ + x⁵ + x⁴ + 1, LSB first, initial 0) of `bytes`. A ROM or a
/// scratchpad whose last byte is the CRC of the others has a CRC8 of 0 over all bytes.
// Out of line: the ROM search and each scratchpad read share one copy.
#[inline(never)]
pub fn crc8(bytes: &[u8]) -> u8 {
    let mut crc = 0u8;
    for &byte in bytes {
        // The byte's bits enter at bit 0 one per shift, so it can be mixed in whole.
        crc ^= byte;
        // A u8 counter: an untyped range would count in i32, four registers on the AVR.
        for _ in 0..8u8 {
            let mix = crc & 1;
            crc >>= 1;
            if mix != 0 {
                crc ^= 0x8c;
            }
        }
    }
    crc
}

/// The temperature in half degrees Celsius from scratchpad bytes 0 (LSB) and 1 (MSB).
pub const fn half_degrees(lsb: u8, msb: u8) -> i16 {
    i16::from_le_bytes([lsb, msb])
}

/// The raw TEMP register value (−20..100 °C over 0..65534) of a temperature in half
/// degrees; equal to `mapping::map(h / 2, TEMP register)` for every `h`.
pub fn register_raw(half: i16) -> u16 {
    // 0..=240 (the clamp in 16 bits), so the product is at most 7 864 080 and the
    // quotient at most 65534.
    let k = (half.clamp(-40, 200) + 40) as u16;
    (u32::from(k) * 32767 / 120) as u16
}

/// The raw TEMP register value of a scratchpad read from a sensor, if its CRC is right.
// In line: its one caller, the tick's last step, then needs no call of its own (measured
// 34 B smaller).
#[inline(always)]
pub fn reading(scratchpad: &[u8; SCRATCHPAD_LEN]) -> Result<u16, ReadingError> {
    if crc8(scratchpad) != 0 {
        return Err(ReadingError::BadCrc);
    }
    Ok(register_raw(half_degrees(scratchpad[0], scratchpad[1])))
}

#[cfg(test)]
mod tests {
    use super::crc8;

    /// The CRC as the bus shifts it: one data bit at a time against the register's bit 0.
    fn bit_serial(bytes: &[u8]) -> u8 {
        let mut crc = 0u8;
        for &byte in bytes {
            for i in 0..8 {
                let mix = (crc ^ (byte >> i)) & 1;
                crc >>= 1;
                if mix != 0 {
                    crc ^= 0x8c;
                }
            }
        }
        crc
    }

    #[test]
    fn the_whole_byte_crc_is_the_bit_serial_one_for_every_pair_of_bytes() {
        for a in 0..=u8::MAX {
            for b in 0..=u8::MAX {
                assert_eq!(crc8(&[a, b]), bit_serial(&[a, b]), "{a:#x} {b:#x}");
            }
        }
        assert_eq!(crc8(&[0x02, 0x1c, 0xb8, 0x01, 0x00, 0x00, 0x00]), 0xa2);
    }
}
