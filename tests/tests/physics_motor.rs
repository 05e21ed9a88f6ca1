//! Emulator tests of the physics loop closer around one chip running `fixture_motor`, a
//! stand-in for the slave's motor stage (Timer1 PWM on D9/D10, direction pins, the PD0
//! encoder interrupt, ADC0/1/6/7), with the drive/steer board model of wheel 1.

use harness::Avr;
use physics::bridge::Bridge;
use physics::drive::DriveParams;
use physics::emulator::Plant;
use physics::gearmotor::EndStop;
use physics::wheel::{Motor, SlaveBoardModel};

/// One 100-ms report of the fixture.
#[derive(Debug, Clone, Copy)]
struct Window {
    /// A rising edges.
    n: u32,
    /// A rising edges with B high.
    nb: u32,
    /// ADC0, ADC1, ADC6, ADC7 readings.
    adc: [u32; 4],
}

/// Parses `W n nb a0 a1 a6 a7`.
fn parse(line: &str) -> Option<Window> {
    let mut words = line.split_whitespace();
    if words.next()? != "W" {
        return None;
    }
    let v: Vec<u32> = words.map(|w| w.parse().ok()).collect::<Option<_>>()?;
    (v.len() == 6).then(|| Window {
        n: v[0],
        nb: v[1],
        adc: [v[2], v[3], v[4], v[5]],
    })
}

/// Runs the plant until `count` complete reports arrive after this call; returns them.
fn windows(plant: &mut Plant, avr: &mut Avr, count: usize) -> Vec<Window> {
    // A line cut by this take is skipped: only whole reports count.
    let taken = avr.uart_take();
    let mut started = taken.last().is_none_or(|&b| b == b'\n');
    let mut text = Vec::new();
    let mut got = Vec::new();
    let done = plant
        .run_until(avr, 100_000 * count as u64 + 250_000, |avr| {
            text.extend(avr.uart_take());
            while let Some(end) = text.iter().position(|&b| b == b'\n') {
                let line: Vec<u8> = text.drain(..=end).collect();
                if started {
                    got.extend(parse(&String::from_utf8_lossy(&line)));
                }
                started = true;
            }
            got.len() >= count
        })
        .unwrap();
    assert!(done, "only {} reports", got.len());
    got
}

/// Fixture chip and a plant with wheel 1's drive/steer board, booted.
fn rig() -> (Avr, Plant) {
    let mut avr = Avr::firmware("fixture_motor").unwrap();
    let mut plant = Plant::single(SlaveBoardModel::drive_steer(1, true).unwrap());
    let ready = avr.uart_read_until(b"motor ready\r\n", 50_000);
    assert!(ready.is_ok(), "{ready:?}");
    plant.run_us(&mut avr, 1_000).unwrap();
    (avr, plant)
}

/// Sends one motor command: motor b'1' or b'2', direction b'F'/b'R'/b'S'/b'B', raw duty.
fn command(avr: &mut Avr, motor: u8, dir: u8, duty: u8) {
    avr.uart_send(&[b'M', motor, dir, duty]);
}

/// The real chip's ADC reading for `mv`, minus simavr's rounding (it scales by 1023).
fn sim_reading(mv: f64) -> u32 {
    (mv.round() * 1023.0 / 5000.0) as u32
}

#[test]
fn half_duty_forward_runs_at_the_model_rate_and_the_chip_counts_every_tick() {
    let (mut avr, mut plant) = rig();
    command(&mut avr, b'1', b'F', 128);
    plant.run_us(&mut avr, 400_000).unwrap();
    let bridge = plant.model(0).unwrap().ds().unwrap().drive.bridge();
    assert_eq!(bridge, Bridge::forward(f64::from(128.0f32 / 255.0)));
    let expected = DriveParams::default().steady_ticks_per_s(&bridge, 0.0);
    assert!((1700.0..1730.0).contains(&expected), "{expected}");

    let reports = windows(&mut plant, &mut avr, 10);
    let counted: u32 = reports.iter().map(|w| w.n).sum();
    let error = (f64::from(counted) - expected).abs() / expected;
    assert!(
        error < 0.01,
        "chip counted {counted} ticks in 1 s, model {expected}"
    );
    let model_rate = plant.model(0).unwrap().ds().unwrap().drive.ticks_per_s();
    assert!((model_rate - expected).abs() < 0.5, "{model_rate}");
    for w in &reports {
        // Forward: B is low at every A rising edge, so the slave's speed is positive.
        assert_eq!(w.nb, 0, "{w:?}");
        assert!((165..=178).contains(&w.n), "{w:?}");
    }
}

#[test]
fn tick_rates_at_quarter_half_and_full_duty_match_the_model() {
    for duty in [64u8, 128, 255] {
        let (mut avr, mut plant) = rig();
        command(&mut avr, b'1', b'F', duty);
        plant.run_us(&mut avr, 300_000).unwrap();
        let bridge = Bridge::forward(f64::from(f32::from(duty) / 255.0));
        let expected = DriveParams::default().steady_ticks_per_s(&bridge, 0.0);
        let reports = windows(&mut plant, &mut avr, 5);
        let rate = f64::from(reports.iter().map(|w| w.n).sum::<u32>()) / 0.5;
        assert!(
            (rate - expected).abs() / expected < 0.01,
            "duty {duty}: chip {rate} ticks/s, model {expected}"
        );
        assert!(reports.iter().all(|w| w.nb == 0), "{reports:?}");
    }
}

#[test]
fn reversing_flips_b_phase() {
    let (mut avr, mut plant) = rig();
    command(&mut avr, b'1', b'R', 128);
    plant.run_us(&mut avr, 400_000).unwrap();
    let model_rate = plant.model(0).unwrap().ds().unwrap().drive.ticks_per_s();
    assert!(model_rate < -1700.0, "{model_rate}");
    let reports = windows(&mut plant, &mut avr, 3);
    for w in &reports {
        assert!(w.n > 160, "{w:?}");
        // Reverse: B is high at every A rising edge; the slave negates (N_B > ⌊N/3⌋).
        assert_eq!(w.nb, w.n, "{w:?}");
    }
    // Forward again: the phase flips back.
    command(&mut avr, b'1', b'F', 128);
    plant.run_us(&mut avr, 400_000).unwrap();
    let reports = windows(&mut plant, &mut avr, 2);
    assert!(
        reports.iter().all(|w| w.nb == 0 && w.n > 160),
        "{reports:?}"
    );
}

#[test]
fn stalling_the_wheel_stops_the_edges_and_raises_the_current() {
    let (mut avr, mut plant) = rig();
    command(&mut avr, b'1', b'F', 128);
    plant.run_us(&mut avr, 400_000).unwrap();
    let running = windows(&mut plant, &mut avr, 2);
    let running_current = running[1].adc[0];
    // Running current ≈ 0.28 A = 27 counts.
    assert!((20..35).contains(&running_current), "{running:?}");

    plant.model_mut(0).unwrap().set_stalled(Motor::M1, true);
    let stalled = windows(&mut plant, &mut avr, 3);
    // The report after the stall may hold edges from before it; later ones hold none.
    for w in &stalled[1..] {
        assert_eq!(w.n, 0, "{w:?}");
    }
    // Stall current at half duty: 6.02 V / 2.2 Ω = 2.74 A = 274 counts.
    let stall_mv = plant.model(0).unwrap().adc_mv()[0].unwrap();
    let reading = stalled[2].adc[0];
    assert_eq!(reading, sim_reading(stall_mv));
    assert!((268..=276).contains(&reading), "{stalled:?}");

    plant.model_mut(0).unwrap().set_stalled(Motor::M1, false);
    plant.run_us(&mut avr, 300_000).unwrap();
    let freed = windows(&mut plant, &mut avr, 1);
    assert!(freed[0].n > 160, "{freed:?}");
}

#[test]
fn an_injected_spike_shows_on_the_current_input_then_ends() {
    let (mut avr, mut plant) = rig();
    plant
        .model_mut(0)
        .unwrap()
        .sense_mut(Motor::M2)
        .inject_spike(4.0, 0.25);
    let during = windows(&mut plant, &mut avr, 1);
    assert_eq!(during[0].adc[1], sim_reading(4.0 * 5000.0 / 10.24));
    plant.run_us(&mut avr, 200_000).unwrap();
    let after = windows(&mut plant, &mut avr, 1);
    assert_eq!(after[0].adc[1], 0, "steer idle, spike over");
}

#[test]
fn the_steer_drives_to_its_end_stop_and_stops() {
    let (mut avr, mut plant) = rig();
    command(&mut avr, b'2', b'F', 255);
    // 60 °/s from 0° to the stop 5° inside CALIBMAX (65.20 − 5 = 60.20°): about 1 s.
    plant.run_us(&mut avr, 1_300_000).unwrap();
    let axis = &plant.model(0).unwrap().ds().unwrap().steer;
    assert_eq!(axis.motor.at_stop(), Some(EndStop::Max));
    let stop = axis.motor.angle_deg();
    assert!((stop - 60.197).abs() < 0.01, "{stop}");
    let pot = axis.pot;
    let reports = windows(&mut plant, &mut avr, 3);
    // Stopped: the pot reading no longer changes, and the slave's formula gives the stop.
    assert!(
        reports.iter().all(|w| w.adc[2] == reports[0].adc[2]),
        "{reports:?}"
    );
    let angle = f64::from(pot.firmware_angle(reports[0].adc[2] as u16));
    assert!(
        (angle - stop).abs() < 0.3,
        "firmware angle {angle}, stop {stop}"
    );
    // Driven into the stop: stall current 12 V / 4 Ω = 3 A = 300 counts.
    assert!((297..=300).contains(&reports[2].adc[1]), "{reports:?}");

    // Reverse leaves the stop and heads for the other one.
    command(&mut avr, b'2', b'R', 255);
    plant.run_us(&mut avr, 500_000).unwrap();
    let moving = windows(&mut plant, &mut avr, 2);
    assert!(moving[1].adc[2] < moving[0].adc[2], "{moving:?}");
    // Moving: the friction current, 0.2 A = 20 counts.
    assert!((18..=21).contains(&moving[1].adc[1]), "{moving:?}");
}

#[test]
fn pot_millivolts_give_the_firmware_the_physical_angle() {
    let (mut avr, mut plant) = rig();
    for angle in [-51.0, -30.0, 0.0, 12.5, 45.0, 60.0] {
        let board = plant.model_mut(0).unwrap().ds_mut().unwrap();
        board.steer.motor.set_angle_deg(angle);
        let pot = board.steer.pot;
        let w = windows(&mut plant, &mut avr, 1)[0];
        let fw = f64::from(pot.firmware_angle(w.adc[2] as u16));
        // One step of the real ADC (0.12°) plus simavr's 1023 scaling (≤ 0.12°).
        assert!((fw - angle).abs() < 0.25, "{angle}° read as {fw}°");
        // The level chassis pot sits mid-scale.
        assert!((510..=512).contains(&w.adc[3]), "{w:?}");
    }
}

#[test]
fn time_the_chip_runs_outside_the_plant_is_caught_up() {
    let (mut avr, mut plant) = rig();
    command(&mut avr, b'1', b'F', 128);
    plant.run_us(&mut avr, 300_000).unwrap();
    let before = plant.model(0).unwrap().ds().unwrap().drive.elapsed_s();
    avr.run_us(100_000);
    plant.run_us(&mut avr, 1_000).unwrap();
    let after = plant.model(0).unwrap().ds().unwrap().drive.elapsed_s();
    assert!((after - before - 0.101).abs() < 1e-5, "{}", after - before);
    let (chip, model) = (avr.cycles(), plant.cycles().unwrap());
    assert!(
        chip >= model && chip - model < 64,
        "chip {chip} plant {model}"
    );
}
