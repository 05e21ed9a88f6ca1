//! The master's temperature sensors in the emulator (reference §9.1): the rover's ten
//! DS18S20s on D6, found at boot; each tick (every 2 s from 5 s) reads one and starts a
//! conversion on the next, so after 2·D s every TEMP register holds map(T) over
//! −20..100. A sensor missing from the bus raises type 10 on the master, spread to all
//! nine slaves.

mod master_support;

use harness::onewire::OneWireBus;
use harness::Avr;
use master_support::{Options, Rig};

/// Reference §3: raw = trunc(((T + 20)·65534)/120) in float32.
fn expected_raw(half_degrees: i16) -> u16 {
    let t = (f32::from(half_degrees) / 2.0).clamp(-20.0, 100.0);
    (((t + 20.0) * 65534.0) / 120.0) as u16
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
    // REGMASTER_TEMPSREAD (id 14, new) in set 3: no sensor read yet at boot.
    avr.uart_send(&[0x04, 0x04, 0x03, 14]);
    assert_eq!(avr.uart_read_exact(1, 100_000).unwrap(), [1]);
    avr.uart_send(&[0x03, 0x03, 0x03]);
    assert_eq!(avr.uart_read_exact(2, 100_000).unwrap(), [0, 0]);
    // D = 10: sensor 9 is read by the tenth tick, at about 5 + 9·2 s.
    avr.run_us(24_000_000);
    avr.uart_send(&[0x03, 0x03, 0x03]);
    assert_eq!(
        avr.uart_read_exact(2, 100_000).unwrap(),
        [0xff, 0x03],
        "all ten sensors read"
    );
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
