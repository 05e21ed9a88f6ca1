//! Temperature sensors: conversion, integer mapping, CRC, ROM search and polling order.

use shared::exception::MasterLatch;
use shared::mapping;
use shared::master::ping::{Action, Outcome, Schedule};
use shared::master::temperature::{
    crc8, half_degrees, reading, register_raw, Poller, ReadingError, Rom, RomSearch, SearchError,
    Sensors, SENSOR_ROM_BYTE1,
};
use shared::regs::{id, BoardKind};

fn temp_register() -> &'static shared::regs::Register {
    BoardKind::Master.register(id::REGMASTER_TEMP1).unwrap()
}

/// The original's float conversion: T = sign·(⌊|raw|/2⌋ + 0.5·(byte0 & 1)).
fn original_celsius(lsb: u8, msb: u8) -> f32 {
    let raw = i32::from(i16::from_le_bytes([lsb, msb]));
    let magnitude = (raw.abs() / 2) as f32 + 0.5 * f32::from(lsb & 1);
    if raw < 0 {
        -magnitude
    } else {
        magnitude
    }
}

#[test]
fn integer_mapping_equals_the_float_mapping_for_every_half_degree_from_minus_60_to_130() {
    let reg = temp_register();
    for half in -120i16..=260 {
        let t = f32::from(half) / 2.0;
        assert_eq!(register_raw(half), mapping::map(t, reg), "{t} °C");
    }
}

#[test]
fn integer_mapping_equals_the_float_path_for_every_scratchpad_value() {
    let reg = temp_register();
    for raw in i16::MIN..=i16::MAX {
        let [lsb, msb] = raw.to_le_bytes();
        assert_eq!(half_degrees(lsb, msb), raw);
        assert_eq!(
            register_raw(raw),
            mapping::map(original_celsius(lsb, msb), reg),
            "raw {raw:#06x}"
        );
    }
}

#[test]
fn reference_conversion_examples() {
    assert_eq!(half_degrees(0x32, 0x00), 50, "25.0 °C");
    assert_eq!(half_degrees(0x33, 0x00), 51, "25.5 °C");
    assert_eq!(half_degrees(0xce, 0xff), -50, "-25.0 °C");
    assert_eq!(original_celsius(0xcd, 0xff), -25.5);
    assert_eq!(register_raw(0), 0x2aaa, "0.0 °C");
    assert_eq!(register_raw(43), 0x5887, "21.5 °C");
    assert_eq!(register_raw(-40), 0, "-20 °C is the bottom");
    assert_eq!(register_raw(-41), 0, "below the range clamps");
    assert_eq!(register_raw(200), 65534, "100 °C is the top");
    assert_eq!(register_raw(i16::MAX), 65534);
}

#[test]
fn crc8_matches_the_datasheet_example_and_checks_scratchpads() {
    // The Maxim application note's ROM: 02 1C B8 01 00 00 00, CRC A2.
    assert_eq!(crc8(&[0x02, 0x1c, 0xb8, 0x01, 0x00, 0x00, 0x00]), 0xa2);
    assert_eq!(
        crc8(&[0x02, 0x1c, 0xb8, 0x01, 0x00, 0x00, 0x00, 0xa2]),
        0,
        "a block ending in its CRC has CRC 0"
    );
    let mut pad = [0x32, 0x00, 0x4b, 0x46, 0xff, 0xff, 0x0c, 0x10, 0];
    pad[8] = crc8(&pad[..8]);
    assert_eq!(reading(&pad), Ok(register_raw(50)));
    pad[0] = 0x33;
    assert_eq!(reading(&pad), Err(ReadingError::BadCrc));
    assert_eq!(
        reading(&[0xff; 9]),
        Err(ReadingError::BadCrc),
        "a sensor that stopped answering reads all ones"
    );
}

/// A ROM with family 0x10, the given byte 1 and a valid CRC.
fn rom(byte1: u8, rest: u8) -> Rom {
    let mut r = [0x10, byte1, rest, 0x08, 0x00, 0x00, 0x00, 0];
    r[7] = crc8(&r[..7]);
    r
}

fn rom_bit(r: &Rom, i: u8) -> bool {
    r[usize::from(i / 8)] & (1 << (i % 8)) != 0
}

/// Runs full search passes against devices on a simulated wired-AND bus.
fn search_all(devices: &[Rom]) -> Result<Vec<Rom>, SearchError> {
    let mut search = RomSearch::new();
    let mut found = Vec::new();
    while !search.finished() {
        let mut taking_part: Vec<&Rom> = devices.iter().collect();
        for i in 0..64u8 {
            let bit = taking_part.iter().all(|r| rom_bit(r, i));
            let complement = taking_part.iter().all(|r| !rom_bit(r, i));
            let direction = search.step(i, bit, complement)?;
            taking_part.retain(|r| rom_bit(r, i) == direction);
        }
        found.push(search.finish()?);
    }
    Ok(found)
}

#[test]
fn the_search_finds_every_device_in_ascending_bit_order() {
    let devices: Vec<Rom> = SENSOR_ROM_BYTE1
        .iter()
        .enumerate()
        .map(|(i, &b)| rom(b, 0x40 + i as u8))
        .collect();
    let found = search_all(&devices).unwrap();
    let mut expected = devices.clone();
    expected.sort_by_key(|r| u64::from_le_bytes(*r).reverse_bits());
    assert_eq!(found, expected);
    assert_eq!(found.len(), 10);
}

#[test]
fn the_search_reports_an_empty_bus_and_a_single_device() {
    assert_eq!(search_all(&[]), Err(SearchError::NoDevice));
    let one = rom(0x9c, 1);
    assert_eq!(search_all(&[one]).unwrap(), vec![one]);
    let mut done = RomSearch::new();
    for i in 0..64 {
        done.step(i, rom_bit(&one, i), !rom_bit(&one, i)).unwrap();
    }
    assert_eq!(done.finish(), Ok(one));
    assert_eq!(done.step(0, true, false), Err(SearchError::Finished));
}

#[test]
fn a_corrupted_search_pass_is_reported() {
    let mut bad = rom(0x20, 3);
    bad[7] ^= 1;
    assert_eq!(search_all(&[bad]), Err(SearchError::BadCrc));
}

fn all_sensors() -> Sensors {
    let mut s = Sensors::new();
    // Discovery order differs from sensor order: byte 1 decides.
    for (i, &b) in SENSOR_ROM_BYTE1.iter().enumerate().rev() {
        assert!(s.push(rom(b, i as u8)));
    }
    s
}

#[test]
fn sensors_are_located_by_rom_byte_1_and_extra_devices_are_ignored() {
    let mut s = all_sensors();
    assert_eq!(s.count(), 10);
    for (i, &b) in SENSOR_ROM_BYTE1.iter().enumerate() {
        assert_eq!(s.locate(i as u8), Some(rom(b, i as u8)));
    }
    assert!(!s.push(rom(0x11, 0)), "an eleventh device is ignored");
    assert_eq!(s.count(), 10);
    assert_eq!(s.locate(10), None);
}

#[test]
fn each_tick_reads_sensor_i_and_converts_sensor_i_plus_1() {
    let s = all_sensors();
    let mut p = Poller::new();
    assert_eq!(p.first_conversion(&s), s.locate(0));
    let mut order = Vec::new();
    for _ in 0..12 {
        let t = p.tick(&s);
        assert_eq!(t.missing, None);
        let (r, _) = t.read.unwrap();
        let (c, rom) = t.convert.unwrap();
        assert_eq!(c, (r + 1) % 10);
        assert_eq!(rom[1], SENSOR_ROM_BYTE1[usize::from(c)]);
        order.push(r);
    }
    assert_eq!(order, [0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 0, 1]);
}

#[test]
fn with_fewer_devices_ids_at_or_above_d_are_never_read_and_a_missing_one_raises() {
    // Seven devices: ambient and controllers 1, 2, 4, 5, 6, 9; controller 3's is missing.
    let mut s = Sensors::new();
    for i in [0usize, 1, 2, 4, 5, 6, 9] {
        s.push(rom(SENSOR_ROM_BYTE1[i], i as u8));
    }
    assert_eq!(s.count(), 7);
    let mut p = Poller::new();
    let ticks: Vec<_> = (0..8).map(|_| p.tick(&s)).collect();
    let reads: Vec<Option<u8>> = ticks.iter().map(|t| t.read.map(|(i, _)| i)).collect();
    assert_eq!(
        reads,
        [
            Some(0),
            Some(1),
            Some(2),
            None,
            Some(4),
            Some(5),
            Some(6),
            Some(0)
        ]
    );
    let missing: Vec<Option<u8>> = ticks.iter().map(|t| t.missing).collect();
    assert_eq!(
        missing,
        [None, None, Some(3), Some(3), None, None, None, None],
        "converting and reading sensor 3 both find it missing"
    );
    assert_eq!(ticks[2].convert, None);
    assert_eq!(ticks[0].exception(), None);
    let e = ticks[3].exception().unwrap();
    assert_eq!(e.data(), 0x000a, "type 10, slave 0, motor 0");
}

#[test]
fn a_missing_sensor_is_latched_and_spread_to_all_nine_slaves() {
    let mut s = Sensors::new();
    s.push(rom(SENSOR_ROM_BYTE1[0], 0)); // only the ambient sensor
    let mut poller = Poller::new();
    let mut schedule = Schedule::new();
    let mut latch = MasterLatch::boot();
    latch.clear();
    // Past the boot resets.
    while let Some(Action::WriteReg(_)) = schedule.poll(0) {
        schedule.feed(Outcome::Done, &mut latch);
    }
    let tick = poller.tick(&s);
    assert_eq!(tick.read.map(|(i, _)| i), Some(0));
    assert_eq!(
        tick.convert.map(|(i, _)| i),
        Some(0),
        "D = 1 wraps to sensor 0"
    );
    assert_eq!(tick.exception(), None, "ids at or above D are never read");
    let mut none = Sensors::new();
    let tick = poller.tick(&none);
    assert!(schedule.raise(tick.exception().unwrap(), &mut latch));
    assert_eq!(latch.data(), 0x000a);
    let mut spread = Vec::new();
    schedule.run(1, &mut latch, |a| {
        if let Action::WriteReg(w) = a {
            spread.push((w.device, w.id, w.raw()));
        }
        Outcome::Done
    });
    let expected: Vec<(u8, u8, u16)> = (1..=9).map(|d| (d, id::REG_EXCEPTIONDATA, 100)).collect();
    assert_eq!(spread, expected);
    none.push(rom(SENSOR_ROM_BYTE1[0], 0));
    assert_eq!(poller.tick(&none).exception(), None, "back on the bus");
}

#[test]
fn no_devices_at_all_makes_every_tick_report_the_ambient_sensor_missing() {
    let s = Sensors::new();
    let mut p = Poller::new();
    for _ in 0..3 {
        let t = p.tick(&s);
        assert_eq!((t.read, t.convert, t.missing), (None, None, Some(0)));
    }
    assert_eq!(p.first_conversion(&s), None);
}
