//! Support for the twin tests: the twin in emulated time behind `hostctl`'s own link code,
//! so each test talks to the rover as the original PC library does (wait for `Ready`, settle
//! 2 s, configure read sets 0, 1, 2, reset exceptions, calibrate, update()) while the whole
//! run costs only emulated time.
//!
//! - [`EmuPort`]: a `hostctl` port whose blocking reads run the twin until bytes arrive or
//!   the timeout passes, in emulated time;
//! - [`EmuClock`]: the library's sleeps, as emulated time;
//! - [`Session`]: one connection, with the library's calls.

#![allow(dead_code)]

use std::cell::RefCell;
use std::collections::VecDeque;
use std::io::{self, Read, Write};
use std::rc::Rc;
use std::time::Duration;

use hostctl::cmd::live::{Poller, Snapshot};
use hostctl::cmd::pc::{self, Motor, Op, Pc};
use hostctl::cmd::run::Clock;
use hostctl::link::Link;
use hostctl::port::Port;
use shared::regs::id;
use twin::Rover;

/// The twin, shared by the port and the clock of one session.
pub type Twin = Rc<RefCell<Rover>>;

/// Chunks of master output, each with the emulated µs it was read at.
pub type OutputLog = Rc<RefCell<Vec<(u64, Vec<u8>)>>>;

/// A serial port onto the twin's master, in emulated time.
pub struct EmuPort {
    twin: Twin,
    timeout_us: u64,
    pending: VecDeque<u8>,
    log: Option<OutputLog>,
}

impl EmuPort {
    /// A port on `twin` with a 1-s read timeout.
    pub fn new(twin: Twin) -> EmuPort {
        EmuPort {
            twin,
            timeout_us: 1_000_000,
            pending: VecDeque::new(),
            log: None,
        }
    }

    /// The same, also logging every chunk the master sends into `log`.
    pub fn recording(twin: Twin, log: OutputLog) -> EmuPort {
        EmuPort {
            log: Some(log),
            ..EmuPort::new(twin)
        }
    }
}

impl Read for EmuPort {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        if self.pending.is_empty() {
            let mut twin = self.twin.borrow_mut();
            let got = twin
                .uart_read_some(self.timeout_us)
                .map_err(io::Error::other)?;
            if let Some(log) = self.log.as_ref().filter(|_| !got.is_empty()) {
                log.borrow_mut().push((twin.micros(), got.clone()));
            }
            self.pending.extend(got);
        }
        if self.pending.is_empty() {
            return Err(io::Error::from(io::ErrorKind::TimedOut));
        }
        let n = buf.len().min(self.pending.len());
        for (slot, byte) in buf.iter_mut().zip(self.pending.drain(..n)) {
            *slot = byte;
        }
        Ok(n)
    }
}

impl Write for EmuPort {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        self.twin.borrow_mut().uart_send(buf);
        Ok(buf.len())
    }

    fn flush(&mut self) -> io::Result<()> {
        Ok(())
    }
}

impl Port for EmuPort {
    fn set_timeout(&mut self, timeout: Duration) -> io::Result<()> {
        self.timeout_us = u64::try_from(timeout.as_micros()).unwrap_or(u64::MAX);
        Ok(())
    }
}

/// The library's sleeps, spent running the twin.
pub struct EmuClock {
    twin: Twin,
    start_us: u64,
}

impl EmuClock {
    /// A clock starting at the twin's time now.
    pub fn new(twin: Twin) -> EmuClock {
        let start_us = twin.borrow().micros();
        EmuClock { twin, start_us }
    }
}

impl EmuClock {
    /// Lets `d` of emulated time pass.
    pub fn sleep_for(&mut self, d: Duration) {
        Clock::sleep(self, d);
    }
}

impl Clock for EmuClock {
    fn now(&self) -> Duration {
        Duration::from_micros(self.twin.borrow().micros() - self.start_us)
    }

    fn sleep(&mut self, d: Duration) {
        let us = u64::try_from(d.as_micros()).unwrap_or(u64::MAX);
        self.twin.borrow_mut().run_us(us).expect("the twin runs");
    }
}

/// The twin from the workspace's images (`TWIN_TEST_FIRMWARE=DIR` picks another directory
/// holding master.elf, slave-drive.elf and slave-lift.elf).
pub fn rover() -> Rover {
    let config = twin::Config {
        firmware_dir: std::env::var_os("TWIN_TEST_FIRMWARE").map(Into::into),
        ..twin::Config::default()
    };
    Rover::with_config(&config).expect("the twin builds (run scripts/firmware.sh)")
}

/// Emulated seconds as microseconds.
pub fn secs(s: f64) -> u64 {
    (s * 1e6) as u64
}

/// One connection to the twin, with the original library's calls.
pub struct Session {
    /// The twin.
    pub twin: Twin,
    /// The link, past the banner.
    pub link: Link<EmuPort>,
    /// The library's state (blocks, demands).
    pub pc: Pc,
    /// update()'s reads.
    pub poller: Poller,
    /// Emulated time.
    pub clock: EmuClock,
}

impl Session {
    /// Builds the twin and connects as the library's init() does: wait for `Ready` (10 lines,
    /// 5 s each), sleep 2 s, configure read sets 0, 1, 2 (each answered with its count).
    pub fn start() -> Session {
        Session::on(rover())
    }

    /// [`Session::start`] on a rover built by the caller (e.g. with faults already in).
    pub fn on(rover: Rover) -> Session {
        let twin = Rc::new(RefCell::new(rover));
        let port = EmuPort::new(Rc::clone(&twin));
        let link = Link::connect(port, "the twin", Duration::ZERO).expect("banner with Ready");
        let mut clock = EmuClock::new(Rc::clone(&twin));
        clock.sleep(hostctl::link::SETTLE);
        let poller = Poller::new().unwrap();
        let mut session = Session {
            twin,
            link,
            pc: Pc::new(),
            poller,
            clock,
        };
        session.poller.configure(&mut session.link).expect(
            "read sets 0, 1, 2 configured: every slave answers (needs the real slave images)",
        );
        session
    }

    /// Sends the library's frames and pauses; every write must be answered 00.
    pub fn send(&mut self, ops: Vec<Op>) {
        for op in ops {
            match op {
                Op::Write(s) => {
                    let reply = self.link.transact(s.device, &s.frame, 1).expect("a reply");
                    assert_eq!(reply, [0], "write {:02x?} refused", s.frame.as_slice());
                }
                Op::Pause(d) => self.clock.sleep(d),
            }
        }
    }

    /// resetExceptions().
    pub fn reset_exceptions(&mut self) {
        self.send(pc::reset_exceptions().unwrap());
    }

    /// calibrate().
    pub fn calibrate(&mut self) {
        let ops = self.pc.calibrate().unwrap();
        self.send(ops);
    }

    /// setRequired on some wheels.
    pub fn set(&mut self, motor: Motor, wheels: &[(u8, f32)]) {
        for &(w, v) in wheels {
            let op = self.pc.set_required(w, motor, v).unwrap();
            self.send(vec![op]);
        }
    }

    /// One write frame, which must be answered 00.
    pub fn write_raw(&mut self, frame: &[u8]) {
        let device = frame[1] >> 4;
        let reply = self.link.transact(device, frame, 1).expect("a reply");
        assert_eq!(reply, [0], "write {frame:02x?} refused");
    }

    /// update(): the ten reads.
    pub fn update(&mut self) -> Snapshot {
        self.poller
            .update(&mut self.link)
            .expect("update() answered")
    }

    /// Runs update() with the library's 10-ms tick until `done` holds or `max_s` of emulated
    /// time pass; returns whether it held, the last snapshot and the time it took.
    pub fn until(
        &mut self,
        max_s: f64,
        mut done: impl FnMut(&Snapshot) -> bool,
    ) -> (bool, Snapshot, Duration) {
        let start = self.clock.now();
        loop {
            let s = self.update();
            let took = self.clock.now() - start;
            if done(&s) {
                return (true, s, took);
            }
            if took.as_secs_f64() >= max_s {
                return (false, s, took);
            }
            self.clock.sleep(Duration::from_millis(10));
        }
    }

    /// Emulated time since the session's clock started.
    pub fn clock_now(&self) -> Duration {
        self.clock.now()
    }

    /// Lets `s` seconds of emulated time pass.
    pub fn pass(&mut self, s: f64) {
        self.clock.sleep(Duration::from_secs_f64(s));
    }
}

/// The actual drive speed of `wheel`, ticks/s.
pub fn drive_speed(s: &Snapshot, wheel: u8) -> f32 {
    let d = pc::device_of(wheel, Motor::Drive);
    s.value(d, id::REGDS_DRIVE_ACTUALSPEED)
        .expect("set 0 holds ACTUALSPEED")
}

/// The actual steer angle of `wheel`, degrees.
pub fn steer_pos(s: &Snapshot, wheel: u8) -> f32 {
    let d = pc::device_of(wheel, Motor::Steer);
    s.value(d, id::REGDS_STEER_ACTUALPOS)
        .expect("set 0 holds STEER_ACTUALPOS")
}

/// The actual lift angle of `wheel`, degrees.
pub fn lift_pos(s: &Snapshot, wheel: u8) -> f32 {
    let d = pc::device_of(wheel, Motor::Lift);
    let reg = if wheel % 2 == 1 {
        id::REGLL_ONE_ACTUALPOS
    } else {
        id::REGLL_TWO_ACTUALPOS
    };
    s.value(d, reg).expect("set 1 holds ACTUALPOS")
}

/// The master's EXCEPTIONDATA.
pub fn master_exception(s: &Snapshot) -> u16 {
    s.raw(0, id::REGMASTER_EXCEPTIONDATA)
        .expect("set 2 holds EXCEPTIONDATA")
}

/// Whether controller `n`'s STATUS was read this update and says it is running (no
/// exception); a controller that did not answer is not.
pub fn slave_running(s: &Snapshot, n: u8) -> bool {
    s.raw(n, id::REG_STATUS)
        .is_some_and(|status| status & 1 == 0)
}

/// Controller `n`'s exception type while its STATUS says it is in exception (`None` also
/// when its STATUS was not read: see [`slave_running`]).
pub fn slave_exception(s: &Snapshot, n: u8) -> Option<u8> {
    let status = s.raw(n, id::REG_STATUS)?;
    (status & 1 == 1).then(|| s.raw(n, id::REG_EXCEPTIONDATA).map(|d| (d & 0xff) as u8))?
}
