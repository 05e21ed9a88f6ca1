//! The master's temperature sensors in the emulator (reference §9.1): the rover's ten
//! DS18S20s on D6, found at boot; each tick (every 2 s from 5 s) reads one and starts a
//! conversion on the next, so after 2·D s every TEMP register holds map(T) over
//! −20..100. A sensor missing from the bus raises type 10 on the master, spread to all
//! nine slaves; one that stops answering after boot reads as no reading until it is back.

mod master_support;

use harness::onewire::OneWireBus;
use harness::Avr;
use master_support::{Options, Rig};

/// Reference §3: raw = trunc(((T + 20)·65534)/120) in float32.
fn expected_raw(half_degrees: i16) -> u16 {
    let t = (f32::from(half_degrees) / 2.0).clamp(-20.0, 100.0);
    (((t + 20.0) * 65534.0) / 120.0) as u16
}

/// Puts REGMASTER_TEMPSREAD (id 14, new) in read set 3.
fn select_tempsread(avr: &mut Avr) {
    avr.uart_send(&[0x04, 0x04, 0x03, 14]);
    assert_eq!(avr.uart_read_exact(1, 100_000).unwrap(), [1]);
}

/// Reads set 3: REGMASTER_TEMPSREAD's two bytes.
fn read_tempsread(avr: &mut Avr) -> Vec<u8> {
    avr.uart_send(&[0x03, 0x03, 0x03]);
    avr.uart_read_exact(2, 100_000).unwrap()
}

/// D = 10: sensor 9 is read by the tenth tick, at about 5 + 9·2 s; by 24 s more every
/// sensor's bit is set.
fn all_ten_read_after_2_d_seconds(avr: &mut Avr) {
    avr.run_us(24_000_000);
    assert_eq!(read_tempsread(avr), [0xff, 0x03], "all ten sensors read");
}

/// Sensor temperatures set before boot, half degrees (the others stay at 20.0 °C).
const SET: [(usize, i16); 5] = [(0, 45), (1, 43), (4, -11), (7, 130), (9, 250)];

#[test]
fn set_2_holds_every_sensor_after_2_d_seconds() {
    let mut avr = Avr::firmware("master").unwrap();
    let sensors = OneWireBus::attach_rover_sensors(&mut avr);
    for (i, half) in SET {
        sensors.set_half_degrees(i, half);
    }
    avr.uart_read_until(b"Ready\r\n", 2_000_000).unwrap();
    // No sensor read yet at boot.
    select_tempsread(&mut avr);
    assert_eq!(read_tempsread(&mut avr), [0, 0]);
    all_ten_read_after_2_d_seconds(&mut avr);
    avr.uart_send(&[0x0e, 0x04, 0x02, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11]);
    assert_eq!(avr.uart_read_exact(1, 100_000).unwrap(), [11]);
    avr.uart_send(&[0x03, 0x03, 0x02]);
    let reply = avr.uart_read_exact(22, 100_000).unwrap();
    let mut half = [40i16; 10];
    for (i, h) in SET {
        half[i] = h;
    }
    for (i, &h) in half.iter().enumerate() {
        let raw = u16::from_le_bytes([reply[2 * i], reply[2 * i + 1]]);
        assert_eq!(raw, expected_raw(h), "sensor {i} at {h} half degrees");
    }
    // Two of them against reference §3's worked example and the range's top.
    assert_eq!(&reply[2..4], &[0x87, 0x58], "21.5 °C");
    assert_eq!(&reply[18..20], &[0xfe, 0xff], "125 °C clamps to 100");
    assert!(
        sensors.violations().is_empty(),
        "{:?}",
        sensors.violations()
    );
    let stats = sensors.stats();
    println!("OneWire: {stats:?}");
}

#[test]
fn the_fastest_sensors_are_all_found_while_serial_bytes_interrupt_the_search() {
    // A presence pulse may start 15 µs after the reset and last 60 µs: low for certain
    // only from 60 to 75 µs. A byte every ~95 µs runs the receive handler throughout the
    // boot's search, so a single sample at 70 µs would often come too late.
    let mut avr = Avr::firmware("master").unwrap();
    let sensors = OneWireBus::attach_rover_sensors(&mut avr);
    sensors.set_presence_us(15, 60);
    avr.uart_send(&[0xff; 4000]);
    avr.uart_read_until(b"Ready\r\n", 2_000_000).unwrap();
    let resets = sensors.stats().resets;
    assert!(
        resets >= 11,
        "ten search passes and the last one's end: {resets}"
    );
    // Let the line go quiet, so that the master takes the next byte as a frame's length.
    avr.uart_discard_input();
    avr.run_us(100_000);
    avr.uart_take();
    // Every sensor was found: each tick reads one, none is missing (no type 10), and
    // after 2·D s all ten are marked read.
    select_tempsread(&mut avr);
    all_ten_read_after_2_d_seconds(&mut avr);
    assert!(
        sensors.violations().is_empty(),
        "{:?}",
        sensors.violations()
    );
}

#[test]
fn a_missing_sensor_raises_type_10_and_spreads_it_to_all_nine() {
    // Controller 1's sensor is off the bus: the first tick (at 5 s) reads the ambient
    // sensor and needs sensor 1 for its conversion.
    let mut rig = Rig::with(Options {
        absent: &[1],
        ..Options::default()
    });
    rig.reset_master();
    rig.clear_records();
    rig.run_to(5_300_000);
    assert_eq!(rig.master_exception(), 0x000a);
    // The missing sensor is never marked read (REGMASTER_TEMPSREAD bit 1 stays clear).
    let read = rig.master_regs(&[14], 2);
    assert_eq!(read[0] & 0b10, 0, "sensor 1 never read: {read:02x?}");
    for addr in 1..=9 {
        let s = rig.slave(addr);
        assert_eq!(
            s.writes_to(0x05),
            vec![vec![0x64, 0x00]],
            "slave {addr} gets the spreading write"
        );
    }
}

/// TEMP1 and REGMASTER_TEMPSREAD.
fn temp1_and_read_bits(rig: &mut Rig) -> (u16, u16) {
    let v = rig.master_regs(&[2, 14], 4);
    (
        u16::from_le_bytes([v[0], v[1]]),
        u16::from_le_bytes([v[2], v[3]]),
    )
}

/// Runs in steps of 0.5 s, up to `limit_s`, until `done` holds for TEMP1 and the read
/// bits; returns them and the seconds it took.
fn run_until(
    rig: &mut Rig,
    limit_s: u32,
    done: impl Fn(u16, u16) -> bool,
) -> Option<(u16, u16, f64)> {
    for half_s in 1..=2 * limit_s {
        rig.run_us(500_000);
        let (temp, bits) = temp1_and_read_bits(rig);
        if done(temp, bits) {
            return Some((temp, bits, f64::from(half_s) / 2.0));
        }
    }
    None
}

#[test]
fn a_sensor_unplugged_after_boot_reads_as_no_reading_until_it_is_back() {
    let mut rig = Rig::with(Options {
        temps: &[(1, 43)],
        ..Options::default()
    });
    rig.reset_master();
    // The second tick (about 7 s) reads sensor 1.
    let (temp, _, _) = run_until(&mut rig, 10, |_, bits| bits & 0b10 != 0)
        .expect("sensor 1 read within 10 s of boot");
    assert_eq!(temp, expected_raw(43), "21.5 °C");
    // Unplugged: its next turn comes ten ticks (about 20 s) later. Until then the last
    // reading stands; then the register shows no reading, 0.0 °C with its bit clear,
    // while the other sensors stay read.
    let sensors = rig.sensors.as_ref().expect("sensors attached");
    sensors.set_present(1, false);
    let (temp, bits, gone) = run_until(&mut rig, 30, |_, bits| bits & 0b10 == 0)
        .expect("sensor 1's bit cleared within 30 s of the unplug");
    assert!(
        (18.0..=22.0).contains(&gone),
        "cleared {gone} s after the unplug"
    );
    assert_eq!(temp, 0x2aaa, "0.0 °C, the value of no reading");
    assert_eq!(bits, 0x3ff & !0b10, "every other sensor read");
    // A sensor found at boot raises no exception when it goes (as the original).
    assert_eq!(rig.master_exception(), 0);
    // Back on the line: its next turn reads it again.
    let sensors = rig.sensors.as_ref().expect("sensors attached");
    sensors.set_present(1, true);
    let (temp, bits, back) = run_until(&mut rig, 30, |_, bits| bits & 0b10 != 0)
        .expect("sensor 1 read again within 30 s");
    assert!(back <= 22.0, "read again {back} s after the replug");
    assert_eq!(temp, expected_raw(43));
    assert_eq!(bits, 0x3ff);
    println!("sensor 1 unplugged: no reading {gone} s later; back in: read again {back} s later");
}
