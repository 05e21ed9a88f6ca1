//! Cycle benchmarks of the drive/steer image in the emulator (not timed tests): the
//! control tick with both controllers running, the encoder-edge task, the idle CPU
//! share and the stack's high-water mark (painted at boot, read back here, within the
//! static bound of `rover_tests::stack_bound`); the TWI byte task
//! under register writes and reads; the highest encoder edge rate counted without a
//! lost edge. Figures go to docs/benchmarks.md (Slave); run with `--nocapture` to see
//! them.

mod slave_support;

use std::cell::RefCell;
use std::collections::HashMap;
use std::rc::Rc;

use harness::{firmware_path, Avr, CpuState, Pin};
use rover_tests::stack_bound::Program;
use shared::regs::id;
use slave_support::{rig, Rig, DRIVE_GAINS, LIFT_GAINS_WHEEL_1, STEER_GAINS_WHEEL_1};

/// Byte addresses of the vectors the slave binds.
const PCINT2: u32 = 5 * 4;
const TIMER0_COMPA: u32 = 14 * 4;
const TIMER0_COMPB: u32 = 15 * 4;
const ADC: u32 = 21 * 4;
const TWI: u32 = 24 * 4;
const VECTORS: [u32; 5] = [PCINT2, TIMER0_COMPA, TIMER0_COMPB, ADC, TWI];

/// Issue 5's goal for the control tick of two motors, mean cycles: met with the steer
/// holding, asserted there.
const TICK_GOAL: u64 = 1_500;

/// Ceilings on the moving ticks' means, which do not meet [`TICK_GOAL`] (docs/benchmarks.md,
/// "Decision"): some 5 % above today's 1,707 and 1,974 cycles, so that a change that makes
/// them slower fails here instead of going unseen.
const SWINGING_CEILING: u64 = 1_800;
const LIFTS_CEILING: u64 = 2_080;

fn pc(avr: &mut Avr) -> u32 {
    // SAFETY: plain field read of the live core.
    unsafe { (*avr.as_ptr()).pc }
}

fn sp(avr: &Avr) -> u16 {
    u16::from_le_bytes([avr.read_data(0x5d), avr.read_data(0x5e)])
}

/// Exclusive cycles per handler run, by vector, and sleeping cycles.
#[derive(Default)]
struct Profile {
    runs: HashMap<u32, Vec<u64>>,
    asleep: u64,
    total: u64,
}

/// Follows handler entries and returns instruction by instruction: the exclusive cycles
/// of every finished handler run, by vector.
#[derive(Default)]
struct Tracker {
    /// (vector, sp at entry, entry cycle, cycles of nested handlers)
    frames: Vec<(u32, u16, u64, u64)>,
    runs: HashMap<u32, Vec<u64>>,
    /// Since when interrupts are off (SREG I clear), and the longest such stretch with
    /// the PC where it ended.
    off_since: Option<u64>,
    longest_off: (u64, u32),
    /// The control tick's exclusive cycles by the byte address of the instruction that
    /// spent them (its interrupt entry included).
    tick_pcs: HashMap<u32, u64>,
    /// The address and the cycle count before the step in progress.
    last: (u32, u64),
}

impl Tracker {
    /// The control task's finished runs (exclusive cycles each).
    fn ticks(&self) -> &[u64] {
        self.runs
            .get(&TIMER0_COMPB)
            .map(Vec::as_slice)
            .unwrap_or_default()
    }

    /// After each step of `avr`.
    fn after_step(&mut self, avr: &mut Avr) {
        let (last_pc, last_cycles) = self.last;
        if self.frames.last().is_some_and(|f| f.0 == TIMER0_COMPB) {
            *self.tick_pcs.entry(last_pc).or_default() += avr.cycles() - last_cycles;
        }
        let now_sp = sp(avr);
        while let Some(&(v, s, at, nested)) = self.frames.last() {
            if now_sp < s + 2 {
                break;
            }
            self.frames.pop();
            let total = avr.cycles() - at;
            self.runs.entry(v).or_default().push(total - nested);
            if let Some(outer) = self.frames.last_mut() {
                outer.3 += total;
            }
        }
        let at = pc(avr);
        if VECTORS.contains(&at) {
            self.frames.push((at, now_sp, avr.cycles(), 0));
        }
        // SAFETY: plain field read of the live core.
        let enabled = unsafe { (*avr.as_ptr()).sreg[7] != 0 };
        match (enabled, self.off_since) {
            (false, None) => self.off_since = Some(avr.cycles()),
            (true, Some(since)) => {
                self.off_since = None;
                let off = avr.cycles() - since;
                if off > self.longest_off.0 {
                    self.longest_off = (off, at);
                }
            }
            _ => {}
        }
        self.last = (at, avr.cycles());
    }
}

/// Steps `avr` for `cycles`, toggling PD0 every `edge_half_period` cycles (0: never).
fn profile(avr: &mut Avr, cycles: u64, edge_half_period: u64) -> Profile {
    let mut p = Profile::default();
    let mut tracker = Tracker::default();
    let start = avr.cycles();
    let mut next_edge = start + edge_half_period;
    let mut level = false;
    while avr.cycles() < start + cycles {
        if edge_half_period > 0 && avr.cycles() >= next_edge {
            level = !level;
            avr.set_pin(Pin::d(0), level);
            next_edge += edge_half_period;
        }
        let before = avr.cycles();
        let asleep = avr.state() == CpuState::Sleeping;
        avr.step();
        if asleep {
            p.asleep += avr.cycles() - before;
        }
        tracker.after_step(avr);
    }
    p.runs = tracker.runs;
    p.total = avr.cycles() - start;
    p
}

fn stats(p: &Profile, v: u32) -> (usize, u64, u64) {
    run_stats(p.runs.get(&v).map(Vec::as_slice).unwrap_or_default())
}

/// (runs, mean, max).
fn run_stats(runs: &[u64]) -> (usize, u64, u64) {
    let max = runs.iter().copied().max().unwrap_or(0);
    let mean = if runs.is_empty() {
        0
    } else {
        runs.iter().sum::<u64>() / runs.len() as u64
    };
    (runs.len(), mean, max)
}

/// Controller 1 (drive/steer) past its boot display, exceptions reset, with calibrate()'s
/// drive and steer gains of wheel 1.
fn calibrated_drive_steer() -> Rig {
    let mut r = rig(1);
    r.run_us(650_000);
    r.reset_exceptions();
    for &(reg, raw) in DRIVE_GAINS.iter().chain(STEER_GAINS_WHEEL_1) {
        r.write_raw(reg, raw);
    }
    r
}

#[test]
fn drive_steer_costs() {
    let mut r = calibrated_drive_steer();
    r.write_value(id::REGDS_DRIVE_REQSPEED, 1000.0);
    r.write_value(id::REGDS_STEER_REQPOS, 20.0);
    r.run_us(1_000_000);
    assert_eq!(r.read_raw(id::REG_STATUS), 0x0008);

    let mut avr = r.avr();
    // 300 ms, with an encoder rising edge every 500 µs (1000 ticks/s).
    let p = profile(&mut avr, 16_000 * 300, 16_000 / 4);
    let (n, mean, max) = stats(&p, TIMER0_COMPB);
    println!("control tick: {n} runs, mean {mean}, max {max} cycles");
    assert!((295..=305).contains(&n), "one tick per ms: {n}");
    assert!(
        mean > 300 && mean <= TICK_GOAL,
        "the tick works within issue 5's goal of {TICK_GOAL} cycles: {mean}"
    );
    let (n, mean, max) = stats(&p, PCINT2);
    println!("encoder edge task: {n} runs, mean {mean}, max {max} cycles");
    assert!(n >= 1_100, "{n} pin changes");
    let (n, mean, max) = stats(&p, ADC);
    println!("ADC task: {n} runs, mean {mean}, max {max} cycles");
    let (n, mean, max) = stats(&p, TIMER0_COMPA);
    println!("millisecond task: {n} runs, mean {mean}, max {max} cycles");
    let idle = 100.0 * p.asleep as f64 / p.total as f64;
    println!("idle (asleep): {idle:.1} % of {} cycles", p.total);
    // The ADC converts in the chip's 13 ADC clocks here (`harness::fidelity`), so the
    // ADC task runs as often as on the chip.
    // 73 % when last recorded; the share moves by a point or so with the run's timing.
    assert!(idle > 65.0 && idle < 100.0, "idle {idle:.1} %");

    // Stack high-water: the lowest address that lost the paint.
    let heap = avr.symbol("__heap_start").expect("symbol") as u16;
    let mut low = heap;
    while low < 0x900 && avr.read_data(low) == 0xc5 {
        low += 1;
    }
    let stack = 0x900 - u32::from(low);
    let statics = u32::from(heap) - 0x100;
    // The worst case is the static bound (`stack_bound`); this run reaches near it.
    let bound = Program::of_elf(&firmware_path("slave-drive"))
        .and_then(|p| p.bound())
        .expect("a static stack bound")
        .total;
    println!(
        "static RAM {statics} B, stack high-water {stack} B (static bound {bound} B), \
         sum with the bound {}",
        statics + bound
    );
    assert!(stack > 20 && stack <= bound, "{stack} of {bound}");
}

/// The TWI task's exclusive cycles per interrupt over one bus operation of the test
/// (acting as the I2C master at 400 kHz), the chip left to finish its last interrupt.
fn twi_runs(r: &mut Rig, tracker: &Rc<RefCell<Tracker>>, op: impl FnOnce(&mut Rig)) -> Vec<u64> {
    tracker.borrow_mut().runs.clear();
    op(r);
    r.bus.run_us(200);
    let runs = tracker.borrow_mut().runs.remove(&TWI);
    runs.unwrap_or_default()
}

#[test]
fn twi_byte_task_costs() {
    let mut r = calibrated_drive_steer();
    r.write_value(id::REGDS_DRIVE_REQSPEED, 1000.0);
    r.run_us(500_000);
    let tracker = Rc::new(RefCell::new(Tracker::default()));
    let t = Rc::clone(&tracker);
    r.avr()
        .set_observer(move |avr| t.borrow_mut().after_step(avr));

    // One register write as the master relays it: SLA+W, id, LSB, MSB, STOP.
    let mut all = Vec::new();
    let mut writes = Vec::new();
    for k in 0..20u16 {
        let runs = twi_runs(&mut r, &tracker, |r| {
            r.write_raw(id::REGDS_DRIVE_REQSPEED, 0x8000 + k)
        });
        assert_eq!(runs.len(), 5, "SLA+W, 3 bytes, STOP: {runs:?}");
        writes.push(runs.iter().sum::<u64>());
        all.extend(runs);
    }
    // One register read: the pointer (SLA+W, id, STOP), then SLA+R, 2 bytes, STOP.
    let mut reads = Vec::new();
    for _ in 0..20 {
        let runs = twi_runs(&mut r, &tracker, |r| {
            assert_eq!(r.read_raw(id::REG_STATUS), 0x0008);
        });
        reads.push(runs.iter().sum::<u64>());
        all.extend(runs);
    }
    // A continued read of 12 bytes: DRIVE_ACTUALSPEED..DRIVE_CURRENT (timed only: what
    // such a read returns is checked by `slave_registers`).
    let mut long_reads = Vec::new();
    for _ in 0..20 {
        let runs = twi_runs(&mut r, &tracker, |r| {
            r.read_bytes(id::REGDS_DRIVE_ACTUALSPEED, 12);
        });
        assert!(runs.len() >= 15, "3 + 13 interrupts or so: {}", runs.len());
        long_reads.push(runs.iter().sum::<u64>());
        all.extend(runs);
    }
    r.avr().clear_observer();
    let (off, at) = tracker.borrow().longest_off;
    println!("longest stretch with interrupts off: {off} cycles (ended at {at:#06x})");

    let (n, mean, max) = run_stats(&all);
    println!("TWI task: {n} interrupts, mean {mean}, max {max} cycles");
    let (_, write_mean, write_max) = run_stats(&writes);
    println!("one register write (5 interrupts): mean {write_mean}, max {write_max} cycles");
    let (_, read_mean, read_max) = run_stats(&reads);
    println!("one 2-byte register read: mean {read_mean}, max {read_max} cycles");
    let (_, long_mean, long_max) = run_stats(&long_reads);
    println!("one 12-byte continued read: mean {long_mean}, max {long_max} cycles");
    // A byte at 400 kHz lasts 22.5 µs = 360 cycles: every interrupt must be far shorter.
    assert!(mean > 20 && max < 360, "mean {mean}, max {max}");
    assert!(write_mean > 5 * 20 && write_max < 5 * 360);
    assert!(long_mean > read_mean, "{long_mean} vs {read_mean}");
}

/// The other master's command: write the pointer (DRIVE_ACTUALSPEED), STOP, read the 12
/// monitoring bytes; its reply, 39 bytes at 115200 baud, takes 3.4 ms.
const READ_12: &[u8] = b"x 01 10 0c\n";
/// One such command every 5 ms, so its UART (polled, no buffer) never overruns.
const TRAFFIC_PERIOD: u64 = 16_000 * 5;

/// A quadrature encoder on PD0 (A) and PD1 (B), forward: A rises, B rises, A falls, B
/// falls, `quarter` cycles apart. Driven from the chip's observer, so every change lands
/// on the chip's own clock (at the first instruction boundary at or after its cycle) even
/// while a bus event runs the chip ahead of the bus.
struct Quadrature {
    quarter: u64,
    next: u64,
    step: usize,
    /// Changes still to make.
    left: u32,
    /// The latest a change landed after its cycle.
    worst_late: u64,
}

impl Quadrature {
    const STEPS: [(u8, bool); 4] = [(0, true), (1, true), (0, false), (1, false)];

    fn drive(&mut self, avr: &mut Avr) {
        while self.left > 0 && avr.cycles() >= self.next {
            let (pin, level) = Self::STEPS[self.step % 4];
            avr.set_pin(Pin::d(pin), level);
            self.worst_late = self.worst_late.max(avr.cycles() - self.next);
            self.step += 1;
            self.left -= 1;
            self.next += self.quarter;
        }
    }
}

/// Feeds `rising` A rising edges at `rate` per second. With a `master` chip, it is sent
/// [`READ_12`] every [`TRAFFIC_PERIOD`] meanwhile. Returns the commands sent and the
/// latest an encoder change landed, in cycles.
fn feed_quadrature(r: &mut Rig, rising: u32, rate: u32, master: Option<usize>) -> (u32, u64) {
    let quarter = 16_000_000 / (4 * u64::from(rate));
    // A bus event may have left the chip ahead of the bus: start on the chip's clock.
    let start = r.avr().cycles().max(r.bus.cycles());
    let encoder = Rc::new(RefCell::new(Quadrature {
        quarter,
        next: start,
        step: 0,
        left: 4 * rising,
        worst_late: 0,
    }));
    let e = Rc::clone(&encoder);
    r.avr().set_observer(move |avr| e.borrow_mut().drive(avr));
    let mut next_command = start;
    let mut commands = 0;
    while encoder.borrow().left > 0 {
        // Bus runs end on the changes' cycles, so a sleeping chip wakes for each.
        let next = encoder.borrow().next;
        let now = r.bus.cycles();
        r.bus.run_cycles(next.saturating_sub(now).max(1));
        encoder.borrow_mut().drive(&mut r.avr());
        if let Some(m) = master.filter(|_| r.bus.cycles() >= next_command) {
            r.bus.uart_send(m, READ_12);
            next_command += TRAFFIC_PERIOD;
            commands += 1;
        }
    }
    r.avr().clear_observer();
    let late = encoder.borrow().worst_late;
    (commands, late)
}

/// The odometer after `256·k` A rising edges at `rate`: REG_RESET bit 2 zeroes it first,
/// so it must read k exactly (one lost edge reads k − 1). With a `master`, also whether
/// every read it was sent meanwhile was answered (12 bytes each).
fn edges_counted(r: &mut Rig, rate: u32, k: u16, master: Option<usize>) -> (u16, bool) {
    r.write_raw(id::REG_RESET, 4);
    r.bus.run_us(3_000);
    assert_eq!(r.read_raw(id::REGDS_DRIVE_ODO), 0);
    if let Some(m) = master {
        r.bus.chip(m).map(|mut a| a.uart_take());
    }
    let (commands, late) = feed_quadrature(r, 256 * u32::from(k), rate, master);
    // Bus runs end on the changes' cycles within an instruction (`harness_sleep`), but an
    // I2C transfer the bus delivers runs the chip ahead until it answers (up to 126 cycles
    // seen with the second master's reads), far less than a quarter period at the rates
    // that matter here.
    assert!(late <= 200, "an encoder change landed {late} cycles late");
    r.bus.run_us(6_000);
    let mut served = true;
    if let Some(m) = master {
        let replies = r.bus.chip(m).map(|mut a| a.uart_take()).unwrap_or_default();
        let answered = replies.iter().filter(|&&b| b == b'=').count();
        assert!(commands > 0);
        served = answered == commands as usize;
    }
    (r.read_raw(id::REGDS_DRIVE_ODO), served)
}

/// The highest rate of `rates` (ascending) below the first that loses an edge.
fn highest_lossless(r: &mut Rig, rates: &[u32], master: Option<usize>) -> u32 {
    let k = 16; // 4096 rising edges a run
    let mut best = 0;
    for &rate in rates {
        let (counted, served) = edges_counted(r, rate, k, master);
        println!(
            "  {rate} A edges/s ({} pin changes/s): odometer {counted} of {k} (x256){}",
            4 * rate,
            if served {
                ""
            } else {
                ", TWI reads not all answered"
            }
        );
        if counted != k || !served {
            break;
        }
        best = rate;
    }
    best
}

#[test]
fn highest_encoder_rate_without_a_lost_edge() {
    let mut r = calibrated_drive_steer();
    r.write_value(id::REGDS_STEER_REQPOS, 20.0);
    r.write_raw(id::REGDS_DRIVE_MODE, 1);
    r.run_us(100_000);
    {
        let mut avr = r.avr();
        avr.set_pin(Pin::d(0), false);
        avr.set_pin(Pin::d(1), false);
    }
    let rates = [
        4_000, 8_000, 12_000, 16_000, 18_000, 20_000, 22_000, 24_000, 28_000, 32_000, 36_000,
        40_000, 44_000, 48_000, 56_000, 64_000, 72_000, 80_000, 96_000, 112_000, 128_000,
    ];
    println!("encoder edges, tick and ADC running:");
    let quiet = highest_lossless(&mut r, &rates, None);
    // A second master on the bus reads the drive's 12 monitoring bytes every 5 ms at
    // 400 kHz all through the run.
    let master = Avr::firmware("fixture_twi_master").expect("fixture_twi_master");
    let m = r.bus.add_master(master).expect("a master");
    r.bus
        .uart_read_until(m, b"twi master", 100_000)
        .expect("banner");
    r.bus.uart_send(m, b"f 0c 0\n");
    r.bus.uart_read_until(m, b"ok", 100_000).expect("400 kHz");
    println!("the same with TWI traffic:");
    let busy = highest_lossless(&mut r, &rates, Some(m));
    println!(
        "highest rate with no lost edge: {quiet} A edges/s = {quiet} ticks/s quiet, \
         {busy} with TWI traffic ({} pin changes/s)",
        4 * busy
    );
    // The rover's top drive speed is 4000 ticks/s (REGDS_DRIVE_REQSPEED's range); the
    // project keeps ten times that with and without bus traffic. (Quiet is not compared
    // with busy: near the limit a loss depends on how the pin changes line up with the
    // other interrupts, so either can come out one rate step higher.)
    assert!(quiet >= 40_000, "edges lost below 10x the top speed, quiet");
    assert!(
        busy >= 40_000,
        "edges lost below 10x the top speed with TWI traffic"
    );
}

/// The control task's exclusive cycles per tick over `ms` of emulated time with the
/// plant closing the loop, so the motors really move; `between(rig, i)` runs before
/// millisecond `i` (demands sent over the bus are part of the run). Returns the tracker
/// of the run, whose `runs` hold the ticks.
fn ticks_in_motion(r: &mut Rig, ms: u64, mut between: impl FnMut(&mut Rig, u64)) -> Tracker {
    let tracker = Rc::new(RefCell::new(Tracker::default()));
    let t = Rc::clone(&tracker);
    r.avr()
        .set_observer(move |avr| t.borrow_mut().after_step(avr));
    for i in 0..ms {
        between(r, i);
        r.run_us(1_000);
    }
    r.avr().clear_observer();
    tracker.take()
}

/// The control tick's mean cycles by the function that spent them, largest first, the
/// functions below `shown` together as "others": where a tick's cycles go. A function
/// is named by its path without its crate's hash; code inlined into it counts as its.
fn tick_by_function(tracker: &Tracker, image: &str, shown: usize) -> Vec<(String, u64)> {
    let program = Program::of_elf(&firmware_path(image)).expect("the image's symbols");
    let ticks = tracker.ticks().len().max(1) as u64;
    let mut by_name: HashMap<String, u64> = HashMap::new();
    for (&pc, &cycles) in &tracker.tick_pcs {
        let name = match program.function_at(pc) {
            Some("__vector_15") => "the tick's vector, with all inlined into it".to_string(),
            Some(n) => format!("{:#}", rustc_demangle::demangle(n)),
            None => format!("{pc:#06x}"),
        };
        *by_name.entry(name).or_default() += cycles;
    }
    let mut all: Vec<(String, u64)> = by_name.into_iter().collect();
    all.sort_by(|a, b| b.1.cmp(&a.1).then_with(|| a.0.cmp(&b.0)));
    let others: u64 = all.iter().skip(shown).map(|(_, c)| c).sum();
    all.truncate(shown);
    all.push(("others".to_string(), others));
    all.into_iter().map(|(n, c)| (n, c / ticks)).collect()
}

/// Prints a breakdown of [`tick_by_function`], and checks that it accounts for every
/// cycle of the ticks the tracker timed: the sum of its means is their mean, to within
/// the rounding of each line.
fn show_breakdown(tracker: &Tracker, image: &str) {
    let lines = tick_by_function(tracker, image, 8);
    println!("  where a tick's cycles go (mean per tick, by function):");
    for (name, cycles) in &lines {
        println!("    {cycles:>5}  {name}");
    }
    let runs = tracker.ticks();
    let (_, mean, _) = run_stats(runs);
    let sum: u64 = lines.iter().map(|(_, c)| c).sum();
    assert!(
        sum <= mean && mean - sum <= lines.len() as u64 + 1,
        "the breakdown sums to {sum}, the ticks' mean is {mean}"
    );
}

#[test]
fn drive_steer_costs_while_steering() {
    let mut r = calibrated_drive_steer();
    r.write_value(id::REGDS_DRIVE_REQSPEED, 1000.0);
    r.run_us(1_000_000);
    let steer = |r: &Rig| {
        let m = r
            .plant
            .model(r.chip)
            .and_then(|m| m.ds().map(|d| d.steer.motor.angle_deg()));
        m.unwrap_or(f64::NAN)
    };
    // The steer swings between -30 and +30 degrees, a new demand every 150 ms, so it is
    // moving (and its controller working) for the whole 450 ms.
    let mut travelled = 0.0;
    let mut last = steer(&r);
    let tracker = ticks_in_motion(&mut r, 450, |r, i| {
        if i % 150 == 0 {
            let to = if (i / 150) % 2 == 0 { 30.0 } else { -30.0 };
            r.write_value(id::REGDS_STEER_REQPOS, to);
        }
        let now = steer(r);
        travelled += (now - last).abs();
        last = now;
    });
    let runs = tracker.ticks();
    let (n, mean, max) = run_stats(runs);
    println!("control tick, drive at 1000 and the steer swinging: {n} runs, mean {mean}, max {max} cycles");
    println!("  the steer travelled {travelled:.0} degrees in 450 ms");
    show_breakdown(&tracker, "slave-drive");
    assert!(
        travelled > 10.0,
        "the steer hardly moved: {travelled:.1} degrees"
    );
    assert!((440..=460).contains(&n), "one tick per ms: {n}");
    assert!(
        mean > 300 && mean <= SWINGING_CEILING && max < 16_000,
        "{mean} / {max}"
    );
}

#[test]
fn lift_lift_costs_while_lifting() {
    let mut r = rig(3);
    r.run_us(650_000);
    r.reset_exceptions();
    // calibrate()'s lift block for ONE, and the same for TWO (its ids are ONE's + 18).
    for &(reg, raw) in LIFT_GAINS_WHEEL_1 {
        r.write_raw(reg, raw);
        r.write_raw(reg + 18, raw);
    }
    r.run_us(200_000);
    let lifts = |r: &Rig| {
        let ll = r.plant.model(r.chip).and_then(|m| {
            m.ll()
                .map(|l| (l.one.motor.angle_deg(), l.two.motor.angle_deg()))
        });
        ll.unwrap_or((f64::NAN, f64::NAN))
    };
    // Both lifts swing between -20 and +20 degrees, in opposite directions; the distance
    // each travels shows that both were moving (and their controllers working).
    let mut travelled = (0.0, 0.0);
    let mut last = lifts(&r);
    let tracker = ticks_in_motion(&mut r, 450, |r, i| {
        if i % 150 == 0 {
            let to = if (i / 150) % 2 == 0 { 20.0 } else { -20.0 };
            r.write_value(id::REGLL_ONE_REQPOS, to);
            r.write_value(id::REGLL_TWO_REQPOS, -to);
        }
        let now = lifts(r);
        travelled.0 += (now.0 - last.0).abs();
        travelled.1 += (now.1 - last.1).abs();
        last = now;
    });
    let runs = tracker.ticks();
    let (n, mean, max) = run_stats(runs);
    println!("control tick, both lifts moving: {n} runs, mean {mean}, max {max} cycles");
    show_breakdown(&tracker, "slave-lift");
    println!(
        "  lift ONE travelled {:.1} degrees, TWO {:.1}, in 450 ms",
        travelled.0, travelled.1
    );
    assert!(
        travelled.0 > 5.0 && travelled.1 > 5.0,
        "the lifts hardly moved: {travelled:?}"
    );
    assert!((440..=460).contains(&n), "one tick per ms: {n}");
    assert!(
        mean > 300 && mean <= LIFTS_CEILING && max < 16_000,
        "{mean} / {max}"
    );
}
