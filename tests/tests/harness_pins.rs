//! Emulator tests of GPIO: driving inputs, reading outputs, tracing changes and
//! reading a PWM duty back.

use harness::{uno, Avr, Pin};

#[test]
fn input_is_mirrored_to_output() {
    let mut avr = Avr::firmware("fixture_pins").unwrap();
    avr.run_us(100);
    assert!(!avr.pin(uno::D13));
    avr.set_pin(Pin::d(2), true);
    avr.run_us(10);
    assert!(avr.pin(uno::D13));
    avr.set_pin(Pin::d(2), false);
    avr.run_us(10);
    assert!(!avr.pin(Pin::new('B', 5)));
}

#[test]
fn trace_records_each_change_with_its_cycle() {
    let mut avr = Avr::firmware("fixture_pins").unwrap();
    avr.run_us(100);
    avr.trace_pin(uno::D13);
    let mut driven = Vec::new();
    for i in 0..6 {
        avr.run_us(50);
        driven.push(avr.cycles());
        avr.set_pin(uno::D2, i % 2 == 0);
    }
    avr.run_us(50);
    let trace = avr.pin_trace(uno::D13);
    assert_eq!(trace.len(), 7, "{trace:?}");
    assert!(!trace[0].1);
    for (i, &(cycle, level)) in trace[1..].iter().enumerate() {
        assert_eq!(level, i % 2 == 0);
        // The mirror loop is a handful of cycles long.
        let lag = cycle - driven[i];
        assert!(lag < 40, "change {i} lagged {lag} cycles");
    }
    assert!(avr.pin_trace(uno::D12).is_empty());
}

#[test]
fn pwm_duty_on_d9_is_a_quarter() {
    let mut avr = Avr::firmware("fixture_pins").unwrap();
    assert_eq!(avr.pwm_duty(uno::D9), None, "timer not yet configured");
    avr.run_us(100);
    assert_eq!(avr.pwm_duty(uno::D9), Some(0.25));
    assert_eq!(avr.pwm_duty(uno::D10), None, "OC1B is not enabled");
    assert_eq!(avr.pwm_duty(uno::D13), None, "not a PWM pin");
}

#[test]
fn detached_pwm_pin_keeps_its_duty_but_draws_no_waveform() {
    let mut with_wave = Avr::firmware("fixture_pins").unwrap();
    let mut detached = Avr::firmware("fixture_pins").unwrap();
    detached.detach_pwm_waveforms();
    for avr in [&mut with_wave, &mut detached] {
        avr.run_us(100);
        avr.trace_pin(uno::D9);
        avr.run_us(200);
    }
    // The trace starts with the level at the start; then the waveform's edges.
    let edges = with_wave.pin_trace(uno::D9).len() - 1;
    assert!(edges >= 4, "{edges} edges in 200 µs of PWM");
    assert_eq!(
        detached.pin_trace(uno::D9).len(),
        1,
        "no waveform once detached"
    );
    assert_eq!(detached.pwm_duty(uno::D9), Some(0.25));
}

#[test]
fn adc_input_keeps_its_value_when_reapplied() {
    let mut avr = Avr::firmware("fixture_pins").unwrap();
    avr.set_adc_mv(3, 1234);
    avr.set_adc_mv(3, 1234);
    assert_eq!(
        avr.adc_input_mv(3),
        Some(1234),
        "the same value again keeps it"
    );
    avr.set_adc_mv(3, 2000);
    avr.set_adc_mv(9, 5);
    assert_eq!(avr.adc_input_mv(3), Some(2000));
    assert_eq!(avr.adc_input_mv(2), Some(0));
    assert_eq!(avr.adc_input_mv(9), None);
}
