//! Cycle benchmarks of the drive/steer image in the emulator (not timed tests): the
//! control tick with both controllers running, the encoder-edge task, the idle CPU
//! share and the worst-case stack (painted at boot, read back here). Figures go to
//! docs/benchmarks.md (Slave); run with `--nocapture` to see them.

mod slave_support;

use harness::{Avr, CpuState, Pin};
use shared::regs::id;
use slave_support::{rig, DRIVE_GAINS, STEER_GAINS_WHEEL_1};

/// Byte addresses of the vectors the slave binds.
const PCINT2: u32 = 5 * 4;
const TIMER0_COMPA: u32 = 14 * 4;
const TIMER0_COMPB: u32 = 15 * 4;
const ADC: u32 = 21 * 4;
const TWI: u32 = 24 * 4;
const VECTORS: [u32; 5] = [PCINT2, TIMER0_COMPA, TIMER0_COMPB, ADC, TWI];

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
    runs: std::collections::HashMap<u32, Vec<u64>>,
    asleep: u64,
    total: u64,
}

/// Steps `avr` for `cycles`, toggling PD0 every `edge_half_period` cycles (0: never).
fn profile(avr: &mut Avr, cycles: u64, edge_half_period: u64) -> Profile {
    let mut p = Profile::default();
    // (vector, sp at entry, entry cycle, cycles of nested handlers)
    let mut frames: Vec<(u32, u16, u64, u64)> = Vec::new();
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
        let now_sp = sp(avr);
        while let Some(&(v, s, at, nested)) = frames.last() {
            if now_sp < s + 2 {
                break;
            }
            frames.pop();
            let total = avr.cycles() - at;
            p.runs.entry(v).or_default().push(total - nested);
            if let Some(outer) = frames.last_mut() {
                outer.3 += total;
            }
        }
        let at = pc(avr);
        if VECTORS.contains(&at) {
            frames.push((at, now_sp, avr.cycles(), 0));
        }
    }
    p.total = avr.cycles() - start;
    p
}

fn stats(p: &Profile, v: u32) -> (usize, u64, u64) {
    let runs = p.runs.get(&v).cloned().unwrap_or_default();
    let max = runs.iter().copied().max().unwrap_or(0);
    let mean = if runs.is_empty() {
        0
    } else {
        runs.iter().sum::<u64>() / runs.len() as u64
    };
    (runs.len(), mean, max)
}

#[test]
fn drive_steer_costs() {
    let mut r = rig(1);
    r.run_us(650_000);
    r.reset_exceptions();
    for &(reg, raw) in DRIVE_GAINS.iter().chain(STEER_GAINS_WHEEL_1) {
        r.write_raw(reg, raw);
    }
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
    assert!(mean > 300, "the tick does work: {mean}");
    let (n, mean, max) = stats(&p, PCINT2);
    println!("encoder edge task: {n} runs, mean {mean}, max {max} cycles");
    assert!(n >= 1_100, "{n} pin changes");
    let (n, mean, max) = stats(&p, ADC);
    println!("ADC task: {n} runs, mean {mean}, max {max} cycles");
    let (n, mean, max) = stats(&p, TIMER0_COMPA);
    println!("millisecond task: {n} runs, mean {mean}, max {max} cycles");
    let idle = 100.0 * p.asleep as f64 / p.total as f64;
    println!("idle (asleep): {idle:.1} % of {} cycles", p.total);
    // simavr converts in 2 ADC clocks instead of 13, so the ADC task runs about 6.5
    // times as often here as on the chip; the idle share is a lower bound.
    assert!(idle > 10.0 && idle < 100.0);

    // Stack high-water: the lowest address that lost the paint.
    let heap = avr.symbol("__heap_start").expect("symbol") as u16;
    let mut low = heap;
    while low < 0x900 && avr.read_data(low) == 0xc5 {
        low += 1;
    }
    let stack = 0x900 - u32::from(low);
    let statics = u32::from(heap) - 0x100;
    println!(
        "static RAM {statics} B, worst-case stack {stack} B, sum {}",
        statics + stack
    );
    assert!(stack > 20 && stack < 1_000, "{stack}");
}
