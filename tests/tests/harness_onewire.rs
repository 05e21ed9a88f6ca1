//! Emulator tests of the OneWire sensor model: the `fixture_onewire` firmware searches,
//! converts and reads the rover's ten DS18S20s on D6, with exact ROMs, scratchpads and
//! temperatures, and no timing violation.

use harness::onewire::{crc8, OneWireBus, ROVER_SENSOR_ROMS};
use harness::Avr;
use shared::master::temperature::{
    reading, register_raw, Sensors, SENSORS as SENSOR_COUNT, SENSOR_ROM_BYTE1,
};

/// Emulated time allowed for one pass of the fixture.
const PASS_US: u64 = 3_000_000;

/// What one pass of the fixture printed.
#[derive(Debug, Default)]
struct Pass {
    roms: Vec<[u8; 8]>,
    conv_polls: Option<u32>,
    /// (ROM, rest of the line after it).
    readings: Vec<([u8; 8], String)>,
}

fn hex_bytes<const N: usize>(s: &str) -> [u8; N] {
    let mut out = [0u8; N];
    for (i, b) in out.iter_mut().enumerate() {
        *b = u8::from_str_radix(&s[2 * i..2 * i + 2], 16).unwrap();
    }
    out
}

/// Runs the fixture until the end of its next pass and parses what it printed.
fn next_pass(avr: &mut Avr) -> Pass {
    let text = avr.uart_read_until(b"end\r\n", PASS_US).unwrap();
    parse(&String::from_utf8(text).unwrap())
}

/// Parses one pass of the fixture's output.
fn parse(text: &str) -> Pass {
    let mut pass = Pass::default();
    let mut count = None;
    for line in text.lines() {
        let mut words = line.split(' ');
        match (words.next(), words.next()) {
            (Some(n), None) if n.starts_with("n=") => count = Some(n[2..].parse().unwrap()),
            (Some("rom"), Some(rom)) => pass.roms.push(hex_bytes(rom)),
            (Some("conv"), Some(polls)) => pass.conv_polls = Some(polls.parse().unwrap()),
            (Some("t"), Some(rom)) => {
                let rest = words.collect::<Vec<_>>().join(" ");
                pass.readings.push((hex_bytes(rom), rest));
            }
            _ => {}
        }
    }
    assert_eq!(count, Some(pass.roms.len()), "{text}");
    pass
}

/// The ROMs in the order the search finds them: ascending, read as 64-bit numbers LSB
/// first.
fn search_order(roms: &[[u8; 8]]) -> Vec<[u8; 8]> {
    let mut sorted = roms.to_vec();
    sorted.sort_by_key(|r| u64::from_le_bytes(*r).reverse_bits());
    sorted
}

/// The scratchpad a DS18S20 holds after measuring `half` half degrees.
fn pad(half: i16) -> [u8; 9] {
    let [lo, hi] = half.to_le_bytes();
    let count_remain = if half & 1 == 0 { 0x0c } else { 0x04 };
    let mut p = [lo, hi, 0x4b, 0x46, 0xff, 0xff, count_remain, 0x10, 0];
    p[8] = crc8(&p[..8]);
    p
}

fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

fn fixture() -> (Avr, OneWireBus) {
    let mut avr = Avr::firmware("fixture_onewire").unwrap();
    let bus = OneWireBus::attach_rover_sensors(&mut avr);
    // The fixture polls read slots while the sensors convert, which only externally
    // powered sensors allow (the master firmware powers them instead: master_temperature).
    bus.set_parasite_power(false);
    avr.uart_read_until(b"ready\r\n", 10_000).unwrap();
    (avr, bus)
}

#[test]
fn the_rover_roms_carry_the_byte_1_the_master_looks_for() {
    assert_eq!(ROVER_SENSOR_ROMS.len(), SENSOR_COUNT);
    for (rom, &byte1) in ROVER_SENSOR_ROMS.iter().zip(&SENSOR_ROM_BYTE1) {
        assert_eq!(rom[0], 0x10, "DS18S20 family");
        assert_eq!(rom[1], byte1);
        assert_eq!(crc8(rom), 0);
    }
}

#[test]
fn ten_sensors_are_found_converted_and_read_exactly() {
    let (mut avr, bus) = fixture();
    let halves: [i16; 10] = [50, 51, -50, -51, 0, 1, -1, 200, -110, 250];
    for (i, &h) in halves.iter().enumerate() {
        bus.set_half_degrees(i, h);
    }
    let pass = next_pass(&mut avr);
    assert_eq!(pass.roms, search_order(&ROVER_SENSOR_ROMS));
    // 750 ms of conversion, polled every ~1.07 ms (1 ms plus a 70-µs read slot).
    let polls = pass.conv_polls.unwrap();
    assert!((690..=705).contains(&polls), "{polls} polls");
    assert_eq!(pass.readings.len(), 10);
    let celsius = [
        "+25.0", "+25.5", "-25.0", "-25.5", "+0.0", "+0.5", "-0.5", "+100.0", "-55.0", "+125.0",
    ];
    for (rom, rest) in &pass.readings {
        let i = ROVER_SENSOR_ROMS.iter().position(|r| r == rom).unwrap();
        let want = format!("{} crc=ok T={}", hex(&pad(halves[i])), celsius[i]);
        assert_eq!(rest, &want, "sensor {i}");
    }
    assert!(bus.violations().is_empty(), "{:?}", bus.violations());
    let stats = bus.stats();
    assert_eq!(stats.conversions, 10);
    assert_eq!(stats.scratchpad_reads, 10);
    assert_eq!(stats.presence_pulses, stats.resets);
}

#[test]
fn the_masters_logic_locates_every_sensor_and_maps_its_reading() {
    let (mut avr, bus) = fixture();
    bus.set_conversion_us(5_000);
    for i in 0..10 {
        bus.set_half_degrees(i, 2 * i as i16 + 41);
    }
    let pass = next_pass(&mut avr);
    let mut sensors = Sensors::new();
    for rom in &pass.roms {
        assert!(sensors.push(*rom));
    }
    for i in 0..10u8 {
        assert_eq!(sensors.locate(i), Some(ROVER_SENSOR_ROMS[usize::from(i)]));
        let (_, rest) = pass
            .readings
            .iter()
            .find(|(rom, _)| *rom == ROVER_SENSOR_ROMS[usize::from(i)])
            .unwrap();
        let scratchpad: [u8; 9] = hex_bytes(&rest[..18]);
        let half = 2 * i16::from(i) + 41;
        assert_eq!(reading(&scratchpad), Ok(register_raw(half)));
    }
    assert_eq!(register_raw(41), 0x5665, "20.5 °C on the ambient sensor");
}

#[test]
fn before_any_conversion_a_sensor_reads_85_degrees() {
    let (mut avr, bus) = fixture();
    // Conversions never finish within a pass: the fixture gives up after 2000 polls.
    bus.set_conversion_us(10_000_000);
    let pass = next_pass(&mut avr);
    assert_eq!(pass.conv_polls, Some(2000));
    assert_eq!((pass.roms.len(), pass.readings.len()), (10, 10));
    for (_, rest) in &pass.readings {
        assert_eq!(rest, &format!("{} crc=ok T=+85.0", hex(&pad(170))));
    }
}

#[test]
fn a_removed_sensor_is_missing_from_the_next_search_and_back_after_reinsertion() {
    let (mut avr, bus) = fixture();
    bus.set_conversion_us(5_000);
    assert_eq!(next_pass(&mut avr).roms.len(), 10);
    bus.set_present(4, false);
    let pass = next_pass(&mut avr);
    let expected: Vec<[u8; 8]> = search_order(&ROVER_SENSOR_ROMS)
        .into_iter()
        .filter(|r| *r != ROVER_SENSOR_ROMS[4])
        .collect();
    assert_eq!(pass.roms, expected);
    assert_eq!(pass.readings.len(), 9);
    bus.set_present(4, true);
    assert_eq!(next_pass(&mut avr).roms.len(), 10);
    assert!(bus.violations().is_empty(), "{:?}", bus.violations());
}

#[test]
fn a_sensor_removed_after_the_search_reads_as_all_ones() {
    let (mut avr, bus) = fixture();
    bus.set_conversion_us(5_000);
    next_pass(&mut avr);
    // Let the next pass's search finish, then pull sensor 0 before its scratchpad read.
    let mut text = avr.uart_read_until(b"conv ", PASS_US).unwrap();
    bus.set_present(0, false);
    text.extend(avr.uart_read_until(b"end\r\n", PASS_US).unwrap());
    let pass = parse(&String::from_utf8(text).unwrap());
    assert_eq!(pass.roms.len(), 10, "found before it was pulled");
    let (_, rest) = pass
        .readings
        .iter()
        .find(|(rom, _)| *rom == ROVER_SENSOR_ROMS[0])
        .unwrap();
    // Nine other sensors still answer the reset, so the presence pulse comes; the
    // MATCH ROM selects nobody and every read slot reads 1.
    assert_eq!(rest, "ffffffffffffffffff crc=bad");
}

#[test]
fn an_empty_bus_has_no_presence_pulse() {
    let mut avr = Avr::firmware("fixture_onewire").unwrap();
    let bus = OneWireBus::attach(&mut avr, harness::uno::D6).unwrap();
    assert!(bus.is_empty());
    let pass = next_pass(&mut avr);
    assert!(pass.roms.is_empty());
    assert_eq!(pass.conv_polls, None);
    assert_eq!(bus.stats().presence_pulses, 0);
    assert!(bus.line_high(), "released and pulled up");
}

#[test]
fn a_chip_reset_in_the_middle_of_a_pass_is_survived() {
    let (mut avr, bus) = fixture();
    bus.set_conversion_us(5_000);
    bus.set_half_degrees(2, -7);
    // Reset in the middle of the search.
    avr.run_us(40_000);
    avr.reset();
    avr.uart_read_until(b"ready\r\n", 10_000).unwrap();
    let pass = next_pass(&mut avr);
    assert_eq!(pass.roms, search_order(&ROVER_SENSOR_ROMS));
    let (_, rest) = pass
        .readings
        .iter()
        .find(|(rom, _)| *rom == ROVER_SENSOR_ROMS[2])
        .unwrap();
    assert_eq!(rest, &format!("{} crc=ok T=-3.5", hex(&pad(-7))));
    assert!(bus.violations().is_empty(), "{:?}", bus.violations());
}

#[test]
fn the_handle_may_outlive_its_chip() {
    let (mut avr, bus) = fixture();
    avr.run_us(10_000);
    let resets = bus.stats().resets;
    assert!(resets > 0);
    drop(avr);
    assert_eq!(bus.len(), 10);
    assert_eq!(bus.stats().resets, resets);
    bus.set_half_degrees(0, 10);
    assert_eq!(bus.scratchpad(0), Some(pad(170)), "never converted");
    assert_eq!(bus.rom(0), Some(ROVER_SENSOR_ROMS[0]));
}
