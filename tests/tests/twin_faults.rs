//! Fault injection through the twin, seen as a PC program sees it: a stalled wheel raises its
//! fault on the master and every motor stops; a slave cut off the bus is detected within the
//! master's bound and, its bus-silence failsafe armed by the master's pings, stops its own
//! wheel after BUSTIMEOUT, while the views go on past it; a rebooted slave stops its wheel and
//! shows its boot state, its positions off calibration; a current spike raises a short; an
//! unplugged temperature sensor raises type 10; the RC receiver takes over the drives, also
//! with the transmitter on from power-up; a PC
//! program that armed the PC-silence failsafe and then hangs gets every motor stopped; the
//! status shows each board's LEDs and bridges as the bench would, and what is injected; the
//! original library's emergency stop, aborted by a silent controller, still stops the rover;
//! a controller that panics stops the rover before its watchdog reboots it; hostctl's
//! `stop` cuts every bridge and leaves no board in exception, and fails naming a board that
//! ignores it; hostctl's `calibrate` after it holds every steer and lift where it stands.
//!
//! Needs the firmware images: `scripts/firmware.sh`.

mod twin_support;

use std::time::Duration;

use hostctl::cmd::live::{view_lines, Dropped, Snapshot};
use hostctl::cmd::pc::{Motor, Pc, WHEELS};
use shared::regs::id;
use twin::wiring::Axis;
use twin_support::{drive_speed, master_exception, rover, slave_exception, slave_running, Session};

/// Checks, by one update(), that every controller answers and none is in an exception;
/// returns that update.
fn no_board_in_exception(s: &mut Session) -> Snapshot {
    let snap = s.update();
    assert_eq!(snap.silent(), [] as [u8; 0], "controllers not answering");
    for n in 1..=9 {
        assert!(
            slave_running(&snap, n),
            "controller {n} in exception or not read: {:?}",
            slave_exception(&snap, n)
        );
    }
    snap
}

/// Polls update() for up to 0.5 s until every controller but `source` shows REMOTESLAVE,
/// the master's spread of `source`'s fault; fails if one does not.
fn assert_spread_from(s: &mut Session, source: u8) {
    let (ok, snap, _) = s.until(0.5, |s| {
        (1..=9u8)
            .filter(|&n| n != source)
            .all(|n| slave_exception(s, n) == Some(3))
    });
    assert!(ok, "not spread from controller {source}: {snap:?}");
}

/// A session calibrated, with exceptions reset.
fn calibrated() -> Session {
    let mut s = Session::start();
    s.calibrate();
    s.reset_exceptions();
    s
}

/// A session calibrated, with exceptions reset, all six drives asked for 1000 ticks/s and
/// turning at more than half of it.
fn driving() -> Session {
    let mut s = calibrated();
    let all: Vec<(u8, f32)> = WHEELS.map(|w| (w, 1000.0)).collect();
    s.set(Motor::Drive, &all);
    let (ok, snap, took) = s.until(5.0, |s| (1..=6).all(|w| drive_speed(s, w) > 500.0));
    assert!(ok, "not moving after {took:?}: {snap:?}");
    s
}

/// [`driving`], on past 5.5 s after the master's boot: the master watches the slaves from
/// 5 s on (reference §5).
fn watched_while_driving() -> Session {
    let mut s = driving();
    let boot_settle = 5.5 - s.clock_now().as_secs_f64();
    if boot_settle > 0.0 {
        s.pass(boot_settle);
    }
    s
}

/// Every wheel's physical drive speed, ticks/s.
fn physical_speeds(s: &Session) -> Vec<f64> {
    let twin = s.twin.borrow();
    WHEELS
        .map(|w| twin.wheel(w).unwrap().drive_ticks_per_s)
        .collect()
}

/// Lets `secs` of emulated time pass, then checks every wheel below 50 ticks/s and every
/// motor of the nine boards (drives, steers, lifts) unpowered.
fn all_at_rest_after(s: &mut Session, secs: f64) {
    s.pass(secs);
    let speeds = physical_speeds(s);
    assert!(
        speeds.iter().all(|v| v.abs() < 50.0),
        "still turning: {speeds:?}"
    );
    assert!(every_motor_stopped(s), "a steer or lift still powered");
}

/// Checks that `snap` shows the master in SlaveSilent (type 11) on `controller`.
fn assert_slave_silent(snap: &Snapshot, controller: u8) {
    assert_eq!(
        split(master_exception(snap)),
        (11, u16::from(controller), 0),
        "SlaveSilent on controller {controller}"
    );
}

/// The master's exception as (type, slave, motor).
fn split(data: u16) -> (u16, u16, u16) {
    (data & 0xff, (data >> 8) & 0xf, data >> 12)
}

#[test]
fn a_stalled_wheel_raises_its_fault_on_the_master_and_every_motor_stops() {
    let mut s = driving();
    // Let the slaves check stalls (the library's calibrate leaves STALLCHECK at 255, off).
    for w in WHEELS {
        let d = hostctl::cmd::pc::device_of(w, Motor::Drive);
        s.write_raw(&[0x05, (d << 4) | 2, 0x01, id::REGDS_DRIVE_STALLCHECK, 0x96]);
    }
    s.twin.borrow_mut().stall(3, Axis::Drive, true).unwrap();
    let (ok, snap, took) = s.until(6.0, |s| master_exception(s) != 0);
    assert!(ok, "no fault on the master after {took:?}");
    // Wheel 3's drive is controller 4, motor 0: STALL (5), or OVERCURRENT (1) if the duty
    // reached the top first.
    let (kind, slave, motor) = split(master_exception(&snap));
    assert!(kind == 5 || kind == 1, "type {kind}");
    assert_eq!((slave, motor), (4, 0));
    println!("stall on wheel 3 reached the master after {took:?} (type {kind})");
    // Spread: every other slave is in REMOTESLAVE, so every motor is stopped.
    assert_spread_from(&mut s, 4);
    all_at_rest_after(&mut s, 3.0);
}

#[test]
fn a_slave_cut_off_the_bus_is_detected_within_its_bound() {
    let mut s = watched_while_driving();
    // Read only the master's set 2 (hostctl's: the library's eleven registers and
    // REGMASTER_TEMPSREAD, 24 bytes, ~2 ms): controller 5 no longer answers, so a full
    // update() would time out on it.
    let set2 = [0x03, 0x03, 0x02];
    let cut_at = s.clock_now();
    s.twin.borrow_mut().cut(5).unwrap();
    let mut seen = None;
    while s.clock_now() - cut_at < Duration::from_millis(500) {
        let reply = s.link.transact(0, &set2, 24).unwrap();
        let data = u16::from_le_bytes([reply[20], reply[21]]);
        if data != 0 {
            seen = Some((data, s.clock_now() - cut_at));
            break;
        }
    }
    let (data, took) = seen.expect("the master never noticed controller 5");
    assert_eq!(split(data), (11, 5, 0), "SlaveSilent on controller 5");
    println!("controller 5 cut off: on the master after {took:?}");
    // The goal: every motor stopped within 50 ms; one set-2 read (~3 ms) more for the
    // PC to see it.
    assert!(took <= Duration::from_millis(53), "detected after {took:?}");
    // Every other slave is told, and their wheels coast to a stop. Controller 5 cannot
    // hear it, but, pinged by the master since 5 s after its boot, its bus-silence
    // failsafe is armed: BUSTIMEOUT (2500 ms) after the last transaction it stopped its
    // own motors, and its wheel (4) coasts to a stop as the others did.
    let mut others_stopped = None;
    let mut cut_stopped = None;
    while s.clock_now() - cut_at < Duration::from_millis(4_500) {
        s.pass(0.01);
        let speeds = physical_speeds(&s);
        let at = s.clock_now() - cut_at;
        let others = speeds
            .iter()
            .enumerate()
            .all(|(i, v)| i == 3 || v.abs() < 50.0);
        if others && others_stopped.is_none() {
            others_stopped = Some(at);
        }
        if speeds[3].abs() < 50.0 {
            cut_stopped = Some(at);
            break;
        }
        if at < Duration::from_millis(2_500) {
            assert!(
                speeds[3] > 800.0,
                "wheel 4 (controller 5) turns until BUSTIMEOUT, at {at:?}: {speeds:?}"
            );
        }
    }
    let others = others_stopped.expect("the other wheels stop");
    let cut = cut_stopped.expect("wheel 4 (controller 5) never stopped");
    println!(
        "cut off: the other wheels stopped after {others:?}, wheel 4 (failsafe) after {cut:?}"
    );
    // Its last transaction came at most a few ms before the cut; the coast to below
    // 50 ticks/s takes as long as the others' after their spread (plus 100 ms).
    let coast = others.saturating_sub(took);
    assert!(
        cut >= Duration::from_millis(2_500)
            && cut <= Duration::from_millis(2_500) + coast + Duration::from_millis(100),
        "wheel 4 stopped after {cut:?} (others coasted for {coast:?})"
    );
    all_at_rest_after(&mut s, 0.5);
    // Back on the bus, it answers again.
    s.twin.borrow_mut().restore(5).unwrap();
    s.pass(0.1);
    let snap = s.update();
    assert!(snap.raw(5, id::REG_STATUS).is_some());
}

#[test]
fn a_controller_driven_and_lost_before_the_first_ping_is_found_by_it() {
    // Driving before the master's watch starts (5 s after its boot), and controller 4
    // (wheel 3's drive and steer) drops off the bus before it.
    let mut s = calibrated();
    let all: Vec<(u8, f32)> = WHEELS.map(|w| (w, 500.0)).collect();
    s.set(Motor::Drive, &all);
    s.update();
    let cut_at = s.twin.borrow().micros();
    assert!(
        cut_at < 4_800_000,
        "cut at {cut_at} us, not before the first ping"
    );
    s.twin.borrow_mut().cut(4).unwrap();
    // The master heard it through the PC's frames, so the first ping (5.0 s) finds it
    // silent, not a board never fitted, and stops every other motor.
    let (ok, snap, took) = s.until(2.0, |s| master_exception(s) != 0);
    assert!(ok, "no exception after {took:?}");
    assert_slave_silent(&snap, 4);
    let at = s.twin.borrow().micros();
    assert!((5_000_000..5_400_000).contains(&at), "found at {at} us");
    // The master stopped the others (not their own demands never arriving).
    assert_spread_from(&mut s, 4);
    s.pass(3.0);
    let speeds = physical_speeds(&s);
    for (w, v) in WHEELS.zip(&speeds) {
        if w != 3 {
            assert!(v.abs() < 50.0, "wheel {w} still turning: {speeds:?}");
        }
    }
}

#[test]
fn update_goes_on_past_a_controller_cut_off_the_bus_and_sees_it_come_back() {
    let mut s = watched_while_driving();
    s.twin.borrow_mut().cut(5).unwrap();
    // hostctl's update(): controller 5's read times out, the master names NoAnswer, and the
    // other nine reads go on.
    let snap = s.update();
    assert_eq!(snap.silent(), [5]);
    let speed = |snap: &Snapshot, w| {
        let d = hostctl::cmd::pc::device_of(w, Motor::Drive);
        snap.value(d, id::REGDS_DRIVE_ACTUALSPEED)
    };
    assert_eq!(speed(&snap, 4), None, "wheel 4 is on controller 5");
    for w in [1, 2, 3, 5, 6] {
        assert!(speed(&snap, w).is_some(), "wheel {w} read");
    }
    assert_slave_silent(&snap, 5);
    let lines = view_lines(
        &snap,
        &Pc::new(),
        &Dropped::default(),
        Duration::ZERO,
        1,
        1.0,
    );
    assert!(
        lines[5].starts_with("4 ") && lines[5].contains("  controller 5: no answer"),
        "{lines:#?}"
    );
    assert!(
        lines
            .iter()
            .any(|l| l.starts_with("no answer: controller 5 does not answer")),
        "{lines:#?}"
    );
    // Back on the bus: the next update reads it again.
    s.twin.borrow_mut().restore(5).unwrap();
    let snap = s.update();
    assert!(snap.silent().is_empty());
    assert!(speed(&snap, 4).is_some());
}

#[test]
fn a_rebooted_controller_stops_its_wheel_and_the_view_shows_it_booted_off_calibration() {
    let mut s = watched_while_driving();
    let mut dropped = Dropped::default();
    let snap = s.update();
    dropped.note(&snap, &s.pc);
    assert_eq!(slave_exception(&snap, 1), None);
    assert!(dropped.calibrated(&s.pc, 1, Motor::Steer));
    // Controller 1 (wheel 1's drive and steer) resets, as in a brown-out.
    s.twin.borrow_mut().reboot(1).unwrap();
    let (ok, snap, took) = s.until(2.0, |s| {
        s.silent().is_empty() && slave_exception(s, 1) == Some(2)
    });
    assert!(
        ok,
        "controller 1 not seen in its boot state after {took:?}: {snap:?}"
    );
    dropped.note(&snap, &s.pc);
    // hostctl's view: wheel 1's steer angle is on the boot calibration, not degrees, and its
    // exception is the boot state; wheel 2's stays in degrees.
    assert!(!dropped.calibrated(&s.pc, 1, Motor::Steer));
    assert!(dropped.calibrated(&s.pc, 2, Motor::Steer));
    let lines = view_lines(&snap, &s.pc, &dropped, Duration::ZERO, 1, 1.0);
    assert!(
        lines[2].starts_with("1 ") && lines[2].contains('*') && lines[2].contains("boot"),
        "{lines:#?}"
    );
    assert!(!lines[3].contains('*'), "{lines:#?}");
    // Its drive is off (the boot state: duty 0), so wheel 1 coasts down.
    s.pass(3.0);
    let wheel_1 = physical_speeds(&s)[0];
    assert!(wheel_1.abs() < 50.0, "wheel 1 still turning at {wheel_1}");
}

#[test]
fn a_current_spike_raises_a_short_and_stops_the_rover() {
    let mut s = driving();
    s.twin
        .borrow_mut()
        .spike(2, Axis::Drive, 8.0, 30.0)
        .unwrap();
    let (ok, snap, took) = s.until(3.0, |s| master_exception(s) != 0);
    assert!(ok, "no fault on the master after {took:?}");
    // Wheel 2's drive is controller 2, motor 0; at a duty below 250 the overcurrent rule
    // calls it SHORTOC (8).
    assert_eq!(split(master_exception(&snap)), (8, 2, 0));
    all_at_rest_after(&mut s, 3.0);
}

#[test]
fn an_unplugged_temperature_sensor_raises_type_10() {
    let mut r = rover();
    // Sensor 2 (controller 2's): the master reads its sensors in turn, one per 2-s tick
    // from 5 s after boot, and notices a missing one when its turn comes.
    r.set_sensor_present(2, false).unwrap();
    let mut s = Session::on(r);
    s.reset_exceptions();
    let (ok, snap, took) = s.until(20.0, |s| master_exception(s) != 0);
    assert!(ok, "no exception after {took:?}");
    assert_eq!(master_exception(&snap), 0x000a, "{snap:?}");
    println!("sensor 2 missing: type 10 on the master {took:?} after the reset");
}

/// A rover whose RC transmitter is set to full forward, straight on: channel 0 at
/// 1000 µs is full forward (drive 1300), 1339 µs centres the steering, 910 µs is normal
/// (not crab) mode.
fn rover_with_rc_full_forward() -> twin::Rover {
    let mut r = rover();
    for (channel, us) in [(0, 1000), (1, 1339), (2, 910)] {
        r.set_rc_width(channel, us).unwrap();
    }
    r
}

#[test]
fn the_rc_receiver_drives_the_rover_and_silences_the_pc_link() {
    let mut s = Session::on(rover_with_rc_full_forward());
    s.reset_exceptions();
    s.twin.borrow_mut().set_rc(true);
    // The master counts the link from 5 s after its boot, once the slaves are back.
    let settle = 5.0 - s.clock_now().as_secs_f64();
    s.pass(settle.max(0.0) + 4.0);
    let speeds = physical_speeds(&s);
    assert!(
        speeds.iter().all(|v| (v - 1300.0).abs() < 80.0),
        "RC drive: {speeds:?}"
    );
    // While the link is up, PC frames are swallowed with no reply.
    assert!(s.link.transact(0, &[0x03, 0x03, 0x02], 24).is_err());
    // The transmitter goes off: 1 s later the link is down and the master stops the
    // drives (new: the original kept them at the last speed); they coast down.
    s.twin.borrow_mut().set_rc(false);
    let mut waited = 0.0;
    while physical_speeds(&s).iter().any(|v| v.abs() >= 50.0) {
        assert!(
            waited < 4.0,
            "still driving {waited:.1} s after the link went: {:?}",
            physical_speeds(&s)
        );
        s.pass(0.1);
        waited += 0.1;
    }
    assert!(
        waited > 1.0,
        "stopped before the link timed out: {waited:.1} s"
    );
    println!("RC transmitter off: every wheel below 50 ticks/s {waited:.1} s later");
    // And the PC is answered again, with the master's registers: the ambient sensor
    // read (REGMASTER_TEMPSREAD bit 0, the set's last word; one sensor a 2-s tick) at the
    // twin's 20.0 °C (0x5555 on −20..100).
    let reply = s
        .link
        .transact(0, &[0x03, 0x03, 0x02], 24)
        .expect("answered");
    let word = |at: usize| u16::from_le_bytes([reply[at], reply[at + 1]]);
    assert_eq!(reply.len(), 24);
    assert_eq!(word(22) & 1, 1, "ambient not read: {reply:02x?}");
    assert!(word(0).abs_diff(0x5555) <= 1, "ambient {:#06x}", word(0));
}

#[test]
fn a_transmitter_on_at_power_up_drives_once_the_slaves_are_back_from_their_boot() {
    // The receiver sends from power-up: the master's boot hard-resets every slave, and
    // the RC link-up's REG_RESET = 1 would reach them while they reboot and be lost.
    let mut r = rover_with_rc_full_forward();
    r.set_rc(true);
    let speeds = |r: &twin::Rover| -> Vec<f64> {
        WHEELS
            .map(|w| r.wheel(w).unwrap().drive_ticks_per_s)
            .collect()
    };
    r.run_us(4_500_000).unwrap();
    assert!(
        speeds(&r).iter().all(|v| v.abs() < 1.0),
        "nothing drives before the slaves are back: {:?}",
        speeds(&r)
    );
    // From 5 s after boot the master counts the link, and its link-up takes every board
    // out of its boot exception: the rover drives at the transmitter's 1300 ticks/s.
    r.run_us(4_500_000).unwrap();
    assert!(
        speeds(&r).iter().all(|v| (v - 1300.0).abs() < 80.0),
        "RC drive from power-up: {:?}",
        speeds(&r)
    );
}

#[test]
fn a_pc_program_that_armed_the_silence_failsafe_and_hangs_gets_every_motor_stopped() {
    let mut s = driving();
    // REGMASTER_PCTIMEOUT = 500 ms, then the program polls as usual for a while: the
    // rover keeps driving.
    s.write_raw(&[0x06, 0x02, 0x01, id::REGMASTER_PCTIMEOUT, 0xf4, 0x01]);
    let (_, snap, _) = s.until(2.0, |_| false);
    assert!((1..=6).all(|w| drive_speed(&snap, w) > 500.0), "{snap:?}");
    assert_eq!(master_exception(&snap), 0);
    // The program hangs with the port open: nothing more is sent.
    let mut waited_ms = 0;
    while !every_motor_stopped(&s) {
        // The first spread must do it: a second one comes a timeout later.
        assert!(
            waited_ms < 600,
            "motors still driven {waited_ms} ms into the silence"
        );
        s.pass(0.01);
        waited_ms += 10;
    }
    assert!(
        waited_ms >= 500,
        "stopped before the timeout: {waited_ms} ms"
    );
    println!("PC silent: every motor's PWM at 0 after {waited_ms} ms (timeout 500 ms)");
    all_at_rest_after(&mut s, 3.0);
    // When the program comes back it finds why: PCSILENT on the master, every slave in
    // REMOTESLAVE.
    let snap = s.update();
    assert_eq!(split(master_exception(&snap)), (13, 0, 0));
    assert!(
        (1..=9u8).all(|n| slave_exception(&snap, n) == Some(3)),
        "{snap:?}"
    );
}

/// The duty on a motor's PWM pin: the timer's, or with the timer off the pin's level (a
/// pin left high without its timer drives the motor at full duty).
fn duty(avr: &harness::Avr, pin: harness::Pin) -> f32 {
    avr.pwm_duty(pin)
        .unwrap_or(if avr.pin(pin) { 1.0 } else { 0.0 })
}

/// Whether every slave has both PWM outputs at duty 0, read from the chips.
fn every_motor_stopped(s: &Session) -> bool {
    motors_stopped_but(s, None)
}

/// Whether every slave but `except` has both PWM outputs at duty 0, read from the chips.
fn motors_stopped_but(s: &Session, except: Option<u8>) -> bool {
    let mut twin = s.twin.borrow_mut();
    let except = except.map(usize::from);
    (1..=9usize).filter(|&c| Some(c) != except).all(|chip| {
        twin.bus().chip(chip).is_some_and(|avr| {
            [harness::uno::D9, harness::uno::D10]
                .iter()
                .all(|&pin| duty(&avr, pin) == 0.0)
        })
    })
}

#[test]
fn from_a_slave_fault_to_every_motor_stopped() {
    let mut s = watched_while_driving();
    assert!(!every_motor_stopped(&s), "the drives are running");
    let chip_2_stopped = |s: &Session| {
        let mut twin = s.twin.borrow_mut();
        let avr = twin.bus().chip(2);
        avr.is_some_and(|a| duty(&a, harness::uno::D9) == 0.0)
    };
    // An 8 A spike on wheel 2's drive (controller 2, motor 0): SHORTOC on that board.
    let at = s.twin.borrow().micros();
    s.twin
        .borrow_mut()
        .spike(2, Axis::Drive, 8.0, 30.0)
        .unwrap();
    let (mut local, mut all) = (None, None);
    while all.is_none() && s.twin.borrow().micros() - at < 2_000_000 {
        s.twin.borrow_mut().run_us(250).unwrap();
        let now = s.twin.borrow().micros() - at;
        if local.is_none() && chip_2_stopped(&s) {
            local = Some(now);
        }
        if every_motor_stopped(&s) {
            all = Some(now);
        }
    }
    let local = local.expect("controller 2 never stopped its drive");
    let all = all.expect("not every motor stopped within 2 s");
    println!(
        "slave fault (8 A spike on wheel 2): its own drive stopped after {local} us, every \
         motor after {all} us (the master reads each slave's status once a second)"
    );
    assert!(local <= 2_000, "{local} us");
    assert!(all <= 1_100_000, "{all} us");
    all_at_rest_after(&mut s, 3.0);
}

#[test]
fn the_librarys_emergency_stop_aborted_by_a_silent_controller_still_stops_the_rover() {
    // The original operator's emergency stop (reference §10.3) sends 36 frames and aborts
    // at the first non-zero reply. The original master answered 00 for a slave that did
    // not acknowledge; this one answers 8c (NoAnswer). So with wheel 1's drive board cut
    // off, the library sends one frame and gives up: the master itself must stop the rest.
    let mut s = watched_while_driving();
    let cut = hostctl::cmd::pc::device_of(1, Motor::Drive);
    let ops = s.pc.emergency_stop().unwrap();
    let mut sent = 0;
    let mut refused = None;
    for op in ops {
        match op {
            hostctl::cmd::pc::Op::Pause(d) => s.clock.sleep_for(d),
            hostctl::cmd::pc::Op::Write(w) => {
                // The board is lost just before the first frame (after the library's
                // pause), so only that frame can tell the master before its own checks.
                if sent == 0 {
                    s.twin.borrow_mut().cut(cut).unwrap();
                    assert!(!motors_stopped_but(&s, Some(cut)), "the drives are running");
                }
                let reply = s.link.transact(w.device, &w.frame, 1).expect("a reply");
                sent += 1;
                if reply != [0] {
                    refused = Some((w.device, reply));
                    break;
                }
            }
        }
    }
    assert_eq!(
        (sent, refused),
        (1, Some((cut, vec![0x8c]))),
        "the library gives up at its first frame, which the master answers NoAnswer"
    );
    // The frame's writes all went unanswered, so the master found the board silent at
    // once and sent every other board into REMOTESLAVE: their motors stop within a few
    // ms of the reply, sooner than the master's own checks (one every 2 ms, none more
    // than 16 ms apart) would have found it, though the library never reached them.
    let at = s.twin.borrow().micros();
    let mut stopped = None;
    while stopped.is_none() && s.twin.borrow().micros() - at < 200_000 {
        s.twin.borrow_mut().run_us(250).unwrap();
        let others = motors_stopped_but(&s, Some(cut));
        if others {
            stopped = Some(s.twin.borrow().micros() - at);
        }
    }
    let stopped = stopped.expect("the other eight boards still drive 200 ms after the stop");
    println!(
        "library stop aborted at controller {cut}: the other boards stopped {stopped} us later"
    );
    assert!(stopped <= 3_000, "{stopped} us after the reply");
    let snap = s.update();
    assert_slave_silent(&snap, cut);
    // The cut board's own bus-silence stop ends its wheel too (BUSTIMEOUT, 2.5 s).
    all_at_rest_after(&mut s, 3.5);
}

#[test]
fn a_controller_that_panics_stops_the_rover_before_its_watchdog_reboot() {
    // Controller 4 (wheel 3's drive and steer) takes its panic path while the rover
    // drives: its own motors stop at once, the master's next access finds it silent and
    // stops the other eight, well before its watchdog reboots it. (A TWI left on would
    // hold SCL until that reboot, as `a_controller_that_hangs…` shows; the panic path
    // switches it off.)
    let mut s = watched_while_driving();
    assert!(!every_motor_stopped(&s), "the drives are running");
    let at = s.twin.borrow().micros();
    let resets = s.twin.borrow_mut().bus().chip(4).unwrap().watchdog_resets();
    {
        let mut twin = s.twin.borrow_mut();
        let mut avr = twin.bus().chip(4).expect("controller 4's chip");
        let handler = avr
            .symbol("__vector_default")
            .expect("the handler is in the image");
        avr.jump_to(handler);
    }
    // No PC traffic: the master's own checks (one every 2 ms) alone must find it.
    let mut stopped = None;
    while stopped.is_none() && s.twin.borrow().micros() - at < 1_500_000 {
        s.twin.borrow_mut().run_us(250).unwrap();
        if every_motor_stopped(&s) {
            stopped = Some(s.twin.borrow().micros() - at);
        }
    }
    let stopped = stopped.expect("a motor still driven 1.5 s after the panic");
    let rebooted = s.twin.borrow_mut().bus().chip(4).unwrap().watchdog_resets();
    println!("controller 4 panicked: every motor stopped {stopped} us later");
    assert_eq!(
        rebooted, resets,
        "found only after the watchdog rebooted it"
    );
    assert!(
        stopped <= 50_000,
        "the goal: every motor stopped within 50 ms"
    );
    let snap = s.update();
    assert_slave_silent(&snap, 4);
}

#[test]
fn a_controller_that_hangs_holds_the_bus_and_every_motor_still_stops() {
    // Controller 4 (wheel 3's drive and steer) hangs with its interrupts off while the
    // rover drives. Its TWI still takes its address at the master's next access and then
    // holds SCL low: no board can be reached until its watchdog reboots it (1 s), and its
    // own PWM runs on until then. Every motor must be stopped soon after that reboot.
    let mut s = watched_while_driving();
    assert!(!every_motor_stopped(&s), "the drives are running");
    let at = s.twin.borrow().micros();
    let resets = s.twin.borrow_mut().bus().chip(4).unwrap().watchdog_resets();
    s.twin.borrow_mut().bus().chip(4).unwrap().hang();
    let held = s
        .twin
        .borrow_mut()
        .run_until(50_000, 100, |t| t.bus().held_by() == Some(4))
        .unwrap();
    assert!(held, "the master's next access to controller 4 is held");
    let held_at = s.twin.borrow().micros() - at;
    let mut stopped = None;
    while stopped.is_none() && s.twin.borrow().micros() - at < 3_000_000 {
        s.twin.borrow_mut().run_us(1_000).unwrap();
        if every_motor_stopped(&s) {
            stopped = Some(s.twin.borrow().micros() - at);
        }
    }
    let rebooted = s.twin.borrow_mut().bus().chip(4).unwrap().watchdog_resets();
    let stopped = stopped.expect("a motor still driven 3 s after the hang");
    println!(
        "controller 4 hung: bus held from {held_at} us, every motor stopped {stopped} us later"
    );
    assert_eq!(rebooted, resets + 1, "its watchdog rebooted it");
    assert!(stopped < 1_100_000, "stopped {stopped} us after the hang");
    let snap = s.update();
    assert_slave_silent(&snap, 4);
    all_at_rest_after(&mut s, 2.0);
}

#[test]
fn hostctls_stop_cuts_every_bridge_and_leaves_no_board_in_exception() {
    // The library's emergency stop sets every gain and demand to 0, which leaves a
    // drive's output decaying ×0.96 a 150-ms window under power (reference §7.1). hostctl's
    // `stop` first sends every controller into REMOTESLAVE (bridges off at its next tick),
    // then the library's frames, then resets the boards it stopped.
    let mut s = watched_while_driving();
    assert!(!every_motor_stopped(&s), "the drives are running");
    let at = s.clock_now();
    hostctl_run(&mut s, "stop", "stop\n").expect("the stop runs");
    let took = s.clock_now() - at;
    println!("hostctl stop took {took:?}");
    // Its 45 frames, the library's 180-ms pause, one update() and the resets.
    assert!(took < Duration::from_millis(600), "{took:?}");
    // At its end every bridge is off (the library's stop alone left each drive near its
    // cruising duty), and no board is left in an exception.
    assert!(every_motor_stopped(&s), "a motor still driven");
    let snap = no_board_in_exception(&mut s);
    assert_eq!(master_exception(&snap), 0);
    // The wheels coast unpowered, and nothing drives them again.
    all_at_rest_after(&mut s, 1.0);
    assert!(every_motor_stopped(&s), "a motor driven again");
}

/// Runs `script` with `hostctl run` over the session's link and clock (the session is past
/// the master's 5-s watch, so the run does not wait for it); returns what it printed.
fn hostctl_run(s: &mut Session, name: &str, script: &str) -> Result<String, String> {
    let dir = std::env::temp_dir().join(format!("hostctl-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join(format!("{name}.rover"));
    std::fs::write(&file, script).unwrap();
    let path = file.display().to_string();
    let cli = <hostctl::Cli as clap::Parser>::try_parse_from(["hostctl", "run", &path]).unwrap();
    let mut plan = hostctl::plan(&cli.command).unwrap();
    if let hostctl::Plan::Run(run) = &mut plan {
        run.settled = s.clock_now();
    }
    let style = hostctl::Style {
        json: false,
        in_place: false,
        width: || None,
    };
    let mut out = Vec::new();
    let ran = hostctl::execute_with_clock(&plan, &mut s.link, style, &mut out, &mut s.clock);
    let _ = std::fs::remove_dir_all(&dir);
    let text = String::from_utf8_lossy(&out).into_owned();
    ran.map(|()| text).map_err(|e| e.to_string())
}

#[test]
fn a_calibrate_after_hostctls_stop_holds_every_steer_and_lift_where_it_stands() {
    // Steers at 20° and lifts at 10°, then hostctl's `stop` (its library frames calibrate
    // every position on -100..100) and a `calibrate`. The library's calibrate alone turns
    // each to the number it held on the stop's scale, now read as degrees; hostctl's holds
    // each board stopped while it runs, so each holds where it stands on the new scale.
    let mut s = calibrated();
    let steers: Vec<(u8, f32)> = WHEELS.map(|w| (w, 20.0)).collect();
    let lifts: Vec<(u8, f32)> = WHEELS.map(|w| (w, 10.0)).collect();
    s.set(Motor::Steer, &steers);
    s.set(Motor::Lift, &lifts);
    let boot_settle = 6.0 - s.clock_now().as_secs_f64();
    s.pass(boot_settle.max(1.0));
    let angles = |s: &Session| -> Vec<(f64, f64)> {
        let twin = s.twin.borrow();
        WHEELS
            .map(|w| {
                let wheel = twin.wheel(w).unwrap();
                (wheel.steer_deg, wheel.lift_deg)
            })
            .collect()
    };
    let before = angles(&s);
    for &(steer, lift) in &before {
        assert!(
            (steer - 20.0).abs() < 2.0 && (lift - 10.0).abs() < 2.0,
            "{before:?}"
        );
    }
    hostctl_run(&mut s, "stop-calibrate", "stop\ncalibrate\n").expect("the script runs");
    s.pass(3.0);
    let after = angles(&s);
    println!("steer and lift angles before {before:?}, 3 s after {after:?}");
    for (b, a) in before.iter().zip(&after) {
        assert!(
            (a.0 - b.0).abs() < 0.05 && (a.1 - b.1).abs() < 0.05,
            "moved: {before:?} -> {after:?}"
        );
    }
    // The boards run again, on the new calibration: the positions read in degrees.
    let snap = no_board_in_exception(&mut s);
    for w in WHEELS {
        let steer = f64::from(twin_support::steer_pos(&snap, w));
        assert!(
            (steer - after[usize::from(w - 1)].0).abs() < 1.5,
            "{w}: {steer}"
        );
    }
    // A demand moves it again.
    s.set(Motor::Steer, &[(1, -10.0)]);
    s.pass(2.0);
    let steer = s.twin.borrow().wheel(1).unwrap().steer_deg;
    assert!((steer + 10.0).abs() < 2.0, "wheel 1's steer at {steer}");
}

/// The line of `twin inject status` that starts with `label`.
fn status_line(r: &mut twin::Rover, label: &str) -> String {
    let status = twin::command::Command::Status.apply(r).unwrap();
    status
        .lines()
        .find(|l| l.starts_with(label))
        .unwrap_or_else(|| panic!("no `{label}` line in:\n{status}"))
        .to_owned()
}

#[test]
fn the_status_lists_running_spikes_and_what_each_sensor_measures() {
    let mut r = rover();
    let apply = |r: &mut twin::Rover, line: &str| {
        twin::command::Command::parse(line)
            .unwrap()
            .apply(r)
            .unwrap()
    };
    assert_eq!(
        status_line(&mut r, "current spikes"),
        "current spikes: none"
    );
    assert_eq!(
        status_line(&mut r, "temperatures"),
        "temperatures °C (ambient, then controllers 1..9): \
         20.0 20.5 21.0 21.5 22.0 22.5 23.0 23.5 24.0 24.5"
    );
    assert_eq!(
        apply(&mut r, "spike 2 steer 3.5 20"),
        "wheel 2 steer: +3.5 A for 20 ms"
    );
    apply(&mut r, "spike 5 lift 1.25 40");
    apply(&mut r, "temp 4 31.5");
    apply(&mut r, "temp 0 -55");
    assert_eq!(
        status_line(&mut r, "current spikes"),
        "current spikes: wheel 2 steer +3.5 A (20.0 ms left), wheel 5 lift +1.25 A (40.0 ms left)"
    );
    // Set values show, to the sensor's ends.
    assert_eq!(
        status_line(&mut r, "temperatures"),
        "temperatures °C (ambient, then controllers 1..9): \
         -55.0 20.5 21.0 21.5 31.5 22.5 23.0 23.5 24.0 24.5"
    );
    r.run_us(25_000).unwrap();
    let line = status_line(&mut r, "current spikes");
    assert!(
        line.starts_with("current spikes: wheel 5 lift +1.25 A (1") && line.ends_with(" ms left)"),
        "the steer spike is over, the lift one has about 15 ms left: {line}"
    );
    r.run_us(20_000).unwrap();
    assert_eq!(
        status_line(&mut r, "current spikes"),
        "current spikes: none"
    );
    // Serial losses pending show, and a clear cancels them.
    apply(&mut r, "drop-serial 5");
    apply(&mut r, "drop-serial 2 to-host");
    assert_eq!(
        status_line(&mut r, "serial bytes lost"),
        "serial bytes lost: 0 to master, 0 to host (5 and 2 pending)"
    );
    assert_eq!(
        apply(&mut r, "drop-serial clear"),
        "serial losses cancelled: 5 bytes to-master and 2 to-host will now arrive"
    );
    assert_eq!(
        status_line(&mut r, "serial bytes lost"),
        "serial bytes lost: 0 to master, 0 to host (0 and 0 pending)"
    );
    assert_eq!(
        apply(&mut r, "drop-serial clear"),
        "no serial byte loss was pending; nothing changed"
    );
}

/// How long LED `led` (1 or 2) of the status line `line` has been lit, in s; None if off.
fn lit_for_s(line: &str, led: u8) -> Option<f64> {
    let (_, rest) = line.split_once(&format!("LED{led} on "))?;
    rest.split(' ').next()?.parse().ok()
}

#[test]
fn the_status_shows_each_board_as_the_bench_would() {
    let mut s = watched_while_driving();
    let boards = |s: &Session| -> Vec<String> {
        let status = twin::command::Command::Status
            .apply(&mut s.twin.borrow_mut())
            .unwrap();
        (1..=9)
            .map(|n| {
                status
                    .lines()
                    .find(|l| l.starts_with(&format!("controller {n} (")))
                    .unwrap_or_else(|| panic!("no line for controller {n}:\n{status}"))
                    .to_owned()
            })
            .collect()
    };
    // Driving: each drive board's bridge runs its drive forward, and no LED is held lit
    // (a ping or the heartbeat flashes one for a moment at most).
    let before = boards(&s);
    for (n, line) in (1..=9).zip(&before) {
        assert!(
            [1, 2]
                .iter()
                .all(|&led| lit_for_s(line, led).is_none_or(|t| t < 0.5)),
            "{line}"
        );
        if n % 3 != 0 {
            let wheel = 2 * ((n - 1) / 3) + n % 3;
            let drive = format!("wheel {wheel} drive forward ");
            assert!(line.contains(&drive), "{line}");
            // A drive board's LED2 only flickers with the heartbeat (1 ms in every 101): it
            // reads as dark for as long as the board has run, and flickering.
            let (_, led2) = line
                .split_once("LED2 off ")
                .unwrap_or_else(|| panic!("{line}"));
            let (age, rest) = led2.split_once(" s").unwrap_or_else(|| panic!("{line}"));
            assert!(age.parse::<f64>().is_ok_and(|age| age > 1.0), "{line}");
            assert!(rest.starts_with(", flickering;"), "{line}");
        }
    }
    // An 8 A spike on wheel 2's drive: controller 2 latches LED1 (its motor 0); the eight
    // boards the master spreads the stop to light both (an exception of no motor); every
    // bridge is off.
    s.twin
        .borrow_mut()
        .spike(2, Axis::Drive, 8.0, 30.0)
        .unwrap();
    s.pass(3.0);
    let after = boards(&s);
    println!("{}", after.join("\n"));
    for (n, line) in (1..=9).zip(&after) {
        let held = |led| lit_for_s(line, led).is_some_and(|t| t >= 1.5);
        if n == 2 {
            assert!(held(1) && !held(2), "{line}");
        } else {
            assert!(held(1) && held(2), "{line}");
        }
        let motors = line.split_once("; ").map_or("", |(_, m)| m);
        let off: Vec<bool> = motors.split(", ").map(|m| m.ends_with(" off")).collect();
        assert_eq!(off, [true, true], "{line}");
    }
}

#[test]
fn hostctls_stop_fails_naming_a_board_that_masks_remoteslave() {
    // Controller 4 masks REMOTESLAVE (DISABLEDEXCEPTIONS bit 3): it ignores the stop's
    // REG_EXCEPTIONDATA and its drive keeps power. The line fails naming it; every other
    // board was stopped and released. (hostctl's exit would then close the port and reboot
    // the rover; this session keeps it open, to show what the failure reports.)
    let mut s = watched_while_driving();
    let error = hostctl_run(&mut s, "masked", "write 4 disabledexceptions 8\nstop\n")
        .expect_err("the stop fails");
    assert!(
        error.contains("line 2 (`stop`) failed: controller(s) 4 ignored the stop"),
        "{error}"
    );
    no_board_in_exception(&mut s);
    // A second on: its wheel (3) still driven under the stop's zero gains, decaying ×0.96
    // a window; every other wheel coasted down unpowered.
    s.pass(1.0);
    let speeds = physical_speeds(&s);
    println!("1 s after the stop, ticks/s: {speeds:?}");
    for (w, v) in WHEELS.zip(&speeds) {
        if w == 3 {
            assert!(*v > 500.0, "wheel 3 at {v}");
        } else {
            assert!(v.abs() < 50.0, "wheel {w} at {v}");
        }
    }
}
