//! Emulator tests of SLEEP: a sleeping CPU wakes on its timer interrupt, and
//! sleeping costs no real time.

use std::time::{Duration, Instant};

use harness::{Avr, CpuState};

#[test]
fn one_second_of_sleep_takes_little_wall_time() {
    let mut avr = Avr::firmware("fixture_sleep").unwrap();
    avr.uart_read_until(b"sleep ready\r\n", 10_000).unwrap();
    let wall = Instant::now();
    let t0 = avr.micros();
    let line = avr.uart_read_until(b"\r\n", 1_100_000).unwrap();
    let emulated = avr.micros() - t0;
    let real = wall.elapsed();
    assert_eq!(line, b"t=100\r\n");
    // 100 ticks of 10 ms, give or take the banner and the print.
    assert!((999_000..1_001_000).contains(&emulated), "{emulated} µs");
    assert!(
        real < Duration::from_millis(500),
        "took {real:?} of wall time"
    );
}

#[test]
fn sleeping_cpu_jumps_to_its_next_interrupt() {
    let mut avr = Avr::firmware("fixture_sleep").unwrap();
    avr.uart_read_until(b"sleep ready\r\n", 10_000).unwrap();
    avr.run_us(25_000);
    let end = avr.micros() + 100_000;
    let (mut steps, mut asleep) = (0u32, 0u32);
    while avr.micros() < end {
        steps += 1;
        if avr.step() == CpuState::Sleeping {
            asleep += 1;
        }
    }
    // 10 ticks in 100 ms: each is one sleep jump plus a short interrupt handler,
    // far fewer steps than the 1.6 M cycles a busy loop would take.
    assert!((10..=12).contains(&asleep), "{asleep} sleeps");
    assert!(steps < 2_000, "{steps} steps");
}

#[test]
fn run_us_stops_on_time_while_sleeping() {
    let mut avr = Avr::firmware("fixture_sleep").unwrap();
    avr.run_us(3_333);
    let t = avr.micros();
    assert!((3_333..3_334).contains(&t), "{t}");
    avr.run_cycles(17);
    assert!(avr.cycles() - t * 16 >= 17);
    assert!(avr.cycles() - t * 16 < 17 + 16 + 5);
}

#[test]
fn symbol_locates_a_static_in_ram() {
    let mut avr = Avr::firmware("fixture_sleep").unwrap();
    let addr = avr.symbol("TICKS").expect("TICKS is exported unmangled");
    assert!((0x100..0x900).contains(&addr), "{addr:#x} is not in SRAM");
    assert_eq!(
        avr.uart_read_until(b"t=100\r\n", 1_100_000).unwrap().len(),
        20
    );
    let addr = addr as u16;
    let ticks = u16::from_le_bytes([avr.read_data(addr), avr.read_data(addr + 1)]);
    assert_eq!(ticks, 100);
    assert_eq!(avr.symbol("no_such_symbol"), None);
}

#[test]
fn runs_end_within_an_instruction_of_their_target_asleep_or_awake() {
    // Runs of 1..300 cycles, as a lock-stepped bus makes them: a CPU that goes to sleep
    // right at the end of a run must not jump past it to its next timer.
    for name in ["fixture_sleep", "slave-drive"] {
        let mut avr = Avr::firmware(name).unwrap();
        avr.eeprom_write(0, &[1]);
        let (mut worst, mut x) = (0, 12_345u32);
        for _ in 0..100_000 {
            x ^= x << 13;
            x ^= x >> 17;
            x ^= x << 5;
            let n = u64::from(x % 300) + 1;
            let target = avr.cycles() + n;
            avr.run_cycles(n);
            worst = worst.max(avr.cycles() - target);
        }
        // The longest instruction takes 5 cycles (an interrupt's entry 4).
        assert!(worst <= 5, "{name}: a run ended {worst} cycles late");
    }
}
