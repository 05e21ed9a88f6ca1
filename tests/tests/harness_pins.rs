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
