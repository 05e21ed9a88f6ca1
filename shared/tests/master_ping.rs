//! The master's schedule against a fake rover: boot resets, ping, spreading, exception
//! masking, liveness checks and the silent-slave bound.

use shared::exception::{ExceptionType, MasterException, MasterLatch};
use shared::master::ping::{
    Action, Outcome, Phase, RegWrite, Schedule, LIVENESS_MAX_AGE_MS, LIVENESS_PERIOD_MS,
    SILENT_DETECT_BOUND_MS,
};
use shared::regs::id;

/// Bus time of one transaction at 100 kHz, µs: a 2-byte write is 4 bytes of 9 bits plus
/// START/STOP; a 2-byte read is a 2-byte write of the id and a 3-byte read.
const WRITE_US: u64 = 400;
const READ_US: u64 = 650;
/// A slave that does not answer: the I2C driver gives up after this long.
const NO_ANSWER_US: u64 = 1000;
/// One temperature tick of OneWire traffic.
const TEMPERATURE_US: u64 = 16_000;
/// One pass of the master loop with nothing to do.
const IDLE_PASS_US: u64 = 50;

#[derive(Clone, Copy, Debug)]
struct Slave {
    present: bool,
    answering: bool,
    /// The slave stops answering at this time (µs).
    silent_from_us: u64,
    status: u16,
    exception: u16,
}

impl Slave {
    fn running(device: u8) -> Slave {
        let board = if device.is_multiple_of(3) {
            0x0004
        } else {
            0x0008
        };
        Slave {
            present: true,
            answering: true,
            silent_from_us: u64::MAX,
            status: board,
            exception: 0x0502,
        }
    }

    fn raise(&mut self, code: u8, motor: u8) {
        self.status |= 1;
        self.exception = u16::from_le_bytes([code, motor]);
    }
}

/// Nine slaves, a µs clock, and a log of every action with its start time.
#[derive(Clone)]
struct Rover {
    slaves: [Slave; 10],
    now_us: u64,
    log: Vec<(u64, Action)>,
    /// Time the master spends on a PC frame after each poll loop (the loop's blocking).
    frame_us: u64,
}

impl Rover {
    fn new() -> Rover {
        let mut slaves = [Slave::running(0); 10];
        for (d, s) in slaves.iter_mut().enumerate() {
            *s = Slave::running(d as u8);
        }
        slaves[0].present = false;
        Rover {
            slaves,
            now_us: 0,
            log: Vec::new(),
            frame_us: 0,
        }
    }

    fn now_ms(&self) -> u32 {
        (self.now_us / 1000) as u32
    }

    fn perform(&mut self, action: Action) -> Outcome {
        self.log.push((self.now_us, action));
        let now = self.now_us;
        let slave = action
            .device()
            .map(|d| &mut self.slaves[usize::from(d)])
            .filter(|s| s.present && s.answering && now < s.silent_from_us);
        let (cost, outcome) = match (action, slave) {
            (Action::TemperatureTick, _) => (TEMPERATURE_US, Outcome::Done),
            (_, None) => (NO_ANSWER_US, Outcome::NoAnswer),
            (Action::WriteReg(w), Some(s)) => {
                if w.id == id::REG_EXCEPTIONDATA {
                    s.raise(3, 5);
                }
                (WRITE_US, Outcome::Done)
            }
            (Action::ReadStatus { .. }, Some(s)) => (READ_US, Outcome::Value(s.status)),
            (Action::ReadExceptionData { .. }, Some(s)) => {
                let data = if s.status & 1 != 0 { s.exception } else { 0 };
                (READ_US, Outcome::Value(data))
            }
        };
        self.now_us += cost;
        outcome
    }

    /// Runs the master loop until `until_us`: poll everything due, then a PC frame (if
    /// any), then an idle pass.
    fn run(&mut self, s: &mut Schedule, latch: &mut MasterLatch, until_us: u64) {
        while self.now_us < until_us {
            // The firmware reads its ms clock for every poll.
            while let Some(a) = s.poll(self.now_ms()) {
                let outcome = self.perform(a);
                s.feed(outcome, latch);
            }
            self.now_us += self.frame_us + IDLE_PASS_US;
        }
    }

    /// Performs everything due now, as one poll loop of the firmware, and returns it.
    fn run_now(&mut self, s: &mut Schedule, latch: &mut MasterLatch) -> Vec<Action> {
        let from = self.now_us;
        let now = self.now_ms();
        s.run(now, latch, |a| self.perform(a));
        self.actions_between(from, self.now_us)
    }

    fn actions_between(&self, from_us: u64, to_us: u64) -> Vec<Action> {
        self.log
            .iter()
            .filter(|(t, _)| (from_us..to_us).contains(t))
            .map(|&(_, a)| a)
            .collect()
    }
}

fn writes_to(actions: &[Action], reg: u8) -> Vec<(u8, Vec<u8>)> {
    actions
        .iter()
        .filter_map(|a| match a {
            Action::WriteReg(w) if w.id == reg => Some((w.device, w.bytes().to_vec())),
            _ => None,
        })
        .collect()
}

fn spread_targets(actions: &[Action]) -> Vec<u8> {
    writes_to(actions, id::REG_EXCEPTIONDATA)
        .into_iter()
        .map(|(d, bytes)| {
            assert_eq!(bytes, [0x64, 0x00], "REG_EXCEPTIONDATA = 100");
            d
        })
        .collect()
}

/// A rover past its boot, with the master's exception cleared (as the PC does).
fn booted() -> (Schedule, MasterLatch, Rover) {
    booted_with(Rover::new())
}

/// A rover run to `until_us` whose master the PC never reset: still in its boot exception.
fn never_reset(until_us: u64) -> (Schedule, MasterLatch, Rover) {
    run_from_boot(Rover::new(), until_us)
}

/// [`booted`] with a rover set up before the boot (e.g. with absent slaves).
fn booted_with(rover: Rover) -> (Schedule, MasterLatch, Rover) {
    let (s, mut latch, rover) = run_from_boot(rover, 5_500_000);
    latch.clear();
    (s, latch, rover)
}

/// `rover` with a master fresh from its boot, run to `until_us`.
fn run_from_boot(mut rover: Rover, until_us: u64) -> (Schedule, MasterLatch, Rover) {
    let mut s = Schedule::new();
    let mut latch = MasterLatch::boot();
    rover.run(&mut s, &mut latch, until_us);
    (s, latch, rover)
}

#[test]
fn boot_hard_resets_slaves_1_to_9_once_and_then_waits_5_s() {
    let mut s = Schedule::new();
    let mut latch = MasterLatch::boot();
    let mut rover = Rover::new();
    assert_eq!(s.phase(), Phase::Boot);
    rover.run(&mut s, &mut latch, 5_000_000);
    let resets = writes_to(&rover.actions_between(0, 5_000_000), id::REG_RESET);
    let expected: Vec<(u8, Vec<u8>)> = (1..=9).map(|d| (d, vec![2])).collect();
    assert_eq!(resets, expected);
    assert_eq!(
        rover.log.len(),
        9,
        "nothing else before 5 s: {:?}",
        rover.log
    );
    assert_eq!(s.phase(), Phase::Settling);
    assert!(!s.started(), "the remote control waits as the pings do");
    assert!(s.booted());
    assert_eq!(latch, MasterLatch::boot(), "boot resets raise nothing");
}

#[test]
fn pings_start_after_5_s_and_repeat_when_more_than_1_s_has_passed() {
    let (mut s, mut latch, mut rover) = booted();
    rover.run(&mut s, &mut latch, 9_500_000);
    assert_eq!(s.phase(), Phase::Running);
    assert!(s.started());
    let ping_starts: Vec<u64> = rover
        .log
        .iter()
        .filter(|(_, a)| matches!(a, Action::WriteReg(w) if w.device == 1 && w.id == id::REG_PING))
        .map(|&(t, _)| t / 1000)
        .collect();
    assert_eq!(ping_starts.len(), 5, "{ping_starts:?}");
    assert_eq!(ping_starts[0], 5001);
    for pair in ping_starts.windows(2) {
        // More than 1000 ms; later only by what the loop was busy with (a temperature tick).
        assert!(
            pair[1] - pair[0] > 1000 && pair[1] - pair[0] <= 1020,
            "{ping_starts:?}"
        );
    }
    let ticks: Vec<u64> = rover
        .log
        .iter()
        .filter(|(_, a)| *a == Action::TemperatureTick)
        .map(|&(t, _)| t / 1000)
        .collect();
    assert_eq!(ticks.len(), 3);
    assert!(ticks[0] >= 5001 && ticks[0] < 5030, "{ticks:?}");
    for pair in ticks.windows(2) {
        assert!(
            pair[1] - pair[0] > 2000 && pair[1] - pair[0] < 2030,
            "{ticks:?}"
        );
    }
}

#[test]
fn a_ping_writes_ping_reads_status_and_reads_exception_data_only_when_bit_0_is_set() {
    let (mut s, mut latch, mut rover) = booted();
    // Every slave still in its boot exception except 2, which the PC reset.
    for d in 1..=9 {
        rover.slaves[d].status |= 1;
    }
    rover.slaves[2].status = 0x0008;
    rover.run(&mut s, &mut latch, 5_900_000);
    rover.log.clear();
    rover.run(&mut s, &mut latch, 6_100_000);
    let ping: Vec<Action> = rover
        .log
        .iter()
        .map(|&(_, a)| a)
        .skip_while(|a| *a != Action::WriteReg(RegWrite::byte(1, id::REG_PING, 0)))
        .collect();
    let mut expected = Vec::new();
    for d in 1..=9u8 {
        expected.push(Action::WriteReg(RegWrite::byte(d, id::REG_PING, 0)));
        expected.push(Action::ReadStatus { device: d });
        if d != 2 {
            expected.push(Action::ReadExceptionData { device: d });
        }
    }
    assert_eq!(ping[..expected.len()], expected[..]);
    assert_eq!(latch.data(), 0, "BOOT never spreads");
}

#[test]
fn a_slave_exception_is_latched_and_spread_to_exactly_the_other_slaves() {
    let (mut s, mut latch, mut rover) = booted();
    for d in 1..=9 {
        rover.slaves[d].status &= !1;
    }
    rover.slaves[4].raise(1, 1); // overcurrent on controller 4, motor 1
    let from = rover.now_us;
    rover.run(&mut s, &mut latch, 7_100_000);
    assert_eq!(latch.data(), 0x1401);
    let actions = rover.actions_between(from, rover.now_us);
    assert_eq!(spread_targets(&actions), [1, 2, 3, 5, 6, 7, 8, 9]);
    // The spread comes right after the read that found it.
    let at = actions
        .iter()
        .position(|a| *a == Action::ReadExceptionData { device: 4 })
        .unwrap();
    assert!(
        matches!(actions[at + 1], Action::WriteReg(w) if w.id == id::REG_EXCEPTIONDATA && w.device == 1)
    );
    // Now every other slave is in REMOTESLAVE, which is never spread again: the next
    // three pings spread nothing.
    let from = rover.now_us;
    rover.run(&mut s, &mut latch, from + 3_000_000);
    let later = rover.actions_between(from, rover.now_us);
    assert!(
        later.contains(&Action::ReadExceptionData { device: 1 }),
        "the pings read the REMOTESLAVE exceptions"
    );
    assert_eq!(spread_targets(&later), Vec::<u8>::new());
    assert_eq!(latch.data(), 0x1401, "the first exception stays latched");
}

#[test]
fn a_slave_silenced_by_its_bus_timeout_spreads_like_any_slave_fault() {
    let (mut s, mut latch, mut rover) = booted();
    for d in 1..=9 {
        rover.slaves[d].status &= !1;
    }
    rover.slaves[7].raise(12, 5); // BUSSILENT on controller 7, no motor
    let from = rover.now_us;
    rover.run(&mut s, &mut latch, 7_100_000);
    assert_eq!(latch.data(), 0x570c);
    let actions = rover.actions_between(from, rover.now_us);
    assert_eq!(spread_targets(&actions), [1, 2, 3, 4, 5, 6, 8, 9]);
}

#[test]
fn a_master_side_exception_spreads_to_all_nine() {
    let (mut s, mut latch, mut rover) = booted();
    let missing = MasterException {
        kind: ExceptionType::SensorMissing,
        slave: 0,
        motor: 0,
    };
    assert!(s.raise(missing, &mut latch));
    assert_eq!(latch.data(), 0x000a);
    assert_eq!(
        spread_targets(&rover.run_now(&mut s, &mut latch)),
        [1, 2, 3, 4, 5, 6, 7, 8, 9]
    );
    assert!(!s.raise(missing, &mut latch), "only the first is latched");
}

#[test]
fn stopping_everything_raises_pc_silent_and_spreads_to_all_nine() {
    let (mut s, mut latch, mut rover) = booted();
    rover.run(&mut s, &mut latch, 7_000_000);
    s.stop_everything(MasterException::PC_SILENT, &mut latch);
    assert_eq!(latch.data(), 0x000d);
    let actions = rover.run_now(&mut s, &mut latch);
    // Before anything else due, each slave once.
    assert_eq!(spread_targets(&actions[..9]), [1, 2, 3, 4, 5, 6, 7, 8, 9]);
    assert_eq!(spread_targets(&actions).len(), 9);
}

#[test]
fn stopping_everything_spreads_even_while_the_master_is_in_exception() {
    // From boot until the PC resets it, the master is in its boot exception, which
    // refuses every other: the spread must not depend on the latch.
    let (mut s, mut latch, mut rover) = never_reset(7_000_000);
    s.stop_everything(MasterException::PC_SILENT, &mut latch);
    assert_eq!(
        latch,
        MasterLatch::boot(),
        "the boot exception stays latched"
    );
    let actions = rover.run_now(&mut s, &mut latch);
    assert_eq!(spread_targets(&actions), [1, 2, 3, 4, 5, 6, 7, 8, 9]);
}

#[test]
fn while_the_master_is_in_exception_slave_exceptions_are_neither_recorded_nor_spread() {
    let mut s = Schedule::new();
    let mut latch = MasterLatch::boot();
    let mut rover = Rover::new();
    for d in 1..=9 {
        rover.slaves[d].status &= !1;
    }
    rover.slaves[7].raise(8, 0); // short on controller 7
    rover.run(&mut s, &mut latch, 8_000_000);
    assert_eq!(latch, MasterLatch::boot(), "still the boot exception");
    assert!(spread_targets(&rover.actions_between(0, rover.now_us)).is_empty());
    // The ping did read it, as the original does.
    assert!(rover
        .log
        .iter()
        .any(|&(_, a)| a == Action::ReadExceptionData { device: 7 }));
}

#[test]
fn resetting_the_master_leaves_slaves_alone_and_a_slave_still_in_exception_is_found_again() {
    let (mut s, mut latch, mut rover) = booted();
    for d in 1..=9 {
        rover.slaves[d].status &= !1;
    }
    rover.slaves[4].raise(1, 0);
    rover.run(&mut s, &mut latch, 6_100_000);
    assert_eq!(latch.data(), 0x0401);
    // The PC resets the master only (a write to REGMASTER_RESET).
    latch.clear();
    let cleared_at = rover.now_us;
    rover.run(&mut s, &mut latch, 6_900_000);
    let after = rover.actions_between(cleared_at, rover.now_us);
    assert!(
        after.iter().all(|a| !matches!(a, Action::WriteReg(_))),
        "no slave is written before the next ping: {after:?}"
    );
    assert_eq!(latch.data(), 0, "not re-raised before the next ping");
    rover.run(&mut s, &mut latch, 7_100_000);
    assert_eq!(latch.data(), 0x0401, "re-detected by the next ping");
    // Slaves in REMOTESLAVE (type 3) alone would not have raised anything.
    let spread = spread_targets(&rover.actions_between(6_900_000, rover.now_us));
    assert_eq!(spread, [1, 2, 3, 5, 6, 7, 8, 9]);
}

/// Start times of the accesses to each slave in a window of the log.
fn access_times(rover: &Rover, from_us: u64, to_us: u64) -> Vec<Vec<u64>> {
    let mut times = vec![Vec::new(); 10];
    for &(t, a) in rover
        .log
        .iter()
        .filter(|(t, _)| (from_us..to_us).contains(t))
    {
        if let Some(d) = a.device() {
            times[usize::from(d)].push(t);
        }
    }
    times
}

#[test]
fn liveness_checks_pace_one_status_read_every_2_ms_and_skip_absent_slaves() {
    let mut rover = Rover::new();
    rover.slaves[8].present = false; // a rover without pair 2's second drive board
    rover.slaves[9].present = false;
    let (mut s, mut latch, mut rover) = booted_with(rover);
    assert_eq!(s.present(), 0b0_1111_1110);
    // 40 ms between pings and temperature ticks.
    rover.run(&mut s, &mut latch, 6_200_000);
    let from = rover.now_us;
    rover.run(&mut s, &mut latch, from + 40_000);
    let checks: Vec<(u64, u8)> = rover
        .log
        .iter()
        .filter(|(t, _)| *t >= from)
        .filter_map(|&(t, a)| match a {
            Action::ReadStatus { device } => Some((t, device)),
            _ => None,
        })
        .collect();
    assert_eq!(checks.len(), 20, "{checks:?}");
    assert!(checks.iter().all(|&(_, d)| (1..=7).contains(&d)));
    for pair in checks.windows(2) {
        let gap_ms = (pair[1].0 - pair[0].0) as f64 / 1000.0;
        assert!(
            (1.9..2.1).contains(&gap_ms),
            "every {LIVENESS_PERIOD_MS} ms: {gap_ms}"
        );
    }
    // Stalest first: each slave is visited once per 7 checks.
    let devices: Vec<u8> = checks.iter().map(|&(_, d)| d).collect();
    for window in devices.windows(7) {
        let mut w = window.to_vec();
        w.sort();
        assert_eq!(w, [1, 2, 3, 4, 5, 6, 7], "{devices:?}");
    }
}

#[test]
fn after_the_loop_was_blocked_every_stale_slave_is_checked_at_once() {
    let (mut s, mut latch, mut rover) = booted();
    rover.frame_us = 15_000;
    rover.run(&mut s, &mut latch, 6_200_000);
    let from = rover.now_us;
    rover.run(&mut s, &mut latch, from + 300_000);
    for (d, times) in access_times(&rover, from, rover.now_us)
        .iter()
        .enumerate()
        .skip(1)
    {
        for pair in times.windows(2) {
            let gap = pair[1] - pair[0];
            // L plus one blocking frame plus the other checks of one catch-up.
            assert!(
                gap <= u64::from(LIVENESS_MAX_AGE_MS) * 1000 + 15_000 + 8 * READ_US + 2000,
                "slave {d} unvisited for {gap} µs"
            );
        }
        assert!(times.len() >= 9, "slave {d}: {times:?}");
    }
    assert_eq!(latch.data(), 0);
}

#[test]
fn slaves_absent_from_boot_are_never_silent() {
    let mut rover = Rover::new();
    for d in 7..=9 {
        rover.slaves[d].present = false;
    }
    let (mut s, mut latch, mut rover) = booted_with(rover);
    rover.run(&mut s, &mut latch, 12_000_000);
    assert_eq!(latch.data(), 0);
    assert_eq!(s.silent(), 0);
    assert_eq!(s.present(), 0b0111_1110);
}

#[test]
fn one_missed_answer_is_rechecked_at_once_and_raises_nothing() {
    let (mut s, mut latch, mut rover) = booted();
    rover.run(&mut s, &mut latch, 6_300_000);
    let mut r = rover.clone();
    // Slave 3 misses exactly one access.
    let mut missed = false;
    let before = r.log.len();
    let mut perform = |r: &mut Rover, a: Action| {
        if !missed && a.device() == Some(3) {
            missed = true;
            r.log.push((r.now_us, a));
            r.now_us += NO_ANSWER_US;
            return Outcome::NoAnswer;
        }
        r.perform(a)
    };
    while r.now_us < 6_400_000 {
        let now = r.now_ms();
        while let Some(a) = s.poll(now) {
            let o = perform(&mut r, a);
            s.feed(o, &mut latch);
        }
        r.now_us += IDLE_PASS_US;
    }
    assert_eq!(latch.data(), 0);
    assert_eq!(s.silent(), 0);
    let after: Vec<Action> = r.log[before..].iter().map(|&(_, a)| a).collect();
    let first = after.iter().position(|a| a.device() == Some(3)).unwrap();
    assert_eq!(
        after[first + 1],
        Action::ReadStatus { device: 3 },
        "immediate re-check"
    );
}

/// Simulates slave `victim` going silent at `at_us` and returns (time the master latched
/// SlaveSilent, time its spread finished), relative to `at_us`.
fn silence(base: &(Schedule, MasterLatch, Rover), victim: usize, at_us: u64) -> (u64, u64) {
    let (mut s, mut latch, mut rover) = base.clone();
    rover.slaves[victim].silent_from_us = at_us;
    let start = at_us;
    let mut latched_at = None;
    while rover.now_us < at_us + 200_000 {
        while let Some(a) = s.poll(rover.now_ms()) {
            let o = rover.perform(a);
            s.feed(o, &mut latch);
            if latched_at.is_none() && latch.data() != 0 {
                latched_at = Some(rover.now_us);
            }
        }
        if latched_at.is_some() {
            break;
        }
        rover.now_us += rover.frame_us + IDLE_PASS_US;
    }
    let latched_at = latched_at.expect("SlaveSilent was raised");
    let expected = MasterException {
        kind: ExceptionType::SlaveSilent,
        slave: victim as u8,
        motor: 0,
    };
    assert_eq!(latch.current(), Some(expected));
    assert_eq!(latch.data(), 0x000b | ((victim as u16) << 8));
    let spread = spread_targets(&rover.actions_between(latched_at - NO_ANSWER_US, rover.now_us));
    let others: Vec<u8> = (1..=9u8).filter(|&d| d != victim as u8).collect();
    assert_eq!(spread, others, "every other slave, once");
    assert_eq!(s.silent(), 1 << victim);
    let spread_done = rover
        .log
        .iter()
        .filter(|&&(t, a)| {
            t >= start && matches!(a, Action::WriteReg(w) if w.id == id::REG_EXCEPTIONDATA)
        })
        .map(|&(t, _)| t + WRITE_US)
        .max()
        .unwrap_or(u64::MAX);
    (latched_at - start, spread_done - start)
}

#[test]
fn a_silent_slave_stops_every_motor_within_the_bound_wherever_it_falls_in_the_schedule() {
    let base = booted();
    let mut worst = (0, 0);
    // Every 3 ms over 2.1 s: all phases of the ping, temperature and check cadences.
    for k in 0..700u64 {
        let victim = 1 + (k % 9) as usize;
        let (latched, spread_done) = silence(&base, victim, 6_000_000 + k * 3000 + k % 3);
        worst = (worst.0.max(latched), worst.1.max(spread_done));
    }
    // The cadence bound plus one temperature tick (the longest block), two failed
    // transfers and a ping's worth of reads that were under way.
    let bound_us =
        u64::from(SILENT_DETECT_BOUND_MS) * 1000 + TEMPERATURE_US + 8 * READ_US + 2 * NO_ANSWER_US;
    eprintln!(
        "worst: latched {} µs, spread done {} µs after silence",
        worst.0, worst.1
    );
    assert!(worst.0 <= bound_us, "latched {} µs after silence", worst.0);
    assert!(
        worst.1 <= 45_000,
        "spread done {} µs after silence: slaves get ≥ 5 ms of the 50-ms goal",
        worst.1
    );
}

#[test]
fn with_pc_frames_blocking_the_loop_the_bound_still_holds() {
    let mut base = booted();
    base.2.frame_us = 15_000; // a 24-register read frame after every poll loop
    let mut worst = 0;
    for k in 0..300u64 {
        let victim = 1 + (k % 9) as usize;
        let (_, spread_done) = silence(&base, victim, 6_000_000 + k * 3331);
        worst = worst.max(spread_done);
    }
    eprintln!("worst with 15-ms frames: spread done {worst} µs after silence");
    assert!(worst <= 45_000, "spread done {worst} µs after silence");
}

#[test]
fn a_silent_slave_is_raised_again_after_a_master_reset_and_forgotten_when_it_answers() {
    let (mut s, mut latch, mut rover) = never_reset(5_600_000);
    rover.slaves[6].answering = false;
    rover.run(&mut s, &mut latch, 5_700_000);
    assert_eq!(latch, MasterLatch::boot(), "masked by the boot exception");
    assert_eq!(s.silent(), 1 << 6, "but known");
    latch.clear();
    let cleared = rover.now_us;
    rover.run(&mut s, &mut latch, cleared + 25_000);
    assert_eq!(latch.data(), 0x060b, "raised again after the reset");
    let spread = spread_targets(&rover.actions_between(cleared, rover.now_us));
    assert_eq!(spread, [1, 2, 3, 4, 5, 7, 8, 9]);
    rover.slaves[6].answering = true;
    rover.run(&mut s, &mut latch, rover.now_us + 25_000);
    assert_eq!(s.silent(), 0);
}

#[test]
fn a_slave_found_silent_while_the_master_is_in_its_boot_exception_still_stops_the_others() {
    // A PC program that reset the slaves but not the master: the boot exception stays
    // latched and refuses SlaveSilent, but the others must stop all the same (the
    // library's emergency stop gives up at the silent board's 8c).
    let (mut s, mut latch, mut rover) = never_reset(6_000_000);
    rover.slaves[4].answering = false;
    let from = rover.now_us;
    rover.run(&mut s, &mut latch, from + 40_000);
    assert_eq!(
        latch,
        MasterLatch::boot(),
        "the boot exception stays latched"
    );
    let spread = spread_targets(&rover.actions_between(from, rover.now_us));
    assert_eq!(
        spread,
        [1, 2, 3, 5, 6, 7, 8, 9],
        "once, when it is found silent"
    );
    // Its later failures do not spread again while the latch refuses them.
    let later = rover.now_us;
    rover.run(&mut s, &mut latch, later + 500_000);
    assert!(spread_targets(&rover.actions_between(later, rover.now_us)).is_empty());
}

/// Every slave is out of reach (a bus held low) for 100 ms, so the master finds one
/// silent and its spread is lost; then all but slave 4 (or all, `all_back`) answer again.
fn spread_lost_on_a_held_bus(clear_before_back: bool, all_back: bool) -> (MasterLatch, Rover, u64) {
    let (mut s, mut latch, mut rover) = booted();
    rover.run(&mut s, &mut latch, 6_000_000);
    for d in 1..=9 {
        rover.slaves[d].answering = false;
    }
    rover.run(&mut s, &mut latch, 6_100_000);
    assert_eq!(latch.data() & 0xff, 11, "SlaveSilent");
    if clear_before_back {
        latch.clear();
    }
    let back = rover.now_us;
    for d in (1..=9).filter(|&d| all_back || d != 4) {
        rover.slaves[d].answering = true;
        rover.slaves[d].status &= !1;
    }
    rover.run(&mut s, &mut latch, back + 40_000);
    (latch, rover, back)
}

#[test]
fn a_spread_the_bus_lost_is_sent_again_when_the_slaves_answer() {
    let (_, rover, back) = spread_lost_on_a_held_bus(false, false);
    let again = spread_targets(&rover.actions_between(back, rover.now_us));
    for d in [1, 2, 3, 5, 6, 7, 8, 9] {
        assert!(again.contains(&d), "slave {d}: {again:?}");
        assert_eq!(
            rover.slaves[usize::from(d)].status & 1,
            1,
            "slave {d} stopped"
        );
    }
}

#[test]
fn a_lost_spread_is_not_sent_again_once_the_pc_has_cleared_the_exception() {
    let (latch, rover, back) = spread_lost_on_a_held_bus(true, true);
    assert_eq!(latch.data(), 0, "every slave answers: nothing raised again");
    assert!(spread_targets(&rover.actions_between(back, rover.now_us)).is_empty());
}

#[test]
fn failures_of_pc_relayed_accesses_count_as_evidence() {
    let (mut s, mut latch, _) = booted();
    let mut rover = Rover::new();
    rover.run(&mut s, &mut latch, 5_600_000);
    s.observe(2, false, 5600, &mut latch);
    assert_eq!(latch.data(), 0);
    s.observe(2, false, 5600, &mut latch);
    assert_eq!(latch.data(), 0x020b);
    assert_eq!(
        s.poll(5600),
        Some(Action::WriteReg(RegWrite::word(
            1,
            id::REG_EXCEPTIONDATA,
            100
        ))),
        "the spread comes next"
    );
    // A slave that never answered is not made silent by relayed failures.
    let mut fresh = Schedule::new();
    let mut l2 = MasterLatch::boot();
    l2.clear();
    fresh.observe(3, false, 0, &mut l2);
    fresh.observe(3, false, 0, &mut l2);
    assert_eq!(l2.data(), 0);
}

#[test]
fn a_slave_the_pc_reached_during_the_settle_and_then_lost_is_found_silent_by_the_first_ping() {
    // The PC drives slave 4 at 2.5 s (the master relays its frame), and slave 4 drops off
    // the bus at 4.3 s, before the pings start.
    let mut rover = Rover::new();
    let mut s = Schedule::new();
    let mut latch = MasterLatch::boot();
    rover.run(&mut s, &mut latch, 2_000_000);
    latch.clear();
    s.observe(4, true, 2500, &mut latch);
    rover.run(&mut s, &mut latch, 4_300_000);
    rover.slaves[4].answering = false;
    // Relayed failures during the settle prove nothing (slaves reboot from the boot resets).
    s.observe(4, false, 4400, &mut latch);
    s.observe(4, false, 4450, &mut latch);
    assert_eq!(latch.data(), 0, "no raise before 5 s");
    rover.run(&mut s, &mut latch, 5_100_000);
    assert_eq!(
        latch.data(),
        0x040b,
        "SlaveSilent naming slave 4 at the first ping"
    );
    let spread = spread_targets(&rover.actions_between(5_000_000, rover.now_us));
    assert_eq!(spread, [1, 2, 3, 5, 6, 7, 8, 9]);
    // A slave never reached before the settle and absent after it is still not fitted.
    let mut absent = Rover::new();
    absent.slaves[7].answering = false;
    let (s, latch, _) = booted_with(absent);
    assert_eq!(latch.data(), 0);
    assert_eq!(s.silent(), 0);
}

#[test]
fn polling_without_feeding_repeats_the_current_action() {
    let mut s = Schedule::new();
    let mut latch = MasterLatch::boot();
    let first = s.poll(0);
    assert_eq!(
        first,
        Some(Action::WriteReg(RegWrite::byte(1, id::REG_RESET, 2)))
    );
    assert_eq!(s.poll(0), first);
    assert!(!s.booted());
    s.feed(Outcome::NoAnswer, &mut latch);
    assert_eq!(
        s.poll(0),
        Some(Action::WriteReg(RegWrite::byte(2, id::REG_RESET, 2)))
    );
}
