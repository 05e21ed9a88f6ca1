//! Executor example: a high-priority task preempts a low-priority one mid-way.
//!
//! Idle fires `low` (PCINT0, priority 1). `low` records `L`, fires `high` (PCINT1,
//! priority 2), burns some cycles and records `l`. `high` preempts it at once, records
//! `H` and fires `low`'s source again, which must wait: `low` is masked while it runs, so
//! its second run (`L` then `l`, without firing `high` again) comes only after the first
//! one ends. Idle then prints `preempt trace=LHlLl`.
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
    }

    #[local]
    struct Local {
        uart: Uart,
        runs: u8,
    }

    #[init]
    fn init;

    #[idle(shared = [trace], local = [uart])]
    fn idle;

    #[task(binds = PCINT0, priority = 1, shared = [trace], local = [runs])]
    fn low;

    #[task(binds = PCINT1, priority = 2, shared = [trace])]
    fn high;
}

fn init(cx: init::Context) -> (Shared, Local) {
    let dp = cx.device;
    setup_triggers(&dp.PORTB, &dp.PORTC, &dp.PORTD, &dp.EXINT);
    let uart = Uart::new(dp.USART0);
    (
        Shared {
            trace: Trace::new(),
        },
        Local { uart, runs: 0 },
    )
}

fn idle(mut cx: idle::Context) -> ! {
    cx.local.uart.put_str(b"exec_preempt ready\n");
    trigger(Trigger::Pcint0);
    // Wait (bounded) for the events, then report what happened.
    wait_for_events(5, || cx.shared.trace.lock(|t| t.len()));
    let uart = &mut *cx.local.uart;
    cx.shared
        .trace
        .lock(|t| uart.put_trace(b"preempt trace=", t));
    loop {
        cx.sleep.sleep();
    }
}

fn low(mut cx: low::Context) {
    *cx.local.runs += 1;
    let first = *cx.local.runs == 1;
    cx.shared.trace.lock(|t| t.push(b'L'));
    if first {
        trigger(Trigger::Pcint1);
    }
    busy(20);
    cx.shared.trace.lock(|t| t.push(b'l'));
}

fn high(mut cx: high::Context) {
    // `high` is the top task and the highest user of `trace`: no lock needed.
    cx.shared.trace.push(b'H');
    trigger(Trigger::Pcint0);
}
