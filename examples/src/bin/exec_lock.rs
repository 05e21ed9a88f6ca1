//! Executor example: a lock holds off exactly the tasks at or below its ceiling.
//!
//! Resource `shared_count` is used by `low` (priority 1) and `mid` (priority 2), so its
//! ceiling is 2. Inside `low`'s lock, `low` fires a task at every level: `peer` (1, same as
//! `low`), `mid` (2, the ceiling), `high` (3) and `top` (4). `high` and `top` run at once,
//! inside the lock; `mid` waits for the unlock; `peer` waits until `low` has finished.
//! Idle prints `lock trace=L[HT]MlP`.
#![no_std]
#![no_main]
#![feature(abi_avr_interrupt)]
#![feature(asm_experimental_arch)]

mod exec_support;

use exec_support::{busy, setup_triggers, trigger, wait_for_events, Trace, Trigger, Uart};

executor::app! {
    #[shared]
    struct Shared {
        trace: Trace,
        shared_count: u8,
    }

    #[local]
    struct Local {
        uart: Uart,
    }

    #[init]
    fn init;

    #[idle(shared = [trace], local = [uart])]
    fn idle;

    #[task(binds = PCINT0, priority = 1, shared = [trace, shared_count])]
    fn low;

    #[task(binds = INT1, priority = 1, shared = [trace])]
    fn peer;

    #[task(binds = PCINT1, priority = 2, shared = [trace, shared_count])]
    fn mid;

    #[task(binds = PCINT2, priority = 3, shared = [trace])]
    fn high;

    #[task(binds = INT0, priority = 4, shared = [trace])]
    fn top;
}

fn init(cx: init::Context) -> (Shared, Local) {
    let dp = cx.device;
    setup_triggers(&dp.PORTB, &dp.PORTC, &dp.PORTD, &dp.EXINT);
    let uart = Uart::new(dp.USART0);
    (
        Shared {
            trace: Trace::new(),
            shared_count: 0,
        },
        Local { uart },
    )
}

fn idle(mut cx: idle::Context) -> ! {
    cx.local.uart.put_str(b"exec_lock ready\n");
    trigger(Trigger::Pcint0);
    // Wait (bounded) for the events, then report what happened.
    wait_for_events(8, || cx.shared.trace.lock(|t| t.len()));
    let uart = &mut *cx.local.uart;
    cx.shared.trace.lock(|t| uart.put_trace(b"lock trace=", t));
    loop {
        cx.sleep.sleep();
    }
}

fn low(mut cx: low::Context) {
    cx.shared.trace.lock(|t| t.push(b'L'));
    let trace = &mut cx.shared.trace;
    cx.shared.shared_count.lock(|n| {
        *n += 1;
        trace.lock(|t| t.push(b'['));
        trigger(Trigger::Int1);
        trigger(Trigger::Pcint1);
        trigger(Trigger::Pcint2);
        trigger(Trigger::Int0);
        busy(20);
        trace.lock(|t| t.push(b']'));
    });
    cx.shared.trace.lock(|t| t.push(b'l'));
}

fn peer(mut cx: peer::Context) {
    cx.shared.trace.lock(|t| t.push(b'P'));
}

fn mid(mut cx: mid::Context) {
    cx.shared.shared_count.lock(|n| *n += 1);
    cx.shared.trace.lock(|t| t.push(b'M'));
}

fn high(mut cx: high::Context) {
    cx.shared.trace.lock(|t| t.push(b'H'));
}

fn top(mut cx: top::Context) {
    cx.shared.trace.push(b'T');
}
