//! Emulator tests of the harness's ADC inputs and reference voltage.

use harness::Avr;

/// Reads the next complete scan line `A v0 .. v7` printed by fixture_adc.
fn next_scan(avr: &mut Avr) -> Vec<u16> {
    // Drop any partial line, then take the next whole one.
    avr.uart_take();
    avr.uart_read_until(b"\n", 50_000).unwrap();
    let line = avr.uart_read_until(b"\r\n", 50_000).unwrap();
    let text = String::from_utf8(line).unwrap();
    let mut words = text.split_whitespace();
    assert_eq!(words.next(), Some("A"), "{text:?}");
    words.map(|w| w.parse().unwrap()).collect()
}

#[test]
fn half_reference_reads_mid_scale() {
    let mut avr = Avr::firmware("fixture_adc").unwrap();
    avr.set_adc_mv(0, 2500);
    let scan = next_scan(&mut avr);
    assert_eq!(scan.len(), 8);
    assert!((511..=512).contains(&scan[0]), "{scan:?}");
}

#[test]
fn every_channel_reads_its_own_input() {
    let mut avr = Avr::firmware("fixture_adc").unwrap();
    let mv = [0, 625, 1250, 1875, 2500, 3125, 3750, 5000];
    for (ch, &v) in mv.iter().enumerate() {
        avr.set_adc_mv(ch as u8, v);
    }
    let scan = next_scan(&mut avr);
    let expected: Vec<u16> = mv
        .iter()
        .map(|&v| (v * 1024 / 5000).min(1023) as u16)
        .collect();
    for (got, want) in scan.iter().zip(&expected) {
        assert!(got.abs_diff(*want) <= 1, "{scan:?} vs {expected:?}");
    }
    assert_eq!(scan[0], 0);
    assert_eq!(scan[7], 1023);
}

#[test]
fn reference_voltage_scales_readings() {
    let mut avr = Avr::firmware("fixture_adc").unwrap();
    avr.set_reference_mv(2500, 2500);
    avr.set_adc_mv(3, 1250);
    let scan = next_scan(&mut avr);
    assert!((511..=512).contains(&scan[3]), "{scan:?}");
}
