//! The slave's panic path in the real images: with both motors driving, the CPU is sent
//! to `__vector_default` (its address from the ELF), where any unbound interrupt goes and
//! which calls the same `halt` as the panic handler. No call in the images can panic, so
//! the linker drops the handler itself; the test checks that this is still so. What a user sees: both motors stopped at once (direction
//! pins low, no PWM), both LEDs lit, interrupts off, the board off the bus (its address
//! not acknowledged), then the 1-s watchdog reboots the board into its boot exception with
//! the motors still off.

mod slave_support;

use harness::{Avr, Pin};
use shared::regs::id;
use slave_support::{rig, Rig, DRIVE_GAINS, LIFT_GAINS_WHEEL_1, STEER_GAINS_WHEEL_1};

/// Whether the CPU has interrupts enabled (SREG's I bit, which the emulator keeps
/// apart from the data space).
fn interrupts_on(avr: &mut Avr) -> bool {
    // SAFETY: plain field read of the live core.
    unsafe { (*avr.as_ptr()).sreg[7] != 0 }
}

/// Both motors of controller `addr` driven: the drive at 1000 ticks/s and the steer held
/// swinging from 40° to −40° (drive/steer), or both lifts held away from their rest (lift/lift).
fn both_driving(addr: u8) -> Rig {
    let mut r = rig(addr);
    r.run_us(650_000);
    r.reset_exceptions();
    if addr == 3 {
        for &(reg, raw) in LIFT_GAINS_WHEEL_1 {
            r.write_raw(reg, raw);
            // The same block for TWO, 18 ids on.
            r.write_raw(reg + 18, raw);
        }
        r.write_value(id::REGLL_ONE_REQPOS, 30.0);
        r.write_value(id::REGLL_TWO_REQPOS, -30.0);
    } else {
        for &(reg, raw) in DRIVE_GAINS.iter().chain(STEER_GAINS_WHEEL_1) {
            r.write_raw(reg, raw);
        }
        r.write_value(id::REGDS_DRIVE_REQSPEED, 1000.0);
        r.write_value(id::REGDS_STEER_REQPOS, 40.0);
    }
    r.run_us(1_500_000);
    if addr != 3 {
        // The steer on its way to the other side, so its duty is well above zero.
        r.write_value(id::REGDS_STEER_REQPOS, -40.0);
        r.run_us(150_000);
    }
    assert_eq!(r.read_raw(id::REG_STATUS) & 1, 0, "running");
    r
}

fn motor_pins_low(avr: &Avr) -> bool {
    [2, 3, 4, 7].iter().all(|&d| !avr.pin(Pin::d(d)))
}

fn duty(avr: &Avr, pin: Pin) -> f32 {
    avr.pwm_duty(pin)
        .unwrap_or(if avr.pin(pin) { 1.0 } else { 0.0 })
}

/// Sends the CPU to the handler and steps it until both motors are off; returns the
/// cycles that took.
fn force_panic(r: &mut Rig) -> u64 {
    let mut avr = r.avr();
    // A call that can panic would link core's panicking module and the handler: then
    // this test must run the handler itself (it calls the same `halt`).
    let panics = avr
        .symbol_containing("panicking")
        .or(avr.symbol_containing("rust_begin_unwind"));
    assert_eq!(panics, None, "the image can now panic");
    let handler = avr
        .symbol("__vector_default")
        .expect("the handler is in the image");
    avr.jump_to(handler);
    let start = avr.cycles();
    while !(motor_pins_low(&avr) && duty(&avr, Pin::d(9)) == 0.0 && duty(&avr, Pin::d(10)) == 0.0) {
        assert!(avr.cycles() - start < 1_000, "motors still on");
        avr.step();
    }
    avr.cycles() - start
}

fn panic_path(addr: u8) {
    let mut r = both_driving(addr);
    {
        let avr = r.avr();
        let m1 = avr.pin(Pin::d(2)) || avr.pin(Pin::d(3));
        let m2 = avr.pin(Pin::d(4)) || avr.pin(Pin::d(7));
        assert!(m1 && m2, "both motors driven");
        assert!(duty(&avr, Pin::d(9)) > 0.0 && duty(&avr, Pin::d(10)) > 0.0);
        assert_eq!(avr.watchdog_resets(), 0);
    }
    let cycles = force_panic(&mut r);
    println!("controller {addr}: motors off {cycles} cycles after the panic");
    assert!(cycles <= 40, "{cycles} cycles");
    let at = r.bus.micros();
    r.run_us(1_000);
    {
        let mut avr = r.avr();
        assert!(motor_pins_low(&avr));
        assert_eq!(duty(&avr, Pin::d(9)), 0.0);
        assert_eq!(duty(&avr, Pin::d(10)), 0.0);
        assert!(avr.pin(Pin::a(2)) && avr.pin(Pin::a(3)), "both LEDs lit");
        assert!(!interrupts_on(&mut avr), "interrupts off");
    }
    // Off the bus while frozen: the TWI is switched off, so the master's address gets no
    // acknowledge (and the master finds the board silent), where a TWI left on would
    // acknowledge and then hold SCL low, the whole bus with it, until the watchdog.
    let refused = r.bus.write(r.addr, &[id::REG_STATUS]);
    assert!(
        matches!(refused, Err(harness::twi::TwiError::AddressNack { .. })),
        "{refused:?}"
    );
    // The watchdog, no longer fed, reboots the board within its 1-s period.
    let chip = r.chip;
    let rebooted = r
        .plant
        .run_until(&mut r.bus, 1_200_000, |bus| {
            bus.chip(chip).unwrap().watchdog_resets() == 1
        })
        .unwrap();
    assert!(rebooted, "no watchdog reset");
    let took = r.bus.micros() - at;
    println!("controller {addr}: watchdog reboot {took} µs after the panic");
    assert!((900_000..=1_100_000).contains(&took), "{took} µs");
    r.run_us(5_000);
    assert_eq!(r.read_raw(id::REG_EXCEPTIONDATA), 0x0502, "boot exception");
    assert_eq!(r.read_raw(id::REG_STATUS) & 1, 1);
    // Motors still off, through the boot and after it.
    for _ in 0..100 {
        r.run_us(1_000);
        let avr = r.avr();
        assert_eq!(duty(&avr, Pin::d(9)), 0.0);
        assert_eq!(duty(&avr, Pin::d(10)), 0.0);
        assert!(
            !avr.pin(Pin::d(3)) && !avr.pin(Pin::d(7)),
            "no reverse drive"
        );
    }
}

#[test]
fn a_panic_on_a_drive_steer_board_stops_both_motors_and_reboots_it() {
    panic_path(1);
}

#[test]
fn a_panic_on_a_lift_lift_board_stops_both_motors_and_reboots_it() {
    panic_path(3);
}
