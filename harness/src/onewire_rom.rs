//! The ROM ids of the rover's ten DS18S20 sensors, and the OneWire CRC8.

/// Family code of the DS18S20.
pub const FAMILY_DS18S20: u8 = 0x10;

/// ROM byte 1 of each sensor (reference §9.1): ambient, then controllers 1..9.
const BYTE1: [u8; 10] = [0x9c, 0x20, 0x51, 0xa8, 0x89, 0x2f, 0xb1, 0xb5, 0x6f, 0x9e];

/// The Dallas/Maxim CRC8 (x⁸ + x⁵ + x⁴ + 1, LSB first, initial 0).
pub const fn crc8(bytes: &[u8]) -> u8 {
    let mut crc = 0u8;
    let mut i = 0;
    while i < bytes.len() {
        let mut b = bytes[i];
        let mut bit = 0;
        while bit < 8 {
            let mix = (crc ^ b) & 1;
            crc >>= 1;
            if mix != 0 {
                crc ^= 0x8c;
            }
            b >>= 1;
            bit += 1;
        }
        i += 1;
    }
    crc
}

/// A DS18S20 ROM: family 0x10, the given six serial bytes, then their CRC.
pub const fn ds18s20_rom(serial: [u8; 6]) -> [u8; 8] {
    let head = [
        FAMILY_DS18S20,
        serial[0],
        serial[1],
        serial[2],
        serial[3],
        serial[4],
        serial[5],
    ];
    let crc = crc8(&head);
    [
        head[0], head[1], head[2], head[3], head[4], head[5], head[6], crc,
    ]
}

/// Sensor `i`'s ROM: byte 1 from the reference; bytes 2..6 are this harness's choice:
/// `0x3a + i`, then `0x02 0x08 0x00 0x00`, as a real DS18S20 serial might read.
const fn rover_rom(i: usize) -> [u8; 8] {
    ds18s20_rom([BYTE1[i], 0x3a + i as u8, 0x02, 0x08, 0x00, 0x00])
}

/// The ROMs of the rover's sensors: index 0 is the ambient sensor (REGMASTER_TEMPAMBIENT),
/// index n the sensor of controller n (REGMASTER_TEMPn).
pub const ROVER_SENSOR_ROMS: [[u8; 8]; 10] = [
    rover_rom(0),
    rover_rom(1),
    rover_rom(2),
    rover_rom(3),
    rover_rom(4),
    rover_rom(5),
    rover_rom(6),
    rover_rom(7),
    rover_rom(8),
    rover_rom(9),
];

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn crc_of_the_datasheet_example() {
        assert_eq!(crc8(&[0x02, 0x1c, 0xb8, 0x01, 0x00, 0x00, 0x00]), 0xa2);
    }

    #[test]
    fn rover_roms_have_the_reference_byte_1_and_a_valid_crc() {
        for (i, rom) in ROVER_SENSOR_ROMS.iter().enumerate() {
            assert_eq!(rom[0], 0x10);
            assert_eq!(rom[1], BYTE1[i]);
            assert_eq!(crc8(rom), 0, "sensor {i}");
        }
        assert_eq!(
            ROVER_SENSOR_ROMS[0][..7],
            [0x10, 0x9c, 0x3a, 0x02, 0x08, 0x00, 0x00]
        );
    }
}
