//! Executor example: nested locks, masked and top-ceiling, in both orders.
//!
//! `low` (priority 1) takes `a` (ceiling 2, shared with `mid`), then inside it `b`
//! (ceiling 3, shared with `high`). Firing `mid` inside `a` and `high` inside `b` shows
//! each unlock releasing exactly its own level: `high` runs when `b` is released, while
//! `a` is still held; `mid` runs when `a` is released. Then `low` takes `trace` (the top
//! ceiling: interrupts off) and nests `a` inside it: the inner lock must leave interrupts
//! off, so `top` and `high`, fired inside, run only after the outer unlock (`top` first,
//! by its higher priority). An unused ADC task makes levels 1 and 2 include ADCSRA, so
//! the inner lock takes the path that saves and restores SREG.
//! Idle prints `nested trace=L([]H)M{()}THl`.
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
        a: u8,
        b: u8,
    }

    #[local]
    struct Local {
        uart: Uart,
    }

    #[init]
    fn init;

    #[idle(shared = [trace], local = [uart])]
    fn idle;

    #[task(binds = PCINT0, priority = 1, shared = [trace, a, b])]
    fn low;

    #[task(binds = ADC, priority = 1)]
    fn adc_unused;

    #[task(binds = PCINT1, priority = 2, shared = [trace, a])]
    fn mid;

    #[task(binds = PCINT2, priority = 3, shared = [trace, b])]
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
            a: 0,
            b: 0,
        },
        Local { uart },
    )
}

fn idle(mut cx: idle::Context) -> ! {
    cx.local.uart.put_str(b"exec_nested_lock ready\n");
    trigger(Trigger::Pcint0);
    // Wait (bounded) for the events, then report what happened.
    wait_for_events(14, || cx.shared.trace.lock(|t| t.len()));
    let uart = &mut *cx.local.uart;
    cx.shared
        .trace
        .lock(|t| uart.put_trace(b"nested trace=", t));
    loop {
        cx.sleep.sleep();
    }
}

fn low(mut cx: low::Context) {
    let low::SharedResources { trace, a, b, .. } = &mut cx.shared;
    trace.lock(|t| t.push(b'L'));
    // Masked inside masked: ceiling 2, then 3.
    a.lock(|a| {
        *a += 1;
        trace.lock(|t| t.push(b'('));
        trigger(Trigger::Pcint1); // mid (2): held until `a` is released
        b.lock(|b| {
            *b += 1;
            trace.lock(|t| t.push(b'['));
            trigger(Trigger::Pcint2); // high (3): held until `b` is released
            busy(10);
            trace.lock(|t| t.push(b']'));
        });
        // `high` has run here, `mid` has not.
        busy(10);
        trace.lock(|t| t.push(b')'));
    });
    // Masked inside the top ceiling: interrupts stay off throughout.
    trace.lock(|t| {
        t.push(b'{');
        trigger(Trigger::Int0); // top (4)
        trigger(Trigger::Pcint2); // high (3)
        a.lock(|a| {
            *a += 1;
            t.push(b'(');
            busy(10);
            t.push(b')');
        });
        busy(10);
        t.push(b'}');
    });
    // Both run here, after the top-ceiling unlock.
    busy(10);
    trace.lock(|t| t.push(b'l'));
}

fn adc_unused(_cx: adc_unused::Context) {}

fn mid(mut cx: mid::Context) {
    *cx.shared.a += 1;
    cx.shared.trace.lock(|t| t.push(b'M'));
}

fn high(mut cx: high::Context) {
    *cx.shared.b += 1;
    cx.shared.trace.lock(|t| t.push(b'H'));
}

fn top(mut cx: top::Context) {
    cx.shared.trace.push(b'T');
}
