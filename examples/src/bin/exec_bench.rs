//! Executor example: cycle counts of dispatch and locks at each priority level.
//!
//! The layout mirrors the slave firmware's: level 1 holds a pin-change task and the ADC,
//! level 2 a pin-change task and the TWI, level 3 (the top) an external-interrupt task.
//! The ADC and TWI tasks never run; they are there so that the level masks cover the same
//! registers as on the rover (level 1: PCICR and ADCSRA; level 2: PCICR, ADCSRA and TWCR).
//!
//! The baseline `bare` is a plain handler outside the executor with the same body as the
//! tasks. That body stamps TCNT1 on entry and on exit (into GPIOR1/GPIOR2) around one
//! inline-assembly `nop`, so that, like every executor task (whose SEI/CLI are inline
//! assembly) and like any handler that calls a function, it gets the classic AVR prologue
//! that saves and clears r1. A second plain handler, `bare_min`, has no `nop`: LLVM then
//! leaves r1 alone, which shows what that prologue costs.
//!
//! Timer1 runs at the CPU clock. For each handler, idle reads TCNT1, fires the handler by
//! toggling its pin, and reads TCNT1 again when control is back. Idle then times a call of
//! a function that locks a resource at each ceiling with an empty closure, minus a call of
//! an empty function: the difference is the lock and unlock alone. It prints, in cycles,
//! `bench level=L entry=E exit=X total=T lock=K` per level, then
//! `bench bare entry=E exit=X total=T` and the same for `bare_min`.
#![no_std]
#![no_main]
#![feature(abi_avr_interrupt)]
#![feature(asm_experimental_arch)]

mod exec_support;

use core::ptr::{read_volatile, write_volatile};

use exec_support::{cycles, setup_triggers, start_cycle_counter, Trigger, Uart};

/// GPIOR1 and GPIOR2 (I/O 0x2A/0x2B): one-cycle `out` targets for the stamps.
const GPIOR1: *mut u8 = 0x4A as *mut u8;
const GPIOR2: *mut u8 = 0x4B as *mut u8;

executor::app! {
    #[shared]
    struct Shared {
        r1: u8,
        r2: u8,
        r3: u8,
    }

    #[local]
    struct Local {
        uart: Uart,
    }

    #[init]
    fn init;

    #[idle(shared = [r1, r2, r3], local = [uart])]
    fn idle;

    #[task(binds = PCINT0, priority = 1, shared = [r1])]
    fn level1;

    #[task(binds = ADC, priority = 1)]
    fn adc_unused;

    #[task(binds = PCINT1, priority = 2, shared = [r2])]
    fn level2;

    #[task(binds = TWI, priority = 2)]
    fn twi_unused;

    #[task(binds = INT0, priority = 3, shared = [r3])]
    fn level3;
}

/// The body of the tasks and of `bare`: stamp entry, a `nop`, stamp exit.
#[inline(always)]
fn body() {
    let entry = cycles();
    // SAFETY: GPIOR1/GPIOR2 are general-purpose I/O registers nothing else uses.
    unsafe { write_volatile(GPIOR1, entry) };
    avr_device::asm::nop();
    let exit = cycles();
    // SAFETY: as above.
    unsafe { write_volatile(GPIOR2, exit) };
}

// `bare`: a plain handler, not managed by the executor, with the tasks' body.
#[avr_device::interrupt(atmega328p)]
fn PCINT2() {
    body();
}

// `bare_min`: the same without the inline-assembly `nop`.
#[avr_device::interrupt(atmega328p)]
fn INT1() {
    let entry = cycles();
    // SAFETY: GPIOR1/GPIOR2 are general-purpose I/O registers nothing else uses.
    unsafe { write_volatile(GPIOR1, entry) };
    let exit = cycles();
    // SAFETY: as above.
    unsafe { write_volatile(GPIOR2, exit) };
}

fn init(cx: init::Context) -> (Shared, Local) {
    let dp = cx.device;
    setup_triggers(&dp.PORTB, &dp.PORTC, &dp.PORTD, &dp.EXINT);
    // The baselines are not tasks, so their enable bits are set here, by hand (the
    // executor adds INT0's at start).
    // SAFETY: PCIE2 and INT1 enabled.
    dp.EXINT.pcicr().write(|w| unsafe { w.bits(1 << 2) });
    dp.EXINT.eimsk().write(|w| unsafe { w.bits(1 << 1) });
    start_cycle_counter(&dp.TC1);
    let uart = Uart::new(dp.USART0);
    (
        Shared {
            r1: 0,
            r2: 0,
            r3: 0,
        },
        Local { uart },
    )
}

/// Cycles from firing a trigger (writing `mask` to the PINx register `pin_reg`) to the
/// handler's entry stamp, from its exit stamp to the
/// return, and from firing to return. Not inlined, so that every measurement runs the
/// very same instructions around the trigger.
#[inline(never)]
fn dispatch(pin_reg: *mut u8, mask: u8) -> (u8, u8, u8) {
    let before = cycles();
    // SAFETY: writing a one to a PINx bit toggles that output pin (see `trigger`).
    unsafe { write_volatile(pin_reg, mask) };
    let after = cycles();
    // SAFETY: GPIOR1/GPIOR2 hold the stamps of the handler that just ran.
    let (entry, exit) = unsafe { (read_volatile(GPIOR1), read_volatile(GPIOR2)) };
    (
        entry.wrapping_sub(before),
        after.wrapping_sub(exit),
        after.wrapping_sub(before),
    )
}

/// [`dispatch`] for trigger `t`.
fn fire(t: Trigger) -> (u8, u8, u8) {
    let (pin_reg, mask) = t.pin();
    dispatch(pin_reg, mask)
}

/// Cycles taken by a call of `f` (call, body, return, and the two TCNT1 reads).
#[inline(never)]
fn time(f: fn(&mut idle::SharedResources<'_>), shared: &mut idle::SharedResources<'_>) -> u8 {
    let before = cycles();
    f(shared);
    cycles().wrapping_sub(before)
}

#[inline(never)]
fn no_lock(_: &mut idle::SharedResources<'_>) {}

#[inline(never)]
fn lock1(s: &mut idle::SharedResources<'_>) {
    s.r1.lock(|_| ());
}

#[inline(never)]
fn lock2(s: &mut idle::SharedResources<'_>) {
    s.r2.lock(|_| ());
}

#[inline(never)]
fn lock3(s: &mut idle::SharedResources<'_>) {
    s.r3.lock(|_| ());
}

fn idle(mut cx: idle::Context) -> ! {
    cx.local.uart.put_str(b"exec_bench ready\n");
    let d1 = fire(Trigger::Pcint0);
    let d2 = fire(Trigger::Pcint1);
    let d3 = fire(Trigger::Int0);
    let bare_pc = fire(Trigger::Pcint2);
    let bare_int = fire(Trigger::Int1);
    let shared = &mut cx.shared;
    let base = time(no_lock, shared);
    let k1 = time(lock1, shared).wrapping_sub(base);
    let k2 = time(lock2, shared).wrapping_sub(base);
    let k3 = time(lock3, shared).wrapping_sub(base);
    let uart = &mut *cx.local.uart;
    for (level, d, k) in [(1u32, d1, k1), (2, d2, k2), (3, d3, k3)] {
        uart.put_str(b"bench ");
        uart.field(b"level", level);
        uart.field(b"entry", u32::from(d.0));
        uart.field(b"exit", u32::from(d.1));
        uart.field(b"total", u32::from(d.2));
        uart.field(b"lock", u32::from(k));
        uart.put(b'\n');
    }
    for (name, d) in [(&b"bare"[..], bare_pc), (&b"bare_min"[..], bare_int)] {
        uart.put_str(b"bench ");
        uart.put_str(name);
        uart.put(b' ');
        uart.field(b"entry", u32::from(d.0));
        uart.field(b"exit", u32::from(d.1));
        uart.field(b"total", u32::from(d.2));
        uart.put(b'\n');
    }
    loop {
        cx.sleep.sleep();
    }
}

fn level1(_cx: level1::Context) {
    body();
}

fn adc_unused(_cx: adc_unused::Context) {}

fn level2(_cx: level2::Context) {
    body();
}

fn twi_unused(_cx: twi_unused::Context) {}

fn level3(_cx: level3::Context) {
    body();
}
