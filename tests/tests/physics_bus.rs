//! Emulator test of the physics loop closer around several chips on one I²C bus: two
//! `fixture_motor` chips, one closed over wheel 1's drive/steer board and one over pair
//! 0's lift/lift board, run in lock step by the bus while the plant feeds each its own
//! encoder edges and ADC millivolts.

use harness::bus::Bus;
use harness::Avr;
use physics::bridge::Bridge;
use physics::drive::DriveParams;
use physics::emulator::Plant;
use physics::wheel::SlaveBoardModel;

/// The fixture's 100-ms reports seen so far on one chip: (N, N_B, ADC0, ADC1, ADC6, ADC7).
type Report = [u32; 6];

/// Parses `W n nb a0 a1 a6 a7`.
fn parse(line: &str) -> Option<Report> {
    let mut words = line.split_whitespace();
    if words.next()? != "W" {
        return None;
    }
    let v: Vec<u32> = words.map(|w| w.parse().ok()).collect::<Option<_>>()?;
    v.try_into().ok()
}

/// Runs the plant until each chip has sent `count` reports after this call.
fn reports(plant: &mut Plant, bus: &mut Bus, count: usize) -> [Vec<Report>; 2] {
    let mut text: [Vec<u8>; 2] = Default::default();
    let mut got: [Vec<Report>; 2] = Default::default();
    let mut started = [false; 2];
    for (chip, s) in started.iter_mut().enumerate() {
        let taken = bus.chip(chip).unwrap().uart_take();
        *s = taken.last().is_none_or(|&b| b == b'\n');
    }
    let done = plant
        .run_until(bus, 100_000 * count as u64 + 250_000, |bus| {
            for chip in 0..2 {
                text[chip].extend(bus.chip(chip).unwrap().uart_take());
                while let Some(end) = text[chip].iter().position(|&b| b == b'\n') {
                    let line: Vec<u8> = text[chip].drain(..=end).collect();
                    if started[chip] {
                        got[chip].extend(parse(&String::from_utf8_lossy(&line)));
                    }
                    started[chip] = true;
                }
            }
            got.iter().all(|g| g.len() >= count)
        })
        .unwrap();
    assert!(done, "{got:?}");
    got
}

#[test]
fn two_chips_on_a_bus_each_close_their_own_loop() {
    let mut bus = Bus::new();
    let ds = bus
        .add_slave(Avr::firmware("fixture_motor").unwrap())
        .unwrap();
    let ll = bus
        .add_slave(Avr::firmware("fixture_motor").unwrap())
        .unwrap();
    let mut plant = Plant::new();
    plant.attach(ds, SlaveBoardModel::for_controller(1).unwrap());
    plant.attach(ll, SlaveBoardModel::for_controller(3).unwrap());
    plant.run_us(&mut bus, 1_000).unwrap();

    // Wheel 1's drive forward at half duty; lift ONE up, lift TWO down, full duty.
    bus.uart_send(ds, b"M1F\x80");
    bus.uart_send(ll, b"M1F\xffM2R\xff");
    plant.run_us(&mut bus, 400_000).unwrap();
    let first = reports(&mut plant, &mut bus, 5);
    let later = reports(&mut plant, &mut bus, 1);

    let bridge = Bridge::forward(f64::from(128.0f32 / 255.0));
    let expected = DriveParams::default().steady_ticks_per_s(&bridge, 0.0);
    let counted: u32 = first[ds].iter().map(|r| r[0]).sum();
    let rate = f64::from(counted) / 0.5;
    assert!(
        (rate - expected).abs() / expected < 0.01,
        "{rate} vs {expected}"
    );
    assert!(first[ds].iter().all(|r| r[1] == 0), "{first:?}");

    // The lift board has no encoder: its chip sees no edge at all.
    assert!(first[ll].iter().all(|r| r[0] == 0), "{first:?}");
    // Lift ONE's pot (ADC6) rises and lift TWO's (ADC7) falls, at 20 °/s each.
    let (one0, two0) = (first[ll][0][4], first[ll][0][5]);
    let (one1, two1) = (later[ll][0][4], later[ll][0][5]);
    assert!(one1 > one0 && two1 < two0, "{first:?} {later:?}");
    let model = plant.model(ll).unwrap().ll().unwrap();
    // About 1.1 s of travel at 20 °/s since the commands.
    let (one, two) = (model.one.motor.angle_deg(), model.two.motor.angle_deg());
    assert!(
        (18.0..26.0).contains(&one) && (-26.0..-18.0).contains(&two),
        "{one} {two}"
    );
    // Lift currents: moving at friction current, 0.35 A = 35 counts.
    assert!((33..=35).contains(&later[ll][0][2]), "{later:?}");
}
