//! The twin gives the same result on one thread and on several: the same scripted drive
//! (connect, configure the read sets, reset the exceptions, drive all six wheels, turn, lift
//! wheel 1, then update() every 10 ms) run with `Config::threads` 1 and 2 must produce
//! byte for byte the same master UART output, at the same emulated times, and exactly the
//! same physical wheel states after every update().
//!
//! NEEDS THE REAL SLAVE IMAGES (the read sets are configured on every slave).

mod twin_support;

use std::cell::RefCell;
use std::rc::Rc;
use std::time::Duration;

use hostctl::cmd::live::Poller;
use hostctl::cmd::pc::{self, Motor, Op, Pc, WHEELS};
use hostctl::link::Link;
use twin::{Rover, WheelState};
use twin_support::{drive_speed, EmuClock, EmuPort, OutputLog};

/// What one run saw: every chunk of master output with the emulated time it was read at,
/// and the six wheels' states after each update().
#[derive(Debug, PartialEq)]
struct Record {
    output: Vec<(u64, Vec<u8>)>,
    wheels: Vec<Vec<WheelState>>,
}

/// Runs the scripted drive on a twin with `threads` threads.
fn drive(threads: usize) -> Record {
    let config = twin::Config {
        firmware_dir: std::env::var_os("TWIN_TEST_FIRMWARE").map(Into::into),
        threads,
        ..twin::Config::default()
    };
    let rover = Rover::with_config(&config).expect("the twin builds (run scripts/firmware.sh)");
    assert_eq!(rover.threads(), threads, "worker threads started");
    let twin = Rc::new(RefCell::new(rover));
    let log: OutputLog = Rc::new(RefCell::new(Vec::new()));
    let port = EmuPort::recording(Rc::clone(&twin), Rc::clone(&log));
    let mut link = Link::connect(port, "the twin", Duration::ZERO).expect("banner with Ready");
    let mut clock = EmuClock::new(Rc::clone(&twin));
    let poller = Poller::new().unwrap();
    poller.configure(&mut link).expect("read sets configured");

    let mut pc = Pc::new();
    let mut ops = pc.calibrate().unwrap();
    ops.extend(pc::reset_exceptions().unwrap());
    for w in WHEELS {
        ops.push(pc.set_required(w, Motor::Drive, 1000.0).unwrap());
    }
    ops.push(pc.set_required(1, Motor::Steer, 40.0).unwrap());
    ops.push(pc.set_required(2, Motor::Steer, 40.0).unwrap());
    ops.push(pc.set_required(1, Motor::Lift, 10.0).unwrap());
    for op in ops {
        match op {
            Op::Write(s) => {
                let reply = link.transact(s.device, &s.frame, 1).expect("a reply");
                assert_eq!(reply, [0], "write {:02x?} refused", s.frame.as_slice());
            }
            Op::Pause(d) => clock.sleep_for(d),
        }
    }

    let mut wheels = Vec::new();
    let mut last = None;
    for _ in 0..30 {
        last = Some(poller.update(&mut link).expect("update() answered"));
        let states = WHEELS
            .map(|w| twin.borrow().wheel(w).unwrap())
            .collect::<Vec<_>>();
        wheels.push(states);
        clock.sleep_for(Duration::from_millis(10));
    }
    // The drive must really be under way, or equal records would prove little.
    let snap = last.unwrap();
    let speeds: Vec<f32> = WHEELS.map(|w| drive_speed(&snap, w)).collect();
    assert!(
        speeds.iter().all(|&s| s > 100.0),
        "wheels not driving: {speeds:?}"
    );
    drop(link);
    let output = log.take();
    Record { output, wheels }
}

#[test]
fn two_threads_drive_exactly_as_one() {
    let one = drive(1);
    let two = drive(2);
    let bytes: usize = one.output.iter().map(|(_, b)| b.len()).sum();
    assert!(bytes > 5_000, "only {bytes} bytes of master output");
    assert_eq!(one.wheels.len(), 30);
    assert!(
        one.wheels.last().unwrap()[0].steer_deg > 1.0,
        "wheel 1 steers"
    );
    assert_eq!(one.output.len(), two.output.len(), "output chunks");
    for (i, (a, b)) in one.output.iter().zip(&two.output).enumerate() {
        assert_eq!(a, b, "master output chunk {i}");
    }
    for (i, (a, b)) in one.wheels.iter().zip(&two.wheels).enumerate() {
        assert_eq!(a, b, "wheel states after update {i}");
    }
}
